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
#include "itkVTKSurfaceMeshIO.h"

#include "itkFFDShapeMatchingVTKUtilities.h"
#include "itkByteSwapper.h"
#include "itkMacro.h"
#include "itksys/SystemTools.hxx"

#include "vtkCellArray.h"
#include "vtkDoubleArray.h"
#include "vtkExecutive.h"
#include "vtkPLYReader.h"
#include "vtkPLYWriter.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkSTLReader.h"
#include "vtkSTLWriter.h"
#include "vtkXMLPolyDataReader.h"
#include "vtkXMLPolyDataWriter.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <iterator>
#include <limits>
#include <sstream>
#include <fstream>
#include <type_traits>
#include <vector>

namespace itk
{
namespace detail
{
/** What a VTKSurfaceMeshIO holds between its calls: the mesh read, or the pieces to write. */
struct VTKSurfaceMeshIOInternals
{
  // Reading.
  vtkSmartPointer<vtkPolyData>  ReadPolyData;
  vtkSmartPointer<vtkDataArray> ReadPointData;

  // Writing.
  std::vector<double>           WritePoints;
  vtkSmartPointer<vtkCellArray> WriteVerts;
  vtkSmartPointer<vtkCellArray> WriteLines;
  vtkSmartPointer<vtkCellArray> WritePolys;
  std::vector<double>           WritePointData;
};
} // namespace detail

namespace
{
/** Copies count values of the given component type from input to output, converted to TOutput. */
template <typename TOutput>
void
ConvertBuffer(const void * input, IOComponentEnum componentType, std::size_t count, TOutput * output)
{
  auto convert = [count, output](const auto * typedInput) {
    std::transform(
      typedInput, typedInput + count, output, [](const auto value) { return static_cast<TOutput>(value); });
  };
  switch (componentType)
  {
    case IOComponentEnum::UCHAR:
      convert(static_cast<const unsigned char *>(input));
      break;
    case IOComponentEnum::CHAR:
      convert(static_cast<const char *>(input));
      break;
    case IOComponentEnum::USHORT:
      convert(static_cast<const unsigned short *>(input));
      break;
    case IOComponentEnum::SHORT:
      convert(static_cast<const short *>(input));
      break;
    case IOComponentEnum::UINT:
      convert(static_cast<const unsigned int *>(input));
      break;
    case IOComponentEnum::INT:
      convert(static_cast<const int *>(input));
      break;
    case IOComponentEnum::ULONG:
      convert(static_cast<const unsigned long *>(input));
      break;
    case IOComponentEnum::LONG:
      convert(static_cast<const long *>(input));
      break;
    case IOComponentEnum::ULONGLONG:
      convert(static_cast<const unsigned long long *>(input));
      break;
    case IOComponentEnum::LONGLONG:
      convert(static_cast<const long long *>(input));
      break;
    case IOComponentEnum::FLOAT:
      convert(static_cast<const float *>(input));
      break;
    case IOComponentEnum::DOUBLE:
      convert(static_cast<const double *>(input));
      break;
    case IOComponentEnum::LDOUBLE:
      convert(static_cast<const long double *>(input));
      break;
    default:
      itkGenericExceptionMacro(<< "VTKSurfaceMeshIO: unsupported component type " << componentType);
  }
}

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

/** Splits a PLY line into words the way VTK's PLY reader does: words are separated by spaces and tabs only (a
 * vertical tab or a form feed is part of a word), a carriage return ends the line. */
std::vector<std::string>
SplitPLYLine(const std::string & line)
{
  std::vector<std::string> words;
  std::string              word;
  for (const char character : line)
  {
    if (character == '\r')
    {
      break;
    }
    if (character == ' ' || character == '\t')
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

/** Checks the structure of a PLY file before VTK reads it (VTK's PLY code crashes on a file
 * shorter than its header announces, and accepts faces on missing vertices): the signature,
 * the header (format, elements, property types, end_header), a vertex element with x, y and
 * z, the presence of every value the header announces, and the range of the face vertex
 * indices. Returns the problem, or "". */
std::string
CheckPLYFile(const std::string & fileName)
{
  struct Property
  {
    bool        IsList{ false };
    std::string CountType;
    std::string Type;
    std::string Name;
  };
  struct Element
  {
    std::string           Name;
    unsigned long long    Count{ 0 };
    std::vector<Property> Properties;
  };

  std::ifstream     file(fileName, std::ios::binary);
  const std::string content((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
  if (content.compare(0, 4, "ply\n") != 0 && content.compare(0, 5, "ply\r\n") != 0)
  {
    return "not a PLY file (it does not start with the line \"ply\")";
  }

  // The header.
  std::string::size_type position = 0;
  std::string            format;
  std::vector<Element>   elements;
  bool                   endOfHeader = false;
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
    if (text.size() > MaximumPLYLineLength || text.find('\0') != std::string::npos)
    {
      return where + "longer than " + std::to_string(MaximumPLYLineLength) + " characters or holding a NUL byte";
    }
    const std::vector<std::string> words = SplitPLYLine(text);
    // The i-th word after the keyword, or "" when the line has fewer words.
    auto              word = [&words](std::size_t i) { return i < words.size() ? words[i] : std::string(); };
    const std::string keyword = word(0);
    if (lineNumber == 1 || keyword.empty() || keyword == "comment" || keyword == "obj_info")
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
    }
    else if (keyword == "element")
    {
      Element           element;
      const std::string count = word(2);
      element.Name = word(1);
      if (element.Name.empty() || count.empty() || count.find_first_not_of("0123456789") != std::string::npos)
      {
        return where + "an element needs a name and a count";
      }
      // VTK counts elements in an int.
      if (count.size() > 10 || std::stoull(count) > static_cast<unsigned long long>(std::numeric_limits<int>::max()))
      {
        return where + "an element count of " + count + ", more than a PLY reader can count";
      }
      element.Count = std::stoull(count);
      elements.push_back(element);
    }
    else if (keyword == "property")
    {
      if (elements.empty())
      {
        return where + "a property before any element";
      }
      Property    property;
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
  const auto vertexElement =
    std::find_if(elements.begin(), elements.end(), [](const Element & element) { return element.Name == "vertex"; });
  if (vertexElement == elements.end())
  {
    return "the PLY header declares no vertex element";
  }
  for (const char * coordinate : { "x", "y", "z" })
  {
    if (std::none_of(
          vertexElement->Properties.begin(), vertexElement->Properties.end(), [coordinate](const Property & property) {
            return !property.IsList && property.Name == coordinate;
          }))
    {
      return std::string("the PLY vertex element has no property ") + coordinate;
    }
  }
  for (const Element & element : elements)
  {
    if (element.Name == "face" && element.Count > 0 &&
        std::none_of(element.Properties.begin(), element.Properties.end(), [](const Property & property) {
          return property.IsList && property.Name == "vertex_indices";
        }))
    {
      return "the PLY face element has no list property vertex_indices";
    }
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
    const char *      endOfLine = std::find(data, end, '\n');
    const std::string text(data, endOfLine);
    data = endOfLine == end ? end : endOfLine + 1;
    if (text.size() > MaximumPLYLineLength || text.find('\0') != std::string::npos)
    {
      return false;
    }
    lineWords = SplitPLYLine(text);
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
  for (const Element & element : elements)
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
      for (const Property & property : element.Properties)
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

/** Checks what VTK's XML PolyData reader does not check before it uses it: the XML must not nest deeper than
 * MaximumVTPNestingDepth (VTK's parser would overflow the stack), and the points' array must have 3
 * components (VTK 9.1 leaks the arrays it read when it has another number). A light scan of the first <Points>
 * element's first <DataArray> tag; everything else (XML syntax, data, encodings) is left to VTK's reader, which
 * reports it. Returns the problem, or "". */
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
  std::string::size_type points = content.find("<Points");
  while (points != std::string::npos && points + 7 < content.size() && content[points + 7] != '>' &&
         !std::isspace(static_cast<unsigned char>(content[points + 7])))
  {
    points = content.find("<Points", points + 7); // e.g. <PointsSomething: not the element
  }
  if (points == std::string::npos)
  {
    return "";
  }
  const std::string::size_type array = content.find("<DataArray", points);
  const std::string::size_type pointsEnd = content.find("</Points", points);
  if (array == std::string::npos || (pointsEnd != std::string::npos && pointsEnd < array))
  {
    return "";
  }
  const std::string::size_type tagEnd = content.find('>', array);
  const std::string tag = content.substr(array, tagEnd == std::string::npos ? std::string::npos : tagEnd - array);
  std::string       components = "1"; // VTK's default when the attribute is missing
  const std::string attribute = "NumberOfComponents=";
  const std::string::size_type at = tag.find(attribute);
  if (at != std::string::npos && at + attribute.size() < tag.size())
  {
    const char                   quote = tag[at + attribute.size()];
    const std::string::size_type valueEnd = tag.find(quote, at + attribute.size() + 1);
    components = tag.substr(at + attribute.size() + 1,
                            valueEnd == std::string::npos ? std::string::npos : valueEnd - at - attribute.size() - 1);
  }
  if (components != "3")
  {
    return "the points' DataArray has NumberOfComponents=\"" + components.substr(0, 20) + "\", not 3";
  }
  return "";
}

/** Reads fileName with a VTK reader of type TReader; sets problem when the reader fails. */
template <typename TReader>
vtkSmartPointer<vtkPolyData>
ReadWithVTK(const std::string & fileName, std::string & problem)
{
  detail::VTKMessageCapture capture;
  auto                      reader = vtkSmartPointer<TReader>::New();
  capture.Observe(reader);
  capture.Observe(reader->GetExecutive());
  if constexpr (std::is_base_of<vtkXMLReader, TReader>::value)
  {
    reader->SetParserErrorObserver(capture.GetCommand());
  }
  reader->SetFileName(fileName.c_str());
  try
  {
    reader->Update();
  }
  catch (const std::exception & error)
  {
    problem = error.what();
    return nullptr;
  }
  vtkSmartPointer<vtkPolyData> output = reader->GetOutput();
  const bool                   noPoints = output == nullptr || output->GetNumberOfPoints() == 0;
  if (capture.HasErrors() || reader->GetErrorCode() != 0 || (noPoints && capture.HasWarnings()))
  {
    problem = capture.GetSummary();
    if (problem.empty())
    {
      problem = "VTK's " + std::string(reader->GetClassName()) +
                " failed without saying why: the file is damaged or not in its format";
    }
    return nullptr;
  }
  if (noPoints)
  {
    problem = "the file holds no points";
    return nullptr;
  }
  problem = detail::CheckVTKPolyDataPointIds(output);
  return problem.empty() ? output : nullptr;
}

/** Writes polyData with the VTK writer given; returns the problem, or "" on success. */
template <typename TWriter>
std::string
WriteWithVTK(TWriter * writer, vtkPolyData * polyData)
{
  detail::VTKMessageCapture capture;
  capture.Observe(writer);
  capture.Observe(writer->GetExecutive());
  writer->SetInputData(polyData);
  int written = 0;
  try
  {
    written = writer->Write();
  }
  catch (const std::exception & error)
  {
    return error.what();
  }
  if (written == 0 || capture.HasErrors() || writer->GetErrorCode() != 0)
  {
    const std::string summary = capture.GetSummary();
    return summary.empty() ? "VTK's " + std::string(writer->GetClassName()) + " failed without saying why" : summary;
  }
  return "";
}
} // namespace

VTKSurfaceMeshIO::VTKSurfaceMeshIO()
  : m_Internals(new detail::VTKSurfaceMeshIOInternals)
{
  for (const char * extension : { ".stl", ".STL", ".ply", ".PLY", ".vtp", ".VTP" })
  {
    this->AddSupportedReadExtension(extension);
    this->AddSupportedWriteExtension(extension);
  }
  this->m_FileType = IOFileEnum::BINARY;
  this->m_ByteOrder = IOByteOrderEnum::LittleEndian;
}

VTKSurfaceMeshIO::~VTKSurfaceMeshIO() = default;

std::string
VTKSurfaceMeshIO::FormatOfFileName(const std::string & fileName)
{
  std::string extension = itksys::SystemTools::GetFilenameLastExtension(fileName);
  std::transform(extension.begin(), extension.end(), extension.begin(), [](unsigned char character) {
    return static_cast<char>(std::tolower(character));
  });
  if (extension == ".stl")
  {
    return "STL";
  }
  if (extension == ".ply")
  {
    return "PLY";
  }
  if (extension == ".vtp")
  {
    return "VTP";
  }
  return "";
}

bool
VTKSurfaceMeshIO::CanReadFile(const char * fileName)
{
  if (fileName == nullptr || FormatOfFileName(fileName).empty())
  {
    return false;
  }
  if (!itksys::SystemTools::FileExists(fileName, true))
  {
    return false;
  }
  std::ifstream file(fileName, std::ios::binary);
  return file.is_open();
}

void
VTKSurfaceMeshIO::ReadMeshInformation()
{
  m_Internals->ReadPolyData = nullptr;
  m_Internals->ReadPointData = nullptr;
  m_NumberOfDroppedCells = 0;

  const std::string format = FormatOfFileName(m_FileName);
  if (format.empty())
  {
    itkExceptionMacro(<< "Cannot read \"" << m_FileName << "\": the file name does not end with .stl, .ply or .vtp");
  }
  if (!itksys::SystemTools::FileExists(m_FileName, true))
  {
    itkExceptionMacro(<< "Cannot read \"" << m_FileName << "\": the file does not exist");
  }

  std::string                  problem = format == "STL"   ? CheckSTLFile(m_FileName)
                                         : format == "PLY" ? CheckPLYFile(m_FileName)
                                                           : CheckVTPFile(m_FileName);
  vtkSmartPointer<vtkPolyData> polyData;
  if (problem.empty())
  {
    if (format == "STL")
    {
      polyData = ReadWithVTK<vtkSTLReader>(m_FileName, problem);
    }
    else if (format == "PLY")
    {
      polyData = ReadWithVTK<vtkPLYReader>(m_FileName, problem);
    }
    else
    {
      polyData = ReadWithVTK<vtkXMLPolyDataReader>(m_FileName, problem);
    }
  }
  if (!problem.empty() || polyData == nullptr)
  {
    itkExceptionMacro(<< "Cannot read " << format << " file \"" << m_FileName << "\": " << problem);
  }

  std::size_t droppedCells = 0;
  {
    detail::VTKMessageCapture capture;
    polyData = detail::TriangulateVTKPolyData(polyData, &droppedCells);
  }
  m_NumberOfDroppedCells = static_cast<SizeValueType>(droppedCells);
  m_Internals->ReadPolyData = polyData;
  m_Internals->ReadPointData = detail::SelectScalarPointData(polyData, m_PointDataArrayName);

  this->m_PointDimension = 3;
  this->m_NumberOfPoints = static_cast<SizeValueType>(polyData->GetNumberOfPoints());
  this->m_PointComponentType = IOComponentEnum::DOUBLE;
  this->m_UpdatePoints = true;

  this->m_NumberOfCells = static_cast<SizeValueType>(polyData->GetNumberOfPolys());
  this->m_CellBufferSize = 5 * this->m_NumberOfCells;
  this->m_CellComponentType = MapComponentType<IdentifierType>::CType;
  this->m_UpdateCells = this->m_NumberOfCells > 0;

  if (m_Internals->ReadPointData != nullptr)
  {
    this->m_NumberOfPointPixels = this->m_NumberOfPoints;
    this->m_PointPixelType = IOPixelEnum::SCALAR;
    this->m_NumberOfPointPixelComponents = 1;
    this->m_PointPixelComponentType = IOComponentEnum::DOUBLE;
    this->m_UpdatePointData = true;
  }
  else
  {
    this->m_NumberOfPointPixels = 0;
    this->m_NumberOfPointPixelComponents = 0;
    this->m_UpdatePointData = false;
  }
  this->m_NumberOfCellPixels = 0;
  this->m_NumberOfCellPixelComponents = 0;
  this->m_UpdateCellData = false;
}

void
VTKSurfaceMeshIO::ReadPoints(void * buffer)
{
  vtkPolyData * polyData = m_Internals->ReadPolyData;
  if (polyData == nullptr)
  {
    itkExceptionMacro(<< "ReadPoints() called before ReadMeshInformation() for \"" << m_FileName << "\"");
  }
  auto *          coordinates = static_cast<double *>(buffer);
  const vtkIdType numberOfPoints = polyData->GetNumberOfPoints();
  for (vtkIdType i = 0; i < numberOfPoints; ++i)
  {
    polyData->GetPoint(i, coordinates + 3 * i);
  }
}

void
VTKSurfaceMeshIO::ReadCells(void * buffer)
{
  vtkPolyData * polyData = m_Internals->ReadPolyData;
  if (polyData == nullptr)
  {
    itkExceptionMacro(<< "ReadCells() called before ReadMeshInformation() for \"" << m_FileName << "\"");
  }
  auto *            cells = static_cast<IdentifierType *>(buffer);
  SizeValueType     index = 0;
  vtkCellArray *    polys = polyData->GetPolys();
  vtkIdType         numberOfCellPoints = 0;
  const vtkIdType * cellPoints = nullptr;
  for (polys->InitTraversal(); polys->GetNextCell(numberOfCellPoints, cellPoints);)
  {
    cells[index++] = static_cast<IdentifierType>(CellGeometryEnum::TRIANGLE_CELL);
    cells[index++] = 3;
    for (vtkIdType j = 0; j < 3; ++j)
    {
      cells[index++] = static_cast<IdentifierType>(cellPoints[j]);
    }
  }
}

void
VTKSurfaceMeshIO::ReadPointData(void * buffer)
{
  vtkDataArray * pointData = m_Internals->ReadPointData;
  if (pointData == nullptr)
  {
    return;
  }
  auto *          values = static_cast<double *>(buffer);
  const vtkIdType numberOfValues = pointData->GetNumberOfTuples();
  for (vtkIdType i = 0; i < numberOfValues; ++i)
  {
    values[i] = pointData->GetComponent(i, 0);
  }
}

void
VTKSurfaceMeshIO::ReadCellData(void * itkNotUsed(buffer))
{}

bool
VTKSurfaceMeshIO::CanWriteFile(const char * fileName)
{
  return fileName != nullptr && !FormatOfFileName(fileName).empty();
}

void
VTKSurfaceMeshIO::WriteMeshInformation()
{
  if (FormatOfFileName(m_FileName).empty())
  {
    itkExceptionMacro(<< "Cannot write \"" << m_FileName << "\": the file name does not end with .stl, .ply or .vtp");
  }
  if (this->m_PointDimension != 2 && this->m_PointDimension != 3)
  {
    itkExceptionMacro(<< "Cannot write \"" << m_FileName << "\": points of dimension " << this->m_PointDimension
                      << " (2 or 3 expected)");
  }
  m_Internals->WritePoints.clear();
  m_Internals->WriteVerts = vtkSmartPointer<vtkCellArray>::New();
  m_Internals->WriteLines = vtkSmartPointer<vtkCellArray>::New();
  m_Internals->WritePolys = vtkSmartPointer<vtkCellArray>::New();
  m_Internals->WritePointData.clear();
}

void
VTKSurfaceMeshIO::WritePoints(void * buffer)
{
  const std::size_t   count = static_cast<std::size_t>(this->m_NumberOfPoints) * this->m_PointDimension;
  std::vector<double> coordinates(count);
  ConvertBuffer(buffer, this->m_PointComponentType, count, coordinates.data());
  m_Internals->WritePoints.assign(static_cast<std::size_t>(this->m_NumberOfPoints) * 3, 0.0);
  for (SizeValueType i = 0; i < this->m_NumberOfPoints; ++i)
  {
    for (unsigned int j = 0; j < this->m_PointDimension; ++j)
    {
      m_Internals->WritePoints[3 * i + j] = coordinates[i * this->m_PointDimension + j];
    }
  }
}

void
VTKSurfaceMeshIO::WriteCells(void * buffer)
{
  if (m_Internals->WritePolys == nullptr)
  {
    itkExceptionMacro(<< "WriteCells() called before WriteMeshInformation() for \"" << m_FileName << "\"");
  }
  std::vector<IdentifierType> cells(this->m_CellBufferSize);
  ConvertBuffer(buffer, this->m_CellComponentType, cells.size(), cells.data());

  SizeValueType          index = 0;
  std::vector<vtkIdType> cellPoints;
  for (SizeValueType cellId = 0; cellId < this->m_NumberOfCells; ++cellId)
  {
    if (index + 2 > cells.size())
    {
      itkExceptionMacro(<< "Cannot write \"" << m_FileName << "\": the cell buffer ends within cell " << cellId);
    }
    const auto           cellType = static_cast<CellGeometryEnum>(cells[index++]);
    const IdentifierType numberOfCellPoints = cells[index++];
    if (index + numberOfCellPoints > cells.size())
    {
      itkExceptionMacro(<< "Cannot write \"" << m_FileName << "\": the cell buffer ends within cell " << cellId);
    }
    cellPoints.clear();
    for (IdentifierType j = 0; j < numberOfCellPoints; ++j)
    {
      const IdentifierType pointId = cells[index++];
      if (pointId >= this->m_NumberOfPoints)
      {
        itkExceptionMacro(<< "Cannot write \"" << m_FileName << "\": cell " << cellId << " refers to point " << pointId
                          << " of " << this->m_NumberOfPoints);
      }
      cellPoints.push_back(static_cast<vtkIdType>(pointId));
    }
    const auto numberOfPoints = static_cast<vtkIdType>(cellPoints.size());
    switch (cellType)
    {
      case CellGeometryEnum::VERTEX_CELL:
        m_Internals->WriteVerts->InsertNextCell(numberOfPoints, cellPoints.data());
        break;
      case CellGeometryEnum::LINE_CELL:
        m_Internals->WriteLines->InsertNextCell(numberOfPoints, cellPoints.data());
        break;
      case CellGeometryEnum::TRIANGLE_CELL:
      case CellGeometryEnum::QUADRILATERAL_CELL:
      case CellGeometryEnum::POLYGON_CELL:
        m_Internals->WritePolys->InsertNextCell(numberOfPoints, cellPoints.data());
        break;
      default:
        itkExceptionMacro(<< "Cannot write \"" << m_FileName << "\": cell " << cellId << " is of type " << cellType
                          << ", which a surface mesh file cannot hold");
    }
  }
}

void
VTKSurfaceMeshIO::WritePointData(void * buffer)
{
  const std::size_t count =
    static_cast<std::size_t>(this->m_NumberOfPointPixels) * std::max(1u, this->m_NumberOfPointPixelComponents);
  m_Internals->WritePointData.resize(count);
  ConvertBuffer(buffer, this->m_PointPixelComponentType, count, m_Internals->WritePointData.data());
}

void
VTKSurfaceMeshIO::WriteCellData(void * itkNotUsed(buffer))
{}

void
VTKSurfaceMeshIO::Write()
{
  const std::string format = FormatOfFileName(m_FileName);
  if (format.empty())
  {
    itkExceptionMacro(<< "Cannot write \"" << m_FileName << "\": the file name does not end with .stl, .ply or .vtp");
  }
  const std::size_t numberOfPoints = m_Internals->WritePoints.size() / 3;
  if (numberOfPoints == 0 || m_Internals->WritePolys == nullptr)
  {
    itkExceptionMacro(<< "Cannot write " << format << " file \"" << m_FileName << "\": the mesh has no points");
  }

  auto points = vtkSmartPointer<vtkPoints>::New();
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(static_cast<vtkIdType>(numberOfPoints));
  for (std::size_t i = 0; i < numberOfPoints; ++i)
  {
    points->SetPoint(static_cast<vtkIdType>(i), m_Internals->WritePoints.data() + 3 * i);
  }
  vtkSmartPointer<vtkPolyData> polyData = vtkSmartPointer<vtkPolyData>::New();
  polyData->SetPoints(points);
  polyData->SetVerts(m_Internals->WriteVerts);
  polyData->SetLines(m_Internals->WriteLines);
  polyData->SetPolys(m_Internals->WritePolys);

  std::string problem;
  if (format == "STL")
  {
    {
      detail::VTKMessageCapture capture;
      polyData = detail::TriangulateVTKPolyData(polyData);
    }
    if (polyData->GetNumberOfPolys() == 0)
    {
      itkExceptionMacro(<< "Cannot write STL file \"" << m_FileName << "\": the mesh has no polygons");
    }
    auto writer = vtkSmartPointer<vtkSTLWriter>::New();
    writer->SetFileName(m_FileName.c_str());
    writer->SetFileTypeToBinary();
    problem = WriteWithVTK(writer.GetPointer(), polyData.GetPointer());
  }
  else if (format == "PLY")
  {
    // VTK's PLY code appends ".ply" to a file name that does not end with it in lower case:
    // such a file is written under a temporary lower-case name, then renamed.
    const bool        lowerCase = itksys::SystemTools::GetFilenameLastExtension(m_FileName) == ".ply";
    const std::string vtkFileName = lowerCase ? m_FileName : m_FileName + ".writing.ply";
    auto              writer = vtkSmartPointer<vtkPLYWriter>::New();
    writer->SetFileName(vtkFileName.c_str());
    writer->SetFileTypeToBinary();
    writer->SetDataByteOrderToLittleEndian();
    problem = WriteWithVTK(writer.GetPointer(), polyData.GetPointer());
    if (problem.empty() && !lowerCase && std::rename(vtkFileName.c_str(), m_FileName.c_str()) != 0)
    {
      itksys::SystemTools::RemoveFile(vtkFileName);
      problem = "cannot rename the temporary file " + vtkFileName;
    }
  }
  else
  {
    const unsigned int numberOfComponents = std::max(1u, this->m_NumberOfPointPixelComponents);
    if (this->m_UpdatePointData && !m_Internals->WritePointData.empty())
    {
      if (m_Internals->WritePointData.size() != numberOfPoints * numberOfComponents)
      {
        itkExceptionMacro(<< "Cannot write VTP file \"" << m_FileName << "\": the point data has "
                          << m_Internals->WritePointData.size() / numberOfComponents << " values for " << numberOfPoints
                          << " points");
      }
      auto array = vtkSmartPointer<vtkDoubleArray>::New();
      array->SetName(m_PointDataArrayName.empty() ? "PointData" : m_PointDataArrayName.c_str());
      array->SetNumberOfComponents(static_cast<int>(numberOfComponents));
      array->SetNumberOfTuples(static_cast<vtkIdType>(numberOfPoints));
      std::copy(m_Internals->WritePointData.begin(), m_Internals->WritePointData.end(), array->GetPointer(0));
      if (numberOfComponents == 1)
      {
        polyData->GetPointData()->SetScalars(array);
      }
      else
      {
        polyData->GetPointData()->AddArray(array);
      }
    }
    auto writer = vtkSmartPointer<vtkXMLPolyDataWriter>::New();
    writer->SetFileName(m_FileName.c_str());
    writer->SetDataModeToAppended();
    writer->EncodeAppendedDataOff();
    if (this->m_UseCompression)
    {
      writer->SetCompressorTypeToZLib();
    }
    else
    {
      writer->SetCompressorTypeToNone();
    }
    problem = WriteWithVTK(writer.GetPointer(), polyData.GetPointer());
  }
  if (problem.empty() && !itksys::SystemTools::FileExists(m_FileName, true))
  {
    problem = "VTK reported no error, yet the file is missing";
  }
  if (!problem.empty())
  {
    itkExceptionMacro(<< "Cannot write " << format << " file \"" << m_FileName << "\": " << problem);
  }
}

void
VTKSurfaceMeshIO::PrintSelf(std::ostream & os, Indent indent) const
{
  Superclass::PrintSelf(os, indent);
  os << indent << "PointDataArrayName: " << m_PointDataArrayName << std::endl;
  os << indent << "NumberOfDroppedCells: " << m_NumberOfDroppedCells << std::endl;
  os << indent << "Internals: ";
  if (m_Internals->ReadPolyData != nullptr)
  {
    os << "mesh read with " << m_Internals->ReadPolyData->GetNumberOfPoints() << " points and "
       << m_Internals->ReadPolyData->GetNumberOfPolys() << " triangles" << std::endl;
  }
  else
  {
    os << "no mesh read" << std::endl;
  }
}
} // namespace itk
