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
#ifndef itkApplyTransformToMeshFilter_hxx
#define itkApplyTransformToMeshFilter_hxx

#include "itkApplyTransformToMeshFilter.h"
#include "itkMultiThreaderBase.h"
#include "itkTotalProgressReporter.h"
#include <algorithm>
#include <cmath>

namespace itk
{
namespace detail
{
/** Solves the small dense system matrix * solution = rhs by Gaussian elimination with partial
 * pivoting. Returns false if the matrix is (numerically) singular. */
template <unsigned int NDimensions>
bool
SolveSmallLinearSystem(Matrix<double, NDimensions, NDimensions> matrix,
                       const double (&rhs)[NDimensions],
                       double (&solution)[NDimensions])
{
  double b[NDimensions];
  double scale = 0.0;
  for (unsigned int i = 0; i < NDimensions; ++i)
  {
    b[i] = rhs[i];
    for (unsigned int j = 0; j < NDimensions; ++j)
    {
      scale = std::max(scale, std::abs(matrix(i, j)));
    }
  }
  if (!(scale > 0.0) || !std::isfinite(scale))
  {
    return false;
  }
  for (unsigned int column = 0; column < NDimensions; ++column)
  {
    unsigned int pivot = column;
    for (unsigned int i = column + 1; i < NDimensions; ++i)
    {
      if (std::abs(matrix(i, column)) > std::abs(matrix(pivot, column)))
      {
        pivot = i;
      }
    }
    if (std::abs(matrix(pivot, column)) <= 1e-12 * scale)
    {
      return false;
    }
    if (pivot != column)
    {
      for (unsigned int j = 0; j < NDimensions; ++j)
      {
        std::swap(matrix(pivot, j), matrix(column, j));
      }
      std::swap(b[pivot], b[column]);
    }
    for (unsigned int i = column + 1; i < NDimensions; ++i)
    {
      const double factor = matrix(i, column) / matrix(column, column);
      for (unsigned int j = column; j < NDimensions; ++j)
      {
        matrix(i, j) -= factor * matrix(column, j);
      }
      b[i] -= factor * b[column];
    }
  }
  for (unsigned int i = NDimensions; i > 0; --i)
  {
    const unsigned int row = i - 1;
    double             sum = b[row];
    for (unsigned int j = row + 1; j < NDimensions; ++j)
    {
      sum -= matrix(row, j) * solution[j];
    }
    solution[row] = sum / matrix(row, row);
    if (!std::isfinite(solution[row]))
    {
      return false;
    }
  }
  return true;
}
} // namespace detail

template <typename TInputMesh, typename TOutputMesh, typename TTransform>
ApplyTransformToMeshFilter<TInputMesh, TOutputMesh, TTransform>::ApplyTransformToMeshFilter()
{
  // The transform is required; its decorated input is named "Transform".
  this->AddRequiredInputName("Transform");
}

template <typename TInputMesh, typename TOutputMesh, typename TTransform>
void
ApplyTransformToMeshFilter<TInputMesh, TOutputMesh, TTransform>::PrintSelf(std::ostream & os, Indent indent) const
{
  Superclass::PrintSelf(os, indent);
  os << indent << "Inverse: " << (m_Inverse ? "On" : "Off") << std::endl;
  os << indent << "InverseTolerance: " << m_InverseTolerance << std::endl;
  os << indent << "MaximumNumberOfInverseIterations: " << m_MaximumNumberOfInverseIterations << std::endl;
  os << indent << "MinimumInverseResidualDecrease: " << m_MinimumInverseResidualDecrease << std::endl;
  os << indent << "FiniteDifferenceStep: " << m_FiniteDifferenceStep << std::endl;
  os << indent << "NumberOfNonConvergedPoints: " << m_NumberOfNonConvergedPoints << std::endl;
  os << indent << "MaximumInverseResidual: " << m_MaximumInverseResidual << std::endl;
  os << indent << "InverseConverged: " << m_InverseConverged.size() << " flags" << std::endl;
  os << indent << "InverseResiduals: " << m_InverseResiduals.size() << " values" << std::endl;
}

template <typename TInputMesh, typename TOutputMesh, typename TTransform>
void
ApplyTransformToMeshFilter<TInputMesh, TOutputMesh, TTransform>::VerifyPreconditions() const
{
  Superclass::VerifyPreconditions();
  if (this->GetTransform() == nullptr)
  {
    itkExceptionMacro(<< "The Transform input holds no transform");
  }
  if (!(m_InverseTolerance > 0.0))
  {
    itkExceptionMacro(<< "InverseTolerance must be positive, it is " << m_InverseTolerance);
  }
  if (m_MaximumNumberOfInverseIterations == 0)
  {
    itkExceptionMacro(<< "MaximumNumberOfInverseIterations must be at least 1");
  }
  if (!(m_MinimumInverseResidualDecrease >= 0.0 && m_MinimumInverseResidualDecrease < 1.0))
  {
    itkExceptionMacro(<< "MinimumInverseResidualDecrease must be in [0, 1), it is "
                      << m_MinimumInverseResidualDecrease);
  }
  if (!(m_FiniteDifferenceStep > 0.0))
  {
    itkExceptionMacro(<< "FiniteDifferenceStep must be positive, it is " << m_FiniteDifferenceStep);
  }
}

template <typename TInputMesh, typename TOutputMesh, typename TTransform>
bool
ApplyTransformToMeshFilter<TInputMesh, TOutputMesh, TTransform>::InvertPoint(
  const JacobianEvaluatorType & jacobianEvaluator,
  const TransformPointType &    target,
  TransformPointType &          solution,
  double &                      residual) const
{
  constexpr unsigned int maximumNumberOfHalvings = 30;
  double                 residualVector[PointDimension];

  // T(x) through the evaluator: the transform's own arithmetic, without ITK's per-call arrays for B-splines.
  const auto evaluate = [&jacobianEvaluator, &target](const TransformPointType & x,
                                                      double(&r)[PointDimension]) -> double {
    const auto image = jacobianEvaluator.TransformPoint(x);
    double     squaredNorm = 0.0;
    for (unsigned int i = 0; i < PointDimension; ++i)
    {
      r[i] = static_cast<double>(image[i]) - static_cast<double>(target[i]);
      squaredNorm += r[i] * r[i];
    }
    const double norm = std::sqrt(squaredNorm);
    return std::isfinite(norm) ? norm : NumericTraits<double>::max();
  };

  // Start at x0 = p - (T(p) - p), or at p if that is closer.
  double residualAtTarget[PointDimension];
  solution = target;
  residual = evaluate(target, residualAtTarget);
  TransformPointType start;
  for (unsigned int i = 0; i < PointDimension; ++i)
  {
    start[i] = target[i] - residualAtTarget[i];
  }
  const double startResidual = evaluate(start, residualVector);
  if (startResidual <= residual)
  {
    solution = start;
    residual = startResidual;
  }
  else
  {
    std::copy(residualAtTarget, residualAtTarget + PointDimension, residualVector);
  }

  // Takes the step x - lambda * direction with lambda halved until the residual decreases.
  const auto dampedStep = [&](const double(&direction)[PointDimension]) -> bool {
    double lambda = 1.0;
    for (unsigned int halving = 0; halving < maximumNumberOfHalvings; ++halving, lambda *= 0.5)
    {
      TransformPointType candidate;
      for (unsigned int i = 0; i < PointDimension; ++i)
      {
        candidate[i] = solution[i] - lambda * direction[i];
      }
      double       candidateResidualVector[PointDimension];
      const double candidateResidual = evaluate(candidate, candidateResidualVector);
      if (candidateResidual < residual)
      {
        solution = candidate;
        residual = candidateResidual;
        std::copy(candidateResidualVector, candidateResidualVector + PointDimension, residualVector);
        return true;
      }
    }
    return false;
  };

  // An iteration that lowered the residual by less than the fraction: the residual has levelled off (no preimage).
  const auto levelsOff = [this, &residual](double before) {
    return residual >= m_InverseTolerance && before - residual < m_MinimumInverseResidualDecrease * before;
  };

  // Damped Newton iteration.
  typename JacobianEvaluatorType::MatrixType jacobian;
  for (unsigned int iteration = 0; iteration < m_MaximumNumberOfInverseIterations && residual >= m_InverseTolerance;
       ++iteration)
  {
    jacobianEvaluator.Evaluate(solution, jacobian);
    double       step[PointDimension];
    const double before = residual;
    if (!detail::SolveSmallLinearSystem<PointDimension>(jacobian, residualVector, step) || !dampedStep(step) ||
        levelsOff(before))
    {
      break;
    }
  }

  // Fixed-point iteration x <- x + (p - T(x)) from the best estimate, when Newton did not get there.
  for (unsigned int iteration = 0; iteration < m_MaximumNumberOfInverseIterations && residual >= m_InverseTolerance;
       ++iteration)
  {
    double fixedPointStep[PointDimension];
    std::copy(residualVector, residualVector + PointDimension, fixedPointStep);
    const double before = residual;
    if (!dampedStep(fixedPointStep) || levelsOff(before))
    {
      break;
    }
  }
  return residual < m_InverseTolerance;
}

template <typename TInputMesh, typename TOutputMesh, typename TTransform>
void
ApplyTransformToMeshFilter<TInputMesh, TOutputMesh, TTransform>::GenerateData()
{
  using OutputPointsContainer = typename OutputMeshType::PointsContainer;
  using OutputPointType = typename OutputMeshType::PointType;
  using OutputCoordRepType = typename OutputPointType::ValueType;

  const InputMeshType * inputMesh = this->GetInput();
  OutputMeshType *      outputMesh = this->GetOutput();
  const TransformType * transform = this->GetTransform();

  m_InverseConverged.clear();
  m_InverseResiduals.clear();
  m_NumberOfNonConvergedPoints = 0;
  m_MaximumInverseResidual = 0.0;

  // Gather the vertices in container order: ids and coordinates.
  const auto *                    inputPoints = inputMesh->GetPoints();
  std::vector<IdentifierType>     ids;
  std::vector<TransformPointType> points;
  if (inputPoints != nullptr)
  {
    ids.reserve(inputPoints->Size());
    points.reserve(inputPoints->Size());
    for (auto it = inputPoints->Begin(); it != inputPoints->End(); ++it)
    {
      ids.push_back(it.Index());
      TransformPointType point;
      for (unsigned int i = 0; i < PointDimension; ++i)
      {
        point[i] = static_cast<typename TransformPointType::ValueType>(it.Value()[i]);
      }
      points.push_back(point);
    }
  }
  const SizeValueType             numberOfPoints = points.size();
  std::vector<TransformPointType> results(numberOfPoints);

  JacobianEvaluatorType jacobianEvaluator;
  if (m_Inverse)
  {
    jacobianEvaluator.Initialize(transform, m_FiniteDifferenceStep);
    m_InverseConverged.assign(numberOfPoints, 0);
    m_InverseResiduals.assign(numberOfPoints, 0.0);
  }

  // Parallel over chunks of vertices; each chunk reports its progress.
  MultiThreaderBase * threader = this->GetMultiThreader();
  const SizeValueType numberOfWorkUnits = std::max<SizeValueType>(1, this->GetNumberOfWorkUnits());
  const SizeValueType chunkSize = std::max<SizeValueType>(64, numberOfPoints / (8 * numberOfWorkUnits) + 1);
  const SizeValueType numberOfChunks = (numberOfPoints + chunkSize - 1) / chunkSize;
  threader->SetNumberOfWorkUnits(this->GetNumberOfWorkUnits());
  threader->ParallelizeArray(
    0,
    numberOfChunks,
    [&](SizeValueType chunk) {
      TotalProgressReporter progress(this, numberOfPoints);
      const SizeValueType   end = std::min(numberOfPoints, (chunk + 1) * chunkSize);
      for (SizeValueType k = chunk * chunkSize; k < end; ++k)
      {
        if (m_Inverse)
        {
          double residual = 0.0;
          m_InverseConverged[k] = this->InvertPoint(jacobianEvaluator, points[k], results[k], residual);
          m_InverseResiduals[k] = residual;
        }
        else
        {
          results[k] = transform->TransformPoint(points[k]);
        }
        progress.CompletedPixel();
      }
    },
    nullptr);

  for (SizeValueType k = 0; k < m_InverseConverged.size(); ++k)
  {
    m_NumberOfNonConvergedPoints += (m_InverseConverged[k] == 0) ? 1 : 0;
    m_MaximumInverseResidual = std::max(m_MaximumInverseResidual, m_InverseResiduals[k]);
  }

  // Same ids, same order; everything else is passed through.
  auto outputPoints = OutputPointsContainer::New();
  for (SizeValueType k = 0; k < numberOfPoints; ++k)
  {
    OutputPointType point;
    for (unsigned int i = 0; i < PointDimension; ++i)
    {
      point[i] = static_cast<OutputCoordRepType>(results[k][i]);
    }
    outputPoints->InsertElement(ids[k], point);
  }
  outputMesh->SetPoints(outputPoints);
  outputMesh->SetBufferedRegion(outputMesh->GetRequestedRegion());

  this->CopyInputMeshToOutputMeshPointData();
  this->CopyInputMeshToOutputMeshCellLinks();
  this->CopyInputMeshToOutputMeshCells();
  this->CopyInputMeshToOutputMeshCellData();
  for (unsigned int dimension = 0; dimension < InputMeshType::MaxTopologicalDimension; ++dimension)
  {
    outputMesh->SetBoundaryAssignments(dimension, inputMesh->GetBoundaryAssignments(dimension));
  }
}
} // namespace itk

#endif // itkApplyTransformToMeshFilter_hxx
