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
#ifndef itkMeshSurfaceDistanceCalculator_h
#define itkMeshSurfaceDistanceCalculator_h

#include "itkFFDShapeMatchingCompatibility.h"
#include "itkObject.h"
#include "itkObjectFactory.h"
#include "FFDShapeMatchingDetail/itkTriangleBoundingVolumeHierarchy.h"
#include <vector>

namespace itk
{
namespace detail
{
/** Percentile of values (fraction in [0, 1]) with linear interpolation between order statistics
 * (position fraction * (n - 1) in the sorted values). values is reordered. Returns 0 for no values. */
inline double
ComputePercentile(std::vector<double> & values, double fraction)
{
  if (values.empty())
  {
    return 0.0;
  }
  fraction = std::min(1.0, std::max(0.0, fraction));
  const double      position = fraction * static_cast<double>(values.size() - 1);
  const std::size_t lower = static_cast<std::size_t>(position);
  std::nth_element(values.begin(), values.begin() + lower, values.end());
  const double lowerValue = values[lower];
  if (lower + 1 >= values.size())
  {
    return lowerValue;
  }
  const double upperValue = *std::min_element(values.begin() + lower + 1, values.end());
  return lowerValue + (position - static_cast<double>(lower)) * (upperValue - lowerValue);
}
} // namespace detail

/** \class MeshSurfaceDistanceCalculator
 * \brief Exact distances from the vertices of one mesh to the triangle surface of another.
 *
 * For every vertex \f$v\f$ of the source mesh A, the calculator computes the exact Euclidean distance
 * \f$d(v) = \min_{t \in B} \mathrm{dist}(v, t)\f$ to the closest triangle t of the target mesh B (the
 * filled triangle, not its plane; point-to-triangle distance by detail::ClosestPointOnTriangle, degenerate
 * triangles treated as their edges). The closest triangle is found through a bounding-box hierarchy
 * over B's triangles (detail::TriangleBoundingVolumeHierarchy, nearest search with pruning), so the result
 * equals the brute-force minimum over all triangles. Vertices are processed in parallel.
 *
 * From the per-vertex distances it reports the mean (the mean directed Hausdorff distance of Table 2 and 3 of
 * "A comparative analysis of B-spline deformation models in 3D shape matching"), the maximum (the directed
 * Hausdorff distance \f$h(A, B)\f$), the root mean square, the median and the 95th percentile (percentiles
 * interpolate linearly between order statistics). ComputeSymmetricHausdorffDistance() gives
 * \f$\max(h(A, B), h(B, A))\f$.
 *
 * Target cells that are triangles or polygons (fan-triangulated) form the surface; other cells are ignored. All
 * source vertices are measured, in point-container order; GetDistances() holds them and MakePointData()
 * returns them as a point-data container for the source mesh (e.g. to colour it by error).
 *
 * \code
 * auto calculator = itk::MeshSurfaceDistanceCalculator<MeshType>::New();
 * calculator->SetSourceMesh(deformedSource);
 * calculator->SetTargetMesh(target);
 * calculator->Compute();
 * std::cout << calculator->GetMeanDistance() << " " << calculator->GetMaximumDistance() << std::endl;
 * \endcode
 *
 * \sa PointCorrespondenceErrorCalculator, HausdorffDistanceImageFilter
 *
 * \ingroup FFDShapeMatching
 */
template <typename TSourceMesh, typename TTargetMesh = TSourceMesh>
class ITK_TEMPLATE_EXPORT MeshSurfaceDistanceCalculator : public Object
{
public:
  ITK_DISALLOW_COPY_AND_MOVE(MeshSurfaceDistanceCalculator);

  using Self = MeshSurfaceDistanceCalculator;
  using Superclass = Object;
  using Pointer = SmartPointer<Self>;
  using ConstPointer = SmartPointer<const Self>;

