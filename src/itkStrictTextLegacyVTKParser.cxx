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
#include <charconv>
#include <cmath>
#include <cstdint>
#include <limits>
#include "itkByteSwapper.h"

namespace itk
{
namespace detail
{
namespace StrictText
{
namespace
{
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
  LegacyVTKParser(const std::string & text, StrictTextMeshIOInternals & mesh)
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

  TextCursor                  m_Cursor;
  StrictTextMeshIOInternals & m_Mesh;
  bool                        m_Binary{ false };
  bool                        m_HasPoints{ false };
  unsigned long long          m_NumberOfFileCells{ 0 };
};
} // namespace

void
ParseLegacyVTK(const std::string & text, StrictTextMeshIOInternals & mesh)
{
  LegacyVTKParser(text, mesh).Parse();
}
} // namespace StrictText
} // namespace detail
} // namespace itk
