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
// Every bad input of TriangleMeshToVoxelImageFilter ends in an exception naming the problem.

#include "itkTriangleMeshToVoxelImageFilter.h"
#include "itkTriangleMeshToVoxelImageFilterTestHelpers.h"

#include "itkLineCell.h"
#include "itkTestingMacros.h"
#include "itkTetrahedronCell.h"

#include <limits>

namespace
{
using MeshType = itk::Mesh<double, 3>;
using MaskImageType = itk::Image<unsigned char, 3>;
using FilterType = itk::TriangleMeshToVoxelImageFilter<MeshType, MaskImageType>;
using ModeEnum = itk::TriangleMeshToVoxelImageFilterEnums::Mode;

// Runs the filter expecting an exception (ITK_TRY_EXPECT_EXCEPTION), then checks that its description
// contains `expected`. Returns EXIT_SUCCESS or EXIT_FAILURE.
int
FailsWith(FilterType * filter, const std::string & expected)
{
  filter->Modified();
  ITK_TRY_EXPECT_EXCEPTION(filter->Update());
  filter->Modified();
  try
  {
    filter->Update();
  }
  catch (const itk::ExceptionObject & error)
  {
    const std::string description = error.GetDescription();
    std::cout << "Expected exception: " << description << std::endl;
    if (description.find(expected) == std::string::npos)
    {
      std::cerr << "The message should contain \"" << expected << "\"." << std::endl;
      return EXIT_FAILURE;
    }
    return EXIT_SUCCESS;
  }
  return EXIT_FAILURE;
}

FilterType::Pointer
MakeFilter(const MeshType * mesh)
{
  auto                    filter = FilterType::New();
  FilterType::SizeType    size = { { 8, 8, 8 } };
  FilterType::PointType   origin;
  FilterType::SpacingType spacing;
  origin.Fill(-4.0);
  spacing.Fill(1.0);
  filter->SetInput(mesh);
  filter->SetSize(size);
  filter->SetOrigin(origin);
  filter->SetSpacing(spacing);
  return filter;
}
} // namespace

