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

#include "itkImage.h"
#include "itkRandomBSplineTransformGenerator.h"
#include "itkTestingMacros.h"
#include <cmath>
#include <sstream>

namespace
{
/** Standard deviation of N(0, sigma^2) clamped to [-a, a]:
 * E[X^2] = sigma^2 (2 Phi(alpha) - 1 - 2 alpha phi(alpha)) + 2 a^2 (1 - Phi(alpha)), alpha = a / sigma. */
double
ClippedNormalStandardDeviation(double sigma, double a)
{
  const double alpha = a / sigma;
  const double pdf = std::exp(-0.5 * alpha * alpha) / std::sqrt(2.0 * 3.14159265358979323846);
  const double cdf = 0.5 * std::erfc(-alpha / std::sqrt(2.0));
  return std::sqrt(sigma * sigma * (2.0 * cdf - 1.0 - 2.0 * alpha * pdf) + 2.0 * a * a * (1.0 - cdf));
}

/** Correlation of each control displacement component with its +x neighbour on an n^3 grid. */
double
NeighbourCorrelation(const itk::OptimizerParameters<double> & parameters, unsigned int n)
{
  double sumProduct = 0.0;
  double sumSquares = 0.0;
  for (unsigned int i = 0; i < parameters.size(); ++i)
  {
    sumSquares += parameters[i] * parameters[i];
    if ((i % n) + 1 < n)
    {
      sumProduct += parameters[i] * parameters[i + 1];
    }
  }
  return sumProduct / sumSquares * n / (n - 1.0);
}
} // namespace

