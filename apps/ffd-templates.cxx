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
// ffd-templates: learns parametric templates (ParametricTemplateTransform) from the transforms of N matched pairs,
// by principal component analysis of their B-spline control displacements.
//
//   ffd-templates --output TEMPLATES.tfm [--variance F] [--max-modes K] TRANSFORM.tfm TRANSFORM.tfm ...
//
// The inputs are ffd-match's --transform-out files (the batch workflow's DIR/<id>/transform.tfm): each holds one
// BSplineTransform, alone or inside a composite with a pose (the pose is left out: the templates model the
// deformation). All must have the same number of control points and the same grid direction. Transforms on one grid
// are used exactly; otherwise every one is resampled onto the grid of the same size covering all their domains
// (ParametricTemplateTransform::ComputeCoefficientsOfTransform). The templates are the leading principal components,
// scaled by their standard deviations (SetTemplatesFromPrincipalComponents), the base is the mean deformation; the
// number of modes is the smallest that explains the fraction --variance of the variance. The file is what
// ffd-match --method par|go+par|mrf+par --templates reads. The output is checked before any work, never replaces
// an input and is written whole or not at all (ffd::OutputFiles). Errors are one line on stderr and exit code 1.

#include "FFDAllocatorSettings.h"
#include "FFDInputFiles.h"
#include "FFDOutputFiles.h"
#include "FFDProgramMessages.h"
#include "FFDProgramSupport.h"
#include "FFDTransformFiles.h"
#include "itkCompositeTransform.h"
#include "itkParametricTemplateTransform.h"
#include "itkRegisterFFDShapeMatchingTransforms.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <iomanip>
#include <iostream>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace
{
using ParametricTransformType = itk::ParametricTemplateTransform<double, 3>;
using BSplineType = ParametricTransformType::BSplineTransformType;
using CoefficientVectorType = ParametricTransformType::CoefficientVectorType;
using ffd::OneLine;

const char * const Usage =
  "usage: ffd-templates --output TEMPLATES.tfm [--variance F] [--max-modes K] TRANSFORM.tfm TRANSFORM.tfm ...\n"
  "  TRANSFORM.tfm  ffd-match --transform-out files (at least two): one BSplineTransform each, alone or in a\n"
  "                 composite with a pose; the same number of control points and grid direction in all\n"
  "  --output       the templates: a ParametricTemplateTransform file for ffd-match --templates\n"
  "  --variance     fraction of the variance the modes explain, in (0, 1] (default 0.95)\n"
  "  --max-modes    at most this many modes (default: no limit)\n";

struct Options
{
  std::string              output;
  double                   variance{ 0.95 };
  unsigned int             maximumModes{ std::numeric_limits<unsigned int>::max() };
  std::vector<std::string> transforms;
};

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
        throw std::runtime_error(argument + " needs a value");
      }
      return argv[++i];
    };
    if (argument == "--help" || argument == "-h")
    {
      std::cout << Usage;
      std::exit(EXIT_SUCCESS);
    }
    else if (argument == "--output")
    {
      options.output = value();
    }
    else if (argument == "--variance")
    {
      const std::string text = value();
      options.variance = ffd::ParseNumber<std::runtime_error>(argument, text);
      if (!(options.variance > 0.0 && options.variance <= 1.0))
      {
        throw std::runtime_error("--variance must be in (0, 1], not '" + text + "'");
      }
    }
    else if (argument == "--max-modes")
    {
      const std::string text = value();
      const double      modes = ffd::ParseNumber<std::runtime_error>(argument, text);
      if (modes != std::floor(modes) || modes < 1.0 || modes > 100000.0)
      {
        throw std::runtime_error("--max-modes must be a whole number in [1, 100000], not '" + text + "'");
      }
      options.maximumModes = static_cast<unsigned int>(modes);
    }
    else if (argument.rfind("--", 0) == 0)
    {
      throw std::runtime_error("unknown argument '" + argument + "'");
    }
    else
    {
      options.transforms.push_back(argument);
    }
  }
  if (options.output.empty())
  {
    throw std::runtime_error("--output is required (see --help)");
  }
  if (options.transforms.size() < 2)
  {
    throw std::runtime_error("give at least two transform files (ffd-match --transform-out), got " +
                             std::to_string(options.transforms.size()));
  }
  return options;
}

