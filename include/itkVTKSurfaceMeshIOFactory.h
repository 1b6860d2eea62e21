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
#ifndef itkVTKSurfaceMeshIOFactory_h
#define itkVTKSurfaceMeshIOFactory_h

#include "itkFFDShapeMatchingCompatibility.h"
#include "FFDShapeMatchingExport.h"
#include "itkObjectFactoryBase.h"

namespace itk
{
/** \class VTKSurfaceMeshIOFactory
 * \brief Creates VTKSurfaceMeshIO objects through ITK's object factory, so that MeshFileReader
 * and MeshFileWriter handle STL, PLY and VTP files.
 *
 * \code
 * itk::VTKSurfaceMeshIOFactory::RegisterOneFactory();
 * using ReaderType = itk::MeshFileReader<itk::Mesh<double, 3>>;
 * auto reader = ReaderType::New();
 * reader->SetFileName("surface.stl");
 * reader->Update();
 * \endcode
 *
 * \sa VTKSurfaceMeshIO, RegisterFFDShapeMatchingMeshIOFactories, OFFMeshIOFactory
 *
 * \ingroup FFDShapeMatching
 */
class FFDShapeMatching_EXPORT VTKSurfaceMeshIOFactory : public ObjectFactoryBase
{
public:
  ITK_DISALLOW_COPY_AND_MOVE(VTKSurfaceMeshIOFactory);

  /** Standard class type aliases. */
  using Self = VTKSurfaceMeshIOFactory;
  using Superclass = ObjectFactoryBase;
  using Pointer = SmartPointer<Self>;
  using ConstPointer = SmartPointer<const Self>;

  /** The ITK version this factory was built with. */
  const char *
  GetITKSourceVersion() const override;

  /** A one-line description of the factory. */
  const char *
  GetDescription() const override;

  /** Method for class instantiation. */
  itkFactorylessNewMacro(Self);

  /** Run-time type information (and related methods). */
  itkOverrideGetNameOfClassMacro(VTKSurfaceMeshIOFactory);

  /** Registers one factory of this type (each call registers one more, as ITK's IO factories
   * do; RegisterFFDShapeMatchingMeshIOFactories() registers only what is missing). */
  static void
  RegisterOneFactory()
  {
    auto factory = VTKSurfaceMeshIOFactory::New();
    ObjectFactoryBase::RegisterFactoryInternal(factory);
  }

protected:
  VTKSurfaceMeshIOFactory();
  ~VTKSurfaceMeshIOFactory() override = default;

  void
  PrintSelf(std::ostream & os, Indent indent) const override;
};
} // namespace itk

#endif // itkVTKSurfaceMeshIOFactory_h
