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
#include "itkBSplineDeformationPenalty.h"
#include "itkBSplineTransformInitializer.h"
#include "itkImage.h"
#include "itkMersenneTwisterRandomVariateGenerator.h"
#include "gtest/gtest.h"

namespace
{
using PenaltyType = itk::BSplineDeformationPenalty<double, 3>;
using TransformType = PenaltyType::BSplineTransformType;

/** A cubic B-spline transform over [0, 40] x [0, 30] x [0, 20] mm with the given mesh size. */
TransformType::Pointer
MakeTransform(unsigned int meshSize)
{
  auto                                  transform = TransformType::New();
  TransformType::PhysicalDimensionsType dimensions;
  dimensions[0] = 40.0;
  dimensions[1] = 30.0;
  dimensions[2] = 20.0;
  TransformType::MeshSizeType mesh;
  mesh.Fill(meshSize);
  TransformType::OriginType origin;
  origin.Fill(0.0);
  TransformType::DirectionType direction;
  direction.SetIdentity();
  transform->SetTransformDomainOrigin(origin);
  transform->SetTransformDomainPhysicalDimensions(dimensions);
  transform->SetTransformDomainMeshSize(mesh);
  transform->SetTransformDomainDirection(direction);
  transform->SetIdentity();
  return transform;
}

/** Physical position along an axis of each control point of the transform. */
std::vector<itk::Point<double, 3>>
ControlPointPositions(const TransformType & transform)
{
  const auto                                                       image = transform.GetCoefficientImages()[0];
  std::vector<itk::Point<double, 3>>                               positions;
  itk::ImageRegionConstIteratorWithIndex<TransformType::ImageType> it(image, image->GetLargestPossibleRegion());
  for (; !it.IsAtEnd(); ++it)
  {
    itk::Point<double, 3> point;
    image->TransformIndexToPhysicalPoint(it.GetIndex(), point);
    positions.push_back(point);
  }
  return positions;
}

void
RandomizeParameters(TransformType & transform, double amplitude, unsigned int seed)
{
  auto random = itk::Statistics::MersenneTwisterRandomVariateGenerator::New();
  random->SetSeed(seed);
  TransformType::ParametersType parameters(transform.GetNumberOfParameters());
  for (unsigned int i = 0; i < parameters.GetSize(); ++i)
  {
    parameters[i] = random->GetUniformVariate(-amplitude, amplitude);
  }
  transform.SetParameters(parameters);
}

/** Central finite-difference check of Evaluate()'s gradient on a sample of parameters. */
void
ExpectGradientMatchesFiniteDifferences(PenaltyType & penalty, TransformType & transform, double tolerance)
{
  PenaltyType::DerivativeType gradient(transform.GetNumberOfParameters());
  gradient.Fill(0.0);
  penalty.Evaluate(transform, &gradient);
  const TransformType::ParametersType base = transform.GetParameters();
  const double                        step = 1e-5;
  for (unsigned int i = 0; i < base.GetSize(); i += 37)
  {
    TransformType::ParametersType shifted = base;
    shifted[i] = base[i] + step;
    transform.SetParameters(shifted);
    const double plus = penalty.Evaluate(transform, nullptr);
    shifted[i] = base[i] - step;
    transform.SetParameters(shifted);
    const double minus = penalty.Evaluate(transform, nullptr);
    const double numeric = (plus - minus) / (2.0 * step);
    EXPECT_NEAR(gradient[i], numeric, tolerance * std::max(1.0, std::abs(numeric))) << "parameter " << i;
  }
  transform.SetParameters(base);
}
} // namespace

TEST(BSplineDeformationPenalty, BasicObject)
{
  auto penalty = PenaltyType::New();
  EXPECT_STREQ(penalty->GetNameOfClass(), "BSplineDeformationPenalty");
  EXPECT_FALSE(penalty->IsActive());
  penalty->SetBendingEnergyWeight(-1.0);
  EXPECT_EQ(penalty->GetBendingEnergyWeight(), 0.0);
  penalty->SetFoldingPenaltyWeight(2.0);
  EXPECT_TRUE(penalty->IsActive());
  std::ostringstream printed;
  penalty->Print(printed);
  EXPECT_NE(printed.str().find("FoldingPenaltyWeight: 2"), std::string::npos);
}

