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
#include "itkCubicBSplineKernel.h"
#include "itkCompositeTransform.h"
#include "itkMatrix.h"
#include "itkTransform.h"
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
 * Initialize() inspects the transform once; Evaluate() is const and may be called from many threads.
 * The transform must stay unchanged between Initialize() and the last Evaluate().
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
    for (unsigned int i = 0; i < NDimensions; ++i)
    {
      index[i] = 0.0;
      for (unsigned int j = 0; j < NDimensions; ++j)
      {
        index[i] += m_PhysicalToIndex(i, j) * (point[j] - m_GridOrigin[j]);
      }
    }
    // Same validity rule as BSplineTransform::InsideValidRegion (outside: zero displacement).
    for (unsigned int i = 0; i < NDimensions; ++i)
    {
      const double maxLimit = static_cast<double>(m_GridSize[i]) - 2.0;
      if (Math::FloatAlmostEqual(index[i], maxLimit, 4))
      {
        index[i] = Math::FloatAddULP(maxLimit, -6);
      }
      else if (index[i] >= maxLimit || index[i] < 1.0)
      {
        return;
      }
    }
    IndexValueType start[NDimensions];
    double         weights[NDimensions][4];
    double         derivatives[NDimensions][4];
    for (unsigned int i = 0; i < NDimensions; ++i)
    {
      start[i] = Math::Floor<IndexValueType>(index[i] + 0.5 - 1.5);
      double u = index[i] - static_cast<double>(start[i]);
      for (unsigned int k = 0; k < 4; ++k)
      {
        weights[i][k] = CubicBSpline(u);
        derivatives[i][k] = CubicBSplineDerivative(u);
        u -= 1.0;
      }
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
      // Separably: each row of 4 coefficients along x is contracted with the x weights and their derivatives, then
      // the rows with the y factors, then the planes with the z factors (about a third of the products of the
      // 64-term sum below).
      for (unsigned int c = 0; c < 4; ++c)
      {
        double plane[3][3] = {}; // [d][0: w_x w_y, 1: w'_x w_y, 2: w_x w'_y]
        for (unsigned int b = 0; b < 4; ++b)
        {
          const SizeValueType first = static_cast<SizeValueType>(start[0]) +
                                      static_cast<SizeValueType>(start[1] + b) * strides[1] +
                                      static_cast<SizeValueType>(start[2] + c) * strides[2];
          for (unsigned int d = 0; d < 3; ++d)
          {
            const auto * row = m_Coefficients[d] + first;
            double       value = 0.0;
            double       slope = 0.0;
            for (unsigned int a = 0; a < 4; ++a)
            {
              value += weights[0][a] * static_cast<double>(row[a]);
              slope += derivatives[0][a] * static_cast<double>(row[a]);
            }
            plane[d][0] += weights[1][b] * value;
            plane[d][1] += weights[1][b] * slope;
            plane[d][2] += derivatives[1][b] * value;
          }
        }
        for (unsigned int d = 0; d < 3; ++d)
        {
          gradient[d][0] += weights[2][c] * plane[d][1];
          gradient[d][1] += weights[2][c] * plane[d][2];
          gradient[d][2] += derivatives[2][c] * plane[d][0];
        }
      }
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
      current = child->m_Transform->TransformPoint(current);
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
};
} // namespace detail
} // namespace itk

#endif // itkSpatialJacobianEvaluator_h
