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
#ifndef itkMeshSurfaceDistanceMetricv4_h
#define itkMeshSurfaceDistanceMetricv4_h

#include "itkFFDShapeMatchingCompatibility.h"
#include "itkBSplineInterpolateImageFunction.h"
#include "itkImage.h"
#include "itkObjectToObjectMetric.h"
#include "FFDShapeMatchingDetail/itkTriangleBoundingVolumeHierarchy.h"
#include <array>
#include <cstdint>
#include <ostream>
#include <vector>

namespace itk
{
/** \class MeshSurfaceDistanceMetricv4Enums
 * \brief Enumerations of MeshSurfaceDistanceMetricv4.
 *
 * \c Evaluation: how the distance from a mapped point to the moving surface is obtained:
 * - \c LinearDistanceMap: trilinear interpolation of the signed distance map,
 * - \c BSplineDistanceMap: cubic B-spline interpolation of the signed distance map,
 * - \c ExactPointToTriangle: exact point-to-triangle distance to the moving mesh (for checking).
 *
 * \ingroup FFDShapeMatching
 */
class MeshSurfaceDistanceMetricv4Enums
{
public:
  enum class Evaluation : uint8_t
  {
    LinearDistanceMap,
    BSplineDistanceMap,
    ExactPointToTriangle
  };
};

/** Prints the qualified enumerator name. */
inline std::ostream &
operator<<(std::ostream & out, const MeshSurfaceDistanceMetricv4Enums::Evaluation value)
{
  switch (value)
  {
    case MeshSurfaceDistanceMetricv4Enums::Evaluation::LinearDistanceMap:
      return out << "itk::MeshSurfaceDistanceMetricv4Enums::Evaluation::LinearDistanceMap";
    case MeshSurfaceDistanceMetricv4Enums::Evaluation::BSplineDistanceMap:
      return out << "itk::MeshSurfaceDistanceMetricv4Enums::Evaluation::BSplineDistanceMap";
    case MeshSurfaceDistanceMetricv4Enums::Evaluation::ExactPointToTriangle:
      return out << "itk::MeshSurfaceDistanceMetricv4Enums::Evaluation::ExactPointToTriangle";
    default:
      return out << "INVALID VALUE FOR itk::MeshSurfaceDistanceMetricv4Enums::Evaluation";
  }
}

/** \class MeshSurfaceDistanceMetricv4
 * \brief Mean distance from the fixed mesh's vertices, mapped by the moving transform, to the moving mesh's surface.
 *
 * The value is \f[ f(\pi) = \frac{1}{n} \sum_{i=1}^{n} |D(T_\pi(x_i))| \f] over the vertices \f$x_i\f$ of the
 * fixed mesh (in shape matching: the target), T the moving transform (target space to source space) and D the
 * signed distance to the moving mesh's surface (the source): the mean directed Hausdorff distance of
 * "A comparative analysis of B-spline deformation models in 3D shape matching". Its derivative, returned as the
 * v4 metrics do (the negative gradient, the direction an optimizer steps along), is
 * \f[ -\frac{1}{n}\sum_i \mathrm{sign}(D)\, \nabla D(T(x_i))^T \frac{\partial T}{\partial \pi}(x_i) . \f]
 *
 * D comes from a signed distance image of the moving surface: MovingDistanceImage when set, otherwise made in
 * Initialize() from the moving mesh by TriangleMeshToVoxelImageFilter (SignedDistance, exact everywhere, voxel
 * DistanceMapSpacing, grid = mesh bounds grown by DistanceMapMargin on each side; UnsignedDistanceMap for open
 * surfaces). It is interpolated trilinearly or by cubic B-splines (Evaluation); the derivative is that of the
 * interpolant, so it matches finite differences of the value. A point outside the image is measured at the
 * closest point of the image box (in index space) plus its distance to it. ExactPointToTriangle evaluates the
 * exact distance to the moving mesh's triangles instead (detail::TriangleBoundingVolumeHierarchy; the gradient
 * is the unit vector from the closest surface point), for checking the map's interpolation error.
 *
 * A ParametricTemplateTransform as moving transform is differentiated sparsely
 * (AccumulateJacobianTransposeProduct()); any other global transform through its dense
 * ComputeJacobianWithRespectToParameters(). Transforms with local support are refused. The fixed transform is
 * not used: the fixed vertices are taken as they are. Points are processed in parallel (NumberOfWorkUnits).
 *
 * \sa ParametricTemplateRegistrationMethod, MeshSurfaceDistanceCalculator, TriangleMeshToVoxelImageFilter
 * \ingroup FFDShapeMatching
 */
template <typename TFixedMesh, typename TMovingMesh = TFixedMesh, typename TDistanceImage = Image<float, 3>>
class ITK_TEMPLATE_EXPORT MeshSurfaceDistanceMetricv4 : public ObjectToObjectMetric<3, 3>
{
public:
  ITK_DISALLOW_COPY_AND_MOVE(MeshSurfaceDistanceMetricv4);

