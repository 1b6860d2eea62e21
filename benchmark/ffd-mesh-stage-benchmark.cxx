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
// ffd-mesh-stage-benchmark: times the mesh stage of the pipeline (benchmark/mesh_stage.py, MESH_STAGE.md).
//
//   ffd-mesh-stage-benchmark (--inverse-mesh MESH --distance-mesh MESH | --sphere RESOLUTION)
//                            [--scale-to 100] [--grid 20] [--sigma 1] [--clip 1] [--margin 5]
//                            [--deform-rms 2] [--seed 1] [--threads 1,2] [--repeat 3] [--json FILE] [--check]
//                            [--inverse-only]
//
// 1. Inverse: the inverse-mesh, scaled so its largest side is --scale-to mm (bounding box from the origin), is
//    moved by the inverse of a random B-spline (RandomBSplineTransformGenerator, --grid control points per axis
//    over the bounding box grown by --margin mm, clipped Gaussian noise --sigma / --clip mm, seed --seed) with
//    ApplyTransformToMeshFilter (InverseOn, its defaults), for each thread count of --threads (best of --repeat
//    runs, a fresh filter each time). Reported: time, converged vertices, max |T(T^-1(p)) - p| (recomputed
//    here with TransformPoint) over converged vertices and over all.
// 2. Distances: the distance-mesh (scaled the same way) and a deformed copy of it (forward application of a
//    smooth random B-spline, RMS control displacement --deform-rms mm, seed --seed + 1): per-vertex exact
//    point-to-surface distances in both directions by MeshSurfaceDistanceCalculator (for each thread count) and
//    by VTK's vtkHausdorffDistancePointSetFilter (point-to-cell, one run computes both directions; serial in
//    VTK 9.1), in the same run; reported: times, directed and symmetric Hausdorff distances, mean distances,
//    and the largest per-vertex difference between the two.
//
// --inverse-only skips stage 2. --sphere RESOLUTION replaces both meshes with a generated sphere
// (RegularSphereMeshSource; resolution 4: 1,026 vertices, 2,048 triangles), for the smoke test. --check exits
// with status 1 unless >= 99.9 % of the vertices converge, every converged vertex satisfies
// |T(T^-1(p)) - p| < 1e-5 mm, the inverse is the same for every thread count, and the module and VTK agree per
// vertex and on the Hausdorff distances to 1e-6 mm; it prints "mesh stage check passed" otherwise.

#include "FFDProgramMeshIO.h"
#include "FFDProgramSupport.h"
#include "itkApplyTransformToMeshFilter.h"
#include "itkMesh.h"
#include "itkMeshSurfaceDistanceCalculator.h"
#include "itkMeshVTKPolyDataConversion.h"
#include "itkMultiThreaderBase.h"
#include "itkRandomBSplineTransformGenerator.h"
#include "itkRegisterFFDShapeMatchingMeshIOFactories.h"
#include "itkRegularSphereMeshSource.h"
#include "itkTriangleCell.h"

