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
#include "itkVTKSurfaceFileChecks.h"
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
#include "vtkXMLDataParser.h"
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
  const auto readerFailed = [&capture, &reader]() { return capture.HasErrors() || reader->GetErrorCode() != 0; };
  try
  {
    if constexpr (std::is_base_of<vtkXMLReader, TReader>::value)
    {
      // The element tree first (no array is read yet): VTK's XML reader leaks what it read from points that do not
      // have 3 components, so such a file is refused before its data are read.
      reader->UpdateInformation();
      if (!readerFailed())
      {
        vtkXMLDataParser * parser = reader->GetXMLParser();
        problem = detail::CheckVTPPointsArrays(parser == nullptr ? nullptr : parser->GetRootElement());
      }
    }
    if (problem.empty() && !readerFailed())
    {
      reader->Update();
    }
  }
  catch (const std::exception & error)
  {
    problem = error.what();
    return nullptr;
  }
  if (!problem.empty())
  {
    return nullptr;
  }
  vtkSmartPointer<vtkPolyData> output = reader->GetOutput();
  const bool                   noPoints = output == nullptr || output->GetNumberOfPoints() == 0;
  if (readerFailed() || (noPoints && capture.HasWarnings()))
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

  std::string                  problem = format == "STL"   ? detail::CheckSTLFile(m_FileName)
                                         : format == "PLY" ? detail::CheckPLYFile(m_FileName)
                                                           : detail::CheckVTPFile(m_FileName);
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
