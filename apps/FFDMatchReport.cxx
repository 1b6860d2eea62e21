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
// ffd-match's scoring and JSON report.

#include "FFDMatchReport.h"
#include "FFDProgramSupport.h"

#include <cmath>
#include <sstream>

namespace ffd
{
ErrorStatistics
TrueError(const MeshType * moved, const MeshType * target, const GroundTruth & truth)
{
  auto calculator = itk::PointCorrespondenceErrorCalculator<MeshType>::New();
  calculator->SetMovedMesh(moved);
  calculator->SetReferenceMesh(target);
  calculator->SetCorrespondences(truth.correspondences);
  calculator->Compute();
  return { calculator->GetMeanError(),
           calculator->GetMedianError(),
           calculator->GetPercentile95Error(),
           calculator->GetMaximumError() };
}

namespace
{
std::string
JsonErrors(const ErrorStatistics & e)
{
  return "{ \"mean\": " + JsonNumber(e.mean) + ", \"median\": " + JsonNumber(e.median) +
         ", \"p95\": " + JsonNumber(e.p95) + ", \"max\": " + JsonNumber(e.max) + " }";
}
} // namespace

std::string
MatchReportJson(const Options & options, const MatchRecord & r)
{
  std::ostringstream report;
  report << "{\n"
         << "  \"program\": \"ffd-match\",\n"
         << "  \"method\": " << JsonString(r.method) << ",\n"
         << "  \"source\": " << JsonString(options.source) << ",\n"
         << "  \"target\": " << JsonString(options.target) << ",\n"
         << "  \"output\": " << JsonString(options.output) << ",\n"
         << "  \"transform\": " << (options.transformOut.empty() ? "null" : JsonString(options.transformOut)) << ",\n"
         << "  \"settings\": { \"grid\": " << r.grid << ", \"voxel_size\": " << JsonNumber(r.voxelSize)
         << ", \"voxelization\": " << JsonString(r.voxelization) << ", \"metric\": " << JsonString(r.metricName)
         << ", \"band_width\": " << JsonNumber(r.bandWidth) << ", \"levels\": " << r.levels
         << ", \"iterations\": " << r.iterations << ", \"sampling\": " << JsonNumber(r.sampling)
         << ", \"seed\": " << r.seed << ", \"bending_weight\": " << JsonNumber(r.bendingWeight)
         << ", \"folding_weight\": " << JsonNumber(r.foldingWeight)
         << ", \"time_limit\": " << JsonNumber(r.timeLimit > 0.0 ? r.timeLimit : NAN) << ", \"threads\": " << r.threads
         << " },\n"
         << "  \"metric_voxels\": " << r.metricVoxels << ",\n"
         << "  \"target_open_boundary_edges\": " << r.openBoundaryEdges << ",\n"
         << "  \"source_vertices\": " << r.sourceVertices << ",\n"
         << "  \"target_vertices\": " << r.targetVertices << ",\n"
         << "  \"initial_transform\": " << JsonString(r.initialTransform) << ",\n";
  if (r.initialTransform != "none")
  {
    report << "  \"pose\": { \"direction\": \"target to source\", \"rotation_angle_degrees\": "
           << JsonNumber(r.poseAngle) << ", \"rotation_axis\": [" << JsonNumber(r.poseAxis[0]) << ", "
           << JsonNumber(r.poseAxis[1]) << ", " << JsonNumber(r.poseAxis[2])
           << "], \"scale\": " << JsonNumber(r.poseScale) << ", \"translation\": [" << JsonNumber(r.poseTranslation[0])
           << ", " << JsonNumber(r.poseTranslation[1]) << ", " << JsonNumber(r.poseTranslation[2])
           << "], \"score\": " << JsonNumber(r.poseScore)
           << ", \"runner_up_score\": " << JsonNumber(r.poseRunnerUpScore)
           << ", \"runner_up_rotation_distance_degrees\": " << JsonNumber(r.poseRunnerUpDistance)
           << ", \"seconds\": " << JsonNumber(r.poseSeconds)
           << ", \"refinement\": { \"deformation_runs\": " << r.poseRefinementResiduals.size() << ", \"residuals\": [";
    for (std::size_t i = 0; i < r.poseRefinementResiduals.size(); ++i)
    {
      report << (i ? ", " : "") << JsonNumber(r.poseRefinementResiduals[i]);
    }
    report << "], \"seconds\": " << JsonNumber(r.poseRefinementSeconds) << " } },\n";
  }
  report << "  \"seconds\": { \"read\": " << JsonNumber(r.readSeconds) << ", \"pose\": " << JsonNumber(r.poseSeconds)
         << ", \"voxelize\": " << JsonNumber(r.voxelizeSeconds) << ", \"register\": " << JsonNumber(r.registerSeconds)
         << ", \"apply\": " << JsonNumber(r.applySeconds) << ", \"score\": " << JsonNumber(r.scoreSeconds)
         << ", \"write\": " << JsonNumber(r.writeSeconds) << ", \"total\": " << JsonNumber(r.totalSeconds) << " },\n"
         << "  \"metric_values\": [";
  for (std::size_t i = 0; i < r.metricValues.size(); ++i)
  {
    report << (i ? ", " : "") << JsonNumber(r.metricValues[i]);
  }
  report << "],\n"
         << "  \"stop_condition\": " << JsonString(r.stopCondition) << ",\n"
         << "  \"time_limit_reached\": " << (r.timeLimitReached ? "true" : "false") << ",\n"
         << "  \"voxel_stage_skipped\": " << (r.voxelStageSkipped ? "true" : "false") << ",\n"
         << "  \"initial_mean_distance\": " << JsonNumber(r.initialMeanDistance) << ",\n"
         << "  \"distance_before\": { \"mean_directed\": " << JsonNumber(r.meanDistanceBefore)
         << ", \"hausdorff_directed\": " << JsonNumber(r.hausdorffBefore) << " },\n"
         << "  \"distance_after\": { \"mean_directed\": " << JsonNumber(r.meanDistanceAfter)
         << ", \"hausdorff_directed\": " << JsonNumber(r.hausdorffAfter) << " },\n"
         << "  \"min_jacobian_determinant\": " << JsonNumber(r.minimumJacobian) << ",\n"
         << "  \"max_jacobian_determinant\": " << JsonNumber(r.maximumJacobian) << ",\n"
         << "  \"non_converged_inverse_vertices\": " << r.nonConvergedVertices << ",\n"
         << "  \"max_inverse_residual\": " << JsonNumber(r.maximumInverseResidual);
  if (r.hasTruth)
  {
    report << ",\n  \"non_converged_inverse_vertices_in_target_region\": " << r.nonConvergedInTargetRegion
           << ",\n  \"true_error_before\": " << JsonErrors(r.trueBefore)
           << ",\n  \"true_error_after\": " << JsonErrors(r.trueAfter)
           << ",\n  \"correspondences\": " << r.correspondences;
  }
  if (!r.demoJson.empty())
  {
    report << ",\n  \"demo\": " << r.demoJson;
  }
  report << "\n}\n";
  return report.str();
}
} // namespace ffd
