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
#ifndef FFDMatchReport_h
#define FFDMatchReport_h

// ffd-match's scoring and JSON report.

#include "FFDMatch.h"

#include <string>
#include <vector>

namespace ffd
{
/** Mean, median, 95th percentile and maximum of the true vertex errors (mm). */
struct ErrorStatistics
{
  double mean{ 0.0 };
  double median{ 0.0 };
  double p95{ 0.0 };
  double max{ 0.0 };
};

/** The true errors of \c moved against \c target over the correspondences of \c truth. */
ErrorStatistics
TrueError(const MeshType * moved, const MeshType * target, const GroundTruth & truth);

/** What a run of ffd-match measured, for the report. */
struct MatchRecord
{
  std::string         method; // the method that ran
  std::string         metricName;
  std::string         stopCondition;
  std::vector<double> metricValues;
  bool                timeLimitReached{ false };
  bool                voxelStageSkipped{ false };
  double              initialMeanDistance{ -1.0 }; // what the voxel stage's skip was decided on; -1: not measured
  // The settings in effect (the filter's).
  unsigned int grid{ 0 };
  double       voxelSize{ 0.0 };
  std::string  voxelization;
  double       bandWidth{ 0.0 };
  unsigned int levels{ 0 };
  unsigned int iterations{ 0 };
  double       sampling{ 0.0 };
  int          seed{ 0 };
  double       bendingWeight{ 0.0 };
  double       foldingWeight{ 0.0 };
  double       timeLimit{ 0.0 };
  unsigned int threads{ 0 };
  // The data.
  std::size_t metricVoxels{ 0 };
  std::size_t openBoundaryEdges{ 0 };
  std::size_t sourceVertices{ 0 };
  std::size_t targetVertices{ 0 };
  // Seconds per stage.
  double readSeconds{ 0.0 };
  double voxelizeSeconds{ 0.0 };
  double registerSeconds{ 0.0 };
  double applySeconds{ 0.0 };
  double scoreSeconds{ 0.0 };
  double writeSeconds{ 0.0 };
  double totalSeconds{ 0.0 };
  // The pose stage (none: the rest is unused): A : target -> source as rotation angle (degrees) and axis, scale,
  // translation of the target centroid, trimmed distance score and the runner-up's.
  std::string initialTransform; // the pose stage that ran
  double      poseSeconds{ 0.0 };
  double      poseAngle{ 0.0 };
  double      poseAxis[3]{ 0.0, 0.0, 1.0 };
  double      poseScale{ 1.0 };
  double      poseTranslation[3]{ 0.0, 0.0, 0.0 };
  double      poseScore{ 0.0 };
  double      poseRunnerUpScore{ 0.0 };
  double      poseRunnerUpDistance{ 0.0 };
  // The pose refinement: the final soft-correspondence residual of each deformation run (empty: not run).
  std::vector<double> poseRefinementResiduals;
  double              poseRefinementSeconds{ 0.0 };
  // The scores.
  double      meanDistanceBefore{ 0.0 };
  double      hausdorffBefore{ 0.0 };
  double      meanDistanceAfter{ 0.0 };
  double      hausdorffAfter{ 0.0 };
  double      minimumJacobian{ 0.0 };
  double      maximumJacobian{ 0.0 };
  std::size_t nonConvergedVertices{ 0 };
  double      maximumInverseResidual{ 0.0 };
  // With a ground truth.
  bool            hasTruth{ false };
  std::size_t     nonConvergedInTargetRegion{ 0 };
  ErrorStatistics trueBefore;
  ErrorStatistics trueAfter;
  std::size_t     correspondences{ 0 };
  std::string     demoJson;
};

/** The JSON report of a run. */
std::string
MatchReportJson(const Options & options, const MatchRecord & record);
} // namespace ffd

#endif // FFDMatchReport_h