int
itkTriangleMeshToVoxelImageFilterExceptionsTest(int argc, char * argv[])
{
  if (argc != 1)
  {
    std::cerr << "Usage: " << itkNameOfTestExecutableMacro(argv) << std::endl;
    return EXIT_FAILURE;
  }
  int  status = EXIT_SUCCESS;
  auto check = [&status](int result) {
    if (result != EXIT_SUCCESS)
    {
      status = EXIT_FAILURE;
    }
  };
  auto sphere = itk::VoxelizationTest::MakeSphere<MeshType>(1, 3.0, { 0.0, 0.0, 0.0 });

  // No input.
  auto noInput = FilterType::New();
  ITK_TRY_EXPECT_EXCEPTION(noInput->Update());
  check(FailsWith(noInput, "Input Primary is required"));

  // Empty mesh, a mesh with points but no cells, a mesh with only lines.
  auto empty = MeshType::New();
  check(FailsWith(MakeFilter(empty), "no points"));
  auto pointsOnly =
    itk::VoxelizationTest::SelectTriangles(sphere.GetPointer(), [](const MeshType::PointType &) { return false; });
  check(FailsWith(MakeFilter(pointsOnly), "no cells"));
  auto linesOnly =
    itk::VoxelizationTest::SelectTriangles(sphere.GetPointer(), [](const MeshType::PointType &) { return false; });
  MeshType::CellAutoPointer line;
  line.TakeOwnership(new itk::LineCell<MeshType::CellType>);
  line->SetPointId(0, 0);
  line->SetPointId(1, 1);
  linesOnly->SetCell(0, line);
  auto linesFilter = MakeFilter(linesOnly);
  ITK_TRY_EXPECT_EXCEPTION(linesFilter->Update());
  check(FailsWith(linesFilter, "no triangle cells"));

  // Only degenerate triangles.
  auto degenerate =
    itk::VoxelizationTest::SelectTriangles(sphere.GetPointer(), [](const MeshType::PointType &) { return false; });
  MeshType::CellAutoPointer flat;
  flat.TakeOwnership(new itk::TriangleCell<MeshType::CellType>);
  flat->SetPointId(0, 0);
  flat->SetPointId(1, 0);
  flat->SetPointId(2, 1);
  degenerate->SetCell(0, flat);
  auto degenerateFilter = MakeFilter(degenerate);
  check(FailsWith(degenerateFilter, "all are degenerate"));
  ITK_TEST_EXPECT_EQUAL(degenerateFilter->GetNumberOfDegenerateTriangles(), 1u);

  // A volume cell; a cell referring to a missing point.
  auto withTetrahedron =
    itk::VoxelizationTest::SelectTriangles(sphere.GetPointer(), [](const MeshType::PointType &) { return true; });
  MeshType::CellAutoPointer tetrahedron;
  tetrahedron.TakeOwnership(new itk::TetrahedronCell<MeshType::CellType>);
  for (unsigned int k = 0; k < 4; ++k)
  {
    tetrahedron->SetPointId(k, k);
  }
  withTetrahedron->SetCell(withTetrahedron->GetNumberOfCells(), tetrahedron);
  check(FailsWith(MakeFilter(withTetrahedron), "volume cell"));
  auto missingPoint =
    itk::VoxelizationTest::SelectTriangles(sphere.GetPointer(), [](const MeshType::PointType &) { return true; });
  MeshType::CellAutoPointer dangling;
  dangling.TakeOwnership(new itk::TriangleCell<MeshType::CellType>);
  dangling->SetPointId(0, 0);
  dangling->SetPointId(1, 1);
  dangling->SetPointId(2, 100000);
  missingPoint->SetCell(missingPoint->GetNumberOfCells(), dangling);
  check(FailsWith(MakeFilter(missingPoint), "does not exist"));

  // NaN and infinite coordinates.
  for (const double bad : { std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity() })
  {
    auto corrupt =
      itk::VoxelizationTest::SelectTriangles(sphere.GetPointer(), [](const MeshType::PointType &) { return true; });
    MeshType::PointType p = corrupt->GetPoint(2);
    p[1] = bad;
    corrupt->SetPoint(2, p);
    auto corruptFilter = MakeFilter(corrupt);
    ITK_TRY_EXPECT_EXCEPTION(corruptFilter->Update());
    check(FailsWith(corruptFilter, "NaN or infinite"));
    FilterType::SpacingType spacing;
    spacing.Fill(1.0);
    ITK_TRY_EXPECT_EXCEPTION(corruptFilter->SetGeometryFromMeshBounds(spacing, 1.0));
  }

  // Zero, negative and NaN spacing; zero size; a reference image with a zero size.
  auto                    geometry = MakeFilter(sphere);
  FilterType::SpacingType spacing;
  for (const double bad : { 0.0, -1.0, std::numeric_limits<double>::quiet_NaN() })
  {
    spacing.Fill(1.0);
    spacing[1] = bad;
    geometry->SetSpacing(spacing);
    ITK_TRY_EXPECT_EXCEPTION(geometry->Update());
    check(FailsWith(geometry, "spacing must be positive"));
    ITK_TRY_EXPECT_EXCEPTION(geometry->SetGeometryFromMeshBounds(spacing, 1.0));
  }
  spacing.Fill(1.0);
  geometry->SetSpacing(spacing);
  FilterType::SizeType zeroSize = { { 8, 0, 8 } };
  geometry->SetSize(zeroSize);
  ITK_TRY_EXPECT_EXCEPTION(geometry->Update());
  check(FailsWith(geometry, "size is zero"));
  auto unsetSize = FilterType::New();
  unsetSize->SetInput(sphere);
  check(FailsWith(unsetSize, "size is zero"));
  auto reference = MaskImageType::New();
  auto withReference = MakeFilter(sphere);
  withReference->SetReferenceImage(reference);
  check(FailsWith(withReference, "reference image size is zero"));

  // Too many voxels: refused before allocation, even for a size whose count overflows 64 bits.
  auto tooLarge = MakeFilter(sphere);
  tooLarge->SetMaximumNumberOfVoxels(511);
  check(FailsWith(tooLarge, "more than MaximumNumberOfVoxels"));
  ITK_TEST_EXPECT_TRUE(tooLarge->GetOutput()->GetBufferPointer() == nullptr);
  FilterType::SizeType huge = { { 1u << 30, 1u << 30, 1u << 30 } };
  tooLarge->SetSize(huge);
  tooLarge->SetMaximumNumberOfVoxels(std::numeric_limits<itk::SizeValueType>::max());
  check(FailsWith(tooLarge, "more than MaximumNumberOfVoxels"));

  // Distance and winding-number modes need a floating-point pixel type.
  for (const auto mode : { ModeEnum::SignedDistance, ModeEnum::WindingNumber })
  {
    auto integerDistance = MakeFilter(sphere);
    integerDistance->SetMode(mode);
    check(FailsWith(integerDistance, "floating-point output pixel type"));
  }

  // Bad parameters.
  auto parameters = MakeFilter(sphere);
  parameters->SetBandWidth(-2.0);
  check(FailsWith(parameters, "BandWidth"));
  parameters->SetBandWidth(1.0);
  parameters->SetOccupancyDistance(-0.5);
  check(FailsWith(parameters, "OccupancyDistance"));
  parameters->SetOccupancyDistance(-1.0);
  parameters->SetBeta(0.5);
  check(FailsWith(parameters, "Beta"));
  parameters->SetBeta(2.0);
  ITK_TRY_EXPECT_NO_EXCEPTION(parameters->Update());

  // A mask image on another grid than the output's, and a mask with the exact (unclamped) distance.
  const auto makeMask = [](const FilterType::SizeType & maskSize, double maskOrigin) {
    auto                    mask = MaskImageType::New();
    FilterType::PointType   maskOriginPoint;
    FilterType::SpacingType maskSpacing;
    maskOriginPoint.Fill(maskOrigin);
    maskSpacing.Fill(1.0);
    mask->SetRegions(MaskImageType::RegionType(maskSize));
    mask->SetOrigin(maskOriginPoint);
    mask->SetSpacing(maskSpacing);
    mask->Allocate(true);
    return mask;
  };
  FilterType::SizeType smaller = { { 8, 7, 8 } };
  FilterType::SizeType same = { { 8, 8, 8 } };
  auto                 masked = MakeFilter(sphere);
  masked->SetMaskImage(makeMask(smaller, -4.0));
  check(FailsWith(masked, "mask image's grid"));
  masked->SetMaskImage(makeMask(same, -3.5));
  check(FailsWith(masked, "mask image's grid"));
  masked->SetMaskImage(makeMask(same, -4.0));
  ITK_TRY_EXPECT_NO_EXCEPTION(masked->Update());
  using RealFilterType = itk::TriangleMeshToVoxelImageFilter<MeshType, itk::Image<float, 3>>;
  auto exactMasked = RealFilterType::New();
  exactMasked->SetInput(sphere);
  exactMasked->SetSize(same);
  exactMasked->SetOrigin(masked->GetOrigin());
  exactMasked->SetMode(ModeEnum::SignedDistance);
  exactMasked->ExactDistanceOn();
  exactMasked->SetMaskImage(makeMask(same, -4.0));
  ITK_TRY_EXPECT_EXCEPTION(exactMasked->Update());
  exactMasked->ExactDistanceOff();
  ITK_TRY_EXPECT_NO_EXCEPTION(exactMasked->Update());

  // Geometry from bounds: null mesh and negative margin.
  ITK_TRY_EXPECT_EXCEPTION(FilterType::New()->SetGeometryFromMeshBounds(spacing, 1.0));
  ITK_TRY_EXPECT_EXCEPTION(parameters->SetGeometryFromMeshBounds(spacing, -1.0));

  std::cout << (status == EXIT_SUCCESS ? "Test finished." : "Test FAILED.") << std::endl;
  return status;
}
