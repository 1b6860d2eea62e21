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
#ifndef itkBSplineNormalMatrixAssembler_h
#define itkBSplineNormalMatrixAssembler_h

#include "itkMacro.h"

#include "itk_eigen.h"
#include ITK_EIGEN(Dense)
#include ITK_EIGEN(Sparse)

#include <algorithm>
#include <array>
#include <map>
#include <vector>

namespace itk
{
namespace detail
{
/** \class BSplineNormalMatrixAssembler
 * \brief Assembles B^T diag(m) B, the normal matrix of weighted cubic B-spline samples on a 3-D control lattice,
 * into one sparsity pattern fixed for the whole registration.
 *
 * B holds, per sample, the 64 weights of its cubic B-spline support (a 4 x 4 x 4 block of the lattice, indices
 * i + n0 (j + n1 k) as in a BSplineTransform's parameters per dimension). The pattern holds every pair of
 * coefficients that share a sample's support block (the support of B^T B) and every entry of a given regularizer
 * (e.g. a lattice bending matrix), nothing else: coefficients far from the samples keep only the regularizer's
 * entries, so a solver's products cost what they cost on Eigen's own sum of the two. Sums of such matrices (the M-step
 * of a coherent point drift on the coefficients: B^T diag(P1) B + s (R + e I)) are then sums of value arrays, without a
 * sparse product or a new structure per iteration.
 *
 * Samples with the same support block are grouped; per block the 64 x 64 product W^T diag(m) W is one dense
 * product, scattered into the pattern through a table of positions. The result equals Eigen's
 * B^T * (m.asDiagonal() * B) up to rounding (tested against it).
 * \ingroup FFDShapeMatching
 */
class BSplineNormalMatrixAssembler
{
public:
  using SparseMatrix = Eigen::SparseMatrix<double>;
  using WeightsType = std::array<double, 64>;
  using IndicesType = std::array<unsigned int, 64>;

