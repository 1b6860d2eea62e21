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
#ifndef itkStrictTextMeshIO_h
#define itkStrictTextMeshIO_h

#include "itkFFDShapeMatchingCompatibility.h"
#include "FFDShapeMatchingExport.h"
#include "itkMeshIOBase.h"

#include <memory>
#include <string>

namespace itk
{
namespace detail
{
struct StrictTextMeshIOInternals;
} // namespace detail

/** \class StrictTextMeshIO
 * \brief Reads OFF, OBJ and legacy VTK POLYDATA meshes strictly: every damaged file ends in an
 * ExceptionObject naming the file, the line and the problem.
 *
 * ITK 5.2's OFFMeshIO, OBJMeshIO and VTKPolyDataMeshIO read these formats with stream
 * extraction and no checks: a malformed number becomes 0 or stops the stream silently, a
 * truncated file gives a misleading cell error, and a "NaN" in a legacy VTK file makes
 * VTKPolyDataMeshIO loop forever. This class reads the same files into the same meshes, but
 * parses the whole file in ReadMeshInformation() and accepts it only when it is complete and
 * consistent:
 * - every coordinate is a finite number (and fits a float when a VTK file declares floats);
 * - the counts announced (OFF header, VTK section headers) match the data, and the file holds
 *   nothing after the data it announces (OFF);
 * - every vertex index is an integer referring to an existing vertex;
 * - every face has at least 3 vertices, every line at least 2 points.
 *
 * Messages read like <tt>Cannot read OFF file "x.off": line 7: expected 3 coordinates of vertex
 * 4, found "ten"</tt>. Vertices, faces and cells are numbered from 0 in OFF and VTK files and
 * from 1 in OBJ files, as the files themselves number them.
 *
 * \par Formats and the meshes they give
 * - OFF (".off"): the ASCII "OFF" format; the header may share its line with the counts, '#'
 *   starts a comment, values after a vertex's 3 coordinates or a face's indices (colors) are
 *   ignored. The COFF, NOFF, 4OFF, nOFF, STOFF variants and binary OFF are refused with a message
 *   saying so. Faces become TRIANGLE_CELL when all faces are triangles, POLYGON_CELL otherwise
 *   (as OFFMeshIO does). Coordinates: double (ITK's OFFMeshIO reads float, which moves a vertex
 *   1e7 mm from the origin by up to 0.5 mm).
 * - OBJ (".obj"): "v" lines (3 coordinates; a 4th weight or vertex colors are ignored) and "f"
 *   lines, with the "i", "i/t", "i//n", "i/t/n" forms and negative (relative) indices. Faces
 *   become POLYGON_CELL (as OBJMeshIO does; MeshFileReader makes a triangle of a 3-point
 *   polygon). Normals, texture coordinates, lines, groups and materials are not read; unknown
 *   statements are refused. Coordinates: double.
 * - Legacy VTK (".vtk"): "# vtk DataFile Version" files, ASCII or BINARY (big-endian), DATASET
 *   POLYDATA with POINTS and VERTICES, LINES, POLYGONS, TRIANGLE_STRIPS in the classic
 *   (count + indices) or the version 5 (OFFSETS + CONNECTIVITY) layout. Vertices become
 *   VERTEX_CELL (one per point of a poly-vertex), lines LINE_CELL, polygons POLYGON_CELL (as
 *   VTKPolyDataMeshIO does) and each triangle of a strip a TRIANGLE_CELL. POINT_DATA: the first
 *   one-component SCALARS array is read as point data (double); the other point and cell
 *   attributes are checked for length and skipped; a METADATA block ends the reading. Other
 *   datasets (UNSTRUCTURED_GRID, ...) are refused. Coordinates: double, except binary float data
 *   (float); ASCII values declared float must fit a float and keep all their digits.
 *
 * A complete file that announces no vertices ("OFF 0 0 0", "POINTS 0 float") gives an empty
 * mesh, as with ITK's readers, for the caller to judge; an empty file or an OBJ file without
 * "v" lines is refused. Degenerate faces (repeated or collinear vertices) and
 * duplicate faces are kept, as ITK's readers keep them: checking geometry is left to the
 * mesh's users.
 *
 * CanReadFile() checks the extension (".off", ".obj", ".vtk", any letter case) and that the file
 * exists and can be opened, and leaves the content to ReadMeshInformation(), so that a damaged
 * file is reported with its problem rather than as a file no IO can read. Register this IO ahead
 * of ITK's with StrictTextMeshIOFactory::RegisterOneFactory() or
 * RegisterFFDShapeMatchingMeshIOFactories(). Writing stays with ITK's IOs: CanWriteFile() is
 * always false.
 *
 * \sa StrictTextMeshIOFactory, RegisterFFDShapeMatchingMeshIOFactories, OFFMeshIO, OBJMeshIO,
 * VTKPolyDataMeshIO, VTKSurfaceMeshIO
 *
 * \ingroup FFDShapeMatching
 */
class FFDShapeMatching_EXPORT StrictTextMeshIO : public MeshIOBase
{
public:
  ITK_DISALLOW_COPY_AND_MOVE(StrictTextMeshIO);

