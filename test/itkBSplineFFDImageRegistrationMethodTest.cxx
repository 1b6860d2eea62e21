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
#include "itkImageRegionIteratorWithIndex.h"
#include "itkMeanSquaresImageToImageMetricv4.h"
#include "itkRegularizedImageToImageMetricv4.h"
#include "itkBSplineTransformInitializer.h"
#include "itkTestingMacros.h"
#include <chrono>
#include <limits>
#include <cmath>

namespace
{
constexpr unsigned int Dimension = 3;
using ImageType = itk::Image<float, Dimension>;
using RegistrationType = itk::BSplineFFDImageRegistrationMethod<ImageType>;
using PointType = itk::Point<double, Dimension>;

/** A smooth ellipsoidal blob (values in [0, 1]) centred at centre + shift, on a 32^3 grid of 1 mm voxels. */
ImageType::Pointer
MakeBlob(const itk::Vector<double, Dimension> & shift)
{
  auto                image = ImageType::New();
  ImageType::SizeType size;
  size.Fill(32);
  image->SetRegions(size);
  image->Allocate();
  itk::ImageRegionIteratorWithIndex<ImageType> it(image, image->GetLargestPossibleRegion());
  for (; !it.IsAtEnd(); ++it)
  {
    PointType point;
    image->TransformIndexToPhysicalPoint(it.GetIndex(), point);
    const double dx = (point[0] - 15.5 - shift[0]) / 9.0;
    const double dy = (point[1] - 15.5 - shift[1]) / 6.5;
    const double dz = (point[2] - 15.5 - shift[2]) / 7.0;
    const double r = std::sqrt(dx * dx + dy * dy + dz * dz);
    it.Set(static_cast<float>(0.5 - 0.5 * std::tanh((r - 1.0) * 4.0)));
  }
  return image;
}

/** Mean |T(x) - (x + shift)| over grid points near the blob's surface. */
double
MeanErrorNearSurface(const RegistrationType::TransformType & transform, const itk::Vector<double, Dimension> & shift)
{
  double       sum = 0.0;
  unsigned int count = 0;
  for (double x = 5.0; x <= 26.0; x += 1.5)
  {
    for (double y = 5.0; y <= 26.0; y += 1.5)
    {
      for (double z = 5.0; z <= 26.0; z += 1.5)
      {
        const double dx = (x - 15.5) / 9.0;
        const double dy = (y - 15.5) / 6.5;
        const double dz = (z - 15.5) / 7.0;
        const double r = std::sqrt(dx * dx + dy * dy + dz * dz);
        if (std::abs(r - 1.0) > 0.15)
        {
          continue;
        }
        PointType point;
        point[0] = x;
        point[1] = y;
        point[2] = z;
        sum += (transform.TransformPoint(point) - (point + shift)).GetNorm();
        ++count;
      }
    }
  }
  return sum / count;
}

/** The penalty's contribution to the regularized metric's derivative equals minus the finite-difference gradient
 * of its contribution to the value. */
int
CheckRegularizedMetricDerivative(const ImageType * fixed, const ImageType * moving)
{
  using PlainMetricType = itk::MeanSquaresImageToImageMetricv4<ImageType, ImageType>;
  using MetricType = itk::RegularizedImageToImageMetricv4<PlainMetricType>;
  using BSplineType = RegistrationType::BSplineTransformType;
  auto                      transform = BSplineType::New();
  auto                      initializer = itk::BSplineTransformInitializer<BSplineType, ImageType>::New();
  BSplineType::MeshSizeType mesh;
  mesh.Fill(3);
  initializer->SetTransform(transform);
  initializer->SetImage(fixed);
  initializer->SetTransformDomainMeshSize(mesh);
  initializer->InitializeTransform();
  BSplineType::ParametersType parameters(transform->GetNumberOfParameters());
  for (unsigned int i = 0; i < parameters.GetSize(); ++i)
  {
    parameters[i] = 3.0 * std::sin(0.7 * i);
  }
  transform->SetParameters(parameters);

  auto plain = PlainMetricType::New();
  auto regularized = MetricType::New();
  ITK_EXERCISE_BASIC_OBJECT_METHODS(regularized, RegularizedImageToImageMetricv4, MeanSquaresImageToImageMetricv4);
  regularized->GetModifiablePenalty()->SetBendingEnergyWeight(0.7);
  regularized->GetModifiablePenalty()->SetFoldingPenaltyWeight(5.0);
  regularized->GetModifiablePenalty()->SetFoldingThreshold(0.9);
  for (PlainMetricType * metric :
       { static_cast<PlainMetricType *>(plain), static_cast<PlainMetricType *>(regularized) })
  {
    metric->SetFixedImage(fixed);
    metric->SetMovingImage(moving);
    metric->SetMovingTransform(transform);
    metric->Initialize();
  }
  PlainMetricType::MeasureType    plainValue, regularizedValue;
  PlainMetricType::DerivativeType plainDerivative, regularizedDerivative;
  plain->GetValueAndDerivative(plainValue, plainDerivative);
  regularized->GetValueAndDerivative(regularizedValue, regularizedDerivative);
  ITK_TEST_EXPECT_TRUE(regularized->GetLastPenaltyValue() > 0.0);
  ITK_TEST_EXPECT_TRUE(
    itk::Math::FloatAlmostEqual(regularizedValue - plainValue, regularized->GetLastPenaltyValue(), 4, 1e-9));
  ITK_TEST_EXPECT_TRUE(itk::Math::FloatAlmostEqual(regularized->GetValue(), regularizedValue, 4, 1e-9));

  const double step = 1e-4;
  int          status = EXIT_SUCCESS;
  for (unsigned int i = 0; i < parameters.GetSize(); i += 17)
  {
    auto shifted = parameters;
    shifted[i] += step;
    transform->SetParameters(shifted);
    const double plus = regularized->GetValue() - plain->GetValue();
    shifted[i] = parameters[i] - step;
    transform->SetParameters(shifted);
    const double minus = regularized->GetValue() - plain->GetValue();
    const double numeric = -(plus - minus) / (2.0 * step);
    const double analytic = regularizedDerivative[i] - plainDerivative[i];
    if (std::abs(numeric - analytic) > 1e-4 * std::max(1.0, std::abs(numeric)))
    {
      std::cerr << "Penalty derivative mismatch at parameter " << i << ": analytic " << analytic << ", numeric "
                << numeric << std::endl;
      status = EXIT_FAILURE;
    }
  }
  transform->SetParameters(parameters);
  return status;
}
} // namespace

