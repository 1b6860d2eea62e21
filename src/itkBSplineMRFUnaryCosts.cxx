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
#include "FFDShapeMatchingDetail/itkBSplineMRFUnaryCosts.h"
#include "itkMultiThreaderBase.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>

namespace itk
{
namespace detail
{
namespace
{
/** Trilinear interpolation of a buffer at a continuous index, clamped to the buffer (constant extension). */
inline double
BSplineMRFInterpolate(const float * buffer, const std::array<unsigned int, 3> & size, const double * index)
{
  size_t base = 0;
  size_t step[3];
  double t[3];
  size_t stride = 1;
  for (unsigned int a = 0; a < 3; ++a)
  {
    const double maxIndex = static_cast<double>(size[a] - 1);
    const double c = std::min(std::max(index[a], 0.0), maxIndex);
    auto         i = static_cast<size_t>(c);
    if (i >= size[a] - 1)
    {
      i = size[a] - 1;
      t[a] = 0.0;
      step[a] = 0;
    }
    else
    {
      t[a] = c - static_cast<double>(i);
      step[a] = stride;
    }
    base += i * stride;
    stride *= size[a];
  }
  const float * p = buffer + base;
  const double  c00 = p[0] + t[0] * (p[step[0]] - p[0]);
  const double  c10 = p[step[1]] + t[0] * (p[step[1] + step[0]] - p[step[1]]);
  const double  c01 = p[step[2]] + t[0] * (p[step[2] + step[0]] - p[step[2]]);
  const double  c11 = p[step[2] + step[1]] + t[0] * (p[step[2] + step[1] + step[0]] - p[step[2] + step[1]]);
  const double  c0 = c00 + t[1] * (c10 - c00);
  const double  c1 = c01 + t[1] * (c11 - c01);
  return c0 + t[2] * (c1 - c0);
}
} // namespace

void
BSplineMRFUnaryCosts::ComputeMovingIndices(const LevelData &    level,
                                           const double * const coefficients[3],
                                           std::vector<float> & indices) const
{
  const size_t gx = level.GridSize[0];
  const size_t gxy = gx * level.GridSize[1];
  indices.resize(3 * level.Voxels.size());
  const auto body = [&](SizeValueType v) {
    const Voxel &  voxel = level.Voxels[v];
    const double * wx = &level.Weights[0][4 * voxel.Index[0]];
    const double * wy = &level.Weights[1][4 * voxel.Index[1]];
    const double * wz = &level.Weights[2][4 * voxel.Index[2]];
    const size_t   base = level.WeightStart[0][voxel.Index[0]] + gx * level.WeightStart[1][voxel.Index[1]] +
                        gxy * level.WeightStart[2][voxel.Index[2]];
    double displacement[3] = { 0.0, 0.0, 0.0 };
    for (unsigned int kz = 0; kz < 4; ++kz)
    {
      for (unsigned int ky = 0; ky < 4; ++ky)
      {
        const double wzy = wz[kz] * wy[ky];
        const size_t row = base + kz * gxy + ky * gx;
        for (unsigned int d = 0; d < 3; ++d)
        {
          const double * c = coefficients[d] + row;
          displacement[d] += wzy * (wx[0] * c[0] + wx[1] * c[1] + wx[2] * c[2] + wx[3] * c[3]);
        }
      }
    }
    for (unsigned int a = 0; a < 3; ++a)
    {
      double shift = 0.0;
      for (unsigned int b = 0; b < 3; ++b)
      {
        shift += level.MovingIndexPerMM[a][b] * displacement[b];
      }
      indices[3 * v + a] = static_cast<float>(voxel.BaseMovingIndex[a] + shift);
    }
  };
  auto threader = MultiThreaderBase::New();
  threader->SetNumberOfWorkUnits(m_NumberOfWorkUnits);
  threader->ParallelizeArray(0, level.Voxels.size(), body, nullptr);
}

double
BSplineMRFUnaryCosts::PointwiseCost(double fixedValue, double movingValue) const
{
  switch (m_Similarity)
  {
    case SimilarityEnum::SumOfSquaredDifferences:
      return (fixedValue - movingValue) * (fixedValue - movingValue);
    case SimilarityEnum::SumOfAbsoluteDifferences:
      return std::abs(fixedValue - movingValue);
    case SimilarityEnum::MutualInformation: {
      const double   bins = m_NumberOfHistogramBins;
      const double   fb = std::min(std::max((fixedValue - m_FixedBinOffset) * m_FixedBinScale, 0.0), bins - 1.0);
      const double   mb = std::min(std::max((movingValue - m_MovingBinOffset) * m_MovingBinScale, 0.0), bins - 1.0);
      const auto     fi = std::min(static_cast<unsigned int>(fb), m_NumberOfHistogramBins - 2);
      const auto     mi = std::min(static_cast<unsigned int>(mb), m_NumberOfHistogramBins - 2);
      const double   ft = fb - fi;
      const double   mt = mb - mi;
      const double * row0 = &m_HistogramCosts[fi * m_NumberOfHistogramBins + mi];
      const double * row1 = row0 + m_NumberOfHistogramBins;
      return (1.0 - ft) * ((1.0 - mt) * row0[0] + mt * row0[1]) + ft * ((1.0 - mt) * row1[0] + mt * row1[1]);
    }
    case SimilarityEnum::NormalizedCrossCorrelation:
    default:
      return 0.0;
  }
}

void
BSplineMRFUnaryCosts::BuildHistogramCosts(const LevelData & level, const std::vector<float> & indices)
{
  const unsigned int  bins = m_NumberOfHistogramBins;
  std::vector<double> movingValues(level.Voxels.size());
  double              fixedMin = std::numeric_limits<double>::max();
  double              fixedMax = -fixedMin;
  for (size_t v = 0; v < level.Voxels.size(); ++v)
  {
    const double index[3] = { indices[3 * v], indices[3 * v + 1], indices[3 * v + 2] };
    movingValues[v] = BSplineMRFInterpolate(level.MovingBuffer, level.MovingSize, index);
    fixedMin = std::min(fixedMin, static_cast<double>(level.Voxels[v].FixedValue));
    fixedMax = std::max(fixedMax, static_cast<double>(level.Voxels[v].FixedValue));
  }
  const size_t movingCount = static_cast<size_t>(level.MovingSize[0]) * level.MovingSize[1] * level.MovingSize[2];
  const auto   movingRange = std::minmax_element(level.MovingBuffer, level.MovingBuffer + movingCount);
  const double movingMin = *movingRange.first;
  const double movingMax = *movingRange.second;
  m_FixedBinOffset = fixedMin;
  m_FixedBinScale = (bins - 1) / std::max(fixedMax - fixedMin, 1e-12);
  m_MovingBinOffset = movingMin;
  m_MovingBinScale = (bins - 1) / std::max(movingMax - movingMin, 1e-12);

  // Joint histogram with linear splatting, then a Gaussian Parzen window of one bin.
  std::vector<double> joint(bins * bins, 0.0);
  for (size_t v = 0; v < level.Voxels.size(); ++v)
  {
    const double fb =
      std::min(std::max((level.Voxels[v].FixedValue - m_FixedBinOffset) * m_FixedBinScale, 0.0), bins - 1.0);
    const double mb = std::min(std::max((movingValues[v] - m_MovingBinOffset) * m_MovingBinScale, 0.0), bins - 1.0);
    const auto   fi = std::min(static_cast<unsigned int>(fb), bins - 2);
    const auto   mi = std::min(static_cast<unsigned int>(mb), bins - 2);
    const double ft = fb - fi;
    const double mt = mb - mi;
    joint[fi * bins + mi] += (1.0 - ft) * (1.0 - mt);
    joint[fi * bins + mi + 1] += (1.0 - ft) * mt;
    joint[(fi + 1) * bins + mi] += ft * (1.0 - mt);
    joint[(fi + 1) * bins + mi + 1] += ft * mt;
  }
  double kernel[7];
  for (int k = -3; k <= 3; ++k)
  {
    kernel[k + 3] = std::exp(-0.5 * k * k);
  }
  std::vector<double> smoothed(bins * bins, 0.0);
  for (unsigned int pass = 0; pass < 2; ++pass)
  {
    std::fill(smoothed.begin(), smoothed.end(), 0.0);
    for (unsigned int i = 0; i < bins; ++i)
    {
      for (unsigned int j = 0; j < bins; ++j)
      {
        double sum = 0.0;
        double weight = 0.0;
        for (int k = -3; k <= 3; ++k)
        {
          const int n = static_cast<int>(pass == 0 ? i : j) + k;
          if (n < 0 || n >= static_cast<int>(bins))
          {
            continue;
          }
          sum += kernel[k + 3] * (pass == 0 ? joint[n * bins + j] : joint[i * bins + n]);
          weight += kernel[k + 3];
        }
        smoothed[i * bins + j] = sum / weight;
      }
    }
    joint.swap(smoothed);
  }
  double total = 0.0;
  for (const double h : joint)
  {
    total += h;
  }
  std::vector<double> fixedMarginal(bins, 0.0);
  std::vector<double> movingMarginal(bins, 0.0);
  for (unsigned int i = 0; i < bins; ++i)
  {
    for (unsigned int j = 0; j < bins; ++j)
    {
      joint[i * bins + j] /= total;
      fixedMarginal[i] += joint[i * bins + j];
      movingMarginal[j] += joint[i * bins + j];
    }
  }
  m_HistogramCosts.assign(bins * bins, 0.0);
  constexpr double epsilon = 1e-10;
  for (unsigned int i = 0; i < bins; ++i)
  {
    for (unsigned int j = 0; j < bins; ++j)
    {
      m_HistogramCosts[i * bins + j] =
        -std::log((joint[i * bins + j] + epsilon) / (fixedMarginal[i] * movingMarginal[j] + epsilon));
    }
  }
}

std::vector<double>
BSplineMRFUnaryCosts::ComputeUnaries(const LevelData &              level,
                                     const std::vector<float> &     indices,
                                     const std::vector<LabelType> & labels,
                                     const std::function<bool()> &  timeIsUp) const
{
  const size_t        numberOfNodes = level.SupportWeight.size();
  const size_t        numberOfLabels = labels.size();
  std::vector<double> unary(numberOfNodes * numberOfLabels, 0.0);
  double              largestWeight = 0.0;
  for (const double w : level.SupportWeight)
  {
    largestWeight = std::max(largestWeight, w);
  }
  const double minimumWeight = 1e-6 * largestWeight;
  const bool   ncc = m_Similarity == SimilarityEnum::NormalizedCrossCorrelation;

  std::atomic<bool> stopped{ false };
  const auto        body = [&](SizeValueType l) {
    if (timeIsUp && (stopped || timeIsUp()))
    {
      stopped = true;
      return;
    }
    double shift[3];
    for (unsigned int a = 0; a < 3; ++a)
    {
      shift[a] = 0.0;
      for (unsigned int b = 0; b < 3; ++b)
      {
        shift[a] += level.MovingIndexPerMM[a][b] * labels[l][b];
      }
    }
    const Voxel * first = level.Voxels.data();
    const auto    movingAt = [&](const Voxel & voxel) {
      const size_t v = &voxel - first;
      const double index[3] = { indices[3 * v] + shift[0],
                                indices[3 * v + 1] + shift[1],
                                indices[3 * v + 2] + shift[2] };
      return BSplineMRFInterpolate(level.MovingBuffer, level.MovingSize, index);
    };
    std::vector<double> rows, planes, projected;
    switch (m_Similarity)
    {
      case SimilarityEnum::SumOfSquaredDifferences:
        Project<1>(
          level,
          [&](const Voxel & voxel, double * out) {
            const double difference = voxel.FixedValue - movingAt(voxel);
            out[0] = difference * difference;
          },
          rows,
          planes,
          projected);
        break;
      case SimilarityEnum::SumOfAbsoluteDifferences:
        Project<1>(
          level,
          [&](const Voxel & voxel, double * out) { out[0] = std::abs(voxel.FixedValue - movingAt(voxel)); },
          rows,
          planes,
          projected);
        break;
      case SimilarityEnum::MutualInformation:
        Project<1>(
          level,
          [&](const Voxel & voxel, double * out) { out[0] = this->PointwiseCost(voxel.FixedValue, movingAt(voxel)); },
          rows,
          planes,
          projected);
        break;
      case SimilarityEnum::NormalizedCrossCorrelation:
      default:
        Project<3>(
          level,
          [&](const Voxel & voxel, double * out) {
            const double moving = movingAt(voxel);
            out[0] = moving;
            out[1] = moving * moving;
            out[2] = moving * voxel.FixedValue;
          },
          rows,
          planes,
          projected);
        break;
    }
    for (size_t p = 0; p < numberOfNodes; ++p)
    {
      const double w = level.SupportWeight[p];
      double       cost = 0.0;
      if (w > minimumWeight)
      {
        if (ncc)
        {
          const double meanFixed = level.FixedMoments[2 * p] / w;
          const double meanMoving = projected[3 * p] / w;
          const double varianceFixed = level.FixedMoments[2 * p + 1] / w - meanFixed * meanFixed;
          const double varianceMoving = projected[3 * p + 1] / w - meanMoving * meanMoving;
          const double covariance = projected[3 * p + 2] / w - meanFixed * meanMoving;
          const double product = varianceFixed * varianceMoving;
          cost = product > 1e-20 ? 1.0 - covariance / std::sqrt(product) : 1.0;
        }
        else
        {
          cost = projected[p] / w;
        }
      }
      unary[p * numberOfLabels + l] = cost;
    }
  };
  auto threader = MultiThreaderBase::New();
  threader->SetNumberOfWorkUnits(m_NumberOfWorkUnits);
  threader->ParallelizeArray(0, numberOfLabels, body, nullptr);
  if (stopped)
  {
    unary.clear();
  }
  return unary;
}

void
BSplineMRFUnaryCosts::Print(std::ostream & os, Indent indent) const
{
  os << indent << "HistogramCosts: " << m_HistogramCosts.size() << " bins" << std::endl;
  os << indent << "FixedBinScale: " << m_FixedBinScale << std::endl;
  os << indent << "FixedBinOffset: " << m_FixedBinOffset << std::endl;
  os << indent << "MovingBinScale: " << m_MovingBinScale << std::endl;
  os << indent << "MovingBinOffset: " << m_MovingBinOffset << std::endl;
}
} // namespace detail
} // namespace itk