  using Self = MeshSurfaceDistanceMetricv4;
  using Superclass = ObjectToObjectMetric<3, 3>;
  using Pointer = SmartPointer<Self>;
  using ConstPointer = SmartPointer<const Self>;

  itkNewMacro(Self);
  itkOverrideGetNameOfClassMacro(MeshSurfaceDistanceMetricv4);

  using FixedMeshType = TFixedMesh;
  using MovingMeshType = TMovingMesh;
  using DistanceImageType = TDistanceImage;
  using typename Superclass::MeasureType;
  using typename Superclass::DerivativeType;
  using typename Superclass::ParametersType;
  using typename Superclass::MovingTransformType;
  using PointType = Point<double, 3>;
  using VectorType = Vector<double, 3>;
  using EvaluationEnum = MeshSurfaceDistanceMetricv4Enums::Evaluation;

  static_assert(TFixedMesh::PointDimension == 3 && TMovingMesh::PointDimension == 3 &&
                  TDistanceImage::ImageDimension == 3,
                "MeshSurfaceDistanceMetricv4 works on three-dimensional meshes and images.");

  /** Mesh whose vertices are mapped (the target). */
  itkSetConstObjectMacro(FixedMesh, FixedMeshType);
  itkGetConstObjectMacro(FixedMesh, FixedMeshType);

  /** Mesh whose surface is measured to (the source); needed for ExactPointToTriangle or without a distance image. */
  itkSetConstObjectMacro(MovingMesh, MovingMeshType);
  itkGetConstObjectMacro(MovingMesh, MovingMeshType);

  /** Signed distance image of the moving surface (negative inside). Default: none, made from the moving mesh. */
  itkSetConstObjectMacro(MovingDistanceImage, DistanceImageType);
  itkGetConstObjectMacro(MovingDistanceImage, DistanceImageType);

  /** How distances are evaluated. Default: LinearDistanceMap. */
  itkSetEnumMacro(Evaluation, EvaluationEnum);
  itkGetEnumMacro(Evaluation, EvaluationEnum);

  /** Voxel size (mm) of the distance map made from the moving mesh. Default: 1. */
  itkSetClampMacro(DistanceMapSpacing, double, 1e-6, NumericTraits<double>::max());
  itkGetConstMacro(DistanceMapSpacing, double);

  /** Margin (mm) around the moving mesh's bounds of the distance map made from it. Default: 10. */
  itkSetClampMacro(DistanceMapMargin, double, 0.0, NumericTraits<double>::max());
  itkGetConstMacro(DistanceMapMargin, double);

  /** Make the distance map unsigned (for open moving surfaces). Default: Off. */
  itkSetMacro(UnsignedDistanceMap, bool);
  itkGetConstMacro(UnsignedDistanceMap, bool);
  itkBooleanMacro(UnsignedDistanceMap);

  /** Average the squared distances \f$D^2\f$ instead of \f$|D|\f$: a smooth measure (the mean absolute distance
   * has a kink wherever a vertex crosses the surface), on which quasi-Newton optimizers converge. Default: Off. */
  itkSetMacro(SquaredDistance, bool);
  itkGetConstMacro(SquaredDistance, bool);
  itkBooleanMacro(SquaredDistance);

