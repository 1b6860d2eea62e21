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
#ifndef itkBSplineSparseImageToImageMetricv4_h
#define itkBSplineSparseImageToImageMetricv4_h

#include "itkFFDShapeMatchingCompatibility.h"
#include "FFDShapeMatchingDetail/itkBSplineCompositeTransformParts.h"
#include "itkBSplineTransform.h"
#include "itkFFDShapeMatchingEnums.h"
#include "FFDShapeMatchingDetail/itkImageBufferGrid.h"
#include "itkImageToImageMetricv4.h"
#include "itkMultiThreaderBase.h"

#include <functional>
#include <vector>

namespace itk
{
namespace detail
{
/** \class BSplineSparseMetricUnusedThreader
 * \brief Placeholder for the dense and sparse threaders of ImageToImageMetricv4.
 *
 * BSplineSparseImageToImageMetricv4 evaluates itself; ImageToImageMetricv4 still needs non-null threaders
 * because its work-unit accessors forward to them. Processing a point through this threader throws.
 *
 * \ingroup FFDShapeMatching
 */
template <typename TDomainPartitioner, typename TImageToImageMetric>
class ITK_TEMPLATE_EXPORT BSplineSparseMetricUnusedThreader
  : public ImageToImageMetricv4GetValueAndDerivativeThreader<TDomainPartitioner, TImageToImageMetric>
{
public:
  ITK_DISALLOW_COPY_AND_MOVE(BSplineSparseMetricUnusedThreader);

  using Self = BSplineSparseMetricUnusedThreader;
  using Superclass = ImageToImageMetricv4GetValueAndDerivativeThreader<TDomainPartitioner, TImageToImageMetric>;
  using Pointer = SmartPointer<Self>;
  using ConstPointer = SmartPointer<const Self>;

  itkNewMacro(Self);
  itkOverrideGetNameOfClassMacro(BSplineSparseMetricUnusedThreader);

  using typename Superclass::VirtualIndexType;
  using typename Superclass::VirtualPointType;
  using typename Superclass::FixedImagePointType;
  using typename Superclass::FixedImagePixelType;
  using typename Superclass::FixedImageGradientType;
  using typename Superclass::MovingImagePointType;
  using typename Superclass::MovingImagePixelType;
  using typename Superclass::MovingImageGradientType;
  using typename Superclass::MeasureType;
  using typename Superclass::DerivativeType;

protected:
  BSplineSparseMetricUnusedThreader() = default;
  ~BSplineSparseMetricUnusedThreader() override = default;

  bool
  ProcessPoint(const VirtualIndexType &,
               const VirtualPointType &,
               const FixedImagePointType &,
               const FixedImagePixelType &,
               const FixedImageGradientType &,
               const MovingImagePointType &,
               const MovingImagePixelType &,
               const MovingImageGradientType &,
               MeasureType &,
               DerivativeType &,
               const ThreadIdType) const override
  {
    itkExceptionMacro("BSplineSparseImageToImageMetricv4 evaluates its samples itself; this threader is unused.");
  }
};
} // namespace detail

/** \class BSplineSparseImageToImageMetricv4
 * \brief Mattes mutual information or mean squares, with a sparse derivative for a cubic B-spline FFD.
 *
 * ITK's v4 image metrics evaluate, at every sample, the full parameter Jacobian of the moving transform and
 * accumulate the derivative over every parameter: one evaluation costs O(samples x parameters). A cubic
 * BSplineTransform moves a point with only \f$4^3\f$ control points, so this metric evaluates the transform
 * and accumulates the derivative over those 64 x 3 parameters only: one evaluation costs O(samples).
 *
 * The metric derives from ImageToImageMetricv4, so ImageRegistrationMethodv4 and the v4 optimizers drive it
 * unchanged: fixed and moving images, fixed and moving masks, virtual domain, fixed transform and sampled
 * point sets are set and read as for any v4 image metric. It overrides GetValue(), GetDerivative() and
 * GetValueAndDerivative() with its own multi-threaded computation (GetMaximumNumberOfWorkUnits() work units,
 * each with its own histogram and derivative buffer, summed in a fixed order: the result is deterministic
 * for a given number of work units).
 *
 * \par Measures (SetMeasure)
 * - \c MattesMutualInformation (default): the value is minus the mutual information of the joint histogram
 *   of NumberOfHistogramBins bins (default 32), built with a zero-order B-spline Parzen window on the fixed
 *   intensity and a cubic B-spline Parzen window on the moving intensity (Mattes et al. 2003); intensity
 *   ranges, padding and bin conventions are those of MattesMutualInformationImageToImageMetricv4.
 * - \c MeanSquares: the mean of (fixed - moving)^2 over the valid samples, as
 *   MeanSquaresImageToImageMetricv4.
 *
 * Values and derivatives equal those of the two ITK metrics configured identically; the derivative follows
 * the v4 convention and points downhill (it is minus the gradient of the value).
 *
 * \par Moving transform
 * A cubic BSplineTransform<double, 3, 3> (any dimension), or a CompositeTransform whose most recent (back)
 * transform is one and is the only transform optimized, as ImageRegistrationMethodv4 sets it up. Transforms
 * in front of the B-spline (e.g. a fixed initial affine) are applied after it; the image gradient is chained
 * through their Jacobian with respect to position (computed once when they are all linear).
 *
 * \par Samples
 * With a sampled point set (UseSampledPointSet, as set up by ImageRegistrationMethodv4 for RANDOM or REGULAR
 * sampling) its virtual points are used, otherwise every voxel of the virtual domain. Initialize() maps them
 * through the fixed transform once and keeps those inside the fixed image buffer and the fixed mask, with
 * their (linearly interpolated) fixed intensity: call Initialize() again after changing the fixed image, mask,
 * transform or samples. A sample whose moving point falls outside the moving image buffer or the moving mask
 * is skipped; GetNumberOfValidPoints() counts the others. With no valid sample the evaluation throws.
 *
 * \par Interpolation and gradients
 * Intensities are linearly interpolated (the metric's interpolators are not used). The moving image gradient is
 * the linearly interpolated image of the moving image gradient filter when UseMovingImageGradientFilter is On
 * (the default, computed by Initialize()), otherwise central differences of the interpolated moving image, as
 * ImageToImageMetricv4's default gradient calculator computes them. The gradient source must include the
 * moving image; a fixed image gradient is never used.
 *
 * \par References
 * D. Mattes, D. R. Haynor, H. Vesselle, T. K. Lewellen and W. Eubank, "PET-CT image registration in the chest
 * using free-form deformations", IEEE Transactions on Medical Imaging 22(1):120-128, 2003,
 * doi:10.1109/TMI.2002.803111.
 *
 * \code
 * using MetricType = itk::BSplineSparseImageToImageMetricv4<ImageType, ImageType>;
 * auto metric = MetricType::New();
 * metric->SetMeasure(itk::FFDShapeMatchingEnums::ImageMetric::MattesMutualInformation);
 * metric->SetNumberOfHistogramBins(32);
 * registration->SetMetric(metric);
 * \endcode
 *
 * \sa MattesMutualInformationImageToImageMetricv4, MeanSquaresImageToImageMetricv4, BSplineTransform,
 * ImageRegistrationMethodv4
 * \ingroup FFDShapeMatching
 */
template <typename TFixedImage, typename TMovingImage>
class ITK_TEMPLATE_EXPORT BSplineSparseImageToImageMetricv4 : public ImageToImageMetricv4<TFixedImage, TMovingImage>
{
public:
  ITK_DISALLOW_COPY_AND_MOVE(BSplineSparseImageToImageMetricv4);

