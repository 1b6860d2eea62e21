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
// Checks of the pose refinement's corrections (itkPoseCorrection.h): the composed transform keeps the pose's type
// and centre and maps every point as the pose followed by the correction, computed point by point here.

#include "FFDShapeMatchingDetail/itkPoseCorrection.h"
#include "itkAffineTransform.h"
#include "itkMath.h"
#include "itkSimilarity3DTransform.h"
#include "itkTranslationTransform.h"
#include "itkVersorRigid3DTransform.h"
#include "gtest/gtest.h"

#include <cmath>

namespace
{
using TransformType = itk::Transform<double, 3, 3>;
using PointType = TransformType::InputPointType;

PointType
MakePoint(double x, double y, double z)
{
  PointType p;
  p[0] = x;
  p[1] = y;
  p[2] = z;
  return p;
}

itk::Vector<double, 3>
Vec(double x, double y, double z)
{
  itk::Vector<double, 3> v;
  v[0] = x;
  v[1] = y;
  v[2] = z;
  return v;
}

// The correction applied to a point, written out: e^s R(omega) (p - c) + c + t, with R from ITK's own versor.
PointType
Corrected(const PointType & p, const PointType & center, const itk::detail::PoseCorrectionParameters & correction)
{
  itk::Vector<double, 3> omega;
  for (unsigned int d = 0; d < 3; ++d)
  {
    omega[d] = correction[d];
  }
  itk::Versor<double> versor;
  const double        angle = omega.GetNorm();
  if (angle > 0.0)
  {
    versor.Set(omega / angle, angle);
  }
  const auto rotated = versor.Transform(p - center);
  PointType  result;
  for (unsigned int d = 0; d < 3; ++d)
  {
    result[d] = std::exp(correction[6]) * rotated[d] + center[d] + correction[3 + d];
  }
  return result;
}

void
ExpectComposition(const TransformType * pose, const itk::detail::PoseCorrectionParameters & correction)
{
  const PointType center = MakePoint(3.0, -2.0, 7.5);
  const auto      composed = itk::detail::ComposePoseCorrection<TransformType>(pose, center, correction);
  ASSERT_NE(composed.GetPointer(), pose);
  EXPECT_STREQ(composed->GetNameOfClass(), pose->GetNameOfClass());
  const auto * linear = dynamic_cast<const itk::MatrixOffsetTransformBase<double, 3, 3> *>(pose);
  const auto * composedLinear =
    dynamic_cast<const itk::MatrixOffsetTransformBase<double, 3, 3> *>(composed.GetPointer());
  ASSERT_NE(composedLinear, nullptr);
  EXPECT_EQ(composedLinear->GetCenter(), linear->GetCenter());
  for (const PointType & p : { MakePoint(0, 0, 0),
                               MakePoint(10, -4, 2),
                               MakePoint(-25, 13, 40),
                               MakePoint(3, -2, 7.5),
                               MakePoint(1e3, 5, -7) })
  {
    const PointType expected = Corrected(pose->TransformPoint(p), center, correction);
    const PointType actual = composed->TransformPoint(p);
    for (unsigned int d = 0; d < 3; ++d)
    {
      EXPECT_NEAR(actual[d], expected[d], 1e-9 * (1.0 + std::abs(expected[d])));
    }
  }
}

itk::Similarity3DTransform<double>::Pointer
MakeSimilarity()
{
  auto                   similarity = itk::Similarity3DTransform<double>::New();
  itk::Vector<double, 3> axis;
  axis[0] = 0.3;
  axis[1] = -0.5;
  axis[2] = 0.8;
  axis.Normalize();
  similarity->SetCenter(MakePoint(1.0, 2.0, 3.0));
  similarity->SetRotation(axis, 2.4);
  similarity->SetScale(0.7);
  similarity->SetTranslation(Vec(40.0, -12.0, 5.0));
  return similarity;
}
} // namespace

TEST(PoseCorrection, RotationMatrixOfVector)
{
  // 90 degrees about z turns x into y; the zero vector is the identity.
  const double quarter[3] = { 0.0, 0.0, 0.5 * itk::Math::pi };
  const auto   rotation = itk::detail::RotationMatrixOfVector(quarter);
  EXPECT_NEAR(rotation(0, 0), 0.0, 1e-15);
  EXPECT_NEAR(rotation(1, 0), 1.0, 1e-15);
  EXPECT_NEAR(rotation(0, 1), -1.0, 1e-15);
  EXPECT_NEAR(rotation(2, 2), 1.0, 1e-15);
  const double zero[3] = { 0.0, 0.0, 0.0 };
  const auto   identity = itk::detail::RotationMatrixOfVector(zero);
  for (unsigned int i = 0; i < 3; ++i)
  {
    for (unsigned int j = 0; j < 3; ++j)
    {
      EXPECT_EQ(identity(i, j), i == j ? 1.0 : 0.0);
    }
  }
}

TEST(PoseCorrection, SimilarityAndAffineTakeEveryCorrection)
{
  const auto similarity = MakeSimilarity();
  ExpectComposition(similarity, { 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0 });
  ExpectComposition(similarity, { 0.05, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0 });
  ExpectComposition(similarity, { 0.0, 0.0, 0.0, 0.0, 1.5, 0.0, 0.0 });
  ExpectComposition(similarity, { 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, std::log(1.02) });
  ExpectComposition(similarity, { -0.03, 0.02, 0.07, 1.0, -2.0, 0.5, std::log(0.97) });

  auto                      affine = itk::AffineTransform<double, 3>::New();
  itk::Matrix<double, 3, 3> matrix;
  const double              values[9] = { 1.1, 0.2, -0.1, 0.05, 0.9, 0.3, -0.2, 0.1, 1.3 };
  for (unsigned int i = 0; i < 9; ++i)
  {
    matrix(i / 3, i % 3) = values[i];
  }
  affine->SetCenter(MakePoint(-4.0, 0.5, 2.0));
  affine->SetMatrix(matrix);
  affine->SetTranslation(Vec(3.0, 2.0, -1.0));
  ExpectComposition(affine, { -0.03, 0.02, 0.07, 1.0, -2.0, 0.5, std::log(1.05) });
}

TEST(PoseCorrection, RigidTakesRotationsAndShiftsOnly)
{
  auto rigid = itk::VersorRigid3DTransform<double>::New();
  rigid->SetCenter(MakePoint(5.0, 5.0, 5.0));
  itk::Vector<double, 3> axis;
  axis[0] = 1.0;
  axis[1] = 1.0;
  axis[2] = 0.0;
  axis.Normalize();
  rigid->SetRotation(axis, 1.0);
  rigid->SetTranslation(Vec(-3.0, 8.0, 1.0));
  ExpectComposition(rigid, { 0.04, -0.01, 0.02, 0.3, 0.0, -1.5, 0.0 });
  // A scaling is not a rigid motion: the rigid transform refuses the scaled matrix.
  EXPECT_THROW(itk::detail::ComposePoseCorrection<TransformType>(
                 rigid.GetPointer(), MakePoint(0, 0, 0), { 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, std::log(1.1) }),
               itk::ExceptionObject);
}

TEST(PoseCorrection, RejectsTransformsWithoutMatrixAndOffset)
{
  auto translation = itk::TranslationTransform<double, 3>::New();
  EXPECT_THROW(itk::detail::ComposePoseCorrection<TransformType>(translation.GetPointer(), MakePoint(0, 0, 0), {}),
               itk::ExceptionObject);
  EXPECT_THROW(itk::detail::ComposePoseCorrection<TransformType>(nullptr, MakePoint(0, 0, 0), {}),
               itk::ExceptionObject);
}
