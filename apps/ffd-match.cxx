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
// ffd-match: matches a source triangle mesh to a target triangle mesh with a B-spline free-form
// deformation. Both meshes are voxelized, the images registered (target = fixed, source = moving,
// so the transform T maps target space to source space), and T^-1 moves the source mesh onto the
// target.
//
//   ffd-match --source S --target T --method go --output DEFORMED [options]
//   ffd-match --demo [--output-dir DIR]
//
// Every output is written to a temporary name next to it and renamed at the end, so a failed run
// leaves nothing half-written. Errors are one line on stderr and exit code 1.

#include "FFDMatchMethods.h"
#include "FFDProgramMeshIO.h"
#include "FFDProgramMessages.h"
#include "FFDProgramSupport.h"
#include "FFDSnapshot.h"
#include "itkApplyTransformToMeshFilter.h"
#include "itkMesh.h"
#include "itkMeshFileReader.h"
#include "itkMeshFileWriter.h"
#include "itkMeshSurfaceDistanceCalculator.h"
#include "itkMultiThreaderBase.h"
#include "itkPointCorrespondenceErrorCalculator.h"
#include "itkRandomBSplineTransformGenerator.h"
#include "itkRegisterFFDShapeMatchingMeshIOFactories.h"
#include "itkTransformFileWriter.h"
#include "itkTransformToJacobianDeterminantImageFilter.h"
#include "itkTriangleCell.h"
#include "itkTriangleMeshToVoxelImageFilter.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <limits>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <unistd.h>
#include <utility>
#include <vector>

