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
#ifndef itkBSplineMRFUnaryCosts_h
#define itkBSplineMRFUnaryCosts_h

#include "FFDShapeMatchingExport.h"
#include "itkBSplineMRFImageRegistrationMethodEnums.h"
#include "itkIndent.h"

#include <array>
#include <cstdint>
#include <functional>
#include <ostream>
#include <vector>

namespace itk
{
namespace detail
{
/** \class BSplineMRFUnaryCosts
 * \brief The unary costs of BSplineMRFImageRegistrationMethod: for each control point and each displacement label,
 * the dissimilarity of the fixed image and the moving image shifted by the label, averaged over the control point's
 * support with its B-spline weights.
 *
 * A level's used fixed voxels, their separable B-spline weights and the moving image's buffer are gathered once
 * (LevelData, filled by the registration method); then, per iteration, ComputeMovingIndices() maps the voxels through
 * the current B-spline, BuildHistogramCosts() refreshes the mutual-information cost table, and ComputeUnaries()
 * projects each label's pointwise costs onto the control points (separably: along x, y, then z), one label per work
 * unit. Similarities: sum of squared or absolute differences, pointwise mutual information from a Parzen-smoothed
 * joint histogram, normalized cross-correlation of the supports.
 *
 * Plain double arithmetic on float buffers, independent of the registration's image types: compiled once into the
 * module's library.
 *
 * \ingroup FFDShapeMatching
 */
class FFDShapeMatching_EXPORT BSplineMRFUnaryCosts
{
public:
  using SimilarityEnum = BSplineMRFImageRegistrationMethodEnums::Similarity;
  using LabelType = std::array<double, 3>;

  /** A used fixed voxel of a level: its intensity, grid position and base moving continuous index. */
  struct Voxel
  {
    float         FixedValue;
    std::uint32_t Index[3];
    float         BaseMovingIndex[3];
  };

  /** Everything about a level's voxels and grid that does not change during the level. */
  struct LevelData
  {
    std::vector<Voxel>                 Voxels;
    std::array<std::vector<int>, 3>    WeightStart;
    std::array<std::vector<double>, 3> Weights; // 4 per image index
    std::array<unsigned int, 3>        ImageSize{};
    std::array<unsigned int, 3>        GridSize{};
    double                             MovingIndexPerMM[3][3]{};
    const float *                      MovingBuffer{ nullptr };
    std::array<unsigned int, 3>        MovingSize{};
    std::vector<double>                SupportWeight; // sum of w_p over the used voxels, per control point
    std::vector<double>                FixedMoments;  // sum of w_p f and w_p f^2 (NCC)
    std::vector<std::uint8_t>          RowUsed;       // per (y, z) row of the image
  };

  void
  SetSimilarity(SimilarityEnum similarity)
  {
    m_Similarity = similarity;
  }

  /** Bins per axis of the joint histogram (mutual information); at least 2. */
  void
  SetNumberOfHistogramBins(unsigned int bins)
  {
    m_NumberOfHistogramBins = bins;
  }

  void
  SetNumberOfWorkUnits(unsigned int workUnits)
  {
    m_NumberOfWorkUnits = workUnits;
  }

  /** Continuous moving indices (3 per used voxel) of the level's voxels mapped through the B-spline whose three
   * coefficient buffers (on the level's control grid) are given. */
  void
  ComputeMovingIndices(const LevelData &    level,
                       const double * const coefficients[3],
                       std::vector<float> & indices) const;

  /** The mutual-information cost table from the joint histogram of the fixed values and the moving values at
   * indices. */
  void
  BuildHistogramCosts(const LevelData & level, const std::vector<float> & indices);

  /** Pointwise dissimilarity of a fixed and a moving intensity, with the current histogram for MutualInformation.
   * Not used for NormalizedCrossCorrelation (0). */
  double
  PointwiseCost(double fixedValue, double movingValue) const;

