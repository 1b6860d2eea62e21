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
#include "itkStrictTextParsing.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <limits>

namespace itk
{
namespace detail
{
namespace StrictText
{
[[noreturn]] void
Fail(const std::string & message)
{
  throw ParseError{ message };
}

[[noreturn]] void
FailAtLine(std::size_t line, const std::string & message)
{
  throw ParseError{ "line " + std::to_string(line) + ": " + message };
}

/** A token quoted for a message: non-printable bytes as \xNN, at most 24 characters. */
std::string
Quote(std::string_view token)
{
  std::string quoted = "\"";
  std::size_t shown = 0;
  for (const char character : token)
  {
    if (shown == 24)
    {
      quoted += "...";
      break;
    }
    const auto byte = static_cast<unsigned char>(character);
    if (std::isprint(byte) && byte != '"' && byte != '\\')
    {
      quoted += character;
    }
    else
    {
      char escaped[8];
      std::snprintf(escaped, sizeof(escaped), "\\x%02X", static_cast<unsigned int>(byte));
      quoted += escaped;
    }
    ++shown;
  }
  return quoted + "\"";
}

std::string
Upper(std::string_view text)
{
  std::string result(text);
  std::transform(result.begin(), result.end(), result.begin(), [](unsigned char character) {
    return static_cast<char>(std::toupper(character));
  });
  return result;
}

/** Parses the whole token as a real number (C locale; "inf", "nan" give non-finite values).
 * Returns false when the token is not a number; sets outOfRange for a number beyond double. */
bool
ParseReal(std::string_view token, double & value, bool & outOfRange)
{
  outOfRange = false;
  if (!token.empty() && token.front() == '+')
  {
    token.remove_prefix(1);
  }
  if (token.empty())
  {
    return false;
  }
  const char * end = token.data() + token.size();
  const auto   result = std::from_chars(token.data(), end, value, std::chars_format::general);
  if (result.ptr != end)
  {
    return false;
  }
  if (result.ec == std::errc::result_out_of_range)
  {
    // A negative exponent means a magnitude below the smallest double: zero for a mesh.
    const std::size_t exponent = token.find_first_of("eE");
    if (exponent != std::string_view::npos && exponent + 1 < token.size() && token[exponent + 1] == '-')
    {
      value = 0.0;
      return true;
    }
    outOfRange = true;
    value = std::numeric_limits<double>::infinity();
    return true;
  }
  return result.ec == std::errc();
}

/** Parses the whole token as a signed integer. */
bool
ParseInteger(std::string_view token, long long & value)
{
  if (!token.empty() && token.front() == '+')
  {
    token.remove_prefix(1);
  }
  if (token.empty())
  {
    return false;
  }
  const char * end = token.data() + token.size();
  const auto   result = std::from_chars(token.data(), end, value);
  return result.ec == std::errc() && result.ptr == end;
}

/** "" when value is a usable coordinate, else what is wrong with it. */
std::string
CoordinateProblem(double value, bool outOfRange, bool asFloat)
{
  if (outOfRange || (std::isfinite(value) && asFloat && std::abs(value) > std::numeric_limits<float>::max()))
  {
    return asFloat ? "a coordinate beyond the range of float" : "a coordinate beyond the range of double";
  }
  if (!std::isfinite(value))
  {
    return "a non-finite coordinate";
  }
  return "";
}

/** Capacity to reserve for count items that need at least bytesPerItem bytes each. */
std::size_t
BoundedReserve(unsigned long long count, std::size_t remainingBytes, std::size_t bytesPerItem)
{
  return static_cast<std::size_t>(std::min<unsigned long long>(count, remainingBytes / bytesPerItem + 1));
}

void
AppendCell(StrictTextMeshIOInternals & mesh, CellGeometryEnum type, const IdentifierType * ids, std::size_t numberOfIds)
{
  mesh.Cells.push_back(static_cast<IdentifierType>(type));
  mesh.Cells.push_back(static_cast<IdentifierType>(numberOfIds));
  mesh.Cells.insert(mesh.Cells.end(), ids, ids + numberOfIds);
  ++mesh.NumberOfCells;
}

void
CheckTrailingNumbers(TextCursor & cursor, const std::string & what)
{
  std::string_view token;
  while (cursor.NextTokenOnLine(token, '#'))
  {
    double value = 0.0;
    bool   outOfRange = false;
    if (!ParseReal(token, value, outOfRange))
    {
      FailAtLine(cursor.Line(), "unexpected " + Quote(token) + " after " + what);
    }
  }
}
} // namespace StrictText
} // namespace detail
} // namespace itk
