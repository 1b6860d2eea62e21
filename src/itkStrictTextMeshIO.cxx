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
#include "itkStrictTextParsing.h"

#include "itkMacro.h"
#include "itksys/SystemTools.hxx"

#include <algorithm>
#include <fstream>
#include <iterator>

namespace itk
{
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
  const std::string extension = detail::StrictText::Upper(itksys::SystemTools::GetFilenameLastExtension(fileName));
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
      detail::StrictText::ParseOFF(text, mesh);
    }
    else if (format == "OBJ")
    {
      detail::StrictText::ParseOBJ(text, mesh);
    }
    else
    {
      detail::StrictText::ParseLegacyVTK(text, mesh);
    }
  }
  catch (const detail::StrictText::ParseError & error)
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