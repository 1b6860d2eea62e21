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
#include "itkFFDShapeMatchingEnums.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <utility>

namespace itk
{
namespace
{
using MethodSpelling = std::pair<FFDShapeMatchingEnums::Method, const char *>;

constexpr std::array<MethodSpelling, 5> MethodSpellings{ { { FFDShapeMatchingEnums::Method::GO, "go" },
                                                           { FFDShapeMatchingEnums::Method::MRF, "mrf" },
                                                           { FFDShapeMatchingEnums::Method::Par, "par" },
                                                           { FFDShapeMatchingEnums::Method::GOPar, "go+par" },
                                                           { FFDShapeMatchingEnums::Method::MRFPar, "mrf+par" } } };
} // namespace

std::string
FFDShapeMatchingEnums::MethodToString(Method method)
{
  for (const auto & spelling : MethodSpellings)
  {
    if (spelling.first == method)
    {
      return spelling.second;
    }
  }
  return "invalid";
}

bool
FFDShapeMatchingEnums::MethodFromString(const std::string & text, Method & method)
{
  std::string lower(text);
  std::transform(lower.begin(), lower.end(), lower.begin(), [](unsigned char c) { return std::tolower(c); });
  for (const auto & spelling : MethodSpellings)
  {
    if (lower == spelling.second)
    {
      method = spelling.first;
      return true;
    }
  }
  return false;
}

std::ostream &
operator<<(std::ostream & out, const FFDShapeMatchingEnums::Method value)
{
  return out << [value] {
    switch (value)
    {
      case FFDShapeMatchingEnums::Method::GO:
        return "itk::FFDShapeMatchingEnums::Method::GO";
      case FFDShapeMatchingEnums::Method::MRF:
        return "itk::FFDShapeMatchingEnums::Method::MRF";
      case FFDShapeMatchingEnums::Method::Par:
        return "itk::FFDShapeMatchingEnums::Method::Par";
      case FFDShapeMatchingEnums::Method::GOPar:
        return "itk::FFDShapeMatchingEnums::Method::GOPar";
      case FFDShapeMatchingEnums::Method::MRFPar:
        return "itk::FFDShapeMatchingEnums::Method::MRFPar";
    }
    return "INVALID VALUE FOR itk::FFDShapeMatchingEnums::Method";
  }();
}

std::ostream &
operator<<(std::ostream & out, const FFDShapeMatchingEnums::ImageMetric value)
{
  return out << [value] {
    switch (value)
    {
      case FFDShapeMatchingEnums::ImageMetric::MattesMutualInformation:
        return "itk::FFDShapeMatchingEnums::ImageMetric::MattesMutualInformation";
      case FFDShapeMatchingEnums::ImageMetric::MeanSquares:
        return "itk::FFDShapeMatchingEnums::ImageMetric::MeanSquares";
    }
    return "INVALID VALUE FOR itk::FFDShapeMatchingEnums::ImageMetric";
  }();
}

std::ostream &
operator<<(std::ostream & out, const FFDShapeMatchingEnums::Optimizer value)
{
  return out << [value] {
    switch (value)
    {
      case FFDShapeMatchingEnums::Optimizer::LBFGSB:
        return "itk::FFDShapeMatchingEnums::Optimizer::LBFGSB";
      case FFDShapeMatchingEnums::Optimizer::RegularStepGradientDescent:
        return "itk::FFDShapeMatchingEnums::Optimizer::RegularStepGradientDescent";
    }
    return "INVALID VALUE FOR itk::FFDShapeMatchingEnums::Optimizer";
  }();
}
} // namespace itk
