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
#ifndef itkMattesMutualInformation_h
#define itkMattesMutualInformation_h

#include "FFDShapeMatchingExport.h"
#include "itkIntTypes.h"

#include <vector>

namespace itk
{
namespace detail
{
/** Mattes' mutual information (Mattes et al. 2003, eqs. 3-4) of a joint histogram of bins x bins counts (fixed
 * bin-major) and its fixed marginal: both are normalized in place to probabilities, sum is set to
 * sum p(f, m) log(p(f, m) / (p(f) p(m))) over the bins with non-zero probabilities, and, when logRatio is given, it
 * is filled with log(p(f, m) / p(m)) per bin (0 where undefined), the factors of the derivative (eq. 11). Returns
 * false, changing nothing, when the histogram sums to zero. BSplineSparseImageToImageMetricv4 computes its value
 * with it, as ITK's MattesMutualInformationImageToImageMetricv4 does. */
FFDShapeMatching_EXPORT bool
ComputeMattesMutualInformation(SizeValueType         bins,
                               std::vector<double> & joint,
                               std::vector<double> & fixedMarginal,
                               std::vector<double> * logRatio,
                               double &              sum);
} // namespace detail
} // namespace itk

#endif // itkMattesMutualInformation_h
