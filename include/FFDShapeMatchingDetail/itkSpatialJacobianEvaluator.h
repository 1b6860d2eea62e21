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
#ifndef itkSpatialJacobianEvaluator_h
#define itkSpatialJacobianEvaluator_h

#include "itkBSplineTransform.h"
#include "FFDShapeMatchingDetail/itkCubicBSplineKernel.h"
#include "itkCompositeTransform.h"
#include "itkMatrix.h"
#include "itkTransform.h"
#include <array>
#include <memory>
#include <vector>

namespace itk
{
namespace detail
{
/** \class SpatialJacobianEvaluator
 * \brief Evaluates the spatial Jacobian \f$\partial T / \partial x\f$ of any transform, thread-safely.
 *
 * ITK 5.2's BSplineTransform does not implement ComputeJacobianWithRespectToPosition(), and a
 * CompositeTransform holding one inherits that gap. This helper closes it:
 * - a cubic BSplineTransform is differentiated analytically (derivative of the B-spline kernel along
 *   each axis, chained with the coefficient grid's index-to-physical mapping); outside the transform's
 *   valid region the Jacobian is the identity, as the transform is;
 * - a CompositeTransform is differentiated by the chain rule over its sub-transforms, in the order
 *   TransformPoint() applies them (last added first);
 * - any other transform uses its own ComputeJacobianWithRespectToPosition() if it implements it,
 *   otherwise central finite differences of TransformPoint() with step FiniteDifferenceStep (mm).
 *
 * TransformPoint() evaluates T itself with the same arithmetic as the transform's own TransformPoint() (the same
 * value to the last bit): for a cubic BSplineTransform, and such members of a CompositeTransform, without the
 * weight and index arrays that ITK allocates on every call; for any other transform, its own.
 *
 * Initialize() inspects the transform once; Evaluate() and TransformPoint() are const and may be called from many
 * threads. The transform must stay unchanged between Initialize() and the last call.
 *
 * \ingroup FFDShapeMatching
 */
template <typename TParametersValueType, unsigned int NDimensions>
class SpatialJacobianEvaluator
{
public:
  using TransformType = Transform<TParametersValueType, NDimensions, NDimensions>;
  using PointType = typename TransformType::InputPointType;
  using MatrixType = Matrix<double, NDimensions, NDimensions>;
  using BSplineTransformType = BSplineTransform<TParametersValueType, NDimensions, 3>;
  using CompositeTransformType = CompositeTransform<TParametersValueType, NDimensions>;

  /** How the Jacobian of the transform (or of one composite member) is obtained. */
  enum class Method : uint8_t
  {
    None,
    BSpline,
    Composite,
    Native,
    FiniteDifference
  };

  /** Inspects the transform and chooses the method. Throws if transform is null. */
  void
  Initialize(const TransformType * transform, double finiteDifferenceStep = 1e-4)
  {
    if (transform == nullptr)
    {
      itkGenericExceptionMacro(<< "SpatialJacobianEvaluator: the transform is null");
    }
    m_Transform = transform;
    m_FiniteDifferenceStep = finiteDifferenceStep;
    m_Children.clear();
    if (const auto * bspline = dynamic_cast<const BSplineTransformType *>(transform))
    {
      m_Method = Method::BSpline;
      this->InitializeBSpline(bspline);
      return;
    }
    if (const auto * composite = dynamic_cast<const CompositeTransformType *>(transform))
    {
      m_Method = Method::Composite;
      const SizeValueType numberOfTransforms = composite->GetNumberOfTransforms();
      // TransformPoint() applies the last added transform first.
      for (SizeValueType i = numberOfTransforms; i > 0; --i)
      {
        auto child = std::make_unique<SpatialJacobianEvaluator>();
        child->Initialize(composite->GetNthTransformConstPointer(i - 1), finiteDifferenceStep);
        m_Children.push_back(std::move(child));
      }
      return;
    }
    m_Method = Method::Native;
    try
    {
      typename TransformType::JacobianPositionType jacobian;
      PointType                                    probe;
      probe.Fill(0.0);
      transform->ComputeJacobianWithRespectToPosition(probe, jacobian);
    }
    catch (const ExceptionObject &)
    {
      m_Method = Method::FiniteDifference;
    }
  }

  /** The method chosen for the top-level transform. */
  Method
  GetMethod() const
  {
    return m_Method;
  }

