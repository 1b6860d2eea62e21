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
#ifndef itkBSplineDeformationPenalty_h
#define itkBSplineDeformationPenalty_h

#include "itkFFDShapeMatchingCompatibility.h"
#include "itkBSplineTransform.h"
#include "itkObject.h"
#include "itkObjectFactory.h"
#include <array>
#include <vector>

namespace itk
{
/** \class BSplineDeformationPenalty
 * \brief Regularization terms of a cubic B-spline deformation, with exact gradients in its coefficients.
 *
 * For a cubic BSplineTransform \f$T(x) = x + u(x)\f$ this computes two penalties and their gradients with
 * respect to the transform's parameters (the control-point displacements):
 *
 * - the <b>bending energy</b>, the thin-plate energy of the displacement averaged over the transform domain,
 *   \f[ E_b = \frac{1}{|\Omega|}\int_\Omega \sum_{d}\sum_{a,b} \Big(\frac{\partial^2 u_d}{\partial x_a \partial
 * x_b}\Big)^2 dx, \f] evaluated exactly: it is a quadratic form \f$\sum_d c_d^T K c_d\f$ in the coefficients, where
 * \f$K\f$ is a sum of Kronecker products of one-dimensional Gram matrices of the B-spline basis and its derivatives
 *   (integrated exactly by Gauss-Legendre quadrature on each knot span);
 * - the <b>folding penalty</b>, the mean over regular samples of the domain (FoldingSamplesPerCell per axis in
 *   each control-grid cell) of \f$\max(0, \tau - \det J(x))^2\f$, where \f$J\f$ is the spatial Jacobian of
 *   \f$T\f$ and \f$\tau\f$ the FoldingThreshold; it is zero for deformations that keep every sampled volume
 *   ratio above \f$\tau\f$ and grows as the deformation approaches folding.
 *
 * The penalty value is BendingEnergyWeight \f$E_b\f$ + FoldingPenaltyWeight \f$E_f\f$. Evaluate() adds
 * its gradient, scaled by a factor, to a parameter-sized array, so that an ITK v4 metric can add it to its
 * own derivative (v4 derivatives point downhill: use a factor of -1 there).
 *
 * The one-dimensional Gram matrices are cached for the transform's mesh size and recomputed when it
 * changes (e.g. between registration levels).
 *
 * \par References
 * D. Rueckert et al., "Nonrigid registration using free-form deformations: application to breast MR images",
 * IEEE TMI 18(8), 1999, doi:10.1109/42.796284 (bending energy of a B-spline FFD).
 *
 * \sa RegularizedImageToImageMetricv4, BSplineTransform
 * \ingroup FFDShapeMatching
 */
template <typename TParametersValueType = double, unsigned int NDimensions = 3>
class ITK_TEMPLATE_EXPORT BSplineDeformationPenalty : public Object
{
public:
  ITK_DISALLOW_COPY_AND_MOVE(BSplineDeformationPenalty);

  using Self = BSplineDeformationPenalty;
  using Superclass = Object;
  using Pointer = SmartPointer<Self>;
  using ConstPointer = SmartPointer<const Self>;

  itkNewMacro(Self);
  itkOverrideGetNameOfClassMacro(BSplineDeformationPenalty);

  static constexpr unsigned int SpaceDimension = NDimensions;

  using BSplineTransformType = BSplineTransform<TParametersValueType, NDimensions, 3>;
  using ParametersType = typename BSplineTransformType::ParametersType;
  using DerivativeType = Array<TParametersValueType>;
  using MeasureType = double;

  /** Weight of the bending energy. Default: 0. */
  itkSetClampMacro(BendingEnergyWeight, double, 0.0, NumericTraits<double>::max());
  itkGetConstMacro(BendingEnergyWeight, double);

  /** Weight of the folding penalty. Default: 0. */
  itkSetClampMacro(FoldingPenaltyWeight, double, 0.0, NumericTraits<double>::max());
  itkGetConstMacro(FoldingPenaltyWeight, double);