TEST(BSplineDeformationPenalty, AffineDisplacementHasNoBendingEnergy)
{
  auto                          transform = MakeTransform(5);
  auto                          positions = ControlPointPositions(*transform);
  const size_t                  n = positions.size();
  TransformType::ParametersType parameters(3 * n);
  for (size_t k = 0; k < n; ++k)
  {
    const auto & p = positions[k];
    parameters[k] = 0.01 * p[0] - 0.02 * p[1] + 0.5;
    parameters[n + k] = 0.03 * p[2];
    parameters[2 * n + k] = -0.01 * p[0] + 0.02 * p[1] + 0.04 * p[2];
  }
  transform->SetParameters(parameters);
  auto penalty = PenaltyType::New();
  penalty->SetBendingEnergyWeight(1.0);
  EXPECT_NEAR(penalty->Evaluate(*transform, nullptr), 0.0, 1e-12);
}

TEST(BSplineDeformationPenalty, QuadraticDisplacementHasExactBendingEnergy)
{
  // Cubic B-splines reproduce x^2 with coefficients x_k^2 - h^2/3: then d^2u_x/dx^2 = 2 everywhere and the
  // domain-averaged bending energy is exactly 4.
  auto                          transform = MakeTransform(4);
  auto                          positions = ControlPointPositions(*transform);
  const double                  h = transform->GetCoefficientImages()[0]->GetSpacing()[0];
  const size_t                  n = positions.size();
  TransformType::ParametersType parameters(3 * n);
  parameters.Fill(0.0);
  for (size_t k = 0; k < n; ++k)
  {
    parameters[k] = positions[k][0] * positions[k][0] - h * h / 3.0;
  }
  transform->SetParameters(parameters);
  TransformType::InputPointType probe;
  probe[0] = 13.7;
  probe[1] = 11.0;
  probe[2] = 4.2;
  EXPECT_NEAR(transform->TransformPoint(probe)[0], probe[0] + probe[0] * probe[0], 1e-9);
  auto penalty = PenaltyType::New();
  penalty->SetBendingEnergyWeight(0.5);
  EXPECT_NEAR(penalty->Evaluate(*transform, nullptr), 0.5 * 4.0, 1e-9);
  EXPECT_NEAR(penalty->GetLastBendingEnergy(), 4.0, 1e-9);
}

TEST(BSplineDeformationPenalty, BendingEnergyGradientMatchesFiniteDifferences)
{
  auto transform = MakeTransform(4);
  RandomizeParameters(*transform, 2.0, 7);
  auto penalty = PenaltyType::New();
  penalty->SetBendingEnergyWeight(0.3);
  ExpectGradientMatchesFiniteDifferences(*penalty, *transform, 1e-5);
}

TEST(BSplineDeformationPenalty, FoldingPenaltyGradientMatchesFiniteDifferences)
{
  auto transform = MakeTransform(3);
  RandomizeParameters(*transform, 6.0, 11);
  auto penalty = PenaltyType::New();
  penalty->SetFoldingPenaltyWeight(2.0);
  penalty->SetFoldingThreshold(0.8);
  const double value = penalty->Evaluate(*transform, nullptr);
  ASSERT_GT(value, 0.0) << "the random deformation must compress some samples below the threshold";
  EXPECT_LT(penalty->GetLastMinimumJacobianDeterminant(), 0.8);
  ExpectGradientMatchesFiniteDifferences(*penalty, *transform, 1e-4);
}

TEST(BSplineDeformationPenalty, IdentityHasNoPenalty)
{
  auto transform = MakeTransform(4);
  auto penalty = PenaltyType::New();
  penalty->SetBendingEnergyWeight(1.0);
  penalty->SetFoldingPenaltyWeight(1.0);
  EXPECT_EQ(penalty->Evaluate(*transform, nullptr), 0.0);
  EXPECT_NEAR(penalty->GetLastMinimumJacobianDeterminant(), 1.0, 1e-12);
}

TEST(BSplineDeformationPenalty, RejectsWrongGradientSize)
{
  auto transform = MakeTransform(3);
  auto penalty = PenaltyType::New();
  penalty->SetBendingEnergyWeight(1.0);
  PenaltyType::DerivativeType gradient(5);
  EXPECT_THROW(penalty->Evaluate(*transform, &gradient), itk::ExceptionObject);
}
