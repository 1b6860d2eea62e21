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
#ifndef itkBSplineSampleNormalOperator_h
#define itkBSplineSampleNormalOperator_h

#include "FFDShapeMatchingDetail/itkBSplineLatticeBendingProduct.h"
#include "FFDShapeMatchingDetail/itkBSplineLatticeRegularization.h"
#include "itkMacro.h"

#include "itk_eigen.h"
#include ITK_EIGEN(Dense)
#include ITK_EIGEN(Sparse)

#include <array>
#include <optional>
#include <utility>
#include <vector>

namespace itk
{
namespace detail
{
/** \class BSplineSampleNormalOperator
 * \brief The product (B^T diag(m) B + s R) X for weighted cubic B-spline samples on a control lattice, without
 * forming the matrix.
 *
 * B holds, per sample, the weights of its cubic B-spline support: a 4 x 4 x 4 block of the lattice (coefficient
 * index i + n0 (j + n1 k), as in a BSplineTransform's parameters per dimension) from its corner \c first, with the
 * separable weights wx[a] wy[b] wz[c] (\c weights[a], \c weights[4 + b], \c weights[8 + c], as
 * detail::BSplineSeparableSupport gives them). m is a mass per sample, R a sparse symmetric regularizer (e.g. a
 * lattice bending matrix) and s its weight. X has three columns (one per coordinate), side by side in a row-major
 * block.
 *
 * Each product is one pass over the samples (per sample: its block of coefficient rows gathered, weighted by the
 * sample's mass and scattered back, four contiguous rows at a time) and one over R's rows. That is the normal matrix
 * of the M-step of a coherent point drift on the coefficients, applied as the conjugate gradients need it: the matrix
 * itself, which holds every pair of coefficients sharing a sample's support (up to 343 per row), is never built,
 * and a new mass costs nothing. The result equals Eigen's (B^T diag(m) B + s R) X up to rounding (tested against
 * it), and GetDiagonal() the matrix's diagonal, for a Jacobi preconditioner. ApplyBasis() and ApplyBasisTranspose()
 * apply B and B^T alone with the same gathers and scatters (the samples' positions and the M-step's right-hand side).
 * \ingroup FFDShapeMatching
 */
class BSplineSampleNormalOperator
{
public:
  using WeightsType = std::array<double, 12>;
  using BlockType = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;
  using RegularizerType = Eigen::SparseMatrix<double, Eigen::RowMajor>;

  /** The samples' supports (corner \c firsts[m], separable \c weights[m]) on a lattice of \c size coefficients,
   * and the regularizer (square, one row per coefficient). Throws itk::ExceptionObject when the sizes do not agree
   * or a support leaves the lattice. The masses start at zero and the regularizer's weight at one. */
  BSplineSampleNormalOperator(const std::array<size_t, 3> &       size,
                              std::vector<unsigned int>           firsts,
                              std::vector<WeightsType>            weights,
                              const Eigen::SparseMatrix<double> & regularizer)
    : BSplineSampleNormalOperator(size, std::move(firsts), std::move(weights))
  {
    if (regularizer.rows() != static_cast<Eigen::Index>(m_Count) || regularizer.cols() != regularizer.rows())
    {
      itkGenericExceptionMacro(<< "BSplineSampleNormalOperator: a " << regularizer.rows() << " x " << regularizer.cols()
                               << " regularizer for " << m_Count << " coefficients");
    }
    m_Regularizer = regularizer;
    m_Regularizer.makeCompressed();
    m_RegularizerDiagonal = m_Regularizer.diagonal();
  }

  /** The same, with R the lattice's bending matrix plus \c shift times the identity
   * (BSplineLatticeBendingMatrix(size) + shift I): R is then applied by its one-axis factors
   * (BSplineLatticeBendingProduct) and never formed entry by entry (GetRegularizer() forms it when asked). */
  BSplineSampleNormalOperator(const std::array<size_t, 3> & size,
                              std::vector<unsigned int>     firsts,
                              std::vector<WeightsType>      weights,
                              double                        shift)
    : BSplineSampleNormalOperator(size, std::move(firsts), std::move(weights))
  {
    m_BendingProduct.emplace(size, shift);
    m_RegularizerDiagonal = m_BendingProduct->GetDiagonal();
  }

  /** The samples' masses m (one per sample) and the regularizer's weight s. */
  void
  SetWeighting(const Eigen::VectorXd & mass, double regularizerWeight)
  {
    if (mass.size() != static_cast<Eigen::Index>(m_Firsts.size()))
    {
      itkGenericExceptionMacro(<< "BSplineSampleNormalOperator: " << mass.size() << " masses for " << m_Firsts.size()
                               << " samples");
    }
    m_Mass = mass;
    m_RegularizerWeight = regularizerWeight;
  }

