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
// TruncatedGaussianImageFilter against the direct triple sum of the sampled, truncated, normalized Gaussian with
// the edge voxels repeated (anisotropic spacing, a different sigma per axis, an axis left alone), the same image
// with 1 and 3 work units, its bad parameters; TruncatedGaussianImageRegistrationMethodv4 hands the metric the
// filter's images at a smoothed level and the input images at an unsmoothed one, and, Off, ITK's own.

#include "itkTruncatedGaussianImageFilter.h"
#include "itkTruncatedGaussianImageRegistrationMethodv4.h"

#include "itkBSplineTransform.h"
#include "itkBSplineTransformInitializer.h"
#include "itkGradientDescentOptimizerv4.h"
#include "itkMeanSquaresImageToImageMetricv4.h"
#include "itkTestingMacros.h"

#include <cmath>
#include <cstring>
#include <random>
#include <vector>

namespace
{
using ImageType = itk::Image<float, 3>;
using FilterType = itk::TruncatedGaussianImageFilter<ImageType>;

ImageType::Pointer
MakeRandomImage(const ImageType::SizeType & size, const ImageType::SpacingType & spacing, unsigned int seed)
{
  auto image = ImageType::New();
  image->SetRegions(size);
  image->SetSpacing(spacing);
  image->Allocate();
  std::mt19937                          generator(seed);
  std::uniform_real_distribution<float> uniform(-1.0f, 3.0f);
  for (size_t i = 0; i < image->GetLargestPossibleRegion().GetNumberOfPixels(); ++i)
  {
    image->GetBufferPointer()[i] = uniform(generator);
  }
  return image;
}

// The direct sum over the whole 3-D kernel, in double.
std::vector<double>
BruteForce(const ImageType * image, const FilterType::SigmaArrayType & sigma, double widthInSigmas)
{
  const auto          size = image->GetLargestPossibleRegion().GetSize();
  std::vector<double> weights[3];
  long                radius[3];
  for (unsigned int d = 0; d < 3; ++d)
  {
    const double spacing = image->GetSpacing()[d];
    radius[d] = sigma[d] == 0.0 ? 0 : static_cast<long>(std::ceil(widthInSigmas * sigma[d] / spacing));
    double sum = 0.0;
    for (long k = -radius[d]; k <= radius[d]; ++k)
    {
      const double x = sigma[d] == 0.0 ? 0.0 : static_cast<double>(k) * spacing / sigma[d];
      weights[d].push_back(std::exp(-0.5 * x * x));
      sum += weights[d].back();
    }
    for (double & w : weights[d])
    {
      w /= sum;
    }
  }
  const auto           clamp = [](long i, long n) { return std::min(std::max(i, 0L), n - 1); };
  std::vector<double>  result;
  ImageType::IndexType index;
  for (long z = 0; z < static_cast<long>(size[2]); ++z)
  {
    for (long y = 0; y < static_cast<long>(size[1]); ++y)
    {
      for (long x = 0; x < static_cast<long>(size[0]); ++x)
      {
        double sum = 0.0;
        for (long c = -radius[2]; c <= radius[2]; ++c)
        {
          for (long b = -radius[1]; b <= radius[1]; ++b)
          {
            for (long a = -radius[0]; a <= radius[0]; ++a)
            {
              index[0] = clamp(x + a, static_cast<long>(size[0]));
              index[1] = clamp(y + b, static_cast<long>(size[1]));
              index[2] = clamp(z + c, static_cast<long>(size[2]));
              sum += weights[0][a + radius[0]] * weights[1][b + radius[1]] * weights[2][c + radius[2]] *
                     static_cast<double>(image->GetPixel(index));
            }
          }
        }
        result.push_back(sum);
      }
    }
  }
  return result;
}

ImageType::Pointer
Smooth(const ImageType * image, const FilterType::SigmaArrayType & sigma, unsigned int workUnits)
{
  auto filter = FilterType::New();
  filter->SetInput(image);
  filter->SetSigmaArray(sigma);
  filter->SetNumberOfWorkUnits(workUnits);
  filter->Update();
  ImageType::Pointer output = filter->GetOutput();
  output->DisconnectPipeline();
  return output;
}

int
TestFilter()
{
  int        status = EXIT_SUCCESS;
  const auto check = [&status](bool ok, const char * what) {
    if (!ok)
    {
      std::cerr << "FAILED: " << what << std::endl;
      status = EXIT_FAILURE;
    }
  };
  ImageType::SizeType    size = { { 13, 9, 11 } };
  ImageType::SpacingType spacing;
  spacing[0] = 1.0;
  spacing[1] = 0.7;
  spacing[2] = 1.3;
  const auto image = MakeRandomImage(size, spacing, 7);

  auto filter = FilterType::New();
  ITK_EXERCISE_BASIC_OBJECT_METHODS(filter, TruncatedGaussianImageFilter, ImageToImageFilter);
  ITK_TEST_EXPECT_EQUAL(filter->GetKernelWidthInSigmas(), 3.0);
  ITK_TEST_EXPECT_EQUAL(filter->GetSigmaArray()[2], 1.0);

  // Sigmas of one voxel, of several, and an axis left alone (sigma 0): every output voxel within 1e-5 of the sum.
  FilterType::SigmaArrayType sigmas[5];
  sigmas[0].Fill(1.0);
  sigmas[1][0] = 2.1;
  sigmas[1][1] = 0.5;
  sigmas[1][2] = 1.7;
  sigmas[2][0] = 1.2;
  sigmas[2][1] = 0.0;
  sigmas[2][2] = 0.9;
  sigmas[3].Fill(0.0); // one axis smoothed (the output written by one pass), then none (a copy)
  sigmas[3][2] = 1.3;
  sigmas[4].Fill(0.0);
  for (const auto & sigma : sigmas)
  {
    const auto   smoothed = Smooth(image, sigma, 1);
    const auto   threaded = Smooth(image, sigma, 3);
    const auto   expected = BruteForce(image, sigma, 3.0);
    double       largest = 0.0;
    const size_t count = expected.size();
    for (size_t i = 0; i < count; ++i)
    {
      largest = std::max(largest, std::abs(static_cast<double>(smoothed->GetBufferPointer()[i]) - expected[i]));
    }
    const bool same =
      std::memcmp(smoothed->GetBufferPointer(), threaded->GetBufferPointer(), count * sizeof(float)) == 0;
    std::cout << "sigma " << sigma << ": largest difference from the direct sum " << largest
              << (same ? ", 1 and 3 work units identical" : ", 1 and 3 work units DIFFER") << std::endl;
    check(largest < 1e-5, "the direct sum");
    check(same, "the same image whatever the work units");
    check(smoothed->GetSpacing() == image->GetSpacing() && smoothed->GetOrigin() == image->GetOrigin(),
          "the input's geometry");
  }

  // Integer pixels, smoothed in float and cast back: the float image's result, truncated.
  {
    using ShortImageType = itk::Image<short, 3>;
    auto shorts = ShortImageType::New();
    shorts->CopyInformation(image);
    shorts->SetRegions(image->GetLargestPossibleRegion());
    shorts->Allocate();
    auto         floats = MakeRandomImage(size, spacing, 5);
    const size_t count = image->GetLargestPossibleRegion().GetNumberOfPixels();
    for (size_t i = 0; i < count; ++i)
    {
      floats->GetBufferPointer()[i] = std::round(100.0f * floats->GetBufferPointer()[i]);
      shorts->GetBufferPointer()[i] = static_cast<short>(floats->GetBufferPointer()[i]);
    }
    auto shortFilter = itk::TruncatedGaussianImageFilter<ShortImageType>::New();
    shortFilter->SetInput(shorts);
    shortFilter->SetSigmaArray(sigmas[1]);
    shortFilter->Update();
    const auto floatSmoothed = Smooth(floats, sigmas[1], 1);
    bool       truncated = true;
    for (size_t i = 0; i < count; ++i)
    {
      truncated = truncated && shortFilter->GetOutput()->GetBufferPointer()[i] ==
                                 static_cast<short>(floatSmoothed->GetBufferPointer()[i]);
    }
    check(truncated, "short pixels: the float result, truncated");
  }

  // The kernel: normalized, symmetric, radius ceil(3 sigma / spacing), and a single 1 for sigma 0.
  filter->SetInput(image);
  filter->SetSigmaArray(sigmas[2]);
  filter->UpdateOutputInformation();
  const auto kernel = filter->ComputeKernel(0);
  double     sum = 0.0;
  for (double w : kernel)
  {
    sum += w;
  }
  check(kernel.size() == 2 * 4 + 1, "radius ceil(3 * 1.2 / 1)");
  check(std::abs(sum - 1.0) < 1e-14 && kernel.front() == kernel.back(), "a normalized, symmetric kernel");
  check(filter->ComputeKernel(1).size() == 1 && filter->ComputeKernel(1)[0] == 1.0, "sigma 0 leaves the axis");

  // A constant image stays constant (within float rounding), so do the faces.
  auto constant = MakeRandomImage(size, spacing, 1);
  constant->FillBuffer(2.5f);
  const auto flat = Smooth(constant, sigmas[1], 2);
  double     flatError = 0.0;
  for (size_t i = 0; i < constant->GetLargestPossibleRegion().GetNumberOfPixels(); ++i)
  {
    flatError = std::max(flatError, std::abs(static_cast<double>(flat->GetBufferPointer()[i]) - 2.5));
  }
  check(flatError < 1e-5, "a constant image stays constant");

  // Bad parameters.
  FilterType::SigmaArrayType negative;
  negative.Fill(1.0);
  negative[1] = -0.5;
  filter->SetSigmaArray(negative);
  ITK_TRY_EXPECT_EXCEPTION(filter->Update());
  filter->SetSigma(std::nan(""));
  ITK_TRY_EXPECT_EXCEPTION(filter->Update());
  filter->SetSigma(1.0);
  filter->SetKernelWidthInSigmas(0.0);
  ITK_TRY_EXPECT_EXCEPTION(filter->Update());
  filter->SetKernelWidthInSigmas(3.0);
  ITK_TRY_EXPECT_NO_EXCEPTION(filter->Update());
  return status;
}

// Records the metric's images at the start of each level.
using TransformType = itk::BSplineTransform<double, 3, 3>;
using RegistrationType = itk::TruncatedGaussianImageRegistrationMethodv4<ImageType, ImageType, TransformType>;
using MetricType = itk::MeanSquaresImageToImageMetricv4<ImageType, ImageType>;

std::vector<ImageType::ConstPointer>
RunTwoLevels(const ImageType * fixed, const ImageType * moving, bool truncated)
{
  auto                        transform = TransformType::New();
  auto                        initializer = itk::BSplineTransformInitializer<TransformType, ImageType>::New();
  TransformType::MeshSizeType meshSize;
  meshSize.Fill(2);
  initializer->SetTransform(transform);
  initializer->SetImage(fixed);
  initializer->SetTransformDomainMeshSize(meshSize);
  initializer->InitializeTransform();
  auto metric = MetricType::New();
  auto optimizer = itk::GradientDescentOptimizerv4::New();
  optimizer->SetNumberOfIterations(1);
  optimizer->SetLearningRate(0.1);
  auto registration = RegistrationType::New();
  registration->SetFixedImage(fixed);
  registration->SetMovingImage(moving);
  registration->SetInitialTransform(transform);
  registration->InPlaceOn();
  registration->SetMetric(metric);
  registration->SetOptimizer(optimizer);
  registration->SetNumberOfLevels(2);
  RegistrationType::ShrinkFactorsArrayType shrink(2);
  shrink[0] = 2;
  shrink[1] = 1;
  registration->SetShrinkFactorsPerLevel(shrink);
  RegistrationType::SmoothingSigmasArrayType sigmas(2);
  sigmas[0] = 1.0;
  sigmas[1] = 0.0;
  registration->SetSmoothingSigmasPerLevel(sigmas);
  registration->SmoothingSigmasAreSpecifiedInPhysicalUnitsOff();
  registration->SetUseTruncatedGaussian(truncated);
  // The optimizer starts each level after the metric is initialized on the level's images; the pointers keep them.
  std::vector<ImageType::ConstPointer> images;
  optimizer->AddObserver(itk::StartEvent(), [&](const itk::EventObject &) {
    images.emplace_back(metric->GetFixedImage());
    images.emplace_back(metric->GetMovingImage());
  });
  registration->Update();
  return images;
}

int
TestRegistration()
{
  int                    status = EXIT_SUCCESS;
  ImageType::SizeType    size = { { 12, 10, 9 } };
  ImageType::SpacingType spacing;
  spacing.Fill(1.0);
  spacing[2] = 1.5;
  const auto fixed = MakeRandomImage(size, spacing, 3);
  const auto moving = MakeRandomImage(size, spacing, 4);

  auto registration = RegistrationType::New();
  ITK_EXERCISE_BASIC_OBJECT_METHODS(
    registration, TruncatedGaussianImageRegistrationMethodv4, ImageRegistrationMethodv4);
  ITK_TEST_EXPECT_TRUE(!registration->GetUseTruncatedGaussian());

  // The smoothed level's images: the filter's (sigma one voxel, in physical units per axis), bit for bit; the last
  // level's: the inputs themselves.
  FilterType::SigmaArrayType voxelSigma;
  for (unsigned int d = 0; d < 3; ++d)
  {
    voxelSigma[d] = spacing[d];
  }
  const auto expectedFixed = Smooth(fixed, voxelSigma, 1);
  const auto expectedMoving = Smooth(moving, voxelSigma, 1);
  const auto count = fixed->GetLargestPossibleRegion().GetNumberOfPixels() * sizeof(float);
  auto       truncated = RunTwoLevels(fixed, moving, true);
  if (truncated.size() != 4)
  {
    std::cerr << "FAILED: two levels expected" << std::endl;
    return EXIT_FAILURE;
  }
  const bool levelOneFixed =
    std::memcmp(truncated[0]->GetBufferPointer(), expectedFixed->GetBufferPointer(), count) == 0;
  const bool levelOneMoving =
    std::memcmp(truncated[1]->GetBufferPointer(), expectedMoving->GetBufferPointer(), count) == 0;
  std::cout << "On: level 1 images are the filter's: " << levelOneFixed << ' ' << levelOneMoving
            << "; level 2 images are the inputs: " << (truncated[2] == fixed.GetPointer()) << ' '
            << (truncated[3] == moving.GetPointer()) << std::endl;
  if (!levelOneFixed || !levelOneMoving || truncated[2] != fixed.GetPointer() || truncated[3] != moving.GetPointer())
  {
    status = EXIT_FAILURE;
  }
  // Off: ITK's recursive Gaussian, a different image.
  auto       recursive = RunTwoLevels(fixed, moving, false);
  const bool differs = recursive.size() == 4 && recursive[1] != moving.GetPointer() &&
                       std::memcmp(recursive[1]->GetBufferPointer(), expectedMoving->GetBufferPointer(), count) != 0;
  std::cout << "Off: level 1's moving image is ITK's recursive Gaussian: " << differs << std::endl;
  if (!differs)
  {
    status = EXIT_FAILURE;
  }
  return status;
}
} // namespace

int
itkTruncatedGaussianImageFilterTest(int, char *[])
{
  const int  filterStatus = TestFilter();
  const int  registrationStatus = TestRegistration();
  const bool passed = filterStatus == EXIT_SUCCESS && registrationStatus == EXIT_SUCCESS;
  std::cout << (passed ? "Test finished." : "Test FAILED.") << std::endl;
  return passed ? EXIT_SUCCESS : EXIT_FAILURE;
}
