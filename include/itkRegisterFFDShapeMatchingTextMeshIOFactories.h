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
#ifndef itkRegisterFFDShapeMatchingTextMeshIOFactories_h
#define itkRegisterFFDShapeMatchingTextMeshIOFactories_h

#include "FFDShapeMatchingExport.h"
#include "itkObjectFactoryBase.h"

/** \file itkRegisterFFDShapeMatchingTextMeshIOFactories.h
 * \brief The module's text mesh formats without VTK: OFF, OBJ and legacy VTK (read by StrictTextMeshIO, written by
 * ITK's own mesh IOs), registered by a library that links no VTK library.
 *
 * \ingroup FFDShapeMatching
 */

namespace itk
{
/** Registers the object factory TFactory (a mesh IO factory with a static RegisterOneFactory()) unless a factory of
 * its type is registered already: calling it again, or after ITK's own automatic registration, changes nothing. */
template <typename TFactory>
void
RegisterMeshIOFactoryOnce()
{
  for (ObjectFactoryBase * factory : ObjectFactoryBase::GetRegisteredFactories())
  {
    if (dynamic_cast<TFactory *>(factory) != nullptr)
    {
      return;
    }
  }
  TFactory::RegisterOneFactory();
}

/** Registers the mesh IO factories of OFFMeshIO, OBJMeshIO, VTKPolyDataMeshIO (legacy .vtk) and StrictTextMeshIO
 * (reads .off, .obj, .vtk; registered at the front, so that it reads these files instead of ITK's IOs, which keep
 * writing them), each once (RegisterMeshIOFactoryOnce()). The VTK library's formats (.stl, .ply, .vtp) come with
 * RegisterFFDShapeMatchingMeshIOFactories(), of the FFDShapeMatchingVTKIO library. Not to be called concurrently with
 * the creation of IO objects.
 *
 * \sa RegisterFFDShapeMatchingMeshIOFactories, StrictTextMeshIOFactory
 * \ingroup FFDShapeMatching
 */
FFDShapeMatching_EXPORT void
RegisterFFDShapeMatchingTextMeshIOFactories();
} // namespace itk

#endif // itkRegisterFFDShapeMatchingTextMeshIOFactories_h
