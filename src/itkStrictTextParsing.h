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
#ifndef itkStrictTextParsing_h
#define itkStrictTextParsing_h

#include "itkCommonEnums.h"
#include "itkIntTypes.h"

#include <cstddef>
#include <cstring>
#include <string>
#include <string_view>
#include <vector>

namespace itk
{
namespace detail
{
/** The mesh read by a StrictTextMeshIO, kept between ReadMeshInformation() and the Read*() calls. */
struct StrictTextMeshIOInternals
{
  std::vector<double>         Points;    // x, y, z per point
  std::vector<IdentifierType> Cells;     // [cell type, number of points, ids...] per cell
  std::vector<double>         PointData; // one value per point, or empty
  SizeValueType               NumberOfCells{ 0 };
  bool                        FloatPoints{ true };
};

/** The strict parsers of StrictTextMeshIO (OFF, OBJ, legacy VTK) and the text cursor and number parsing they share.
 * Each parser fills a StrictTextMeshIOInternals or throws a ParseError naming the line and the problem. */
namespace StrictText
{
/** A problem found while parsing; the caller adds the file name. */
struct ParseError
{
  std::string Message;
};

/** Throws a ParseError with the message. */
[[noreturn]] void
Fail(const std::string & message);

/** Throws a ParseError with the message, prefixed by the line number. */
[[noreturn]] void
FailAtLine(std::size_t line, const std::string & message);

/** A token quoted for a message: non-printable bytes as \xNN, at most 24 characters. */
std::string
Quote(std::string_view token);

/** The text in upper case (C locale). */
std::string
Upper(std::string_view text);

/** Parses the whole token as a real number (C locale; "inf", "nan" give non-finite values).
 * Returns false when the token is not a number; sets outOfRange for a number beyond double. */
bool
ParseReal(std::string_view token, double & value, bool & outOfRange);

/** Parses the whole token as a signed integer. */
bool
ParseInteger(std::string_view token, long long & value);

/** "" when value is a usable coordinate, else what is wrong with it. */
std::string
CoordinateProblem(double value, bool outOfRange, bool asFloat);

/** Reads a text held in memory token by token, keeping the line number. */
class TextCursor
{
public:
  explicit TextCursor(const std::string & text)
    : m_Text(text)
  {}

  /** Line of the position (1-based). */
  std::size_t
  Line() const
  {
    return m_Line;
  }

  bool
  AtEnd() const
  {
    return m_Position >= m_Text.size();
  }

  /** The next token, skipping spaces, line ends and (when commentChar is not 0) comments that run
   * from commentChar to the end of the line. tokenLine receives its line. False at the end. */
  bool
  NextToken(std::string_view & token, std::size_t & tokenLine, char commentChar = 0)
  {
    for (;;)
    {
      this->SkipBlanks();
      if (AtEnd())
      {
        return false;
      }
      const char character = m_Text[m_Position];
      if (character == '\n')
      {
        ++m_Position;
        ++m_Line;
        continue;
      }
      if (commentChar != 0 && character == commentChar)
      {
        this->SkipRestOfLine();
        continue;
      }
      break;
    }
    tokenLine = m_Line;
    token = this->TakeToken(commentChar);
    return true;
  }

  /** The next token on the current line, or false at its end (the line end is not consumed). */
  bool
  NextTokenOnLine(std::string_view & token, char commentChar = 0)
  {
    this->SkipBlanks();
    if (AtEnd() || m_Text[m_Position] == '\n' || (commentChar != 0 && m_Text[m_Position] == commentChar))
    {
      return false;
    }
    token = this->TakeToken(commentChar);
    return true;
  }

  /** Moves to the start of the next line. */
  void
  SkipRestOfLine()
  {
    while (!AtEnd() && m_Text[m_Position] != '\n')
    {
      ++m_Position;
    }
    if (!AtEnd())
    {
      ++m_Position;
      ++m_Line;
    }
  }

  /** The rest of the current line (without its line end), and moves to the next line. */
  std::string_view
  TakeLine()
  {
    const std::size_t start = m_Position;
    while (!AtEnd() && m_Text[m_Position] != '\n')
    {
      ++m_Position;
    }
    std::string_view line(m_Text.data() + start, m_Position - start);
    if (!AtEnd())
    {
      ++m_Position;
      ++m_Line;
    }
    if (!line.empty() && line.back() == '\r')
    {
      line.remove_suffix(1);
    }
    return line;
  }

  /** Copies size raw bytes, or returns false when fewer remain. */
  bool
  ReadRaw(char * destination, std::size_t size)
  {
    if (m_Text.size() - m_Position < size)
    {
      return false;
    }
    std::memcpy(destination, m_Text.data() + m_Position, size);
    m_Position += size;
    return true;
  }

  std::size_t
  Remaining() const
  {
    return m_Text.size() - m_Position;
  }

private:
  void
  SkipBlanks()
  {
    while (!AtEnd())
    {
      const char character = m_Text[m_Position];
      if (character != ' ' && character != '\t' && character != '\r' && character != '\f' && character != '\v')
      {
        break;
      }
      ++m_Position;
    }
  }

  std::string_view
  TakeToken(char commentChar)
  {
    const std::size_t start = m_Position;
    while (!AtEnd())
    {
      const char character = m_Text[m_Position];
      if (character == ' ' || character == '\t' || character == '\r' || character == '\n' || character == '\f' ||
          character == '\v' || (commentChar != 0 && character == commentChar))
      {
        break;
      }
      ++m_Position;
    }
    return { m_Text.data() + start, m_Position - start };
  }

  const std::string & m_Text;
  std::size_t         m_Position{ 0 };
  std::size_t         m_Line{ 1 };
};

/** Capacity to reserve for count items that need at least bytesPerItem bytes each. */
std::size_t
BoundedReserve(unsigned long long count, std::size_t remainingBytes, std::size_t bytesPerItem);

/** Appends a cell of the type with its point ids to the mesh. */
void
AppendCell(StrictTextMeshIOInternals & mesh,
           CellGeometryEnum            type,
           const IdentifierType *      ids,
           std::size_t                 numberOfIds);

/** Checks that the rest of the line holds numbers only (colors after vertices and faces). */
void
CheckTrailingNumbers(TextCursor & cursor, const std::string & what);

/** Parses an OFF text (OFF, COFF, NOFF, STOFF... headers; polygons of any size). */
void
ParseOFF(const std::string & text, StrictTextMeshIOInternals & mesh);

/** Parses a Wavefront OBJ text (vertices and faces; other statements checked and ignored). */
void
ParseOBJ(const std::string & text, StrictTextMeshIOInternals & mesh);

/** Parses a legacy VTK text (ASCII or BINARY POLYDATA or UNSTRUCTURED_GRID). */
void
ParseLegacyVTK(const std::string & text, StrictTextMeshIOInternals & mesh);
} // namespace StrictText
} // namespace detail
} // namespace itk

#endif // itkStrictTextParsing_h
