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
#ifndef itkBSplineLatticeBlockJacobi_h
#define itkBSplineLatticeBlockJacobi_h

#include "FFDShapeMatchingDetail/itkBSplineSampleNormalOperator.h"

#include "itk_eigen.h"
#include ITK_EIGEN(Cholesky)
#include ITK_EIGEN(Dense)
#include ITK_EIGEN(Sparse)

#include <array>
#include <cstdint>
#include <vector>

namespace itk
{
namespace detail
{
/** \class BSplineLatticeBlockJacobi
 * \brief Block Jacobi preconditioner for the M-step's matrix A = B^T diag(m) B + s R of a
 * detail::BSplineSampleNormalOperator: the control lattice cut into blocks of 2 x 2 x 2 coefficients, M^-1 r the
 * inverse of each block's 8 x 8 part of A applied to the block's part of r.
 *
 * Jacobi's diagonal treats each coefficient alone; B^T diag(m) B couples every pair of coefficients that share a
 * sample's support, and with masses that vary from sample to sample the diagonal is a weak guide to it. A block
 * holds the strongest of those couplings (the nearest neighbours along each axis and their diagonals), so the
 * conjugate gradients need fewer iterations (with a coarse correction added, detail::BSplineLatticeCoarseCorrection,
 * about a third fewer on the benchmark's meshes; benchmark/PEERS_MESH.md).
 *
 * The blocks' parts of R (from R's one-axis factors when the operator applies R by them, from its entries
 * otherwise) and their inverses are formed once. Update() adds the samples' parts at the operator's current masses,
 * from their separable weights (per sample and axis, the pairs of its four support nodes in one block), and factors
 * the blocks the samples reach (Cholesky); the others are s R's blocks, whose inverses are scaled. A block whose
 * factorization fails falls back to its diagonal's inverse (zero where the diagonal is not positive). Where the lattice
 * has an odd number of coefficients along an axis, its last blocks are one coefficient thick there (their missing slots
 * are left out). Tested against the blocks of the explicit matrix. \ingroup FFDShapeMatching
 */
class BSplineLatticeBlockJacobi
{
public:
  using BlockType = BSplineSampleNormalOperator::BlockType;
  /** A block's part of a matrix: slot i + 2 j + 4 k for the coefficient at offset (i, j, k) in the block. */
  using SlotMatrixType = Eigen::Matrix<double, 8, 8>;

