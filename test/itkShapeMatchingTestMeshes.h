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
// Generated meshes with known correspondences for the tests of the shape-matching methods: a closed sphere (the
// source) and a smoothly deformed cap of it (the target, an open patch), with the measures the tests assert on.
#ifndef itkShapeMatchingTestMeshes_h
#define itkShapeMatchingTestMeshes_h

#include "itkMesh.h"
#include "itkMeshSurfaceDistanceCalculator.h"
#include "itkPointCorrespondenceErrorCalculator.h"
#include "itkTransform.h"
#include "itkTriangleCell.h"

#include <algorithm>
#include <cmath>
#include <map>

namespace ShapeMatchingTestMeshes
{
using MeshType = itk::Mesh<double, 3>;

inline void
AddTriangle(MeshType * mesh, itk::IdentifierType a, itk::IdentifierType b, itk::IdentifierType c)
{
  MeshType::CellAutoPointer cell;
  cell.TakeOwnership(new itk::TriangleCell<MeshType::CellType>);
  cell->SetPointId(0, a);
  cell->SetPointId(1, b);
  cell->SetPointId(2, c);
  mesh->SetCell(mesh->GetNumberOfCells(), cell);
}

// A closed latitude-longitude sphere of radius r around (cx, cy, cz).
inline MeshType::Pointer
MakeSphere(double r, double cx, double cy, double cz)
{
  constexpr unsigned int rings = 16;
  constexpr unsigned int sectors = 32;
  auto                   mesh = MeshType::New();
  MeshType::PointType    p;
  p[0] = cx;
  p[1] = cy;
  p[2] = cz + r;
  mesh->SetPoint(0, p);
  for (unsigned int i = 1; i < rings; ++i)
  {
    const double theta = itk::Math::pi * i / rings;
    for (unsigned int j = 0; j < sectors; ++j)
    {
      const double phi = 2.0 * itk::Math::pi * j / sectors;
      p[0] = cx + r * std::sin(theta) * std::cos(phi);
      p[1] = cy + r * std::sin(theta) * std::sin(phi);
      p[2] = cz + r * std::cos(theta);
      mesh->SetPoint(1 + (i - 1) * sectors + j, p);
    }
  }
  const itk::IdentifierType south = 1 + (rings - 1) * sectors;
  p[0] = cx;
  p[1] = cy;
  p[2] = cz - r;
  mesh->SetPoint(south, p);
  const auto id = [](unsigned int i, unsigned int j) { return 1 + (i - 1) * sectors + j % sectors; };
  for (unsigned int j = 0; j < sectors; ++j)
  {
    AddTriangle(mesh, 0, id(1, j), id(1, j + 1));
    AddTriangle(mesh, south, id(rings - 1, j + 1), id(rings - 1, j));
    for (unsigned int i = 1; i + 1 < rings; ++i)
    {
      AddTriangle(mesh, id(i, j), id(i + 1, j), id(i + 1, j + 1));
      AddTriangle(mesh, id(i, j), id(i + 1, j + 1), id(i, j + 1));
    }
  }
  return mesh;
}

// The triangles of \c source above z = zCut, their vertices moved by a smooth deformation (of up to 1.5 units,
// times \c amplitude: 0 cuts the patch out as it is); the ids of the same material point in source and target are
// kept in \c truth.
inline MeshType::Pointer
MakeDeformedPatch(const MeshType *                                                                 source,
                  double                                                                           zCut,
                  itk::PointCorrespondenceErrorCalculator<MeshType>::CorrespondenceContainerType & truth,
                  double                                                                           amplitude = 1.0)
{
  auto                                               target = MeshType::New();
  std::map<itk::IdentifierType, itk::IdentifierType> newId;
  for (auto it = source->GetCells()->Begin(); it != source->GetCells()->End(); ++it)
  {
    const auto * ids = it.Value()->GetPointIds();
    bool         above = true;
    for (unsigned int k = 0; k < 3; ++k)
    {
      above = above && source->GetPoint(ids[k])[2] > zCut;
    }
    if (!above)
    {
      continue;
    }
    itk::IdentifierType mapped[3];
    for (unsigned int k = 0; k < 3; ++k)
    {
      auto found = newId.find(ids[k]);
      if (found == newId.end())
      {
        MeshType::PointType p = source->GetPoint(ids[k]);
        const double        x = p[0];
        const double        y = p[1];
        p[0] += amplitude * 1.5 * std::sin(y / 8.0);
        p[1] += amplitude * 1.0 * std::cos(x / 9.0);
        p[2] += amplitude * 0.8 * std::sin((x + y) / 10.0);
        found = newId.emplace(ids[k], newId.size()).first;
        target->SetPoint(found->second, p);
        truth.emplace_back(ids[k], found->second);
      }
      mapped[k] = found->second;
    }
    AddTriangle(target, mapped[0], mapped[1], mapped[2]);
  }
  return target;
}

// Mean directed distance from the target's vertices to the surface of \c moved (the paper's measure).
inline double
MeanDistance(const MeshType * target, const MeshType * moved)
{
  auto calculator = itk::MeshSurfaceDistanceCalculator<MeshType>::New();
  calculator->SetSourceMesh(target);
  calculator->SetTargetMesh(moved);
  calculator->Compute();
  return calculator->GetMeanDistance();
}

inline double
MeanTrueError(const MeshType *                                                                       moved,
              const MeshType *                                                                       target,
              const itk::PointCorrespondenceErrorCalculator<MeshType>::CorrespondenceContainerType & truth)
{
  auto calculator = itk::PointCorrespondenceErrorCalculator<MeshType>::New();
  calculator->SetMovedMesh(moved);
  calculator->SetReferenceMesh(target);
  calculator->SetCorrespondences(truth);
  calculator->Compute();
  return calculator->GetMeanError();
}
// Mean |T(y) - x| over the correspondences (x a source vertex, y its target vertex): the true error of a transform
// T that maps target points to source points, the direction every registration method of the module returns.
inline double
TransformTrueError(const itk::Transform<double, 3, 3> *                                                   transform,
                   const MeshType *                                                                       source,
                   const MeshType *                                                                       target,
                   const itk::PointCorrespondenceErrorCalculator<MeshType>::CorrespondenceContainerType & truth)
{
  double sum = 0.0;
  for (const auto & pair : truth)
  {
    sum += transform->TransformPoint(target->GetPoint(pair.second)).EuclideanDistanceTo(source->GetPoint(pair.first));
  }
  return sum / static_cast<double>(truth.size());
}

// A closed, lumpy, non-symmetric blob about 100 units across: a latitude-longitude sphere whose radius varies with
// the direction by terms that no rotation or mirror maps onto themselves (bumps down to about 20 units across, so
// that a part of it has a shape of its own), then stretched (axes 50, 36, 27) and moved
// to (cx, cy, cz).
inline MeshType::Pointer
MakeLumpyShape(double cx, double cy, double cz, unsigned int rings = 40, unsigned int sectors = 80)
{
  auto       mesh = MeshType::New();
  const auto place = [&](double theta, double phi) {
    const double x = std::sin(theta) * std::cos(phi);
    const double y = std::sin(theta) * std::sin(phi);
    const double z = std::cos(theta);
    const double r = 1.0 + 0.18 * x * y + 0.22 * std::max(0.0, x + 0.4 * z) * std::max(0.0, x + 0.4 * z) +
                     0.12 * z * z * z - 0.1 * y * z + 0.08 * std::sin(3.0 * phi + 1.0) * std::sin(theta) +
                     0.06 * std::sin(4.0 * theta) * std::sin(5.0 * phi + 0.5) +
                     0.04 * std::sin(theta) * std::cos(7.0 * phi - 0.3 * theta);
    MeshType::PointType p;
    p[0] = cx + 50.0 * r * x;
    p[1] = cy + 36.0 * r * y;
    p[2] = cz + 27.0 * r * z;
    return p;
  };
  mesh->SetPoint(0, place(0.0, 0.0));
  for (unsigned int i = 1; i < rings; ++i)
  {
    for (unsigned int j = 0; j < sectors; ++j)
    {
      mesh->SetPoint(1 + (i - 1) * sectors + j, place(itk::Math::pi * i / rings, 2.0 * itk::Math::pi * j / sectors));
    }
  }
  const itk::IdentifierType south = 1 + (rings - 1) * sectors;
  mesh->SetPoint(south, place(itk::Math::pi, 0.0));
  const auto id = [sectors](unsigned int i, unsigned int j) { return 1 + (i - 1) * sectors + j % sectors; };
  for (unsigned int j = 0; j < sectors; ++j)
  {
    AddTriangle(mesh, 0, id(1, j), id(1, j + 1));
    AddTriangle(mesh, south, id(rings - 1, j + 1), id(rings - 1, j));
    for (unsigned int i = 1; i + 1 < rings; ++i)
    {
      AddTriangle(mesh, id(i, j), id(i + 1, j), id(i + 1, j + 1));
      AddTriangle(mesh, id(i, j), id(i + 1, j + 1), id(i, j + 1));
    }
  }
  return mesh;
}

// The benchmark's target region: the triangles of \c source with all three vertices in the central box covering
// \c fraction of each axis of its bounding box (an open, possibly disconnected part), vertex ids renumbered; the
// ids of the same point in source and target go to \c truth.
inline MeshType::Pointer
MakeCentralBoxRegion(const MeshType *                                                                 source,
                     double                                                                           fraction,
                     itk::PointCorrespondenceErrorCalculator<MeshType>::CorrespondenceContainerType & truth)
{
  const auto * box = source->GetBoundingBox();
  const auto   inside = [&](const MeshType::PointType & p) {
    for (unsigned int d = 0; d < 3; ++d)
    {
      const double centre = 0.5 * (box->GetMinimum()[d] + box->GetMaximum()[d]);
      const double half = 0.5 * fraction * (box->GetMaximum()[d] - box->GetMinimum()[d]);
      if (std::abs(p[d] - centre) > half)
      {
        return false;
      }
    }
    return true;
  };
  auto                                               target = MeshType::New();
  std::map<itk::IdentifierType, itk::IdentifierType> newId;
  for (auto it = source->GetCells()->Begin(); it != source->GetCells()->End(); ++it)
  {
    const auto * ids = it.Value()->GetPointIds();
    if (!inside(source->GetPoint(ids[0])) || !inside(source->GetPoint(ids[1])) || !inside(source->GetPoint(ids[2])))
    {
      continue;
    }
    itk::IdentifierType mapped[3];
    for (unsigned int k = 0; k < 3; ++k)
    {
      auto found = newId.find(ids[k]);
      if (found == newId.end())
      {
        found = newId.emplace(ids[k], newId.size()).first;
        target->SetPoint(found->second, source->GetPoint(ids[k]));
        truth.emplace_back(ids[k], found->second);
      }
      mapped[k] = found->second;
    }
    AddTriangle(target, mapped[0], mapped[1], mapped[2]);
  }
  return target;
}

// A copy of \c mesh (points and triangles) with every point mapped by \c transform.
template <typename TTransform>
inline MeshType::Pointer
TransformedCopy(const MeshType * mesh, const TTransform * transform)
{
  auto copy = MeshType::New();
  for (auto it = mesh->GetPoints()->Begin(); it != mesh->GetPoints()->End(); ++it)
  {
    copy->SetPoint(it.Index(), transform->TransformPoint(it.Value()));
  }
  for (auto it = mesh->GetCells()->Begin(); it != mesh->GetCells()->End(); ++it)
  {
    const auto * ids = it.Value()->GetPointIds();
    AddTriangle(copy, ids[0], ids[1], ids[2]);
  }
  return copy;
}
} // namespace ShapeMatchingTestMeshes

#endif // itkShapeMatchingTestMeshes_h
