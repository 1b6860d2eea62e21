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
#ifndef FFDProgramSupport_h
#define FFDProgramSupport_h

// Small helpers shared by the module's command-line programs (ffd-match, ffd-voxelize):
// wall-clock timing, number parsing, one-line error text and JSON string quoting.

#include <chrono>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <stdexcept>
#include <string>

namespace ffd
{
using ClockType = std::chrono::steady_clock;

/** Seconds elapsed since \c start. */
inline double
SecondsSince(ClockType::time_point start)
{
  return std::chrono::duration<double>(ClockType::now() - start).count();
}

/** The finite number spelled by the whole of \c text, the value of command-line option \c option; throws
 * \c TError (constructible from a message) otherwise. */
template <typename TError>
double
ParseNumber(const std::string & option, const std::string & text)
{
  std::size_t used = 0;
  double      value = 0.0;
  try
  {
    value = std::stod(text, &used);
  }
  catch (const std::exception &)
  {
    used = 0;
  }
  if (text.empty() || used != text.size() || !std::isfinite(value))
  {
    throw TError(option + " needs a finite number, not '" + text + "'");
  }
  return value;
}

/** The first line of \c text, without trailing blanks: ITK's exception descriptions span several lines. The
 * "ITK ERROR: ClassName(0x...): " prefix of ITK's messages (an object address means nothing to a user) is dropped. */
inline std::string
OneLine(const std::string & text)
{
  std::string       line = text.substr(0, text.find('\n'));
  const std::string itkPrefix = "ITK ERROR: ";
  if (line.compare(0, itkPrefix.size(), itkPrefix) == 0)
  {
    line.erase(0, itkPrefix.size());
    const std::size_t open = line.find("(0x");
    const std::size_t close = line.find("): ");
    if (open != std::string::npos && close != std::string::npos && open < close &&
        line.find(' ') > open) // "ClassName(0x...): " and not a sentence that happens to contain "(0x"
    {
      line.erase(0, close + 3);
    }
  }
  while (!line.empty() && (line.back() == '\r' || line.back() == ' '))
  {
    line.pop_back();
  }
  return line;
}

/** \c text as a quoted JSON string. */
inline std::string
JsonString(const std::string & text)
{
  std::ostringstream out;
  out << '"';
  for (const char c : text)
  {
    if (c == '"' || c == '\\')
    {
      out << '\\' << c;
    }
    else if (static_cast<unsigned char>(c) < 0x20)
    {
      char buffer[8];
      std::snprintf(buffer, sizeof(buffer), "\\u%04x", c);
      out << buffer;
    }
    else
    {
      out << c;
    }
  }
  out << '"';
  return out.str();
}
/** A number in JSON: 10 significant digits; non-finite values become null. */
inline std::string
JsonNumber(double value)
{
  if (!std::isfinite(value))
  {
    return "null";
  }
  std::ostringstream out;
  out.precision(10);
  out << value;
  return out.str();
}
} // namespace ffd

#endif // FFDProgramSupport_h