  /** Unary costs of the labels (displacements in mm), control point-major; when timeIsUp is given and says so
   * before a label, an empty vector. */
  std::vector<double>
  ComputeUnaries(const LevelData &              level,
                 const std::vector<float> &     indices,
                 const std::vector<LabelType> & labels,
                 const std::function<bool()> &  timeIsUp = {}) const;

  /** Projects per-voxel values (VChannels of them, from valueFunction(voxel, values)) onto the control points with
   * their B-spline weights, separably: along x into rows, along y into planes, along z into projected. */
  template <unsigned int VChannels, typename TValueFunction>
  static void
  Project(const LevelData &     level,
          TValueFunction &&     valueFunction,
          std::vector<double> & rows,
          std::vector<double> & planes,
          std::vector<double> & projected)
  {
    const size_t           ny = level.ImageSize[1];
    const size_t           nz = level.ImageSize[2];
    const size_t           gx = level.GridSize[0];
    const size_t           gy = level.GridSize[1];
    const size_t           gz = level.GridSize[2];
    constexpr unsigned int channels = VChannels;
    // Along x: rows[(z * ny + y) * gx + cx][channel].
    rows.assign(nz * ny * gx * channels, 0.0);
    double value[VChannels];
    for (const Voxel & voxel : level.Voxels)
    {
      valueFunction(voxel, value);
      const size_t base =
        ((voxel.Index[2] * ny + voxel.Index[1]) * gx + level.WeightStart[0][voxel.Index[0]]) * channels;
      const double * weights = &level.Weights[0][4 * voxel.Index[0]];
      for (unsigned int k = 0; k < 4; ++k)
      {
        for (unsigned int c = 0; c < channels; ++c)
        {
          rows[base + k * channels + c] += weights[k] * value[c];
        }
      }
    }
    // Along y: planes[(z * gy + cy) * gx + cx][channel].
    planes.assign(nz * gy * gx * channels, 0.0);
    const size_t rowLength = gx * channels;
    for (size_t z = 0; z < nz; ++z)
    {
      for (size_t y = 0; y < ny; ++y)
      {
        if (!level.RowUsed[y + ny * z])
        {
          continue;
        }
        const double * row = &rows[(z * ny + y) * rowLength];
        const double * weights = &level.Weights[1][4 * y];
        const size_t   start = level.WeightStart[1][y];
        for (unsigned int k = 0; k < 4; ++k)
        {
          double *     plane = &planes[(z * gy + start + k) * rowLength];
          const double w = weights[k];
          for (size_t i = 0; i < rowLength; ++i)
          {
            plane[i] += w * row[i];
          }
        }
      }
    }
    // Along z: projected[(cz * gy + cy) * gx + cx][channel].
    projected.assign(gz * gy * gx * channels, 0.0);
    const size_t planeLength = gy * rowLength;
    for (size_t z = 0; z < nz; ++z)
    {
      const double * plane = &planes[z * planeLength];
      const double * weights = &level.Weights[2][4 * z];
      const size_t   start = level.WeightStart[2][z];
      for (unsigned int k = 0; k < 4; ++k)
      {
        double *     out = &projected[(start + k) * planeLength];
        const double w = weights[k];
        if (w == 0.0)
        {
          continue;
        }
        for (size_t i = 0; i < planeLength; ++i)
        {
          out[i] += w * plane[i];
        }
      }
    }
  }

  /** Prints the histogram's state. */
  void
  Print(std::ostream & os, Indent indent) const;

private:
  SimilarityEnum      m_Similarity{ SimilarityEnum::MutualInformation };
  unsigned int        m_NumberOfHistogramBins{ 32 };
  unsigned int        m_NumberOfWorkUnits{ 1 };
  std::vector<double> m_HistogramCosts{};
  double              m_FixedBinScale{ 1.0 };
  double              m_FixedBinOffset{ 0.0 };
  double              m_MovingBinScale{ 1.0 };
  double              m_MovingBinOffset{ 0.0 };
};
} // namespace detail
} // namespace itk

#endif // itkBSplineMRFUnaryCosts_h