  /** True if some part of the transform is differentiated by finite differences. */
  bool
  UsesFiniteDifferences() const
  {
    if (m_Method == Method::FiniteDifference)
    {
      return true;
    }
    for (const auto & child : m_Children)
    {
      if (child->UsesFiniteDifferences())
      {
        return true;
      }
    }
    return false;
  }

  /** Writes \f$\partial T / \partial x\f$ at point into jacobian. Thread-safe. */
  void
  Evaluate(const PointType & point, MatrixType & jacobian) const
  {
    switch (m_Method)
    {
      case Method::BSpline:
        this->EvaluateBSpline(point, jacobian);
        break;
      case Method::Composite:
        this->EvaluateComposite(point, jacobian);
        break;
      case Method::Native: {
        typename TransformType::JacobianPositionType native;
        m_Transform->ComputeJacobianWithRespectToPosition(point, native);
        for (unsigned int i = 0; i < NDimensions; ++i)
        {
          for (unsigned int j = 0; j < NDimensions; ++j)
          {
            jacobian(i, j) = native(i, j);
          }
        }
        break;
      }
      case Method::FiniteDifference:
        this->EvaluateFiniteDifference(point, jacobian);
        break;
      case Method::None:
      default:
        itkGenericExceptionMacro(<< "SpatialJacobianEvaluator: Initialize() was not called");
    }
  }

  /** T(point), as the transform's TransformPoint() computes it. Thread-safe. */
  PointType
  TransformPoint(const PointType & point) const
  {
    switch (m_Method)
    {
      case Method::BSpline:
        return m_Coefficients[0] != nullptr ? this->TransformPointBSpline(point) : m_Transform->TransformPoint(point);
      case Method::Composite: {
        PointType current = point;
        for (const auto & child : m_Children)
        {
          current = child->TransformPoint(current);
        }
        return current;
      }
      case Method::Native:
      case Method::FiniteDifference:
        return m_Transform->TransformPoint(point);
      case Method::None:
      default:
        itkGenericExceptionMacro(<< "SpatialJacobianEvaluator: Initialize() was not called");
    }
  }

  /** Writes \f$\partial T / \partial x\f$ at \c points[k] into \c jacobians[k], k = 0 .. count - 1, as Evaluate()
   * does (up to rounding). For a 3-D BSplineTransform and a row of points that share their coordinates along the
   * second and third axes of the coefficient lattice (a row of an image grid aligned with the lattice), the
   * coefficients are contracted along those two axes once per lattice node of the row instead of once per point;
   * any other row is evaluated point by point. Thread-safe. */
  void
  EvaluateRow(const PointType * points, size_t count, MatrixType * jacobians) const
  {
    if constexpr (NDimensions == 3)
    {
      if (m_Method == Method::BSpline && m_Coefficients[0] != nullptr && count >= 8)
      {
        this->EvaluateBSplineRow(points, count, jacobians);
        return;
      }
    }
    for (size_t k = 0; k < count; ++k)
    {
      this->Evaluate(points[k], jacobians[k]);
    }
  }

private:
  void
  InitializeBSpline(const BSplineTransformType * bspline)
  {
    const auto & images = bspline->GetCoefficientImages();
    m_GridSize = images[0]->GetLargestPossibleRegion().GetSize();
    m_GridOrigin = images[0]->GetOrigin();
    // d(continuous index)/d(physical point) = diag(1/spacing) * direction^-1
    const auto & spacing = images[0]->GetSpacing();
    const auto   inverseDirection = images[0]->GetInverseDirection();
    for (unsigned int i = 0; i < NDimensions; ++i)
    {
      for (unsigned int j = 0; j < NDimensions; ++j)
      {
        m_PhysicalToIndex(i, j) = inverseDirection(i, j) / spacing[i];
      }
    }
    for (unsigned int d = 0; d < NDimensions; ++d)
    {
      m_Coefficients[d] = images[d]->GetBufferPointer();
    }
    m_CoefficientImage = images[0];
  }

