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
#ifndef itkMeshRegistrationMethodBase_h
#define itkMeshRegistrationMethodBase_h

#include "itkFFDShapeMatchingCompatibility.h"
#include "itkDataObjectDecorator.h"
#include "itkProcessObject.h"
#include "itkTransform.h"

namespace itk
{
/** \class MeshRegistrationMethodBase
 * \brief What the module's registration methods on meshes share: the fixed mesh (target) and moving mesh (source)
 * inputs, the estimated transform (fixed space -> moving space) as a decorated output, and the seed of their random
 * samples.
 *
 * The derived methods (MeshPoseRegistrationMethod, BSplineCoherentPointDriftRegistrationMethod,
 * ParametricTemplateRegistrationMethod) add their own inputs and settings and set the output in GenerateData()
 * (SetTransformOutputValue()). As ITK's registration methods, the transform maps points of the fixed mesh into the
 * moving mesh's space.
 *
 * \ingroup FFDShapeMatching
 */
template <typename TFixedMesh, typename TMovingMesh>
class ITK_TEMPLATE_EXPORT MeshRegistrationMethodBase : public ProcessObject
{
public:
  ITK_DISALLOW_COPY_AND_MOVE(MeshRegistrationMethodBase);

  using Self = MeshRegistrationMethodBase;
  using Superclass = ProcessObject;
  using Pointer = SmartPointer<Self>;
  using ConstPointer = SmartPointer<const Self>;

  itkOverrideGetNameOfClassMacro(MeshRegistrationMethodBase);

  static constexpr unsigned int Dimension = TFixedMesh::PointDimension;

  using FixedMeshType = TFixedMesh;
  using MovingMeshType = TMovingMesh;
  using TransformType = Transform<double, Dimension, Dimension>;
  using DecoratedTransformType = DataObjectDecorator<TransformType>;

  /** The fixed mesh (target). */
  itkSetInputMacro(FixedMesh, FixedMeshType);
  itkGetInputMacro(FixedMesh, FixedMeshType);

  /** The moving mesh (source); required unless the derived method says otherwise. */
  itkSetInputMacro(MovingMesh, MovingMeshType);
  itkGetInputMacro(MovingMesh, MovingMeshType);

  /** The estimated transform, fixed space to moving space, as a decorated output. */
  const DecoratedTransformType *
  GetTransformOutput() const;

  /** The estimated transform itself (null before Update()). */
  const TransformType *
  GetTransform() const;

  /** Seed of the method's random samples. Default: 121212. */
  itkSetMacro(RandomSeed, int);
  itkGetConstMacro(RandomSeed, int);

protected:
  /** \c movingMeshRequired: whether Update() needs the moving mesh (a method may take its moving shape otherwise). */
  explicit MeshRegistrationMethodBase(bool movingMeshRequired = true);
  ~MeshRegistrationMethodBase() override = default;

  void
  PrintSelf(std::ostream & os, Indent indent) const override;

  using DataObjectPointerArraySizeType = ProcessObject::DataObjectPointerArraySizeType;
  using Superclass::MakeOutput;
  ProcessObject::DataObjectPointer
  MakeOutput(DataObjectPointerArraySizeType index) override;

  /** Sets the decorated output's transform. */
  void
  SetTransformOutputValue(const TransformType * transform);

private:
  int m_RandomSeed{ 121212 };
};
} // namespace itk

#ifndef ITK_MANUAL_INSTANTIATION
#  include "itkMeshRegistrationMethodBase.hxx"
#endif

#endif // itkMeshRegistrationMethodBase_h
