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
#ifndef itkVTKSurfaceMeshIO_h
#define itkVTKSurfaceMeshIO_h

#include "itkFFDShapeMatchingCompatibility.h"
#include "FFDShapeMatchingExport.h"
#include "itkMeshIOBase.h"

#include <memory>
#include <string>

namespace itk
{
namespace detail
{
struct VTKSurfaceMeshIOInternals;
} // namespace detail

/** \class VTKSurfaceMeshIO
 * \brief Reads and writes surface meshes in the STL, PLY and VTK XML PolyData (VTP) formats
 * through VTK's readers and writers.
 *
 * ITK 5.2 reads and writes OFF, OBJ and legacy VTK meshes (OFFMeshIO, OBJMeshIO,
 * VTKPolyDataMeshIO) but none of the formats above; this class adds them to MeshFileReader and
 * MeshFileWriter. Register it once with VTKSurfaceMeshIOFactory::RegisterOneFactory() (or
 * RegisterFFDShapeMatchingMeshIOFactories(), which registers ITK's OFF, OBJ and VTK mesh IOs
 * too); the format is chosen by the file name extension, ".stl", ".ply" or ".vtp" in any
 * letter case. VTK stays out of this header: user code needs no VTK include paths.
 *
 * \par Reading
 * The whole file is read by ReadMeshInformation() (vtkSTLReader, vtkPLYReader,
 * vtkXMLPolyDataReader), then handed over point by point and cell by cell:
 * - points as double coordinates, in the file's order (vtkSTLReader merges the coincident
 *   corners of an STL file's facets into shared points);
 * - cells as triangles only: polygons with more than three points and triangle strips are
 *   triangulated (vtkTriangleFilter), vertex and line cells are dropped and counted in
 *   GetNumberOfDroppedCells(); a file with points and no polygons gives a mesh without cells;
 * - point data: one value per point, as double, from the single-component array named
 *   PointDataArrayName if the file has one, else from the active scalars if they have one
 *   component; other point arrays (normals, colors, ...) and all cell data are not read.
 *
 * A file that cannot be read ends in an ExceptionObject whose description names the file and
 * the problem (the message VTK reported, a binary STL shorter than its triangle count needs,
 * a PLY file without its "ply" signature, a file without points); VTK's own messages are
 * caught and never printed. CanReadFile() checks the extension and that the file exists and
 * can be opened, and leaves the content to ReadMeshInformation(), so that a damaged file is
 * reported with its problem rather than as a file no IO can read.
 *
 * \par Writing
 * Files are always written binary (binary STL, binary little-endian PLY, appended raw VTP;
 * MeshFileWriter's default ASCII file type cannot be told from an explicit request, so it is
 * ignored). Triangles, quadrilaterals and polygons become polygons, line cells lines and vertex
 * cells vertices; volume and quadratic cells are refused. STL stores triangles and float
 * coordinates only: polygons are triangulated, lines and vertices and point data are not
 * written, and points are merged on reading. PLY stores float coordinates and polygons; point
 * data is not written. VTP keeps double coordinates, all cells and the point data (as an array
 * named PointDataArrayName, made the active scalars when it has one component); compression
 * (zlib) follows MeshIOBase::UseCompression. Cell data is not written to any format.
 *
 * \par Threads
 * While VTK reads or writes, VTK's process-wide output window is replaced to catch its
 * messages, so the VTK calls of all instances of this class are serialized by a process-wide
 * mutex.
 *
 * \sa VTKSurfaceMeshIOFactory, RegisterFFDShapeMatchingMeshIOFactories, MeshFileReader,
 * MeshFileWriter, OFFMeshIO, VTKPolyDataMeshIO
 *
 * \ingroup FFDShapeMatching
 */
class FFDShapeMatching_EXPORT VTKSurfaceMeshIO : public MeshIOBase
{
public:
  ITK_DISALLOW_COPY_AND_MOVE(VTKSurfaceMeshIO);

  /** Standard class type aliases. */
  using Self = VTKSurfaceMeshIO;
  using Superclass = MeshIOBase;
  using Pointer = SmartPointer<Self>;
  using ConstPointer = SmartPointer<const Self>;

  using SizeValueType = Superclass::SizeValueType;

  /** Method for creation through the object factory. */
  itkNewMacro(Self);

  /** Run-time type information (and related methods). */
  itkOverrideGetNameOfClassMacro(VTKSurfaceMeshIO);

  /** Name of the point data array: the array read as point data when the file has a
   * single-component array of that name (otherwise the single-component active scalars are
   * read), and the name given to the point data written to VTP files. Default: "PointData". */
  itkSetStringMacro(PointDataArrayName);
  itkGetStringMacro(PointDataArrayName);

  /** Number of vertex and line cells of the last file read that were dropped because the mesh
   * receives triangles only. */
  itkGetConstMacro(NumberOfDroppedCells, SizeValueType);

  /*-------- Reading ----- */

  /** True when fileName ends with ".stl", ".ply" or ".vtp" (any letter case) and names an
   * existing file that can be opened. */
  bool
  CanReadFile(const char * fileName) override;

  /** Reads the whole file and sets the numbers of points, cells and point values, and their
   * component types (double coordinates and point values, IdentifierType cell buffer). Throws
   * an ExceptionObject naming the file and the problem when the file cannot be read or holds
   * no points. */
  void
  ReadMeshInformation() override;

  /** Copies the point coordinates (double, three per point) into buffer. */
  void
  ReadPoints(void * buffer) override;

  /** Copies the cells into buffer as [TRIANGLE_CELL, 3, id0, id1, id2] per cell
   * (IdentifierType values). */
  void
  ReadCells(void * buffer) override;

  /** Copies the point data (double, one value per point) into buffer. */
  void
  ReadPointData(void * buffer) override;

  /** Cell data is never read (the cells are rebuilt by triangulation): announces none and
   * copies nothing. */
  void
  ReadCellData(void * buffer) override;

  /*-------- Writing ----- */

  /** True when fileName ends with ".stl", ".ply" or ".vtp" (any letter case). */
  bool
  CanWriteFile(const char * fileName) override;

  /** Checks the file format and the point dimension (2 or 3) and prepares the output. */
  void
  WriteMeshInformation() override;

  /** Takes the point coordinates, of the PointComponentType, PointDimension per point. */
  void
  WritePoints(void * buffer) override;

  /** Takes the cells, of the CellComponentType, as [cell type, number of points, ids...]. */
  void
  WriteCells(void * buffer) override;

  /** Takes the point data, of the PointPixelComponentType (VTP files only keep it). */
  void
  WritePointData(void * buffer) override;

  /** Cell data is not written: ignores buffer. */
  void
  WriteCellData(void * buffer) override;

  /** Writes the file with VTK. Throws an ExceptionObject naming the file and the problem when
   * a cell refers to a missing point, there is nothing the format can store, or VTK fails. */
  void
  Write() override;

protected:
  VTKSurfaceMeshIO();
  ~VTKSurfaceMeshIO() override;

  void
  PrintSelf(std::ostream & os, Indent indent) const override;

private:
  /** "STL", "PLY" or "VTP" for a file name with that extension (any case), else "". */
  static std::string
  FormatOfFileName(const std::string & fileName);

  std::string                                        m_PointDataArrayName{ "PointData" };
  SizeValueType                                      m_NumberOfDroppedCells{ 0 };
  std::unique_ptr<detail::VTKSurfaceMeshIOInternals> m_Internals;
};
} // namespace itk

#endif // itkVTKSurfaceMeshIO_h
