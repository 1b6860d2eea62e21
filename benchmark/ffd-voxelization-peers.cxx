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
// ffd-voxelization-peers: times TriangleMeshToVoxelImageFilter and its peers on one mesh and one grid,
// and scores every result against a reference computed voxel by voxel.
//
//   ffd-voxelization-peers MESH [--scale-to L] [--voxel-size S] [--margin M] [--threads N] [--repeat R]
//                          [--vtk-distance-voxels N] [--reference-beta B] [--tasks occupancy,solid,sdf]
//                          [--patch-radius R] [--no-reference] [--reference-band] [--no-exact-sdf]
//                          [--no-vtk-distance] [--json FILE]
//
// Peers, on the same triangles and the same grid (voxel centres origin + i * S):
//   occupancy  module (Occupancy)          vs vtkVoxelModeller
//   solid      module (Solid)              vs itk::TriangleMeshToBinaryImageFilter, vtkPolyDataToImageStencil
//                                             + vtkImageStencil
//   sdf        module (SignedDistance, band and exact) vs vtkImplicitPolyDataDistance (evaluated per voxel)
//                                             and itk::SignedMaurerDistanceMapImageFilter on ITK's binary image
// References (not timed): inside = |generalized winding number| > 1/2, evaluated per voxel with the
// module's reference path (ScanLineAccelerationOff, Beta = --reference-beta); distance = exact
// point-to-triangle distance per voxel (reference path, ExactDistanceOn), signed by that inside.
// vtkImplicitPolyDataDistance is evaluated on at most --vtk-distance-voxels voxels (whole z slices
// spread over the grid); its time is scaled to the whole grid and flagged as such.
// Times are the best of --repeat runs (one run when it takes over 2 s), each from a fresh filter
// (hierarchies and locators included), for each thread count of --threads (e.g. 1,2).
// Memory: before the first run of a peer its previous output is released, the free heap returned to the
// system (malloc_trim), the kernel's peak-RSS mark reset (/proc/self/clear_refs) and the RSS read; the
// reported peak is VmHWM - that RSS after the run: what the peer allocates on top of what the program
// already holds (mesh, references), its output included.
// --no-reference skips the references (timing and memory only, for the growth runs); --reference-band makes
// the reference distance exact only up to twice the sdf band (errors then scored in the band only); --no-exact-sdf
// skips the module's exact-everywhere distance and --no-vtk-distance vtkImplicitPolyDataDistance.
// --patch-radius R (open patch): the peers run on the triangles whose centroid lies within R of the mesh
// vertex nearest to the centre of the bounding box's +x face, an open surface cut out of the (scaled) mesh;
// the grid still covers the whole mesh. Its references: inside = inside of the whole mesh (winding number),
// distance = distance to the patch. Inside/outside is scored only where the patch decides it: voxels nearer
// to the patch than to the rest of the mesh by more than half a voxel diagonal (the side of the patch they
// lie on is the whole mesh's inside there); occupancy (a distance rule) is scored everywhere.

#include "FFDProgramMeshIO.h"
#include "itkImage.h"
#include "itkMesh.h"
#include "itkMeshFileReader.h"
#include "itkMeshVTKPolyDataConversion.h"
#include "itkMultiThreaderBase.h"
#include "itkRegisterFFDShapeMatchingMeshIOFactories.h"
#include "itkSignedMaurerDistanceMapImageFilter.h"
#include "itkTriangleCell.h"
#include "itkTriangleMeshToBinaryImageFilter.h"
#include "itkTriangleMeshToVoxelImageFilter.h"

#include "vtkImageData.h"
#include "vtkImageStencil.h"
#include "vtkImplicitPolyDataDistance.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"
#include "vtkPolyDataToImageStencil.h"
#include "vtkTriangleFilter.h"
#include "vtkVoxelModeller.h"

#include <algorithm>
#include <array>
#include <map>
#if defined(__linux__)
#  include <malloc.h> // malloc_trim(): memory figures (Linux only; elsewhere no peak is reported)
#endif
#if !defined(_WIN32)
#  include <sys/resource.h> // getrusage(): CPU time
#endif
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <iostream>
#include <limits>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

