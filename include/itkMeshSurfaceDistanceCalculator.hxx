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
#ifndef itkMeshSurfaceDistanceCalculator_hxx
#define itkMeshSurfaceDistanceCalculator_hxx

#include "itkMeshSurfaceDistanceCalculator.h"
#include "itkMeshPolygonTriangles.h"
#include "itkMultiThreaderBase.h"
#include <cmath>

namespace itk
{
template <typename TSourceMesh, typename TTargetMesh>
template <typename TMesh>
std::vector<typename MeshSurfaceDistanceCalculator<TSourceMesh, TTargetMesh>::HierarchyType::Triangle>
MeshSurfaceDistanceCalculator<TSourceMesh, TTargetMesh>::ExtractTriangles(const TMesh * mesh)
{
  std::vector<typename HierarchyType::Triangle> triangles;
  const auto *                                  cells = mesh->GetCells();
  if (cells == nullptr)
  {
    return triangles;
  }
  const auto toVector = [mesh](IdentifierType id) {
    typename TMesh::PointType point{};
    if (!mesh->GetPoint(id, &point))
    {
      itkGenericExceptionMacro(<< "A cell refers to the missing point " << id);
    }
    return typename HierarchyType::VectorType{
      { static_cast<double>(point[0]), static_cast<double>(point[1]), static_cast<double>(point[2]) }
    };
  };
  triangles.reserve(cells->Size());
  ForEachPolygonTriangle(mesh, [&](IdentifierType, const typename TMesh::PointIdentifier * ids) {
    triangles.push_back({ toVector(ids[0]), toVector(ids[1]), toVector(ids[2]) });
  });
  return triangles;
}

template <typename TSourceMesh, typename TTargetMesh>
void
MeshSurfaceDistanceCalculator<TSourceMesh, TTargetMesh>::Compute()
{
  if (m_SourceMesh == nullptr || m_TargetMesh == nullptr)
  {
    itkExceptionMacro(<< "Both the source mesh and the target mesh must be set");
  }
  const auto * points = m_SourceMesh->GetPoints();
  if (points == nullptr || points->Size() == 0)
  {
    itkExceptionMacro(<< "The source mesh has no vertex");
  }
  HierarchyType hierarchy;
  hierarchy.Build(ExtractTriangles(m_TargetMesh.GetPointer()), 4, false); // distances only
  if (hierarchy.GetNumberOfTriangles() == 0)
  {
    itkExceptionMacro(<< "The target mesh has no triangle");
  }

  std::vector<typename HierarchyType::VectorType> queries;
  queries.reserve(points->Size());
  m_PointIdentifiers.clear();
  m_PointIdentifiers.reserve(points->Size());
  for (auto it = points->Begin(); it != points->End(); ++it)
  {
    const auto & point = it.Value();
    m_PointIdentifiers.push_back(it.Index());
    queries.push_back(
      { { static_cast<double>(point[0]), static_cast<double>(point[1]), static_cast<double>(point[2]) } });
  }

  const SizeValueType numberOfPoints = queries.size();
  m_Distances.assign(numberOfPoints, 0.0);
  constexpr SizeValueType chunkSize = 256;
  const SizeValueType     numberOfChunks = (numberOfPoints + chunkSize - 1) / chunkSize;
  auto                    threader = MultiThreaderBase::New();
  if (m_NumberOfWorkUnits > 0)
  {
    threader->SetNumberOfWorkUnits(m_NumberOfWorkUnits);
  }
  threader->ParallelizeArray(
    0,
    numberOfChunks,
    [&](SizeValueType chunk) {
      const SizeValueType end = std::min(numberOfPoints, (chunk + 1) * chunkSize);
      for (SizeValueType k = chunk * chunkSize; k < end; ++k)
      {
        m_Distances[k] = std::sqrt(hierarchy.SquaredDistance(queries[k]));
      }
    },
    nullptr);

  double sum = 0.0;
  double sumOfSquares = 0.0;
  m_MaximumDistance = 0.0;
  for (const double distance : m_Distances)
  {
    sum += distance;
    sumOfSquares += distance * distance;
    m_MaximumDistance = std::max(m_MaximumDistance, distance);
  }
  m_MeanDistance = sum / static_cast<double>(numberOfPoints);
  m_RootMeanSquareDistance = std::sqrt(sumOfSquares / static_cast<double>(numberOfPoints));
  m_MedianDistance = this->GetDistancePercentile(0.5);
  m_Percentile95Distance = this->GetDistancePercentile(0.95);
  this->Modified();
}

template <typename TSourceMesh, typename TTargetMesh>
double
MeshSurfaceDistanceCalculator<TSourceMesh, TTargetMesh>::GetDistancePercentile(double fraction) const
{
  DistanceContainerType values = m_Distances;
  return detail::ComputePercentile(values, fraction);
}

template <typename TSourceMesh, typename TTargetMesh>
auto
MeshSurfaceDistanceCalculator<TSourceMesh, TTargetMesh>::MakePointData() const ->
  typename PointDataContainerType::Pointer
{
  using PixelType = typename SourceMeshType::PixelType;
  auto pointData = PointDataContainerType::New();
  for (std::size_t k = 0; k < m_Distances.size(); ++k)
  {
    pointData->InsertElement(m_PointIdentifiers[k], static_cast<PixelType>(m_Distances[k]));
  }
  return pointData;
}

template <typename TSourceMesh, typename TTargetMesh>
double
MeshSurfaceDistanceCalculator<TSourceMesh, TTargetMesh>::ComputeSymmetricHausdorffDistance(const SourceMeshType * meshA,
                                                                                           const TargetMeshType * meshB)
{
  auto forward = Self::New();
  forward->SetSourceMesh(meshA);
  forward->SetTargetMesh(meshB);
  forward->Compute();
  auto backward = MeshSurfaceDistanceCalculator<TTargetMesh, TSourceMesh>::New();
  backward->SetSourceMesh(meshB);
  backward->SetTargetMesh(meshA);
  backward->Compute();
  return std::max(forward->GetMaximumDistance(), backward->GetMaximumDistance());
}

template <typename TSourceMesh, typename TTargetMesh>
void
MeshSurfaceDistanceCalculator<TSourceMesh, TTargetMesh>::PrintSelf(std::ostream & os, Indent indent) const
{
  Superclass::PrintSelf(os, indent);
  itkPrintSelfObjectMacro(SourceMesh);
  itkPrintSelfObjectMacro(TargetMesh);
  os << indent << "NumberOfWorkUnits: " << m_NumberOfWorkUnits << std::endl;
  os << indent << "MeanDistance: " << m_MeanDistance << std::endl;
  os << indent << "MaximumDistance: " << m_MaximumDistance << std::endl;
  os << indent << "RootMeanSquareDistance: " << m_RootMeanSquareDistance << std::endl;
  os << indent << "MedianDistance: " << m_MedianDistance << std::endl;
  os << indent << "Percentile95Distance: " << m_Percentile95Distance << std::endl;
  os << indent << "Distances: " << m_Distances.size() << " values" << std::endl;
  os << indent << "PointIdentifiers: " << m_PointIdentifiers.size() << " values" << std::endl;
}
} // namespace itk

#endif // itkMeshSurfaceDistanceCalculator_hxx