namespace
{
using ffd::Error;
using ffd::ImageType;
using ffd::MaskImageType;
using ffd::MeshType;
using ffd::Options;
using ImageVoxelizerType = itk::TriangleMeshToVoxelImageFilter<MeshType, ImageType>;
using MaskVoxelizerType = itk::TriangleMeshToVoxelImageFilter<MeshType, MaskImageType>;
using ApplyType = itk::ApplyTransformToMeshFilter<MeshType, MeshType>;
using SurfaceDistanceType = itk::MeshSurfaceDistanceCalculator<MeshType>;
using CorrespondenceErrorType = itk::PointCorrespondenceErrorCalculator<MeshType>;
using JacobianFilterType = itk::TransformToJacobianDeterminantImageFilter<ImageType>;
using ModeEnum = itk::TriangleMeshToVoxelImageFilterEnums::Mode;
using ffd::ClockType;
using ffd::JsonNumber;
using ffd::JsonString;
using ffd::OneLine;
using ffd::SecondsSince;

const char * const Usage =
  "usage: ffd-match --source S --target T --method go|mrf|par|go+par|mrf+par --output DEFORMED\n"
  "                 [--grid 20] [--voxel-size 1.0] [--voxelization occupancy|solid|sdf]\n"
  "                 [--templates FILE.tfm] [--template-split none|control-point|axis]\n"
  "                 [--transform-out FILE.tfm] [--report FILE.json] [--snapshot FILE.png]\n"
  "                 [--threads N] [--seed S]\n"
  "                 [--levels L] [--iterations N] [--sampling P]\n"
  "                 [--time-limit SECONDS] [--memory-limit MB]\n"
  "                 [--bending-weight W] [--folding-weight W] [--mrf-weight W] [--mrf-pyramid on|off]\n"
  "       ffd-match --demo [--output-dir DIR] [same tuning options]\n"
  "  --source        mesh moved onto the target (OFF, OBJ, VTK, VTP, STL or PLY)\n"
  "  --target        mesh (or open surface patch) matched to\n"
  "  --method        go: B-spline FFD by gradient-based image registration; mrf: by discrete\n"
  "                  Markov-random-field optimization of the control points; par: template\n"
  "                  weights fitted to the meshes directly (needs --templates); go+par, mrf+par:\n"
  "                  go or mrf, refined by par\n"
  "  --templates     ITK transform file of B-spline templates on one grid (par methods)\n"
  "  --template-split control-point (default): one weight per control point and template;\n"
  "                  axis: per control point and axis; none: one weight per template\n"
  "  --mrf-weight    regularization weight lambda of method mrf (default 1)\n"
  "  --mrf-pyramid   off (default): every mrf level uses the full-resolution images; on: coarse levels\n"
  "                  use smoothed, shrunk images (faster, less accurate on thin distance bands)\n"
  "  --output        deformed source: the source's vertex order and cells, moved onto the target\n"
  "  --grid          control points per axis of the final B-spline grid, >= 4 (default 20)\n"
  "  --voxel-size    voxel edge length in mesh units (default 1.0)\n"
  "  --voxelization  sdf (default): unsigned distance in a band, mean squares metric;\n"
  "                  occupancy: surface voxels, Mattes mutual information; solid: inside voxels\n"
  "                  (winding number), Mattes mutual information. The metric samples a band\n"
  "                  around the target surface.\n"
  "  --transform-out write T (target space -> source space) as an ITK transform file\n"
  "  --report        write a JSON report (stage times, metric per iteration, distances, ...)\n"
  "  --snapshot      write a before/after picture (PNG; VTK off-screen rendering needs an X display:\n"
  "                  run under xvfb-run on a machine without one)\n"
  "  --threads       number of threads (default all)\n"
  "  --seed          seed of the metric sampling (and of the demo's deformation), default 121212\n"
  "  --levels        resolution levels (default 2)\n"
  "  --iterations    optimizer iterations per level (default 50; mrf: 8)\n"
  "  --sampling      fraction of the band voxels sampled by the metric, (0, 1] (default 0.25)\n"
  "  --time-limit    stop the registration after this many seconds and go on with the transform\n"
  "                  reached so far (the report says so); default: no limit\n"
  "  --memory-limit  refuse (before any work) a voxel grid whose images would need more than this many\n"
  "                  MB; default: 80 % of the available memory\n"
  "  --bending-weight weight of the B-spline bending energy added to the metric (default 1)\n"
  "  --folding-weight weight of the folding (negative Jacobian) penalty added to the metric (default 0)\n"
  "  --demo          build a CAD-like part, cut and deform a target from it, match and score it;\n"
  "                  writes source.vtp, target.vtp, deformed.vtp, transform.tfm, report.json and,\n"
  "                  with a display, snapshot.png\n"
  "  --output-dir    folder of the demo's files (default demo-output)\n";

// Known correspondences (demo): the source vertex id and the target vertex id of the same material point.
struct GroundTruth
{
  CorrespondenceErrorType::CorrespondenceContainerType correspondences;
};

double
ParseNumber(const std::string & option, const std::string & text)
{
  return ffd::ParseNumber<Error>(option, text);
}

unsigned int
ParseWholeNumber(const std::string & option, const std::string & text, double minimum, double maximum)
{
  const double value = ParseNumber(option, text);
  if (value != std::floor(value) || value < minimum || value > maximum)
  {
    std::ostringstream message;
    message << option << " must be a whole number in [" << minimum << ", " << maximum << "], not '" << text << "'";
    throw Error(message.str());
  }
  return static_cast<unsigned int>(value);
}

Options
ParseArguments(int argc, char * argv[])
{
  Options options;
  for (int i = 1; i < argc; ++i)
  {
    const std::string argument = argv[i];
    const auto        value = [&]() -> std::string {
      if (i + 1 >= argc)
      {
        throw Error(argument + " needs a value");
      }
      return argv[++i];
    };
    if (argument == "--help" || argument == "-h")
    {
      std::cout << Usage;
      std::exit(EXIT_SUCCESS);
    }
    else if (argument == "--source")
    {
      options.source = value();
    }
    else if (argument == "--target")
    {
      options.target = value();
    }
    else if (argument == "--method")
    {
      options.method = value();
    }
    else if (argument == "--output")
    {
      options.output = value();
    }
    else if (argument == "--grid")
    {
      const std::string text = value();
      const double      grid = ParseNumber(argument, text);
      if (grid != std::floor(grid) || grid < 4 || grid > 200)
      {
        throw Error("--grid must be a whole number of control points per axis in [4, 200], not '" + text + "'");
      }
      options.grid = static_cast<unsigned int>(grid);
      options.gridGiven = true;
    }
    else if (argument == "--voxel-size")
    {
      options.voxelSize = ParseNumber(argument, value());
      if (!(options.voxelSize > 0.0))
      {
        throw Error("--voxel-size must be > 0");
      }
      options.voxelSizeGiven = true;
    }
    else if (argument == "--voxelization")
    {
      options.voxelization = value();
      if (options.voxelization != "occupancy" && options.voxelization != "solid" && options.voxelization != "sdf")
      {
        throw Error("--voxelization must be occupancy, solid or sdf, not '" + options.voxelization + "'");
      }
    }
    else if (argument == "--transform-out")
    {
      options.transformOut = value();
    }
    else if (argument == "--report")
    {
      options.report = value();
    }
    else if (argument == "--threads")
    {
      options.threads = static_cast<int>(ParseWholeNumber(argument, value(), 1, 4096));
    }
    else if (argument == "--seed")
    {
      options.seed = static_cast<int>(ParseWholeNumber(argument, value(), 0, 2147483647.0));
    }
    else if (argument == "--levels")
    {
      options.levels = ParseWholeNumber(argument, value(), 1, 8);
      options.levelsGiven = true;
    }
    else if (argument == "--iterations")
    {
      options.iterations = ParseWholeNumber(argument, value(), 1, 100000);
      options.iterationsGiven = true;
    }
    else if (argument == "--sampling")
    {
      options.sampling = ParseNumber(argument, value());
      if (!(options.sampling > 0.0 && options.sampling <= 1.0))
      {
        throw Error("--sampling must be in (0, 1]");
      }
      options.samplingGiven = true;
    }
    else if (argument == "--bending-weight" || argument == "--folding-weight")
    {
      const double weight = ParseNumber(argument, value());
      if (weight < 0.0)
      {
        throw Error(argument + " must be >= 0");
      }
      (argument == "--bending-weight" ? options.bendingWeight : options.foldingWeight) = weight;
    }
    else if (argument == "--mrf-weight")
    {
      options.mrfWeight = ParseNumber(argument, value());
      if (options.mrfWeight < 0.0)
      {
        throw Error("--mrf-weight must be >= 0");
      }
    }
    else if (argument == "--mrf-pyramid")
    {
      const std::string setting = value();
      if (setting != "on" && setting != "off")
      {
        throw Error("--mrf-pyramid must be on or off, not '" + setting + "'");
      }
      options.mrfPyramid = setting == "on";
    }
    else if (argument == "--time-limit")
    {
      options.timeLimit = ParseNumber(argument, value());
      if (!(options.timeLimit > 0.0))
      {
        throw Error("--time-limit must be > 0 seconds");
      }
    }
    else if (argument == "--memory-limit")
    {
      options.memoryLimit = ParseNumber(argument, value());
      if (!(options.memoryLimit >= 1.0))
      {
        throw Error("--memory-limit must be at least 1 MB");
      }
    }
    else if (argument == "--demo")
    {
      options.demo = true;
    }
    else if (argument == "--output-dir")
    {
      options.outputDir = value();
    }
    else if (argument == "--snapshot")
    {
      options.snapshot = value();
      std::string why;
      if (!ffd::SnapshotPossible(why))
      {
        throw Error(why);
      }
    }
    else if (argument == "--templates")
    {
      options.templates = value();
    }
    else if (argument == "--template-split")
    {
      options.templateSplit = value();
      if (options.templateSplit != "none" && options.templateSplit != "control-point" &&
          options.templateSplit != "axis")
      {
        throw Error("--template-split must be none, control-point or axis, not '" + options.templateSplit + "'");
      }
    }
    else
    {
      throw Error("unknown argument '" + argument + "' (see --help)");
    }
  }
  if (options.demo)
  {
    if (!options.source.empty() || !options.target.empty() || !options.output.empty())
    {
      throw Error("--demo makes its own meshes: do not give --source, --target or --output");
    }
    return options;
  }
  if (options.method.empty())
  {
    throw Error("--method is required (go, mrf, par, go+par or mrf+par; see --help)");
  }
  if (options.method != "go" && options.method != "mrf" && options.method != "par" && options.method != "go+par" &&
      options.method != "mrf+par")
  {
    throw Error("unknown method '" + options.method + "' (expected go, mrf, par, go+par or mrf+par)");
  }
  const bool usesTemplates = options.method.find("par") != std::string::npos;
  if (usesTemplates && options.templates.empty())
  {
    throw Error("method " + options.method + " needs --templates FILE (an ITK transform file of B-spline templates)");
  }
  if (!usesTemplates && !options.templates.empty())
  {
    throw Error("--templates is used by the methods par, go+par and mrf+par only");
  }
  if (!ffd::MethodAvailable(options.method))
  {
    throw Error("method " + options.method + " is not available yet (use go)");
  }
  if (options.source.empty() || options.target.empty() || options.output.empty())
  {
    throw Error("--source, --target and --output are required (see --help)");
  }
  std::string extension = std::filesystem::path(options.output).extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(), [](unsigned char c) {
    return static_cast<char>(std::tolower(c));
  });
  if (extension != ".off" && extension != ".obj" && extension != ".vtk" && extension != ".vtp" && extension != ".stl" &&
      extension != ".ply")
  {
    throw Error("--output must name a mesh file ending in .off, .obj, .vtk, .vtp, .stl or .ply, not '" +
                options.output + "'");
  }
  return options;
}

