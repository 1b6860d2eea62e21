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
#ifndef itkBSplineSparseImageToImageMetricv4_hxx
#define itkBSplineSparseImageToImageMetricv4_hxx

#include "itkBSplineSparseImageToImageMetricv4.h"
#include "FFDShapeMatchingDetail/itkMattesMutualInformation.h"
#include "itkCompositeTransform.h"
#include "FFDShapeMatchingDetail/itkCubicBSplineKernel.h"
#include "itkImageRegionConstIteratorWithIndex.h"
#include "itkMath.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <type_traits>

namespace itk
{
template <typename TFixedImage, typename TMovingImage>
BSplineSparseImageToImageMetricv4<TFixedImage, TMovingImage>::BSplineSparseImageToImageMetricv4()
{
  using DenseThreaderType =
    detail::BSplineSparseMetricUnusedThreader<ThreadedImageRegionPartitioner<Superclass::VirtualImageDimension>,
                                              Superclass>;
  using SparseThreaderType = detail::BSplineSparseMetricUnusedThreader<ThreadedIndexedContainerPartitioner, Superclass>;
  this->m_DenseGetValueAndDerivativeThreader = DenseThreaderType::New();
  this->m_SparseGetValueAndDerivativeThreader = SparseThreaderType::New();
  m_Threader = MultiThreaderBase::New();
}

template <typename TFixedImage, typename TMovingImage>
void
BSplineSparseImageToImageMetricv4<TFixedImage, TMovingImage>::Initialize()
{
  Superclass::Initialize();
  if (!this->GetGradientSourceIncludesMoving())
  {
    itkExceptionMacro("The gradient source must include the moving image.");
  }
  this->ResolveMovingTransform(); // throws for an unsupported moving transform

  m_MovingGrid.SetFromImage(this->m_MovingImage.GetPointer());
  m_MovingBuffer = this->m_MovingImage->GetBufferPointer();
  m_GradientBuffer = nullptr;
  if (this->GetUseMovingImageGradientFilter())
  {
    if (this->m_MovingImageGradientImage.IsNull())
    {
      itkExceptionMacro("The moving image gradient image was not computed.");
    }
    m_GradientGrid.SetFromImage(this->m_MovingImageGradientImage.GetPointer());
    m_GradientBuffer = this->m_MovingImageGradientImage->GetBufferPointer();
  }

  this->ComputeIntensityRanges();
  this->CacheSamples();
  if (m_Samples.empty())
  {
    itkExceptionMacro("No sample of the virtual domain maps inside the fixed image buffer and the fixed image mask.");
  }
}

template <typename TFixedImage, typename TMovingImage>
auto
BSplineSparseImageToImageMetricv4<TFixedImage, TMovingImage>::GetValue() const -> MeasureType
{
  MeasureType value{};
  if (m_Measure == MeasureEnum::MeanSquares)
  {
    this->ComputeMeanSquares(value, nullptr);
  }
  else
  {
    this->ComputeMattes(value, nullptr);
  }
  return value;
}

template <typename TFixedImage, typename TMovingImage>
void
BSplineSparseImageToImageMetricv4<TFixedImage, TMovingImage>::GetDerivative(DerivativeType & derivative) const
{
  MeasureType value{};
  this->GetValueAndDerivative(value, derivative);
}

template <typename TFixedImage, typename TMovingImage>
void
BSplineSparseImageToImageMetricv4<TFixedImage, TMovingImage>::GetValueAndDerivative(MeasureType &    value,
                                                                                    DerivativeType & derivative) const
{
  if (m_Measure == MeasureEnum::MeanSquares)
  {
    this->ComputeMeanSquares(value, &derivative);
  }
  else
  {
    this->ComputeMattes(value, &derivative);
  }
}

template <typename TFixedImage, typename TMovingImage>
void
BSplineSparseImageToImageMetricv4<TFixedImage, TMovingImage>::PrintSelf(std::ostream & os, Indent indent) const
{
  Superclass::PrintSelf(os, indent);
  os << indent << "Measure: " << m_Measure << std::endl;
  os << indent << "NumberOfHistogramBins: " << m_NumberOfHistogramBins << std::endl;
  itkPrintSelfObjectMacro(Threader);
  os << indent << "NumberOfSamples: " << m_Samples.size() << std::endl;
  os << indent << "FixedImageTrueMin: " << m_FixedImageTrueMin << std::endl;
  os << indent << "FixedImageTrueMax: " << m_FixedImageTrueMax << std::endl;
  os << indent << "MovingImageTrueMin: " << m_MovingImageTrueMin << std::endl;
  os << indent << "MovingImageTrueMax: " << m_MovingImageTrueMax << std::endl;
  os << indent << "MovingGrid: start " << m_MovingGrid.Start[0] << ", end " << m_MovingGrid.End[0] << " (first axis)"
     << std::endl;
  os << indent << "GradientGrid: start " << m_GradientGrid.Start[0] << ", end " << m_GradientGrid.End[0]
     << " (first axis)" << std::endl;
  os << indent << "MovingBuffer: " << static_cast<const void *>(m_MovingBuffer) << std::endl;
  os << indent << "GradientBuffer: " << static_cast<const void *>(m_GradientBuffer) << std::endl;
  os << indent << "FixedImageBinSize: " << m_FixedImageBinSize << std::endl;
  os << indent << "MovingImageBinSize: " << m_MovingImageBinSize << std::endl;
  os << indent << "FixedImageNormalizedMin: " << m_FixedImageNormalizedMin << std::endl;
  os << indent << "MovingImageNormalizedMin: " << m_MovingImageNormalizedMin << std::endl;
  os << indent << "BSplineTransform: " << static_cast<const void *>(m_Parts.BSpline) << std::endl;
  os << indent << "NumberOfFrontTransforms: " << m_Parts.Front.size() << std::endl;
  os << indent << "FrontIsLinear: " << (m_Parts.FrontIsLinear ? "On" : "Off") << std::endl;
  os << indent << "FrontMatrix: " << m_Parts.FrontMatrix << std::endl;
  os << indent << "FrontOffset: " << m_Parts.FrontOffset << std::endl;
  os << indent << "NumberOfCoefficients: " << m_NumberOfCoefficients << std::endl;
  os << indent << "NumberOfWorkUnitResults: " << m_WorkUnitResults.size() << std::endl;
  os << indent << "NumberOfStoredSampleGradients: " << m_SampleGradients.size() << std::endl;
  os << indent << "NumberOfStoredSampleMovingValues: " << m_SampleMovingValues.size() << std::endl;
  os << indent << "NumberOfStoredSampleStates: " << m_SampleStates.size() << std::endl;
}

template <typename TFixedImage, typename TMovingImage>
auto
BSplineSparseImageToImageMetricv4<TFixedImage, TMovingImage>::ResolveMovingTransform() const -> TransformParts
{
  if (this->m_MovingTransform.IsNull())
  {
    itkExceptionMacro("MovingTransform is not present");
  }
  try
  {
    return TransformParts::Resolve(this->m_MovingTransform.GetPointer());
  }
  catch (const ExceptionObject & error)
  {
    itkExceptionMacro(<< error.GetDescription());
  }
}

template <typename TFixedImage, typename TMovingImage>
void
BSplineSparseImageToImageMetricv4<TFixedImage, TMovingImage>::ComputeIntensityRanges()
{
  // The ranges of MattesMutualInformationImageToImageMetricv4::Initialize().
  m_FixedImageTrueMin = NumericTraits<FixedImagePixelType>::max();
  m_FixedImageTrueMax = NumericTraits<FixedImagePixelType>::NonpositiveMin();
  const TFixedImage * fixedImage = this->m_FixedImage.GetPointer();
  const auto          addFixed = [this](double value) {
    m_FixedImageTrueMin = std::min(m_FixedImageTrueMin, value);
    m_FixedImageTrueMax = std::max(m_FixedImageTrueMax, value);
  };
  if (this->m_UseSampledPointSet)
  {
    const auto * points = this->m_UseVirtualSampledPointSet ? this->m_VirtualSampledPointSet->GetPoints()
                                                            : this->m_FixedSampledPointSet->GetPoints();
    for (auto it = points->Begin(); it != points->End(); ++it)
    {
      const auto point = this->m_UseVirtualSampledPointSet ? this->m_FixedTransform->TransformPoint(it.Value())
                                                           : typename TFixedImage::PointType(it.Value());
      typename TFixedImage::IndexType index;
      if (fixedImage->TransformPhysicalPointToIndex(point, index))
      {
        addFixed(fixedImage->GetPixel(index));
      }
    }
  }
  else
  {
    ImageRegionConstIteratorWithIndex<TFixedImage> it(fixedImage, fixedImage->GetBufferedRegion());
    for (; !it.IsAtEnd(); ++it)
    {
      if (this->m_FixedImageMask)
      {
        typename TFixedImage::PointType point;
        fixedImage->TransformIndexToPhysicalPoint(it.GetIndex(), point);
        if (!this->m_FixedImageMask->IsInsideInWorldSpace(point))
        {
          continue;
        }
      }
      addFixed(it.Value());
    }
  }

  m_MovingImageTrueMin = NumericTraits<MovingImagePixelType>::max();
  m_MovingImageTrueMax = NumericTraits<MovingImagePixelType>::NonpositiveMin();
  const TMovingImage *                            movingImage = this->m_MovingImage.GetPointer();
  ImageRegionConstIteratorWithIndex<TMovingImage> it(movingImage, movingImage->GetBufferedRegion());
  for (; !it.IsAtEnd(); ++it)
  {
    if (this->m_MovingImageMask)
    {
      typename TMovingImage::PointType point;
      movingImage->TransformIndexToPhysicalPoint(it.GetIndex(), point);
      if (!this->m_MovingImageMask->IsInsideInWorldSpace(point))
      {
        continue;
      }
    }
    m_MovingImageTrueMin = std::min(m_MovingImageTrueMin, static_cast<double>(it.Value()));
    m_MovingImageTrueMax = std::max(m_MovingImageTrueMax, static_cast<double>(it.Value()));
  }
}

template <typename TFixedImage, typename TMovingImage>
void
BSplineSparseImageToImageMetricv4<TFixedImage, TMovingImage>::CacheSamples()
{
  m_Samples.clear();
  Grid                fixedGrid;
  const TFixedImage * fixedImage = this->m_FixedImage.GetPointer();
  fixedGrid.SetFromImage(fixedImage);
  const auto * fixedBuffer = fixedImage->GetBufferPointer();

  const auto addSample = [&](const VirtualPointType & virtualPoint) {
    const auto fixedPoint = this->m_FixedTransform->TransformPoint(virtualPoint);
    if (this->m_FixedImageMask && !this->m_FixedImageMask->IsInsideInWorldSpace(fixedPoint))
    {
      return;
    }
    double continuousIndex[ImageDimension];
    if (!fixedGrid.ToContinuousIndex(fixedPoint, continuousIndex))
    {
      return;
    }
    double value = 0.0;
    fixedGrid.InterpolateLinear(fixedBuffer, continuousIndex, value);
    Sample sample;
    sample.Point = virtualPoint;
    sample.FixedValue = static_cast<double>(static_cast<FixedImagePixelType>(value));
    m_Samples.push_back(sample);
  };

  if (this->m_UseSampledPointSet)
  {
    const auto * points = this->m_VirtualSampledPointSet->GetPoints();
    m_Samples.reserve(points->Size());
    for (auto it = points->Begin(); it != points->End(); ++it)
    {
      addSample(it.Value());
    }
  }
  else
  {
    const auto * virtualImage = this->GetVirtualImage();
    const auto   region = this->GetVirtualRegion();
    m_Samples.reserve(region.GetNumberOfPixels());
    ImageRegionConstIteratorWithIndex<typename Superclass::VirtualImageType> it(virtualImage, region);
    for (; !it.IsAtEnd(); ++it)
    {
      VirtualPointType virtualPoint;
      virtualImage->TransformIndexToPhysicalPoint(it.GetIndex(), virtualPoint);
      addSample(virtualPoint);
    }
  }
}

template <typename TFixedImage, typename TMovingImage>
bool
BSplineSparseImageToImageMetricv4<TFixedImage, TMovingImage>::ComputeSupport(const VirtualPointType & point,
                                                                             Support &                support) const
{
  // Valid region and weights of BSplineTransform::InsideValidRegion and BSplineInterpolationWeightFunction.
  double continuousIndex[ImageDimension];
  m_CoefficientGrid.ToContinuousIndex(point, continuousIndex);
  for (unsigned int i = 0; i < ImageDimension; ++i)
  {
    double       index = continuousIndex[i];
    const double maxLimit = static_cast<double>(m_CoefficientGrid.End[i] + 1) - 1.0 - 1.0;
    if (Math::FloatAlmostEqual(index, maxLimit, 4))
    {
      index = Math::FloatAddULP(maxLimit, -6);
    }
    else if (index >= maxLimit || index < 1.0)
    {
      return false;
    }
    support.Start[i] = Math::Floor<IndexValueType>(index + 0.5 - 1.5);
    detail::CubicBSplineWeights(index - static_cast<double>(support.Start[i]) - 1.0, support.Weights[i]);
  }
  return true;
}

template <typename TFixedImage, typename TMovingImage>
template <typename TFunctor>
void
BSplineSparseImageToImageMetricv4<TFixedImage, TMovingImage>::ForEachSupportPoint(const Support & support,
                                                                                  TFunctor &&     functor) const
{
  // Generic dimension: odometer over the support (3-D uses unrolled loops in the callers).
  unsigned int position[ImageDimension] = {};
  while (true)
  {
    double          weight = 1.0;
    OffsetValueType offset = 0;
    for (unsigned int d = 0; d < ImageDimension; ++d)
    {
      weight *= support.Weights[d][position[d]];
      offset += (support.Start[d] + position[d]) * m_CoefficientGrid.Stride[d];
    }
    functor(offset, weight);
    unsigned int d = 0;
    while (d < ImageDimension && ++position[d] == SupportSize)
    {
      position[d++] = 0;
    }
    if (d == ImageDimension)
    {
      break;
    }
  }
}

template <typename TFixedImage, typename TMovingImage>
void
BSplineSparseImageToImageMetricv4<TFixedImage, TMovingImage>::ComputeMovingGradient(
  const VirtualPointType & movingPoint,
  const double *           continuousIndex,
  GradientType &           gradient) const
{
  if (m_GradientBuffer != nullptr)
  {
    double gradientIndex[ImageDimension];
    m_GradientGrid.ToContinuousIndex(movingPoint, gradientIndex);
    m_GradientGrid.InterpolateLinear(m_GradientBuffer, gradientIndex, gradient);
    return;
  }
  // Central differences of the interpolated image along the physical axes, zero where a neighbour leaves the
  // buffer (CentralDifferenceImageFunction::Evaluate(point)).
  (void)continuousIndex;
  const auto & spacing = this->m_MovingImage->GetSpacing();
  for (unsigned int d = 0; d < ImageDimension; ++d)
  {
    VirtualPointType below = movingPoint;
    VirtualPointType above = movingPoint;
    below[d] -= 0.5 * spacing[d];
    above[d] += 0.5 * spacing[d];
    double       belowIndex[ImageDimension];
    double       aboveIndex[ImageDimension];
    const double delta = above[d] - below[d];
    if (!m_MovingGrid.ToContinuousIndex(below, belowIndex) || !m_MovingGrid.ToContinuousIndex(above, aboveIndex) ||
        !(delta > 10.0 * NumericTraits<double>::epsilon()))
    {
      gradient[d] = 0.0;
      continue;
    }
    double belowValue = 0.0;
    double aboveValue = 0.0;
    m_MovingGrid.InterpolateLinear(m_MovingBuffer, belowIndex, belowValue);
    m_MovingGrid.InterpolateLinear(m_MovingBuffer, aboveIndex, aboveValue);
    gradient[d] = (aboveValue - belowValue) / delta;
  }
}

template <typename TFixedImage, typename TMovingImage>
bool
BSplineSparseImageToImageMetricv4<TFixedImage, TMovingImage>::EvaluateSample(const Sample &         sample,
                                                                             const TransformParts & parts,
                                                                             bool                   computeGradient,
                                                                             Support &              support,
                                                                             bool &                 insideGrid,
                                                                             double &               movingValue,
                                                                             GradientType &         gradient) const
{
  // z = B(x): B-spline displacement over the 4^D support.
  VirtualPointType deformed = sample.Point;
  insideGrid = this->ComputeSupport(sample.Point, support);
  if (insideGrid)
  {
    double displacement[ImageDimension] = {};
    if constexpr (ImageDimension == 3)
    {
      // Separable: a 4-term dot product along the first axis per row, weighted by the other two axes.
      const double * weights0 = support.Weights[0];
      for (unsigned int k = 0; k < SupportSize; ++k)
      {
        const OffsetValueType offsetK = (support.Start[2] + k) * m_CoefficientGrid.Stride[2] + support.Start[0];
        for (unsigned int j = 0; j < SupportSize; ++j)
        {
          const OffsetValueType row = offsetK + (support.Start[1] + j) * m_CoefficientGrid.Stride[1];
          const double          weightKJ = support.Weights[2][k] * support.Weights[1][j];
          for (unsigned int d = 0; d < ImageDimension; ++d)
          {
            const double * coefficients = m_Coefficients[d] + row;
            displacement[d] += weightKJ * (weights0[0] * coefficients[0] + weights0[1] * coefficients[1] +
                                           weights0[2] * coefficients[2] + weights0[3] * coefficients[3]);
          }
        }
      }
    }
    else
    {
      this->ForEachSupportPoint(support, [&](OffsetValueType offset, double weight) {
        for (unsigned int d = 0; d < ImageDimension; ++d)
        {
          displacement[d] += weight * m_Coefficients[d][offset];
        }
      });
    }
    for (unsigned int d = 0; d < ImageDimension; ++d)
    {
      deformed[d] += displacement[d];
    }
  }

  // y = F(z) through the transforms applied after the B-spline.
  VirtualPointType     movingPoint = deformed;
  PositionJacobianType frontJacobian;
  if (!parts.Front.empty())
  {
    if (parts.FrontIsLinear)
    {
      for (unsigned int i = 0; i < ImageDimension; ++i)
      {
        double sum = parts.FrontOffset[i];
        for (unsigned int j = 0; j < ImageDimension; ++j)
        {
          sum += parts.FrontMatrix[i][j] * deformed[j];
        }
        movingPoint[i] = sum;
      }
      frontJacobian = parts.FrontMatrix;
    }
    else
    {
      frontJacobian.SetIdentity();
      for (const MovingTransformType * front : parts.Front)
      {
        if (computeGradient)
        {
          typename MovingTransformType::JacobianPositionType jacobian;
          front->ComputeJacobianWithRespectToPosition(movingPoint, jacobian);
          frontJacobian = PositionJacobianType(jacobian) * frontJacobian;
        }
        movingPoint = front->TransformPoint(movingPoint);
      }
    }
  }

  if (this->m_MovingImageMask && !this->m_MovingImageMask->IsInsideInWorldSpace(movingPoint))
  {
    return false;
  }
  double continuousIndex[ImageDimension];
  if (!m_MovingGrid.ToContinuousIndex(movingPoint, continuousIndex))
  {
    return false;
  }
  double value = 0.0;
  m_MovingGrid.InterpolateLinear(m_MovingBuffer, continuousIndex, value);
  movingValue = static_cast<double>(static_cast<MovingImagePixelType>(value));

  if (computeGradient && insideGrid)
  {
    GradientType imageGradient;
    this->ComputeMovingGradient(movingPoint, continuousIndex, imageGradient);
    if (parts.Front.empty())
    {
      gradient = imageGradient;
    }
    else
    {
      // Chain rule: d I(F(z)) / dz = J_F^T grad I.
      for (unsigned int j = 0; j < ImageDimension; ++j)
      {
        double sum = 0.0;
        for (unsigned int i = 0; i < ImageDimension; ++i)
        {
          sum += frontJacobian[i][j] * imageGradient[i];
        }
        gradient[j] = sum;
      }
    }
  }
  return true;
}

template <typename TFixedImage, typename TMovingImage>
void
BSplineSparseImageToImageMetricv4<TFixedImage, TMovingImage>::AccumulateSparse(const Support &      support,
                                                                               const GradientType & weightedGradient,
                                                                               double *             derivative) const
{
  // Parameter layout of BSplineTransform: all coefficients of dimension 0, then of dimension 1, ...
  if constexpr (ImageDimension == 3)
  {
    const double * weights0 = support.Weights[0];
    for (unsigned int k = 0; k < SupportSize; ++k)
    {
      const OffsetValueType offsetK = (support.Start[2] + k) * m_CoefficientGrid.Stride[2] + support.Start[0];
      for (unsigned int j = 0; j < SupportSize; ++j)
      {
        const OffsetValueType row = offsetK + (support.Start[1] + j) * m_CoefficientGrid.Stride[1];
        const double          weightKJ = support.Weights[2][k] * support.Weights[1][j];
        for (unsigned int d = 0; d < ImageDimension; ++d)
        {
          double *     target = derivative + d * m_NumberOfCoefficients + row;
          const double scaled = weightKJ * weightedGradient[d];
          target[0] += scaled * weights0[0];
          target[1] += scaled * weights0[1];
          target[2] += scaled * weights0[2];
          target[3] += scaled * weights0[3];
        }
      }
    }
    return;
  }
  this->ForEachSupportPoint(support, [&](OffsetValueType offset, double weight) {
    double * target = derivative + offset;
    for (unsigned int d = 0; d < ImageDimension; ++d)
    {
      target[d * m_NumberOfCoefficients] += weight * weightedGradient[d];
    }
  });
}

template <typename TFixedImage, typename TMovingImage>
void
BSplineSparseImageToImageMetricv4<TFixedImage, TMovingImage>::PrepareEvaluation(bool computeDerivative) const
{
  if (m_Samples.empty() || m_MovingBuffer == nullptr)
  {
    itkExceptionMacro("The metric is not initialized: call Initialize() first.");
  }
  m_Parts = this->ResolveMovingTransform();
  const BSplineTransformType * bspline = m_Parts.BSpline;
  const auto &                 coefficientImages = bspline->GetCoefficientImages();
  m_CoefficientGrid.SetFromImage(coefficientImages[0].GetPointer());
  for (unsigned int d = 0; d < ImageDimension; ++d)
  {
    m_Coefficients[d] = coefficientImages[d]->GetBufferPointer();
  }
  m_NumberOfCoefficients = coefficientImages[0]->GetBufferedRegion().GetNumberOfPixels();
  const SizeValueType numberOfParameters = this->GetNumberOfParameters();
  if (numberOfParameters != ImageDimension * m_NumberOfCoefficients)
  {
    itkExceptionMacro("The moving transform has " << numberOfParameters
                                                  << " parameters to optimize but its B-spline has "
                                                  << ImageDimension * m_NumberOfCoefficients << '.');
  }

  const SizeValueType numberOfSamples = m_Samples.size();
  // The samples are cut into a fixed number of parts, whatever the number of threads, and the parts' sums are
  // added in order: the value and derivative are bit-identical for every thread count.
  constexpr SizeValueType numberOfParts = 16;
  const SizeValueType     numberOfWorkUnits =
    std::max<SizeValueType>(1, std::min<SizeValueType>(numberOfParts, numberOfSamples));
  const bool          mattes = m_Measure == MeasureEnum::MattesMutualInformation;
  const SizeValueType bins = m_NumberOfHistogramBins;
  m_WorkUnitResults.resize(numberOfWorkUnits);
  for (auto & result : m_WorkUnitResults)
  {
    result.Measure = 0.0;
    result.NumberOfValidPoints = 0;
    result.JointHistogram.assign(mattes ? bins * bins : 0, 0.0);
    result.FixedMarginal.assign(mattes ? bins : 0, 0.0);
    result.Derivative.assign(computeDerivative ? numberOfParameters : 0, 0.0);
  }
  if (mattes && computeDerivative)
  {
    m_SampleGradients.resize(numberOfSamples);
    m_SampleMovingValues.resize(numberOfSamples);
    m_SampleStates.resize(numberOfSamples);
  }
  if (mattes)
  {
    // Bin sizes and padding of MattesMutualInformationImageToImageMetricv4::Initialize().
    constexpr int padding = 2;
    m_FixedImageBinSize =
      (m_FixedImageTrueMax - m_FixedImageTrueMin) / static_cast<double>(m_NumberOfHistogramBins - 2 * padding);
    m_MovingImageBinSize =
      (m_MovingImageTrueMax - m_MovingImageTrueMin) / static_cast<double>(m_NumberOfHistogramBins - 2 * padding);
    if (!(m_FixedImageBinSize > 0.0) || !(m_MovingImageBinSize > 0.0))
    {
      itkExceptionMacro("Mattes mutual information needs a fixed and a moving intensity range of positive width "
                        "(fixed ["
                        << m_FixedImageTrueMin << ", " << m_FixedImageTrueMax << "], moving [" << m_MovingImageTrueMin
                        << ", " << m_MovingImageTrueMax << "]).");
    }
    m_FixedImageNormalizedMin = m_FixedImageTrueMin / m_FixedImageBinSize - static_cast<double>(padding);
    m_MovingImageNormalizedMin = m_MovingImageTrueMin / m_MovingImageBinSize - static_cast<double>(padding);
  }
}

template <typename TFixedImage, typename TMovingImage>
void
BSplineSparseImageToImageMetricv4<TFixedImage, TMovingImage>::RunWorkUnits(
  const std::function<void(SizeValueType, SizeValueType, WorkUnitResult &)> & body) const
{
  const SizeValueType numberOfWorkUnits = m_WorkUnitResults.size();
  const SizeValueType numberOfSamples = m_Samples.size();
  const auto          threads = static_cast<ThreadIdType>(
    std::max<SizeValueType>(1, std::min<SizeValueType>(this->GetMaximumNumberOfWorkUnits(), numberOfWorkUnits)));
  m_Threader->SetMaximumNumberOfThreads(threads);
  m_Threader->SetNumberOfWorkUnits(threads);
  m_Threader->ParallelizeArray(
    0,
    numberOfWorkUnits,
    [&](SizeValueType workUnit) {
      const SizeValueType begin = numberOfSamples * workUnit / numberOfWorkUnits;
      const SizeValueType end = numberOfSamples * (workUnit + 1) / numberOfWorkUnits;
      body(begin, end, m_WorkUnitResults[workUnit]);
    },
    nullptr);
}

template <typename TFixedImage, typename TMovingImage>
void
BSplineSparseImageToImageMetricv4<TFixedImage, TMovingImage>::SumDerivatives(DerivativeType & derivative,
                                                                             double           scale) const
{
  const SizeValueType numberOfParameters = this->GetNumberOfParameters();
  if (derivative.Size() != numberOfParameters)
  {
    derivative.SetSize(numberOfParameters);
  }
  for (SizeValueType p = 0; p < numberOfParameters; ++p)
  {
    double sum = 0.0;
    for (const auto & result : m_WorkUnitResults)
    {
      sum += result.Derivative[p];
    }
    derivative[p] = static_cast<DerivativeValueType>(sum * scale);
  }
}

template <typename TFixedImage, typename TMovingImage>
void
BSplineSparseImageToImageMetricv4<TFixedImage, TMovingImage>::ComputeMeanSquares(MeasureType &    value,
                                                                                 DerivativeType * derivative) const
{
  const bool computeDerivative = derivative != nullptr;
  this->PrepareEvaluation(computeDerivative);
  const TransformParts & parts = m_Parts;
  this->RunWorkUnits([&](SizeValueType begin, SizeValueType end, WorkUnitResult & result) {
    Support      support;
    GradientType gradient;
    for (SizeValueType i = begin; i < end; ++i)
    {
      bool   insideGrid = false;
      double movingValue = 0.0;
      if (!this->EvaluateSample(m_Samples[i], parts, computeDerivative, support, insideGrid, movingValue, gradient))
      {
        continue;
      }
      const double difference = m_Samples[i].FixedValue - movingValue;
      result.Measure += difference * difference;
      ++result.NumberOfValidPoints;
      if (computeDerivative && insideGrid)
      {
        // Downhill: -d (f - m)^2 / dp = 2 (f - m) grad(m) . dT/dp.
        this->AccumulateSparse(support, gradient * (2.0 * difference), result.Derivative.data());
      }
    }
  });

  SizeValueType numberOfValidPoints = 0;
  double        sum = 0.0;
  for (const auto & result : m_WorkUnitResults)
  {
    numberOfValidPoints += result.NumberOfValidPoints;
    sum += result.Measure;
  }
  this->m_NumberOfValidPoints = numberOfValidPoints;
  if (numberOfValidPoints == 0)
  {
    itkExceptionMacro("All " << m_Samples.size()
                             << " samples map outside the moving image buffer (or mask): the images do not overlap.");
  }
  value = static_cast<MeasureType>(sum / static_cast<double>(numberOfValidPoints));
  this->m_Value = value;
  if (computeDerivative)
  {
    this->SumDerivatives(*derivative, 1.0 / static_cast<double>(numberOfValidPoints));
  }
}

template <typename TFixedImage, typename TMovingImage>
OffsetValueType
BSplineSparseImageToImageMetricv4<TFixedImage, TMovingImage>::FixedParzenIndex(double fixedValue) const
{
  auto       index = static_cast<OffsetValueType>(fixedValue / m_FixedImageBinSize - m_FixedImageNormalizedMin);
  const auto lastIndex = static_cast<OffsetValueType>(m_NumberOfHistogramBins) - 3;
  return std::min(std::max<OffsetValueType>(index, 2), lastIndex);
}

template <typename TFixedImage, typename TMovingImage>
OffsetValueType
BSplineSparseImageToImageMetricv4<TFixedImage, TMovingImage>::MovingParzenIndex(double   movingValue,
                                                                                double & firstArgument) const
{
  const double term = movingValue / m_MovingImageBinSize - m_MovingImageNormalizedMin;
  auto         index = static_cast<OffsetValueType>(term);
  const auto   lastIndex = static_cast<OffsetValueType>(m_NumberOfHistogramBins) - 3;
  index = std::min(std::max<OffsetValueType>(index, 2), lastIndex);
  firstArgument = static_cast<double>(index - 1) - term;
  return index - 1;
}

template <typename TFixedImage, typename TMovingImage>
void
BSplineSparseImageToImageMetricv4<TFixedImage, TMovingImage>::ComputeMattes(MeasureType &    value,
                                                                            DerivativeType * derivative) const
{
  const bool computeDerivative = derivative != nullptr;
  this->PrepareEvaluation(computeDerivative);
  const TransformParts & parts = m_Parts;
  const SizeValueType    bins = m_NumberOfHistogramBins;

  // Pass 1: joint histogram (cubic Parzen window on the moving intensity, box on the fixed one).
  this->RunWorkUnits([&](SizeValueType begin, SizeValueType end, WorkUnitResult & result) {
    Support      support;
    GradientType gradient;
    for (SizeValueType i = begin; i < end; ++i)
    {
      bool   insideGrid = false;
      double movingValue = 0.0;
      bool   valid =
        this->EvaluateSample(m_Samples[i], parts, computeDerivative, support, insideGrid, movingValue, gradient);
      valid = valid && movingValue >= m_MovingImageTrueMin && movingValue <= m_MovingImageTrueMax;
      if (computeDerivative)
      {
        m_SampleStates[i] = valid ? (insideGrid ? 1 : 2) : 0;
        m_SampleMovingValues[i] = movingValue;
        m_SampleGradients[i] = gradient;
      }
      if (!valid)
      {
        continue;
      }
      const OffsetValueType fixedIndex = this->FixedParzenIndex(m_Samples[i].FixedValue);
      double                argument = 0.0;
      const OffsetValueType movingIndex = this->MovingParzenIndex(movingValue, argument);
      double *              row = result.JointHistogram.data() + fixedIndex * bins + movingIndex;
      for (unsigned int k = 0; k < 4; ++k, argument += 1.0)
      {
        row[k] += detail::CubicBSpline(argument);
      }
      result.FixedMarginal[fixedIndex] += 1.0;
      ++result.NumberOfValidPoints;
    }
  });

  // Sum the work units in a fixed order.
  std::vector<double> joint(bins * bins, 0.0);
  std::vector<double> fixedMarginal(bins, 0.0);
  SizeValueType       numberOfValidPoints = 0;
  for (const auto & result : m_WorkUnitResults)
  {
    for (SizeValueType b = 0; b < bins * bins; ++b)
    {
      joint[b] += result.JointHistogram[b];
    }
    for (SizeValueType b = 0; b < bins; ++b)
    {
      fixedMarginal[b] += result.FixedMarginal[b];
    }
    numberOfValidPoints += result.NumberOfValidPoints;
  }
  this->m_NumberOfValidPoints = numberOfValidPoints;
  if (numberOfValidPoints == 0)
  {
    itkExceptionMacro("All " << m_Samples.size()
                             << " samples map outside the moving image buffer (or mask) or its intensity range: the "
                                "images do not overlap.");
  }
  // Normalized histograms, value and the log ratios of the derivative (Mattes et al. 2003, eqs. 3-4 and 11).
  std::vector<double> logRatio;
  double              sum = 0.0;
  if (!detail::ComputeMattesMutualInformation(bins, joint, fixedMarginal, computeDerivative ? &logRatio : nullptr, sum))
  {
    itkExceptionMacro("The joint histogram sums to zero.");
  }
  value = static_cast<MeasureType>(-sum);
  this->m_Value = value;
  if (!computeDerivative)
  {
    return;
  }

  // Pass 2: d MI / dp = sum_x [ -1 / (binSize N) sum_k beta3'(arg_k) log ratio(f, m_k) ] grad(m) . dT/dp, which
  // is the downhill direction of the value -MI.
  const double scale = -1.0 / (m_MovingImageBinSize * static_cast<double>(numberOfValidPoints));
  this->RunWorkUnits([&](SizeValueType begin, SizeValueType end, WorkUnitResult & result) {
    Support support;
    for (SizeValueType i = begin; i < end; ++i)
    {
      if (m_SampleStates[i] != 1)
      {
        continue;
      }
      const OffsetValueType fixedIndex = this->FixedParzenIndex(m_Samples[i].FixedValue);
      double                argument = 0.0;
      const OffsetValueType movingIndex = this->MovingParzenIndex(m_SampleMovingValues[i], argument);
      const double *        ratios = logRatio.data() + fixedIndex * bins + movingIndex;
      double                factor = 0.0;
      for (unsigned int k = 0; k < 4; ++k, argument += 1.0)
      {
        factor += detail::CubicBSplineDerivative(argument) * ratios[k];
      }
      if (factor == 0.0)
      {
        continue;
      }
      this->ComputeSupport(m_Samples[i].Point, support);
      this->AccumulateSparse(support, m_SampleGradients[i] * (factor * scale), result.Derivative.data());
    }
  });
  this->SumDerivatives(*derivative, 1.0);
}
} // namespace itk

#endif // itkBSplineSparseImageToImageMetricv4_hxx
