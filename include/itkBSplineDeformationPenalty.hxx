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
#ifndef itkBSplineDeformationPenalty_hxx
#define itkBSplineDeformationPenalty_hxx

#include "itkBSplineDeformationPenalty.h"
#include "FFDShapeMatchingDetail/itkCubicBSplineKernel.h"
#include "itk_eigen.h"
#include ITK_EIGEN(Core)
#include <algorithm>
#include <cmath>
#include <type_traits>

namespace itk
{
namespace detail
{
/** Determinant and cofactor matrix of a 2x2 or 3x3 matrix. */
template <unsigned int NDimensions>
double
DeterminantAndCofactors(const double (&m)[NDimensions][NDimensions], double (&cofactors)[NDimensions][NDimensions])
{
  static_assert(NDimensions == 2 || NDimensions == 3, "2-D or 3-D only");
  if constexpr (NDimensions == 2)
  {
    cofactors[0][0] = m[1][1];
    cofactors[0][1] = -m[1][0];
    cofactors[1][0] = -m[0][1];
    cofactors[1][1] = m[0][0];
    return m[0][0] * m[1][1] - m[0][1] * m[1][0];
  }
  else
  {
    for (unsigned int i = 0; i < 3; ++i)
    {
      for (unsigned int j = 0; j < 3; ++j)
      {
        const unsigned int i1 = (i + 1) % 3;
        const unsigned int i2 = (i + 2) % 3;
        const unsigned int j1 = (j + 1) % 3;
        const unsigned int j2 = (j + 2) % 3;
        cofactors[i][j] = m[i1][j1] * m[i2][j2] - m[i1][j2] * m[i2][j1];
      }
    }
    return m[0][0] * cofactors[0][0] + m[0][1] * cofactors[0][1] + m[0][2] * cofactors[0][2];
  }
}
} // namespace detail

template <typename TParametersValueType, unsigned int NDimensions>
auto
BSplineDeformationPenalty<TParametersValueType, NDimensions>::Evaluate(const BSplineTransformType & transform,
                                                                       DerivativeType *             gradient,
                                                                       double gradientFactor) -> MeasureType
{
  if (gradient != nullptr && gradient->GetSize() != transform.GetNumberOfParameters())
  {
    itkExceptionMacro(<< "Gradient has " << gradient->GetSize() << " elements, the transform "
                      << transform.GetNumberOfParameters() << " parameters");
  }
  m_LastBendingEnergy = 0.0;
  m_LastFoldingPenalty = 0.0;
  MeasureType value = 0.0;
  if (m_BendingEnergyWeight > 0.0)
  {
    m_LastBendingEnergy = this->EvaluateBendingEnergy(transform, gradient, gradientFactor * m_BendingEnergyWeight);
    value += m_BendingEnergyWeight * m_LastBendingEnergy;
  }
  if (m_FoldingPenaltyWeight > 0.0)
  {
    m_LastFoldingPenalty = this->EvaluateFoldingPenalty(transform, gradient, gradientFactor * m_FoldingPenaltyWeight);
    value += m_FoldingPenaltyWeight * m_LastFoldingPenalty;
  }
  return value;
}

template <typename TParametersValueType, unsigned int NDimensions>
void
BSplineDeformationPenalty<TParametersValueType, NDimensions>::UpdateGramMatrices(const MeshSizeType & meshSize)
{
  if (m_GramMatricesValid && meshSize == m_CachedMeshSize)
  {
    return;
  }
  // Four-point Gauss-Legendre quadrature: exact for the degree-6 products of cubic pieces.
  const double nodes[4] = { -0.8611363115940526, -0.3399810435848563, 0.3399810435848563, 0.8611363115940526 };
  const double weights[4] = { 0.3478548451374538, 0.6521451548625461, 0.6521451548625461, 0.3478548451374538 };
  m_Gram.clear();
  m_Gram.resize(NDimensions);
  for (unsigned int axis = 0; axis < NDimensions; ++axis)
  {
    const unsigned int cells = meshSize[axis];
    const unsigned int n = cells + 3;
    for (unsigned int order = 0; order < 3; ++order)
    {
      GramMatrixType & gram = m_Gram[axis][order];
      gram.assign(n * n, 0.0);
      for (unsigned int cell = 0; cell < cells; ++cell)
      {
        for (unsigned int q = 0; q < 4; ++q)
        {
          const double t = cell + 0.5 * (1.0 + nodes[q]);
          const double w = 0.5 * weights[q];
          // Control points cell .. cell + 3 support this span (control point i sits at t = i - 1).
          for (unsigned int i = cell; i < cell + 4; ++i)
          {
            const double bi = detail::CubicBSplineOfOrder(t - (static_cast<double>(i) - 1.0), order);
            for (unsigned int j = cell; j < cell + 4; ++j)
            {
              const double bj = detail::CubicBSplineOfOrder(t - (static_cast<double>(j) - 1.0), order);
              gram[i * n + j] += w * bi * bj;
            }
          }
        }
      }
    }
  }
  // The seven diagonals of each (banded) matrix, diagonal d holding row i's weight of i + d - 3 at i (zero outside).
  m_Diagonals.assign(NDimensions, {});
  for (unsigned int axis = 0; axis < NDimensions; ++axis)
  {
    const size_t n = meshSize[axis] + 3;
    for (unsigned int order = 0; order < 3; ++order)
    {
      std::vector<double> & diagonals = m_Diagonals[axis][order];
      diagonals.assign(7 * n, 0.0);
      for (size_t i = 0; i < n; ++i)
      {
        for (size_t d = 0; d < 7; ++d)
        {
          if (i + d >= 3 && i + d - 3 < n)
          {
            diagonals[d * n + i] = m_Gram[axis][order][i * n + i + d - 3];
          }
        }
      }
    }
  }
  m_CachedMeshSize = meshSize;
  m_GramMatricesValid = true;
}

template <typename TParametersValueType, unsigned int NDimensions>
void
BSplineDeformationPenalty<TParametersValueType, NDimensions>::ApplyAlongAxis(unsigned int   axis,
                                                                             unsigned int   order,
                                                                             const double * in,
                                                                             double *       out) const
{
  const GramMatrixType & matrix = m_Gram[axis][order];
  size_t                 total = 1;
  size_t                 stride = 1;
  for (unsigned int a = 0; a < NDimensions; ++a)
  {
    total *= m_CachedMeshSize[a] + 3;
    stride *= a < axis ? m_CachedMeshSize[a] + 3 : 1;
  }
  const size_t n = m_CachedMeshSize[axis] + 3;
  const size_t outer = total / (n * stride);
  using BlockType = Eigen::Array<double, 8, 1>;
  constexpr size_t block = BlockType::SizeAtCompileTime;
  for (size_t o = 0; o < outer; ++o)
  {
    const size_t base = o * n * stride;
    if (stride == 1)
    {
      // One contiguous line: its interior rows (every neighbour within the line) a block of rows at a time, with the
      // matrix's diagonals as the weights (the same products, added in the same order, as row by row below).
      const double * line = in + base;
      double *       target = out + base;
      const double * diagonals = m_Diagonals[axis][order].data();
      size_t         i = 3;
      for (; i + block + 3 <= n; i += block)
      {
        BlockType sum = BlockType::Zero();
        for (size_t d = 0; d < 7; ++d)
        {
          sum += Eigen::Map<const BlockType>(diagonals + d * n + i) * Eigen::Map<const BlockType>(line + i + d - 3);
        }
        Eigen::Map<BlockType>(target + i) = sum;
      }
      for (size_t r = 0; r < n; ++r)
      {
        if (r >= 3 && r < i)
        {
          continue;
        }
        const size_t jBegin = r >= 3 ? r - 3 : 0;
        const size_t jEnd = std::min(n, r + 4);
        double       sum = 0.0;
        for (size_t j = jBegin; j < jEnd; ++j)
        {
          sum += matrix[r * n + j] * line[j];
        }
        target[r] = sum;
      }
      continue;
    }
    for (size_t i = 0; i < n; ++i)
    {
      // The Gram matrices are banded: a cubic B-spline overlaps the three neighbours on each side. The lines along
      // this axis side by side, a block of contiguous values at a time: each block's sums stay in registers over the
      // band (the same products, added in the same order, as value by value).
      const size_t   jBegin = i >= 3 ? i - 3 : 0;
      const size_t   jEnd = std::min(n, i + 4);
      double *       target = out + base + i * stride;
      const double * weights = matrix.data() + i * n;
      const double * lines = in + base;
      size_t         inner = 0;
      for (; inner + block <= stride; inner += block)
      {
        BlockType sum = BlockType::Zero();
        for (size_t j = jBegin; j < jEnd; ++j)
        {
          sum += weights[j] * Eigen::Map<const BlockType>(lines + j * stride + inner);
        }
        Eigen::Map<BlockType>(target + inner) = sum;
      }
      for (; inner < stride; ++inner)
      {
        double sum = 0.0;
        for (size_t j = jBegin; j < jEnd; ++j)
        {
          sum += weights[j] * lines[j * stride + inner];
        }
        target[inner] = sum;
      }
    }
  }
}

template <typename TParametersValueType, unsigned int NDimensions>
double
BSplineDeformationPenalty<TParametersValueType, NDimensions>::EvaluateBendingEnergy(
  const BSplineTransformType & transform,
  DerivativeType *             gradient,
  double                       gradientFactor)
{
  const MeshSizeType meshSize = transform.GetTransformDomainMeshSize();
  this->UpdateGramMatrices(meshSize);
  const auto spacing = transform.GetCoefficientImages()[0]->GetSpacing();
  double     cellCount = 1.0;
  size_t     numberOfControlPoints = 1;
  for (unsigned int axis = 0; axis < NDimensions; ++axis)
  {
    cellCount *= meshSize[axis];
    numberOfControlPoints *= meshSize[axis] + 3;
  }

  // The energy is c^T H c with H = sum over the second derivatives d^2/dx_a dx_b (a <= b; the mixed ones twice) of
  // a Kronecker product of per-axis Gram matrices: the derivative orders per axis add up to two. H c is formed axis
  // by axis with the partial products shared: after the first k axes, one partial product per prefix of orders
  // (orders[0..k-1], adding up to at most two); the last axis' order is then fixed, so the prefixes are summed per
  // last-axis order, each with its term's factor, before the last axis (3 + 6 + 3 one-axis products in 3-D instead
  // of 18).
  struct Partial
  {
    std::array<unsigned int, NDimensions> orders;
    const double *                        values;
  };
  const auto factorOf = [&](const std::array<unsigned int, NDimensions> & orders) {
    double       denominator = cellCount;
    unsigned int derivatives = 0;
    for (unsigned int axis = 0; axis < NDimensions; ++axis)
    {
      for (unsigned int k = 0; k < orders[axis]; ++k)
      {
        denominator *= spacing[axis] * spacing[axis];
        ++derivatives;
      }
    }
    bool pure = false;
    for (unsigned int axis = 0; axis < NDimensions; ++axis)
    {
      pure = pure || orders[axis] == 2;
    }
    return (pure ? 1.0 : 2.0) / denominator * (derivatives == 2 ? 1.0 : 0.0);
  };

  const ParametersType & parameters = transform.GetParameters();
  double                 energy = 0.0;
  // The partial products live in buffers kept between calls (one set per axis but the last), as do the sums.
  m_PartialProducts.resize(NDimensions);
  std::vector<double> & product = m_ProductBuffers[0];
  std::vector<double> & scratch = m_ProductBuffers[1];
  std::vector<double> & alongLast = m_ProductBuffers[2];
  std::vector<double> & converted = m_ProductBuffers[3];
  product.resize(numberOfControlPoints);
  scratch.resize(numberOfControlPoints);
  alongLast.resize(numberOfControlPoints);
  for (unsigned int d = 0; d < NDimensions; ++d)
  {
    const TParametersValueType * coefficients = parameters.data_block() + d * numberOfControlPoints;
    const double *               values = nullptr;
    if constexpr (std::is_same_v<TParametersValueType, double>)
    {
      values = coefficients;
    }
    else
    {
      converted.assign(coefficients, coefficients + numberOfControlPoints);
      values = converted.data();
    }
    std::vector<Partial> level(1);
    level[0].orders.fill(0);
    level[0].values = values;
    for (unsigned int axis = 0; axis + 1 < NDimensions; ++axis)
    {
      std::vector<Partial>               next;
      std::vector<std::vector<double>> & storage = m_PartialProducts[axis];
      size_t                             usedBuffers = 0;
      for (const Partial & partial : level)
      {
        unsigned int used = 0;
        for (unsigned int a = 0; a < axis; ++a)
        {
          used += partial.orders[a];
        }
        for (unsigned int order = 0; used + order <= 2; ++order)
        {
          if (storage.size() <= usedBuffers)
          {
            storage.emplace_back();
          }
          std::vector<double> & buffer = storage[usedBuffers++];
          buffer.resize(numberOfControlPoints);
          Partial extended{ partial.orders, buffer.data() };
          extended.orders[axis] = order;
          this->ApplyAlongAxis(axis, order, partial.values, buffer.data());
          next.push_back(extended);
        }
      }
      level = std::move(next);
    }
    constexpr unsigned int last = NDimensions - 1;
    std::fill(product.begin(), product.end(), 0.0);
    for (unsigned int order = 0; order <= 2; ++order)
    {
      std::fill(scratch.begin(), scratch.end(), 0.0);
      bool any = false;
      for (Partial & partial : level)
      {
        unsigned int used = 0;
        for (unsigned int a = 0; a < last; ++a)
        {
          used += partial.orders[a];
        }
        if (used + order != 2)
        {
          continue;
        }
        partial.orders[last] = order;
        const double factor = factorOf(partial.orders);
        for (size_t k = 0; k < numberOfControlPoints; ++k)
        {
          scratch[k] += factor * partial.values[k];
        }
        any = true;
      }
      if (!any)
      {
        continue;
      }
      this->ApplyAlongAxis(last, order, scratch.data(), alongLast.data());
      for (size_t k = 0; k < numberOfControlPoints; ++k)
      {
        product[k] += alongLast[k];
      }
    }
    double dot = 0.0;
    for (size_t k = 0; k < numberOfControlPoints; ++k)
    {
      dot += coefficients[k] * product[k];
    }
    energy += dot;
    if (gradient != nullptr)
    {
      const double scale = 2.0 * gradientFactor;
      for (size_t k = 0; k < numberOfControlPoints; ++k)
      {
        (*gradient)[d * numberOfControlPoints + k] += scale * product[k];
      }
    }
  }
  return energy;
}

template <typename TParametersValueType, unsigned int NDimensions>
double
BSplineDeformationPenalty<TParametersValueType, NDimensions>::EvaluateFoldingPenalty(
  const BSplineTransformType & transform,
  DerivativeType *             gradient,
  double                       gradientFactor)
{
  const MeshSizeType     meshSize = transform.GetTransformDomainMeshSize();
  const auto             coefficientImage = transform.GetCoefficientImages()[0];
  const auto             spacing = coefficientImage->GetSpacing();
  const auto             direction = coefficientImage->GetDirection();
  const ParametersType & parameters = transform.GetParameters();

  std::array<size_t, NDimensions> controlSize{};
  std::array<size_t, NDimensions> sampleSize{};
  size_t                          numberOfControlPoints = 1;
  size_t                          numberOfSamples = 1;
  for (unsigned int axis = 0; axis < NDimensions; ++axis)
  {
    controlSize[axis] = meshSize[axis] + 3;
    sampleSize[axis] = meshSize[axis] * m_FoldingSamplesPerCell;
    numberOfControlPoints *= controlSize[axis];
    numberOfSamples *= sampleSize[axis];
  }
  constexpr unsigned int support = 4;
  size_t                 supportSize = 1;
  for (unsigned int axis = 0; axis < NDimensions; ++axis)
  {
    supportSize *= support;
  }

  double                                       penalty = 0.0;
  double                                       minimumDeterminant = NumericTraits<double>::max();
  std::array<size_t, NDimensions>              sample{};
  std::vector<std::array<double, NDimensions>> basisGradients(supportSize);
  std::vector<size_t>                          controlIndices(supportSize);
  for (size_t s = 0; s < numberOfSamples; ++s)
  {
    // Basis values and parametric derivatives along each axis at this sample.
    double       values[NDimensions][support];
    double       derivatives[NDimensions][support];
    unsigned int first[NDimensions];
    for (unsigned int axis = 0; axis < NDimensions; ++axis)
    {
      const unsigned int cell = static_cast<unsigned int>(sample[axis] / m_FoldingSamplesPerCell);
      const double       t = cell + (sample[axis] % m_FoldingSamplesPerCell + 0.5) / m_FoldingSamplesPerCell;
      first[axis] = cell;
      for (unsigned int k = 0; k < support; ++k)
      {
        const double u = t - (static_cast<double>(cell + k) - 1.0);
        values[axis][k] = detail::CubicBSplineOfOrder(u, 0);
        derivatives[axis][k] = detail::CubicBSplineOfOrder(u, 1) / spacing[axis];
      }
    }
    double jacobian[NDimensions][NDimensions];
    for (unsigned int a = 0; a < NDimensions; ++a)
    {
      for (unsigned int b = 0; b < NDimensions; ++b)
      {
        jacobian[a][b] = (a == b) ? 1.0 : 0.0;
      }
    }
    for (size_t local = 0; local < supportSize; ++local)
    {
      size_t rest = local;
      size_t controlIndex = 0;
      size_t stride = 1;
      double gradientGrid[NDimensions];
      for (unsigned int axis = 0; axis < NDimensions; ++axis)
      {
        gradientGrid[axis] = 1.0;
      }
      for (unsigned int axis = 0; axis < NDimensions; ++axis)
      {
        const unsigned int k = rest % support;
        rest /= support;
        controlIndex += (first[axis] + k) * stride;
        stride *= controlSize[axis];
        for (unsigned int g = 0; g < NDimensions; ++g)
        {
          gradientGrid[g] *= (g == axis) ? derivatives[axis][k] : values[axis][k];
        }
      }
      // Gradient in physical space: rotate the grid-frame gradient by the grid's direction.
      std::array<double, NDimensions> physical{};
      for (unsigned int b = 0; b < NDimensions; ++b)
      {
        for (unsigned int g = 0; g < NDimensions; ++g)
        {
          physical[b] += direction[b][g] * gradientGrid[g];
        }
      }
      basisGradients[local] = physical;
      controlIndices[local] = controlIndex;
      for (unsigned int a = 0; a < NDimensions; ++a)
      {
        const double coefficient = parameters[a * numberOfControlPoints + controlIndex];
        for (unsigned int b = 0; b < NDimensions; ++b)
        {
          jacobian[a][b] += coefficient * physical[b];
        }
      }
    }
    double       cofactors[NDimensions][NDimensions];
    const double determinant = detail::DeterminantAndCofactors<NDimensions>(jacobian, cofactors);
    minimumDeterminant = std::min(minimumDeterminant, determinant);
    const double shortfall = m_FoldingThreshold - determinant;
    if (shortfall > 0.0)
    {
      penalty += shortfall * shortfall;
      if (gradient != nullptr)
      {
        // d(shortfall^2)/dc_{k,a} = -2 shortfall * sum_b cof_ab dB_k/dx_b, averaged over the samples.
        const double scale = -2.0 * shortfall * gradientFactor / static_cast<double>(numberOfSamples);
        for (size_t local = 0; local < supportSize; ++local)
        {
          for (unsigned int a = 0; a < NDimensions; ++a)
          {
            double sum = 0.0;
            for (unsigned int b = 0; b < NDimensions; ++b)
            {
              sum += cofactors[a][b] * basisGradients[local][b];
            }
            (*gradient)[a * numberOfControlPoints + controlIndices[local]] += scale * sum;
          }
        }
      }
    }
    for (unsigned int axis = 0; axis < NDimensions; ++axis)
    {
      if (++sample[axis] < sampleSize[axis])
      {
        break;
      }
      sample[axis] = 0;
    }
  }
  m_LastMinimumJacobianDeterminant = minimumDeterminant;
  return penalty / static_cast<double>(numberOfSamples);
}

template <typename TParametersValueType, unsigned int NDimensions>
void
BSplineDeformationPenalty<TParametersValueType, NDimensions>::PrintSelf(std::ostream & os, Indent indent) const
{
  Superclass::PrintSelf(os, indent);
  os << indent << "BendingEnergyWeight: " << m_BendingEnergyWeight << std::endl;
  os << indent << "FoldingPenaltyWeight: " << m_FoldingPenaltyWeight << std::endl;
  os << indent << "FoldingThreshold: " << m_FoldingThreshold << std::endl;
  os << indent << "FoldingSamplesPerCell: " << m_FoldingSamplesPerCell << std::endl;
  os << indent << "LastBendingEnergy: " << m_LastBendingEnergy << std::endl;
  os << indent << "LastFoldingPenalty: " << m_LastFoldingPenalty << std::endl;
  os << indent << "LastMinimumJacobianDeterminant: " << m_LastMinimumJacobianDeterminant << std::endl;
  os << indent << "CachedMeshSize: " << m_CachedMeshSize << std::endl;
  os << indent << "GramMatricesValid: " << (m_GramMatricesValid ? "On" : "Off") << std::endl;
}
} // namespace itk

#endif // itkBSplineDeformationPenalty_hxx
