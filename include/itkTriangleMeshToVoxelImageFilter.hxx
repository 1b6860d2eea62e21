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
#ifndef itkTriangleMeshToVoxelImageFilter_hxx
#define itkTriangleMeshToVoxelImageFilter_hxx

#include "itkTriangleMeshToVoxelImageFilter.h"
#include "itkCellInterface.h"
#include "itkImageRegionIteratorWithIndex.h"
#include "itkMath.h"
#include "itkTotalProgressReporter.h"

#include <cmath>
#include <limits>
#include <vector>

namespace itk
{
template <typename TInputMesh, typename TOutputImage>
TriangleMeshToVoxelImageFilter<TInputMesh, TOutputImage>::TriangleMeshToVoxelImageFilter()
{
  this->SetNumberOfRequiredInputs(1);
  m_Origin.Fill(0.0);
  m_Spacing.Fill(1.0);
  m_Direction.SetIdentity();
  this->ThreaderUpdateProgressOff();
}

template <typename TInputMesh, typename TOutputImage>
void
TriangleMeshToVoxelImageFilter<TInputMesh, TOutputImage>::SetInput(const InputMeshType * input)
{
  // The process object holds non-const inputs; the mesh is only read.
  this->ProcessObject::SetNthInput(0, const_cast<InputMeshType *>(input));
}

template <typename TInputMesh, typename TOutputImage>
auto
TriangleMeshToVoxelImageFilter<TInputMesh, TOutputImage>::GetInput() const -> const InputMeshType *
{
  return itkDynamicCastInDebugMode<const InputMeshType *>(this->ProcessObject::GetInput(0));
}

template <typename TInputMesh, typename TOutputImage>
void
TriangleMeshToVoxelImageFilter<TInputMesh, TOutputImage>::ComputeGeometryFromMeshBounds(const InputMeshType * mesh,
                                                                                        const SpacingType &   spacing,
                                                                                        double                margin,
                                                                                        PointType &           origin,
                                                                                        SizeType &            size)
{
  if (mesh == nullptr || mesh->GetPoints() == nullptr || mesh->GetNumberOfPoints() == 0)
  {
    itkGenericExceptionMacro("ComputeGeometryFromMeshBounds: the mesh is null or has no points.");
  }
  if (!std::isfinite(margin) || margin < 0.0)
  {
    itkGenericExceptionMacro("ComputeGeometryFromMeshBounds: the margin must be finite and >= 0, not " << margin
                                                                                                       << '.');
  }
  double lower[3] = { std::numeric_limits<double>::infinity(),
                      std::numeric_limits<double>::infinity(),
                      std::numeric_limits<double>::infinity() };
  double upper[3] = { -lower[0], -lower[1], -lower[2] };
  for (auto it = mesh->GetPoints()->Begin(); it != mesh->GetPoints()->End(); ++it)
  {
    for (unsigned int k = 0; k < 3; ++k)
    {
      const auto value = static_cast<double>(it.Value()[k]);
      if (!std::isfinite(value))
      {
        itkGenericExceptionMacro("ComputeGeometryFromMeshBounds: point " << it.Index()
                                                                         << " has a NaN or infinite coordinate.");
      }
      lower[k] = std::min(lower[k], value);
      upper[k] = std::max(upper[k], value);
    }
  }
  for (unsigned int k = 0; k < 3; ++k)
  {
    if (!(spacing[k] > 0.0) || !std::isfinite(spacing[k]))
    {
      itkGenericExceptionMacro("ComputeGeometryFromMeshBounds: the spacing must be positive and finite, not " << spacing
                                                                                                              << '.');
    }
    const double extent = upper[k] - lower[k] + 2.0 * margin;
    const double count = std::max(1.0, std::ceil(extent / spacing[k]));
    if (count > 1e15)
    {
      itkGenericExceptionMacro("ComputeGeometryFromMeshBounds: " << count << " voxels along axis " << k
                                                                 << " is too many for the spacing " << spacing << '.');
    }
    size[k] = static_cast<SizeValueType>(count);
    origin[k] = 0.5 * (lower[k] + upper[k]) - 0.5 * (count - 1.0) * spacing[k];
  }
}

template <typename TInputMesh, typename TOutputImage>
void
TriangleMeshToVoxelImageFilter<TInputMesh, TOutputImage>::SetGeometryFromMeshBounds(const SpacingType & spacing,
                                                                                    double              margin)
{
  PointType origin;
  SizeType  size;
  ComputeGeometryFromMeshBounds(this->GetInput(), spacing, margin, origin, size);
  DirectionType identity;
  identity.SetIdentity();
  this->SetOrigin(origin);
  this->SetSpacing(spacing);
  this->SetSize(size);
  this->SetDirection(identity);
}

template <typename TInputMesh, typename TOutputImage>
ModifiedTimeType
TriangleMeshToVoxelImageFilter<TInputMesh, TOutputImage>::GetMTime() const
{
  ModifiedTimeType result = Superclass::GetMTime();
  if (m_ReferenceImage)
  {
    result = std::max(result, m_ReferenceImage->GetMTime());
  }
  return result;
}

template <typename TInputMesh, typename TOutputImage>
void
TriangleMeshToVoxelImageFilter<TInputMesh, TOutputImage>::PrintSelf(std::ostream & os, Indent indent) const
{
  Superclass::PrintSelf(os, indent);
  os << indent << "Mode: " << m_Mode << std::endl;
  os << indent << "InsideValue: " << static_cast<typename NumericTraits<OutputPixelType>::PrintType>(m_InsideValue)
     << std::endl;
  os << indent << "OutsideValue: " << static_cast<typename NumericTraits<OutputPixelType>::PrintType>(m_OutsideValue)
     << std::endl;
  itkPrintSelfObjectMacro(ReferenceImage);
  os << indent << "Origin: " << m_Origin << std::endl;
  os << indent << "Spacing: " << m_Spacing << std::endl;
  os << indent << "Size: " << m_Size << std::endl;
  os << indent << "Direction: " << m_Direction << std::endl;
  os << indent << "OccupancyDistance: " << m_OccupancyDistance << std::endl;
  os << indent << "BandWidth: " << m_BandWidth << std::endl;
  os << indent << "ExactDistance: " << (m_ExactDistance ? "On" : "Off") << std::endl;
  os << indent << "UnsignedDistance: " << (m_UnsignedDistance ? "On" : "Off") << std::endl;
  os << indent << "AbsoluteWindingNumber: " << (m_AbsoluteWindingNumber ? "On" : "Off") << std::endl;
  os << indent << "Beta: " << m_Beta << std::endl;
  os << indent << "MaximumNumberOfVoxels: " << m_MaximumNumberOfVoxels << std::endl;
  os << indent << "NumberOfTriangles: " << m_NumberOfTriangles << std::endl;
  os << indent << "NumberOfDegenerateTriangles: " << m_NumberOfDegenerateTriangles << std::endl;
  os << indent << "Hierarchy nodes: " << m_Hierarchy.GetNumberOfNodes() << std::endl;
  os << indent << "HierarchyIsCurrent: " << (m_HierarchyIsCurrent ? "On" : "Off") << std::endl;
  os << indent << "EffectiveOccupancyDistance: " << m_EffectiveOccupancyDistance << std::endl;
  os << indent << "EffectiveBandWidth: " << m_EffectiveBandWidth << std::endl;
}

template <typename TInputMesh, typename TOutputImage>
void
TriangleMeshToVoxelImageFilter<TInputMesh, TOutputImage>::ComputeOutputGeometry(OutputImageRegionType & region,
                                                                                SpacingType &           spacing,
                                                                                PointType &             origin,
                                                                                DirectionType &         direction) const
{
  if (m_ReferenceImage)
  {
    region = m_ReferenceImage->GetLargestPossibleRegion();
    spacing = m_ReferenceImage->GetSpacing();
    origin = m_ReferenceImage->GetOrigin();
    direction = m_ReferenceImage->GetDirection();
  }
  else
  {
    typename OutputImageRegionType::IndexType start;
    start.Fill(0);
    region.SetIndex(start);
    region.SetSize(m_Size);
    spacing = m_Spacing;
    origin = m_Origin;
    direction = m_Direction;
  }
}

template <typename TInputMesh, typename TOutputImage>
void
TriangleMeshToVoxelImageFilter<TInputMesh, TOutputImage>::VerifyPreconditions() ITKv5_CONST
{
  Superclass::VerifyPreconditions();

  OutputImageRegionType region;
  SpacingType           spacing;
  PointType             origin;
  DirectionType         direction;
  this->ComputeOutputGeometry(region, spacing, origin, direction);
  const char * source = m_ReferenceImage ? "reference image" : "output";
  for (unsigned int k = 0; k < OutputImageDimension; ++k)
  {
    if (!(spacing[k] > 0.0) || !std::isfinite(spacing[k]))
    {
      itkExceptionMacro("The " << source << " spacing must be positive and finite, not " << spacing << '.');
    }
    if (!std::isfinite(origin[k]))
    {
      itkExceptionMacro("The " << source << " origin is not finite: " << origin << '.');
    }
    if (region.GetSize(k) == 0)
    {
      itkExceptionMacro("The " << source << " size is zero along axis " << k << " (size " << region.GetSize()
                               << "): set Size or a reference image.");
    }
  }
  // Checked in floating point so a huge size cannot overflow the count.
  double numberOfVoxels = 1.0;
  for (unsigned int k = 0; k < OutputImageDimension; ++k)
  {
    numberOfVoxels *= static_cast<double>(region.GetSize(k));
  }
  if (numberOfVoxels > static_cast<double>(m_MaximumNumberOfVoxels))
  {
    itkExceptionMacro("The output would have " << numberOfVoxels << " voxels (size " << region.GetSize()
                                               << "), more than MaximumNumberOfVoxels = " << m_MaximumNumberOfVoxels
                                               << ".");
  }
  const bool realOutputMode = m_Mode == ModeEnum::SignedDistance || m_Mode == ModeEnum::WindingNumber;
  if (realOutputMode && NumericTraits<OutputPixelType>::is_integer)
  {
    itkExceptionMacro("Mode " << m_Mode << " needs a floating-point output pixel type.");
  }
  if (!std::isfinite(m_BandWidth) || (m_BandWidth < 0.0 && m_BandWidth != -1.0))
  {
    itkExceptionMacro("BandWidth must be >= 0 (or -1 for three voxels), not " << m_BandWidth << '.');
  }
  if (!std::isfinite(m_OccupancyDistance) || (m_OccupancyDistance < 0.0 && m_OccupancyDistance != -1.0))
  {
    itkExceptionMacro("OccupancyDistance must be >= 0 (or -1 for half the voxel diagonal), not " << m_OccupancyDistance
                                                                                                 << '.');
  }
  if (!std::isfinite(m_Beta) || m_Beta < 0.0 || (m_Beta > 0.0 && m_Beta < 1.0))
  {
    itkExceptionMacro("Beta must be 0 (exact) or >= 1, not " << m_Beta << '.');
  }
}

template <typename TInputMesh, typename TOutputImage>
void
TriangleMeshToVoxelImageFilter<TInputMesh, TOutputImage>::GenerateOutputInformation()
{
  // The input is a mesh: the superclass would copy its information into the image; set it here instead.
  OutputImageType *     output = this->GetOutput();
  OutputImageRegionType region;
  SpacingType           spacing;
  PointType             origin;
  DirectionType         direction;
  this->ComputeOutputGeometry(region, spacing, origin, direction);
  output->SetLargestPossibleRegion(region);
  output->SetSpacing(spacing);
  output->SetOrigin(origin);
  output->SetDirection(direction);

  double diagonalSquared = 0.0;
  double largestSpacing = 0.0;
  for (unsigned int k = 0; k < OutputImageDimension; ++k)
  {
    diagonalSquared += spacing[k] * spacing[k];
    largestSpacing = std::max(largestSpacing, static_cast<double>(spacing[k]));
  }
  m_EffectiveOccupancyDistance = m_OccupancyDistance < 0.0 ? 0.5 * std::sqrt(diagonalSquared) : m_OccupancyDistance;
  m_EffectiveBandWidth = m_BandWidth < 0.0 ? 3.0 * largestSpacing : m_BandWidth;

  // Called once per pipeline update, not once per streamed piece: the hierarchy is rebuilt on the
  // next BeforeThreadedGenerateData() only when the mesh or the parameters changed.
  m_HierarchyIsCurrent = false;
}

template <typename TInputMesh, typename TOutputImage>
void
TriangleMeshToVoxelImageFilter<TInputMesh, TOutputImage>::BeforeThreadedGenerateData()
{
  if (!m_HierarchyIsCurrent)
  {
    this->BuildTriangleHierarchy();
    m_HierarchyIsCurrent = true;
  }
}

template <typename TInputMesh, typename TOutputImage>
void
TriangleMeshToVoxelImageFilter<TInputMesh, TOutputImage>::BuildTriangleHierarchy()
{
  using TriangleType = detail::TriangleBoundingVolumeHierarchy::Triangle;
  using VectorType = detail::TriangleBoundingVolumeHierarchy::VectorType;

  const InputMeshType * mesh = this->GetInput();
  if (mesh == nullptr)
  {
    itkExceptionMacro("No input mesh.");
  }
  const auto * points = mesh->GetPoints();
  if (points == nullptr || points->Size() == 0)
  {
    itkExceptionMacro("The input mesh is empty: it has no points.");
  }
  for (auto it = points->Begin(); it != points->End(); ++it)
  {
    for (unsigned int k = 0; k < 3; ++k)
    {
      if (!std::isfinite(static_cast<double>(it.Value()[k])))
      {
        itkExceptionMacro("Point " << it.Index() << " of the input mesh has a NaN or infinite coordinate ("
                                   << it.Value() << ").");
      }
    }
  }
  const auto * cells = mesh->GetCells();
  if (cells == nullptr || cells->Size() == 0)
  {
    itkExceptionMacro("The input mesh has no cells: it needs triangle cells.");
  }

  std::vector<TriangleType> triangles;
  triangles.reserve(cells->Size());
  SizeValueType numberOfDegenerate = 0;
  const auto    toVector = [points, this](typename InputMeshType::PointIdentifier id, SizeValueType cellId) {
    if (!points->IndexExists(id))
    {
      itkExceptionMacro("Cell " << cellId << " of the input mesh refers to point " << id << ", which does not exist.");
    }
    const auto & p = points->ElementAt(id);
    return VectorType{ static_cast<double>(p[0]), static_cast<double>(p[1]), static_cast<double>(p[2]) };
  };
  for (auto it = cells->Begin(); it != cells->End(); ++it)
  {
    const auto * cell = it.Value();
    if (cell == nullptr)
    {
      continue;
    }
    const unsigned int dimension = cell->GetDimension();
    if (dimension < 2)
    {
      continue; // Vertices and lines have no area.
    }
    if (dimension > 2)
    {
      itkExceptionMacro("Cell " << it.Index() << " of the input mesh is a volume cell (" << cell->GetNumberOfPoints()
                                << " points): only triangle and polygon cells are supported.");
    }
    const auto numberOfPoints = static_cast<unsigned int>(cell->GetNumberOfPoints());
    if (numberOfPoints < 3)
    {
      continue;
    }
    const auto *     ids = cell->PointIdsBegin();
    const VectorType first = toVector(ids[0], it.Index());
    for (unsigned int i = 1; i + 1 < numberOfPoints; ++i)
    {
      const TriangleType triangle{ first, toVector(ids[i], it.Index()), toVector(ids[i + 1], it.Index()) };
      double             ab[3];
      double             ac[3];
      for (unsigned int k = 0; k < 3; ++k)
      {
        ab[k] = triangle.b[k] - triangle.a[k];
        ac[k] = triangle.c[k] - triangle.a[k];
      }
      const double n0 = ab[1] * ac[2] - ab[2] * ac[1];
      const double n1 = ab[2] * ac[0] - ab[0] * ac[2];
      const double n2 = ab[0] * ac[1] - ab[1] * ac[0];
      if (n0 == 0.0 && n1 == 0.0 && n2 == 0.0)
      {
        ++numberOfDegenerate;
        continue;
      }
      triangles.push_back(triangle);
    }
  }
  m_NumberOfDegenerateTriangles = numberOfDegenerate;
  m_NumberOfTriangles = triangles.size();
  if (triangles.empty())
  {
    itkExceptionMacro("The input mesh has no triangle cells"
                      << (numberOfDegenerate > 0 ? " of non-zero area (all are degenerate)." : "."));
  }
  m_Hierarchy.Build(std::move(triangles));
}

template <typename TInputMesh, typename TOutputImage>
bool
TriangleMeshToVoxelImageFilter<TInputMesh, TOutputImage>::IsInside(double windingNumber) const
{
  return (m_AbsoluteWindingNumber ? std::abs(windingNumber) : windingNumber) > 0.5;
}

template <typename TInputMesh, typename TOutputImage>
void
TriangleMeshToVoxelImageFilter<TInputMesh, TOutputImage>::DynamicThreadedGenerateData(
  const OutputImageRegionType & outputRegionForThread)
{
  using VectorType = detail::TriangleBoundingVolumeHierarchy::VectorType;
  OutputImageType *     output = this->GetOutput();
  TotalProgressReporter progress(this, output->GetRequestedRegion().GetNumberOfPixels());

  const double band = m_EffectiveBandWidth;
  const double bandSquared = band * band;
  const double beta = m_Beta;

  ImageRegionIteratorWithIndex<OutputImageType> it(output, outputRegionForThread);
  PointType                                     point;
  for (; !it.IsAtEnd(); ++it)
  {
    output->TransformIndexToPhysicalPoint(it.GetIndex(), point);
    const VectorType q{ static_cast<double>(point[0]), static_cast<double>(point[1]), static_cast<double>(point[2]) };
    switch (m_Mode)
    {
      case ModeEnum::Occupancy:
        it.Set(m_Hierarchy.AnyTriangleWithin(q, m_EffectiveOccupancyDistance) ? m_InsideValue : m_OutsideValue);
        break;
      case ModeEnum::BandMask:
        it.Set(m_Hierarchy.AnyTriangleWithin(q, band) ? m_InsideValue : m_OutsideValue);
        break;
      case ModeEnum::Solid:
        it.Set(this->IsInside(m_Hierarchy.WindingNumber(q, beta)) ? m_InsideValue : m_OutsideValue);
        break;
      case ModeEnum::WindingNumber:
        it.Set(static_cast<OutputPixelType>(m_Hierarchy.WindingNumber(q, beta)));
        break;
      case ModeEnum::SignedDistance: {
        const double squaredDistance =
          m_Hierarchy.SquaredDistance(q, m_ExactDistance ? std::numeric_limits<double>::infinity() : bandSquared);
        double distance = (!m_ExactDistance && squaredDistance >= bandSquared) ? band : std::sqrt(squaredDistance);
        if (!m_UnsignedDistance && this->IsInside(m_Hierarchy.WindingNumber(q, beta)))
        {
          distance = -distance;
        }
        it.Set(static_cast<OutputPixelType>(distance));
        break;
      }
    }
    progress.CompletedPixel();
  }
}
} // namespace itk

#endif // itkTriangleMeshToVoxelImageFilter_hxx
