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

#include "itkAffineTransform.h"
#include "itkApplyTransformToMeshFilter.h"
#include "itkBSplineTransform.h"
#include "itkCommand.h"
#include "itkCompositeTransform.h"
#include "itkMersenneTwisterRandomVariateGenerator.h"
#include "itkRegularSphereMeshSource.h"
#include "itkTestingMacros.h"
#include "itkTimeProbe.h"

#include <cmath>
#include <limits>

namespace
{
constexpr unsigned int Dimension = 3;
using MeshTraitsType = itk::DefaultStaticMeshTraits<double, Dimension, Dimension, double, double, double>;
using MeshType = itk::Mesh<double, Dimension, MeshTraitsType>;
using TransformType = itk::Transform<double, Dimension, Dimension>;
using BSplineType = itk::BSplineTransform<double, Dimension, 3>;
using AffineType = itk::AffineTransform<double, Dimension>;
using CompositeType = itk::CompositeTransform<double, Dimension>;
using FilterType = itk::ApplyTransformToMeshFilter<MeshType, MeshType>;
using RandomType = itk::Statistics::MersenneTwisterRandomVariateGenerator;

/** A B-spline over [0, 100]^3 mm whose control displacements are uniform in [-amplitude, amplitude] x spacing.
 *
 * With zeroBoundary, the control points whose basis functions reach the boundary of the domain (the first three
 * and the last three along each axis of the meshSize + 3 per axis) have zero displacement, so the transform is the
 * identity on the boundary and outside the domain: it then maps the domain onto itself, and every point of the
 * domain has a preimage in it. */
BSplineType::Pointer
MakeRandomBSpline(unsigned int seed, double amplitude, unsigned int meshSize = 7, bool zeroBoundary = false)
{
  auto                                bspline = BSplineType::New();
  BSplineType::OriginType             origin;
  BSplineType::PhysicalDimensionsType dimensions;
  BSplineType::MeshSizeType           mesh;
  origin.Fill(0.0);
  dimensions.Fill(100.0);
  mesh.Fill(meshSize);
  bspline->SetTransformDomainOrigin(origin);
  bspline->SetTransformDomainPhysicalDimensions(dimensions);
  bspline->SetTransformDomainMeshSize(mesh);
  const double spacing = 100.0 / meshSize;
  auto         random = RandomType::New();
  random->SetSeed(seed);
  BSplineType::ParametersType parameters(bspline->GetNumberOfParameters());
  for (unsigned int i = 0; i < parameters.size(); ++i)
  {
    parameters[i] = amplitude * spacing * random->GetUniformVariate(-1.0, 1.0);
  }
  if (zeroBoundary)
  {
    // Parameters are stored component by component, each a control grid in x-fastest order.
    const unsigned int perAxis = meshSize + 3;
    const unsigned int perComponent = perAxis * perAxis * perAxis;
    const auto         touchesBoundary = [meshSize](unsigned int index) { return index < 3 || index >= meshSize; };
    for (unsigned int k = 0; k < perComponent; ++k)
    {
      const unsigned int x = k % perAxis;
      const unsigned int y = (k / perAxis) % perAxis;
      const unsigned int z = k / (perAxis * perAxis);
      if (touchesBoundary(x) || touchesBoundary(y) || touchesBoundary(z))
      {
        for (unsigned int d = 0; d < Dimension; ++d)
        {
          parameters[k + d * perComponent] = 0.0;
        }
      }
    }
  }
  bspline->SetParameters(parameters);
  return bspline;
}

/** A mesh holding only points (random inside [margin, 100 - margin]^3), with point data = id. */
MeshType::Pointer
MakeRandomPointMesh(unsigned int seed, unsigned int numberOfPoints, double margin)
{
  auto mesh = MeshType::New();
  auto random = RandomType::New();
  random->SetSeed(seed);
  for (unsigned int i = 0; i < numberOfPoints; ++i)
  {
    MeshType::PointType point;
    for (unsigned int d = 0; d < Dimension; ++d)
    {
      point[d] = random->GetUniformVariate(margin, 100.0 - margin);
    }
    mesh->SetPoint(i, point);
    mesh->SetPointData(i, static_cast<double>(i));
  }
  return mesh;
}

struct ProgressRecord
{
  unsigned int intermediate{ 0 };
};

double
Distance(const itk::Point<double, 3> & a, const itk::Point<double, 3> & b)
{
  return a.EuclideanDistanceTo(b);
}

/** Largest control-point displacement magnitude of a B-spline. */
double
MaximumDisplacement(const BSplineType * bspline)
{
  const auto &       parameters = bspline->GetParameters();
  const unsigned int n = parameters.size() / Dimension;
  double             maximum = 0.0;
  for (unsigned int i = 0; i < n; ++i)
  {
    double squared = 0.0;
    for (unsigned int d = 0; d < Dimension; ++d)
    {
      squared += parameters[i + d * n] * parameters[i + d * n];
    }
    maximum = std::max(maximum, std::sqrt(squared));
  }
  return maximum;
}

/** Distance from a point to the boundary of the cube [0, 100]^3. */
double
DistanceToDomainBoundary(const MeshType::PointType & point)
{
  double distance = 100.0;
  for (unsigned int d = 0; d < Dimension; ++d)
  {
    distance = std::min(distance, std::min(point[d], 100.0 - point[d]));
  }
  return distance;
}

/** Inverse round trip: returns false if a check fails; prints the figures.
 *
 * ITK's B-spline has zero displacement outside its domain but not at the domain's boundary, so a
 * point p closer to the boundary than the largest displacement may have no preimage at all. Farther
 * in, a preimage exists (the map x + t d(x), t in [0, 1], never reaches p from the boundary, so T has
 * degree 1 at p). The convergence requirement applies to the points farther than interiorMargin from
 * the boundary of [0, 100]^3; all points are checked for correct flags. */
bool
CheckInverseRoundTrip(const TransformType * transform,
                      const MeshType *      mesh,
                      double                checkTolerance,
                      double                minimumConvergedFraction,
                      const char *          label,
                      double                interiorMargin = 0.0)
{
  auto filter = FilterType::New();
  filter->SetInput(mesh);
  filter->SetTransform(transform);
  filter->InverseOn();
  itk::TimeProbe clock;
  clock.Start();
  filter->Update();
  clock.Stop();
  const MeshType *   output = filter->GetOutput();
  const auto &       converged = filter->GetInverseConverged();
  const auto &       residuals = filter->GetInverseResiduals();
  bool               ok = converged.size() == mesh->GetNumberOfPoints() && residuals.size() == converged.size();
  double             maximumError = 0.0;
  double             sumError = 0.0;
  itk::SizeValueType numberConverged = 0;
  itk::SizeValueType numberInterior = 0;
  itk::SizeValueType numberInteriorConverged = 0;
  for (itk::IdentifierType i = 0; ok && i < mesh->GetNumberOfPoints(); ++i)
  {
    const double error = Distance(transform->TransformPoint(output->GetPoint(i)), mesh->GetPoint(i));
    if (DistanceToDomainBoundary(mesh->GetPoint(i)) > interiorMargin)
    {
      ++numberInterior;
      numberInteriorConverged += converged[i] ? 1 : 0;
    }
    if (converged[i])
    {
      ++numberConverged;
      maximumError = std::max(maximumError, error);
      sumError += error;
      if (error >= checkTolerance)
      {
        std::cerr << label << ": converged vertex " << i << " has |T(x) - p| = " << error << std::endl;
        ok = false;
      }
    }
    // The reported residual is the true one.
    if (std::abs(error - residuals[i]) > 1e-9)
    {
      std::cerr << label << ": vertex " << i << " reports residual " << residuals[i] << " but has " << error
                << std::endl;
      ok = false;
    }
  }
  const double fraction = static_cast<double>(numberInteriorConverged) / std::max<double>(1, numberInterior);
  std::cout << label << ": " << mesh->GetNumberOfPoints() << " points, converged "
            << 100.0 * numberConverged / mesh->GetNumberOfPoints() << " % of all, " << 100.0 * fraction << " % of the "
            << numberInterior << " farther than " << interiorMargin << " mm from the domain boundary"
            << ", max |T(Tinv(p)) - p| = " << maximumError << " mm, mean "
            << sumError / std::max<double>(1, numberConverged) << " mm, non-converged "
            << filter->GetNumberOfNonConvergedPoints() << ", time " << clock.GetTotal() << " s" << std::endl;
  if (filter->GetNumberOfNonConvergedPoints() != mesh->GetNumberOfPoints() - numberConverged)
  {
    std::cerr << label << ": GetNumberOfNonConvergedPoints disagrees with the flags" << std::endl;
    ok = false;
  }
  if (fraction < minimumConvergedFraction)
  {
    std::cerr << label << ": converged fraction " << fraction << " < " << minimumConvergedFraction << std::endl;
    ok = false;
  }
  return ok;
}
} // namespace

