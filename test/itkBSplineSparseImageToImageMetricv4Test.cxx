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

#include "itkAffineTransform.h"
#include "itkBSplineSparseImageToImageMetricv4.h"
#include "itkCompositeTransform.h"
#include "itkGradientDescentOptimizerv4.h"
#include "itkImageMaskSpatialObject.h"
#include "itkImageRegistrationMethodv4.h"
#include "itkImageRegionIteratorWithIndex.h"
#include "itkMattesMutualInformationImageToImageMetricv4.h"
#include "itkMeanSquaresImageToImageMetricv4.h"
#include "itkMersenneTwisterRandomVariateGenerator.h"
#include "itkTestingMacros.h"
#include "itkTimeProbe.h"

#include <algorithm>
#include <cmath>
#include <iostream>
#include <sstream>
#include <string>

namespace
{
constexpr unsigned int Dimension = 3;
using ImageType = itk::Image<float, Dimension>;
using MetricType = itk::BSplineSparseImageToImageMetricv4<ImageType, ImageType>;
using MeasureEnum = MetricType::MeasureEnum;
using BSplineType = itk::BSplineTransform<double, Dimension, 3>;
using CompositeType = itk::CompositeTransform<double, Dimension>;
using TransformType = itk::Transform<double, Dimension, Dimension>;
using MaskImageType = itk::Image<unsigned char, Dimension>;
using MaskType = itk::ImageMaskSpatialObject<Dimension>;
using ImageMetricType = itk::ImageToImageMetricv4<ImageType, ImageType>;
using MattesType = itk::MattesMutualInformationImageToImageMetricv4<ImageType, ImageType>;
using MeanSquaresType = itk::MeanSquaresImageToImageMetricv4<ImageType, ImageType>;
using PointSetType = ImageMetricType::FixedSampledPointSetType;

/** Smooth blobs on a size^3 grid; shift moves their centres (in mm). */
ImageType::Pointer
MakeBlobImage(unsigned int size, double shift, double amplitudeScale)
{
  auto                   image = ImageType::New();
  ImageType::RegionType  region;
  ImageType::SizeType    imageSize;
  ImageType::SpacingType spacing;
  ImageType::PointType   origin;
  imageSize.Fill(size);
  region.SetSize(imageSize);
  spacing[0] = 1.0;
  spacing[1] = 1.1;
  spacing[2] = 0.9;
  origin[0] = -3.0;
  origin[1] = 5.0;
  origin[2] = 2.0;
  image->SetRegions(region);
  image->SetSpacing(spacing);
  image->SetOrigin(origin);
  image->Allocate();

  const double                                 blobs[4][5] = { { 0.3, 0.35, 0.4, 0.18, 100.0 },
                                                               { 0.65, 0.6, 0.55, 0.15, 70.0 },
                                                               { 0.4, 0.7, 0.65, 0.12, 50.0 },
                                                               { 0.7, 0.3, 0.3, 0.1, 80.0 } };
  itk::ImageRegionIteratorWithIndex<ImageType> it(image, region);
  for (; !it.IsAtEnd(); ++it)
  {
    ImageType::PointType point;
    image->TransformIndexToPhysicalPoint(it.GetIndex(), point);
    double value = 10.0;
    for (const auto & blob : blobs)
    {
      double squaredDistance = 0.0;
      for (unsigned int d = 0; d < Dimension; ++d)
      {
        const double extent = spacing[d] * (size - 1);
        const double centre = origin[d] + blob[d] * extent + shift;
        const double sigma = blob[3] * extent;
        squaredDistance += (point[d] - centre) * (point[d] - centre) / (sigma * sigma);
      }
      value += amplitudeScale * blob[4] * std::exp(-0.5 * squaredDistance);
    }
    it.Set(static_cast<float>(value));
  }
  return image;
}

/** A cubic B-spline over the image domain with random coefficients (seeded). */
BSplineType::Pointer
MakeBSpline(const ImageType * image, unsigned int meshSize, double amplitude, unsigned int seed)
{
  auto                                bspline = BSplineType::New();
  BSplineType::PhysicalDimensionsType dimensions;
  BSplineType::MeshSizeType           mesh;
  for (unsigned int d = 0; d < Dimension; ++d)
  {
    dimensions[d] = image->GetSpacing()[d] * (image->GetLargestPossibleRegion().GetSize()[d] - 1);
  }
  mesh.Fill(meshSize);
  bspline->SetTransformDomainOrigin(image->GetOrigin());
  bspline->SetTransformDomainPhysicalDimensions(dimensions);
  bspline->SetTransformDomainMeshSize(mesh);
  bspline->SetTransformDomainDirection(image->GetDirection());

  auto generator = itk::Statistics::MersenneTwisterRandomVariateGenerator::New();
  generator->SetSeed(seed);
  BSplineType::ParametersType parameters(bspline->GetNumberOfParameters());
  for (unsigned int p = 0; p < parameters.Size(); ++p)
  {
    parameters[p] = generator->GetUniformVariate(-amplitude, amplitude);
  }
  bspline->SetParametersByValue(parameters);
  return bspline;
}

/** A binary sphere mask covering the centre of the image. */
MaskType::Pointer
MakeMask(const ImageType * image)
{
  auto mask = MaskImageType::New();
  mask->CopyInformation(image);
  mask->SetRegions(image->GetLargestPossibleRegion());
  mask->Allocate();
  const auto                                       size = image->GetLargestPossibleRegion().GetSize();
  itk::ImageRegionIteratorWithIndex<MaskImageType> it(mask, mask->GetLargestPossibleRegion());
  for (; !it.IsAtEnd(); ++it)
  {
    double squaredRadius = 0.0;
    for (unsigned int d = 0; d < Dimension; ++d)
    {
      const double offset = (it.GetIndex()[d] - 0.5 * (size[d] - 1)) / (0.4 * size[d]);
      squaredRadius += offset * offset;
    }
    it.Set(squaredRadius <= 1.0 ? 1 : 0);
  }
  auto spatialObject = MaskType::New();
  spatialObject->SetImage(mask);
  spatialObject->Update();
  return spatialObject;
}

/** Same inputs and settings for a metric under test and an ITK reference metric. */
void
Configure(ImageMetricType * metric,
          const ImageType * fixedImage,
          const ImageType * movingImage,
          TransformType *   transform,
          const MaskType *  mask,
          PointSetType *    samples,
          bool              useGradientFilter,
          const MaskType *  movingMask = nullptr)
{
  metric->SetMovingImageMask(movingMask);
  metric->SetFixedImage(fixedImage);
  metric->SetMovingImage(movingImage);
  metric->SetMovingTransform(transform);
  metric->SetFixedImageMask(mask);
  metric->SetUseMovingImageGradientFilter(useGradientFilter);
  if (samples != nullptr)
  {
    metric->SetVirtualSampledPointSet(samples);
    metric->SetUseSampledPointSet(true);
    metric->SetUseVirtualSampledPointSet(true);
  }
}

/** Relative agreement of value (1e-6) and derivative (1e-4 of the largest reference component). */
bool
CompareWithReference(const std::string & name, MetricType * metric, ImageMetricType * reference)
{
  MetricType::MeasureType    value = 0.0;
  MetricType::MeasureType    referenceValue = 0.0;
  MetricType::DerivativeType derivative;
  MetricType::DerivativeType referenceDerivative;
  metric->GetValueAndDerivative(value, derivative);
  reference->GetValueAndDerivative(referenceValue, referenceDerivative);

  double maxReference = 0.0;
  double maxDifference = 0.0;
  for (unsigned int p = 0; p < referenceDerivative.Size(); ++p)
  {
    maxReference = std::max(maxReference, std::abs(referenceDerivative[p]));
    maxDifference = std::max(maxDifference, std::abs(referenceDerivative[p] - derivative[p]));
  }
  const double valueError = std::abs(value - referenceValue) / std::max(std::abs(referenceValue), 1e-300);
  const double derivativeError = maxDifference / std::max(maxReference, 1e-300);
  std::cout << name << ": value " << value << " (ITK " << referenceValue << ", rel. error " << valueError
            << "), derivative rel. error " << derivativeError << " (max |ITK derivative| " << maxReference
            << "), valid points " << metric->GetNumberOfValidPoints() << " (ITK " << reference->GetNumberOfValidPoints()
            << ")" << std::endl;

  bool ok = derivative.Size() == referenceDerivative.Size() && valueError <= 1e-6 && derivativeError <= 1e-4 &&
            maxReference > 0.0 && metric->GetNumberOfValidPoints() == reference->GetNumberOfValidPoints();
  // GetValue alone must give the same value.
  ok = ok && std::abs(metric->GetValue() - value) <= 1e-12 * std::abs(value);
  if (!ok)
  {
    std::cerr << "FAILED: " << name << std::endl;
  }
  return ok;
}

ImageMetricType::Pointer
MakeReference(MeasureEnum measure)
{
  if (measure == MeasureEnum::MeanSquares)
  {
    return MeanSquaresType::New().GetPointer();
  }
  auto mattes = MattesType::New();
  mattes->SetNumberOfHistogramBins(32);
  return mattes.GetPointer();
}

/** Derivative against central finite differences of GetValue for the largest components. */
bool
CheckFiniteDifferences(const std::string & name, MetricType * metric, BSplineType * bspline)
{
  MetricType::MeasureType    value = 0.0;
  MetricType::DerivativeType derivative;
  metric->GetValueAndDerivative(value, derivative);
  std::vector<unsigned int> order(derivative.Size());
  for (unsigned int p = 0; p < order.size(); ++p)
  {
    order[p] = p;
  }
  std::partial_sort(order.begin(), order.begin() + 5, order.end(), [&](unsigned int a, unsigned int b) {
    return std::abs(derivative[a]) > std::abs(derivative[b]);
  });
  const double                maxDerivative = std::abs(derivative[order[0]]);
  BSplineType::ParametersType parameters = bspline->GetParameters();
  constexpr double            step = 1e-3;
  bool                        ok = true;
  for (unsigned int k = 0; k < 5; ++k)
  {
    const unsigned int          p = order[k];
    BSplineType::ParametersType shifted = parameters;
    shifted[p] = parameters[p] + step;
    bspline->SetParametersByValue(shifted);
    const double above = metric->GetValue();
    shifted[p] = parameters[p] - step;
    bspline->SetParametersByValue(shifted);
    const double below = metric->GetValue();
    // The v4 derivative points downhill: it approximates -dValue/dp.
    const double finiteDifference = -(above - below) / (2.0 * step);
    const double error = std::abs(finiteDifference - derivative[p]) / maxDerivative;
    std::cout << name << ": parameter " << p << " derivative " << derivative[p] << ", finite difference "
              << finiteDifference << ", error " << error << std::endl;
    ok = ok && error <= 0.05;
  }
  bspline->SetParametersByValue(parameters);
  if (!ok)
  {
    std::cerr << "FAILED: " << name << " finite differences" << std::endl;
  }
  return ok;
}

/** Final parameters of a few gradient-descent iterations of ImageRegistrationMethodv4 driving a metric. */
BSplineType::ParametersType
RunRegistration(ImageMetricType * metric, const ImageType * fixedImage, const ImageType * movingImage, double rate)
{
  using RegistrationType = itk::ImageRegistrationMethodv4<ImageType, ImageType, BSplineType>;
  using OptimizerType = itk::GradientDescentOptimizerv4;
  auto initial = MakeBSpline(fixedImage, 3, 0.0, 1);
  auto optimizer = OptimizerType::New();
  optimizer->SetLearningRate(rate);
  optimizer->SetNumberOfIterations(5);
  optimizer->DoEstimateLearningRateOnceOff();
  optimizer->DoEstimateLearningRateAtEachIterationOff();
  optimizer->SetMinimumConvergenceValue(-1.0);
  auto registration = RegistrationType::New();
  registration->SetFixedImage(fixedImage);
  registration->SetMovingImage(movingImage);
  registration->SetMetric(metric);
  registration->SetOptimizer(optimizer);
  registration->SetInitialTransform(initial);
  registration->InPlaceOn();
  registration->SetNumberOfLevels(1);
  RegistrationType::ShrinkFactorsArrayType shrinkFactors(1);
  shrinkFactors[0] = 1;
  registration->SetShrinkFactorsPerLevel(shrinkFactors);
  RegistrationType::SmoothingSigmasArrayType sigmas(1);
  sigmas[0] = 0.0;
  registration->SetSmoothingSigmasPerLevel(sigmas);
  registration->SetMetricSamplingStrategy(RegistrationType::MetricSamplingStrategyEnum::REGULAR);
  registration->SetMetricSamplingPercentage(0.5);
  registration->MetricSamplingReinitializeSeed(17);
  registration->Update();
  std::cout << metric->GetNameOfClass() << " driven by ImageRegistrationMethodv4: " << optimizer->GetCurrentIteration()
            << " iterations, final value " << optimizer->GetCurrentMetricValue() << std::endl;
  return registration->GetTransform()->GetParameters();
}

/** The generic-dimension code path: value and derivative against ITK's metrics on 2-D images. */
bool
Check2D()
{
  using Image2DType = itk::Image<float, 2>;
  using Metric2DType = itk::BSplineSparseImageToImageMetricv4<Image2DType, Image2DType>;
  using BSpline2DType = itk::BSplineTransform<double, 2, 3>;
  const auto makeImage = [](double shift) {
    auto                    image = Image2DType::New();
    Image2DType::RegionType region;
    Image2DType::SizeType   size;
    size.Fill(32);
    region.SetSize(size);
    image->SetRegions(region);
    Image2DType::SpacingType spacing;
    spacing[0] = 1.0;
    spacing[1] = 1.3;
    image->SetSpacing(spacing);
    image->Allocate();
    itk::ImageRegionIteratorWithIndex<Image2DType> it(image, region);
    for (; !it.IsAtEnd(); ++it)
    {
      const double x = it.GetIndex()[0] - 14.0 - shift;
      const double y = it.GetIndex()[1] - 17.0;
      const double u = it.GetIndex()[0] - 22.0;
      const double v = it.GetIndex()[1] - 9.0 + shift;
      it.Set(static_cast<float>(10.0 + 100.0 * std::exp(-(x * x + y * y) / 40.0) +
                                60.0 * std::exp(-(u * u + v * v) / 20.0)));
    }
    return image;
  };
  const auto fixedImage = makeImage(0.0);
  const auto movingImage = makeImage(1.5);

  auto                                  bspline = BSpline2DType::New();
  BSpline2DType::PhysicalDimensionsType dimensions;
  BSpline2DType::MeshSizeType           mesh;
  for (unsigned int d = 0; d < 2; ++d)
  {
    dimensions[d] = fixedImage->GetSpacing()[d] * 31.0;
  }
  mesh.Fill(4);
  bspline->SetTransformDomainOrigin(fixedImage->GetOrigin());
  bspline->SetTransformDomainPhysicalDimensions(dimensions);
  bspline->SetTransformDomainMeshSize(mesh);
  auto generator = itk::Statistics::MersenneTwisterRandomVariateGenerator::New();
  generator->SetSeed(5);
  BSpline2DType::ParametersType parameters(bspline->GetNumberOfParameters());
  for (unsigned int p = 0; p < parameters.Size(); ++p)
  {
    parameters[p] = generator->GetUniformVariate(-1.5, 1.5);
  }
  bspline->SetParametersByValue(parameters);

  bool ok = true;
  for (const MeasureEnum measure : { MeasureEnum::MeanSquares, MeasureEnum::MattesMutualInformation })
  {
    using Reference2DType = itk::ImageToImageMetricv4<Image2DType, Image2DType>;
    Reference2DType::Pointer reference;
    if (measure == MeasureEnum::MeanSquares)
    {
      reference = itk::MeanSquaresImageToImageMetricv4<Image2DType, Image2DType>::New().GetPointer();
    }
    else
    {
      auto mattes = itk::MattesMutualInformationImageToImageMetricv4<Image2DType, Image2DType>::New();
      mattes->SetNumberOfHistogramBins(32);
      reference = mattes.GetPointer();
    }
    auto metric = Metric2DType::New();
    metric->SetMeasure(measure);
    for (Reference2DType * m : { static_cast<Reference2DType *>(metric), reference.GetPointer() })
    {
      m->SetFixedImage(fixedImage);
      m->SetMovingImage(movingImage);
      m->SetMovingTransform(bspline);
      m->SetUseMovingImageGradientFilter(false);
      m->Initialize();
    }
    Metric2DType::MeasureType    value = 0.0;
    Metric2DType::MeasureType    referenceValue = 0.0;
    Metric2DType::DerivativeType derivative;
    Metric2DType::DerivativeType referenceDerivative;
    metric->GetValueAndDerivative(value, derivative);
    reference->GetValueAndDerivative(referenceValue, referenceDerivative);
    double maxReference = 0.0;
    double maxDifference = 0.0;
    for (unsigned int p = 0; p < referenceDerivative.Size(); ++p)
    {
      maxReference = std::max(maxReference, std::abs(referenceDerivative[p]));
      maxDifference = std::max(maxDifference, std::abs(referenceDerivative[p] - derivative[p]));
    }
    const double valueError = std::abs(value - referenceValue) / std::abs(referenceValue);
    std::cout << "2-D " << measure << ": value " << value << " (ITK " << referenceValue << "), derivative rel. error "
              << maxDifference / maxReference << std::endl;
    ok = ok && valueError <= 1e-6 && maxReference > 0.0 && maxDifference <= 1e-4 * maxReference;
  }
  return ok;
}

/** Time one GetValueAndDerivative of each metric on a 64^3 image with a 20^3 control grid. */
int
RunTiming()
{
  const auto fixedImage = MakeBlobImage(64, 0.0, 1.0);
  const auto movingImage = MakeBlobImage(64, 2.0, 0.9);
  const auto bspline = MakeBSpline(fixedImage, 17, 1.0, 7);
  std::cout << "Timing: 64^3 voxels, " << bspline->GetNumberOfParameters() << " parameters, "
            << itk::MultiThreaderBase::GetGlobalDefaultNumberOfThreads() << " threads" << std::endl;
  for (const MeasureEnum measure : { MeasureEnum::MeanSquares, MeasureEnum::MattesMutualInformation })
  {
    auto metric = MetricType::New();
    metric->SetMeasure(measure);
    auto reference = MakeReference(measure);
    Configure(metric, fixedImage, movingImage, bspline, nullptr, nullptr, true);
    Configure(reference, fixedImage, movingImage, bspline, nullptr, nullptr, true);
    ITK_TRY_EXPECT_NO_EXCEPTION(metric->Initialize());
    ITK_TRY_EXPECT_NO_EXCEPTION(reference->Initialize());

    MetricType::MeasureType    value = 0.0;
    MetricType::DerivativeType derivative;
    itk::TimeProbe             probe;
    constexpr unsigned int     repetitions = 5;
    for (unsigned int r = 0; r < repetitions; ++r)
    {
      probe.Start();
      metric->GetValueAndDerivative(value, derivative);
      probe.Stop();
    }
    itk::TimeProbe valueProbe;
    valueProbe.Start();
    metric->GetValue();
    valueProbe.Stop();

    MetricType::MeasureType    referenceValue = 0.0;
    MetricType::DerivativeType referenceDerivative;
    itk::TimeProbe             referenceProbe;
    referenceProbe.Start();
    reference->GetValueAndDerivative(referenceValue, referenceDerivative);
    referenceProbe.Stop();

    double maxReference = 0.0;
    double maxDifference = 0.0;
    for (unsigned int p = 0; p < referenceDerivative.Size(); ++p)
    {
      maxReference = std::max(maxReference, std::abs(referenceDerivative[p]));
      maxDifference = std::max(maxDifference, std::abs(referenceDerivative[p] - derivative[p]));
    }
    std::cout << measure << ": sparse GetValueAndDerivative " << probe.GetMean() << " s, GetValue "
              << valueProbe.GetTotal() << " s; ITK GetValueAndDerivative " << referenceProbe.GetTotal()
              << " s; speed-up " << referenceProbe.GetTotal() / probe.GetMean() << "; value " << value << " (ITK "
              << referenceValue << "), derivative rel. difference " << maxDifference / maxReference << std::endl;
  }
  return EXIT_SUCCESS;
}
} // namespace

