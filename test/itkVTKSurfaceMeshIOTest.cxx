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
#include "itkVTKSurfaceMeshIO.h"
#include "itkVTKSurfaceMeshIOFactory.h"
#include "itkRegisterFFDShapeMatchingMeshIOFactories.h"

#include "itkLineCell.h"
#include "itkMesh.h"
#include "itkMeshFileReader.h"
#include "itkMeshFileWriter.h"
#include "itkOFFMeshIOFactory.h"
#include "itkQuadrilateralCell.h"
#include "itkRegularSphereMeshSource.h"
#include "itkTetrahedronCell.h"
#include "itkTestingMacros.h"
#include "itkTriangleCell.h"
#include "itkVertexCell.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iterator>
#include <limits>
#include <random>
#include <string>
#include <vector>

// Writes meshes to STL, PLY and VTP and reads them back through MeshFileReader/Writer and the
// factory, reads an OFF file written by ITK, and checks that damaged or missing files end in an
// ExceptionObject naming the file and the problem.
namespace
{
using MeshType = itk::Mesh<double, 3>; // float coordinates, ITK's default
using DoubleMeshType = itk::Mesh<double, 3, itk::DefaultStaticMeshTraits<double, 3, 3, double, double, double>>;

template <typename TMesh>
typename TMesh::Pointer
MakeSphere(unsigned int resolution)
{
  using SourceType = itk::RegularSphereMeshSource<TMesh>;
  auto                            source = SourceType::New();
  typename SourceType::VectorType scale;
  typename SourceType::PointType  center;
  scale[0] = 10.0;
  scale[1] = 7.3;
  scale[2] = 5.1;
  center[0] = 1.0 / 3.0;
  center[1] = -2.25;
  center[2] = 0.1;
  source->SetScale(scale);
  source->SetCenter(center);
  source->SetResolution(resolution);
  source->Update();
  typename TMesh::Pointer mesh = source->GetOutput();
  mesh->DisconnectPipeline();
  for (typename TMesh::PointIdentifier i = 0; i < mesh->GetNumberOfPoints(); ++i)
  {
    const typename TMesh::PointType point = mesh->GetPoint(i);
    mesh->SetPointData(i, point[0] * point[1] + std::sqrt(2.0) * point[2]);
  }
  return mesh;
}

template <typename TMesh>
void
WriteMesh(const TMesh * mesh, const std::string & fileName)
{
  auto writer = itk::MeshFileWriter<TMesh>::New();
  writer->SetInput(mesh);
  writer->SetFileName(fileName);
  writer->Update();
}

template <typename TMesh>
typename TMesh::Pointer
ReadMesh(const std::string & fileName)
{
  auto reader = itk::MeshFileReader<TMesh>::New();
  reader->SetFileName(fileName);
  reader->Update();
  typename TMesh::Pointer mesh = reader->GetOutput();
  mesh->DisconnectPipeline();
  return mesh;
}

/** True when every cell of mesh is a triangle. */
template <typename TMesh>
bool
AllTriangles(const TMesh * mesh)
{
  for (auto it = mesh->GetCells()->Begin(); it != mesh->GetCells()->End(); ++it)
  {
    if (it.Value()->GetType() != itk::CellGeometryEnum::TRIANGLE_CELL)
    {
      return false;
    }
  }
  return true;
}

/** Sum of the triangle areas of mesh. */
template <typename TMesh>
double
SurfaceArea(const TMesh * mesh)
{
  double area = 0.0;
  for (auto it = mesh->GetCells()->Begin(); it != mesh->GetCells()->End(); ++it)
  {
    const auto * ids = it.Value()->GetPointIds();
    const auto   a = mesh->GetPoint(ids[0]);
    const auto   b = mesh->GetPoint(ids[1]);
    const auto   c = mesh->GetPoint(ids[2]);
    const auto   cross = itk::CrossProduct(b - a, c - a);
    area += 0.5 * cross.GetNorm();
  }
  return area;
}

/** Largest distance from a point of `from` to its nearest point of `to` (brute force). */
template <typename TMeshA, typename TMeshB>
double
DirectedPointDistance(const TMeshA * from, const TMeshB * to)
{
  double largest = 0.0;
  for (typename TMeshA::PointIdentifier i = 0; i < from->GetNumberOfPoints(); ++i)
  {
    const auto p = from->GetPoint(i);
    double     nearest = std::numeric_limits<double>::max();
    for (typename TMeshB::PointIdentifier j = 0; j < to->GetNumberOfPoints(); ++j)
    {
      const auto q = to->GetPoint(j);
      double     squared = 0.0;
      for (unsigned int k = 0; k < 3; ++k)
      {
        squared += (double(p[k]) - double(q[k])) * (double(p[k]) - double(q[k]));
      }
      nearest = std::min(nearest, squared);
    }
    largest = std::max(largest, std::sqrt(nearest));
  }
  return largest;
}

/** Largest coordinate difference between the points of two meshes with the same point ids;
 * infinity when the numbers of points differ. */
template <typename TMeshA, typename TMeshB>
double
SamePointIdsDifference(const TMeshA * a, const TMeshB * b)
{
  if (a->GetNumberOfPoints() != b->GetNumberOfPoints())
  {
    return std::numeric_limits<double>::infinity();
  }
  double largest = 0.0;
  for (typename TMeshA::PointIdentifier i = 0; i < a->GetNumberOfPoints(); ++i)
  {
    for (unsigned int k = 0; k < 3; ++k)
    {
      largest = std::max(largest, std::abs(double(a->GetPoint(i)[k]) - double(b->GetPoint(i)[k])));
    }
  }
  return largest;
}

/** True when both meshes have the same cells with the same point ids, in the same order. */
template <typename TMeshA, typename TMeshB>
bool
SameCells(const TMeshA * a, const TMeshB * b)
{
  if (a->GetNumberOfCells() != b->GetNumberOfCells())
  {
    return false;
  }
  auto itB = b->GetCells()->Begin();
  for (auto itA = a->GetCells()->Begin(); itA != a->GetCells()->End(); ++itA, ++itB)
  {
    if (itA.Value()->GetNumberOfPoints() != itB.Value()->GetNumberOfPoints())
    {
      return false;
    }
    for (unsigned int k = 0; k < itA.Value()->GetNumberOfPoints(); ++k)
    {
      if (itA.Value()->GetPointIds()[k] != itB.Value()->GetPointIds()[k])
      {
        return false;
      }
    }
  }
  return true;
}

/** Largest difference between the point data of two meshes; infinity when sizes differ. */
template <typename TMeshA, typename TMeshB>
double
PointDataDifference(const TMeshA * a, const TMeshB * b)
{
  if (a->GetPointData()->Size() != b->GetPointData()->Size())
  {
    return std::numeric_limits<double>::infinity();
  }
  double largest = 0.0;
  for (typename TMeshA::PointIdentifier i = 0; i < a->GetPointData()->Size(); ++i)
  {
    largest = std::max(largest, std::abs(a->GetPointData()->ElementAt(i) - b->GetPointData()->ElementAt(i)));
  }
  return largest;
}

/** Reads fileName, expecting an ExceptionObject whose description names the file and contains
 * expectedText. */
bool
ReadFails(const std::string & fileName, const std::string & expectedText)
{
  try
  {
    ReadMesh<MeshType>(fileName);
  }
  catch (const itk::ExceptionObject & exception)
  {
    const std::string description = exception.GetDescription();
    std::cout << "Expected exception for " << fileName << ": " << description << std::endl;
    const bool namesFile = description.find(fileName) != std::string::npos;
    const bool namesProblem = description.find(expectedText) != std::string::npos;
    if (!namesFile || !namesProblem)
    {
      std::cerr << "The exception for " << fileName << " does not contain "
                << (namesFile ? "\"" + expectedText + "\"" : "the file name") << std::endl;
    }
    return namesFile && namesProblem;
  }
  std::cerr << "Reading " << fileName << " did not throw" << std::endl;
  return false;
}

void
WriteText(const std::string & fileName, const std::string & text)
{
  std::ofstream file(fileName, std::ios::binary);
  file << text;
}

std::size_t
CountRegisteredFactories(const char * className)
{
  std::size_t count = 0;
  for (itk::ObjectFactoryBase * factory : itk::ObjectFactoryBase::GetRegisteredFactories())
  {
    count += std::string(factory->GetNameOfClass()) == className ? 1 : 0;
  }
  return count;
}
} // namespace

