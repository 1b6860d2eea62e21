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
#ifndef itkTruncatedGaussianImageFilter_hxx
#define itkTruncatedGaussianImageFilter_hxx

#include "itkTruncatedGaussianImageFilter.h"
#include "itkMultiThreaderBase.h"
#include "itkNumericTraits.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <type_traits>

namespace itk
{
template <typename TImage>
TruncatedGaussianImageFilter<TImage>::TruncatedGaussianImageFilter()
{
  m_SigmaArray.Fill(1.0);
}

template <typename TImage>
void
TruncatedGaussianImageFilter<TImage>::PrintSelf(std::ostream & os, Indent indent) const
{
  Superclass::PrintSelf(os, indent);
  os << indent << "SigmaArray: " << m_SigmaArray << std::endl;
  os << indent << "KernelWidthInSigmas: " << m_KernelWidthInSigmas << std::endl;
}

template <typename TImage>
void
TruncatedGaussianImageFilter<TImage>::VerifyPreconditions() const
{
  Superclass::VerifyPreconditions();
  for (unsigned int d = 0; d < ImageDimension; ++d)
  {
    if (!(m_SigmaArray[d] >= 0.0) || !std::isfinite(m_SigmaArray[d]))
    {
      itkExceptionMacro("Sigma must be finite and >= 0, not " << m_SigmaArray << '.');
    }
  }
  if (!(m_KernelWidthInSigmas > 0.0) || !std::isfinite(m_KernelWidthInSigmas))
  {
    itkExceptionMacro("KernelWidthInSigmas must be finite and > 0, not " << m_KernelWidthInSigmas << '.');
  }
}

template <typename TImage>
void
TruncatedGaussianImageFilter<TImage>::GenerateInputRequestedRegion()
{
  Superclass::GenerateInputRequestedRegion();
  if (auto * input = const_cast<ImageType *>(this->GetInput()))
  {
    input->SetRequestedRegionToLargestPossibleRegion();
  }
}

template <typename TImage>
void
TruncatedGaussianImageFilter<TImage>::EnlargeOutputRequestedRegion(DataObject * output)
{
  Superclass::EnlargeOutputRequestedRegion(output);
  output->SetRequestedRegionToLargestPossibleRegion();
}

template <typename TImage>
std::vector<double>
TruncatedGaussianImageFilter<TImage>::ComputeKernel(unsigned int axis) const
{
  const double sigma = m_SigmaArray[axis];
  const double spacing = this->GetInput()->GetSpacing()[axis];
  if (sigma == 0.0)
  {
    return { 1.0 };
  }
  const auto          radius = static_cast<long>(std::ceil(m_KernelWidthInSigmas * sigma / spacing));
  std::vector<double> weights(static_cast<size_t>(2 * radius + 1));
  double              sum = 0.0;
  for (long k = -radius; k <= radius; ++k)
  {
    const double x = static_cast<double>(k) * spacing / sigma;
    weights[static_cast<size_t>(k + radius)] = std::exp(-0.5 * x * x);
    sum += weights[static_cast<size_t>(k + radius)];
  }
  for (double & weight : weights)
  {
    weight /= sum;
  }
  return weights;
}

template <typename TImage>
void
TruncatedGaussianImageFilter<TImage>::GenerateData()
{
  using RealType = typename NumericTraits<PixelType>::FloatType;
  const ImageType * input = this->GetInput();
  ImageType *       output = this->GetOutput();
  this->AllocateOutputs();

  const auto region = input->GetBufferedRegion();
  const long size[3] = { static_cast<long>(region.GetSize(0)),
                         static_cast<long>(region.GetSize(1)),
                         static_cast<long>(region.GetSize(2)) };
  const long stride[3] = { 1, size[0], size[0] * size[1] };
  const auto count = static_cast<size_t>(size[0] * size[1] * size[2]);

  MultiThreaderBase * threader = this->GetMultiThreader();
  threader->SetNumberOfWorkUnits(this->GetNumberOfWorkUnits());

  // The passes along the axes whose kernel is wider than one voxel, from the input to the output. Where the pixels
  // are their own real type (float, double) the passes run between the output's buffer and one scratch buffer,
  // arranged so that the last pass writes the output; otherwise between two real buffers, cast at the end.
  std::vector<unsigned int>            axes;
  std::array<std::vector<RealType>, 3> kernels;
  for (unsigned int axis = 0; axis < 3; ++axis)
  {
    const std::vector<double> kernel = this->ComputeKernel(axis);
    kernels[axis].assign(kernel.begin(), kernel.end());
    if (kernel.size() > 1)
    {
      axes.push_back(axis);
    }
  }
  const auto pass = [&](unsigned int axis, const RealType * from, RealType * to) {
    const std::vector<RealType> & weights = kernels[axis];
    const long                    radius = static_cast<long>(weights.size() / 2);
    const long                    n = size[axis];
    if (axis == 0)
    {
      // Along the rows: each row padded by its edge voxels, then a dot product per voxel.
      threader->ParallelizeArray(
        0,
        static_cast<SizeValueType>(size[1] * size[2]),
        [&](SizeValueType row) {
          std::vector<RealType> padded(static_cast<size_t>(n + 2 * radius));
          const RealType *      line = from + static_cast<long>(row) * n;
          for (long i = -radius; i < n + radius; ++i)
          {
            padded[static_cast<size_t>(i + radius)] = line[std::min(std::max(i, 0L), n - 1)];
          }
          RealType * out = to + static_cast<long>(row) * n;
          for (long i = 0; i < n; ++i)
          {
            RealType sum = 0;
            for (long k = 0; k <= 2 * radius; ++k)
            {
              sum += weights[static_cast<size_t>(k)] * padded[static_cast<size_t>(i + k)];
            }
            out[i] = sum;
          }
        },
        nullptr);
      return;
    }
    // Across the rows: whole rows weighted and added, the first axis innermost (contiguous).
    const long other = axis == 1 ? 2 : 1;
    threader->ParallelizeArray(
      0,
      static_cast<SizeValueType>(size[other]),
      [&](SizeValueType outer) {
        for (long i = 0; i < n; ++i)
        {
          RealType * out = to + static_cast<long>(outer) * stride[other] + i * stride[axis];
          for (long k = -radius; k <= radius; ++k)
          {
            const long       source = std::min(std::max(i + k, 0L), n - 1);
            const RealType * in = from + static_cast<long>(outer) * stride[other] + source * stride[axis];
            const RealType   weight = weights[static_cast<size_t>(k + radius)];
            if (k == -radius)
            {
              for (long x = 0; x < size[0]; ++x)
              {
                out[x] = weight * in[x];
              }
            }
            else
            {
              for (long x = 0; x < size[0]; ++x)
              {
                out[x] += weight * in[x];
              }
            }
          }
        }
      },
      nullptr);
  };

  const PixelType * inputBuffer = input->GetBufferPointer();
  PixelType *       outputBuffer = output->GetBufferPointer();
  if constexpr (std::is_same<PixelType, RealType>::value)
  {
    if (axes.empty())
    {
      std::copy(inputBuffer, inputBuffer + count, outputBuffer);
    }
    std::unique_ptr<RealType[]> scratch(axes.size() > 1 ? new RealType[count] : nullptr);
    const RealType *            from = inputBuffer;
    for (size_t p = 0; p < axes.size(); ++p)
    {
      RealType * to = (axes.size() - 1 - p) % 2 == 0 ? outputBuffer : scratch.get();
      pass(axes[p], from, to);
      from = to;
      this->UpdateProgress(static_cast<float>(p + 1) / static_cast<float>(axes.size()));
    }
  }
  else
  {
    std::vector<RealType> current(inputBuffer, inputBuffer + count);
    std::vector<RealType> next(axes.size() > 0 ? count : 0);
    for (size_t p = 0; p < axes.size(); ++p)
    {
      pass(axes[p], current.data(), next.data());
      current.swap(next);
      this->UpdateProgress(static_cast<float>(p + 1) / static_cast<float>(axes.size()));
    }
    for (size_t i = 0; i < count; ++i)
    {
      outputBuffer[i] = static_cast<PixelType>(current[i]);
    }
  }
}
} // namespace itk

#endif // itkTruncatedGaussianImageFilter_hxx
