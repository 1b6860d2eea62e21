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
#ifndef itkBSplineFFDImageRegistrationMethod_h
#define itkBSplineFFDImageRegistrationMethod_h

#include "itkFFDShapeMatchingCompatibility.h"
#include "itkBSplineImageRegistrationMethodBase.h"
#include "itkFFDShapeMatchingEnums.h"
#include <string>
#include <vector>

namespace itk
{
/** \class BSplineFFDImageRegistrationMethod
 * \brief Registers two voxel images with a cubic B-spline free-form deformation by gradient-based global
 * optimization (the "GO" method of the FFDShapeMatching pipeline).
 *
 * This pipeline object composes ITK's own registration parts: ImageRegistrationMethodv4, a BSplineTransform
 * initialized over the fixed image by BSplineTransformInitializer with NumberOfControlPointsPerAxis control
 * points per axis, the Mattes mutual-information or mean-squares measure (BSplineSparseImageToImageMetricv4,
 * which gives the values and derivatives of ITK's Mattes and mean-squares v4 metrics at a cost per sample
 * independent of the grid size; regularized by RegularizedImageToImageMetricv4 with the B-spline bending energy
 * and a folding penalty), and the
 * LBFGSB or regular-step gradient-descent v4 optimizer. A multi-resolution schedule (NumberOfLevels,
 * shrinking the images by 2 per level and smoothing them) refines the control grid between levels with
 * BSplineTransformParametersAdaptor. An optional affine stage (moments initialization, affine Mattes MI)
 * runs first.
 *
 * Inputs: the fixed image (index 0; in shape matching the target's voxel image), the moving image
 * (the source's) and an optional fixed-image mask restricting the metric's samples (non-zero = used;
 * e.g. a band around the target surface).
 * Output: the transform T, fixed space to moving space (ITK's convention), as a decorated
 * Transform<double, 3, 3> (GetTransformOutput()), ready to connect into a mesh-transform filter. Without the
 * affine stage it is the BSplineTransform itself; with it, a CompositeTransform applying the B-spline first,
 * then the affine transform.
 *
 * Progress is reported per optimizer iteration; an IterationEvent is invoked with each, and the metric value
 * trajectory is kept (GetMetricValues()). A run-time limit (MaximumRunTime) stops the optimization cleanly with
 * the parameters reached so far; a metric that stops being finite (a diverging optimization) ends Update() with
 * an ExceptionObject instead of a meaningless transform.
 *
 * \sa RegularizedImageToImageMetricv4, ImageRegistrationMethodv4, BSplineTransform
 * \ingroup FFDShapeMatching
 */
template <typename TFixedImage, typename TMovingImage = TFixedImage>
class ITK_TEMPLATE_EXPORT BSplineFFDImageRegistrationMethod
  : public BSplineImageRegistrationMethodBase<TFixedImage, TMovingImage>
{
public:
  ITK_DISALLOW_COPY_AND_MOVE(BSplineFFDImageRegistrationMethod);

  using Self = BSplineFFDImageRegistrationMethod;
  using Superclass = BSplineImageRegistrationMethodBase<TFixedImage, TMovingImage>;
  using Pointer = SmartPointer<Self>;
  using ConstPointer = SmartPointer<const Self>;

  itkNewMacro(Self);
  itkOverrideGetNameOfClassMacro(BSplineFFDImageRegistrationMethod);

  static constexpr unsigned int ImageDimension = TFixedImage::ImageDimension;

  using typename Superclass::BSplineTransformType;
  using typename Superclass::DecoratedTransformType;
  using typename Superclass::FixedImageType;
  using typename Superclass::MaskImageType;
  using typename Superclass::MovingImageType;
  using typename Superclass::TransformType;
  using ImageMetricEnum = FFDShapeMatchingEnums::ImageMetric;
  using OptimizerEnum = FFDShapeMatchingEnums::Optimizer;

  // Inputs (fixed image, moving image, fixed-image mask) and the decorated transform output: see the superclass.

  /** Image similarity. Default: Mattes mutual information (the paper's measure). */
  itkSetEnumMacro(Metric, ImageMetricEnum);
  itkGetEnumMacro(Metric, ImageMetricEnum);

  /** Optimizer. Default: LBFGSB. */
  itkSetEnumMacro(Optimizer, OptimizerEnum);
  itkGetEnumMacro(Optimizer, OptimizerEnum);

  /** Histogram bins of the Mattes metric. Default: 32. */
  itkSetClampMacro(NumberOfHistogramBins, unsigned int, 5, 512);
  itkGetConstMacro(NumberOfHistogramBins, unsigned int);

  /** Fraction of (masked) fixed voxels sampled by the metric, in (0, 1]; 1 uses every voxel. Default: 1. */
  itkSetClampMacro(SamplingPercentage, double, 1e-6, 1.0);
  itkGetConstMacro(SamplingPercentage, double);

  /** Seed of the random metric sampling. Default: 121212. */
  itkSetMacro(RandomSeed, int);
  itkGetConstMacro(RandomSeed, int);

  // NumberOfControlPointsPerAxis (default 20) and NumberOfLevels (default 1): see the superclass. Level l (from 0)
  // also shrinks the images by 2^(L-1-l).

  /** Maximum optimizer iterations per level. Default: 100. */
  itkSetClampMacro(NumberOfIterations, unsigned int, 1, NumericTraits<unsigned int>::max());
  itkGetConstMacro(NumberOfIterations, unsigned int);

  /** LBFGSB's projected-gradient tolerance, or the regular-step optimizer's minimum step length (mm).
   * Default: 1e-5. */
  itkSetMacro(ConvergenceTolerance, double);
  itkGetConstMacro(ConvergenceTolerance, double);

  /** Weight of the B-spline bending energy added to the metric. Default: 0. */
  itkSetClampMacro(BendingEnergyWeight, double, 0.0, NumericTraits<double>::max());
  itkGetConstMacro(BendingEnergyWeight, double);

  /** Weight of the folding penalty added to the metric. Default: 0. */
  itkSetClampMacro(FoldingPenaltyWeight, double, 0.0, NumericTraits<double>::max());
  itkGetConstMacro(FoldingPenaltyWeight, double);

  /** Run an affine registration (moments-initialized, Mattes MI) before the B-spline stage. Default: Off. */
  itkSetMacro(UseAffineStage, bool);
  itkGetConstMacro(UseAffineStage, bool);
  itkBooleanMacro(UseAffineStage);

  /** How the metric takes the moving image's gradient. On (default, ITK's default): from a gradient image computed
   * once per level by a recursive Gaussian derivative filter (sigma = one voxel) over the whole moving image, then
   * interpolated. Off: by central differences of the interpolated moving image at each sample, as it is needed. Off
   * skips the filter, whose cost grows with the moving image, not with the samples; on a 1 mm distance image it gives
   * a rougher gradient, which the module's benchmark measured as less accurate for GO alone in the paper's noise
   * regime but as accurate (and faster) where a coherent point drift stage refines GO's result (method GOCPD of
   * MeshShapeMatchingFilter turns it Off). */
  itkSetMacro(UseMovingImageGradientFilter, bool);
  itkGetConstMacro(UseMovingImageGradientFilter, bool);
  itkBooleanMacro(UseMovingImageGradientFilter);

  /** How the coarse levels' fixed and moving images are smoothed (sigma half the level's shrink factor, in voxels).
   * Off (default, ITK's): SmoothingRecursiveGaussianImageFilter. On: TruncatedGaussianImageFilter, a sampled Gaussian
   * truncated at three sigmas (TruncatedGaussianImageRegistrationMethodv4), about a quarter of the recursive filter's
   * time at these sigmas. Method GOCPD of MeshShapeMatchingFilter turns it On (benchmark/PEERS_MESH.md). */
  itkSetMacro(UseTruncatedGaussianSmoothing, bool);
  itkGetConstMacro(UseTruncatedGaussianSmoothing, bool);
  itkBooleanMacro(UseTruncatedGaussianSmoothing);

  // MaximumRunTime and TimeLimitReached: see the superclass. When the limit is reached the optimizer stops at the
  // current iteration, keeping the best parameters so far, and any remaining level makes one iteration (so the
  // output has the final control grid).

  /** Metric value after each optimizer iteration, over all levels, of the last Update(). */
  const std::vector<double> &
  GetMetricValues() const
  {
    return m_MetricValues;
  }

  /** The optimizers' stop conditions of the last Update(), one line per stage and level. */
  itkGetConstReferenceMacro(StopConditionDescription, std::string);

protected:
  BSplineFFDImageRegistrationMethod()
    : Superclass(1)
  {}
  ~BSplineFFDImageRegistrationMethod() override = default;

  void
  VerifyPreconditions() const override;

  void
  GenerateData() override;

  void
  PrintSelf(std::ostream & os, Indent indent) const override;

private:
  using AffineTransformPointer = typename Transform<double, ImageDimension, ImageDimension>::Pointer;

  AffineTransformPointer
  RunAffineStage();

  typename BSplineTransformType::Pointer
  RunBSplineStage(const TransformType * movingInitialTransform);

  ImageMetricEnum m_Metric{ ImageMetricEnum::MattesMutualInformation };
  OptimizerEnum   m_Optimizer{ OptimizerEnum::LBFGSB };
  unsigned int    m_NumberOfHistogramBins{ 32 };
  double          m_SamplingPercentage{ 1.0 };
  int             m_RandomSeed{ 121212 };
  unsigned int    m_NumberOfIterations{ 100 };
  double          m_ConvergenceTolerance{ 1e-5 };
  double          m_BendingEnergyWeight{ 0.0 };
  double          m_FoldingPenaltyWeight{ 0.0 };
  bool            m_UseAffineStage{ false };
  bool            m_UseMovingImageGradientFilter{ true };
  bool            m_UseTruncatedGaussianSmoothing{ false };

  std::vector<double> m_MetricValues{};
  std::string         m_StopConditionDescription{};
};
} // namespace itk

#ifndef ITK_MANUAL_INSTANTIATION
#  include "itkBSplineFFDImageRegistrationMethod.hxx"
#endif

#endif // itkBSplineFFDImageRegistrationMethod_h
