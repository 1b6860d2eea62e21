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
#include "itkTransformFileChecks.h"
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <vector>

namespace itk
{
std::string
FindProblemInBSplineFixedParameters(const double * fixedParameters,
                                    std::size_t    numberOfFixedParameters,
                                    unsigned int   dimension,
                                    long long      numberOfParameters)
{
  const std::size_t needed = dimension * (3 + static_cast<std::size_t>(dimension));
  if (numberOfFixedParameters < needed)
  {
    return "a B-spline grid needs " + std::to_string(needed) + " fixed parameters, there are " +
           std::to_string(numberOfFixedParameters);
  }
  for (std::size_t i = 0; i < needed; ++i)
  {
    if (!std::isfinite(fixedParameters[i]))
    {
      return "fixed parameter " + std::to_string(i) + " of the B-spline grid is not a finite number";
    }
  }
  double points = 1.0;
  for (unsigned int d = 0; d < dimension; ++d)
  {
    const double size = fixedParameters[d];
    if (size < 1.0 || size > MaximumBSplineGridSizeAlongAxis || size != std::floor(size))
    {
      std::ostringstream problem;
      problem << "the B-spline grid size along axis " << d << " is " << size << ", not a whole number in [1, "
              << MaximumBSplineGridSizeAlongAxis << "]";
      return problem.str();
    }
    points *= size;
    const double spacing = fixedParameters[2 * dimension + d];
    if (!(spacing > 0.0))
    {
      std::ostringstream problem;
      problem << "the B-spline grid spacing along axis " << d << " is " << spacing << ", not positive";
      return problem.str();
    }
  }
  if (numberOfParameters >= 0 && static_cast<double>(numberOfParameters) != points * dimension)
  {
    std::ostringstream problem;
    problem << "the B-spline grid has " << points << " points, which need " << points * dimension
            << " parameters, there are " << numberOfParameters;
    return problem.str();
  }
  return "";
}

namespace
{
/** The numbers of a "Parameters:" or "FixedParameters:" value, or a problem. */
std::string
ReadNumbers(const std::string & text, std::size_t lineNumber, std::vector<double> & numbers)
{
  numbers.clear();
  std::istringstream words(text);
  std::string        word;
  while (words >> word)
  {
    char *       end = nullptr;
    const double value = std::strtod(word.c_str(), &end);
    if (end != word.c_str() + word.size() || !std::isfinite(value))
    {
      return "line " + std::to_string(lineNumber) + ": \"" + word.substr(0, 40) + "\" is not a finite number";
    }
    numbers.push_back(value);
  }
  return "";
}

/** Trims spaces, tabs and line ends at both ends, as ITK's text transform reader does. */
std::string
Trim(const std::string & text)
{
  const std::string::size_type first = text.find_first_not_of(" \t\r\n");
  if (first == std::string::npos)
  {
    return "";
  }
  return text.substr(first, text.find_last_not_of(" \t\r\n") - first + 1);
}

/** Follows ITK's text transform reader: a "Transform:" line creates a transform, and the next "Parameters:" and
 * "FixedParameters:" lines (in either order) are set on the transform created last; "ComponentTransformFile:" reads
 * another file (followed up to a depth of 4). */
std::string
FindProblemInTextTransformFileAtDepth(const std::string & fileName, unsigned int depth)
{
  std::ifstream file(fileName, std::ios::binary);
  if (!file || depth > 4)
  {
    return "";
  }
  std::string         name;
  std::size_t         transformLine = 0;
  std::vector<double> parameters;
  std::vector<double> fixedParameters;
  bool                haveParameters = false;
  bool                haveFixedParameters = false;
  const auto          check = [&]() -> std::string {
    haveParameters = haveFixedParameters = false;
    const bool bspline = name.rfind("BSplineTransform_", 0) == 0;
    const bool parametric = name.rfind("ParametricTemplateTransform_", 0) == 0;
    if (!bspline && !parametric)
    {
      return "";
    }
    const char         last = name.back();
    const unsigned int dimension = last >= '1' && last <= '9' ? static_cast<unsigned int>(last - '0') : 3;
    const long long    numberOfParameters = bspline ? static_cast<long long>(parameters.size()) : -1;
    const std::string  problem = FindProblemInBSplineFixedParameters(
      fixedParameters.data(), fixedParameters.size(), dimension, numberOfParameters);
    return problem.empty() ? "" : "transform " + name + " (line " + std::to_string(transformLine) + "): " + problem;
  };
  std::string line;
  for (std::size_t lineNumber = 1; std::getline(file, line); ++lineNumber)
  {
    line = Trim(line);
    const std::string::size_type colon = line.find(':');
    if (line.empty() || line[0] == '#' || colon == std::string::npos)
    {
      continue; // ITK skips comments, and refuses lines without a colon itself
    }
    const std::string key = Trim(line.substr(0, colon));
    const std::string value = Trim(line.substr(colon + 1));
    std::string       problem;
    if (key == "Transform")
    {
      name = value;
      transformLine = lineNumber;
    }
    else if (key == "ComponentTransformFile")
    {
      problem = FindProblemInTextTransformFileAtDepth(value, depth + 1);
    }
    else if (key == "Parameters" || key == "FixedParameters")
    {
      const bool fixed = key == "FixedParameters";
      problem = ReadNumbers(value, lineNumber, fixed ? fixedParameters : parameters);
      (fixed ? haveFixedParameters : haveParameters) = true;
      if (problem.empty() && haveParameters && haveFixedParameters)
      {
        problem = check();
      }
    }
    if (!problem.empty())
    {
      return problem;
    }
  }
  return "";
}
} // namespace

std::string
FindProblemInTextTransformFile(const std::string & fileName)
{
  return FindProblemInTextTransformFileAtDepth(fileName, 0);
}
} // namespace itk
