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
#include "itkApplyTransformToMeshFilter.h"
#include "itkBSplineFFDImageRegistrationMethod.h"
#include "itkBSplineTransformInitializer.h"
#include "itkParametricTemplateRegistrationMethod.h"
#include "itkRandomBSplineTransformGenerator.h"
#include "itkRegularSphereMeshSource.h"
#include "itkTestingMacros.h"
#include "itkTriangleCell.h"
#include "itkTriangleMeshToVoxelImageFilter.h"
#include <chrono>
#include <cmath>
#include <map>

namespace
{
constexpr unsigned int Dimension = 3;
using MeshType = itk::Mesh<double, Dimension>;
using ImageType = itk::Image<float, Dimension>;
using MaskType = itk::Image<unsigned char, Dimension>;
using RegistrationType = itk::ParametricTemplateRegistrationMethod<MeshType, MeshType, ImageType>;
using ParametricType = RegistrationType::ParametricTransformType;
using BSplineType = ParametricType::BSplineTransformType;
using GOType = itk::BSplineFFDImageRegistrationMethod<ImageType>;
using ApplyType = itk::ApplyTransformToMeshFilter<MeshType, MeshType, RegistrationType::TransformType>;
using VoxelizerType = itk::TriangleMeshToVoxelImageFilter<MeshType, ImageType>;
using MaskVoxelizerType = itk::TriangleMeshToVoxelImageFilter<MeshType, MaskType>;
constexpr unsigned int ControlPointsPerAxis = 6;

/** The generated case: the source, a region of it moved by T_true^-1 (the target), and T_true. */
struct Case
{
  MeshType::Pointer    source;
  MeshType::Pointer    region;
  MeshType::Pointer    target;
  ImageType::Pointer   reference; // geometry of the target's voxel image (not allocated)
  BSplineType::Pointer truth;
};

MeshType::Pointer
MakeEllipsoid()
{
  auto                                               sphere = itk::RegularSphereMeshSource<MeshType>::New();
  itk::RegularSphereMeshSource<MeshType>::VectorType scale;
  scale[0] = 20.0;
  scale[1] = 15.0;
  scale[2] = 12.0;
  sphere->SetScale(scale);
  sphere->SetResolution(4);
  sphere->Update();
  MeshType::Pointer mesh = sphere->GetOutput();
  mesh->DisconnectPipeline();
  return mesh;
}

/** The triangles of mesh whose three vertices have x > cut, with their vertices renumbered. */
MeshType::Pointer
ExtractRegion(const MeshType * mesh, double cut)
{
  auto                                                           region = MeshType::New();
  std::map<MeshType::PointIdentifier, MeshType::PointIdentifier> renumbered;
  MeshType::CellIdentifier                                       cellId = 0;
  for (auto it = mesh->GetCells()->Begin(); it != mesh->GetCells()->End(); ++it)
  {
    const auto * ids = it.Value()->GetPointIds();
    bool         inside = it.Value()->GetNumberOfPoints() == 3;
    for (unsigned int j = 0; inside && j < 3; ++j)
    {
      inside = mesh->GetPoint(ids[j])[0] > cut;
    }
    if (!inside)
    {
      continue;
    }
    MeshType::CellAutoPointer cell;
    cell.TakeOwnership(new itk::TriangleCell<MeshType::CellType>);
    for (unsigned int j = 0; j < 3; ++j)
    {
      auto found = renumbered.find(ids[j]);
      if (found == renumbered.end())
      {
        found = renumbered.emplace(ids[j], renumbered.size()).first;
        region->SetPoint(found->second, mesh->GetPoint(ids[j]));
      }
      cell->SetPointId(j, found->second);
    }
    region->SetCell(cellId++, cell);
  }
  return region;
}

Case
MakeCase()
{
  Case example;
  example.source = MakeEllipsoid();
  example.region = ExtractRegion(example.source, -8.0);

  // The target's voxel grid: the region's bounds grown by 6 mm, 1 mm voxels.
  VoxelizerType::SpacingType spacing;
  spacing.Fill(1.0);
  VoxelizerType::PointType origin;
  VoxelizerType::SizeType  size;
  VoxelizerType::ComputeGeometryFromMeshBounds(example.region, spacing, 6.0, origin, size);
  example.reference = ImageType::New();
  example.reference->SetRegions(size);
  example.reference->SetOrigin(origin);
  example.reference->SetSpacing(spacing);

  // T_true: Gaussian noise (sigma 1.5 mm, clipped at 3 mm) on the grid GO uses over that image.
  example.truth = BSplineType::New();
  auto                      initializer = itk::BSplineTransformInitializer<BSplineType, ImageType>::New();
  BSplineType::MeshSizeType meshSize;
  meshSize.Fill(ControlPointsPerAxis - 3);
  initializer->SetTransform(example.truth);
  initializer->SetImage(example.reference);
  initializer->SetTransformDomainMeshSize(meshSize);
  initializer->InitializeTransform();
  auto generator = itk::RandomBSplineTransformGenerator<>::New();
  generator->SetDomainFromImage(example.reference);
  generator->SetNumberOfControlPointsPerAxis(ControlPointsPerAxis);
  generator->SetSigma(1.5);
  generator->SetClipAmplitude(3.0);
  generator->SetSeed(2026);
  generator->Generate();
  example.truth->SetParametersByValue(generator->GetTransform()->GetParameters());

  // The target: T_true^-1 of the region's vertices (same cells).
  auto inverse = ApplyType::New();
  inverse->SetInput(example.region);
  inverse->SetTransform(example.truth);
  inverse->InverseOn();
  inverse->Update();
  if (inverse->GetNumberOfNonConvergedPoints() != 0)
  {
    itkGenericExceptionMacro(<< "T_true is not invertible at " << inverse->GetNumberOfNonConvergedPoints()
                             << " vertices");
  }
  example.target = inverse->GetOutput();
  example.target->DisconnectPipeline();
  return example;
}

/** Mean |T(t_i) - s_i|: the true error of T over the target's vertices (known correspondences). */
double
TrueError(const Case & example, const RegistrationType::TransformType * transform)
{
  double sum = 0.0;
  for (auto it = example.target->GetPoints()->Begin(); it != example.target->GetPoints()->End(); ++it)
  {
    RegistrationType::TransformType::InputPointType point;
    point.CastFrom(it.Value());
    const auto mapped = transform != nullptr ? transform->TransformPoint(point) : point;
    RegistrationType::TransformType::InputPointType truth;
    truth.CastFrom(example.region->GetPoint(it.Index()));
    sum += (mapped - truth).GetNorm();
  }
  return sum / example.target->GetNumberOfPoints();
}

/** GO on voxel images, as the module's program runs it: unsigned distance maps, metric in a band around the
 * target. */
GOType::Pointer
MakeGO(const Case & example)
{
  auto fixedVoxelizer = VoxelizerType::New();
  fixedVoxelizer->SetInput(example.target);
  fixedVoxelizer->SetReferenceImage(example.reference);
  fixedVoxelizer->SetMode(itk::TriangleMeshToVoxelImageFilterEnums::Mode::SignedDistance);
  fixedVoxelizer->SetUnsignedDistance(true);
  fixedVoxelizer->SetBandWidth(4.0);
  auto movingVoxelizer = VoxelizerType::New();
  movingVoxelizer->SetInput(example.source);
  VoxelizerType::SpacingType spacing;
  spacing.Fill(1.0);
  movingVoxelizer->SetGeometryFromMeshBounds(spacing, 8.0);
  movingVoxelizer->SetMode(itk::TriangleMeshToVoxelImageFilterEnums::Mode::SignedDistance);
  movingVoxelizer->SetUnsignedDistance(true);
  movingVoxelizer->SetBandWidth(4.0);
  auto mask = MaskVoxelizerType::New();
  mask->SetInput(example.target);
  mask->SetReferenceImage(example.reference);
  mask->SetMode(itk::TriangleMeshToVoxelImageFilterEnums::Mode::BandMask);
  mask->SetBandWidth(3.0);

  // (GO checks its images' sizes before updating its inputs: update them first.)
  fixedVoxelizer->Update();
  movingVoxelizer->Update();
  mask->Update();
  auto go = GOType::New();
  go->SetFixedImage(fixedVoxelizer->GetOutput());
  go->SetMovingImage(movingVoxelizer->GetOutput());
  go->SetFixedImageMask(mask->GetOutput());
  go->SetMetric(itk::FFDShapeMatchingEnums::ImageMetric::MeanSquares);
  go->SetNumberOfControlPointsPerAxis(ControlPointsPerAxis);
  go->SetNumberOfIterations(60);
  return go;
}

double
SecondsSince(std::chrono::steady_clock::time_point & start)
{
  const auto   now = std::chrono::steady_clock::now();
  const double seconds = std::chrono::duration<double>(now - start).count();
  start = now;
  return seconds;
}
} // namespace