  /** Jacobian determinant below which the folding penalty applies. Default: 0.1. */
  itkSetMacro(FoldingThreshold, double);
  itkGetConstMacro(FoldingThreshold, double);

  /** Samples per axis in each control-grid cell for the folding penalty. Default: 2. */
  itkSetClampMacro(FoldingSamplesPerCell, unsigned int, 1, 16);
  itkGetConstMacro(FoldingSamplesPerCell, unsigned int);

  /** True when either weight is positive. */
  bool
  IsActive() const
  {
    return m_BendingEnergyWeight > 0.0 || m_FoldingPenaltyWeight > 0.0;
  }

  /** Returns the weighted penalty of \c transform at its current parameters. When \c gradient is not null it
   * must have the transform's number of parameters; \c gradientFactor times the penalty's gradient is added
   * to it. The last unweighted terms are kept for GetLastBendingEnergy() / GetLastFoldingPenalty(). */
  MeasureType
  Evaluate(const BSplineTransformType & transform, DerivativeType * gradient, double gradientFactor = 1.0);

  /** Unweighted bending energy \f$E_b\f$ of the last Evaluate(). */
  itkGetConstMacro(LastBendingEnergy, double);

  /** Unweighted folding penalty \f$E_f\f$ of the last Evaluate(). */
  itkGetConstMacro(LastFoldingPenalty, double);

  /** Smallest sampled Jacobian determinant of the last Evaluate() that computed the folding term. */
  itkGetConstMacro(LastMinimumJacobianDeterminant, double);

protected:
  BSplineDeformationPenalty() = default;
  ~BSplineDeformationPenalty() override = default;
  void
  PrintSelf(std::ostream & os, Indent indent) const override;

private:
  using MeshSizeType = typename BSplineTransformType::MeshSizeType;
  /** Row-major n x n matrix of one axis. */
  using GramMatrixType = std::vector<double>;

  void
  UpdateGramMatrices(const MeshSizeType & meshSize);

  /** out = A in along one axis of the control lattice (the lines along \c axis, each multiplied by the banded
   * Gram matrix A of that axis and derivative order), for values with axis 0 fastest. */
  void
  ApplyAlongAxis(unsigned int axis, unsigned int order, const double * in, double * out) const;

  double
  EvaluateBendingEnergy(const BSplineTransformType & transform, DerivativeType * gradient, double gradientFactor);

  double
  EvaluateFoldingPenalty(const BSplineTransformType & transform, DerivativeType * gradient, double gradientFactor);

  double       m_BendingEnergyWeight{ 0.0 };
  double       m_FoldingPenaltyWeight{ 0.0 };
  double       m_FoldingThreshold{ 0.1 };
  unsigned int m_FoldingSamplesPerCell{ 2 };
  double       m_LastBendingEnergy{ 0.0 };
  double       m_LastFoldingPenalty{ 0.0 };
  double       m_LastMinimumJacobianDeterminant{ 1.0 };

  MeshSizeType m_CachedMeshSize{};
  bool         m_GramMatricesValid{ false };
  /** m_Gram[axis][order]: Gram matrix of the order-th derivatives of the basis along an axis. */
  std::vector<std::array<GramMatrixType, 3>> m_Gram{};
  /** m_Diagonals[axis][order]: the seven diagonals of m_Gram[axis][order], for products along contiguous lines. */
  std::vector<std::array<std::vector<double>, 3>> m_Diagonals{};
  /** Buffers of EvaluateBendingEnergy(), kept between calls: the partial products after each axis but the last, and
   * the product, two sums and the coefficients converted to double (for other parameter types). */
  std::vector<std::vector<std::vector<double>>> m_PartialProducts{};
  std::array<std::vector<double>, 4>            m_ProductBuffers{};
};
} // namespace itk

#ifndef ITK_MANUAL_INSTANTIATION
#  include "itkBSplineDeformationPenalty.hxx"
#endif

#endif // itkBSplineDeformationPenalty_h