  /** out = (B^T diag(m) B + s R) in. */
  void
  Apply(const BlockType & in, BlockType & out) const
  {
    if (in.rows() != static_cast<Eigen::Index>(m_Count))
    {
      itkGenericExceptionMacro(<< "BSplineSampleNormalOperator: " << in.rows() << " rows for " << m_Count
                               << " coefficients");
    }
    out.resize(in.rows(), 3);
    const double * source = in.data();
    double *       target = out.data();
    if (m_BendingProduct)
    {
      m_BendingProduct->Apply(source, target, m_RegularizerWeight);
    }
    else
    {
      this->ApplyRegularizerEntries(source, target);
    }
    for (size_t m = 0; m < m_Firsts.size(); ++m)
    {
      const double mass = m_Mass[static_cast<Eigen::Index>(m)];
      if (mass == 0.0)
      {
        continue;
      }
      std::array<double, 3> v = this->GatherSample(source, m);
      for (double & value : v)
      {
        value *= mass;
      }
      this->ScatterSample(v, m, target);
    }
  }

private:
  /** The samples and the lattice, checked; the public constructors add the regularizer. */
  BSplineSampleNormalOperator(const std::array<size_t, 3> & size,
                              std::vector<unsigned int>     firsts,
                              std::vector<WeightsType>      weights)
    : m_Size(size)
    , m_RowStride(size[0])
    , m_SliceStride(size[0] * size[1])
    , m_Count(size[0] * size[1] * size[2])
    , m_Firsts(std::move(firsts))
    , m_Weights(std::move(weights))
    , m_Mass(Eigen::VectorXd::Zero(static_cast<Eigen::Index>(m_Firsts.size())))
  {
    if (m_Firsts.size() != m_Weights.size())
    {
      itkGenericExceptionMacro(<< "BSplineSampleNormalOperator: " << m_Firsts.size() << " supports but "
                               << m_Weights.size() << " weight sets");
    }
    for (size_t m = 0; m < m_Firsts.size(); ++m)
    {
      const size_t first = m_Firsts[m];
      if (first % size[0] + 3 >= size[0] || (first / size[0]) % size[1] + 3 >= size[1] ||
          first / m_SliceStride + 3 >= size[2])
      {
        itkGenericExceptionMacro(<< "BSplineSampleNormalOperator: sample " << m << "'s support leaves the " << size[0]
                                 << " x " << size[1] << " x " << size[2] << " lattice");
      }
    }
  }

  /** target = s R source from R's entries, row by row, each row's three sums held in registers. */
  void
  ApplyRegularizerEntries(const double * source, double * target) const
  {
    const auto * rowStarts = m_Regularizer.outerIndexPtr();
    const auto * columns = m_Regularizer.innerIndexPtr();
    const auto * values = m_Regularizer.valuePtr();
    for (Eigen::Index row = 0; row < m_Regularizer.rows(); ++row)
    {
      std::array<double, 3> sum{ 0.0, 0.0, 0.0 };
      for (auto k = rowStarts[row]; k < rowStarts[row + 1]; ++k)
      {
        const double   value = values[k];
        const double * column = source + 3 * static_cast<Eigen::Index>(columns[k]);
        for (unsigned int d = 0; d < 3; ++d)
        {
          sum[d] += value * column[d];
        }
      }
      for (unsigned int d = 0; d < 3; ++d)
      {
        target[3 * row + d] = sum[d] * m_RegularizerWeight;
      }
    }
  }

public:
  /** out = B in: per sample, the three columns of \c in (one row per coefficient) summed over its support with its
   * weights (one row per sample). */
  void
  ApplyBasis(const BlockType & in, BlockType & out) const
  {
    if (in.rows() != static_cast<Eigen::Index>(m_Count))
    {
      itkGenericExceptionMacro(<< "BSplineSampleNormalOperator: " << in.rows() << " rows for " << m_Count
                               << " coefficients");
    }
    out.resize(static_cast<Eigen::Index>(m_Firsts.size()), 3);
    for (size_t m = 0; m < m_Firsts.size(); ++m)
    {
      const std::array<double, 3> v = this->GatherSample(in.data(), m);
      for (unsigned int d = 0; d < 3; ++d)
      {
        out(static_cast<Eigen::Index>(m), d) = v[d];
      }
    }
  }

  /** out = B^T in: per sample, its row of \c in spread over its support with its weights (one row per
   * coefficient). */
  void
  ApplyBasisTranspose(const BlockType & in, BlockType & out) const
  {
    if (in.rows() != static_cast<Eigen::Index>(m_Firsts.size()))
    {
      itkGenericExceptionMacro(<< "BSplineSampleNormalOperator: " << in.rows() << " rows for " << m_Firsts.size()
                               << " samples");
    }
    out.setZero(static_cast<Eigen::Index>(m_Count), 3);
    for (size_t m = 0; m < m_Firsts.size(); ++m)
    {
      this->ScatterSample({ in(static_cast<Eigen::Index>(m), 0),
                            in(static_cast<Eigen::Index>(m), 1),
                            in(static_cast<Eigen::Index>(m), 2) },
                          m,
                          out.data());
    }
  }

