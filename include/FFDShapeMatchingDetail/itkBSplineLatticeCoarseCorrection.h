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
#ifndef itkBSplineLatticeCoarseCorrection_h
#define itkBSplineLatticeCoarseCorrection_h

#include "FFDShapeMatchingDetail/itkBSplineSampleNormalOperator.h"

#include "itk_eigen.h"
#include ITK_EIGEN(Cholesky)
#include ITK_EIGEN(Dense)
#include ITK_EIGEN(Sparse)

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

namespace itk
{
namespace detail
{
/** \class BSplineLatticeCoarseCorrection
 * \brief The coarse-grid part of a two-level preconditioner for the M-step's matrix A = B^T diag(m) B + s R of a
 * detail::BSplineSampleNormalOperator: C = P (P^T A P)^-1 P^T.
 *
 * P interpolates a coarse lattice of \c coarsePerAxis nodes per axis (spread evenly over the fine lattice, fewer where
 * the fine lattice has fewer) trilinearly onto the fine control lattice. Jacobi's D^-1 damps the fine lattice's
 * oscillating errors quickly but its smooth errors (whole regions of coefficients moving together, where the
 * bending term is weak) slowly; C solves for those on the coarse lattice. D^-1 + C is then the conjugate gradients'
 * preconditioner (detail::SolveConjugateGradient's \c correct adds C r).
 *
 * P^T R P is formed once (from R's one-axis factors when the operator applies R by them, from its entries otherwise);
 * Update() forms P^T B^T diag(m) B P from the samples' separable weights (a few coarse nodes
 * per axis and sample) at the operator's current masses, adds s P^T R P and factors the result (dense Cholesky; the
 * factor's rows are kept packed for the substitutions).
 * Where the factorization fails (the coarse matrix is not positive definite, e.g. no mass and no regularizer),
 * AddCorrection adds nothing and the preconditioner is Jacobi's alone. Restriction P^T and prolongation P are applied
 * axis by axis. Tested against the explicit matrices.
 * \ingroup FFDShapeMatching
 */
class BSplineLatticeCoarseCorrection
{
public:
  using BlockType = BSplineSampleNormalOperator::BlockType;

  /** The correction for \c normal (kept by reference: it must outlive this object) on a coarse lattice of
   * \c coarsePerAxis nodes per axis (at least 2; at most the fine lattice's size, per axis). Throws
   * itk::ExceptionObject for fewer than 2 nodes or a fine lattice with fewer than 2 along an axis. */
  BSplineLatticeCoarseCorrection(const BSplineSampleNormalOperator & normal, size_t coarsePerAxis)
    : m_Normal(normal)
  {
    const auto & size = normal.GetSize();
    if (coarsePerAxis < 2 || std::min({ size[0], size[1], size[2] }) < 2)
    {
      itkGenericExceptionMacro(<< "BSplineLatticeCoarseCorrection: " << coarsePerAxis << " coarse nodes per axis on a "
                               << size[0] << " x " << size[1] << " x " << size[2]
                               << " lattice (at least 2 of each are needed)");
    }
    for (unsigned int d = 0; d < 3; ++d)
    {
      Axis & axis = m_Axes[d];
      axis.Coarse = std::min(coarsePerAxis, size[d]);
      axis.Low.resize(size[d]);
      axis.Fraction.resize(size[d]);
      for (size_t i = 0; i < size[d]; ++i)
      {
        const double t =
          static_cast<double>(i) * static_cast<double>(axis.Coarse - 1) / static_cast<double>(size[d] - 1);
        const size_t low = std::min(static_cast<size_t>(std::floor(t)), axis.Coarse - 2);
        axis.Low[i] = static_cast<unsigned int>(low);
        axis.Fraction[i] = t - static_cast<double>(low);
      }
    }
    if (const BSplineLatticeBendingProduct * bending = normal.GetBendingProduct())
    {
      m_CoarseRegularizer = this->ProjectBendingMatrix(*bending);
    }
    else
    {
      const Eigen::SparseMatrix<double> prolongation = GetProlongation();
      m_CoarseRegularizer = Eigen::MatrixXd(prolongation.transpose() * (normal.GetRegularizer() * prolongation));
    }
  }