int
itkParametricTemplateRegistrationMethodTest(int argc, char * argv[])
{
  if (argc != 1)
  {
    std::cerr << "Usage: " << itkNameOfTestExecutableMacro(argv) << std::endl;
    return EXIT_FAILURE;
  }
  auto       clock = std::chrono::steady_clock::now();
  const Case example = MakeCase();
  std::cout << "Case: source " << example.source->GetNumberOfPoints() << " vertices, target "
            << example.target->GetNumberOfPoints() << " vertices, " << SecondsSince(clock) << " s" << std::endl;

  // Templates: T_true's control displacements, one template per control point (directions known).
  auto templates = ParametricType::New();
  templates->SetTemplatesFromBSplineTransforms({ example.truth.GetPointer() },
                                               itk::ParametricTemplateTransformEnums::TemplateSplit::ControlPoint);
  std::cout << templates->GetNumberOfTemplates() << " templates" << std::endl;

  auto registration = RegistrationType::New();
  ITK_EXERCISE_BASIC_OBJECT_METHODS(registration, ParametricTemplateRegistrationMethod, MeshRegistrationMethodBase);
  ITK_TEST_SET_GET_VALUE(RegistrationType::OptimizerEnum::LBFGS, registration->GetOptimizer());
  ITK_TEST_SET_GET_VALUE(RegistrationType::EvaluationEnum::LinearDistanceMap, registration->GetEvaluation());
  ITK_TEST_SET_GET_VALUE(100u, registration->GetNumberOfIterations());
  ITK_TEST_SET_GET_BOOLEAN(registration, ResampleBaseTransform, true);
  ITK_TEST_SET_GET_BOOLEAN(registration, UseSquaredDistance, true);
  ITK_TEST_SET_GET_VALUE(50u, registration->GetNumberOfExactRefinementIterations());
  std::cout << RegistrationType::OptimizerEnum::OnePlusOneEvolutionary << std::endl;

  // Bad input: no template transform, no templates, no source, an empty source, an empty target.
  registration->SetFixedMesh(example.target);
  registration->SetMovingMesh(example.source);
  ITK_TRY_EXPECT_EXCEPTION(registration->Update());
  registration->SetTemplateTransform(ParametricType::New());
  ITK_TRY_EXPECT_EXCEPTION(registration->Update());
  registration->SetTemplateTransform(templates);
  registration->SetMovingMesh(MeshType::New());
  ITK_TRY_EXPECT_EXCEPTION(registration->Update());
  registration->SetMovingMesh(nullptr);
  ITK_TRY_EXPECT_EXCEPTION(registration->Update());
  registration->SetMovingMesh(example.source);
  registration->SetFixedMesh(MeshType::New());
  ITK_TRY_EXPECT_EXCEPTION(registration->Update());
  registration->SetFixedMesh(example.target);
  // A base on another grid is refused when resampling is off.
  auto otherGrid = BSplineType::New();
  registration->SetBaseTransform(otherGrid);
  registration->ResampleBaseTransformOff();
  ITK_TRY_EXPECT_EXCEPTION(registration->Update());
  registration->ResampleBaseTransformOn();
  registration->SetBaseTransformInput(nullptr);

  // Par.
  const double errorBefore = TrueError(example, nullptr);
  unsigned int iterationEvents = 0;
  registration->AddObserver(itk::IterationEvent(), [&iterationEvents](const itk::EventObject &) { ++iterationEvents; });
  clock = std::chrono::steady_clock::now();
  ITK_TRY_EXPECT_NO_EXCEPTION(registration->Update());
  const double parSeconds = SecondsSince(clock);
  const double parError = TrueError(example, registration->GetTransform());
  std::cout << "par: true error " << errorBefore << " -> " << parError << " mm; metric "
            << registration->GetInitialMetricValue() << " -> " << registration->GetFinalMetricValue()
            << " mm^2; mean distance " << registration->GetInitialMeanDistance() << " -> "
            << registration->GetFinalMeanDistance() << " mm; " << registration->GetMetricValues().size()
            << " iterations, " << parSeconds << " s\n  " << registration->GetStopConditionDescription() << std::endl;
  int status = EXIT_SUCCESS;
  ITK_TEST_EXPECT_TRUE(parError <= 0.2 * errorBefore);
  ITK_TEST_EXPECT_TRUE(registration->GetFinalMetricValue() < registration->GetInitialMetricValue());
  ITK_TEST_EXPECT_TRUE(registration->GetFinalMeanDistance() < 0.1 * registration->GetInitialMeanDistance());
  ITK_TEST_EXPECT_EQUAL(iterationEvents, registration->GetMetricValues().size());
  ITK_TEST_EXPECT_TRUE(iterationEvents > 0);
  ITK_TEST_EXPECT_TRUE(registration->GetTransformOutput()->Get() == registration->GetTransform());
  ITK_TEST_EXPECT_TRUE(registration->GetParametricTransform() != nullptr);
  ITK_TEST_EXPECT_TRUE(templates->GetParameters().GetSize() == templates->GetNumberOfTemplates()); // not changed
  ITK_TEST_EXPECT_EQUAL(templates->GetParameters()[0], 0.0);

  // The result moves the source region onto the target through the inverse mesh filter.
  auto apply = ApplyType::New();
  apply->SetInput(example.region);
  apply->SetTransformInput(registration->GetTransformOutput());
  apply->InverseOn();
  apply->SetInverseTolerance(1e-6);
  ITK_TRY_EXPECT_NO_EXCEPTION(apply->Update());
  ITK_TEST_EXPECT_EQUAL(apply->GetNumberOfNonConvergedPoints(), 0u);
  double vertexError = 0.0;
  for (auto it = apply->GetOutput()->GetPoints()->Begin(); it != apply->GetOutput()->GetPoints()->End(); ++it)
  {
    vertexError += (it.Value() - example.target->GetPoint(it.Index())).GetNorm();
  }
  vertexError /= example.target->GetNumberOfPoints();
  std::cout << "Deformed source region vs target: mean vertex error " << vertexError << " mm" << std::endl;
  ITK_TEST_EXPECT_TRUE(vertexError <= 0.25 * errorBefore);

  // The (1+1) evolution strategy runs and never ends worse than it starts.
  registration->SetOptimizer(RegistrationType::OptimizerEnum::OnePlusOneEvolutionary);
  registration->SetNumberOfIterations(60);
  registration->SetNumberOfExactRefinementIterations(0);
  clock = std::chrono::steady_clock::now();
  ITK_TRY_EXPECT_NO_EXCEPTION(registration->Update());
  std::cout << "par (1+1 ES, 60 iterations): true error " << TrueError(example, registration->GetTransform())
            << " mm; metric " << registration->GetInitialMetricValue() << " -> " << registration->GetFinalMetricValue()
            << " mm, " << SecondsSince(clock) << " s" << std::endl;
  ITK_TEST_EXPECT_TRUE(registration->GetFinalMetricValue() <= registration->GetInitialMetricValue());

  // GO, then GO + Par: the GO result is the base (on the templates' grid), Par refines it through the pipeline.
  // Run-time limit. A negative limit is clamped to none, as for the image methods.
  ITK_TEST_SET_GET_VALUE(0.0, registration->GetMaximumRunTime());
  registration->SetMaximumRunTime(-1.0);
  ITK_TEST_SET_GET_VALUE(0.0, registration->GetMaximumRunTime());
  ITK_TEST_EXPECT_TRUE(!registration->GetTimeLimitReached());
  // A limit already past at the first iteration stops every optimizer there, and skips the exact refinement.
  registration->SetNumberOfExactRefinementIterations(50);
  for (const auto optimizer : { RegistrationType::OptimizerEnum::LBFGS,
                                RegistrationType::OptimizerEnum::LBFGSB,
                                RegistrationType::OptimizerEnum::OnePlusOneEvolutionary })
  {
    registration->SetOptimizer(optimizer);
    registration->SetMaximumRunTime(1e-9);
    ITK_TRY_EXPECT_NO_EXCEPTION(registration->Update());
    std::cout << optimizer << " limited to 1e-9 s: " << registration->GetMetricValues().size() << " iteration(s); "
              << registration->GetStopConditionDescription();
    ITK_TEST_EXPECT_TRUE(registration->GetTimeLimitReached());
    // The (1+1) strategy makes one iteration. The quasi-Newton optimizers stop at their first iteration too, but
    // their function evaluations are iteration events as well (FunctionEvaluationIterationEvent is an
    // IterationEvent): a few events, against hundreds without the limit.
    const auto events = registration->GetMetricValues().size();
    ITK_TEST_EXPECT_TRUE(
      optimizer == RegistrationType::OptimizerEnum::OnePlusOneEvolutionary ? events == 1 : events >= 1 && events <= 5);
    ITK_TEST_EXPECT_TRUE(registration->GetStopConditionDescription().find("stopped early") != std::string::npos);
    ITK_TEST_EXPECT_TRUE(registration->GetFinalMetricValue() <= registration->GetInitialMetricValue());
    ITK_TEST_EXPECT_TRUE(registration->GetParametricTransform() != nullptr);
  }
  // A run of a huge number of (slow, exact) iterations that would not converge stops at a limit of 0.5 s, with a
  // valid transform no worse than the start. The bound on the time it took allows for a sanitizer build on a loaded
  // machine: 10 s, far below the unlimited run.
  registration->SetOptimizer(RegistrationType::OptimizerEnum::OnePlusOneEvolutionary);
  registration->SetEvaluation(RegistrationType::EvaluationEnum::ExactPointToTriangle);
  registration->SetConvergenceTolerance(0.0);
  registration->SetNumberOfIterations(100000000);
  registration->SetMaximumRunTime(0.5);
  ITK_TEST_SET_GET_VALUE(0.5, registration->GetMaximumRunTime());
  clock = std::chrono::steady_clock::now();
  ITK_TRY_EXPECT_NO_EXCEPTION(registration->Update());
  {
    const double seconds = SecondsSince(clock);
    const auto * limited = registration->GetParametricTransform();
    bool         finite = limited != nullptr;
    for (unsigned int i = 0; finite && i < limited->GetNumberOfParameters(); ++i)
    {
      finite = std::isfinite(limited->GetParameters()[i]);
    }
    std::cout << "par (1+1 ES, 10^8 exact iterations) limited to 0.5 s: " << seconds << " s, "
              << registration->GetMetricValues().size() << " iterations, true error "
              << TrueError(example, registration->GetTransform()) << " mm" << std::endl;
    ITK_TEST_EXPECT_TRUE(seconds < 10.0);
    ITK_TEST_EXPECT_TRUE(registration->GetTimeLimitReached());
    ITK_TEST_EXPECT_TRUE(finite);
    ITK_TEST_EXPECT_TRUE(registration->GetFinalMetricValue() <= registration->GetInitialMetricValue());
    ITK_TEST_EXPECT_TRUE(TrueError(example, registration->GetTransform()) <= errorBefore);
  }
  registration->SetMaximumRunTime(0.0);
  registration->SetEvaluation(RegistrationType::EvaluationEnum::LinearDistanceMap);
  registration->SetConvergenceTolerance(1e-5);
  std::cout << registration;

  auto go = MakeGO(example);
  clock = std::chrono::steady_clock::now();
  ITK_TRY_EXPECT_NO_EXCEPTION(go->Update());
  const double goSeconds = SecondsSince(clock);
  const double goError = TrueError(example, go->GetTransform());
  registration->SetOptimizer(RegistrationType::OptimizerEnum::LBFGS);
  registration->SetNumberOfIterations(100);
  registration->SetNumberOfExactRefinementIterations(50);
  registration->SetBaseTransformInput(go->GetTransformOutput());
  registration->ResampleBaseTransformOff(); // the GO grid is the templates' grid: used exactly
  for (const auto mode :
       { RegistrationType::BaseTransformModeEnum::ProjectOntoTemplates, RegistrationType::BaseTransformModeEnum::Base })
  {
    registration->SetBaseTransformMode(mode);
    clock = std::chrono::steady_clock::now();
    ITK_TRY_EXPECT_NO_EXCEPTION(registration->Update());
    const double goParSeconds = SecondsSince(clock);
    const double goParError = TrueError(example, registration->GetTransform());
    std::cout << "go: true error " << goError << " mm (" << goSeconds << " s); go+par (" << mode << "): " << goParError
              << " mm (" << goParSeconds << " s), mean distance " << registration->GetInitialMeanDistance() << " -> "
              << registration->GetFinalMeanDistance() << std::endl;
    if (mode == RegistrationType::BaseTransformModeEnum::ProjectOntoTemplates)
    {
      ITK_TEST_EXPECT_TRUE(goParError <= goError);
    }
    else
    {
      // The base is GO exactly (same grid), so the starting mean distance is GO's.
      const auto & goParameters = go->GetTransform()->GetParameters();
      ITK_TEST_EXPECT_TRUE(registration->GetParametricTransform()->GetBaseCoefficients() ==
                           ParametricType::CoefficientVectorType(goParameters.begin(), goParameters.end()));
    }
  }
  return status;
}
