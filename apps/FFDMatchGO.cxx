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
// ffd-match, method go: BSplineFFDImageRegistrationMethod on the voxel images.

#include "FFDMatchMethods.h"
#include "FFDProgramSupport.h"
#include "itkBSplineFFDImageRegistrationMethod.h"

#include <iomanip>
#include <iostream>

namespace ffd
{
std::string
GOMetricName(const Options & options)
{
  return options.voxelization == "sdf" ? "MeanSquares" : "MattesMutualInformation";
}

RegistrationResult
RegisterGO(const RegistrationInputs & inputs, const Options & options)
{
  using RegistrationType = itk::BSplineFFDImageRegistrationMethod<ImageType>;
  using MetricEnum = itk::FFDShapeMatchingEnums::ImageMetric;

  auto registration = RegistrationType::New();
  registration->SetFixedImage(inputs.fixed);
  registration->SetMovingImage(inputs.moving);
  registration->SetFixedImageMask(inputs.mask);
  registration->SetNumberOfControlPointsPerAxis(options.grid);
  // Distances compare by their differences; occupancy and solid labels by their statistics.
  registration->SetMetric(options.voxelization == "sdf" ? MetricEnum::MeanSquares
                                                        : MetricEnum::MattesMutualInformation);
  registration->SetNumberOfLevels(options.levels);
  registration->SetNumberOfIterations(options.iterations);
  registration->SetSamplingPercentage(options.sampling);
  registration->SetRandomSeed(options.seed);
  registration->SetBendingEnergyWeight(options.bendingWeight);
  registration->SetFoldingPenaltyWeight(options.foldingWeight);
  registration->SetMaximumRunTime(options.timeLimit);

  PrintRegistrationProgress(
    registration.GetPointer(),
    [r = registration.GetPointer()]() -> const std::vector<double> & { return r->GetMetricValues(); },
    "iteration",
    "metric",
    10);
  std::cerr << "ffd-match: register (go): grid " << options.grid << ", " << options.levels << " levels, "
            << options.iterations << " iterations per level, sampling " << std::defaultfloat << options.sampling
            << ", metric " << GOMetricName(options) << std::endl;
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
  result.metricValues = registration->GetMetricValues();
  result.metricName = GOMetricName(options);
  result.stopCondition = registration->GetStopConditionDescription();
  result.timeLimitReached = registration->GetTimeLimitReached();
  return result;
}
} // namespace ffd
