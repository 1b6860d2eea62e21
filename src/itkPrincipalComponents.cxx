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
#include "FFDShapeMatchingDetail/itkPrincipalComponents.h"
#include "itkMacro.h"

#include "itk_eigen.h"
#include ITK_EIGEN(SVD)
#include <cmath>

namespace itk
{
namespace detail
{
void
ComputePrincipalComponents(const std::vector<std::vector<double>> & examples,
                           unsigned int                             numberOfComponents,
                           std::vector<double> &                    mean,
                           std::vector<std::vector<double>> &       components,
                           std::vector<double> &                    standardDeviations)
{
  if (examples.size() < 2)
  {
    itkGenericExceptionMacro(<< "Principal components need at least two examples, got " << examples.size());
  }
  const std::size_t length = examples[0].size();
  const std::size_t count = examples.size();
  for (const auto & example : examples)
  {
    if (example.size() != length || length == 0)
    {
      itkGenericExceptionMacro(<< "The examples must be non-empty coefficient vectors of equal length");
    }
  }
  mean.assign(length, 0.0);
  for (const auto & example : examples)
  {
    for (std::size_t i = 0; i < length; ++i)
    {
      mean[i] += example[i] / static_cast<double>(count);
    }
  }
  Eigen::MatrixXd centred(length, count);
  for (std::size_t j = 0; j < count; ++j)
  {
    for (std::size_t i = 0; i < length; ++i)
    {
      centred(i, j) = examples[j][i] - mean[i];
    }
  }
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(centred, Eigen::ComputeThinU);
  const auto &                            singularValues = svd.singularValues();
  const auto &                            u = svd.matrixU();
  components.clear();
  standardDeviations.clear();
  const double largest = singularValues.size() > 0 ? singularValues[0] : 0.0;
  for (Eigen::Index k = 0; k < singularValues.size() && components.size() < numberOfComponents; ++k)
  {
    if (!(singularValues[k] > 1e-12 * largest) || largest == 0.0)
    {
      break;
    }
    std::vector<double> component(length);
    for (std::size_t i = 0; i < length; ++i)
    {
      component[i] = u(static_cast<Eigen::Index>(i), k);
    }
    components.push_back(std::move(component));
    standardDeviations.push_back(singularValues[k] / std::sqrt(static_cast<double>(count - 1)));
  }
}

} // namespace detail
} // namespace itk
