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
#include <set>

namespace itk
{
namespace detail
{
namespace StrictText
{
namespace
{
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
} // namespace

void
ParseOBJ(const std::string & text, StrictTextMeshIOInternals & mesh)
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
} // namespace StrictText
} // namespace detail
} // namespace itk