int
itkApplyTransformToMeshFilterTest(int argc, char * argv[])
{
  if (argc != 1)
  {
    std::cerr << "Usage: " << itkNameOfTestExecutableMacro(argv) << std::endl;
    return EXIT_FAILURE;
  }
  int testStatus = EXIT_SUCCESS;

  auto filter = FilterType::New();
  ITK_EXERCISE_BASIC_OBJECT_METHODS(filter, ApplyTransformToMeshFilter, MeshToMeshFilter);
  ITK_TEST_SET_GET_BOOLEAN(filter, Inverse, true);
  ITK_TEST_SET_GET_VALUE(1e-7, (filter->SetInverseTolerance(1e-7), filter->GetInverseTolerance()));
  ITK_TEST_SET_GET_VALUE(
    20u, (filter->SetMaximumNumberOfInverseIterations(20), filter->GetMaximumNumberOfInverseIterations()));
  ITK_TEST_SET_GET_VALUE(1e-3, (filter->SetFiniteDifferenceStep(1e-3), filter->GetFiniteDifferenceStep()));
  ITK_TEST_SET_GET_VALUE(0.0,
                         (filter->SetMinimumInverseResidualDecrease(0.0), filter->GetMinimumInverseResidualDecrease()));

  // A closed sphere with point data and cell data.
  using SphereSourceType = itk::RegularSphereMeshSource<MeshType>;
  auto                        sphereSource = SphereSourceType::New();
  SphereSourceType::PointType center;
  center.Fill(50.0);
  SphereSourceType::VectorType scale;
  scale.Fill(30.0);
  sphereSource->SetCenter(center);
  sphereSource->SetScale(scale);
  sphereSource->SetResolution(3);
  sphereSource->Update();
  MeshType::Pointer sphere = sphereSource->GetOutput();
  sphere->DisconnectPipeline();
  for (itk::IdentifierType i = 0; i < sphere->GetNumberOfPoints(); ++i)
  {
    sphere->SetPointData(i, 0.5 * i);
  }
  for (itk::IdentifierType i = 0; i < sphere->GetNumberOfCells(); ++i)
  {
    sphere->SetCellData(i, 2.0 * i);
  }

  // Missing transform.
  filter = FilterType::New();
  filter->SetInput(sphere);
  ITK_TRY_EXPECT_EXCEPTION(filter->Update());

  // Bad settings.
  auto affine = AffineType::New();
  filter->SetTransform(affine);
  filter->SetInverseTolerance(0.0);
  ITK_TRY_EXPECT_EXCEPTION(filter->Update());
  filter->SetInverseTolerance(1e-6);
  for (const double decrease : { -1e-3, 1.0, std::numeric_limits<double>::quiet_NaN() })
  {
    filter->SetMinimumInverseResidualDecrease(decrease);
    ITK_TRY_EXPECT_EXCEPTION(filter->Update());
  }
  filter->SetMinimumInverseResidualDecrease(1e-3);

  // Forward mode: T(p) per vertex; cells, point data and cell data pass through.
  AffineType::MatrixType matrix;
  matrix(0, 0) = 1.1;
  matrix(0, 1) = 0.2;
  matrix(0, 2) = -0.1;
  matrix(1, 0) = 0.05;
  matrix(1, 1) = 0.9;
  matrix(1, 2) = 0.1;
  matrix(2, 0) = 0.0;
  matrix(2, 1) = -0.15;
  matrix(2, 2) = 1.05;
  affine->SetMatrix(matrix);
  AffineType::OutputVectorType translation;
  translation[0] = 3.0;
  translation[1] = -2.0;
  translation[2] = 1.5;
  affine->SetTranslation(translation);

  // Through the decorator, as a registration method's transform output would be connected.
  auto decorated = FilterType::DecoratedTransformType::New();
  decorated->Set(affine);
  filter->SetTransformInput(decorated);
  ITK_TEST_EXPECT_TRUE(filter->GetTransform() == affine.GetPointer());
  ITK_TRY_EXPECT_NO_EXCEPTION(filter->Update());
  {
    const MeshType * output = filter->GetOutput();
    ITK_TEST_EXPECT_EQUAL(output->GetNumberOfPoints(), sphere->GetNumberOfPoints());
    ITK_TEST_EXPECT_EQUAL(output->GetNumberOfCells(), sphere->GetNumberOfCells());
    ITK_TEST_EXPECT_TRUE(filter->GetInverseConverged().empty());
    double maximumError = 0.0;
    bool   dataOk = true;
    for (itk::IdentifierType i = 0; i < sphere->GetNumberOfPoints(); ++i)
    {
      maximumError = std::max(maximumError, Distance(output->GetPoint(i), affine->TransformPoint(sphere->GetPoint(i))));
      double value = -1.0;
      dataOk = dataOk && output->GetPointData(i, &value) && value == 0.5 * i;
    }
    for (itk::IdentifierType i = 0; i < sphere->GetNumberOfCells(); ++i)
    {
      MeshType::CellAutoPointer inputCell;
      MeshType::CellAutoPointer outputCell;
      sphere->GetCell(i, inputCell);
      output->GetCell(i, outputCell);
      dataOk = dataOk && inputCell->GetNumberOfPoints() == outputCell->GetNumberOfPoints() &&
               std::equal(inputCell->PointIdsBegin(), inputCell->PointIdsEnd(), outputCell->PointIdsBegin());
      double value = -1.0;
      dataOk = dataOk && output->GetCellData(i, &value) && value == 2.0 * i;
    }
    std::cout << "Forward affine: max |out - T(p)| = " << maximumError << std::endl;
    ITK_TEST_EXPECT_TRUE(maximumError == 0.0);
    ITK_TEST_EXPECT_TRUE(dataOk);
  }

  // Progress is reported up to 1.
  {
    ProgressRecord record;
    auto           observer = itk::CStyleCommand::New();
    observer->SetClientData(&record);
    observer->SetCallback([](itk::Object * caller, const itk::EventObject &, void * clientData) {
      auto &      progressRecord = *static_cast<ProgressRecord *>(clientData);
      const float progress = static_cast<itk::ProcessObject *>(caller)->GetProgress();
      progressRecord.intermediate += (progress > 0.0f && progress < 1.0f) ? 1 : 0;
    });
    const auto tag = filter->AddObserver(itk::ProgressEvent(), observer);
    filter->Modified();
    filter->Update();
    filter->RemoveObserver(tag);
    std::cout << "Progress: " << record.intermediate << " intermediate reports, final " << filter->GetProgress()
              << std::endl;
    ITK_TEST_EXPECT_TRUE(filter->GetProgress() > 0.99f);
    ITK_TEST_EXPECT_TRUE(record.intermediate > 0);
  }

  // A mesh with float coordinates (itk::Mesh<float, 3>): forward and inverse.
  {
    using FloatMeshType = itk::Mesh<float, 3>;
    using FloatFilterType = itk::ApplyTransformToMeshFilter<FloatMeshType, FloatMeshType>;
    auto floatMesh = FloatMeshType::New();
    for (itk::IdentifierType i = 0; i < sphere->GetNumberOfPoints(); ++i)
    {
      FloatMeshType::PointType point;
      point.CastFrom(sphere->GetPoint(i));
      floatMesh->SetPoint(i, point);
    }
    auto floatFilter = FloatFilterType::New();
    floatFilter->SetInput(floatMesh);
    floatFilter->SetTransform(affine);
    ITK_TRY_EXPECT_NO_EXCEPTION(floatFilter->Update());
    auto inverseFilter = FloatFilterType::New();
    inverseFilter->SetInput(floatFilter->GetOutput());
    inverseFilter->SetTransform(affine);
    inverseFilter->InverseOn();
    inverseFilter->SetInverseTolerance(1e-4);
    ITK_TRY_EXPECT_NO_EXCEPTION(inverseFilter->Update());
    double maximumError = 0.0;
    for (itk::IdentifierType i = 0; i < floatMesh->GetNumberOfPoints(); ++i)
    {
      maximumError = std::max(
        maximumError,
        static_cast<double>(inverseFilter->GetOutput()->GetPoint(i).EuclideanDistanceTo(floatMesh->GetPoint(i))));
    }
    std::cout << "Float mesh: forward then inverse, max error " << maximumError << std::endl;
    ITK_TEST_EXPECT_TRUE(maximumError < 1e-4);
  }

  // Pipeline: modifying the decorated transform re-executes the filter.
  {
    const itk::ModifiedTimeType before = filter->GetOutput()->GetMTime();
    filter->Update();
    ITK_TEST_EXPECT_EQUAL(filter->GetOutput()->GetMTime(), before); // nothing changed: no re-run
    translation[0] = -7.0;
    affine->SetTranslation(translation);
    filter->Update();
    ITK_TEST_EXPECT_TRUE(filter->GetOutput()->GetMTime() > before);
    const double error = Distance(filter->GetOutput()->GetPoint(5), affine->TransformPoint(sphere->GetPoint(5)));
    std::cout << "After modifying the transform: |out - T(p)| = " << error << std::endl;
    ITK_TEST_EXPECT_TRUE(error == 0.0);
  }

  // Inverse of an affine transform equals its exact inverse.
  {
    filter->InverseOn();
    ITK_TRY_EXPECT_NO_EXCEPTION(filter->Update());
    auto   inverse = AffineType::New();
    double maximumError = 0.0;
    affine->GetInverse(inverse);
    for (itk::IdentifierType i = 0; i < sphere->GetNumberOfPoints(); ++i)
    {
      maximumError = std::max(maximumError,
                              Distance(filter->GetOutput()->GetPoint(i), inverse->TransformPoint(sphere->GetPoint(i))));
    }
    std::cout << "Inverse affine: max |out - A^-1 p| = " << maximumError
              << ", non-converged: " << filter->GetNumberOfNonConvergedPoints() << std::endl;
    ITK_TEST_EXPECT_TRUE(maximumError < 1e-6);
    ITK_TEST_EXPECT_EQUAL(filter->GetNumberOfNonConvergedPoints(), 0);
  }

  // The analytic spatial Jacobian of the B-spline agrees with finite differences.
  {
    const auto                                       bspline = MakeRandomBSpline(7, 0.4);
    itk::detail::SpatialJacobianEvaluator<double, 3> analytic;
    itk::detail::SpatialJacobianEvaluator<double, 3> numeric;
    analytic.Initialize(bspline);
    auto composite = CompositeType::New();
    composite->AddTransform(affine);
    composite->AddTransform(bspline);
    itk::detail::SpatialJacobianEvaluator<double, 3> chain;
    chain.Initialize(composite);
    ITK_TEST_EXPECT_TRUE((analytic.GetMethod() == itk::detail::SpatialJacobianEvaluator<double, 3>::Method::BSpline));
    ITK_TEST_EXPECT_TRUE(!chain.UsesFiniteDifferences());
    auto   random = RandomType::New();
    double maximumDifference = 0.0;
    double maximumChainDifference = 0.0;
    random->SetSeed(11);
    for (unsigned int n = 0; n < 200; ++n)
    {
      itk::Point<double, 3> point;
      for (unsigned int d = 0; d < 3; ++d)
      {
        point[d] = random->GetUniformVariate(1.0, 99.0);
      }
      itk::Matrix<double, 3, 3> jacobian;
      analytic.Evaluate(point, jacobian);
      itk::Matrix<double, 3, 3> chainJacobian;
      chain.Evaluate(point, chainJacobian);
      constexpr double h = 1e-4;
      for (unsigned int j = 0; j < 3; ++j)
      {
        auto forward = point;
        auto backward = point;
        forward[j] += h;
        backward[j] -= h;
        const auto difference = bspline->TransformPoint(forward) - bspline->TransformPoint(backward);
        const auto compositeDifference = composite->TransformPoint(forward) - composite->TransformPoint(backward);
        for (unsigned int i = 0; i < 3; ++i)
        {
          maximumDifference = std::max(maximumDifference, std::abs(jacobian(i, j) - difference[i] / (2 * h)));
          maximumChainDifference =
            std::max(maximumChainDifference, std::abs(chainJacobian(i, j) - compositeDifference[i] / (2 * h)));
        }
      }
    }
    std::cout << "B-spline spatial Jacobian vs finite differences: " << maximumDifference
              << ", composite: " << maximumChainDifference << std::endl;
    ITK_TEST_EXPECT_TRUE(maximumDifference < 1e-6);
    ITK_TEST_EXPECT_TRUE(maximumChainDifference < 1e-6);

    // The evaluator's T(x) is the transform's own TransformPoint(), to the bit: the B-spline, the composite and the
    // affine, at random points inside and around the domain, on the domain's faces and at the valid region's upper
    // end (where ITK moves the index a few ULPs inside).
    itk::detail::SpatialJacobianEvaluator<double, 3> plain;
    plain.Initialize(affine);
    std::vector<itk::Point<double, 3>> probes;
    for (unsigned int n = 0; n < 3000; ++n)
    {
      itk::Point<double, 3> point;
      for (unsigned int d = 0; d < 3; ++d)
      {
        point[d] = random->GetUniformVariate(-10.0, 110.0);
      }
      probes.push_back(point);
    }
    for (const double face : { 0.0, 100.0, std::nextafter(100.0, 0.0), std::nextafter(100.0, 200.0), 1e-13 })
    {
      for (unsigned int axis = 0; axis < 3; ++axis)
      {
        itk::Point<double, 3> point;
        point.Fill(37.5);
        point[axis] = face;
        probes.push_back(point);
      }
    }
    unsigned int differing = 0;
    unsigned int moved = 0;
    for (const auto & point : probes)
    {
      differing += analytic.TransformPoint(point) != bspline->TransformPoint(point);
      differing += chain.TransformPoint(point) != composite->TransformPoint(point);
      differing += plain.TransformPoint(point) != affine->TransformPoint(point);
      moved += bspline->TransformPoint(point) != point;
    }
    std::cout << "Evaluator's T(x) against TransformPoint(): " << differing << " of " << 3 * probes.size()
              << " differ (" << moved << " points moved by the B-spline)" << std::endl;
    ITK_TEST_EXPECT_EQUAL(differing, 0);
    ITK_TEST_EXPECT_TRUE(moved > probes.size() / 2 && moved < probes.size());
    itk::detail::SpatialJacobianEvaluator<double, 3> uninitialized;
    ITK_TRY_EXPECT_EXCEPTION(uninitialized.TransformPoint(probes[0]));
  }

  // Inverse round trip with random B-spline deformations (displacements up to 0.4 x spacing), the issue's
  // requirement: uniform random points over the whole domain, B-splines whose displacement is zero on the domain's
  // boundary (so every point of the domain has a preimage): all converged points within 1e-5 mm, >= 99.9 %
  // converged.
  for (unsigned int seed = 1; seed <= 3; ++seed)
  {
    const auto bspline = MakeRandomBSpline(seed, 0.4, 10, true);
    // Not a trivial deformation: the free control points (7 per axis, spacing 10 mm) move by up to 0.4 x 10 mm per
    // component.
    ITK_TEST_EXPECT_TRUE(MaximumDisplacement(bspline) > 4.0);
    {
      // The boundary is fixed: points on two faces (other coordinates anywhere) do not move.
      MeshType::PointType onFace;
      onFace[0] = 0.0;
      onFace[1] = 37.0 + seed;
      onFace[2] = 61.5;
      ITK_TEST_EXPECT_TRUE(bspline->TransformPoint(onFace).EuclideanDistanceTo(onFace) < 1e-12);
      onFace[0] = 43.25;
      onFace[2] = 100.0 - 1e-9;
      ITK_TEST_EXPECT_TRUE(bspline->TransformPoint(onFace).EuclideanDistanceTo(onFace) < 1e-8);
    }
    const auto        points = MakeRandomPointMesh(200 + seed, 10000, 0.0);
    const std::string label = "B-spline with fixed boundary, whole domain, seed " + std::to_string(seed);
    if (!CheckInverseRoundTrip(bspline, points, 1e-5, 0.999, label.c_str(), 0.0))
    {
      testStatus = EXIT_FAILURE;
    }
  }

  // The general case: ITK's B-spline moves the domain's boundary, so points closer to it than the largest
  // displacement may have no preimage. Reported over the whole domain (a figure, typically 96-97 %); checked
  // (>= 99.9 %) for the points farther inside than the largest control displacement.
  for (unsigned int seed = 1; seed <= 3; ++seed)
  {
    const auto        bspline = MakeRandomBSpline(seed, 0.4);
    const auto        points = MakeRandomPointMesh(100 + seed, 10000, 0.0);
    const std::string label = "B-spline round trip, seed " + std::to_string(seed);
    if (!CheckInverseRoundTrip(bspline, points, 1e-5, 0.999, label.c_str(), MaximumDisplacement(bspline)))
    {
      testStatus = EXIT_FAILURE;
    }
  }

  // Where the residual levels off (points near the boundary of ITK's B-spline's domain, which have no preimage),
  // the default stops iterating once an iteration gains less than 0.1 % of the residual. Against iterating while
  // the residual decreases at all (0): the same points converge, at the same positions; at the others the residuals
  // left add up to at most 1 % more, and at most 1 % of those points keep a residual more than 1 % higher (a few can
  // be lower or higher: the fixed-point scheme may still find a lower residual after a level stretch, and rounding
  // decides where a stretch ends).
  {
    const auto bspline = MakeRandomBSpline(2, 0.4);
    const auto points = MakeRandomPointMesh(102, 10000, 0.0);
    auto       stopping = FilterType::New();
    auto       continuing = FilterType::New();
    for (FilterType * each : { stopping.GetPointer(), continuing.GetPointer() })
    {
      each->SetInput(points);
      each->SetTransform(bspline);
      each->InverseOn();
    }
    continuing->SetMinimumInverseResidualDecrease(0.0);
    itk::TimeProbe stoppingClock;
    itk::TimeProbe continuingClock;
    stoppingClock.Start();
    ITK_TRY_EXPECT_NO_EXCEPTION(stopping->Update());
    stoppingClock.Stop();
    continuingClock.Start();
    ITK_TRY_EXPECT_NO_EXCEPTION(continuing->Update());
    continuingClock.Stop();
    bool               same = stopping->GetInverseConverged() == continuing->GetInverseConverged();
    double             largestRatio = 0.0;
    double             stoppingSum = 0.0;
    double             continuingSum = 0.0;
    itk::SizeValueType lower = 0;
    itk::SizeValueType higher = 0;
    for (itk::IdentifierType i = 0; same && i < points->GetNumberOfPoints(); ++i)
    {
      if (stopping->GetInverseConverged()[i])
      {
        same = stopping->GetOutput()->GetPoint(i) == continuing->GetOutput()->GetPoint(i);
        continue;
      }
      const double ratio = stopping->GetInverseResiduals()[i] / continuing->GetInverseResiduals()[i];
      largestRatio = std::max(largestRatio, ratio);
      stoppingSum += stopping->GetInverseResiduals()[i];
      continuingSum += continuing->GetInverseResiduals()[i];
      lower += ratio < 0.99 ? 1 : 0;
      higher += ratio > 1.01 ? 1 : 0;
    }
    const itk::SizeValueType nonConverged = stopping->GetNumberOfNonConvergedPoints();
    std::cout << "Levelling off: " << nonConverged << " of 10000 without a preimage, residuals adding up to "
              << stoppingSum / continuingSum << " x, " << higher << " more than 1 % higher (at most " << largestRatio
              << " x), " << lower << " more than 1 % lower; time " << stoppingClock.GetTotal() << " s against "
              << continuingClock.GetTotal() << " s" << std::endl;
    ITK_TEST_EXPECT_TRUE(same);
    ITK_TEST_EXPECT_TRUE(stoppingSum <= 1.01 * continuingSum);
    ITK_TEST_EXPECT_TRUE(100 * higher <= nonConverged);
    ITK_TEST_EXPECT_TRUE(stopping->GetNumberOfNonConvergedPoints() > 0);
  }

  // Composite transform: affine after B-spline.
  {
    auto composite = CompositeType::New();
    composite->AddTransform(affine);
    const auto bspline = MakeRandomBSpline(21, 0.3);
    composite->AddTransform(bspline);
    // T = A o B; points A(q) with q at least the largest B-spline displacement inside the B-spline domain have a
    // preimage.
    auto points = MakeRandomPointMesh(22, 5000, MaximumDisplacement(bspline) + 1e-3);
    for (itk::IdentifierType i = 0; i < points->GetNumberOfPoints(); ++i)
    {
      points->SetPoint(i, affine->TransformPoint(points->GetPoint(i)));
    }
    if (!CheckInverseRoundTrip(composite, points, 1e-5, 0.999, "Composite round trip", -1e9))
    {
      testStatus = EXIT_FAILURE;
    }
  }

  // A singular (folding) affine map: only points in its range z = 0 can converge; the others are flagged.
  {
    auto                   flatten = AffineType::New();
    AffineType::MatrixType flat;
    flat.SetIdentity();
    flat(2, 2) = 0.0;
    flatten->SetMatrix(flat);
    auto points = MakeRandomPointMesh(31, 1000, 0.0);
    for (itk::IdentifierType i = 0; i < 100; ++i)
    {
      auto point = points->GetPoint(i);
      point[2] = 0.0;
      points->SetPoint(i, point);
    }
    auto flatFilter = FilterType::New();
    flatFilter->SetInput(points);
    flatFilter->SetTransform(flatten);
    flatFilter->InverseOn();
    ITK_TRY_EXPECT_NO_EXCEPTION(flatFilter->Update());
    const auto & converged = flatFilter->GetInverseConverged();
    bool         flagsOk = true;
    for (itk::IdentifierType i = 0; i < points->GetNumberOfPoints(); ++i)
    {
      flagsOk = flagsOk && (converged[i] != 0) == (i < 100);
      // A flagged vertex keeps its best estimate, which is no worse than the input point.
      flagsOk = flagsOk && flatFilter->GetInverseResiduals()[i] <= std::abs(points->GetPoint(i)[2]) + 1e-12;
    }
    std::cout << "Singular affine: non-converged " << flatFilter->GetNumberOfNonConvergedPoints() << " of 1000"
              << std::endl;
    ITK_TEST_EXPECT_EQUAL(flatFilter->GetNumberOfNonConvergedPoints(), 900);
    ITK_TEST_EXPECT_TRUE(flagsOk);
  }

  // A strongly folding B-spline (displacements up to 2.5 x spacing): some vertices do not converge, and
  // every vertex not flagged satisfies the tolerance.
  {
    const auto bspline = MakeRandomBSpline(41, 2.5);
    const auto points = MakeRandomPointMesh(42, 5000, 0.0);
    auto       foldFilter = FilterType::New();
    foldFilter->SetInput(points);
    foldFilter->SetTransform(bspline);
    foldFilter->InverseOn();
    ITK_TRY_EXPECT_NO_EXCEPTION(foldFilter->Update());
    if (!CheckInverseRoundTrip(bspline, points, 1e-6, 0.0, "Folding B-spline"))
    {
      testStatus = EXIT_FAILURE;
    }
    ITK_TEST_EXPECT_TRUE(foldFilter->GetNumberOfNonConvergedPoints() > 0);
  }

  // Timing figure: 75 000 vertices through the inverse of a random B-spline on a 20^3 control grid.
  {
    const auto bspline = MakeRandomBSpline(51, 0.4, 17);
    const auto points = MakeRandomPointMesh(52, 75000, 0.0);
    if (!CheckInverseRoundTrip(bspline, points, 1e-5, 0.999, "75k vertices, 20^3 grid", MaximumDisplacement(bspline)))
    {
      testStatus = EXIT_FAILURE;
    }
  }

  std::cout << "Test finished." << std::endl;
  return testStatus;
}
