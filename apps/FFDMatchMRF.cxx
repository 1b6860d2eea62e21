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
// ffd-match, method mrf: BSplineMRFImageRegistrationMethod (discrete labels, alpha-expansion) on the voxel images.

#include "FFDMatchMethods.h"
#include "FFDProgramSupport.h"
#include "itkBSplineMRFImageRegistrationMethod.h"

#include <iomanip>
#include <iostream>
#include <sstream>

namespace ffd
{
RegistrationResult
RegisterMRF(const RegistrationInputs & inputs, const Options & options)
{
  using RegistrationType = itk::BSplineMRFImageRegistrationMethod<ImageType>;
  using SimilarityEnum = RegistrationType::SimilarityEnum;

  auto registration = RegistrationType::New();
  registration->SetFixedImage(inputs.fixed);
  registration->SetMovingImage(inputs.moving);
  registration->SetFixedImageMask(inputs.mask);
  registration->SetNumberOfControlPointsPerAxis(options.grid);
  // Distances compare by their differences (sum of squared differences); occupancy and solid labels by their
  // statistics (pointwise mutual information).
  registration->SetSimilarity(options.voxelization == "sdf" ? SimilarityEnum::SumOfSquaredDifferences
                                                            : SimilarityEnum::MutualInformation);
  // Settings measured on the benchmark's signed-distance pairs (1 mm voxels, band mask; benchmark/RESULTS.md):
  // 19 sparse labels up to 0.4 x the control spacing, shrinking by 2/3 per iteration, 2 grid levels at full image
  // resolution (a shrunk image loses the thin band the distances live in), 8 iterations per level, quadratic
  // regularization of weight 1, fold rejection.
  registration->SetNumberOfLevels(options.levelsGiven ? options.levels : 2);
  registration->SetNumberOfIterationsPerLevel(options.iterationsGiven ? options.iterations : 8);
  registration->SetNumberOfLabelSteps(3);
  registration->SetMaximumDisplacementFactor(0.4);
  registration->SetLabelShrinkFactor(0.67);
  registration->SetRegularizationWeight(options.mrfWeight);
  registration->SetRejectFoldingUpdates(true);
  registration->SetUseImagePyramid(options.mrfPyramid);
  registration->SetNumberOfSolverCycles(1);

  PrintRegistrationProgress(
    registration.GetPointer(),
    [r = registration.GetPointer()]() -> const std::vector<double> & { return r->GetEnergyValues(); },
    "iteration",
    "energy",
    1);
  std::cerr << "ffd-match: register (mrf): grid " << options.grid << ", " << registration->GetNumberOfLevels()
            << " levels, " << registration->GetNumberOfIterationsPerLevel() << " iterations per level, similarity "
            << (options.voxelization == "sdf" ? "SSD" : "pointwise MI") << ", lambda " << options.mrfWeight
            << std::endl;
  try
  {
    registration->Update();
  }
  catch (const itk::ExceptionObject & error)
  {
    throw Error("registration failed: " + OneLine(error.GetDescription()));
  }

  RegistrationResult result;
  result.transform = registration->GetTransformOutput();
  result.metricValues = registration->GetEnergyValues();
  result.metricName = options.voxelization == "sdf" ? "MRF energy (SSD)" : "MRF energy (pointwise MI)";
  std::ostringstream stop;
  stop << "mrf: " << registration->GetEnergyValues().size() << " iterations, "
       << registration->GetNumberOfRejectedUpdates() << " updates rejected";
  result.stopCondition = stop.str();
  return result;
}
} // namespace ffd
