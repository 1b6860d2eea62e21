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
#include "FFDShapeMatchingDetail/itkMattesMutualInformation.h"
#include "itkCompensatedSummation.h"
#include "itkNumericTraits.h"

#include <cmath>
#include <limits>

namespace itk
{
namespace detail
{
bool
ComputeMattesMutualInformation(SizeValueType         bins,
                               std::vector<double> & joint,
                               std::vector<double> & fixedMarginal,
                               std::vector<double> * logRatio,
                               double &              sum)
{
  CompensatedSummation<double> jointSum;
  for (const double bin : joint)
  {
    jointSum += bin;
  }
  if (jointSum.GetSum() < NumericTraits<double>::epsilon())
  {
    return false;
  }

  const double normalization = 1.0 / jointSum.GetSum();
  for (auto & bin : joint)
  {
    bin *= normalization;
  }
  for (auto & bin : fixedMarginal)
  {
    bin *= normalization;
  }
  std::vector<double> movingMarginal(bins, 0.0);
  for (SizeValueType f = 0; f < bins; ++f)
  {
    for (SizeValueType m = 0; m < bins; ++m)
    {
      movingMarginal[m] += joint[f * bins + m];
    }
  }
  constexpr double closeToZero = std::numeric_limits<double>::epsilon();
  if (logRatio != nullptr)
  {
    logRatio->assign(bins * bins, 0.0);
  }
  sum = 0.0;
  for (SizeValueType f = 0; f < bins; ++f)
  {
    if (!(fixedMarginal[f] > closeToZero))
    {
      continue;
    }
    const double logFixedMarginal = std::log(fixedMarginal[f]);
    for (SizeValueType m = 0; m < bins; ++m)
    {
      const double p = joint[f * bins + m];
      if (movingMarginal[m] > closeToZero && p > closeToZero)
      {
        const double ratio = std::log(p / movingMarginal[m]);
        sum += p * (ratio - logFixedMarginal);
        if (logRatio != nullptr)
        {
          (*logRatio)[f * bins + m] = ratio;
        }
      }
    }
  }
  return true;
}
} // namespace detail
} // namespace itk
