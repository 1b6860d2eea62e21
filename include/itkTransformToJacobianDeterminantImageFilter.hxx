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
#ifndef itkTransformToJacobianDeterminantImageFilter_hxx
#define itkTransformToJacobianDeterminantImageFilter_hxx

#include "itkTransformToJacobianDeterminantImageFilter.h"
#include "itkImageScanlineIterator.h"
#include "itkTotalProgressReporter.h"
#include "FFDShapeMatchingDetail/itkMatrixDeterminant.h"
#include <limits>
#include <vector>

namespace itk
{
template <typename TOutputImage, typename TTransform>
TransformToJacobianDeterminantImageFilter<TOutputImage, TTransform>::TransformToJacobianDeterminantImageFilter()
{
  this->AddRequiredInputName("Transform");
  this->DynamicMultiThreadingOn();
  this->ThreaderUpdateProgressOff();
}

template <typename TOutputImage, typename TTransform>
void
TransformToJacobianDeterminantImageFilter<TOutputImage, TTransform>::PrintSelf(std::ostream & os, Indent indent) const
{
  Superclass::PrintSelf(os, indent);
  os << indent << "Size: " << m_Size << std::endl;
  os << indent << "OutputStartIndex: " << m_OutputStartIndex << std::endl;
  os << indent << "OutputSpacing: " << m_OutputSpacing << std::endl;
  os << indent << "OutputOrigin: " << m_OutputOrigin << std::endl;
  os << indent << "OutputDirection: " << m_OutputDirection << std::endl;
  os << indent << "UseReferenceImage: " << (m_UseReferenceImage ? "On" : "Off") << std::endl;
  os << indent << "FiniteDifferenceStep: " << m_FiniteDifferenceStep << std::endl;
  os << indent << "MinimumDeterminant: " << m_MinimumDeterminant << std::endl;
  os << indent << "MaximumDeterminant: " << m_MaximumDeterminant << std::endl;
  os << indent << "JacobianEvaluator: "
     << (m_JacobianEvaluator.GetMethod() == JacobianEvaluatorType::Method::None ? "not initialized" : "initialized")
     << std::endl;
}

template <typename TOutputImage, typename TTransform>
void
TransformToJacobianDeterminantImageFilter<TOutputImage, TTransform>::VerifyPreconditions() const
{
  Superclass::VerifyPreconditions();
  if (this->GetTransform() == nullptr)
  {
    itkExceptionMacro(<< "The Transform input holds no transform");
  }
  if (m_UseReferenceImage && this->GetReferenceImage() == nullptr)
  {
    itkExceptionMacro(<< "UseReferenceImage is On but no reference image is set");
  }
  if (!(m_FiniteDifferenceStep > 0.0))
  {
    itkExceptionMacro(<< "FiniteDifferenceStep must be positive, it is " << m_FiniteDifferenceStep);
  }
}

template <typename TOutputImage, typename TTransform>
void
TransformToJacobianDeterminantImageFilter<TOutputImage, TTransform>::GenerateOutputInformation()
{
  OutputImageType * output = this->GetOutput();
  if (output == nullptr)
  {
    return;
  }
  const ReferenceImageBaseType * referenceImage = this->GetReferenceImage();
  if (m_UseReferenceImage && referenceImage != nullptr)
  {
    output->SetLargestPossibleRegion(referenceImage->GetLargestPossibleRegion());
    output->SetSpacing(referenceImage->GetSpacing());
    output->SetOrigin(referenceImage->GetOrigin());
    output->SetDirection(referenceImage->GetDirection());
  }
  else
  {
    output->SetLargestPossibleRegion(OutputImageRegionType(m_OutputStartIndex, m_Size));
    output->SetSpacing(m_OutputSpacing);
    output->SetOrigin(m_OutputOrigin);
    output->SetDirection(m_OutputDirection);
  }
}

template <typename TOutputImage, typename TTransform>
void
TransformToJacobianDeterminantImageFilter<TOutputImage, TTransform>::BeforeThreadedGenerateData()
{
  m_JacobianEvaluator.Initialize(this->GetTransform(), m_FiniteDifferenceStep);
  m_MinimumDeterminant = std::numeric_limits<double>::max();
  m_MaximumDeterminant = std::numeric_limits<double>::lowest();
}

template <typename TOutputImage, typename TTransform>
void
TransformToJacobianDeterminantImageFilter<TOutputImage, TTransform>::DynamicThreadedGenerateData(
  const OutputImageRegionType & outputRegionForThread)
{
  OutputImageType *     output = this->GetOutput();
  TotalProgressReporter progress(this, output->GetRequestedRegion().GetNumberOfPixels());
  double                minimum = std::numeric_limits<double>::max();
  double                maximum = std::numeric_limits<double>::lowest();
  // Line by line: the evaluator contracts a B-spline's coefficients once per line where it can.
  const SizeValueType                                     lineLength = outputRegionForThread.GetSize(0);
  std::vector<typename JacobianEvaluatorType::PointType>  points(lineLength);
  std::vector<typename JacobianEvaluatorType::MatrixType> jacobians(lineLength);
  for (ImageScanlineIterator<OutputImageType> it(output, outputRegionForThread); !it.IsAtEnd(); it.NextLine())
  {
    IndexType index = it.GetIndex();
    for (SizeValueType k = 0; k < lineLength; ++k, ++index[0])
    {
      output->TransformIndexToPhysicalPoint(index, points[k]);
    }
    m_JacobianEvaluator.EvaluateRow(points.data(), lineLength, jacobians.data());
    for (SizeValueType k = 0; k < lineLength; ++k, ++it)
    {
      const double determinant = detail::MatrixDeterminant(jacobians[k]);
      it.Set(static_cast<PixelType>(determinant));
      minimum = std::min(minimum, determinant);
      maximum = std::max(maximum, determinant);
    }
    progress.Completed(lineLength);
  }
  const std::lock_guard<std::mutex> lock(m_Mutex);
  m_MinimumDeterminant = std::min(m_MinimumDeterminant, minimum);
  m_MaximumDeterminant = std::max(m_MaximumDeterminant, maximum);
}
} // namespace itk

#endif // itkTransformToJacobianDeterminantImageFilter_hxx