int
itkBSplineFFDImageRegistrationMethodTest(int argc, char * argv[])
{
  if (argc != 1)
  {
    std::cerr << "Usage: " << itkNameOfTestExecutableMacro(argv) << std::endl;
    return EXIT_FAILURE;
  }
  itk::Vector<double, Dimension> noShift;
  noShift.Fill(0.0);
  itk::Vector<double, Dimension> shift;
  shift[0] = 2.0;
  shift[1] = -1.5;
  shift[2] = 1.0;
  const auto fixed = MakeBlob(noShift);
  const auto moving = MakeBlob(shift);

  auto       clock = std::chrono::steady_clock::now();
  const auto elapsed = [&clock]() {
    const auto   now = std::chrono::steady_clock::now();
    const double seconds = std::chrono::duration<double>(now - clock).count();
    clock = now;
    return seconds;
  };
  int status = CheckRegularizedMetricDerivative(fixed, moving);
  std::cout << "Derivative check: " << elapsed() << " s" << std::endl;

  auto registration = RegistrationType::New();
  ITK_EXERCISE_BASIC_OBJECT_METHODS(
    registration, BSplineFFDImageRegistrationMethod, BSplineImageRegistrationMethodBase);
  ITK_TEST_SET_GET_VALUE(20u, registration->GetNumberOfControlPointsPerAxis());
  ITK_TEST_SET_GET_VALUE(1u, registration->GetNumberOfLevels());
  ITK_TEST_SET_GET_BOOLEAN(registration, UseAffineStage, false);
  ITK_TEST_SET_GET_BOOLEAN(registration, UseMovingImageGradientFilter, true);

  // Bad input: no moving image; too small an image for the number of levels.
  registration->SetFixedImage(fixed);
  ITK_TRY_EXPECT_EXCEPTION(registration->Update());
  registration->SetMovingImage(moving);
  registration->SetNumberOfLevels(6);
  ITK_TRY_EXPECT_EXCEPTION(registration->Update());
  // Grid and levels out of range are refused (BSplineImageRegistrationMethodBase), not clamped.
  registration->SetNumberOfLevels(1);
  registration->SetNumberOfControlPointsPerAxis(3);
  ITK_TRY_EXPECT_EXCEPTION(registration->Update());
  registration->SetNumberOfControlPointsPerAxis(1001);
  ITK_TRY_EXPECT_EXCEPTION(registration->Update());
  registration->SetNumberOfControlPointsPerAxis(6);
  registration->SetNumberOfLevels(0);
  ITK_TRY_EXPECT_EXCEPTION(registration->Update());
  registration->SetNumberOfLevels(9);
  ITK_TRY_EXPECT_EXCEPTION(registration->Update());

  // Recovery of a smooth displacement, on mean squares and on Mattes MI, with the moving image's gradient from
  // ITK's gradient filter and from central differences at the samples.
  const double errorBefore = shift.GetNorm();
  for (const auto metric : { itk::FFDShapeMatchingEnums::ImageMetric::MeanSquares,
                             itk::FFDShapeMatchingEnums::ImageMetric::MattesMutualInformation })
  {
    for (const bool filtered : { true, false })
    {
      registration->SetUseMovingImageGradientFilter(filtered);
      registration->SetNumberOfLevels(2);
      registration->SetNumberOfControlPointsPerAxis(6);
      registration->SetNumberOfIterations(40);
      registration->SetMetric(metric);
      registration->SetBendingEnergyWeight(0.0);
      ITK_TRY_EXPECT_NO_EXCEPTION(registration->Update());
      const double errorAfter = MeanErrorNearSurface(*registration->GetTransform(), shift);
      std::cout << metric << (filtered ? " (gradient filter)" : " (central differences)")
                << ": mean error near the surface " << errorBefore << " -> " << errorAfter << " mm after "
                << registration->GetMetricValues().size() << " iterations, " << elapsed() << " s\n"
                << registration->GetStopConditionDescription();
      ITK_TEST_EXPECT_TRUE(errorAfter < 0.4 * errorBefore);
      ITK_TEST_EXPECT_TRUE(!registration->GetMetricValues().empty());
      ITK_TEST_EXPECT_TRUE(registration->GetMetricValues().back() < registration->GetMetricValues().front());
    }
  }
  registration->UseMovingImageGradientFilterOn();

  // A heavy bending-energy weight keeps the deformation near the identity.
  registration->SetMetric(itk::FFDShapeMatchingEnums::ImageMetric::MeanSquares);
  registration->SetBendingEnergyWeight(1e6);
  registration->SetNumberOfIterations(15);
  ITK_TRY_EXPECT_NO_EXCEPTION(registration->Update());
  const double stiffError = MeanErrorNearSurface(*registration->GetTransform(), shift);
  std::cout << "With a heavy bending weight: " << stiffError << " mm (no motion: " << errorBefore << " mm), "
            << registration->GetMetricValues().size() << " iterations, " << elapsed() << " s\n";
  const auto & stiffParameters = registration->GetTransform()->GetParameters();
  double       largest = 0.0;
  for (unsigned int i = 0; i < stiffParameters.GetSize(); ++i)
  {
    largest = std::max(largest, std::abs(stiffParameters[i]));
  }
  ITK_TEST_EXPECT_TRUE(largest < 0.1 * errorBefore);

  // A run-time limit that is over at once: a few iterations per level (LBFGSB reports its start and its first
  // step before it can stop), the final grid, the limit reported.
  registration->SetBendingEnergyWeight(0.0);
  registration->SetNumberOfIterations(40);
  registration->SetMaximumRunTime(1e-9);
  ITK_TEST_SET_GET_VALUE(1e-9, registration->GetMaximumRunTime());
  ITK_TRY_EXPECT_NO_EXCEPTION(registration->Update());
  std::cout << "With a run-time limit: " << registration->GetMetricValues().size() << " iterations\n"
            << registration->GetStopConditionDescription();
  ITK_TEST_EXPECT_TRUE(registration->GetTimeLimitReached());
  ITK_TEST_EXPECT_TRUE(registration->GetMetricValues().size() <= 3u * 2u);
  ITK_TEST_EXPECT_EQUAL(registration->GetTransform()->GetNumberOfParameters(), 3u * 6u * 6u * 6u);
  ITK_TEST_EXPECT_TRUE(registration->GetStopConditionDescription().find("run-time limit") != std::string::npos);
  registration->SetMaximumRunTime(0.0);
  registration->SetNumberOfIterations(5);
  ITK_TRY_EXPECT_NO_EXCEPTION(registration->Update());
  ITK_TEST_EXPECT_TRUE(!registration->GetTimeLimitReached());

  // Broken input (a fixed image with NaN voxels) ends in an exception, not in a transform.
  auto broken = ImageType::New();
  broken->CopyInformation(fixed);
  broken->SetRegions(fixed->GetLargestPossibleRegion());
  broken->Allocate();
  for (itk::SizeValueType i = 0; i < fixed->GetLargestPossibleRegion().GetNumberOfPixels(); ++i)
  {
    broken->GetBufferPointer()[i] = i % 7 == 0 ? std::numeric_limits<float>::quiet_NaN() : fixed->GetBufferPointer()[i];
  }
  registration->SetFixedImage(broken);
  ITK_TRY_EXPECT_EXCEPTION(registration->Update());
  registration->SetFixedImage(fixed);

  // The transform output is a pipeline output: it carries the transform.
  ITK_TEST_EXPECT_TRUE(registration->GetTransformOutput()->Get() == registration->GetTransform());
  return status;
}
