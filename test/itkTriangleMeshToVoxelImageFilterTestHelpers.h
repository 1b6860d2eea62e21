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
#ifndef itkTriangleMeshToVoxelImageFilterTestHelpers_h
#define itkTriangleMeshToVoxelImageFilterTestHelpers_h

// Inputs and brute-force references shared by the voxelization tests.

#include "itkMesh.h"
#include "FFDShapeMatchingDetail/itkPointTriangleDistance.h"
#include "itkRegularSphereMeshSource.h"
#include "FFDShapeMatchingDetail/itkTriangleBoundingVolumeHierarchy.h"
#include "itkTriangleCell.h"

#include <array>
#include <cmath>
#include <limits>
#include <vector>

namespace itk
{
namespace VoxelizationTest
{
using Vector3 = std::array<double, 3>;
using Triangle = detail::TriangleBoundingVolumeHierarchy::Triangle;

/** A polyhedral sphere (8 * 4^resolution triangles). */
template <typename TMesh>
typename TMesh::Pointer
MakeSphere(unsigned int resolution, double radius, const Vector3 & center)
{
  auto                                                source = RegularSphereMeshSource<TMesh>::New();
  typename RegularSphereMeshSource<TMesh>::VectorType scale;
  scale.Fill(radius);
  typename RegularSphereMeshSource<TMesh>::PointType centerPoint;
  for (unsigned int k = 0; k < 3; ++k)
  {
    centerPoint[k] = center[k];
  }
  source->SetResolution(resolution);
  source->SetScale(scale);
  source->SetCenter(centerPoint);
  source->Update();
  typename TMesh::Pointer mesh = source->GetOutput();
  mesh->DisconnectPipeline();
  return mesh;
}

/** The triangle cells of a mesh, in physical coordinates. */
template <typename TMesh>
std::vector<Triangle>
ExtractTriangles(const TMesh * mesh)
{
  std::vector<Triangle> triangles;
  for (auto it = mesh->GetCells()->Begin(); it != mesh->GetCells()->End(); ++it)
  {
    if (it.Value()->GetNumberOfPoints() != 3)
    {
      continue;
    }
    const auto * ids = it.Value()->PointIdsBegin();
    Triangle     t;
    for (unsigned int k = 0; k < 3; ++k)
    {
      t.a[k] = mesh->GetPoint(ids[0])[k];
      t.b[k] = mesh->GetPoint(ids[1])[k];
      t.c[k] = mesh->GetPoint(ids[2])[k];
    }
    triangles.push_back(t);
  }
  return triangles;
}

/** A new mesh with the same points and only the triangles whose vertices all satisfy keep(point). */
template <typename TMesh, typename TPredicate>
typename TMesh::Pointer
SelectTriangles(const TMesh * mesh, TPredicate keep, bool flip = false)
{
  using CellAutoPointer = typename TMesh::CellAutoPointer;
  using TriangleCellType = TriangleCell<typename TMesh::CellType>;
  auto result = TMesh::New();
  for (auto it = mesh->GetPoints()->Begin(); it != mesh->GetPoints()->End(); ++it)
  {
    result->SetPoint(it.Index(), it.Value());
  }
  typename TMesh::CellIdentifier cellId = 0;
  for (auto it = mesh->GetCells()->Begin(); it != mesh->GetCells()->End(); ++it)
  {
    const auto * ids = it.Value()->PointIdsBegin();
    if (it.Value()->GetNumberOfPoints() != 3 || !keep(mesh->GetPoint(ids[0])) || !keep(mesh->GetPoint(ids[1])) ||
        !keep(mesh->GetPoint(ids[2])))
    {
      continue;
    }
    CellAutoPointer cell;
    cell.TakeOwnership(new TriangleCellType);
    cell->SetPointId(0, ids[0]);
    cell->SetPointId(1, flip ? ids[2] : ids[1]);
    cell->SetPointId(2, flip ? ids[1] : ids[2]);
    result->SetCell(cellId++, cell);
  }
  return result;
}

/** Brute-force exact distance from q to the closest of all triangles. */
inline double
BruteForceDistance(const Vector3 & q, const std::vector<Triangle> & triangles)
{
  double best = std::numeric_limits<double>::infinity();
  for (const auto & t : triangles)
  {
    best = std::min(best, detail::PointTriangleSquaredDistance(q, t.a, t.b, t.c));
  }
  return std::sqrt(best);
}

/** Brute-force exact generalized winding number: sum of all solid angles / 4 pi. */
inline double
BruteForceWindingNumber(const Vector3 & q, const std::vector<Triangle> & triangles)
{
  double sum = 0.0;
  for (const auto & t : triangles)
  {
    sum += detail::TriangleSolidAngle(q, t.a, t.b, t.c);
  }
  return sum / (4.0 * 3.14159265358979323846);
}

/** Number of crossings of the ray q + t d (t > 0) with the triangles (Moller-Trumbore). */
inline unsigned int
RayCrossings(const Vector3 & q, const Vector3 & d, const std::vector<Triangle> & triangles)
{
  unsigned int count = 0;
  for (const auto & t : triangles)
  {
    const Vector3 e1{ t.b[0] - t.a[0], t.b[1] - t.a[1], t.b[2] - t.a[2] };
    const Vector3 e2{ t.c[0] - t.a[0], t.c[1] - t.a[1], t.c[2] - t.a[2] };
    const Vector3 p{ d[1] * e2[2] - d[2] * e2[1], d[2] * e2[0] - d[0] * e2[2], d[0] * e2[1] - d[1] * e2[0] };
    const double  determinant = e1[0] * p[0] + e1[1] * p[1] + e1[2] * p[2];
    if (std::abs(determinant) < 1e-14)
    {
      continue;
    }
    const Vector3 s{ q[0] - t.a[0], q[1] - t.a[1], q[2] - t.a[2] };
    const double  u = (s[0] * p[0] + s[1] * p[1] + s[2] * p[2]) / determinant;
    if (u < 0.0 || u > 1.0)
    {
      continue;
    }
    const Vector3 r{ s[1] * e1[2] - s[2] * e1[1], s[2] * e1[0] - s[0] * e1[2], s[0] * e1[1] - s[1] * e1[0] };
    const double  v = (d[0] * r[0] + d[1] * r[1] + d[2] * r[2]) / determinant;
    if (v < 0.0 || u + v > 1.0)
    {
      continue;
    }
    if ((e2[0] * r[0] + e2[1] * r[1] + e2[2] * r[2]) / determinant > 0.0)
    {
      ++count;
    }
  }
  return count;
}

/** Inside a closed surface by ray parity, majority of three skew rays (independent of winding numbers). */
inline bool
BruteForceInsideByParity(const Vector3 & q, const std::vector<Triangle> & triangles)
{
  const Vector3 directions[3] = { { 0.3141592, 0.2718281, 0.9121 },
                                  { -0.5772156, 0.7071067, -0.4142135 },
                                  { 0.1234567, -0.8765432, 0.3333333 } };
  unsigned int  votes = 0;
  for (const auto & d : directions)
  {
    votes += RayCrossings(q, d, triangles) % 2;
  }
  return votes >= 2;
}
} // namespace VoxelizationTest
} // namespace itk

#endif // itkTriangleMeshToVoxelImageFilterTestHelpers_h