  /** The number of coarse coefficients (per coordinate). */
  size_t
  GetNumberOfCoarseCoefficients() const
  {
    return m_Axes[0].Coarse * m_Axes[1].Coarse * m_Axes[2].Coarse;
  }

  /** P as a sparse matrix (fine coefficients x coarse coefficients). */
  Eigen::SparseMatrix<double>
  GetProlongation() const
  {
    const auto &                        size = m_Normal.GetSize();
    std::vector<Eigen::Triplet<double>> entries;
    entries.reserve(8 * size[0] * size[1] * size[2]);
    for (size_t k = 0; k < size[2]; ++k)
    {
      for (size_t j = 0; j < size[1]; ++j)
      {
        for (size_t i = 0; i < size[0]; ++i)
        {
          const std::array<size_t, 3> at{ i, j, k };
          for (unsigned int corner = 0; corner < 8; ++corner)
          {
            double                weight = 1.0;
            std::array<size_t, 3> coarse{};
            for (unsigned int d = 0; d < 3; ++d)
            {
              const bool   upper = ((corner >> d) & 1U) != 0;
              const auto & axis = m_Axes[d];
              weight *= upper ? axis.Fraction[at[d]] : 1.0 - axis.Fraction[at[d]];
              coarse[d] = axis.Low[at[d]] + (upper ? 1 : 0);
            }
            entries.emplace_back(
              static_cast<int>(i + size[0] * (j + size[1] * k)),
              static_cast<int>(coarse[0] + m_Axes[0].Coarse * (coarse[1] + m_Axes[1].Coarse * coarse[2])),
              weight);
          }
        }
      }
    }
    Eigen::SparseMatrix<double> prolongation(static_cast<Eigen::Index>(size[0] * size[1] * size[2]),
                                             static_cast<Eigen::Index>(GetNumberOfCoarseCoefficients()));
    prolongation.setFromTriplets(entries.begin(), entries.end());
    return prolongation;
  }

  /** Forms and factors P^T A P at the operator's current masses and regularizer weight. */
  void
  Update()
  {
    const size_t    c0 = m_Axes[0].Coarse;
    const size_t    c1 = m_Axes[1].Coarse;
    const auto &    size = m_Normal.GetSize();
    const auto &    firsts = m_Normal.GetFirsts();
    const auto &    weights = m_Normal.GetWeights();
    const auto &    mass = m_Normal.GetMass();
    Eigen::MatrixXd coarse = m_Normal.GetRegularizerWeight() * m_CoarseRegularizer;
    for (size_t m = 0; m < firsts.size(); ++m)
    {
      const double sampleMass = mass[static_cast<Eigen::Index>(m)];
      if (sampleMass == 0.0)
      {
        continue;
      }
      // Per axis, the sample's weights on the coarse nodes (at most 5: its 4 fine nodes span at most 3 coarse steps).
      const std::array<size_t, 3>          corner{ firsts[m] % size[0],
                                          (firsts[m] / size[0]) % size[1],
                                          firsts[m] / (size[0] * size[1]) };
      std::array<std::array<double, 5>, 3> axisWeights{};
      std::array<size_t, 3>                base{};
      std::array<size_t, 3>                count{};
      for (unsigned int d = 0; d < 3; ++d)
      {
        const Axis & axis = m_Axes[d];
        base[d] = axis.Low[corner[d]];
        for (unsigned int a = 0; a < 4; ++a)
        {
          const size_t i = corner[d] + a;
          const size_t low = axis.Low[i] - base[d];
          const double w = weights[m][4 * d + a];
          axisWeights[d][low] += w * (1.0 - axis.Fraction[i]);
          axisWeights[d][low + 1] += w * axis.Fraction[i];
          count[d] = std::max(count[d], low + 2);
        }
      }
      std::array<double, 125> values{};
      std::array<size_t, 125> indices{};
      unsigned int            n = 0;
      for (size_t c = 0; c < count[2]; ++c)
      {
        for (size_t b = 0; b < count[1]; ++b)
        {
          for (size_t a = 0; a < count[0]; ++a, ++n)
          {
            values[n] = axisWeights[0][a] * axisWeights[1][b] * axisWeights[2][c];
            indices[n] = (base[0] + a) + c0 * ((base[1] + b) + c1 * (base[2] + c));
          }
        }
      }
      // The lower triangle (the indices increase with n), which the Cholesky factorization reads.
      for (unsigned int p = 0; p < n; ++p)
      {
        const double scaled = sampleMass * values[p];
        for (unsigned int q = 0; q <= p; ++q)
        {
          coarse(static_cast<Eigen::Index>(indices[p]), static_cast<Eigen::Index>(indices[q])) += scaled * values[q];
        }
      }
    }
    const Eigen::LLT<Eigen::MatrixXd> factor(coarse);
    m_Factored = factor.info() == Eigen::Success;
    if (m_Factored)
    {
      // L's rows packed one after the other (row i holds i + 1 entries), for SolveFactoredInPlace.
      const Eigen::MatrixXd & lower = factor.matrixLLT();
      const Eigen::Index      n = lower.rows();
      m_PackedFactor.resize(static_cast<size_t>(n * (n + 1) / 2));
      size_t at = 0;
      for (Eigen::Index i = 0; i < n; ++i)
      {
        for (Eigen::Index j = 0; j <= i; ++j)
        {
          m_PackedFactor[at++] = lower(i, j);
        }
      }
    }
  }

