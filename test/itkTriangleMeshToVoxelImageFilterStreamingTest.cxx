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
// Streamed (StreamingImageFilter, 5 divisions) and single-threaded results are bit-identical to a
// whole, two-thread update, in every mode; a streamed piece only computes its own region.

#include "itkTriangleMeshToVoxelImageFilter.h"
#include "itkTriangleMeshToVoxelImageFilterTestHelpers.h"

#include "itkImageFileWriter.h"
#include "itkStreamingImageFilter.h"
#include "itkTestingMacros.h"

#include <cstring>

namespace
{
using MeshType = itk::Mesh<double, 3>;
using ImageType = itk::Image<float, 3>;
using FilterType = itk::TriangleMeshToVoxelImageFilter<MeshType, ImageType>;
using ModeEnum = itk::TriangleMeshToVoxelImageFilterEnums::Mode;

bool
SameBits(const ImageType * a, const ImageType * b)
{
  const size_t count = a->GetLargestPossibleRegion().GetNumberOfPixels();
  return a->GetBufferedRegion() == a->GetLargestPossibleRegion() &&
         b->GetBufferedRegion() == b->GetLargestPossibleRegion() &&
         a->GetLargestPossibleRegion() == b->GetLargestPossibleRegion() &&
         std::memcmp(a->GetBufferPointer(), b->GetBufferPointer(), count * sizeof(float)) == 0;
}
} // namespace

int
itkTriangleMeshToVoxelImageFilterStreamingTest(int argc, char * argv[])
{
  if (argc != 2)
  {
    std::cerr << "Usage: " << itkNameOfTestExecutableMacro(argv) << " outputImage" << std::endl;
    return EXIT_FAILURE;
  }
  auto sphere = itk::VoxelizationTest::MakeSphere<MeshType>(4, 8.0, { 0.2, 0.1, -0.3 });

  FilterType::SpacingType spacing;
  spacing[0] = 0.6;
  spacing[1] = 0.55;
  spacing[2] = 0.5;

  int status = EXIT_SUCCESS;
  for (const auto mode :
       { ModeEnum::Occupancy, ModeEnum::Solid, ModeEnum::SignedDistance, ModeEnum::BandMask, ModeEnum::WindingNumber })
  {
    auto whole = FilterType::New();
    whole->SetInput(sphere);
    whole->SetGeometryFromMeshBounds(spacing, 2.0);
    whole->SetMode(mode);
    whole->SetNumberOfWorkUnits(2);
    ITK_TRY_EXPECT_NO_EXCEPTION(whole->Update());

    auto single = FilterType::New();
    single->SetInput(sphere);
    single->SetGeometryFromMeshBounds(spacing, 2.0);
    single->SetMode(mode);
    single->SetNumberOfWorkUnits(1);
    ITK_TRY_EXPECT_NO_EXCEPTION(single->Update());

    auto piecewise = FilterType::New();
    piecewise->SetInput(sphere);
    piecewise->SetGeometryFromMeshBounds(spacing, 2.0);
    piecewise->SetMode(mode);
    auto streamer = itk::StreamingImageFilter<ImageType, ImageType>::New();
    streamer->SetInput(piecewise->GetOutput());
    streamer->SetNumberOfStreamDivisions(5);
    ITK_TRY_EXPECT_NO_EXCEPTION(streamer->Update());
    // The last piece is smaller than the whole image: the filter produced only the requested pieces.
    ITK_TEST_EXPECT_TRUE(piecewise->GetOutput()->GetBufferedRegion().GetNumberOfPixels() <
                         whole->GetOutput()->GetBufferedRegion().GetNumberOfPixels());

    const bool streamedSame = SameBits(whole->GetOutput(), streamer->GetOutput());
    const bool threadsSame = SameBits(whole->GetOutput(), single->GetOutput());
    std::cout << mode << ": " << whole->GetOutput()->GetLargestPossibleRegion().GetSize()
              << " streamed identical: " << streamedSame << ", 1 vs 2 threads identical: " << threadsSame << std::endl;
    if (!streamedSame || !threadsSame)
    {
      status = EXIT_FAILURE;
    }
    if (mode == ModeEnum::SignedDistance)
    {
      ITK_TRY_EXPECT_NO_EXCEPTION(itk::WriteImage(streamer->GetOutput(), argv[1]));
    }
  }
  return status;
}