  using Self = BSplineSparseImageToImageMetricv4;
  using Superclass = ImageToImageMetricv4<TFixedImage, TMovingImage>;
  using Pointer = SmartPointer<Self>;
  using ConstPointer = SmartPointer<const Self>;

  itkNewMacro(Self);
  itkOverrideGetNameOfClassMacro(BSplineSparseImageToImageMetricv4);

  using typename Superclass::MeasureType;
  using typename Superclass::DerivativeType;
  using typename Superclass::DerivativeValueType;
  using typename Superclass::MovingTransformType;
  using typename Superclass::VirtualPointType;
  using typename Superclass::FixedImagePixelType;
  using typename Superclass::MovingImagePixelType;

  static constexpr unsigned int ImageDimension = TMovingImage::ImageDimension;
  static constexpr unsigned int SupportSize = 4;
  using BSplineTransformType = BSplineTransform<double, ImageDimension, 3>;
  using MeasureEnum = FFDShapeMatchingEnums::ImageMetric;

  /** The similarity measure. Default: MattesMutualInformation. */
  itkSetEnumMacro(Measure, MeasureEnum);
  itkGetEnumMacro(Measure, MeasureEnum);

  /** Number of histogram bins per image of the Mattes measure (at least 5). Default: 32. */
  itkSetClampMacro(NumberOfHistogramBins, SizeValueType, 5, NumericTraits<SizeValueType>::max());
  itkGetConstMacro(NumberOfHistogramBins, SizeValueType);

  /** Number of samples kept by Initialize() (inside the fixed image buffer and the fixed mask). */
  SizeValueType
  GetNumberOfSamples() const
  {
    return static_cast<SizeValueType>(m_Samples.size());
  }

  /** Initializes the superclass (virtual domain, sampled points, moving gradient image), checks the moving transform,
   * computes the histogram intensity ranges and caches the samples with their fixed intensities. Throws when the
   * moving transform is not supported or no sample lies in the fixed image and mask. */
  void
  Initialize() override;

  /** The value alone (one pass over the samples, no image gradient). Throws when no sample is valid. */
  MeasureType
  GetValue() const override;

