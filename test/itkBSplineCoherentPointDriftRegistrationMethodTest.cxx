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
// BSplineCoherentPointDriftRegistrationMethod (the CPD method): its lattice bending energy, B-spline weights and
// normal-matrix assembly and k-d tree search within a radius against brute force, ITK and Eigen, and the registration
// of a deformed cap to a sphere with known correspondences.

#include "itkBSplineCoherentPointDriftRegistrationMethod.h"
#include "FFDShapeMatchingDetail/itkBSplineLatticeBendingProduct.h"
#include "FFDShapeMatchingDetail/itkBSplineLatticeBlockJacobi.h"
#include "FFDShapeMatchingDetail/itkBSplineLatticeCoarseCorrection.h"
#include "FFDShapeMatchingDetail/itkNeighborCandidateLists.h"
#include "itkShapeMatchingTestMeshes.h"
#include "FFDShapeMatchingDetail/itkSpatialJacobianEvaluator.h"
#include "itkTestingMacros.h"
#include "itkTranslationTransform.h"

#include "itk_eigen.h"
#include ITK_EIGEN(IterativeLinearSolvers)
#include ITK_EIGEN(SparseCholesky)

#include <algorithm>
#include <functional>
#include <iostream>
#include <limits>
#include <random>
#include <set>
#include <string>

namespace
{
using namespace ShapeMatchingTestMeshes;
using RegistrationType = itk::BSplineCoherentPointDriftRegistrationMethod<MeshType>;
using BSplineType = RegistrationType::BSplineTransformType;
using CorrespondenceContainerType = itk::PointCorrespondenceErrorCalculator<MeshType>::CorrespondenceContainerType;

// c^T R c against the bending sum written out, and R annihilating an affine field.
int
TestBendingMatrix()
{
  const std::array<size_t, 3> size{ 5, 4, 6 };
  const auto                  bending = itk::detail::BSplineLatticeBendingMatrix(size);
  const auto                  at = [&size](size_t i, size_t j, size_t k) { return i + size[0] * (j + size[1] * k); };
  std::mt19937                engine(7);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  Eigen::VectorXd                        c(size[0] * size[1] * size[2]);
  for (Eigen::Index n = 0; n < c.size(); ++n)
  {
    c[n] = uniform(engine);
  }
  double brute = 0.0;
  for (size_t k = 0; k < size[2]; ++k)
  {
    for (size_t j = 0; j < size[1]; ++j)
    {
      for (size_t i = 0; i < size[0]; ++i)
      {
        if (i + 2 < size[0])
        {
          brute += std::pow(c[at(i, j, k)] - 2.0 * c[at(i + 1, j, k)] + c[at(i + 2, j, k)], 2);
        }
        if (j + 2 < size[1])
        {
          brute += std::pow(c[at(i, j, k)] - 2.0 * c[at(i, j + 1, k)] + c[at(i, j + 2, k)], 2);
        }
        if (k + 2 < size[2])
        {
          brute += std::pow(c[at(i, j, k)] - 2.0 * c[at(i, j, k + 1)] + c[at(i, j, k + 2)], 2);
        }
        if (i + 1 < size[0] && j + 1 < size[1])
        {
          brute += 2.0 * std::pow(c[at(i, j, k)] - c[at(i + 1, j, k)] - c[at(i, j + 1, k)] + c[at(i + 1, j + 1, k)], 2);
        }
        if (i + 1 < size[0] && k + 1 < size[2])
        {
          brute += 2.0 * std::pow(c[at(i, j, k)] - c[at(i + 1, j, k)] - c[at(i, j, k + 1)] + c[at(i + 1, j, k + 1)], 2);
        }
        if (j + 1 < size[1] && k + 1 < size[2])
        {
          brute += 2.0 * std::pow(c[at(i, j, k)] - c[at(i, j + 1, k)] - c[at(i, j, k + 1)] + c[at(i, j + 1, k + 1)], 2);
        }
      }
    }
  }
  const double quadratic = c.dot(bending * c);
  std::cout << "bending energy " << quadratic << ", brute force " << brute << std::endl;
  int status = EXIT_SUCCESS;
  if (std::abs(quadratic - brute) > 1e-9 * brute)
  {
    std::cerr << "the bending matrix differs from the bending sum" << std::endl;
    status = EXIT_FAILURE;
  }
  Eigen::VectorXd affine(c.size());
  for (size_t k = 0; k < size[2]; ++k)
  {
    for (size_t j = 0; j < size[1]; ++j)
    {
      for (size_t i = 0; i < size[0]; ++i)
      {
        affine[at(i, j, k)] = 0.3 + 1.5 * i - 0.7 * j + 2.0 * k;
      }
    }
  }
  if ((bending * affine).cwiseAbs().maxCoeff() > 1e-9)
  {
    std::cerr << "the bending matrix does not annihilate an affine field" << std::endl;
    status = EXIT_FAILURE;
  }
  return status;
}

// The bending matrix applied by its one-axis factors (BSplineLatticeBendingProduct) against the sparse product
// factor (R + shift I) X, three columns, on lattices with sides from one node (no differences) up, and its result
// overwritten rather than added to.
int
TestBendingProduct()
{
  int                                      status = EXIT_SUCCESS;
  const std::vector<std::array<size_t, 3>> sizes{ { 1, 1, 1 }, { 2, 3, 1 },  { 3, 3, 3 },
                                                  { 5, 4, 6 }, { 23, 4, 2 }, { 9, 11, 7 } };
  std::mt19937                             engine(5);
  std::uniform_real_distribution<double>   uniform(-1.0, 1.0);
  for (const auto & size : sizes)
  {
    const auto                  count = static_cast<Eigen::Index>(size[0] * size[1] * size[2]);
    const double                shift = 0.01;
    const double                factor = 0.7;
    Eigen::SparseMatrix<double> identity(count, count);
    identity.setIdentity();
    const Eigen::SparseMatrix<double> shifted = itk::detail::BSplineLatticeBendingMatrix(size) + shift * identity;
    Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> in(count, 3);
    for (Eigen::Index n = 0; n < in.size(); ++n)
    {
      in.data()[n] = uniform(engine);
    }
    const Eigen::MatrixXd                                     expected = factor * (shifted * Eigen::MatrixXd(in));
    Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> out =
      Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>::Constant(count, 3, 1e3);
    const itk::detail::BSplineLatticeBendingProduct product(size, shift);
    ITK_TEST_EXPECT_EQUAL(product.GetNumberOfValues(), static_cast<size_t>(3 * count));
    product.Apply(in.data(), out.data(), factor);
    const double difference = (Eigen::MatrixXd(out) - expected).cwiseAbs().maxCoeff();
    std::cout << "bending product on " << size[0] << " x " << size[1] << " x " << size[2]
              << ": largest difference to the sparse product " << difference << std::endl;
    if (!(difference < 1e-13 * std::max(1.0, expected.cwiseAbs().maxCoeff())))
    {
      std::cerr << "the bending product differs from the sparse one" << std::endl;
      status = EXIT_FAILURE;
    }
  }
  return status;
}

// p + sum_j w_j c_j from the support weights against BSplineTransform::TransformPoint, for random coefficients.
int
TestSupportWeights()
{
  auto                                transform = BSplineType::New();
  BSplineType::MeshSizeType           meshSize;
  BSplineType::PhysicalDimensionsType dimensions;
  BSplineType::OriginType             origin;
  for (unsigned int d = 0; d < 3; ++d)
  {
    meshSize[d] = 4 + d;
    dimensions[d] = 30.0 + 5.0 * d;
    origin[d] = -10.0 + d;
  }
  transform->SetTransformDomainOrigin(origin);
  transform->SetTransformDomainPhysicalDimensions(dimensions);
  transform->SetTransformDomainMeshSize(meshSize);
  std::mt19937                           engine(3);
  std::uniform_real_distribution<double> uniform(-2.0, 2.0);
  BSplineType::ParametersType            parameters(transform->GetNumberOfParameters());
  for (unsigned int n = 0; n < parameters.size(); ++n)
  {
    parameters[n] = uniform(engine);
  }
  transform->SetParameters(parameters);
  const size_t                           perDimension = transform->GetNumberOfParametersPerDimension();
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  double                                 largest = 0.0;
  // The fold checks' determinants from the separable supports, against SpatialJacobianEvaluator's.
  itk::detail::SpatialJacobianEvaluator<double, 3> evaluator;
  evaluator.Initialize(transform);
  const auto *                         lattice = transform->GetCoefficientImages()[0].GetPointer();
  const auto                           latticeSize = lattice->GetLargestPossibleRegion().GetSize();
  std::array<std::array<double, 3>, 3> indexFromPhysical{};
  for (unsigned int j = 0; j < 3; ++j)
  {
    for (unsigned int k = 0; k < 3; ++k)
    {
      indexFromPhysical[j][k] = lattice->GetInverseDirection()(j, k) / lattice->GetSpacing()[j];
    }
  }
  const std::array<const double *, 3> columns{ parameters.data_block(),
                                               parameters.data_block() + perDimension,
                                               parameters.data_block() + 2 * perDimension };
  double                              largestDeterminantDifference = 0.0;
  double                              smallestDeterminant = 1.0;
  for (unsigned int trial = 0; trial < 200; ++trial)
  {
    BSplineType::InputPointType p;
    for (unsigned int d = 0; d < 3; ++d)
    {
      p[d] = origin[d] + unit(engine) * dimensions[d] * 0.999;
    }
    std::array<double, 64>       weights{};
    std::array<unsigned int, 64> indices{};
    if (!itk::detail::BSplineSupportWeights(transform->GetCoefficientImages()[0].GetPointer(), p, weights, indices))
    {
      std::cerr << "a point inside the domain has no support" << std::endl;
      return EXIT_FAILURE;
    }
    unsigned int           first = 0;
    std::array<double, 12> separable{};
    std::array<double, 12> derivatives{};
    ITK_TEST_EXPECT_TRUE(itk::detail::BSplineSeparableSupport(lattice, p, first, separable, &derivatives));
    const double determinant = itk::detail::SeparableSupportJacobianDeterminant(
      latticeSize[0], latticeSize[1], first, separable, derivatives, columns, indexFromPhysical);
    itk::Matrix<double, 3, 3> jacobian;
    evaluator.Evaluate(p, jacobian);
    largestDeterminantDifference =
      std::max(largestDeterminantDifference, std::abs(determinant - itk::detail::Determinant3(jacobian)));
    smallestDeterminant = std::min(smallestDeterminant, determinant);
    const auto expected = transform->TransformPoint(p);
    for (unsigned int d = 0; d < 3; ++d)
    {
      double value = p[d];
      for (unsigned int j = 0; j < 64; ++j)
      {
        value += weights[j] * parameters[d * perDimension + indices[j]];
      }
      largest = std::max(largest, std::abs(value - expected[d]));
    }
  }
  BSplineType::InputPointType outside = origin;
  outside[0] -= 5.0;
  std::array<double, 64>       weights{};
  std::array<unsigned int, 64> indices{};
  std::cout << "support weights against TransformPoint: largest difference " << largest << " mm" << std::endl;
  std::cout << "fold-check determinants against SpatialJacobianEvaluator: largest difference "
            << largestDeterminantDifference << " (smallest determinant " << smallestDeterminant << ")" << std::endl;
  ITK_TEST_EXPECT_TRUE(largestDeterminantDifference < 1e-12);
  ITK_TEST_EXPECT_TRUE(smallestDeterminant < 0.9); // the coefficients deform the lattice
  if (largest > 1e-9 ||
      itk::detail::BSplineSupportWeights(transform->GetCoefficientImages()[0].GetPointer(), outside, weights, indices))
  {
    std::cerr << "the support weights differ from the transform's" << std::endl;
    return EXIT_FAILURE;
  }
  return EXIT_SUCCESS;
}

// Random samples on a small control lattice, in the M-step's form: separable support weights (several samples
// sharing a block, blocks at the lattice's corners), masses (two of them zero), a bending regularizer and its weight,
// with B, the samples' weights, as an explicit sparse matrix.
struct RandomSamples
{
  std::array<size_t, 3>                                              Size{ 7, 5, 8 };
  std::vector<std::array<size_t, 3>>                                 Corners{};
  std::vector<unsigned int>                                          Firsts{};
  std::vector<itk::detail::BSplineSampleNormalOperator::WeightsType> Weights{};
  Eigen::SparseMatrix<double>                                        Basis{};
  Eigen::VectorXd                                                    Mass{};
  Eigen::SparseMatrix<double>                                        Regularizer{};
  double                                                             RegularizerWeight{ 0.7 };