  /** The preconditioner for \c normal (kept by reference: it must outlive this object). Call Update() before
   * Apply(). */
  explicit BSplineLatticeBlockJacobi(const BSplineSampleNormalOperator & normal)
    : m_Normal(normal)
  {
    const auto & size = normal.GetSize();
    for (unsigned int d = 0; d < 3; ++d)
    {
      m_Blocks[d] = (size[d] + 1) / 2;
    }
    const size_t count = this->GetNumberOfBlocks();
    m_Corner.resize(count);
    m_SlotMask.resize(count);
    for (size_t bk = 0; bk < m_Blocks[2]; ++bk)
    {
      for (size_t bj = 0; bj < m_Blocks[1]; ++bj)
      {
        for (size_t bi = 0; bi < m_Blocks[0]; ++bi)
        {
          const size_t b = bi + m_Blocks[0] * (bj + m_Blocks[1] * bk);
          std::uint8_t mask = 0;
          for (unsigned int slot = 0; slot < 8; ++slot)
          {
            const std::array<size_t, 3> at{ 2 * bi + (slot & 1U), 2 * bj + ((slot >> 1) & 1U), 2 * bk + (slot >> 2) };
            if (at[0] < size[0] && at[1] < size[1] && at[2] < size[2])
            {
              mask = static_cast<std::uint8_t>(mask | (1U << slot));
            }
          }
          m_Corner[b] = 2 * bi + size[0] * (2 * bj + size[1] * 2 * bk);
          m_SlotMask[b] = mask;
        }
      }
    }
    for (unsigned int slot = 0; slot < 8; ++slot)
    {
      m_SlotOffset[slot] = (slot & 1U) + size[0] * (((slot >> 1) & 1U) + size[1] * (slot >> 2));
    }

    // R's blocks (their missing slots the identity) and their inverses.
    m_Regularizer.resize(count);
    if (const BSplineLatticeBendingProduct * bending = normal.GetBendingProduct())
    {
      for (size_t b = 0; b < count; ++b)
      {
        SlotMatrixType & block = m_Regularizer[b];
        block.setZero();
        for (unsigned int p = 0; p < 8; ++p)
        {
          for (unsigned int q = 0; q < 8; ++q)
          {
            if (this->HasSlot(b, p) && this->HasSlot(b, q))
            {
              block(p, q) = this->BendingEntry(*bending, this->SlotPosition(b, p), this->SlotPosition(b, q));
            }
          }
        }
      }
    }
    else
    {
      const BSplineSampleNormalOperator::RegularizerType regularizer = normal.GetRegularizer();
      for (size_t b = 0; b < count; ++b)
      {
        m_Regularizer[b].setZero();
      }
      for (Eigen::Index row = 0; row < regularizer.outerSize(); ++row)
      {
        const size_t       b = this->BlockOf(static_cast<size_t>(row));
        const unsigned int p = this->SlotOf(static_cast<size_t>(row));
        for (BSplineSampleNormalOperator::RegularizerType::InnerIterator it(regularizer, row); it; ++it)
        {
          if (this->BlockOf(static_cast<size_t>(it.col())) == b)
          {
            m_Regularizer[b](p, this->SlotOf(static_cast<size_t>(it.col()))) = it.value();
          }
        }
      }
    }
    m_RegularizerInverse.resize(count);
    for (size_t b = 0; b < count; ++b)
    {
      this->CompleteMissingSlots(b, m_Regularizer[b]);
      m_RegularizerInverse[b] = this->Invert(b, m_Regularizer[b]);
    }

    // The blocks some sample's support reaches: only these change with the masses.
    std::vector<char> reached(count, 0);
    for (const unsigned int first : normal.GetFirsts())
    {
      const std::array<size_t, 3> corner = this->Position(first);
      for (size_t c = corner[2] / 2; c <= (corner[2] + 3) / 2; ++c)
      {
        for (size_t b = corner[1] / 2; b <= (corner[1] + 3) / 2; ++b)
        {
          for (size_t a = corner[0] / 2; a <= (corner[0] + 3) / 2; ++a)
          {
            reached[a + m_Blocks[0] * (b + m_Blocks[1] * c)] = 1;
          }
        }
      }
    }
    for (size_t b = 0; b < count; ++b)
    {
      if (reached[b])
      {
        m_ReachedIndex.push_back(b);
      }
    }
    m_Inverse.resize(count);
    m_Assembled.resize(count);
  }

  /** The number of blocks: ceil(n / 2) per axis of the lattice. */
  size_t
  GetNumberOfBlocks() const
  {
    return m_Blocks[0] * m_Blocks[1] * m_Blocks[2];
  }

  /** The number of blocks some sample's support reaches. */
  size_t
  GetNumberOfReachedBlocks() const
  {
    return m_ReachedIndex.size();
  }

