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
#ifndef itkStrictTextMeshIOFactory_h
#define itkStrictTextMeshIOFactory_h

#include "itkFFDShapeMatchingCompatibility.h"
#include "FFDShapeMatchingExport.h"
#include "itkObjectFactoryBase.h"

namespace itk
{
/** \class StrictTextMeshIOFactory
 * \brief Creates StrictTextMeshIO objects through ITK's object factory, so that MeshFileReader
 * reads OFF, OBJ and legacy VTK files strictly.
 *
 * ITK's MeshIOFactory asks the registered IOs in registration order and takes the first that
 * can read the file, so this factory must come before OFFMeshIOFactory, OBJMeshIOFactory and
 * VTKPolyDataMeshIOFactory: RegisterOneFactory() inserts it at the front of the list.
 *
 * \code
 * itk::StrictTextMeshIOFactory::RegisterOneFactory();
 * using ReaderType = itk::MeshFileReader<itk::Mesh<double, 3>>;
 * auto reader = ReaderType::New();
 * reader->SetFileName("surface.off");
 * reader->Update(); // throws, naming the line and the problem, if the file is damaged
 * \endcode
 *
 * \sa StrictTextMeshIO, RegisterFFDShapeMatchingMeshIOFactories, OFFMeshIOFactory
 *
 * \ingroup FFDShapeMatching
 */
class FFDShapeMatching_EXPORT StrictTextMeshIOFactory : public ObjectFactoryBase
{
public:
  ITK_DISALLOW_COPY_AND_MOVE(StrictTextMeshIOFactory);

  /** Standard class type aliases. */
  using Self = StrictTextMeshIOFactory;
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
  itkOverrideGetNameOfClassMacro(StrictTextMeshIOFactory);

  /** Registers one factory of this type at the front of the factory list, ahead of ITK's own
   * OFF, OBJ and VTK mesh IO factories (each call registers one more;
   * RegisterFFDShapeMatchingMeshIOFactories() registers only what is missing). */
  static void
  RegisterOneFactory()
  {
    auto factory = StrictTextMeshIOFactory::New();
    ObjectFactoryBase::RegisterFactory(factory, ObjectFactoryEnums::InsertionPosition::INSERT_AT_FRONT);
  }

protected:
  StrictTextMeshIOFactory();
  ~StrictTextMeshIOFactory() override = default;

  void
  PrintSelf(std::ostream & os, Indent indent) const override;
};
} // namespace itk

#endif // itkStrictTextMeshIOFactory_h