  size_t
  Count() const
  {
    return Size[0] * Size[1] * Size[2];
  }

  // B^T diag(m) B + s R, dense.
  Eigen::MatrixXd
  ExplicitMatrix() const
  {
    return ExplicitMatrixAt(Mass, RegularizerWeight);
  }

  /** Other masses, 0.5 to 1.5 times these (as between two updates of a preconditioner). */
  Eigen::VectorXd
  ChangedMass() const
  {
    Eigen::VectorXd changed = Mass;
    for (Eigen::Index m = 0; m < changed.size(); ++m)
    {
      changed[m] *= 0.5 + static_cast<double>(m % 7) / 6.0;
    }
    return changed;
  }

  /** B^T diag(mass) B + weight R. */
  Eigen::MatrixXd
  ExplicitMatrixAt(const Eigen::VectorXd & mass, double weight) const
  {
    return Eigen::MatrixXd(Basis.transpose() * (mass.asDiagonal() * Basis)) + weight * Eigen::MatrixXd(Regularizer);
  }
};

RandomSamples
MakeRandomSamples()
{
  RandomSamples                          samples;
  const auto &                           size = samples.Size;
  std::mt19937                           engine(11);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  samples.Corners = { { 0, 0, 0 }, { 3, 1, 4 }, { 3, 1, 4 }, { 3, 1, 4 }, { 2, 0, 1 } };
  for (unsigned int extra = 0; extra < 40; ++extra)
  {
    samples.Corners.push_back({ engine() % (size[0] - 3), engine() % (size[1] - 3), engine() % (size[2] - 3) });
  }
  samples.Corners.push_back({ size[0] - 4, size[1] - 4, size[2] - 4 });
  std::vector<Eigen::Triplet<double>> entries;
  for (size_t m = 0; m < samples.Corners.size(); ++m)
  {
    const auto &                                          corner = samples.Corners[m];
    itk::detail::BSplineSampleNormalOperator::WeightsType w{};
    for (double & value : w)
    {
      value = uniform(engine);
    }
    samples.Firsts.push_back(static_cast<unsigned int>(corner[0] + size[0] * (corner[1] + size[1] * corner[2])));
    samples.Weights.push_back(w);
    for (unsigned int n = 0; n < 64; ++n)
    {
      const size_t a = n % 4;
      const size_t b = (n / 4) % 4;
      const size_t c = n / 16;
      entries.emplace_back(static_cast<int>(m),
                           static_cast<int>((corner[0] + a) + size[0] * ((corner[1] + b) + size[1] * (corner[2] + c))),
                           w[a] * w[4 + b] * w[8 + c]);
    }
  }
  samples.Basis.resize(static_cast<Eigen::Index>(samples.Corners.size()), static_cast<Eigen::Index>(samples.Count()));
  samples.Basis.setFromTriplets(entries.begin(), entries.end());
  samples.Mass.resize(static_cast<Eigen::Index>(samples.Corners.size()));
  for (Eigen::Index m = 0; m < samples.Mass.size(); ++m)
  {
    samples.Mass[m] = uniform(engine);
  }
  samples.Mass[1] = 0.0; // samples without mass: one of a shared block, one alone
  samples.Mass[4] = 0.0;
  Eigen::SparseMatrix<double> identity(static_cast<Eigen::Index>(samples.Count()),
                                       static_cast<Eigen::Index>(samples.Count()));
  identity.setIdentity();
  samples.Regularizer = itk::detail::BSplineLatticeBendingMatrix(size) + 1e-3 * identity;
  return samples;
}

// The M-step's matrix applied without being formed, (B^T diag(m) B + s R) X, against Eigen's product of the explicit
// matrices, its diagonal against the explicit one, and bad inputs.
int
TestSampleNormalOperator()
{
  using Operator = itk::detail::BSplineSampleNormalOperator;
  const RandomSamples samples = MakeRandomSamples();
  const auto &        size = samples.Size;
  const size_t        count = samples.Count();
  const auto &        firsts = samples.Firsts;
  const auto &        weights = samples.Weights;
  const auto &        regularizer = samples.Regularizer;
  const double        weight = samples.RegularizerWeight;
  const auto &        mass = samples.Mass;

  Operator normal(size, firsts, weights, regularizer);
  normal.SetWeighting(mass, weight);
  const Eigen::MatrixXd     explicitMatrix = samples.ExplicitMatrix();
  const Operator::BlockType in = Operator::BlockType::Random(static_cast<Eigen::Index>(count), 3);
  Operator::BlockType       out(static_cast<Eigen::Index>(count), 3);
  normal.Apply(in, out);
  const Eigen::MatrixXd expected = explicitMatrix * Eigen::MatrixXd(in);
  const double          difference = (Eigen::MatrixXd(out) - expected).cwiseAbs().maxCoeff();
  const double          diagonalDifference = (normal.GetDiagonal() - explicitMatrix.diagonal()).cwiseAbs().maxCoeff();
  std::cout << "normal operator: largest difference to Eigen's product " << difference << ", to the diagonal "
            << diagonalDifference << std::endl;
  ITK_TEST_EXPECT_TRUE(difference < 1e-12 * std::max(1.0, expected.cwiseAbs().maxCoeff()));
  ITK_TEST_EXPECT_TRUE(diagonalDifference < 1e-13 && expected.cwiseAbs().maxCoeff() > 1.0);
  ITK_TEST_EXPECT_TRUE(explicitMatrix.diagonal().minCoeff() < explicitMatrix.diagonal().maxCoeff());

  // The same operator with R given as the lattice's bending matrix plus 1e-3 I (applied by its one-axis factors).
  Operator bent(size, firsts, weights, 1e-3);
  bent.SetWeighting(mass, weight);
  Operator::BlockType bentOut(static_cast<Eigen::Index>(count), 3);
  bent.Apply(in, bentOut);
  const double bentDifference = (Eigen::MatrixXd(bentOut) - expected).cwiseAbs().maxCoeff();
  std::cout << "normal operator with the bending product: largest difference to Eigen's product " << bentDifference
            << std::endl;
  ITK_TEST_EXPECT_TRUE(bentDifference < 1e-12 * std::max(1.0, expected.cwiseAbs().maxCoeff()));
  ITK_TEST_EXPECT_TRUE((Eigen::MatrixXd(bent.GetRegularizer()) - Eigen::MatrixXd(regularizer)).cwiseAbs().maxCoeff() <
                       1e-15);
  ITK_TEST_EXPECT_TRUE((bent.GetDiagonal() - explicitMatrix.diagonal()).cwiseAbs().maxCoeff() < 1e-13);

  // B and B^T alone (the samples' positions and the M-step's right-hand side), against the explicit B.
  Operator::BlockType atSamples;
  normal.ApplyBasis(in, atSamples);
  const Eigen::MatrixXd     expectedAtSamples = samples.Basis * Eigen::MatrixXd(in);
  const Operator::BlockType perSample =
    Operator::BlockType::Random(static_cast<Eigen::Index>(samples.Corners.size()), 3);
  Operator::BlockType spread = Operator::BlockType::Ones(static_cast<Eigen::Index>(count), 3);
  normal.ApplyBasisTranspose(perSample, spread);
  const Eigen::MatrixXd expectedSpread = samples.Basis.transpose() * Eigen::MatrixXd(perSample);
  const double          basisDifference = (Eigen::MatrixXd(atSamples) - expectedAtSamples).cwiseAbs().maxCoeff();
  const double          transposeDifference = (Eigen::MatrixXd(spread) - expectedSpread).cwiseAbs().maxCoeff();
  std::cout << "normal operator: B against Eigen's " << basisDifference << ", B^T " << transposeDifference << std::endl;
  ITK_TEST_EXPECT_TRUE(atSamples.rows() == static_cast<Eigen::Index>(samples.Corners.size()));
  ITK_TEST_EXPECT_TRUE(basisDifference < 1e-13 && expectedAtSamples.cwiseAbs().maxCoeff() > 0.1);
  ITK_TEST_EXPECT_TRUE(transposeDifference < 1e-13 && expectedSpread.cwiseAbs().maxCoeff() > 0.1);
  ITK_TRY_EXPECT_EXCEPTION(normal.ApplyBasis(perSample, atSamples));
  ITK_TRY_EXPECT_EXCEPTION(normal.ApplyBasisTranspose(in, spread));

  // Bad inputs: a support leaving the lattice along each axis, sizes that do not agree.
  for (unsigned int axis = 0; axis < 3; ++axis)
  {
    std::array<size_t, 3> corner{ 0, 0, 0 };
    corner[axis] = size[axis] - 3;
    auto outside = firsts;
    outside[0] = static_cast<unsigned int>(corner[0] + size[0] * (corner[1] + size[1] * corner[2]));
    ITK_TRY_EXPECT_EXCEPTION(Operator(size, outside, weights, regularizer));
  }
  Eigen::SparseMatrix<double> small(3, 3);
  ITK_TRY_EXPECT_EXCEPTION(Operator(size, firsts, weights, small));
  auto fewer = weights;
  fewer.pop_back();
  ITK_TRY_EXPECT_EXCEPTION(Operator(size, firsts, fewer, regularizer));
  ITK_TRY_EXPECT_EXCEPTION(normal.SetWeighting(Eigen::VectorXd::Ones(3), weight));
  Operator::BlockType shortBlock = Operator::BlockType::Zero(static_cast<Eigen::Index>(count) - 1, 3);
  ITK_TRY_EXPECT_EXCEPTION(normal.Apply(shortBlock, out));
  return EXIT_SUCCESS;
}

// The coarse-lattice correction of the preconditioner: its prolongation against trilinear interpolation computed
// directly (it reproduces linear fields and sums to one per fine node), its axis-by-axis restriction and prolongation
// against the sparse matrix, the correction P (P^T A P)^-1 P^T r against the explicit matrices, conjugate gradients
// with it against the direct solve (and in fewer iterations than Jacobi's alone), a coarse matrix that cannot be
// factored, and bad inputs.
int
TestCoarseCorrection()
{
  using Operator = itk::detail::BSplineSampleNormalOperator;
  using Correction = itk::detail::BSplineLatticeCoarseCorrection;
  const RandomSamples samples = MakeRandomSamples();
  const auto &        size = samples.Size;
  const auto          count = static_cast<Eigen::Index>(samples.Count());
  Operator            normal(size, samples.Firsts, samples.Weights, samples.Regularizer);
  normal.SetWeighting(samples.Mass, samples.RegularizerWeight);
  const std::array<size_t, 3> coarse{ 3, 3, 3 };
  Correction                  correction(normal, coarse[0]);
  ITK_TEST_EXPECT_EQUAL(correction.GetNumberOfCoarseCoefficients(), static_cast<size_t>(27));

  // P: fine node (i, j, k) lies at coarse coordinates i (3 - 1) / (7 - 1), j (3 - 1) / (5 - 1), k (3 - 1) / (8 - 1).
  const Eigen::SparseMatrix<double> prolongation = correction.GetProlongation();
  Eigen::MatrixXd                   direct = Eigen::MatrixXd::Zero(count, 27);
  for (size_t k = 0; k < size[2]; ++k)
  {
    for (size_t j = 0; j < size[1]; ++j)
    {
      for (size_t i = 0; i < size[0]; ++i)
      {
        const std::array<size_t, 3> at{ i, j, k };
        for (size_t node = 0; node < 27; ++node)
        {
          const std::array<size_t, 3> coarseAt{ node % 3, (node / 3) % 3, node / 9 };
          double                      weight = 1.0;
          for (unsigned int d = 0; d < 3; ++d)
          {
            const double t = static_cast<double>(at[d]) * 2.0 / static_cast<double>(size[d] - 1);
            weight *= std::max(0.0, 1.0 - std::abs(t - static_cast<double>(coarseAt[d])));
          }
          direct(static_cast<Eigen::Index>(i + size[0] * (j + size[1] * k)), static_cast<Eigen::Index>(node)) = weight;
        }
      }
    }
  }
  const double toDirect = (Eigen::MatrixXd(prolongation) - direct).cwiseAbs().maxCoeff();
  ITK_TEST_EXPECT_TRUE(toDirect < 1e-14);
  ITK_TEST_EXPECT_TRUE((direct.rowwise().sum().array() - 1.0).abs().maxCoeff() < 1e-14);

  const Operator::BlockType fine = Operator::BlockType::Random(count, 3);
  const Operator::BlockType coarseBlock = Operator::BlockType::Random(27, 3);
  Operator::BlockType       restricted;
  Operator::BlockType       prolongated;
  correction.Restrict(fine, restricted);
  correction.Prolongate(coarseBlock, prolongated);
  const double restrictDifference =
    (Eigen::MatrixXd(restricted) - Eigen::MatrixXd(prolongation.transpose() * fine)).cwiseAbs().maxCoeff();
  const double prolongDifference =
    (Eigen::MatrixXd(prolongated) - Eigen::MatrixXd(prolongation * coarseBlock)).cwiseAbs().maxCoeff();
  ITK_TEST_EXPECT_TRUE(restrictDifference < 1e-13 && prolongDifference < 1e-14);

  // The correction against the explicit P (P^T A P)^-1 P^T r.
  correction.Update();
  ITK_TEST_EXPECT_TRUE(correction.IsFactored());
  const Eigen::MatrixXd     explicitMatrix = samples.ExplicitMatrix();
  const Eigen::MatrixXd     coarseMatrix = direct.transpose() * explicitMatrix * direct;
  const Operator::BlockType residual = Operator::BlockType::Random(count, 3);
  const Eigen::MatrixXd expected = direct * coarseMatrix.llt().solve(direct.transpose() * Eigen::MatrixXd(residual));
  Operator::BlockType   corrected = Operator::BlockType::Ones(count, 3);
  correction.AddCorrection(residual, corrected);
  const double correctionDifference =
    (Eigen::MatrixXd(corrected) - Eigen::MatrixXd::Ones(count, 3) - expected).cwiseAbs().maxCoeff();
  std::cout << "coarse correction: prolongation to direct " << toDirect << ", restriction " << restrictDifference
            << ", prolongation " << prolongDifference << ", correction to the explicit one " << correctionDifference
            << std::endl;
  ITK_TEST_EXPECT_TRUE(correctionDifference < 1e-9 * std::max(1.0, expected.cwiseAbs().maxCoeff()));

  // Conjugate gradients with the correction reach the direct solve's answer, in fewer iterations than without.
  const Operator::BlockType rightHandSide = Operator::BlockType::Random(count, 3);
  const auto apply = [&normal](const Operator::BlockType & in, Operator::BlockType & out) { normal.Apply(in, out); };
  // Solves A X = rightHandSide at the operator's current weighting with Jacobi's preconditioner alone and with the
  // correction's last factorization; checks both against the direct solve with explicitMatrix and that the correction
  // takes fewer iterations.
  const auto checkSolves = [&](const Eigen::MatrixXd & explicitMatrix, const char * what) {
    const Eigen::MatrixXd exact = explicitMatrix.llt().solve(Eigen::MatrixXd(rightHandSide));
    Operator::BlockType   jacobiOnly = Operator::BlockType::Zero(count, 3);
    Operator::BlockType   twoLevel = Operator::BlockType::Zero(count, 3);
    const auto            jacobiIterations =
      itk::detail::SolveConjugateGradient<3>(apply, normal.GetDiagonal(), rightHandSide, jacobiOnly, 100000, 1e-10);
    const auto twoLevelIterations = itk::detail::SolveConjugateGradient<3>(
      apply,
      normal.GetDiagonal(),
      rightHandSide,
      twoLevel,
      100000,
      1e-10,
      [&correction](const Operator::BlockType & r, Operator::BlockType & z) { correction.AddCorrection(r, z); });
    const double scale = exact.cwiseAbs().maxCoeff();
    const double jacobiError = (Eigen::MatrixXd(jacobiOnly) - exact).cwiseAbs().maxCoeff() / scale;
    const double twoLevelError = (Eigen::MatrixXd(twoLevel) - exact).cwiseAbs().maxCoeff() / scale;
    std::cout << what << ": conjugate gradients to 1e-10: Jacobi " << jacobiIterations << " iterations (error "
              << jacobiError << "), with the coarse correction " << twoLevelIterations << " (error " << twoLevelError
              << ")" << std::endl;
    ITK_TEST_EXPECT_TRUE(jacobiError < 1e-6 && twoLevelError < 1e-6);
    ITK_TEST_EXPECT_TRUE(twoLevelIterations < jacobiIterations);
    return EXIT_SUCCESS;
  };
  ITK_TEST_EXPECT_EQUAL(checkSolves(explicitMatrix, "factored at these masses"), EXIT_SUCCESS);

  // A factorization formed at other masses and another regularizer weight (as the registration keeps it between
  // updates, CoarseCorrectionUpdateInterval) is still a valid preconditioner: the same answer, fewer iterations than
  // Jacobi's alone.
  const Eigen::VectorXd changedMass = samples.ChangedMass();
  normal.SetWeighting(changedMass, 1.3 * samples.RegularizerWeight);
  ITK_TEST_EXPECT_EQUAL(
    checkSolves(samples.ExplicitMatrixAt(changedMass, 1.3 * samples.RegularizerWeight), "factored at other masses"),
    EXIT_SUCCESS);
  normal.SetWeighting(samples.Mass, samples.RegularizerWeight);

  // No mass and no regularizer: nothing to factor, nothing added.
  Operator empty(size, samples.Firsts, samples.Weights, samples.Regularizer);
  empty.SetWeighting(Eigen::VectorXd::Zero(samples.Mass.size()), 0.0);
  Correction unfactored(empty, 3);
  unfactored.Update();
  ITK_TEST_EXPECT_TRUE(!unfactored.IsFactored());
  Operator::BlockType unchanged = residual;
  unfactored.AddCorrection(residual, unchanged);
  ITK_TEST_EXPECT_TRUE((unchanged - residual).cwiseAbs().maxCoeff() == 0.0);

  // More coarse nodes than the fine lattice has: the fine lattice's own, P = I.
  const Correction full(normal, 100);
  ITK_TEST_EXPECT_EQUAL(full.GetNumberOfCoarseCoefficients(), samples.Count());
  ITK_TEST_EXPECT_TRUE(
    (Eigen::MatrixXd(full.GetProlongation()) - Eigen::MatrixXd::Identity(count, count)).cwiseAbs().maxCoeff() == 0.0);
  ITK_TRY_EXPECT_EXCEPTION(Correction(normal, 1));
  return EXIT_SUCCESS;
}

// The block Jacobi preconditioner: its blocks against the explicit matrix's 2 x 2 x 2 blocks (the lattice's odd sides
// leaving thinner blocks at the ends), with R given entry by entry and by its one-axis factors, the blocks samples
// reach, conjugate gradients with it and the coarse correction against the direct solve (in fewer iterations than with
// Jacobi's diagonal), blocks formed at other masses, and a block that cannot be factored.
int
TestBlockJacobi()
{
  using Operator = itk::detail::BSplineSampleNormalOperator;
  using BlockJacobi = itk::detail::BSplineLatticeBlockJacobi;
  const RandomSamples samples = MakeRandomSamples();
  const auto &        size = samples.Size;
  const auto          count = static_cast<Eigen::Index>(samples.Count());
  Operator            byEntries(size, samples.Firsts, samples.Weights, samples.Regularizer);
  Operator            byFactors(size, samples.Firsts, samples.Weights, 1e-3);
  byEntries.SetWeighting(samples.Mass, samples.RegularizerWeight);
  byFactors.SetWeighting(samples.Mass, samples.RegularizerWeight);
  BlockJacobi fromEntries(byEntries);
  BlockJacobi fromFactors(byFactors);
  ITK_TEST_EXPECT_EQUAL(fromEntries.GetNumberOfBlocks(), static_cast<size_t>(4 * 3 * 4));

  // The blocks a sample's 4 x 4 x 4 support reaches, counted directly.
  std::set<std::array<size_t, 3>> reached;
  for (const auto & corner : samples.Corners)
  {
    for (size_t c = 0; c < 4; ++c)
    {
      for (size_t b = 0; b < 4; ++b)
      {
        for (size_t a = 0; a < 4; ++a)
        {
          reached.insert({ (corner[0] + a) / 2, (corner[1] + b) / 2, (corner[2] + c) / 2 });
        }
      }
    }
  }
  ITK_TEST_EXPECT_EQUAL(fromEntries.GetNumberOfReachedBlocks(), reached.size());

  // z = M^-1 r against each block of the explicit matrix solved alone (the block's coefficients listed directly).
  const auto expectedApply = [&](const Eigen::MatrixXd & explicitMatrix, const Operator::BlockType & residual) {
    Eigen::MatrixXd expected = Eigen::MatrixXd::Zero(count, 3);
    for (size_t bk = 0; bk < (size[2] + 1) / 2; ++bk)
    {
      for (size_t bj = 0; bj < (size[1] + 1) / 2; ++bj)
      {
        for (size_t bi = 0; bi < (size[0] + 1) / 2; ++bi)
        {
          std::vector<Eigen::Index> members;
          for (size_t k = 2 * bk; k < std::min(2 * bk + 2, size[2]); ++k)
          {
            for (size_t j = 2 * bj; j < std::min(2 * bj + 2, size[1]); ++j)
            {
              for (size_t i = 2 * bi; i < std::min(2 * bi + 2, size[0]); ++i)
              {
                members.push_back(static_cast<Eigen::Index>(i + size[0] * (j + size[1] * k)));
              }
            }
          }
          const auto      n = static_cast<Eigen::Index>(members.size());
          Eigen::MatrixXd block(n, n);
          Eigen::MatrixXd right(n, 3);
          for (Eigen::Index p = 0; p < n; ++p)
          {
            right.row(p) = residual.row(members[p]);
            for (Eigen::Index q = 0; q < n; ++q)
            {
              block(p, q) = explicitMatrix(members[p], members[q]);
            }
          }
          const Eigen::MatrixXd solved = block.llt().solve(right);
          for (Eigen::Index p = 0; p < n; ++p)
          {
            expected.row(members[p]) = solved.row(p);
          }
        }
      }
    }
    return expected;
  };
  fromEntries.Update();
  fromFactors.Update();
  const Operator::BlockType residual = Operator::BlockType::Random(count, 3);
  const Eigen::MatrixXd     expected = expectedApply(samples.ExplicitMatrix(), residual);
  Operator::BlockType       zEntries;
  Operator::BlockType       zFactors;
  fromEntries.Apply(residual, zEntries);
  fromFactors.Apply(residual, zFactors);
  const double scale = std::max(1.0, expected.cwiseAbs().maxCoeff());
  const double entriesDifference = (Eigen::MatrixXd(zEntries) - expected).cwiseAbs().maxCoeff() / scale;
  const double factorsDifference = (Eigen::MatrixXd(zFactors) - expected).cwiseAbs().maxCoeff() / scale;
  std::cout << "block Jacobi: " << fromEntries.GetNumberOfBlocks() << " blocks ("
            << fromEntries.GetNumberOfReachedBlocks()
            << " reached by samples), relative difference to the explicit blocks' solves " << entriesDifference
            << " (R by entries), " << factorsDifference << " (R by factors)" << std::endl;
  ITK_TEST_EXPECT_TRUE(entriesDifference < 1e-10 && factorsDifference < 1e-10);

  // Conjugate gradients with block Jacobi and the coarse correction reach the direct solve's answer in fewer
  // iterations than with Jacobi's diagonal and the same correction; so do blocks formed at other masses.
  itk::detail::BSplineLatticeCoarseCorrection correction(byFactors, 3);
  const Operator::BlockType                   rightHandSide = Operator::BlockType::Random(count, 3);
  const auto apply = [&byFactors](const Operator::BlockType & in, Operator::BlockType & out) {
    byFactors.Apply(in, out);
  };
  const auto checkSolves = [&](const Eigen::MatrixXd & explicitMatrix, const char * what) {
    correction.Update();
    const Eigen::MatrixXd exact = explicitMatrix.llt().solve(Eigen::MatrixXd(rightHandSide));
    Operator::BlockType   diagonal = Operator::BlockType::Zero(count, 3);
    Operator::BlockType   blocks = Operator::BlockType::Zero(count, 3);
    const auto            diagonalIterations = itk::detail::SolveConjugateGradient<3>(
      apply,
      byFactors.GetDiagonal(),
      rightHandSide,
      diagonal,
      100000,
      1e-10,
      [&correction](const Operator::BlockType & r, Operator::BlockType & z) { correction.AddCorrection(r, z); });
    const auto blockIterations = itk::detail::SolvePreconditionedConjugateGradient<3>(
      apply,
      [&](const Operator::BlockType & r, Operator::BlockType & z) {
        fromFactors.Apply(r, z);
        correction.AddCorrection(r, z);
      },
      rightHandSide,
      blocks,
      100000,
      1e-10);
    const double exactScale = exact.cwiseAbs().maxCoeff();
    const double diagonalError = (Eigen::MatrixXd(diagonal) - exact).cwiseAbs().maxCoeff() / exactScale;
    const double blockError = (Eigen::MatrixXd(blocks) - exact).cwiseAbs().maxCoeff() / exactScale;
    std::cout << what << ": conjugate gradients to 1e-10 with the coarse correction: Jacobi " << diagonalIterations
              << " iterations (error " << diagonalError << "), block Jacobi " << blockIterations << " (error "
              << blockError << ")" << std::endl;
    ITK_TEST_EXPECT_TRUE(diagonalError < 1e-6 && blockError < 1e-6);
    ITK_TEST_EXPECT_TRUE(blockIterations < diagonalIterations);
    return EXIT_SUCCESS;
  };
  ITK_TEST_EXPECT_EQUAL(checkSolves(samples.ExplicitMatrix(), "block Jacobi formed at these masses"), EXIT_SUCCESS);
  const Eigen::VectorXd changedMass = samples.ChangedMass();
  byFactors.SetWeighting(changedMass, 1.3 * samples.RegularizerWeight);
  ITK_TEST_EXPECT_EQUAL(checkSolves(samples.ExplicitMatrixAt(changedMass, 1.3 * samples.RegularizerWeight),
                                    "block Jacobi formed at other masses"),
                        EXIT_SUCCESS);

  // Blocks without mass and without regularizer are not positive definite: each falls back to its diagonal, whose
  // zero entries give zero.
  Operator empty(size, samples.Firsts, samples.Weights, samples.Regularizer);
  empty.SetWeighting(Eigen::VectorXd::Zero(samples.Mass.size()), 0.0);
  BlockJacobi unfactored(empty);
  unfactored.Update();
  Operator::BlockType zero;
  unfactored.Apply(residual, zero);
  ITK_TEST_EXPECT_TRUE(zero.rows() == count && zero.allFinite() && zero.cwiseAbs().maxCoeff() == 0.0);
  return EXIT_SUCCESS;
}

// The coarse correction of an operator whose R is the lattice's bending matrix plus a shift (its coarse matrix made
// from R's one-axis factors) against the same operator given R entry by entry (its coarse matrix P^T R P from the
// sparse product), for several lattices and coarse sizes: the same corrections up to rounding.
int
TestCoarseCorrectionFromFactors()
{
  using Operator = itk::detail::BSplineSampleNormalOperator;
  using Correction = itk::detail::BSplineLatticeCoarseCorrection;
  const RandomSamples                                           samples = MakeRandomSamples();
  const std::array<std::pair<std::array<size_t, 3>, size_t>, 4> cases{
    { { { 7, 5, 8 }, 3 }, { { 7, 5, 8 }, 4 }, { { 9, 11, 7 }, 5 }, { { 4, 4, 4 }, 100 } }
  };
  double largest = 0.0;
  for (const auto & [size, coarse] : cases)
  {
    // The random samples' supports moved into this lattice (corners clamped), with their weights and masses.
    std::vector<unsigned int> firsts;
    for (const auto & corner : samples.Corners)
    {
      std::array<size_t, 3> at{};
      for (unsigned int d = 0; d < 3; ++d)
      {
        at[d] = std::min(corner[d], size[d] - 4);
      }
      firsts.push_back(static_cast<unsigned int>(at[0] + size[0] * (at[1] + size[1] * at[2])));
    }
    const double                shift = 1e-3;
    const auto                  count = static_cast<Eigen::Index>(size[0] * size[1] * size[2]);
    Eigen::SparseMatrix<double> identity(count, count);
    identity.setIdentity();
    const Eigen::SparseMatrix<double> regularizer = itk::detail::BSplineLatticeBendingMatrix(size) + shift * identity;
    Operator                          byFactors(size, firsts, samples.Weights, shift);
    Operator                          byEntries(size, firsts, samples.Weights, regularizer);
    ITK_TEST_EXPECT_TRUE(byFactors.GetBendingProduct() != nullptr && byEntries.GetBendingProduct() == nullptr);
    byFactors.SetWeighting(samples.Mass, samples.RegularizerWeight);
    byEntries.SetWeighting(samples.Mass, samples.RegularizerWeight);
    Correction fromFactors(byFactors, coarse);
    Correction fromEntries(byEntries, coarse);
    fromFactors.Update();
    fromEntries.Update();
    ITK_TEST_EXPECT_TRUE(fromFactors.IsFactored() && fromEntries.IsFactored());
    const Operator::BlockType residual = Operator::BlockType::Random(count, 3);
    Operator::BlockType       a = Operator::BlockType::Zero(count, 3);
    Operator::BlockType       b = Operator::BlockType::Zero(count, 3);
    fromFactors.AddCorrection(residual, a);
    fromEntries.AddCorrection(residual, b);
    const double difference = (a - b).cwiseAbs().maxCoeff() / std::max(1.0, b.cwiseAbs().maxCoeff());
    largest = std::max(largest, difference);
    ITK_TEST_EXPECT_TRUE(difference < 1e-9);
    // The diagonal from the factors, against the formed matrix's.
    ITK_TEST_EXPECT_TRUE((byFactors.GetDiagonal() - byEntries.GetDiagonal()).cwiseAbs().maxCoeff() < 1e-12);
  }
  std::cout << "coarse correction from R's one-axis factors: largest relative difference to P^T R P from R's entries "
            << largest << std::endl;
  return EXIT_SUCCESS;
}

// The side-by-side conjugate gradients against Eigen's ConjugateGradient (same iterations, column by column) and a
// sparse Cholesky solve, on the M-step's kind of matrix (a bending matrix plus random block products); a zero
// right-hand column, the starting guess, and bad inputs.
int
TestConjugateGradient()
{
  using SparseMatrix = Eigen::SparseMatrix<double>;
  using Block = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;
  const std::array<size_t, 3>            size{ 9, 8, 7 };
  const auto                             count = static_cast<Eigen::Index>(size[0] * size[1] * size[2]);
  std::mt19937                           engine(5);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  SparseMatrix                           data(count, count);
  {
    std::vector<Eigen::Triplet<double>> entries;
    for (unsigned int m = 0; m < 200; ++m)
    {
      const size_t first =
        (engine() % (size[0] - 3)) + size[0] * ((engine() % (size[1] - 3)) + size[1] * (engine() % (size[2] - 3)));
      for (unsigned int n = 0; n < 64; ++n)
      {
        entries.emplace_back(static_cast<int>(m),
                             static_cast<int>(first + n % 4 + size[0] * ((n / 4) % 4 + size[1] * (n / 16))),
                             uniform(engine));
      }
    }
    SparseMatrix basis(200, count);
    basis.setFromTriplets(entries.begin(), entries.end());
    data = basis.transpose() * basis;
  }
  SparseMatrix identity(count, count);
  identity.setIdentity();
  const SparseMatrix matrix = data + 0.3 * (itk::detail::BSplineLatticeBendingMatrix(size) + 1e-3 * identity);
  Block              rightHandSide = Block::Random(count, 3);
  rightHandSide.col(2).setZero();
  const Block guess = Block::Random(count, 3);

  // 6 iterations from the guess, against Eigen's iterates. (Further on, the two runs part by more than rounding: on
  // a matrix this ill-conditioned, conjugate gradients amplify the rounding of each product's summation order, which
  // differs between the two; the converged answers agree, checked below.)
  Block      solution = guess;
  const auto iterations = itk::detail::SolveSparseConjugateGradient<3>(matrix, rightHandSide, solution, 6, 1e-12);
  Eigen::ConjugateGradient<SparseMatrix, Eigen::Lower | Eigen::Upper> eigenSolver;
  eigenSolver.setMaxIterations(6);
  eigenSolver.setTolerance(1e-12);
  eigenSolver.compute(matrix);
  double toEigen = 0.0;
  for (int c = 0; c < 3; ++c)
  {
    const Eigen::VectorXd reference =
      eigenSolver.solveWithGuess(Eigen::VectorXd(rightHandSide.col(c)), Eigen::VectorXd(guess.col(c)));
    toEigen = std::max(toEigen,
                       (reference - Eigen::VectorXd(solution.col(c))).cwiseAbs().maxCoeff() /
                         std::max(1.0, reference.cwiseAbs().maxCoeff()));
  }
  std::cout << "conjugate gradients: " << iterations << " iterations, largest relative difference to Eigen's "
            << toEigen << std::endl;
  ITK_TEST_EXPECT_EQUAL(iterations, 6u);
  ITK_TEST_EXPECT_TRUE(toEigen < 1e-9);
  ITK_TEST_EXPECT_TRUE(solution.col(2).cwiseAbs().maxCoeff() == 0.0);

  // To convergence, against a direct solve.
  solution.setZero();
  const auto converged = itk::detail::SolveSparseConjugateGradient<3>(matrix, rightHandSide, solution, 100000, 1e-12);
  Eigen::SimplicialLDLT<SparseMatrix> direct(matrix);
  const Block                         exact = direct.solve(Eigen::MatrixXd(rightHandSide));
  const double                        toDirect = (exact - solution).cwiseAbs().maxCoeff() / exact.cwiseAbs().maxCoeff();
  std::cout << "converged in " << converged << " iterations, relative difference to the direct solve " << toDirect
            << std::endl;
  ITK_TEST_EXPECT_TRUE(converged < 100000 && toDirect < 1e-8);

  // Started at the answer: no iteration.
  Block atAnswer = exact;
  ITK_TEST_EXPECT_EQUAL(itk::detail::SolveSparseConjugateGradient<3>(matrix, rightHandSide, atAnswer, 50, 1e-6), 0u);

  Block short_ = Block::Zero(count - 1, 3);
  ITK_TRY_EXPECT_EXCEPTION(itk::detail::SolveSparseConjugateGradient<3>(matrix, short_, solution, 10, 1e-8));
  SparseMatrix zeroDiagonal = matrix;
  zeroDiagonal.coeffRef(4, 4) = 0.0;
  ITK_TRY_EXPECT_EXCEPTION(
    itk::detail::SolveSparseConjugateGradient<3>(zeroDiagonal, rightHandSide, solution, 10, 1e-8));
  return EXIT_SUCCESS;
}

// The k-d tree's nearest points within a radius against brute force: every count and radius, including none found,
// fewer than k within the radius, k beyond the cloud's size and an unbounded radius (knnSearch's answer).
int
TestNearestWithinRadius()
{
  using PointType = itk::Point<double, 3>; // as the registration's samples
  std::mt19937                           engine(11);
  std::uniform_real_distribution<double> uniform(0.0, 10.0);
  std::vector<PointType>                 cloud(500);
  for (auto & point : cloud)
  {
    for (unsigned int d = 0; d < 3; ++d)
    {
      point[d] = uniform(engine);
    }
  }
  const itk::detail::PointCloudAdaptor<PointType> adaptor{ cloud };
  itk::detail::PointCloudKdTree<PointType>        tree(3, adaptor, nanoflann::KDTreeSingleIndexAdaptorParams(8));
  tree.buildIndex();
  size_t checked = 0;
  for (unsigned int q = 0; q < 100; ++q)
  {
    PointType query;
    for (unsigned int d = 0; d < 3; ++d)
    {
      query[d] = uniform(engine) * 1.2 - 1.0; // some queries outside the cloud's box
    }
    std::vector<std::pair<double, size_t>> all;
    for (size_t n = 0; n < cloud.size(); ++n)
    {
      all.emplace_back(query.SquaredEuclideanDistanceTo(cloud[n]), n);
    }
    std::sort(all.begin(), all.end());
    for (const size_t k : { size_t{ 0 }, size_t{ 1 }, size_t{ 8 }, size_t{ 600 } })
    {
      for (const double squaredRadius : { 0.0, 0.25, 4.0, 1e300 })
      {
        std::vector<size_t> indices(k + 1, 99999);
        std::vector<double> distances(k + 1, -1.0);
        const size_t        found = itk::detail::SearchNearestWithinRadius(
          tree, query.GetDataPointer(), k, squaredRadius, indices.data(), distances.data());
        size_t expected = 0;
        while (expected < k && expected < all.size() && all[expected].first < squaredRadius)
        {
          ++expected;
        }
        ITK_TEST_EXPECT_EQUAL(found, expected);
        for (size_t j = 0; j < found; ++j)
        {
          ITK_TEST_EXPECT_EQUAL(indices[j], all[j].second);
          ITK_TEST_EXPECT_TRUE(distances[j] == all[j].first);
        }
        ITK_TEST_EXPECT_EQUAL(indices[k], 99999u); // nothing written past k
        checked += found;
      }
    }
    // Unbounded, the same as nanoflann's own k-nearest search.
    std::array<size_t, 8> bounded{};
    std::array<size_t, 8> plain{};
    std::array<double, 8> boundedDistances{};
    std::array<double, 8> plainDistances{};
    itk::detail::SearchNearestWithinRadius(
      tree, query.GetDataPointer(), 8, std::numeric_limits<double>::max(), bounded.data(), boundedDistances.data());
    tree.knnSearch(query.GetDataPointer(), 8, plain.data(), plainDistances.data());
    ITK_TEST_EXPECT_TRUE(bounded == plain && boundedDistances == plainDistances);
  }
  std::cout << "nearest within a radius: " << checked << " points found as by brute force" << std::endl;
  ITK_TEST_EXPECT_TRUE(checked > 1000);
  return EXIT_SUCCESS;
}

// The candidate lists against brute force: queries moving a little each round (some not at all, every one far
// once), radii shrinking and growing; every search visits exactly the points within the radius, and the k nearest
// are brute force's, in its order and with its distances; most searches are answered without building a list.
int
TestNeighborCandidateLists()
{
  using PointType = itk::Point<double, 3>;
  ITK_TRY_EXPECT_EXCEPTION(itk::detail::NeighborCandidateLists(10, 0.0));
  std::mt19937                           engine(23);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  std::vector<PointType>                 points(400);
  std::vector<std::array<double, 3>>     queries(300);
  for (auto & p : points)
  {
    for (unsigned int d = 0; d < 3; ++d)
    {
      p[d] = 10.0 * uniform(engine);
    }
  }
  for (auto & q : queries)
  {
    q = { 14.0 * uniform(engine) - 2.0, 14.0 * uniform(engine) - 2.0, 14.0 * uniform(engine) - 2.0 };
  }
  const itk::detail::PointCloudAdaptor<PointType> adaptor{ points };
  itk::detail::PointCloudKdTree<PointType>        tree(3, adaptor, nanoflann::KDTreeSingleIndexAdaptorParams(8));
  tree.buildIndex();
  itk::detail::NeighborCandidateLists lists(queries.size(), 0.25);
  size_t                              searches = 0;
  size_t                              rebuilds = 0;
  size_t                              wrong = 0;
  size_t                              found = 0;
  for (unsigned int round = 0; round < 40; ++round)
  {
    const double radius = 1.5 + 0.3 * std::sin(0.7 * round); // shrinking and growing
    const double squaredRadius = radius * radius;
    for (size_t n = 0; n < queries.size(); ++n)
    {
      const double * query = queries[n].data();
      if (lists.NeedsRebuild(n, query, radius))
      {
        lists.Rebuild(n, tree, query, radius);
        ++rebuilds;
      }
      ++searches;
      std::vector<std::pair<double, size_t>> all;
      for (size_t j = 0; j < points.size(); ++j)
      {
        double squaredDistance = 0.0;
        for (unsigned int d = 0; d < 3; ++d)
        {
          squaredDistance += (query[d] - points[j][d]) * (query[d] - points[j][d]);
        }
        if (squaredDistance < squaredRadius)
        {
          all.emplace_back(squaredDistance, j);
        }
      }
      std::sort(all.begin(), all.end());
      std::vector<std::pair<double, size_t>> visited;
      lists.ForEachWithin(n, points, query, squaredRadius, [&visited](size_t index, double squaredDistance) {
        visited.emplace_back(squaredDistance, index);
      });
      std::sort(visited.begin(), visited.end());
      wrong += visited == all ? 0 : 1;
      std::array<size_t, 8>                  indices{};
      std::array<double, 8>                  distances{};
      std::vector<std::pair<double, size_t>> alsoVisited;
      const size_t                           count = lists.Search(
        n, points, query, 8, squaredRadius, indices.data(), distances.data(), [&alsoVisited](size_t index, double d2) {
          alsoVisited.emplace_back(d2, index);
        });
      wrong += count == std::min<size_t>(8, all.size()) ? 0 : 1;
      // The visitor sees every point within the radius, as ForEachWithin does.
      std::sort(alsoVisited.begin(), alsoVisited.end());
      wrong += alsoVisited == all ? 0 : 1;
      // Without a visitor, the same k nearest.
      std::array<size_t, 8> plainIndices{};
      std::array<double, 8> plainDistances{};
      wrong += lists.Search(n, points, query, 8, squaredRadius, plainIndices.data(), plainDistances.data()) == count &&
                   plainIndices == indices && plainDistances == distances
                 ? 0
                 : 1;
      for (size_t j = 0; j < count && j < all.size(); ++j)
      {
        wrong += indices[j] == all[j].second && distances[j] == all[j].first ? 0 : 1;
      }
      found += count;
    }
    // Move the queries: not at all every fifth round, each one far in its own round, a little otherwise.
    for (size_t n = 0; n < queries.size(); ++n)
    {
      const double step = round % 5 == 4 ? 0.0 : (n % 40 == round ? 2.0 : 0.05);
      for (unsigned int d = 0; d < 3; ++d)
      {
        queries[n][d] += step * (uniform(engine) - 0.5);
      }
    }
  }
  std::cout << "neighbour candidate lists: " << searches << " searches, " << rebuilds << " lists built, " << found
            << " neighbours found, " << wrong << " answers wrong" << std::endl;
  ITK_TEST_EXPECT_EQUAL(wrong, static_cast<size_t>(0));
  ITK_TEST_EXPECT_TRUE(found > 10000);
  ITK_TEST_EXPECT_TRUE(rebuilds > queries.size() && 3 * rebuilds < searches);
  return EXIT_SUCCESS;
}

/** The smallest det J of the transform at the mesh's vertices. */
double
MinimumDeterminantAt(const itk::Transform<double, 3, 3> * transform, const MeshType * mesh)
{
  const auto * bspline = dynamic_cast<const BSplineType *>(transform);
  if (bspline == nullptr)
  {
    return -1.0;
  }
  itk::detail::SpatialJacobianEvaluator<double, 3> jacobian;
  jacobian.Initialize(bspline);
  itk::Matrix<double, 3, 3> matrix;
  double                    minimum = itk::NumericTraits<double>::max();
  for (auto it = mesh->GetPoints()->Begin(); it != mesh->GetPoints()->End(); ++it)
  {
    jacobian.Evaluate(it.Value(), matrix);
    minimum = std::min(minimum, itk::detail::Determinant3(matrix));
  }
  return minimum;
}
} // namespace

