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
#ifndef itkBSplineMRFImageRegistrationMethod_hxx
#define itkBSplineMRFImageRegistrationMethod_hxx

#include "itkBSplineMRFImageRegistrationMethod.h"
#include "itkBSplineTransformInitializer.h"
#include "itkBSplineTransformParametersAdaptor.h"
#include "itkCastImageFilter.h"
#include "FFDShapeMatchingDetail/itkCubicBSplineKernel.h"
#include "itkDiscreteGaussianImageFilter.h"
#include "itkImageRegionConstIteratorWithIndex.h"
#include "FFDShapeMatchingDetail/itkMatrixDeterminant.h"
#include "itkMultiThreaderBase.h"
#include <functional>
#include "itkShrinkImageFilter.h"
#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>

namespace itk
{
template <typename TFixedImage, typename TMovingImage>
auto
BSplineMRFImageRegistrationMethod<TFixedImage, TMovingImage>::MakeLabels(double maximumDisplacement) const
  -> std::vector<DisplacementType>
{
  std::vector<DisplacementType> labels;
  DisplacementType              zero;
  zero.Fill(0.0);
  labels.push_back(zero);
  const int steps = static_cast<int>(m_NumberOfLabelSteps);
  if (m_LabelSet == LabelSetEnum::Dense)
  {
    for (int z = -steps; z <= steps; ++z)
    {
      for (int y = -steps; y <= steps; ++y)
      {
        for (int x = -steps; x <= steps; ++x)
        {
          if (x == 0 && y == 0 && z == 0)
          {
            continue;
          }
          DisplacementType label;
          label[0] = maximumDisplacement * x / steps;
          label[1] = maximumDisplacement * y / steps;
          label[2] = maximumDisplacement * z / steps;
          labels.push_back(label);
        }
      }
    }
    return labels;
  }
  for (int step = 1; step <= steps; ++step)
  {
    const double length = maximumDisplacement * step / steps;
    for (int z = -1; z <= 1; ++z)
    {
      for (int y = -1; y <= 1; ++y)
      {
        for (int x = -1; x <= 1; ++x)
        {
          const int nonZero = (x != 0) + (y != 0) + (z != 0);
          if (nonZero == 0 || (nonZero > 1 && m_LabelSet != LabelSetEnum::SparseWithDiagonals))
          {
            continue;
          }
          const double     scale = length / std::sqrt(static_cast<double>(nonZero));
          DisplacementType label;
          label[0] = scale * x;
          label[1] = scale * y;
          label[2] = scale * z;
          labels.push_back(label);
        }
      }
    }
  }
  return labels;
}

template <typename TFixedImage, typename TMovingImage>
void
BSplineMRFImageRegistrationMethod<TFixedImage, TMovingImage>::VerifyPreconditions() const
{
  Superclass::VerifyPreconditions();
  if (m_NumberOfIterationsPerLevel < 1)
  {
    itkExceptionMacro(<< "NumberOfIterationsPerLevel must be at least 1");
  }
  if (m_NumberOfLabelSteps < 1)
  {
    itkExceptionMacro(<< "NumberOfLabelSteps must be at least 1 (no label to try)");
  }
  if (!(m_MaximumDisplacementFactor > 0.0 && m_MaximumDisplacementFactor <= 1.0) || !(m_MaximumDisplacement >= 0.0) ||
      !std::isfinite(m_MaximumDisplacement))
  {
    itkExceptionMacro(<< "MaximumDisplacementFactor must be in (0, 1] and MaximumDisplacement >= 0");
  }
  if (!(m_LabelShrinkFactor > 0.0 && m_LabelShrinkFactor <= 1.0))
  {
    itkExceptionMacro(<< "LabelShrinkFactor must be in (0, 1], is " << m_LabelShrinkFactor);
  }
  if (!(m_RegularizationWeight >= 0.0) || !std::isfinite(m_RegularizationWeight))
  {
    itkExceptionMacro(<< "RegularizationWeight must be finite and >= 0, is " << m_RegularizationWeight);
  }
  if (!(m_TruncationValue > 0.0))
  {
    itkExceptionMacro(<< "TruncationValue must be > 0, is " << m_TruncationValue);
  }
  if (m_NumberOfHistogramBins < 4)
  {
    itkExceptionMacro(<< "NumberOfHistogramBins must be at least 4, is " << m_NumberOfHistogramBins);
  }
  if (m_NumberOfSolverCycles < 1)
  {
    itkExceptionMacro(<< "NumberOfSolverCycles must be at least 1");
  }
  if (m_Solver == SolverEnum::Exhaustive)
  {
    itkExceptionMacro(<< "The exhaustive solver is for tiny test graphs only");
  }
  this->VerifyImageInputs();
}

template <typename TFixedImage, typename TMovingImage>
void
BSplineMRFImageRegistrationMethod<TFixedImage, TMovingImage>::GenerateData()
{
  m_EnergyValues.clear();
  m_EnergyLevels.clear();
  m_LabelingEnergyValues.clear();
  m_NumberOfRejectedUpdates = 0;
  this->StartRunTimeClock();
  this->UpdateProgress(0.0f);

  // The transform: cubic B-spline over the fixed image, coarsest grid first.
  auto transform = BSplineTransformType::New();
  using InitializerType = BSplineTransformInitializer<BSplineTransformType, FixedImageType>;
  auto                                        initializer = InitializerType::New();
  typename BSplineTransformType::MeshSizeType meshSize;
  meshSize.Fill(this->GetMeshSizeAtLevel(0));
  initializer->SetTransform(transform);
  initializer->SetImage(this->GetFixedImage());
  initializer->SetTransformDomainMeshSize(meshSize);
  initializer->InitializeTransform();
  transform->SetIdentity();

  unsigned int iterationCount = 0;
  for (unsigned int level = 0; level < this->GetNumberOfLevels(); ++level)
  {
    if (level > 0 && this->GetMeshSizeAtLevel(level) != this->GetMeshSizeAtLevel(level - 1))
    {
      using AdaptorType = BSplineTransformParametersAdaptor<BSplineTransformType>;
      auto adaptor = AdaptorType::New();
      meshSize.Fill(this->GetMeshSizeAtLevel(level));
      adaptor->SetTransform(transform);
      adaptor->SetRequiredTransformDomainOrigin(transform->GetTransformDomainOrigin());
      adaptor->SetRequiredTransformDomainPhysicalDimensions(transform->GetTransformDomainPhysicalDimensions());
      adaptor->SetRequiredTransformDomainDirection(transform->GetTransformDomainDirection());
      adaptor->SetRequiredTransformDomainMeshSize(meshSize);
      adaptor->AdaptTransformParameters();
    }
    if (!this->CheckRunTime())
    {
      this->RunLevel(level, transform, iterationCount);
    }
  }
  m_MinimumJacobianDeterminant = this->MinimumJacobianDeterminantOf(transform);
  this->SetTransformOutputValue(transform);
  this->UpdateProgress(1.0f);
}

template <typename TFixedImage, typename TMovingImage>
template <typename TImage>
auto
BSplineMRFImageRegistrationMethod<TFixedImage, TMovingImage>::MakeLevelImage(const TImage * input, unsigned int factor)
  -> InternalImagePointer
{
  if (factor == 1)
  {
    auto cast = CastImageFilter<TImage, InternalImageType>::New();
    cast->SetInput(input);
    cast->Update();
    return cast->GetOutput();
  }
  auto smoother = DiscreteGaussianImageFilter<TImage, InternalImageType>::New();
  smoother->SetInput(input);
  smoother->SetUseImageSpacing(false);
  smoother->SetVariance(0.25 * factor * factor);
  smoother->SetMaximumKernelWidth(64);
  auto shrinker = ShrinkImageFilter<InternalImageType, InternalImageType>::New();
  shrinker->SetInput(smoother->GetOutput());
  shrinker->SetShrinkFactors(factor);
  shrinker->Update();
  return shrinker->GetOutput();
}

template <typename TFixedImage, typename TMovingImage>
void
BSplineMRFImageRegistrationMethod<TFixedImage, TMovingImage>::PrepareLevel(const InternalImageType *    fixed,
                                                                           const MaskImageType *        mask,
                                                                           const InternalImageType *    moving,
                                                                           const BSplineTransformType * transform,
                                                                           LevelData &                  level) const
{
  const auto * coefficients = transform->GetCoefficientImages()[0].GetPointer();
  const auto   fixedDirection = fixed->GetDirection();
  const auto   gridDirection = coefficients->GetDirection();
  for (unsigned int i = 0; i < 3; ++i)
  {
    for (unsigned int j = 0; j < 3; ++j)
    {
      if (std::abs(fixedDirection[i][j] - gridDirection[i][j]) > 1e-6)
      {
        itkExceptionMacro(<< "The control grid must be aligned with the fixed image");
      }
    }
  }
  const auto fixedRegion = fixed->GetBufferedRegion();
  for (unsigned int a = 0; a < 3; ++a)
  {
    level.ImageSize[a] = static_cast<unsigned int>(fixedRegion.GetSize()[a]);
    level.GridSize[a] = static_cast<unsigned int>(coefficients->GetLargestPossibleRegion().GetSize()[a]);
    level.MovingSize[a] = static_cast<unsigned int>(moving->GetBufferedRegion().GetSize()[a]);
  }
  // Per-axis B-spline weights: the grid is aligned with the image, so grid index a depends on image index a only.
  std::array<std::vector<uint8_t>, 3> valid;
  for (unsigned int a = 0; a < 3; ++a)
  {
    const unsigned int n = level.ImageSize[a];
    level.WeightStart[a].assign(n, 0);
    level.Weights[a].assign(4 * n, 0.0);
    valid[a].assign(n, 0);
    const double maxLimit = static_cast<double>(level.GridSize[a]) - 2.0;
    for (unsigned int j = 0; j < n; ++j)
    {
      typename InternalImageType::IndexType index = fixedRegion.GetIndex();
      index[a] += j;
      typename InternalImageType::PointType point;
      fixed->TransformIndexToPhysicalPoint(index, point);
      ContinuousIndex<double, 3> gridIndex;
      coefficients->TransformPhysicalPointToContinuousIndex(point, gridIndex);
      double g = gridIndex[a];
      if (g < 1.0 - 1e-9 || g > maxLimit + 1e-9)
      {
        continue;
      }
      g = std::min(std::max(g, 1.0), maxLimit);
      int start = static_cast<int>(std::floor(g)) - 1;
      start = std::min(start, static_cast<int>(level.GridSize[a]) - 4);
      level.WeightStart[a][j] = start;
      for (unsigned int k = 0; k < 4; ++k)
      {
        level.Weights[a][4 * j + k] = detail::CubicBSpline(g - start - k);
      }
      valid[a][j] = 1;
    }
  }
  // Moving geometry: continuous index = A (x - origin).
  Matrix<double, 3, 3> indexToPoint;
  for (unsigned int i = 0; i < 3; ++i)
  {
    for (unsigned int j = 0; j < 3; ++j)
    {
      indexToPoint[i][j] = moving->GetDirection()[i][j] * moving->GetSpacing()[j];
    }
  }
  const Matrix<double, 3, 3> pointToIndex(indexToPoint.GetInverse());
  for (unsigned int i = 0; i < 3; ++i)
  {
    for (unsigned int j = 0; j < 3; ++j)
    {
      level.MovingIndexPerMM[i][j] = pointToIndex[i][j];
    }
  }
  level.MovingBuffer = moving->GetBufferPointer();
  const auto movingStart = moving->GetBufferedRegion().GetIndex();

  // The used voxels.
  level.Voxels.clear();
  level.RowUsed.assign(static_cast<size_t>(level.ImageSize[1]) * level.ImageSize[2], 0);
  ImageRegionConstIteratorWithIndex<InternalImageType> it(fixed, fixedRegion);
  for (; !it.IsAtEnd(); ++it)
  {
    const auto   index = it.GetIndex();
    unsigned int local[3];
    bool         inside = true;
    for (unsigned int a = 0; a < 3; ++a)
    {
      local[a] = static_cast<unsigned int>(index[a] - fixedRegion.GetIndex()[a]);
      inside = inside && valid[a][local[a]];
    }
    if (!inside)
    {
      continue;
    }
    typename InternalImageType::PointType point;
    fixed->TransformIndexToPhysicalPoint(index, point);
    if (mask != nullptr)
    {
      typename MaskImageType::IndexType maskIndex;
      if (!mask->TransformPhysicalPointToIndex(point, maskIndex) || mask->GetPixel(maskIndex) == 0)
      {
        continue;
      }
    }
    Voxel voxel;
    voxel.FixedValue = it.Get();
    for (unsigned int a = 0; a < 3; ++a)
    {
      voxel.Index[a] = local[a];
      double sum = 0.0;
      for (unsigned int b = 0; b < 3; ++b)
      {
        sum += pointToIndex[a][b] * (point[b] - moving->GetOrigin()[b]);
      }
      voxel.BaseMovingIndex[a] = static_cast<float>(sum - movingStart[a]);
    }
    level.Voxels.push_back(voxel);
    level.RowUsed[local[1] + static_cast<size_t>(level.ImageSize[1]) * local[2]] = 1;
  }
  if (level.Voxels.empty())
  {
    itkExceptionMacro(<< "No fixed voxel lies in the mask and the B-spline domain");
  }

  // Summed support weights and, for NCC, the fixed moments.
  std::vector<double> rows, planes;
  detail::BSplineMRFUnaryCosts::Project<1>(
    level, [](const Voxel &, double * value) { value[0] = 1.0; }, rows, planes, level.SupportWeight);
  level.FixedMoments.clear();
  if (m_Similarity == SimilarityEnum::NormalizedCrossCorrelation)
  {
    detail::BSplineMRFUnaryCosts::Project<2>(
      level,
      [](const Voxel & voxel, double * value) {
        value[0] = voxel.FixedValue;
        value[1] = static_cast<double>(voxel.FixedValue) * voxel.FixedValue;
      },
      rows,
      planes,
      level.FixedMoments);
  }
}

template <typename TFixedImage, typename TMovingImage>
void
BSplineMRFImageRegistrationMethod<TFixedImage, TMovingImage>::ComputeMovingIndices(
  const LevelData &            level,
  const BSplineTransformType * transform,
  std::vector<float> &         indices) const
{
  const auto &         images = transform->GetCoefficientImages();
  const double * const coefficients[3] = { images[0]->GetBufferPointer(),
                                           images[1]->GetBufferPointer(),
                                           images[2]->GetBufferPointer() };
  m_UnaryCosts.ComputeMovingIndices(level, coefficients, indices);
}

template <typename TFixedImage, typename TMovingImage>
double
BSplineMRFImageRegistrationMethod<TFixedImage, TMovingImage>::PointwiseCost(double fixedValue, double movingValue) const
{
  return m_UnaryCosts.PointwiseCost(fixedValue, movingValue);
}

template <typename TFixedImage, typename TMovingImage>
void
BSplineMRFImageRegistrationMethod<TFixedImage, TMovingImage>::ConfigureUnaryCosts()
{
  m_UnaryCosts.SetSimilarity(m_Similarity);
  m_UnaryCosts.SetNumberOfHistogramBins(m_NumberOfHistogramBins);
  m_UnaryCosts.SetNumberOfWorkUnits(this->GetNumberOfWorkUnits());
}

namespace detail
{
/** Displacement vectors as plain arrays, the form of the unary costs' labels and of the solver's label vectors. */
template <typename TVector>
std::vector<std::array<double, 3>>
BSplineMRFLabelArrays(const std::vector<TVector> & vectors)
{
  std::vector<std::array<double, 3>> arrays(vectors.size());
  for (size_t l = 0; l < vectors.size(); ++l)
  {
    arrays[l] = { { vectors[l][0], vectors[l][1], vectors[l][2] } };
  }
  return arrays;
}
} // namespace detail

template <typename TFixedImage, typename TMovingImage>
std::vector<double>
BSplineMRFImageRegistrationMethod<TFixedImage, TMovingImage>::ComputeUnaries(
  const LevelData &                     level,
  const std::vector<float> &            indices,
  const std::vector<DisplacementType> & labels,
  bool                                  stopAtTimeLimit) const
{
  const auto            displacements = detail::BSplineMRFLabelArrays(labels);
  std::function<bool()> timeIsUp;
  if (stopAtTimeLimit)
  {
    timeIsUp = [this] { return this->IsRunTimeExceeded(); };
  }
  return m_UnaryCosts.ComputeUnaries(level, indices, displacements, timeIsUp);
}

template <typename TFixedImage, typename TMovingImage>
std::vector<double>
BSplineMRFImageRegistrationMethod<TFixedImage, TMovingImage>::ComputeUnaryCosts(
  const InternalImageType *             fixed,
  const MaskImageType *                 mask,
  const InternalImageType *             moving,
  const BSplineTransformType *          transform,
  const std::vector<DisplacementType> & labels)
{
  if (fixed == nullptr || moving == nullptr || transform == nullptr || labels.empty())
  {
    itkExceptionMacro(<< "ComputeUnaryCosts needs images, a transform and at least one label");
  }
  this->ConfigureUnaryCosts();
  LevelData level;
  this->PrepareLevel(fixed, mask, moving, transform, level);
  std::vector<float> indices;
  this->ComputeMovingIndices(level, transform, indices);
  if (m_Similarity == SimilarityEnum::MutualInformation)
  {
    m_UnaryCosts.BuildHistogramCosts(level, indices);
  }
  return this->ComputeUnaries(level, indices, labels);
}

template <typename TFixedImage, typename TMovingImage>
double
BSplineMRFImageRegistrationMethod<TFixedImage, TMovingImage>::Pairwise(const DisplacementType & difference,
                                                                       double                   inverseSpacing) const
{
  const double squared = difference.GetSquaredNorm() * inverseSpacing * inverseSpacing;
  switch (m_PairwiseFunction)
  {
    case PairwiseFunctionEnum::Quadratic:
      return m_RegularizationWeight * squared;
    case PairwiseFunctionEnum::Absolute:
      return m_RegularizationWeight * std::sqrt(squared);
    case PairwiseFunctionEnum::Truncated:
    default:
      return m_RegularizationWeight * std::min(std::sqrt(squared), m_TruncationValue);
  }
}

namespace detail
{
/** The 6-neighbour edges of a control grid, in parameter order. */
inline std::vector<std::pair<SizeValueType, SizeValueType>>
BSplineMRFGridEdges(const std::array<unsigned int, 3> & size)
{
  std::vector<std::pair<SizeValueType, SizeValueType>> edges;
  const SizeValueType                                  strides[3] = { 1, size[0], SizeValueType{ size[0] } * size[1] };
  for (unsigned int z = 0; z < size[2]; ++z)
  {
    for (unsigned int y = 0; y < size[1]; ++y)
    {
      for (unsigned int x = 0; x < size[0]; ++x)
      {
        const SizeValueType p = x + strides[1] * y + strides[2] * z;
        const unsigned int  position[3] = { x, y, z };
        for (unsigned int a = 0; a < 3; ++a)
        {
          if (position[a] + 1 < size[a])
          {
            edges.emplace_back(p, p + strides[a]);
          }
        }
      }
    }
  }
  return edges;
}
} // namespace detail

template <typename TFixedImage, typename TMovingImage>
double
BSplineMRFImageRegistrationMethod<TFixedImage, TMovingImage>::RegularizationEnergy(
  const BSplineTransformType * transform) const
{
  const auto &                      images = transform->GetCoefficientImages();
  const auto                        size = images[0]->GetLargestPossibleRegion().GetSize();
  const std::array<unsigned int, 3> gridSize{ static_cast<unsigned int>(size[0]),
                                              static_cast<unsigned int>(size[1]),
                                              static_cast<unsigned int>(size[2]) };
  const auto &                      spacing = images[0]->GetSpacing();
  const double                      inverseSpacing = 3.0 / (spacing[0] + spacing[1] + spacing[2]);
  double                            energy = 0.0;
  for (const auto & edge : detail::BSplineMRFGridEdges(gridSize))
  {
    DisplacementType difference;
    for (unsigned int d = 0; d < 3; ++d)
    {
      const double * c = images[d]->GetBufferPointer();
      difference[d] = c[edge.first] - c[edge.second];
    }
    energy += this->Pairwise(difference, inverseSpacing);
  }
  return energy;
}

template <typename TFixedImage, typename TMovingImage>
double
BSplineMRFImageRegistrationMethod<TFixedImage, TMovingImage>::MinimumJacobianDeterminantOf(
  const BSplineTransformType * transform) const
{
  // Two samples per axis in each cell of the control grid, at local coordinates 1/4 and 3/4: there the 1-D
  // weights and derivatives are the same in every cell. The 27 partial sums per cell and sample (3 components x 3
  // derivative directions, each a tensor product of 4-tap filters) are computed separably: along x, then y, then z.
  const auto & images = transform->GetCoefficientImages();
  const auto   size = images[0]->GetLargestPossibleRegion().GetSize();
  const auto & spacing = images[0]->GetSpacing();
  const auto   inverseDirection = images[0]->GetInverseDirection();
  // taps[s][t][k]: sample s (local 1/4 or 3/4), t = 0 the weights, t = 1 the derivatives.
  double taps[2][2][4];
  for (unsigned int sample = 0; sample < 2; ++sample)
  {
    const double t = 0.25 + 0.5 * sample;
    for (unsigned int k = 0; k < 4; ++k)
    {
      taps[sample][0][k] = detail::CubicBSpline(1.0 + t - k);
      taps[sample][1][k] = detail::CubicBSplineDerivative(1.0 + t - k);
    }
  }
  const size_t n[3] = { size[0], size[1], size[2] };
  const size_t cells[3] = { n[0] - 3, n[1] - 3, n[2] - 3 };
  // Filters one axis of a (nx, ny, nz) array into a (cells along that axis) one, with taps f.
  const auto filterAxis = [](const double * in,
                             const size_t(&inSize)[3],
                             unsigned int          axis,
                             const double *        f,
                             std::vector<double> & out,
                             size_t(&outSize)[3]) {
    for (unsigned int a = 0; a < 3; ++a)
    {
      outSize[a] = a == axis ? inSize[a] - 3 : inSize[a];
    }
    out.resize(outSize[0] * outSize[1] * outSize[2]);
    const size_t stride = axis == 0 ? 1 : (axis == 1 ? inSize[0] : inSize[0] * inSize[1]);
    for (size_t z = 0; z < outSize[2]; ++z)
    {
      for (size_t y = 0; y < outSize[1]; ++y)
      {
        for (size_t x = 0; x < outSize[0]; ++x)
        {
          const double * first = &in[x + inSize[0] * (y + inSize[1] * z)];
          out[x + outSize[0] * (y + outSize[1] * z)] =
            f[0] * first[0] + f[1] * first[stride] + f[2] * first[2 * stride] + f[3] * first[3 * stride];
        }
      }
    }
  };
  const size_t numberOfCells = cells[0] * cells[1] * cells[2];
  // gradient[s][d][j][cell] = d displacement_d / d grid index_j at sample s of the cell.
  std::vector<double> gradient[8][3][3];
  std::vector<double> alongX, alongY, alongZ;
  size_t              sizeX[3], sizeY[3], sizeZ[3];
  for (unsigned int d = 0; d < 3; ++d)
  {
    for (unsigned int sx = 0; sx < 2; ++sx)
    {
      for (unsigned int tx = 0; tx < 2; ++tx)
      {
        filterAxis(images[d]->GetBufferPointer(), n, 0, taps[sx][tx], alongX, sizeX);
        for (unsigned int sy = 0; sy < 2; ++sy)
        {
          for (unsigned int ty = 0; ty + tx < 2; ++ty)
          {
            filterAxis(alongX.data(), sizeX, 1, taps[sy][ty], alongY, sizeY);
            for (unsigned int sz = 0; sz < 2; ++sz)
            {
              // Exactly one axis takes the derivative taps; it is the derivative's direction.
              for (unsigned int tz = (tx + ty == 0) ? 1 : 0; tz + ty + tx < 2; ++tz)
              {
                filterAxis(alongY.data(), sizeY, 2, taps[sz][tz], alongZ, sizeZ);
                gradient[sx + 2 * sy + 4 * sz][d][tx ? 0 : (ty ? 1 : 2)].swap(alongZ);
              }
            }
          }
        }
      }
    }
  }
  double minimum = std::numeric_limits<double>::max();
  for (unsigned int sample = 0; sample < 8; ++sample)
  {
    for (size_t cell = 0; cell < numberOfCells; ++cell)
    {
      Matrix<double, 3, 3> jacobian;
      for (unsigned int d = 0; d < 3; ++d)
      {
        for (unsigned int k = 0; k < 3; ++k)
        {
          double sum = (d == k) ? 1.0 : 0.0;
          for (unsigned int j = 0; j < 3; ++j)
          {
            sum += gradient[sample][d][j][cell] * inverseDirection[j][k] / spacing[j];
          }
          jacobian[d][k] = sum;
        }
      }
      minimum = std::min(minimum, detail::MatrixDeterminant(jacobian));
    }
  }
  return minimum;
}

template <typename TFixedImage, typename TMovingImage>
void
BSplineMRFImageRegistrationMethod<TFixedImage, TMovingImage>::RunLevel(unsigned int           level,
                                                                       BSplineTransformType * transform,
                                                                       unsigned int &         iterationCount)
{
  const unsigned int   factor = m_UseImagePyramid ? 1u << (this->GetNumberOfLevels() - 1 - level) : 1u;
  InternalImagePointer fixed = MakeLevelImage(this->GetFixedImage(), factor);
  InternalImagePointer moving = MakeLevelImage(this->GetMovingImage(), factor);

  this->ConfigureUnaryCosts();
  LevelData data;
  this->PrepareLevel(fixed, this->GetFixedImageMask(), moving, transform, data);
  std::vector<float> indices;
  std::vector<float> candidateIndices;
  this->ComputeMovingIndices(data, transform, indices);
  if (m_Similarity == SimilarityEnum::MutualInformation)
  {
    m_UnaryCosts.BuildHistogramCosts(data, indices);
  }

  const auto & spacing = transform->GetCoefficientImages()[0]->GetSpacing();
  const double meanSpacing = (spacing[0] + spacing[1] + spacing[2]) / 3.0;
  const double inverseSpacing = 1.0 / meanSpacing;
  double       maximumDisplacement = m_MaximumDisplacement > 0.0 ? m_MaximumDisplacement / std::pow(2.0, level)
                                                                 : m_MaximumDisplacementFactor * meanSpacing;

  const SizeValueType numberOfNodes = data.SupportWeight.size();
  const auto          edges = detail::BSplineMRFGridEdges(data.GridSize);
  auto                solver = MRFLabelingSolver::New();
  solver->SetAlgorithm(m_Solver);
  solver->SetMaximumNumberOfCycles(m_NumberOfSolverCycles);
  solver->ReuseSpanningTreeOn(); // the level's first iteration chooses the tree
  solver->SetNumberOfNodes(numberOfNodes);
  for (const auto & edge : edges)
  {
    solver->AddEdge(edge.first, edge.second);
  }

  const std::vector<DisplacementType> zeroLabel(1, MakeLabels(0.0)[0]);
  std::vector<DisplacementType>       edgeDifferences(edges.size());
  const double totalIterations = static_cast<double>(m_NumberOfIterationsPerLevel) * this->GetNumberOfLevels();
  for (unsigned int iteration = 0; iteration < m_NumberOfIterationsPerLevel; ++iteration)
  {
    if (this->GetAbortGenerateData())
    {
      ProcessAborted exception(__FILE__, __LINE__);
      exception.SetDescription("BSplineMRFImageRegistrationMethod aborted");
      throw exception;
    }
    if (this->CheckRunTime())
    {
      break;
    }
    const auto labels = this->MakeLabels(maximumDisplacement);
    auto       unary = this->ComputeUnaries(data, indices, labels, true);
    if (unary.empty())
    {
      this->CheckRunTime(); // incomplete costs: the iteration is dropped
      break;
    }
    double dataEnergy = 0.0;
    for (SizeValueType p = 0; p < numberOfNodes; ++p)
    {
      dataEnergy += unary[p * labels.size()];
    }
    const double energy = dataEnergy + this->RegularizationEnergy(transform);

    // Pairwise terms of this iteration: lambda rho((u_p + d_a - u_q - d_b) / h).
    const auto & parameters = transform->GetParameters();
    for (SizeValueType k = 0; k < edges.size(); ++k)
    {
      for (unsigned int d = 0; d < 3; ++d)
      {
        edgeDifferences[k][d] =
          parameters[d * numberOfNodes + edges[k].first] - parameters[d * numberOfNodes + edges[k].second];
      }
    }
    solver->SetNumberOfLabels(static_cast<MRFLabelingSolver::LabelType>(labels.size()));
    solver->SetUnaryCosts(std::move(unary));
    if (m_PairwiseFunction == PairwiseFunctionEnum::Quadratic)
    {
      // The solver's inline model: lambda |u_p + d_a - u_q - d_b|^2 / h^2.
      solver->SetQuadraticPairwise(detail::BSplineMRFLabelArrays(labels),
                                   detail::BSplineMRFLabelArrays(edgeDifferences),
                                   m_RegularizationWeight * inverseSpacing * inverseSpacing);
    }
    else
    {
      solver->SetPairwiseFunction([this, &edgeDifferences, &labels, inverseSpacing](SizeValueType                edge,
                                                                                    MRFLabelingSolver::LabelType a,
                                                                                    MRFLabelingSolver::LabelType b) {
        return this->Pairwise(edgeDifferences[edge] + labels[a] - labels[b], inverseSpacing);
      });
    }
    // The solver gets the time left (at least a trace, so that it stops at once when none is).
    solver->SetMaximumRunTime(
      this->GetMaximumRunTime() > 0.0 ? std::max(1e-9, this->GetMaximumRunTime() - this->GetElapsedRunTime()) : 0.0);
    MRFLabelingSolver::LabelingType labeling(numberOfNodes, 0);
    m_LabelingEnergyValues.push_back(solver->Solve(labeling));

    // Candidate update u + d, kept if it neither folds nor raises the energy.
    bool moved = false;
    auto candidate = parameters;
    for (SizeValueType p = 0; p < numberOfNodes; ++p)
    {
      if (labeling[p] != 0)
      {
        moved = true;
        for (unsigned int d = 0; d < 3; ++d)
        {
          candidate[d * numberOfNodes + p] += labels[labeling[p]][d];
        }
      }
    }
    double acceptedEnergy = energy;
    if (moved)
    {
      auto candidateTransform = BSplineTransformType::New();
      candidateTransform->SetFixedParameters(transform->GetFixedParameters());
      candidateTransform->SetParametersByValue(candidate);
      bool accept =
        !m_RejectFoldingUpdates || this->MinimumJacobianDeterminantOf(candidateTransform) >= m_FoldingThreshold;
      if (accept)
      {
        this->ComputeMovingIndices(data, candidateTransform, candidateIndices);
        const auto zeroUnary = this->ComputeUnaries(data, candidateIndices, zeroLabel);
        // Summed in the order of the iteration's energy above, so that equal energies compare equal.
        double candidateEnergy = 0.0;
        for (const double value : zeroUnary)
        {
          candidateEnergy += value;
        }
        candidateEnergy += this->RegularizationEnergy(candidateTransform);
        accept = candidateEnergy <= energy;
        if (accept)
        {
          transform->SetParametersByValue(candidate);
          indices.swap(candidateIndices);
          acceptedEnergy = candidateEnergy;
        }
      }
      if (!accept)
      {
        ++m_NumberOfRejectedUpdates;
      }
    }
    m_EnergyValues.push_back(acceptedEnergy);
    m_EnergyLevels.push_back(level);
    maximumDisplacement *= m_LabelShrinkFactor;
    ++iterationCount;
    this->UpdateProgress(static_cast<float>(std::min(0.99, iterationCount / totalIterations)));
    this->InvokeEvent(IterationEvent());
  }
}

template <typename TFixedImage, typename TMovingImage>
void
BSplineMRFImageRegistrationMethod<TFixedImage, TMovingImage>::PrintSelf(std::ostream & os, Indent indent) const
{
  Superclass::PrintSelf(os, indent);
  os << indent << "NumberOfIterationsPerLevel: " << m_NumberOfIterationsPerLevel << std::endl;
  os << indent << "LabelSet: " << m_LabelSet << std::endl;
  os << indent << "NumberOfLabelSteps: " << m_NumberOfLabelSteps << std::endl;
  os << indent << "MaximumDisplacementFactor: " << m_MaximumDisplacementFactor << std::endl;
  os << indent << "MaximumDisplacement: " << m_MaximumDisplacement << std::endl;
  os << indent << "LabelShrinkFactor: " << m_LabelShrinkFactor << std::endl;
  os << indent << "Similarity: " << m_Similarity << std::endl;
  os << indent << "NumberOfHistogramBins: " << m_NumberOfHistogramBins << std::endl;
  os << indent << "RegularizationWeight: " << m_RegularizationWeight << std::endl;
  os << indent << "PairwiseFunction: " << m_PairwiseFunction << std::endl;
  os << indent << "TruncationValue: " << m_TruncationValue << std::endl;
  os << indent << "RejectFoldingUpdates: " << (m_RejectFoldingUpdates ? "On" : "Off") << std::endl;
  os << indent << "UseImagePyramid: " << (m_UseImagePyramid ? "On" : "Off") << std::endl;
  os << indent << "FoldingThreshold: " << m_FoldingThreshold << std::endl;
  os << indent << "NumberOfSolverCycles: " << m_NumberOfSolverCycles << std::endl;
  os << indent << "Solver: " << m_Solver << std::endl;
  os << indent << "EnergyValues: " << m_EnergyValues.size() << " iterations" << std::endl;
  os << indent << "EnergyLevels: " << m_EnergyLevels.size() << std::endl;
  os << indent << "LabelingEnergyValues: " << m_LabelingEnergyValues.size() << std::endl;
  os << indent << "NumberOfRejectedUpdates: " << m_NumberOfRejectedUpdates << std::endl;
  os << indent << "MinimumJacobianDeterminant: " << m_MinimumJacobianDeterminant << std::endl;
  m_UnaryCosts.Print(os, indent);
}
} // namespace itk

#endif // itkBSplineMRFImageRegistrationMethod_hxx
