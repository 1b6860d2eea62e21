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
#include "itkTriangleCell.h"

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

// The triangles of \c source above z = zCut, their vertices moved by a smooth deformation; the ids of the same
// material point in source and target are kept in \c truth.
inline MeshType::Pointer
MakeDeformedPatch(const MeshType *                                                                 source,
                  double                                                                           zCut,
                  itk::PointCorrespondenceErrorCalculator<MeshType>::CorrespondenceContainerType & truth)
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
        p[0] += 1.5 * std::sin(y / 8.0);
        p[1] += 1.0 * std::cos(x / 9.0);
        p[2] += 0.8 * std::sin((x + y) / 10.0);
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
} // namespace ShapeMatchingTestMeshes

#endif // itkShapeMatchingTestMeshes_h