#include "vtkDataArray.h"
#include "vtkHausdorffDistancePointSetFilter.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPointSet.h"
#include "vtkPolyData.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <ctime>
#include <fstream>
#include <functional>
#include <iostream>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace
{
using MeshTraitsType = itk::DefaultStaticMeshTraits<double, 3, 3, double, double, double>;
using MeshType = itk::Mesh<double, 3, MeshTraitsType>;
using ApplyType = itk::ApplyTransformToMeshFilter<MeshType, MeshType>;
using GeneratorType = itk::RandomBSplineTransformGenerator<double, 3>;
using DistanceType = itk::MeshSurfaceDistanceCalculator<MeshType>;
using ffd::ClockType;

struct Error : std::runtime_error
{
  using std::runtime_error::runtime_error;
};

struct Options
{
  std::string      inverseMesh;
  std::string      distanceMesh;
  unsigned int     sphereResolution{ 0 };
  double           scaleTo{ 100.0 };
  unsigned int     grid{ 20 };
  double           sigma{ 1.0 };
  double           clip{ 1.0 };
  double           margin{ 5.0 };
  double           deformRMS{ 2.0 };
  uint32_t         seed{ 1 };
  std::vector<int> threads{ 1, 2 };
  int              repeat{ 3 };
  std::string      json;
  bool             check{ false };
  bool             distances{ true };
};

/** Best wall time (s) of `repeat` runs; a run over 5 s is not repeated. `cpuSeconds`, when given, receives the
 * process CPU time (all threads) of that best run: on a shared machine, CPU time near wall time with two threads
 * means the process got one core's worth of time. */
double
BestSeconds(const std::function<void()> & run, int repeat, double * cpuSeconds = nullptr)
{
  double best = std::numeric_limits<double>::infinity();
  for (int r = 0; r < repeat; ++r)
  {
    const std::clock_t cpuStart = std::clock();
    const auto         start = ClockType::now();
    run();
    const double seconds = ffd::SecondsSince(start);
    if (seconds < best)
    {
      best = seconds;
      if (cpuSeconds != nullptr)
      {
        *cpuSeconds = static_cast<double>(std::clock() - cpuStart) / CLOCKS_PER_SEC;
      }
    }
    if (best > 5.0)
    {
      break;
    }
  }
  return best;
}

/** Counts the triangles of a mesh. */
itk::SizeValueType
NumberOfTriangles(const MeshType * mesh)
{
  itk::SizeValueType count = 0;
  for (auto it = mesh->GetCells()->Begin(); it != mesh->GetCells()->End(); ++it)
  {
    count += (it.Value()->GetNumberOfPoints() >= 3) ? it.Value()->GetNumberOfPoints() - 2 : 0;
  }
  return count;
}

MeshType::Pointer
ScaledTriangles(const MeshType * mesh, double side)
{
  return ffd::ScaledTriangleCopy(mesh, side, ffd::MeshPlacement::LowerCornerAtOrigin);
}

/** The mesh of a file, or the generated sphere when --sphere is given; scaled. */
MeshType::Pointer
LoadMesh(const std::string & fileName, const Options & options)
{
  MeshType::Pointer mesh;
  if (options.sphereResolution > 0)
  {
    auto                                               sphere = itk::RegularSphereMeshSource<MeshType>::New();
    itk::RegularSphereMeshSource<MeshType>::VectorType scale;
    scale.Fill(1.0);
    sphere->SetScale(scale);
    sphere->SetResolution(options.sphereResolution);
    sphere->Update();
    mesh = sphere->GetOutput();
  }
  else
  {
    mesh = ffd::ReadCheckedMesh<Error, MeshType>(fileName, "input");
  }
  MeshType::Pointer scaled = ScaledTriangles(mesh, options.scaleTo);
  if (scaled->GetNumberOfPoints() == 0 || scaled->GetNumberOfCells() == 0)
  {
    throw Error("mesh '" + fileName + "' has no triangles");
  }
  return scaled;
}

/** Bounding box of a mesh's points grown by `margin` on every side. */
void
GrownBounds(const MeshType * mesh, double margin, GeneratorType::PointType & lower, GeneratorType::PointType & upper)
{
  lower.Fill(std::numeric_limits<double>::infinity());
  upper.Fill(-std::numeric_limits<double>::infinity());
  for (auto it = mesh->GetPoints()->Begin(); it != mesh->GetPoints()->End(); ++it)
  {
    for (unsigned int k = 0; k < 3; ++k)
    {
      lower[k] = std::min(lower[k], it.Value()[k] - margin);
      upper[k] = std::max(upper[k], it.Value()[k] + margin);
    }
  }
}

struct ThreadTime
{
  int    threads{ 1 };
  double seconds{ 0.0 };
  double cpuSeconds{ 0.0 };
};

std::string
ThreadTimesJson(const std::vector<ThreadTime> & times)
{
  std::ostringstream out;
  out << "[";
  for (std::size_t i = 0; i < times.size(); ++i)
  {
    out << (i ? ", " : "") << "{\"threads\": " << times[i].threads
        << ", \"seconds\": " << ffd::JsonNumber(times[i].seconds)
        << ", \"cpu_seconds\": " << ffd::JsonNumber(times[i].cpuSeconds) << "}";
  }
  out << "]";
  return out.str();
}

/** A random B-spline generator over the mesh's bounding box grown by --margin, with --grid control points per axis;
 * the caller sets the noise. */
GeneratorType::Pointer
MakeGeneratorOver(const MeshType * mesh, const Options & options)
{
  auto                     generator = GeneratorType::New();
  GeneratorType::PointType lower;
  GeneratorType::PointType upper;
  GrownBounds(mesh, options.margin, lower, upper);
  generator->SetDomainFromBoundingBox(lower, upper);
  generator->SetNumberOfControlPointsPerAxis(options.grid);
  return generator;
}

/** Stage 1: inverse application. Appends its JSON object to `json`; returns false if a --check criterion fails. */
bool
RunInverse(const Options & options, std::ostringstream & json)
{
  const MeshType::Pointer      mesh = LoadMesh(options.inverseMesh, options);
  const GeneratorType::Pointer generator = MakeGeneratorOver(mesh, options);
  generator->SetSigma(options.sigma);
  generator->SetClipAmplitude(options.clip);
  generator->SetSeed(options.seed);
  generator->Generate();
  const GeneratorType::TransformType * transform = generator->GetTransform();
  const auto &                         gridSpacing = transform->GetCoefficientImages()[0]->GetSpacing();
  const double                         spacing = std::max({ gridSpacing[0], gridSpacing[1], gridSpacing[2] });
  std::cerr << "inverse: " << mesh->GetNumberOfPoints() << " vertices, " << NumberOfTriangles(mesh)
            << " triangles, grid " << options.grid << "^3 (spacing up to " << spacing << " mm), min det J "
            << generator->GetMinimumJacobianDeterminant() << std::endl;

  std::vector<ThreadTime>          times;
  ApplyType::Pointer               filter;
  std::vector<MeshType::PointType> firstResult;
  bool                             sameAcrossThreads = true;
  for (const int threads : options.threads)
  {
    itk::MultiThreaderBase::SetGlobalDefaultNumberOfThreads(static_cast<itk::ThreadIdType>(threads));
    double       cpuSeconds = 0.0;
    const double seconds = BestSeconds(
      [&]() {
        filter = ApplyType::New();
        filter->SetNumberOfWorkUnits(static_cast<itk::ThreadIdType>(threads));
        filter->SetInput(mesh);
        filter->SetTransform(transform);
        filter->InverseOn();
        filter->Update();
      },
      options.repeat,
      &cpuSeconds);
    times.push_back({ threads, seconds, cpuSeconds });
    std::cerr << "  " << threads << " thread(s): " << seconds << " s" << std::endl;
    const MeshType * output = filter->GetOutput();
    for (itk::IdentifierType i = 0; i < output->GetNumberOfPoints(); ++i)
    {
      if (firstResult.size() < output->GetNumberOfPoints())
      {
        firstResult.push_back(output->GetPoint(i));
      }
      else if (firstResult[i] != output->GetPoint(i))
      {
        sameAcrossThreads = false;
      }
    }
  }

  // Round-trip errors, recomputed from the output positions.
  const MeshType *   output = filter->GetOutput();
  const auto &       converged = filter->GetInverseConverged();
  double             maximumConverged = 0.0;
  double             maximumAll = 0.0;
  double             sumConverged = 0.0;
  itk::SizeValueType numberConverged = 0;
  for (itk::IdentifierType i = 0; i < mesh->GetNumberOfPoints(); ++i)
  {
    const double error = transform->TransformPoint(output->GetPoint(i)).EuclideanDistanceTo(mesh->GetPoint(i));
    maximumAll = std::max(maximumAll, error);
    if (converged[i])
    {
      ++numberConverged;
      sumConverged += error;
      maximumConverged = std::max(maximumConverged, error);
    }
  }
  double maximumDisplacement = 0.0;
  for (itk::IdentifierType i = 0; i < mesh->GetNumberOfPoints(); ++i)
  {
    maximumDisplacement = std::max(maximumDisplacement, output->GetPoint(i).EuclideanDistanceTo(mesh->GetPoint(i)));
  }
  const double percent = 100.0 * static_cast<double>(numberConverged) / mesh->GetNumberOfPoints();
  std::cerr << "  converged " << numberConverged << " of " << mesh->GetNumberOfPoints() << " (" << percent
            << " %), max |T(T^-1(p)) - p| " << maximumConverged << " mm (all vertices: " << maximumAll
            << " mm), largest vertex displacement " << maximumDisplacement << " mm"
            << (sameAcrossThreads ? "" : ", RESULTS DIFFER BETWEEN THREAD COUNTS") << std::endl;

  json << "\"inverse\": {\"mesh\": " << ffd::JsonString(options.inverseMesh)
       << ", \"vertices\": " << mesh->GetNumberOfPoints() << ", \"triangles\": " << NumberOfTriangles(mesh)
       << ", \"scale_to_mm\": " << ffd::JsonNumber(options.scaleTo) << ", \"grid\": " << options.grid
       << ", \"control_spacing_mm\": " << ffd::JsonNumber(spacing)
       << ", \"margin_mm\": " << ffd::JsonNumber(options.margin) << ", \"sigma_mm\": " << ffd::JsonNumber(options.sigma)
       << ", \"clip_mm\": " << ffd::JsonNumber(options.clip) << ", \"seed\": " << options.seed
       << ", \"min_jacobian_determinant\": " << ffd::JsonNumber(generator->GetMinimumJacobianDeterminant())
       << ", \"tolerance_mm\": " << ffd::JsonNumber(filter->GetInverseTolerance())
       << ", \"max_iterations\": " << filter->GetMaximumNumberOfInverseIterations()
       << ", \"times\": " << ThreadTimesJson(times) << ", \"converged\": " << numberConverged
       << ", \"converged_percent\": " << ffd::JsonNumber(percent)
       << ", \"non_converged\": " << filter->GetNumberOfNonConvergedPoints()
       << ", \"max_round_trip_error_converged_mm\": " << ffd::JsonNumber(maximumConverged)
       << ", \"mean_round_trip_error_converged_mm\": "
       << ffd::JsonNumber(sumConverged / std::max<double>(1, numberConverged))
       << ", \"max_round_trip_error_all_mm\": " << ffd::JsonNumber(maximumAll)
       << ", \"max_vertex_displacement_mm\": " << ffd::JsonNumber(maximumDisplacement)
       << ", \"same_result_for_all_thread_counts\": " << (sameAcrossThreads ? "true" : "false") << "}";

  bool ok = true;
  if (percent < 99.9)
  {
    std::cerr << "check: only " << percent << " % of the vertices converged" << std::endl;
    ok = false;
  }
  if (maximumConverged >= 1e-5)
  {
    std::cerr << "check: a converged vertex has |T(T^-1(p)) - p| = " << maximumConverged << " mm" << std::endl;
    ok = false;
  }
  if (!sameAcrossThreads)
  {
    std::cerr << "check: the result depends on the thread count" << std::endl;
    ok = false;
  }
  return ok;
}

/** The point array "Distance" of a VTK output, as a vector. */
std::vector<double>
DistanceArray(vtkPointSet * output)
{
  vtkDataArray * array = output->GetPointData()->GetArray("Distance");
  if (array == nullptr)
  {
    throw Error("vtkHausdorffDistancePointSetFilter gave no 'Distance' array");
  }
  std::vector<double> values(static_cast<std::size_t>(array->GetNumberOfTuples()));
  for (vtkIdType i = 0; i < array->GetNumberOfTuples(); ++i)
  {
    values[static_cast<std::size_t>(i)] = array->GetTuple1(i);
  }
  return values;
}

double
LargestDifference(const std::vector<double> & a, const std::vector<double> & b)
{
  if (a.size() != b.size())
  {
    return std::numeric_limits<double>::infinity();
  }
  double largest = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i)
  {
    largest = std::max(largest, std::abs(a[i] - b[i]));
  }
  return largest;
}

