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
// ffd-match, methods par, go+par and mrf+par: ParametricTemplateRegistrationMethod on the meshes themselves, with
// templates from --templates; after go or mrf, their B-spline result is the starting point.

#include "FFDInputFiles.h"
#include "FFDMatchMethods.h"
#include "FFDProgramSupport.h"
#include "itkCompositeTransform.h"
#include "itkParametricTemplateRegistrationMethod.h"
#include "itkParametricTemplateTransform.h"
#include "itkRegisterFFDShapeMatchingTransforms.h"
#include "itkTransformFileChecks.h"
#include "itkTransformFileReader.h"

#include <iomanip>
#include <iostream>
#include <sstream>
#include <vector>

namespace ffd
{
namespace
{
using ParametricTransformType = itk::ParametricTemplateTransform<double, 3>;
using BSplineType = ParametricTransformType::BSplineTransformType;

// The templates of --templates: a parametric-template transform file, or B-spline transforms on one grid (each
// a template, split by --template-split).
ParametricTransformType::Pointer
ReadTemplates(const Options & options)
{
  CheckTemplatesFile<Error>(options.templates);
  itk::RegisterFFDShapeMatchingTransforms();
  // ITK's reader builds B-spline grids from unchecked values (a negative size is undefined behaviour).
  const std::string fileProblem = itk::FindProblemInTextTransformFile(options.templates);
  if (!fileProblem.empty())
  {
    throw Error("cannot read the templates '" + options.templates + "': " + fileProblem);
  }
  auto reader = itk::TransformFileReaderTemplate<double>::New();
  reader->SetFileName(options.templates);
  try
  {
    reader->Update();
  }
  catch (const itk::ExceptionObject & error)
  {
    throw Error("cannot read the templates '" + options.templates + "': " + OneLine(error.GetDescription()));
  }
  catch (const std::exception & error)
  {
    // ITK 5.2's text transform reader throws standard exceptions on some malformed files (found by fuzzing).
    throw Error("cannot read the templates '" + options.templates + "': malformed transform file (" +
                OneLine(error.what()) + ")");
  }
  ParametricTransformType::Pointer                         templates;
  std::vector<const BSplineType *>                         bsplines;
  std::vector<itk::TransformBaseTemplate<double>::Pointer> all(reader->GetTransformList()->begin(),
                                                               reader->GetTransformList()->end());
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
  ParametricTransformType::TemplateSplitEnum split = ParametricTransformType::TemplateSplitEnum::None;
  itk::ParametricTemplateTransformEnums::TemplateSplitFromString(options.templateSplit, split);
  templates = ParametricTransformType::New();
  try
  {
    templates->SetTemplatesFromBSplineTransforms(bsplines, split);
  }
  catch (const itk::ExceptionObject & error)
  {
    throw Error("cannot make templates from '" + options.templates + "': " + OneLine(error.GetDescription()));
  }
  return templates;
}
} // namespace

RegistrationResult
RegisterPar(const RegistrationInputs & inputs, const Options & options, const DecoratedTransformType * base)
{
  using RegistrationType = itk::ParametricTemplateRegistrationMethod<MeshType, MeshType, ImageType>;
  const ParametricTransformType::Pointer templates = ReadTemplates(options);

  auto registration = RegistrationType::New();
  registration->SetFixedMesh(inputs.target);
  registration->SetMovingMesh(inputs.source);
  registration->SetTemplateTransform(templates);
  if (base != nullptr)
  {
    registration->SetBaseTransformInput(base);
  }
  registration->SetDistanceMapSpacing(options.voxelSize);
  if (options.iterationsGiven)
  {
    registration->SetNumberOfIterations(options.iterations);
  }
  registration->SetRandomSeed(options.seed);

  PrintRegistrationProgress(
    registration.GetPointer(),
    [r = registration.GetPointer()]() -> const std::vector<double> & { return r->GetMetricValues(); },
    "evaluation",
    "metric",
    20);
  std::cerr << "ffd-match: register (par" << (base != nullptr ? ", refining the voxel result" : "")
            << "): " << templates->GetNumberOfParameters() << " template weights from " << options.templates
            << std::endl;
  try
  {
    registration->Update();
  }
  catch (const itk::ExceptionObject & error)
  {
    throw Error("registration failed: " + OneLine(error.GetDescription()));
  }
  std::cerr << "ffd-match: register: mean directed distance of the match " << std::setprecision(3)
            << registration->GetInitialMeanDistance() << " -> " << registration->GetFinalMeanDistance() << " mm"
            << std::endl;

  RegistrationResult result;
  result.transform = registration->GetTransformOutput();
  result.metricValues = registration->GetMetricValues();
  result.metricName = "mean squared distance to the source surface";
  result.stopCondition = registration->GetStopConditionDescription();
  return result;
}
} // namespace ffd