  /** Number of work units; 0 (default) uses the global default of MultiThreaderBase. */
  itkSetMacro(NumberOfWorkUnits, unsigned int);
  itkGetConstMacro(NumberOfWorkUnits, unsigned int);

  /** The distance image in use after Initialize() (given or made). */
  itkGetConstObjectMacro(DistanceImage, DistanceImageType);

  /** Number of fixed vertices mapped outside the distance image in the last evaluation. */
  itkGetConstMacro(NumberOfPointsOutsideDistanceImage, SizeValueType);

  /** Checks the inputs, collects the fixed vertices, makes the distance map or the triangle hierarchy. */
  void
  Initialize() override;

  MeasureType
  GetValue() const override;

  void
  GetDerivative(DerivativeType & derivative) const override;

  void
  GetValueAndDerivative(MeasureType & value, DerivativeType & derivative) const override;

  /** |D| at a point of the moving space and, if gradient is not null, its gradient. */
  double
  EvaluateDistance(const PointType & point, VectorType * gradient) const;

  bool
  SupportsArbitraryVirtualDomainSamples() const override
  {
    return false;
  }

protected:
  MeshSurfaceDistanceMetricv4();
  ~MeshSurfaceDistanceMetricv4() override = default;

  void
  PrintSelf(std::ostream & os, Indent indent) const override;

private:
  using InterpolatorType = BSplineInterpolateImageFunction<DistanceImageType, double, double>;
  using HierarchyType = detail::TriangleBoundingVolumeHierarchy;

  /** Value, and derivative when requested. */
  void
  Evaluate(MeasureType & value, DerivativeType * derivative) const;

  double
  EvaluateMapDistance(const PointType & point, VectorType * gradient) const;

  double
  EvaluateExactDistance(const PointType & point, VectorType * gradient) const;

  /** Fills the uniform cell grid of the triangles (after the hierarchy is built). */
  void
  BuildTriangleGrid();

  typename FixedMeshType::ConstPointer     m_FixedMesh;
  typename MovingMeshType::ConstPointer    m_MovingMesh;
  typename DistanceImageType::ConstPointer m_MovingDistanceImage;
  EvaluationEnum                           m_Evaluation{ EvaluationEnum::LinearDistanceMap };
  double                                   m_DistanceMapSpacing{ 1.0 };
  double                                   m_DistanceMapMargin{ 10.0 };
  bool                                     m_UnsignedDistanceMap{ false };
  bool                                     m_SquaredDistance{ false };
  unsigned int                             m_NumberOfWorkUnits{ 0 };
  typename DistanceImageType::ConstPointer m_DistanceImage;
  mutable SizeValueType                    m_NumberOfPointsOutsideDistanceImage{ 0 };

  std::vector<PointType>                        m_FixedPoints;
  typename InterpolatorType::Pointer            m_Interpolator;
  Matrix<double, 3, 3>                          m_PhysicalToIndex;
  Matrix<double, 3, 3>                          m_IndexToPhysical;
  PointType                                     m_MapOrigin;
  Size<3>                                       m_MapSize{};
  const typename DistanceImageType::PixelType * m_MapBuffer{ nullptr };
  HierarchyType                                 m_Hierarchy;
  std::vector<std::array<double, 6>>            m_TriangleBounds;
  // Uniform grid over the triangles' boxes (cell lists in CSR form): the closest triangle for the exact gradient.
  std::array<double, 3>        m_CellOrigin{};
  double                       m_CellSize{ 1.0 };
  std::array<SizeValueType, 3> m_CellCounts{};
  std::vector<SizeValueType>   m_CellOffsets;
  std::vector<std::uint32_t>   m_CellTriangles;
};
} // namespace itk

#ifndef ITK_MANUAL_INSTANTIATION
#  include "itkMeshSurfaceDistanceMetricv4.hxx"
#endif

#endif // itkMeshSurfaceDistanceMetricv4_h
