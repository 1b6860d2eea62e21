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
#include "itkBSplineFFDImageRegistrationMethod.h"
#include "itkBSplineMRFImageRegistrationMethod.h"
#include "itkBSplineTransformInitializer.h"
#include "itkImageRegionIteratorWithIndex.h"
#include "itkLinearInterpolateImageFunction.h"
#include "itkMultiThreaderBase.h"
#include "itkRandomBSplineTransformGenerator.h"
#include "FFDShapeMatchingDetail/itkSpatialJacobianEvaluator.h"
#include "FFDShapeMatchingDetail/itkMatrixDeterminant.h"
#include "itkTestingMacros.h"
#include <chrono>
#include <ctime>
#include <cmath>
#include <iomanip>
#include <random>
#include <sstream>

namespace
{
constexpr unsigned int Dimension = 3;
using ImageType = itk::Image<float, Dimension>;
using MaskType = itk::Image<unsigned char, Dimension>;
using RegistrationType = itk::BSplineMRFImageRegistrationMethod<ImageType>;
using BSplineType = RegistrationType::BSplineTransformType;
using PointType = itk::Point<double, Dimension>;
using SimilarityEnum = itk::BSplineMRFImageRegistrationMethodEnums::Similarity;
using PairwiseEnum = itk::BSplineMRFImageRegistrationMethodEnums::PairwiseFunction;
using LabelSetEnum = itk::BSplineMRFImageRegistrationMethodEnums::LabelSet;
using SolverEnum = itk::MRFLabelingSolverEnums::Algorithm;

/** The smallest Jacobian determinant of a B-spline at local coordinates 1/4 and 3/4 of each control cell, point by
 * point with SpatialJacobianEvaluator: the reference for the registration's separable evaluation. */
double
BruteForceMinimumJacobianDeterminant(const BSplineType * transform)
{
  itk::detail::SpatialJacobianEvaluator<double, Dimension> evaluator;
  evaluator.Initialize(transform);
  const auto grid = transform->GetCoefficientImages()[0]; // a copy: the array is returned by value
  const auto size = grid->GetLargestPossibleRegion().GetSize();
  double     minimum = std::numeric_limits<double>::max();
  for (unsigned int cz = 0; cz + 3 < size[2]; ++cz)
  {
    for (unsigned int cy = 0; cy + 3 < size[1]; ++cy)
    {
      for (unsigned int cx = 0; cx + 3 < size[0]; ++cx)
      {
        for (unsigned int sample = 0; sample < 8; ++sample)
        {
          // Cell c spans continuous indices c + 1 to c + 2 of the coefficient grid.
          itk::ContinuousIndex<double, Dimension> index;
          index[0] = cx + 1.25 + 0.5 * (sample & 1u);
          index[1] = cy + 1.25 + 0.5 * ((sample >> 1) & 1u);
          index[2] = cz + 1.25 + 0.5 * ((sample >> 2) & 1u);
          PointType point;
          grid->TransformContinuousIndexToPhysicalPoint(index, point);
          itk::Matrix<double, Dimension, Dimension> jacobian;
          evaluator.Evaluate(point, jacobian);
          minimum = std::min(minimum, itk::detail::MatrixDeterminant(jacobian));
        }
      }
    }
  }
  return minimum;
}

/** Signed distance-like function of a smooth bumpy closed surface (star-shaped around the centre, radius R). */
double
ShapeDistance(const PointType & point, const PointType & centre, double radius)
{
  const double dx = point[0] - centre[0];
  const double dy = point[1] - centre[1];
  const double dz = point[2] - centre[2];
  const double r = std::sqrt(dx * dx + dy * dy + dz * dz);
  if (r < 1e-9)
  {
    return -radius;
  }
  const double theta = std::acos(dz / r);
  const double phi = std::atan2(dy, dx);
  const double surface = radius * (1.0 + 0.12 * std::sin(2.0 * theta) * std::cos(3.0 * phi) + 0.08 * std::cos(theta));
  return r - surface;
}

ImageType::Pointer
MakeImage(unsigned int size)
{
  auto                image = ImageType::New();
  ImageType::SizeType imageSize;
  imageSize.Fill(size);
  image->SetRegions(imageSize);
  image->Allocate();
  return image;
}

/** A test case: moving = shape distance; fixed(x) = moving(T_true(x)); mask = band around the fixed surface. */
struct Case
{
  ImageType::Pointer     Fixed;
  ImageType::Pointer     Moving;
  MaskType::Pointer      Mask;
  BSplineType::Pointer   Truth;
  std::vector<PointType> SurfacePoints; // fixed points near the target surface
};

Case
MakeCase(unsigned int size, double radius, double rmsDisplacement, unsigned int truthControlPoints, double band)
{
  Case      result;
  PointType centre;
  centre.Fill(0.5 * (size - 1));
  result.Moving = MakeImage(size);
  result.Fixed = MakeImage(size);
  for (itk::ImageRegionIteratorWithIndex<ImageType> it(result.Moving, result.Moving->GetLargestPossibleRegion());
       !it.IsAtEnd();
       ++it)
  {
    PointType point;
    result.Moving->TransformIndexToPhysicalPoint(it.GetIndex(), point);
    it.Set(static_cast<float>(ShapeDistance(point, centre, radius)));
  }
  using GeneratorType = itk::RandomBSplineTransformGenerator<double, Dimension>;
  auto generator = GeneratorType::New();
  generator->SetDomainFromImage(result.Fixed);
  generator->SetNumberOfControlPointsPerAxis(truthControlPoints);
  generator->SetNoise(itk::RandomBSplineTransformGeneratorEnums::Noise::SmoothedGaussian);
  generator->SetSmoothingSigma(1.0);
  generator->SetRMSDisplacement(rmsDisplacement);
  generator->SetSeed(7);
  generator->Generate();
  result.Truth = generator->GetModifiableTransform();

  result.Mask = MaskType::New();
  result.Mask->CopyInformation(result.Fixed);
  result.Mask->SetRegions(result.Fixed->GetLargestPossibleRegion());
  result.Mask->Allocate();
  for (itk::ImageRegionIteratorWithIndex<ImageType> it(result.Fixed, result.Fixed->GetLargestPossibleRegion());
       !it.IsAtEnd();
       ++it)
  {
    PointType point;
    result.Fixed->TransformIndexToPhysicalPoint(it.GetIndex(), point);
    const double value = ShapeDistance(result.Truth->TransformPoint(point), centre, radius);
    it.Set(static_cast<float>(value));
    result.Mask->SetPixel(it.GetIndex(), std::abs(value) <= band ? 1 : 0);
    if (std::abs(value) < 0.5)
    {
      result.SurfacePoints.push_back(point);
    }
  }
  return result;
}

/** Mean |T(x) - T_true(x)| over the target surface points. */
double
TrueError(const Case & testCase, const itk::Transform<double, 3, 3> * transform)
{
  double sum = 0.0;
  for (const auto & point : testCase.SurfacePoints)
  {
    const auto estimated = transform == nullptr ? point : transform->TransformPoint(point);
    sum += (estimated - testCase.Truth->TransformPoint(point)).GetNorm();
  }
  return sum / testCase.SurfacePoints.size();
}

/** Unary costs computed directly: per control point p and label d, sum over the masked voxels x of
 * w_p(x) c(F(x), M(T(x) + d)) divided by the sum of w_p(x); w_p(x) from the transform's parameter Jacobian. */
int
CheckUnaryProjection(SimilarityEnum similarity)
{
  const unsigned int size = 14;
  auto               fixed = MakeImage(size);
  auto               moving = MakeImage(size);
  auto               mask = MaskType::New();
  mask->SetRegions(fixed->GetLargestPossibleRegion());
  mask->Allocate();
  std::mt19937                           random(99);
  std::uniform_real_distribution<double> noise(-0.3, 0.3);
  for (itk::ImageRegionIteratorWithIndex<ImageType> it(fixed, fixed->GetLargestPossibleRegion()); !it.IsAtEnd(); ++it)
  {
    const auto index = it.GetIndex();
    it.Set(
      static_cast<float>(std::sin(0.4 * index[0]) + 0.5 * std::cos(0.3 * index[1] + 0.2 * index[2]) + noise(random)));
    moving->SetPixel(index,
                     static_cast<float>(std::sin(0.45 * index[0] + 0.3) + 0.4 * std::cos(0.25 * index[1]) +
                                        0.3 * std::sin(0.35 * index[2])));
    mask->SetPixel(index, (index[0] + index[1] + 2 * index[2]) % 5 != 0 ? 1 : 0);
  }
  auto                      transform = BSplineType::New();
  BSplineType::MeshSizeType meshSize;
  meshSize.Fill(3);
  auto initializer = itk::BSplineTransformInitializer<BSplineType, ImageType>::New();
  initializer->SetTransform(transform);
  initializer->SetImage(fixed);
  initializer->SetTransformDomainMeshSize(meshSize);
  initializer->InitializeTransform();
  BSplineType::ParametersType parameters(transform->GetNumberOfParameters());
  for (unsigned int i = 0; i < parameters.GetSize(); ++i)
  {
    parameters[i] = noise(random) * 3.0;
  }
  transform->SetParametersByValue(parameters);

  auto registration = RegistrationType::New();
  registration->SetSimilarity(similarity);
  registration->SetLabelSet(LabelSetEnum::SparseWithDiagonals);
  registration->SetNumberOfLabelSteps(1);
  const auto labels = registration->MakeLabels(1.3);
  const auto unary = registration->ComputeUnaryCosts(fixed, mask, moving, transform, labels);

  const unsigned int numberOfNodes = transform->GetNumberOfParameters() / Dimension;
  ITK_TEST_EXPECT_EQUAL(unary.size(), numberOfNodes * labels.size());
  auto interpolator = itk::LinearInterpolateImageFunction<ImageType, double>::New();
  interpolator->SetInputImage(moving);
  std::vector<double> weightSum(numberOfNodes, 0.0);
  std::vector<double> costSum(numberOfNodes * labels.size(), 0.0);
  // NCC moments per node and label: sum w, w f, w f^2, w m, w m^2, w f m.
  std::vector<std::array<double, 6>> moments(numberOfNodes * labels.size(), std::array<double, 6>{});
  BSplineType::JacobianType          jacobian;
  for (itk::ImageRegionIteratorWithIndex<ImageType> it(fixed, fixed->GetLargestPossibleRegion()); !it.IsAtEnd(); ++it)
  {
    if (mask->GetPixel(it.GetIndex()) == 0)
    {
      continue;
    }
    PointType point;
    fixed->TransformIndexToPhysicalPoint(it.GetIndex(), point);
    transform->ComputeJacobianWithRespectToParameters(point, jacobian);
    const auto mapped = transform->TransformPoint(point);
    for (unsigned int l = 0; l < labels.size(); ++l)
    {
      itk::ContinuousIndex<double, Dimension> index;
      moving->TransformPhysicalPointToContinuousIndex(mapped + labels[l], index);
      for (unsigned int a = 0; a < Dimension; ++a)
      {
        index[a] = std::min(std::max(index[a], 0.0), size - 1.0);
      }
      const double m = interpolator->EvaluateAtContinuousIndex(index);
      const double f = it.Get();
      for (unsigned int p = 0; p < numberOfNodes; ++p)
      {
        const double w = jacobian(0, p);
        if (w == 0.0)
        {
          continue;
        }
        if (l == 0)
        {
          weightSum[p] += w;
        }
        costSum[p * labels.size() + l] += w * registration->PointwiseCost(f, m);
        auto & moment = moments[p * labels.size() + l];
        moment[0] += w;
        moment[1] += w * f;
        moment[2] += w * f * f;
        moment[3] += w * m;
        moment[4] += w * m * m;
        moment[5] += w * f * m;
      }
    }
  }
  double largestDifference = 0.0;
  double largestCost = 0.0;
  for (unsigned int p = 0; p < numberOfNodes; ++p)
  {
    for (unsigned int l = 0; l < labels.size(); ++l)
    {
      double direct = 0.0;
      if (weightSum[p] > 0.0)
      {
        if (similarity == SimilarityEnum::NormalizedCrossCorrelation)
        {
          const auto & m = moments[p * labels.size() + l];
          const double meanF = m[1] / m[0];
          const double meanM = m[3] / m[0];
          const double varF = m[2] / m[0] - meanF * meanF;
          const double varM = m[4] / m[0] - meanM * meanM;
          direct = 1.0 - (m[5] / m[0] - meanF * meanM) / std::sqrt(varF * varM);
        }
        else
        {
          direct = costSum[p * labels.size() + l] / weightSum[p];
        }
      }
      largestDifference = std::max(largestDifference, std::abs(direct - unary[p * labels.size() + l]));
      largestCost = std::max(largestCost, std::abs(direct));
    }
  }
  std::cout << similarity << ": projected vs direct unary costs, largest difference " << largestDifference
            << " (largest cost " << largestCost << ")" << std::endl;
  ITK_TEST_EXPECT_TRUE(largestCost > 0.0);
  return largestDifference <= 1e-4 * std::max(1.0, largestCost) ? EXIT_SUCCESS : EXIT_FAILURE;
}

bool
EnergiesNeverIncrease(const RegistrationType * registration)
{
  const auto & energies = registration->GetEnergyValues();
  const auto & levels = registration->GetEnergyLevels();
  for (size_t i = 1; i < energies.size(); ++i)
  {
    if (levels[i] == levels[i - 1] && energies[i] > energies[i - 1])
    {
      std::cerr << "Energy increased at iteration " << i << ": " << std::setprecision(17) << energies[i - 1] << " -> "
                << energies[i] << std::endl;
      return false;
    }
  }
  return !energies.empty();
}

/** Settings of the MRF runs of the timing mode. */
struct TimingSettings
{
  unsigned int Cycles{ 2 };
  unsigned int Steps{ 3 };
  unsigned int Iterations{ 5 };
  double       Lambda{ 0.5 };
  double       Shrink{ 0.67 };
};

/** Wall-clock and process CPU seconds of a call. */
template <typename TFunction>
std::pair<double, double>
Measure(TFunction && function)
{
  const auto    wallStart = std::chrono::steady_clock::now();
  const clock_t cpuStart = std::clock();
  function();
  return { std::chrono::duration<double>(std::chrono::steady_clock::now() - wallStart).count(),
           static_cast<double>(std::clock() - cpuStart) / CLOCKS_PER_SEC };
}

/** Timing against the GO method on 100^3 cases (not run by CTest): a smooth deformation (8^3 control points) and
 * the paper's kind (20^3 control points), both with a 6 mm band mask around the target surface. */
int
RunTiming(const TimingSettings & settings)
{
  itk::MultiThreaderBase::SetGlobalDefaultNumberOfThreads(2);
  for (const unsigned int truthGrid : { 8u, 20u })
  {
    const auto   testCase = MakeCase(100, 30.0, truthGrid == 8 ? 3.0 : 2.5, truthGrid, 6.0);
    const double before = TrueError(testCase, nullptr);
    unsigned int used = 0;
    for (itk::ImageRegionIteratorWithIndex<MaskType> it(testCase.Mask, testCase.Mask->GetLargestPossibleRegion());
         !it.IsAtEnd();
         ++it)
    {
      used += it.Get() != 0;
    }
    std::cout << "100^3 case, true deformation on " << truthGrid
              << "^3 control points: " << testCase.SurfacePoints.size() << " surface points, " << used
              << " band voxels, true error before " << before << " mm" << std::endl;
    for (const auto similarity : { SimilarityEnum::SumOfSquaredDifferences, SimilarityEnum::MutualInformation })
    {
      auto mrf = RegistrationType::New();
      mrf->SetFixedImage(testCase.Fixed);
      mrf->SetMovingImage(testCase.Moving);
      mrf->SetFixedImageMask(testCase.Mask);
      mrf->SetSimilarity(similarity);
      mrf->SetNumberOfSolverCycles(settings.Cycles);
      mrf->SetNumberOfLabelSteps(settings.Steps);
      mrf->SetNumberOfIterationsPerLevel(settings.Iterations);
      mrf->SetRegularizationWeight(settings.Lambda);
      mrf->SetLabelShrinkFactor(settings.Shrink);
      const auto seconds = Measure([&mrf]() { mrf->Update(); });
      std::cout << "  MRF " << similarity << ": " << seconds.first << " s wall, " << seconds.second
                << " s CPU, true error " << TrueError(testCase, mrf->GetTransform()) << " mm, min det J "
                << mrf->GetMinimumJacobianDeterminant() << ", rejected " << mrf->GetNumberOfRejectedUpdates() << "/"
                << mrf->GetEnergyValues().size() << std::endl;
    }
    using GOType = itk::BSplineFFDImageRegistrationMethod<ImageType>;
    for (const auto metric : { itk::FFDShapeMatchingEnums::ImageMetric::MeanSquares,
                               itk::FFDShapeMatchingEnums::ImageMetric::MattesMutualInformation })
    {
      auto go = GOType::New();
      go->SetFixedImage(testCase.Fixed);
      go->SetMovingImage(testCase.Moving);
      go->SetFixedImageMask(testCase.Mask);
      go->SetMetric(metric);
      go->SetNumberOfLevels(3);
      const auto seconds = Measure([&go]() { go->Update(); });
      std::cout << "  GO " << metric << ": " << seconds.first << " s wall, " << seconds.second << " s CPU, true error "
                << TrueError(testCase, go->GetTransform()) << " mm, " << go->GetMetricValues().size() << " iterations"
                << std::endl;
    }
  }
  return EXIT_SUCCESS;
}
} // namespace

