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
// Mesh files through the module's IO factories as the programs use them: coordinates far from the origin keep
// double precision in every format that can hold it, and a VTP file nested too deep for VTK's XML parser is
// refused with an exception instead of crashing.

#include "itkMesh.h"
#include "itkMeshFileReader.h"
#include "itkMeshFileWriter.h"
#include "itkMeshIOFactory.h"
#include "itkObjectFactoryBase.h"
#include "itkRegisterFFDShapeMatchingMeshIOFactories.h"
#include "itkRegisterFFDShapeMatchingTextMeshIOFactories.h"
#include "itkTriangleCell.h"
#include "gtest/gtest.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <unistd.h>

namespace
{
// Double coordinates, as the programs use (itk::Mesh<double, 3> stores float coordinates).
using MeshType = itk::Mesh<double, 3, itk::DefaultStaticMeshTraits<double, 3, 3, double, double, double>>;

std::filesystem::path
TemporaryFolder()
{
  const auto folder =
    std::filesystem::temp_directory_path() / ("itkMeshFileIOGTest-" + std::to_string(static_cast<long>(getpid())));
  std::filesystem::create_directories(folder);
  return folder;
}

// A tetrahedron 1e7 mm from the origin whose coordinates need all of a double's digits.
MeshType::Pointer
FarTetrahedron()
{
  auto         mesh = MeshType::New();
  const double offset = 1.0e7;
  const double corners[4][3] = { { 0.123456789012, 0.987654321098, 0.5 },
                                 { 10.314159265358, 0.271828182845, 0.1 },
                                 { 0.707106781186, 10.577215664901, 0.3 },
                                 { 0.141421356237, 0.173205080756, 10.223606797749 } };
  for (unsigned int i = 0; i < 4; ++i)
  {
    MeshType::PointType point;
    for (unsigned int k = 0; k < 3; ++k)
    {
      point[k] = offset + corners[i][k];
    }
    mesh->SetPoint(i, point);
  }
  const unsigned int faces[4][3] = { { 0, 2, 1 }, { 0, 1, 3 }, { 0, 3, 2 }, { 1, 2, 3 } };
  for (unsigned int f = 0; f < 4; ++f)
  {
    MeshType::CellAutoPointer cell;
    cell.TakeOwnership(new itk::TriangleCell<MeshType::CellType>);
    for (unsigned int k = 0; k < 3; ++k)
    {
      cell->SetPointId(k, faces[f][k]);
    }
    mesh->SetCell(f, cell);
  }
  return mesh;
}

// The largest coordinate difference after writing mesh to fileName and reading it back: point by point, or, with
// anyOrder (STL keeps no point ids: VTK's reader merges and renumbers them), to the nearest point read.
double
RoundTripError(const MeshType * mesh, const std::string & fileName, bool anyOrder = false)
{
  auto writer = itk::MeshFileWriter<MeshType>::New();
  writer->SetInput(mesh);
  writer->SetFileName(fileName);
  writer->Update();
  auto reader = itk::MeshFileReader<MeshType>::New();
  reader->SetFileName(fileName);
  reader->Update();
  const MeshType * read = reader->GetOutput();
  EXPECT_EQ(read->GetNumberOfPoints(), mesh->GetNumberOfPoints()) << fileName;
  const auto difference = [&](MeshType::PointIdentifier i, MeshType::PointIdentifier j) {
    double largest = 0.0;
    for (unsigned int k = 0; k < 3; ++k)
    {
      largest = std::max(largest, std::abs(read->GetPoint(j)[k] - mesh->GetPoint(i)[k]));
    }
    return largest;
  };
  double largest = 0.0;
  for (MeshType::PointIdentifier i = 0; i < mesh->GetNumberOfPoints(); ++i)
  {
    double nearest = std::numeric_limits<double>::infinity();
    for (MeshType::PointIdentifier j = 0; j < read->GetNumberOfPoints(); ++j)
    {
      if (anyOrder || j == i)
      {
        nearest = std::min(nearest, difference(i, j));
      }
    }
    largest = std::max(largest, nearest);
  }
  return largest;
}
} // namespace

