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
// ffd-match's command line: the options, their checks and the usage text.

#include "FFDMatch.h"
#include "FFDMatchPipeline.h"
#include "FFDProgramSupport.h"
#include "FFDSnapshot.h"
#include "itkMultiThreaderBase.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <iomanip>
#include <iostream>
#include <sstream>

namespace ffd
{
namespace
{
// The usage text, with the defaults of the matching filter.
std::string
Usage()
{
  const MatchingDefaults defaults = GetMatchingDefaults();
  std::ostringstream     usage;
  usage << "usage: ffd-match --source S --target T --output DEFORMED\n"
           "                 [--method go+cpd|go|mrf|par|go+par|mrf+par]\n"
           "                 [--grid N] [--voxel-size S] [--voxelization occupancy|solid|sdf]\n"
           "                 [--templates FILE.tfm] [--template-split none|control-point|axis]\n"
           "                 [--transform-out FILE.tfm] [--report FILE.json] [--snapshot FILE.png]\n"
           "                 [--initial-transform none|rigid|similarity|affine] [--pose-refinement N]\n"
           "                 [--skip-go-below VOXELS]\n"
           "                 [--threads N] [--seed S]\n"
           "                 [--levels L] [--iterations N] [--sampling P]\n"
           "                 [--time-limit SECONDS] [--memory-limit MB]\n"
           "                 [--bending-weight W] [--folding-weight W] [--mrf-weight W] [--mrf-pyramid on|off]\n"
           "                 [--mrf-solver tree|expansion|icm]\n"
           "       ffd-match --demo [--output-dir DIR] [same tuning options]\n"
           "  --source        mesh moved onto the target (OFF, OBJ, VTK, VTP, STL or PLY)\n"
           "  --target        mesh (or open surface patch) matched to\n"
           "  --method        (default "
        << Options::Enums::MethodToString(defaults.method)
        << ") go+cpd: go, refined by coherent point drift on the B-spline\n"
           "                  coefficients (soft vertex correspondences in both directions, bending\n"
           "                  prior); go: B-spline FFD by gradient-based image registration; mrf: by discrete\n"
           "                  Markov-random-field optimization of the control points; par: template\n"
           "                  weights fitted to the meshes directly (needs --templates); go+par, mrf+par:\n"
           "                  go or mrf, refined by par\n"
           "  --templates     ITK transform file of B-spline templates on one grid (par methods)\n"
           "  --template-split control-point: one weight per control point and template; axis: per control\n"
           "                  point and axis; none: one weight per template (default "
        << itk::ParametricTemplateTransformEnums::TemplateSplitToString(Options{}.templateSplit)
        << ")\n"
           "  --mrf-weight    regularization weight lambda of method mrf (default "
        << defaults.mrfWeight
        << ")\n"
           "  --mrf-pyramid   off: every mrf level uses the full-resolution images; on: coarse levels use\n"
           "                  smoothed, shrunk images (faster, less accurate on thin distance bands) (default "
        << (defaults.mrfPyramid ? "on" : "off")
        << ")\n"
           "  --mrf-solver    tree: exact minimum on a minimum spanning tree of the control grid, then ICM\n"
           "                  sweeps; expansion: alpha-expansion by max-flow (slower); icm: greedy sweeps\n"
           "                  (default "
        << MRFSolverToString(defaults.mrfSolver)
        << ")\n"
           "  --output        deformed source: the source's vertex order and cells, moved onto the target\n"
           "  --grid          control points per axis of the final B-spline grid, >= 4 (default "
        << defaults.grid
        << ")\n"
           "  --voxel-size    voxel edge length in mesh units (default "
        << defaults.voxelSize
        << ")\n"
           "  --voxelization  sdf: unsigned distance in a band, mean squares metric; occupancy: surface\n"
           "                  voxels, Mattes mutual information; solid: inside voxels (winding number), Mattes\n"
           "                  mutual information. The metric samples a band around the target surface\n"
           "                  (default "
        << Options::Enums::VoxelizationToString(defaults.voxelization)
        << ")\n"
           "  --initial-transform  the pose stage before the deformation: none (the meshes must overlap),\n"
           "                  or a rigid, similarity (rigid + isotropic scale) or affine pose found from any\n"
           "                  rotation, scale and translation, with a partial target; T is then the composite\n"
           "                  of the deformation and the pose (default "
        << Options::Enums::InitialTransformToString(defaults.initialTransform)
        << ")\n"
           "  --pose-refinement  with a pose stage and go+cpd: at most N more deformation runs from small\n"
           "                  corrections of the pose (rotations, shifts, scalings), keeping the run whose\n"
           "                  soft correspondences fit best (default "
        << defaults.poseRefinementRuns
        << "; 0: the pose stage's pose only)\n"
           "  --skip-go-below go+cpd without a pose stage: when the target's vertices lie, on average, less\n"
           "                  than VOXELS voxels from the source surface, GO (and the source's voxelization)\n"
           "                  is left out and the point-drift stage starts from the identity (default "
        << defaults.skipGoBelow
        << ";\n"
           "                  0: always run GO)\n"
           "  --transform-out write T (target space -> source space) as an ITK transform file\n"
           "  --report        write a JSON report (stage times, metric per iteration, distances, ...)\n"
           "  --snapshot      write a before/after picture (PNG; VTK off-screen rendering needs an X display:\n"
           "                  run under xvfb-run on a machine without one)\n"
           "  --threads       number of threads (default all)\n"
           "  --seed          seed of the metric sampling (and of the demo's deformation), default "
        << defaults.seed
        << "\n"
           "  --levels        resolution levels (default "
        << defaults.levels
        << ")\n"
           "  --iterations    optimizer iterations per level (default go "
        << defaults.goIterations << ", mrf " << defaults.mrfIterations << ", par " << defaults.parIterations
        << ")\n"
           "  --sampling      fraction of the band voxels sampled by the metric, (0, 1] (default "
        << defaults.sampling
        << ")\n"
           "  --time-limit    stop the registration after this many seconds and go on with the transform\n"
           "                  reached so far (the report says so); default: no limit\n"
           "  --memory-limit  refuse (before any work) a voxel grid whose images would need more than this many\n"
           "                  MB; default: 80 % of the available memory\n"
           "  --bending-weight weight of the B-spline bending energy added to the metric (default "
        << defaults.bendingWeight
        << ")\n"
           "  --folding-weight weight of the folding (negative Jacobian) penalty added to the metric (default "
        << defaults.foldingWeight
        << ")\n"
           "  --demo          build a CAD-like part, cut and deform a target from it, match and score it;\n"
           "                  writes source.vtp, target.vtp, deformed.vtp, transform.tfm, report.json and,\n"
           "                  with a display, snapshot.png\n"
           "  --output-dir    folder of the demo's files (default demo-output)\n";
  return usage.str();
}

double
Number(const std::string & option, const std::string & text)
{
  return ParseNumber<Error>(option, text);
}

unsigned int
WholeNumber(const std::string & option, const std::string & text, double minimum, double maximum)
{
  const double value = Number(option, text);
  if (value != std::floor(value) || value < minimum || value > maximum)
  {
    std::ostringstream message;
    // (Whole bounds in full: 2147483647, not 2.14748e+09.)
    message << std::setprecision(15) << option << " must be a whole number in [" << minimum << ", " << maximum
            << "], not '" << text << "'";
    throw Error(message.str());
  }
  return static_cast<unsigned int>(value);
}
} // namespace

std::string
MRFSolverToString(Options::MRFSolverEnum solver)
{
  switch (solver)
  {
    case Options::MRFSolverEnum::AlphaExpansion:
      return "expansion";
    case Options::MRFSolverEnum::ICM:
      return "icm";
    case Options::MRFSolverEnum::SpanningTree:
    default:
      return "tree";
  }
}

bool
MRFSolverFromString(const std::string & text, Options::MRFSolverEnum & solver)
{
  using Solver = Options::MRFSolverEnum;
  std::string lower = text; // case-insensitive, as the library's parsers of the other names
  std::transform(
    lower.begin(), lower.end(), lower.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  for (const Solver candidate : { Solver::SpanningTree, Solver::AlphaExpansion, Solver::ICM })
  {
    if (lower == MRFSolverToString(candidate))
    {
      solver = candidate;
      return true;
    }
  }
  return false;
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
      std::cout << Usage();
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
      const std::string      text = value();
      Options::Enums::Method method;
      if (!Options::Enums::MethodFromString(text, method))
      {
        throw Error("unknown method '" + text + "' (expected go, mrf, par, go+par, mrf+par or go+cpd)");
      }
      options.method = method;
    }
    else if (argument == "--output")
    {
      options.output = value();
    }
    else if (argument == "--grid")
    {
      const std::string text = value();
      const double      grid = Number(argument, text);
      if (grid != std::floor(grid) || grid < 4 || grid > 200)
      {
        throw Error("--grid must be a whole number of control points per axis in [4, 200], not '" + text + "'");
      }
      options.grid = static_cast<unsigned int>(grid);
    }
    else if (argument == "--voxel-size")
    {
      options.voxelSize = Number(argument, value());
      if (!(*options.voxelSize > 0.0))
      {
        throw Error("--voxel-size must be > 0");
      }
    }
    else if (argument == "--voxelization")
    {
      const std::string            text = value();
      Options::Enums::Voxelization voxelization;
      if (!Options::Enums::VoxelizationFromString(text, voxelization))
      {
        throw Error("--voxelization must be occupancy, solid or sdf, not '" + text + "'");
      }
      options.voxelization = voxelization;
    }
    else if (argument == "--initial-transform")
    {
      const std::string                text = value();
      Options::Enums::InitialTransform initialTransform;
      if (!Options::Enums::InitialTransformFromString(text, initialTransform))
      {
        throw Error("--initial-transform must be none, rigid, similarity or affine, not '" + text + "'");
      }
      options.initialTransform = initialTransform;
    }
    else if (argument == "--pose-refinement")
    {
      options.poseRefinementRuns = WholeNumber(argument, value(), 0, 1000);
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
      options.threads = static_cast<int>(WholeNumber(argument, value(), 1, 4096));
    }
    else if (argument == "--seed")
    {
      options.seed = static_cast<int>(WholeNumber(argument, value(), 0, 2147483647.0));
    }
    else if (argument == "--levels")
    {
      options.levels = WholeNumber(argument, value(), 1, 8);
    }
    else if (argument == "--iterations")
    {
      options.iterations = WholeNumber(argument, value(), 1, 100000);
    }
    else if (argument == "--sampling")
    {
      options.sampling = Number(argument, value());
      if (!(*options.sampling > 0.0 && *options.sampling <= 1.0))
      {
        throw Error("--sampling must be in (0, 1]");
      }
    }
    else if (argument == "--skip-go-below")
    {
      const double voxels = Number(argument, value());
      if (!(voxels >= 0.0) || !std::isfinite(voxels))
      {
        throw Error("--skip-go-below must be a finite number >= 0");
      }
      options.skipGoBelow = voxels;
    }
    else if (argument == "--bending-weight" || argument == "--folding-weight" || argument == "--mrf-weight")
    {
      const double weight = Number(argument, value());
      if (weight < 0.0)
      {
        throw Error(argument + " must be >= 0");
      }
      (argument == "--bending-weight" ? options.bendingWeight
                                      : (argument == "--folding-weight" ? options.foldingWeight : options.mrfWeight)) =
        weight;
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
    else if (argument == "--mrf-solver")
    {
      const std::string      setting = value();
      Options::MRFSolverEnum solver;
      if (!MRFSolverFromString(setting, solver))
      {
        throw Error("--mrf-solver must be tree, expansion or icm, not '" + setting + "'");
      }
      options.mrfSolver = solver;
    }
    else if (argument == "--time-limit")
    {
      options.timeLimit = Number(argument, value());
      if (!(*options.timeLimit > 0.0))
      {
        throw Error("--time-limit must be > 0 seconds");
      }
    }
    else if (argument == "--memory-limit")
    {
      options.memoryLimit = Number(argument, value());
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
      if (!SnapshotPossible(why))
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
      const std::string text = value();
      if (!itk::ParametricTemplateTransformEnums::TemplateSplitFromString(text, options.templateSplit))
      {
        throw Error("--template-split must be none, control-point or axis, not '" + text + "'");
      }
    }
    else
    {
      throw Error("unknown argument '" + argument + "' (see --help)");
    }
  }
  // --threads goes to ITK's global settings here, before any ITK object is made (the check of the method below makes
  // a matching filter for its default): ITK's thread pool, once made, keeps the threads it started with.
  if (options.threads > 0)
  {
    itk::MultiThreaderBase::SetGlobalDefaultNumberOfThreads(options.threads);
    itk::MultiThreaderBase::SetGlobalMaximumNumberOfThreads(options.threads);
  }
  if (options.demo)
  {
    if (!options.source.empty() || !options.target.empty() || !options.output.empty())
    {
      throw Error("--demo makes its own meshes: do not give --source, --target or --output");
    }
    return options;
  }
  using Method = Options::Enums::Method;
  const Method method = options.method.value_or(GetMatchingDefaults().method);
  const bool   usesTemplates = method == Method::Par || method == Method::GOPar || method == Method::MRFPar;
  if (usesTemplates && options.templates.empty())
  {
    throw Error("method " + Options::Enums::MethodToString(method) +
                " needs --templates FILE (an ITK transform file of B-spline templates)");
  }
  if (!usesTemplates && !options.templates.empty())
  {
    throw Error("--templates is used by the methods par, go+par and mrf+par only");
  }
  if (options.source.empty() || options.target.empty() || options.output.empty())
  {
    throw Error("--source, --target and --output are required (see --help)");
  }
  return options;
}
} // namespace ffd
