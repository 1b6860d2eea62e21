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

#include "itkRegularSphereMeshSource.h"
#include "itkTestingMacros.h"
#include "itkTetrahedronCell.h"
#include "itkTriangleCell.h"

#include "vtkCellArray.h"
#include "vtkDataArray.h"
#include "vtkFloatArray.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSmartPointer.h"

#include <cmath>

// Round trips itk::Mesh -> vtkPolyData -> itk::Mesh (exact), checks the vtkPolyData made from a
// mesh against the mesh, triangulation of polygons and strips, and the refusals.
namespace
{
using MeshType = itk::Mesh<double, 3>;
using DoubleMeshType = itk::Mesh<double, 3, itk::DefaultStaticMeshTraits<double, 3, 3, double, double, double>>;

template <typename TMesh>
typename TMesh::Pointer
MakeSphere()
{
  using SourceType = itk::RegularSphereMeshSource<TMesh>;
  auto                            source = SourceType::New();
  typename SourceType::VectorType scale;
  scale[0] = 3.0;
  scale[1] = 2.0 / 3.0;
  scale[2] = 1.7;
  source->SetScale(scale);
  source->SetResolution(3);
  source->Update();
  typename TMesh::Pointer mesh = source->GetOutput();
  mesh->DisconnectPipeline();
  for (typename TMesh::PointIdentifier i = 0; i < mesh->GetNumberOfPoints(); ++i)
  {
    mesh->SetPointData(i, std::exp(mesh->GetPoint(i)[0]) / 7.0);
  }
  return mesh;
}

/** True when both meshes have exactly the same points, point data and triangles. */
template <typename TMesh>
bool
IdenticalMeshes(const TMesh * a, const TMesh * b)
{
  if (a->GetNumberOfPoints() != b->GetNumberOfPoints() || a->GetNumberOfCells() != b->GetNumberOfCells() ||
      a->GetPointData()->Size() != b->GetPointData()->Size())
  {
    std::cerr << "Sizes differ" << std::endl;
    return false;
  }
  for (typename TMesh::PointIdentifier i = 0; i < a->GetNumberOfPoints(); ++i)
  {
    if (a->GetPoint(i) != b->GetPoint(i))
    {
      std::cerr << "Point " << i << " differs: " << a->GetPoint(i) << " vs " << b->GetPoint(i) << std::endl;
      return false;
    }
  }
  for (typename TMesh::PointIdentifier i = 0; i < a->GetPointData()->Size(); ++i)
  {
    if (a->GetPointData()->ElementAt(i) != b->GetPointData()->ElementAt(i))
    {
      std::cerr << "Point value " << i << " differs" << std::endl;
      return false;
    }
  }
  auto itB = b->GetCells()->Begin();
  for (auto itA = a->GetCells()->Begin(); itA != a->GetCells()->End(); ++itA, ++itB)
  {
    if (itA.Value()->GetType() != itB.Value()->GetType() ||
        itA.Value()->GetNumberOfPoints() != itB.Value()->GetNumberOfPoints())
    {
      std::cerr << "Cell " << itA.Index() << " differs in type" << std::endl;
      return false;
    }
    for (unsigned int k = 0; k < itA.Value()->GetNumberOfPoints(); ++k)
    {
      if (itA.Value()->GetPointIds()[k] != itB.Value()->GetPointIds()[k])
      {
        std::cerr << "Cell " << itA.Index() << " differs in its points" << std::endl;
        return false;
      }
    }
  }
  return true;
}

/** True when polyData holds the points, triangles and point data of mesh, as arrayName. */
template <typename TMesh>
bool
PolyDataMatchesMesh(vtkPolyData * polyData, const TMesh * mesh, const char * arrayName)
{
  if (polyData->GetNumberOfPoints() != static_cast<vtkIdType>(mesh->GetNumberOfPoints()) ||
      polyData->GetNumberOfPolys() != static_cast<vtkIdType>(mesh->GetNumberOfCells()) ||
      polyData->GetNumberOfCells() != static_cast<vtkIdType>(mesh->GetNumberOfCells()))
  {
    std::cerr << "vtkPolyData sizes differ from the mesh" << std::endl;
    return false;
  }
  if (polyData->GetPoints()->GetDataType() != VTK_DOUBLE)
  {
    std::cerr << "vtkPolyData points are not double" << std::endl;
    return false;
  }
  for (typename TMesh::PointIdentifier i = 0; i < mesh->GetNumberOfPoints(); ++i)
  {
    double point[3];
    polyData->GetPoint(static_cast<vtkIdType>(i), point);
    for (unsigned int k = 0; k < 3; ++k)
    {
      if (point[k] != static_cast<double>(mesh->GetPoint(i)[k]))
      {
        std::cerr << "vtkPolyData point " << i << " differs" << std::endl;
        return false;
      }
    }
  }
  vtkDataArray * scalars = polyData->GetPointData()->GetScalars();
  if (scalars == nullptr || std::string(scalars->GetName()) != arrayName || scalars->GetNumberOfComponents() != 1)
  {
    std::cerr << "vtkPolyData has no active scalars named " << arrayName << std::endl;
    return false;
  }
  for (typename TMesh::PointIdentifier i = 0; i < mesh->GetNumberOfPoints(); ++i)
  {
    if (scalars->GetComponent(static_cast<vtkIdType>(i), 0) != mesh->GetPointData()->ElementAt(i))
    {
      std::cerr << "vtkPolyData point value " << i << " differs" << std::endl;
      return false;
    }
  }
  vtkIdType         numberOfCellPoints = 0;
  const vtkIdType * cellPoints = nullptr;
  auto              cellIt = mesh->GetCells()->Begin();
  vtkCellArray *    polys = polyData->GetPolys();
  for (polys->InitTraversal(); polys->GetNextCell(numberOfCellPoints, cellPoints); ++cellIt)
  {
    if (numberOfCellPoints != 3)
    {
      return false;
    }
    for (unsigned int k = 0; k < 3; ++k)
    {
      if (static_cast<vtkIdType>(cellIt.Value()->GetPointIds()[k]) != cellPoints[k])
      {
        std::cerr << "vtkPolyData cell " << cellIt.Index() << " differs" << std::endl;
        return false;
      }
    }
  }
  return true;
}

template <typename TMesh>
int
RoundTrip()
{
  const typename TMesh::Pointer mesh = MakeSphere<TMesh>();
  auto                          polyData = vtkSmartPointer<vtkPolyData>::New();
  ITK_TRY_EXPECT_NO_EXCEPTION(itk::MeshToVTKPolyData(mesh, polyData, "distance"));
  ITK_TEST_EXPECT_TRUE(PolyDataMatchesMesh(polyData.GetPointer(), mesh.GetPointer(), "distance"));

  auto back = TMesh::New();
  ITK_TRY_EXPECT_NO_EXCEPTION(itk::VTKPolyDataToMesh(polyData, back, "distance"));
  ITK_TEST_EXPECT_TRUE(IdenticalMeshes(back.GetPointer(), mesh.GetPointer()));

  // Without a name, the active scalars are taken; the mesh given is emptied first.
  ITK_TRY_EXPECT_NO_EXCEPTION(itk::VTKPolyDataToMesh(polyData, back));
  ITK_TEST_EXPECT_TRUE(IdenticalMeshes(back.GetPointer(), mesh.GetPointer()));

  // A missing array name is refused.
  ITK_TRY_EXPECT_EXCEPTION(itk::VTKPolyDataToMesh(polyData, back, "noSuchArray"));

  // Without point data, none is made.
  polyData->GetPointData()->Initialize();
  ITK_TRY_EXPECT_NO_EXCEPTION(itk::VTKPolyDataToMesh(polyData, back));
  ITK_TEST_EXPECT_EQUAL(back->GetPointData()->Size(), 0u);
  ITK_TEST_EXPECT_EQUAL(back->GetNumberOfCells(), mesh->GetNumberOfCells());
  return EXIT_SUCCESS;
}
} // namespace