  /** The derivative (downhill), computed with the value. */
  void
  GetDerivative(DerivativeType & derivative) const override;

  /** Value and downhill derivative; \c derivative is resized to GetNumberOfParameters(). Throws when no sample is
   * valid. */
  void
  GetValueAndDerivative(MeasureType & value, DerivativeType & derivative) const override;

protected:
  BSplineSparseImageToImageMetricv4();
  ~BSplineSparseImageToImageMetricv4() override = default;
  void
  PrintSelf(std::ostream & os, Indent indent) const override;

private:
  using GradientType = Vector<double, ImageDimension>;
  using MovingGradientPixelType = typename Superclass::MovingImageGradientImageType::PixelType;
  using PositionJacobianType = Matrix<double, ImageDimension, ImageDimension>;

  /** A kept sample: its virtual point and its fixed intensity. */
  struct Sample
  {
    VirtualPointType Point;
    double           FixedValue{ 0.0 };
  };

  /** Support of the cubic B-spline at a point: first grid index and the 1-D weights per dimension. */
  struct Support
  {
    IndexValueType Start[ImageDimension];
    double         Weights[ImageDimension][SupportSize];
  };

  using TransformParts = detail::BSplineCompositeTransformParts<ImageDimension>;

  using Grid = detail::ImageBufferGrid<ImageDimension>;

  /** Per work unit partial results. */
  struct WorkUnitResult
  {
    double              Measure{ 0.0 };
    SizeValueType       NumberOfValidPoints{ 0 };
    std::vector<double> JointHistogram;
    std::vector<double> FixedMarginal;
    std::vector<double> Derivative;
  };

  TransformParts
  ResolveMovingTransform() const;

  void
  CacheSamples();

  void
  ComputeIntensityRanges();

  bool
  ComputeSupport(const VirtualPointType & point, Support & support) const;

  bool
  EvaluateSample(const Sample &         sample,
                 const TransformParts & parts,
                 bool                   computeGradient,
                 Support &              support,
                 bool &                 insideGrid,
                 double &               movingValue,
                 GradientType &         gradient) const;

  void
  ComputeMovingGradient(const VirtualPointType & movingPoint,
                        const double *           continuousIndex,
                        GradientType &           gradient) const;

  template <typename TFunctor>
  void
  ForEachSupportPoint(const Support & support, TFunctor && functor) const;

  void
  AccumulateSparse(const Support & support, const GradientType & weightedGradient, double * derivative) const;

  void
  PrepareEvaluation(bool computeDerivative) const;

  void
  RunWorkUnits(const std::function<void(SizeValueType, SizeValueType, WorkUnitResult &)> & body) const;

  void
  ComputeMeanSquares(MeasureType & value, DerivativeType * derivative) const;

  void
  ComputeMattes(MeasureType & value, DerivativeType * derivative) const;

  void
  SumDerivatives(DerivativeType & derivative, double scale) const;

  /** Fixed histogram bin of an intensity (zero-order Parzen window). */
  OffsetValueType
  FixedParzenIndex(double fixedValue) const;

  /** First of the four moving histogram bins of an intensity, and the cubic window argument at that bin. */
  OffsetValueType
  MovingParzenIndex(double movingValue, double & firstArgument) const;

  MeasureEnum   m_Measure{ MeasureEnum::MattesMutualInformation };
  SizeValueType m_NumberOfHistogramBins{ 32 };

  MultiThreaderBase::Pointer m_Threader;

  std::vector<Sample> m_Samples;

  double m_FixedImageTrueMin{ 0.0 };
  double m_FixedImageTrueMax{ 0.0 };
  double m_MovingImageTrueMin{ 0.0 };
  double m_MovingImageTrueMax{ 0.0 };

  Grid                            m_MovingGrid;
  Grid                            m_GradientGrid;
  const MovingImagePixelType *    m_MovingBuffer{ nullptr };
  const MovingGradientPixelType * m_GradientBuffer{ nullptr };

  mutable double m_FixedImageBinSize{ 0.0 };
  mutable double m_MovingImageBinSize{ 0.0 };
  mutable double m_FixedImageNormalizedMin{ 0.0 };
  mutable double m_MovingImageNormalizedMin{ 0.0 };

  mutable TransformParts              m_Parts;
  mutable Grid                        m_CoefficientGrid;
  mutable const double *              m_Coefficients[ImageDimension]{};
  mutable SizeValueType               m_NumberOfCoefficients{ 0 };
  mutable std::vector<WorkUnitResult> m_WorkUnitResults;
  mutable std::vector<GradientType>   m_SampleGradients;
  mutable std::vector<double>         m_SampleMovingValues;
  mutable std::vector<uint8_t>        m_SampleStates;
};
} // namespace itk

#ifndef ITK_MANUAL_INSTANTIATION
#  include "itkBSplineSparseImageToImageMetricv4.hxx"
#endif

#endif // itkBSplineSparseImageToImageMetricv4_h
