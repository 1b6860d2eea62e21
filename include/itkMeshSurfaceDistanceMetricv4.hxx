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
#ifndef itkMeshSurfaceDistanceMetricv4_hxx
#define itkMeshSurfaceDistanceMetricv4_hxx

#include "itkMeshSurfaceDistanceMetricv4.h"
#include "itkMeshSurfaceDistanceCalculator.h"
#include "itkMultiThreaderBase.h"
#include "itkParametricTemplateTransform.h"
#include "itkTriangleMeshToVoxelImageFilter.h"
#include <algorithm>
#include <cmath>
#include <limits>

namespace itk
{
template <typename TFixedMesh, typename TMovingMesh, typename TDistanceImage>
MeshSurfaceDistanceMetricv4<TFixedMesh, TMovingMesh, TDistanceImage>::MeshSurfaceDistanceMetricv4()
{
  m_Interpolator = InterpolatorType::New();
}

template <typename TFixedMesh, typename TMovingMesh, typename TDistanceImage>
void
MeshSurfaceDistanceMetricv4<TFixedMesh, TMovingMesh, TDistanceImage>::Initialize()
{
  Superclass::Initialize();
  if (this->m_MovingTransform->GetTransformCategory() == MovingTransformType::TransformCategoryEnum::DisplacementField)
  {
    itkExceptionMacro(<< "Transforms with local support are not supported");
  }
  if (m_FixedMesh.IsNull() || m_FixedMesh->GetNumberOfPoints() == 0)
  {
    itkExceptionMacro(<< "The fixed mesh is missing or has no vertex");
  }
  m_FixedPoints.clear();
  m_FixedPoints.reserve(m_FixedMesh->GetNumberOfPoints());
  for (auto it = m_FixedMesh->GetPoints()->Begin(); it != m_FixedMesh->GetPoints()->End(); ++it)
  {
    PointType point;
    for (unsigned int d = 0; d < 3; ++d)
    {
      point[d] = static_cast<double>(it.Value()[d]);
      if (!std::isfinite(point[d]))
      {
        itkExceptionMacro(<< "Fixed vertex " << it.Index() << " has a non-finite coordinate");
      }
    }
    m_FixedPoints.push_back(point);
  }

  if (m_Evaluation == EvaluationEnum::ExactPointToTriangle)
  {
    if (m_MovingMesh.IsNull())
    {
      itkExceptionMacro(<< "Exact point-to-triangle distances need the moving mesh");
    }
    auto triangles = MeshSurfaceDistanceCalculator<MovingMeshType>::ExtractTriangles(m_MovingMesh.GetPointer());
    if (triangles.empty())
    {
      itkExceptionMacro(<< "The moving mesh has no triangle");
    }
    m_Hierarchy.Build(std::move(triangles), 4, false); // distances only
    m_TriangleBounds.clear();
    for (const auto & triangle : m_Hierarchy.GetTriangles())
    {
      std::array<double, 6> bounds;
      for (unsigned int d = 0; d < 3; ++d)
      {
        bounds[d] = std::min(triangle.a[d], std::min(triangle.b[d], triangle.c[d]));
        bounds[3 + d] = std::max(triangle.a[d], std::max(triangle.b[d], triangle.c[d]));
      }
      m_TriangleBounds.push_back(bounds);
    }
    this->BuildTriangleGrid();
    return;
  }

  // The distance map: given, or made from the moving mesh.
  if (m_MovingDistanceImage.IsNotNull())
  {
    m_DistanceImage = m_MovingDistanceImage;
  }
  else
  {
    if (m_MovingMesh.IsNull() || m_MovingMesh->GetNumberOfPoints() == 0)
    {
      itkExceptionMacro(<< "Neither a moving distance image nor a non-empty moving mesh is set");
    }
    using VoxelizerType = TriangleMeshToVoxelImageFilter<MovingMeshType, DistanceImageType>;
    auto                                voxelizer = VoxelizerType::New();
    typename VoxelizerType::SpacingType spacing;
    typename VoxelizerType::PointType   origin;
    typename VoxelizerType::SizeType    size;
    spacing.Fill(m_DistanceMapSpacing);
    VoxelizerType::ComputeGeometryFromMeshBounds(m_MovingMesh, spacing, m_DistanceMapMargin, origin, size);
    voxelizer->SetInput(m_MovingMesh);
    voxelizer->SetOrigin(origin);
    voxelizer->SetSpacing(spacing);
    voxelizer->SetSize(size);
    voxelizer->SetMode(TriangleMeshToVoxelImageFilterEnums::Mode::SignedDistance);
    voxelizer->SetExactDistance(true);
    voxelizer->SetUnsignedDistance(m_UnsignedDistanceMap);
    if (m_NumberOfWorkUnits > 0)
    {
      voxelizer->SetNumberOfWorkUnits(m_NumberOfWorkUnits);
    }
    voxelizer->Update();
    m_DistanceImage = voxelizer->GetOutput();
  }
  const auto & region = m_DistanceImage->GetBufferedRegion();
  for (unsigned int d = 0; d < 3; ++d)
  {
    if (region.GetSize()[d] < 4)
    {
      itkExceptionMacro(<< "The distance image needs at least 4 voxels per axis, has " << region.GetSize());
    }
  }
  if (region != m_DistanceImage->GetLargestPossibleRegion())
  {
    itkExceptionMacro(<< "The distance image must be buffered whole");
  }
  m_MapSize = region.GetSize();
  m_MapBuffer = m_DistanceImage->GetBufferPointer();
  // Physical point of continuous index u: origin + direction * diag(spacing) * u (start index 0 assumed below).
  const auto & spacing = m_DistanceImage->GetSpacing();
  const auto & direction = m_DistanceImage->GetDirection();
  for (unsigned int i = 0; i < 3; ++i)
  {
    for (unsigned int j = 0; j < 3; ++j)
    {
      m_IndexToPhysical(i, j) = direction(i, j) * spacing[j];
      m_PhysicalToIndex(j, i) = direction(i, j) / spacing[j];
    }
  }
  typename DistanceImageType::IndexType start = region.GetIndex();
  m_DistanceImage->TransformIndexToPhysicalPoint(start, m_MapOrigin);
  if (m_Evaluation == EvaluationEnum::BSplineDistanceMap)
  {
    m_Interpolator->SetSplineOrder(3);
    m_Interpolator->SetUseImageDirection(false);
    m_Interpolator->SetInputImage(m_DistanceImage);
  }
}

template <typename TFixedMesh, typename TMovingMesh, typename TDistanceImage>
void
MeshSurfaceDistanceMetricv4<TFixedMesh, TMovingMesh, TDistanceImage>::BuildTriangleGrid()
{
  // Cell size: twice the mean largest box extent of the triangles, at most 64 cells per axis.
  std::array<double, 3> lower{
    { std::numeric_limits<double>::max(), std::numeric_limits<double>::max(), std::numeric_limits<double>::max() }
  };
  std::array<double, 3> upper{ { std::numeric_limits<double>::lowest(),
                                 std::numeric_limits<double>::lowest(),
                                 std::numeric_limits<double>::lowest() } };
  double                meanExtent = 0.0;
  for (const auto & bounds : m_TriangleBounds)
  {
    double extent = 0.0;
    for (unsigned int d = 0; d < 3; ++d)
    {
      lower[d] = std::min(lower[d], bounds[d]);
      upper[d] = std::max(upper[d], bounds[3 + d]);
      extent = std::max(extent, bounds[3 + d] - bounds[d]);
    }
    meanExtent += extent / static_cast<double>(m_TriangleBounds.size());
  }
  double largestSide = 0.0;
  for (unsigned int d = 0; d < 3; ++d)
  {
    largestSide = std::max(largestSide, upper[d] - lower[d]);
  }
  m_CellSize = std::max({ 2.0 * meanExtent, largestSide / 64.0, 1e-9 });
  SizeValueType numberOfCells = 1;
  for (unsigned int d = 0; d < 3; ++d)
  {
    m_CellOrigin[d] = lower[d];
    m_CellCounts[d] = static_cast<SizeValueType>(std::floor((upper[d] - lower[d]) / m_CellSize)) + 1;
    numberOfCells *= m_CellCounts[d];
  }
  const auto cellRange = [this](const std::array<double, 6> & bounds, SizeValueType first[3], SizeValueType last[3]) {
    for (unsigned int d = 0; d < 3; ++d)
    {
      first[d] = static_cast<SizeValueType>(std::floor((bounds[d] - m_CellOrigin[d]) / m_CellSize));
      last[d] = std::min(m_CellCounts[d] - 1,
                         static_cast<SizeValueType>(std::floor((bounds[3 + d] - m_CellOrigin[d]) / m_CellSize)));
    }
  };
  std::vector<SizeValueType> counts(numberOfCells + 1, 0);
  for (int pass = 0; pass < 2; ++pass)
  {
    std::vector<SizeValueType> next;
    if (pass == 1)
    {
      for (SizeValueType c = 0; c < numberOfCells; ++c)
      {
        counts[c + 1] += counts[c];
      }
      m_CellOffsets = counts;
      m_CellTriangles.assign(counts.back(), 0);
      next.assign(counts.begin(), counts.end() - 1);
    }
    for (std::size_t t = 0; t < m_TriangleBounds.size(); ++t)
    {
      SizeValueType first[3];
      SizeValueType last[3];
      cellRange(m_TriangleBounds[t], first, last);
      for (SizeValueType z = first[2]; z <= last[2]; ++z)
      {
        for (SizeValueType y = first[1]; y <= last[1]; ++y)
        {
          for (SizeValueType x = first[0]; x <= last[0]; ++x)
          {
            const SizeValueType cell = x + m_CellCounts[0] * (y + m_CellCounts[1] * z);
            if (pass == 0)
            {
              ++counts[cell + 1];
            }
            else
            {
              m_CellTriangles[next[cell]++] = static_cast<std::uint32_t>(t);
            }
          }
        }
      }
    }
  }
}

template <typename TFixedMesh, typename TMovingMesh, typename TDistanceImage>
double
MeshSurfaceDistanceMetricv4<TFixedMesh, TMovingMesh, TDistanceImage>::EvaluateDistance(const PointType & point,
                                                                                       VectorType *      gradient) const
{
  if (m_Evaluation == EvaluationEnum::ExactPointToTriangle)
  {
    return this->EvaluateExactDistance(point, gradient);
  }
  return this->EvaluateMapDistance(point, gradient);
}

template <typename TFixedMesh, typename TMovingMesh, typename TDistanceImage>
double
MeshSurfaceDistanceMetricv4<TFixedMesh, TMovingMesh, TDistanceImage>::EvaluateMapDistance(const PointType & point,
                                                                                          VectorType * gradient) const
{
  if (m_MapBuffer == nullptr)
  {
    itkExceptionMacro(<< "Initialize() was not called");
  }
  // Continuous index relative to the buffer start, clamped to the image box.
  double u[3];
  double clamped[3];
  bool   isClamped[3];
  bool   outside = false;
  for (unsigned int i = 0; i < 3; ++i)
  {
    u[i] = 0.0;
    for (unsigned int j = 0; j < 3; ++j)
    {
      u[i] += m_PhysicalToIndex(i, j) * (point[j] - m_MapOrigin[j]);
    }
    const double upper = static_cast<double>(m_MapSize[i] - 1);
    clamped[i] = std::min(upper, std::max(0.0, u[i]));
    isClamped[i] = clamped[i] != u[i];
    outside = outside || isClamped[i];
  }
  double value = 0.0;
  double indexGradient[3] = { 0.0, 0.0, 0.0 };
  if (m_Evaluation == EvaluationEnum::BSplineDistanceMap)
  {
    typename InterpolatorType::ContinuousIndexType index;
    const auto                                     start = m_DistanceImage->GetBufferedRegion().GetIndex();
    for (unsigned int i = 0; i < 3; ++i)
    {
      index[i] = clamped[i] + static_cast<double>(start[i]);
    }
    typename InterpolatorType::OutputType          interpolated;
    typename InterpolatorType::CovariantVectorType derivative;
    m_Interpolator->EvaluateValueAndDerivativeAtContinuousIndex(index, interpolated, derivative);
    value = interpolated;
    const auto & spacing = m_DistanceImage->GetSpacing();
    for (unsigned int i = 0; i < 3; ++i)
    {
      indexGradient[i] = derivative[i] * spacing[i]; // without direction: d/du_i divided by spacing_i
    }
  }
  else
  {
    IndexValueType base[3];
    double         fraction[3];
    for (unsigned int i = 0; i < 3; ++i)
    {
      base[i] = std::min(static_cast<IndexValueType>(m_MapSize[i]) - 2, static_cast<IndexValueType>(clamped[i]));
      fraction[i] = clamped[i] - static_cast<double>(base[i]);
    }
    const SizeValueType strideY = m_MapSize[0];
    const SizeValueType strideZ = m_MapSize[0] * m_MapSize[1];
    const SizeValueType offset = base[0] + base[1] * strideY + base[2] * strideZ;
    double              corner[2][2][2];
    for (unsigned int c = 0; c < 8; ++c)
    {
      const unsigned int x = c & 1u;
      const unsigned int y = (c >> 1) & 1u;
      const unsigned int z = (c >> 2) & 1u;
      corner[z][y][x] = static_cast<double>(m_MapBuffer[offset + x + y * strideY + z * strideZ]);
    }
    const double fx = fraction[0];
    const double fy = fraction[1];
    const double fz = fraction[2];
    double       c00 = corner[0][0][0] * (1 - fx) + corner[0][0][1] * fx;
    double       c10 = corner[0][1][0] * (1 - fx) + corner[0][1][1] * fx;
    double       c01 = corner[1][0][0] * (1 - fx) + corner[1][0][1] * fx;
    double       c11 = corner[1][1][0] * (1 - fx) + corner[1][1][1] * fx;
    const double c0 = c00 * (1 - fy) + c10 * fy;
    const double c1 = c01 * (1 - fy) + c11 * fy;
    value = c0 * (1 - fz) + c1 * fz;
    indexGradient[2] = c1 - c0;
    indexGradient[1] = (c10 - c00) * (1 - fz) + (c11 - c01) * fz;
    const double dx00 = corner[0][0][1] - corner[0][0][0];
    const double dx10 = corner[0][1][1] - corner[0][1][0];
    const double dx01 = corner[1][0][1] - corner[1][0][0];
    const double dx11 = corner[1][1][1] - corner[1][1][0];
    indexGradient[0] = (dx00 * (1 - fy) + dx10 * fy) * (1 - fz) + (dx01 * (1 - fy) + dx11 * fy) * fz;
  }
  const double sign = value < 0.0 ? -1.0 : 1.0;
  double       distance = sign * value;
  if (gradient != nullptr)
  {
    for (unsigned int j = 0; j < 3; ++j)
    {
      double sum = 0.0;
      for (unsigned int i = 0; i < 3; ++i)
      {
        if (!isClamped[i])
        {
          sum += sign * indexGradient[i] * m_PhysicalToIndex(i, j);
        }
      }
      (*gradient)[j] = sum;
    }
  }
  if (outside)
  {
    // Distance to the closest point of the image box, added; its gradient is the unit offset.
    VectorType offset;
    for (unsigned int j = 0; j < 3; ++j)
    {
      double boxPoint = m_MapOrigin[j];
      for (unsigned int i = 0; i < 3; ++i)
      {
        boxPoint += m_IndexToPhysical(j, i) * clamped[i];
      }
      offset[j] = point[j] - boxPoint;
    }
    const double length = offset.GetNorm();
    distance += length;
    if (gradient != nullptr && length > 0.0)
    {
      *gradient += offset / length;
    }
  }
  return distance;
}

template <typename TFixedMesh, typename TMovingMesh, typename TDistanceImage>
double
MeshSurfaceDistanceMetricv4<TFixedMesh, TMovingMesh, TDistanceImage>::EvaluateExactDistance(const PointType & point,
                                                                                            VectorType * gradient) const
{
  if (m_Hierarchy.GetNumberOfTriangles() == 0)
  {
    itkExceptionMacro(<< "Initialize() was not called");
  }
  const HierarchyType::VectorType query{ { point[0], point[1], point[2] } };
  const double                    squaredDistance = m_Hierarchy.SquaredDistance(query);
  const double                    distance = std::sqrt(squaredDistance);
  if (gradient == nullptr)
  {
    return distance;
  }
  gradient->Fill(0.0);
  if (distance == 0.0)
  {
    return distance;
  }
  // The closest point: among the triangles of the cells within the distance whose box is within the distance.
  const auto &              triangles = m_Hierarchy.GetTriangles();
  double                    best = std::numeric_limits<double>::infinity();
  HierarchyType::VectorType closest{};
  HierarchyType::VectorType candidate{};
  const double              reach = squaredDistance * (1.0 + 1e-9) + 1e-18;
  const double              radius = std::sqrt(reach);
  IndexValueType            first[3];
  IndexValueType            last[3];
  for (unsigned int d = 0; d < 3; ++d)
  {
    const double low = std::floor((query[d] - radius - m_CellOrigin[d]) / m_CellSize);
    const double high = std::floor((query[d] + radius - m_CellOrigin[d]) / m_CellSize);
    first[d] = static_cast<IndexValueType>(std::max(0.0, low));
    last[d] = static_cast<IndexValueType>(std::min(static_cast<double>(m_CellCounts[d]) - 1.0, high));
  }
  for (IndexValueType z = first[2]; z <= last[2]; ++z)
  {
    for (IndexValueType y = first[1]; y <= last[1]; ++y)
    {
      for (IndexValueType x = first[0]; x <= last[0]; ++x)
      {
        const SizeValueType cell = x + m_CellCounts[0] * (y + m_CellCounts[1] * z);
        for (SizeValueType entry = m_CellOffsets[cell]; entry < m_CellOffsets[cell + 1]; ++entry)
        {
          const std::uint32_t t = m_CellTriangles[entry];
          const auto &        bounds = m_TriangleBounds[t];
          double              boxDistance = 0.0;
          for (unsigned int d = 0; d < 3; ++d)
          {
            const double gap = std::max(0.0, std::max(bounds[d] - query[d], query[d] - bounds[3 + d]));
            boxDistance += gap * gap;
          }
          if (boxDistance > reach)
          {
            continue;
          }
          const double candidateDistance =
            detail::ClosestPointOnTriangle(query, triangles[t].a, triangles[t].b, triangles[t].c, candidate);
          if (candidateDistance < best)
          {
            best = candidateDistance;
            closest = candidate;
          }
        }
      }
    }
  }
  if (best == std::numeric_limits<double>::infinity())
  {
    for (const auto & triangle : triangles) // not reached for queries the cells cover; kept as a safeguard
    {
      const double candidateDistance =
        detail::ClosestPointOnTriangle(query, triangle.a, triangle.b, triangle.c, candidate);
      if (candidateDistance < best)
      {
        best = candidateDistance;
        closest = candidate;
      }
    }
  }
  for (unsigned int d = 0; d < 3; ++d)
  {
    (*gradient)[d] = (query[d] - closest[d]) / distance;
  }
  return distance;
}

template <typename TFixedMesh, typename TMovingMesh, typename TDistanceImage>
void
MeshSurfaceDistanceMetricv4<TFixedMesh, TMovingMesh, TDistanceImage>::Evaluate(MeasureType &    value,
                                                                               DerivativeType * derivative) const
{
  if (m_FixedPoints.empty())
  {
    itkExceptionMacro(<< "Initialize() was not called or the fixed mesh has no vertex");
  }
  const MovingTransformType *  transform = this->m_MovingTransform.GetPointer();
  const auto *                 parametric = dynamic_cast<const ParametricTemplateTransform<double, 3> *>(transform);
  const NumberOfParametersType numberOfParameters = transform->GetNumberOfParameters();
  const SizeValueType          numberOfPoints = m_FixedPoints.size();
  const double                 scale = 1.0 / static_cast<double>(numberOfPoints);

  auto threader = MultiThreaderBase::New();
  if (m_NumberOfWorkUnits > 0)
  {
    threader->SetNumberOfWorkUnits(m_NumberOfWorkUnits);
  }
  const SizeValueType numberOfChunks =
    std::min<SizeValueType>(numberOfPoints, 4 * static_cast<SizeValueType>(threader->GetNumberOfWorkUnits()));
  std::vector<double>         values(numberOfChunks, 0.0);
  std::vector<SizeValueType>  outsideCounts(numberOfChunks, 0);
  std::vector<DerivativeType> derivatives(derivative != nullptr ? numberOfChunks : 0);
  threader->ParallelizeArray(
    0,
    numberOfChunks,
    [&](SizeValueType chunk) {
      const SizeValueType first = chunk * numberOfPoints / numberOfChunks;
      const SizeValueType last = (chunk + 1) * numberOfPoints / numberOfChunks;
      double              sum = 0.0;
      DerivativeType *    local = nullptr;
      if (derivative != nullptr)
      {
        local = &derivatives[chunk];
        local->SetSize(numberOfParameters);
        local->Fill(0.0);
      }
      typename MovingTransformType::JacobianType jacobian;
      VectorType                                 gradient;
      for (SizeValueType i = first; i < last; ++i)
      {
        const PointType mapped = transform->TransformPoint(m_FixedPoints[i]);
        if (m_Evaluation != EvaluationEnum::ExactPointToTriangle)
        {
          for (unsigned int k = 0; k < 3; ++k)
          {
            double u = 0.0;
            for (unsigned int j = 0; j < 3; ++j)
            {
              u += m_PhysicalToIndex(k, j) * (mapped[j] - m_MapOrigin[j]);
            }
            if (u < 0.0 || u > static_cast<double>(m_MapSize[k] - 1))
            {
              ++outsideCounts[chunk];
              break;
            }
          }
        }
        const double distance = this->EvaluateDistance(mapped, local != nullptr ? &gradient : nullptr);
        sum += m_SquaredDistance ? distance * distance : distance;
        if (local == nullptr)
        {
          continue;
        }
        if (m_SquaredDistance)
        {
          gradient *= 2.0 * distance;
        }
        // v4 derivative: the negative gradient of the mean.
        if (parametric != nullptr)
        {
          parametric->AccumulateJacobianTransposeProduct(m_FixedPoints[i], gradient, -scale, *local);
        }
        else
        {
          transform->ComputeJacobianWithRespectToParameters(m_FixedPoints[i], jacobian);
          for (NumberOfParametersType k = 0; k < numberOfParameters; ++k)
          {
            double dot = 0.0;
            for (unsigned int d = 0; d < 3; ++d)
            {
              dot += jacobian(d, k) * gradient[d];
            }
            (*local)[k] -= scale * dot;
          }
        }
      }
      values[chunk] = sum;
    },
    nullptr);
  double        total = 0.0;
  SizeValueType outside = 0;
  for (SizeValueType chunk = 0; chunk < numberOfChunks; ++chunk)
  {
    total += values[chunk];
    outside += outsideCounts[chunk];
  }
  value = total * scale;
  m_NumberOfPointsOutsideDistanceImage = outside;
  if (derivative != nullptr)
  {
    derivative->SetSize(numberOfParameters);
    derivative->Fill(0.0);
    for (const auto & local : derivatives)
    {
      *derivative += local;
    }
  }
  this->m_Value = value;
  this->m_NumberOfValidPoints = numberOfPoints;
}

template <typename TFixedMesh, typename TMovingMesh, typename TDistanceImage>
auto
MeshSurfaceDistanceMetricv4<TFixedMesh, TMovingMesh, TDistanceImage>::GetValue() const -> MeasureType
{
  MeasureType value = 0.0;
  this->Evaluate(value, nullptr);
  return value;
}

template <typename TFixedMesh, typename TMovingMesh, typename TDistanceImage>
void
MeshSurfaceDistanceMetricv4<TFixedMesh, TMovingMesh, TDistanceImage>::GetDerivative(DerivativeType & derivative) const
{
  MeasureType value = 0.0;
  this->Evaluate(value, &derivative);
}

template <typename TFixedMesh, typename TMovingMesh, typename TDistanceImage>
void
MeshSurfaceDistanceMetricv4<TFixedMesh, TMovingMesh, TDistanceImage>::GetValueAndDerivative(
  MeasureType &    value,
  DerivativeType & derivative) const
{
  this->Evaluate(value, &derivative);
}

template <typename TFixedMesh, typename TMovingMesh, typename TDistanceImage>
void
MeshSurfaceDistanceMetricv4<TFixedMesh, TMovingMesh, TDistanceImage>::PrintSelf(std::ostream & os, Indent indent) const
{
  Superclass::PrintSelf(os, indent);
  itkPrintSelfObjectMacro(FixedMesh);
  itkPrintSelfObjectMacro(MovingMesh);
  itkPrintSelfObjectMacro(MovingDistanceImage);
  os << indent << "Evaluation: " << m_Evaluation << std::endl;
  os << indent << "DistanceMapSpacing: " << m_DistanceMapSpacing << std::endl;
  os << indent << "DistanceMapMargin: " << m_DistanceMapMargin << std::endl;
  os << indent << "UnsignedDistanceMap: " << (m_UnsignedDistanceMap ? "On" : "Off") << std::endl;
  os << indent << "SquaredDistance: " << (m_SquaredDistance ? "On" : "Off") << std::endl;
  os << indent << "NumberOfWorkUnits: " << m_NumberOfWorkUnits << std::endl;
  itkPrintSelfObjectMacro(DistanceImage);
  os << indent << "NumberOfPointsOutsideDistanceImage: " << m_NumberOfPointsOutsideDistanceImage << std::endl;
  os << indent << "FixedPoints: " << m_FixedPoints.size() << std::endl;
  itkPrintSelfObjectMacro(Interpolator);
  os << indent << "PhysicalToIndex: " << m_PhysicalToIndex << std::endl;
  os << indent << "IndexToPhysical: " << m_IndexToPhysical << std::endl;
  os << indent << "MapOrigin: " << m_MapOrigin << std::endl;
  os << indent << "MapSize: " << m_MapSize << std::endl;
  os << indent << "MapBuffer: " << (m_MapBuffer != nullptr ? "set" : "none") << std::endl;
  os << indent << "Triangles: " << m_Hierarchy.GetNumberOfTriangles() << std::endl;
  os << indent << "TriangleBounds: " << m_TriangleBounds.size() << std::endl;
  os << indent << "CellOrigin: " << m_CellOrigin[0] << ", " << m_CellOrigin[1] << ", " << m_CellOrigin[2] << std::endl;
  os << indent << "CellSize: " << m_CellSize << std::endl;
  os << indent << "CellCounts: " << m_CellCounts[0] << ", " << m_CellCounts[1] << ", " << m_CellCounts[2] << std::endl;
  os << indent << "CellTriangles: " << m_CellTriangles.size() << std::endl;
}
} // namespace itk

#endif // itkMeshSurfaceDistanceMetricv4_hxx