int
itkMeshVTKPolyDataConversionTest(int argc, char * argv[])
{
  if (argc != 1)
  {
    std::cerr << "Usage: " << itkNameOfTestExecutableMacro(argv) << std::endl;
    return EXIT_FAILURE;
  }

  // Exact round trips for both mesh types.
  if (RoundTrip<MeshType>() != EXIT_SUCCESS || RoundTrip<DoubleMeshType>() != EXIT_SUCCESS)
  {
    return EXIT_FAILURE;
  }

  // Double coordinates that float cannot hold survive.
  {
    auto                      mesh = DoubleMeshType::New();
    DoubleMeshType::PointType point;
    point[0] = 0.1;
    point[1] = 1.0 / 3.0;
    point[2] = 1e-17 + 1.0;
    mesh->SetPoint(0, point);
    auto polyData = vtkSmartPointer<vtkPolyData>::New();
    itk::MeshToVTKPolyData(mesh, polyData);
    auto back = DoubleMeshType::New();
    itk::VTKPolyDataToMesh(polyData, back);
    ITK_TEST_EXPECT_EQUAL(back->GetNumberOfPoints(), 1u);
    ITK_TEST_EXPECT_TRUE(back->GetPoint(0) == point);
    ITK_TEST_EXPECT_EQUAL(back->GetNumberOfCells(), 0u);
  }

  // A vtkPolyData with a unit square, a triangle strip of three triangles, a line and a vertex:
  // 2 + 3 triangles, the line and vertex dropped, float point data taken as active scalars.
  {
    auto points = vtkSmartPointer<vtkPoints>::New();
    for (int i = 0; i < 5; ++i)
    {
      points->InsertNextPoint(i % 2, i / 2, 0.0); // strip zig-zag (0,0) (1,0) (0,1) (1,1) (0,2)
    }
    points->InsertNextPoint(5.0, 0.0, 1.0);
    points->InsertNextPoint(6.0, 0.0, 1.0);
    points->InsertNextPoint(6.0, 1.0, 1.0);
    points->InsertNextPoint(5.0, 1.0, 1.0);
    auto polys = vtkSmartPointer<vtkCellArray>::New();
    polys->InsertNextCell({ 5, 6, 7, 8 });
    auto strips = vtkSmartPointer<vtkCellArray>::New();
    strips->InsertNextCell({ 0, 1, 2, 3, 4 });
    auto lines = vtkSmartPointer<vtkCellArray>::New();
    lines->InsertNextCell({ 0, 5 });
    auto verts = vtkSmartPointer<vtkCellArray>::New();
    verts->InsertNextCell({ 8 });
    auto values = vtkSmartPointer<vtkFloatArray>::New();
    values->SetName("values");
    for (vtkIdType i = 0; i < points->GetNumberOfPoints(); ++i)
    {
      values->InsertNextValue(0.25f * static_cast<float>(i));
    }
    auto polyData = vtkSmartPointer<vtkPolyData>::New();
    polyData->SetPoints(points);
    polyData->SetPolys(polys);
    polyData->SetStrips(strips);
    polyData->SetLines(lines);
    polyData->SetVerts(verts);
    polyData->GetPointData()->SetScalars(values);

    auto mesh = MeshType::New();
    ITK_TRY_EXPECT_NO_EXCEPTION(itk::VTKPolyDataToMesh(polyData, mesh));
    ITK_TEST_EXPECT_EQUAL(mesh->GetNumberOfPoints(), 9u);
    ITK_TEST_EXPECT_EQUAL(mesh->GetNumberOfCells(), 5u);
    double area = 0.0;
    for (auto it = mesh->GetCells()->Begin(); it != mesh->GetCells()->End(); ++it)
    {
      ITK_TEST_EXPECT_TRUE(it.Value()->GetType() == itk::CellGeometryEnum::TRIANGLE_CELL);
      const auto * ids = it.Value()->GetPointIds();
      area += 0.5 * itk::CrossProduct(mesh->GetPoint(ids[1]) - mesh->GetPoint(ids[0]),
                                      mesh->GetPoint(ids[2]) - mesh->GetPoint(ids[0]))
                      .GetNorm();
    }
    ITK_TEST_EXPECT_TRUE(itk::Math::FloatAlmostEqual(area, 1.0 + 1.5, 4, 1e-12));
    ITK_TEST_EXPECT_EQUAL(mesh->GetPointData()->Size(), 9u);
    for (unsigned int i = 0; i < 9; ++i)
    {
      ITK_TEST_EXPECT_EQUAL(mesh->GetPointData()->ElementAt(i), 0.25 * i);
    }
  }

  // Refusals: null arguments, a volume cell, a cell on a missing point.
  {
    auto polyData = vtkSmartPointer<vtkPolyData>::New();
    auto mesh = MeshType::New();
    ITK_TRY_EXPECT_EXCEPTION(itk::VTKPolyDataToMesh(nullptr, mesh));
    ITK_TRY_EXPECT_EXCEPTION(itk::VTKPolyDataToMesh(polyData, static_cast<MeshType *>(nullptr)));
    ITK_TRY_EXPECT_EXCEPTION(itk::MeshToVTKPolyData(static_cast<const MeshType *>(nullptr), polyData));
    ITK_TRY_EXPECT_EXCEPTION(itk::MeshToVTKPolyData(mesh, nullptr));

    for (unsigned int i = 0; i < 4; ++i)
    {
      MeshType::PointType point;
      point.Fill(0.0);
      point[i % 3] = i;
      mesh->SetPoint(i, point);
    }
    MeshType::CellAutoPointer cell;
    cell.TakeOwnership(new itk::TetrahedronCell<MeshType::CellType>);
    for (unsigned int k = 0; k < 4; ++k)
    {
      cell->SetPointId(k, k);
    }
    mesh->SetCell(0, cell);
    ITK_TRY_EXPECT_EXCEPTION(itk::MeshToVTKPolyData(mesh, polyData));

    // Replacing a cell does not free the old one (itk::Mesh owns cells through raw pointers): free it first.
    delete mesh->GetCells()->ElementAt(0);
    mesh->GetCells()->DeleteIndex(0);
    cell.TakeOwnership(new itk::TriangleCell<MeshType::CellType>);
    cell->SetPointId(0, 0);
    cell->SetPointId(1, 1);
    cell->SetPointId(2, 7);
    mesh->SetCell(0, cell);
    ITK_TRY_EXPECT_EXCEPTION(itk::MeshToVTKPolyData(mesh, polyData));
  }

  std::cout << "Test finished." << std::endl;
  return EXIT_SUCCESS;
}