int
itkBSplineSparseImageToImageMetricv4Test(int argc, char * argv[])
{
  if (argc > 2)
  {
    std::cerr << "Usage: " << itkNameOfTestExecutableMacro(argv) << " [timing]" << std::endl;
    return EXIT_FAILURE;
  }
  if (argc == 2)
  {
    if (std::string(argv[1]) != "timing")
    {
      std::cerr << "Unknown mode " << argv[1] << "; expected \"timing\"." << std::endl;
      return EXIT_FAILURE;
    }
    return RunTiming();
  }

  int testStatus = EXIT_SUCCESS;

  const auto fixedImage = MakeBlobImage(24, 0.0, 1.0);
  const auto movingImage = MakeBlobImage(24, 1.5, 0.9);
  const auto bspline = MakeBSpline(fixedImage, 3, 1.5, 1234);
  const auto mask = MakeMask(fixedImage);

  auto metric = MetricType::New();
  ITK_EXERCISE_BASIC_OBJECT_METHODS(metric, BSplineSparseImageToImageMetricv4, ImageToImageMetricv4);
  metric->SetMeasure(MeasureEnum::MeanSquares);
  ITK_TEST_SET_GET_VALUE(MeasureEnum::MeanSquares, metric->GetMeasure());
  metric->SetMeasure(MeasureEnum::MattesMutualInformation);
  ITK_TEST_SET_GET_VALUE(MeasureEnum::MattesMutualInformation, metric->GetMeasure());
  metric->SetNumberOfHistogramBins(2);
  ITK_TEST_EXPECT_EQUAL(metric->GetNumberOfHistogramBins(), 5);
  metric->SetNumberOfHistogramBins(32);
  ITK_TEST_SET_GET_VALUE(32, metric->GetNumberOfHistogramBins());

  // Evaluating before Initialize() throws.
  metric->SetFixedImage(fixedImage);
  metric->SetMovingImage(movingImage);
  metric->SetMovingTransform(bspline);
  ITK_TRY_EXPECT_EXCEPTION(metric->GetValue());

  // Value and derivative equal ITK's metrics: both measures, both moving gradient sources, with and without a
  // fixed mask, with a sampled point set, with a composite (fixed affine, then the B-spline).
  auto composite = CompositeType::New();
  auto affine = itk::AffineTransform<double, Dimension>::New();
  {
    auto matrix = affine->GetMatrix();
    matrix[0][0] = 1.02;
    matrix[0][1] = 0.05;
    matrix[1][0] = -0.04;
    matrix[2][2] = 0.97;
    affine->SetMatrix(matrix);
    itk::AffineTransform<double, Dimension>::OutputVectorType translation;
    translation[0] = 0.7;
    translation[1] = -0.5;
    translation[2] = 0.3;
    affine->SetTranslation(translation);
  }
  composite->AddTransform(affine);
  composite->AddTransform(bspline);
  composite->SetOnlyMostRecentTransformToOptimizeOn();

  auto samples = PointSetType::New();
  {
    auto generator = itk::Statistics::MersenneTwisterRandomVariateGenerator::New();
    generator->SetSeed(99);
    const auto    region = fixedImage->GetLargestPossibleRegion();
    unsigned long id = 0;
    for (unsigned int i = 0; i < 3000; ++i)
    {
      itk::ContinuousIndex<double, Dimension> index;
      for (unsigned int d = 0; d < Dimension; ++d)
      {
        index[d] = generator->GetUniformVariate(0.0, region.GetSize()[d] - 1.0);
      }
      PointSetType::PointType point;
      fixedImage->TransformContinuousIndexToPhysicalPoint(index, point);
      samples->SetPoint(id++, point);
    }
  }

  for (const MeasureEnum measure : { MeasureEnum::MeanSquares, MeasureEnum::MattesMutualInformation })
  {
    for (const bool useGradientFilter : { false, true })
    {
      for (int setup = 0; setup < 5; ++setup)
      {
        const MaskType * setupMask = setup == 1 ? mask.GetPointer() : nullptr;
        const MaskType * movingMask = setup == 4 ? mask.GetPointer() : nullptr;
        PointSetType *   setupSamples = setup == 2 ? samples.GetPointer() : nullptr;
        TransformType *  transform =
          setup == 3 ? static_cast<TransformType *>(composite) : static_cast<TransformType *>(bspline);
        const char * setupName[] = { "full", "masked", "sampled", "composite", "moving mask" };

        auto sparse = MetricType::New();
        sparse->SetMeasure(measure);
        auto reference = MakeReference(measure);
        Configure(sparse, fixedImage, movingImage, transform, setupMask, setupSamples, useGradientFilter, movingMask);
        Configure(
          reference, fixedImage, movingImage, transform, setupMask, setupSamples, useGradientFilter, movingMask);
        ITK_TRY_EXPECT_NO_EXCEPTION(sparse->Initialize());
        ITK_TRY_EXPECT_NO_EXCEPTION(reference->Initialize());
        std::ostringstream name;
        name << measure << ", " << (useGradientFilter ? "gradient filter" : "central differences") << ", "
             << setupName[setup];
        if (!CompareWithReference(name.str(), sparse, reference))
        {
          testStatus = EXIT_FAILURE;
        }
        if (setup == 1)
        {
          ITK_TEST_EXPECT_TRUE(sparse->GetNumberOfSamples() <
                               fixedImage->GetLargestPossibleRegion().GetNumberOfPixels());
        }
        if (setup == 0 && !useGradientFilter && !CheckFiniteDifferences(name.str(), sparse, bspline))
        {
          testStatus = EXIT_FAILURE;
        }
      }
    }
  }

  // ImageRegistrationMethodv4 drives the metric unchanged (composite transform, REGULAR sampled point set) and
  // follows the same optimization path as with ITK's metrics.
  for (const MeasureEnum measure : { MeasureEnum::MeanSquares, MeasureEnum::MattesMutualInformation })
  {
    auto sparse = MetricType::New();
    sparse->SetMeasure(measure);
    auto                        reference = MakeReference(measure);
    const double                rate = measure == MeasureEnum::MeanSquares ? 0.05 : 20.0;
    BSplineType::ParametersType sparseParameters;
    BSplineType::ParametersType referenceParameters;
    ITK_TRY_EXPECT_NO_EXCEPTION(sparseParameters = RunRegistration(sparse, fixedImage, movingImage, rate));
    ITK_TRY_EXPECT_NO_EXCEPTION(referenceParameters = RunRegistration(reference, fixedImage, movingImage, rate));
    double maxParameter = 0.0;
    double maxDifference = 0.0;
    for (unsigned int p = 0; p < referenceParameters.Size(); ++p)
    {
      maxParameter = std::max(maxParameter, std::abs(referenceParameters[p]));
      maxDifference = std::max(maxDifference, std::abs(referenceParameters[p] - sparseParameters[p]));
    }
    std::cout << measure << " registration: max |parameter| " << maxParameter << ", max difference to ITK "
              << maxDifference << std::endl;
    ITK_TEST_EXPECT_TRUE(maxParameter > 0.01 && maxDifference <= 1e-6 * maxParameter);
  }

  // The generic-dimension code path.
  if (!Check2D())
  {
    std::cerr << "FAILED: 2-D comparison" << std::endl;
    testStatus = EXIT_FAILURE;
  }

  // The result is deterministic for a given number of work units, and does not depend on it beyond rounding.
  {
    auto one = MetricType::New();
    auto two = MetricType::New();
    Configure(one, fixedImage, movingImage, bspline, nullptr, nullptr, true);
    Configure(two, fixedImage, movingImage, bspline, nullptr, nullptr, true);
    one->SetMaximumNumberOfWorkUnits(1);
    two->SetMaximumNumberOfWorkUnits(2);
    ITK_TRY_EXPECT_NO_EXCEPTION(one->Initialize());
    ITK_TRY_EXPECT_NO_EXCEPTION(two->Initialize());
    MetricType::MeasureType    valueOne = 0.0;
    MetricType::MeasureType    valueTwo = 0.0;
    MetricType::MeasureType    valueAgain = 0.0;
    MetricType::DerivativeType derivativeOne;
    MetricType::DerivativeType derivativeTwo;
    MetricType::DerivativeType derivativeAgain;
    one->GetValueAndDerivative(valueOne, derivativeOne);
    two->GetValueAndDerivative(valueTwo, derivativeTwo);
    two->GetValueAndDerivative(valueAgain, derivativeAgain);
    ITK_TEST_EXPECT_EQUAL(valueTwo, valueAgain);
    ITK_TEST_EXPECT_TRUE(derivativeTwo == derivativeAgain);
    ITK_TEST_EXPECT_TRUE(std::abs(valueOne - valueTwo) <= 1e-12 * std::abs(valueOne));
    double maxDifference = 0.0;
    double maxDerivative = 0.0;
    for (unsigned int p = 0; p < derivativeOne.Size(); ++p)
    {
      maxDifference = std::max(maxDifference, std::abs(derivativeOne[p] - derivativeTwo[p]));
      maxDerivative = std::max(maxDerivative, std::abs(derivativeOne[p]));
    }
    ITK_TEST_EXPECT_TRUE(maxDifference <= 1e-12 * maxDerivative);
  }

  // Unsupported transforms and images that do not overlap are rejected with an exception.
  {
    auto bad = MetricType::New();
    Configure(bad, fixedImage, movingImage, affine, nullptr, nullptr, false);
    ITK_TRY_EXPECT_EXCEPTION(bad->Initialize());

    auto twoOptimized = CompositeType::New();
    twoOptimized->AddTransform(affine);
    twoOptimized->AddTransform(bspline);
    twoOptimized->SetAllTransformsToOptimizeOn();
    Configure(bad, fixedImage, movingImage, twoOptimized, nullptr, nullptr, false);
    ITK_TRY_EXPECT_EXCEPTION(bad->Initialize());

    auto farImage = MakeBlobImage(24, 0.0, 1.0);
    auto origin = farImage->GetOrigin();
    origin[0] += 1000.0;
    farImage->SetOrigin(origin);
    for (const MeasureEnum measure : { MeasureEnum::MeanSquares, MeasureEnum::MattesMutualInformation })
    {
      bad->SetMeasure(measure);
      Configure(bad, fixedImage, farImage, bspline, nullptr, nullptr, false);
      ITK_TRY_EXPECT_NO_EXCEPTION(bad->Initialize());
      ITK_TRY_EXPECT_EXCEPTION(bad->GetValue());
    }
  }

  std::cout << "Test finished." << std::endl;
  return testStatus;
}
