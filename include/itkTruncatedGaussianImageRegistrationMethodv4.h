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
#ifndef itkTruncatedGaussianImageRegistrationMethodv4_h
#define itkTruncatedGaussianImageRegistrationMethodv4_h

#include "itkFFDShapeMatchingCompatibility.h"
#include "itkImageRegistrationMethodv4.h"
#include "itkTruncatedGaussianImageFilter.h"

namespace itk
{
/** \class TruncatedGaussianImageRegistrationMethodv4
 * \brief ImageRegistrationMethodv4 that can smooth each level's images with TruncatedGaussianImageFilter.
 *
 * ImageRegistrationMethodv4 smooths the fixed and moving images of a level with SmoothingRecursiveGaussianImageFilter
 * when the level's sigma is positive. With UseTruncatedGaussian On, this subclass lets the superclass set the level
 * up without smoothing, then smooths both images with TruncatedGaussianImageFilter (the level's sigma, in voxels or
 * physical units as SmoothingSigmasAreSpecifiedInPhysicalUnits says, times KernelWidthInSigmas = 3) and hands them
 * to the metric, before the superclass initializes it. Off (the default) is ImageRegistrationMethodv4 unchanged.
 * Only a single image metric is smoothed this way; a multi-metric or point-set metric keeps the superclass's
 * smoothing.
 *
 * \sa ImageRegistrationMethodv4, TruncatedGaussianImageFilter
 * \ingroup FFDShapeMatching
 */
template <typename TFixedImage, typename TMovingImage, typename TTransform>
class ITK_TEMPLATE_EXPORT TruncatedGaussianImageRegistrationMethodv4
  : public ImageRegistrationMethodv4<TFixedImage, TMovingImage, TTransform>
{
public:
  ITK_DISALLOW_COPY_AND_MOVE(TruncatedGaussianImageRegistrationMethodv4);

  using Self = TruncatedGaussianImageRegistrationMethodv4;
  using Superclass = ImageRegistrationMethodv4<TFixedImage, TMovingImage, TTransform>;
  using Pointer = SmartPointer<Self>;
  using ConstPointer = SmartPointer<const Self>;

  itkNewMacro(Self);
  itkOverrideGetNameOfClassMacro(TruncatedGaussianImageRegistrationMethodv4);

  /** Smooth each level's images with TruncatedGaussianImageFilter instead of the recursive Gaussian. Default: Off. */
  itkSetMacro(UseTruncatedGaussian, bool);
  itkGetConstMacro(UseTruncatedGaussian, bool);
  itkBooleanMacro(UseTruncatedGaussian);

protected:
  TruncatedGaussianImageRegistrationMethodv4() = default;
  ~TruncatedGaussianImageRegistrationMethodv4() override = default;

  void
  PrintSelf(std::ostream & os, Indent indent) const override
  {
    Superclass::PrintSelf(os, indent);
    os << indent << "UseTruncatedGaussian: " << (m_UseTruncatedGaussian ? "On" : "Off") << std::endl;
  }

  void
  InitializeRegistrationAtEachLevel(const SizeValueType level) override
  {
    using CategoryEnum = ObjectToObjectMetricBaseTemplateEnums::MetricCategory;
    const double sigma = this->m_SmoothingSigmasPerLevel[level];
    // Without a metric the superclass throws its own exception.
    if (!m_UseTruncatedGaussian || !(sigma > 0.0) || this->m_Metric.IsNull() ||
        this->m_Metric->GetMetricCategory() != CategoryEnum::IMAGE_METRIC)
    {
      Superclass::InitializeRegistrationAtEachLevel(level);
      return;
    }
    // The superclass sets the level up on the unsmoothed images; the smoothed ones replace them in the metric.
    this->m_SmoothingSigmasPerLevel[level] = 0.0;
    try
    {
      Superclass::InitializeRegistrationAtEachLevel(level);
    }
    catch (...)
    {
      this->m_SmoothingSigmasPerLevel[level] = sigma;
      throw;
    }
    this->m_SmoothingSigmasPerLevel[level] = sigma;
    const auto fixed = this->Smooth(this->GetFixedImage(0), sigma);
    const auto moving = this->Smooth(this->GetMovingImage(0), sigma);
    this->m_FixedSmoothImages[0] = fixed;
    this->m_MovingSmoothImages[0] = moving;
    this->m_Metric->SetFixedObject(fixed);
    this->m_Metric->SetMovingObject(moving);
  }

private:
  template <typename TImage>
  typename TImage::Pointer
  Smooth(const TImage * image, double sigma) const
  {
    using FilterType = TruncatedGaussianImageFilter<TImage>;
    auto                                filter = FilterType::New();
    typename FilterType::SigmaArrayType sigmas;
    for (unsigned int d = 0; d < TImage::ImageDimension; ++d)
    {
      sigmas[d] = this->m_SmoothingSigmasAreSpecifiedInPhysicalUnits ? sigma : sigma * image->GetSpacing()[d];
    }
    filter->SetSigmaArray(sigmas);
    filter->SetInput(image);
    filter->SetNumberOfWorkUnits(this->GetNumberOfWorkUnits());
    filter->Update();
    typename TImage::Pointer smoothed = filter->GetOutput();
    smoothed->DisconnectPipeline();
    return smoothed;
  }

  bool m_UseTruncatedGaussian{ false };
};
} // namespace itk

#endif // itkTruncatedGaussianImageRegistrationMethodv4_h