  /** BSplineTransform::TransformPoint()'s arithmetic, step by step: the continuous index from the coefficient image,
   * its valid region (identity outside), ITK's cubic kernel per axis, the weights multiplied axis by axis and the
   * coefficients summed with the first axis fastest. */
  PointType
  TransformPointBSpline(const PointType & point) const
  {
    using ContinuousIndexType = ContinuousIndex<TParametersValueType, NDimensions>;
    ContinuousIndexType index;
    m_CoefficientImage->TransformPhysicalPointToContinuousIndex(point, index);
    for (unsigned int i = 0; i < NDimensions; ++i)
    {
      double value = index[i];
      if (!this->ClampToValidRegion(i, value))
      {
        return point;
      }
      index[i] = value;
    }
    IndexValueType start[NDimensions];
    double         weights[NDimensions][4];
    for (unsigned int i = 0; i < NDimensions; ++i)
    {
      start[i] = Math::Floor<IndexValueType>(index[i] + 0.5 - 1.5);
      double x = index[i] - static_cast<double>(start[i]);
      for (unsigned int k = 0; k < 4; ++k)
      {
        weights[i][k] = ITKCubicBSplineKernel(x);
        x -= 1.0;
      }
    }
    SizeValueType strides[NDimensions];
    SizeValueType stride = 1;
    for (unsigned int i = 0; i < NDimensions; ++i)
    {
      strides[i] = stride;
      stride *= m_GridSize[i];
    }
    PointType    output;
    unsigned int offset[NDimensions] = {};
    output.Fill(0.0);
    constexpr unsigned int numberOfWeights = 1u << (2 * NDimensions);
    for (unsigned int n = 0; n < numberOfWeights; ++n)
    {
      SizeValueType linear = 0;
      double        weight = 1.0;
      for (unsigned int i = 0; i < NDimensions; ++i)
      {
        linear += static_cast<SizeValueType>(start[i] + offset[i]) * strides[i];
        weight *= weights[i][offset[i]];
      }
      for (unsigned int d = 0; d < NDimensions; ++d)
      {
        output[d] += static_cast<TParametersValueType>(weight * m_Coefficients[d][linear]);
      }
      for (unsigned int i = 0; i < NDimensions; ++i)
      {
        if (++offset[i] < 4)
        {
          break;
        }
        offset[i] = 0;
      }
    }
    for (unsigned int d = 0; d < NDimensions; ++d)
    {
      output[d] += point[d];
    }
    return output;
  }

  /** BSplineKernelFunction<3>::Evaluate(), written as ITK writes it (the point values must agree to the bit). */
  static double
  ITKCubicBSplineKernel(double u)
  {
    const double absValue = std::abs(u);
    if (absValue < 1.0)
    {
      const double sqrValue = absValue * absValue;
      return (4.0 - 6.0 * sqrValue + 3.0 * sqrValue * absValue) / 6.0;
    }
    if (absValue < 2.0)
    {
      const double sqrValue = absValue * absValue;
      return (8.0 - 12.0 * absValue + 6.0 * sqrValue - sqrValue * absValue) / 6.0;
    }
    return 0.0;
  }

  void
  EvaluateBSpline(const PointType & point, MatrixType & jacobian) const
  {
    jacobian.SetIdentity();
    if (m_Coefficients[0] == nullptr)
    {
      return;
    }
    double index[NDimensions];
    if (!this->LatticeIndex(point, index))
    {
      return;
    }
    IndexValueType start[NDimensions];
    double         weights[NDimensions][4];
    double         derivatives[NDimensions][4];
    for (unsigned int i = 0; i < NDimensions; ++i)
    {
      start[i] = SupportWeights(index[i], weights[i], derivatives[i]);
    }
    // G(d, j) = d displacement_d / d index_j
    double        gradient[NDimensions][NDimensions] = {};
    SizeValueType strides[NDimensions];
    SizeValueType stride = 1;
    for (unsigned int i = 0; i < NDimensions; ++i)
    {
      strides[i] = stride;
      stride *= m_GridSize[i];
    }
    if constexpr (NDimensions == 3)
    {
      const SizeValueType first = static_cast<SizeValueType>(start[0]) +
                                  static_cast<SizeValueType>(start[1]) * strides[1] +
                                  static_cast<SizeValueType>(start[2]) * strides[2];
      CubicBSplineSupportIndexGradient(
        m_Coefficients, first, strides[1], strides[2], &weights[0][0], &derivatives[0][0], gradient);
    }
    else
    {
      unsigned int           offset[NDimensions] = {};
      constexpr unsigned int numberOfWeights = 1u << (2 * NDimensions);
      for (unsigned int n = 0; n < numberOfWeights; ++n)
      {
        SizeValueType linear = 0;
        for (unsigned int i = 0; i < NDimensions; ++i)
        {
          linear += static_cast<SizeValueType>(start[i] + offset[i]) * strides[i];
        }
        for (unsigned int j = 0; j < NDimensions; ++j)
        {
          double w = 1.0;
          for (unsigned int i = 0; i < NDimensions; ++i)
          {
            w *= (i == j) ? derivatives[i][offset[i]] : weights[i][offset[i]];
          }
          for (unsigned int d = 0; d < NDimensions; ++d)
          {
            gradient[d][j] += w * static_cast<double>(m_Coefficients[d][linear]);
          }
        }
        for (unsigned int i = 0; i < NDimensions; ++i)
        {
          if (++offset[i] < 4)
          {
            break;
          }
          offset[i] = 0;
        }
      }
    }
    this->AddIndexGradient(gradient, jacobian);
  }