/** Outputs written under temporary names in their own folders and renamed into place by Commit(). */
class PendingOutputs
{
public:
  ~PendingOutputs()
  {
    for (const auto & entry : m_Entries)
    {
      std::remove(entry.second.c_str());
    }
  }

  // Reserves a temporary name for a final name (same folder, same extension) and checks that it can be
  // written now, before any long computation.
  std::string
  Add(const std::string & finalName)
  {
    const std::size_t slash = finalName.find_last_of('/');
    const std::string directory = slash == std::string::npos ? std::string() : finalName.substr(0, slash + 1);
    const std::string name = slash == std::string::npos ? finalName : finalName.substr(slash + 1);
    if (name.empty())
    {
      throw Error("cannot write '" + finalName + "': not a file name");
    }
    const std::size_t dot = name.find('.');
    const std::string extension = dot == std::string::npos ? std::string() : name.substr(dot);
    const std::string stem = dot == std::string::npos ? name : name.substr(0, dot);
    const std::string temporary = directory + ".ffd-match-" + std::to_string(getpid()) + "-" +
                                  std::to_string(m_Entries.size()) + "-" + stem + extension;
    {
      std::ofstream probe(temporary);
      if (!probe)
      {
        throw Error("cannot write '" + finalName + "': the folder does not exist or is not writable");
      }
    }
    std::remove(temporary.c_str());
    m_Entries.emplace_back(finalName, temporary);
    return temporary;
  }

  void
  Commit()
  {
    for (const auto & entry : m_Entries)
    {
      if (std::rename(entry.second.c_str(), entry.first.c_str()) != 0)
      {
        throw Error("cannot move the result into '" + entry.first + "'");
      }
    }
    m_Entries.clear();
  }

private:
  std::vector<std::pair<std::string, std::string>> m_Entries;
};

// Reads a mesh and checks it: points present and finite, at least one triangle (or polygon) cell.
MeshType::Pointer
ReadMesh(const std::string & fileName, const std::string & role)
{
  return ffd::ReadCheckedMesh<Error, MeshType>(fileName, role);
}

void
WriteMesh(const MeshType * mesh, const std::string & fileName, const std::string & shownName)
{
  ffd::WriteMeshFile<Error>(mesh, fileName, shownName);
}

// The voxelization filter's mode for a --voxelization name.
ModeEnum
VoxelizationModeFor(const std::string & name)
{
  if (name == "occupancy")
  {
    return ModeEnum::Occupancy;
  }
  if (name == "solid")
  {
    return ModeEnum::Solid;
  }
  return ModeEnum::SignedDistance;
}

ImageType::Pointer
Voxelize(const MeshType * mesh, const Options & options, double bandWidth, const std::string & role)
{
  auto filter = ImageVoxelizerType::New();
  filter->SetInput(mesh);
  filter->SetMode(VoxelizationModeFor(options.voxelization));
  filter->SetBandWidth(bandWidth);
  filter->SetUnsignedDistance(true); // open target patches have no inside
  ImageVoxelizerType::SpacingType spacing;
  spacing.Fill(options.voxelSize);
  filter->SetGeometryFromMeshBounds(spacing, bandWidth + 2.0 * options.voxelSize);
  filter->SetMaximumNumberOfVoxels(itk::NumericTraits<itk::SizeValueType>::max()); // CheckMemory() decided
  try
  {
    filter->Update();
  }
  catch (const itk::ExceptionObject & error)
  {
    throw Error("cannot voxelize the " + role + " mesh: " + OneLine(error.GetDescription()));
  }
  ImageType::Pointer image = filter->GetOutput();
  image->DisconnectPipeline();
  const auto size = image->GetLargestPossibleRegion().GetSize();
  std::cerr << "ffd-match: voxelize: " << role << " " << filter->GetNumberOfTriangles() << " triangles";
  if (filter->GetNumberOfDegenerateTriangles() > 0)
  {
    std::cerr << " (" << filter->GetNumberOfDegenerateTriangles() << " of zero area skipped)";
  }
  std::cerr << " -> " << size[0] << "x" << size[1] << "x" << size[2] << " voxels (" << options.voxelization << ")"
            << std::endl;
  return image;
}

// Bounding box of a mesh's points.
void
BoundsOf(const MeshType * mesh, std::array<double, 3> & lower, std::array<double, 3> & upper)
{
  lower.fill(std::numeric_limits<double>::infinity());
  upper.fill(-std::numeric_limits<double>::infinity());
  for (auto it = mesh->GetPoints()->Begin(); it != mesh->GetPoints()->End(); ++it)
  {
    for (unsigned int d = 0; d < 3; ++d)
    {
      lower[d] = std::min(lower[d], static_cast<double>(it.Value()[d]));
      upper[d] = std::max(upper[d], static_cast<double>(it.Value()[d]));
    }
  }
}

// The registration estimates a deformation, not a placement: meshes whose boxes (grown by the band) do not meet
// cannot be matched, and the metric would find no voxel to compare.
void
CheckOverlap(const MeshType * source, const MeshType * target, double bandWidth)
{
  std::array<double, 3> sourceLower;
  std::array<double, 3> sourceUpper;
  std::array<double, 3> targetLower;
  std::array<double, 3> targetUpper;
  BoundsOf(source, sourceLower, sourceUpper);
  BoundsOf(target, targetLower, targetUpper);
  for (unsigned int d = 0; d < 3; ++d)
  {
    if (targetLower[d] > sourceUpper[d] + bandWidth || targetUpper[d] < sourceLower[d] - bandWidth)
    {
      throw Error("the target does not overlap the source (their bounding boxes are apart along axis " +
                  std::to_string(d) + "): ffd-match estimates a deformation, not a placement; align them first");
    }
  }
}

// Available memory in MB (MemAvailable of /proc/meminfo), or 0 when unknown.
double
AvailableMemoryMB()
{
  std::ifstream meminfo("/proc/meminfo");
  std::string   key;
  double        kilobytes = 0.0;
  std::string   unit;
  while (meminfo >> key >> kilobytes >> unit)
  {
    if (key == "MemAvailable:")
    {
      return kilobytes / 1024.0;
    }
  }
  return 0.0;
}

