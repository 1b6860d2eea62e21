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
#ifndef itkMeshOpenBoundaryMaskImageFilter_h
#define itkMeshOpenBoundaryMaskImageFilter_h

#include "itkFFDShapeMatchingCompatibility.h"
#include "itkImageToImageFilter.h"
#include "itkMesh.h"

namespace itk
{
/** \class MeshOpenBoundaryMaskImageFilter
 * \brief Clears the voxels of a mask that lie within a radius of a mesh's open boundary.
 *
 * The open boundary of a polygon mesh is the set of its edges used by exactly one triangle or polygon (the rim of
 * a cut-out surface patch). The output is the input mask with every non-zero voxel whose centre lies closer than
 * Radius to such an edge set to zero; other voxels are copied. The exact point-to-segment distance decides, and
 * only the voxels inside each edge's bounding box (grown by Radius) are visited.
 *
 * Shape matching uses it on the band mask of a partial target: near the rim of a cut-out patch, the distance to the
 * patch differs from the distance to the whole source surface whatever the deformation, so those voxels are left
 * out of the metric.
 *
 * The mesh is the second input (SetMesh()); GetNumberOfOpenBoundaryEdges() counts its open edges after Update().
 *
 * \sa TriangleMeshToVoxelImageFilter
 * \ingroup FFDShapeMatching
 */
template <typename TMaskImage, typename TMesh>
class ITK_TEMPLATE_EXPORT MeshOpenBoundaryMaskImageFilter : public ImageToImageFilter<TMaskImage, TMaskImage>
{
public:
  ITK_DISALLOW_COPY_AND_MOVE(MeshOpenBoundaryMaskImageFilter);

  using Self = MeshOpenBoundaryMaskImageFilter;
  using Superclass = ImageToImageFilter<TMaskImage, TMaskImage>;
  using Pointer = SmartPointer<Self>;
  using ConstPointer = SmartPointer<const Self>;

  itkNewMacro(Self);
  itkOverrideGetNameOfClassMacro(MeshOpenBoundaryMaskImageFilter);

  using MaskImageType = TMaskImage;
  using MeshType = TMesh;

  static_assert(MaskImageType::ImageDimension == MeshType::PointDimension,
                "The mask and the mesh must have the same dimension.");

  /** The mesh whose open boundary is cut out of the mask (required). */
  itkSetInputMacro(Mesh, MeshType);
  itkGetInputMacro(Mesh, MeshType);

  /** Distance (physical units) from the open boundary within which voxels are cleared. Default: 0 (none). */
  itkSetClampMacro(Radius, double, 0.0, NumericTraits<double>::max());
  itkGetConstMacro(Radius, double);

  /** Number of open boundary edges of the mesh in the last Update(). */
  itkGetConstMacro(NumberOfOpenBoundaryEdges, SizeValueType);

  /** Number of non-zero voxels of the output of the last Update(). */
  itkGetConstMacro(NumberOfMaskVoxels, SizeValueType);

protected:
  MeshOpenBoundaryMaskImageFilter();
  ~MeshOpenBoundaryMaskImageFilter() override = default;

  void
  PrintSelf(std::ostream & os, Indent indent) const override;

  /** The whole mask is needed: edges reach anywhere. */
  void
  GenerateInputRequestedRegion() override;

  void
  EnlargeOutputRequestedRegion(DataObject * output) override;

  void
  GenerateData() override;

private:
  double        m_Radius{ 0.0 };
  SizeValueType m_NumberOfOpenBoundaryEdges{ 0 };
  SizeValueType m_NumberOfMaskVoxels{ 0 };
};
} // namespace itk

#ifndef ITK_MANUAL_INSTANTIATION
#  include "itkMeshOpenBoundaryMaskImageFilter.hxx"
#endif

#endif // itkMeshOpenBoundaryMaskImageFilter_h
