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
// wall-clock timing, number parsing, one-line error text, JSON string quoting, and keeping the libraries' own
// output off stderr while they read.

#include <cctype>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>
#include <unistd.h>

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
 * \c TError (constructible from a message) otherwise. A number too small for a normal double (5e-324, 1e-400)
 * is accepted as the nearest double (a denormal or 0: each option's own range check judges it); a number too
 * large for a double (1e400) is refused as not finite. */
template <typename TError>
double
ParseNumber(const std::string & option, const std::string & text)
{
  const auto refuse = [&]() { return TError(option + " needs a finite number, not '" + text + "'"); };
  // std::strtod, unlike std::stod, gives the rounded value on underflow (ERANGE with a result of magnitude at
  // most the smallest normal double) and +-HUGE_VAL on overflow.
  if (text.empty() || std::isspace(static_cast<unsigned char>(text[0])))
  {
    throw refuse();
  }
  char * end = nullptr;
  errno = 0;
  const double value = std::strtod(text.c_str(), &end);
  const bool   overflow = errno == ERANGE && std::abs(value) > std::numeric_limits<double>::min();
  if (end != text.c_str() + text.size() || overflow || !std::isfinite(value))
  {
    throw refuse();
  }
  return value;
}

/** The first line of \c text, without trailing blanks: ITK's exception descriptions span several lines. The
 * "ITK ERROR: ClassName(0x...): " and "itk::ERROR: ClassName(0x...): " prefixes of ITK's messages (an object address
 * means nothing to a user) are dropped, also inside the line. A first line that ends in ':' ("Error reading x.nrrd:")
 * is followed by the last non-empty line, the innermost reason of a library's error chain, without its "[nrrd] " tag.
 */
inline std::string
OneLine(const std::string & text)
{
  std::string line = text.substr(0, text.find('\n'));
  // Wherever the prefixes stand: a library error that wraps another ("registration failed: ITK ERROR: ...") repeats
  // them inside the line.
  for (const std::string itkPrefix : { "ITK ERROR: ", "itk::ERROR: " })
  {
    for (std::size_t at = line.find(itkPrefix); at != std::string::npos; at = line.find(itkPrefix, at))
    {
      line.erase(at, itkPrefix.size());
      const std::size_t open = line.find("(0x", at);
      const std::size_t close = line.find("): ", at);
      if (open != std::string::npos && close != std::string::npos && open < close &&
          line.find(' ', at) > open) // "ClassName(0x...): " and not a sentence that happens to contain "(0x"
      {
        line.erase(at, close + 3 - at);
      }
    }
  }
  const auto trimmed = [](std::string value) {
    while (!value.empty() && (value.back() == '\r' || value.back() == ' ' || value.back() == '\t'))
    {
      value.pop_back();
    }
    return value;
  };
  line = trimmed(line);
  const std::size_t newline = text.find('\n');
  if (!line.empty() && line.back() == ':' && newline != std::string::npos)
  {
    std::istringstream rest(text.substr(newline + 1));
    std::string        reason;
    for (std::string next; std::getline(rest, next);)
    {
      next = trimmed(next);
      const std::size_t start = next.find_first_not_of(" \t");
      if (start != std::string::npos)
      {
        reason = next.substr(start);
      }
    }
    if (reason.size() > 2 && reason[0] == '[' && reason.find("] ") != std::string::npos)
    {
      reason.erase(0, reason.find("] ") + 2);
    }
    if (!reason.empty())
    {
      line += " " + reason;
    }
  }
  return line;
}

/** The length of the well-formed UTF-8 sequence (RFC 3629: no overlong forms, no surrogates, at most U+10FFFF)
 * that starts at \c text[at], or 0 when the bytes there are not one. */
inline std::size_t
Utf8SequenceLength(const std::string & text, std::size_t at)
{
  const auto          byte = [&](std::size_t i) { return static_cast<unsigned char>(text[i]); };
  const unsigned char lead = byte(at);
  std::size_t         length = 0;
  unsigned char       low = 0x80; // range of the second byte
  unsigned char       high = 0xBF;
  if (lead < 0x80)
  {
    return 1;
  }
  if (lead >= 0xC2 && lead <= 0xDF)
  {
    length = 2;
  }
  else if (lead >= 0xE0 && lead <= 0xEF)
  {
    length = 3;
    low = lead == 0xE0 ? 0xA0 : 0x80;
    high = lead == 0xED ? 0x9F : 0xBF;
  }
  else if (lead >= 0xF0 && lead <= 0xF4)
  {
    length = 4;
    low = lead == 0xF0 ? 0x90 : 0x80;
    high = lead == 0xF4 ? 0x8F : 0xBF;
  }
  else
  {
    return 0;
  }
  if (at + length > text.size() || byte(at + 1) < low || byte(at + 1) > high)
  {
    return 0;
  }
  for (std::size_t i = 2; i < length; ++i)
  {
    if (byte(at + i) < 0x80 || byte(at + i) > 0xBF)
    {
      return 0;
    }
  }
  return length;
}

/** \c text as a quoted JSON string (valid JSON for any bytes): quotes, backslashes and control characters are
 * escaped, well-formed UTF-8 is kept, and every byte that is not part of well-formed UTF-8 (a file name in
 * another encoding) becomes \\u00XX, its Latin-1 reading. */
inline std::string
JsonString(const std::string & text)
{
  std::ostringstream out;
  out << '"';
  for (std::size_t i = 0; i < text.size();)
  {
    const char        c = text[i];
    const std::size_t length = Utf8SequenceLength(text, i);
    if (c == '"' || c == '\\')
    {
      out << '\\' << c;
    }
    else if (length == 0 || static_cast<unsigned char>(c) < 0x20 || c == 0x7F)
    {
      char buffer[8];
      std::snprintf(buffer, sizeof(buffer), "\\u%04x", static_cast<unsigned int>(static_cast<unsigned char>(c)));
      out << buffer;
    }
    else
    {
      out << text.substr(i, length);
      i += length;
      continue;
    }
    ++i;
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

/** While an instance lives, whatever the process writes to stderr (file descriptor 2: std::cerr, C stdio, VTK's
 * logger, MetaIO's and NIfTI's messages) goes to a temporary file instead; Text() gives it. Wrap library reads in
 * one, so that a refusal is the program's one line, not the library's output before it. When no temporary file
 * can be made, stderr is left as it is. Not for use while other threads write to stderr. */
class LibraryOutputCapture
{
public:
  LibraryOutputCapture()
  {
    std::cerr.flush();
    std::fflush(stderr);
    m_File = std::tmpfile();
    m_Saved = m_File != nullptr ? ::dup(2) : -1;
    if (m_Saved >= 0 && ::dup2(fileno(m_File), 2) < 0)
    {
      ::close(m_Saved);
      m_Saved = -1;
    }
  }
  ~LibraryOutputCapture() { Restore(); }
  LibraryOutputCapture(const LibraryOutputCapture &) = delete;
  LibraryOutputCapture &
  operator=(const LibraryOutputCapture &) = delete;

  /** Gives stderr back (the destructor does it too) and returns what was written meanwhile. */
  std::string
  Restore()
  {
    if (m_Saved >= 0)
    {
      std::cerr.flush();
      std::fflush(stderr);
      ::dup2(m_Saved, 2);
      ::close(m_Saved);
      m_Saved = -1;
    }
    if (m_File != nullptr)
    {
      std::rewind(m_File);
      char        buffer[4096];
      std::size_t count = 0;
      while (m_Text.size() < 65536 && (count = std::fread(buffer, 1, sizeof(buffer), m_File)) > 0)
      {
        m_Text.append(buffer, count);
      }
      std::fclose(m_File);
      m_File = nullptr;
    }
    return m_Text;
  }

private:
  std::FILE * m_File{ nullptr };
  int         m_Saved{ -1 };
  std::string m_Text;
};
} // namespace ffd

#endif // FFDProgramSupport_h
