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
#ifndef itkTruncatedGaussianImageFilter_h
#define itkTruncatedGaussianImageFilter_h

#include "itkFFDShapeMatchingCompatibility.h"
#include "itkFixedArray.h"
#include "itkImageToImageFilter.h"

#include <vector>

namespace itk
{
/** \class TruncatedGaussianImageFilter
 * \brief Smooths a 3-D image with a sampled Gaussian kernel, truncated and normalized, one axis after the other.
 *
 * Along each axis d the kernel's weights are exp(-(k s_d)^2 / (2 sigma_d^2)) for the offsets k = -r_d..r_d (s_d the
 * spacing, r_d = ceil(KernelWidthInSigmas sigma_d / s_d)), divided by their sum; beyond the image's faces the edge
 * voxel is repeated (zero flux). The passes run along the first axis, then the second, then the third, in the pixel
 * type's precision (float for float images) with the row-wise passes over contiguous memory. A sigma of 0 along an
 * axis leaves that axis alone.
 *
 * It is a cheaper stand-in for SmoothingRecursiveGaussianImageFilter at the small sigmas of a registration's
 * coarse levels (one or two voxels), where the recursive filter's fourth-order approximation of the Gaussian is
 * also at its least accurate. Its output is the whole image: the filter asks for the whole input.
 *
 * \sa SmoothingRecursiveGaussianImageFilter, DiscreteGaussianImageFilter
 * \ingroup FFDShapeMatching
 */
template <typename TImage>
class ITK_TEMPLATE_EXPORT TruncatedGaussianImageFilter : public ImageToImageFilter<TImage, TImage>
{
public:
  ITK_DISALLOW_COPY_AND_MOVE(TruncatedGaussianImageFilter);

  using Self = TruncatedGaussianImageFilter;
  using Superclass = ImageToImageFilter<TImage, TImage>;
  using Pointer = SmartPointer<Self>;
  using ConstPointer = SmartPointer<const Self>;

  itkNewMacro(Self);
  itkOverrideGetNameOfClassMacro(TruncatedGaussianImageFilter);

  using ImageType = TImage;
  using PixelType = typename TImage::PixelType;
  static constexpr unsigned int ImageDimension = TImage::ImageDimension;
  using SigmaArrayType = FixedArray<double, ImageDimension>;

  static_assert(ImageDimension == 3, "TruncatedGaussianImageFilter smooths 3-D images.");

  /** Standard deviation per axis, in physical units (0 leaves the axis alone). Default: 1 along every axis. */
  itkSetMacro(SigmaArray, SigmaArrayType);
  itkGetConstReferenceMacro(SigmaArray, SigmaArrayType);

  /** Sets the same standard deviation along every axis. */
  void
  SetSigma(double sigma)
  {
    SigmaArrayType sigmas;
    sigmas.Fill(sigma);
    this->SetSigmaArray(sigmas);
  }

  /** Half width of the kernel in standard deviations (rounded up to whole voxels). Default: 3. */
  itkSetMacro(KernelWidthInSigmas, double);
  itkGetConstMacro(KernelWidthInSigmas, double);

  /** The normalized weights of the kernel along an axis, offsets -r..r, for the input's spacing along it (the input's
   * information must be current). */
  std::vector<double>
  ComputeKernel(unsigned int axis) const;

protected:
  TruncatedGaussianImageFilter();
  ~TruncatedGaussianImageFilter() override = default;

  void
  PrintSelf(std::ostream & os, Indent indent) const override;

  void
  VerifyPreconditions() const override;

  /** The whole input and output: each pass reads whole lines. */
  void
  GenerateInputRequestedRegion() override;

  void
  EnlargeOutputRequestedRegion(DataObject * output) override;

  void
  GenerateData() override;

private:
  SigmaArrayType m_SigmaArray{}; // Filled with 1 in the constructor.
  double         m_KernelWidthInSigmas{ 3.0 };
};
} // namespace itk

#ifndef ITK_MANUAL_INSTANTIATION
#  include "itkTruncatedGaussianImageFilter.hxx"
#endif

#endif // itkTruncatedGaussianImageFilter_h
