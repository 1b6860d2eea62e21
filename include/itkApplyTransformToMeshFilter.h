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
#ifndef itkApplyTransformToMeshFilter_h
#define itkApplyTransformToMeshFilter_h

#include "itkFFDShapeMatchingCompatibility.h"
#include "itkDataObjectDecorator.h"
#include "itkMeshToMeshFilter.h"
#include "FFDShapeMatchingDetail/itkSpatialJacobianEvaluator.h"
#include "itkTransform.h"
#include <vector>

namespace itk
{
/** \class ApplyTransformToMeshFilter
 * \brief Moves every vertex of a mesh by a transform, or by the transform's inverse.
 *
 * Forward mode (InverseOff, the default) writes \f$T(p)\f$ for every input vertex \f$p\f$.
 * Inverse mode (InverseOn) writes the \f$x\f$ that solves \f$T(x) = p\f$, for transforms that have
 * no closed-form inverse such as BSplineTransform. This is how a registration result
 * \f$T\f$ : target space \f$\to\f$ source space moves the source mesh onto the target.
 *
 * The inverse is found per vertex by damped Newton iteration with the spatial Jacobian of the
 * transform, starting at \f$x_0 = p - (T(p) - p)\f$ (or at \f$p\f$ if that is closer). A Newton step is
 * halved until the residual \f$|T(x) - p|\f$ decreases; if it does not, or the Jacobian is singular,
 * fixed-point iteration \f$x \leftarrow x + (p - T(x))\f$ (damped the same way) continues from the
 * best estimate. A vertex has converged when its residual is below InverseTolerance (mm) within
 * MaximumNumberOfInverseIterations iterations of each scheme. A scheme also stops when one of its
 * iterations lowers the residual by less than MinimumInverseResidualDecrease (a fraction of the residual): where
 * a vertex has no preimage the residual levels off above zero, and the iterations would otherwise go on, each with
 * up to 30 halvings, for a gain of a millionth of it. A vertex that has not converged keeps
 * its best estimate and is flagged: GetInverseConverged() holds one flag per vertex (in point
 * container order), GetInverseResiduals() the final residual per vertex, and
 * GetNumberOfNonConvergedPoints() their count. These are valid after Update() in inverse mode.
 *
 * A vertex can lack a preimage altogether: a folding transform does not cover all of space, and BSplineTransform
 * jumps to zero displacement outside its domain, so inside the domain, closer to its boundary than the largest
 * displacement, some points are images of nothing. Such vertices are flagged. Vertices outside the domain of a
 * B-spline map to themselves (converged). Farther inside than the largest displacement, a non-folding B-spline
 * always has a preimage and the inverse converges.
 *
 * The spatial Jacobian comes from detail::SpatialJacobianEvaluator: analytic for cubic
 * BSplineTransform (ITK 5.2's lacks ComputeJacobianWithRespectToPosition) and for CompositeTransform
 * by the chain rule, the transform's own otherwise, central finite differences as a last resort.
 *
 * The transform is a decorated pipeline input, so the transform output of a registration method
 * (e.g. ImageRegistrationMethodv4::GetTransformOutput()) connects directly with SetTransformInput(),
 * and a change of the transform re-executes the filter. TTransform must then be the registration's
 * output transform type. Vertex ids and order, cells, cell links, point data and cell data are
 * passed through unchanged. Vertices are processed in parallel.
 *
 * \code
 * using FilterType = itk::ApplyTransformToMeshFilter<MeshType, MeshType, TransformType>;
 * auto filter = FilterType::New();
 * filter->SetInput(sourceMesh);
 * filter->SetTransformInput(registration->GetTransformOutput());
 * filter->InverseOn();
 * filter->Update();
 * std::cout << filter->GetNumberOfNonConvergedPoints() << " vertices did not converge\n";
 * \endcode
 *
 * \sa TransformMeshFilter, BSplineTransform, ImageRegistrationMethodv4
 *
 * \ingroup FFDShapeMatching
 */
template <typename TInputMesh,
          typename TOutputMesh,
          typename TTransform = Transform<double, TInputMesh::PointDimension, TInputMesh::PointDimension>>
class ITK_TEMPLATE_EXPORT ApplyTransformToMeshFilter : public MeshToMeshFilter<TInputMesh, TOutputMesh>
{
public:
  ITK_DISALLOW_COPY_AND_MOVE(ApplyTransformToMeshFilter);

