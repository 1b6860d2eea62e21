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
#include "itkStrictTextMeshIOFactory.h"

#include "itkStrictTextMeshIO.h"
#include "itkVersion.h"

namespace itk
{
StrictTextMeshIOFactory::StrictTextMeshIOFactory()
{
  this->RegisterOverride("itkMeshIOBase",
                         "itkStrictTextMeshIO",
                         "Strict OFF, OBJ and legacy VTK mesh reader",
                         true,
                         CreateObjectFunction<StrictTextMeshIO>::New());
}

const char *
StrictTextMeshIOFactory::GetITKSourceVersion() const
{
  return ITK_SOURCE_VERSION;
}

const char *
StrictTextMeshIOFactory::GetDescription() const
{
  return "StrictTextMeshIO factory: reads OFF, OBJ and legacy VTK meshes strictly";
}

void
StrictTextMeshIOFactory::PrintSelf(std::ostream & os, Indent indent) const
{
  Superclass::PrintSelf(os, indent);
}

// Called by the factory registration that ITK generates for the modules a project loads (itk-module.cmake's
// FACTORY_NAMES MeshIO::StrictText), as ITK's own mesh IO factories are.
static bool StrictTextMeshIOFactoryHasBeenRegistered;

void FFDShapeMatching_EXPORT
StrictTextMeshIOFactoryRegister__Private()
{
  if (!StrictTextMeshIOFactoryHasBeenRegistered)
  {
    StrictTextMeshIOFactoryHasBeenRegistered = true;
    StrictTextMeshIOFactory::RegisterOneFactory();
  }
}
} // namespace itk
