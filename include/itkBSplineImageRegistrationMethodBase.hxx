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
#ifndef itkBSplineImageRegistrationMethodBase_hxx
#define itkBSplineImageRegistrationMethodBase_hxx

#include "itkBSplineImageRegistrationMethodBase.h"
#include <algorithm>
#include <cmath>

namespace itk
{
template <typename TFixedImage, typename TMovingImage>
BSplineImageRegistrationMethodBase<TFixedImage, TMovingImage>::BSplineImageRegistrationMethodBase(
  unsigned int numberOfLevels)
  : m_NumberOfLevels(numberOfLevels)
{
  this->SetPrimaryInputName("FixedImage");
  this->AddRequiredInputName("MovingImage", 1);
  this->AddOptionalInputName("FixedImageMask", 2);
  this->SetNumberOfRequiredOutputs(1);
  this->SetNthOutput(0, this->MakeOutput(0));
}

template <typename TFixedImage, typename TMovingImage>
auto
BSplineImageRegistrationMethodBase<TFixedImage, TMovingImage>::MakeOutput(DataObjectPointerArraySizeType)
  -> DataObjectPointer
{
  return DecoratedTransformType::New().GetPointer();
}

template <typename TFixedImage, typename TMovingImage>
auto
BSplineImageRegistrationMethodBase<TFixedImage, TMovingImage>::GetTransformOutput() const
  -> const DecoratedTransformType *
{
  return static_cast<const DecoratedTransformType *>(this->ProcessObject::GetOutput(0));
}

template <typename TFixedImage, typename TMovingImage>
auto
BSplineImageRegistrationMethodBase<TFixedImage, TMovingImage>::GetTransform() const -> const TransformType *
{
  return this->GetTransformOutput()->Get();
}

template <typename TFixedImage, typename TMovingImage>
void
BSplineImageRegistrationMethodBase<TFixedImage, TMovingImage>::SetTransformOutputValue(TransformType * transform)
{
  static_cast<DecoratedTransformType *>(this->ProcessObject::GetOutput(0))->Set(transform);
}

template <typename TFixedImage, typename TMovingImage>
void
BSplineImageRegistrationMethodBase<TFixedImage, TMovingImage>::StartRunTimeClock()
{
  m_StartTime = std::chrono::steady_clock::now();
  m_TimeLimitReached = false;
}

template <typename TFixedImage, typename TMovingImage>
double
BSplineImageRegistrationMethodBase<TFixedImage, TMovingImage>::GetElapsedRunTime() const
{
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - m_StartTime).count();
}

template <typename TFixedImage, typename TMovingImage>
bool
BSplineImageRegistrationMethodBase<TFixedImage, TMovingImage>::IsRunTimeExceeded() const
{
  return m_MaximumRunTime > 0.0 && this->GetElapsedRunTime() > m_MaximumRunTime;
}

template <typename TFixedImage, typename TMovingImage>
bool
BSplineImageRegistrationMethodBase<TFixedImage, TMovingImage>::CheckRunTime()
{
  if (!m_TimeLimitReached && this->IsRunTimeExceeded())
  {
    m_TimeLimitReached = true;
  }
  return m_TimeLimitReached;
}

template <typename TFixedImage, typename TMovingImage>
void
BSplineImageRegistrationMethodBase<TFixedImage, TMovingImage>::PrintSelf(std::ostream & os, Indent indent) const
{
  Superclass::PrintSelf(os, indent);
  os << indent << "NumberOfControlPointsPerAxis: " << m_NumberOfControlPointsPerAxis << std::endl;
  os << indent << "NumberOfLevels: " << m_NumberOfLevels << std::endl;
  os << indent << "MaximumRunTime: " << m_MaximumRunTime << std::endl;
  os << indent << "TimeLimitReached: " << (m_TimeLimitReached ? "true" : "false") << std::endl;
}

template <typename TFixedImage, typename TMovingImage>
unsigned int
BSplineImageRegistrationMethodBase<TFixedImage, TMovingImage>::ComputeMeshSizeAtLevel(
  unsigned int numberOfControlPointsPerAxis,
  unsigned int numberOfLevels,
  unsigned int level)
{
  const unsigned int finalMeshSize = std::max(numberOfControlPointsPerAxis, 4u) - 3;
  const unsigned int levels = std::max(numberOfLevels, 1u);
  const unsigned int coarsening = levels - 1 - std::min(level, levels - 1);
  const double       meshSize = std::round(finalMeshSize / std::pow(2.0, coarsening));
  return std::max(1u, static_cast<unsigned int>(meshSize));
}

template <typename TFixedImage, typename TMovingImage>
void
BSplineImageRegistrationMethodBase<TFixedImage, TMovingImage>::VerifyImageInputs() const
{
  if (m_NumberOfControlPointsPerAxis < 4 || m_NumberOfControlPointsPerAxis > 1000)
  {
    itkExceptionMacro(<< "NumberOfControlPointsPerAxis must be in [4, 1000], is " << m_NumberOfControlPointsPerAxis);
  }
  if (m_NumberOfLevels < 1 || m_NumberOfLevels > 8)
  {
    itkExceptionMacro(<< "NumberOfLevels must be in [1, 8], is " << m_NumberOfLevels);
  }
  const unsigned int numberOfLevels = m_NumberOfLevels;
  const auto *       fixed = this->GetFixedImage();
  const auto *       moving = this->GetMovingImage();
  if (fixed->GetLargestPossibleRegion().GetNumberOfPixels() == 0 ||
      moving->GetLargestPossibleRegion().GetNumberOfPixels() == 0)
  {
    itkExceptionMacro(<< "The fixed and moving images must not be empty");
  }
  const auto * mask = this->GetFixedImageMask();
  if (mask != nullptr && mask->GetLargestPossibleRegion().GetNumberOfPixels() == 0)
  {
    itkExceptionMacro(<< "The fixed-image mask is empty");
  }
  const unsigned int shrink = 1u << (std::max(numberOfLevels, 1u) - 1);
  for (unsigned int d = 0; d < ImageDimension; ++d)
  {
    if (fixed->GetLargestPossibleRegion().GetSize()[d] < 2 * shrink ||
        moving->GetLargestPossibleRegion().GetSize()[d] < 2 * shrink)
    {
      itkExceptionMacro(<< "The images are too small (" << fixed->GetLargestPossibleRegion().GetSize() << ", "
                        << moving->GetLargestPossibleRegion().GetSize() << ") for " << numberOfLevels
                        << " resolution levels");
    }
  }
}
} // namespace itk

#endif // itkBSplineImageRegistrationMethodBase_hxx
