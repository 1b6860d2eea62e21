/*=========================================================================
 *
 *  Copyright NumFOCUS
 *
 *  Licensed under the Apache License, Version 2.0 (the "License");
 *  you may not use this file except in compliance with the License.
 *  You may obtain a copy of the License at
 *
 *         http://www.apache.org/licenses/LICENSE-2.0.txt
 *
 *  Unless required by applicable law or agreed to in writing, software
 *  distributed under the License is distributed on an "AS IS" BASIS,
 *  WITHOUT WARRANTIES OR CONDITIONS OF ANY KIND, either express or implied.
 *  See the License for the specific language governing permissions and
 *  limitations under the License.
 *
 *=========================================================================*/
#ifndef itkPointCloudKdTree_h
#define itkPointCloudKdTree_h

#include <nanoflann.hpp>

#include <cstddef>
#include <vector>

namespace itk
{
namespace detail
{
/** A vector of ITK points as nanoflann's point cloud. */
template <typename TPoint>
struct PointCloudAdaptor
{
  const std::vector<TPoint> & Points;

  size_t
  kdtree_get_point_count() const
  {
    return Points.size();
  }
  double
  kdtree_get_pt(size_t index, size_t dimension) const
  {
    return Points[index][dimension];
  }
  template <typename TBox>
  bool
  kdtree_get_bbox(TBox &) const
  {
    return false;
  }
};

/** nanoflann's k-d tree over a PointCloudAdaptor (Euclidean distance, 3-D). */
template <typename TPoint>
using PointCloudKdTree =
  nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, PointCloudAdaptor<TPoint>>,
                                      PointCloudAdaptor<TPoint>,
                                      3,
                                      size_t>;
} // namespace detail
} // namespace itk

#endif // itkPointCloudKdTree_h