  /** The pattern for a lattice of \c size coefficients, the samples' supports (\c indices[m] in the order of
   * detail::BSplineSupportWeights: the first axis fastest) and a \c regularizer whose entries the pattern also holds
   * (its entries at most 3 lattice steps apart along each axis). */
  BSplineNormalMatrixAssembler(const std::array<size_t, 3> &    size,
                               const std::vector<IndicesType> & indices,
                               const std::vector<WeightsType> & weights,
                               const SparseMatrix &             regularizer)
    : m_Size(size)
  {
    const size_t count = size[0] * size[1] * size[2];
    if (regularizer.rows() != static_cast<Eigen::Index>(count) || regularizer.cols() != regularizer.rows())
    {
      itkGenericExceptionMacro(<< "BSplineNormalMatrixAssembler: a " << regularizer.rows() << " x "
                               << regularizer.cols() << " regularizer for " << count << " coefficients");
    }
    if (indices.size() != weights.size())
    {
      itkGenericExceptionMacro(<< "BSplineNormalMatrixAssembler: " << indices.size() << " supports but "
                               << weights.size() << " weight sets");
    }
    // The offset between supports a and b of one block (local coordinates a = a0 + 4 (a1 + 4 a2)).
    for (unsigned int a = 0; a < 64; ++a)
    {
      for (unsigned int b = 0; b < 64; ++b)
      {
        m_LocalOffsets[a * 64 + b] = OffsetIndex(static_cast<long>(a % 4) - static_cast<long>(b % 4),
                                                 static_cast<long>((a / 4) % 4) - static_cast<long>((b / 4) % 4),
                                                 static_cast<long>(a / 16) - static_cast<long>(b / 16));
      }
    }

    // The samples grouped by support block (its first index).
    std::map<unsigned int, std::vector<size_t>> groups;
    for (size_t m = 0; m < indices.size(); ++m)
    {
      if (indices[m][63] >= count)
      {
        itkGenericExceptionMacro(<< "BSplineNormalMatrixAssembler: sample " << m << " has a support outside the "
                                 << size[0] << " x " << size[1] << " x " << size[2] << " lattice");
      }
      groups[indices[m][0]].push_back(m);
    }
    for (auto & group : groups)
    {
      Block block;
      block.Indices = indices[group.second.front()];
      block.Samples = std::move(group.second);
      block.Weights.resize(static_cast<Eigen::Index>(block.Samples.size()), 64);
      for (size_t s = 0; s < block.Samples.size(); ++s)
      {
        for (unsigned int n = 0; n < 64; ++n)
        {
          block.Weights(static_cast<Eigen::Index>(s), n) = weights[block.Samples[s]][n];
        }
      }
      m_LargestBlock = std::max(m_LargestBlock, block.Samples.size());
      m_Blocks.push_back(std::move(block));
    }

    // The entries needed: the regularizer's and every pair within one block.
    std::vector<char> needed(count * Offsets, 0);
    for (Eigen::Index column = 0; column < regularizer.outerSize(); ++column)
    {
      for (SparseMatrix::InnerIterator entry(regularizer, column); entry; ++entry)
      {
        needed[static_cast<size_t>(column) * Offsets +
               OffsetBetween(static_cast<size_t>(entry.row()), static_cast<size_t>(column))] = 1;
      }
    }
    for (const Block & block : m_Blocks)
    {
      for (unsigned int b = 0; b < 64; ++b)
      {
        for (unsigned int a = 0; a < 64; ++a)
        {
          needed[static_cast<size_t>(block.Indices[b]) * Offsets + m_LocalOffsets[a * 64 + b]] = 1;
        }
      }
    }

    // The pattern, column by column, rows in increasing order; the table of positions per column and offset.
    m_Pattern.resize(static_cast<Eigen::Index>(count), static_cast<Eigen::Index>(count));
    m_Positions.assign(count * Offsets, -1);
    std::vector<int> outer(count + 1, 0);
    std::vector<int> inner;
    for (size_t column = 0; column < count; ++column)
    {
      const std::array<long, 3> at = LatticeCoordinates(column);
      for (long c = -3; c <= 3; ++c)
      {
        for (long b = -3; b <= 3; ++b)
        {
          for (long a = -3; a <= 3; ++a)
          {
            const std::array<long, 3> row{ at[0] + a, at[1] + b, at[2] + c };
            if (!InsideLattice(row) || !needed[column * Offsets + OffsetIndex(a, b, c)])
            {
              continue;
            }
            m_Positions[column * Offsets + OffsetIndex(a, b, c)] = static_cast<int>(inner.size());
            inner.push_back(
              static_cast<int>(row[0] + static_cast<long>(size[0]) * (row[1] + static_cast<long>(size[1]) * row[2])));
          }
        }
      }
      outer[column + 1] = static_cast<int>(inner.size());
    }
    Eigen::VectorXi perColumn(static_cast<Eigen::Index>(count));
    for (size_t column = 0; column < count; ++column)
    {
      perColumn[static_cast<Eigen::Index>(column)] = outer[column + 1] - outer[column];
    }
    m_Pattern.reserve(perColumn);
    for (size_t column = 0; column < count; ++column)
    {
      for (int p = outer[column]; p < outer[column + 1]; ++p)
      {
        m_Pattern.insert(inner[p], static_cast<Eigen::Index>(column)) = 0.0;
      }
    }
    m_Pattern.makeCompressed();
  }

  /** The fixed pattern, every value zero. */
  const SparseMatrix &
  GetPattern() const
  {
    return m_Pattern;
  }

  /** The values of \c matrix aligned with the pattern's value array (entries outside the pattern are an error). */
  Eigen::VectorXd
  Align(const SparseMatrix & matrix) const
  {
    if (matrix.rows() != m_Pattern.rows() || matrix.cols() != m_Pattern.cols())
    {
      itkGenericExceptionMacro(<< "BSplineNormalMatrixAssembler: a " << matrix.rows() << " x " << matrix.cols()
                               << " matrix does not fit the " << m_Pattern.rows() << " x " << m_Pattern.cols()
                               << " pattern");
    }
    Eigen::VectorXd values = Eigen::VectorXd::Zero(m_Pattern.nonZeros());
    for (Eigen::Index column = 0; column < matrix.outerSize(); ++column)
    {
      for (SparseMatrix::InnerIterator entry(matrix, column); entry; ++entry)
      {
        const int position = m_Positions[static_cast<size_t>(column) * Offsets +
                                         OffsetBetween(static_cast<size_t>(entry.row()), static_cast<size_t>(column))];
        if (position < 0)
        {
          itkGenericExceptionMacro(<< "BSplineNormalMatrixAssembler: entry (" << entry.row() << ", " << column
                                   << ") is outside the pattern");
        }
        values[position] += entry.value();
      }
    }
    return values;
  }

