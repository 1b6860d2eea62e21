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
#ifndef FFDMatch_h
#define FFDMatch_h

// ffd-match, the program of the module's shape-matching pipeline (itk::MeshShapeMatchingFilter). Its parts, one
// job per file: the command line (FFDMatchOptions.cxx), the filter's set-up, progress and the templates file
// (FFDMatchPipeline.cxx), scoring and the JSON report (FFDMatchReport.cxx), the demo (FFDMatchDemo.cxx), and the
// run itself (ffd-match.cxx).

#include "itkFFDShapeMatchingEnums.h"
#include "itkImage.h"
#include "itkMRFLabelingSolver.h"
#include "itkMesh.h"
#include "itkParametricTemplateTransform.h"
#include "itkPointCorrespondenceErrorCalculator.h"

#include <optional>
#include <stdexcept>
#include <string>

namespace ffd
{
// Double coordinates from reading to writing (itk::Mesh<double, 3> stores float coordinates, which move a vertex
// 1e7 mm from the origin by up to 0.5 mm); the same type as FFDSnapshot.h's DoubleCoordinateMeshType.
using MeshType = itk::Mesh<double, 3, itk::DefaultStaticMeshTraits<double, 3, 3, double, double, double>>;
using ImageType = itk::Image<float, 3>;

/** A failure of the run: one line for the user, exit code 1. */
struct Error : std::runtime_error
{
  using std::runtime_error::runtime_error;
};

/** The command line of ffd-match, parsed: the methods and modes as the library's enums. The settings of the method
 * are optional: those not given keep the defaults of itk::MeshShapeMatchingFilter, which are the module's tuned
 * settings (written there once; the usage text prints them from the filter). */
struct Options
{
  using Enums = itk::FFDShapeMatchingEnums;
  using TemplateSplitEnum = itk::ParametricTemplateTransformEnums::TemplateSplit;
  using MRFSolverEnum = itk::MRFLabelingSolverEnums::Algorithm;

  std::string       source;
  std::string       target;
  std::string       output;
  std::string       transformOut;
  std::string       report;
  std::string       snapshot;
  std::string       templates;
  TemplateSplitEnum templateSplit{ TemplateSplitEnum::ControlPoint }; // the program's own: how a file's B-splines
                                                                      // become templates
  int         threads{ 0 };
  double      memoryLimit{ 0.0 }; // MB, 0 = from the available memory
  bool        demo{ false };
  std::string outputDir{ "demo-output" };

  std::optional<Enums::Method>           method;
  std::optional<Enums::InitialTransform> initialTransform; // the pose stage
  std::optional<unsigned int>            grid;
  std::optional<double>                  voxelSize;
  std::optional<Enums::Voxelization>     voxelization;
  std::optional<int>                     seed;
  std::optional<unsigned int>            levels;
  std::optional<unsigned int>            iterations;
  std::optional<double>                  sampling;
  std::optional<double>                  bendingWeight;
  std::optional<double>                  skipGoBelow; // go+cpd: GO left out below this mean distance (voxels)
  std::optional<double>                  foldingWeight;
  std::optional<double>                  mrfWeight;
  std::optional<bool>                    mrfPyramid;
  std::optional<MRFSolverEnum>           mrfSolver;
  std::optional<double>                  timeLimit;          // seconds of registration
  std::optional<unsigned int>            poseRefinementRuns; // deformation runs added by the pose refinement
};

/** The command-line spelling of an MRF solver ("tree", "expansion", "icm"), and its parse (false for other text). */
std::string
MRFSolverToString(Options::MRFSolverEnum solver);
bool
MRFSolverFromString(const std::string & text, Options::MRFSolverEnum & solver);

/** The options of the command line; throws Error on a bad one. --help prints the usage and exits. */
Options
ParseArguments(int argc, char * argv[]);

/** Known correspondences (demo): the source vertex id and the target vertex id of the same material point. */
struct GroundTruth
{
  itk::PointCorrespondenceErrorCalculator<MeshType>::CorrespondenceContainerType correspondences;
};

/** Runs the pipeline on options.source / options.target and writes options.output (and the transform, report and
 * snapshot files), all or nothing. With a ground truth (demo), the true vertex errors are scored and reported too,
 * and \c demoJson is added to the report. Returns the ratio of the true mean error after to before (or of the mean
 * directed distance). */
double
Match(const Options & options, const GroundTruth * truth, const std::string & demoJson);

/** The demo: builds a CAD-like part, cuts and deforms a target from it, matches and scores it. Returns the exit
 * code. */
int
RunDemo(Options options);
} // namespace ffd

#endif // FFDMatch_h
