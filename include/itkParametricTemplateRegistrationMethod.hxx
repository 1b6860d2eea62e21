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
#ifndef itkParametricTemplateRegistrationMethod_hxx
#define itkParametricTemplateRegistrationMethod_hxx

#include "itkParametricTemplateRegistrationMethod.h"
#include "itkLBFGSBOptimizerv4.h"
#include "itkLBFGSOptimizerv4.h"
#include "itkNormalVariateGenerator.h"
#include "itkOnePlusOneEvolutionaryOptimizerv4.h"
#include <algorithm>
#include <cmath>
#include <sstream>

namespace itk
{
template <typename TFixedMesh, typename TMovingMesh, typename TDistanceImage>
ParametricTemplateRegistrationMethod<TFixedMesh, TMovingMesh, TDistanceImage>::ParametricTemplateRegistrationMethod()
  : Superclass(false)
{
  this->AddOptionalInputName("MovingDistanceImage", 2);
  this->AddRequiredInputName("TemplateTransform", 3);
  this->AddOptionalInputName("BaseTransform", 4);
}

template <typename TFixedMesh, typename TMovingMesh, typename TDistanceImage>
auto
ParametricTemplateRegistrationMethod<TFixedMesh, TMovingMesh, TDistanceImage>::GetParametricTransform() const
  -> const ParametricTransformType *
{
  return dynamic_cast<const ParametricTransformType *>(this->GetTransform());
}

template <typename TFixedMesh, typename TMovingMesh, typename TDistanceImage>
void
ParametricTemplateRegistrationMethod<TFixedMesh, TMovingMesh, TDistanceImage>::VerifyPreconditions() const
{
  Superclass::VerifyPreconditions();
  if (this->GetMovingMesh() == nullptr && this->GetMovingDistanceImage() == nullptr)
  {
    itkExceptionMacro(<< "Neither a moving (source) mesh nor a moving distance image is set");
  }
  if (this->GetMovingMesh() == nullptr && m_Evaluation == EvaluationEnum::ExactPointToTriangle)
  {
    itkExceptionMacro(<< "Exact point-to-triangle evaluation needs the moving (source) mesh");
  }
}

template <typename TFixedMesh, typename TMovingMesh, typename TDistanceImage>
void
ParametricTemplateRegistrationMethod<TFixedMesh, TMovingMesh, TDistanceImage>::VerifyInputData() const
{
  // The inputs' contents, known only once the upstream pipeline has run.
  if (this->GetFixedMesh()->GetNumberOfPoints() == 0)
  {
    itkExceptionMacro(<< "The fixed (target) mesh has no vertex");
  }
  const auto * movingMesh = this->GetMovingMesh();
  if (movingMesh != nullptr && (movingMesh->GetNumberOfPoints() == 0 || movingMesh->GetNumberOfCells() == 0))
  {
    itkExceptionMacro(<< "The moving (source) mesh is empty");
  }
  const ParametricTransformType * templates = this->GetTemplateTransform();
  if (templates == nullptr || templates->GetNumberOfTemplates() == 0)
  {
    itkExceptionMacro(<< "The template transform has no template");
  }
  const auto * baseInput = this->GetBaseTransformInput();
  if (baseInput != nullptr && baseInput->Get() == nullptr)
  {
    itkExceptionMacro(<< "The base transform input holds no transform");
  }
  const TransformType * base = this->GetBaseTransform();
  if (base != nullptr && !m_ResampleBaseTransform)
  {
    const auto * bspline = dynamic_cast<const typename ParametricTransformType::BSplineTransformType *>(base);
    if (bspline == nullptr || !templates->IsOnSameGrid(bspline))
    {
      itkExceptionMacro(<< "The base transform (" << base->GetNameOfClass()
                        << ") is not a BSplineTransform on the templates' grid, and ResampleBaseTransform is Off");
    }
  }
}

template <typename TFixedMesh, typename TMovingMesh, typename TDistanceImage>
void
ParametricTemplateRegistrationMethod<TFixedMesh, TMovingMesh, TDistanceImage>::GenerateData()
{
  m_MetricValues.clear();
  m_StopConditionDescription.clear();
  m_TimeLimitReached = false;
  m_StartTime = std::chrono::steady_clock::now();
  this->UpdateProgress(0.0f);
  this->VerifyInputData();

  // The transform: a copy of the template transform, with the base input if any.
  const ParametricTransformType * templates = this->GetTemplateTransform();
  auto                            transform = ParametricTransformType::New();
  transform->SetFixedParameters(templates->GetFixedParameters());
  transform->SetParameters(templates->GetParameters());
  if (const TransformType * base = this->GetBaseTransform())
  {
    if (m_BaseTransformMode == BaseTransformModeEnum::Base)
    {
      transform->SetBaseFromTransform(base);
    }
    else
    {
      transform->SetParameters(transform->ProjectCoefficients(transform->ComputeCoefficientsOfTransform(base)));
    }
  }

  const bool refine = m_Evaluation != EvaluationEnum::ExactPointToTriangle && m_NumberOfExactRefinementIterations > 0 &&
                      this->GetMovingMesh() != nullptr;
  this->RunStage(transform, m_Evaluation, m_NumberOfIterations, true);
  if (refine && !m_TimeLimitReached)
  {
    this->RunStage(transform, EvaluationEnum::ExactPointToTriangle, m_NumberOfExactRefinementIterations, false);
  }

  this->SetTransformOutputValue(transform);
  this->UpdateProgress(1.0f);
}

template <typename TFixedMesh, typename TMovingMesh, typename TDistanceImage>
void
ParametricTemplateRegistrationMethod<TFixedMesh, TMovingMesh, TDistanceImage>::RunStage(
  ParametricTransformType * transform,
  EvaluationEnum            evaluation,
  unsigned int              iterations,
  bool                      first)
{
  auto metric = MetricType::New();
  metric->SetFixedMesh(this->GetFixedMesh());
  metric->SetMovingMesh(this->GetMovingMesh());
  metric->SetMovingDistanceImage(this->GetMovingDistanceImage());
  metric->SetEvaluation(evaluation);
  metric->SetDistanceMapSpacing(m_DistanceMapSpacing);
  metric->SetDistanceMapMargin(m_DistanceMapMargin);
  metric->SetNumberOfWorkUnits(this->GetNumberOfWorkUnits());
  metric->SetMovingTransform(transform);
  metric->Initialize();

  const auto initialParameters = transform->GetParameters();
  if (first)
  {
    metric->SetSquaredDistance(false);
    m_InitialMeanDistance = metric->GetValue();
  }
  metric->SetSquaredDistance(m_UseSquaredDistance);
  const double initialValue = metric->GetValue();
  if (first)
  {
    m_InitialMetricValue = initialValue;
  }

  const auto finalParameters = this->RunOptimizer(metric, transform, iterations);
  transform->SetParameters(finalParameters);
  m_FinalMetricValue = metric->GetValue();
  if (!(m_FinalMetricValue <= initialValue))
  {
    transform->SetParameters(initialParameters);
    m_FinalMetricValue = initialValue;
    m_StopConditionDescription += " (ended worse than it started: weights kept)";
  }
  m_StopConditionDescription += '\n';
  metric->SetSquaredDistance(false);
  m_FinalMeanDistance = metric->GetValue();
}

template <typename TFixedMesh, typename TMovingMesh, typename TDistanceImage>
auto
ParametricTemplateRegistrationMethod<TFixedMesh, TMovingMesh, TDistanceImage>::RunOptimizer(
  MetricType *                    metric,
  const ParametricTransformType * transform,
  unsigned int                    iterations) -> typename ParametricTransformType::ParametersType
{
  const unsigned int                                            numberOfParameters = transform->GetNumberOfParameters();
  typename ObjectToObjectOptimizerBaseTemplate<double>::Pointer optimizer;
  typename OnePlusOneEvolutionaryOptimizerv4<double>::Pointer   evolutionary;
  switch (m_Optimizer)
  {
    case OptimizerEnum::OnePlusOneEvolutionary: {
      evolutionary = OnePlusOneEvolutionaryOptimizerv4<double>::New();
      auto generator = Statistics::NormalVariateGenerator::New();
      generator->Initialize(this->GetRandomSeed());
      evolutionary->SetNormalVariateGenerator(generator);
      // Growth and shrink factors as recommended by Styner et al. for the (1+1) strategy.
      evolutionary->Initialize(m_InitialSearchRadius, 1.05, std::pow(1.05, -0.25));
      evolutionary->SetEpsilon(m_ConvergenceTolerance);
      evolutionary->SetMaximumIteration(iterations);
      optimizer = evolutionary.GetPointer();
      break;
    }
    case OptimizerEnum::LBFGSB: {
      auto                                  lbfgsb = LBFGSBOptimizerv4::New();
      LBFGSBOptimizerv4::BoundSelectionType selection(numberOfParameters);
      selection.Fill(m_WeightBound > 0.0 ? LBFGSBOptimizerv4::BOTHBOUNDED : LBFGSBOptimizerv4::UNBOUNDED);
      LBFGSBOptimizerv4::BoundValueType lower(numberOfParameters);
      LBFGSBOptimizerv4::BoundValueType upper(numberOfParameters);
      lower.Fill(-m_WeightBound);
      upper.Fill(m_WeightBound);
      lbfgsb->SetBoundSelection(selection);
      lbfgsb->SetLowerBound(lower);
      lbfgsb->SetUpperBound(upper);
      lbfgsb->SetNumberOfIterations(iterations);
      lbfgsb->SetMaximumNumberOfFunctionEvaluations(3 * iterations + 10);
      lbfgsb->SetMaximumNumberOfCorrections(7);
      lbfgsb->SetCostFunctionConvergenceFactor(1e7);
      lbfgsb->SetGradientConvergenceTolerance(m_ConvergenceTolerance);
      optimizer = lbfgsb.GetPointer();
      break;
    }
    case OptimizerEnum::LBFGS:
    default: {
      auto lbfgs = LBFGSOptimizerv4::New();
      lbfgs->SetNumberOfIterations(iterations);
      lbfgs->SetMaximumNumberOfFunctionEvaluations(3 * iterations + 10);
      lbfgs->SetGradientConvergenceTolerance(m_ConvergenceTolerance);
      lbfgs->SetLineSearchAccuracy(0.9);
      lbfgs->SetDefaultStepLength(1.0);
      optimizer = lbfgs.GetPointer();
      break;
    }
  }
  optimizer->SetMetric(metric); // unit scales: the weights are in template units

  const double total = static_cast<double>(m_NumberOfIterations + m_NumberOfExactRefinementIterations);
  auto         record = [this, metric, &optimizer, &evolutionary, total](const EventObject &) {
    m_MetricValues.push_back(evolutionary ? evolutionary->GetCurrentCost() : metric->GetCurrentValue());
    if (m_MaximumRunTime > 0.0 && !m_TimeLimitReached &&
        std::chrono::duration<double>(std::chrono::steady_clock::now() - m_StartTime).count() > m_MaximumRunTime)
    {
      // The (1+1) strategy stops on request; the quasi-Newton optimizers end the iteration whose count reaches
      // their maximum, lowered to 0 so that this very iteration is the last (vnl counts from 0).
      m_TimeLimitReached = true;
      if (evolutionary)
      {
        evolutionary->StopOptimization();
      }
      else
      {
        optimizer->SetNumberOfIterations(0);
      }
    }
    this->UpdateProgress(static_cast<float>(std::min(0.99, m_MetricValues.size() / total)));
    this->InvokeEvent(IterationEvent());
  };
  const unsigned long tag = optimizer->AddObserver(IterationEvent(), record);
  try
  {
    optimizer->StartOptimization();
  }
  catch (...)
  {
    optimizer->RemoveObserver(tag);
    throw;
  }
  optimizer->RemoveObserver(tag);
  std::ostringstream stop;
  stop << metric->GetEvaluation() << ", " << m_Optimizer << ": " << optimizer->GetStopConditionDescription();
  if (m_TimeLimitReached)
  {
    stop << " (stopped early: the run-time limit of " << m_MaximumRunTime << " s was reached)";
  }
  m_StopConditionDescription += stop.str();
  return optimizer->GetCurrentPosition();
}

template <typename TFixedMesh, typename TMovingMesh, typename TDistanceImage>
void
ParametricTemplateRegistrationMethod<TFixedMesh, TMovingMesh, TDistanceImage>::PrintSelf(std::ostream & os,
                                                                                         Indent         indent) const
{
  Superclass::PrintSelf(os, indent);
  os << indent << "Optimizer: " << m_Optimizer << std::endl;
  os << indent << "Evaluation: " << m_Evaluation << std::endl;
  os << indent << "DistanceMapSpacing: " << m_DistanceMapSpacing << std::endl;
  os << indent << "DistanceMapMargin: " << m_DistanceMapMargin << std::endl;
  os << indent << "NumberOfIterations: " << m_NumberOfIterations << std::endl;
  os << indent << "ConvergenceTolerance: " << m_ConvergenceTolerance << std::endl;
  os << indent << "WeightBound: " << m_WeightBound << std::endl;
  os << indent << "InitialSearchRadius: " << m_InitialSearchRadius << std::endl;
  os << indent << "ResampleBaseTransform: " << (m_ResampleBaseTransform ? "On" : "Off") << std::endl;
  os << indent << "BaseTransformMode: " << m_BaseTransformMode << std::endl;
  os << indent << "UseSquaredDistance: " << (m_UseSquaredDistance ? "On" : "Off") << std::endl;
  os << indent << "NumberOfExactRefinementIterations: " << m_NumberOfExactRefinementIterations << std::endl;
  os << indent << "MaximumRunTime: " << m_MaximumRunTime << std::endl;
  os << indent << "TimeLimitReached: " << (m_TimeLimitReached ? "true" : "false") << std::endl;
  os << indent << "MetricValues: " << m_MetricValues.size() << " iterations" << std::endl;
  os << indent << "InitialMetricValue: " << m_InitialMetricValue << std::endl;
  os << indent << "FinalMetricValue: " << m_FinalMetricValue << std::endl;
  os << indent << "InitialMeanDistance: " << m_InitialMeanDistance << std::endl;
  os << indent << "FinalMeanDistance: " << m_FinalMeanDistance << std::endl;
  os << indent << "StopConditionDescription: " << m_StopConditionDescription << std::endl;
}
} // namespace itk

#endif // itkParametricTemplateRegistrationMethod_hxx
