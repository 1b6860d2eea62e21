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
#ifndef itkMeshPolygonTriangles_h
#define itkMeshPolygonTriangles_h

#include "itkCommonEnums.h"
#include "itkMacro.h"

namespace itk
{
/** Calls visit(cellIdentifier, pointIds) for each triangle of the polygon cells of a mesh, where pointIds is an
 * array of the triangle's three point identifiers. Triangle, quadrilateral and polygon cells with at least three
 * points are fan-triangulated from their first point, in cell order and point order; cells of other types
 * (vertices, lines, quadratic cells) are skipped, and so are volume cells unless volumeCellsAreErrors, in which case
 * an ExceptionObject names the first one. The point identifiers are not checked: the visitor decides what a missing
 * point means.
 *
 * This is the one place where the module turns a polygon mesh into triangles: the voxelizer, the exact distances,
 * the pose stage's surface samples and the programs' triangulated copies all see the same triangles; a program that
 * needs the triangles the module's filters see calls it too.
 *
 * \ingroup FFDShapeMatching
 */
template <typename TMesh, typename TVisitor>
void
ForEachPolygonTriangle(const TMesh * mesh, TVisitor && visit, bool volumeCellsAreErrors = false)
{
  const auto * cells = mesh->GetCells();
  if (cells == nullptr)
  {
    return;
  }
  for (auto it = cells->Begin(); it != cells->End(); ++it)
  {
    const auto * cell = it.Value();
    if (cell == nullptr)
    {
      continue;
    }
    if (cell->GetDimension() > 2 && volumeCellsAreErrors)
    {
      itkGenericExceptionMacro(<< "Cell " << it.Index() << " of the input mesh is a volume cell ("
                               << cell->GetNumberOfPoints()
                               << " points): only triangle and polygon cells are supported.");
    }
    const auto type = cell->GetType();
    if ((type != CellGeometryEnum::TRIANGLE_CELL && type != CellGeometryEnum::QUADRILATERAL_CELL &&
         type != CellGeometryEnum::POLYGON_CELL) ||
        cell->GetNumberOfPoints() < 3)
    {
      continue;
    }
    const auto *       ids = cell->PointIdsBegin();
    const unsigned int numberOfPoints = cell->GetNumberOfPoints();
    for (unsigned int i = 1; i + 1 < numberOfPoints; ++i)
    {
      const typename TMesh::PointIdentifier triangle[3] = { ids[0], ids[i], ids[i + 1] };
      visit(it.Index(), triangle);
    }
  }
}
} // namespace itk

#endif // itkMeshPolygonTriangles_h
