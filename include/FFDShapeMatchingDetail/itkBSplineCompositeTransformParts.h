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
#ifndef itkBSplineCompositeTransformParts_h
#define itkBSplineCompositeTransformParts_h

#include "itkBSplineTransform.h"
#include "itkCompositeTransform.h"
#include "itkMatrix.h"
#include "itkVector.h"

#include <vector>

namespace itk
{
namespace detail
{
/** \class BSplineCompositeTransformParts
 * \brief A transform taken apart for a B-spline metric: its cubic B-spline (the only part optimized) and the fixed
 * transforms applied after it, composed into one affine map y = M z + c when they are all linear.
 *
 * Resolve() accepts a cubic BSplineTransform<double, VDimension, 3>, or a CompositeTransform whose most recent (back)
 * transform is one and is the only one flagged for optimization; it throws an ExceptionObject naming what it found
 * otherwise. BSplineSparseImageToImageMetricv4 evaluates its samples through these parts.
 *
 * \ingroup FFDShapeMatching
 */
template <unsigned int VDimension>
struct BSplineCompositeTransformParts
{
  using TransformType = Transform<double, VDimension, VDimension>;
  using BSplineTransformType = BSplineTransform<double, VDimension, 3>;
  using MatrixType = Matrix<double, VDimension, VDimension>;
  using VectorType = Vector<double, VDimension>;

  const BSplineTransformType *       BSpline{ nullptr };
  std::vector<const TransformType *> Front; // in the order they are applied
  bool                               FrontIsLinear{ true };
  MatrixType                         FrontMatrix{ MatrixType::GetIdentity() };
  VectorType                         FrontOffset = VectorType(0.0);

  /** The parts of a moving transform; throws for a transform the metric cannot differentiate. */
  static BSplineCompositeTransformParts
  Resolve(const TransformType * moving)
  {
    BSplineCompositeTransformParts parts;
    if (moving == nullptr)
    {
      itkGenericExceptionMacro("The moving transform is null");
    }
    parts.BSpline = dynamic_cast<const BSplineTransformType *>(moving);
    if (parts.BSpline != nullptr)
    {
      return parts;
    }

    using CompositeType = CompositeTransform<double, VDimension>;
    const auto * composite = dynamic_cast<const CompositeType *>(moving);
    if (composite == nullptr || composite->GetNumberOfTransforms() == 0)
    {
      itkGenericExceptionMacro("The moving transform must be a cubic BSplineTransform<double, "
                               << VDimension << ", 3> or a CompositeTransform ending with one; it is a "
                               << moving->GetNameOfClass() << '.');
    }
    const SizeValueType numberOfTransforms = composite->GetNumberOfTransforms();
    parts.BSpline =
      dynamic_cast<const BSplineTransformType *>(composite->GetNthTransformConstPointer(numberOfTransforms - 1));
    if (parts.BSpline == nullptr)
    {
      itkGenericExceptionMacro("The most recent (back) transform of the moving CompositeTransform must be a cubic "
                               "BSplineTransform<double, "
                               << VDimension << ", 3>; it is a "
                               << composite->GetNthTransformConstPointer(numberOfTransforms - 1)->GetNameOfClass()
                               << '.');
    }
    if (!composite->GetNthTransformToOptimize(numberOfTransforms - 1))
    {
      itkGenericExceptionMacro(
        "The B-spline transform of the moving CompositeTransform is not flagged for optimization.");
    }
    for (SizeValueType i = numberOfTransforms - 1; i-- > 0;)
    {
      if (composite->GetNthTransformToOptimize(i))
      {
        itkGenericExceptionMacro(
          "Only the B-spline (back) transform of the moving CompositeTransform may be optimized; "
          "transform "
          << i << " is flagged too.");
      }
      const TransformType * front = composite->GetNthTransformConstPointer(i);
      parts.Front.push_back(front);
      parts.FrontIsLinear =
        parts.FrontIsLinear && front->GetTransformCategory() == TransformType::TransformCategoryEnum::Linear;
    }
    if (parts.FrontIsLinear)
    {
      // Compose y = M z + c over the front transforms, in the order they are applied.
      typename TransformType::InputPointType origin;
      origin.Fill(0.0);
      for (const TransformType * front : parts.Front)
      {
        typename TransformType::JacobianPositionType jacobian;
        front->ComputeJacobianWithRespectToPosition(origin, jacobian);
        MatrixType matrix(jacobian);
        const auto offset = front->TransformPoint(origin);
        VectorType newOffset = matrix * parts.FrontOffset;
        for (unsigned int d = 0; d < VDimension; ++d)
        {
          newOffset[d] += offset[d];
        }
        parts.FrontMatrix = matrix * parts.FrontMatrix;
        parts.FrontOffset = newOffset;
      }
    }
    return parts;
  }
};
} // namespace detail
} // namespace itk

#endif // itkBSplineCompositeTransformParts_h
