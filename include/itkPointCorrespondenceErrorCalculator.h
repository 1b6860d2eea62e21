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
#ifndef itkPointCorrespondenceErrorCalculator_h
#define itkPointCorrespondenceErrorCalculator_h

#include "itkFFDShapeMatchingCompatibility.h"
#include "itkMeshSurfaceDistanceCalculator.h"
#include "itkObject.h"
#include "itkObjectFactory.h"
#include <utility>
#include <vector>

namespace itk
{
/** \class PointCorrespondenceErrorCalculator
 * \brief True registration error where vertex correspondences are known: |moved vertex - ground truth|.
 *
 * For every correspondence (moved id, reference id), the error is the Euclidean distance between the
 * moved mesh's vertex (e.g. the deformed source) and the reference mesh's vertex (its known true position).
 * Without an explicit correspondence list, every vertex of the moved mesh corresponds to the reference vertex
 * with the same id. The calculator reports the mean, root mean square, median, 95th percentile and maximum of
 * the errors (percentiles interpolate linearly between order statistics) and keeps the errors per
 * correspondence (GetErrors(), in correspondence order, or moved point-container order without a list).
 *
 * \code
 * auto calculator = itk::PointCorrespondenceErrorCalculator<MeshType>::New();
 * calculator->SetMovedMesh(deformedSource);
 * calculator->SetReferenceMesh(groundTruth);
 * calculator->Compute();
 * \endcode
 *
 * \sa MeshSurfaceDistanceCalculator
 *
 * \ingroup FFDShapeMatching
 */
template <typename TMovedMesh, typename TReferenceMesh = TMovedMesh>
class ITK_TEMPLATE_EXPORT PointCorrespondenceErrorCalculator : public Object
{
public:
  ITK_DISALLOW_COPY_AND_MOVE(PointCorrespondenceErrorCalculator);

  using Self = PointCorrespondenceErrorCalculator;
  using Superclass = Object;
  using Pointer = SmartPointer<Self>;
  using ConstPointer = SmartPointer<const Self>;

  itkNewMacro(Self);
  itkOverrideGetNameOfClassMacro(PointCorrespondenceErrorCalculator);

  using MovedMeshType = TMovedMesh;
  using ReferenceMeshType = TReferenceMesh;
  using CorrespondenceType = std::pair<IdentifierType, IdentifierType>;
  using CorrespondenceContainerType = std::vector<CorrespondenceType>;
  using ErrorContainerType = std::vector<double>;

  static_assert(MovedMeshType::PointDimension == ReferenceMeshType::PointDimension,
                "Both meshes must have the same dimension.");

  /** Mesh whose vertices were moved (e.g. the deformed source). */
  itkSetConstObjectMacro(MovedMesh, MovedMeshType);
  itkGetConstObjectMacro(MovedMesh, MovedMeshType);

  /** Mesh holding the true positions. */
  itkSetConstObjectMacro(ReferenceMesh, ReferenceMeshType);
  itkGetConstObjectMacro(ReferenceMesh, ReferenceMeshType);

  /** Pairs (moved id, reference id). Empty (default): same ids. */
  void
  SetCorrespondences(const CorrespondenceContainerType & correspondences)
  {
    m_Correspondences = correspondences;
    this->Modified();
  }
  itkGetConstReferenceMacro(Correspondences, CorrespondenceContainerType);

  /** Computes the errors and their statistics. Throws if a mesh is missing, there is no correspondence, or
   * an id has no point. */
  void
  Compute();

  /** Mean error. */
  itkGetConstMacro(MeanError, double);

  /** Root mean square error. */
  itkGetConstMacro(RootMeanSquareError, double);

  /** Median error. */
  itkGetConstMacro(MedianError, double);

  /** 95th percentile of the errors. */
  itkGetConstMacro(Percentile95Error, double);

  /** Maximum error. */
  itkGetConstMacro(MaximumError, double);

  /** Error of each correspondence. */
  itkGetConstReferenceMacro(Errors, ErrorContainerType);

protected:
  PointCorrespondenceErrorCalculator() = default;
  ~PointCorrespondenceErrorCalculator() override = default;
  void
  PrintSelf(std::ostream & os, Indent indent) const override;

private:
  typename MovedMeshType::ConstPointer     m_MovedMesh;
  typename ReferenceMeshType::ConstPointer m_ReferenceMesh;
  CorrespondenceContainerType              m_Correspondences;
  double                                   m_MeanError{ 0.0 };
  double                                   m_RootMeanSquareError{ 0.0 };
  double                                   m_MedianError{ 0.0 };
  double                                   m_Percentile95Error{ 0.0 };
  double                                   m_MaximumError{ 0.0 };
  ErrorContainerType                       m_Errors;
};
} // namespace itk

#ifndef ITK_MANUAL_INSTANTIATION
#  include "itkPointCorrespondenceErrorCalculator.hxx"
#endif

#endif // itkPointCorrespondenceErrorCalculator_h
