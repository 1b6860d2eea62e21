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
#include "itkVTKSurfaceFileChecks.h"

#include "itkByteSwapper.h"
#include "itksys/SystemTools.hxx"

#include "vtkPLY.h"
#include "vtkXMLDataElement.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <limits>
#include <sstream>
#include <utility>
#include <vector>

namespace itk
{
namespace detail
{
/** The problem of a binary STL file whose size does not fit its triangle count, or "". An ASCII
 * file (as vtkSTLReader classifies it) is left to vtkSTLReader's parser. */
std::string
CheckSTLFile(const std::string & fileName)
{
  const unsigned long fileSize = itksys::SystemTools::FileLength(fileName);
  if (itksys::SystemTools::DetectFileType(fileName.c_str()) == itksys::SystemTools::FileTypeText)
  {
    return "";
  }
  constexpr unsigned long headerSize = 84; // 80-byte comment, 32-bit triangle count
  constexpr unsigned long triangleSize = 50;
  if (fileSize < headerSize)
  {
    return "a binary STL file needs an 84-byte header, the file has " + std::to_string(fileSize) + " bytes";
  }
  std::ifstream file(fileName, std::ios::binary);
  unsigned char header[headerSize];
  file.read(reinterpret_cast<char *>(header), headerSize);
  if (!file)
  {
    return "cannot read the 84-byte binary STL header";
  }
  // The triangle count is little-endian, whatever the machine.
  const unsigned long numberOfTriangles =
    static_cast<unsigned long>(header[80]) | (static_cast<unsigned long>(header[81]) << 8) |
    (static_cast<unsigned long>(header[82]) << 16) | (static_cast<unsigned long>(header[83]) << 24);
  const unsigned long long neededSize =
    headerSize + static_cast<unsigned long long>(triangleSize) * static_cast<unsigned long long>(numberOfTriangles);
  if (fileSize < neededSize)
  {
    return "truncated binary STL file: its header announces " + std::to_string(numberOfTriangles) +
           " triangles, which need " + std::to_string(neededSize) + " bytes, the file has " + std::to_string(fileSize) +
           " bytes";
  }
  return "";
}

namespace
{
/** Size in bytes of a PLY scalar type, 0 for an unknown type name. */
unsigned int
PLYTypeSize(const std::string & type)
{
  if (type == "char" || type == "uchar" || type == "int8" || type == "uint8")
  {
    return 1;
  }
  if (type == "short" || type == "ushort" || type == "int16" || type == "uint16")
  {
    return 2;
  }
  if (type == "int" || type == "uint" || type == "int32" || type == "uint32" || type == "float" || type == "float32")
  {
    return 4;
  }
  if (type == "double" || type == "float64")
  {
    return 8;
  }
  return 0;
}

/** Decodes one binary PLY value of the given type at data. */
double
DecodePLYValue(const char * data, const std::string & type, bool bigEndian)
{
  const unsigned int size = std::min(PLYTypeSize(type), 8u); // PLY scalars have at most 8 bytes
  char               bytes[8];
  std::copy(data, data + size, bytes);
  const bool systemIsBigEndian = ByteSwapper<int>::SystemIsBigEndian();
  if (bigEndian != systemIsBigEndian)
  {
    std::reverse(bytes, bytes + size);
  }
  auto as = [&bytes](auto value) {
    std::memcpy(&value, bytes, sizeof(value));
    return static_cast<double>(value);
  };
  if (type == "char" || type == "int8")
  {
    return as(int8_t{});
  }
  if (type == "uchar" || type == "uint8")
  {
    return as(uint8_t{});
  }
  if (type == "short" || type == "int16")
  {
    return as(int16_t{});
  }
  if (type == "ushort" || type == "uint16")
  {
    return as(uint16_t{});
  }
  if (type == "int" || type == "int32")
  {
    return as(int32_t{});
  }
  if (type == "uint" || type == "uint32")
  {
    return as(uint32_t{});
  }
  if (type == "float" || type == "float32")
  {
    return as(float{});
  }
  return as(double{});
}

/** Longest line VTK's PLY reader reads as one line (its line buffer, less the end of line): a longer line is cut,
 * and the rest read as the next line. */
constexpr std::string::size_type MaximumPLYLineLength = 4094;

/** The text of a PLY line as VTK 9's PLY reader reads it: the first "vertex_index" in the line is written over as
 * "vertex_indices", which ends the line there (the common misspelling of the face property made the right one). */
std::string
PLYLineAsVTKReadsIt(const std::string & line)
{
  const std::string::size_type misspelling = line.find("vertex_index");
  return misspelling == std::string::npos ? line : line.substr(0, misspelling) + "vertex_indices";
}

/** Splits a PLY line (as PLYLineAsVTKReadsIt gives it) into words the way VTK's PLY reader does: words are
 * separated by spaces, tabs and carriage returns only (a vertical tab or a form feed is part of a word). */
std::vector<std::string>
SplitPLYLine(const std::string & line)
{
  std::vector<std::string> words;
  std::string              word;
  for (const char character : line)
  {
    if (character == ' ' || character == '\t' || character == '\r')
    {
      if (!word.empty())
      {
        words.push_back(word);
        word.clear();
      }
    }
    else
    {
      word += character;
    }
  }
  if (!word.empty())
  {
    words.push_back(word);
  }
  return words;
}

/** A line of a PLY file's header or ASCII data, read the way VTK's PLY reader reads it: its words, or the reason
 * VTK could not read it as one line (too long once read, or holding a NUL byte). */
struct PLYLine
{
  std::vector<std::string> Words;
  std::string              Problem;
};

PLYLine
ReadPLYLine(const std::string & text)
{
  PLYLine           line;
  const std::string read = PLYLineAsVTKReadsIt(text);
  if (read.size() > MaximumPLYLineLength || read.find('\0') != std::string::npos)
  {
    line.Problem = "longer than " + std::to_string(MaximumPLYLineLength) + " characters or holding a NUL byte";
    return line;
  }
  line.Words = SplitPLYLine(read);
  return line;
}

/** A property of a PLY element, as the header declares it. */
struct PLYProperty
{
  bool        IsList{ false };
  std::string CountType;
  std::string Type;
  std::string Name;
};

/** An element of a PLY file, as the header declares it. */
struct PLYElement
{
  std::string              Name;
  unsigned long long       Count{ 0 };
  std::vector<PLYProperty> Properties;
};

/** Whether element declares a property of this name. */
bool
HasPLYProperty(const PLYElement & element, const std::string & name)
{
  return std::any_of(element.Properties.begin(), element.Properties.end(), [&name](const PLYProperty & property) {
    return property.Name == name;
  });
}

/** The first element of this name, or elements.end(). */
std::vector<PLYElement>::const_iterator
FindPLYElement(const std::vector<PLYElement> & elements, const std::string & name)
{
  return std::find_if(
    elements.begin(), elements.end(), [&name](const PLYElement & element) { return element.Name == name; });
}

/** The problem of declared elements that VTK 9.1's vtkPLYReader would misread, or "". It reads the vertex and face
 * elements only, in the file's order, and skips no other element: another element's data before theirs would be
 * read as vertices or faces. Within them it reads a list property only when it asked for one (face vertex_indices,
 * and face texcoord when the vertices have no texture coordinates): it sizes any other list by a type it never set,
 * and stores a list it asked for as a single value (or the reverse) over its own memory. \c vertex is the elements'
 * vertex element (FindPLYElement(), not their end), \c face their face element or their end. */
std::string
CheckPLYElementsForVTK(const std::vector<PLYElement> &               elements,
                       const std::vector<PLYElement>::const_iterator vertex,
                       const std::vector<PLYElement>::const_iterator face)
{
  const auto lastRead = std::max(vertex, face == elements.end() ? vertex : face);
  for (auto element = elements.begin(); element < lastRead; ++element)
  {
    if (element != vertex && element != face && element->Count > 0)
    {
      return "the PLY element " + element->Name +
             " holds data before the vertex or face element's, which VTK's PLY "
             "reader would read as theirs (it skips no other element)";
    }
  }
  const bool vertexTextureCoordinates = (HasPLYProperty(*vertex, "u") && HasPLYProperty(*vertex, "v")) ||
                                        (HasPLYProperty(*vertex, "texture_u") && HasPLYProperty(*vertex, "texture_v"));
  for (const PLYProperty & property : vertex->Properties)
  {
    if (property.IsList)
    {
      return "the PLY vertex element has the list property " + property.Name + ", which VTK's PLY reader cannot skip";
    }
  }
  if (face == elements.end())
  {
    return "";
  }
  for (const PLYProperty & property : face->Properties)
  {
    const bool read = property.Name == "vertex_indices" || (property.Name == "texcoord" && !vertexTextureCoordinates);
    if (property.IsList && !read)
    {
      return "the PLY face element has the list property " + property.Name + ", which VTK's PLY reader cannot skip";
    }
    if (!property.IsList && read)
    {
      return "the PLY face property " + property.Name + " is not a list";
    }
  }
  return "";
}

/** The problem of a PLY header that VTK's own header parser (vtkPLY::ply_open_for_reading, which vtkPLYReader calls)
 * reads otherwise than elements, or "": the same elements in the same order, with the same counts and the same
 * properties, so that the data check below walks the structure VTK will read. vtkPLYReader 9.1 goes on reading a
 * file whose vertex coordinates it cannot find, on memory it has freed. Call it only on a header that passed the
 * textual check (VTK's parser reads past its word list on a short element or property line). */
std::string
CompareWithVTKPLYHeader(const std::string & fileName, const std::vector<PLYElement> & elements)
{
  int       numberOfElements = 0;
  char **   elementNames = nullptr;
  PlyFile * ply = vtkPLY::ply_open_for_reading(fileName.c_str(), &numberOfElements, &elementNames);
  if (ply == nullptr)
  {
    return "VTK's PLY reader cannot read the header";
  }
  std::string problem;
  if (numberOfElements != static_cast<int>(elements.size()) || ply->nelems != numberOfElements)
  {
    problem = "VTK's PLY reader finds " + std::to_string(numberOfElements) + " elements in the header, not " +
              std::to_string(elements.size());
  }
  for (int i = 0; problem.empty() && i < numberOfElements; ++i)
  {
    const PlyElement & read = *ply->elems[i];
    const PLYElement & declared = elements[static_cast<std::size_t>(i)];
    bool               same = declared.Name == read.name &&
                declared.Count == static_cast<unsigned long long>(std::max(read.num, 0)) &&
                declared.Properties.size() == static_cast<std::size_t>(std::max(read.nprops, 0));
    for (std::size_t j = 0; same && j < declared.Properties.size(); ++j)
    {
      same = declared.Properties[j].Name == read.props[j]->name &&
             declared.Properties[j].IsList == (read.props[j]->is_list != 0);
    }
    if (!same)
    {
      problem =
        "VTK's PLY reader reads element " + std::to_string(i) + " (" + declared.Name + ") of the header otherwise";
    }
  }
  int          index = 0;
  PlyElement * vertex = problem.empty() ? vtkPLY::find_element(ply, "vertex") : nullptr;
  if (problem.empty() &&
      (vertex == nullptr || vtkPLY::find_property(vertex, "x", &index) == nullptr ||
       vtkPLY::find_property(vertex, "y", &index) == nullptr || vtkPLY::find_property(vertex, "z", &index) == nullptr))
  {
    problem = "VTK's PLY reader finds no vertex element with properties x, y and z";
  }
  for (int i = 0; i < numberOfElements; ++i)
  {
    std::free(elementNames[i]);
  }
  std::free(elementNames);
  vtkPLY::ply_close(ply);
  return problem;
}

} // namespace

/** Checks the structure of a PLY file before VTK reads it (VTK's PLY code crashes on a file
 * shorter than its header announces, and accepts faces on missing vertices): the signature,
 * the header (format, elements, property types, end_header, read line by line as VTK reads it, then compared with
 * the header VTK's own parser builds), a vertex element with x, y and z, elements and properties VTK's reader can
 * read, the presence of every value the header announces, and the range of the face vertex indices. Returns the
 * problem, or "". */
std::string
CheckPLYFile(const std::string & fileName)
{
  std::ifstream     file(fileName, std::ios::binary);
  const std::string content((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
  if (content.compare(0, 4, "ply\n") != 0 && content.compare(0, 5, "ply\r\n") != 0)
  {
    return "not a PLY file (it does not start with the line \"ply\")";
  }

  // The header.
  std::string::size_type  position = 0;
  std::string             format;
  std::vector<PLYElement> elements;
  bool                    endOfHeader = false;
  for (unsigned int lineNumber = 1; !endOfHeader; ++lineNumber)
  {
    const std::string::size_type endOfLine = content.find('\n', position);
    if (endOfLine == std::string::npos)
    {
      return "the PLY header has no end_header line";
    }
    const std::string text = content.substr(position, endOfLine - position);
    position = endOfLine + 1;
    const std::string where = "PLY header line " + std::to_string(lineNumber) + ": ";
    const PLYLine     line = ReadPLYLine(text);
    if (!line.Problem.empty())
    {
      return where + line.Problem;
    }
    const std::vector<std::string> & words = line.Words;
    // The i-th word after the keyword, or "" when the line has fewer words.
    auto              word = [&words](std::size_t i) { return i < words.size() ? words[i] : std::string(); };
    const std::string keyword = word(0);
    if (keyword.empty())
    {
      // VTK's PLY reader ends the header at a line without words and would read the rest as data.
      return where + "a blank line within the header";
    }
    if (lineNumber == 1 || keyword == "comment" || keyword == "obj_info")
    {
      continue;
    }
    if (keyword == "format")
    {
      format = word(1);
      if (format != "ascii" && format != "binary_little_endian" && format != "binary_big_endian")
      {
        return where + "unknown format \"" + format + "\"";
      }
      if (words.size() != 3)
      {
        return where + "a format line needs the format and the version, and nothing else";
      }
    }
    else if (keyword == "element")
    {
      PLYElement        element;
      const std::string count = word(2);
      element.Name = word(1);
      if (element.Name.empty() || count.empty() || count.find_first_not_of("0123456789") != std::string::npos)
      {
        return where + "an element needs a name and a count";
      }
      if (words.size() != 3)
      {
        return where + "an element line needs a name and a count, and nothing else";
      }
      // VTK counts elements in an int.
      if (count.size() > 10 || std::stoull(count) > static_cast<unsigned long long>(std::numeric_limits<int>::max()))
      {
        return where + "an element count of " + count + ", more than a PLY reader can count";
      }
      element.Count = std::stoull(count);
      // Readers look elements and properties up by name: a second one of a name would be read as the first.
      if (std::any_of(elements.begin(), elements.end(), [&element](const PLYElement & declared) {
            return declared.Name == element.Name;
          }))
      {
        return where + "a second element named \"" + element.Name + "\"";
      }
      elements.push_back(element);
    }
    else if (keyword == "property")
    {
      if (elements.empty())
      {
        return where + "a property before any element";
      }
      PLYProperty property;
      std::size_t next = 1;
      property.Type = word(next++);
      if (property.Type == "list")
      {
        property.IsList = true;
        property.CountType = word(next++);
        property.Type = word(next++);
        if (PLYTypeSize(property.CountType) == 0 || property.CountType == "float" || property.CountType == "float32" ||
            property.CountType == "double" || property.CountType == "float64")
        {
          return where + "a list count of type \"" + property.CountType + "\"";
        }
      }
      property.Name = word(next);
      if (PLYTypeSize(property.Type) == 0 || property.Name.empty())
      {
        return where + "a property of unknown type \"" + property.Type + "\" or without a name";
      }
      if (HasPLYProperty(elements.back(), property.Name))
      {
        return where + "a second property named \"" + property.Name + "\" in element " + elements.back().Name;
      }
      elements.back().Properties.push_back(property);
    }
    else if (keyword == "end_header")
    {
      endOfHeader = true;
    }
    else
    {
      return where + "unknown keyword \"" + keyword + "\"";
    }
  }
  if (format.empty())
  {
    return "the PLY header has no format line";
  }
  // VTK 9.1's PLY code frees the property list of an element that has none (found by fuzzing).
  for (const PLYElement & element : elements)
  {
    if (element.Properties.empty())
    {
      return "the PLY element " + element.Name + " has no property";
    }
  }
  const auto vertexElement = FindPLYElement(elements, "vertex");
  const auto faceElement = FindPLYElement(elements, "face");
  if (vertexElement == elements.end())
  {
    return "the PLY header declares no vertex element";
  }
  for (const char * coordinate : { "x", "y", "z" })
  {
    if (std::none_of(
          vertexElement->Properties.begin(),
          vertexElement->Properties.end(),
          [coordinate](const PLYProperty & property) { return !property.IsList && property.Name == coordinate; }))
    {
      return std::string("the PLY vertex element has no property ") + coordinate;
    }
  }
  // Element names are unique (the header loop refuses a second one), so the first face element is the only one.
  if (faceElement != elements.end() && faceElement->Count > 0 &&
      std::none_of(faceElement->Properties.begin(), faceElement->Properties.end(), [](const PLYProperty & property) {
        return property.IsList && property.Name == "vertex_indices";
      }))
  {
    return "the PLY face element has no list property vertex_indices";
  }
  std::string vtkProblem = CheckPLYElementsForVTK(elements, vertexElement, faceElement);
  if (vtkProblem.empty())
  {
    vtkProblem = CompareWithVTKPLYHeader(fileName, elements);
  }
  if (!vtkProblem.empty())
  {
    return vtkProblem;
  }
  const double numberOfVertices = static_cast<double>(vertexElement->Count);

  // The body: every announced value present, face vertex indices in range. ASCII data is checked the way VTK's
  // PLY reader reads it (VTK frees memory twice on some ASCII files that other readers would accept): each element
  // on a line of its own, words separated by spaces and tabs only, exactly as many words as its properties need.
  const bool               ascii = format == "ascii";
  const bool               bigEndian = format == "binary_big_endian";
  const char *             data = content.data() + position;
  const char *             end = content.data() + content.size();
  std::vector<std::string> lineWords; // ASCII: the words of the current element's line not read yet
  std::size_t              nextWord = 0;
  // ASCII: moves to the next line; false at the end of the data or on a line VTK would not read as one line.
  auto readLine = [&data, end, &lineWords, &nextWord]() -> bool {
    if (data >= end)
    {
      return false;
    }
    const char * endOfLine = std::find(data, end, '\n');
    PLYLine      line = ReadPLYLine(std::string(data, endOfLine));
    data = endOfLine == end ? end : endOfLine + 1;
    if (!line.Problem.empty())
    {
      return false;
    }
    lineWords = std::move(line.Words);
    nextWord = 0;
    return true;
  };
  // Reads the next value; false at the end of the data (ASCII: of the element's line) or on a malformed number.
  auto readValue = [&data, end, ascii, bigEndian, &lineWords, &nextWord](const std::string & type,
                                                                         double &            value) -> bool {
    if (ascii)
    {
      if (nextWord >= lineWords.size())
      {
        return false;
      }
      const std::string & token = lineWords[nextWord++];
      char *              parsedEnd = nullptr;
      value = std::strtod(token.c_str(), &parsedEnd);
      return parsedEnd == token.c_str() + token.size();
    }
    const unsigned int size = PLYTypeSize(type);
    if (end - data < static_cast<std::ptrdiff_t>(size))
    {
      return false;
    }
    value = DecodePLYValue(data, type, bigEndian);
    data += size;
    return true;
  };
  for (const PLYElement & element : elements)
  {
    const bool isFace = element.Name == "face";
    for (unsigned long long i = 0; i < element.Count; ++i)
    {
      // The problem's text, made only when there is one (this loop runs once per vertex and face).
      const auto where = [&element, i, ascii]() {
        return (ascii ? "ASCII" : "binary") + std::string(" PLY data ends or is malformed in ") + element.Name + " " +
               std::to_string(i) + " of " + std::to_string(element.Count);
      };
      if (ascii && !readLine())
      {
        return where();
      }
      for (const PLYProperty & property : element.Properties)
      {
        double value = 0.0;
        if (!property.IsList)
        {
          if (!readValue(property.Type, value))
          {
            return where();
          }
          continue;
        }
        double count = 0.0;
        if (!readValue(property.CountType, count) || count < 0.0 || count != std::floor(count))
        {
          return where();
        }
        const bool isIndexList = isFace && property.Name == "vertex_indices";
        for (double j = 0; j < count; ++j)
        {
          if (!readValue(property.Type, value))
          {
            return where();
          }
          if (isIndexList && (value < 0.0 || value >= numberOfVertices || value != std::floor(value)))
          {
            std::ostringstream problem;
            problem << "PLY face " << i << " refers to vertex " << value << " of " << vertexElement->Count;
            return problem.str();
          }
        }
      }
      if (ascii && nextWord != lineWords.size())
      {
        return "ASCII PLY " + element.Name + " " + std::to_string(i) + " of " + std::to_string(element.Count) +
               " has " + std::to_string(lineWords.size()) + " values on its line, its properties need " +
               std::to_string(nextWord);
      }
    }
  }
  return "";
}

namespace
{
/** The deepest nesting of XML elements a VTP file may have: VTK's files use 5-8 levels (VTKFile, PolyData, Piece,
 * Points, DataArray, InformationKey, ...). VTK's expat-based parser recurses per level and overflows the stack
 * somewhere between 100 000 and 300 000 levels. */
constexpr std::size_t MaximumVTPNestingDepth = 256;

/** The nesting depth of the XML elements in content (comments, CDATA, processing instructions and declarations
 * skipped, quoted attribute values honoured), scanned up to the <AppendedData> element, whose raw binary data is
 * not XML; the scan stops as soon as the depth passes limit. */
std::size_t
XMLNestingDepth(const std::string & content, std::size_t limit)
{
  std::size_t depth = 0;
  std::size_t deepest = 0;
  std::size_t at = content.find('<');
  const auto  skipPast = [&](const char * end, std::size_t from) {
    const std::size_t found = content.find(end, from);
    return found == std::string::npos ? std::string::npos : found + std::strlen(end);
  };
  while (at != std::string::npos && at + 1 < content.size())
  {
    if (content.compare(at, 4, "<!--") == 0)
    {
      at = skipPast("-->", at + 4);
    }
    else if (content.compare(at, 9, "<![CDATA[") == 0)
    {
      at = skipPast("]]>", at + 9);
    }
    else if (content[at + 1] == '?' || content[at + 1] == '!')
    {
      at = skipPast(">", at + 2);
    }
    else if (content[at + 1] == '/')
    {
      depth -= depth > 0 ? 1 : 0;
      at = skipPast(">", at + 2);
    }
    else
    {
      if (content.compare(at + 1, 12, "AppendedData") == 0)
      {
        break;
      }
      // The end of the tag: a '>' outside quoted attribute values; "/>" closes an empty element.
      std::size_t end = at + 1;
      char        quote = 0;
      for (; end < content.size(); ++end)
      {
        const char c = content[end];
        if (quote != 0)
        {
          quote = c == quote ? 0 : quote;
        }
        else if (c == '"' || c == '\'')
        {
          quote = c;
        }
        else if (c == '>')
        {
          break;
        }
      }
      if (end >= content.size())
      {
        break;
      }
      if (content[end - 1] != '/')
      {
        deepest = std::max(deepest, ++depth);
        if (deepest > limit)
        {
          break;
        }
      }
      at = end + 1;
    }
    at = at == std::string::npos ? at : content.find('<', at);
  }
  return deepest;
}

} // namespace

/** Checks, before VTK's XML parser sees the file, that its XML does not nest deeper than MaximumVTPNestingDepth
 * (VTK's parser would overflow the stack). Everything else (XML syntax, data, encodings) is left to VTK's reader,
 * which reports it; the points' arrays are checked on the parsed element tree (CheckVTPPointsArrays). Returns the
 * problem, or "". */
std::string
CheckVTPFile(const std::string & fileName)
{
  std::ifstream     file(fileName, std::ios::binary);
  const std::string content((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
  const std::size_t depth = XMLNestingDepth(content, MaximumVTPNestingDepth);
  if (depth > MaximumVTPNestingDepth)
  {
    return "its XML nests elements more than " + std::to_string(MaximumVTPNestingDepth) +
           " levels deep (a VTP file needs fewer than 10): refused, as VTK's XML parser would overflow the stack";
  }
  return "";
}

std::string
CheckVTPPointsArrays(vtkXMLDataElement * root)
{
  if (root == nullptr)
  {
    return "VTK's XML parser gave no element tree";
  }
  // Depth-first over the tree, without recursion (CheckVTPFile bounds the depth, but a stack of elements costs
  // nothing).
  std::vector<vtkXMLDataElement *> elements{ root };
  while (!elements.empty())
  {
    vtkXMLDataElement * element = elements.back();
    elements.pop_back();
    const bool isPoints = element->GetName() != nullptr && std::strcmp(element->GetName(), "Points") == 0;
    for (int index = 0; index < element->GetNumberOfNestedElements(); ++index)
    {
      vtkXMLDataElement * nested = element->GetNestedElement(index);
      if (isPoints)
      {
        const char * text = nested->GetAttribute("NumberOfComponents");
        int          components = 0;
        if (text == nullptr)
        {
          return "the points' DataArray has no NumberOfComponents (VTK takes 1), not 3";
        }
        if (!nested->GetScalarAttribute("NumberOfComponents", components) || components != 3)
        {
          return "the points' DataArray has NumberOfComponents=\"" + std::string(text).substr(0, 20) + "\", not 3";
        }
      }
      elements.push_back(nested);
    }
  }
  return "";
}
} // namespace detail
} // namespace itk
