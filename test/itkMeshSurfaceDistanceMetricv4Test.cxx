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
#include "itkMeshSurfaceDistanceMetricv4.h"
#include "itkMeshSurfaceDistanceCalculator.h"
#include "itkMersenneTwisterRandomVariateGenerator.h"
#include "itkParametricTemplateTransform.h"
#include "itkRegularSphereMeshSource.h"
#include "itkTestingMacros.h"
#include "itkTriangleMeshToVoxelImageFilter.h"
#include <cmath>

namespace
{
constexpr unsigned int Dimension = 3;
using MeshType = itk::Mesh<double, Dimension>;
using ImageType = itk::Image<float, Dimension>;
using MetricType = itk::MeshSurfaceDistanceMetricv4<MeshType, MeshType, ImageType>;
using TransformType = itk::ParametricTemplateTransform<double, Dimension>;
using EvaluationEnum = MetricType::EvaluationEnum;

/** An ellipsoid with semi-axes 20, 15 and 12 mm centred at (1, 2, 3), 2562 vertices. */
MeshType::Pointer
MakeEllipsoid()
{
  auto                                               source = itk::RegularSphereMeshSource<MeshType>::New();
  itk::RegularSphereMeshSource<MeshType>::VectorType scale;
  scale[0] = 20.0;
  scale[1] = 15.0;
  scale[2] = 12.0;
  MeshType::PointType center;
  center[0] = 1.0;
  center[1] = 2.0;
  center[2] = 3.0;
  source->SetScale(scale);
  source->SetCenter(center);
  source->SetResolution(4);
  source->Update();
  return source->GetOutput();
}

/** The vertices of the upper half (y > centre), pushed outwards by factor and shifted: a region near the surface. */
MeshType::Pointer
MakeTargetVertices(const MeshType * source, double factor)
{
  auto          target = MeshType::New();
  unsigned long id = 0;
  for (auto it = source->GetPoints()->Begin(); it != source->GetPoints()->End(); ++it)
  {
    const auto & point = it.Value();
    if (point[1] < 2.0)
    {
      continue;
    }
    MeshType::PointType moved;
    moved[0] = 1.0 + factor * (point[0] - 1.0) + 0.4;
    moved[1] = 2.0 + factor * (point[1] - 2.0) - 0.3;
    moved[2] = 3.0 + factor * (point[2] - 3.0) + 0.2 * std::sin(point[0] / 5.0);
    target->SetPoint(id++, moved);
  }
  return target;
}

/** Templates: four random smooth fields on a 7^3 grid over [-30, 32] x [-25, 29] x [-20, 26]. */
TransformType::Pointer
MakeTransform()
{
  auto                                  transform = TransformType::New();
  TransformType::OriginType             origin;
  TransformType::PhysicalDimensionsType extent;
  TransformType::MeshSizeType           meshSize;
  origin[0] = -30.0;
  origin[1] = -25.0;
  origin[2] = -20.0;
  extent[0] = 62.0;
  extent[1] = 54.0;
  extent[2] = 46.0;
  meshSize.Fill(4);
  TransformType::DirectionType direction;
  direction.SetIdentity();
  transform->SetTransformDomain(origin, extent, meshSize, direction);
  auto random = itk::Statistics::MersenneTwisterRandomVariateGenerator::New();
  random->SetSeed(7);
  std::vector<TransformType::CoefficientVectorType> templates(4);
  for (auto & values : templates)
  {
    values.resize(transform->GetNumberOfCoefficients());
    for (auto & value : values)
    {
      value = random->GetNormalVariate();
    }
  }
  transform->SetTemplates(templates);
  TransformType::ParametersType weights(4);
  weights[0] = 0.3;
  weights[1] = -0.2;
  weights[2] = 0.5;
  weights[3] = 0.1;
  transform->SetParameters(weights);
  return transform;
}

/** The v4 derivative (negative gradient) against central differences of the value. */
int
CheckDerivative(MetricType * metric, TransformType * transform, double step, double tolerance, const char * what)
{
  MetricType::MeasureType    value;
  MetricType::DerivativeType derivative;
  metric->GetValueAndDerivative(value, derivative);
  const auto parameters = transform->GetParameters();
  double     largest = 0.0;
  for (unsigned int k = 0; k < derivative.GetSize(); ++k)
  {
    largest = std::max(largest, std::abs(derivative[k]));
  }
  int    status = EXIT_SUCCESS;
  double worst = 0.0;
  for (unsigned int k = 0; k < parameters.GetSize(); ++k)
  {
    auto shifted = parameters;
    shifted[k] += step;
    transform->SetParameters(shifted);
    const double plus = metric->GetValue();
    shifted[k] = parameters[k] - step;
    transform->SetParameters(shifted);
    const double minus = metric->GetValue();
    const double numeric = -(plus - minus) / (2.0 * step);
    worst = std::max(worst, std::abs(numeric - derivative[k]) / largest);
    if (std::abs(numeric - derivative[k]) > tolerance * largest)
    {
      std::cerr << what << ": derivative " << k << " is " << derivative[k] << ", finite differences give " << numeric
                << std::endl;
      status = EXIT_FAILURE;
    }
  }
  transform->SetParameters(parameters);
  std::cout << what << ": value " << value << " mm, largest relative derivative error " << worst << std::endl;
  return status;
}
} // namespace

