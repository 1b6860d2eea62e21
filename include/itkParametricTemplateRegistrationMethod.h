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
#ifndef itkParametricTemplateRegistrationMethod_h
#define itkParametricTemplateRegistrationMethod_h

#include "itkFFDShapeMatchingCompatibility.h"
#include "itkMeshRegistrationMethodBase.h"
#include "itkDataObjectDecorator.h"
#include "itkImage.h"
#include "itkMeshSurfaceDistanceMetricv4.h"
#include "itkParametricTemplateTransform.h"
#include "itkTransform.h"
#include <chrono>
#include <cstdint>
#include <ostream>
#include <string>
#include <vector>

namespace itk
{
/** \class ParametricTemplateRegistrationMethodEnums
 * \brief Enumerations of ParametricTemplateRegistrationMethod.
 *
 * \c Optimizer: the ITK v4 optimizer finding the template weights:
 * - \c OnePlusOneEvolutionary: OnePlusOneEvolutionaryOptimizerv4, the (1+1) evolution strategy of the paper's
 *   parametric method (values only),
 * - \c LBFGS: LBFGSOptimizerv4 (quasi-Newton on the metric's analytic derivative),
 * - \c LBFGSB: LBFGSBOptimizerv4 (the same with optional bounds on the weights).
 *
 * \ingroup FFDShapeMatching
 */
class ParametricTemplateRegistrationMethodEnums
{
public:
  enum class Optimizer : uint8_t
  {
    OnePlusOneEvolutionary,
    LBFGS,
    LBFGSB
  };