int
itkVTKSurfaceMeshIOTest(int argc, char * argv[])
{
  if (argc != 2)
  {
    std::cerr << "Missing parameters." << std::endl;
    std::cerr << "Usage: " << itkNameOfTestExecutableMacro(argv) << " outputDirectory" << std::endl;
    return EXIT_FAILURE;
  }
  const std::string outputDirectory = std::string(argv[1]) + "/itkVTKSurfaceMeshIOTest_";
  int               testStatus = EXIT_SUCCESS;

  // The IO object itself.
  auto io = itk::VTKSurfaceMeshIO::New();
  ITK_EXERCISE_BASIC_OBJECT_METHODS(io, VTKSurfaceMeshIO, MeshIOBase);
  ITK_TEST_EXPECT_EQUAL(std::string(io->GetPointDataArrayName()), "PointData");
  io->SetPointDataArrayName("distance");
  ITK_TEST_SET_GET_VALUE(std::string("distance"), std::string(io->GetPointDataArrayName()));
  io->SetPointDataArrayName("PointData");
  ITK_TEST_EXPECT_TRUE(io->CanWriteFile("a.stl"));
  ITK_TEST_EXPECT_TRUE(io->CanWriteFile("a.PLY"));
  ITK_TEST_EXPECT_TRUE(io->CanWriteFile("dir.x/a.Vtp"));
  ITK_TEST_EXPECT_TRUE(!io->CanWriteFile("a.off"));
  ITK_TEST_EXPECT_TRUE(!io->CanWriteFile("a.stl.gz"));
  ITK_TEST_EXPECT_TRUE(!io->CanWriteFile("stl"));
  ITK_TEST_EXPECT_TRUE(!io->CanReadFile((outputDirectory + "missing.stl").c_str()));
  ITK_TEST_EXPECT_EQUAL(io->GetSupportedReadExtensions().size(), 6u);

  const MeshType::Pointer sphere = MakeSphere<MeshType>(3);
  std::cout << "Sphere: " << sphere->GetNumberOfPoints() << " points, " << sphere->GetNumberOfCells() << " cells"
            << std::endl;

  // Without the factory, MeshFileWriter knows no STL writer.
  if (CountRegisteredFactories("VTKSurfaceMeshIOFactory") == 0)
  {
    ITK_TRY_EXPECT_EXCEPTION(WriteMesh(sphere.GetPointer(), outputDirectory + "unregistered.stl"));
  }
  itk::VTKSurfaceMeshIOFactory::RegisterOneFactory();
  ITK_TEST_EXPECT_EQUAL(CountRegisteredFactories("VTKSurfaceMeshIOFactory"), 1u);

  // The three formats through MeshFileWriter and MeshFileReader.
  for (const std::string extension : { "stl", "PLY", "vtp" })
  {
    const std::string fileName = outputDirectory + "sphere." + extension;
    ITK_TRY_EXPECT_NO_EXCEPTION(WriteMesh(sphere.GetPointer(), fileName));
    MeshType::Pointer readMesh;
    ITK_TRY_EXPECT_NO_EXCEPTION(readMesh = ReadMesh<MeshType>(fileName));
    std::cout << extension << ": " << readMesh->GetNumberOfPoints() << " points, " << readMesh->GetNumberOfCells()
              << " cells, " << readMesh->GetPointData()->Size() << " point values" << std::endl;

    ITK_TEST_EXPECT_EQUAL(readMesh->GetNumberOfCells(), sphere->GetNumberOfCells());
    ITK_TEST_EXPECT_TRUE(AllTriangles(readMesh.GetPointer()));
    ITK_TEST_EXPECT_TRUE(itk::Math::FloatAlmostEqual(SurfaceArea(readMesh.GetPointer()),
                                                     SurfaceArea(sphere.GetPointer()),
                                                     4,
                                                     1e-9 * SurfaceArea(sphere.GetPointer())));
    if (extension == "stl")
    {
      // STL keeps float facet corners; vtkSTLReader merges them back into shared points.
      ITK_TEST_EXPECT_TRUE(DirectedPointDistance(readMesh.GetPointer(), sphere.GetPointer()) <= 1e-5);
      ITK_TEST_EXPECT_TRUE(DirectedPointDistance(sphere.GetPointer(), readMesh.GetPointer()) <= 1e-5);
      ITK_TEST_EXPECT_EQUAL(readMesh->GetNumberOfPoints(), sphere->GetNumberOfPoints());
      ITK_TEST_EXPECT_EQUAL(readMesh->GetPointData()->Size(), 0u);
    }
    else
    {
      // PLY (float) and VTP (double) keep the points and cells as they are; the sphere's
      // coordinates are floats, so both are exact.
      ITK_TEST_EXPECT_EQUAL(SamePointIdsDifference(readMesh.GetPointer(), sphere.GetPointer()), 0.0);
      ITK_TEST_EXPECT_TRUE(SameCells(readMesh.GetPointer(), sphere.GetPointer()));
    }
    if (extension == "vtp")
    {
      ITK_TEST_EXPECT_EQUAL(PointDataDifference(readMesh.GetPointer(), sphere.GetPointer()), 0.0);
    }
  }

  // Double coordinates survive VTP exactly, and PLY to float precision.
  {
    const DoubleMeshType::Pointer doubleSphere = MakeSphere<DoubleMeshType>(2);
    for (const std::string extension : { "vtp", "ply" })
    {
      const std::string fileName = outputDirectory + "doubleSphere." + extension;
      ITK_TRY_EXPECT_NO_EXCEPTION(WriteMesh(doubleSphere.GetPointer(), fileName));
      DoubleMeshType::Pointer readMesh;
      ITK_TRY_EXPECT_NO_EXCEPTION(readMesh = ReadMesh<DoubleMeshType>(fileName));
      const double difference = SamePointIdsDifference(readMesh.GetPointer(), doubleSphere.GetPointer());
      std::cout << extension << " of double coordinates: largest difference " << difference << std::endl;
      if (extension == "vtp")
      {
        ITK_TEST_EXPECT_EQUAL(difference, 0.0);
        ITK_TEST_EXPECT_EQUAL(PointDataDifference(readMesh.GetPointer(), doubleSphere.GetPointer()), 0.0);
      }
      else
      {
        ITK_TEST_EXPECT_TRUE(difference > 0.0 && difference <= 1e-5);
      }
      ITK_TEST_EXPECT_TRUE(SameCells(readMesh.GetPointer(), doubleSphere.GetPointer()));
    }
  }

  // The registration helper adds each of ITK's OFF/OBJ/VTK factories and ours only when none is
  // registered yet (ITK's automatic registration may have registered some, even twice).
  {
    const char * factoryNames[] = {
      "VTKSurfaceMeshIOFactory", "OFFMeshIOFactory", "OBJMeshIOFactory", "VTKPolyDataMeshIOFactory"
    };
    std::vector<std::size_t> countsBefore;
    for (const char * factoryName : factoryNames)
    {
      countsBefore.push_back(CountRegisteredFactories(factoryName));
    }
    itk::RegisterFFDShapeMatchingMeshIOFactories();
    itk::RegisterFFDShapeMatchingMeshIOFactories();
    for (std::size_t i = 0; i < countsBefore.size(); ++i)
    {
      const std::size_t countAfter = CountRegisteredFactories(factoryNames[i]);
      std::cout << factoryNames[i] << " registered " << countsBefore[i] << " time(s) before the helper, " << countAfter
                << " after" << std::endl;
      ITK_TEST_EXPECT_EQUAL(countAfter, std::max<std::size_t>(countsBefore[i], 1));
    }
  }

  // An OFF file written by ITK, read back, then converted to VTP.
  {
    const std::string offName = outputDirectory + "sphere.off";
    ITK_TRY_EXPECT_NO_EXCEPTION(WriteMesh(sphere.GetPointer(), offName));
    MeshType::Pointer offMesh;
    ITK_TRY_EXPECT_NO_EXCEPTION(offMesh = ReadMesh<MeshType>(offName));
    ITK_TEST_EXPECT_EQUAL(offMesh->GetNumberOfCells(), sphere->GetNumberOfCells());
    ITK_TEST_EXPECT_TRUE(SamePointIdsDifference(offMesh.GetPointer(), sphere.GetPointer()) <= 1e-5);
    ITK_TEST_EXPECT_TRUE(SameCells(offMesh.GetPointer(), sphere.GetPointer()));
    const std::string vtpName = outputDirectory + "fromOFF.vtp";
    ITK_TRY_EXPECT_NO_EXCEPTION(WriteMesh(offMesh.GetPointer(), vtpName));
    MeshType::Pointer vtpMesh;
    ITK_TRY_EXPECT_NO_EXCEPTION(vtpMesh = ReadMesh<MeshType>(vtpName));
    ITK_TEST_EXPECT_EQUAL(SamePointIdsDifference(vtpMesh.GetPointer(), offMesh.GetPointer()), 0.0);
    ITK_TEST_EXPECT_TRUE(SameCells(vtpMesh.GetPointer(), offMesh.GetPointer()));
  }

  // An ASCII PLY with two unit quadrilaterals and a convex pentagon (area 4): read as 2 + 2 + 3
  // triangles covering the same area.
  {
    const std::string fileName = outputDirectory + "quads.ply";
    WriteText(fileName,
              "ply\nformat ascii 1.0\ncomment two unit quads and a pentagon\n"
              "element vertex 11\nproperty float x\nproperty float y\nproperty float z\n"
              "element face 3\nproperty list uchar int vertex_indices\nend_header\n"
              "0 0 0\n1 0 0\n2 0 0\n0 1 0\n1 1 0\n2 1 0\n"
              "0 0 5\n2 0 5\n2.5 1 5\n1 2 5\n-0.5 1 5\n"
              "4 0 1 4 3\n4 1 2 5 4\n5 6 7 8 9 10\n");
    MeshType::Pointer quads;
    ITK_TRY_EXPECT_NO_EXCEPTION(quads = ReadMesh<MeshType>(fileName));
    ITK_TEST_EXPECT_EQUAL(quads->GetNumberOfPoints(), 11u);
    ITK_TEST_EXPECT_EQUAL(quads->GetNumberOfCells(), 7u);
    ITK_TEST_EXPECT_TRUE(AllTriangles(quads.GetPointer()));
    ITK_TEST_EXPECT_TRUE(itk::Math::FloatAlmostEqual(SurfaceArea(quads.GetPointer()), 6.0, 4, 1e-12));
  }

  // Mixed cells through VTP: quads are triangulated, lines and vertices dropped and counted.
  {
    auto mixed = MeshType::New();
    for (unsigned int i = 0; i < 6; ++i)
    {
      MeshType::PointType point;
      point[0] = i % 3;
      point[1] = i / 3;
      point[2] = 0.5;
      mixed->SetPoint(i, point);
    }
    MeshType::CellAutoPointer cell;
    cell.TakeOwnership(new itk::TriangleCell<MeshType::CellType>);
    cell->SetPointId(0, 0);
    cell->SetPointId(1, 1);
    cell->SetPointId(2, 4);
    mixed->SetCell(0, cell);
    cell.TakeOwnership(new itk::QuadrilateralCell<MeshType::CellType>);
    for (unsigned int k = 0; k < 4; ++k)
    {
      const unsigned int ids[4] = { 1, 2, 5, 4 };
      cell->SetPointId(k, ids[k]);
    }
    mixed->SetCell(1, cell);
    cell.TakeOwnership(new itk::LineCell<MeshType::CellType>);
    cell->SetPointId(0, 0);
    cell->SetPointId(1, 3);
    mixed->SetCell(2, cell);
    cell.TakeOwnership(new itk::VertexCell<MeshType::CellType>);
    cell->SetPointId(0, 3);
    mixed->SetCell(3, cell);
    const std::string fileName = outputDirectory + "mixed.vtp";
    ITK_TRY_EXPECT_NO_EXCEPTION(WriteMesh(mixed.GetPointer(), fileName));

    auto mixedIO = itk::VTKSurfaceMeshIO::New();
    auto reader = itk::MeshFileReader<MeshType>::New();
    reader->SetMeshIO(mixedIO);
    reader->SetFileName(fileName);
    ITK_TRY_EXPECT_NO_EXCEPTION(reader->Update());
    ITK_TEST_EXPECT_EQUAL(reader->GetOutput()->GetNumberOfCells(), 3u);
    ITK_TEST_EXPECT_TRUE(AllTriangles(reader->GetOutput()));
    ITK_TEST_EXPECT_EQUAL(mixedIO->GetNumberOfDroppedCells(), 2u);
    ITK_TEST_EXPECT_TRUE(itk::Math::FloatAlmostEqual(SurfaceArea(reader->GetOutput()), 1.5, 4, 1e-12));

    // STL cannot hold the line and the vertex: they are left out, the quad is split.
    const std::string stlName = outputDirectory + "mixed.stl";
    ITK_TRY_EXPECT_NO_EXCEPTION(WriteMesh(mixed.GetPointer(), stlName));
    MeshType::Pointer stlMesh;
    ITK_TRY_EXPECT_NO_EXCEPTION(stlMesh = ReadMesh<MeshType>(stlName));
    ITK_TEST_EXPECT_EQUAL(stlMesh->GetNumberOfCells(), 3u);

    // A volume cell cannot be written to a surface file.
    cell.TakeOwnership(new itk::TetrahedronCell<MeshType::CellType>);
    for (unsigned int k = 0; k < 4; ++k)
    {
      cell->SetPointId(k, k);
    }
    mixed->SetCell(4, cell);
    ITK_TRY_EXPECT_EXCEPTION(WriteMesh(mixed.GetPointer(), outputDirectory + "tetrahedron.vtp"));
  }

  // Writing into a folder that does not exist.
  ITK_TRY_EXPECT_EXCEPTION(WriteMesh(sphere.GetPointer(), outputDirectory + "no/such/folder/sphere.stl"));
  ITK_TRY_EXPECT_EXCEPTION(WriteMesh(sphere.GetPointer(), outputDirectory + "no/such/folder/sphere.vtp"));

  // Bad inputs: each read ends in an exception naming the file and the problem.
  {
    const std::string missing = outputDirectory + "missing.stl";
    ITK_TRY_EXPECT_EXCEPTION(ReadMesh<MeshType>(missing));
    ITK_TEST_EXPECT_TRUE(ReadFails(missing, "exist"));

    // A binary STL cut short.
    std::ifstream     original(outputDirectory + "sphere.stl", std::ios::binary);
    std::vector<char> bytes((std::istreambuf_iterator<char>(original)), std::istreambuf_iterator<char>());
    ITK_TEST_EXPECT_EQUAL(bytes.size(), 84u + 50u * sphere->GetNumberOfCells());
    const std::string truncated = outputDirectory + "truncated.stl";
    WriteText(truncated, std::string(bytes.begin(), bytes.end() - 70));
    ITK_TRY_EXPECT_EXCEPTION(ReadMesh<MeshType>(truncated));
    ITK_TEST_EXPECT_TRUE(ReadFails(truncated, "truncated binary STL"));

    // An STL of a few bytes, and an ASCII STL with a broken vertex line.
    const std::string tiny = outputDirectory + "tiny.stl";
    WriteText(tiny, std::string("\x01\x02\x03", 3));
    ITK_TEST_EXPECT_TRUE(ReadFails(tiny, "84-byte header"));
    const std::string badASCII = outputDirectory + "badASCII.stl";
    WriteText(badASCII, "solid x\n facet normal 0 0 1\n  outer loop\n   vertex 0 0 0\n   vertex 1 0\n");
    ITK_TEST_EXPECT_TRUE(ReadFails(badASCII, "line 5"));

    // Binary garbage named .ply, without and with the PLY signature.
    std::mt19937                       generator(20261122);
    std::uniform_int_distribution<int> byteDistribution(0, 255);
    std::string                        garbage(4096, '\0');
    for (char & byte : garbage)
    {
      byte = static_cast<char>(byteDistribution(generator));
    }
    const std::string garbagePLY = outputDirectory + "garbage.ply";
    WriteText(garbagePLY, garbage);
    ITK_TRY_EXPECT_EXCEPTION(ReadMesh<MeshType>(garbagePLY));
    ITK_TEST_EXPECT_TRUE(ReadFails(garbagePLY, "not a PLY file"));
    const std::string signedGarbagePLY = outputDirectory + "signedGarbage.ply";
    WriteText(signedGarbagePLY, "ply\n" + garbage);
    ITK_TEST_EXPECT_TRUE(ReadFails(signedGarbagePLY, "PLY file"));

    // PLY files whose data ends before the header's counts, whose face refers to a missing
    // vertex, or whose faces have no vertex_indices (VTK's own PLY code would crash on them).
    const std::string plyHeader = "ply\nformat binary_little_endian 1.0\nelement vertex 100\nproperty float x\n"
                                  "property float y\nproperty float z\nelement face 10\n"
                                  "property list uchar int vertex_indices\nend_header\n";
    const std::string truncatedPLY = outputDirectory + "truncated.ply";
    WriteText(truncatedPLY, plyHeader + std::string(120, '\0'));
    ITK_TEST_EXPECT_TRUE(ReadFails(truncatedPLY, "binary PLY data ends or is malformed in vertex 10 of 100"));
    const std::string truncatedASCIIPLY = outputDirectory + "truncatedASCII.ply";
    WriteText(truncatedASCIIPLY,
              "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
              "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1\n");
    ITK_TEST_EXPECT_TRUE(ReadFails(truncatedASCIIPLY, "ASCII PLY data ends or is malformed in vertex 2 of 3"));
    const std::string badIndexPLY = outputDirectory + "badIndex.ply";
    WriteText(badIndexPLY,
              "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
              "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n");
    ITK_TEST_EXPECT_TRUE(ReadFails(badIndexPLY, "PLY face 0 refers to vertex 7 of 3"));
    const std::string noIndicesPLY = outputDirectory + "noIndices.ply";
    WriteText(noIndicesPLY,
              "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
              "element face 1\nproperty list uchar int vertex_indixes\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
    ITK_TEST_EXPECT_TRUE(ReadFails(noIndicesPLY, "no list property vertex_indices"));

    // Headers VTK's PLY reader reads otherwise than a plain reading would (it then reads freed memory, or the data
    // as other elements): a blank line ends VTK's header, a carriage return separates words like a space, readers
    // look properties up by name. The common misspelling vertex_index is read as vertex_indices, as VTK does.
    const std::string xyz = "property float x\nproperty float y\nproperty float z\n";
    auto              triangle = [](const std::string & header, const std::string & faceProperty) {
      return "ply\nformat ascii 1.0\nelement vertex 3\n" + header + "element face 1\nproperty list uchar int " +
             faceProperty + "\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
    };
    const std::string blankLinePLY = outputDirectory + "blankHeaderLine.ply";
    WriteText(blankLinePLY, triangle("property float x\n\nproperty float y\nproperty float z\n", "vertex_indices"));
    ITK_TEST_EXPECT_TRUE(ReadFails(blankLinePLY, "PLY header line 5: a blank line within the header"));
    const std::string carriageReturnPLY = outputDirectory + "carriageReturnElement.ply";
    WriteText(carriageReturnPLY,
              triangle("property float x\n\relement extra 0\nproperty float y\nproperty float z\n", "vertex_indices"));
    ITK_TEST_EXPECT_TRUE(ReadFails(carriageReturnPLY, "the PLY vertex element has no property y"));
    const std::string twiceNamedPLY = outputDirectory + "twiceNamedProperty.ply";
    WriteText(twiceNamedPLY, triangle("property float x\n" + xyz, "vertex_indices"));
    ITK_TEST_EXPECT_TRUE(
      ReadFails(twiceNamedPLY, "PLY header line 5: a second property named \"x\" in element vertex"));
    const std::string shortFormatPLY = outputDirectory + "shortFormat.ply";
    std::string       shortFormat = triangle(xyz, "vertex_indices");
    WriteText(shortFormatPLY, shortFormat.replace(shortFormat.find(" 1.0"), 4, ""));
    ITK_TEST_EXPECT_TRUE(ReadFails(shortFormatPLY, "a format line needs the format and the version"));
    const std::string misspelledPLY = outputDirectory + "vertexIndex.ply";
    WriteText(misspelledPLY, triangle(xyz, "vertex_index"));
    MeshType::Pointer misspelled;
    ITK_TRY_EXPECT_NO_EXCEPTION(misspelled = ReadMesh<MeshType>(misspelledPLY));
    ITK_TEST_EXPECT_EQUAL(misspelled->GetNumberOfPoints(), 3u);
    ITK_TEST_EXPECT_EQUAL(misspelled->GetNumberOfCells(), 1u);

    // VTK 9.1's PLY reader reads the vertex and face elements only and skips no other element's data, and reads a
    // list only where it asked for one (it sizes any other by a type it never set): such files are refused, while
    // an element after the faces and the face texture coordinates it reads are accepted.
    const std::string vertexList = "property float x\nproperty float y\nproperty float z\nproperty list uchar int n\n";
    const std::string vertexListPLY = outputDirectory + "vertexList.ply";
    WriteText(vertexListPLY, triangle(vertexList, "vertex_indices"));
    ITK_TEST_EXPECT_TRUE(ReadFails(vertexListPLY, "the PLY vertex element has the list property n, which VTK"));
    auto withFaceExtra = [&triangle, &xyz](const std::string & extraProperty, const std::string & extraValues) {
      std::string text = triangle(xyz, "vertex_indices\n" + extraProperty);
      return text.replace(text.rfind("3 0 1 2"), 7, "3 0 1 2 " + extraValues);
    };
    const std::string faceListPLY = outputDirectory + "faceList.ply";
    WriteText(faceListPLY, withFaceExtra("property list uchar float extra", "2 0.5 0.25"));
    ITK_TEST_EXPECT_TRUE(ReadFails(faceListPLY, "the PLY face element has the list property extra, which VTK"));
    const std::string scalarTexturePLY = outputDirectory + "scalarTexcoord.ply";
    WriteText(scalarTexturePLY, withFaceExtra("property float texcoord", "0.5"));
    ITK_TEST_EXPECT_TRUE(ReadFails(scalarTexturePLY, "the PLY face property texcoord is not a list"));
    const std::string faceTexturePLY = outputDirectory + "faceTexcoord.ply";
    WriteText(faceTexturePLY, withFaceExtra("property list uchar float texcoord", "6 0 0 1 0 0 1"));
    ITK_TRY_EXPECT_NO_EXCEPTION(ReadMesh<MeshType>(faceTexturePLY));
    const std::string elementBeforePLY = outputDirectory + "elementBeforeVertices.ply";
    WriteText(
      elementBeforePLY,
      "ply\nformat ascii 1.0\nelement material 1\nproperty float shine\nelement vertex 3\n" + xyz +
        "element face 1\nproperty list uchar int vertex_indices\nend_header\n0.5\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
    ITK_TEST_EXPECT_TRUE(ReadFails(elementBeforePLY, "the PLY element material holds data before the vertex"));
    const std::string elementAfterPLY = outputDirectory + "elementAfterFaces.ply";
    WriteText(elementAfterPLY,
              "ply\nformat ascii 1.0\nelement vertex 3\n" + xyz +
                "element face 1\nproperty list uchar int vertex_indices\nelement edge 1\nproperty int a\n"
                "property int b\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n0 1\n");
    MeshType::Pointer afterFaces;
    ITK_TRY_EXPECT_NO_EXCEPTION(afterFaces = ReadMesh<MeshType>(elementAfterPLY));
    ITK_TEST_EXPECT_EQUAL(afterFaces->GetNumberOfCells(), 1u);

    // A binary VTP cut in its appended data, and a VTP whose polygon refers to a missing point.
    std::ifstream     vtpFile(outputDirectory + "sphere.vtp", std::ios::binary);
    std::vector<char> vtpBytes((std::istreambuf_iterator<char>(vtpFile)), std::istreambuf_iterator<char>());
    const std::string cutBinaryVTP = outputDirectory + "cutBinary.vtp";
    WriteText(cutBinaryVTP, std::string(vtpBytes.begin(), vtpBytes.begin() + vtpBytes.size() * 6 / 10));
    ITK_TEST_EXPECT_TRUE(ReadFails(cutBinaryVTP, "VTP file"));
    const std::string badIndexVTP = outputDirectory + "badIndex.vtp";
    WriteText(badIndexVTP,
              "<?xml version=\"1.0\"?>\n<VTKFile type=\"PolyData\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
              "<PolyData><Piece NumberOfPoints=\"3\" NumberOfVerts=\"0\" NumberOfLines=\"0\" NumberOfStrips=\"0\" "
              "NumberOfPolys=\"1\"><Points><DataArray type=\"Float32\" NumberOfComponents=\"3\" format=\"ascii\">"
              "0 0 0 1 0 0 0 1 0</DataArray></Points><Polys>"
              "<DataArray type=\"Int32\" Name=\"connectivity\" format=\"ascii\">0 1 7</DataArray>"
              "<DataArray type=\"Int32\" Name=\"offsets\" format=\"ascii\">3</DataArray></Polys>"
              "</Piece></PolyData></VTKFile>\n");
    ITK_TEST_EXPECT_TRUE(ReadFails(badIndexVTP, "a cell refers to point 7 of 3"));

    // An empty VTP file, a cut XML file, and a valid VTP without points.
    const std::string emptyVTP = outputDirectory + "empty.vtp";
    WriteText(emptyVTP, "");
    ITK_TRY_EXPECT_EXCEPTION(ReadMesh<MeshType>(emptyVTP));
    ITK_TEST_EXPECT_TRUE(ReadFails(emptyVTP, "XML"));
    const std::string cutVTP = outputDirectory + "cut.vtp";
    WriteText(cutVTP, "<?xml version=\"1.0\"?>\n<VTKFile type=\"PolyData\" version=\"1.0\">\n<PolyData><Piece");
    ITK_TEST_EXPECT_TRUE(ReadFails(cutVTP, "XML"));
    const std::string noPointsVTP = outputDirectory + "noPoints.vtp";
    WriteText(noPointsVTP,
              "<?xml version=\"1.0\"?>\n<VTKFile type=\"PolyData\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
              "<PolyData><Piece NumberOfPoints=\"0\" NumberOfVerts=\"0\" NumberOfLines=\"0\" NumberOfStrips=\"0\" "
              "NumberOfPolys=\"0\"><Points><DataArray type=\"Float32\" NumberOfComponents=\"3\" format=\"ascii\">"
              "</DataArray></Points></Piece></PolyData></VTKFile>\n");
    ITK_TEST_EXPECT_TRUE(ReadFails(noPointsVTP, "no points"));

    // Points whose array does not have 3 components are refused before VTK reads the arrays (VTK 9.1 leaks them),
    // wherever the element stands: behind a comment that looks like points, in a second piece, without the
    // attribute (VTK takes 1), or with a value the parser resolves from a character reference.
    auto cubeVTP =
      [](const std::string & beforePiece, const std::string & firstComponents, const std::string & secondPiece) {
        const std::string piece =
          "<Piece NumberOfPoints=\"3\" NumberOfVerts=\"0\" NumberOfLines=\"0\" NumberOfStrips=\"0\" "
          "NumberOfPolys=\"1\"><Points><DataArray type=\"Float32\" COMPONENTS format=\"ascii\">"
          "0 0 0 1 0 0 0 1 0</DataArray></Points><Polys>"
          "<DataArray type=\"Int32\" Name=\"connectivity\" format=\"ascii\">0 1 2</DataArray>"
          "<DataArray type=\"Int32\" Name=\"offsets\" format=\"ascii\">3</DataArray></Polys></Piece>";
        auto withComponents = [&piece](const std::string & components) {
          std::string text = piece;
          return text.replace(text.find("COMPONENTS"), 10, components);
        };
        return "<?xml version=\"1.0\"?>\n<VTKFile type=\"PolyData\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
               "<PolyData>" +
               beforePiece + withComponents(firstComponents) +
               (secondPiece.empty() ? std::string() : withComponents(secondPiece)) + "</PolyData></VTKFile>\n";
      };
    const std::string three = "NumberOfComponents=\"3\"";
    const std::string one = "NumberOfComponents=\"1\"";
    const std::string hiddenPoints = "<!-- <Points><DataArray " + three + "> -->";
    const std::string commentVTP = outputDirectory + "pointsAfterComment.vtp";
    WriteText(commentVTP, cubeVTP(hiddenPoints, one, ""));
    ITK_TEST_EXPECT_TRUE(ReadFails(commentVTP, "the points' DataArray has NumberOfComponents=\"1\", not 3"));
    const std::string secondPieceVTP = outputDirectory + "secondPieceOneComponent.vtp";
    WriteText(secondPieceVTP, cubeVTP("", three, one));
    ITK_TEST_EXPECT_TRUE(ReadFails(secondPieceVTP, "the points' DataArray has NumberOfComponents=\"1\", not 3"));
    const std::string noAttributeVTP = outputDirectory + "noComponentsAttribute.vtp";
    WriteText(noAttributeVTP, cubeVTP("", "", ""));
    ITK_TEST_EXPECT_TRUE(ReadFails(noAttributeVTP, "the points' DataArray has no NumberOfComponents"));
    const std::string referenceVTP = outputDirectory + "componentsByReference.vtp";
    WriteText(referenceVTP, cubeVTP("", "NumberOfComponents=\"&#50;\"", ""));
    ITK_TEST_EXPECT_TRUE(ReadFails(referenceVTP, "the points' DataArray has NumberOfComponents=\"2\", not 3"));
    // The same comment before valid points does not stop a file from being read, nor does a second valid piece.
    const std::string validCommentVTP = outputDirectory + "validAfterComment.vtp";
    WriteText(validCommentVTP, cubeVTP("<!-- <Points><DataArray " + one + "> -->", three, three));
    const auto commentedMesh = ReadMesh<MeshType>(validCommentVTP);
    ITK_TEST_EXPECT_EQUAL(commentedMesh->GetNumberOfPoints(), 6);
    ITK_TEST_EXPECT_EQUAL(commentedMesh->GetNumberOfCells(), 2);

    // The same through the IO object directly.
    io->SetFileName(truncated);
    ITK_TRY_EXPECT_EXCEPTION(io->ReadMeshInformation());
  }

  std::cout << "Test finished." << std::endl;
  return testStatus;
}
