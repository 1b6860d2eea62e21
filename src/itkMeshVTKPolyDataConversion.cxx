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
#include "itkMeshVTKPolyDataConversion.h"

#include "itkFFDShapeMatchingVTKUtilities.h"
#include "itkTriangleCell.h"

#include "vtkCellArray.h"
#include "vtkDoubleArray.h"
#include "vtkPointData.h"
#include "vtkPoints.h"

#include <limits>
#include <vector>

namespace itk
{
namespace
{
using DoubleMeshType = Mesh<double, 3, DefaultStaticMeshTraits<double, 3, 3, double, double, double>>;

template <typename ConversionMeshType>
void
VTKPolyDataToMeshImplementation(vtkPolyData *        polyData,
                                ConversionMeshType * mesh,
                                const std::string &  pointDataArrayName)
{
  if (polyData == nullptr || mesh == nullptr)
  {
    itkGenericExceptionMacro(<< "VTKPolyDataToMesh: the " << (polyData == nullptr ? "vtkPolyData" : "mesh")
                             << " is null");
  }
  vtkDataArray * pointData = nullptr;
  if (!pointDataArrayName.empty())
  {
    pointData = polyData->GetPointData()->GetArray(pointDataArrayName.c_str());
    if (pointData == nullptr || pointData->GetNumberOfComponents() != 1)
    {
      itkGenericExceptionMacro(<< "VTKPolyDataToMesh: the vtkPolyData has no single-component point array named \""
                               << pointDataArrayName << "\"");
    }
  }
  else
  {
    pointData = detail::SelectScalarPointData(polyData, "");
  }

  const std::string problem = detail::CheckVTKPolyDataPointIds(polyData);
  if (!problem.empty())
  {
    itkGenericExceptionMacro(<< "VTKPolyDataToMesh: " << problem);
  }
  vtkSmartPointer<vtkPolyData> triangles;
  {
    detail::VTKMessageCapture capture;
    triangles = detail::TriangulateVTKPolyData(polyData);
  }

  using PointIdentifier = typename ConversionMeshType::PointIdentifier;
  using CellIdentifier = typename ConversionMeshType::CellIdentifier;
  mesh->Initialize();
  mesh->SetPoints(ConversionMeshType::PointsContainer::New());
  mesh->SetPointData(ConversionMeshType::PointDataContainer::New());
  mesh->SetCells(ConversionMeshType::CellsContainer::New());
  const vtkIdType numberOfPoints = polyData->GetNumberOfPoints();
  mesh->GetPoints()->Reserve(static_cast<PointIdentifier>(numberOfPoints));
  typename ConversionMeshType::PointType point;
  double                                 coordinates[3];
  for (vtkIdType i = 0; i < numberOfPoints; ++i)
  {
    polyData->GetPoint(i, coordinates);
    for (unsigned int j = 0; j < 3; ++j)
    {
      point[j] = static_cast<typename ConversionMeshType::PointType::ValueType>(coordinates[j]);
    }
    mesh->SetPoint(static_cast<PointIdentifier>(i), point);
  }
  if (pointData != nullptr)
  {
    mesh->GetPointData()->Reserve(static_cast<PointIdentifier>(numberOfPoints));
    for (vtkIdType i = 0; i < numberOfPoints; ++i)
    {
      mesh->SetPointData(static_cast<PointIdentifier>(i), pointData->GetComponent(i, 0));
    }
  }

  using TriangleCellType = TriangleCell<typename ConversionMeshType::CellType>;
  vtkCellArray *    polys = triangles->GetPolys();
  vtkIdType         numberOfCellPoints = 0;
  const vtkIdType * cellPoints = nullptr;
  CellIdentifier    cellId = 0;
  mesh->GetCells()->Reserve(static_cast<CellIdentifier>(triangles->GetNumberOfPolys()));
  for (polys->InitTraversal(); polys->GetNextCell(numberOfCellPoints, cellPoints);)
  {
    typename ConversionMeshType::CellAutoPointer cell;
    cell.TakeOwnership(new TriangleCellType);
    for (unsigned int j = 0; j < 3; ++j)
    {
      cell->SetPointId(j, static_cast<PointIdentifier>(cellPoints[j]));
    }
    mesh->SetCell(cellId++, cell);
  }
}

template <typename ConversionMeshType>
void
MeshToVTKPolyDataImplementation(const ConversionMeshType * mesh,
                                vtkPolyData *              polyData,
                                const std::string &        pointDataArrayName)
{
  using PointIdentifier = typename ConversionMeshType::PointIdentifier;
  if (mesh == nullptr || polyData == nullptr)
  {
    itkGenericExceptionMacro(<< "MeshToVTKPolyData: the " << (mesh == nullptr ? "mesh" : "vtkPolyData") << " is null");
  }
  const PointIdentifier numberOfPoints = mesh->GetNumberOfPoints();
  auto                  points = vtkSmartPointer<vtkPoints>::New();
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(static_cast<vtkIdType>(numberOfPoints));
  const typename ConversionMeshType::PointsContainer * meshPoints = mesh->GetPoints();
  for (PointIdentifier i = 0; i < numberOfPoints; ++i)
  {
    const typename ConversionMeshType::PointType & point = meshPoints->ElementAt(i);
    points->SetPoint(static_cast<vtkIdType>(i),
                     static_cast<double>(point[0]),
                     static_cast<double>(point[1]),
                     static_cast<double>(point[2]));
  }

  auto                   verts = vtkSmartPointer<vtkCellArray>::New();
  auto                   lines = vtkSmartPointer<vtkCellArray>::New();
  auto                   polys = vtkSmartPointer<vtkCellArray>::New();
  std::vector<vtkIdType> cellPoints;
  if (mesh->GetCells() != nullptr)
  {
    for (auto it = mesh->GetCells()->Begin(); it != mesh->GetCells()->End(); ++it)
    {
      const typename ConversionMeshType::CellType * cell = it.Value();
      cellPoints.clear();
      for (auto pointIt = cell->PointIdsBegin(); pointIt != cell->PointIdsEnd(); ++pointIt)
      {
        if (*pointIt >= numberOfPoints)
        {
          itkGenericExceptionMacro(<< "MeshToVTKPolyData: cell " << it.Index() << " refers to point " << *pointIt
                                   << " of " << numberOfPoints);
        }
        cellPoints.push_back(static_cast<vtkIdType>(*pointIt));
      }
      const auto numberOfCellPoints = static_cast<vtkIdType>(cellPoints.size());
      switch (cell->GetType())
      {
        case CellGeometryEnum::VERTEX_CELL:
          verts->InsertNextCell(numberOfCellPoints, cellPoints.data());
          break;
        case CellGeometryEnum::LINE_CELL:
          lines->InsertNextCell(numberOfCellPoints, cellPoints.data());
          break;
        case CellGeometryEnum::TRIANGLE_CELL:
        case CellGeometryEnum::QUADRILATERAL_CELL:
        case CellGeometryEnum::POLYGON_CELL:
          polys->InsertNextCell(numberOfCellPoints, cellPoints.data());
          break;
        default:
          itkGenericExceptionMacro(<< "MeshToVTKPolyData: cell " << it.Index() << " is of type " << cell->GetType()
                                   << ", which vtkPolyData cannot hold");
      }
    }
  }

  polyData->Initialize();
  polyData->SetPoints(points);
  polyData->SetVerts(verts);
  polyData->SetLines(lines);
  polyData->SetPolys(polys);

  const typename ConversionMeshType::PointDataContainer * meshPointData = mesh->GetPointData();
  if (meshPointData != nullptr && meshPointData->Size() > 0)
  {
    auto array = vtkSmartPointer<vtkDoubleArray>::New();
    array->SetName(pointDataArrayName.c_str());
    array->SetNumberOfComponents(1);
    array->SetNumberOfTuples(static_cast<vtkIdType>(numberOfPoints));
    for (PointIdentifier i = 0; i < numberOfPoints; ++i)
    {
      double value = std::numeric_limits<double>::quiet_NaN();
      mesh->GetPointData(i, &value);
      array->SetValue(static_cast<vtkIdType>(i), value);
    }
    polyData->GetPointData()->SetScalars(array);
  }
}
} // namespace

void
VTKPolyDataToMesh(vtkPolyData * polyData, Mesh<double, 3> * mesh, const std::string & pointDataArrayName)
{
  VTKPolyDataToMeshImplementation(polyData, mesh, pointDataArrayName);
}

void
VTKPolyDataToMesh(vtkPolyData * polyData, DoubleMeshType * mesh, const std::string & pointDataArrayName)
{
  VTKPolyDataToMeshImplementation(polyData, mesh, pointDataArrayName);
}

void
MeshToVTKPolyData(const Mesh<double, 3> * mesh, vtkPolyData * polyData, const std::string & pointDataArrayName)
{
  MeshToVTKPolyDataImplementation(mesh, polyData, pointDataArrayName);
}

void
MeshToVTKPolyData(const DoubleMeshType * mesh, vtkPolyData * polyData, const std::string & pointDataArrayName)
{
  MeshToVTKPolyDataImplementation(mesh, polyData, pointDataArrayName);
}
} // namespace itk
