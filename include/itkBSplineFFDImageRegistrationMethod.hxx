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
#ifndef itkBSplineFFDImageRegistrationMethod_hxx
#define itkBSplineFFDImageRegistrationMethod_hxx

#include "itkFFDShapeMatchingCompatibility.h"
#include "itkBSplineFFDImageRegistrationMethod.h"
#include "itkAffineTransform.h"
#include "itkBSplineTransformInitializer.h"
#include "itkBSplineTransformParametersAdaptor.h"
#include "itkCenteredTransformInitializer.h"
#include "itkCommand.h"
#include "itkCompositeTransform.h"
#include "itkImageMaskSpatialObject.h"
#include "itkImageRegistrationMethodv4.h"
#include "itkTruncatedGaussianImageRegistrationMethodv4.h"
#include "itkLBFGSBOptimizerv4.h"
#include "itkBSplineSparseImageToImageMetricv4.h"
#include "itkMattesMutualInformationImageToImageMetricv4.h"
#include "itkRegistrationParameterScalesFromPhysicalShift.h"
#include "itkRegularStepGradientDescentOptimizerv4.h"
#include "itkRegularizedImageToImageMetricv4.h"
#include <cmath>
#include <sstream>

namespace itk
{
namespace detail
{
/** \class UnitScalesLBFGSBOptimizerv4
 * \brief LBFGSBOptimizerv4 that takes the unit scales ImageRegistrationMethodv4 hands it at every level without
 * a warning, and keeps them sized for the current level.
 *
 * LBFGSB works without parameter scales, and ITK 5.2's LBFGSBOptimizerv4 says so on the console whenever scales
 * are set, which ImageRegistrationMethodv4 does at each resolution level. Users of the module's registration would
 * see that warning on every run although nothing is wrong; this optimizer sets the unit scales silently and
 * warns only when scales other than one are asked for.
 * \ingroup FFDShapeMatching
 */
class UnitScalesLBFGSBOptimizerv4 : public LBFGSBOptimizerv4
{
public:
  ITK_DISALLOW_COPY_AND_MOVE(UnitScalesLBFGSBOptimizerv4);
  using Self = UnitScalesLBFGSBOptimizerv4;
  using Superclass = LBFGSBOptimizerv4;
  using Pointer = SmartPointer<Self>;
  itkNewMacro(Self);
  itkOverrideGetNameOfClassMacro(UnitScalesLBFGSBOptimizerv4);

  void
  SetScales(const ScalesType & scales) override
  {
    for (unsigned int i = 0; i < scales.Size(); ++i)
    {
      if (scales[i] != 1.0)
      {
        Superclass::SetScales(scales);
        return;
      }
    }
    this->m_Scales.SetSize(this->m_Metric->GetNumberOfLocalParameters());
    this->m_Scales.Fill(1.0);
    this->m_ScalesAreIdentity = true;
  }

  /** Unit scales follow the metric's parameters when a level refines the grid: ITK 5.4's ImageRegistrationMethodv4
   * does not hand the optimizer new scales at each level (5.2's does), and the base class refuses scales of the
   * previous level's size. Scales other than one are left to the base class's check. */
  void
  StartOptimization(bool doOnlyInitialization = false) override
  {
    if (this->m_Metric && this->m_ScalesAreIdentity &&
        this->m_Scales.Size() != this->m_Metric->GetNumberOfLocalParameters())
    {
      this->m_Scales.SetSize(this->m_Metric->GetNumberOfLocalParameters());
      this->m_Scales.Fill(1.0);
    }
    Superclass::StartOptimization(doOnlyInitialization);
  }

protected:
  UnitScalesLBFGSBOptimizerv4() = default;
  ~UnitScalesLBFGSBOptimizerv4() override = default;
};
} // namespace detail
} // namespace itk