  itkNewMacro(Self);
  itkOverrideGetNameOfClassMacro(MeshSurfaceDistanceCalculator);

  using SourceMeshType = TSourceMesh;
  using TargetMeshType = TTargetMesh;
  using DistanceContainerType = std::vector<double>;
  using PointDataContainerType = typename SourceMeshType::PointDataContainer;
  using HierarchyType = detail::TriangleBoundingVolumeHierarchy;

  static_assert(SourceMeshType::PointDimension == 3 && TargetMeshType::PointDimension == 3,
                "MeshSurfaceDistanceCalculator measures three-dimensional meshes.");

  /** Mesh whose vertices are measured (A). */
  itkSetConstObjectMacro(SourceMesh, SourceMeshType);
  itkGetConstObjectMacro(SourceMesh, SourceMeshType);

  /** Mesh whose triangle surface is measured to (B). */
  itkSetConstObjectMacro(TargetMesh, TargetMeshType);
  itkGetConstObjectMacro(TargetMesh, TargetMeshType);

  /** Number of work units; 0 (default) uses the global default of MultiThreaderBase. */
  itkSetMacro(NumberOfWorkUnits, unsigned int);
  itkGetConstMacro(NumberOfWorkUnits, unsigned int);

  /** Computes all distances and statistics. Throws if a mesh is missing, the source has no vertex or the
   * target has no triangle. */
  void
  Compute();

  /** Mean of the per-vertex distances: the mean directed Hausdorff distance from source to target. */
  itkGetConstMacro(MeanDistance, double);

  /** Maximum of the per-vertex distances: the directed Hausdorff distance from source to target. */
  itkGetConstMacro(MaximumDistance, double);

  /** Root mean square of the per-vertex distances. */
  itkGetConstMacro(RootMeanSquareDistance, double);

  /** Median of the per-vertex distances. */
  itkGetConstMacro(MedianDistance, double);

  /** 95th percentile of the per-vertex distances. */
  itkGetConstMacro(Percentile95Distance, double);

  /** Exact distance of each source vertex to the target surface, in point-container order. */
  itkGetConstReferenceMacro(Distances, DistanceContainerType);

  /** Percentile (fraction in [0, 1]) of the per-vertex distances of the last Compute(). */
  double
  GetDistancePercentile(double fraction) const;

  /** The per-vertex distances as point data of the source mesh (same point ids). */
  typename PointDataContainerType::Pointer
  MakePointData() const;

  /** Symmetric Hausdorff distance max(h(A, B), h(B, A)) of two triangle meshes. */
  static double
  ComputeSymmetricHausdorffDistance(const SourceMeshType * meshA, const TargetMeshType * meshB);

  /** Collects the triangles of a mesh (triangle and polygon cells, polygons fan-triangulated). */
  template <typename TMesh>
  static std::vector<typename HierarchyType::Triangle>
  ExtractTriangles(const TMesh * mesh);

protected:
  MeshSurfaceDistanceCalculator() = default;
  ~MeshSurfaceDistanceCalculator() override = default;
  void
  PrintSelf(std::ostream & os, Indent indent) const override;

private:
  typename SourceMeshType::ConstPointer m_SourceMesh;
  typename TargetMeshType::ConstPointer m_TargetMesh;
  unsigned int                          m_NumberOfWorkUnits{ 0 };
  double                                m_MeanDistance{ 0.0 };
  double                                m_MaximumDistance{ 0.0 };
  double                                m_RootMeanSquareDistance{ 0.0 };
  double                                m_MedianDistance{ 0.0 };
  double                                m_Percentile95Distance{ 0.0 };
  DistanceContainerType                 m_Distances;
  std::vector<IdentifierType>           m_PointIdentifiers;
};
} // namespace itk

#ifndef ITK_MANUAL_INSTANTIATION
#  include "itkMeshSurfaceDistanceCalculator.hxx"
#endif

#endif // itkMeshSurfaceDistanceCalculator_h
