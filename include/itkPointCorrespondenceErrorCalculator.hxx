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
#ifndef itkPointCorrespondenceErrorCalculator_hxx
#define itkPointCorrespondenceErrorCalculator_hxx

#include "itkPointCorrespondenceErrorCalculator.h"
#include <cmath>

namespace itk
{
template <typename TMovedMesh, typename TReferenceMesh>
void
PointCorrespondenceErrorCalculator<TMovedMesh, TReferenceMesh>::Compute()
{
  if (m_MovedMesh == nullptr || m_ReferenceMesh == nullptr)
  {
    itkExceptionMacro(<< "Both the moved mesh and the reference mesh must be set");
  }
  CorrespondenceContainerType pairs = m_Correspondences;
  if (pairs.empty() && m_MovedMesh->GetPoints() != nullptr)
  {
    for (auto it = m_MovedMesh->GetPoints()->Begin(); it != m_MovedMesh->GetPoints()->End(); ++it)
    {
      pairs.emplace_back(it.Index(), it.Index());
    }
  }
  if (pairs.empty())
  {
    itkExceptionMacro(<< "There is no correspondence: the moved mesh has no vertex");
  }
  m_Errors.assign(pairs.size(), 0.0);
  double sum = 0.0;
  double sumOfSquares = 0.0;
  m_MaximumError = 0.0;
  for (std::size_t k = 0; k < pairs.size(); ++k)
  {
    typename MovedMeshType::PointType     moved{};
    typename ReferenceMeshType::PointType reference{};
    if (!m_MovedMesh->GetPoint(pairs[k].first, &moved))
    {
      itkExceptionMacro(<< "The moved mesh has no point " << pairs[k].first);
    }
    if (!m_ReferenceMesh->GetPoint(pairs[k].second, &reference))
    {
      itkExceptionMacro(<< "The reference mesh has no point " << pairs[k].second);
    }
    double squared = 0.0;
    for (unsigned int d = 0; d < MovedMeshType::PointDimension; ++d)
    {
      const double difference = static_cast<double>(moved[d]) - static_cast<double>(reference[d]);
      squared += difference * difference;
    }
    m_Errors[k] = std::sqrt(squared);
    sum += m_Errors[k];
    sumOfSquares += squared;
    m_MaximumError = std::max(m_MaximumError, m_Errors[k]);
  }
  m_MeanError = sum / static_cast<double>(pairs.size());
  m_RootMeanSquareError = std::sqrt(sumOfSquares / static_cast<double>(pairs.size()));
  ErrorContainerType values = m_Errors;
  m_MedianError = detail::ComputePercentile(values, 0.5);
  m_Percentile95Error = detail::ComputePercentile(values, 0.95);
  this->Modified();
}

template <typename TMovedMesh, typename TReferenceMesh>
void
PointCorrespondenceErrorCalculator<TMovedMesh, TReferenceMesh>::PrintSelf(std::ostream & os, Indent indent) const
{
  Superclass::PrintSelf(os, indent);
  itkPrintSelfObjectMacro(MovedMesh);
  itkPrintSelfObjectMacro(ReferenceMesh);
  os << indent << "Correspondences: " << m_Correspondences.size() << " pairs" << std::endl;
  os << indent << "MeanError: " << m_MeanError << std::endl;
  os << indent << "RootMeanSquareError: " << m_RootMeanSquareError << std::endl;
  os << indent << "MedianError: " << m_MedianError << std::endl;
  os << indent << "Percentile95Error: " << m_Percentile95Error << std::endl;
  os << indent << "MaximumError: " << m_MaximumError << std::endl;
  os << indent << "Errors: " << m_Errors.size() << " values" << std::endl;
}
} // namespace itk

#endif // itkPointCorrespondenceErrorCalculator_hxx