namespace itk
{
template <typename TFixedImage, typename TMovingImage>
void
BSplineFFDImageRegistrationMethod<TFixedImage, TMovingImage>::VerifyPreconditions() const
{
  Superclass::VerifyPreconditions();
  this->VerifyImageInputs();
}

template <typename TFixedImage, typename TMovingImage>
void
BSplineFFDImageRegistrationMethod<TFixedImage, TMovingImage>::GenerateData()
{
  m_MetricValues.clear();
  m_StopConditionDescription.clear();
  this->StartRunTimeClock();
  this->UpdateProgress(0.0f);

  typename TransformType::Pointer affine;
  if (m_UseAffineStage)
  {
    affine = this->RunAffineStage();
  }
  typename TransformType::Pointer result = this->RunBSplineStage(affine).GetPointer();
  for (std::size_t i = 0; i < m_MetricValues.size(); ++i)
  {
    if (!std::isfinite(m_MetricValues[i]))
    {
      itkExceptionMacro("The metric became " << m_MetricValues[i] << " at iteration " << i + 1
                                             << ": the optimization diverged (check the images and the weights).");
    }
  }
  if (affine)
  {
    // ITK's composite applies the most recently added transform first: B-spline, then affine.
    auto composite = CompositeTransform<double, ImageDimension>::New();
    composite->AddTransform(affine);
    composite->AddTransform(result);
    result = composite;
  }
  this->SetTransformOutputValue(result);
  this->UpdateProgress(1.0f);
}

template <typename TFixedImage, typename TMovingImage>
auto
BSplineFFDImageRegistrationMethod<TFixedImage, TMovingImage>::RunAffineStage() -> AffineTransformPointer
{
  using AffineType = AffineTransform<double, ImageDimension>;
  using RegistrationType = ImageRegistrationMethodv4<FixedImageType, MovingImageType, AffineType>;
  using MetricType = MattesMutualInformationImageToImageMetricv4<FixedImageType, MovingImageType>;
  using OptimizerType = RegularStepGradientDescentOptimizerv4<double>;

  auto affine = AffineType::New();
  using InitializerType = CenteredTransformInitializer<AffineType, FixedImageType, MovingImageType>;
  auto initializer = InitializerType::New();
  initializer->SetTransform(affine);
  initializer->SetFixedImage(this->GetFixedImage());
  initializer->SetMovingImage(this->GetMovingImage());
  initializer->MomentsOn();
  initializer->InitializeTransform();

  auto metric = MetricType::New();
  metric->SetNumberOfHistogramBins(m_NumberOfHistogramBins);
  auto optimizer = OptimizerType::New();
  optimizer->SetLearningRate(1.0);
  optimizer->SetMinimumStepLength(1e-3);
  optimizer->SetRelaxationFactor(0.5);
  optimizer->SetNumberOfIterations(m_NumberOfIterations);
  auto scales = RegistrationParameterScalesFromPhysicalShift<MetricType>::New();
  scales->SetMetric(metric);
  optimizer->SetScalesEstimator(scales);
  optimizer->SetDoEstimateLearningRateOnce(true);

  auto registration = RegistrationType::New();
  registration->SetFixedImage(this->GetFixedImage());
  registration->SetMovingImage(this->GetMovingImage());
  registration->SetInitialTransform(affine);
  registration->InPlaceOn();
  registration->SetMetric(metric);
  registration->SetOptimizer(optimizer);
  registration->SetNumberOfLevels(1);
  typename RegistrationType::ShrinkFactorsArrayType shrink(1);
  shrink[0] = 1;
  registration->SetShrinkFactorsPerLevel(shrink);
  typename RegistrationType::SmoothingSigmasArrayType sigmas(1);
  sigmas[0] = 0.0;
  registration->SetSmoothingSigmasPerLevel(sigmas);
  registration->SetMetricSamplingStrategy(RegistrationType::MetricSamplingStrategyEnum::RANDOM);
  registration->SetMetricSamplingPercentage(std::min(m_SamplingPercentage, 0.2));
  registration->MetricSamplingReinitializeSeed(m_RandomSeed);
  registration->Update();

  std::ostringstream stop;
  stop << "affine: " << optimizer->GetStopConditionDescription() << '\n';
  m_StopConditionDescription += stop.str();
  return affine.GetPointer();
}

template <typename TFixedImage, typename TMovingImage>
auto
BSplineFFDImageRegistrationMethod<TFixedImage, TMovingImage>::RunBSplineStage(
  const TransformType * movingInitialTransform) -> typename BSplineTransformType::Pointer
{
  using RegistrationType =
    TruncatedGaussianImageRegistrationMethodv4<FixedImageType, MovingImageType, BSplineTransformType>;
  // The B-spline-sparse metric gives ITK's Mattes MI and mean squares values and derivatives, at a cost
  // per sample independent of the number of control points.
  using RegularizedMetricType =
    RegularizedImageToImageMetricv4<BSplineSparseImageToImageMetricv4<FixedImageType, MovingImageType>>;
  using ImageMetricType = ImageToImageMetricv4<FixedImageType, MovingImageType>;

  const auto * fixed = this->GetFixedImage();

  // The transform: cubic B-spline over the fixed image, coarsest grid first.
  auto transform = BSplineTransformType::New();
  using InitializerType = BSplineTransformInitializer<BSplineTransformType, FixedImageType>;
  auto                                        initializer = InitializerType::New();
  typename BSplineTransformType::MeshSizeType meshSize;
  meshSize.Fill(this->GetMeshSizeAtLevel(0));
  initializer->SetTransform(transform);
  initializer->SetImage(fixed);
  initializer->SetTransformDomainMeshSize(meshSize);
  initializer->InitializeTransform();
  transform->SetIdentity();

  // The metric, regularized.
  auto regularized = RegularizedMetricType::New();
  regularized->SetMeasure(m_Metric);
  regularized->SetNumberOfHistogramBins(m_NumberOfHistogramBins);
  regularized->GetModifiablePenalty()->SetBendingEnergyWeight(m_BendingEnergyWeight);
  regularized->GetModifiablePenalty()->SetFoldingPenaltyWeight(m_FoldingPenaltyWeight);
  typename ImageMetricType::Pointer metric = regularized.GetPointer();
  metric->SetUseMovingImageGradientFilter(m_UseMovingImageGradientFilter);
  if (const auto * mask = this->GetFixedImageMask())
  {
    using SpatialMaskType = ImageMaskSpatialObject<ImageDimension>;
    auto spatialMask = SpatialMaskType::New();
    spatialMask->SetImage(mask);
    spatialMask->Update();
    metric->SetFixedImageMask(spatialMask);
  }

  auto registration = RegistrationType::New();
  registration->SetFixedImage(fixed);
  registration->SetMovingImage(this->GetMovingImage());
  if (movingInitialTransform != nullptr)
  {
    registration->SetMovingInitialTransform(movingInitialTransform);
  }
  registration->SetInitialTransform(transform);
  registration->InPlaceOn();
  registration->SetMetric(metric);
  registration->SetUseTruncatedGaussian(m_UseTruncatedGaussianSmoothing);

  // Resolution schedule and control-grid refinement.
  const unsigned int                                                  levels = this->GetNumberOfLevels();
  typename RegistrationType::ShrinkFactorsArrayType                   shrink(levels);
  typename RegistrationType::SmoothingSigmasArrayType                 sigmas(levels);
  typename RegistrationType::TransformParametersAdaptorsContainerType adaptors;
  for (unsigned int level = 0; level < levels; ++level)
  {
    const unsigned int factor = 1u << (levels - 1 - level);
    shrink[level] = factor;
    sigmas[level] = factor > 1 ? 0.5 * factor : 0.0;
    using AdaptorType = BSplineTransformParametersAdaptor<BSplineTransformType>;
    auto                                        adaptor = AdaptorType::New();
    typename BSplineTransformType::MeshSizeType levelMeshSize;
    levelMeshSize.Fill(this->GetMeshSizeAtLevel(level));
    adaptor->SetRequiredTransformDomainOrigin(transform->GetTransformDomainOrigin());
    adaptor->SetRequiredTransformDomainPhysicalDimensions(transform->GetTransformDomainPhysicalDimensions());
    adaptor->SetRequiredTransformDomainDirection(transform->GetTransformDomainDirection());
    adaptor->SetRequiredTransformDomainMeshSize(levelMeshSize);
    adaptors.push_back(adaptor.GetPointer());
  }
  registration->SetNumberOfLevels(levels);
  registration->SetShrinkFactorsPerLevel(shrink);
  registration->SetSmoothingSigmasPerLevel(sigmas);
  registration->SmoothingSigmasAreSpecifiedInPhysicalUnitsOff();
  registration->SetTransformParametersAdaptorsPerLevel(adaptors);
  if (m_SamplingPercentage < 1.0)
  {
    registration->SetMetricSamplingStrategy(RegistrationType::MetricSamplingStrategyEnum::RANDOM);
    registration->SetMetricSamplingPercentage(m_SamplingPercentage);
    registration->MetricSamplingReinitializeSeed(m_RandomSeed);
  }

  // The optimizer.
  using RSGDType = RegularStepGradientDescentOptimizerv4<double>;
  const unsigned int finalNumberOfParameters =
    ImageDimension * static_cast<unsigned int>(std::pow(this->GetNumberOfControlPointsPerAxis(), ImageDimension));
  typename ObjectToObjectOptimizerBaseTemplate<double>::Pointer optimizer;
  typename LBFGSBOptimizerv4::Pointer                           lbfgsb;
  if (m_Optimizer == OptimizerEnum::LBFGSB)
  {
    lbfgsb = detail::UnitScalesLBFGSBOptimizerv4::New().GetPointer();
    // Unbounded; sized for the finest grid (the optimizer accepts a longer selection).
    LBFGSBOptimizerv4::BoundSelectionType bounds(finalNumberOfParameters);
    bounds.Fill(LBFGSBOptimizerv4::UNBOUNDED);
    lbfgsb->SetBoundSelection(bounds);
    LBFGSBOptimizerv4::BoundValueType noBounds(finalNumberOfParameters);
    noBounds.Fill(0.0);
    lbfgsb->SetLowerBound(noBounds);
    lbfgsb->SetUpperBound(noBounds);
    lbfgsb->SetNumberOfIterations(m_NumberOfIterations);
    lbfgsb->SetMaximumNumberOfFunctionEvaluations(2 * m_NumberOfIterations + 10);
    lbfgsb->SetMaximumNumberOfCorrections(7);
    lbfgsb->SetCostFunctionConvergenceFactor(1e7);
    lbfgsb->SetGradientConvergenceTolerance(m_ConvergenceTolerance);
    optimizer = lbfgsb.GetPointer();
  }
  else
  {
    auto rsgd = RSGDType::New();
    rsgd->SetLearningRate(1.0);
    rsgd->SetMinimumStepLength(m_ConvergenceTolerance);
    rsgd->SetRelaxationFactor(0.7);
    rsgd->SetNumberOfIterations(m_NumberOfIterations);
    auto scales = RegistrationParameterScalesFromPhysicalShift<ImageMetricType>::New();
    scales->SetMetric(metric);
    rsgd->SetScalesEstimator(scales);
    rsgd->SetDoEstimateLearningRateAtEachIteration(false);
    rsgd->SetDoEstimateLearningRateOnce(true);
    optimizer = rsgd.GetPointer();
  }
  registration->SetOptimizer(optimizer);

  // Observers: metric trajectory and progress per iteration; LBFGSB restarts from the adapted transform.
  // The optimizers stop early, keeping the current (best so far) parameters, when the metric stops being finite
  // or the run-time limit is reached: LBFGSB ends at the iteration whose count reaches its (lowered) maximum,
  // the regular-step optimizer on request. Later levels then make one iteration each, so the final grid stays.
  const auto stopNow = [&optimizer, &lbfgsb]() {
    if (lbfgsb)
    {
      lbfgsb->SetNumberOfIterations(1);
    }
    else
    {
      static_cast<RSGDType *>(optimizer.GetPointer())->StopOptimization();
    }
  };
  const double totalIterations = static_cast<double>(m_NumberOfIterations) * levels;
  auto         recordIteration = [this, &optimizer, &stopNow, totalIterations]() {
    const double value = optimizer->GetCurrentMetricValue();
    m_MetricValues.push_back(value);
    if (this->CheckRunTime() || !std::isfinite(value))
    {
      stopNow();
    }
    this->UpdateProgress(static_cast<float>(std::min(0.99, m_MetricValues.size() / totalIterations)));
    this->InvokeEvent(IterationEvent());
  };
  const unsigned long iterationTag =
    optimizer->AddObserver(IterationEvent(), [&recordIteration](const EventObject &) { recordIteration(); });
  unsigned long levelTag = 0;
  if (lbfgsb)
  {
    levelTag = registration->AddObserver(MultiResolutionIterationEvent(), [this, &lbfgsb](const EventObject &) {
      // An empty initial position makes LBFGSB start from the (adapted) transform's parameters.
      lbfgsb->SetInitialPosition(typename LBFGSBOptimizerv4::ParametersType(0));
      if (this->GetTimeLimitReached())
      {
        lbfgsb->SetNumberOfIterations(1);
      }
    });
  }
  registration->Update();
  optimizer->RemoveObserver(iterationTag);
  if (lbfgsb)
  {
    registration->RemoveObserver(levelTag);
  }

  std::ostringstream stop;
  stop << "b-spline: " << optimizer->GetStopConditionDescription();
  if (this->GetTimeLimitReached())
  {
    stop << " (stopped early: the run-time limit of " << this->GetMaximumRunTime() << " s was reached)";
  }
  stop << '\n';
  m_StopConditionDescription += stop.str();
  return transform;
}

template <typename TFixedImage, typename TMovingImage>
void
BSplineFFDImageRegistrationMethod<TFixedImage, TMovingImage>::PrintSelf(std::ostream & os, Indent indent) const
{
  Superclass::PrintSelf(os, indent);
  os << indent << "Metric: " << m_Metric << std::endl;
  os << indent << "Optimizer: " << m_Optimizer << std::endl;
  os << indent << "NumberOfHistogramBins: " << m_NumberOfHistogramBins << std::endl;
  os << indent << "SamplingPercentage: " << m_SamplingPercentage << std::endl;
  os << indent << "RandomSeed: " << m_RandomSeed << std::endl;
  os << indent << "NumberOfIterations: " << m_NumberOfIterations << std::endl;
  os << indent << "ConvergenceTolerance: " << m_ConvergenceTolerance << std::endl;
  os << indent << "BendingEnergyWeight: " << m_BendingEnergyWeight << std::endl;
  os << indent << "FoldingPenaltyWeight: " << m_FoldingPenaltyWeight << std::endl;
  os << indent << "UseAffineStage: " << (m_UseAffineStage ? "On" : "Off") << std::endl;
  os << indent << "UseMovingImageGradientFilter: " << (m_UseMovingImageGradientFilter ? "On" : "Off") << std::endl;
  os << indent << "UseTruncatedGaussianSmoothing: " << (m_UseTruncatedGaussianSmoothing ? "On" : "Off") << std::endl;
  os << indent << "MetricValues: " << m_MetricValues.size() << " iterations" << std::endl;
  os << indent << "StopConditionDescription: " << m_StopConditionDescription << std::endl;
}
} // namespace itk

#endif // itkBSplineFFDImageRegistrationMethod_hxx