double
Mean(const std::vector<double> & values)
{
  double sum = 0.0;
  for (const double value : values)
  {
    sum += value;
  }
  return values.empty() ? 0.0 : sum / values.size();
}

/** Stage 2: distances, module against VTK. */
bool
RunDistances(const Options & options, std::ostringstream & json)
{
  const MeshType::Pointer      meshA = LoadMesh(options.distanceMesh, options);
  const GeneratorType::Pointer generator = MakeGeneratorOver(meshA, options);
  generator->SetNoise(GeneratorType::NoiseEnum::SmoothedGaussian);
  generator->SetSmoothingSigma(2.5);
  generator->SetRMSDisplacement(options.deformRMS);
  generator->SetSeed(options.seed + 1);
  generator->Generate();
  auto deform = ApplyType::New();
  deform->SetInput(meshA);
  deform->SetTransform(generator->GetTransform());
  deform->Update();
  const MeshType::Pointer meshB = deform->GetOutput();
  std::cerr << "distances: A " << meshA->GetNumberOfPoints() << " vertices, " << NumberOfTriangles(meshA)
            << " triangles; B = A deformed (RMS control displacement " << options.deformRMS << " mm, min det J "
            << generator->GetMinimumJacobianDeterminant() << ")" << std::endl;

  // The module: A -> B and B -> A.
  std::vector<ThreadTime> moduleTimes;
  std::vector<double>     moduleAB;
  std::vector<double>     moduleBA;
  for (const int threads : options.threads)
  {
    itk::MultiThreaderBase::SetGlobalDefaultNumberOfThreads(static_cast<itk::ThreadIdType>(threads));
    double       cpuSeconds = 0.0;
    const double seconds = BestSeconds(
      [&]() {
        auto forward = DistanceType::New();
        forward->SetNumberOfWorkUnits(static_cast<unsigned int>(threads));
        forward->SetSourceMesh(meshA);
        forward->SetTargetMesh(meshB);
        forward->Compute();
        auto backward = DistanceType::New();
        backward->SetNumberOfWorkUnits(static_cast<unsigned int>(threads));
        backward->SetSourceMesh(meshB);
        backward->SetTargetMesh(meshA);
        backward->Compute();
        moduleAB = forward->GetDistances();
        moduleBA = backward->GetDistances();
      },
      options.repeat,
      &cpuSeconds);
    moduleTimes.push_back({ threads, seconds, cpuSeconds });
    std::cerr << "  module, " << threads << " thread(s): " << seconds << " s (both directions)" << std::endl;
  }

  // VTK: one filter run computes both directions.
  vtkNew<vtkPolyData> polyA;
  vtkNew<vtkPolyData> polyB;
  itk::MeshToVTKPolyData(meshA.GetPointer(), polyA);
  itk::MeshToVTKPolyData(meshB.GetPointer(), polyB);
  std::vector<double> vtkAB;
  std::vector<double> vtkBA;
  double              vtkHausdorff = 0.0;
  double              vtkRelative[2] = { 0.0, 0.0 };
  double              vtkCPUSeconds = 0.0;
  const double        vtkSeconds = BestSeconds(
    [&]() {
      vtkNew<vtkHausdorffDistancePointSetFilter> hausdorff;
      hausdorff->SetInputData(0, polyA);
      hausdorff->SetInputData(1, polyB);
      hausdorff->SetTargetDistanceMethodToPointToCell();
      hausdorff->Update();
      vtkAB = DistanceArray(vtkPointSet::SafeDownCast(hausdorff->GetOutputDataObject(0)));
      vtkBA = DistanceArray(vtkPointSet::SafeDownCast(hausdorff->GetOutputDataObject(1)));
      vtkHausdorff = hausdorff->GetHausdorffDistance();
      hausdorff->GetRelativeDistance(vtkRelative);
    },
    options.repeat,
    &vtkCPUSeconds);
  std::cerr << "  vtkHausdorffDistancePointSetFilter: " << vtkSeconds << " s (both directions)" << std::endl;

  const double moduleHausdorffAB = moduleAB.empty() ? 0.0 : *std::max_element(moduleAB.begin(), moduleAB.end());
  const double moduleHausdorffBA = moduleBA.empty() ? 0.0 : *std::max_element(moduleBA.begin(), moduleBA.end());
  const double moduleHausdorff = std::max(moduleHausdorffAB, moduleHausdorffBA);
  const double differenceAB = LargestDifference(moduleAB, vtkAB);
  const double differenceBA = LargestDifference(moduleBA, vtkBA);
  const double differenceHausdorff = std::max({ std::abs(moduleHausdorff - vtkHausdorff),
                                                std::abs(moduleHausdorffAB - vtkRelative[0]),
                                                std::abs(moduleHausdorffBA - vtkRelative[1]) });
  std::cerr << "  Hausdorff: module " << moduleHausdorff << " (A->B " << moduleHausdorffAB << ", B->A "
            << moduleHausdorffBA << "), VTK " << vtkHausdorff << " (" << vtkRelative[0] << ", " << vtkRelative[1]
            << "); mean A->B " << Mean(moduleAB) << " / " << Mean(vtkAB) << "; largest per-vertex difference "
            << std::max(differenceAB, differenceBA) << " mm" << std::endl;

  json << "\"distances\": {\"mesh\": " << ffd::JsonString(options.distanceMesh)
       << ", \"vertices\": " << meshA->GetNumberOfPoints() << ", \"triangles\": " << NumberOfTriangles(meshA)
       << ", \"deform_rms_mm\": " << ffd::JsonNumber(options.deformRMS)
       << ", \"deform_min_jacobian_determinant\": " << ffd::JsonNumber(generator->GetMinimumJacobianDeterminant())
       << ", \"module_times\": " << ThreadTimesJson(moduleTimes) << ", \"vtk_seconds\": " << ffd::JsonNumber(vtkSeconds)
       << ", \"vtk_cpu_seconds\": " << ffd::JsonNumber(vtkCPUSeconds)
       << ", \"module_hausdorff_mm\": " << ffd::JsonNumber(moduleHausdorff) << ", \"module_directed_hausdorff_mm\": ["
       << ffd::JsonNumber(moduleHausdorffAB) << ", " << ffd::JsonNumber(moduleHausdorffBA) << "], \"module_mean_mm\": ["
       << ffd::JsonNumber(Mean(moduleAB)) << ", " << ffd::JsonNumber(Mean(moduleBA))
       << "], \"vtk_hausdorff_mm\": " << ffd::JsonNumber(vtkHausdorff) << ", \"vtk_relative_distance_mm\": ["
       << ffd::JsonNumber(vtkRelative[0]) << ", " << ffd::JsonNumber(vtkRelative[1]) << "], \"vtk_mean_mm\": ["
       << ffd::JsonNumber(Mean(vtkAB)) << ", " << ffd::JsonNumber(Mean(vtkBA)) << "], \"max_vertex_difference_mm\": ["
       << ffd::JsonNumber(differenceAB) << ", " << ffd::JsonNumber(differenceBA)
       << "], \"max_hausdorff_difference_mm\": " << ffd::JsonNumber(differenceHausdorff) << "}";

  if (!(std::max(differenceAB, differenceBA) < 1e-6) || !(differenceHausdorff < 1e-6))
  {
    std::cerr << "check: the module and VTK differ by " << std::max(differenceAB, differenceBA) << " mm per vertex and "
              << differenceHausdorff << " mm in the Hausdorff distances" << std::endl;
    return false;
  }
  return true;
}

