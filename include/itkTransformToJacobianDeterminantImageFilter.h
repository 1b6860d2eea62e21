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
#ifndef itkTransformToJacobianDeterminantImageFilter_h
#define itkTransformToJacobianDeterminantImageFilter_h

#include "itkFFDShapeMatchingCompatibility.h"
#include "itkDataObjectDecorator.h"
#include "itkImageSource.h"
#include "FFDShapeMatchingDetail/itkSpatialJacobianEvaluator.h"
#include "itkTransform.h"
#include <mutex>

namespace itk
{
/** \class TransformToJacobianDeterminantImageFilter
 * \brief Samples the Jacobian determinant \f$\det(\partial T / \partial x)\f$ of a transform on an image grid.
 *
 * Each output pixel holds the determinant of the spatial Jacobian of the transform at the pixel's physical
 * position: 1 where the transform preserves volume, below 1 where it compresses, at or below 0 where it folds.
 * The Jacobian comes from detail::SpatialJacobianEvaluator (analytic for cubic BSplineTransform and, by the
 * chain rule, CompositeTransform; the transform's own ComputeJacobianWithRespectToPosition() otherwise; central
 * finite differences with step FiniteDifferenceStep as a last resort).
 *
 * The output geometry is taken from a reference image (SetReferenceImage() with UseReferenceImageOn()) or from
 * Size, OutputStartIndex, OutputSpacing, OutputOrigin and OutputDirection, as in
 * TransformToDisplacementFieldFilter. The filter is multi-threaded and streams. After Update(),
 * GetMinimumDeterminant() and GetMaximumDeterminant() give the extremes over the region that was computed
 * (the folding check of a deformation).
 *
 * \sa TransformToDisplacementFieldFilter, DisplacementFieldJacobianDeterminantFilter
 *
 * \ingroup FFDShapeMatching
 */
template <typename TOutputImage,
          typename TTransform = Transform<double, TOutputImage::ImageDimension, TOutputImage::ImageDimension>>
class ITK_TEMPLATE_EXPORT TransformToJacobianDeterminantImageFilter : public ImageSource<TOutputImage>
{
public:
  ITK_DISALLOW_COPY_AND_MOVE(TransformToJacobianDeterminantImageFilter);

  using Self = TransformToJacobianDeterminantImageFilter;
  using Superclass = ImageSource<TOutputImage>;
  using Pointer = SmartPointer<Self>;
  using ConstPointer = SmartPointer<const Self>;

  itkNewMacro(Self);
  itkOverrideGetNameOfClassMacro(TransformToJacobianDeterminantImageFilter);

  static constexpr unsigned int ImageDimension = TOutputImage::ImageDimension;

  using OutputImageType = TOutputImage;
  using OutputImageRegionType = typename OutputImageType::RegionType;
  using PixelType = typename OutputImageType::PixelType;
  using TransformType = TTransform;
  using DecoratedTransformType = DataObjectDecorator<TransformType>;
  using ParametersValueType = typename TransformType::ParametersValueType;
  using JacobianEvaluatorType = detail::SpatialJacobianEvaluator<ParametersValueType, ImageDimension>;
  using SizeType = typename OutputImageType::SizeType;
  using IndexType = typename OutputImageType::IndexType;
  using SpacingType = typename OutputImageType::SpacingType;
  using OriginType = typename OutputImageType::PointType;
  using DirectionType = typename OutputImageType::DirectionType;
  using ReferenceImageBaseType = ImageBase<ImageDimension>;

  static_assert(TransformType::InputSpaceDimension == ImageDimension &&
                  TransformType::OutputSpaceDimension == ImageDimension,
                "The transform must map the image's space onto itself.");

  /** The transform (required), as a decorated pipeline input. */
  itkSetGetDecoratedObjectInputMacro(Transform, TransformType);

  /** Output size. Default: 0 (must be set unless a reference image is used). */
  itkSetMacro(Size, SizeType);
  itkGetConstReferenceMacro(Size, SizeType);

  /** Index of the first output pixel. Default: 0. */
  itkSetMacro(OutputStartIndex, IndexType);
  itkGetConstReferenceMacro(OutputStartIndex, IndexType);

  /** Output spacing. Default: 1. */
  itkSetMacro(OutputSpacing, SpacingType);
  itkGetConstReferenceMacro(OutputSpacing, SpacingType);

  /** Output origin. Default: 0. */
  itkSetMacro(OutputOrigin, OriginType);
  itkGetConstReferenceMacro(OutputOrigin, OriginType);

  /** Output direction. Default: identity. */
  itkSetMacro(OutputDirection, DirectionType);
  itkGetConstReferenceMacro(OutputDirection, DirectionType);

  /** Image whose geometry the output copies when UseReferenceImage is On. */
  itkSetInputMacro(ReferenceImage, ReferenceImageBaseType);
  itkGetInputMacro(ReferenceImage, ReferenceImageBaseType);

  /** Take the output geometry from the reference image. Default: Off. */
  itkSetMacro(UseReferenceImage, bool);
  itkGetConstMacro(UseReferenceImage, bool);
  itkBooleanMacro(UseReferenceImage);

  /** Step (mm) of the finite differences used when the transform has no spatial Jacobian. Default: 1e-4. */
  itkSetMacro(FiniteDifferenceStep, double);
  itkGetConstMacro(FiniteDifferenceStep, double);

  /** Smallest determinant over the region computed by the last Update(). */
  itkGetConstMacro(MinimumDeterminant, double);

  /** Largest determinant over the region computed by the last Update(). */
  itkGetConstMacro(MaximumDeterminant, double);

protected:
  TransformToJacobianDeterminantImageFilter();
  ~TransformToJacobianDeterminantImageFilter() override = default;
  void
  PrintSelf(std::ostream & os, Indent indent) const override;

  void
  VerifyPreconditions() const override;

  void
  GenerateOutputInformation() override;

  void
  BeforeThreadedGenerateData() override;

  void
  DynamicThreadedGenerateData(const OutputImageRegionType & outputRegionForThread) override;

private:
  SizeType              m_Size{};
  IndexType             m_OutputStartIndex{};
  SpacingType           m_OutputSpacing{ 1.0 };
  OriginType            m_OutputOrigin{};
  DirectionType         m_OutputDirection{ DirectionType::GetIdentity() };
  bool                  m_UseReferenceImage{ false };
  double                m_FiniteDifferenceStep{ 1e-4 };
  double                m_MinimumDeterminant{ 0.0 };
  double                m_MaximumDeterminant{ 0.0 };
  JacobianEvaluatorType m_JacobianEvaluator;
  std::mutex            m_Mutex;
};
} // namespace itk

#ifndef ITK_MANUAL_INSTANTIATION
#  include "itkTransformToJacobianDeterminantImageFilter.hxx"
#endif

#endif // itkTransformToJacobianDeterminantImageFilter_h
