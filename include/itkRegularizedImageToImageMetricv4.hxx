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
#ifndef itkRegularizedImageToImageMetricv4_hxx
#define itkRegularizedImageToImageMetricv4_hxx

#include "itkRegularizedImageToImageMetricv4.h"

namespace itk
{
template <typename TImageToImageMetric>
RegularizedImageToImageMetricv4<TImageToImageMetric>::RegularizedImageToImageMetricv4()
{
  m_Penalty = PenaltyType::New();
}

template <typename TImageToImageMetric>
auto
RegularizedImageToImageMetricv4<TImageToImageMetric>::GetRegularizedTransform() const -> const BSplineTransformType *
{
  using CompositeType = CompositeTransform<ParametersValueType, ImageDimension>;
  const auto * moving = this->GetMovingTransform();
  if (const auto * bspline = dynamic_cast<const BSplineTransformType *>(moving))
  {
    return bspline;
  }
  if (const auto * composite = dynamic_cast<const CompositeType *>(moving))
  {
    if (composite->GetNumberOfTransforms() > 0)
    {
      return dynamic_cast<const BSplineTransformType *>(composite->GetBackTransform());
    }
  }
  return nullptr;
}

template <typename TImageToImageMetric>
void
RegularizedImageToImageMetricv4<TImageToImageMetric>::Initialize()
{
  Superclass::Initialize();
  if (m_Penalty->IsActive() && this->GetRegularizedTransform() == nullptr)
  {
    itkExceptionMacro(<< "Regularization weights are set, but the moving transform is neither a cubic "
                         "BSplineTransform nor a CompositeTransform ending with one");
  }
}

template <typename TImageToImageMetric>
auto
RegularizedImageToImageMetricv4<TImageToImageMetric>::GetValue() const -> MeasureType
{
  m_LastImageMetricValue = Superclass::GetValue();
  m_LastPenaltyValue = 0.0;
  if (m_Penalty->IsActive())
  {
    m_LastPenaltyValue = m_Penalty->Evaluate(*this->GetRegularizedTransform(), nullptr);
  }
  return m_LastImageMetricValue + m_LastPenaltyValue;
}

template <typename TImageToImageMetric>
void
RegularizedImageToImageMetricv4<TImageToImageMetric>::GetDerivative(DerivativeType & derivative) const
{
  MeasureType value;
  this->GetValueAndDerivative(value, derivative);
}

template <typename TImageToImageMetric>
void
RegularizedImageToImageMetricv4<TImageToImageMetric>::GetValueAndDerivative(MeasureType &    value,
                                                                            DerivativeType & derivative) const
{
  Superclass::GetValueAndDerivative(value, derivative);
  m_LastImageMetricValue = value;
  m_LastPenaltyValue = 0.0;
  if (m_Penalty->IsActive())
  {
    // v4 derivatives point downhill: subtract the penalty's gradient.
    m_LastPenaltyValue = m_Penalty->Evaluate(*this->GetRegularizedTransform(), &derivative, -1.0);
    value += m_LastPenaltyValue;
  }
}

template <typename TImageToImageMetric>
void
RegularizedImageToImageMetricv4<TImageToImageMetric>::PrintSelf(std::ostream & os, Indent indent) const
{
  Superclass::PrintSelf(os, indent);
  itkPrintSelfObjectMacro(Penalty);
  os << indent << "LastImageMetricValue: " << m_LastImageMetricValue << std::endl;
  os << indent << "LastPenaltyValue: " << m_LastPenaltyValue << std::endl;
}
} // namespace itk

#endif // itkRegularizedImageToImageMetricv4_hxx
