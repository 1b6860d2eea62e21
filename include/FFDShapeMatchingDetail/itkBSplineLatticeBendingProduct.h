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
#ifndef itkBSplineLatticeBendingProduct_h
#define itkBSplineLatticeBendingProduct_h

#include "itk_eigen.h"
#include ITK_EIGEN(Core)

#include <algorithm>
#include <array>
#include <cstddef>
#include <vector>

namespace itk
{
namespace detail
{
/** \class BSplineLatticeBendingProduct
 * \brief The product (R + shift I) X for the bending matrix R of BSplineLatticeBendingMatrix(size)
 * (itkBSplineLatticeRegularization.h), without the matrix, for three columns side by side.
 *
 * R is a sum of one-axis factors: R = sum_a K_a + 2 sum_{a<b} L_a L_b, where K_a = D2^T D2 (D2 the second
 * differences) and L_a = D1^T D1 (D1 the first differences) act along axis a alone: banded matrices of the axis'
 * length, five and three wide. The product applies them axis by axis, with the mixed terms' partial products shared
 * (2 (L_x L_y + L_x L_z + L_y L_z) X = 2 L_y (L_x X) + 2 L_z (L_x X + L_y X)): seven one-axis passes whose inner loops
 * run over contiguous values, in place of the matrix's 25 entries per row gathered by index. Equal to the sparse
 * product up to rounding (tested against it). X and the result hold three values per coefficient (coefficient index
 * i + n0 (j + n1 k)), row-major. Not for concurrent calls on one object (the passes share its scratch buffer).
 * \ingroup FFDShapeMatching
 */
class BSplineLatticeBendingProduct
{
public:
  static constexpr unsigned int Columns = 3;
  /** Eight contiguous values, summed side by side (Eigen's vector instructions). */
  using BlockType = Eigen::Array<double, 8, 1>;

  BSplineLatticeBendingProduct(const std::array<size_t, 3> & size, double shift)
    : m_Size(size)
    , m_Shift(shift)
  {
    size_t stride = Columns;
    for (unsigned int axis = 0; axis < 3; ++axis)
    {
      m_Stride[axis] = stride;
      stride *= size[axis];
      const size_t n = size[axis];
      // D2^T D2 and D1^T D1 of this axis, dense (n is a lattice's side: tens of nodes).
      m_Second[axis].assign(n * n, 0.0);
      m_First[axis].assign(n * n, 0.0);
      for (size_t r = 0; r + 2 < n; ++r)
      {
        const double row[3] = { 1.0, -2.0, 1.0 };
        for (size_t i = 0; i < 3; ++i)
        {
          for (size_t j = 0; j < 3; ++j)
          {
            m_Second[axis][(r + i) * n + r + j] += row[i] * row[j];
          }
        }
      }
      for (size_t r = 0; r + 1 < n; ++r)
      {
        const double row[2] = { -1.0, 1.0 };
        for (size_t i = 0; i < 2; ++i)
        {
          for (size_t j = 0; j < 2; ++j)
          {
            m_First[axis][(r + i) * n + r + j] += row[i] * row[j];
          }
        }
      }
    }
    m_Count = stride;
    m_AlongX.resize(m_Count);
  }

  /** out = factor (R + shift I) in, each holding Columns values per coefficient. */
  void
  Apply(const double * in, double * out, double factor) const
  {
    for (size_t q = 0; q < m_Count; ++q)
    {
      out[q] = factor * m_Shift * in[q];
    }
    for (unsigned int axis = 0; axis < 3; ++axis)
    {
      this->AddAlongAxis(m_Second[axis], 2, axis, factor, in, out);
    }
    std::fill(m_AlongX.begin(), m_AlongX.end(), 0.0);
    this->AddAlongAxis(m_First[0], 1, 0, 1.0, in, m_AlongX.data());
    this->AddAlongAxis(m_First[1], 1, 1, 2.0 * factor, m_AlongX.data(), out);
    // L_x X, read: L_x X + L_y X in its place.
    this->AddAlongAxis(m_First[1], 1, 1, 1.0, in, m_AlongX.data());
    this->AddAlongAxis(m_First[2], 1, 2, 2.0 * factor, m_AlongX.data(), out);
  }

  /** One term of R: per axis the order of its one-axis factor (0 the identity, 1 D1^T D1, 2 D2^T D2) and its
   * weight. */
  struct Term
  {
    std::array<unsigned int, 3> Orders;
    double                      Weight;
  };

  /** R's terms: sum_a K_a + 2 sum_{a<b} L_a L_b (the shift adds the identity, of orders 0, 0, 0). */
  static constexpr std::array<Term, 6> Terms{ { { { 2, 0, 0 }, 1.0 },
                                                { { 0, 2, 0 }, 1.0 },
                                                { { 0, 0, 2 }, 1.0 },
                                                { { 1, 1, 0 }, 2.0 },
                                                { { 1, 0, 1 }, 2.0 },
                                                { { 0, 1, 1 }, 2.0 } } };