// The one BSplineTransform of an ffd-match transform file (top level or inside a composite).
BSplineType::Pointer
ReadBSpline(const std::string & fileName)
{
  ffd::CheckInputFile<std::runtime_error>(fileName, "transform", ffd::MaximumTransformFileSize);
  ffd::TransformListType all;
  try
  {
    all = ffd::ReadTransformFile(fileName);
  }
  catch (const std::exception & error)
  {
    throw std::runtime_error("cannot read transform '" + fileName + "': " + OneLine(error.what()));
  }
  std::vector<BSplineType::Pointer> bsplines;
  for (std::size_t i = 0; i < all.size(); ++i)
  {
    if (auto * composite = dynamic_cast<itk::CompositeTransform<double, 3> *>(all[i].GetPointer()))
    {
      for (unsigned int k = 0; k < composite->GetNumberOfTransforms(); ++k)
      {
        all.push_back(composite->GetNthTransform(k).GetPointer());
      }
    }
    else if (auto * bspline = dynamic_cast<BSplineType *>(all[i].GetPointer()))
    {
      bsplines.push_back(bspline);
    }
  }
  if (bsplines.size() != 1)
  {
    throw std::runtime_error("transform '" + fileName + "' holds " + std::to_string(bsplines.size()) +
                             " BSplineTransform_double_3_3, expected one (an ffd-match --transform-out file)");
  }
  return bsplines.front();
}

std::string
ControlPointsText(const BSplineType * transform)
{
  const auto size = transform->GetCoefficientImages()[0]->GetLargestPossibleRegion().GetSize();
  return std::to_string(size[0]) + "x" + std::to_string(size[1]) + "x" + std::to_string(size[2]);
}

// The templates' grid: the transforms' own when they share one, else the grid of the same size and direction whose
// domain covers all of theirs. Throws for another number of control points or another direction. Returns the
// number of transforms that are not on that grid (resampled).
std::size_t
SetCommonGrid(const std::vector<BSplineType::Pointer> & bsplines,
              const std::vector<std::string> &          names,
              ParametricTransformType *                 templates)
{
  const BSplineType * first = bsplines.front();
  const auto          direction = first->GetTransformDomainDirection();
  double              low[3];
  double              high[3];
  std::fill(low, low + 3, std::numeric_limits<double>::max());
  std::fill(high, high + 3, std::numeric_limits<double>::lowest());
  bool sameGrid = true;
  for (std::size_t i = 0; i < bsplines.size(); ++i)
  {
    const BSplineType * transform = bsplines[i];
    if (ControlPointsText(transform) != ControlPointsText(first))
    {
      throw std::runtime_error("mismatched grids: '" + names[i] + "' has " + ControlPointsText(transform) +
                               " control points, '" + names[0] + "' has " + ControlPointsText(first) +
                               " (match every pair with the same --grid)");
    }
    const auto otherDirection = transform->GetTransformDomainDirection();
    for (unsigned int r = 0; r < 3; ++r)
    {
      for (unsigned int c = 0; c < 3; ++c)
      {
        if (std::abs(otherDirection[r][c] - direction[r][c]) > 1e-9)
        {
          throw std::runtime_error("mismatched grids: '" + names[i] + "' has another grid direction than '" + names[0] +
                                   "'");
        }
      }
    }
    sameGrid = sameGrid && transform->GetFixedParameters() == first->GetFixedParameters();
    // The domain in the grid's own axes: origin' = D^T origin, extent along each axis.
    const auto origin = transform->GetTransformDomainOrigin();
    const auto dimensions = transform->GetTransformDomainPhysicalDimensions();
    for (unsigned int axis = 0; axis < 3; ++axis)
    {
      double start = 0.0;
      for (unsigned int r = 0; r < 3; ++r)
      {
        start += direction[r][axis] * origin[r];
      }
      low[axis] = std::min(low[axis], start);
      high[axis] = std::max(high[axis], start + dimensions[axis]);
    }
  }
  if (sameGrid)
  {
    templates->SetGridFromBSplineTransform(first);
    return 0;
  }
  ParametricTransformType::OriginType             origin;
  ParametricTransformType::PhysicalDimensionsType dimensions;
  for (unsigned int r = 0; r < 3; ++r)
  {
    origin[r] = 0.0;
    for (unsigned int axis = 0; axis < 3; ++axis)
    {
      origin[r] += direction[r][axis] * low[axis];
    }
    dimensions[r] = high[r] - low[r];
  }
  templates->SetTransformDomain(origin, dimensions, first->GetTransformDomainMeshSize(), direction);
  return static_cast<std::size_t>(std::count_if(
    bsplines.begin(), bsplines.end(), [&](const BSplineType * t) { return !templates->IsOnSameGrid(t); }));
}