  /** Whether the last Update() factored the coarse matrix. */
  bool
  IsFactored() const
  {
    return m_Factored;
  }

  /** z += P (P^T A P)^-1 P^T r (nothing when the coarse matrix is not factored). */
  void
  AddCorrection(const BlockType & residual, BlockType & z) const
  {
    if (!m_Factored)
    {
      return;
    }
    Restrict(residual, m_Coarse);
    SolveFactoredInPlace(m_Coarse);
    Prolongate(m_Coarse, m_Fine);
    z += m_Fine;
  }

  /** coarse = P^T fine, axis by axis. */
  void
  Restrict(const BlockType & fine, BlockType & coarse) const
  {
    const auto & size = m_Normal.GetSize();
    const size_t c0 = m_Axes[0].Coarse;
    const size_t c1 = m_Axes[1].Coarse;
    m_AlongX.setZero(static_cast<Eigen::Index>(c0 * size[1] * size[2]), 3);
    for (size_t jk = 0; jk < size[1] * size[2]; ++jk)
    {
      for (size_t i = 0; i < size[0]; ++i)
      {
        const auto   row = fine.row(static_cast<Eigen::Index>(i + size[0] * jk));
        const size_t low = m_Axes[0].Low[i] + c0 * jk;
        m_AlongX.row(static_cast<Eigen::Index>(low)) += (1.0 - m_Axes[0].Fraction[i]) * row;
        m_AlongX.row(static_cast<Eigen::Index>(low + 1)) += m_Axes[0].Fraction[i] * row;
      }
    }
    m_AlongY.setZero(static_cast<Eigen::Index>(c0 * c1 * size[2]), 3);
    for (size_t k = 0; k < size[2]; ++k)
    {
      for (size_t j = 0; j < size[1]; ++j)
      {
        const double fraction = m_Axes[1].Fraction[j];
        const size_t low = c0 * (m_Axes[1].Low[j] + c1 * k);
        for (size_t i = 0; i < c0; ++i)
        {
          const auto row = m_AlongX.row(static_cast<Eigen::Index>(i + c0 * (j + size[1] * k)));
          m_AlongY.row(static_cast<Eigen::Index>(low + i)) += (1.0 - fraction) * row;
          m_AlongY.row(static_cast<Eigen::Index>(low + c0 + i)) += fraction * row;
        }
      }
    }
    coarse.setZero(static_cast<Eigen::Index>(GetNumberOfCoarseCoefficients()), 3);
    for (size_t k = 0; k < size[2]; ++k)
    {
      const double fraction = m_Axes[2].Fraction[k];
      const size_t low = c0 * c1 * m_Axes[2].Low[k];
      for (size_t ij = 0; ij < c0 * c1; ++ij)
      {
        const auto row = m_AlongY.row(static_cast<Eigen::Index>(ij + c0 * c1 * k));
        coarse.row(static_cast<Eigen::Index>(low + ij)) += (1.0 - fraction) * row;
        coarse.row(static_cast<Eigen::Index>(low + c0 * c1 + ij)) += fraction * row;
      }
    }
  }