  /** The diagonal of R + shift I, one value per coefficient. */
  Eigen::VectorXd
  GetDiagonal() const
  {
    Eigen::VectorXd diagonal(static_cast<Eigen::Index>(m_Size[0] * m_Size[1] * m_Size[2]));
    for (size_t k = 0; k < m_Size[2]; ++k)
    {
      for (size_t j = 0; j < m_Size[1]; ++j)
      {
        for (size_t i = 0; i < m_Size[0]; ++i)
        {
          const std::array<size_t, 3> at{ i, j, k };
          double                      value = m_Shift;
          for (const Term & term : Terms)
          {
            double product = term.Weight;
            for (unsigned int axis = 0; axis < 3; ++axis)
            {
              product *= term.Orders[axis] == 0
                           ? 1.0
                           : GetAxisFactor(axis, term.Orders[axis])[at[axis] * m_Size[axis] + at[axis]];
            }
            value += product;
          }
          diagonal[static_cast<Eigen::Index>(i + m_Size[0] * (j + m_Size[1] * k))] = value;
        }
      }
    }
    return diagonal;
  }

  /** The shift added to R. */
  double
  GetShift() const
  {
    return m_Shift;
  }

  /** D2^T D2 (\c order 2) or D1^T D1 (\c order 1) of an axis: dense, row-major, the axis' length squared. */
  const std::vector<double> &
  GetAxisFactor(unsigned int axis, unsigned int order) const
  {
    return order == 2 ? m_Second[axis] : m_First[axis];
  }

  /** The number of values a product reads and writes: Columns per coefficient. */
  size_t
  GetNumberOfValues() const
  {
    return m_Count;
  }

private:
  /** out += factor A in along \c axis, A the axis' banded matrix (half-width \c band): per position i along the
   * axis, the hyperplane of values at i is a set of contiguous runs (one per index of the axes above), each summed
   * over the band a block at a time in registers before it is added. */
  void
  AddAlongAxis(const std::vector<double> & matrix,
               size_t                      band,
               unsigned int                axis,
               double                      factor,
               const double *              in,
               double *                    out) const
  {
    const size_t n = m_Size[axis];
    const size_t run = m_Stride[axis];
    const size_t period = run * n;
    // Along the first axis a run is one coefficient's Columns values: the lines are contiguous instead, and away
    // from their ends (band <= i < n - band) the matrix's rows are one stencil (a banded Toeplitz matrix), applied
    // along the line with constant weights; the ends take the rows one by one below.
    const bool alongLines = run == Columns && n > 2 * band;
    for (size_t base = 0; base < m_Count; base += period)
    {
      if (alongLines)
      {
        const double *   stencil = matrix.data() + band * n; // row band: weights of band - band .. band + band
        const size_t     width = 2 * band + 1;
        const size_t     end = base + (n - band) * run;
        constexpr size_t block = BlockType::SizeAtCompileTime;
        size_t           q = base + band * run;
        for (; q + block <= end; q += block)
        {
          BlockType sum = BlockType::Zero();
          for (size_t o = 0; o < width; ++o)
          {
            sum += stencil[o] * Eigen::Map<const BlockType>(in + q + o * run - band * run);
          }
          Eigen::Map<BlockType>(out + q) += factor * sum;
        }
        for (; q < end; ++q)
        {
          double sum = 0.0;
          for (size_t o = 0; o < width; ++o)
          {
            sum += stencil[o] * in[q + o * run - band * run];
          }
          out[q] += factor * sum;
        }
      }
      for (size_t i = 0; i < n; ++i)
      {
        if (alongLines && i >= band && i < n - band)
        {
          continue;
        }
        const size_t     jBegin = i >= band ? i - band : 0;
        const size_t     jEnd = std::min(n, i + band + 1);
        const double *   weights = matrix.data() + i * n;
        double *         target = out + base + i * run;
        constexpr size_t block = BlockType::SizeAtCompileTime;
        size_t           q = 0;
        for (; q + block <= run; q += block)
        {
          BlockType sum = BlockType::Zero();
          for (size_t j = jBegin; j < jEnd; ++j)
          {
            sum += weights[j] * Eigen::Map<const BlockType>(in + base + j * run + q);
          }
          Eigen::Map<BlockType>(target + q) += factor * sum;
        }
        for (; q < run; ++q)
        {
          double sum = 0.0;
          for (size_t j = jBegin; j < jEnd; ++j)
          {
            sum += weights[j] * in[base + j * run + q];
          }
          target[q] += factor * sum;
        }
      }
    }
  }

  std::array<size_t, 3>              m_Size;
  double                             m_Shift;
  std::array<size_t, 3>              m_Stride{};
  size_t                             m_Count{ 0 };
  std::array<std::vector<double>, 3> m_Second{};
  std::array<std::vector<double>, 3> m_First{};
  mutable std::vector<double>        m_AlongX{};
};
} // namespace detail
} // namespace itk

#endif // itkBSplineLatticeBendingProduct_h