// The number of modes: the fewest whose variance reaches the fraction, at most maximumModes.
unsigned int
ChooseModes(const std::vector<double> & deviations, double fraction, unsigned int maximumModes)
{
  double total = 0.0;
  for (const double deviation : deviations)
  {
    total += deviation * deviation;
  }
  double       cumulative = 0.0;
  unsigned int modes = 0;
  while (modes < deviations.size() && modes < maximumModes && cumulative < fraction * total * (1.0 - 1e-12))
  {
    cumulative += deviations[modes] * deviations[modes];
    ++modes;
  }
  return modes;
}

int
Run(const Options & options)
{
  ffd::OutputFiles outputs("ffd-templates");
  for (const auto & name : options.transforms)
  {
    outputs.AddInput(name);
  }
  const std::string temporary = outputs.Add(options.output, "--output", { ".tfm", ".txt" }, false);

  itk::RegisterFFDShapeMatchingTransforms();
  std::vector<BSplineType::Pointer> bsplines;
  for (const auto & name : options.transforms)
  {
    bsplines.push_back(ReadBSpline(name));
  }
  auto                               templates = ParametricTransformType::New();
  const std::size_t                  resampled = SetCommonGrid(bsplines, options.transforms, templates);
  std::vector<CoefficientVectorType> examples;
  for (const auto & bspline : bsplines)
  {
    examples.push_back(templates->ComputeCoefficientsOfTransform(bspline));
  }

  CoefficientVectorType              mean;
  std::vector<CoefficientVectorType> components;
  std::vector<double>                deviations;
  ParametricTransformType::ComputePrincipalComponents(
    examples, static_cast<unsigned int>(examples.size()), mean, components, deviations);
  if (deviations.empty())
  {
    throw std::runtime_error("the transforms do not vary: they have no principal component");
  }
  const unsigned int modes = ChooseModes(deviations, options.variance, options.maximumModes);
  templates->SetTemplatesFromPrincipalComponents(examples, modes);
  templates->SetBaseCoefficients(mean);

  double total = 0.0;
  for (const double deviation : deviations)
  {
    total += deviation * deviation;
  }
  std::cout << "ffd-templates: " << bsplines.size() << " transforms, " << ControlPointsText(bsplines.front())
            << " control points";
  if (resampled > 0)
  {
    std::cout << " (" << resampled << " resampled onto the grid covering all their domains)";
  }
  std::cout << "\n" << std::setprecision(4);
  double cumulative = 0.0;
  double explained = 0.0;
  for (std::size_t k = 0; k < deviations.size(); ++k)
  {
    cumulative += deviations[k] * deviations[k];
    explained = k < modes ? cumulative : explained;
    std::cout << "ffd-templates: mode " << k + 1 << ": standard deviation " << deviations[k] << ", variance "
              << 100.0 * deviations[k] * deviations[k] / total << " % (cumulative " << 100.0 * cumulative / total
              << " %)" << (k < modes ? "" : ", left out") << "\n";
  }

  try
  {
    ffd::WriteTransformFile(templates, temporary);
  }
  catch (const std::exception & error)
  {
    throw std::runtime_error("cannot write --output '" + options.output + "': " + OneLine(error.what()));
  }
  outputs.Commit();
  std::cout << "ffd-templates: " << modes << " modes explain " << 100.0 * explained / total << " % of the variance"
            << " (--variance " << 100.0 * options.variance << " %); wrote " << options.output << std::endl;
  return EXIT_SUCCESS;
}
} // namespace

int
main(int argc, char * argv[])
{
  ffd::KeepFreedMemoryForReuse();
  ffd::CollectLibraryMessages();
  try
  {
    return Run(ParseArguments(argc, argv));
  }
  catch (const itk::ExceptionObject & error)
  {
    std::cerr << "ffd-templates: error: " << OneLine(error.GetDescription()) << std::endl;
  }
  catch (const std::bad_alloc &)
  {
    std::cerr << "ffd-templates: error: not enough memory for the principal components of these transforms"
              << std::endl;
  }
  catch (const std::exception & error)
  {
    std::cerr << "ffd-templates: error: " << OneLine(error.what()) << std::endl;
  }
  return EXIT_FAILURE;
}
