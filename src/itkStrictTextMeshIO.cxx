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
#include "itkStrictTextMeshIO.h"

#include "itkByteSwapper.h"
#include "itkMacro.h"
#include "itksys/SystemTools.hxx"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>
#include <set>
#include <sstream>
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
} // namespace detail

namespace
{
/** A problem found while parsing; the caller adds the file name. */
struct ParseError
{
  std::string Message;
};

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
BoundedReserve(unsigned long long count, std::size_t remainingBytes, std::size_t bytesPerItem)
{
  return static_cast<std::size_t>(std::min<unsigned long long>(count, remainingBytes / bytesPerItem + 1));
}

void
AppendCell(detail::StrictTextMeshIOInternals & mesh,
           CellGeometryEnum                    type,
           const IdentifierType *              ids,
           std::size_t                         numberOfIds)
{
  mesh.Cells.push_back(static_cast<IdentifierType>(type));
  mesh.Cells.push_back(static_cast<IdentifierType>(numberOfIds));
  mesh.Cells.insert(mesh.Cells.end(), ids, ids + numberOfIds);
  ++mesh.NumberOfCells;
}

/*---------------------------------------- OFF ----------------------------------------*/

/** Reads a count of the OFF header. */
unsigned long long
ReadOFFCount(TextCursor & cursor, const char * what, bool required)
{
  std::string_view token;
  std::size_t      line = cursor.Line();
  if (required ? !cursor.NextToken(token, line, '#') : !cursor.NextTokenOnLine(token, '#'))
  {
    if (!required)
    {
      return 0;
    }
    FailAtLine(line, std::string("the file ends before the number of ") + what);
  }
  long long value = 0;
  if (!ParseInteger(token, value) || value < 0)
  {
    FailAtLine(line, std::string("expected the number of ") + what + ", found " + Quote(token));
  }
  return static_cast<unsigned long long>(value);
}

/** Moves to the next line that holds a token (skipping blank and comment lines); false at the end. */
bool
NextDataLine(TextCursor & cursor, char commentChar)
{
  for (;;)
  {
    if (cursor.AtEnd())
    {
      return false;
    }
    std::string_view token;
    TextCursor       probe = cursor;
    if (probe.NextTokenOnLine(token, commentChar))
    {
      return true;
    }
    cursor.SkipRestOfLine();
  }
}

/** Checks that the rest of the line holds numbers only (colors after vertices and faces). */
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

void
ParseOFF(const std::string & text, detail::StrictTextMeshIOInternals & mesh)
{
  TextCursor       cursor(text);
  std::string_view token;
  std::size_t      line = 1;
  if (!cursor.NextToken(token, line, '#'))
  {
    Fail(text.empty() ? "the file is empty" : "the file holds no OFF header");
  }
  if (token != "OFF")
  {
    const std::string upper = Upper(token);
    if (upper.size() > 3 && upper.compare(upper.size() - 3, 3, "OFF") == 0 && token.size() <= 8)
    {
      FailAtLine(line,
                 "the OFF variant " + Quote(token) + " is not supported (plain \"OFF\" only: no per-vertex colors, " +
                   "normals, texture coordinates or other dimensions)");
    }
    FailAtLine(line, "expected the keyword \"OFF\", found " + Quote(token));
  }
  {
    TextCursor probe = cursor;
    if (probe.NextTokenOnLine(token, '#') && Upper(token) == "BINARY")
    {
      FailAtLine(line, "binary OFF files are not supported (ASCII OFF only)");
    }
  }
  const unsigned long long numberOfVertices = ReadOFFCount(cursor, "vertices", true);
  const unsigned long long numberOfFaces = ReadOFFCount(cursor, "faces", true);
  ReadOFFCount(cursor, "edges", false);
  CheckTrailingNumbers(cursor, "the numbers of vertices, faces and edges");
  cursor.SkipRestOfLine();

  mesh.FloatPoints = false; // read as double: a float would move a vertex 1e7 mm from the origin by up to 0.5 mm
  mesh.Points.reserve(3 * BoundedReserve(numberOfVertices, cursor.Remaining(), 6));
  for (unsigned long long vertex = 0; vertex < numberOfVertices; ++vertex)
  {
    if (!NextDataLine(cursor, '#'))
    {
      Fail("the file ends after " + std::to_string(vertex) + " of " + std::to_string(numberOfVertices) + " vertices");
    }
    line = cursor.Line();
    for (unsigned int k = 0; k < 3; ++k)
    {
      if (!cursor.NextTokenOnLine(token, '#'))
      {
        FailAtLine(line,
                   "expected 3 coordinates of vertex " + std::to_string(vertex) + ", found " + std::to_string(k) +
                     (cursor.AtEnd() ? " before the end of the file" : ""));
      }
      double value = 0.0;
      bool   outOfRange = false;
      if (!ParseReal(token, value, outOfRange))
      {
        FailAtLine(line, "expected 3 coordinates of vertex " + std::to_string(vertex) + ", found " + Quote(token));
      }
      const std::string problem = CoordinateProblem(value, outOfRange, false);
      if (!problem.empty())
      {
        FailAtLine(line, "vertex " + std::to_string(vertex) + " has " + problem + " (" + Quote(token) + ")");
      }
      mesh.Points.push_back(value);
    }
    CheckTrailingNumbers(cursor, "the coordinates of vertex " + std::to_string(vertex));
    cursor.SkipRestOfLine();
  }

  bool                        allTriangles = true;
  std::vector<IdentifierType> ids;
  std::vector<std::size_t>    faceStarts;
  faceStarts.reserve(BoundedReserve(numberOfFaces, cursor.Remaining(), 8));
  mesh.Cells.reserve(5 * faceStarts.capacity());
  for (unsigned long long face = 0; face < numberOfFaces; ++face)
  {
    if (!NextDataLine(cursor, '#'))
    {
      Fail("the file ends after " + std::to_string(face) + " of " + std::to_string(numberOfFaces) + " faces");
    }
    line = cursor.Line();
    const std::string name = "face " + std::to_string(face);
    cursor.NextTokenOnLine(token, '#');
    long long count = 0;
    if (!ParseInteger(token, count))
    {
      FailAtLine(line, "expected the number of vertices of " + name + ", found " + Quote(token));
    }
    if (count < 3)
    {
      FailAtLine(line, name + " has " + std::to_string(count) + " vertices, a face needs at least 3");
    }
    ids.clear();
    for (long long j = 0; j < count; ++j)
    {
      if (!cursor.NextTokenOnLine(token, '#'))
      {
        FailAtLine(line,
                   (cursor.AtEnd() ? "the file ends within " : "the line ends within ") + name + " (" +
                     std::to_string(j) + " of its " + std::to_string(count) + " vertex indices)");
      }
      long long index = 0;
      if (!ParseInteger(token, index))
      {
        FailAtLine(line, "expected vertex index " + std::to_string(j) + " of " + name + ", found " + Quote(token));
      }
      if (index < 0 || static_cast<unsigned long long>(index) >= numberOfVertices)
      {
        FailAtLine(line,
                   name + " refers to vertex " + std::to_string(index) + ", the file has " +
                     std::to_string(numberOfVertices));
      }
      ids.push_back(static_cast<IdentifierType>(index));
    }
    CheckTrailingNumbers(cursor, "the vertex indices of " + name);
    cursor.SkipRestOfLine();
    allTriangles = allTriangles && count == 3;
    AppendCell(mesh, CellGeometryEnum::POLYGON_CELL, ids.data(), ids.size());
  }
  if (NextDataLine(cursor, '#'))
  {
    FailAtLine(cursor.Line(),
               "unexpected data after the " + std::to_string(numberOfFaces) +
                 " faces the header announces (wrong face count?)");
  }
  if (allTriangles)
  {
    // As OFFMeshIO: all-triangle files give triangle cells.
    for (std::size_t index = 0; index < mesh.Cells.size(); index += 5)
    {
      mesh.Cells[index] = static_cast<IdentifierType>(CellGeometryEnum::TRIANGLE_CELL);
    }
  }
}

/*---------------------------------------- OBJ ----------------------------------------*/

bool
IsKnownOBJStatement(std::string_view keyword)
{
  static const std::set<std::string_view> known = {
    "vt",         "vn",    "vp",    "l",      "p",      "g",     "o",     "s",        "usemtl",   "mtllib",
    "cstype",     "deg",   "bmat",  "step",   "curv",   "curv2", "surf",  "parm",     "trim",     "hole",
    "scrv",       "sp",    "end",   "con",    "mg",     "lod",   "bevel", "c_interp", "d_interp", "trace_obj",
    "shadow_obj", "ctech", "stech", "maplib", "usemap", "call",  "csh"
  };
  return known.count(keyword) > 0;
}

void
ParseOBJ(const std::string & text, detail::StrictTextMeshIOInternals & mesh)
{
  TextCursor  cursor(text);
  std::size_t numberOfVertices = 0;
  struct PendingIndex
  {
    long long     Index; // 1-based index as written
    std::size_t   Line;
    SizeValueType Face;
  };
  std::vector<PendingIndex>   pending; // positive indices, checked once all vertices are known
  std::vector<IdentifierType> ids;
  mesh.FloatPoints = false; // read as double: a float would move a vertex 1e7 mm from the origin by up to 0.5 mm
  while (!cursor.AtEnd())
  {
    const std::size_t line = cursor.Line();
    std::string_view  keyword;
    if (!cursor.NextTokenOnLine(keyword, '#'))
    {
      cursor.SkipRestOfLine();
      continue;
    }
    if (keyword == "v")
    {
      ++numberOfVertices;
      const std::string name = "vertex " + std::to_string(numberOfVertices);
      std::string_view  token;
      for (unsigned int k = 0; k < 3; ++k)
      {
        if (!cursor.NextTokenOnLine(token, '#'))
        {
          FailAtLine(line, "expected 3 coordinates of " + name + ", found " + std::to_string(k));
        }
        double value = 0.0;
        bool   outOfRange = false;
        if (!ParseReal(token, value, outOfRange))
        {
          FailAtLine(line, "expected 3 coordinates of " + name + ", found " + Quote(token));
        }
        const std::string problem = CoordinateProblem(value, outOfRange, false);
        if (!problem.empty())
        {
          FailAtLine(line, name + " has " + problem + " (" + Quote(token) + ")");
        }
        mesh.Points.push_back(value);
      }
      CheckTrailingNumbers(cursor, "the coordinates of " + name);
    }
    else if (keyword == "f")
    {
      const SizeValueType face = mesh.NumberOfCells + 1;
      const std::string   name = "face " + std::to_string(face);
      std::string_view    token;
      ids.clear();
      while (cursor.NextTokenOnLine(token, '#'))
      {
        // "i", "i/t", "i//n" or "i/t/n": the vertex index comes first, the others must be integers.
        const std::size_t slash = token.find('/');
        const auto        vertexPart = token.substr(0, slash);
        long long         index = 0;
        bool              wellFormed = ParseInteger(vertexPart, index);
        if (wellFormed && slash != std::string_view::npos)
        {
          std::string_view  rest = token.substr(slash + 1);
          const std::size_t second = rest.find('/');
          const auto        texturePart = rest.substr(0, second);
          long long         other = 0;
          wellFormed = (texturePart.empty() && second != std::string_view::npos) || ParseInteger(texturePart, other);
          if (wellFormed && second != std::string_view::npos)
          {
            wellFormed = ParseInteger(rest.substr(second + 1), other);
          }
        }
        if (!wellFormed)
        {
          FailAtLine(line, "expected a vertex reference of " + name + ", found " + Quote(token));
        }
        if (index == 0)
        {
          FailAtLine(line, name + " refers to vertex 0; OBJ files count vertices from 1");
        }
        if (index < 0)
        {
          const long long resolved = static_cast<long long>(numberOfVertices) + index; // 0-based
          if (resolved < 0)
          {
            FailAtLine(line,
                       name + " refers to vertex " + std::to_string(index) + ", only " +
                         std::to_string(numberOfVertices) + " vertices precede it");
          }
          ids.push_back(static_cast<IdentifierType>(resolved));
        }
        else
        {
          pending.push_back({ index, line, face });
          ids.push_back(static_cast<IdentifierType>(index - 1));
        }
      }
      if (ids.size() < 3)
      {
        FailAtLine(line, name + " has " + std::to_string(ids.size()) + " vertices, a face needs at least 3");
      }
      AppendCell(mesh, CellGeometryEnum::POLYGON_CELL, ids.data(), ids.size());
    }
    else if (!IsKnownOBJStatement(keyword))
    {
      FailAtLine(line, "unknown OBJ statement " + Quote(keyword));
    }
    cursor.SkipRestOfLine();
  }
  if (numberOfVertices == 0)
  {
    Fail("the file holds no vertices (no \"v\" line)");
  }
  for (const PendingIndex & reference : pending)
  {
    if (static_cast<unsigned long long>(reference.Index) > numberOfVertices)
    {
      FailAtLine(reference.Line,
                 "face " + std::to_string(reference.Face) + " refers to vertex " + std::to_string(reference.Index) +
                   ", the file has " + std::to_string(numberOfVertices));
    }
  }
}

/*------------------------------------- legacy VTK -------------------------------------*/

/** A VTK data type: its size in bytes in binary files, and how to decode it. */
struct VTKType
{
  std::string  Name;
  unsigned int Size{ 0 };
  bool         IsFloat{ false };
  bool         IsSigned{ false };
};

bool
LookUpVTKType(std::string_view name, VTKType & type)
{
  const std::string lower = [&name] {
    std::string result(name);
    std::transform(
      result.begin(), result.end(), result.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return result;
  }();
  struct Entry
  {
    const char * Name;
    unsigned int Size;
    bool         IsFloat;
    bool         IsSigned;
  };
  static const Entry entries[] = { { "bit", 0, false, false },
                                   { "unsigned_char", 1, false, false },
                                   { "char", 1, false, true },
                                   { "signed_char", 1, false, true },
                                   { "unsigned_short", 2, false, false },
                                   { "short", 2, false, true },
                                   { "unsigned_int", 4, false, false },
                                   { "int", 4, false, true },
                                   { "unsigned_long", 8, false, false },
                                   { "long", 8, false, true },
                                   { "vtkidtype", 4, false, true },
                                   { "vtktypeint8", 1, false, true },
                                   { "vtktypeuint8", 1, false, false },
                                   { "vtktypeint16", 2, false, true },
                                   { "vtktypeuint16", 2, false, false },
                                   { "vtktypeint32", 4, false, true },
                                   { "vtktypeuint32", 4, false, false },
                                   { "vtktypeint64", 8, false, true },
                                   { "vtktypeuint64", 8, false, false },
                                   { "float", 4, true, true },
                                   { "double", 8, true, true },
                                   { "vtktypefloat32", 4, true, true },
                                   { "vtktypefloat64", 8, true, true } };
  for (const Entry & entry : entries)
  {
    if (lower == entry.Name && entry.Size > 0)
    {
      type = { lower, entry.Size, entry.IsFloat, entry.IsSigned };
      return true;
    }
  }
  return false;
}

/** Decodes one big-endian binary value. */
double
DecodeBigEndian(const char * data, const VTKType & type)
{
  unsigned char bytes[8];
  std::memcpy(bytes, data, type.Size);
  if (!ByteSwapper<int>::SystemIsBigEndian())
  {
    std::reverse(bytes, bytes + type.Size);
  }
  auto as = [&bytes](auto value) {
    std::memcpy(&value, bytes, sizeof(value));
    return static_cast<double>(value);
  };
  if (type.IsFloat)
  {
    return type.Size == 4 ? as(float{}) : as(double{});
  }
  switch (type.Size)
  {
    case 1:
      return type.IsSigned ? as(int8_t{}) : as(uint8_t{});
    case 2:
      return type.IsSigned ? as(int16_t{}) : as(uint16_t{});
    case 4:
      return type.IsSigned ? as(int32_t{}) : as(uint32_t{});
    default:
      return type.IsSigned ? as(int64_t{}) : as(uint64_t{});
  }
}

class LegacyVTKParser
{
public:
  LegacyVTKParser(const std::string & text, detail::StrictTextMeshIOInternals & mesh)
    : m_Cursor(text)
    , m_Mesh(mesh)
  {}

  void
  Parse()
  {
    this->ParseHeader();
    std::string_view token;
    std::size_t      line = 0;
    if (!this->Next(token, line))
    {
      Fail("the file ends before its DATASET line");
    }
    while (Upper(token) == "FIELD")
    {
      this->SkipField(line);
      if (!this->Next(token, line))
      {
        Fail("the file ends before its DATASET line");
      }
    }
    if (Upper(token) != "DATASET")
    {
      FailAtLine(line, "expected \"DATASET POLYDATA\", found " + Quote(token));
    }
    if (!this->Next(token, line))
    {
      Fail("the file ends after \"DATASET\"");
    }
    if (Upper(token) != "POLYDATA")
    {
      FailAtLine(line,
                 "DATASET " + Quote(token) +
                   " is not supported (POLYDATA only; other datasets are read by ITK's or VTK's own readers)");
    }
    this->ParseSections();
    if (!m_HasPoints)
    {
      Fail("the file has no POINTS section");
    }
  }

private:
  bool
  Next(std::string_view & token, std::size_t & line)
  {
    return m_Cursor.NextToken(token, line);
  }

  void
  ParseHeader()
  {
    if (m_Cursor.AtEnd())
    {
      Fail("the file is empty");
    }
    const std::string_view     first = m_Cursor.TakeLine();
    constexpr std::string_view signature = "# vtk DataFile Version";
    if (first.substr(0, signature.size()) != signature)
    {
      FailAtLine(1, "not a legacy VTK file: expected \"# vtk DataFile Version\", found " + Quote(first));
    }
    std::string_view versionText = first.substr(signature.size());
    while (!versionText.empty() && versionText.front() == ' ')
    {
      versionText.remove_prefix(1);
    }
    double     version = 0.0;
    const auto result = std::from_chars(versionText.data(), versionText.data() + versionText.size(), version);
    if (result.ec != std::errc() || !std::isfinite(version))
    {
      FailAtLine(1, "the file version " + Quote(versionText) + " is not a number");
    }
    if (m_Cursor.AtEnd())
    {
      Fail("the file ends after its first line (a title line and ASCII or BINARY must follow)");
    }
    m_Cursor.TakeLine(); // title
    std::string_view token;
    std::size_t      line = 0;
    if (!m_Cursor.NextToken(token, line))
    {
      Fail("the file ends before ASCII or BINARY");
    }
    const std::string fileType = Upper(token);
    if (line != 3 || (fileType != "ASCII" && fileType != "BINARY"))
    {
      FailAtLine(line, "expected ASCII or BINARY on line 3, found " + Quote(token));
    }
    m_Binary = fileType == "BINARY";
  }

  void
  ParseSections()
  {
    std::string_view token;
    std::size_t      line = 0;
    while (this->Next(token, line))
    {
      const std::string keyword = Upper(token);
      if (keyword == "POINTS")
      {
        this->ParsePoints(line);
      }
      else if (keyword == "VERTICES" || keyword == "LINES" || keyword == "POLYGONS" || keyword == "TRIANGLE_STRIPS")
      {
        this->ParseCells(keyword, line);
      }
      else if (keyword == "POINT_DATA" || keyword == "CELL_DATA")
      {
        if (this->ParseAttributes(keyword, line))
        {
          return; // METADATA: the rest is not read
        }
      }
      else if (keyword == "FIELD")
      {
        this->SkipField(line);
      }
      else if (keyword == "METADATA")
      {
        return;
      }
      else
      {
        FailAtLine(line, "unexpected " + Quote(token) + " where a POLYDATA section keyword is expected");
      }
    }
  }

  unsigned long long
  ReadCount(const std::string & what, std::size_t keywordLine)
  {
    std::string_view token;
    std::size_t      line = 0;
    if (!this->Next(token, line))
    {
      FailAtLine(keywordLine, "the file ends before " + what);
    }
    long long value = 0;
    if (!ParseInteger(token, value) || value < 0)
    {
      FailAtLine(line, "expected " + what + ", found " + Quote(token));
    }
    return static_cast<unsigned long long>(value);
  }

  VTKType
  ReadType(const std::string & what, std::size_t keywordLine)
  {
    std::string_view token;
    std::size_t      line = 0;
    if (!this->Next(token, line))
    {
      FailAtLine(keywordLine, "the file ends before the data type of " + what);
    }
    VTKType type;
    if (!LookUpVTKType(token, type))
    {
      FailAtLine(line, "unknown or unsupported data type " + Quote(token) + " of " + what);
    }
    return type;
  }

  /** In a binary file, the data starts on the line after its header line. */
  void
  StartBinaryData(std::size_t headerLine, const std::string & what)
  {
    std::string_view token;
    if (m_Cursor.NextTokenOnLine(token))
    {
      FailAtLine(headerLine, "unexpected " + Quote(token) + " at the end of the header of " + what);
    }
    if (m_Cursor.AtEnd())
    {
      Fail("the file ends before the binary data of " + what);
    }
    m_Cursor.SkipRestOfLine();
  }

  /** Reads count values of type; calls store(i, value, line) for each. ASCII values must be
   * numbers; describe(i) names value i for messages. */
  template <typename TStore, typename TDescribe>
  void
  ReadValues(unsigned long long  count,
             const VTKType &     type,
             std::size_t         headerLine,
             const std::string & what,
             TStore &&           store,
             TDescribe &&        describe)
  {
    if (count == 0)
    {
      return;
    }
    if (m_Binary)
    {
      this->StartBinaryData(headerLine, what);
      if (count > m_Cursor.Remaining() / type.Size)
      {
        Fail("the file ends within the binary data of " + what + " (" + std::to_string(count) + " values of " +
             std::to_string(type.Size) + " bytes announced, " + std::to_string(m_Cursor.Remaining()) + " bytes left)");
      }
      char bytes[8];
      for (unsigned long long i = 0; i < count; ++i)
      {
        m_Cursor.ReadRaw(bytes, type.Size);
        store(i, DecodeBigEndian(bytes, type), false, std::size_t{ 0 });
      }
      return;
    }
    std::string_view token;
    std::size_t      line = headerLine;
    for (unsigned long long i = 0; i < count; ++i)
    {
      if (!this->Next(token, line))
      {
        FailAtLine(line, "the file ends " + describe(i));
      }
      double value = 0.0;
      bool   outOfRange = false;
      if (!ParseReal(token, value, outOfRange))
      {
        FailAtLine(line, "expected a number " + describe(i) + ", found " + Quote(token));
      }
      store(i, value, outOfRange, line);
    }
  }

  void
  ParsePoints(std::size_t keywordLine)
  {
    if (m_HasPoints)
    {
      FailAtLine(keywordLine, "a second POINTS section");
    }
    const unsigned long long numberOfPoints = this->ReadCount("the number of points", keywordLine);
    const VTKType            type = this->ReadType("POINTS", keywordLine);
    if (numberOfPoints > m_Cursor.Remaining())
    {
      FailAtLine(keywordLine,
                 "POINTS announces " + std::to_string(numberOfPoints) + " points, more than the " +
                   std::to_string(m_Cursor.Remaining()) + " bytes left in the file can hold");
    }
    // Declared floats must fit a float; ASCII values keep every digit written (read as double), binary ones are
    // float data.
    const bool asFloat = type.Name != "double" && type.Name != "vtktypefloat64";
    m_Mesh.FloatPoints = m_Binary && asFloat;
    m_Mesh.Points.reserve(3 * BoundedReserve(numberOfPoints, m_Cursor.Remaining(), m_Binary ? 12 : 6));
    m_Mesh.Points.clear();
    this->ReadValues(
      3 * numberOfPoints,
      type,
      keywordLine,
      "POINTS",
      [this, asFloat](unsigned long long i, double value, bool outOfRange, std::size_t line) {
        const std::string problem = CoordinateProblem(value, outOfRange, asFloat);
        if (!problem.empty())
        {
          const std::string message = "point " + std::to_string(i / 3) + " has " + problem;
          if (m_Binary)
          {
            Fail(message);
          }
          FailAtLine(line, message);
        }
        m_Mesh.Points.push_back(value);
      },
      [numberOfPoints](unsigned long long i) {
        return "after " + std::to_string(i / 3) + " of " + std::to_string(numberOfPoints) + " points" +
               (i % 3 != 0 ? " (within point " + std::to_string(i / 3) + ")" : std::string());
      });
    m_HasPoints = true;
  }

  /** Reads count integer values of a cell section (connectivity or offsets). */
  std::vector<long long>
  ReadIntegers(unsigned long long         count,
               const VTKType &            type,
               std::size_t                headerLine,
               const std::string &        what,
               std::vector<std::size_t> & lines)
  {
    std::vector<long long> values;
    values.reserve(BoundedReserve(count, m_Cursor.Remaining(), m_Binary ? type.Size : 2));
    lines.clear();
    this->ReadValues(
      count,
      type,
      headerLine,
      what,
      [&values, &lines, &what](unsigned long long i, double value, bool, std::size_t line) {
        if (!(value == std::floor(value)) || std::abs(value) > 9.0e15)
        {
          const std::string message = "value " + std::to_string(i) + " of " + what + " is not an integer";
          if (line == 0)
          {
            Fail(message);
          }
          FailAtLine(line, message);
        }
        values.push_back(static_cast<long long>(value));
        lines.push_back(line);
      },
      [count, &what](unsigned long long i) {
        return "after " + std::to_string(i) + " of the " + std::to_string(count) + " values of " + what;
      });
    return values;
  }

  [[noreturn]] void
  FailAt(const std::vector<std::size_t> & lines, std::size_t index, const std::string & message)
  {
    if (index < lines.size() && lines[index] != 0)
    {
      FailAtLine(lines[index], message);
    }
    Fail(message);
  }

  void
  ParseCells(const std::string & keyword, std::size_t keywordLine)
  {
    if (!m_HasPoints)
    {
      FailAtLine(keywordLine, keyword + " before POINTS");
    }
    const unsigned long long first = this->ReadCount("the number of " + keyword + " cells", keywordLine);
    const unsigned long long second = this->ReadCount("the size of " + keyword, keywordLine);

    // Cells as (start, count) into ids, with the line of each id for messages.
    std::vector<long long>                           ids;
    std::vector<std::size_t>                         idLines;
    std::vector<std::pair<std::size_t, std::size_t>> cells;

    TextCursor       probe = m_Cursor;
    std::string_view token;
    std::size_t      line = 0;
    if (probe.NextToken(token, line) && Upper(token) == "OFFSETS")
    {
      // Version 5 layout: "OFFSETS type" (first values), "CONNECTIVITY type" (second values).
      this->Next(token, line);
      const VTKType                offsetType = this->ReadType(keyword + " OFFSETS", line);
      std::vector<std::size_t>     offsetLines;
      const std::vector<long long> offsets =
        this->ReadIntegers(first, offsetType, line, keyword + " OFFSETS", offsetLines);
      if (!this->Next(token, line) || Upper(token) != "CONNECTIVITY")
      {
        FailAtLine(line, "expected CONNECTIVITY after the OFFSETS of " + keyword);
      }
      const VTKType connectivityType = this->ReadType(keyword + " CONNECTIVITY", line);
      ids = this->ReadIntegers(second, connectivityType, line, keyword + " CONNECTIVITY", idLines);
      if (first == 0 ? second != 0 : (offsets.front() != 0 || offsets.back() != static_cast<long long>(second)))
      {
        FailAt(offsetLines, 0, "the OFFSETS of " + keyword + " do not run from 0 to " + std::to_string(second));
      }
      for (std::size_t i = 0; i + 1 < offsets.size(); ++i)
      {
        if (offsets[i + 1] < offsets[i])
        {
          FailAt(offsetLines, i + 1, "the OFFSETS of " + keyword + " decrease at cell " + std::to_string(i));
        }
        cells.emplace_back(static_cast<std::size_t>(offsets[i]), static_cast<std::size_t>(offsets[i + 1] - offsets[i]));
      }
    }
    else
    {
      // Classic layout: per cell its number of points, then the point ids; second values in all.
      const std::vector<long long> values =
        this->ReadIntegers(second, VTKType{ "int", 4, false, true }, keywordLine, keyword, idLines);
      std::size_t position = 0;
      for (unsigned long long cell = 0; cell < first; ++cell)
      {
        if (position >= values.size())
        {
          FailAtLine(keywordLine,
                     keyword + " announces " + std::to_string(first) + " cells in " + std::to_string(second) +
                       " values, the values end after " + std::to_string(cell) + " cells");
        }
        const long long count = values[position];
        if (count < 0 || static_cast<unsigned long long>(count) >= values.size() - position)
        {
          FailAt(idLines,
                 position,
                 keyword + " cell " + std::to_string(cell) + " has " + std::to_string(count) +
                   " points, more than the values left in the " + std::to_string(second) + " announced");
        }
        cells.emplace_back(position + 1, static_cast<std::size_t>(count));
        position += 1 + static_cast<std::size_t>(count);
      }
      if (position != values.size())
      {
        FailAtLine(keywordLine,
                   keyword + " announces " + std::to_string(second) + " values, its " + std::to_string(first) +
                     " cells use " + std::to_string(position));
      }
      ids = values;
    }

    const std::size_t           numberOfPoints = m_Mesh.Points.size() / 3;
    std::vector<IdentifierType> cellIds;
    for (std::size_t cell = 0; cell < cells.size(); ++cell)
    {
      const auto [start, count] = cells[cell];
      cellIds.clear();
      for (std::size_t j = start; j < start + count; ++j)
      {
        if (ids[j] < 0 || static_cast<unsigned long long>(ids[j]) >= numberOfPoints)
        {
          FailAt(idLines,
                 j,
                 keyword + " cell " + std::to_string(cell) + " refers to point " + std::to_string(ids[j]) +
                   ", the file has " + std::to_string(numberOfPoints) + " points");
        }
        cellIds.push_back(static_cast<IdentifierType>(ids[j]));
      }
      const std::size_t minimum = keyword == "VERTICES" ? 1 : keyword == "LINES" ? 2 : 3;
      if (count < minimum)
      {
        FailAt(idLines,
               start == 0 ? 0 : start - 1,
               keyword + " cell " + std::to_string(cell) + " has " + std::to_string(count) + " points, at least " +
                 std::to_string(minimum) + " needed");
      }
      this->AddCells(keyword, cellIds);
      ++m_NumberOfFileCells;
    }
  }

  void
  AddCells(const std::string & keyword, const std::vector<IdentifierType> & ids)
  {
    if (keyword == "VERTICES")
    {
      for (const IdentifierType id : ids)
      {
        AppendCell(m_Mesh, CellGeometryEnum::VERTEX_CELL, &id, 1);
      }
    }
    else if (keyword == "LINES")
    {
      AppendCell(m_Mesh, CellGeometryEnum::LINE_CELL, ids.data(), ids.size());
    }
    else if (keyword == "POLYGONS")
    {
      AppendCell(m_Mesh, CellGeometryEnum::POLYGON_CELL, ids.data(), ids.size());
    }
    else
    {
      // Triangle k of a strip is (k, k+1, k+2), with every other one flipped to keep the orientation.
      for (std::size_t k = 0; k + 2 < ids.size(); ++k)
      {
        IdentifierType triangle[3] = { ids[k], ids[k + 1], ids[k + 2] };
        if (k % 2 == 1)
        {
          std::swap(triangle[0], triangle[1]);
        }
        AppendCell(m_Mesh, CellGeometryEnum::TRIANGLE_CELL, triangle, 3);
      }
    }
  }

  /** Skips ignored values after checking they are there (and are numbers in ASCII files). */
  void
  SkipValues(unsigned long long count, const VTKType & type, std::size_t headerLine, const std::string & what)
  {
    this->ReadValues(
      count,
      type,
      headerLine,
      what,
      [](unsigned long long, double, bool, std::size_t) {},
      [count, &what](unsigned long long i) {
        return "after " + std::to_string(i) + " of the " + std::to_string(count) + " values of " + what;
      });
  }

  /** Reads a "POINT_DATA n" or "CELL_DATA n" block; returns true when a METADATA block ends it. */
  bool
  ParseAttributes(const std::string & keyword, std::size_t keywordLine)
  {
    const bool               isPointData = keyword == "POINT_DATA";
    const unsigned long long count = this->ReadCount("the number of " + keyword + " tuples", keywordLine);
    const unsigned long long expected = isPointData ? m_Mesh.Points.size() / 3 : m_NumberOfFileCells;
    if (count != expected)
    {
      FailAtLine(keywordLine,
                 keyword + " announces " + std::to_string(count) + " tuples, the file has " + std::to_string(expected) +
                   (isPointData ? " points" : " cells"));
    }
    std::string_view token;
    std::size_t      line = 0;
    for (;;)
    {
      TextCursor probe = m_Cursor;
      if (!probe.NextToken(token, line))
      {
        return false;
      }
      const std::string attribute = Upper(token);
      if (attribute == "POINT_DATA" || attribute == "CELL_DATA" || attribute == "POINTS" || attribute == "POLYGONS" ||
          attribute == "VERTICES" || attribute == "LINES" || attribute == "TRIANGLE_STRIPS")
      {
        return false;
      }
      this->Next(token, line);
      const std::size_t attributeLine = line;
      if (attribute == "METADATA")
      {
        return true;
      }
      if (attribute == "FIELD")
      {
        this->SkipField(attributeLine);
        continue;
      }
      std::string_view name;
      if (!this->Next(name, line))
      {
        FailAtLine(attributeLine, "the file ends after " + attribute);
      }
      const std::string what = keyword + " " + attribute + " " + std::string(name);
      if (attribute == "SCALARS")
      {
        const VTKType    type = this->ReadType(what, attributeLine);
        unsigned int     components = 1;
        std::string_view optional;
        if (m_Cursor.NextTokenOnLine(optional))
        {
          long long value = 0;
          if (!ParseInteger(optional, value) || value < 1 || value > 4)
          {
            FailAtLine(attributeLine, "expected 1 to 4 components of " + what + ", found " + Quote(optional));
          }
          components = static_cast<unsigned int>(value);
        }
        // An optional "LOOKUP_TABLE name" line precedes the values.
        TextCursor lookUp = m_Cursor;
        if (lookUp.NextToken(token, line) && Upper(token) == "LOOKUP_TABLE")
        {
          this->Next(token, line);
          if (!this->Next(token, line))
          {
            FailAtLine(line, "the file ends after LOOKUP_TABLE of " + what);
          }
        }
        const std::size_t valuesLine = line == 0 ? attributeLine : line;
        const bool        keep = isPointData && components == 1 && m_Mesh.PointData.empty();
        if (keep)
        {
          m_Mesh.PointData.reserve(BoundedReserve(count, m_Cursor.Remaining(), 2));
          this->ReadValues(
            count,
            type,
            valuesLine,
            what,
            [this](unsigned long long, double value, bool, std::size_t) { m_Mesh.PointData.push_back(value); },
            [count, &what](unsigned long long i) {
              return "after " + std::to_string(i) + " of the " + std::to_string(count) + " values of " + what;
            });
        }
        else
        {
          this->SkipValues(count * components, type, valuesLine, what);
        }
      }
      else if (attribute == "VECTORS" || attribute == "NORMALS" || attribute == "TENSORS")
      {
        const VTKType type = this->ReadType(what, attributeLine);
        this->SkipValues(count * (attribute == "TENSORS" ? 9 : 3), type, attributeLine, what);
      }
      else if (attribute == "TEXTURE_COORDINATES")
      {
        const unsigned long long dimension = this->ReadCount("the dimension of " + what, attributeLine);
        if (dimension < 1 || dimension > 3)
        {
          FailAtLine(attributeLine, "the dimension of " + what + " must be 1, 2 or 3");
        }
        const VTKType type = this->ReadType(what, attributeLine);
        this->SkipValues(count * dimension, type, attributeLine, what);
      }
      else if (attribute == "COLOR_SCALARS")
      {
        const unsigned long long components = this->ReadCount("the number of components of " + what, attributeLine);
        if (components < 1 || components > 4)
        {
          FailAtLine(attributeLine, "the number of components of " + what + " must be 1 to 4");
        }
        const VTKType type = m_Binary ? VTKType{ "unsigned_char", 1, false, false } : VTKType{ "float", 4, true, true };
        this->SkipValues(count * components, type, attributeLine, what);
      }
      else if (attribute == "LOOKUP_TABLE")
      {
        const unsigned long long size = this->ReadCount("the size of " + what, attributeLine);
        if (size > m_Cursor.Remaining())
        {
          FailAtLine(attributeLine, "the size of " + what + " exceeds the bytes left in the file");
        }
        const VTKType type = m_Binary ? VTKType{ "unsigned_char", 1, false, false } : VTKType{ "float", 4, true, true };
        this->SkipValues(4 * size, type, attributeLine, what);
      }
      else
      {
        FailAtLine(attributeLine, "unexpected " + Quote(token) + " in " + keyword);
      }
    }
  }

  /** Skips "FIELD name numberOfArrays" and its arrays "name components tuples type values". */
  void
  SkipField(std::size_t keywordLine)
  {
    std::string_view token;
    std::size_t      line = 0;
    if (!this->Next(token, line))
    {
      FailAtLine(keywordLine, "the file ends after FIELD");
    }
    const unsigned long long numberOfArrays = this->ReadCount("the number of FIELD arrays", keywordLine);
    for (unsigned long long i = 0; i < numberOfArrays; ++i)
    {
      std::string_view name;
      if (!this->Next(name, line))
      {
        Fail("the file ends after " + std::to_string(i) + " of " + std::to_string(numberOfArrays) + " FIELD arrays");
      }
      const std::string        what = "FIELD array " + std::string(name);
      const std::size_t        arrayLine = line;
      const unsigned long long components = this->ReadCount("the number of components of " + what, arrayLine);
      const unsigned long long tuples = this->ReadCount("the number of tuples of " + what, arrayLine);
      const VTKType            type = this->ReadType(what, arrayLine);
      if (components != 0 && tuples > std::numeric_limits<unsigned long long>::max() / components)
      {
        FailAtLine(arrayLine, "the size of " + what + " overflows");
      }
      this->SkipValues(components * tuples, type, arrayLine, what);
    }
  }

  TextCursor                          m_Cursor;
  detail::StrictTextMeshIOInternals & m_Mesh;
  bool                                m_Binary{ false };
  bool                                m_HasPoints{ false };
  unsigned long long                  m_NumberOfFileCells{ 0 };
};
} // namespace

StrictTextMeshIO::StrictTextMeshIO()
  : m_Internals(new detail::StrictTextMeshIOInternals)
{
  for (const char * extension : { ".off", ".OFF", ".obj", ".OBJ", ".vtk", ".VTK" })
  {
    this->AddSupportedReadExtension(extension);
  }
  this->m_FileType = IOFileEnum::ASCII;
}

StrictTextMeshIO::~StrictTextMeshIO() = default;

std::string
StrictTextMeshIO::FormatOfFileName(const std::string & fileName)
{
  const std::string extension = Upper(itksys::SystemTools::GetFilenameLastExtension(fileName));
  if (extension == ".OFF" || extension == ".OBJ" || extension == ".VTK")
  {
    return extension.substr(1);
  }
  return "";
}

bool
StrictTextMeshIO::CanReadFile(const char * fileName)
{
  if (fileName == nullptr || FormatOfFileName(fileName).empty() || !itksys::SystemTools::FileExists(fileName, true))
  {
    return false;
  }
  std::ifstream file(fileName, std::ios::binary);
  return file.is_open();
}

void
StrictTextMeshIO::ReadMeshInformation()
{
  *m_Internals = detail::StrictTextMeshIOInternals{};
  const std::string format = FormatOfFileName(m_FileName);
  const std::string formatName = format == "VTK" ? "legacy VTK" : format;
  if (format.empty())
  {
    itkExceptionMacro(<< "Cannot read \"" << m_FileName << "\": the file name does not end with .off, .obj or .vtk");
  }
  std::ifstream file(m_FileName, std::ios::binary);
  if (!file.is_open() || !itksys::SystemTools::FileExists(m_FileName, true))
  {
    itkExceptionMacro(<< "Cannot read " << formatName << " file \"" << m_FileName
                      << "\": the file does not exist or cannot be opened");
  }
  std::string text;
  try
  {
    text.assign(std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>());
  }
  catch (const std::bad_alloc &)
  {
    itkExceptionMacro(<< "Cannot read " << formatName << " file \"" << m_FileName << "\": out of memory");
  }
  if (file.bad())
  {
    itkExceptionMacro(<< "Cannot read " << formatName << " file \"" << m_FileName << "\": a read error occurred");
  }

  auto & mesh = *m_Internals;
  try
  {
    if (format == "OFF")
    {
      ParseOFF(text, mesh);
    }
    else if (format == "OBJ")
    {
      ParseOBJ(text, mesh);
    }
    else
    {
      LegacyVTKParser(text, mesh).Parse();
    }
  }
  catch (const ParseError & error)
  {
    *m_Internals = detail::StrictTextMeshIOInternals{};
    itkExceptionMacro(<< "Cannot read " << formatName << " file \"" << m_FileName << "\": " << error.Message);
  }
  catch (const std::bad_alloc &)
  {
    *m_Internals = detail::StrictTextMeshIOInternals{};
    itkExceptionMacro(<< "Cannot read " << formatName << " file \"" << m_FileName
                      << "\": out of memory (the counts it announces are too large)");
  }

  this->m_FileType = IOFileEnum::ASCII;
  this->m_PointDimension = 3;
  this->m_NumberOfPoints = static_cast<SizeValueType>(mesh.Points.size() / 3);
  this->m_PointComponentType = mesh.FloatPoints ? IOComponentEnum::FLOAT : IOComponentEnum::DOUBLE;
  this->m_UpdatePoints = this->m_NumberOfPoints > 0;

  this->m_NumberOfCells = mesh.NumberOfCells;
  this->m_CellBufferSize = static_cast<SizeValueType>(mesh.Cells.size());
  this->m_CellComponentType = MapComponentType<IdentifierType>::CType;
  this->m_UpdateCells = this->m_NumberOfCells > 0;

  this->m_PointPixelType = IOPixelEnum::SCALAR;
  this->m_PointPixelComponentType = IOComponentEnum::DOUBLE;
  if (!mesh.PointData.empty())
  {
    this->m_NumberOfPointPixels = this->m_NumberOfPoints;
    this->m_NumberOfPointPixelComponents = 1;
    this->m_UpdatePointData = true;
  }
  else
  {
    this->m_NumberOfPointPixels = 0;
    this->m_NumberOfPointPixelComponents = 1;
    this->m_UpdatePointData = false;
  }
  this->m_CellPixelType = IOPixelEnum::SCALAR;
  this->m_CellPixelComponentType = IOComponentEnum::DOUBLE;
  this->m_NumberOfCellPixels = 0;
  this->m_NumberOfCellPixelComponents = 1;
  this->m_UpdateCellData = false;
}

void
StrictTextMeshIO::ReadPoints(void * buffer)
{
  const std::vector<double> & points = m_Internals->Points;
  if (m_Internals->FloatPoints)
  {
    std::transform(points.begin(), points.end(), static_cast<float *>(buffer), [](double value) {
      return static_cast<float>(value);
    });
  }
  else
  {
    std::copy(points.begin(), points.end(), static_cast<double *>(buffer));
  }
}

void
StrictTextMeshIO::ReadCells(void * buffer)
{
  std::copy(m_Internals->Cells.begin(), m_Internals->Cells.end(), static_cast<IdentifierType *>(buffer));
}

void
StrictTextMeshIO::ReadPointData(void * buffer)
{
  std::copy(m_Internals->PointData.begin(), m_Internals->PointData.end(), static_cast<double *>(buffer));
}

void
StrictTextMeshIO::ReadCellData(void * itkNotUsed(buffer))
{}

bool
StrictTextMeshIO::CanWriteFile(const char * itkNotUsed(fileName))
{
  return false;
}

void
StrictTextMeshIO::WriteMeshInformation()
{
  itkExceptionMacro(<< "StrictTextMeshIO does not write files (\"" << m_FileName << "\"): ITK's mesh IOs do");
}

void
StrictTextMeshIO::WritePoints(void * itkNotUsed(buffer))
{
  itkExceptionMacro(<< "StrictTextMeshIO does not write files (\"" << m_FileName << "\"): ITK's mesh IOs do");
}

void
StrictTextMeshIO::WriteCells(void * itkNotUsed(buffer))
{
  itkExceptionMacro(<< "StrictTextMeshIO does not write files (\"" << m_FileName << "\"): ITK's mesh IOs do");
}

void
StrictTextMeshIO::WritePointData(void * itkNotUsed(buffer))
{
  itkExceptionMacro(<< "StrictTextMeshIO does not write files (\"" << m_FileName << "\"): ITK's mesh IOs do");
}

void
StrictTextMeshIO::WriteCellData(void * itkNotUsed(buffer))
{
  itkExceptionMacro(<< "StrictTextMeshIO does not write files (\"" << m_FileName << "\"): ITK's mesh IOs do");
}

void
StrictTextMeshIO::Write()
{
  itkExceptionMacro(<< "StrictTextMeshIO does not write files (\"" << m_FileName << "\"): ITK's mesh IOs do");
}

void
StrictTextMeshIO::PrintSelf(std::ostream & os, Indent indent) const
{
  Superclass::PrintSelf(os, indent);
  os << indent << "Internals: " << m_Internals->Points.size() / 3 << " points ("
     << (m_Internals->FloatPoints ? "float" : "double") << "), " << m_Internals->NumberOfCells << " cells, "
     << m_Internals->PointData.size() << " point data values read" << std::endl;
}
} // namespace itk
