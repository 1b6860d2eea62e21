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
#ifndef FFDProgramMeshIO_h
#define FFDProgramMeshIO_h

// Mesh reading, writing and normalization shared by the module's command-line programs (ffd-match and the benchmark
// programs): every refusal is one line naming the file and the problem, thrown as the program's own error type.

#include "FFDInputFiles.h"
#include "FFDProgramSupport.h"
#include "itkMeshFileReader.h"
#include "itkMeshFileWriter.h"
#include "itkMeshPolygonTriangles.h"
#include "itkTriangleCell.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <system_error>

namespace ffd
{
/** The extension of \c fileName in lower case, with its dot (".stl"), or "" when it has none. */
inline std::string
LowerCaseExtension(const std::string & fileName)
{
  std::string extension = std::filesystem::path(fileName).extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(), [](unsigned char c) {
    return static_cast<char>(std::tolower(c));
  });
  return extension;
}

/** Reads the mesh \c fileName (\c role names it in messages: "source", "target", ...) and checks it: a readable,
 * non-empty regular file of at most \c maximumSize bytes (CheckInputFile: a FIFO or a device is refused before any
 * reader opens it), points present and finite, at least one triangle or polygon cell. Throws \c TError otherwise.
 * The messages VTK and ITK give while reading are kept off stderr (LibraryOutputCapture); a refusal quotes the
 * reader's exception. */
template <typename TError, typename TMesh>
typename TMesh::Pointer
ReadCheckedMesh(const std::string & fileName,
                const std::string & role,
                std::uintmax_t      maximumSize = MaximumMeshFileSize)
{
  CheckInputFile<TError>(fileName, role + " mesh", maximumSize);
  auto reader = itk::MeshFileReader<TMesh>::New();
  reader->SetFileName(fileName);
  try
  {
    LibraryOutputCapture capture; // what VTK's and ITK's readers print on stderr before they fail
    reader->Update();
  }
  catch (const std::bad_alloc &)
  {
    throw TError("not enough memory to read " + role + " mesh '" + fileName + "'");
  }
  catch (const itk::ExceptionObject & error)
  {
    throw TError("cannot read " + role + " mesh '" + fileName + "': " + OneLine(error.GetDescription()));
  }
  typename TMesh::Pointer mesh = reader->GetOutput();
  mesh->DisconnectPipeline();
  if (mesh->GetNumberOfPoints() == 0)
  {
    throw TError(role + " mesh '" + fileName + "' has no points");
  }
  for (auto it = mesh->GetPoints()->Begin(); it != mesh->GetPoints()->End(); ++it)
  {
    for (unsigned int d = 0; d < TMesh::PointDimension; ++d)
    {
      if (!std::isfinite(it.Value()[d]))
      {
        throw TError(role + " mesh '" + fileName + "' has a non-finite coordinate (vertex " +
                     std::to_string(it.Index()) + ")");
      }
    }
  }
  itk::SizeValueType faces = 0;
  if (mesh->GetCells() != nullptr)
  {
    for (auto it = mesh->GetCells()->Begin(); it != mesh->GetCells()->End(); ++it)
    {
      const auto type = it.Value()->GetType();
      if ((type == itk::CellGeometryEnum::TRIANGLE_CELL || type == itk::CellGeometryEnum::POLYGON_CELL) &&
          it.Value()->GetNumberOfPoints() >= 3)
      {
        ++faces;
      }
    }
  }
  if (faces == 0)
  {
    throw TError(role + " mesh '" + fileName + "' has no triangles");
  }
  return mesh;
}

/** Writes \c mesh to \c fileName (the format from its extension); \c shownName is the name messages use (the final
 * name when \c fileName is a temporary one). Throws \c TError on failure. */
