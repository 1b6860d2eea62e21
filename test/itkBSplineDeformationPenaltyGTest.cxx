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
#include "FFDShapeMatchingDetail/itkCubicBSplineKernel.h"
#include "itkImage.h"
#include "itkMersenneTwisterRandomVariateGenerator.h"
#include "gtest/gtest.h"

namespace
{
using PenaltyType = itk::BSplineDeformationPenalty<double, 3>;
using TransformType = PenaltyType::BSplineTransformType;

/** A cubic B-spline transform over the box from \c origin with the given physical dimensions and mesh size. */
TransformType::Pointer
MakeTransform(const TransformType::MeshSizeType &           mesh,
              const TransformType::PhysicalDimensionsType & dimensions,
              const TransformType::OriginType &             origin)
{
  auto                         transform = TransformType::New();
  TransformType::DirectionType direction;
  direction.SetIdentity();
  transform->SetTransformDomainOrigin(origin);
  transform->SetTransformDomainPhysicalDimensions(dimensions);
  transform->SetTransformDomainMeshSize(mesh);
  transform->SetTransformDomainDirection(direction);
  transform->SetIdentity();
  return transform;
}

/** A cubic B-spline transform over [0, 40] x [0, 30] x [0, 20] mm with the given mesh size. */
TransformType::Pointer
MakeTransform(unsigned int meshSize)
{
  TransformType::PhysicalDimensionsType dimensions;
  dimensions[0] = 40.0;
  dimensions[1] = 30.0;
  dimensions[2] = 20.0;
  TransformType::MeshSizeType mesh;
  mesh.Fill(meshSize);
  TransformType::OriginType origin;
  origin.Fill(0.0);
  return MakeTransform(mesh, dimensions, origin);
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

TEST(BSplineDeformationPenalty, BendingEnergyMatchesQuadratureOfSecondDerivatives)
{
  // Random coefficients on a lattice with a different number of cells and a different spacing along each axis: the
  // energy against a brute-force Gauss quadrature of every second derivative (mixed ones twice) of every
  // displacement component, averaged over the domain.
  TransformType::PhysicalDimensionsType dimensions;
  dimensions[0] = 40.0;
  dimensions[1] = 18.0;
  dimensions[2] = 25.0;
  TransformType::MeshSizeType mesh;
  mesh[0] = 5;
  mesh[1] = 3;
  mesh[2] = 4;
  TransformType::OriginType origin;
  origin.Fill(-3.0);
  auto transform = MakeTransform(mesh, dimensions, origin);
  RandomizeParameters(*transform, 2.0, 11);

  const TransformType::ParametersType parameters = transform->GetParameters();
  const size_t                        n0 = mesh[0] + 3;
  const size_t                        n1 = mesh[1] + 3;
  const size_t                        count = n0 * n1 * (mesh[2] + 3);
  double                              spacing[3];
  for (unsigned int a = 0; a < 3; ++a)
  {
    spacing[a] = dimensions[a] / mesh[a];
  }
  // The derivative of the given orders of displacement component d at lattice coordinates t (control point i at
  // t = i - 1), in physical units.
  const auto derivative = [&](unsigned int d, const double t[3], const unsigned int orders[3]) {
    // The support: control points floor(t) .. floor(t) + 3 along each axis (every other weight is zero).
    size_t first[3];
    for (unsigned int a = 0; a < 3; ++a)
    {
      first[a] = static_cast<size_t>(std::floor(t[a]));
    }
    double sum = 0.0;
    for (size_t k = first[2]; k < first[2] + 4; ++k)
    {
      for (size_t j = first[1]; j < first[1] + 4; ++j)
      {
        for (size_t i = first[0]; i < first[0] + 4; ++i)
        {
          const size_t at[3] = { i, j, k };
          double       weight = 1.0;
          for (unsigned int a = 0; a < 3; ++a)
          {
            weight *= itk::detail::CubicBSplineOfOrder(t[a] - (static_cast<double>(at[a]) - 1.0), orders[a]) /
                      std::pow(spacing[a], orders[a]);
          }
          sum += weight * parameters[d * count + i + n0 * (j + n1 * k)];
        }
      }
    }
    return sum;
  };
  // The lattice coordinates above are the transform's: the displacement agrees with TransformPoint.
  const double                  probeT[3] = { 2.3, 1.6, 0.7 };
  const unsigned int            none[3] = { 0, 0, 0 };
  TransformType::InputPointType probe;
  for (unsigned int a = 0; a < 3; ++a)
  {
    probe[a] = origin[a] + probeT[a] * spacing[a];
  }
  EXPECT_NEAR(transform->TransformPoint(probe)[1] - probe[1], derivative(1, probeT, none), 1e-9);

  // 4-point Gauss-Legendre per axis and cell: exact for the squared derivatives (degree 6 per axis).
  const double nodes[4] = { 0.0694318442029737, 0.3300094782075719, 0.6699905217924281, 0.9305681557970263 };
  const double weights[4] = { 0.1739274225687269, 0.3260725774312731, 0.3260725774312731, 0.1739274225687269 };
  double       sum = 0.0;
  for (unsigned int cz = 0; cz < mesh[2]; ++cz)
  {
    for (unsigned int cy = 0; cy < mesh[1]; ++cy)
    {
      for (unsigned int cx = 0; cx < mesh[0]; ++cx)
      {
        for (unsigned int q = 0; q < 64; ++q)
        {
          const double t[3] = { cx + nodes[q % 4], cy + nodes[(q / 4) % 4], cz + nodes[q / 16] };
          const double w = weights[q % 4] * weights[(q / 4) % 4] * weights[q / 16];
          for (unsigned int d = 0; d < 3; ++d)
          {
            for (unsigned int a = 0; a < 3; ++a)
            {
              for (unsigned int b = a; b < 3; ++b)
              {
                unsigned int orders[3] = { 0, 0, 0 };
                ++orders[a];
                ++orders[b];
                const double value = derivative(d, t, orders);
                sum += (a == b ? 1.0 : 2.0) * w * value * value;
              }
            }
          }
        }
      }
    }
  }
  const double expected = sum / static_cast<double>(mesh[0] * mesh[1] * mesh[2]);
  auto         penalty = PenaltyType::New();
  penalty->SetBendingEnergyWeight(1.0);
  EXPECT_NEAR(penalty->Evaluate(*transform, nullptr), expected, 1e-9 * expected);
  EXPECT_GT(expected, 0.0);
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