// Refuses, before any allocation, voxel grids whose images would not fit the memory limit. Measured peak use of
// ffd-match is about 32 bytes per voxel of the two grids together (the images, the mask, the level copies and the
// metric's gradients); 40 is budgeted.
void
CheckMemory(const MeshType * source, const MeshType * target, const Options & options, double bandWidth)
{
  constexpr double bytesPerVoxel = 40.0;
  double           voxels = 0.0;
  for (const MeshType * mesh : { source, target })
  {
    ImageVoxelizerType::SpacingType spacing;
    spacing.Fill(options.voxelSize);
    ImageVoxelizerType::PointType origin;
    ImageVoxelizerType::SizeType  size;
    try
    {
      ImageVoxelizerType::ComputeGeometryFromMeshBounds(
        mesh, spacing, bandWidth + 2.0 * options.voxelSize, origin, size);
    }
    catch (const itk::ExceptionObject & error)
    {
      throw Error("cannot lay a voxel grid over the " + std::string(mesh == source ? "source" : "target") +
                  " mesh: " + OneLine(error.GetDescription()));
    }
    voxels += static_cast<double>(size[0]) * static_cast<double>(size[1]) * static_cast<double>(size[2]);
  }
  const double available = AvailableMemoryMB();
  const double limit = options.memoryLimit > 0.0 ? options.memoryLimit : (available > 0.0 ? 0.8 * available : 8192.0);
  const double needed = voxels * bytesPerVoxel / (1024.0 * 1024.0);
  if (needed > limit)
  {
    std::ostringstream message;
    message << std::fixed << std::setprecision(0) << "the voxel images would need about " << needed << " MB (" << voxels
            << " voxels at --voxel-size " << std::defaultfloat << options.voxelSize
            << "), more than the memory limit of " << std::fixed << std::setprecision(0) << limit
            << " MB: use a larger --voxel-size or raise --memory-limit";
    throw Error(message.str());
  }
}

// The band around the target surface, without the part within the band of the target's open boundary
// (edges of one triangle): there the distance to a cut-out patch differs from the distance to the whole
// source surface whatever the deformation, so those voxels are left out of the metric.
MaskImageType::Pointer
BandMask(const MeshType * mesh, const ImageType * reference, double bandWidth, std::size_t & boundaryEdges)
{
  auto filter = MaskVoxelizerType::New();
  filter->SetInput(mesh);
  filter->SetMode(ModeEnum::BandMask);
  filter->SetBandWidth(bandWidth);
  filter->SetReferenceImage(reference);
  filter->Update();
  MaskImageType::Pointer mask = filter->GetOutput();
  mask->DisconnectPipeline();

  std::map<std::pair<itk::IdentifierType, itk::IdentifierType>, unsigned int> edgeUse;
  for (auto it = mesh->GetCells()->Begin(); it != mesh->GetCells()->End(); ++it)
  {
    const auto *       ids = it.Value()->GetPointIds();
    const unsigned int n = it.Value()->GetNumberOfPoints();
    const auto         type = it.Value()->GetType();
    if (n < 3 || (type != itk::CellGeometryEnum::TRIANGLE_CELL && type != itk::CellGeometryEnum::POLYGON_CELL))
    {
      continue;
    }
    for (unsigned int j = 0; j < n; ++j)
    {
      const auto a = ids[j];
      const auto b = ids[(j + 1) % n];
      ++edgeUse[std::make_pair(std::min(a, b), std::max(a, b))];
    }
  }
  const double radius = bandWidth + 0.5 * reference->GetSpacing()[0];
  const auto   region = mask->GetLargestPossibleRegion();
  boundaryEdges = 0;
  for (const auto & edge : edgeUse)
  {
    if (edge.second != 1)
    {
      continue;
    }
    ++boundaryEdges;
    const auto               a = mesh->GetPoint(edge.first.first);
    const auto               b = mesh->GetPoint(edge.first.second);
    const auto               ab = b - a;
    const double             length2 = ab.GetSquaredNorm();
    MaskImageType::PointType low;
    MaskImageType::PointType high;
    for (unsigned int d = 0; d < 3; ++d)
    {
      low[d] = std::min(a[d], b[d]) - radius;
      high[d] = std::max(a[d], b[d]) + radius;
    }
    itk::ContinuousIndex<double, 3> lowIndex;
    itk::ContinuousIndex<double, 3> highIndex;
    mask->TransformPhysicalPointToContinuousIndex(low, lowIndex);
    mask->TransformPhysicalPointToContinuousIndex(high, highIndex);
    MaskImageType::IndexType first;
    MaskImageType::IndexType last;
    for (unsigned int d = 0; d < 3; ++d)
    {
      const double lo = std::min(lowIndex[d], highIndex[d]);
      const double hi = std::max(lowIndex[d], highIndex[d]);
      first[d] = std::max<itk::IndexValueType>(region.GetIndex(d), static_cast<itk::IndexValueType>(std::floor(lo)));
      last[d] =
        std::min<itk::IndexValueType>(region.GetIndex(d) + static_cast<itk::IndexValueType>(region.GetSize(d)) - 1,
                                      static_cast<itk::IndexValueType>(std::ceil(hi)));
    }
    MaskImageType::IndexType index;
    for (index[2] = first[2]; index[2] <= last[2]; ++index[2])
    {
      for (index[1] = first[1]; index[1] <= last[1]; ++index[1])
      {
        for (index[0] = first[0]; index[0] <= last[0]; ++index[0])
        {
          if (mask->GetPixel(index) == 0)
          {
            continue;
          }
          MaskImageType::PointType p;
          mask->TransformIndexToPhysicalPoint(index, p);
          double t = 0.0;
          if (length2 > 0.0)
          {
            double dot = 0.0;
            for (unsigned int d = 0; d < 3; ++d)
            {
              dot += (p[d] - a[d]) * ab[d];
            }
            t = std::min(1.0, std::max(0.0, dot / length2));
          }
          double distance2 = 0.0;
          for (unsigned int d = 0; d < 3; ++d)
          {
            const double delta = p[d] - (a[d] + t * ab[d]);
            distance2 += delta * delta;
          }
          if (distance2 < radius * radius)
          {
            mask->SetPixel(index, 0);
          }
        }
      }
    }
  }
  return mask;
}

struct ErrorStatistics
{
  double mean{ 0.0 };
  double median{ 0.0 };
  double p95{ 0.0 };
  double max{ 0.0 };
};

ErrorStatistics
TrueError(const MeshType * moved, const MeshType * target, const GroundTruth & truth)
{
  auto calculator = CorrespondenceErrorType::New();
  calculator->SetMovedMesh(moved);
  calculator->SetReferenceMesh(target);
  calculator->SetCorrespondences(truth.correspondences);
  calculator->Compute();
  return { calculator->GetMeanError(),
           calculator->GetMedianError(),
           calculator->GetPercentile95Error(),
           calculator->GetMaximumError() };
}

std::string
JsonErrors(const ErrorStatistics & e)
{
  return "{ \"mean\": " + JsonNumber(e.mean) + ", \"median\": " + JsonNumber(e.median) +
         ", \"p95\": " + JsonNumber(e.p95) + ", \"max\": " + JsonNumber(e.max) + " }";
}