  /** Forms and inverts the blocks of A at the operator's current masses and regularizer weight. */
  void
  Update()
  {
    const double s = m_Normal.GetRegularizerWeight();
    const size_t count = this->GetNumberOfBlocks();
    // The blocks no sample reaches are s R's: their inverses are R's scaled (zero when s is, as the diagonal's
    // fallback gives for a zero block).
    const double inverseWeight = s > 0.0 ? 1.0 / s : 0.0;
    for (size_t b = 0; b < count; ++b)
    {
      m_Inverse[b] = inverseWeight * m_RegularizerInverse[b];
    }
    for (const size_t b : m_ReachedIndex)
    {
      m_Assembled[b] = s * m_Regularizer[b];
    }
    const auto & firsts = m_Normal.GetFirsts();
    const auto & weights = m_Normal.GetWeights();
    const auto & mass = m_Normal.GetMass();
    // Per axis, the pairs of a support's four nodes that fall in one block: the block's index along the axis, the two
    // slots' bits and the product of the two weights.
    struct AxisPair
    {
      size_t       Block;
      unsigned int First;
      unsigned int Second;
      double       Weight;
    };
    std::array<std::array<AxisPair, 8>, 3> pairs{};
    std::array<unsigned int, 3>            pairCount{};
    for (size_t m = 0; m < firsts.size(); ++m)
    {
      const double sampleMass = mass[static_cast<Eigen::Index>(m)];
      if (sampleMass == 0.0)
      {
        continue;
      }
      const std::array<size_t, 3> corner = this->Position(firsts[m]);
      for (unsigned int d = 0; d < 3; ++d)
      {
        pairCount[d] = 0;
        for (unsigned int a = 0; a < 4; ++a)
        {
          for (unsigned int c = 0; c < 4; ++c)
          {
            const size_t i = corner[d] + a;
            const size_t j = corner[d] + c;
            if (i / 2 == j / 2)
            {
              pairs[d][pairCount[d]++] = AxisPair{ i / 2,
                                                   static_cast<unsigned int>(i & 1U),
                                                   static_cast<unsigned int>(j & 1U),
                                                   weights[m][4 * d + a] * weights[m][4 * d + c] };
            }
          }
        }
      }
      for (unsigned int z = 0; z < pairCount[2]; ++z)
      {
        const AxisPair & pz = pairs[2][z];
        for (unsigned int y = 0; y < pairCount[1]; ++y)
        {
          const AxisPair & py = pairs[1][y];
          const double     yz = sampleMass * py.Weight * pz.Weight;
          const size_t     row = m_Blocks[0] * (py.Block + m_Blocks[1] * pz.Block);
          for (unsigned int x = 0; x < pairCount[0]; ++x)
          {
            const AxisPair & px = pairs[0][x];
            m_Assembled[px.Block + row](px.First + 2 * py.First + 4 * pz.First,
                                        px.Second + 2 * py.Second + 4 * pz.Second) += yz * px.Weight;
          }
        }
      }
    }
    for (const size_t b : m_ReachedIndex)
    {
      this->CompleteMissingSlots(b, m_Assembled[b]);
      m_Inverse[b] = this->Invert(b, m_Assembled[b]);
    }
  }

  /** z = M^-1 r: per block, its inverse times the block's rows of r. */
  void
  Apply(const BlockType & residual, BlockType & z) const
  {
    z.resize(residual.rows(), 3);
    const double *              in = residual.data();
    double *                    out = z.data();
    Eigen::Matrix<double, 8, 3> gathered;
    Eigen::Matrix<double, 8, 3> product;
    for (size_t b = 0; b < m_Corner.size(); ++b)
    {
      const std::uint8_t mask = m_SlotMask[b];
      for (unsigned int slot = 0; slot < 8; ++slot)
      {
        if ((mask >> slot) & 1U)
        {
          const double * row = in + 3 * (m_Corner[b] + m_SlotOffset[slot]);
          gathered.row(slot) << row[0], row[1], row[2];
        }
        else
        {
          gathered.row(slot).setZero();
        }
      }
      product.noalias() = m_Inverse[b] * gathered;
      for (unsigned int slot = 0; slot < 8; ++slot)
      {
        if ((mask >> slot) & 1U)
        {
          double * row = out + 3 * (m_Corner[b] + m_SlotOffset[slot]);
          for (unsigned int c = 0; c < 3; ++c)
          {
            row[c] = product(slot, c);
          }
        }
      }
    }
  }

private:
  /** Whether block \c b's slot \c slot holds a coefficient (not at a thin block's missing side). */
  bool
  HasSlot(size_t b, unsigned int slot) const
  {
    return ((m_SlotMask[b] >> slot) & 1U) != 0;
  }

