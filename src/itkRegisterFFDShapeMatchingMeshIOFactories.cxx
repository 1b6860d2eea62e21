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
#include "itkRegisterFFDShapeMatchingMeshIOFactories.h"

#include "itkOBJMeshIOFactory.h"
#include "itkOFFMeshIOFactory.h"
#include "itkStrictTextMeshIOFactory.h"
#include "itkVTKPolyDataMeshIOFactory.h"
#include "itkVTKSurfaceMeshIOFactory.h"

namespace itk
{
namespace
{
/** Registers a factory of type TFactory unless one is registered already. */
template <typename TFactory>
void
RegisterFactoryOnce()
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
} // namespace

void
RegisterFFDShapeMatchingMeshIOFactories()
{
  RegisterFactoryOnce<OFFMeshIOFactory>();
  RegisterFactoryOnce<OBJMeshIOFactory>();
  RegisterFactoryOnce<VTKPolyDataMeshIOFactory>();
  RegisterFactoryOnce<VTKSurfaceMeshIOFactory>();
  // Inserted at the front: MeshIOFactory asks the IOs in registration order, so the strict
  // reader takes .off, .obj and .vtk files before ITK's IOs above (which still write them).
  RegisterFactoryOnce<StrictTextMeshIOFactory>();
}
} // namespace itk
