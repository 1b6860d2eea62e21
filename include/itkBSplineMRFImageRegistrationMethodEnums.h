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
#ifndef itkBSplineMRFImageRegistrationMethodEnums_h
#define itkBSplineMRFImageRegistrationMethodEnums_h

#include "FFDShapeMatchingExport.h"
#include <cstdint>
#include <ostream>

namespace itk
{
/** \class BSplineMRFImageRegistrationMethodEnums
 * \brief Enumerations of BSplineMRFImageRegistrationMethod.
 *
 * \c Similarity: the pointwise dissimilarity of the unary costs.
 * - \c MutualInformation: minus the pointwise mutual information \f$-\log \frac{p(f,m)}{p(f)p(m)}\f$ of a
 *   Parzen-windowed joint histogram of the fixed and (warped) moving intensities;
 * - \c SumOfSquaredDifferences: \f$(f - m)^2\f$;
 * - \c SumOfAbsoluteDifferences: \f$|f - m|\f$;
 * - \c NormalizedCrossCorrelation: one minus the correlation of f and m over a control point's support,
 *   weighted by its B-spline weights.
 *
 * \c PairwiseFunction: the regularization \f$\rho\f$ of the difference v of two neighbouring control points'
 * displacements, in control spacings: \c Quadratic \f$|v|^2\f$, \c Absolute \f$|v|\f$, \c Truncated
 * \f$\min(|v|, \tau)\f$.
 *
 * \c LabelSet: the candidate displacements. \c Sparse: zero and steps along +-x, +-y, +-z;
 * \c SparseWithDiagonals: those plus the 20 diagonal directions of the cube; \c Dense: the full cube of steps.
 *
 * \ingroup FFDShapeMatching
 */
class FFDShapeMatching_EXPORT BSplineMRFImageRegistrationMethodEnums
{
public:
  enum class Similarity : uint8_t
  {
    MutualInformation,
    SumOfSquaredDifferences,
    SumOfAbsoluteDifferences,
    NormalizedCrossCorrelation
  };

  enum class PairwiseFunction : uint8_t
  {
    Quadratic,
    Absolute,
    Truncated
  };

  enum class LabelSet : uint8_t
  {
    Sparse,
    SparseWithDiagonals,
    Dense
  };
};

/** Prints the qualified enumerator name. */
extern FFDShapeMatching_EXPORT std::ostream &
operator<<(std::ostream & out, const BSplineMRFImageRegistrationMethodEnums::Similarity value);

/** Prints the qualified enumerator name. */
extern FFDShapeMatching_EXPORT std::ostream &
operator<<(std::ostream & out, const BSplineMRFImageRegistrationMethodEnums::PairwiseFunction value);

/** Prints the qualified enumerator name. */
extern FFDShapeMatching_EXPORT std::ostream &
operator<<(std::ostream & out, const BSplineMRFImageRegistrationMethodEnums::LabelSet value);
} // namespace itk

#endif // itkBSplineMRFImageRegistrationMethodEnums_h