  /** The continuous index of \c point on the coefficient lattice, with BSplineTransform::InsideValidRegion's rule:
   * false outside the valid region (where the displacement is zero). */
  bool
  LatticeIndex(const PointType & point, double index[NDimensions]) const
  {
    for (unsigned int i = 0; i < NDimensions; ++i)
    {
      index[i] = 0.0;
      for (unsigned int j = 0; j < NDimensions; ++j)
      {
        index[i] += m_PhysicalToIndex(i, j) * (point[j] - m_GridOrigin[j]);
      }
    }
    for (unsigned int i = 0; i < NDimensions; ++i)
    {
      if (!this->ClampToValidRegion(i, index[i]))
      {
        return false;
      }
    }
    return true;
  }

  /** False when the continuous index along \c axis is outside the valid region; moves an index at the region's
   * upper end (within a few ULPs) just inside it, as BSplineTransform does. */
  bool
  ClampToValidRegion(unsigned int axis, double & index) const
  {
    const double maxLimit = static_cast<double>(m_GridSize[axis]) - 2.0;
    if (Math::FloatAlmostEqual(index, maxLimit, 4))
    {
      index = Math::FloatAddULP(maxLimit, -6);
    }
    else if (index >= maxLimit || index < 1.0)
    {
      return false;
    }
    return true;
  }

  /** The first lattice node of the support of a continuous index along one axis, and the four weights and their
   * derivatives. */
  static IndexValueType
  SupportWeights(double index, double weights[4], double derivatives[4])
  {
    const IndexValueType start = Math::Floor<IndexValueType>(index + 0.5 - 1.5);
    double               u = index - static_cast<double>(start);
    for (unsigned int k = 0; k < 4; ++k)
    {
      weights[k] = CubicBSpline(u);
      derivatives[k] = CubicBSplineDerivative(u);
      u -= 1.0;
    }
    return start;
  }

  /** jacobian += G d index / d x, for the index gradient G(d, j) = d displacement_d / d index_j. */
  void
  AddIndexGradient(const double gradient[NDimensions][NDimensions], MatrixType & jacobian) const
  {
    for (unsigned int d = 0; d < NDimensions; ++d)
    {
      for (unsigned int k = 0; k < NDimensions; ++k)
      {
        double sum = 0.0;
        for (unsigned int j = 0; j < NDimensions; ++j)
        {
          sum += gradient[d][j] * m_PhysicalToIndex(j, k);
        }
        jacobian(d, k) += sum;
      }
    }
  }

