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

namespace itk
{
namespace detail
{
namespace StrictText
{
namespace
{

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
} // namespace

void
ParseOFF(const std::string & text, StrictTextMeshIOInternals & mesh)
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
} // namespace StrictText
} // namespace detail
} // namespace itk
