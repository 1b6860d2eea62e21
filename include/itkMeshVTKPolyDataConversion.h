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
#ifndef itkMeshVTKPolyDataConversion_h
#define itkMeshVTKPolyDataConversion_h

#include "FFDShapeMatchingExport.h"
#include "itkMesh.h"

#include <string>

class vtkPolyData;

/** \file itkMeshVTKPolyDataConversion.h
 * \brief Conversion between vtkPolyData and the triangle meshes of the module, for rendering,
 * distance computations and benchmarks.
 *
 * Two mesh types are served, each by an overload: ITK's default itk::Mesh<double, 3> (float
 * coordinates) and the double-coordinate mesh
 * itk::Mesh<double, 3, itk::DefaultStaticMeshTraits<double, 3, 3, double, double, double>>.
 * The point order is kept and coordinates are copied without rounding beyond the mesh's own
 * coordinate type, so a triangle mesh converted to vtkPolyData and back is the same mesh. Only
 * vtkPolyData is forward-declared here: code that calls these functions includes the VTK
 * headers it uses itself.
 *
 * \code
 * auto polyData = vtkSmartPointer<vtkPolyData>::New();
 * itk::MeshToVTKPolyData(mesh, polyData, "distance");
 * auto back = itk::Mesh<double, 3>::New();
 * itk::VTKPolyDataToMesh(polyData, back, "distance");
 * \endcode
 *
 * \ingroup FFDShapeMatching
 */

namespace itk
{
/** Fills mesh (replacing what it held) with the points and polygons of polyData: the points
 * with the same ids and coordinates; the triangles of its polygons and triangle strips, in
 * order (polygons with more than three points and strips are triangulated by
 * vtkTriangleFilter, degenerate ones may vanish); vertex and line cells are dropped. Point
 * data: the single-component point array named pointDataArrayName when that name is not empty
 * (an exception if it is missing or has several components), otherwise the active scalars when
 * they have one component, otherwise none. Cell data is not converted. Throws an
 * ExceptionObject when polyData or mesh is null.
 *
 * \ingroup FFDShapeMatching
 */
FFDShapeMatching_EXPORT void
VTKPolyDataToMesh(vtkPolyData * polyData, Mesh<double, 3> * mesh, const std::string & pointDataArrayName = "");

/** The same for the double-coordinate mesh. */
FFDShapeMatching_EXPORT void
VTKPolyDataToMesh(vtkPolyData *                                                                    polyData,
                  Mesh<double, 3, DefaultStaticMeshTraits<double, 3, 3, double, double, double>> * mesh,
                  const std::string & pointDataArrayName = "");

/** Fills polyData (replacing what it held) with the points and cells of mesh: double points
 * with the same ids; triangles, quadrilaterals and polygons as polygons, line cells as lines
 * and vertex cells as vertices (VTK keeps vertices, lines and polygons in separate lists, so a
 * mesh mixing them comes back grouped by kind; a mesh of one kind keeps its cell order). When
 * the mesh has point data, it becomes a one-component double array named pointDataArrayName,
 * set as the active scalars (points without a value get NaN). Cell data is not converted.
 * Throws an ExceptionObject when mesh or polyData is null, when a cell is a volume or quadratic
 * cell, or when a cell refers to a point the mesh does not have.
 *
 * \ingroup FFDShapeMatching
 */
FFDShapeMatching_EXPORT void
MeshToVTKPolyData(const Mesh<double, 3> * mesh,
                  vtkPolyData *           polyData,
                  const std::string &     pointDataArrayName = "PointData");

/** The same for the double-coordinate mesh. */
FFDShapeMatching_EXPORT void
MeshToVTKPolyData(const Mesh<double, 3, DefaultStaticMeshTraits<double, 3, 3, double, double, double>> * mesh,
                  vtkPolyData *                                                                          polyData,
                  const std::string & pointDataArrayName = "PointData");
} // namespace itk

#endif // itkMeshVTKPolyDataConversion_h