// Runs the pipeline on options.source / options.target and writes options.output (and the transform
// and report files). With a ground truth (demo), the true vertex errors are scored and reported too.
// Returns the ratio of the true mean error after to before (or of the mean directed distance).
// The registration stage of the chosen method.
ffd::RegistrationResult
Register(const ffd::RegistrationInputs & inputs, const Options & options)
{
  if (options.method == "go")
  {
    return ffd::RegisterGO(inputs, options);
  }
  if (options.method == "mrf")
  {
    return ffd::RegisterMRF(inputs, options);
  }
  if (options.method == "par")
  {
    return ffd::RegisterPar(inputs, options, nullptr);
  }
  // go+par, mrf+par: the voxel method's result is Par's starting point; the record keeps both stages.
  const ffd::RegistrationResult voxel =
    options.method == "go+par" ? ffd::RegisterGO(inputs, options) : ffd::RegisterMRF(inputs, options);
  ffd::RegistrationResult refined = ffd::RegisterPar(inputs, options, voxel.transform);
  refined.metricName = voxel.metricName + ", then " + refined.metricName;
  refined.stopCondition = voxel.stopCondition +
                          (voxel.stopCondition.empty() || voxel.stopCondition.back() == '\n' ? "" : "\n") +
                          refined.stopCondition;
  refined.timeLimitReached = voxel.timeLimitReached;
  return refined;
}

