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
#ifndef itkPrincipalComponents_h
#define itkPrincipalComponents_h

#include "FFDShapeMatchingExport.h"

#include <vector>

namespace itk
{
namespace detail
{
/** Principal components of example vectors (Eigen's JacobiSVD of the centred examples): their mean, the
 * numberOfComponents leading unit components, and the standard deviation along each (singular value / sqrt(n - 1)).
 * Components with zero deviation are dropped. Throws an ExceptionObject for fewer than two examples or vectors of
 * unequal or zero length. ParametricTemplateTransform builds its principal-component templates with it. */
FFDShapeMatching_EXPORT void
ComputePrincipalComponents(const std::vector<std::vector<double>> & examples,
                           unsigned int                             numberOfComponents,
                           std::vector<double> &                    mean,
                           std::vector<std::vector<double>> &       components,
                           std::vector<double> &                    standardDeviations);
} // namespace detail
} // namespace itk

#endif // itkPrincipalComponents_h