  /** The lattice's size, the samples' corners and separable weights, their masses, R and s, as given. */
  const std::array<size_t, 3> &
  GetSize() const
  {
    return m_Size;
  }
  const std::vector<unsigned int> &
  GetFirsts() const
  {
    return m_Firsts;
  }
  const std::vector<WeightsType> &
  GetWeights() const
  {
    return m_Weights;
  }
  const Eigen::VectorXd &
  GetMass() const
  {
    return m_Mass;
  }
  /** R as a sparse matrix (formed here when R is the lattice's bending matrix plus a shift). */
  RegularizerType
  GetRegularizer() const
  {
    if (m_BendingProduct)
    {
      const auto                  count = static_cast<Eigen::Index>(m_Count);
      Eigen::SparseMatrix<double> identity(count, count);
      identity.setIdentity();
      return RegularizerType(BSplineLatticeBendingMatrix(m_Size) + m_BendingProduct->GetShift() * identity);
    }
    return m_Regularizer;
  }

  /** The one-axis factors of R when it is the lattice's bending matrix plus a shift (null otherwise). */
  const BSplineLatticeBendingProduct *
  GetBendingProduct() const
  {
    return m_BendingProduct ? &*m_BendingProduct : nullptr;
  }
  double
  GetRegularizerWeight() const
  {
    return m_RegularizerWeight;
  }

  /** The diagonal of B^T diag(m) B + s R. */
  Eigen::VectorXd
  GetDiagonal() const
  {
    Eigen::VectorXd diagonal = m_RegularizerWeight * m_RegularizerDiagonal;
    for (size_t m = 0; m < m_Firsts.size(); ++m)
    {
      const double        mass = m_Mass[static_cast<Eigen::Index>(m)];
      const WeightsType & w = m_Weights[m];
      for (unsigned int c = 0; c < 4; ++c)
      {
        for (unsigned int b = 0; b < 4; ++b)
        {
          for (unsigned int a = 0; a < 4; ++a)
          {
            const double weight = w[a] * w[4 + b] * w[8 + c];
            diagonal[static_cast<Eigen::Index>(m_Firsts[m] + a + b * m_RowStride + c * m_SliceStride)] +=
              mass * weight * weight;
          }
        }
      }
    }
    return diagonal;
  }

private:
  /** Twelve contiguous values: a row of four coefficients along the first axis, three values each. */
  using RowOfFour = Eigen::Array<double, 12, 1>;

  /** sum over sample m's support of wx[a] wy[b] wz[c] values(row); values holds three per coefficient. The four
   * contiguous rows along the first axis (twelve values) are summed with wy[b] wz[c] over the 16 rows of the support
   * first, twelve values side by side (Eigen's vector instructions), and weighted with wx[a] at the end. */
  std::array<double, 3>
  GatherSample(const double * values, size_t m) const
  {
    const WeightsType & w = m_Weights[m];
    RowOfFour           rowSum = RowOfFour::Zero();
    for (unsigned int c = 0; c < 4; ++c)
    {
      for (unsigned int b = 0; b < 4; ++b)
      {
        rowSum += (w[4 + b] * w[8 + c]) *
                  Eigen::Map<const RowOfFour>(values + 3 * (m_Firsts[m] + b * m_RowStride + c * m_SliceStride));
      }
    }
    std::array<double, 3> v{ 0.0, 0.0, 0.0 };
    for (unsigned int a = 0; a < 4; ++a)
    {
      for (unsigned int d = 0; d < 3; ++d)
      {
        v[d] += w[a] * rowSum[3 * a + d];
      }
    }
    return v;
  }

  /** values(row) += wx[a] wy[b] wz[c] v over sample m's support: wx[a] v (twelve values, the four contiguous rows
   * along the first axis) is formed once, then added with wy[b] wz[c] to each of the 16 rows (Eigen's vector
   * instructions). */
  void
  ScatterSample(const std::array<double, 3> & v, size_t m, double * values) const
  {
    const WeightsType & w = m_Weights[m];
    RowOfFour           spread;
    for (unsigned int a = 0; a < 4; ++a)
    {
      for (unsigned int d = 0; d < 3; ++d)
      {
        spread[3 * a + d] = w[a] * v[d];
      }
    }
    for (unsigned int c = 0; c < 4; ++c)
    {
      for (unsigned int b = 0; b < 4; ++b)
      {
        Eigen::Map<RowOfFour>(values + 3 * (m_Firsts[m] + b * m_RowStride + c * m_SliceStride)) +=
          (w[4 + b] * w[8 + c]) * spread;
      }
    }
  }

  std::array<size_t, 3>     m_Size;
  size_t                    m_RowStride;
  size_t                    m_SliceStride;
  size_t                    m_Count;
  std::vector<unsigned int> m_Firsts;
  std::vector<WeightsType>  m_Weights;
  RegularizerType           m_Regularizer{}; // Empty when m_BendingProduct applies R.
  Eigen::VectorXd           m_RegularizerDiagonal;
  Eigen::VectorXd           m_Mass;
  double                    m_RegularizerWeight{ 1.0 };
  // R's product by its one-axis factors, when R is the lattice's bending matrix plus a shift.
  std::optional<BSplineLatticeBendingProduct> m_BendingProduct{};
};
} // namespace detail
} // namespace itk

#endif // itkBSplineSampleNormalOperator_h