  /** How the base transform input (a voxel method's result) enters:
   * - \c Base: its control displacements become the transform's base, the templates add to them;
   * - \c ProjectOntoTemplates: the base stays as the template transform has it, and the initial weights are the
   *   least-squares projection of the input's control displacements onto the templates (for templates that carry
   *   the deformation itself, e.g. known directions per control point: what the voxel result has off those
   *   directions is dropped). */
  enum class BaseTransformMode : uint8_t
  {
    Base,
    ProjectOntoTemplates
  };
};

/** Prints the qualified enumerator name. */
inline std::ostream &
operator<<(std::ostream & out, const ParametricTemplateRegistrationMethodEnums::Optimizer value)
{
  switch (value)
  {
    case ParametricTemplateRegistrationMethodEnums::Optimizer::OnePlusOneEvolutionary:
      return out << "itk::ParametricTemplateRegistrationMethodEnums::Optimizer::OnePlusOneEvolutionary";
    case ParametricTemplateRegistrationMethodEnums::Optimizer::LBFGS:
      return out << "itk::ParametricTemplateRegistrationMethodEnums::Optimizer::LBFGS";
    case ParametricTemplateRegistrationMethodEnums::Optimizer::LBFGSB:
      return out << "itk::ParametricTemplateRegistrationMethodEnums::Optimizer::LBFGSB";
    default:
      return out << "INVALID VALUE FOR itk::ParametricTemplateRegistrationMethodEnums::Optimizer";
  }
}

/** Prints the qualified enumerator name. */
inline std::ostream &
operator<<(std::ostream & out, const ParametricTemplateRegistrationMethodEnums::BaseTransformMode value)
{
  switch (value)
  {
    case ParametricTemplateRegistrationMethodEnums::BaseTransformMode::Base:
      return out << "itk::ParametricTemplateRegistrationMethodEnums::BaseTransformMode::Base";
    case ParametricTemplateRegistrationMethodEnums::BaseTransformMode::ProjectOntoTemplates:
      return out << "itk::ParametricTemplateRegistrationMethodEnums::BaseTransformMode::ProjectOntoTemplates";
    default:
      return out << "INVALID VALUE FOR itk::ParametricTemplateRegistrationMethodEnums::BaseTransformMode";
  }
}

/** \class ParametricTemplateRegistrationMethod
 * \brief Matches a target mesh to a source mesh with a parametric-template B-spline transform (the "Par" method
 * of the FFDShapeMatching pipeline, and the "GO+Par" / "MRF+Par" refinement).
 *
 * The transform is a ParametricTemplateTransform: control displacements base + sum_k pi_k delta_k on a B-spline
 * grid, with fixed templates delta_k (TemplateTransform input: its grid, templates, base and initial weights are
 * copied) and the K weights pi_k estimated. The measure is MeshSurfaceDistanceMetricv4: the mean distance from the
 * target (fixed) mesh's vertices, mapped by T into source space, to the source (moving) surface, through a signed
 * distance map of the source (MovingDistanceImage input, or made from the MovingMesh input) or exactly.
 * The weights are found by an ITK v4 optimizer (Optimizer): LBFGS by default (measured: see the module's
 * benchmark notes), LBFGSB, or the (1+1) evolution strategy of the paper.
 *
 * Inputs: the fixed mesh (index 0, the target; its vertices are used), the moving mesh (the source) and/or the
 * moving signed distance image, the template transform, and an optional base transform (a decorated
 * Transform<double, 3, 3>: connect the transform output of BSplineFFDImageRegistrationMethod or of the MRF
 * method for the refinement; a BSplineTransform on the templates' grid becomes the base exactly, any other
 * transform is resampled onto the grid, see ParametricTemplateTransform::SetBaseFromTransform()).
 * Output: the transform T, target space to source space, as a decorated Transform<double, 3, 3> (the
 * ParametricTemplateTransform; GetParametricTransform() gives it with its own type).
 *
 * The metric uses the process object's NumberOfWorkUnits. Progress is reported per optimizer iteration; an
 * IterationEvent is invoked with each, and the metric value trajectory is kept (GetMetricValues()). The result is never
 * worse than the initial weights: if the optimizer ends at a larger metric value, the initial weights are kept.
 * A run-time limit (MaximumRunTime) stops the optimizer at its first iteration past the limit, with the weights
 * reached (or the initial ones, if better), and skips the exact refinement.
 *
 * \par References
 * The parametric model and its (1+1) evolution strategy: "A comparative analysis of B-spline deformation models
 * in 3D shape matching", section 3.3.
 *
 * \sa ParametricTemplateTransform, MeshSurfaceDistanceMetricv4, BSplineFFDImageRegistrationMethod
 * \ingroup FFDShapeMatching
 */
template <typename TFixedMesh, typename TMovingMesh = TFixedMesh, typename TDistanceImage = Image<float, 3>>
class ITK_TEMPLATE_EXPORT ParametricTemplateRegistrationMethod
  : public MeshRegistrationMethodBase<TFixedMesh, TMovingMesh>
{
public:
  ITK_DISALLOW_COPY_AND_MOVE(ParametricTemplateRegistrationMethod);

  using Self = ParametricTemplateRegistrationMethod;
  using Superclass = MeshRegistrationMethodBase<TFixedMesh, TMovingMesh>;
  using Pointer = SmartPointer<Self>;
  using ConstPointer = SmartPointer<const Self>;

  itkNewMacro(Self);
  itkOverrideGetNameOfClassMacro(ParametricTemplateRegistrationMethod);

  using FixedMeshType = TFixedMesh;
  using MovingMeshType = TMovingMesh;
  using DistanceImageType = TDistanceImage;
  using TransformType = Transform<double, 3, 3>;
  using ParametricTransformType = ParametricTemplateTransform<double, 3>;
  using DecoratedTransformType = DataObjectDecorator<TransformType>;
  using MetricType = MeshSurfaceDistanceMetricv4<TFixedMesh, TMovingMesh, TDistanceImage>;
  using EvaluationEnum = typename MetricType::EvaluationEnum;
  using OptimizerEnum = ParametricTemplateRegistrationMethodEnums::Optimizer;
  using BaseTransformModeEnum = ParametricTemplateRegistrationMethodEnums::BaseTransformMode;

  // FixedMesh (its vertices are mapped by T) and MovingMesh (its surface is measured to; needed unless a
  // MovingDistanceImage is given, and for exact evaluation), GetTransformOutput(), GetTransform() and RandomSeed (of
  // the (1+1) strategy's normal variates): see the superclass.

  /** Optional signed distance image of the moving surface (e.g. from TriangleMeshToVoxelImageFilter). */
  itkSetInputMacro(MovingDistanceImage, DistanceImageType);
  itkGetInputMacro(MovingDistanceImage, DistanceImageType);

  /** The templates: grid, templates, base and initial weights of this transform are used (it is not changed). */
  itkSetGetDecoratedObjectInputMacro(TemplateTransform, ParametricTransformType);

  /** Optional base deformation replacing the template transform's base (GO or MRF result). */
  itkSetGetDecoratedObjectInputMacro(BaseTransform, TransformType);

  /** The estimated transform as a ParametricTemplateTransform (null before Update()). */
  const ParametricTransformType *
  GetParametricTransform() const;

  /** Optimizer. Default: LBFGS. */
  itkSetEnumMacro(Optimizer, OptimizerEnum);
  itkGetEnumMacro(Optimizer, OptimizerEnum);

  /** Distance evaluation of the metric. Default: LinearDistanceMap. */
  itkSetEnumMacro(Evaluation, EvaluationEnum);
  itkGetEnumMacro(Evaluation, EvaluationEnum);

  /** Voxel size (mm) of the distance map made from the moving mesh. Default: 1. */
  itkSetClampMacro(DistanceMapSpacing, double, 1e-6, NumericTraits<double>::max());
  itkGetConstMacro(DistanceMapSpacing, double);

  /** Margin (mm) of the distance map made from the moving mesh around its bounds. Default: 10. */
  itkSetClampMacro(DistanceMapMargin, double, 0.0, NumericTraits<double>::max());
  itkGetConstMacro(DistanceMapMargin, double);

  /** Minimize the mean squared distance (On), a smooth measure on which the quasi-Newton optimizers converge, or
   * the mean absolute distance of the paper (Off), which has a kink wherever a vertex crosses the surface.
   * Default: On. */
  itkSetMacro(UseSquaredDistance, bool);
  itkGetConstMacro(UseSquaredDistance, bool);
  itkBooleanMacro(UseSquaredDistance);

  /** After a distance-map stage, this many more iterations with exact point-to-triangle distances (needs the
   * moving mesh; 0: none). The map's interpolation error (a few hundredths of a voxel near faceted surfaces)
   * otherwise moves the optimum. Default: 50. */
  itkSetMacro(NumberOfExactRefinementIterations, unsigned int);
  itkGetConstMacro(NumberOfExactRefinementIterations, unsigned int);

  /** Maximum optimizer iterations. Default: 100. */
  itkSetClampMacro(NumberOfIterations, unsigned int, 1, NumericTraits<unsigned int>::max());
  itkGetConstMacro(NumberOfIterations, unsigned int);

  /** Wall-clock limit of Update() in seconds; 0 (the default) means none, and a negative value is clamped to 0.
   * Checked at every optimizer iteration: the first iteration past it stops the optimizer (the exact refinement is
   * then skipped) and GetTimeLimitReached() is true. */
  itkSetClampMacro(MaximumRunTime, double, 0.0, NumericTraits<double>::max());
  itkGetConstMacro(MaximumRunTime, double);

  /** Whether the last Update() stopped at MaximumRunTime. */
  itkGetConstMacro(TimeLimitReached, bool);

  /** LBFGS / LBFGSB gradient tolerance, or the (1+1) strategy's search-radius (Frobenius norm) limit.
   * Default: 1e-5. */
  itkSetClampMacro(ConvergenceTolerance, double, 0.0, NumericTraits<double>::max());
  itkGetConstMacro(ConvergenceTolerance, double);

  /** Bound on |pi_k| for LBFGSB; 0 means unbounded. Default: 0. */
  itkSetClampMacro(WeightBound, double, 0.0, NumericTraits<double>::max());
  itkGetConstMacro(WeightBound, double);

  /** Initial search radius of the (1+1) strategy, in weight units. Default: 0.5. */
  itkSetClampMacro(InitialSearchRadius, double, 1e-12, NumericTraits<double>::max());
  itkGetConstMacro(InitialSearchRadius, double);

  /** How the base transform input is used. Default: ProjectOntoTemplates. */
  itkSetEnumMacro(BaseTransformMode, BaseTransformModeEnum);
  itkGetEnumMacro(BaseTransformMode, BaseTransformModeEnum);

  /** Resample a base transform that is not a BSplineTransform on the templates' grid onto the grid (On), or refuse
   * it (Off). Default: On. */
  itkSetMacro(ResampleBaseTransform, bool);
  itkGetConstMacro(ResampleBaseTransform, bool);
  itkBooleanMacro(ResampleBaseTransform);

  /** Metric value after each optimizer iteration of the last Update(). */
  const std::vector<double> &
  GetMetricValues() const
  {
    return m_MetricValues;
  }

  /** Metric value (the optimized measure, of the first stage) at the initial weights of the last Update(). */
  itkGetConstMacro(InitialMetricValue, double);

  /** Metric value (the optimized measure, of the last stage) of the result of the last Update(). */
  itkGetConstMacro(FinalMetricValue, double);

  /** Mean distance (mm) from the mapped fixed vertices to the moving surface at the initial weights, evaluated as
   * the first stage evaluates (Evaluation). */
  itkGetConstMacro(InitialMeanDistance, double);

  /** Mean distance (mm) from the mapped fixed vertices to the moving surface for the result, evaluated as the last
   * stage evaluates (exactly after an exact refinement). */
  itkGetConstMacro(FinalMeanDistance, double);

  /** The optimizer's stop condition of the last Update(). */
  itkGetConstReferenceMacro(StopConditionDescription, std::string);

protected:
  ParametricTemplateRegistrationMethod();
  ~ParametricTemplateRegistrationMethod() override = default;

  void
  VerifyPreconditions() const override;

  void
  GenerateData() override;

  void
  PrintSelf(std::ostream & os, Indent indent) const override;

private:
  /** Runs the chosen optimizer on the metric; returns its final position. */
  typename ParametricTransformType::ParametersType
  RunOptimizer(MetricType * metric, const ParametricTransformType * transform, unsigned int iterations);

  /** Checks the inputs' contents (after the upstream pipeline ran); throws for empty meshes, no templates, a
   * refused base. */
  void
  VerifyInputData() const;

  /** One optimization stage with the given evaluation; keeps the weights only if the measure decreased. */
  void
  RunStage(ParametricTransformType * transform, EvaluationEnum evaluation, unsigned int iterations, bool first);

  OptimizerEnum         m_Optimizer{ OptimizerEnum::LBFGS };
  EvaluationEnum        m_Evaluation{ EvaluationEnum::LinearDistanceMap };
  double                m_DistanceMapSpacing{ 1.0 };
  double                m_DistanceMapMargin{ 10.0 };
  unsigned int          m_NumberOfIterations{ 100 };
  double                m_ConvergenceTolerance{ 1e-5 };
  double                m_WeightBound{ 0.0 };
  double                m_InitialSearchRadius{ 0.5 };
  bool                  m_ResampleBaseTransform{ true };
  BaseTransformModeEnum m_BaseTransformMode{ BaseTransformModeEnum::ProjectOntoTemplates };
  bool                  m_UseSquaredDistance{ true };
  unsigned int          m_NumberOfExactRefinementIterations{ 50 };
  double                m_MaximumRunTime{ 0.0 };

  bool                                  m_TimeLimitReached{ false };
  std::chrono::steady_clock::time_point m_StartTime{};

  std::vector<double> m_MetricValues{};
  double              m_InitialMetricValue{ 0.0 };
  double              m_FinalMetricValue{ 0.0 };
  double              m_InitialMeanDistance{ 0.0 };
  double              m_FinalMeanDistance{ 0.0 };
  std::string         m_StopConditionDescription{};
};
} // namespace itk

#ifndef ITK_MANUAL_INSTANTIATION
#  include "itkParametricTemplateRegistrationMethod.hxx"
#endif

#endif // itkParametricTemplateRegistrationMethod_h