int
itkBSplineMRFImageRegistrationMethodTest(int argc, char * argv[])
{
  if (argc > 7)
  {
    std::cerr << "Usage: " << itkNameOfTestExecutableMacro(argv)
              << " [timing [cycles [steps [iterations [lambda [shrink]]]]]]" << std::endl;
    return EXIT_FAILURE;
  }
  if (argc >= 2)
  {
    if (std::string(argv[1]) != "timing")
    {
      std::cerr << "Unknown mode " << argv[1] << "; expected \"timing\"." << std::endl;
      return EXIT_FAILURE;
    }
    TimingSettings settings;
    settings.Cycles = argc > 2 ? std::stoi(argv[2]) : settings.Cycles;
    settings.Steps = argc > 3 ? std::stoi(argv[3]) : settings.Steps;
    settings.Iterations = argc > 4 ? std::stoi(argv[4]) : settings.Iterations;
    settings.Lambda = argc > 5 ? std::stod(argv[5]) : settings.Lambda;
    settings.Shrink = argc > 6 ? std::stod(argv[6]) : settings.Shrink;
    return RunTiming(settings);
  }
  int testStatus = EXIT_SUCCESS;

  auto registration = RegistrationType::New();
  ITK_EXERCISE_BASIC_OBJECT_METHODS(
    registration, BSplineMRFImageRegistrationMethod, BSplineImageRegistrationMethodBase);
  ITK_TEST_SET_GET_VALUE(20u, registration->GetNumberOfControlPointsPerAxis());
  ITK_TEST_SET_GET_VALUE(3u, registration->GetNumberOfLevels());
  ITK_TEST_SET_GET_VALUE(5u, registration->GetNumberOfIterationsPerLevel());
  ITK_TEST_SET_GET_VALUE(3u, registration->GetNumberOfLabelSteps());
  ITK_TEST_SET_GET_VALUE(0.4, registration->GetMaximumDisplacementFactor());
  ITK_TEST_SET_GET_VALUE(0.67, registration->GetLabelShrinkFactor());
  ITK_TEST_SET_GET_VALUE(SimilarityEnum::MutualInformation, registration->GetSimilarity());
  ITK_TEST_SET_GET_VALUE(PairwiseEnum::Quadratic, registration->GetPairwiseFunction());
  ITK_TEST_SET_GET_VALUE(LabelSetEnum::Sparse, registration->GetLabelSet());
  ITK_TEST_SET_GET_VALUE(SolverEnum::AlphaExpansion, registration->GetSolver());
  ITK_TEST_SET_GET_BOOLEAN(registration, RejectFoldingUpdates, true);
  ITK_TEST_SET_GET_BOOLEAN(registration, UseImagePyramid, true);
  std::ostringstream printed;
  printed << SimilarityEnum::NormalizedCrossCorrelation << ' ' << PairwiseEnum::Truncated << ' ' << LabelSetEnum::Dense;
  ITK_TEST_EXPECT_EQUAL(
    printed.str(),
    std::string("itk::BSplineMRFImageRegistrationMethodEnums::Similarity::NormalizedCrossCorrelation "
                "itk::BSplineMRFImageRegistrationMethodEnums::PairwiseFunction::Truncated "
                "itk::BSplineMRFImageRegistrationMethodEnums::LabelSet::Dense"));

  // Label sets: sizes and the zero label first.
  registration->SetNumberOfLabelSteps(2);
  ITK_TEST_EXPECT_EQUAL(registration->MakeLabels(1.0).size(), 13u);
  registration->SetLabelSet(LabelSetEnum::SparseWithDiagonals);
  ITK_TEST_EXPECT_EQUAL(registration->MakeLabels(1.0).size(), 53u);
  registration->SetLabelSet(LabelSetEnum::Dense);
  ITK_TEST_EXPECT_EQUAL(registration->MakeLabels(1.0).size(), 125u);
  ITK_TEST_EXPECT_EQUAL(registration->MakeLabels(1.0)[0].GetNorm(), 0.0);
  registration->SetLabelSet(LabelSetEnum::Sparse);
  registration->SetNumberOfLabelSteps(3);

  auto       clock = std::chrono::steady_clock::now();
  const auto elapsed = [&clock]() {
    const auto   now = std::chrono::steady_clock::now();
    const double seconds = std::chrono::duration<double>(now - clock).count();
    clock = now;
    return seconds;
  };

  // Unary projection equals the direct computation.
  for (const auto similarity : { SimilarityEnum::SumOfSquaredDifferences,
                                 SimilarityEnum::SumOfAbsoluteDifferences,
                                 SimilarityEnum::MutualInformation,
                                 SimilarityEnum::NormalizedCrossCorrelation })
  {
    if (CheckUnaryProjection(similarity) != EXIT_SUCCESS)
    {
      testStatus = EXIT_FAILURE;
    }
  }
  std::cout << "Unary checks: " << elapsed() << " s" << std::endl;

  const auto   testCase = MakeCase(40, 11.0, 2.0, 8, 5.0);
  const double before = TrueError(testCase, nullptr);

  // Bad input.
  registration->SetFixedImage(testCase.Fixed);
  ITK_TRY_EXPECT_EXCEPTION(registration->Update()); // no moving image
  registration->SetMovingImage(testCase.Moving);
  registration->SetNumberOfControlPointsPerAxis(3);
  ITK_TRY_EXPECT_EXCEPTION(registration->Update()); // grid < 4
  registration->SetNumberOfControlPointsPerAxis(8);
  registration->SetNumberOfLabelSteps(0);
  ITK_TRY_EXPECT_EXCEPTION(registration->Update()); // no label
  registration->SetNumberOfLabelSteps(3);
  registration->SetNumberOfLevels(7);
  ITK_TRY_EXPECT_EXCEPTION(registration->Update()); // images too small for the levels
  registration->SetNumberOfLevels(2);
  registration->SetLabelShrinkFactor(0.0);
  ITK_TRY_EXPECT_EXCEPTION(registration->Update());
  registration->SetLabelShrinkFactor(0.67);
  registration->SetRegularizationWeight(-1.0);
  ITK_TRY_EXPECT_EXCEPTION(registration->Update());
  registration->SetRegularizationWeight(0.5);
  registration->SetSolver(SolverEnum::Exhaustive);
  ITK_TRY_EXPECT_EXCEPTION(registration->Update());
  registration->SetSolver(SolverEnum::AlphaExpansion);
  auto emptyMask = MaskType::New();
  emptyMask->CopyInformation(testCase.Mask);
  emptyMask->SetRegions(testCase.Mask->GetLargestPossibleRegion());
  emptyMask->Allocate(true);
  registration->SetFixedImageMask(emptyMask);
  ITK_TRY_EXPECT_EXCEPTION(registration->Update()); // no voxel in the mask
  registration->SetFixedImageMask(testCase.Mask);

  // End to end on the generated case, each similarity.
  for (const auto similarity : { SimilarityEnum::SumOfSquaredDifferences,
                                 SimilarityEnum::MutualInformation,
                                 SimilarityEnum::SumOfAbsoluteDifferences,
                                 SimilarityEnum::NormalizedCrossCorrelation })
  {
    registration->SetSimilarity(similarity);
    ITK_TRY_EXPECT_NO_EXCEPTION(registration->Update());
    const double after = TrueError(testCase, registration->GetTransform());
    std::cout << similarity << ": true error " << before << " -> " << after << " mm, min det J "
              << registration->GetMinimumJacobianDeterminant() << ", " << registration->GetNumberOfRejectedUpdates()
              << " rejected of " << registration->GetEnergyValues().size() << ", " << elapsed() << " s" << std::endl;
    ITK_TEST_EXPECT_TRUE(after <= 0.4 * before);
    ITK_TEST_EXPECT_TRUE(EnergiesNeverIncrease(registration));
    ITK_TEST_EXPECT_TRUE(registration->GetMinimumJacobianDeterminant() > 0.0);
  }

  // Without the image pyramid (every level at full resolution) the same accuracy holds.
  registration->SetSimilarity(SimilarityEnum::SumOfSquaredDifferences);
  registration->UseImagePyramidOff();
  ITK_TRY_EXPECT_NO_EXCEPTION(registration->Update());
  {
    const double after = TrueError(testCase, registration->GetTransform());
    std::cout << "SSD without the image pyramid: true error " << before << " -> " << after << " mm, " << elapsed()
              << " s" << std::endl;
    ITK_TEST_EXPECT_TRUE(after <= 0.4 * before);
    ITK_TEST_EXPECT_TRUE(EnergiesNeverIncrease(registration));
    ITK_TEST_EXPECT_TRUE(registration->GetMinimumJacobianDeterminant() > 0.0);
  }
  registration->UseImagePyramidOn();

  // Alpha-expansion reaches a labeling energy no higher than ICM's on the same first iteration.
  registration->SetSimilarity(SimilarityEnum::SumOfSquaredDifferences);
  registration->SetNumberOfLevels(1);
  registration->SetNumberOfIterationsPerLevel(1);
  registration->SetSolver(SolverEnum::ICM);
  ITK_TRY_EXPECT_NO_EXCEPTION(registration->Update());
  const double icmEnergy = registration->GetLabelingEnergyValues().front();
  registration->SetSolver(SolverEnum::AlphaExpansion);
  ITK_TRY_EXPECT_NO_EXCEPTION(registration->Update());
  const double expansionEnergy = registration->GetLabelingEnergyValues().front();
  std::cout << "First-iteration labeling energy: alpha-expansion " << expansionEnergy << ", ICM " << icmEnergy
            << std::endl;
  ITK_TEST_EXPECT_TRUE(expansionEnergy <= icmEnergy);

  // The spanning-tree solver (the tree's exact minimum, then two ICM sweeps) registers as accurately, with energies
  // that never increase.
  registration->SetSolver(SolverEnum::SpanningTree);
  registration->SetNumberOfSolverCycles(3);
  registration->SetNumberOfLevels(2);
  registration->SetNumberOfIterationsPerLevel(5);
  ITK_TRY_EXPECT_NO_EXCEPTION(registration->Update());
  {
    const double after = TrueError(testCase, registration->GetTransform());
    std::cout << "SSD, spanning-tree solver: true error " << before << " -> " << after << " mm, " << elapsed() << " s"
              << std::endl;
    ITK_TEST_EXPECT_TRUE(after <= 0.4 * before);
    ITK_TEST_EXPECT_TRUE(EnergiesNeverIncrease(registration));
    ITK_TEST_EXPECT_TRUE(registration->GetMinimumJacobianDeterminant() > 0.0);
    // The separable minimum Jacobian determinant against point-by-point evaluation.
    const double bruteForce =
      BruteForceMinimumJacobianDeterminant(dynamic_cast<const BSplineType *>(registration->GetTransform()));
    std::cout << "min det J: separable " << registration->GetMinimumJacobianDeterminant() << ", point by point "
              << bruteForce << std::endl;
    ITK_TEST_EXPECT_TRUE(std::abs(registration->GetMinimumJacobianDeterminant() - bruteForce) < 1e-9);
  }
  registration->SetSolver(SolverEnum::AlphaExpansion);
  registration->SetNumberOfSolverCycles(2);

  // A huge regularization weight keeps the transform near the identity.
  registration->SetNumberOfLevels(2);
  registration->SetNumberOfIterationsPerLevel(5);
  registration->SetRegularizationWeight(1e6);
  ITK_TRY_EXPECT_NO_EXCEPTION(registration->Update());
  // The pairwise terms do not see a uniform translation: what must vanish is the deformation about it.
  const auto &       stiff = registration->GetTransform()->GetParameters();
  const unsigned int numberOfNodes = stiff.GetSize() / Dimension;
  double             largest = 0.0;
  double             largestMean = 0.0;
  for (unsigned int d = 0; d < Dimension; ++d)
  {
    double mean = 0.0;
    for (unsigned int p = 0; p < numberOfNodes; ++p)
    {
      mean += stiff[d * numberOfNodes + p] / numberOfNodes;
    }
    largestMean = std::max(largestMean, std::abs(mean));
    for (unsigned int p = 0; p < numberOfNodes; ++p)
    {
      largest = std::max(largest, std::abs(stiff[d * numberOfNodes + p] - mean));
    }
  }
  std::cout << "Huge lambda: largest control displacement about the mean " << largest << " mm (mean translation up to "
            << largestMean << " mm)" << std::endl;
  ITK_TEST_EXPECT_TRUE(largest < 0.05 * before);

  // Run-time limit. A negative limit is clamped to none, as GO's.
  ITK_TEST_SET_GET_VALUE(0.0, registration->GetMaximumRunTime());
  ITK_TEST_EXPECT_TRUE(!registration->GetTimeLimitReached());
  registration->SetMaximumRunTime(-1.0);
  ITK_TEST_SET_GET_VALUE(0.0, registration->GetMaximumRunTime());
  // A run of a huge number of iterations over many labels (the dense cube, 343 of them, at a range that does not
  // shrink), which would take hours, stops at a limit of 0.5 s, with a valid transform on the final grid, no worse
  // than the start. The bound on the time it took allows for a sanitizer build on a loaded machine (a label pass
  // is the unit the limit is checked at): 10 s, far below the unlimited run.
  registration->SetRegularizationWeight(0.5);
  registration->SetSimilarity(SimilarityEnum::SumOfSquaredDifferences);
  registration->SetNumberOfLevels(2);
  registration->SetNumberOfIterationsPerLevel(1000000);
  registration->SetLabelSet(LabelSetEnum::Dense);
  registration->SetLabelShrinkFactor(1.0);
  registration->SetMaximumRunTime(0.5);
  ITK_TEST_SET_GET_VALUE(0.5, registration->GetMaximumRunTime());
  elapsed();
  ITK_TRY_EXPECT_NO_EXCEPTION(registration->Update());
  {
    const double seconds = elapsed();
    const auto * limited = dynamic_cast<const BSplineType *>(registration->GetTransform());
    ITK_TEST_EXPECT_TRUE(limited != nullptr);
    bool finite = true;
    for (unsigned int i = 0; i < limited->GetNumberOfParameters(); ++i)
    {
      finite = finite && std::isfinite(limited->GetParameters()[i]);
    }
    const double after = TrueError(testCase, limited);
    std::cout << "Dense labels, 10^6 iterations per level, limited to 0.5 s: " << seconds << " s, "
              << registration->GetEnergyValues().size() << " iterations, true error " << before << " -> " << after
              << " mm" << std::endl;
    ITK_TEST_EXPECT_TRUE(seconds < 10.0);
    ITK_TEST_EXPECT_TRUE(registration->GetTimeLimitReached());
    ITK_TEST_EXPECT_TRUE(finite);
    ITK_TEST_EXPECT_EQUAL(limited->GetCoefficientImages()[0]->GetLargestPossibleRegion().GetSize()[0],
                          registration->GetMeshSizeAtLevel(1) + 3);
    // On a loaded machine the limit can pass while the first iteration's unary costs are computed: that
    // iteration is dropped and the transform stays the identity.
    ITK_TEST_EXPECT_TRUE(registration->GetEnergyValues().empty() || EnergiesNeverIncrease(registration));
    ITK_TEST_EXPECT_TRUE(registration->GetMinimumJacobianDeterminant() > 0.0);
    ITK_TEST_EXPECT_TRUE(after <= before);
  }
  registration->SetMaximumRunTime(0.0);
  registration->SetLabelSet(LabelSetEnum::Sparse);
  registration->SetLabelShrinkFactor(0.67);
  registration->SetNumberOfIterationsPerLevel(5);
  std::cout << registration;

  // The transform output is a pipeline output: it carries the transform.
  ITK_TEST_EXPECT_TRUE(registration->GetTransformOutput()->Get() == registration->GetTransform());
  std::cout << "Total: " << elapsed() << " s" << std::endl;
  return testStatus;
}
