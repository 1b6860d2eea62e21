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
#include "itkImageScanlineIterator.h"
#include "itkMath.h"
#include "itkMeshPolygonTriangles.h"
#include "itkTotalProgressReporter.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <mutex>
#include <unordered_map>
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
void
TriangleMeshToVoxelImageFilter<TInputMesh, TOutputImage>::PrintSelf(std::ostream & os, Indent indent) const
{
  Superclass::PrintSelf(os, indent);
  os << indent << "Mode: " << m_Mode << std::endl;
  os << indent << "InsideValue: " << static_cast<typename NumericTraits<OutputPixelType>::PrintType>(m_InsideValue)
     << std::endl;
  os << indent << "OutsideValue: " << static_cast<typename NumericTraits<OutputPixelType>::PrintType>(m_OutsideValue)
     << std::endl;
  os << indent << "ReferenceImage: " << this->GetReferenceImage() << std::endl;
  os << indent << "MaskImage: " << this->GetMaskImage() << std::endl;
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
  os << indent << "ScanLineAcceleration: " << (m_ScanLineAcceleration ? "On" : "Off") << std::endl;
  os << indent << "MaximumNumberOfVoxels: " << m_MaximumNumberOfVoxels << std::endl;
  os << indent << "NumberOfTriangles: " << m_NumberOfTriangles << std::endl;
  os << indent << "NumberOfDegenerateTriangles: " << m_NumberOfDegenerateTriangles << std::endl;
  os << indent << "Hierarchy nodes: " << m_TriangleSet.GetNumberOfHierarchyNodes() << std::endl;
  os << indent << "HierarchyIsCurrent: " << (m_HierarchyIsCurrent ? "On" : "Off") << std::endl;
  os << indent << "EffectiveOccupancyDistance: " << m_EffectiveOccupancyDistance << std::endl;
  os << indent << "EffectiveBandWidth: " << m_EffectiveBandWidth << std::endl;
  m_TriangleSet.Print(os, indent);
}

