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
#ifndef itkMeshOpenBoundaryMaskImageFilter_hxx
#define itkMeshOpenBoundaryMaskImageFilter_hxx

#include "itkMeshOpenBoundaryMaskImageFilter.h"
#include "itkImageAlgorithm.h"
#include "itkImageRegionConstIterator.h"
#include "itkImageRegionIteratorWithIndex.h"
#include "itkTotalProgressReporter.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>

namespace itk
{
template <typename TMaskImage, typename TMesh>
MeshOpenBoundaryMaskImageFilter<TMaskImage, TMesh>::MeshOpenBoundaryMaskImageFilter()
{
  this->SetNumberOfRequiredInputs(2);
  this->AddRequiredInputName("Mesh", 1);
}

template <typename TMaskImage, typename TMesh>
void
MeshOpenBoundaryMaskImageFilter<TMaskImage, TMesh>::PrintSelf(std::ostream & os, Indent indent) const
{
  Superclass::PrintSelf(os, indent);
  os << indent << "Radius: " << m_Radius << std::endl;
  os << indent << "NumberOfOpenBoundaryEdges: " << m_NumberOfOpenBoundaryEdges << std::endl;
  os << indent << "NumberOfMaskVoxels: " << m_NumberOfMaskVoxels << std::endl;
}

template <typename TMaskImage, typename TMesh>
void
MeshOpenBoundaryMaskImageFilter<TMaskImage, TMesh>::GenerateInputRequestedRegion()
{
  Superclass::GenerateInputRequestedRegion();
  if (auto * input = const_cast<MaskImageType *>(this->GetInput()))
  {
    input->SetRequestedRegionToLargestPossibleRegion();
  }
}

template <typename TMaskImage, typename TMesh>
void
MeshOpenBoundaryMaskImageFilter<TMaskImage, TMesh>::EnlargeOutputRequestedRegion(DataObject * output)
{
  Superclass::EnlargeOutputRequestedRegion(output);
  output->SetRequestedRegionToLargestPossibleRegion();
}

template <typename TMaskImage, typename TMesh>
void
MeshOpenBoundaryMaskImageFilter<TMaskImage, TMesh>::GenerateData()
{
  constexpr unsigned int Dimension = MaskImageType::ImageDimension;
  const MaskImageType *  input = this->GetInput();
  const MeshType *       mesh = this->GetMesh();
  MaskImageType *        mask = this->GetOutput();
  this->AllocateOutputs();
  const auto region = mask->GetLargestPossibleRegion();
  ImageAlgorithm::Copy(input, mask, region, region);

  // Edges used by exactly one face form the open boundary.
  using IdentifierPair = std::pair<IdentifierType, IdentifierType>;
  std::map<IdentifierPair, unsigned int> edgeUse;
  if (mesh->GetCells() != nullptr)
  {
    for (auto it = mesh->GetCells()->Begin(); it != mesh->GetCells()->End(); ++it)
    {
      const auto *       ids = it.Value()->GetPointIds();
      const unsigned int n = it.Value()->GetNumberOfPoints();
      const auto         type = it.Value()->GetType();
      if (n < 3 || (type != CellGeometryEnum::TRIANGLE_CELL && type != CellGeometryEnum::POLYGON_CELL))
      {
        continue;
      }
      for (unsigned int j = 0; j < n; ++j)
      {
        const auto a = ids[j];
        const auto b = ids[(j + 1) % n];
        ++edgeUse[std::make_pair(std::min(a, b), std::max(a, b))];
      }
    }
  }

  m_NumberOfOpenBoundaryEdges = 0;
  for (const auto & edge : edgeUse)
  {
    m_NumberOfOpenBoundaryEdges += edge.second == 1;
  }
  TotalProgressReporter progress(this, std::max<SizeValueType>(1, m_NumberOfOpenBoundaryEdges));
  const double          radius2 = m_Radius * m_Radius;
  for (const auto & edge : edgeUse)
  {
    if (edge.second != 1 || !(m_Radius > 0.0))
    {
      continue;
    }
    const auto                        a = mesh->GetPoint(edge.first.first);
    const auto                        b = mesh->GetPoint(edge.first.second);
    const auto                        ab = b - a;
    const double                      length2 = ab.GetSquaredNorm();
    typename MaskImageType::PointType low;
    typename MaskImageType::PointType high;
    for (unsigned int d = 0; d < Dimension; ++d)
    {
      low[d] = std::min(a[d], b[d]) - m_Radius;
      high[d] = std::max(a[d], b[d]) + m_Radius;
    }
    const auto                        lowIndex = mask->template TransformPhysicalPointToContinuousIndex<double>(low);
    const auto                        highIndex = mask->template TransformPhysicalPointToContinuousIndex<double>(high);
    typename MaskImageType::IndexType first;
    typename MaskImageType::IndexType last;
    bool                              empty = false;
    for (unsigned int d = 0; d < Dimension; ++d)
    {
      const double lo = std::min(lowIndex[d], highIndex[d]);
      const double hi = std::max(lowIndex[d], highIndex[d]);
      first[d] = std::max<IndexValueType>(region.GetIndex(d), static_cast<IndexValueType>(std::floor(lo)));
      last[d] = std::min<IndexValueType>(region.GetIndex(d) + static_cast<IndexValueType>(region.GetSize(d)) - 1,
                                         static_cast<IndexValueType>(std::ceil(hi)));
      empty = empty || first[d] > last[d];
    }
    if (!empty)
    {
      typename MaskImageType::SizeType size;
      for (unsigned int d = 0; d < Dimension; ++d)
      {
        size[d] = static_cast<SizeValueType>(last[d] - first[d] + 1);
      }
      const typename MaskImageType::RegionType box(first, size);
      for (ImageRegionIteratorWithIndex<MaskImageType> it(mask, box); !it.IsAtEnd(); ++it)
      {
        if (it.Get() == NumericTraits<typename MaskImageType::PixelType>::ZeroValue())
        {
          continue;
        }
        typename MaskImageType::PointType p;
        mask->TransformIndexToPhysicalPoint(it.GetIndex(), p);
        double t = 0.0;
        if (length2 > 0.0)
        {
          double dot = 0.0;
          for (unsigned int d = 0; d < Dimension; ++d)
          {
            dot += (p[d] - a[d]) * ab[d];
          }
          t = std::min(1.0, std::max(0.0, dot / length2));
        }
        double distance2 = 0.0;
        for (unsigned int d = 0; d < Dimension; ++d)
        {
          const double delta = p[d] - (a[d] + t * ab[d]);
          distance2 += delta * delta;
        }
        if (distance2 < radius2)
        {
          it.Set(NumericTraits<typename MaskImageType::PixelType>::ZeroValue());
        }
      }
    }
    progress.CompletedPixel();
  }

  m_NumberOfMaskVoxels = 0;
  for (ImageRegionConstIterator<MaskImageType> it(mask, region); !it.IsAtEnd(); ++it)
  {
    m_NumberOfMaskVoxels += it.Get() != NumericTraits<typename MaskImageType::PixelType>::ZeroValue();
  }
}
} // namespace itk

#endif // itkMeshOpenBoundaryMaskImageFilter_hxx