// The text formats' registration (no VTK) and the whole one: each factory registered once however often they are
// called (or after ITK's automatic registration), the strict reader in front for .off, .obj and .vtk, and VTK's
// surface IO reading .stl after the whole registration.
TEST(MeshFileIO, RegistrationsRegisterEachFactoryOnce)
{
  const auto count = [](const char * name) {
    int found = 0;
    for (itk::ObjectFactoryBase * factory : itk::ObjectFactoryBase::GetRegisteredFactories())
    {
      found += std::string(factory->GetNameOfClass()) == name ? 1 : 0;
    }
    return found;
  };
  const auto readerOf = [](const char * fileName) {
    const auto io = itk::MeshIOFactory::CreateMeshIO(fileName, itk::IOFileModeEnum::ReadMode);
    return io.IsNull() ? std::string() : std::string(io->GetNameOfClass());
  };
  for (int call = 0; call < 2; ++call)
  {
    itk::RegisterFFDShapeMatchingTextMeshIOFactories();
    for (const char * name :
         { "OFFMeshIOFactory", "OBJMeshIOFactory", "VTKPolyDataMeshIOFactory", "StrictTextMeshIOFactory" })
    {
      EXPECT_EQ(count(name), 1) << name << " after call " << call;
    }
  }
  // The reader an IO factory gives for an existing file of each format.
  const auto folder = TemporaryFolder();
  const auto fileOf = [&folder](const char * extension) {
    const std::string fileName = (folder / (std::string("part") + extension)).string();
    auto              writer = itk::MeshFileWriter<MeshType>::New();
    writer->SetInput(FarTetrahedron());
    writer->SetFileName(fileName);
    writer->Update();
    return fileName;
  };
  for (const char * extension : { ".off", ".obj", ".vtk" })
  {
    EXPECT_EQ(readerOf(fileOf(extension).c_str()), "StrictTextMeshIO") << extension;
  }
  itk::RegisterFFDShapeMatchingMeshIOFactories();
  itk::RegisterFFDShapeMatchingMeshIOFactories();
  EXPECT_EQ(count("VTKSurfaceMeshIOFactory"), 1);
  EXPECT_EQ(count("StrictTextMeshIOFactory"), 1);
  EXPECT_EQ(readerOf(fileOf(".stl").c_str()), "VTKSurfaceMeshIO");
  EXPECT_EQ(readerOf(fileOf(".off").c_str()), "StrictTextMeshIO");
  std::filesystem::remove_all(folder);
}

// OFF, OBJ, legacy VTK and VTP hold double coordinates: a round trip 1e7 mm from the origin is exact to 1e-6 mm.
// Binary STL is float32 by format and VTK 9.1's PLY reader and writer are float32: their error at 1e7 mm is up
// to half a float step there (0.5 mm), and is checked to be no worse.
TEST(MeshFileIO, DoublePrecisionFarFromTheOrigin)
{
  itk::RegisterFFDShapeMatchingMeshIOFactories();
  const auto              folder = TemporaryFolder();
  const MeshType::Pointer mesh = FarTetrahedron();
  for (const char * extension : { ".off", ".obj", ".vtk", ".vtp", ".VTP" })
  {
    const std::string fileName = (folder / (std::string("far") + extension)).string();
    EXPECT_LE(RoundTripError(mesh, fileName), 1.0e-6) << fileName;
  }
  for (const char * extension : { ".stl", ".ply" })
  {
    const std::string fileName = (folder / (std::string("far") + extension)).string();
    const double      error = RoundTripError(mesh, fileName, true);
    EXPECT_LE(error, 0.5) << fileName;
    EXPECT_GT(error, 1.0e-6) << fileName << ": float32 no longer; update docs/ffd-match.md, \"Limits and errors\"";
  }
  std::filesystem::remove_all(folder);
}