  /** fine = P coarse, axis by axis. */
  void
  Prolongate(const BlockType & coarse, BlockType & fine) const
  {
    const auto & size = m_Normal.GetSize();
    const size_t c0 = m_Axes[0].Coarse;
    const size_t c1 = m_Axes[1].Coarse;
    m_AlongY.resize(static_cast<Eigen::Index>(c0 * c1 * size[2]), 3);
    for (size_t k = 0; k < size[2]; ++k)
    {
      const double fraction = m_Axes[2].Fraction[k];
      const size_t low = c0 * c1 * m_Axes[2].Low[k];
      for (size_t ij = 0; ij < c0 * c1; ++ij)
      {
        m_AlongY.row(static_cast<Eigen::Index>(ij + c0 * c1 * k)) =
          (1.0 - fraction) * coarse.row(static_cast<Eigen::Index>(low + ij)) +
          fraction * coarse.row(static_cast<Eigen::Index>(low + c0 * c1 + ij));
      }
    }
    m_AlongX.resize(static_cast<Eigen::Index>(c0 * size[1] * size[2]), 3);
    for (size_t k = 0; k < size[2]; ++k)
    {
      for (size_t j = 0; j < size[1]; ++j)
      {
        const double fraction = m_Axes[1].Fraction[j];
        const size_t low = c0 * (m_Axes[1].Low[j] + c1 * k);
        for (size_t i = 0; i < c0; ++i)
        {
          m_AlongX.row(static_cast<Eigen::Index>(i + c0 * (j + size[1] * k))) =
            (1.0 - fraction) * m_AlongY.row(static_cast<Eigen::Index>(low + i)) +
            fraction * m_AlongY.row(static_cast<Eigen::Index>(low + c0 + i));
        }
      }
    }
    fine.resize(static_cast<Eigen::Index>(size[0] * size[1] * size[2]), 3);
    for (size_t jk = 0; jk < size[1] * size[2]; ++jk)
    {
      for (size_t i = 0; i < size[0]; ++i)
      {
        const size_t low = m_Axes[0].Low[i] + c0 * jk;
        fine.row(static_cast<Eigen::Index>(i + size[0] * jk)) =
          (1.0 - m_Axes[0].Fraction[i]) * m_AlongX.row(static_cast<Eigen::Index>(low)) +
          m_Axes[0].Fraction[i] * m_AlongX.row(static_cast<Eigen::Index>(low + 1));
      }
    }
  }

private:
  /** coarse = (L L^T)^-1 coarse with the last Update()'s factor L (after a successful one): forward and back
   * substitution over L's packed rows, the three columns side by side. L is read twice, row after row, which costs
   * about a third of Eigen's LLT::solveInPlace on the few columns of a row-major block (there, the blocked
   * triangular solves' packing dominates). */
  void
  SolveFactoredInPlace(BlockType & coarse) const
  {
    const Eigen::Index n = coarse.rows();
    m_CoarseColumns = coarse;
    const double * row = m_PackedFactor.data();
    for (Eigen::Index i = 0; i < n; ++i) // L y = b: y_i = (b_i - L_i,<i y_<i) / L_ii
    {
      const Eigen::Map<const Eigen::VectorXd> lower(row, i);
      for (int c = 0; c < 3; ++c)
      {
        m_CoarseColumns(i, c) = (m_CoarseColumns(i, c) - lower.dot(m_CoarseColumns.col(c).head(i))) / row[i];
      }
      row += i + 1;
    }
    for (Eigen::Index i = n - 1; i >= 0; --i) // L^T x = y: x_i = y_i / L_ii, then y_<i -= L_i,<i x_i
    {
      row -= i + 1;
      const Eigen::Map<const Eigen::VectorXd> lower(row, i);
      for (int c = 0; c < 3; ++c)
      {
        const double x = m_CoarseColumns(i, c) / row[i];
        m_CoarseColumns(i, c) = x;
        m_CoarseColumns.col(c).head(i) -= x * lower;
      }
    }
    coarse = m_CoarseColumns;
  }