namespace
{
using MeshType = itk::Mesh<double, 3>;
using MaskImageType = itk::Image<unsigned char, 3>;
using RealImageType = itk::Image<float, 3>;
using MaskFilterType = itk::TriangleMeshToVoxelImageFilter<MeshType, MaskImageType>;
using RealFilterType = itk::TriangleMeshToVoxelImageFilter<MeshType, RealImageType>;
using ModeEnum = itk::TriangleMeshToVoxelImageFilterEnums::Mode;
using ClockType = std::chrono::steady_clock;

struct Options
{
  std::string      mesh;
  double           scaleTo{ 100.0 };
  double           voxelSize{ 1.0 };
  double           margin{ 3.0 };
  std::vector<int> threads{ 1 };
  int              repeat{ 3 };
  long             vtkDistanceVoxels{ 300000 };
  double           referenceBeta{ 2.0 };
  std::string      json;
  std::string      tasks{ "occupancy,solid,sdf" };
  double           patchRadius{ 0.0 };
  bool             reference{ true };
  bool             exactSdf{ true };
  bool             vtkDistance{ true };
  bool             referenceBand{ false };

  bool
  HasTask(const std::string & task) const
  {
    return ("," + tasks + ",").find("," + task + ",") != std::string::npos;
  }
};

struct Grid
{
  MaskFilterType::PointType origin;
  MaskImageType::SizeType   size;
  double                    spacing{ 1.0 };
  size_t                    count{ 0 };
};

struct Result
{
  std::string name;
  std::string task;
  int         threads{ 1 };
  double      seconds{ 0.0 };
  double      cpuSeconds{ 0.0 };
  bool        extrapolated{ false };
  long        disagree{ -1 };
  long        disagreeFar{ -1 };
  double      maxError{ -1.0 };
  double      maxErrorBand{ -1.0 };
  long        signErrors{ -1 };
  long        evaluated{ 0 };
  double      peakMegabytes{ -1.0 };
};

// A field of /proc/self/status in kB (VmRSS, VmHWM), or -1 when it cannot be read.
long
StatusKilobytes(const std::string & key)
{
  std::ifstream status("/proc/self/status");
  std::string   line;
  while (std::getline(status, line))
  {
    if (line.compare(0, key.size() + 1, key + ":") == 0)
    {
      return std::stol(line.substr(key.size() + 1));
    }
  }
  return -1;
}

// Best wall time and best CPU time (user + system of the process) of `repeat` runs (one when over 2 s), and the
// peak RSS the first run adds to the process (MB). On a loaded machine the CPU time of a one-thread run is the
// steadier figure (preemption adds wall time, not CPU time).
// Before that first run, `release` drops the previous output, the free heap is returned to the system and the
// kernel's peak mark reset; the later runs are timed without this (it makes their allocations fault again).
std::tuple<double, double, double>
Measure(const std::function<void()> & run, int repeat, const std::function<void()> & release)
{
  double     best = std::numeric_limits<double>::infinity();
  double     bestCpu = std::numeric_limits<double>::infinity();
  double     peak = -1.0;
  const auto cpuSeconds = []() {
#if !defined(_WIN32)
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    return static_cast<double>(usage.ru_utime.tv_sec + usage.ru_stime.tv_sec) +
           1e-6 * static_cast<double>(usage.ru_utime.tv_usec + usage.ru_stime.tv_usec);
#else
    return std::chrono::duration<double>(ClockType::now().time_since_epoch()).count(); // Wall time instead.
#endif
  };
  for (int r = 0; r < repeat; ++r)
  {
    long before = -1;
    if (r == 0)
    {
      release();
#if defined(__linux__)
      malloc_trim(0);
#endif
      std::ofstream clear("/proc/self/clear_refs");
      clear << "5"; // Resets VmHWM to the current RSS (Linux >= 4.0).
      clear.close();
      before = clear ? StatusKilobytes("VmRSS") : -1;
    }
    const double cpuStart = cpuSeconds();
    const auto   start = ClockType::now();
    run();
    best = std::min(best, std::chrono::duration<double>(ClockType::now() - start).count());
    bestCpu = std::min(bestCpu, cpuSeconds() - cpuStart);
    const long high = r == 0 ? StatusKilobytes("VmHWM") : -1;
    if (before >= 0 && high >= 0)
    {
      peak = static_cast<double>(high - before) / 1024.0;
    }
    if (best > 2.0)
    {
      break; // Slow runs are timed once.
    }
  }
  return std::make_tuple(best, bestCpu, peak);
}

// True when every edge is used as often in one direction as in the other once equal coordinates are merged.
bool
IsClosed(const MeshType * mesh)
{
  std::map<std::array<double, 3>, long>     merged;
  std::map<MeshType::PointIdentifier, long> idOf;
  for (auto it = mesh->GetPoints()->Begin(); it != mesh->GetPoints()->End(); ++it)
  {
    const std::array<double, 3> key{ it.Value()[0], it.Value()[1], it.Value()[2] };
    const auto                  inserted = merged.emplace(key, static_cast<long>(merged.size()));
    idOf[it.Index()] = inserted.first->second;
  }
  std::map<std::pair<long, long>, long> net;
  for (auto it = mesh->GetCells()->Begin(); it != mesh->GetCells()->End(); ++it)
  {
    const auto * ids = it.Value()->PointIdsBegin();
    for (unsigned int e = 0; e < 3; ++e)
    {
      const long a = idOf[ids[e]];
      const long b = idOf[ids[(e + 1) % 3]];
      if (a != b)
      {
        net[{ std::min(a, b), std::max(a, b) }] += a < b ? 1 : -1;
      }
    }
  }
  return std::all_of(net.begin(), net.end(), [](const auto & edge) { return edge.second == 0; });
}

// The triangles whose centroid lies within `radius` of the vertex nearest to the centre of the +x face of the
// bounding box (`patch`), and the others (`rest`); both share the points of `mesh`.
void
SplitPatch(const MeshType * mesh, double radius, MeshType::Pointer & patch, MeshType::Pointer & rest)
{
  double lower[3] = { std::numeric_limits<double>::infinity(),
                      std::numeric_limits<double>::infinity(),
                      std::numeric_limits<double>::infinity() };
  double upper[3] = { -lower[0], -lower[1], -lower[2] };
  for (auto it = mesh->GetPoints()->Begin(); it != mesh->GetPoints()->End(); ++it)
  {
    for (unsigned int k = 0; k < 3; ++k)
    {
      lower[k] = std::min(lower[k], static_cast<double>(it.Value()[k]));
      upper[k] = std::max(upper[k], static_cast<double>(it.Value()[k]));
    }
  }
  const double        face[3] = { upper[0], 0.5 * (lower[1] + upper[1]), 0.5 * (lower[2] + upper[2]) };
  MeshType::PointType seed = mesh->GetPoints()->Begin().Value();
  double              nearest = std::numeric_limits<double>::infinity();
  for (auto it = mesh->GetPoints()->Begin(); it != mesh->GetPoints()->End(); ++it)
  {
    double squared = 0.0;
    for (unsigned int k = 0; k < 3; ++k)
    {
      squared += (it.Value()[k] - face[k]) * (it.Value()[k] - face[k]);
    }
    if (squared < nearest)
    {
      nearest = squared;
      seed = it.Value();
    }
  }
  patch = MeshType::New();
  rest = MeshType::New();
  for (auto it = mesh->GetPoints()->Begin(); it != mesh->GetPoints()->End(); ++it)
  {
    patch->SetPoint(it.Index(), it.Value());
    rest->SetPoint(it.Index(), it.Value());
  }
  MeshType::CellIdentifier patchId = 0;
  MeshType::CellIdentifier restId = 0;
  for (auto it = mesh->GetCells()->Begin(); it != mesh->GetCells()->End(); ++it)
  {
    const auto * ids = it.Value()->PointIdsBegin();
    double       squared = 0.0;
    for (unsigned int k = 0; k < 3; ++k)
    {
      const double centroid = (mesh->GetPoint(ids[0])[k] + mesh->GetPoint(ids[1])[k] + mesh->GetPoint(ids[2])[k]) / 3.0;
      squared += (centroid - seed[k]) * (centroid - seed[k]);
    }
    MeshType::CellAutoPointer triangle;
    triangle.TakeOwnership(new itk::TriangleCell<MeshType::CellType>);
    for (unsigned int v = 0; v < 3; ++v)
    {
      triangle->SetPointId(v, ids[v]);
    }
    if (squared <= radius * radius)
    {
      patch->SetCell(patchId++, triangle);
    }
    else
    {
      rest->SetCell(restId++, triangle);
    }
  }
}

MeshType::Pointer
ScaledTriangles(const MeshType * mesh, double side)
{
  return ffd::ScaledTriangleCopy(mesh, side, ffd::MeshPlacement::CentreAtOrigin);
}

template <typename TFilter>
void
SetGrid(TFilter * filter, const Grid & grid)
{
  typename TFilter::SpacingType spacing;
  spacing.Fill(grid.spacing);
  filter->SetOrigin(grid.origin);
  filter->SetSpacing(spacing);
  filter->SetSize(grid.size);
}

template <typename TImage>
typename TImage::Pointer
RunModule(const MeshType *                                  mesh,
          const Grid &                                      grid,
          ModeEnum                                          mode,
          const std::function<void(itk::ProcessObject *)> & setup)
{
  auto filter = itk::TriangleMeshToVoxelImageFilter<MeshType, TImage>::New();
  filter->SetInput(mesh);
  SetGrid(filter.GetPointer(), grid);
  filter->SetMode(mode);
  setup(filter.GetPointer());
  filter->Update();
  typename TImage::Pointer output = filter->GetOutput();
  output->DisconnectPipeline();
  return output;
}

MaskImageType::Pointer
RunItkBinary(const MeshType * mesh, const Grid & grid)
{
  auto filter = itk::TriangleMeshToBinaryImageFilter<MeshType, MaskImageType>::New();
  filter->SetInput(const_cast<MeshType *>(mesh));
  MaskImageType::SpacingType spacing;
  spacing.Fill(grid.spacing);
  filter->SetSpacing(spacing);
  filter->SetOrigin(grid.origin);
  filter->SetSize(grid.size);
  MaskImageType::IndexType index;
  index.Fill(0);
  filter->SetIndex(index);
  filter->SetInsideValue(1);
  filter->SetOutsideValue(0);
  filter->Update();
  MaskImageType::Pointer output = filter->GetOutput();
  output->DisconnectPipeline();
  return output;
}

void
Json(std::ostream & out, const char * key, double value, bool comma = true)
{
  out << "\"" << key << "\": ";
  if (std::isfinite(value))
  {
    out << value;
  }
  else
  {
    out << "null";
  }
  out << (comma ? ", " : "");
}

int
Run(const Options & options)
{
  itk::RegisterFFDShapeMatchingMeshIOFactories();
  itk::MultiThreaderBase::SetGlobalDefaultNumberOfThreads(
    static_cast<itk::ThreadIdType>(*std::max_element(options.threads.begin(), options.threads.end())));
  auto reader = itk::MeshFileReader<MeshType>::New();
  reader->SetFileName(options.mesh);
  reader->Update();
  const MeshType::Pointer whole = ScaledTriangles(reader->GetOutput(), options.scaleTo);
  MeshType::Pointer       mesh = whole;
  MeshType::Pointer       rest;
  if (options.patchRadius > 0.0)
  {
    SplitPatch(whole, options.patchRadius, mesh, rest);
  }
  const bool closed = IsClosed(mesh);

  Grid                        grid;
  MaskFilterType::SpacingType spacing;
  spacing.Fill(options.voxelSize);
  grid.spacing = options.voxelSize;
  MaskFilterType::ComputeGeometryFromMeshBounds(whole, spacing, options.margin, grid.origin, grid.size);
  grid.count = grid.size[0] * grid.size[1] * grid.size[2];
  const double halfDiagonal = 0.5 * std::sqrt(3.0) * grid.spacing;
  const double band = 3.0 * grid.spacing;
  std::cerr << options.mesh << ": " << mesh->GetNumberOfCells() << " triangles"
            << (closed ? " (closed), " : " (open), ") << grid.size << " voxels" << std::endl;

  // References, voxel by voxel: inside from the whole mesh, distance to the triangles the peers get, and for
  // a patch the distance to the rest of the mesh (where the patch decides inside/outside).
  const auto             start = ClockType::now();
  RealImageType::Pointer referenceWinding;
  RealImageType::Pointer referenceDistance;
  RealImageType::Pointer restDistance;
  // With --reference-band the distances are exact up to twice the sdf band and clamped there (bounded queries):
  // enough for occupancy, for "far" and for the errors in the band, much cheaper on fine grids.
  const auto exactDistanceOf = [&](const MeshType * triangles) {
    return RunModule<RealImageType>(triangles, grid, ModeEnum::SignedDistance, [&](itk::ProcessObject * p) {
      auto * f = static_cast<RealFilterType *>(p);
      f->ScanLineAccelerationOff();
      f->UnsignedDistanceOn();
      f->SetExactDistance(!options.referenceBand);
      f->SetBandWidth(2.0 * band);
    });
  };
  if (options.reference)
  {
    referenceWinding = RunModule<RealImageType>(whole, grid, ModeEnum::WindingNumber, [&](itk::ProcessObject * p) {
      auto * f = static_cast<RealFilterType *>(p);
      f->ScanLineAccelerationOff();
      f->SetBeta(options.referenceBeta);
    });
    referenceDistance = exactDistanceOf(mesh);
    if (rest)
    {
      restDistance = exactDistanceOf(rest);
    }
  }
  const double      referenceSeconds = std::chrono::duration<double>(ClockType::now() - start).count();
  const float *     winding = options.reference ? referenceWinding->GetBufferPointer() : nullptr;
  const float *     distance = options.reference ? referenceDistance->GetBufferPointer() : nullptr;
  std::vector<char> inside(options.reference ? grid.count : 0);
  std::vector<char> decided(options.reference ? grid.count : 0, 1);
  long              insideCount = options.reference ? 0 : -1;
  long              decidedCount = options.reference ? 0 : -1;
  for (size_t i = 0; i < inside.size(); ++i)
  {
    inside[i] = std::abs(winding[i]) > 0.5f;
    insideCount += inside[i];
    if (restDistance)
    {
      decided[i] = distance[i] + halfDiagonal < restDistance->GetBufferPointer()[i];
    }
    decidedCount += decided[i];
  }
  referenceWinding = nullptr;
  restDistance = nullptr;
  const auto signedReference = [&](size_t i) { return inside[i] ? -distance[i] : distance[i]; };

  std::vector<Result> results;
  const auto          scoreMask = [&](Result & result, const unsigned char * values, bool occupancy) {
    if (!options.reference)
    {
      return;
    }
    result.disagree = 0;
    result.disagreeFar = 0;
    result.evaluated = 0;
    for (size_t i = 0; i < grid.count; ++i)
    {
      if (!occupancy && !decided[i])
      {
        continue;
      }
      ++result.evaluated;
      const bool expected = occupancy ? distance[i] <= halfDiagonal : inside[i];
      if ((values[i] != 0) != expected)
      {
        ++result.disagree;
        result.disagreeFar += distance[i] > halfDiagonal;
      }
    }
  };
  const auto scoreDistanceAt = [&](Result & result, const float * values, size_t from, size_t to) {
    for (size_t i = from; i < to; ++i)
    {
      if (!decided[i])
      {
        continue;
      }
      ++result.evaluated;
      const double error = std::abs(values[i] - signedReference(i));
      result.maxError = options.referenceBand ? -1.0 : std::max(result.maxError, error);
      if (distance[i] < band)
      {
        result.maxErrorBand = std::max(result.maxErrorBand, error);
      }
      result.signErrors += distance[i] > halfDiagonal && ((values[i] < 0.0f) != static_cast<bool>(inside[i]));
    }
  };
  const auto scoreDistance = [&](Result & result, const float * values, const std::vector<size_t> & slices) {
    if (!options.reference)
    {
      return;
    }
    result.maxError = 0.0;
    result.maxErrorBand = 0.0;
    result.signErrors = 0;
    result.evaluated = 0;
    const size_t sliceVoxels = grid.size[0] * grid.size[1];
    if (slices.empty())
    {
      scoreDistanceAt(result, values, 0, grid.count);
    }
    for (const size_t k : slices)
    {
      scoreDistanceAt(result, values, k * sliceVoxels, (k + 1) * sliceVoxels);
    }
  };
  const auto none = []() {};

  for (const int threads : options.threads)
  {
    itk::MultiThreaderBase::SetGlobalDefaultNumberOfThreads(static_cast<itk::ThreadIdType>(threads));
    std::cerr << "  " << threads << " thread(s)" << std::endl;
    // Module.
    if (options.HasTask("occupancy"))
    {
      Result                 result{ "module", "occupancy", threads };
      MaskImageType::Pointer image;
      std::tie(result.seconds, result.cpuSeconds, result.peakMegabytes) = Measure(
        [&]() { image = RunModule<MaskImageType>(mesh, grid, ModeEnum::Occupancy, [](itk::ProcessObject *) {}); },
        options.repeat,
        [&]() { image = nullptr; });
      scoreMask(result, image->GetBufferPointer(), true);
      results.push_back(result);
    }
    if (options.HasTask("solid"))
    {
      Result                 result{ "module", "solid", threads };
      MaskImageType::Pointer image;
      std::tie(result.seconds, result.cpuSeconds, result.peakMegabytes) =
        Measure([&]() { image = RunModule<MaskImageType>(mesh, grid, ModeEnum::Solid, [](itk::ProcessObject *) {}); },
                options.repeat,
                [&]() { image = nullptr; });
      scoreMask(result, image->GetBufferPointer(), false);
      results.push_back(result);
    }
    for (const bool exact : { false, true })
    {
      if (!options.HasTask("sdf") || (exact && !options.exactSdf))
      {
        continue;
      }
      Result result{ exact ? "module (exact everywhere)" : "module (exact in band, clamped)", "sdf", threads };
      RealImageType::Pointer image;
      std::tie(result.seconds, result.cpuSeconds, result.peakMegabytes) = Measure(
        [&]() {
          image = RunModule<RealImageType>(mesh, grid, ModeEnum::SignedDistance, [exact](itk::ProcessObject * p) {
            static_cast<RealFilterType *>(p)->SetExactDistance(exact);
          });
        },
        options.repeat,
        [&]() { image = nullptr; });
      scoreDistance(result, image->GetBufferPointer(), {});
      results.push_back(result);
    }

    // ITK's binary filter, and its signed Maurer distance.
    if (options.HasTask("solid") || options.HasTask("sdf"))
    {
      MaskImageType::Pointer itkBinary;
      Result                 result{ "itk::TriangleMeshToBinaryImageFilter", "solid", threads };
      std::tie(result.seconds, result.cpuSeconds, result.peakMegabytes) =
        Measure([&]() { itkBinary = RunItkBinary(mesh, grid); }, options.repeat, [&]() { itkBinary = nullptr; });
      scoreMask(result, itkBinary->GetBufferPointer(), false);
      if (options.HasTask("solid"))
      {
        results.push_back(result);
      }
      if (options.HasTask("sdf"))
      {
        Result                 maurer{ "itk binary + SignedMaurerDistanceMapImageFilter", "sdf", threads };
        RealImageType::Pointer image;
        double                 maurerSeconds = 0.0;
        double                 maurerCpu = 0.0;
        std::tie(maurerSeconds, maurerCpu, maurer.peakMegabytes) = Measure(
          [&]() {
            auto filter = itk::SignedMaurerDistanceMapImageFilter<MaskImageType, RealImageType>::New();
            filter->SetInput(itkBinary);
            filter->SetUseImageSpacing(true);
            filter->SetSquaredDistance(false);
            filter->SetInsideIsPositive(false);
            filter->SetBackgroundValue(0);
            filter->Update();
            image = filter->GetOutput();
            image->DisconnectPipeline();
          },
          options.repeat,
          [&]() { image = nullptr; });
        maurer.seconds = result.seconds + maurerSeconds;
        maurer.cpuSeconds = result.cpuSeconds + maurerCpu;
        maurer.peakMegabytes = std::max(maurer.peakMegabytes, result.peakMegabytes);
        scoreDistance(maurer, image->GetBufferPointer(), {});
        results.push_back(maurer);
      }
    }

    // VTK peers.
    vtkNew<vtkPolyData> polyData;
    itk::MeshToVTKPolyData(mesh.GetPointer(), polyData.GetPointer());
    double bounds[6];
    for (unsigned int k = 0; k < 3; ++k)
    {
      bounds[2 * k] = grid.origin[k];
      bounds[2 * k + 1] = grid.origin[k] + (grid.size[k] - 1) * grid.spacing;
    }
    if (options.HasTask("occupancy"))
    {
      Result                        result{ "vtkVoxelModeller", "occupancy", threads };
      vtkSmartPointer<vtkImageData> image;
      std::tie(result.seconds, result.cpuSeconds, result.peakMegabytes) = Measure(
        [&]() {
          vtkNew<vtkVoxelModeller> modeller;
          modeller->SetInputData(polyData);
          modeller->SetSampleDimensions(
            static_cast<int>(grid.size[0]), static_cast<int>(grid.size[1]), static_cast<int>(grid.size[2]));
          modeller->SetModelBounds(bounds);
          const double largest = std::max({ bounds[1] - bounds[0], bounds[3] - bounds[2], bounds[5] - bounds[4] });
          modeller->SetMaximumDistance(halfDiagonal / largest);
          modeller->SetScalarTypeToUnsignedChar();
          modeller->Update();
          image = modeller->GetOutput();
        },
        options.repeat,
        [&]() { image = nullptr; });
      scoreMask(result, static_cast<const unsigned char *>(image->GetScalarPointer()), true);
      results.push_back(result);
    }
    if (options.HasTask("solid"))
    {
      Result                        result{ "vtkPolyDataToImageStencil + vtkImageStencil", "solid", threads };
      vtkSmartPointer<vtkImageData> image;
      vtkNew<vtkImageData>          ones;
      ones->SetDimensions(
        static_cast<int>(grid.size[0]), static_cast<int>(grid.size[1]), static_cast<int>(grid.size[2]));
      ones->SetOrigin(grid.origin[0], grid.origin[1], grid.origin[2]);
      ones->SetSpacing(grid.spacing, grid.spacing, grid.spacing);
      ones->AllocateScalars(VTK_UNSIGNED_CHAR, 1);
      std::fill_n(static_cast<unsigned char *>(ones->GetScalarPointer()), grid.count, 1);
      std::tie(result.seconds, result.cpuSeconds, result.peakMegabytes) = Measure(
        [&]() {
          vtkNew<vtkPolyDataToImageStencil> stencil;
          stencil->SetInputData(polyData);
          stencil->SetOutputOrigin(grid.origin[0], grid.origin[1], grid.origin[2]);
          stencil->SetOutputSpacing(grid.spacing, grid.spacing, grid.spacing);
          stencil->SetOutputWholeExtent(0,
                                        static_cast<int>(grid.size[0]) - 1,
                                        0,
                                        static_cast<int>(grid.size[1]) - 1,
                                        0,
                                        static_cast<int>(grid.size[2]) - 1);
          vtkNew<vtkImageStencil> fill;
          fill->SetInputData(ones);
          fill->SetStencilConnection(stencil->GetOutputPort());
          fill->ReverseStencilOff();
          fill->SetBackgroundValue(0);
          fill->Update();
          image = fill->GetOutput();
        },
        options.repeat,
        [&]() { image = nullptr; });
      scoreMask(result, static_cast<const unsigned char *>(image->GetScalarPointer()), false);
      results.push_back(result);
    }
    if (options.HasTask("sdf") && options.vtkDistance && threads == options.threads.front()) // Timed once.
    {
      // Whole z slices spread over the grid, at most vtkDistanceVoxels voxels; time scaled to the grid.
      Result       result{ "vtkImplicitPolyDataDistance (per voxel)", "sdf", threads };
      const size_t sliceVoxels = grid.size[0] * grid.size[1];
      const size_t slices = std::max<size_t>(
        1, std::min<size_t>(grid.size[2], static_cast<size_t>(options.vtkDistanceVoxels) / sliceVoxels));
      const size_t        sliceStep = std::max<size_t>(1, grid.size[2] / slices);
      std::vector<size_t> chosen;
      for (size_t k = sliceStep / 2; k < grid.size[2] && chosen.size() < slices; k += sliceStep)
      {
        chosen.push_back(k);
      }
      std::vector<float> values(grid.count, 0.0f); // Allocated before: its peak leaves the output out.
      std::tie(result.seconds, result.cpuSeconds, result.peakMegabytes) = Measure(
        [&]() {
          vtkNew<vtkImplicitPolyDataDistance> implicit;
          implicit->SetInput(polyData);
          for (const size_t k : chosen)
          {
            for (size_t j = 0; j < grid.size[1]; ++j)
            {
              for (size_t i = 0; i < grid.size[0]; ++i)
              {
                double x[3] = { grid.origin[0] + i * grid.spacing,
                                grid.origin[1] + j * grid.spacing,
                                grid.origin[2] + k * grid.spacing };
                values[(k * grid.size[1] + j) * grid.size[0] + i] = static_cast<float>(implicit->EvaluateFunction(x));
              }
            }
          }
        },
        1,
        none);
      const double fraction = static_cast<double>(chosen.size() * sliceVoxels) / static_cast<double>(grid.count);
      result.extrapolated = fraction < 1.0;
      result.seconds /= fraction;
      result.cpuSeconds /= fraction;
      scoreDistance(result, values.data(), chosen);
      if (!options.reference)
      {
        result.evaluated = static_cast<long>(chosen.size() * sliceVoxels);
      }
      results.push_back(result);
    }
  }

  std::ostringstream out;
  out << "{\"mesh\": \"" << options.mesh << "\", \"triangles\": " << mesh->GetNumberOfCells()
      << ", \"whole_mesh_triangles\": " << whole->GetNumberOfCells() << ", \"patch_radius\": " << options.patchRadius
      << ", \"closed\": " << (closed ? "true" : "false") << ", \"size\": [" << grid.size[0] << ", " << grid.size[1]
      << ", " << grid.size[2] << "], \"voxels\": " << grid.count << ", \"voxel_size\": " << grid.spacing
      << ", \"reference\": " << (options.reference ? "true" : "false")
      << ", \"reference_band\": " << (options.referenceBand ? "true" : "false")
      << ", \"reference_beta\": " << options.referenceBeta << ", \"reference_seconds\": " << referenceSeconds
      << ", \"inside_voxels\": " << insideCount << ", \"decided_voxels\": " << decidedCount << ", \"band\": " << band
      << ", \"process_peak_megabytes\": " << StatusKilobytes("VmPeak") / 1024.0 << ",\n \"results\": [\n";
  for (size_t r = 0; r < results.size(); ++r)
  {
    const Result & result = results[r];
    out << "  {\"name\": \"" << result.name << "\", \"task\": \"" << result.task
        << "\", \"threads\": " << result.threads << ", ";
    Json(out, "seconds", result.seconds);
    Json(out, "cpu_seconds", result.cpuSeconds);
    Json(out, "peak_megabytes", result.peakMegabytes);
    out << "\"extrapolated\": " << (result.extrapolated ? "true" : "false")
        << ", \"evaluated_voxels\": " << result.evaluated << ", \"disagree\": " << result.disagree
        << ", \"disagree_far\": " << result.disagreeFar << ", \"sign_errors\": " << result.signErrors << ", ";
    Json(out, "max_abs_error", result.maxError);
    Json(out, "max_abs_error_in_band", result.maxErrorBand, false);
    out << "}" << (r + 1 < results.size() ? "," : "") << "\n";
  }
  out << " ]}\n";
  if (options.json.empty())
  {
    std::cout << out.str();
  }
  else
  {
    std::ofstream file(options.json);
    file << out.str();
    if (!file)
    {
      std::cerr << "ffd-voxelization-peers: cannot write " << options.json << std::endl;
      return EXIT_FAILURE;
    }
  }
  for (const Result & result : results)
  {
    std::cerr << "  " << result.threads << " thread(s) " << result.task << " " << result.name << ": " << result.seconds
              << " s, " << result.peakMegabytes << " MB" << std::endl;
  }
  return EXIT_SUCCESS;
}
} // namespace

