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
#include "itkStrictTextMeshIO.h"
#include "itkStrictTextMeshIOFactory.h"
#include "itkRegisterFFDShapeMatchingMeshIOFactories.h"

#include "itkMesh.h"
#include "itkMeshFileReader.h"
#include "itkMeshFileWriter.h"
#include "itkMeshIOFactory.h"
#include "itkOBJMeshIO.h"
#include "itkOFFMeshIO.h"
#include "itkRegularSphereMeshSource.h"
#include "itkTestingMacros.h"
#include "itkVTKPolyDataMeshIO.h"

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cstdio>
#include <cmath>
#include <fstream>
#include <iterator>
#include <random>
#include <sstream>
#include <string>
#include <vector>

// Reads damaged OFF, OBJ and legacy VTK files (the fixtures in Input/BadInput and files made
// here) and checks the exact message of each; checks that good files read into the same meshes
// as with ITK's own readers; truncates and corrupts good files at every byte and checks that each
// read ends in a mesh or an ExceptionObject, within a bounded time.
namespace
{
using MeshType = itk::Mesh<double, 3>; // as the module's programs read meshes
using ReaderType = itk::MeshFileReader<MeshType>;

void
WriteText(const std::string & fileName, const std::string & text)
{
  std::ofstream file(fileName, std::ios::binary);
  file << text;
}

std::string
ReadText(const std::string & fileName)
{
  std::ifstream file(fileName, std::ios::binary);
  return { std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>() };
}

/** Reads fileName with the given IO, or through the factories when meshIO is null. */
MeshType::Pointer
ReadMesh(const std::string & fileName, itk::MeshIOBase * meshIO)
{
  auto reader = ReaderType::New();
  reader->SetFileName(fileName);
  if (meshIO != nullptr)
  {
    reader->SetMeshIO(meshIO);
  }
  reader->Update();
  MeshType::Pointer mesh = reader->GetOutput();
  mesh->DisconnectPipeline();
  return mesh;
}

/** The description of the exception reading fileName throws, or "no exception". */
std::string
ReadError(const std::string & fileName, itk::MeshIOBase * meshIO = nullptr)
{
  try
  {
    ReadMesh(fileName, meshIO);
  }
  catch (const itk::ExceptionObject & error)
  {
    return error.GetDescription();
  }
  return "no exception";
}

/** True when both meshes have the same points (exactly), point data and cells (type and ids). */
bool
SameMesh(const MeshType * a, const MeshType * b)
{
  if (a->GetNumberOfPoints() != b->GetNumberOfPoints() || a->GetNumberOfCells() != b->GetNumberOfCells() ||
      a->GetNumberOfPoints() == 0)
  {
    std::cout << "  sizes differ: " << a->GetNumberOfPoints() << "/" << a->GetNumberOfCells() << " points/cells vs "
              << b->GetNumberOfPoints() << "/" << b->GetNumberOfCells() << std::endl;
    return false;
  }
  for (MeshType::PointIdentifier i = 0; i < a->GetNumberOfPoints(); ++i)
  {
    if (a->GetPoint(i) != b->GetPoint(i))
    {
      std::cout << "  point " << i << " differs: " << a->GetPoint(i) << " vs " << b->GetPoint(i) << std::endl;
      return false;
    }
  }
  const auto *      aData = a->GetPointData();
  const auto *      bData = b->GetPointData();
  const std::size_t aSize = aData == nullptr ? 0 : aData->Size();
  const std::size_t bSize = bData == nullptr ? 0 : bData->Size();
  if (aSize != bSize)
  {
    std::cout << "  point data sizes differ: " << aSize << " vs " << bSize << std::endl;
    return false;
  }
  for (std::size_t i = 0; i < aSize; ++i)
  {
    if (aData->ElementAt(i) != bData->ElementAt(i))
    {
      std::cout << "  point data " << i << " differs" << std::endl;
      return false;
    }
  }
  for (MeshType::CellIdentifier i = 0; i < a->GetNumberOfCells(); ++i)
  {
    MeshType::CellAutoPointer aCell;
    MeshType::CellAutoPointer bCell;
    a->GetCell(i, aCell);
    b->GetCell(i, bCell);
    if (aCell->GetType() != bCell->GetType() || aCell->GetNumberOfPoints() != bCell->GetNumberOfPoints() ||
        !std::equal(aCell->PointIdsBegin(), aCell->PointIdsEnd(), bCell->PointIdsBegin()))
    {
      std::cout << "  cell " << i << " differs" << std::endl;
      return false;
    }
  }
  return true;
}

MeshType::Pointer
MakeSphere(bool withPointData)
{
  using SourceType = itk::RegularSphereMeshSource<MeshType>;
  auto                   source = SourceType::New();
  SourceType::VectorType scale;
  scale[0] = 10.0;
  scale[1] = 7.3;
  scale[2] = 5.1;
  SourceType::PointType center;
  center[0] = 1.0 / 3.0;
  center[1] = -2.25;
  center[2] = 0.1;
  source->SetScale(scale);
  source->SetCenter(center);
  source->SetResolution(1);
  source->Update();
  MeshType::Pointer mesh = source->GetOutput();
  mesh->DisconnectPipeline();
  if (withPointData)
  {
    for (MeshType::PointIdentifier i = 0; i < mesh->GetNumberOfPoints(); ++i)
    {
      mesh->SetPointData(i, 0.25 * static_cast<double>(i) - 1.5);
    }
  }
  return mesh;
}

void
WriteMesh(const MeshType * mesh, const std::string & fileName, itk::MeshIOBase * meshIO, bool binary)
{
  auto writer = itk::MeshFileWriter<MeshType>::New();
  writer->SetInput(mesh);
  writer->SetFileName(fileName);
  writer->SetMeshIO(meshIO);
  if (binary)
  {
    writer->SetFileTypeAsBINARY();
  }
  writer->Update();
}

/** One damaged file and the exact message reading it must give (after the file name). */
struct BadCase
{
  std::string File;
  std::string Format;
  std::string Message;
};

int
CheckBadCase(const std::string & fileName, const std::string & format, const std::string & message)
{
  const std::string expected = "Cannot read " + format + " file \"" + fileName + "\": " + message;
  // ITK prefixes the description with "ITK ERROR: StrictTextMeshIO(address): ".
  std::string       actual = ReadError(fileName);
  const std::string prefix = "ITK ERROR: StrictTextMeshIO(";
  if (actual.compare(0, prefix.size(), prefix) == 0 && actual.find("): ") != std::string::npos)
  {
    actual = actual.substr(actual.find("): ") + 3);
  }
  std::cout << "  " << actual << std::endl;
  if (actual != expected)
  {
    std::cerr << "Wrong message for " << fileName << "\n  expected: " << expected << "\n  actual:   " << actual
              << std::endl;
    return EXIT_FAILURE;
  }
  return EXIT_SUCCESS;
}

/** Reads every truncation and some corruptions of a good file: each ends in a mesh or an
 * ExceptionObject. When mustMatchWhenRead, a truncation that reads must give the original mesh.
 * Returns the number of failures. */
int
FuzzFile(const std::string &  goodFile,
         const std::string &  scratchFile,
         const MeshType *     original,
         bool                 mustMatchWhenRead,
         std::mt19937 &       generator,
         unsigned int         numberOfCorruptions,
         itk::SizeValueType & numberOfReads,
         itk::SizeValueType & numberOfAccepted)
{
  const std::string text = ReadText(goodFile);
  int               failures = 0;
  auto              tryRead = [&](const std::string & content, bool isTruncation, std::size_t where) {
    // A new file each time: overwriting one in place makes the file system flush it on every close.
    std::remove(scratchFile.c_str());
    WriteText(scratchFile, content);
    ++numberOfReads;
    try
    {
      MeshType::Pointer mesh = ReadMesh(scratchFile, itk::StrictTextMeshIO::New());
      ++numberOfAccepted;
      // Cutting the file within its last number leaves a valid file: the only truncation allowed
      // to read into another mesh.
      std::string removed = text.substr(std::min(where, text.size()));
      while (!removed.empty() && std::isspace(static_cast<unsigned char>(removed.back())))
      {
        removed.pop_back();
      }
      const bool withinLastToken = !removed.empty() && std::none_of(removed.begin(), removed.end(), [](char c) {
        return std::isspace(static_cast<unsigned char>(c));
      }) && where > 0 && !std::isspace(static_cast<unsigned char>(text[where - 1]));
      if (isTruncation && mustMatchWhenRead && !withinLastToken && !SameMesh(mesh.GetPointer(), original))
      {
        std::cerr << goodFile << " truncated to " << where << " bytes reads into another mesh" << std::endl;
        ++failures;
      }
    }
    catch (const itk::ExceptionObject & error)
    {
      const std::string description = error.GetDescription();
      if (description.find("): Cannot read ") == std::string::npos ||
          description.find(scratchFile) == std::string::npos)
      {
        std::cerr << "Unexpected message at " << where << ": " << description << std::endl;
        ++failures;
      }
    }
    catch (const std::exception & error)
    {
      std::cerr << goodFile << " altered at " << where << ": a std::exception escaped: " << error.what() << std::endl;
      ++failures;
    }
  };
  for (std::size_t size = 0; size < text.size(); ++size)
  {
    tryRead(text.substr(0, size), true, size);
  }
  const char                                 replacements[] = { 'x', '9', '-', ' ', '\n', '.', 'e', '\0', '\xff', '/' };
  std::uniform_int_distribution<std::size_t> position(0, text.size() - 1);
  std::uniform_int_distribution<std::size_t> replacement(0, sizeof(replacements) - 1);
  std::uniform_int_distribution<int>         anyByte(0, 255);
  for (unsigned int i = 0; i < numberOfCorruptions; ++i)
  {
    std::string       corrupted = text;
    const std::size_t where = position(generator);
    corrupted[where] = (i % 2 == 0) ? replacements[replacement(generator)] : static_cast<char>(anyByte(generator));
    tryRead(corrupted, false, where);
  }
  return failures;
}
} // namespace