  /** The values of B^T diag(mass) B, aligned with the pattern's value array (\c mass per sample). */
  void
  Assemble(const Eigen::VectorXd & mass, Eigen::VectorXd & values) const
  {
    values.setZero(m_Pattern.nonZeros());
    Eigen::Matrix<double, 64, 64> product;
    Eigen::MatrixXd               weighted(static_cast<Eigen::Index>(m_LargestBlock), 64);
    for (const Block & block : m_Blocks)
    {
      const auto rows = static_cast<Eigen::Index>(block.Samples.size());
      bool       any = false;
      for (Eigen::Index s = 0; s < rows; ++s)
      {
        const double m = mass[static_cast<Eigen::Index>(block.Samples[static_cast<size_t>(s)])];
        any = any || m != 0.0;
        weighted.row(s) = m * block.Weights.row(s);
      }
      if (!any)
      {
        continue;
      }
      product.noalias() = block.Weights.transpose() * weighted.topRows(rows);
      for (unsigned int b = 0; b < 64; ++b)
      {
        const int * positions = m_Positions.data() + static_cast<size_t>(block.Indices[b]) * Offsets;
        for (unsigned int a = 0; a < 64; ++a)
        {
          values[positions[m_LocalOffsets[a * 64 + b]]] += product(a, b);
        }
      }
    }
  }

  /** \c matrix with the pattern and \c values (aligned with the pattern's value array). */
  void
  Fill(const Eigen::VectorXd & values, SparseMatrix & matrix) const
  {
    if (matrix.nonZeros() != m_Pattern.nonZeros() || matrix.rows() != m_Pattern.rows())
    {
      matrix = m_Pattern;
    }
    std::copy(values.data(), values.data() + values.size(), matrix.valuePtr());
  }

private:
  static constexpr size_t Offsets = 343;

  struct Block
  {
    IndicesType         Indices{};
    std::vector<size_t> Samples;
    Eigen::MatrixXd     Weights;
  };

  static unsigned int
  OffsetIndex(long a, long b, long c)
  {
    return static_cast<unsigned int>((a + 3) + 7 * ((b + 3) + 7 * (c + 3)));
  }

  /** The offset index of row \c row in column \c column; throws beyond 3 lattice steps along an axis. */
  unsigned int
  OffsetBetween(size_t row, size_t column) const
  {
    const std::array<long, 3> p = LatticeCoordinates(row);
    const std::array<long, 3> q = LatticeCoordinates(column);
    if (std::max({ std::abs(p[0] - q[0]), std::abs(p[1] - q[1]), std::abs(p[2] - q[2]) }) > 3)
    {
      itkGenericExceptionMacro(<< "BSplineNormalMatrixAssembler: entry (" << row << ", " << column
                               << ") is more than 3 lattice steps off the diagonal");
    }
    return OffsetIndex(p[0] - q[0], p[1] - q[1], p[2] - q[2]);
  }

  std::array<long, 3>
  LatticeCoordinates(size_t index) const
  {
    return { static_cast<long>(index % m_Size[0]),
             static_cast<long>((index / m_Size[0]) % m_Size[1]),
             static_cast<long>(index / (m_Size[0] * m_Size[1])) };
  }

  bool
  InsideLattice(const std::array<long, 3> & at) const
  {
    for (unsigned int d = 0; d < 3; ++d)
    {
      if (at[d] < 0 || at[d] >= static_cast<long>(m_Size[d]))
      {
        return false;
      }
    }
    return true;
  }

  std::array<size_t, 3>          m_Size;
  SparseMatrix                   m_Pattern;
  std::vector<int>               m_Positions;
  std::array<unsigned int, 4096> m_LocalOffsets{};
  std::vector<Block>             m_Blocks;
  size_t                         m_LargestBlock{ 0 };
};
} // namespace detail
} // namespace itk

#endif // itkBSplineNormalMatrixAssembler_h
