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
#ifndef itkMeshRegistrationMethodBase_hxx
#define itkMeshRegistrationMethodBase_hxx

namespace itk
{
template <typename TFixedMesh, typename TMovingMesh>
MeshRegistrationMethodBase<TFixedMesh, TMovingMesh>::MeshRegistrationMethodBase(bool movingMeshRequired)
{
  this->SetPrimaryInputName("FixedMesh");
  if (movingMeshRequired)
  {
    this->AddRequiredInputName("MovingMesh", 1);
  }
  else
  {
    this->AddOptionalInputName("MovingMesh", 1);
  }
  this->SetNumberOfRequiredOutputs(1);
  this->SetNthOutput(0, this->MakeOutput(0));
}

template <typename TFixedMesh, typename TMovingMesh>
ProcessObject::DataObjectPointer
MeshRegistrationMethodBase<TFixedMesh, TMovingMesh>::MakeOutput(DataObjectPointerArraySizeType)
{
  return DecoratedTransformType::New().GetPointer();
}

template <typename TFixedMesh, typename TMovingMesh>
auto
MeshRegistrationMethodBase<TFixedMesh, TMovingMesh>::GetTransformOutput() const -> const DecoratedTransformType *
{
  return static_cast<const DecoratedTransformType *>(this->ProcessObject::GetOutput(0));
}

template <typename TFixedMesh, typename TMovingMesh>
auto
MeshRegistrationMethodBase<TFixedMesh, TMovingMesh>::GetTransform() const -> const TransformType *
{
  return this->GetTransformOutput()->Get();
}

template <typename TFixedMesh, typename TMovingMesh>
void
MeshRegistrationMethodBase<TFixedMesh, TMovingMesh>::SetTransformOutputValue(const TransformType * transform)
{
  static_cast<DecoratedTransformType *>(this->ProcessObject::GetOutput(0))->Set(transform);
}

template <typename TFixedMesh, typename TMovingMesh>
void
MeshRegistrationMethodBase<TFixedMesh, TMovingMesh>::PrintSelf(std::ostream & os, Indent indent) const
{
  Superclass::PrintSelf(os, indent);
  os << indent << "RandomSeed: " << m_RandomSeed << std::endl;
}
} // namespace itk

#endif // itkMeshRegistrationMethodBase_hxx
