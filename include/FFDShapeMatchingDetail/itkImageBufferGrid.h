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
#ifndef itkImageBufferGrid_h
#define itkImageBufferGrid_h

#include "itkIntTypes.h"
#include "itkMath.h"
#include "itkMatrix.h"
#include "itkPoint.h"

#include <type_traits>

namespace itk
{
namespace detail
{
/** \class ImageBufferGrid
 * \brief The index geometry of an image's buffer (physical point to continuous index, buffer bounds and strides)
 * and linear interpolation on the raw buffer, with the arithmetic of ITK's ImageBase and
 * LinearInterpolateImageFunction, for hot loops that must give the same values without their virtual calls.
 *
 * \ingroup FFDShapeMatching
 */
template <unsigned int VDimension>
struct ImageBufferGrid
{
  using MatrixType = Matrix<double, VDimension, VDimension>;
  using PointType = Point<double, VDimension>;

  MatrixType      PointToIndex{ MatrixType::GetIdentity() };
  PointType       Origin = PointType(0.0);
  IndexValueType  Start[VDimension]{};
  IndexValueType  End[VDimension]{};
  OffsetValueType Stride[VDimension]{};

  /** Takes the geometry of the image's buffered region. */
  template <typename TImage>
  void
  SetFromImage(const TImage * image)
  {
    // The matrix of ImageBase::ComputeIndexToPhysicalPointMatrices(), computed the same way.
    typename TImage::DirectionType scale;
    scale.Fill(0.0);
    for (unsigned int i = 0; i < VDimension; ++i)
    {
      scale[i][i] = image->GetSpacing()[i];
    }
    const typename TImage::DirectionType indexToPoint = image->GetDirection() * scale;
    PointToIndex = MatrixType(indexToPoint.GetInverse());

    const auto & region = image->GetBufferedRegion();
    const auto & offsets = image->GetOffsetTable();
    for (unsigned int i = 0; i < VDimension; ++i)
    {
      Origin[i] = image->GetOrigin()[i];
      Start[i] = region.GetIndex()[i];
      End[i] = region.GetIndex()[i] + static_cast<IndexValueType>(region.GetSize()[i]) - 1;
      Stride[i] = offsets[i];
    }
  }

  /** The continuous index of a physical point; true when it lies inside the buffer ([start - 0.5, end + 0.5) per
   * axis, as ImageFunction::IsInsideBuffer). */
  template <typename TPoint>
  bool
  ToContinuousIndex(const TPoint & point, double * continuousIndex) const
  {
    // Same arithmetic and bounds as ImageBase::TransformPhysicalPointToContinuousIndex and
    // ImageFunction::IsInsideBuffer: [start - 0.5, end + 0.5).
    bool inside = true;
    for (unsigned int i = 0; i < VDimension; ++i)
    {
      double sum = 0.0;
      for (unsigned int j = 0; j < VDimension; ++j)
      {
        sum += PointToIndex[i][j] * (point[j] - Origin[j]);
      }
      continuousIndex[i] = sum;
      inside = inside && (sum >= static_cast<double>(Start[i]) - 0.5 && sum < static_cast<double>(End[i]) + 0.5);
    }
    return inside;
  }

  /** Linear interpolation of the buffer (scalar or vector pixels) at a continuous index inside it. */
  template <typename TPixel, typename TValue>
  void
  InterpolateLinear(const TPixel * buffer, const double * continuousIndex, TValue & value) const
  {
    // Linear interpolation with the boundary handling of LinearInterpolateImageFunction: below the first index the
    // first sample is used, past the last index the last one.
    OffsetValueType baseOffset = 0;
    OffsetValueType step[VDimension];
    double          distance[VDimension];
    for (unsigned int i = 0; i < VDimension; ++i)
    {
      IndexValueType base = Math::Floor<IndexValueType>(continuousIndex[i]);
      if (base < Start[i])
      {
        base = Start[i];
        distance[i] = 0.0;
      }
      else
      {
        distance[i] = continuousIndex[i] - static_cast<double>(base);
      }
      step[i] = base + 1 > End[i] ? 0 : Stride[i];
      baseOffset += (base - Start[i]) * Stride[i];
    }
    value = TValue{};
    for (unsigned int corner = 0; corner < (1u << VDimension); ++corner)
    {
      double          weight = 1.0;
      OffsetValueType offset = baseOffset;
      for (unsigned int i = 0; i < VDimension; ++i)
      {
        if (corner & (1u << i))
        {
          weight *= distance[i];
          offset += step[i];
        }
        else
        {
          weight *= 1.0 - distance[i];
        }
      }
      if (weight != 0.0)
      {
        const TPixel & pixel = buffer[offset];
        if constexpr (std::is_arithmetic<TPixel>::value)
        {
          value += weight * static_cast<double>(pixel);
        }
        else
        {
          for (unsigned int d = 0; d < VDimension; ++d)
          {
            value[d] += weight * static_cast<double>(pixel[d]);
          }
        }
      }
    }
  }
};
} // namespace detail
} // namespace itk

#endif // itkImageBufferGrid_h