int
itkRandomBSplineTransformGeneratorTest(int argc, char * argv[])
{
  if (argc != 1)
  {
    std::cerr << "Usage: " << itkNameOfTestExecutableMacro(argv) << std::endl;
    return EXIT_FAILURE;
  }
  using GeneratorType = itk::RandomBSplineTransformGenerator<double, 3>;
  using NoiseEnum = GeneratorType::NoiseEnum;

  auto generator = GeneratorType::New();
  ITK_EXERCISE_BASIC_OBJECT_METHODS(generator, RandomBSplineTransformGenerator, Object);
  ITK_TEST_SET_GET_VALUE(20u, generator->GetNumberOfControlPointsPerAxis());
  ITK_TEST_SET_GET_VALUE(4u,
                         (generator->SetNumberOfControlPointsPerAxis(2), generator->GetNumberOfControlPointsPerAxis()));
  generator->SetNumberOfControlPointsPerAxis(20);
  ITK_TEST_SET_GET_VALUE(1.5, (generator->SetSigma(1.5), generator->GetSigma()));
  ITK_TEST_SET_GET_VALUE(2.5, (generator->SetClipAmplitude(2.5), generator->GetClipAmplitude()));
  ITK_TEST_SET_GET_VALUE(2.0, (generator->SetSmoothingSigma(2.0), generator->GetSmoothingSigma()));
  ITK_TEST_SET_GET_VALUE(3.0, (generator->SetRMSDisplacement(3.0), generator->GetRMSDisplacement()));
  ITK_TEST_SET_GET_VALUE(7u, (generator->SetSeed(7), generator->GetSeed()));
  ITK_TEST_SET_GET_VALUE(
    10u, (generator->SetNumberOfJacobianSamplesPerAxis(10), generator->GetNumberOfJacobianSamplesPerAxis()));
  generator->SetNoise(NoiseEnum::SmoothedGaussian);
  ITK_TEST_EXPECT_TRUE(generator->GetNoise() == NoiseEnum::SmoothedGaussian);
  std::ostringstream enumText;
  enumText << NoiseEnum::ClippedGaussian;
  ITK_TEST_EXPECT_EQUAL(enumText.str(),
                        std::string("itk::RandomBSplineTransformGeneratorEnums::Noise::ClippedGaussian"));

  // An empty domain is refused.
  GeneratorType::PhysicalDimensionsType empty;
  empty.Fill(0.0);
  generator->SetPhysicalDimensions(empty);
  ITK_TRY_EXPECT_EXCEPTION(generator->Generate());

  // Domain from an image: from the outer corner of the first voxel, size x spacing.
  using ImageType = itk::Image<unsigned char, 3>;
  auto                 image = ImageType::New();
  ImageType::SizeType  size = { { 50, 40, 30 } };
  ImageType::PointType imageOrigin;
  imageOrigin[0] = 10.0;
  imageOrigin[1] = -5.0;
  imageOrigin[2] = 2.0;
  ImageType::SpacingType spacing;
  spacing.Fill(2.0);
  image->SetRegions(size);
  image->SetOrigin(imageOrigin);
  image->SetSpacing(spacing);
  generator->SetDomainFromImage(image);
  ITK_TEST_EXPECT_TRUE(std::abs(generator->GetOrigin()[0] - 9.0) < 1e-12);
  ITK_TEST_EXPECT_TRUE(std::abs(generator->GetPhysicalDimensions()[1] - 80.0) < 1e-12);
  GeneratorType::PointType minimum;
  GeneratorType::PointType maximum;
  minimum.Fill(0.0);
  maximum.Fill(100.0);
  generator->SetDomainFromBoundingBox(minimum, maximum);
  ITK_TEST_EXPECT_TRUE(std::abs(generator->GetPhysicalDimensions()[2] - 100.0) < 1e-12);

  // Clipped Gaussian noise: reproducible for a seed, statistics of the clipped normal.
  const double sigma = 2.0;
  const double clip = 3.0;
  generator->SetNoise(NoiseEnum::ClippedGaussian);
  generator->SetSigma(sigma);
  generator->SetClipAmplitude(clip);
  generator->SetSeed(2024);
  ITK_TRY_EXPECT_NO_EXCEPTION(generator->Generate());
  const auto first = generator->GetTransform()->GetParameters();
  ITK_TEST_EXPECT_EQUAL(first.size(), 3u * 20 * 20 * 20);
  ITK_TEST_EXPECT_EQUAL(generator->GetTransform()->GetTransformDomainMeshSize()[0], 17);
  auto second = GeneratorType::New();
  second->SetDomainFromBoundingBox(minimum, maximum);
  second->SetSigma(sigma);
  second->SetClipAmplitude(clip);
  second->SetSeed(2024);
  second->Generate();
  ITK_TEST_EXPECT_TRUE(first == second->GetTransform()->GetParameters());
  second->SetSeed(2025);
  second->Generate();
  ITK_TEST_EXPECT_TRUE(!(first == second->GetTransform()->GetParameters()));

  double       sum = 0.0;
  double       sumOfSquares = 0.0;
  double       largest = 0.0;
  unsigned int clipped = 0;
  for (unsigned int i = 0; i < first.size(); ++i)
  {
    sum += first[i];
    sumOfSquares += first[i] * first[i];
    largest = std::max(largest, std::abs(first[i]));
    clipped += (std::abs(first[i]) == clip) ? 1 : 0;
  }
  const double n = first.size();
  const double mean = sum / n;
  const double standardDeviation = std::sqrt(sumOfSquares / n - mean * mean);
  const double expectedDeviation = ClippedNormalStandardDeviation(sigma, clip);
  const double expectedClippedFraction = std::erfc(clip / sigma / std::sqrt(2.0));
  std::cout << "Clipped Gaussian: mean " << mean << ", std " << standardDeviation << " (analytic " << expectedDeviation
            << "), max |d| " << largest << ", clipped fraction " << clipped / n << " (analytic "
            << expectedClippedFraction << "), min det J " << generator->GetMinimumJacobianDeterminant()
            << ", max det J " << generator->GetMaximumJacobianDeterminant() << std::endl;
  ITK_TEST_EXPECT_TRUE(std::abs(mean) < 4.0 * expectedDeviation / std::sqrt(n));
  ITK_TEST_EXPECT_TRUE(std::abs(standardDeviation / expectedDeviation - 1.0) < 0.03);
  ITK_TEST_EXPECT_TRUE(largest <= clip);
  ITK_TEST_EXPECT_TRUE(std::abs(clipped / n - expectedClippedFraction) < 0.01);
  ITK_TEST_EXPECT_TRUE(generator->GetMinimumJacobianDeterminant() <= generator->GetMaximumJacobianDeterminant());

  // Small noise does not fold; large noise does.
  generator->SetSigma(0.3);
  generator->SetClipAmplitude(1.0);
  generator->Generate();
  const double gentle = generator->GetMinimumJacobianDeterminant();
  generator->SetSigma(20.0);
  generator->SetClipAmplitude(40.0);
  generator->Generate();
  const double violent = generator->GetMinimumJacobianDeterminant();
  std::cout << "Min det J: sigma 0.3 -> " << gentle << ", sigma 20 -> " << violent << std::endl;
  ITK_TEST_EXPECT_TRUE(gentle > 0.5);
  ITK_TEST_EXPECT_TRUE(violent < 0.0);

  // Smoothed noise: hits the RMS, and neighbours are correlated (white noise: not).
  generator->SetNoise(NoiseEnum::SmoothedGaussian);
  generator->SetRMSDisplacement(2.5);
  generator->SetSmoothingSigma(2.0);
  generator->Generate();
  const auto & smooth = generator->GetTransform()->GetParameters();
  double       squares = 0.0;
  for (unsigned int i = 0; i < smooth.size(); ++i)
  {
    squares += smooth[i] * smooth[i];
  }
  const double rms = std::sqrt(squares / (smooth.size() / 3));
  const double smoothCorrelation = NeighbourCorrelation(smooth, 20);
  generator->SetSmoothingSigma(0.0);
  generator->Generate();
  const double whiteCorrelation = NeighbourCorrelation(generator->GetTransform()->GetParameters(), 20);
  std::cout << "Smoothed Gaussian: RMS " << rms << " (requested 2.5), neighbour correlation " << smoothCorrelation
            << " (white: " << whiteCorrelation << ")" << std::endl;
  ITK_TEST_EXPECT_TRUE(std::abs(rms - 2.5) < 1e-9);
  ITK_TEST_EXPECT_TRUE(smoothCorrelation > 0.8);
  ITK_TEST_EXPECT_TRUE(std::abs(whiteCorrelation) < 0.05);

  std::cout << "Test finished." << std::endl;
  return EXIT_SUCCESS;
}
