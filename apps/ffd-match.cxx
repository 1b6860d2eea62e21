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
// ffd-match: matches a source triangle mesh to a target triangle mesh with a B-spline free-form deformation
// (itk::MeshShapeMatchingFilter): both meshes are voxelized, the images registered (target = fixed, source =
// moving, so the transform T maps target space to source space), and T^-1 moves the source mesh onto the target.
//
//   ffd-match --source S --target T --method go --output DEFORMED [options]
//   ffd-match --demo [--output-dir DIR]
//
// Every output is checked before any work and written under a temporary name next to it; all are renamed into
// place together at the end, so a failed run changes no file. Errors are one line on stderr and exit code 1.

#include "FFDAllocatorSettings.h"
#include "FFDMatch.h"
#include "FFDMatchPipeline.h"
#include "FFDMatchReport.h"
#include "FFDOutputFiles.h"
#include "FFDProgramMeshIO.h"
#include "FFDProgramMessages.h"
#include "FFDProgramSupport.h"
#include "FFDSnapshot.h"
#include "FFDTransformFiles.h"
#include "itkMeshSurfaceDistanceCalculator.h"
#include "itkMultiThreaderBase.h"
#include "itkRegisterFFDShapeMatchingMeshIOFactories.h"
#include "itkTransformToJacobianDeterminantImageFilter.h"

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <sstream>