  /** Standard class type aliases. */
  using Self = StrictTextMeshIO;
  using Superclass = MeshIOBase;
  using Pointer = SmartPointer<Self>;
  using ConstPointer = SmartPointer<const Self>;

  using SizeValueType = Superclass::SizeValueType;

  /** Method for creation through the object factory. */
  itkNewMacro(Self);

  /** Run-time type information (and related methods). */
  itkOverrideGetNameOfClassMacro(StrictTextMeshIO);

  /*-------- Reading ----- */

  /** True when fileName ends with ".off", ".obj" or ".vtk" (any letter case) and names an
   * existing file that can be opened. */
  bool
  CanReadFile(const char * fileName) override;

  /** Reads and checks the whole file, then sets the numbers of points, cells and point values and
   * their component types. Throws an ExceptionObject naming the file, the line and the problem
   * when the file is damaged or of an unsupported variant. */
  void
  ReadMeshInformation() override;

  /** Copies the point coordinates (float or double, as GetPointComponentType() says, three per
   * point) into buffer. */
  void
  ReadPoints(void * buffer) override;

  /** Copies the cells into buffer as [cell type, number of points, ids...] per cell
   * (IdentifierType values). */
  void
  ReadCells(void * buffer) override;

  /** Copies the point data (double, one value per point) into buffer. */
  void
  ReadPointData(void * buffer) override;

  /** Cell data is not read: announces none and copies nothing. */
  void
  ReadCellData(void * buffer) override;

  /*-------- Writing (left to ITK's IOs) ----- */

  /** Always false: OFFMeshIO, OBJMeshIO and VTKPolyDataMeshIO write these formats. */
  bool
  CanWriteFile(const char * fileName) override;

  /** Throws: this IO does not write. */
  void
  WriteMeshInformation() override;

  /** Throws: this IO does not write. */
  void
  WritePoints(void * buffer) override;

  /** Throws: this IO does not write. */
  void
  WriteCells(void * buffer) override;

  /** Throws: this IO does not write. */
  void
  WritePointData(void * buffer) override;

  /** Throws: this IO does not write. */
  void
  WriteCellData(void * buffer) override;

  /** Throws: this IO does not write. */
  void
  Write() override;

protected:
  StrictTextMeshIO();
  ~StrictTextMeshIO() override;

  void
  PrintSelf(std::ostream & os, Indent indent) const override;

private:
  /** "OFF", "OBJ" or "VTK" for a file name with that extension (any case), else "". */
  static std::string
  FormatOfFileName(const std::string & fileName);

  std::unique_ptr<detail::StrictTextMeshIOInternals> m_Internals;
};
} // namespace itk

#endif // itkStrictTextMeshIO_h