// A VTP file nesting 300 000 elements crashed VTK's XML parser (stack overflow); it is refused before parsing.
TEST(MeshFileIO, RefusesDeeplyNestedVTP)
{
  itk::RegisterFFDShapeMatchingMeshIOFactories();
  const auto        folder = TemporaryFolder();
  const std::string fileName = (folder / "deep.vtp").string();
  {
    std::ofstream file(fileName);
    file << "<?xml version=\"1.0\"?>\n<VTKFile type=\"PolyData\" version=\"0.1\">";
    for (int i = 0; i < 300000; ++i)
    {
      file << "<a>";
    }
    for (int i = 0; i < 300000; ++i)
    {
      file << "</a>";
    }
    file << "</VTKFile>\n";
  }
  auto reader = itk::MeshFileReader<MeshType>::New();
  reader->SetFileName(fileName);
  try
  {
    reader->Update();
    ADD_FAILURE() << "the deeply nested VTP file was read";
  }
  catch (const itk::ExceptionObject & error)
  {
    const std::string description = error.GetDescription();
    EXPECT_NE(description.find("deep.vtp"), std::string::npos) << description;
    EXPECT_NE(description.find("nests elements more than 256 levels deep"), std::string::npos) << description;
  }
  // 200 levels (deeper than any VTP file) are left to VTK's reader, which reports what it misses.
  {
    std::ofstream file(fileName);
    file << "<?xml version=\"1.0\"?>\n<VTKFile type=\"PolyData\" version=\"0.1\"><!-- <<<< --><PolyData>";
    for (int i = 0; i < 200; ++i)
    {
      file << "<a b=\"x>y\">";
    }
    for (int i = 0; i < 200; ++i)
    {
      file << "</a>";
    }
    file << "</PolyData></VTKFile>\n";
  }
  try
  {
    reader->Modified();
    reader->Update();
    ADD_FAILURE() << "a VTP file without points was read";
  }
  catch (const itk::ExceptionObject & error)
  {
    EXPECT_EQ(std::string(error.GetDescription()).find("nests elements"), std::string::npos) << error.GetDescription();
  }
  std::filesystem::remove_all(folder);
}

// The functions ITK's generated factory registration calls for itk-module.cmake's FACTORY_NAMES (MeshIO::StrictText,
// MeshIO::VTKSurface): each registers its factory once, however often it is called.
namespace itk
{
void
StrictTextMeshIOFactoryRegister__Private();
void
VTKSurfaceMeshIOFactoryRegister__Private();
} // namespace itk

namespace
{
size_t
CountRegisteredFactories(const char * className)
{
  size_t count = 0;
  for (const auto & factory : itk::ObjectFactoryBase::GetRegisteredFactories())
  {
    count += std::string(factory->GetNameOfClass()) == className ? 1 : 0;
  }
  return count;
}
} // namespace

TEST(MeshFileIO, FactoryNamesRegisterEachFactoryOnce)
{
  const size_t strictBefore = CountRegisteredFactories("StrictTextMeshIOFactory");
  const size_t surfaceBefore = CountRegisteredFactories("VTKSurfaceMeshIOFactory");
  for (int call = 0; call < 3; ++call)
  {
    itk::StrictTextMeshIOFactoryRegister__Private();
    itk::VTKSurfaceMeshIOFactoryRegister__Private();
  }
  const size_t strictAfter = CountRegisteredFactories("StrictTextMeshIOFactory");
  const size_t surfaceAfter = CountRegisteredFactories("VTKSurfaceMeshIOFactory");
  EXPECT_GE(strictAfter, 1u);
  EXPECT_GE(surfaceAfter, 1u);
  EXPECT_LE(strictAfter - strictBefore, 1u);
  EXPECT_LE(surfaceAfter - surfaceBefore, 1u);
}
