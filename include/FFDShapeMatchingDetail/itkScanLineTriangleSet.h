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
#ifndef itkScanLineTriangleSet_h
#define itkScanLineTriangleSet_h

#include "FFDShapeMatchingExport.h"
#include "itkIndent.h"
#include "FFDShapeMatchingDetail/itkScanLineWindingNumber.h"
#include "FFDShapeMatchingDetail/itkTriangleBoundingVolumeHierarchy.h"

#include <array>
#include <cmath>
#include <ostream>
#include <string>
#include <atomic>
#include <cstdint>
#include <mutex>
#include <vector>

namespace itk
{
namespace detail
{
/** \class ScanLineTriangleSet
 * \brief The triangles of a voxelization and what the scan-line path of TriangleMeshToVoxelImageFilter asks of
 * them, row by row: inside flags and squared distances of the voxel centres of one grid row.
 *
 * SetTriangles() takes the mesh's triangles (and, for the modes that decide inside and outside, the welded vertex
 * numbers of their corners, from which the winding number's gradient bound is built); the bounding-volume
 * hierarchy is built on first use, once, from any thread. Prepare() maps the triangles into the continuous-index
 * space of the output grid and bins them by the rows of the requested region: by the rows their projection
 * crosses (for the inside flags) and by the rows they reach within a distance (for the distances). The row
 * queries are then const and may run from many threads.
 *
 * The geometry is plain double arithmetic, independent of the filter's mesh and image types: it is compiled once
 * into the module's library.
 *
 * \ingroup FFDShapeMatching
 */
class FFDShapeMatching_EXPORT ScanLineTriangleSet
{
public:
  using HierarchyType = TriangleBoundingVolumeHierarchy;
  using VectorType = HierarchyType::VectorType;
  using TriangleType = HierarchyType::Triangle;

  /** The output grid and the requested region that Prepare() bins for. */
  struct GridGeometry
  {
    double        InverseDirection[3][3]{}; // Inverse of the grid's direction matrix.
    double        Spacing[3]{};
    double        Origin[3]{};
    long          RegionIndex[3]{};
    unsigned long RegionSize[3]{};
  };

  ScanLineTriangleSet() = default;
  ScanLineTriangleSet(const ScanLineTriangleSet &) = delete;
  ScanLineTriangleSet &
  operator=(const ScanLineTriangleSet &) = delete;

  /** Takes the triangles; corners holds the welded vertex numbers of each triangle's corners when needInside
   * (the winding number's gradient bound is built from them), and is ignored otherwise. */
  void
  SetTriangles(std::vector<TriangleType>                         triangles,
               const std::vector<std::array<std::uint32_t, 3>> & corners,
               bool                                              needInside);

  const std::vector<TriangleType> &
  GetTriangles() const
  {
    return m_Triangles;
  }

  /** The bounding-volume hierarchy over the triangles, built on first use (thread-safe). */
  const HierarchyType &
  GetHierarchy() const;

  /** Number of nodes of the hierarchy built so far (0 before the first use). */
  std::size_t
  GetNumberOfHierarchyNodes() const
  {
    return m_Hierarchy.GetNumberOfNodes();
  }

  /** Maps the triangles into the grid's continuous-index space and bins them for the rows of the requested region:
   * by crossing when needSign; by reach when reachDistance >= 0 (for reachOnly modes, the triangles whose grown
   * bounding box meets the region are listed instead, for a triangle-by-triangle pass). */
  void
  Prepare(const GridGeometry & grid, bool needSign, double reachDistance, bool reachOnly);

  /** Inside flags of the voxels first, ..., first + inside.size() - 1 of the row (j, k), whose physical centres
   * are points; spacingAlongRow is the grid's spacing along the row, beta the winding number's far-field accuracy
   * and absoluteWindingNumber its inside rule (see IsInside()). */
  void
  ComputeRowInside(long                            first,
                   long                            j,
                   long                            k,
                   const std::vector<VectorType> & points,
                   double                          spacingAlongRow,
                   double                          beta,
                   bool                            absoluteWindingNumber,
                   std::vector<char> &             inside) const;

  /** Exact squared distances from the voxels of the row (j, k) (physical centres in points) to the closest
   * triangle, for the voxels within radius of a triangle (infinity elsewhere), for a grid of the given spacing and
   * an orthonormal direction. With anyWithin, a voxel stops at the first triangle within radius. */
  void
  ComputeRowSquaredDistances(long                            first,
                             long                            j,
                             long                            k,
                             const double                    spacing[3],
                             double                          radius,
                             bool                            anyWithin,
                             const std::vector<VectorType> & points,
                             std::vector<double> &           squaredDistances) const;

  /** Inside means |w| > 1/2 (absoluteWindingNumber) or w > 1/2, w the winding number. */
  static bool
  IsInside(bool absoluteWindingNumber, double windingNumber)
  {
    return (absoluteWindingNumber ? std::abs(windingNumber) : windingNumber) > 0.5;
  }

  /** True when the winding-number interval [value - radius, value + radius] lies on one side of the thresholds. */
  static bool
  IsDecided(bool absoluteWindingNumber, double value, double radius)
  {
    const auto straddles = [value, radius](double threshold) {
      return value - radius <= threshold && value + radius >= threshold;
    };
    return !straddles(0.5) && !(absoluteWindingNumber && straddles(-0.5));
  }

  /** The triangles in the grid's continuous-index space (after Prepare()). */
  const std::vector<IndexSpaceTriangle> &
  GetIndexTriangles() const
  {
    return m_IndexTriangles;
  }

  /** The triangles reaching the requested region (after Prepare() for a reachOnly mode). */
  const std::vector<std::uint32_t> &
  GetRegionTriangles() const
  {
    return m_RegionTriangles;
  }

  /** The reach distance in index units per axis, grown a little for rounding (after Prepare()). */
  const std::array<double, 3> &
  GetReachMargin() const
  {
    return m_ReachMargin;
  }

  /** Prints the sizes of the sets (edges with a net current, bins, region triangles, orientation). */
  void
  Print(std::ostream & os, Indent indent) const;

private:
  std::vector<TriangleType>       m_Triangles{};
  mutable HierarchyType           m_Hierarchy{};
  mutable std::atomic<bool>       m_HierarchyBuilt{ false };
  mutable std::mutex              m_HierarchyMutex{};
  WindingNumberGradientBound      m_GradientBound{};
  std::vector<IndexSpaceTriangle> m_IndexTriangles{};
  ScanLineTriangleBins            m_CrossingBins{};
  ScanLineTriangleBins            m_ReachBins{};
  std::array<double, 3>           m_ReachMargin{ { 0.0, 0.0, 0.0 } };
  std::vector<std::uint32_t>      m_RegionTriangles{}; // Reaching the requested region (occupancy, band).
  int                             m_OrientationSign{ 1 };
  /** Per triangle, for ComputeRowSquaredDistances() at the spacing of the last Prepare(): its first corner in the
   * grid's frame scaled to physical units, and its plane's unit normal there (zero for a degenerate triangle). */
  struct ScaledPlane
  {
    std::array<double, 3> corner;
    std::array<double, 3> normal;
  };
  std::vector<ScaledPlane> m_ScaledPlanes{};
  std::array<double, 3>    m_ScaledPlaneSpacing{ { 0.0, 0.0, 0.0 } };

  /** The scaled plane of an index-space triangle for the given spacing. */
  static ScaledPlane
  MakeScaledPlane(const IndexSpaceTriangle & t, const double spacing[3]);
};
} // namespace detail
} // namespace itk

#endif // itkScanLineTriangleSet_h