int
itkStrictTextMeshIOTest(int argc, char * argv[])
{
  if (argc != 3)
  {
    std::cerr << "Missing parameters." << std::endl;
    std::cerr << "Usage: " << itkNameOfTestExecutableMacro(argv) << " inputDirectory outputDirectory" << std::endl;
    return EXIT_FAILURE;
  }
  const std::string inputDirectory = std::string(argv[1]) + "/";
  const std::string badDirectory = inputDirectory + "BadInput/";
  const std::string outputDirectory = std::string(argv[2]) + "/";
  int               testStatus = EXIT_SUCCESS;

  auto meshIO = itk::StrictTextMeshIO::New();
  ITK_EXERCISE_BASIC_OBJECT_METHODS(meshIO, StrictTextMeshIO, MeshIOBase);
  ITK_TEST_EXPECT_TRUE(meshIO->CanReadFile((inputDirectory + "cube.off").c_str()));
  ITK_TEST_EXPECT_TRUE(!meshIO->CanReadFile((inputDirectory + "missing.off").c_str()));
  ITK_TEST_EXPECT_TRUE(!meshIO->CanReadFile((inputDirectory + "BadWrapping").c_str()));
  ITK_TEST_EXPECT_TRUE(!meshIO->CanWriteFile((outputDirectory + "x.off").c_str()));
  ITK_TRY_EXPECT_EXCEPTION(meshIO->Write());

  // The registration helper puts the strict reader ahead of ITK's readers; ITK's IOs still write.
  itk::RegisterFFDShapeMatchingMeshIOFactories();
  itk::RegisterFFDShapeMatchingMeshIOFactories();
  {
    std::size_t numberOfStrictFactories = 0;
    for (itk::ObjectFactoryBase * factory : itk::ObjectFactoryBase::GetRegisteredFactories())
    {
      numberOfStrictFactories += dynamic_cast<itk::StrictTextMeshIOFactory *>(factory) != nullptr ? 1 : 0;
    }
    ITK_TEST_EXPECT_EQUAL(numberOfStrictFactories, 1);
    const MeshType::Pointer sphere = MakeSphere(false);
    for (const char * extension : { "off", "obj", "vtk" })
    {
      const std::string        fileName = outputDirectory + "StrictTextMeshIOTestFactory." + extension;
      itk::MeshIOBase::Pointer writeIO =
        itk::MeshIOFactory::CreateMeshIO(fileName.c_str(), itk::MeshIOFactory::IOFileModeEnum::WriteMode);
      ITK_TEST_EXPECT_TRUE(writeIO.IsNotNull() &&
                           dynamic_cast<itk::StrictTextMeshIO *>(writeIO.GetPointer()) == nullptr);
      ITK_TRY_EXPECT_NO_EXCEPTION(WriteMesh(sphere.GetPointer(), fileName, writeIO, false));
      itk::MeshIOBase::Pointer readIO =
        itk::MeshIOFactory::CreateMeshIO(fileName.c_str(), itk::MeshIOFactory::IOFileModeEnum::ReadMode);
      std::cout << extension << " files: read by " << (readIO ? readIO->GetNameOfClass() : "nothing") << ", written by "
                << writeIO->GetNameOfClass() << std::endl;
      ITK_TEST_EXPECT_TRUE(readIO.IsNotNull() && dynamic_cast<itk::StrictTextMeshIO *>(readIO.GetPointer()) != nullptr);
      auto reader = ReaderType::New();
      reader->SetFileName(fileName);
      ITK_TRY_EXPECT_NO_EXCEPTION(reader->Update());
      ITK_TEST_EXPECT_TRUE(dynamic_cast<itk::StrictTextMeshIO *>(reader->GetModifiableMeshIO()) != nullptr);
    }
  }

  // The fixtures: each damaged file gives its message, naming the file, the line and the problem.
  std::cout << "Damaged fixtures:" << std::endl;
  const std::vector<BadCase> badCases = {
    { "truncated.off", "OFF", "line 12: the file ends within face 1 (1 of its 3 vertex indices)" },
    { "malformed.off", "OFF", "line 5: expected 3 coordinates of vertex 2, found \"ten\"" },
    { "bad-index.off", "OFF", "line 22: face 11 refers to vertex 99, the file has 8" },
    { "garbage.off",
      "OFF",
      "line 1: expected the keyword \"OFF\", found \"\\xA5M\\xCA\\x18%0\\xBB\\x1Dm\\x13,\\xDE\\xD6\"" },
    { "empty-file.off", "OFF", "the file is empty" },
    { "infinite.off", "OFF", "line 4: vertex 1 has a non-finite coordinate (\"inf\")" },
    { "malformed.obj", "OBJ", "line 2: expected 3 coordinates of vertex 2, found \"zero\"" },
    { "bad-index.obj", "OBJ", "line 9: face 1 refers to vertex 20, the file has 8" },
    { "truncated.vtk", "legacy VTK", "line 6: the file ends after 2 of 8 points" },
    { "nan-text.vtk", "legacy VTK", "line 8: point 2 has a non-finite coordinate" },
  };
  for (const BadCase & badCase : badCases)
  {
    if (CheckBadCase(badDirectory + badCase.File, badCase.Format, badCase.Message) != EXIT_SUCCESS)
    {
      testStatus = EXIT_FAILURE;
    }
  }

  // Fixtures with a documented graceful result: read as ITK's readers read them.
  {
    std::cout << "Graceful fixtures:" << std::endl;
    MeshType::Pointer strict;
    MeshType::Pointer itkMesh;
    // Quadrilaterals: polygon cells, as OFFMeshIO gives.
    ITK_TRY_EXPECT_NO_EXCEPTION(strict = ReadMesh(badDirectory + "quads.off", nullptr));
    ITK_TRY_EXPECT_NO_EXCEPTION(itkMesh = ReadMesh(badDirectory + "quads.off", itk::OFFMeshIO::New()));
    ITK_TEST_EXPECT_TRUE(SameMesh(strict.GetPointer(), itkMesh.GetPointer()));
    ITK_TEST_EXPECT_EQUAL(strict->GetNumberOfCells(), 6);
    MeshType::CellAutoPointer cell;
    strict->GetCell(0, cell);
    ITK_TEST_EXPECT_EQUAL(cell->GetType(), itk::CellGeometryEnum::POLYGON_CELL);
    ITK_TEST_EXPECT_EQUAL(cell->GetNumberOfPoints(), 4);
    // Degenerate and duplicate triangles are kept (the mesh's users judge geometry).
    ITK_TRY_EXPECT_NO_EXCEPTION(strict = ReadMesh(badDirectory + "degenerate.off", nullptr));
    ITK_TRY_EXPECT_NO_EXCEPTION(itkMesh = ReadMesh(badDirectory + "degenerate.off", itk::OFFMeshIO::New()));
    ITK_TEST_EXPECT_TRUE(SameMesh(strict.GetPointer(), itkMesh.GetPointer()));
    ITK_TEST_EXPECT_EQUAL(strict->GetNumberOfPoints(), 9);
    ITK_TEST_EXPECT_EQUAL(strict->GetNumberOfCells(), 17);
    // Points with one vertex cell and no polygons.
    ITK_TRY_EXPECT_NO_EXCEPTION(strict = ReadMesh(badDirectory + "points-only.vtk", nullptr));
    ITK_TRY_EXPECT_NO_EXCEPTION(itkMesh = ReadMesh(badDirectory + "points-only.vtk", itk::VTKPolyDataMeshIO::New()));
    ITK_TEST_EXPECT_TRUE(SameMesh(strict.GetPointer(), itkMesh.GetPointer()));
    ITK_TEST_EXPECT_EQUAL(strict->GetNumberOfPoints(), 8);
    ITK_TEST_EXPECT_EQUAL(strict->GetNumberOfCells(), 1);
    std::cout << "  quads.off: 6 polygon cells; degenerate.off: 9 points, 17 triangles; points-only.vtk: 8 points, "
                 "1 vertex cell"
              << std::endl;
  }

  // Good files read identically to ITK's readers: the committed cube, and a sphere written by
  // ITK's writers to OFF, OBJ, ASCII and binary legacy VTK (with point data).
  std::vector<std::pair<std::string, MeshType::Pointer>> goodFiles;
  {
    std::cout << "Good files:" << std::endl;
    const MeshType::Pointer sphere = MakeSphere(false);
    const MeshType::Pointer sphereWithData = MakeSphere(true);
    struct GoodCase
    {
      std::string              File;
      itk::MeshIOBase::Pointer IO;
      const MeshType *         Written;
      bool                     Binary;
    };
    const std::vector<GoodCase> goodCases = {
      { inputDirectory + "cube.off", itk::OFFMeshIO::New(), nullptr, false },
      { outputDirectory + "StrictTextMeshIOTestSphere.off", itk::OFFMeshIO::New(), sphere.GetPointer(), false },
      { outputDirectory + "StrictTextMeshIOTestSphere.obj", itk::OBJMeshIO::New(), sphere.GetPointer(), false },
      { outputDirectory + "StrictTextMeshIOTestSphereASCII.vtk",
        itk::VTKPolyDataMeshIO::New(),
        sphereWithData.GetPointer(),
        false },
      { outputDirectory + "StrictTextMeshIOTestSphereBinary.vtk",
        itk::VTKPolyDataMeshIO::New(),
        sphereWithData.GetPointer(),
        true },
    };
    for (const GoodCase & goodCase : goodCases)
    {
      if (goodCase.Written != nullptr)
      {
        ITK_TRY_EXPECT_NO_EXCEPTION(WriteMesh(goodCase.Written, goodCase.File, goodCase.IO, goodCase.Binary));
      }
      MeshType::Pointer strict;
      MeshType::Pointer itkMesh;
      ITK_TRY_EXPECT_NO_EXCEPTION(strict = ReadMesh(goodCase.File, itk::StrictTextMeshIO::New()));
      // A new IO of the same class as the writer's, for reading.
      itk::LightObject::Pointer readIO = goodCase.IO->CreateAnother();
      ITK_TRY_EXPECT_NO_EXCEPTION(itkMesh =
                                    ReadMesh(goodCase.File, dynamic_cast<itk::MeshIOBase *>(readIO.GetPointer())));
      const bool same = SameMesh(strict.GetPointer(), itkMesh.GetPointer());
      std::cout << "  " << goodCase.File << ": " << strict->GetNumberOfPoints() << " points, "
                << strict->GetNumberOfCells() << " cells, "
                << (strict->GetPointData() != nullptr ? strict->GetPointData()->Size() : 0) << " point values, "
                << (same ? "same as ITK's reader" : "DIFFERENT from ITK's reader") << std::endl;
      ITK_TEST_EXPECT_TRUE(same);
      if (goodCase.Written != nullptr)
      {
        ITK_TEST_EXPECT_EQUAL(strict->GetNumberOfCells(), goodCase.Written->GetNumberOfCells());
        ITK_TEST_EXPECT_EQUAL(strict->GetNumberOfPoints(), goodCase.Written->GetNumberOfPoints());
      }
      goodFiles.emplace_back(goodCase.File, strict);
    }
  }

  // Files made here: further damage with its message, and supported variants.
  {
    std::cout << "Files made here:" << std::endl;
    const std::string          cubeOFF = ReadText(inputDirectory + "cube.off");
    const std::string          offName = outputDirectory + "StrictTextMeshIOTestCase.off";
    const std::string          objName = outputDirectory + "StrictTextMeshIOTestCase.obj";
    const std::string          vtkName = outputDirectory + "StrictTextMeshIOTestCase.vtk";
    const std::string          vtkHeader = "# vtk DataFile Version 3.0\ntitle\nASCII\nDATASET POLYDATA\n";
    const std::string          square = "POINTS 4 float\n0 0 0 1 0 0 1 1 0 0 1 0\n";
    const std::vector<BadCase> madeCases = {
      { "COFF\n3 1 0\n0 0 0 1 1 1 1\n",
        "OFF",
        "line 1: the OFF variant \"COFF\" is not supported (plain \"OFF\" only: no per-vertex colors, normals, "
        "texture coordinates or other dimensions)" },
      { "OFF BINARY\n", "OFF", "line 1: binary OFF files are not supported (ASCII OFF only)" },
      { "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n2 0 1\n", "OFF", "line 6: face 0 has 2 vertices, a face needs at least 3" },
      { "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n3 0 2 1\n",
        "OFF",
        "line 7: unexpected data after the 1 faces the header announces (wrong face count?)" },
      { "OFF\n-3 1 0\n", "OFF", "line 2: expected the number of vertices, found \"-3\"" },
      { "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1e309 0\n3 0 1 2\n",
        "OFF",
        "line 5: vertex 2 has a coordinate beyond the range of double (\"1e309\")" },
      { "OFF\n3 1 0\n0 0 0\n1 0 0\n", "OFF", "the file ends after 2 of 3 vertices" },
      { "OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", "OFF", "the file ends after 1 of 2 faces" },
      { "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2.5\n",
        "OFF",
        "line 6: expected vertex index 2 of face 0, found \"2.5\"" },
      { "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n",
        "OBJ",
        "line 4: face 1 refers to vertex 0; OBJ files count vertices from 1" },
      { "v 0 0 0\nv 1 0 0\nf -1 -2 -3\nv 0 1 0\n",
        "OBJ",
        "line 3: face 1 refers to vertex -3, only 2 vertices precede it" },
      { "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2\n", "OBJ", "line 4: face 1 has 2 vertices, a face needs at least 3" },
      { "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/x 2 3\n",
        "OBJ",
        "line 4: expected a vertex reference of face 1, found \"1/x\"" },
      { "v 0 0 0\nv 1 0 nan\n", "OBJ", "line 2: vertex 2 has a non-finite coordinate (\"nan\")" },
      { "v 0 0 0\nbogus 1 2\n", "OBJ", "line 2: unknown OBJ statement \"bogus\"" },
      { "# only a comment\n", "OBJ", "the file holds no vertices (no \"v\" line)" },
      { "# vtk DataFile Version 3.0\ntitle\nASCII\nDATASET UNSTRUCTURED_GRID\n",
        "legacy VTK",
        "line 4: DATASET \"UNSTRUCTURED_GRID\" is not supported (POLYDATA only; other datasets are read by ITK's or "
        "VTK's own readers)" },
      { "solid x\n",
        "legacy VTK",
        "line 1: not a legacy VTK file: expected \"# vtk DataFile Version\", found \"solid x\"" },
      { vtkHeader + square + "POLYGONS 1 6\n4 0 1 2 3 7\n",
        "legacy VTK",
        "line 7: POLYGONS announces 6 values, its 1 cells use 5" },
      { vtkHeader + square + "POLYGONS 1 5\n4 0 1 2 3 7\n",
        "legacy VTK",
        "line 8: unexpected \"7\" where a POLYDATA section keyword is expected" },
      { vtkHeader + square + "POLYGONS 1 5\n4 0 1 2 9\n",
        "legacy VTK",
        "line 8: POLYGONS cell 0 refers to point 9, the file has 4 points" },
      { vtkHeader + square + "POLYGONS 1 5\n4 0 1 2 3\nPOINT_DATA 3\n",
        "legacy VTK",
        "line 9: POINT_DATA announces 3 tuples, the file has 4 points" },
      { vtkHeader + square + "POLYGONS 1 5\n4 0 1 2 3\nPOINT_DATA 4\nSCALARS s float 1\nLOOKUP_TABLE default\n1 2 3\n",
        "legacy VTK",
        "line 12: the file ends after 3 of the 4 values of POINT_DATA SCALARS s" },
      { vtkHeader + "POLYGONS 1 4\n3 0 1 2\n", "legacy VTK", "line 5: POLYGONS before POINTS" },
      { vtkHeader + "POINTS 1 float\n0 0 0\nCELLS 1 2\n",
        "legacy VTK",
        "line 7: unexpected \"CELLS\" where a POLYDATA section keyword is expected" },
      { std::string("# vtk DataFile Version 3.0\ntitle\nBINARY\nDATASET POLYDATA\nPOINTS 2 float\n") +
          std::string(
            "\x00\x00\x00\x00\x3f\x80\x00\x00\x00\x00\x00\x00\x7f\xc0\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00", 24) +
          "\n",
        "legacy VTK",
        "point 1 has a non-finite coordinate" },
      { std::string("# vtk DataFile Version 3.0\ntitle\nBINARY\nDATASET POLYDATA\nPOINTS 2 float\n") +
          std::string(20, '\0'),
        "legacy VTK",
        "the file ends within the binary data of POINTS (6 values of 4 bytes announced, 20 bytes left)" },
    };
    for (const BadCase & madeCase : madeCases)
    {
      const std::string fileName = madeCase.Format == "OFF" ? offName : madeCase.Format == "OBJ" ? objName : vtkName;
      std::remove(fileName.c_str());
      WriteText(fileName, madeCase.File);
      if (CheckBadCase(fileName, madeCase.Format, madeCase.Message) != EXIT_SUCCESS)
      {
        testStatus = EXIT_FAILURE;
      }
    }

    // OFF with comments, counts on the header line and face colors: the cube.
    MeshType::Pointer strict;
    MeshType::Pointer reference;
    ITK_TRY_EXPECT_NO_EXCEPTION(reference = ReadMesh(inputDirectory + "cube.off", itk::OFFMeshIO::New()));
    std::string variant = "# a comment\nOFF 8 12 0 # counts\n" + cubeOFF.substr(cubeOFF.find("-1 -1 -1"));
    variant.insert(variant.find("3 0 2 3") + 7, " 255 0 0 # a red face");
    WriteText(offName, variant);
    ITK_TRY_EXPECT_NO_EXCEPTION(strict = ReadMesh(offName, nullptr));
    ITK_TEST_EXPECT_TRUE(SameMesh(strict.GetPointer(), reference.GetPointer()));

    // A complete file announcing no vertices is an empty mesh, for the caller to judge.
    std::remove(offName.c_str());
    WriteText(offName, "OFF\n0 0 0\n");
    ITK_TRY_EXPECT_NO_EXCEPTION(strict = ReadMesh(offName, nullptr));
    ITK_TEST_EXPECT_EQUAL(strict->GetNumberOfPoints(), 0);
    ITK_TEST_EXPECT_EQUAL(strict->GetNumberOfCells(), 0);

    // OBJ index forms and negative indices give the same mesh as plain indices.
    // (Normals are not read as point data: the reference has none.)
    const std::string objVertices = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0 1.0\nvt 0 0\n";
    WriteText(objName, objVertices + "f 1 2 3\nf 1 3 4\n");
    ITK_TRY_EXPECT_NO_EXCEPTION(reference = ReadMesh(objName, itk::OBJMeshIO::New()));
    std::remove(objName.c_str());
    WriteText(objName,
              "o square\n" + objVertices + "vn 0 0 1\ng g1\ns off\nf 1/1/1 2//1 3/1\r\nf -4/1 -2 -1//1 # comment\n");
    ITK_TRY_EXPECT_NO_EXCEPTION(strict = ReadMesh(objName, nullptr));
    ITK_TEST_EXPECT_TRUE(SameMesh(strict.GetPointer(), reference.GetPointer()));

    // Legacy VTK: triangle strips become triangles (every other one flipped), the version 5
    // OFFSETS/CONNECTIVITY layout reads as the classic one, attributes other than the scalars are
    // skipped.
    std::remove(vtkName.c_str());
    WriteText(vtkName,
              vtkHeader + "POINTS 5 double\n0 0 0 1 0 0 0 1 0 1 1 0 0 2 0\nTRIANGLE_STRIPS 1 6\n5 0 1 2 3 4\n");
    ITK_TRY_EXPECT_NO_EXCEPTION(strict = ReadMesh(vtkName, nullptr));
    ITK_TEST_EXPECT_EQUAL(strict->GetNumberOfCells(), 3);
    const std::vector<std::vector<MeshType::PointIdentifier>> stripTriangles = { { 0, 1, 2 },
                                                                                 { 2, 1, 3 },
                                                                                 { 2, 3, 4 } };
    for (MeshType::CellIdentifier i = 0; i < std::min<MeshType::CellIdentifier>(3, strict->GetNumberOfCells()); ++i)
    {
      MeshType::CellAutoPointer cell;
      strict->GetCell(i, cell);
      ITK_TEST_EXPECT_EQUAL(cell->GetType(), itk::CellGeometryEnum::TRIANGLE_CELL);
      ITK_TEST_EXPECT_TRUE(std::equal(cell->PointIdsBegin(), cell->PointIdsEnd(), stripTriangles[i].begin()));
    }
    const std::string classic = vtkHeader + square + "POLYGONS 2 8\n3 0 1 2\n3 0 2 3\nLINES 1 3\n2 0 2\n" +
                                "POINT_DATA 4\nNORMALS n float\n0 0 1 0 0 1 0 0 1 0 0 1\n" +
                                "SCALARS s double\nLOOKUP_TABLE default\n0.5 1.5 2.5 3.5\n";
    std::remove(vtkName.c_str());
    WriteText(vtkName, classic);
    ITK_TRY_EXPECT_NO_EXCEPTION(reference = ReadMesh(vtkName, nullptr));
    ITK_TEST_EXPECT_EQUAL(reference->GetNumberOfCells(), 3);
    ITK_TEST_EXPECT_TRUE(reference->GetPointData() != nullptr && reference->GetPointData()->Size() == 4 &&
                         reference->GetPointData()->ElementAt(3) == 3.5);
    std::remove(vtkName.c_str());
    WriteText(vtkName,
              "# vtk DataFile Version 5.1\ntitle\nASCII\nDATASET POLYDATA\n" + square +
                "POLYGONS 3 6\nOFFSETS vtktypeint64\n0 3 6\nCONNECTIVITY vtktypeint64\n0 1 2 0 2 3\n" +
                "LINES 2 2\nOFFSETS vtktypeint64\n0 2\nCONNECTIVITY vtktypeint64\n0 2\n" +
                "POINT_DATA 4\nNORMALS n float\n0 0 1 0 0 1 0 0 1 0 0 1\n" +
                "SCALARS s double 1\nLOOKUP_TABLE default\n0.5 1.5 2.5 3.5\nMETADATA\nINFORMATION 0\n\n");
    ITK_TRY_EXPECT_NO_EXCEPTION(strict = ReadMesh(vtkName, nullptr));
    ITK_TEST_EXPECT_TRUE(SameMesh(strict.GetPointer(), reference.GetPointer()));
  }

  // Fuzz-like loop: every truncation and random corruptions of the good files end in a mesh or an
  // ExceptionObject naming the file, within a bounded time.
  {
    std::cout << "Truncations and corruptions:" << std::endl;
    std::mt19937       generator(20261122u);
    const auto         start = std::chrono::steady_clock::now();
    itk::SizeValueType numberOfReads = 0;
    itk::SizeValueType numberOfAccepted = 0;
    int                failures = 0;
    for (const auto & goodFile : goodFiles)
    {
      const std::string extension = goodFile.first.substr(goodFile.first.size() - 4);
      const std::string scratchFile = outputDirectory + "StrictTextMeshIOTestFuzz" + extension;
      // OFF and VTK files announce their counts: a truncation that reads must be the whole mesh
      // (VTK files only up to their point data, which a truncation may remove whole).
      const bool mustMatch = extension == ".off";
      failures += FuzzFile(
        goodFile.first, scratchFile, goodFile.second, mustMatch, generator, 1500, numberOfReads, numberOfAccepted);
    }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::cout << "  " << numberOfReads << " altered files read in " << seconds << " s: " << numberOfAccepted
              << " accepted, " << numberOfReads - numberOfAccepted << " refused with a message, " << failures
              << " failures" << std::endl;
    ITK_TEST_EXPECT_EQUAL(failures, 0);
    // A hang would be caught by the test's CTest TIMEOUT; the time itself is not asserted (sanitizer builds are
    // several times slower).
  }

  return testStatus;
}