int
itkMeshSurfaceDistanceMetricv4Test(int argc, char * argv[])
{
  if (argc != 1)
  {
    std::cerr << "Usage: " << itkNameOfTestExecutableMacro(argv) << std::endl;
    return EXIT_FAILURE;
  }
  const auto source = MakeEllipsoid();
  const auto target = MakeTargetVertices(source, 1.05);
  auto       transform = MakeTransform();

  auto metric = MetricType::New();
  ITK_EXERCISE_BASIC_OBJECT_METHODS(metric, MeshSurfaceDistanceMetricv4, ObjectToObjectMetric);
  ITK_TEST_SET_GET_VALUE(EvaluationEnum::LinearDistanceMap, metric->GetEvaluation());
  ITK_TEST_SET_GET_VALUE(1.0, metric->GetDistanceMapSpacing());
  ITK_TEST_SET_GET_VALUE(10.0, metric->GetDistanceMapMargin());
  ITK_TEST_SET_GET_BOOLEAN(metric, UnsignedDistanceMap, false);
  ITK_TEST_EXPECT_TRUE(!metric->SupportsArbitraryVirtualDomainSamples());
  std::cout << EvaluationEnum::BSplineDistanceMap << std::endl;

  // Bad input: no fixed mesh, an empty one, no moving surface.
  metric->SetMovingTransform(transform);
  ITK_TRY_EXPECT_EXCEPTION(metric->Initialize());
  metric->SetFixedMesh(MeshType::New());
  ITK_TRY_EXPECT_EXCEPTION(metric->Initialize());
  metric->SetFixedMesh(target);
  ITK_TRY_EXPECT_EXCEPTION(metric->Initialize());
  metric->SetEvaluation(EvaluationEnum::ExactPointToTriangle);
  ITK_TRY_EXPECT_EXCEPTION(metric->Initialize());
  ITK_TRY_EXPECT_EXCEPTION(metric->GetValue());

  // Exact reference: the mean directed distance of the mapped vertices, by MeshSurfaceDistanceCalculator.
  metric->SetMovingMesh(source);
  ITK_TRY_EXPECT_NO_EXCEPTION(metric->Initialize());
  const double exact = metric->GetValue();
  auto         mapped = MeshType::New();
  for (auto it = target->GetPoints()->Begin(); it != target->GetPoints()->End(); ++it)
  {
    mapped->SetPoint(it.Index(), transform->TransformPoint(it.Value()));
  }
  auto calculator = itk::MeshSurfaceDistanceCalculator<MeshType>::New();
  calculator->SetSourceMesh(mapped);
  calculator->SetTargetMesh(source);
  calculator->Compute();
  std::cout << "Exact mean directed distance " << exact << " mm (calculator: " << calculator->GetMeanDistance()
            << " mm), " << target->GetNumberOfPoints() << " vertices" << std::endl;
  std::cout << "  difference " << exact - calculator->GetMeanDistance() << std::endl;
  ITK_TEST_EXPECT_TRUE(std::abs(exact - calculator->GetMeanDistance()) < 1e-6);
  ITK_TEST_EXPECT_TRUE(exact > 0.5);
  int status = CheckDerivative(metric, transform, 1e-6, 1e-4, "exact point-to-triangle");

  // Distance maps: within the interpolation error of the exact value. Linear interpolation of a function with
  // second derivatives bounded by the largest curvature k (here 20/12^2 mm^-1) errs by at most
  // h^2/8 * 3k = 0.05 mm at h = 1 mm.
  const double interpolationBound = 3.0 * (20.0 / 144.0) / 8.0;
  for (const auto evaluation : { EvaluationEnum::LinearDistanceMap, EvaluationEnum::BSplineDistanceMap })
  {
    metric->SetEvaluation(evaluation);
    ITK_TRY_EXPECT_NO_EXCEPTION(metric->Initialize());
    const double value = metric->GetValue();
    std::cout << evaluation << ": " << value << " mm, exact " << exact << " mm, difference " << value - exact
              << " (bound " << interpolationBound << ")" << std::endl;
    ITK_TEST_EXPECT_TRUE(std::abs(value - exact) <= interpolationBound);
    ITK_TEST_EXPECT_EQUAL(metric->GetNumberOfPointsOutsideDistanceImage(), 0u);
    ITK_TEST_EXPECT_EQUAL(metric->GetNumberOfValidPoints(), target->GetNumberOfPoints());
    if (CheckDerivative(metric,
                        transform,
                        1e-6,
                        2e-3,
                        evaluation == EvaluationEnum::LinearDistanceMap ? "linear distance map"
                                                                        : "B-spline distance map") != EXIT_SUCCESS)
    {
      status = EXIT_FAILURE;
    }
  }
  const auto * distanceImage = metric->GetDistanceImage();
  ITK_TEST_EXPECT_TRUE(distanceImage != nullptr);

  // Any other transform goes through its dense Jacobian: a BSplineTransform equals unit templates on its grid.
  metric->SetEvaluation(EvaluationEnum::LinearDistanceMap);
  auto bspline = transform->MakeBSplineTransform();
  auto unit = TransformType::New();
  unit->SetGridFromBSplineTransform(bspline);
  std::vector<TransformType::SparseCoefficientVector> unitTemplates(unit->GetNumberOfCoefficients());
  for (itk::SizeValueType i = 0; i < unitTemplates.size(); ++i)
  {
    unitTemplates[i].Indices.push_back(i);
    unitTemplates[i].Values.push_back(1.0);
  }
  unit->SetSparseTemplates(unitTemplates);
  unit->SetParameters(bspline->GetParameters());
  MetricType::MeasureType    denseValue, sparseValue;
  MetricType::DerivativeType denseDerivative, sparseDerivative;
  metric->SetMovingTransform(bspline);
  metric->Initialize();
  metric->GetValueAndDerivative(denseValue, denseDerivative);
  metric->SetMovingTransform(unit);
  metric->Initialize();
  metric->GetValueAndDerivative(sparseValue, sparseDerivative);
  ITK_TEST_EXPECT_EQUAL(denseValue, sparseValue);
  double largestDifference = 0.0;
  for (unsigned int k = 0; k < denseDerivative.GetSize(); ++k)
  {
    largestDifference = std::max(largestDifference, std::abs(denseDerivative[k] - sparseDerivative[k]));
  }
  std::cout << "Dense and sparse Jacobian paths differ by " << largestDifference << std::endl;
  ITK_TEST_EXPECT_TRUE(largestDifference < 1e-12);

  // A small given distance image: vertices mapped outside it are measured to its box, derivative still exact.
  using VoxelizerType = itk::TriangleMeshToVoxelImageFilter<MeshType, ImageType>;
  auto                       voxelizer = VoxelizerType::New();
  VoxelizerType::SpacingType spacing;
  VoxelizerType::PointType   origin;
  VoxelizerType::SizeType    size;
  spacing.Fill(1.5);
  VoxelizerType::ComputeGeometryFromMeshBounds(source, spacing, 0.5, origin, size);
  voxelizer->SetInput(source);
  voxelizer->SetOrigin(origin);
  voxelizer->SetSpacing(spacing);
  voxelizer->SetSize(size);
  voxelizer->SetMode(itk::TriangleMeshToVoxelImageFilterEnums::Mode::SignedDistance);
  voxelizer->SetExactDistance(true);
  voxelizer->Update();
  auto outer = MakeTargetVertices(source, 1.2);
  metric->SetFixedMesh(outer);
  metric->SetMovingDistanceImage(voxelizer->GetOutput());
  metric->SetMovingTransform(transform);
  ITK_TRY_EXPECT_NO_EXCEPTION(metric->Initialize());
  ITK_TEST_EXPECT_TRUE(metric->GetDistanceImage() == voxelizer->GetOutput());
  if (CheckDerivative(metric, transform, 1e-6, 2e-3, "vertices outside the image") != EXIT_SUCCESS)
  {
    status = EXIT_FAILURE;
  }
  std::cout << metric->GetNumberOfPointsOutsideDistanceImage() << " of " << outer->GetNumberOfPoints()
            << " vertices outside the distance image" << std::endl;
  ITK_TEST_EXPECT_TRUE(metric->GetNumberOfPointsOutsideDistanceImage() > 0);
  return status;
}
