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
#ifndef FFDMatchPipeline_h
#define FFDMatchPipeline_h

// ffd-match's pipeline: itk::MeshShapeMatchingFilter set up from the command line, with progress lines on stderr.
// The filter's template code compiles in this file's translation unit only.

#include "FFDMatch.h"
#include "itkFFDShapeMatchingEnums.h"
#include "itkMeshShapeMatchingFilter.h"

namespace ffd
{
using MatchingFilterType = itk::MeshShapeMatchingFilter<MeshType, ImageType>;

/** The defaults of the matching filter, for the usage text and for the checks of the command line. */
struct MatchingDefaults
{
  Options::Enums::Method           method;
  Options::Enums::InitialTransform initialTransform;
  Options::Enums::Voxelization     voxelization;
  unsigned int                     grid;
  double                           voxelSize;
  unsigned int                     levels;
  unsigned int                     goIterations;
  unsigned int                     mrfIterations;
  unsigned int                     parIterations;
  double                           sampling;
  double                           bendingWeight;
  double                           foldingWeight;
  double                           mrfWeight;
  bool                             mrfPyramid;
  Options::MRFSolverEnum           mrfSolver;
  int                              seed;
  double                           skipGoBelow;
  unsigned int                     poseRefinementRuns;
};

MatchingDefaults
GetMatchingDefaults();

/** A matching filter with the method and the settings given on the command line (the others keep the filter's
 * defaults), the templates read from --templates, and progress lines on stderr. Throws Error. */
MatchingFilterType::Pointer
NewMatchingFilter(const Options & options);

/** Refuses, before any allocation, voxel grids over \c source and \c target (with the filter's voxel size and margin)
 * whose images would need more than \c memoryLimit MB (0: 80 % of the available memory). Throws Error. */
void
CheckMemory(const MeshType * source, const MeshType * target, const MatchingFilterType * filter, double memoryLimit);

/** Runs the filter; a refusal of the library becomes an Error. */
void
RunMatchingFilter(MatchingFilterType * filter);
} // namespace ffd

#endif // FFDMatchPipeline_h
