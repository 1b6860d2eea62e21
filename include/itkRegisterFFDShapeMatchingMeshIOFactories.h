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
#ifndef itkRegisterFFDShapeMatchingMeshIOFactories_h
#define itkRegisterFFDShapeMatchingMeshIOFactories_h

#include "FFDShapeMatchingExport.h"

/** \file itkRegisterFFDShapeMatchingMeshIOFactories.h
 * \brief One call that makes MeshFileReader and MeshFileWriter handle every mesh format of the
 * module's programs: OFF, OBJ and legacy VTK (read by StrictTextMeshIO, written by ITK's own
 * mesh IOs) and STL, PLY and VTP (VTKSurfaceMeshIO).
 *
 * \ingroup FFDShapeMatching
 */

namespace itk
{
/** Registers the mesh IO factories of OFFMeshIO, OBJMeshIO, VTKPolyDataMeshIO (legacy .vtk),
 * VTKSurfaceMeshIO (.stl, .ply, .vtp) and StrictTextMeshIO (reads .off, .obj, .vtk; registered
 * at the front, so that it reads these files instead of ITK's IOs, which keep writing them)
 * with ITK's object factory, each one only when no
 * factory of its type is registered yet, so calling it again (or after ITK's own automatic
 * registration) changes nothing. Not to be called concurrently with the creation of IO
 * objects.
 *
 * \code
 * itk::RegisterFFDShapeMatchingMeshIOFactories();
 * auto reader = itk::MeshFileReader<itk::Mesh<double, 3>>::New();
 * reader->SetFileName("source.ply");
 * reader->Update();
 * \endcode
 *
 * \sa VTKSurfaceMeshIOFactory
 * \ingroup FFDShapeMatching
 */
FFDShapeMatching_EXPORT void
RegisterFFDShapeMatchingMeshIOFactories();
} // namespace itk

#endif // itkRegisterFFDShapeMatchingMeshIOFactories_h