int
main(int argc, char * argv[])
{
  Options options;
  try
  {
    for (int i = 1; i < argc; ++i)
    {
      const std::string argument = argv[i];
      const auto        value = [&]() -> std::string {
        if (i + 1 >= argc)
        {
          throw std::runtime_error(argument + " needs a value");
        }
        return argv[++i];
      };
      const auto number = [&]() {
        const std::string text = value();
        size_t            used = 0;
        const double      result = std::stod(text, &used);
        if (used != text.size() || !std::isfinite(result))
        {
          throw std::runtime_error(argument + " needs a finite number, not '" + text + "'");
        }
        return result;
      };
      if (argument == "--scale-to")
      {
        options.scaleTo = number();
      }
      else if (argument == "--voxel-size")
      {
        options.voxelSize = number();
      }
      else if (argument == "--margin")
      {
        options.margin = number();
      }
      else if (argument == "--threads")
      {
        // One count or a comma-separated list: the peers are timed for each, against one reference.
        options.threads.clear();
        std::stringstream list(value());
        std::string       item;
        while (std::getline(list, item, ','))
        {
          size_t    used = 0;
          const int count = std::stoi(item, &used);
          if (used != item.size() || count < 1)
          {
            throw std::runtime_error("--threads needs whole numbers >= 1");
          }
          options.threads.push_back(count);
        }
      }
      else if (argument == "--repeat")
      {
        options.repeat = static_cast<int>(number());
      }
      else if (argument == "--vtk-distance-voxels")
      {
        options.vtkDistanceVoxels = static_cast<long>(number());
      }
      else if (argument == "--reference-beta")
      {
        options.referenceBeta = number();
      }
      else if (argument == "--json")
      {
        options.json = value();
      }
      else if (argument == "--tasks")
      {
        options.tasks = value();
      }
      else if (argument == "--patch-radius")
      {
        options.patchRadius = number();
      }
      else if (argument == "--no-reference")
      {
        options.reference = false;
      }
      else if (argument == "--no-exact-sdf")
      {
        options.exactSdf = false;
      }
      else if (argument == "--no-vtk-distance")
      {
        options.vtkDistance = false;
      }
      else if (argument == "--reference-band")
      {
        options.referenceBand = true;
      }
      else if (options.mesh.empty() && !argument.empty() && argument[0] != '-')
      {
        options.mesh = argument;
      }
      else
      {
        throw std::runtime_error("unknown argument '" + argument + "'");
      }
    }
    if (options.mesh.empty() || !(options.voxelSize > 0.0) || options.threads.empty() || options.repeat < 1)
    {
      throw std::runtime_error("usage: ffd-voxelization-peers MESH [--scale-to L] [--voxel-size S] [--margin M] "
                               "[--threads N] [--repeat R] [--vtk-distance-voxels N] [--reference-beta B] "
                               "[--tasks occupancy,solid,sdf] [--patch-radius R] [--no-reference] "
                               "[--no-exact-sdf] [--no-vtk-distance] [--reference-band] [--json FILE]");
    }
    return Run(options);
  }
  catch (const itk::ExceptionObject & error)
  {
    std::cerr << "ffd-voxelization-peers: " << error.GetDescription() << std::endl;
  }
  catch (const std::exception & error)
  {
    std::cerr << "ffd-voxelization-peers: " << error.what() << std::endl;
  }
  return EXIT_FAILURE;
}
