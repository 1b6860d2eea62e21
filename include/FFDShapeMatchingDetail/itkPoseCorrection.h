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
#ifndef itkPoseCorrection_h
#define itkPoseCorrection_h

#include "itkMacro.h"
#include "itkMatrixOffsetTransformBase.h"
#include "itkTransform.h"

#include <array>
#include <cmath>

namespace itk
{
namespace detail
{
/** A small similarity about a centre c, applied after a pose:
 * \f$\delta(p) = e^{s} R(\omega) (p - c) + c + t\f$, with \f$R(\omega)\f$ the rotation by the rotation vector
 * \f$\omega\f$ (radians; its direction is the axis, its length the angle). The seven numbers are kept in one array,
 * \f$(\omega_x, \omega_y, \omega_z, t_x, t_y, t_z, s)\f$, so that a search can step along each of them.
 *
 * \ingroup FFDShapeMatching
 */
using PoseCorrectionParameters = std::array<double, 7>;

/** The rotation matrix of the rotation vector \c omega (radians), by Rodrigues' formula. */
inline Matrix<double, 3, 3>
RotationMatrixOfVector(const double omega[3])
{
  const double         angle = std::sqrt(omega[0] * omega[0] + omega[1] * omega[1] + omega[2] * omega[2]);
  Matrix<double, 3, 3> rotation;
  rotation.SetIdentity();
  if (angle <= 0.0)
  {
    return rotation;
  }
  const double k[3] = { omega[0] / angle, omega[1] / angle, omega[2] / angle };
  const double c = std::cos(angle);
  const double s = std::sin(angle);
  for (unsigned int i = 0; i < 3; ++i)
  {
    for (unsigned int j = 0; j < 3; ++j)
    {
      rotation(i, j) = (1.0 - c) * k[i] * k[j] + (i == j ? c : 0.0);
    }
  }
  rotation(0, 1) -= s * k[2];
  rotation(1, 0) += s * k[2];
  rotation(0, 2) += s * k[1];
  rotation(2, 0) -= s * k[1];
  rotation(1, 2) -= s * k[0];
  rotation(2, 1) += s * k[0];
  return rotation;
}

/** The pose \c pose followed by the correction \c correction about \c center, as one transform of the pose's own
 * type (a copy of \c pose: VersorRigid3DTransform, Similarity3DTransform or AffineTransform, or any other
 * MatrixOffsetTransformBase whose SetMatrix() accepts the product): if pose(x) = M x + o, the result is
 * x -> e^s R (M x + o - c) + c + t. Its centre is the pose's. A rigid pose only takes a correction without scale
 * (s = 0); a transform that is not a MatrixOffsetTransformBase, or a correction its type cannot hold, throws an
 * ExceptionObject. */
template <typename TTransform>
typename TTransform::Pointer
ComposePoseCorrection(const TTransform *                          pose,
                      const typename TTransform::InputPointType & center,
                      const PoseCorrectionParameters &            correction)
{
  using LinearType = MatrixOffsetTransformBase<double, 3, 3>;
  const auto * linear = dynamic_cast<const LinearType *>(pose);
  if (linear == nullptr)
  {
    itkGenericExceptionMacro(<< "ComposePoseCorrection: the pose must be a MatrixOffsetTransformBase (rigid, "
                             << "similarity or affine), not a " << (pose ? pose->GetNameOfClass() : "null pointer"));
  }
  const Matrix<double, 3, 3> rotation = RotationMatrixOfVector(correction.data());
  const double               scale = std::exp(correction[6]);
  const auto                 matrix = linear->GetMatrix();
  const auto                 offset = linear->GetOffset();
  Matrix<double, 3, 3>       composedMatrix = rotation * matrix;
  composedMatrix *= scale;
  typename LinearType::OutputVectorType composedOffset;
  for (unsigned int i = 0; i < 3; ++i)
  {
    double sum = 0.0;
    for (unsigned int j = 0; j < 3; ++j)
    {
      sum += rotation(i, j) * (offset[j] - center[j]);
    }
    composedOffset[i] = scale * sum + center[i] + correction[3 + i];
  }
  typename TTransform::Pointer copy = pose->Clone();
  auto *                       composed = dynamic_cast<LinearType *>(copy.GetPointer());
  composed->SetMatrix(composedMatrix);
  composed->SetOffset(composedOffset);
  return copy;
}
} // namespace detail
} // namespace itk

#endif // itkPoseCorrection_h
