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
// libFuzzer target: the mesh-reading and voxelization path of the module's programs.
// The first input byte picks the file format (OFF, OBJ, legacy VTK, STL, PLY, VTP); the rest is the file.
// Whatever the bytes, reading must end in a mesh or an itk::ExceptionObject, and a mesh that was read must
// voxelize (or be refused with an ExceptionObject) within a small voxel budget: no crash, hang, leak or
// undefined behaviour.

#include "itkMesh.h"
#include "itkMeshFileReader.h"
#include "itkRegisterFFDShapeMatchingMeshIOFactories.h"
#include "itkTriangleMeshToVoxelImageFilter.h"

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <string>
#include <unistd.h>

namespace
{
using MeshType = itk::Mesh<double, 3>;
using ImageType = itk::Image<float, 3>;
using VoxelizerType = itk::TriangleMeshToVoxelImageFilter<MeshType, ImageType>;

const char * const Extensions[] = { ".off", ".obj", ".vtk", ".stl", ".ply", ".vtp" };
} // namespace

extern "C" int
LLVMFuzzerInitialize(int *, char ***)
{
  itk::RegisterFFDShapeMatchingMeshIOFactories();
  itk::MultiThreaderBase::SetGlobalDefaultNumberOfThreads(1);
  return 0;
}

extern "C" int
LLVMFuzzerTestOneInput(const uint8_t * data, size_t size)
{
  if (size < 1)
  {
    return 0;
  }
  const std::string fileName = "/tmp/ffd-mesh-fuzz-" + std::to_string(getpid()) + Extensions[data[0] % 6];
  {
    std::ofstream file(fileName, std::ios::binary);
    file.write(reinterpret_cast<const char *>(data + 1), static_cast<std::streamsize>(size - 1));
  }
  try
  {
    auto reader = itk::MeshFileReader<MeshType>::New();
    reader->SetFileName(fileName);
    reader->Update();
    auto voxelizer = VoxelizerType::New();
    voxelizer->SetInput(reader->GetOutput());
    voxelizer->SetMode(data[0] / 6 % 2 ? itk::TriangleMeshToVoxelImageFilterEnums::Mode::SignedDistance
                                       : itk::TriangleMeshToVoxelImageFilterEnums::Mode::Solid);
    voxelizer->SetBandWidth(2.0);
    voxelizer->SetMaximumNumberOfVoxels(32 * 32 * 32);
    VoxelizerType::SpacingType spacing;
    spacing.Fill(1.0);
    voxelizer->SetGeometryFromMeshBounds(spacing, 2.0);
    voxelizer->Update();
  }
  catch (const itk::ExceptionObject &)
  {
    // Refused with a message: the expected outcome for damaged input.
  }
  std::remove(fileName.c_str());
  return 0;
}