double
Match(const Options & options, const GroundTruth * truth, PendingOutputs & pending, const std::string & demoJson)
{
  const std::string outputTemporary = pending.Add(options.output);
  const std::string transformTemporary =
    options.transformOut.empty() ? std::string() : pending.Add(options.transformOut);
  const std::string reportTemporary = options.report.empty() ? std::string() : pending.Add(options.report);
  const std::string snapshotTemporary = options.snapshot.empty() ? std::string() : pending.Add(options.snapshot);
  const auto        totalStart = ClockType::now();

  // Read.
  auto                    start = ClockType::now();
  const MeshType::Pointer source = ReadMesh(options.source, "source");
  const MeshType::Pointer target = ReadMesh(options.target, "target");
  const double            readSeconds = SecondsSince(start);
  std::cerr << "ffd-match: read: source " << source->GetNumberOfPoints() << " vertices, target "
            << target->GetNumberOfPoints() << " vertices (" << std::fixed << std::setprecision(2) << readSeconds
            << " s)" << std::endl;

  // Voxelize: the same voxel size and band for both; the metric samples the band around the target.
  start = ClockType::now();
  const double bandWidth = 2.0 * options.voxelSize;
  CheckOverlap(source, target, bandWidth);
  CheckMemory(source, target, options, bandWidth);
  const ImageType::Pointer     fixed = Voxelize(target, options, bandWidth, "target");
  const ImageType::Pointer     moving = Voxelize(source, options, bandWidth, "source");
  std::size_t                  boundaryEdges = 0;
  const MaskImageType::Pointer mask = BandMask(target, fixed, bandWidth, boundaryEdges);
  std::size_t                  maskVoxels = 0;
  for (std::size_t i = 0; i < mask->GetLargestPossibleRegion().GetNumberOfPixels(); ++i)
  {
    maskVoxels += mask->GetBufferPointer()[i] != 0;
  }
  if (maskVoxels == 0)
  {
    throw Error("the target surface leaves no voxel to compare (too small for --voxel-size, or all open boundary)");
  }
  const double voxelizeSeconds = SecondsSince(start);
  std::cerr << "ffd-match: voxelize: " << maskVoxels << " metric voxels in the band (" << boundaryEdges
            << " open boundary edges left out), " << voxelizeSeconds << " s" << std::endl;

  // Register: T maps target (fixed) space to source (moving) space.
  start = ClockType::now();
  ffd::RegistrationInputs inputs;
  inputs.fixed = fixed;
  inputs.moving = moving;
  inputs.mask = mask;
  inputs.source = source;
  inputs.target = target;
  const ffd::RegistrationResult registration = Register(inputs, options);
  const double                  registerSeconds = SecondsSince(start);
  std::cerr << "ffd-match: register: " << registration.metricValues.size() << " iterations, " << std::fixed
            << std::setprecision(2) << registerSeconds << " s"
            << (registration.timeLimitReached ? " (stopped at --time-limit; the transform reached so far is used)" : "")
            << std::endl;

  // Apply: T^-1 moves the source onto the target.
  start = ClockType::now();
  auto apply = ApplyType::New();
  apply->SetInput(source);
  apply->SetTransformInput(registration.transform);
  apply->InverseOn();
  apply->SetInverseTolerance(1e-4);
  apply->Update();
  const MeshType * deformed = apply->GetOutput();
  const double     applySeconds = SecondsSince(start);
  std::cerr << "ffd-match: apply: " << apply->GetNumberOfNonConvergedPoints() << " non-converged inverse vertices ("
            << applySeconds << " s)" << std::endl;

  // Score: target vertices to the source surface, before and after; Jacobian of T over the target image.
  start = ClockType::now();
  auto before = SurfaceDistanceType::New();
  before->SetSourceMesh(target);
  before->SetTargetMesh(source);
  before->Compute();
  auto after = SurfaceDistanceType::New();
  after->SetSourceMesh(target);
  after->SetTargetMesh(deformed);
  after->Compute();
  auto jacobian = JacobianFilterType::New();
  jacobian->SetTransformInput(registration.transform);
  jacobian->SetReferenceImage(fixed);
  jacobian->UseReferenceImageOn();
  jacobian->Update();
  ErrorStatistics trueBefore;
  ErrorStatistics trueAfter;
  if (truth != nullptr)
  {
    trueBefore = TrueError(source, target, *truth);
    trueAfter = TrueError(deformed, target, *truth);
  }
  const double scoreSeconds = SecondsSince(start);
  std::cerr << "ffd-match: score: mean directed distance target->source " << std::setprecision(3)
            << before->GetMeanDistance() << " mm before, " << after->GetMeanDistance() << " mm after (Hausdorff "
            << before->GetMaximumDistance() << " -> " << after->GetMaximumDistance() << " mm); min det J "
            << jacobian->GetMinimumDeterminant() << std::endl;

  // Write.
  start = ClockType::now();
  WriteMesh(deformed, outputTemporary, options.output);
  if (!transformTemporary.empty())
  {
    auto writer = itk::TransformFileWriterTemplate<double>::New();
    writer->SetInput(registration.transform->Get());
    writer->SetFileName(transformTemporary);
    try
    {
      writer->Update();
    }
    catch (const itk::ExceptionObject & error)
    {
      throw Error("cannot write the transform '" + options.transformOut + "': " + OneLine(error.GetDescription()));
    }
  }
  if (!snapshotTemporary.empty())
  {
    std::ostringstream title;
    title << "ffd-match --method " << options.method << ": mean directed distance " << std::setprecision(3)
          << before->GetMeanDistance() << " -> " << after->GetMeanDistance() << " mm";
    try
    {
      ffd::WriteSnapshot(
        source, deformed, target, before->GetDistances(), after->GetDistances(), title.str(), snapshotTemporary);
    }
    catch (const std::exception & error)
    {
      throw Error(std::string("cannot write the snapshot '") + options.snapshot + "': " + OneLine(error.what()));
    }
  }
  const double writeSeconds = SecondsSince(start);
  const double totalSeconds = SecondsSince(totalStart);

  if (!reportTemporary.empty())
  {
    std::ofstream report(reportTemporary);
    report << "{\n"
           << "  \"program\": \"ffd-match\",\n"
           << "  \"method\": " << JsonString(options.method) << ",\n"
           << "  \"source\": " << JsonString(options.source) << ",\n"
           << "  \"target\": " << JsonString(options.target) << ",\n"
           << "  \"output\": " << JsonString(options.output) << ",\n"
           << "  \"transform\": " << (options.transformOut.empty() ? "null" : JsonString(options.transformOut)) << ",\n"
           << "  \"settings\": { \"grid\": " << options.grid << ", \"voxel_size\": " << JsonNumber(options.voxelSize)
           << ", \"voxelization\": " << JsonString(options.voxelization)
           << ", \"metric\": " << JsonString(registration.metricName) << ", \"band_width\": " << JsonNumber(bandWidth)
           << ", \"levels\": " << options.levels << ", \"iterations\": " << options.iterations
           << ", \"sampling\": " << JsonNumber(options.sampling) << ", \"seed\": " << options.seed
           << ", \"bending_weight\": " << JsonNumber(options.bendingWeight)
           << ", \"folding_weight\": " << JsonNumber(options.foldingWeight)
           << ", \"time_limit\": " << JsonNumber(options.timeLimit > 0.0 ? options.timeLimit : NAN)
           << ", \"threads\": " << itk::MultiThreaderBase::GetGlobalDefaultNumberOfThreads() << " },\n"
           << "  \"metric_voxels\": " << maskVoxels << ",\n"
           << "  \"target_open_boundary_edges\": " << boundaryEdges << ",\n"
           << "  \"source_vertices\": " << source->GetNumberOfPoints() << ",\n"
           << "  \"target_vertices\": " << target->GetNumberOfPoints() << ",\n"
           << "  \"seconds\": { \"read\": " << JsonNumber(readSeconds)
           << ", \"voxelize\": " << JsonNumber(voxelizeSeconds) << ", \"register\": " << JsonNumber(registerSeconds)
           << ", \"apply\": " << JsonNumber(applySeconds) << ", \"score\": " << JsonNumber(scoreSeconds)
           << ", \"write\": " << JsonNumber(writeSeconds) << ", \"total\": " << JsonNumber(totalSeconds) << " },\n"
           << "  \"metric_values\": [";
    const auto & values = registration.metricValues;
    for (std::size_t i = 0; i < values.size(); ++i)
    {
      report << (i ? ", " : "") << JsonNumber(values[i]);
    }
    report << "],\n"
           << "  \"stop_condition\": " << JsonString(registration.stopCondition) << ",\n"
           << "  \"time_limit_reached\": " << (registration.timeLimitReached ? "true" : "false") << ",\n"
           << "  \"distance_before\": { \"mean_directed\": " << JsonNumber(before->GetMeanDistance())
           << ", \"hausdorff_directed\": " << JsonNumber(before->GetMaximumDistance()) << " },\n"
           << "  \"distance_after\": { \"mean_directed\": " << JsonNumber(after->GetMeanDistance())
           << ", \"hausdorff_directed\": " << JsonNumber(after->GetMaximumDistance()) << " },\n"
           << "  \"min_jacobian_determinant\": " << JsonNumber(jacobian->GetMinimumDeterminant()) << ",\n"
           << "  \"max_jacobian_determinant\": " << JsonNumber(jacobian->GetMaximumDeterminant()) << ",\n"
           << "  \"non_converged_inverse_vertices\": " << apply->GetNumberOfNonConvergedPoints() << ",\n"
           << "  \"max_inverse_residual\": " << JsonNumber(apply->GetMaximumInverseResidual());
    if (truth != nullptr)
    {
      // Non-converged inverse vertices among those with a true position (the target region).
      std::size_t  nonConvergedInRegion = 0;
      const auto & converged = apply->GetInverseConverged();
      for (const auto & correspondence : truth->correspondences)
      {
        nonConvergedInRegion += correspondence.first < converged.size() && !converged[correspondence.first];
      }
      report << ",\n  \"non_converged_inverse_vertices_in_target_region\": " << nonConvergedInRegion;
      report << ",\n  \"true_error_before\": " << JsonErrors(trueBefore)
             << ",\n  \"true_error_after\": " << JsonErrors(trueAfter)
             << ",\n  \"correspondences\": " << truth->correspondences.size();
    }
    if (!demoJson.empty())
    {
      report << ",\n  \"demo\": " << demoJson;
    }
    report << "\n}\n";
    report.close();
    if (!report)
    {
      throw Error("cannot write the report '" + options.report + "'");
    }
  }
  pending.Commit();

  const double ratio = truth != nullptr ? trueAfter.mean / trueBefore.mean
                                        : after->GetMeanDistance() / std::max(1e-12, before->GetMeanDistance());
  std::cout << "ffd-match: wrote " << options.output << " in " << std::fixed << std::setprecision(2) << totalSeconds
            << " s; mean directed distance reduced to "
            << static_cast<int>(
                 std::lround(100.0 * after->GetMeanDistance() / std::max(1e-12, before->GetMeanDistance())))
            << "% of the start" << std::endl;
  if (truth != nullptr)
  {
    std::cout << std::setprecision(3) << "ffd-match: true error before: mean " << trueBefore.mean << ", median "
              << trueBefore.median << ", p95 " << trueBefore.p95 << ", max " << trueBefore.max << " mm\n"
              << "ffd-match: true error after:  mean " << trueAfter.mean << ", median " << trueAfter.median << ", p95 "
              << trueAfter.p95 << ", max " << trueAfter.max << " mm\n"
              << "ffd-match: true error reduced to " << static_cast<int>(std::lround(100.0 * ratio)) << "% of the start"
              << std::endl;
  }
  return ratio;
}

// ---------------------------------------------------------------------------------------------------
// Demo part: a rectangular flange plate with a rectangular boss on top and a round through hole.
// The surface is a tensor grid (profile curve around the hole x angle around the hole axis), so it is
// closed, watertight and of genus one by construction; square corners are sampled exactly.

// Distance from the origin to the rectangle [-hx, hx] x [-hy, hy] along the direction at angle theta.
double
RectangleRadius(double theta, double hx, double hy)
{
  const double c = std::abs(std::cos(theta));
  const double s = std::abs(std::sin(theta));
  double       r = std::numeric_limits<double>::infinity();
  if (c > 1e-12)
  {
    r = std::min(r, hx / c);
  }
  if (s > 1e-12)
  {
    r = std::min(r, hy / s);
  }
  return r;
}

