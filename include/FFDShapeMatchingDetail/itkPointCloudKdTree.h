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

/** nanoflann's result set for the k nearest points closer than a radius: a k-nearest search whose bound starts at
 * the radius instead of infinity, so that branches of the tree beyond it are never visited. The points are kept
 * nearest first in caller-owned arrays of length k. Written to the interface that nanoflann's searches call (the
 * same in its versions 1.4 to 1.7): addPoint, worstDist, size, full and sort. */
class NearestWithinRadiusResultSet
{
public:
  using DistanceType = double;
  using IndexType = size_t;
  using CountType = size_t;

  NearestWithinRadiusResultSet(size_t capacity, double squaredRadius, size_t * indices, double * squaredDistances)
    : m_Indices(indices)
    , m_SquaredDistances(squaredDistances)
    , m_Capacity(capacity)
    , m_SquaredRadius(squaredRadius)
  {}

  size_t
  size() const
  {
    return m_Count;
  }
  bool
  empty() const
  {
    return m_Count == 0;
  }
  bool
  full() const
  {
    return m_Count == m_Capacity;
  }
  /** The bound of the search: the radius until k points are held, then the k-th distance. */
  double
  worstDist() const
  {
    return m_Count < m_Capacity ? m_SquaredRadius : m_SquaredDistances[m_Count - 1];
  }
  /** Inserts a point in distance order if it is within the bound; the search always continues. */
  bool
  addPoint(double squaredDistance, size_t index)
  {
    if (m_Capacity == 0 || !(squaredDistance < worstDist()))
    {
      return true;
    }
    size_t position = m_Count < m_Capacity ? m_Count : m_Capacity - 1;
    for (; position > 0 && m_SquaredDistances[position - 1] > squaredDistance; --position)
    {
      m_SquaredDistances[position] = m_SquaredDistances[position - 1];
      m_Indices[position] = m_Indices[position - 1];
    }
    m_SquaredDistances[position] = squaredDistance;
    m_Indices[position] = index;
    if (m_Count < m_Capacity)
    {
      ++m_Count;
    }
    return true;
  }
  void
  sort()
  {} // kept in order by addPoint

private:
  size_t * m_Indices;
  double * m_SquaredDistances;
  size_t   m_Capacity;
  double   m_SquaredRadius;
  size_t   m_Count{ 0 };
};

/** The at most k points of a k-d tree nearest to a query among those at a squared distance below squaredRadius,
 * nearest first: knnSearch's answer without the points at or beyond the radius, found without visiting the parts of
 * the tree beyond it. Returns how many were found. */
template <typename TTree>
size_t
SearchNearestWithinRadius(const TTree &  tree,
                          const double * query,
                          size_t         k,
                          double         squaredRadius,
                          size_t *       indices,
                          double *       squaredDistances)
{
  NearestWithinRadiusResultSet result(k, squaredRadius, indices, squaredDistances);
  if (k > 0)
  {
    tree.findNeighbors(result, query, {});
  }
  return result.size();
}

} // namespace detail
} // namespace itk

#endif // itkPointCloudKdTree_h
