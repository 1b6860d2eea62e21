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
#ifndef itkFFDShapeMatchingCompatibility_h
#define itkFFDShapeMatchingCompatibility_h

#include "itkMacro.h"

/** \file itkFFDShapeMatchingCompatibility.h
 * \brief The one place where the module meets the differences between the ITK releases it builds against (5.2, 5.4
 * and 6). The rest of the module is written in today's API; what an older ITK lacks is supplied here, keyed on
 * ITK_VERSION_MAJOR and ITK_VERSION_MINOR.
 * \ingroup FFDShapeMatching
 */

#if ITK_VERSION_MAJOR < 5 || (ITK_VERSION_MAJOR == 5 && ITK_VERSION_MINOR < 4)
/** itkOverrideGetNameOfClassMacro (ITK 5.4; itkTypeMacro is deprecated there and removed under
 * ITK_FUTURE_LEGACY_REMOVE), supplied for older releases. */
#  define itkOverrideGetNameOfClassMacro(thisClass)                                                                    \
    const char * GetNameOfClass() const override                                                                       \
    {                                                                                                                  \
      return #thisClass;                                                                                               \
    }                                                                                                                  \
    ITK_MACROEND_NOOP_STATEMENT
#endif

namespace itk
{
namespace detail
{
/** The interpolation weights and parameter indices of one point's B-spline support, as
 * BSplineBaseTransform::TransformPoint(point, mapped, weights, indices, inside) fills them: dynamic arrays sized
 * for the transform before ITK 5.3, fixed-size arrays from 5.3 on. Iterate with Size().
 * \ingroup FFDShapeMatching
 */
template <typename TBSplineTransform>
struct BSplineSupportArrays
{
  typename TBSplineTransform::WeightsType             Weights;
  typename TBSplineTransform::ParameterIndexArrayType Indices;

  explicit BSplineSupportArrays(const TBSplineTransform & transform)
  {
#if ITK_VERSION_MAJOR < 5 || (ITK_VERSION_MAJOR == 5 && ITK_VERSION_MINOR < 3)
    Weights.SetSize(transform.GetNumberOfWeights());
    Indices.SetSize(transform.GetNumberOfWeights());
#else
    (void)transform;
#endif
  }

  /** Fills the arrays for a point; false when the point is outside the transform's grid. */
  template <typename TPoint>
  bool
  Evaluate(const TBSplineTransform & transform, const TPoint & point)
  {
    typename TBSplineTransform::OutputPointType mapped;
    bool                                        inside = false;
    transform.TransformPoint(point, mapped, Weights, Indices, inside);
    return inside;
  }
};

/** The index of an image iterator's position (one without an index of its own, such as ImageScanlineIterator):
 * ComputeIndex() from ITK 6 on, where GetIndex() is deprecated, GetIndex() before.
 * \ingroup FFDShapeMatching
 */
template <typename TIterator>
auto
IteratorIndex(const TIterator & iterator)
{
#if ITK_VERSION_MAJOR >= 6
  return iterator.ComputeIndex();
#else
  return iterator.GetIndex();
#endif
}
} // namespace detail
} // namespace itk

#endif