template <typename TError, typename TMesh>
void
WriteMeshFile(const TMesh * mesh, const std::string & fileName, const std::string & shownName)
{
  auto writer = itk::MeshFileWriter<TMesh>::New();
  writer->SetInput(mesh);
  writer->SetFileName(fileName);
  try
  {
    writer->Update();
  }
  catch (const itk::ExceptionObject & error)
  {
    throw TError("cannot write mesh '" + shownName + "': " + OneLine(error.GetDescription()));
  }
}
/** Writes \c mesh as WriteMeshFile() does, then reads the file back: a full disk or a file size limit can leave a
 * cut file that a writer does not notice. Throws \c TError when the file does not read back whole (for every format
 * but STL, which does not share vertices, with the same number of points). */
template <typename TError, typename TMesh>
void
WriteCheckedMeshFile(const TMesh * mesh, const std::string & fileName, const std::string & shownName)
{
  WriteMeshFile<TError>(mesh, fileName, shownName);
  auto reader = itk::MeshFileReader<TMesh>::New();
  reader->SetFileName(fileName);
  try
  {
    reader->Update();
  }
  catch (const itk::ExceptionObject & error)
  {
    throw TError("cannot write mesh '" + shownName + "': the written file does not read back (" +
                 OneLine(error.GetDescription()) + "); is the disk full or a file size limit reached?");
  }
  if (LowerCaseExtension(fileName) != ".stl" && reader->GetOutput()->GetNumberOfPoints() != mesh->GetNumberOfPoints())
  {
    throw TError("cannot write mesh '" + shownName + "': the written file holds " +
                 std::to_string(reader->GetOutput()->GetNumberOfPoints()) + " points, not " +
                 std::to_string(mesh->GetNumberOfPoints()) + "; is the disk full or a file size limit reached?");
  }
}

/** Where ScaledTriangleCopy puts the bounding box of the mesh. */
enum class MeshPlacement
{
  LowerCornerAtOrigin, //!< the box starts at the origin (the benchmark's cases)
  CentreAtOrigin       //!< the box is centred on the origin
};

/** A copy of \c mesh scaled so the largest side of its bounding box is \c side (unscaled when \c side <= 0),
 * placed as \c placement says, with every polygon of 3 or more points split into a fan of triangles (other cells
 * are dropped). Point ids are kept. */
template <typename TMesh>
typename TMesh::Pointer
ScaledTriangleCopy(const TMesh * mesh, double side, MeshPlacement placement)
{
  constexpr unsigned int Dimension = TMesh::PointDimension;
  const auto *           bounds = mesh->GetBoundingBox();
  double                 lower[Dimension];
  double                 upper[Dimension];
  double                 largest = 0.0;
  double                 anchor[Dimension];
  for (unsigned int k = 0; k < Dimension; ++k)
  {
    lower[k] = static_cast<double>(bounds->GetMinimum()[k]);
    upper[k] = static_cast<double>(bounds->GetMaximum()[k]);
    largest = std::max(largest, upper[k] - lower[k]);
    anchor[k] = placement == MeshPlacement::CentreAtOrigin ? 0.5 * (lower[k] + upper[k]) : lower[k];
  }
  const double scale = side > 0.0 && largest > 0.0 ? side / largest : 1.0;
  auto         result = TMesh::New();
  for (auto it = mesh->GetPoints()->Begin(); it != mesh->GetPoints()->End(); ++it)
  {
    typename TMesh::PointType point;
    for (unsigned int k = 0; k < Dimension; ++k)
    {
      point[k] = (it.Value()[k] - anchor[k]) * scale;
    }
    result->SetPoint(it.Index(), point);
  }
  typename TMesh::CellIdentifier cellId = 0;
  itk::ForEachPolygonTriangle(mesh, [&](itk::IdentifierType, const typename TMesh::PointIdentifier * ids) {
    typename TMesh::CellAutoPointer triangle;
    triangle.TakeOwnership(new itk::TriangleCell<typename TMesh::CellType>);
    for (unsigned int k = 0; k < 3; ++k)
    {
      triangle->SetPointId(k, ids[k]);
    }
    result->SetCell(cellId++, triangle);
  });
  return result;
}
} // namespace ffd

#endif // FFDProgramMeshIO_h
