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
#ifndef itkSparseMultipleRightHandConjugateGradient_h
#define itkSparseMultipleRightHandConjugateGradient_h

#include "itkMacro.h"

#include "itk_eigen.h"
#include ITK_EIGEN(Dense)
#include ITK_EIGEN(Sparse)

#include <algorithm>
#include <limits>

namespace itk
{
namespace detail
{
/** \file itkSparseMultipleRightHandConjugateGradient.h
 * \brief Jacobi-preconditioned conjugate gradients for A X = B with a symmetric positive definite A and a few
 * right-hand sides (columns of B), run side by side.
 *
 * Each column follows its own conjugate-gradient recurrence (the iterates equal those of
 * Eigen::ConjugateGradient with its diagonal preconditioner, column by column, up to rounding), but every iteration
 * applies A once to all columns: where A is a sparse matrix larger than the cache, or a matrix-free operator that
 * passes over its samples (detail::BSplineSampleNormalOperator), that pass is what costs, and three columns cost
 * about one column's time.
 *
 * SolveConjugateGradient takes A as \c apply(in, out), out = A in on row-major blocks, and its \c diagonal; the
 * preconditioner is D^-1, or D^-1 + C with a \c correct(r, z) that adds C r to z = D^-1 r (C symmetric positive
 * semi-definite, e.g. a coarse-grid correction, detail::BSplineLatticeCoarseCorrection).
 * SolveSparseConjugateGradient takes A as a sparse matrix: its product is taken as the row-major transpose of the
 * column-major A (equal, A being symmetric), so one pass over A's entries serves every column.
 *
 * A column stops when its residual norm is below \c tolerance times its right-hand side's norm, or after
 * \c maximumIterations. \c solution holds the starting guess on entry. Returns the largest number of iterations any
 * column took. Throws itk::ExceptionObject when the sizes do not agree or the diagonal is not positive.
 * \ingroup FFDShapeMatching
 */
/** A preconditioner correction that adds nothing (the preconditioner is then D^-1 alone). */
struct NoPreconditionerCorrection
{
  template <typename TBlock>
  void
  operator()(const TBlock &, TBlock &) const
  {}
};

/** The conjugate gradients with a general preconditioner: \c precondition(r, z) sets z = M^-1 r, M symmetric positive
 * definite (e.g. block Jacobi, detail::BSplineLatticeBlockJacobi, plus a coarse correction). \c apply, the
 * right-hand side, the starting guess in \c solution, the stopping rule and the result as SolveConjugateGradient. */
template <int TColumns, typename TApply, typename TPrecondition>
unsigned int
SolvePreconditionedConjugateGradient(
  const TApply &                                                           apply,
  const TPrecondition &                                                    precondition,
  const Eigen::Matrix<double, Eigen::Dynamic, TColumns, Eigen::RowMajor> & rightHandSide,
  Eigen::Matrix<double, Eigen::Dynamic, TColumns, Eigen::RowMajor> &       solution,
  unsigned int                                                             maximumIterations,
  double                                                                   tolerance)
{
  using BlockType = Eigen::Matrix<double, Eigen::Dynamic, TColumns, Eigen::RowMajor>;
  using RowType = Eigen::Matrix<double, 1, TColumns>;
  const Eigen::Index size = rightHandSide.rows();
  if (solution.rows() != size)
  {
    itkGenericExceptionMacro(<< "SolveConjugateGradient: " << size << " right-hand rows and " << solution.rows()
                             << " solution rows do not agree");
  }

  BlockType product(size, TColumns);
  apply(solution, product);
  BlockType     residual = rightHandSide - product;
  const RowType rightNorm2 = rightHandSide.colwise().squaredNorm();
  RowType       threshold;
  for (int c = 0; c < TColumns; ++c)
  {
    threshold[c] = std::max(tolerance * tolerance * rightNorm2[c], std::numeric_limits<double>::min());
    if (rightNorm2[c] == 0.0)
    {
      solution.col(c).setZero();
      residual.col(c).setZero();
    }
  }
  RowType residualNorm2 = residual.colwise().squaredNorm();
  auto    active = [&](int c) { return rightNorm2[c] != 0.0 && residualNorm2[c] >= threshold[c]; };

  BlockType direction(size, TColumns);
  precondition(residual, direction);
  RowType      rho = (residual.cwiseProduct(direction)).colwise().sum();
  unsigned int iterations = 0;
  for (; iterations < maximumIterations; ++iterations)
  {
    bool any = false;
    for (int c = 0; c < TColumns; ++c)
    {
      any = any || active(c);
    }
    if (!any)
    {
      break;
    }
    apply(direction, product);
    RowType curvature = RowType::Zero();
    for (Eigen::Index n = 0; n < size; ++n)
    {
      curvature += direction.row(n).cwiseProduct(product.row(n));
    }
    RowType alpha = RowType::Zero();
    for (int c = 0; c < TColumns; ++c)
    {
      if (active(c) && curvature[c] > 0.0)
      {
        alpha[c] = rho[c] / curvature[c];
      }
    }
    // One pass: the step, the new residual and its norm; then its preconditioned form (kept in product) and rho.
    RowType rhoNew = RowType::Zero();
    residualNorm2.setZero();
    for (Eigen::Index n = 0; n < size; ++n)
    {
      solution.row(n) += direction.row(n).cwiseProduct(alpha);
      residual.row(n) -= product.row(n).cwiseProduct(alpha);
      residualNorm2 += residual.row(n).cwiseAbs2();
    }
    precondition(residual, product);
    for (Eigen::Index n = 0; n < size; ++n)
    {
      rhoNew += residual.row(n).cwiseProduct(product.row(n));
    }
    RowType beta = RowType::Zero();
    for (int c = 0; c < TColumns; ++c)
    {
      if (alpha[c] != 0.0 && rho[c] != 0.0)
      {
        beta[c] = rhoNew[c] / rho[c];
      }
      else
      {
        residualNorm2[c] = 0.0; // a column that made no step has converged or broken down: freeze it
      }
    }
    for (Eigen::Index n = 0; n < size; ++n)
    {
      direction.row(n) = product.row(n) + direction.row(n).cwiseProduct(beta);
    }
    rho = rhoNew;
  }
  return iterations;
}

template <int TColumns, typename TApply, typename TCorrect = NoPreconditionerCorrection>
unsigned int
SolveConjugateGradient(const TApply &                                                           apply,
                       const Eigen::VectorXd &                                                  diagonal,
                       const Eigen::Matrix<double, Eigen::Dynamic, TColumns, Eigen::RowMajor> & rightHandSide,
                       Eigen::Matrix<double, Eigen::Dynamic, TColumns, Eigen::RowMajor> &       solution,
                       unsigned int                                                             maximumIterations,
                       double                                                                   tolerance,
                       const TCorrect &                                                         correct = TCorrect())
{
  using BlockType = Eigen::Matrix<double, Eigen::Dynamic, TColumns, Eigen::RowMajor>;
  const Eigen::Index size = diagonal.size();
  if (rightHandSide.rows() != size || solution.rows() != size)
  {
    itkGenericExceptionMacro(<< "SolveConjugateGradient: a diagonal of " << size << " entries, " << rightHandSide.rows()
                             << " right-hand rows and " << solution.rows() << " solution rows do not agree");
  }
  Eigen::VectorXd inverseDiagonal(size);
  for (Eigen::Index n = 0; n < size; ++n)
  {
    if (!(diagonal[n] > 0.0))
    {
      itkGenericExceptionMacro(<< "SolveConjugateGradient: diagonal entry " << n << " is " << diagonal[n]
                               << ", not positive");
    }
    inverseDiagonal[n] = 1.0 / diagonal[n];
  }
  return SolvePreconditionedConjugateGradient<TColumns>(
    apply,
    [&inverseDiagonal, &correct](const BlockType & residual, BlockType & z) {
      z.noalias() = inverseDiagonal.asDiagonal() * residual;
      correct(residual, z);
    },
    rightHandSide,
    solution,
    maximumIterations,
    tolerance);
}

/** SolveConjugateGradient with A a sparse symmetric matrix (see the file's description). */
template <int TColumns>
unsigned int
SolveSparseConjugateGradient(const Eigen::SparseMatrix<double> &                                      matrix,
                             const Eigen::Matrix<double, Eigen::Dynamic, TColumns, Eigen::RowMajor> & rightHandSide,
                             Eigen::Matrix<double, Eigen::Dynamic, TColumns, Eigen::RowMajor> &       solution,
                             unsigned int                                                             maximumIterations,
                             double                                                                   tolerance)
{
  using BlockType = Eigen::Matrix<double, Eigen::Dynamic, TColumns, Eigen::RowMajor>;
  if (matrix.cols() != matrix.rows())
  {
    itkGenericExceptionMacro(<< "SolveSparseConjugateGradient: a " << matrix.rows() << " x " << matrix.cols()
                             << " matrix is not square");
  }
  const auto transposed = matrix.transpose(); // row-major view; equal to matrix, which is symmetric
  return SolveConjugateGradient<TColumns>(
    [&transposed](const BlockType & in, BlockType & out) { out.noalias() = transposed * in; },
    Eigen::VectorXd(matrix.diagonal()),
    rightHandSide,
    solution,
    maximumIterations,
    tolerance);
}
} // namespace detail
} // namespace itk

#endif // itkSparseMultipleRightHandConjugateGradient_h
