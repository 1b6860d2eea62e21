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
#include "itkRegisterFFDShapeMatchingTextMeshIOFactories.h"

#include "itkOBJMeshIOFactory.h"
#include "itkOFFMeshIOFactory.h"
#include "itkStrictTextMeshIOFactory.h"
#include "itkVTKPolyDataMeshIOFactory.h"

namespace itk
{
void
RegisterFFDShapeMatchingTextMeshIOFactories()
{
  RegisterMeshIOFactoryOnce<OFFMeshIOFactory>();
  RegisterMeshIOFactoryOnce<OBJMeshIOFactory>();
  RegisterMeshIOFactoryOnce<VTKPolyDataMeshIOFactory>();
  // Inserted at the front: MeshIOFactory asks the IOs in registration order, so the strict
  // reader takes .off, .obj and .vtk files before ITK's IOs above (which still write them).
  RegisterMeshIOFactoryOnce<StrictTextMeshIOFactory>();
}
} // namespace itk