MeshType::Pointer
MakeDemoPart()
{
  constexpr double holeRadius = 7.0;
  constexpr double flangeX = 50.0; // half sizes: 100 x 70 x 8 mm flange
  constexpr double flangeY = 35.0;
  constexpr double flangeHeight = 8.0;
  constexpr double bossX = 22.0; // 44 x 32 mm boss up to 24 mm
  constexpr double bossY = 16.0;
  constexpr double shoulderHeight = 24.0;
  constexpr double topX = 13.0; // 26 x 20 mm top boss up to 40 mm
  constexpr double topY = 10.0;
  constexpr double height = 40.0;

  // Angles: uniform, plus the rectangles' corners.
  std::vector<double>    angles;
  constexpr unsigned int uniformAngles = 128;
  for (unsigned int k = 0; k < uniformAngles; ++k)
  {
    angles.push_back(2.0 * itk::Math::pi * k / uniformAngles);
  }
  for (const auto & half :
       { std::make_pair(flangeX, flangeY), std::make_pair(bossX, bossY), std::make_pair(topX, topY) })
  {
    const double a = std::atan2(half.second, half.first);
    for (const double corner : { a, itk::Math::pi - a, itk::Math::pi + a, 2.0 * itk::Math::pi - a })
    {
      angles.push_back(corner);
    }
  }
  std::sort(angles.begin(), angles.end());
  angles.erase(std::unique(angles.begin(), angles.end(), [](double a, double b) { return std::abs(a - b) < 1e-3; }),
               angles.end());

  // Profile key points around the hole: (outline, z), 0 = hole circle, 1 = boss, 2 = flange, 3 = top boss; and
  // the number of segments to the next key point.
  struct Key
  {
    int          outline;
    double       z;
    unsigned int segments;
  };
  const std::vector<Key> keys{ { 0, 0.0, 10 },           { 2, 0.0, 2 },
                               { 2, flangeHeight, 5 },   { 1, flangeHeight, 8 },
                               { 1, shoulderHeight, 3 }, { 3, shoulderHeight, 8 },
                               { 3, height, 4 },         { 0, height, 16 } };
  const auto             position = [&](int outline, double z, double theta) {
    const double        r = outline == 0   ? holeRadius
                                        : outline == 1 ? RectangleRadius(theta, bossX, bossY)
                                        : outline == 2 ? RectangleRadius(theta, flangeX, flangeY)
                                                       : RectangleRadius(theta, topX, topY);
    MeshType::PointType p;
    p[0] = r * std::cos(theta);
    p[1] = r * std::sin(theta);
    p[2] = z;
    return p;
  };

  auto         mesh = MeshType::New();
  unsigned int profileSize = 0;
  for (const Key & key : keys)
  {
    profileSize += key.segments;
  }
  const auto          n = static_cast<unsigned int>(angles.size());
  itk::IdentifierType id = 0;
  for (std::size_t k = 0; k < keys.size(); ++k)
  {
    const Key & from = keys[k];
    const Key & to = keys[(k + 1) % keys.size()];
    for (unsigned int s = 0; s < from.segments; ++s)
    {
      const double t = static_cast<double>(s) / from.segments;
      for (const double theta : angles)
      {
        const auto          a = position(from.outline, from.z, theta);
        const auto          b = position(to.outline, to.z, theta);
        MeshType::PointType p;
        for (unsigned int d = 0; d < 3; ++d)
        {
          p[d] = (1.0 - t) * a[d] + t * b[d];
        }
        mesh->SetPoint(id++, p);
      }
    }
  }

  // Two triangles per grid quad; orientation fixed afterwards from the signed volume.
  std::vector<std::array<itk::IdentifierType, 3>> triangles;
  for (unsigned int i = 0; i < profileSize; ++i)
  {
    const unsigned int i1 = (i + 1) % profileSize;
    for (unsigned int k = 0; k < n; ++k)
    {
      const unsigned int k1 = (k + 1) % n;
      const auto v = [n](unsigned int a, unsigned int b) { return static_cast<itk::IdentifierType>(a * n + b); };
      triangles.push_back({ v(i, k), v(i1, k), v(i1, k1) });
      triangles.push_back({ v(i, k), v(i1, k1), v(i, k1) });
    }
  }
  double volume = 0.0;
  for (const auto & t : triangles)
  {
    const auto a = mesh->GetPoint(t[0]).GetVectorFromOrigin();
    const auto b = mesh->GetPoint(t[1]).GetVectorFromOrigin();
    const auto c = mesh->GetPoint(t[2]).GetVectorFromOrigin();
    volume += a * itk::CrossProduct(b, c) / 6.0;
  }
  using CellAutoPointer = MeshType::CellType::CellAutoPointer;
  using TriangleType = itk::TriangleCell<MeshType::CellType>;
  itk::IdentifierType cellId = 0;
  for (auto t : triangles)
  {
    if (volume < 0.0)
    {
      std::swap(t[1], t[2]);
    }
    CellAutoPointer cell;
    cell.TakeOwnership(new TriangleType);
    for (unsigned int j = 0; j < 3; ++j)
    {
      cell->SetPointId(j, t[j]);
    }
    mesh->SetCell(cellId++, cell);
  }
  return mesh;
}

