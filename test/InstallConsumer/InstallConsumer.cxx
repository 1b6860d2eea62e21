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
// A user's program built against an installed FFDShapeMatching (find_package + target_link_libraries only):
// reads two meshes through the module's mesh IOs and voxelizes the second one.
#include "itkImageRegionConstIterator.h"
#include "itkMesh.h"
#include "itkMeshFileReader.h"
#include "itkRegisterFFDShapeMatchingMeshIOFactories.h"
#include "itkTriangleMeshToVoxelImageFilter.h"

#include <iostream>

int
main(int argc, char * argv[])
{
  if (argc != 3)
  {
    std::cerr << "usage: InstallConsumer SOURCE_MESH TARGET_MESH" << std::endl;
    return EXIT_FAILURE;
  }
  using MeshType = itk::Mesh<double, 3>;
  using ImageType = itk::Image<unsigned char, 3>;
  itk::RegisterFFDShapeMatchingMeshIOFactories();
  try
  {
    MeshType::Pointer meshes[2];
    for (int i = 0; i < 2; ++i)
    {
      auto reader = itk::MeshFileReader<MeshType>::New();
      reader->SetFileName(argv[i + 1]);
      reader->Update();
      meshes[i] = reader->GetOutput();
      std::cout << argv[i + 1] << ": " << meshes[i]->GetNumberOfPoints() << " points, " << meshes[i]->GetNumberOfCells()
                << " cells" << std::endl;
    }
    auto voxelizer = itk::TriangleMeshToVoxelImageFilter<MeshType, ImageType>::New();
    voxelizer->SetInput(meshes[1]);
    ImageType::SpacingType spacing;
    spacing.Fill(0.25);
    voxelizer->SetGeometryFromMeshBounds(spacing, 0.5);
    voxelizer->SetMode(itk::TriangleMeshToVoxelImageFilterEnums::Mode::Solid);
    voxelizer->Update();
    const ImageType * image = voxelizer->GetOutput();
    std::size_t       inside = 0;
    for (itk::ImageRegionConstIterator<ImageType> it(image, image->GetBufferedRegion()); !it.IsAtEnd(); ++it)
    {
      inside += it.Get() != 0;
    }
    const ImageType::SizeType size = image->GetBufferedRegion().GetSize();
    std::cout << "voxelized " << size[0] << "x" << size[1] << "x" << size[2] << ", " << inside << " inside"
              << std::endl;
  }
  catch (const itk::ExceptionObject & error)
  {
    std::cerr << "InstallConsumer: error: " << error.GetDescription() << std::endl;
    return EXIT_FAILURE;
  }
  return EXIT_SUCCESS;
}
