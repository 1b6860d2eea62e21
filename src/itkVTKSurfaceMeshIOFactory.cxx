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
#include "itkVTKSurfaceMeshIOFactory.h"

#include "itkVTKSurfaceMeshIO.h"
#include "itkVersion.h"

namespace itk
{
VTKSurfaceMeshIOFactory::VTKSurfaceMeshIOFactory()
{
  this->RegisterOverride("itkMeshIOBase",
                         "itkVTKSurfaceMeshIO",
                         "STL, PLY and VTP mesh IO through VTK",
                         true,
                         CreateObjectFunction<VTKSurfaceMeshIO>::New());
}

const char *
VTKSurfaceMeshIOFactory::GetITKSourceVersion() const
{
  return ITK_SOURCE_VERSION;
}

const char *
VTKSurfaceMeshIOFactory::GetDescription() const
{
  return "VTKSurfaceMeshIO factory: reads and writes STL, PLY and VTP meshes through VTK";
}

void
VTKSurfaceMeshIOFactory::PrintSelf(std::ostream & os, Indent indent) const
{
  Superclass::PrintSelf(os, indent);
}

// Called by the factory registration that ITK generates for the modules a project loads (itk-module.cmake's
// FACTORY_NAMES MeshIO::VTKSurface), as ITK's own mesh IO factories are.
static bool VTKSurfaceMeshIOFactoryHasBeenRegistered;

void FFDShapeMatching_EXPORT
VTKSurfaceMeshIOFactoryRegister__Private()
{
  if (!VTKSurfaceMeshIOFactoryHasBeenRegistered)
  {
    VTKSurfaceMeshIOFactoryHasBeenRegistered = true;
    VTKSurfaceMeshIOFactory::RegisterOneFactory();
  }
}
} // namespace itk