namespace ffd
{
namespace
{
using Enums = itk::FFDShapeMatchingEnums;
using SurfaceDistanceType = itk::MeshSurfaceDistanceCalculator<MeshType>;
using JacobianFilterType = itk::TransformToJacobianDeterminantImageFilter<ImageType>;

// The outputs of a run, declared (and so checked) before any work. Returns the temporary names, in the order output,
// transform, report, snapshot (empty when not asked for).
std::vector<std::string>
DeclareOutputs(const Options & options, OutputFiles & outputs)
{
  std::vector<std::string> names(4);
  try
  {
    outputs.AddInput(options.source);
    outputs.AddInput(options.target);
    if (!options.templates.empty())
    {
      outputs.AddInput(options.templates);
    }
    names[0] = outputs.Add(options.output, "--output", { ".off", ".obj", ".vtk", ".vtp", ".stl", ".ply" }, false);
    if (!options.transformOut.empty())
    {
      names[1] = outputs.Add(options.transformOut, "--transform-out", {}, false);
      if (!IsWritableTransformFileName(names[1]))
      {
        throw Error("--transform-out must name a transform file ITK can write (e.g. .tfm, .txt), not '" +
                    options.transformOut + "'");
      }
    }
    if (!options.report.empty())
    {
      names[2] = outputs.Add(options.report, "--report", {}, true);
    }
    if (!options.snapshot.empty())
    {
      names[3] = outputs.Add(options.snapshot, "--snapshot", { ".png" }, false);
    }
  }
  catch (const Error &)
  {
    throw;
  }
  catch (const std::runtime_error & error)
  {
    throw Error(error.what());
  }
  return names;
}

// Writes T to \c fileName (the temporary name of \c options.transformOut) and reads it back.
void
WriteTransform(const MatchingFilterType::TransformType * transform,
               const std::string &                       fileName,
               const Options &                           options)
{
  try
  {
    WriteTransformFile(transform, fileName);
  }
  catch (const std::exception & error)
  {
    // ITK's messages name the file written, a temporary one: the user knows the output by its own name.
    std::string problem = OneLine(error.what());
    for (std::size_t at = problem.find(fileName); at != std::string::npos; at = problem.find(fileName, at))
    {
      problem.replace(at, fileName.size(), options.transformOut);
      at += options.transformOut.size();
    }
    throw Error("cannot write the transform '" + options.transformOut + "': " + problem +
                "; is the disk full or a file size limit reached?");
  }
}
} // namespace

double
Match(const Options & options, const GroundTruth * truth, const std::string & demoJson)
{
  OutputFiles                    outputs("ffd-match");
  const std::vector<std::string> temporary = DeclareOutputs(options, outputs);
  const auto                     totalStart = ClockType::now();
  MatchRecord                    record;

  // Read.
  auto                    start = ClockType::now();
  const MeshType::Pointer source = ReadCheckedMesh<Error, MeshType>(options.source, "source");
  const MeshType::Pointer target = ReadCheckedMesh<Error, MeshType>(options.target, "target");
  record.readSeconds = SecondsSince(start);
  std::cerr << "ffd-match: read: source " << source->GetNumberOfPoints() << " vertices, target "
            << target->GetNumberOfPoints() << " vertices (" << std::fixed << std::setprecision(2) << record.readSeconds
            << " s)" << std::endl;

  // Match: voxelize, register (T maps target space to source space), apply T^-1 to the source.
  const MatchingFilterType::Pointer matching = NewMatchingFilter(options);
  matching->SetSourceMesh(source);
  matching->SetTargetMesh(target);
  // Without a pose stage the meshes must overlap already; with one, the filter checks it after the pose.
  if (matching->GetInitialTransform() == Enums::InitialTransform::None)
  {
    try
    {
      MatchingFilterType::CheckOverlap(source, target, matching->GetBandWidth());
    }
    catch (const itk::ExceptionObject & error)
    {
      throw Error(OneLine(error.GetDescription()));
    }
  }
  CheckMemory(source, target, matching, options.memoryLimit);
  RunMatchingFilter(matching);
  const MeshType *                          deformed = matching->GetOutput();
  const MatchingFilterType::TransformType * transform = matching->GetTransform();
  const auto *                              apply = matching->GetModifiableMeshTransformFilter();
  const bool                                posed = matching->GetInitialTransform() != Enums::InitialTransform::None;
  const auto *                              pose = matching->GetModifiablePoseRegistration();
  // The pose the deformation started from (the pose stage's, or its refinement's), decomposed by the filter.
  const auto & axis = matching->GetPoseRotationAxis();
  const auto & shift = matching->GetPoseTranslation();
  if (posed)
  {
    std::cerr << "ffd-match: pose (" << Enums::InitialTransformToString(matching->GetInitialTransform())
              << ", target -> source): rotation " << std::fixed << std::setprecision(2)
              << matching->GetPoseRotationAngle() << " deg about (" << std::setprecision(3) << axis[0] << ", "
              << axis[1] << ", " << axis[2] << "), scale " << std::setprecision(4) << matching->GetPoseScale()
              << ", translation (" << std::setprecision(2) << shift[0] << ", " << shift[1] << ", " << shift[2]
              << "); score " << std::setprecision(3) << pose->GetScore() << " (runner-up " << pose->GetRunnerUpScore()
              << ") (" << std::setprecision(2) << matching->GetPoseTime() << " s)" << std::endl;
    const auto & residuals = matching->GetPoseRefinementResiduals();
    if (!residuals.empty())
    {
      std::cerr << "ffd-match: pose refinement: " << residuals.size() - 1 << " more deformation runs, residual "
                << std::setprecision(4) << residuals.front() << " -> "
                << *std::min_element(residuals.begin(), residuals.end()) << " (" << std::setprecision(2)
                << matching->GetPoseRefinementTime() << " s)" << std::endl;
    }
  }
  if (matching->GetVoxelStageSkipped())
  {
    std::cerr << "ffd-match: register: GO left out: the target lies " << std::fixed << std::setprecision(3)
              << matching->GetInitialMeanDistance() << " mm from the source surface on average, under "
              << matching->GetVoxelStageDistanceThreshold()
              << " voxels (--skip-go-below); the point-drift stage starts from the identity" << std::endl;
  }
  std::cerr << "ffd-match: voxelize: " << std::fixed << std::setprecision(2) << matching->GetVoxelizationTime()
            << " s; register: " << matching->GetMetricValues().size() << " iterations, " << std::fixed
            << std::setprecision(2) << matching->GetRegistrationTime() << " s"
            << (matching->GetTimeLimitReached() ? " (stopped at --time-limit; the transform reached so far is used)"
                                                : "")
            << std::endl;
  std::cerr << "ffd-match: apply: " << apply->GetNumberOfNonConvergedPoints() << " non-converged inverse vertices ("
            << matching->GetMeshTransformTime() << " s)" << std::endl;

  // Score: target vertices to the source surface, before and after; Jacobian of T over the target image.
  start = ClockType::now();
  const auto distancesTo = [&target](const MeshType * surface) {
    auto calculator = SurfaceDistanceType::New();
    calculator->SetSourceMesh(target);
    calculator->SetTargetMesh(surface);
    calculator->Compute();
    return calculator;
  };
  // The distances before: those the filter measured for its voxel stage's decision (the same target and source
  // without a pose stage), or computed here.
  SurfaceDistanceType::ConstPointer before = matching->GetInitialDistances();
  if (before.IsNull())
  {
    before = distancesTo(source);
  }
  const auto after = distancesTo(deformed);
  auto       jacobian = JacobianFilterType::New();
  // The deformation's Jacobian (B, on the grid of the target as the deformation stage saw it, the posed target):
  // without a pose stage that is T itself; with one, T's is B's times the pose's determinant.
  jacobian->SetTransformInput(matching->GetDeformationTransformOutput());
  jacobian->SetReferenceImage(matching->GetModifiableTargetVoxelizer()->GetOutput());
  jacobian->UseReferenceImageOn();
  jacobian->Update();
  if (truth != nullptr)
  {
    record.hasTruth = true;
    record.trueBefore = TrueError(source, target, *truth);
    record.trueAfter = TrueError(deformed, target, *truth);
    record.correspondences = truth->correspondences.size();
    // Non-converged inverse vertices among those with a true position (the target region).
    const auto & converged = apply->GetInverseConverged();
    for (const auto & correspondence : truth->correspondences)
    {
      record.nonConvergedInTargetRegion += correspondence.first < converged.size() && !converged[correspondence.first];
    }
  }
  record.scoreSeconds = SecondsSince(start);
  std::cerr << "ffd-match: score: mean directed distance target->source " << std::setprecision(3)
            << before->GetMeanDistance() << " mm before, " << after->GetMeanDistance() << " mm after (Hausdorff "
            << before->GetMaximumDistance() << " -> " << after->GetMaximumDistance() << " mm); min det J "
            << jacobian->GetMinimumDeterminant() << std::endl;

  // Write (under the temporary names), each file checked.
  start = ClockType::now();
  WriteCheckedMeshFile<Error>(deformed, temporary[0], options.output);
  if (!temporary[1].empty())
  {
    WriteTransform(transform, temporary[1], options);
  }
  if (!temporary[3].empty())
  {
    std::ostringstream title;
    title << "ffd-match --method " << Enums::MethodToString(matching->GetMethod()) << ": mean directed distance "
          << std::setprecision(3) << before->GetMeanDistance() << " -> " << after->GetMeanDistance() << " mm";
    try
    {
      WriteSnapshot(source, deformed, target, before->GetDistances(), after->GetDistances(), title.str(), temporary[3]);
    }
    catch (const std::exception & error)
    {
      throw Error(std::string("cannot write the snapshot '") + options.snapshot + "': " + OneLine(error.what()));
    }
  }
  record.writeSeconds = SecondsSince(start);
  record.totalSeconds = SecondsSince(totalStart);

  if (!options.report.empty())
  {
    const auto method = matching->GetMethod();
    record.method = Enums::MethodToString(method);
    record.metricName = matching->GetMetricName();
    record.stopCondition = matching->GetStopConditionDescription();
    record.metricValues = matching->GetMetricValues();
    record.timeLimitReached = matching->GetTimeLimitReached();
    record.voxelStageSkipped = matching->GetVoxelStageSkipped();
    record.initialMeanDistance = matching->GetInitialMeanDistance();
    record.grid = matching->GetNumberOfControlPointsPerAxis();
    record.voxelSize = matching->GetVoxelSize();
    record.voxelization = Enums::VoxelizationToString(matching->GetVoxelization());
    record.bandWidth = matching->GetBandWidth();
    record.levels = matching->GetNumberOfLevels();
    record.iterations =
      matching->GetNumberOfIterationsOf(method == Enums::Method::MRF || method == Enums::Method::MRFPar
                                          ? Enums::Method::MRF
                                          : (method == Enums::Method::Par ? method : Enums::Method::GO));
    record.sampling = matching->GetSamplingPercentage();
    record.seed = matching->GetRandomSeed();
    record.bendingWeight = matching->GetBendingEnergyWeight();
    record.foldingWeight = matching->GetFoldingPenaltyWeight();
    record.timeLimit = matching->GetMaximumRunTime();
    record.threads = itk::MultiThreaderBase::GetGlobalDefaultNumberOfThreads();
    record.metricVoxels = matching->GetNumberOfMetricVoxels();
    record.openBoundaryEdges = matching->GetNumberOfOpenBoundaryEdges();
    record.sourceVertices = source->GetNumberOfPoints();
    record.targetVertices = target->GetNumberOfPoints();
    record.initialTransform = Enums::InitialTransformToString(matching->GetInitialTransform());
    if (posed)
    {
      record.poseSeconds = matching->GetPoseTime();
      record.poseAngle = matching->GetPoseRotationAngle();
      record.poseScale = matching->GetPoseScale();
      record.poseRefinementResiduals = matching->GetPoseRefinementResiduals();
      record.poseRefinementSeconds = matching->GetPoseRefinementTime();
      record.poseScore = pose->GetScore();
      record.poseRunnerUpScore = pose->GetRunnerUpScore();
      record.poseRunnerUpDistance = pose->GetRunnerUpRotationDistance();
      for (unsigned int d = 0; d < 3; ++d)
      {
        record.poseAxis[d] = axis[d];
        record.poseTranslation[d] = shift[d];
      }
    }
    record.voxelizeSeconds = matching->GetVoxelizationTime();
    record.registerSeconds = matching->GetRegistrationTime();
    record.applySeconds = matching->GetMeshTransformTime();
    record.meanDistanceBefore = before->GetMeanDistance();
    record.hausdorffBefore = before->GetMaximumDistance();
    record.meanDistanceAfter = after->GetMeanDistance();
    record.hausdorffAfter = after->GetMaximumDistance();
    record.minimumJacobian = jacobian->GetMinimumDeterminant();
    record.maximumJacobian = jacobian->GetMaximumDeterminant();
    record.nonConvergedVertices = apply->GetNumberOfNonConvergedPoints();
    record.maximumInverseResidual = apply->GetMaximumInverseResidual();
    record.demoJson = demoJson;
    try
    {
      outputs.WriteText(options.report, MatchReportJson(options, record));
    }
    catch (const std::runtime_error & error)
    {
      throw Error(error.what());
    }
  }
  try
  {
    outputs.Commit();
  }
  catch (const std::runtime_error & error)
  {
    throw Error(error.what());
  }

  const double distanceRatio = after->GetMeanDistance() / std::max(1e-12, before->GetMeanDistance());
  std::cout << "ffd-match: wrote " << options.output << " in " << std::fixed << std::setprecision(2)
            << record.totalSeconds << " s; mean directed distance reduced to "
            << static_cast<int>(std::lround(100.0 * distanceRatio)) << "% of the start" << std::endl;
  if (truth == nullptr)
  {
    return distanceRatio;
  }
  const double ratio = record.trueAfter.mean / record.trueBefore.mean;
  const auto & b = record.trueBefore;
  const auto & a = record.trueAfter;
  std::cout << std::setprecision(3) << "ffd-match: true error before: mean " << b.mean << ", median " << b.median
            << ", p95 " << b.p95 << ", max " << b.max << " mm\n"
            << "ffd-match: true error after:  mean " << a.mean << ", median " << a.median << ", p95 " << a.p95
            << ", max " << a.max << " mm\n"
            << "ffd-match: true error reduced to " << static_cast<int>(std::lround(100.0 * ratio)) << "% of the start"
            << std::endl;
  return ratio;
}
} // namespace ffd

int
main(int argc, char * argv[])
{
  ffd::KeepFreedMemoryForReuse();
  ffd::CollectLibraryMessages();
  try
  {
    const ffd::Options options = ffd::ParseArguments(argc, argv); // also applies --threads
    itk::RegisterFFDShapeMatchingMeshIOFactories();
    if (options.demo)
    {
      return ffd::RunDemo(options);
    }
    ffd::Match(options, nullptr, std::string());
    return EXIT_SUCCESS;
  }
  catch (const itk::ExceptionObject & error)
  {
    std::cerr << "ffd-match: error: " << ffd::OneLine(error.GetDescription()) << std::endl;
  }
  catch (const std::bad_alloc &)
  {
    std::cerr << "ffd-match: error: not enough memory (use a larger --voxel-size or a smaller --grid)" << std::endl;
  }
  catch (const std::exception & error)
  {
    std::cerr << "ffd-match: error: " << ffd::OneLine(error.what()) << std::endl;
  }
  return EXIT_FAILURE;
}
