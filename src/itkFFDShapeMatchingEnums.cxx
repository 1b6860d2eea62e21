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

constexpr std::array<MethodSpelling, 6> MethodSpellings{ { { FFDShapeMatchingEnums::Method::GO, "go" },
                                                           { FFDShapeMatchingEnums::Method::MRF, "mrf" },
                                                           { FFDShapeMatchingEnums::Method::Par, "par" },
                                                           { FFDShapeMatchingEnums::Method::GOPar, "go+par" },
                                                           { FFDShapeMatchingEnums::Method::MRFPar, "mrf+par" },
                                                           { FFDShapeMatchingEnums::Method::GOCPD, "go+cpd" } } };

using VoxelizationSpelling = std::pair<FFDShapeMatchingEnums::Voxelization, const char *>;

constexpr std::array<VoxelizationSpelling, 3> VoxelizationSpellings{
  { { FFDShapeMatchingEnums::Voxelization::Occupancy, "occupancy" },
    { FFDShapeMatchingEnums::Voxelization::Solid, "solid" },
    { FFDShapeMatchingEnums::Voxelization::SignedDistance, "sdf" } }
};

using InitialTransformSpelling = std::pair<FFDShapeMatchingEnums::InitialTransform, const char *>;

constexpr std::array<InitialTransformSpelling, 4> InitialTransformSpellings{
  { { FFDShapeMatchingEnums::InitialTransform::None, "none" },
    { FFDShapeMatchingEnums::InitialTransform::Rigid, "rigid" },
    { FFDShapeMatchingEnums::InitialTransform::Similarity, "similarity" },
    { FFDShapeMatchingEnums::InitialTransform::Affine, "affine" } }
};

// The spelling of \c value in \c spellings, or "invalid".
template <typename TEnum, std::size_t N>
std::string
SpellingOf(const std::array<std::pair<TEnum, const char *>, N> & spellings, TEnum value)
{
  for (const auto & spelling : spellings)
  {
    if (spelling.first == value)
    {
      return spelling.second;
    }
  }
  return "invalid";
}

// Parses \c text (case-insensitive) into \c value; false, and \c value unchanged, when no spelling matches.
template <typename TEnum, std::size_t N>
bool
ParseSpelling(const std::array<std::pair<TEnum, const char *>, N> & spellings, const std::string & text, TEnum & value)
{
  std::string lower(text);
  std::transform(lower.begin(), lower.end(), lower.begin(), [](unsigned char c) { return std::tolower(c); });
  for (const auto & spelling : spellings)
  {
    if (lower == spelling.second)
    {
      value = spelling.first;
      return true;
    }
  }
  return false;
}
} // namespace

std::string
FFDShapeMatchingEnums::MethodToString(Method method)
{
  return SpellingOf(MethodSpellings, method);
}

bool
FFDShapeMatchingEnums::MethodFromString(const std::string & text, Method & method)
{
  return ParseSpelling(MethodSpellings, text, method);
}

std::string
FFDShapeMatchingEnums::VoxelizationToString(Voxelization voxelization)
{
  return SpellingOf(VoxelizationSpellings, voxelization);
}

bool
FFDShapeMatchingEnums::VoxelizationFromString(const std::string & text, Voxelization & voxelization)
{
  return ParseSpelling(VoxelizationSpellings, text, voxelization);
}

std::string
FFDShapeMatchingEnums::InitialTransformToString(InitialTransform initialTransform)
{
  return SpellingOf(InitialTransformSpellings, initialTransform);
}

bool
FFDShapeMatchingEnums::InitialTransformFromString(const std::string & text, InitialTransform & initialTransform)
{
  return ParseSpelling(InitialTransformSpellings, text, initialTransform);
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
      case FFDShapeMatchingEnums::Method::GOCPD:
        return "itk::FFDShapeMatchingEnums::Method::GOCPD";
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

std::ostream &
operator<<(std::ostream & out, const FFDShapeMatchingEnums::Voxelization value)
{
  return out << [value] {
    switch (value)
    {
      case FFDShapeMatchingEnums::Voxelization::Occupancy:
        return "itk::FFDShapeMatchingEnums::Voxelization::Occupancy";
      case FFDShapeMatchingEnums::Voxelization::Solid:
        return "itk::FFDShapeMatchingEnums::Voxelization::Solid";
      case FFDShapeMatchingEnums::Voxelization::SignedDistance:
        return "itk::FFDShapeMatchingEnums::Voxelization::SignedDistance";
    }
    return "INVALID VALUE FOR itk::FFDShapeMatchingEnums::Voxelization";
  }();
}

std::ostream &
operator<<(std::ostream & out, const FFDShapeMatchingEnums::InitialTransform value)
{
  return out << [value] {
    switch (value)
    {
      case FFDShapeMatchingEnums::InitialTransform::None:
        return "itk::FFDShapeMatchingEnums::InitialTransform::None";
      case FFDShapeMatchingEnums::InitialTransform::Rigid:
        return "itk::FFDShapeMatchingEnums::InitialTransform::Rigid";
      case FFDShapeMatchingEnums::InitialTransform::Similarity:
        return "itk::FFDShapeMatchingEnums::InitialTransform::Similarity";
      case FFDShapeMatchingEnums::InitialTransform::Affine:
        return "itk::FFDShapeMatchingEnums::InitialTransform::Affine";
    }
    return "INVALID VALUE FOR itk::FFDShapeMatchingEnums::InitialTransform";
  }();
}
} // namespace itk