template <typename TInputMesh, typename TOutputImage>
void
TriangleMeshToVoxelImageFilter<TInputMesh, TOutputImage>::ComputeOutputGeometry(OutputImageRegionType & region,
                                                                                SpacingType &           spacing,
                                                                                PointType &             origin,
                                                                                DirectionType &         direction) const
{
  if (const ReferenceImageType * reference = this->GetReferenceImage())
  {
    region = reference->GetLargestPossibleRegion();
    spacing = reference->GetSpacing();
    origin = reference->GetOrigin();
    direction = reference->GetDirection();
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
TriangleMeshToVoxelImageFilter<TInputMesh, TOutputImage>::VerifyPreconditions() const
{
  Superclass::VerifyPreconditions();

  OutputImageRegionType region;
  SpacingType           spacing;
  PointType             origin;
  DirectionType         direction;
  this->ComputeOutputGeometry(region, spacing, origin, direction);
  const char * source = this->GetReferenceImage() != nullptr ? "reference image" : "output";
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
  if (this->GetMaskImage() != nullptr && m_Mode == ModeEnum::SignedDistance && m_ExactDistance)
  {
    itkExceptionMacro("A mask image needs the banded distance: the voxels outside it hold +BandWidth, which "
                      "ExactDistance On does not clamp to.");
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

  if (const MaskImageType * mask = this->GetMaskImage())
  {
    // The tolerance of ImageToImageFilter's input check: a millionth of a voxel.
    const double tolerance = 1e-6 * largestSpacing;
    bool         same = mask->GetLargestPossibleRegion() == region;
    for (unsigned int r = 0; r < OutputImageDimension && same; ++r)
    {
      same = std::abs(mask->GetOrigin()[r] - origin[r]) <= tolerance &&
             std::abs(mask->GetSpacing()[r] - spacing[r]) <= tolerance;
      for (unsigned int c = 0; c < OutputImageDimension && same; ++c)
      {
        same = std::abs(mask->GetDirection()[r][c] - direction[r][c]) <= 1e-6;
      }
    }
    if (!same)
    {
      itkExceptionMacro("The mask image's grid (region "
                        << mask->GetLargestPossibleRegion() << ", origin " << mask->GetOrigin() << ", spacing "
                        << mask->GetSpacing() << ") is not the output's (region " << region << ", origin " << origin
                        << ", spacing " << spacing << ").");
    }
  }

  // Called once per pipeline update, not once per streamed piece: the hierarchy is rebuilt on the
  // next BeforeThreadedGenerateData() only when the mesh or the parameters changed.
  m_HierarchyIsCurrent = false;
}

template <typename TInputMesh, typename TOutputImage>
void
TriangleMeshToVoxelImageFilter<TInputMesh, TOutputImage>::GenerateInputRequestedRegion()
{
  Superclass::GenerateInputRequestedRegion();
  if (const MaskImageType * mask = this->GetMaskImage())
  {
    // The pipeline holds its inputs as non-const data objects; only the requested region is changed.
    const_cast<MaskImageType *>(mask)->SetRequestedRegion(this->GetOutput()->GetRequestedRegion());
  }
}

template <typename TInputMesh, typename TOutputImage>
auto
TriangleMeshToVoxelImageFilter<TInputMesh, TOutputImage>::GetFarValue() const -> OutputPixelType
{
  switch (m_Mode)
  {
    case ModeEnum::SignedDistance:
      return static_cast<OutputPixelType>(m_EffectiveBandWidth);
    case ModeEnum::WindingNumber:
      return NumericTraits<OutputPixelType>::ZeroValue();
    default:
      return m_OutsideValue;
  }
}

template <typename TInputMesh, typename TOutputImage>
void
TriangleMeshToVoxelImageFilter<TInputMesh, TOutputImage>::ClearVoxelsOutsideMask(const OutputImageRegionType & region)
{
  const MaskImageType * mask = this->GetMaskImage();
  if (mask == nullptr)
  {
    return;
  }
  const OutputPixelType                     farValue = this->GetFarValue();
  ImageScanlineIterator<OutputImageType>    it(this->GetOutput(), region);
  ImageScanlineConstIterator<MaskImageType> maskIt(mask, region);
  while (!it.IsAtEnd())
  {
    while (!it.IsAtEndOfLine())
    {
      if (!maskIt.Get())
      {
        it.Set(farValue);
      }
      ++it;
      ++maskIt;
    }
    it.NextLine();
    maskIt.NextLine();
  }
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
  if (this->UsesScanLines())
  {
    this->PrepareScanLines();
  }
}

template <typename TInputMesh, typename TOutputImage>
bool
TriangleMeshToVoxelImageFilter<TInputMesh, TOutputImage>::UsesScanLines() const
{
  if (!m_ScanLineAcceleration || m_Mode == ModeEnum::WindingNumber)
  {
    return false;
  }
  // Distances across rows need an orthonormal direction; the solid and the exact distance do not.
  const DirectionType & direction = this->GetOutput()->GetDirection();
  for (unsigned int r = 0; r < 3; ++r)
  {
    for (unsigned int c = 0; c < 3; ++c)
    {
      double dot = 0.0;
      for (unsigned int d = 0; d < 3; ++d)
      {
        dot += direction[d][r] * direction[d][c];
      }
      if (std::abs(dot - (r == c ? 1.0 : 0.0)) > 1e-9)
      {
        return m_Mode == ModeEnum::Solid || (m_Mode == ModeEnum::SignedDistance && m_ExactDistance);
      }
    }
  }
  return true;
}

template <typename TInputMesh, typename TOutputImage>
void
TriangleMeshToVoxelImageFilter<TInputMesh, TOutputImage>::PrepareScanLines()
{
  const OutputImageType *                   output = this->GetOutput();
  detail::ScanLineTriangleSet::GridGeometry grid;
  const auto                                inverseDirection = output->GetDirection().GetInverse();
  const OutputImageRegionType &             region = output->GetRequestedRegion();
  for (unsigned int r = 0; r < 3; ++r)
  {
    for (unsigned int c = 0; c < 3; ++c)
    {
      grid.InverseDirection[r][c] = inverseDirection[r][c];
    }
    grid.Spacing[r] = output->GetSpacing()[r];
    grid.Origin[r] = output->GetOrigin()[r];
    grid.RegionIndex[r] = region.GetIndex(r);
    grid.RegionSize[r] = region.GetSize(r);
  }
  double reachDistance = -1.0;
  switch (m_Mode)
  {
    case ModeEnum::Occupancy:
      reachDistance = m_EffectiveOccupancyDistance;
      break;
    case ModeEnum::BandMask:
      reachDistance = m_EffectiveBandWidth;
      break;
    case ModeEnum::SignedDistance:
      reachDistance = m_ExactDistance ? -1.0 : m_EffectiveBandWidth;
      break;
    default:
      break;
  }
  m_TriangleSet.Prepare(grid, this->ModeNeedsSign(), reachDistance, this->ModeIsReachOnly());
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

  // Points with the same coordinates share one vertex number, so that the net current of an edge
  // (WindingNumberGradientBound) is found by vertex numbers even in a triangle soup. Only the modes that
  // decide inside/outside need it (occupancy and the band mask are distances only).
  const bool needInside = this->ModeNeedsSign() || m_Mode == ModeEnum::WindingNumber;
  std::vector<std::pair<VectorType, typename InputMeshType::PointIdentifier>> sortedPoints;
  sortedPoints.reserve(needInside ? points->Size() : 0);
  typename InputMeshType::PointIdentifier largestId = 0;
  for (auto it = points->Begin(); it != points->End() && needInside; ++it)
  {
    const auto & p = it.Value();
    sortedPoints.emplace_back(
      VectorType{ static_cast<double>(p[0]), static_cast<double>(p[1]), static_cast<double>(p[2]) }, it.Index());
    largestId = std::max(largestId, it.Index());
  }
  std::sort(sortedPoints.begin(), sortedPoints.end());
  const bool                 denseIds = largestId < 4 * sortedPoints.size() + 16;
  std::vector<std::uint32_t> vertexOfDenseId(denseIds ? largestId + 1 : 0, 0);
  std::unordered_map<typename InputMeshType::PointIdentifier, std::uint32_t> vertexOfSparseId;
  std::uint32_t                                                              vertex = 0;
  for (size_t i = 0; i < sortedPoints.size(); ++i)
  {
    if (i > 0 && sortedPoints[i].first != sortedPoints[i - 1].first)
    {
      ++vertex;
    }
    if (denseIds)
    {
      vertexOfDenseId[sortedPoints[i].second] = vertex;
    }
    else
    {
      vertexOfSparseId[sortedPoints[i].second] = vertex;
    }
  }
  const auto vertexOf = [&](typename InputMeshType::PointIdentifier id) {
    return denseIds ? vertexOfDenseId[id] : vertexOfSparseId[id];
  };

  std::vector<TriangleType> triangles;
  triangles.reserve(cells->Size());
  std::vector<std::array<std::uint32_t, 3>> corners;
  corners.reserve(needInside ? cells->Size() : 0);
  SizeValueType numberOfDegenerate = 0;
  const auto    toVector = [points, this](typename InputMeshType::PointIdentifier id, SizeValueType cellId) {
    if (!points->IndexExists(id))
    {
      itkExceptionMacro("Cell " << cellId << " of the input mesh refers to point " << id << ", which does not exist.");
    }
    const auto & p = points->ElementAt(id);
    return VectorType{ static_cast<double>(p[0]), static_cast<double>(p[1]), static_cast<double>(p[2]) };
  };
  const auto visit = [&](SizeValueType cellId, const typename InputMeshType::PointIdentifier * ids) {
    const TriangleType triangle{ toVector(ids[0], cellId), toVector(ids[1], cellId), toVector(ids[2], cellId) };
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
      return;
    }
    triangles.push_back(triangle);
    if (needInside)
    {
      corners.push_back({ { vertexOf(ids[0]), vertexOf(ids[1]), vertexOf(ids[2]) } });
    }
  };
  ForEachPolygonTriangle(mesh, visit, true);
  m_NumberOfDegenerateTriangles = numberOfDegenerate;
  m_NumberOfTriangles = triangles.size();
  if (triangles.empty())
  {
    itkExceptionMacro("The input mesh has no triangle cells"
                      << (numberOfDegenerate > 0 ? " of non-zero area (all are degenerate)." : "."));
  }
  m_TriangleSet.SetTriangles(std::move(triangles), corners, needInside);
}

template <typename TInputMesh, typename TOutputImage>
auto
TriangleMeshToVoxelImageFilter<TInputMesh, TOutputImage>::GetHierarchy() const
  -> const detail::TriangleBoundingVolumeHierarchy &
{
  return m_TriangleSet.GetHierarchy();
}

template <typename TInputMesh, typename TOutputImage>
bool
TriangleMeshToVoxelImageFilter<TInputMesh, TOutputImage>::IsInside(double windingNumber) const
{
  return detail::ScanLineTriangleSet::IsInside(m_AbsoluteWindingNumber, windingNumber);
}

template <typename TInputMesh, typename TOutputImage>
void
TriangleMeshToVoxelImageFilter<TInputMesh, TOutputImage>::DynamicThreadedGenerateData(
  const OutputImageRegionType & outputRegionForThread)
{
  if (this->UsesScanLines() && this->ModeIsReachOnly())
  {
    this->GenerateReachByTriangles(outputRegionForThread);
    this->ClearVoxelsOutsideMask(outputRegionForThread);
  }
  else if (this->UsesScanLines())
  {
    this->GenerateByScanLines(outputRegionForThread);
  }
  else
  {
    this->GeneratePerVoxel(outputRegionForThread);
  }
}

template <typename TInputMesh, typename TOutputImage>
void
TriangleMeshToVoxelImageFilter<TInputMesh, TOutputImage>::GenerateReachByTriangles(const OutputImageRegionType & region)
{
  using VectorType = detail::TriangleBoundingVolumeHierarchy::VectorType;
  OutputImageType *     output = this->GetOutput();
  TotalProgressReporter progress(this, output->GetRequestedRegion().GetNumberOfPixels());
  const SizeValueType   numberOfPixels = region.GetNumberOfPixels();

  // Outside everywhere first; a triangle then marks the voxels within reach. A voxel already marked is
  // skipped: it is inside whichever triangle marked it, so the order of the triangles does not matter.
  OutputPixelType * buffer = output->GetBufferPointer();
  long              from[3], to[3];
  for (unsigned int d = 0; d < 3; ++d)
  {
    from[d] = region.GetIndex(d);
    to[d] = from[d] + static_cast<long>(region.GetSize(d)) - 1;
  }
  typename OutputImageType::IndexType index;
  for (index[2] = from[2]; index[2] <= to[2]; ++index[2])
  {
    for (index[1] = from[1]; index[1] <= to[1]; ++index[1])
    {
      index[0] = from[0];
      std::fill_n(buffer + output->ComputeOffset(index), region.GetSize(0), m_OutsideValue);
    }
  }
  progress.Completed(numberOfPixels / 2);
  if (m_InsideValue == m_OutsideValue)
  {
    progress.Completed(numberOfPixels - numberOfPixels / 2);
    return;
  }

  const double          radius = m_Mode == ModeEnum::Occupancy ? m_EffectiveOccupancyDistance : m_EffectiveBandWidth;
  const double          radiusSquared = radius * radius;
  const SpacingType &   spacing = output->GetSpacing();
  const double          unit = std::min({ spacing[0], spacing[1], spacing[2] });
  const double          limit = radiusSquared * (1.0 + 1e-9) + 1e-9 * unit * unit;
  const OffsetValueType rowStride = output->GetOffsetTable()[1];
  const OffsetValueType sliceStride = output->GetOffsetTable()[2];
  const OutputPixelType insideValue = m_InsideValue;
  // Voxel centres are computed as ImageBase::TransformIndexToPhysicalPoint() computes them (the same
  // operations in the same order on the same index-to-physical matrix, direction * diag(spacing), so the
  // same doubles as the per-voxel path), from local copies.
  double matrix[3][3];
  for (unsigned int r = 0; r < 3; ++r)
  {
    for (unsigned int c = 0; c < 3; ++c)
    {
      matrix[r][c] = output->GetDirection()[r][c] * spacing[c];
    }
  }
  const double o0 = output->GetOrigin()[0];
  const double o1 = output->GetOrigin()[1];
  const double o2 = output->GetOrigin()[2];
  const double m00 = matrix[0][0], m01 = matrix[0][1], m02 = matrix[0][2];
  const double m10 = matrix[1][0], m11 = matrix[1][1], m12 = matrix[1][2];
  const double m20 = matrix[2][0], m21 = matrix[2][1], m22 = matrix[2][2];
  const auto   centre = [=](long i0, long i1, long i2) {
    const double x0 = static_cast<double>(i0);
    const double x1 = static_cast<double>(i1);
    const double x2 = static_cast<double>(i2);
    double       p0 = o0;
    p0 += m00 * x0;
    p0 += m01 * x1;
    p0 += m02 * x2;
    double p1 = o1;
    p1 += m10 * x0;
    p1 += m11 * x1;
    p1 += m12 * x2;
    double p2 = o2;
    p2 += m20 * x0;
    p2 += m21 * x1;
    p2 += m22 * x2;
    return VectorType{ p0, p1, p2 };
  };
  // Slab half-width: the voxels of a row farther than this from a triangle's plane are skipped; it exceeds
  // the reach by far more than rounding (the exact test decides the voxels inside it).
  const double slab = std::sqrt(limit) * (1.0 + 1e-6) + 1e-6 * unit;
  VectorType   closest;
  for (const std::uint32_t t : m_TriangleSet.GetRegionTriangles())
  {
    const detail::IndexSpaceTriangle & box = m_TriangleSet.GetIndexTriangles()[t];
    long                               lower[3], upper[3];
    bool                               empty = false;
    for (unsigned int d = 0; d < 3; ++d)
    {
      lower[d] = std::max(from[d], static_cast<long>(std::ceil(box.lower[d] - m_TriangleSet.GetReachMargin()[d])));
      upper[d] = std::min(to[d], static_cast<long>(std::floor(box.upper[d] + m_TriangleSet.GetReachMargin()[d])));
      empty = empty || lower[d] > upper[d];
    }
    if (empty)
    {
      continue;
    }
    // The distance to the triangle's plane is a lower bound of the distance to the triangle; it is linear
    // in the index: start of the box + slope per step along a row + the changes per row and per slice.
    const auto & triangle = m_TriangleSet.GetTriangles()[t];
    double       ab[3], ac[3];
    for (unsigned int d = 0; d < 3; ++d)
    {
      ab[d] = triangle.b[d] - triangle.a[d];
      ac[d] = triangle.c[d] - triangle.a[d];
    }
    double normal[3] = { ab[1] * ac[2] - ab[2] * ac[1], ab[2] * ac[0] - ab[0] * ac[2], ab[0] * ac[1] - ab[1] * ac[0] };
    const double normalLength = std::sqrt(normal[0] * normal[0] + normal[1] * normal[1] + normal[2] * normal[2]);
    for (double & component : normal)
    {
      component = normalLength > 0.0 ? component / normalLength : 0.0;
    }
    const double      n0 = normal[0], n1 = normal[1], n2 = normal[2];
    const double      a0 = triangle.a[0], a1 = triangle.a[1], a2 = triangle.a[2];
    const VectorType  corner = centre(lower[0], lower[1], lower[2]);
    const double      base = n0 * (corner[0] - a0) + n1 * (corner[1] - a1) + n2 * (corner[2] - a2);
    const double      slope = n0 * m00 + n1 * m10 + n2 * m20;
    const double      perRow = n0 * m01 + n1 * m11 + n2 * m21;
    const double      perSlice = n0 * m02 + n1 * m12 + n2 * m22;
    const double      span = static_cast<double>(upper[0] - lower[0]);
    const bool        flat = std::abs(slope) * (span + 1.0) <= 1e-9 * unit;
    const double      inverseSlope = flat ? 0.0 : 1.0 / slope;
    OutputPixelType * slice = buffer + output->ComputeOffset({ { lower[0], lower[1], lower[2] } });
    for (long k = lower[2]; k <= upper[2]; ++k, slice += sliceStride)
    {
      OutputPixelType * row = slice;
      for (long j = lower[1]; j <= upper[1]; ++j, row += rowStride)
      {
        const double start =
          base + perRow * static_cast<double>(j - lower[1]) + perSlice * static_cast<double>(k - lower[2]);
        double first = 0.0;
        double last = span;
        if (flat)
        {
          if (std::abs(start) > slab + std::abs(slope) * (span + 1.0))
          {
            continue;
          }
        }
        else
        {
          double t1 = (-slab - start) * inverseSlope;
          double t2 = (slab - start) * inverseSlope;
          if (t1 > t2)
          {
            std::swap(t1, t2);
          }
          first = std::max(first, std::ceil(std::max(t1, -1.0) - 1e-6));
          last = std::min(last, std::floor(std::min(t2, span + 1.0) + 1e-6));
        }
        const long        end = lower[0] + static_cast<long>(last);
        OutputPixelType * pixel = row + static_cast<OffsetValueType>(first);
        for (long i = lower[0] + static_cast<long>(first); i <= end; ++i, ++pixel)
        {
          if (*pixel == insideValue)
          {
            continue;
          }
          const VectorType q = centre(i, j, k);
          const double     plane = n0 * (q[0] - a0) + n1 * (q[1] - a1) + n2 * (q[2] - a2);
          if (plane * plane * (1.0 - 1e-9) - 1e-9 * unit * unit > limit)
          {
            continue;
          }
          if (detail::ClosestPointOnTriangle(q, triangle.a, triangle.b, triangle.c, closest) <= radiusSquared)
          {
            *pixel = insideValue;
          }
        }
      }
    }
  }
  progress.Completed(numberOfPixels - numberOfPixels / 2);
}

template <typename TInputMesh, typename TOutputImage>
void
TriangleMeshToVoxelImageFilter<TInputMesh, TOutputImage>::GenerateByScanLines(const OutputImageRegionType & region)
{
  using VectorType = detail::TriangleBoundingVolumeHierarchy::VectorType;
  OutputImageType *     output = this->GetOutput();
  TotalProgressReporter progress(this, output->GetRequestedRegion().GetNumberOfPixels());

  const double band = m_EffectiveBandWidth;
  const double bandSquared = band * band;
  const bool   needSign = this->ModeNeedsSign();
  const bool   needReach = this->ModeIsReachOnly() || (m_Mode == ModeEnum::SignedDistance && !m_ExactDistance);
  const long   first = region.GetIndex(0);
  const auto   count = static_cast<size_t>(region.GetSize(0));
  // Distance between neighbouring voxel centres of a row (for the exact distance's warm start).
  double step = 0.0;
  for (unsigned int d = 0; d < 3; ++d)
  {
    step += output->GetDirection()[d][0] * output->GetDirection()[d][0];
  }
  step = std::sqrt(step) * output->GetSpacing()[0];
  const double spacing[3] = { output->GetSpacing()[0], output->GetSpacing()[1], output->GetSpacing()[2] };

  std::vector<char>                                                inside(count, 0);
  std::vector<double>                                              squaredDistances(count, 0.0);
  std::vector<detail::TriangleBoundingVolumeHierarchy::VectorType> points(count);
  const double                           radius = m_Mode == ModeEnum::Occupancy ? m_EffectiveOccupancyDistance : band;
  const double                           radiusSquared = radius * radius;
  const MaskImageType *                  mask = this->GetMaskImage();
  const OutputPixelType                  farValue = this->GetFarValue();
  PointType                              point;
  ImageScanlineIterator<OutputImageType> it(output, region);
  while (!it.IsAtEnd())
  {
    auto       index = detail::IteratorIndex(it);
    const long j = index[1];
    const long k = index[2];
    // The row is computed between its first and last masked voxel (the whole row without a mask).
    const unsigned char * maskRow = mask != nullptr ? mask->GetBufferPointer() + mask->ComputeOffset(index) : nullptr;
    size_t                spanFirst = 0;
    size_t                spanEnd = count;
    if (maskRow != nullptr)
    {
      while (spanFirst < count && !maskRow[spanFirst])
      {
        ++spanFirst;
      }
      while (spanEnd > spanFirst && !maskRow[spanEnd - 1])
      {
        --spanEnd;
      }
    }
    const size_t span = spanEnd - spanFirst;
    inside.resize(span);
    squaredDistances.resize(span);
    points.resize(span);
    const long spanStart = first + static_cast<long>(spanFirst);
    for (size_t i = 0; i < span; ++i)
    {
      index[0] = spanStart + static_cast<long>(i);
      output->TransformIndexToPhysicalPoint(index, point);
      points[i] =
        VectorType{ static_cast<double>(point[0]), static_cast<double>(point[1]), static_cast<double>(point[2]) };
    }
    if (needSign && span > 0)
    {
      m_TriangleSet.ComputeRowInside(
        spanStart, j, k, points, output->GetSpacing()[0], m_Beta, m_AbsoluteWindingNumber, inside);
    }
    if (needReach && span > 0)
    {
      m_TriangleSet.ComputeRowSquaredDistances(
        spanStart, j, k, spacing, radius, m_Mode != ModeEnum::SignedDistance, points, squaredDistances);
    }
    double previousDistance = -1.0;
    for (size_t voxel = 0; voxel < count; ++voxel, ++it)
    {
      if (maskRow != nullptr && !maskRow[voxel])
      {
        it.Set(farValue);
        continue;
      }
      const size_t i = voxel - spanFirst;
      switch (m_Mode)
      {
        case ModeEnum::Occupancy:
        case ModeEnum::BandMask:
          it.Set(squaredDistances[i] <= radiusSquared ? m_InsideValue : m_OutsideValue);
          break;
        case ModeEnum::Solid:
          it.Set(inside[i] ? m_InsideValue : m_OutsideValue);
          break;
        case ModeEnum::SignedDistance: {
          double distance = band;
          if (m_ExactDistance)
          {
            // The previous voxel's distance plus the step bounds this one; the query with that bound finds
            // the same closest triangle, and falls back to an unbounded query when it finds none.
            const double infinity = std::numeric_limits<double>::infinity();
            const double bound = previousDistance >= 0.0
                                   ? (previousDistance + step) * (previousDistance + step) * (1.0 + 1e-6) + 1e-12
                                   : infinity;
            double       squaredDistance = this->GetHierarchy().SquaredDistance(points[i], bound);
            if (squaredDistance >= bound)
            {
              squaredDistance = this->GetHierarchy().SquaredDistance(points[i], infinity);
            }
            distance = std::sqrt(squaredDistance);
            previousDistance = distance;
          }
          else if (squaredDistances[i] < bandSquared)
          {
            distance = std::sqrt(squaredDistances[i]);
          }
          if (needSign && inside[i])
          {
            distance = -distance;
          }
          it.Set(static_cast<OutputPixelType>(distance));
          break;
        }
        case ModeEnum::WindingNumber:
          break; // Per voxel (GeneratePerVoxel).
      }
    }
    progress.Completed(count);
    it.NextLine();
  }
}

template <typename TInputMesh, typename TOutputImage>
void
TriangleMeshToVoxelImageFilter<TInputMesh, TOutputImage>::GeneratePerVoxel(
  const OutputImageRegionType & outputRegionForThread)
{
  using VectorType = detail::TriangleBoundingVolumeHierarchy::VectorType;
  OutputImageType *     output = this->GetOutput();
  TotalProgressReporter progress(this, output->GetRequestedRegion().GetNumberOfPixels());

  const double band = m_EffectiveBandWidth;
  const double bandSquared = band * band;
  const double beta = m_Beta;

  const MaskImageType *                         mask = this->GetMaskImage();
  const OutputPixelType                         farValue = this->GetFarValue();
  ImageRegionIteratorWithIndex<OutputImageType> it(output, outputRegionForThread);
  PointType                                     point;
  for (; !it.IsAtEnd(); ++it)
  {
    if (mask != nullptr && !mask->GetPixel(it.GetIndex()))
    {
      it.Set(farValue);
      progress.CompletedPixel();
      continue;
    }
    output->TransformIndexToPhysicalPoint(it.GetIndex(), point);
    const VectorType q{ static_cast<double>(point[0]), static_cast<double>(point[1]), static_cast<double>(point[2]) };
    switch (m_Mode)
    {
      case ModeEnum::Occupancy:
        it.Set(this->GetHierarchy().AnyTriangleWithin(q, m_EffectiveOccupancyDistance) ? m_InsideValue
                                                                                       : m_OutsideValue);
        break;
      case ModeEnum::BandMask:
        it.Set(this->GetHierarchy().AnyTriangleWithin(q, band) ? m_InsideValue : m_OutsideValue);
        break;
      case ModeEnum::Solid:
        it.Set(this->IsInside(this->GetHierarchy().WindingNumber(q, beta)) ? m_InsideValue : m_OutsideValue);
        break;
      case ModeEnum::WindingNumber:
        it.Set(static_cast<OutputPixelType>(this->GetHierarchy().WindingNumber(q, beta)));
        break;
      case ModeEnum::SignedDistance: {
        const double squaredDistance = this->GetHierarchy().SquaredDistance(
          q, m_ExactDistance ? std::numeric_limits<double>::infinity() : bandSquared);
        double distance = (!m_ExactDistance && squaredDistance >= bandSquared) ? band : std::sqrt(squaredDistance);
        if (!m_UnsignedDistance && this->IsInside(this->GetHierarchy().WindingNumber(q, beta)))
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
