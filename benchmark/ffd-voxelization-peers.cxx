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
//                          [--vtk-distance-voxels N] [--reference-beta B] [--json FILE]
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
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <iostream>
#include <limits>
#include <sstream>
#include <string>
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
  bool        extrapolated{ false };
  long        disagree{ -1 };
  long        disagreeFar{ -1 };
  double      maxError{ -1.0 };
  double      maxErrorBand{ -1.0 };
  long        signErrors{ -1 };
  long        evaluated{ 0 };
};

double
SecondsOf(const std::function<void()> & run, int repeat)
{
  double best = std::numeric_limits<double>::infinity();
  for (int r = 0; r < repeat; ++r)
  {
    const auto start = ClockType::now();
    run();
    best = std::min(best, std::chrono::duration<double>(ClockType::now() - start).count());
    if (best > 2.0)
    {
      break; // Slow runs are timed once.
    }
  }
  return best;
}

// A copy of the mesh, centred and scaled so its largest side is `side`, with polygons split into triangle fans.
MeshType::Pointer
ScaledTriangles(const MeshType * mesh, double side)
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
  const double largest = std::max({ upper[0] - lower[0], upper[1] - lower[1], upper[2] - lower[2] });
  const double scale = side > 0.0 && largest > 0.0 ? side / largest : 1.0;
  auto         result = MeshType::New();
  for (auto it = mesh->GetPoints()->Begin(); it != mesh->GetPoints()->End(); ++it)
  {
    MeshType::PointType p;
    for (unsigned int k = 0; k < 3; ++k)
    {
      p[k] = (it.Value()[k] - 0.5 * (lower[k] + upper[k])) * scale;
    }
    result->SetPoint(it.Index(), p);
  }
  MeshType::CellIdentifier cellId = 0;
  for (auto it = mesh->GetCells()->Begin(); it != mesh->GetCells()->End(); ++it)
  {
    const auto * cell = it.Value();
    if (cell->GetDimension() != 2 || cell->GetNumberOfPoints() < 3)
    {
      continue;
    }
    const auto * ids = cell->PointIdsBegin();
    for (unsigned int i = 1; i + 1 < cell->GetNumberOfPoints(); ++i)
    {
      MeshType::CellAutoPointer triangle;
      triangle.TakeOwnership(new itk::TriangleCell<MeshType::CellType>);
      triangle->SetPointId(0, ids[0]);
      triangle->SetPointId(1, ids[i]);
      triangle->SetPointId(2, ids[i + 1]);
      result->SetCell(cellId++, triangle);
    }
  }
  return result;
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
  const MeshType::Pointer mesh = ScaledTriangles(reader->GetOutput(), options.scaleTo);

  Grid                        grid;
  MaskFilterType::SpacingType spacing;
  spacing.Fill(options.voxelSize);
  grid.spacing = options.voxelSize;
  MaskFilterType::ComputeGeometryFromMeshBounds(mesh, spacing, options.margin, grid.origin, grid.size);
  grid.count = grid.size[0] * grid.size[1] * grid.size[2];
  const double halfDiagonal = 0.5 * std::sqrt(3.0) * grid.spacing;
  const double band = 3.0 * grid.spacing;
  std::cerr << options.mesh << ": " << mesh->GetNumberOfCells() << " triangles, " << grid.size << " voxels"
            << std::endl;

  // References, voxel by voxel.
  const auto start = ClockType::now();
  auto referenceWinding = RunModule<RealImageType>(mesh, grid, ModeEnum::WindingNumber, [&](itk::ProcessObject * p) {
    auto * f = static_cast<RealFilterType *>(p);
    f->ScanLineAccelerationOff();
    f->SetBeta(options.referenceBeta);
  });
  auto referenceDistance = RunModule<RealImageType>(mesh, grid, ModeEnum::SignedDistance, [](itk::ProcessObject * p) {
    auto * f = static_cast<RealFilterType *>(p);
    f->ScanLineAccelerationOff();
    f->UnsignedDistanceOn();
    f->ExactDistanceOn();
  });
  const double      referenceSeconds = std::chrono::duration<double>(ClockType::now() - start).count();
  const float *     winding = referenceWinding->GetBufferPointer();
  const float *     distance = referenceDistance->GetBufferPointer();
  std::vector<char> inside(grid.count);
  long              insideCount = 0;
  for (size_t i = 0; i < grid.count; ++i)
  {
    inside[i] = std::abs(winding[i]) > 0.5f;
    insideCount += inside[i];
  }
  const auto signedReference = [&](size_t i) { return inside[i] ? -distance[i] : distance[i]; };

  std::vector<Result> results;
  const auto          scoreMask = [&](Result & result, const unsigned char * values, bool occupancy) {
    result.disagree = 0;
    result.disagreeFar = 0;
    for (size_t i = 0; i < grid.count; ++i)
    {
      const bool expected = occupancy ? distance[i] <= halfDiagonal : inside[i];
      if ((values[i] != 0) != expected)
      {
        ++result.disagree;
        result.disagreeFar += distance[i] > halfDiagonal;
      }
    }
    result.evaluated = static_cast<long>(grid.count);
  };
  const auto scoreDistance = [&](Result & result, const float * values) {
    result.maxError = 0.0;
    result.maxErrorBand = 0.0;
    result.signErrors = 0;
    for (size_t i = 0; i < grid.count; ++i)
    {
      const double error = std::abs(values[i] - signedReference(i));
      result.maxError = std::max(result.maxError, error);
      if (distance[i] < band)
      {
        result.maxErrorBand = std::max(result.maxErrorBand, error);
      }
      result.signErrors += distance[i] > halfDiagonal && ((values[i] < 0.0f) != static_cast<bool>(inside[i]));
    }
    result.evaluated = static_cast<long>(grid.count);
  };

  for (const int threads : options.threads)
  {
    itk::MultiThreaderBase::SetGlobalDefaultNumberOfThreads(static_cast<itk::ThreadIdType>(threads));
    std::cerr << "  " << threads << " thread(s)" << std::endl;
    // Module.
    {
      Result                 result{ "module", "occupancy", threads };
      MaskImageType::Pointer image;
      result.seconds = SecondsOf(
        [&]() { image = RunModule<MaskImageType>(mesh, grid, ModeEnum::Occupancy, [](itk::ProcessObject *) {}); },
        options.repeat);
      scoreMask(result, image->GetBufferPointer(), true);
      results.push_back(result);
    }
    {
      Result                 result{ "module", "solid", threads };
      MaskImageType::Pointer image;
      result.seconds =
        SecondsOf([&]() { image = RunModule<MaskImageType>(mesh, grid, ModeEnum::Solid, [](itk::ProcessObject *) {}); },
                  options.repeat);
      scoreMask(result, image->GetBufferPointer(), false);
      results.push_back(result);
    }
    for (const bool exact : { false, true })
    {
      Result result{ exact ? "module (exact everywhere)" : "module (exact in band, clamped)", "sdf", threads };
      RealImageType::Pointer image;
      result.seconds = SecondsOf(
        [&]() {
          image = RunModule<RealImageType>(mesh, grid, ModeEnum::SignedDistance, [exact](itk::ProcessObject * p) {
            static_cast<RealFilterType *>(p)->SetExactDistance(exact);
          });
        },
        options.repeat);
      scoreDistance(result, image->GetBufferPointer());
      results.push_back(result);
    }

    // ITK's binary filter, and its signed Maurer distance.
    MaskImageType::Pointer itkBinary;
    {
      Result result{ "itk::TriangleMeshToBinaryImageFilter", "solid", threads };
      result.seconds = SecondsOf([&]() { itkBinary = RunItkBinary(mesh, grid); }, options.repeat);
      scoreMask(result, itkBinary->GetBufferPointer(), false);
      results.push_back(result);
      Result                 maurer{ "itk binary + SignedMaurerDistanceMapImageFilter", "sdf", threads };
      RealImageType::Pointer image;
      const double           maurerSeconds = SecondsOf(
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
        options.repeat);
      maurer.seconds = result.seconds + maurerSeconds;
      scoreDistance(maurer, image->GetBufferPointer());
      results.push_back(maurer);
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
    {
      Result                        result{ "vtkVoxelModeller", "occupancy", threads };
      vtkSmartPointer<vtkImageData> image;
      result.seconds = SecondsOf(
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
        options.repeat);
      scoreMask(result, static_cast<const unsigned char *>(image->GetScalarPointer()), true);
      results.push_back(result);
    }
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
      result.seconds = SecondsOf(
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
        options.repeat);
      scoreMask(result, static_cast<const unsigned char *>(image->GetScalarPointer()), false);
      results.push_back(result);
    }
    if (threads == options.threads.front()) // Single-threaded: timed once.
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
      std::vector<float> values(grid.count, 0.0f);
      result.seconds = SecondsOf(
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
        1);
      const double fraction = static_cast<double>(chosen.size() * sliceVoxels) / static_cast<double>(grid.count);
      result.extrapolated = fraction < 1.0;
      result.seconds /= fraction;
      result.maxError = 0.0;
      result.maxErrorBand = 0.0;
      result.signErrors = 0;
      for (const size_t k : chosen)
      {
        for (size_t v = k * sliceVoxels; v < (k + 1) * sliceVoxels; ++v)
        {
          const double error = std::abs(values[v] - signedReference(v));
          result.maxError = std::max(result.maxError, error);
          if (distance[v] < band)
          {
            result.maxErrorBand = std::max(result.maxErrorBand, error);
          }
          result.signErrors += distance[v] > halfDiagonal && ((values[v] < 0.0f) != static_cast<bool>(inside[v]));
        }
      }
      result.evaluated = static_cast<long>(chosen.size() * sliceVoxels);
      results.push_back(result);
    }
  }

  std::ostringstream out;
  out << "{\"mesh\": \"" << options.mesh << "\", \"triangles\": " << mesh->GetNumberOfCells() << ", \"size\": ["
      << grid.size[0] << ", " << grid.size[1] << ", " << grid.size[2] << "], \"voxels\": " << grid.count
      << ", \"voxel_size\": " << grid.spacing << ", \"reference_beta\": " << options.referenceBeta
      << ", \"reference_seconds\": " << referenceSeconds << ", \"inside_voxels\": " << insideCount
      << ", \"band\": " << band << ",\n \"results\": [\n";
  for (size_t r = 0; r < results.size(); ++r)
  {
    const Result & result = results[r];
    out << "  {\"name\": \"" << result.name << "\", \"task\": \"" << result.task
        << "\", \"threads\": " << result.threads << ", ";
    Json(out, "seconds", result.seconds);
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
              << " s" << std::endl;
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
                               "[--json FILE]");
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