  using Self = ApplyTransformToMeshFilter;
  using Superclass = MeshToMeshFilter<TInputMesh, TOutputMesh>;
  using Pointer = SmartPointer<Self>;
  using ConstPointer = SmartPointer<const Self>;

  itkNewMacro(Self);
  itkOverrideGetNameOfClassMacro(ApplyTransformToMeshFilter);

  static constexpr unsigned int PointDimension = TInputMesh::PointDimension;

  using InputMeshType = TInputMesh;
  using OutputMeshType = TOutputMesh;
  using TransformType = TTransform;
  using DecoratedTransformType = DataObjectDecorator<TransformType>;
  using ParametersValueType = typename TransformType::ParametersValueType;
  using TransformPointType = typename TransformType::InputPointType;
  using JacobianEvaluatorType = detail::SpatialJacobianEvaluator<ParametersValueType, PointDimension>;
  using FlagContainerType = std::vector<unsigned char>;
  using ResidualContainerType = std::vector<double>;

  static_assert(TransformType::InputSpaceDimension == PointDimension &&
                  TransformType::OutputSpaceDimension == PointDimension,
                "The transform must map the mesh's space onto itself.");

  /** The transform applied to the vertices (required), as a decorated pipeline input. */
  itkSetGetDecoratedObjectInputMacro(Transform, TransformType);

  /** Apply the inverse of the transform (solve T(x) = p) instead of the transform. Default: Off. */
  itkSetMacro(Inverse, bool);
  itkGetConstMacro(Inverse, bool);
  itkBooleanMacro(Inverse);

  /** Residual |T(x) - p| (mm) below which an inverse vertex has converged. Default: 1e-6. */
  itkSetMacro(InverseTolerance, double);
  itkGetConstMacro(InverseTolerance, double);

  /** Iteration limit of each inverse scheme (Newton, then fixed point). Default: 50. */
  itkSetMacro(MaximumNumberOfInverseIterations, unsigned int);
  itkGetConstMacro(MaximumNumberOfInverseIterations, unsigned int);

  /** Fraction of the residual below which one iteration's decrease stops an inverse scheme (Newton, then fixed
   * point). In [0, 1); 0 continues while the residual decreases at all. Default: 1e-3. */
  itkSetMacro(MinimumInverseResidualDecrease, double);
  itkGetConstMacro(MinimumInverseResidualDecrease, double);

  /** Step (mm) of the finite differences used when the transform has no spatial Jacobian. Default: 1e-4. */
  itkSetMacro(FiniteDifferenceStep, double);
  itkGetConstMacro(FiniteDifferenceStep, double);

  /** Number of vertices whose inverse did not converge in the last inverse run. */
  itkGetConstMacro(NumberOfNonConvergedPoints, SizeValueType);

  /** Largest final residual |T(x) - p| (mm) of the last inverse run. */
  itkGetConstMacro(MaximumInverseResidual, double);

  /** One flag per vertex (point container order): 1 if its inverse converged. Empty in forward mode. */
  itkGetConstReferenceMacro(InverseConverged, FlagContainerType);

  /** One final residual |T(x) - p| (mm) per vertex (point container order). Empty in forward mode. */
  itkGetConstReferenceMacro(InverseResiduals, ResidualContainerType);

protected:
  ApplyTransformToMeshFilter();
  ~ApplyTransformToMeshFilter() override = default;
  void
  PrintSelf(std::ostream & os, Indent indent) const override;

  void
  VerifyPreconditions() const override;

  void
  GenerateData() override;

  /** Solves T(x) = target for one vertex, T as the evaluator (initialized with the transform) evaluates it and its
   * spatial Jacobian; returns true if converged, writes the best x and its residual. */
  bool
  InvertPoint(const JacobianEvaluatorType & jacobianEvaluator,
              const TransformPointType &    target,
              TransformPointType &          solution,
              double &                      residual) const;

private:
  bool                  m_Inverse{ false };
  double                m_InverseTolerance{ 1e-6 };
  unsigned int          m_MaximumNumberOfInverseIterations{ 50 };
  double                m_MinimumInverseResidualDecrease{ 1e-3 };
  double                m_FiniteDifferenceStep{ 1e-4 };
  SizeValueType         m_NumberOfNonConvergedPoints{ 0 };
  double                m_MaximumInverseResidual{ 0.0 };
  FlagContainerType     m_InverseConverged;
  ResidualContainerType m_InverseResiduals;
};
} // namespace itk

#ifndef ITK_MANUAL_INSTANTIATION
#  include "itkApplyTransformToMeshFilter.hxx"
#endif

#endif // itkApplyTransformToMeshFilter_h