int
itkBSplineCoherentPointDriftRegistrationMethodTest(int, char *[])
{
  if (TestBendingMatrix() != EXIT_SUCCESS || TestBendingProduct() != EXIT_SUCCESS ||
      TestSupportWeights() != EXIT_SUCCESS || TestSampleNormalOperator() != EXIT_SUCCESS ||
      TestCoarseCorrection() != EXIT_SUCCESS || TestCoarseCorrectionFromFactors() != EXIT_SUCCESS ||
      TestBlockJacobi() != EXIT_SUCCESS || TestConjugateGradient() != EXIT_SUCCESS ||
      TestNearestWithinRadius() != EXIT_SUCCESS || TestNeighborCandidateLists() != EXIT_SUCCESS)
  {
    return EXIT_FAILURE;
  }
  int                         testStatus = EXIT_SUCCESS;
  const MeshType::Pointer     source = MakeSphere(20.0, 0.0, 0.0, 0.0);
  CorrespondenceContainerType truth;
  const MeshType::Pointer     target = MakeDeformedPatch(source, -5.0, truth);

  auto registration = RegistrationType::New();
  ITK_EXERCISE_BASIC_OBJECT_METHODS(
    registration, BSplineCoherentPointDriftRegistrationMethod, MeshRegistrationMethodBase);
  ITK_TEST_EXPECT_EQUAL(registration->GetNumberOfControlPointsPerAxis(), 20u);
  ITK_TEST_EXPECT_EQUAL(registration->GetNumberOfIterations(), 40u);
  ITK_TEST_EXPECT_EQUAL(registration->GetNumberOfSolverIterations(), 30u);
  ITK_TEST_EXPECT_EQUAL(registration->GetNumberOfFixedSamples(), 20000u);
  ITK_TEST_EXPECT_EQUAL(registration->GetNumberOfMovingSamples(), 50000u);
  ITK_TEST_SET_GET_VALUE(0.0, registration->GetOverRelaxation()); // automatic
  registration->SetOverRelaxation(-1.0);
  ITK_TEST_SET_GET_VALUE(0.0, registration->GetOverRelaxation()); // clamped
  registration->SetOverRelaxation(3.0);
  ITK_TEST_SET_GET_VALUE(1.95, registration->GetOverRelaxation()); // clamped
  registration->SetOverRelaxation(0.0);
  ITK_TEST_SET_GET_VALUE(0.0, registration->GetMomentum()); // none
  registration->SetMomentum(2.0);
  ITK_TEST_SET_GET_VALUE(0.99, registration->GetMomentum()); // clamped
  registration->SetMomentum(-5.0);
  ITK_TEST_SET_GET_VALUE(0.0, registration->GetMomentum()); // clamped
  ITK_TEST_SET_GET_VALUE(0.5, registration->GetForwardWeight());
  registration->SetForwardWeight(2.0);
  ITK_TEST_SET_GET_VALUE(1.0, registration->GetForwardWeight()); // clamped
  ITK_TEST_SET_GET_VALUE(1e-3, registration->GetConvergenceTolerance());
  registration->SetConvergenceTolerance(-1.0);
  ITK_TEST_SET_GET_VALUE(0.0, registration->GetConvergenceTolerance()); // clamped
  registration->SetConvergenceTolerance(1e-3);
  ITK_TEST_SET_GET_VALUE(1e-3, registration->GetSolverTolerance());
  registration->SetSolverTolerance(2.0);
  ITK_TEST_SET_GET_VALUE(1.0, registration->GetSolverTolerance()); // clamped
  registration->SetSolverTolerance(-1.0);
  ITK_TEST_SET_GET_VALUE(0.0, registration->GetSolverTolerance()); // clamped
  registration->SetSolverTolerance(1e-3);
  ITK_TEST_SET_GET_VALUE(7u, registration->GetNumberOfCoarseControlPointsPerAxis());
  ITK_TEST_SET_GET_VALUE(10u, registration->GetCoarseCorrectionUpdateInterval());
  registration->SetCoarseCorrectionUpdateInterval(0);
  ITK_TEST_SET_GET_VALUE(1u, registration->GetCoarseCorrectionUpdateInterval()); // clamped
  registration->SetCoarseCorrectionUpdateInterval(10);
  ITK_TEST_EXPECT_TRUE(registration->GetUseBlockJacobiPreconditioner());
  ITK_TEST_SET_GET_BOOLEAN(registration, UseBlockJacobiPreconditioner, true);

  // Bad input: no meshes, an empty one, a target without polygons, meshes apart, an initial transform that is not a
  // B-spline.
  ITK_TRY_EXPECT_EXCEPTION(registration->Update());
  registration->SetFixedMesh(MeshType::New());
  registration->SetMovingMesh(source);
  ITK_TRY_EXPECT_EXCEPTION(registration->Update());
  auto pointsOnly = MeshType::New();
  pointsOnly->SetPoints(target->GetPoints());
  registration->SetFixedMesh(pointsOnly);
  ITK_TRY_EXPECT_EXCEPTION(registration->Update());
  registration->SetFixedMesh(target);
  registration->SetMovingMesh(MakeSphere(20.0, 500.0, 0.0, 0.0));
  ITK_TRY_EXPECT_EXCEPTION(registration->Update());
  registration->SetMovingMesh(source);
  using DecoratedType = RegistrationType::DecoratedTransformType;
  auto translation = itk::TranslationTransform<double, 3>::New();
  auto decorated = DecoratedType::New();
  decorated->Set(translation);
  registration->SetInitialTransformInput(decorated);
  ITK_TRY_EXPECT_EXCEPTION(registration->Update());
  registration->SetInitialTransformInput(nullptr);

  // The cap is matched: the true error falls to less than 60 % of the start (measured: see the output), no fold at
  // the target's vertices, one sigma and metric value per iteration, sigma ends at its floor, progress reaches 1.
  registration->SetForwardWeight(0.5);
  registration->SetNumberOfControlPointsPerAxis(8);
  unsigned int iterations = 0;
  registration->AddObserver(itk::IterationEvent(), [&](const itk::EventObject &) { ++iterations; });
  auto identity = BSplineType::New();
  identity->SetIdentity();
  const double before = TransformTrueError(identity, source, target, truth);
  ITK_TRY_EXPECT_NO_EXCEPTION(registration->Update());
  const auto * transform = dynamic_cast<const BSplineType *>(registration->GetTransform());
  ITK_TEST_EXPECT_TRUE(transform != nullptr);
  const double after = TransformTrueError(transform, source, target, truth);
  const double minimumDeterminant = MinimumDeterminantAt(transform, target);
  std::cout << "cpd: true error " << before << " -> " << after << " mm, " << registration->GetSigmaValues().size()
            << " iterations, sigma " << registration->GetSigmaValues().front() << " -> "
            << registration->GetSigmaValues().back() << " mm, min det J " << minimumDeterminant << "; "
            << registration->GetStopConditionDescription() << std::endl;
  ITK_TEST_EXPECT_TRUE(after < 0.6 * before);
  ITK_TEST_EXPECT_TRUE(minimumDeterminant > 0.0);
  ITK_TEST_EXPECT_EQUAL(registration->GetSigmaValues().size(), registration->GetMetricValues().size());
  ITK_TEST_EXPECT_EQUAL(iterations, registration->GetSigmaValues().size());
  ITK_TEST_EXPECT_TRUE(registration->GetSigmaValues().back() < registration->GetSigmaValues().front());
  ITK_TEST_EXPECT_TRUE(std::abs(registration->GetProgress() - 1.0f) < 1e-6f);
  ITK_TEST_EXPECT_EQUAL(transform->GetCoefficientImages()[0]->GetLargestPossibleRegion().GetSize()[0], 8u);
  ITK_TEST_EXPECT_TRUE(!registration->GetTimeLimitReached());

  // Further runs on the cap from the identity (grid 8), each with one setting changed.
  const auto runOnCap = [&](const std::function<void(RegistrationType *)> & configure) {
    auto run = RegistrationType::New();
    run->SetFixedMesh(target);
    run->SetMovingMesh(source);
    run->SetNumberOfControlPointsPerAxis(8);
    configure(run);
    run->Update();
    return run;
  };

  // Over-relaxed EM from the identity (1.8 instead of the automatic 1) also matches the cap without folding.
  {
    const auto   relaxed = runOnCap([](RegistrationType * run) { run->SetOverRelaxation(1.8); });
    const double relaxedError = TransformTrueError(relaxed->GetTransform(), source, target, truth);
    std::cout << "over-relaxed EM: true error " << relaxedError << " mm (plain " << after << " mm)" << std::endl;
    ITK_TEST_EXPECT_TRUE(relaxedError < before);
    ITK_TEST_EXPECT_TRUE(std::abs(relaxedError - after) > 1e-6); // the setting is used
  }

  // Over-relaxed EM with momentum 0.9 from the identity: on this cap of a sphere, where sliding along the surface
  // costs nothing, the momentum carries the correspondences along it (measured 1.29 mm against 0.97 mm without), which
  // is why it is not the default; it still ends below the start, without folding, and differs from the run without.
  {
    const auto   relaxed = runOnCap([](RegistrationType * run) { run->SetOverRelaxation(1.8); });
    const auto   pushed = runOnCap([](RegistrationType * run) {
      run->SetOverRelaxation(1.8);
      run->SetMomentum(0.9);
    });
    const double relaxedError = TransformTrueError(relaxed->GetTransform(), source, target, truth);
    const double pushedError = TransformTrueError(pushed->GetTransform(), source, target, truth);
    const double pushedDeterminant = MinimumDeterminantAt(pushed->GetTransform(), target);
    std::cout << "over-relaxed EM with momentum 0.9: true error " << pushedError << " mm, min det J "
              << pushedDeterminant << " (without: " << relaxedError << " mm)" << std::endl;
    ITK_TEST_EXPECT_TRUE(pushedError < before);
    ITK_TEST_EXPECT_TRUE(pushedDeterminant > 0.0);
    ITK_TEST_EXPECT_TRUE(std::abs(pushedError - relaxedError) > 1e-6); // the setting is used
  }

  // The solver tolerance: M-steps solved to NumberOfSolverIterations every time (tolerance 0) end near the default's
  // (1e-3) result, which stops the conjugate gradients earlier.
  {
    const auto   exact = runOnCap([](RegistrationType * run) { run->SetSolverTolerance(0.0); });
    const double exactError = TransformTrueError(exact->GetTransform(), source, target, truth);
    std::cout << "solver tolerance 0: true error " << exactError << " mm (1e-3: " << after << " mm)" << std::endl;
    ITK_TEST_EXPECT_TRUE(exactError < 0.6 * before);
    ITK_TEST_EXPECT_TRUE(std::abs(exactError - after) < 0.1 * exactError);
    ITK_TEST_EXPECT_TRUE(std::abs(exactError - after) > 1e-9); // the setting is used
  }

  // Jacobi's diagonal in place of the blocks (the coarse correction kept): the M-steps solved to the same tolerance
  // end near the default's result, the blocks in fewer conjugate-gradient iterations.
  {
    const auto   diagonal = runOnCap([](RegistrationType * run) { run->UseBlockJacobiPreconditionerOff(); });
    const auto   blocks = runOnCap([](RegistrationType *) {});
    const double diagonalError = TransformTrueError(diagonal->GetTransform(), source, target, truth);
    std::cout << "Jacobi's diagonal: true error " << diagonalError << " mm in "
              << diagonal->GetNumberOfSolverIterationsTaken() << " conjugate-gradient iterations (blocks: " << after
              << " mm in " << blocks->GetNumberOfSolverIterationsTaken() << ")" << std::endl;
    ITK_TEST_EXPECT_TRUE(std::abs(diagonalError - after) < 0.1 * after);
    ITK_TEST_EXPECT_TRUE(blocks->GetNumberOfSolverIterationsTaken() > 0);
    ITK_TEST_EXPECT_TRUE(blocks->GetNumberOfSolverIterationsTaken() < diagonal->GetNumberOfSolverIterationsTaken());
  }

  // The convergence tolerance: with none the run takes every iteration; a coarse one stops it once sigma is at its
  // floor, earlier, and says why; the default stops between the two.
  {
    const auto runWith = [&](double tolerance, unsigned int & count, std::string & description) {
      const auto run = runOnCap([tolerance](RegistrationType * r) { r->SetConvergenceTolerance(tolerance); });
      count = static_cast<unsigned int>(run->GetSigmaValues().size());
      description = run->GetStopConditionDescription();
      return TransformTrueError(run->GetTransform(), source, target, truth);
    };
    unsigned int fullCount = 0;
    unsigned int coarseCount = 0;
    std::string  fullStop;
    std::string  coarseStop;
    const double fullError = runWith(0.0, fullCount, fullStop);
    const double coarseError = runWith(0.05, coarseCount, coarseStop);
    std::cout << "convergence tolerance 0: " << fullCount << " iterations, " << fullError << " mm (" << fullStop
              << "); 0.05: " << coarseCount << " iterations, " << coarseError << " mm (" << coarseStop
              << "); 1e-3: " << iterations << " iterations, " << after << " mm" << std::endl;
    ITK_TEST_EXPECT_EQUAL(fullCount, 40u);
    ITK_TEST_EXPECT_TRUE(fullStop.find("the maximum") != std::string::npos);
    ITK_TEST_EXPECT_TRUE(coarseCount < iterations && iterations <= fullCount);
    ITK_TEST_EXPECT_TRUE(coarseStop.find("mm RMS, below 0.05 x the control spacing") != std::string::npos);
    ITK_TEST_EXPECT_TRUE(coarseError < before);
  }

  // From an initial B-spline: its grid is kept, and a further run from the result does not undo it.
  // (The first result is replaced by the next Update(): what is compared later is kept now.)
  const unsigned int firstNumberOfParameters = transform->GetNumberOfParameters();
  auto               start = BSplineType::New();
  start->SetFixedParameters(transform->GetFixedParameters());
  start->SetParameters(transform->GetParameters());
  decorated->Set(start);
  registration->SetInitialTransformInput(decorated);
  registration->SetNumberOfControlPointsPerAxis(5); // ignored: the initial transform's grid is used
  registration->SetNumberOfIterations(3);
  registration->SetInitialSigma(registration->GetSigmaValues().back());
  ITK_TRY_EXPECT_NO_EXCEPTION(registration->Update());
  const double again = TransformTrueError(registration->GetTransform(), source, target, truth);
  std::cout << "from the result, 3 more iterations: " << again << " mm" << std::endl;
  ITK_TEST_EXPECT_EQUAL(registration->GetTransform()->GetNumberOfParameters(), firstNumberOfParameters);
  ITK_TEST_EXPECT_TRUE(again < 1.1 * after);

  // From the result, 15 more iterations at the floor with momentum 0.9 and without it: neither undoes the match nor
  // folds.
  for (const double momentum : { 0.9, 0.0 })
  {
    registration->SetMomentum(momentum);
    registration->SetNumberOfIterations(15);
    registration->SetMinimumSigma(registration->GetInitialSigma());
    ITK_TRY_EXPECT_NO_EXCEPTION(registration->Update());
    const double further = TransformTrueError(registration->GetTransform(), source, target, truth);
    const double determinant = MinimumDeterminantAt(registration->GetTransform(), target);
    std::cout << "from the result, momentum " << momentum << ": " << registration->GetSigmaValues().size()
              << " iterations, " << further << " mm, min det J " << determinant << std::endl;
    ITK_TEST_EXPECT_TRUE(further < 1.1 * after);
    ITK_TEST_EXPECT_TRUE(determinant > 0.0);
  }
  registration->SetMomentum(0.0);
  registration->SetMinimumSigma(0.0);
  registration->SetNumberOfIterations(3);

  // A run-time limit that is over at once: no iteration, the start transform, the limit reported.
  registration->SetMaximumRunTime(1e-9);
  ITK_TRY_EXPECT_NO_EXCEPTION(registration->Update());
  ITK_TEST_EXPECT_TRUE(registration->GetTimeLimitReached());
  ITK_TEST_EXPECT_TRUE(registration->GetSigmaValues().empty());
  ITK_TEST_EXPECT_TRUE(registration->GetStopConditionDescription().find("run-time limit") != std::string::npos);
  std::cout << registration;
  std::cout << "Test finished." << std::endl;
  return testStatus;
}