  std::array<size_t, 3>
  Position(size_t index) const
  {
    const auto & size = m_Normal.GetSize();
    return { index % size[0], (index / size[0]) % size[1], index / (size[0] * size[1]) };
  }

  std::array<size_t, 3>
  SlotPosition(size_t b, unsigned int slot) const
  {
    return this->Position(m_Corner[b] + m_SlotOffset[slot]);
  }

  size_t
  BlockOf(size_t index) const
  {
    const std::array<size_t, 3> at = this->Position(index);
    return at[0] / 2 + m_Blocks[0] * (at[1] / 2 + m_Blocks[1] * (at[2] / 2));
  }

  static unsigned int
  SlotOf(const std::array<size_t, 3> & at)
  {
    return static_cast<unsigned int>((at[0] & 1U) + 2 * (at[1] & 1U) + 4 * (at[2] & 1U));
  }

  unsigned int
  SlotOf(size_t index) const
  {
    return SlotOf(this->Position(index));
  }

  /** (R + shift I)(i, j) from R's one-axis factors. */
  double
  BendingEntry(const BSplineLatticeBendingProduct & bending,
               const std::array<size_t, 3> &        i,
               const std::array<size_t, 3> &        j) const
  {
    const auto & size = m_Normal.GetSize();
    double       value = i == j ? bending.GetShift() : 0.0;
    for (const auto & term : BSplineLatticeBendingProduct::Terms)
    {
      double product = term.Weight;
      for (unsigned int axis = 0; axis < 3 && product != 0.0; ++axis)
      {
        product *= term.Orders[axis] == 0
                     ? (i[axis] == j[axis] ? 1.0 : 0.0)
                     : bending.GetAxisFactor(axis, term.Orders[axis])[i[axis] * size[axis] + j[axis]];
      }
      value += product;
    }
    return value;
  }

  /** The missing slots' rows and columns of a block's matrix set to those of the identity. */
  void
  CompleteMissingSlots(size_t b, SlotMatrixType & block) const
  {
    for (unsigned int slot = 0; slot < 8; ++slot)
    {
      if (!this->HasSlot(b, slot))
      {
        block.row(slot).setZero();
        block.col(slot).setZero();
        block(slot, slot) = 1.0;
      }
    }
  }

  /** The block's inverse, its missing slots zeroed; the diagonal's inverse where the Cholesky factorization fails. */
  SlotMatrixType
  Invert(size_t b, const SlotMatrixType & block) const
  {
    SlotMatrixType                   inverse;
    const Eigen::LLT<SlotMatrixType> factor(block);
    if (factor.info() == Eigen::Success)
    {
      inverse = factor.solve(SlotMatrixType::Identity());
    }
    else
    {
      inverse.setZero();
      for (unsigned int slot = 0; slot < 8; ++slot)
      {
        inverse(slot, slot) = block(slot, slot) > 0.0 ? 1.0 / block(slot, slot) : 0.0;
      }
    }
    for (unsigned int slot = 0; slot < 8; ++slot)
    {
      if (!this->HasSlot(b, slot))
      {
        inverse.row(slot).setZero();
        inverse.col(slot).setZero();
      }
    }
    return inverse;
  }

  const BSplineSampleNormalOperator & m_Normal;
  std::array<size_t, 3>               m_Blocks{};
  std::array<size_t, 8>               m_SlotOffset{};
  std::vector<size_t>                 m_Corner{};
  std::vector<std::uint8_t>           m_SlotMask{};
  std::vector<size_t>                 m_ReachedIndex{};
  std::vector<SlotMatrixType>         m_Regularizer{};
  std::vector<SlotMatrixType>         m_RegularizerInverse{};
  std::vector<SlotMatrixType>         m_Assembled{};
  std::vector<SlotMatrixType>         m_Inverse{};
};
} // namespace detail
} // namespace itk

#endif // itkBSplineLatticeBlockJacobi_h