std::vector<int>
ParseThreads(const std::string & text)
{
  std::vector<int>  threads;
  std::stringstream stream(text);
  std::string       item;
  while (std::getline(stream, item, ','))
  {
    const double value = ffd::ParseNumber<Error>("--threads", item);
    if (value < 1 || value != std::floor(value))
    {
      throw Error("--threads needs positive integers, not '" + item + "'");
    }
    threads.push_back(static_cast<int>(value));
  }
  if (threads.empty())
  {
    throw Error("--threads needs at least one thread count");
  }
  return threads;
}

Options
ParseArguments(int argc, char * argv[])
{
  Options options;
  for (int i = 1; i < argc; ++i)
  {
    const std::string option = argv[i];
    if (option == "--check")
    {
      options.check = true;
      continue;
    }
    if (option == "--inverse-only")
    {
      options.distances = false;
      continue;
    }
    if (i + 1 >= argc)
    {
      throw Error("unknown option or missing value: " + option);
    }
    const std::string value = argv[++i];
    const auto        number = [&]() { return ffd::ParseNumber<Error>(option, value); };
    if (option == "--inverse-mesh")
      options.inverseMesh = value;
    else if (option == "--distance-mesh")
      options.distanceMesh = value;
    else if (option == "--sphere")
      options.sphereResolution = static_cast<unsigned int>(std::max(1.0, number()));
    else if (option == "--scale-to")
      options.scaleTo = number();
    else if (option == "--grid")
      options.grid = static_cast<unsigned int>(std::max(4.0, number()));
    else if (option == "--sigma")
      options.sigma = number();
    else if (option == "--clip")
      options.clip = number();
    else if (option == "--margin")
      options.margin = number();
    else if (option == "--deform-rms")
      options.deformRMS = number();
    else if (option == "--seed")
      options.seed = static_cast<uint32_t>(number());
    else if (option == "--threads")
      options.threads = ParseThreads(value);
    else if (option == "--repeat")
      options.repeat = static_cast<int>(std::max(1.0, number()));
    else if (option == "--json")
      options.json = value;
    else
      throw Error("unknown option: " + option);
  }
  if (options.sphereResolution > 0)
  {
    options.inverseMesh = options.distanceMesh = "sphere (resolution " + std::to_string(options.sphereResolution) + ")";
  }
  else if (options.inverseMesh.empty() || (options.distances && options.distanceMesh.empty()))
  {
    throw Error("give --inverse-mesh and --distance-mesh (or --inverse-only), or --sphere RESOLUTION");
  }
  return options;
}
} // namespace

int
main(int argc, char * argv[])
{
  try
  {
    const Options options = ParseArguments(argc, argv);
    itk::RegisterFFDShapeMatchingMeshIOFactories();
    std::ostringstream json;
    json << "{\"threads\": [";
    for (std::size_t i = 0; i < options.threads.size(); ++i)
    {
      json << (i ? ", " : "") << options.threads[i];
    }
    json << "], \"repeat\": " << options.repeat << ", ";
    bool ok = RunInverse(options, json);
    if (options.distances)
    {
      json << ", ";
      ok = RunDistances(options, json) && ok;
    }
    json << "}\n";
    if (!options.json.empty())
    {
      std::ofstream out(options.json);
      out << json.str();
      if (!out)
      {
        throw Error("cannot write '" + options.json + "'");
      }
    }
    else
    {
      std::cout << json.str();
    }
    if (options.check)
    {
      if (!ok)
      {
        return EXIT_FAILURE;
      }
      std::cout << "mesh stage check passed" << std::endl;
    }
    return EXIT_SUCCESS;
  }
  catch (const std::exception & error)
  {
    std::cerr << "ffd-mesh-stage-benchmark: error: " << ffd::OneLine(error.what()) << std::endl;
    return EXIT_FAILURE;
  }
}
