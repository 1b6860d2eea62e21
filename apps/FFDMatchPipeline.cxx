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
// ffd-match's pipeline: the matching filter set up from the command line, the templates of --templates, and the
// progress lines.

#include "FFDMatchPipeline.h"
#include "FFDInputFiles.h"
#include "FFDProgramSupport.h"
#include "FFDTransformFiles.h"
#include "itkCompositeTransform.h"

#include <fstream>
#include <iomanip>
#include <sstream>
#include <iostream>
#include <vector>

namespace ffd
{
namespace
{
using ParametricTransformType = MatchingFilterType::ParametricTransformType;
using BSplineType = ParametricTransformType::BSplineTransformType;

// The templates of --templates: a parametric-template transform file, or B-spline transforms on one grid (each
// a template, split by --template-split).
ParametricTransformType::Pointer
ReadTemplates(const Options & options)
{
  CheckTemplatesFile<Error>(options.templates);
  TransformListType all;
  try
  {
    all = ReadTransformFile(options.templates);
  }
  catch (const std::exception & error)
  {
    throw Error("cannot read the templates '" + options.templates + "': " + OneLine(error.what()));
  }
  ParametricTransformType::Pointer templates;
  std::vector<const BSplineType *> bsplines;
  for (std::size_t i = 0; i < all.size(); ++i)
  {
    if (auto * composite = dynamic_cast<itk::CompositeTransform<double, 3> *>(all[i].GetPointer()))
    {
      for (unsigned int k = 0; k < composite->GetNumberOfTransforms(); ++k)
      {
        all.push_back(composite->GetNthTransform(k).GetPointer());
      }
    }
    else if (auto * parametric = dynamic_cast<ParametricTransformType *>(all[i].GetPointer()))
    {
      templates = parametric;
    }
    else if (const auto * bspline = dynamic_cast<const BSplineType *>(all[i].GetPointer()))
    {
      bsplines.push_back(bspline);
    }
  }
  if (templates)
  {
    return templates;
  }
  if (bsplines.empty())
  {
    throw Error("the templates '" + options.templates +
                "' hold no BSplineTransform_double_3_3 and no parametric-template transform");
  }
  templates = ParametricTransformType::New();
  try
  {
    templates->SetTemplatesFromBSplineTransforms(bsplines, options.templateSplit);
  }
  catch (const itk::ExceptionObject & error)
  {
    throw Error("cannot make templates from '" + options.templates + "': " + OneLine(error.GetDescription()));
  }
  return templates;
}

// Prints "ffd-match: register: <step> N <quantity> V (T s)" on stderr at the first IterationEvent of
// \c registration and at every \c every-th, with the values that \c values() returns at that moment.
template <typename TRegistration, typename TValues>
void
PrintRegistrationProgress(TRegistration *     registration,
                          TValues             values,
                          const std::string & step,
                          const std::string & quantity,
                          std::size_t         every)
{
  auto start = std::make_shared<ClockType::time_point>(ClockType::now());
  registration->AddObserver(itk::StartEvent(), [start](const itk::EventObject &) { *start = ClockType::now(); });
  registration->AddObserver(itk::IterationEvent(), [=](const itk::EventObject &) {
    const auto &      list = values();
    const std::size_t n = list.size();
    if (n == 1 || (n > 0 && n % every == 0))
    {
      std::cerr << "ffd-match: register: " << step << ' ' << n << ' ' << quantity << ' ' << std::setprecision(6)
                << std::defaultfloat << list.back() << " (" << std::fixed << std::setprecision(1)
                << SecondsSince(*start) << " s)" << std::endl;
    }
  });
}

// Prints the voxelization line of \c role when \c voxelizer ends.
void
PrintVoxelization(MatchingFilterType::VoxelizerType * voxelizer, const std::string & role, const std::string & mode)
{
  voxelizer->AddObserver(itk::EndEvent(), [voxelizer, role, mode](const itk::EventObject &) {
    const auto size = voxelizer->GetOutput()->GetLargestPossibleRegion().GetSize();
    std::cerr << "ffd-match: voxelize: " << role << " " << voxelizer->GetNumberOfTriangles() << " triangles";
    if (voxelizer->GetNumberOfDegenerateTriangles() > 0)
    {
      std::cerr << " (" << voxelizer->GetNumberOfDegenerateTriangles() << " of zero area skipped)";
    }
    std::cerr << " -> " << size[0] << "x" << size[1] << "x" << size[2] << " voxels (" << mode << ")" << std::endl;
  });
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
} // namespace

// Refuses, before any allocation, voxel grids whose images would not fit the memory limit. Measured peak use of
// ffd-match is about 32 bytes per voxel of the two grids together (the images, the mask, the level copies and the
// metric's gradients); 40 is budgeted.
void
CheckMemory(const MeshType * source, const MeshType * target, const MatchingFilterType * filter, double memoryLimit)
{
  constexpr double bytesPerVoxel = 40.0;
  double           voxels = 0.0;
  for (const MeshType * mesh : { source, target })
  {
    MatchingFilterType::VoxelizerType::SpacingType spacing;
    spacing.Fill(filter->GetVoxelSize());
    MatchingFilterType::VoxelizerType::PointType origin;
    MatchingFilterType::VoxelizerType::SizeType  size;
    try
    {
      MatchingFilterType::VoxelizerType::ComputeGeometryFromMeshBounds(
        mesh, spacing, filter->GetVoxelGridMargin(), origin, size);
    }
    catch (const itk::ExceptionObject & error)
    {
      throw Error("cannot lay a voxel grid over the " + std::string(mesh == source ? "source" : "target") +
                  " mesh: " + OneLine(error.GetDescription()));
    }
    voxels += static_cast<double>(size[0]) * static_cast<double>(size[1]) * static_cast<double>(size[2]);
  }
  const double available = AvailableMemoryMB();
  const double limit = memoryLimit > 0.0 ? memoryLimit : (available > 0.0 ? 0.8 * available : 8192.0);
  const double needed = voxels * bytesPerVoxel / (1024.0 * 1024.0);
  if (needed > limit)
  {
    std::ostringstream message;
    message << std::fixed << std::setprecision(0) << "the voxel images would need about " << needed << " MB (" << voxels
            << " voxels at --voxel-size " << std::defaultfloat << filter->GetVoxelSize()
            << "), more than the memory limit of " << std::fixed << std::setprecision(0) << limit
            << " MB: use a larger --voxel-size or raise --memory-limit";
    throw Error(message.str());
  }
}


MatchingDefaults
GetMatchingDefaults()
{
  const auto filter = MatchingFilterType::New();
  using MethodEnum = MatchingFilterType::MethodEnum;
  return { filter->GetMethod(),
           filter->GetInitialTransform(),
           filter->GetVoxelization(),
           filter->GetNumberOfControlPointsPerAxis(),
           filter->GetVoxelSize(),
           filter->GetNumberOfLevels(),
           filter->GetNumberOfIterationsOf(MethodEnum::GO),
           filter->GetNumberOfIterationsOf(MethodEnum::MRF),
           filter->GetNumberOfIterationsOf(MethodEnum::Par),
           filter->GetSamplingPercentage(),
           filter->GetBendingEnergyWeight(),
           filter->GetFoldingPenaltyWeight(),
           filter->GetMRFRegularizationWeight(),
           filter->GetMRFUseImagePyramid(),
           filter->GetMRFSolver(),
           filter->GetRandomSeed(),
           filter->GetVoxelStageDistanceThreshold(),
           filter->GetPoseRefinementRuns() };
}

MatchingFilterType::Pointer
NewMatchingFilter(const Options & options)
{
  using Enums = itk::FFDShapeMatchingEnums;
  auto       filter = MatchingFilterType::New();
  const auto given = [](const auto & value, auto set) {
    if (value)
    {
      set(*value);
    }
  };
  given(options.method, [&](Enums::Method v) { filter->SetMethod(v); });
  given(options.initialTransform, [&](Enums::InitialTransform v) { filter->SetInitialTransform(v); });
  given(options.voxelization, [&](Enums::Voxelization v) { filter->SetVoxelization(v); });
  given(options.grid, [&](unsigned int v) { filter->SetNumberOfControlPointsPerAxis(v); });
  given(options.voxelSize, [&](double v) { filter->SetVoxelSize(v); });
  given(options.levels, [&](unsigned int v) { filter->SetNumberOfLevels(v); });
  given(options.iterations, [&](unsigned int v) { filter->SetNumberOfIterations(v); });
  given(options.sampling, [&](double v) { filter->SetSamplingPercentage(v); });
  given(options.bendingWeight, [&](double v) { filter->SetBendingEnergyWeight(v); });
  given(options.skipGoBelow, [&](double v) { filter->SetVoxelStageDistanceThreshold(v); });
  given(options.foldingWeight, [&](double v) { filter->SetFoldingPenaltyWeight(v); });
  given(options.mrfWeight, [&](double v) { filter->SetMRFRegularizationWeight(v); });
  given(options.mrfPyramid, [&](bool v) { filter->SetMRFUseImagePyramid(v); });
  given(options.mrfSolver, [&](Options::MRFSolverEnum v) { filter->SetMRFSolver(v); });
  given(options.timeLimit, [&](double v) { filter->SetMaximumRunTime(v); });
  given(options.seed, [&](int v) { filter->SetRandomSeed(v); });
  given(options.poseRefinementRuns, [&](unsigned int v) { filter->SetPoseRefinementRuns(v); });
  if (!options.templates.empty())
  {
    filter->SetTemplateTransform(ReadTemplates(options));
  }
  // The memory check of the program decided on the grid size before any work.
  filter->GetModifiableTargetVoxelizer()->SetMaximumNumberOfVoxels(itk::NumericTraits<itk::SizeValueType>::max());
  filter->GetModifiableSourceVoxelizer()->SetMaximumNumberOfVoxels(itk::NumericTraits<itk::SizeValueType>::max());

  // Progress lines.
  const std::string mode = Enums::VoxelizationToString(filter->GetVoxelization());
  PrintVoxelization(filter->GetModifiableTargetVoxelizer(), "target", mode);
  PrintVoxelization(filter->GetModifiableSourceVoxelizer(), "source", mode);
  auto * cut = filter->GetModifiableOpenBoundaryMask();
  cut->AddObserver(itk::EndEvent(), [cut](const itk::EventObject &) {
    std::cerr << "ffd-match: voxelize: " << cut->GetNumberOfMaskVoxels() << " metric voxels in the band ("
              << cut->GetNumberOfOpenBoundaryEdges() << " open boundary edges left out)" << std::endl;
  });
  const bool distances = filter->GetVoxelization() == Enums::Voxelization::SignedDistance;
  auto *     go = filter->GetModifiableGORegistration();
  go->AddObserver(itk::StartEvent(), [go, distances](const itk::EventObject &) {
    std::cerr << "ffd-match: register (go): grid " << go->GetNumberOfControlPointsPerAxis() << ", "
              << go->GetNumberOfLevels() << " levels, " << go->GetNumberOfIterations()
              << " iterations per level, sampling " << std::defaultfloat << go->GetSamplingPercentage() << ", metric "
              << (distances ? "MeanSquares" : "MattesMutualInformation") << std::endl;
  });
  PrintRegistrationProgress(
    go, [go]() -> const std::vector<double> & { return go->GetMetricValues(); }, "iteration", "metric", 10);
  auto * mrf = filter->GetModifiableMRFRegistration();
  mrf->AddObserver(itk::StartEvent(), [mrf, distances](const itk::EventObject &) {
    std::cerr << "ffd-match: register (mrf): grid " << mrf->GetNumberOfControlPointsPerAxis() << ", "
              << mrf->GetNumberOfLevels() << " levels, " << mrf->GetNumberOfIterationsPerLevel()
              << " iterations per level, similarity " << (distances ? "SSD" : "pointwise MI") << ", lambda "
              << mrf->GetRegularizationWeight() << std::endl;
  });
  PrintRegistrationProgress(
    mrf, [mrf]() -> const std::vector<double> & { return mrf->GetEnergyValues(); }, "iteration", "energy", 1);
  auto *            par = filter->GetModifiableParRegistration();
  const std::string templatesFile = options.templates;
  par->AddObserver(itk::StartEvent(), [par, templatesFile](const itk::EventObject &) {
    std::cerr << "ffd-match: register (par" << (par->GetBaseTransform() != nullptr ? ", refining the voxel result" : "")
              << "): " << par->GetTemplateTransform()->GetNumberOfParameters() << " template weights from "
              << templatesFile << std::endl;
  });
  PrintRegistrationProgress(
    par, [par]() -> const std::vector<double> & { return par->GetMetricValues(); }, "evaluation", "metric", 20);
  par->AddObserver(itk::EndEvent(), [par](const itk::EventObject &) {
    std::cerr << "ffd-match: register: mean directed distance of the match " << std::setprecision(3)
              << par->GetInitialMeanDistance() << " -> " << par->GetFinalMeanDistance() << " mm" << std::endl;
  });
  return filter;
}

void
RunMatchingFilter(MatchingFilterType * filter)
{
  try
  {
    filter->Update();
  }
  catch (const itk::ExceptionObject & error)
  {
    throw Error(OneLine(error.GetDescription()));
  }
}
} // namespace ffd
