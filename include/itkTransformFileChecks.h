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
#ifndef itkTransformFileChecks_h
#define itkTransformFileChecks_h

#include "FFDShapeMatchingExport.h"
#include <cstddef>
#include <string>

/** \file itkTransformFileChecks.h
 * \brief Checks of B-spline grids and ITK text transform files before ITK builds transforms from them.
 *
 * ITK 5.2's BSplineTransform takes its grid from its fixed parameters without checking them: a negative or
 * fractional grid size is converted to an unsigned size (undefined behaviour), a huge one allocates the
 * coefficient images before the parameters are compared with it. The module checks the values first, so that a
 * damaged transform file or template file ends in a message rather than a crash.
 *
 * \ingroup FFDShapeMatching
 */

namespace itk
{
/** Largest number of B-spline control points per axis the checks accept (a grid of 2^16 points per axis already
 * needs more memory than any machine the module runs on). */
constexpr double MaximumBSplineGridSizeAlongAxis = 65536.0;

/** Checks the fixed parameters of a BSplineTransform of the given dimension: (dimension) grid sizes, origin,
 * spacing, direction, in ITK's order. Grid sizes must be whole numbers in [1, MaximumBSplineGridSizeAlongAxis],
 * every value finite, spacings positive. When numberOfParameters is not negative, it must equal dimension times the
 * number of grid points. Returns the problem in one line, or "" when the values make a valid grid. */
FFDShapeMatching_EXPORT std::string
                        FindProblemInBSplineFixedParameters(const double * fixedParameters,
                                                            std::size_t    numberOfFixedParameters,
                                                            unsigned int   dimension,
                                                            long long      numberOfParameters = -1);

/** Checks an ITK text transform file (.tfm, .txt: "Transform:", "Parameters:", "FixedParameters:" lines) for what
 * ITK's reader does not check: every value a finite number, and the fixed parameters of every BSplineTransform
 * (see FindProblemInBSplineFixedParameters) and of every ParametricTemplateTransform (whose first fixed parameters
 * are a B-spline grid). Returns the problem in one line naming the transform, or "" (also for files that are not
 * text transform files: ITK's reader reports those). */
FFDShapeMatching_EXPORT std::string
                        FindProblemInTextTransformFile(const std::string & fileName);
} // namespace itk

#endif // itkTransformFileChecks_h