  /** EvaluateRow() for a 3-D BSplineTransform. */
  void
  EvaluateBSplineRow(const PointType * points, size_t count, MatrixType * jacobians) const
  {
    // The continuous indices; the row path needs the second and third ones shared by every point.
    std::vector<std::array<double, 3>> indices(count);
    for (size_t k = 0; k < count; ++k)
    {
      for (unsigned int i = 0; i < 3; ++i)
      {
        indices[k][i] = 0.0;
        for (unsigned int j = 0; j < 3; ++j)
        {
          indices[k][i] += m_PhysicalToIndex(i, j) * (points[k][j] - m_GridOrigin[j]);
        }
      }
      if (indices[k][1] != indices[0][1] || indices[k][2] != indices[0][2])
      {
        for (size_t n = 0; n < count; ++n)
        {
          this->Evaluate(points[n], jacobians[n]);
        }
        return;
      }
    }
    double across[2] = { indices[0][1], indices[0][2] };
    if (!this->ClampToValidRegion(1, across[0]) || !this->ClampToValidRegion(2, across[1]))
    {
      for (size_t k = 0; k < count; ++k)
      {
        jacobians[k].SetIdentity();
      }
      return;
    }
    double               weights[3][4];
    double               derivatives[3][4];
    const IndexValueType start1 = SupportWeights(across[0], weights[1], derivatives[1]);
    const IndexValueType start2 = SupportWeights(across[1], weights[2], derivatives[2]);
    // Per lattice node i along the first axis and coordinate d: the coefficients contracted along the second and
    // third axes with (w1 w2, w1' w2, w1 w2').
    const size_t        n0 = m_GridSize[0];
    const size_t        stride1 = n0;
    const size_t        stride2 = n0 * m_GridSize[1];
    std::vector<double> contracted(n0 * 9, 0.0);
    for (unsigned int c = 0; c < 4; ++c)
    {
      for (unsigned int b = 0; b < 4; ++b)
      {
        const double valueWeight = weights[1][b] * weights[2][c];
        const double slope1Weight = derivatives[1][b] * weights[2][c];
        const double slope2Weight = weights[1][b] * derivatives[2][c];
        const size_t rowStart = static_cast<size_t>(start1 + static_cast<IndexValueType>(b)) * stride1 +
                                static_cast<size_t>(start2 + static_cast<IndexValueType>(c)) * stride2;
        for (unsigned int d = 0; d < 3; ++d)
        {
          const TParametersValueType * row = m_Coefficients[d] + rowStart;
          for (size_t i = 0; i < n0; ++i)
          {
            const double value = static_cast<double>(row[i]);
            contracted[9 * i + 3 * d] += valueWeight * value;
            contracted[9 * i + 3 * d + 1] += slope1Weight * value;
            contracted[9 * i + 3 * d + 2] += slope2Weight * value;
          }
        }
      }
    }
    for (size_t k = 0; k < count; ++k)
    {
      jacobians[k].SetIdentity();
      double along = indices[k][0];
      if (!this->ClampToValidRegion(0, along))
      {
        continue;
      }
      const IndexValueType start0 = SupportWeights(along, weights[0], derivatives[0]);
      double               gradient[3][3] = {};
      for (unsigned int a = 0; a < 4; ++a)
      {
        const double * node = contracted.data() + 9 * static_cast<size_t>(start0 + static_cast<IndexValueType>(a));
        for (unsigned int d = 0; d < 3; ++d)
        {
          gradient[d][0] += derivatives[0][a] * node[3 * d];
          gradient[d][1] += weights[0][a] * node[3 * d + 1];
          gradient[d][2] += weights[0][a] * node[3 * d + 2];
        }
      }
      this->AddIndexGradient(gradient, jacobians[k]);
    }
  }

  void
  EvaluateComposite(const PointType & point, MatrixType & jacobian) const
  {
    jacobian.SetIdentity();
    PointType current = point;
    for (const auto & child : m_Children)
    {
      MatrixType local;
      child->Evaluate(current, local);
      jacobian = local * jacobian;
      current = child->TransformPoint(current);
    }
  }

  void
  EvaluateFiniteDifference(const PointType & point, MatrixType & jacobian) const
  {
    for (unsigned int j = 0; j < NDimensions; ++j)
    {
      PointType forward = point;
      PointType backward = point;
      forward[j] += m_FiniteDifferenceStep;
      backward[j] -= m_FiniteDifferenceStep;
      const auto forwardImage = m_Transform->TransformPoint(forward);
      const auto backwardImage = m_Transform->TransformPoint(backward);
      for (unsigned int i = 0; i < NDimensions; ++i)
      {
        jacobian(i, j) = (forwardImage[i] - backwardImage[i]) / (2.0 * m_FiniteDifferenceStep);
      }
    }
  }

  const TransformType *                                  m_Transform{ nullptr };
  Method                                                 m_Method{ Method::None };
  double                                                 m_FiniteDifferenceStep{ 1e-4 };
  std::vector<std::unique_ptr<SpatialJacobianEvaluator>> m_Children;
  Size<NDimensions>                                      m_GridSize{};
  PointType                                              m_GridOrigin{};
  MatrixType                                             m_PhysicalToIndex{};
  const TParametersValueType *                           m_Coefficients[NDimensions] = {};
  const typename BSplineTransformType::ImageType *       m_CoefficientImage{ nullptr };
};
} // namespace detail
} // namespace itk

#endif // itkSpatialJacobianEvaluator_h