  /** P^T (R + shift I) P for the lattice's bending matrix R from its one-axis factors: P is the Kronecker product of
   * the axes' interpolations P_a and each term of R + shift I one of one-axis matrices A_a (the identity, D1^T D1 or
   * D2^T D2), so each term's projection is the Kronecker product of the small P_a^T A_a P_a (no fine-lattice matrix
   * is formed). */
  Eigen::MatrixXd
  ProjectBendingMatrix(const BSplineLatticeBendingProduct & bending) const
  {
    const auto & size = m_Normal.GetSize();
    // projected[axis][order]: P_a^T A P_a, A the identity (order 0), D1^T D1 (1) or D2^T D2 (2) of the axis.
    std::array<std::array<Eigen::MatrixXd, 3>, 3> projected;
    for (unsigned int axis = 0; axis < 3; ++axis)
    {
      const Axis &    a = m_Axes[axis];
      const auto      n = static_cast<Eigen::Index>(size[axis]);
      Eigen::MatrixXd interpolation = Eigen::MatrixXd::Zero(n, static_cast<Eigen::Index>(a.Coarse));
      for (Eigen::Index i = 0; i < n; ++i)
      {
        interpolation(i, a.Low[i]) += 1.0 - a.Fraction[i];
        interpolation(i, a.Low[i] + 1) += a.Fraction[i];
      }
      projected[axis][0] = interpolation.transpose() * interpolation;
      for (unsigned int order = 1; order < 3; ++order)
      {
        const Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> factor(
          bending.GetAxisFactor(axis, order).data(), n, n);
        projected[axis][order] = interpolation.transpose() * factor * interpolation;
      }
    }
    // The terms of R (BSplineLatticeBendingProduct::Terms) and the shift's identity.
    std::vector<BSplineLatticeBendingProduct::Term> terms(BSplineLatticeBendingProduct::Terms.begin(),
                                                          BSplineLatticeBendingProduct::Terms.end());
    terms.push_back({ { 0, 0, 0 }, bending.GetShift() });
    const Eigen::Index c0 = static_cast<Eigen::Index>(m_Axes[0].Coarse);
    const Eigen::Index c1 = static_cast<Eigen::Index>(m_Axes[1].Coarse);
    const Eigen::Index c2 = static_cast<Eigen::Index>(m_Axes[2].Coarse);
    Eigen::MatrixXd    coarse = Eigen::MatrixXd::Zero(c0 * c1 * c2, c0 * c1 * c2);
    for (const auto & term : terms)
    {
      const Eigen::MatrixXd & x = projected[0][term.Orders[0]];
      const Eigen::MatrixXd & y = projected[1][term.Orders[1]];
      const Eigen::MatrixXd & z = projected[2][term.Orders[2]];
      for (Eigen::Index k = 0; k < c2; ++k)
      {
        for (Eigen::Index kk = 0; kk < c2; ++kk)
        {
          for (Eigen::Index j = 0; j < c1; ++j)
          {
            for (Eigen::Index jj = 0; jj < c1; ++jj)
            {
              const double yz = term.Weight * y(j, jj) * z(k, kk);
              coarse.block(c0 * (j + c1 * k), c0 * (jj + c1 * kk), c0, c0) += yz * x;
            }
          }
        }
      }
    }
    return coarse;
  }

  /** Per axis: each fine node's lower coarse node and its fraction of the way to the next. */
  struct Axis
  {
    std::vector<unsigned int> Low;
    std::vector<double>       Fraction;
    size_t                    Coarse{ 0 };
  };

  const BSplineSampleNormalOperator & m_Normal;
  std::array<Axis, 3>                 m_Axes;
  Eigen::MatrixXd                     m_CoarseRegularizer;
  std::vector<double>                 m_PackedFactor; // L's rows, L L^T = P^T A P (see SolveFactoredInPlace).
  bool                                m_Factored{ false };
  mutable Eigen::Matrix<double, Eigen::Dynamic, 3> m_CoarseColumns;
  mutable BlockType                                m_AlongX;
  mutable BlockType                                m_AlongY;
  mutable BlockType                                m_Coarse;
  mutable BlockType                                m_Fine;
};
} // namespace detail
} // namespace itk

#endif // itkBSplineLatticeCoarseCorrection_h