int
RunDemo(Options options)
{
  const auto start = ClockType::now();
  if (!options.gridGiven)
  {
    options.grid = 8;
  }
  if (!options.voxelSizeGiven)
  {
    options.voxelSize = 1.5;
  }
  if (!options.levelsGiven)
  {
    options.levels = 2;
  }
  if (!options.iterationsGiven)
  {
    options.iterations = 40;
  }
  if (!options.samplingGiven)
  {
    options.sampling = 0.5;
  }
  std::error_code error;
  std::filesystem::create_directories(options.outputDir, error);
  if (error || !std::filesystem::is_directory(options.outputDir))
  {
    throw Error("cannot create the output folder '" + options.outputDir + "'");
  }
  const std::string dir = options.outputDir + "/";

  // Source: the part, scaled so its largest side is 100 mm.
  MeshType::Pointer source = MakeDemoPart();
  const auto        boxOf = [](const MeshType * mesh, MeshType::PointType & low, MeshType::PointType & high) {
    low.Fill(std::numeric_limits<float>::max());
    high.Fill(std::numeric_limits<float>::lowest());
    for (auto it = mesh->GetPoints()->Begin(); it != mesh->GetPoints()->End(); ++it)
    {
      for (unsigned int d = 0; d < 3; ++d)
      {
        low[d] = std::min(low[d], it.Value()[d]);
        high[d] = std::max(high[d], it.Value()[d]);
      }
    }
  };
  MeshType::PointType low;
  MeshType::PointType high;
  boxOf(source, low, high);
  double largest = 0.0;
  for (unsigned int d = 0; d < 3; ++d)
  {
    largest = std::max(largest, static_cast<double>(high[d] - low[d]));
  }
  const double scale = 100.0 / largest;
  for (auto it = source->GetPoints()->Begin(); it != source->GetPoints()->End(); ++it)
  {
    for (unsigned int d = 0; d < 3; ++d)
    {
      it.Value()[d] *= scale;
    }
  }
  boxOf(source, low, high);

  // Region: a central box, 60 % of the extent in x and y, 70 % in z (it keeps the flange's top face).
  MeshType::PointType regionMinimum;
  MeshType::PointType regionMaximum;
  const double        fraction[3] = { 0.6, 0.6, 0.7 };
  for (unsigned int d = 0; d < 3; ++d)
  {
    const double centre = 0.5 * (low[d] + high[d]);
    regionMinimum[d] = centre - 0.5 * fraction[d] * (high[d] - low[d]);
    regionMaximum[d] = centre + 0.5 * fraction[d] * (high[d] - low[d]);
  }

  // Deformation: smooth random B-spline noise around the region.
  using GeneratorType = itk::RandomBSplineTransformGenerator<double, 3>;
  auto                     generator = GeneratorType::New();
  GeneratorType::PointType domainMinimum;
  GeneratorType::PointType domainMaximum;
  for (unsigned int d = 0; d < 3; ++d)
  {
    domainMinimum[d] = regionMinimum[d] - 10.0;
    domainMaximum[d] = regionMaximum[d] + 10.0;
  }
  generator->SetDomainFromBoundingBox(domainMinimum, domainMaximum);
  generator->SetNumberOfControlPointsPerAxis(6);
  generator->SetNoise(GeneratorType::NoiseEnum::SmoothedGaussian);
  generator->SetSmoothingSigma(1.0);
  generator->SetRMSDisplacement(10.0);
  generator->SetSeed(static_cast<uint32_t>(options.seed));
  generator->Generate();
  const auto * deformation = generator->GetTransform();

  // Target: the region's triangles (all three vertices inside), moved by the deformation; the vertex ids
  // of source and target are the ground-truth correspondences.
  const auto inside = [&](const MeshType::PointType & p) {
    for (unsigned int d = 0; d < 3; ++d)
    {
      if (p[d] < regionMinimum[d] || p[d] > regionMaximum[d])
      {
        return false;
      }
    }
    return true;
  };
  auto                                               target = MeshType::New();
  std::map<itk::IdentifierType, itk::IdentifierType> targetId;
  GroundTruth                                        truth;
  itk::IdentifierType                                targetCellId = 0;
  for (auto it = source->GetCells()->Begin(); it != source->GetCells()->End(); ++it)
  {
    const auto * ids = it.Value()->GetPointIds();
    bool         all = true;
    for (unsigned int j = 0; j < 3; ++j)
    {
      all = all && inside(source->GetPoint(ids[j]));
    }
    if (!all)
    {
      continue;
    }
    using TriangleType = itk::TriangleCell<MeshType::CellType>;
    MeshType::CellType::CellAutoPointer cell;
    cell.TakeOwnership(new TriangleType);
    for (unsigned int j = 0; j < 3; ++j)
    {
      auto found = targetId.find(ids[j]);
      if (found == targetId.end())
      {
        const itk::IdentifierType newId = targetId.size();
        found = targetId.emplace(ids[j], newId).first;
        target->SetPoint(newId, deformation->TransformPoint(source->GetPoint(ids[j])));
        truth.correspondences.emplace_back(ids[j], newId);
      }
      cell->SetPointId(j, found->second);
    }
    target->SetCell(targetCellId++, cell);
  }
  std::cerr << "ffd-match: demo: source " << source->GetNumberOfPoints() << " vertices, " << source->GetNumberOfCells()
            << " triangles; target " << target->GetNumberOfPoints() << " vertices, " << target->GetNumberOfCells()
            << " triangles; control displacement RMS 10 mm (seed " << options.seed << "), min det J "
            << generator->GetMinimumJacobianDeterminant() << std::endl;

  // The meshes are written and read back by the ordinary pipeline.
  options.source = dir + "source.vtp";
  options.target = dir + "target.vtp";
  options.output = dir + "deformed.vtp";
  options.transformOut = dir + "transform.tfm";
  options.report = dir + "report.json";
  std::string noSnapshot;
  if (ffd::SnapshotPossible(noSnapshot))
  {
    options.snapshot = dir + "snapshot.png";
  }
  else
  {
    std::cerr << "ffd-match: demo: no snapshot.png: " << noSnapshot << std::endl;
  }
  options.method = "go";
  {
    PendingOutputs    inputs;
    const std::string sourceTemporary = inputs.Add(options.source);
    const std::string targetTemporary = inputs.Add(options.target);
    WriteMesh(source, sourceTemporary, options.source);
    WriteMesh(target, targetTemporary, options.target);
    inputs.Commit();
  }
  std::ostringstream demoJson;
  demoJson << "{ \"source_triangles\": " << source->GetNumberOfCells()
           << ", \"target_triangles\": " << target->GetNumberOfCells() << ", \"region_fraction\": [0.6, 0.6, 0.7]"
           << ", \"deformation\": { \"control_points_per_axis\": 6, \"noise\": \"SmoothedGaussian\""
           << ", \"rms_control_displacement\": 10, \"seed\": " << options.seed
           << ", \"min_jacobian_determinant\": " << JsonNumber(generator->GetMinimumJacobianDeterminant()) << " } }";
  PendingOutputs pending;
  const double   ratio = Match(options, &truth, pending, demoJson.str());
  std::cout << "ffd-match: demo finished in " << std::fixed << std::setprecision(1) << SecondsSince(start)
            << " s; files in " << options.outputDir << std::endl;
  return ratio < 1.0 ? EXIT_SUCCESS : EXIT_FAILURE;
}
} // namespace

int
main(int argc, char * argv[])
{
  ffd::CollectLibraryMessages();
  try
  {
    const Options options = ParseArguments(argc, argv);
    if (options.threads > 0)
    {
      itk::MultiThreaderBase::SetGlobalDefaultNumberOfThreads(options.threads);
      itk::MultiThreaderBase::SetGlobalMaximumNumberOfThreads(options.threads);
    }
    itk::RegisterFFDShapeMatchingMeshIOFactories();
    if (options.demo)
    {
      return RunDemo(options);
    }
    PendingOutputs pending;
    Match(options, nullptr, pending, std::string());
    return EXIT_SUCCESS;
  }
  catch (const itk::ExceptionObject & error)
  {
    std::cerr << "ffd-match: error: " << OneLine(error.GetDescription()) << std::endl;
  }
  catch (const std::bad_alloc &)
  {
    std::cerr << "ffd-match: error: not enough memory to finish the run" << std::endl;
  }
  catch (const std::exception & error)
  {
    std::cerr << "ffd-match: error: " << OneLine(error.what()) << std::endl;
  }
  return EXIT_FAILURE;
}
