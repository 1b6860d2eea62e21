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
// The scan-line path of TriangleMeshToVoxelImageFilter (ScanLineAcceleration On, the default) gives
// the same image, bit for bit, as the reference path that computes every voxel on its own
// (ScanLineAcceleration Off), in every mode, on closed, holed, inverted, inconsistently oriented,
// self-intersecting and open meshes, on grids whose rows run exactly through edges and vertices, and
// on a rotated, anisotropic grid; streamed and single-threaded scan-line results are identical too.
// With a mask image, the masked voxels hold the unmasked values and the others the far value, on both paths.
// Also checks detail::ScanLineCrossings() and detail::WindingNumberGradientBound on small cases.

#include "itkTriangleMeshToVoxelImageFilter.h"
#include "itkTriangleMeshToVoxelImageFilterTestHelpers.h"

#include "itkImageRegionIteratorWithIndex.h"
#include "itkQuadrilateralCell.h"
#include "itkStreamingImageFilter.h"
#include "itkTestingMacros.h"

#include <algorithm>
#include <cstring>
#include <functional>
#include <string>

namespace
{
using MeshType = itk::Mesh<double, 3>;
using RealImageType = itk::Image<float, 3>;
using FilterType = itk::TriangleMeshToVoxelImageFilter<MeshType, RealImageType>;
using ModeEnum = itk::TriangleMeshToVoxelImageFilterEnums::Mode;
using itk::VoxelizationTest::Vector3;

struct Grid
{
  FilterType::PointType     origin;
  FilterType::SpacingType   spacing;
  FilterType::SizeType      size;
  FilterType::DirectionType direction;
};

// Counts the voxels that differ between two whole images of the same region.
size_t
CountDifferences(const RealImageType * a, const RealImageType * b)
{
  const size_t count = a->GetLargestPossibleRegion().GetNumberOfPixels();
  size_t       differences = 0;
  for (size_t i = 0; i < count; ++i)
  {
    if (std::memcmp(a->GetBufferPointer() + i, b->GetBufferPointer() + i, sizeof(float)) != 0)
    {
      if (++differences <= 3)
      {
        std::cout << "  voxel " << a->ComputeIndex(static_cast<RealImageType::OffsetValueType>(i)) << ": "
                  << a->GetBufferPointer()[i] << " vs " << b->GetBufferPointer()[i] << std::endl;
      }
    }
  }
  return differences;
}

RealImageType::Pointer
Voxelize(const MeshType *                          mesh,
         const Grid &                              grid,
         const std::function<void(FilterType *)> & setup,
         bool                                      scanLines,
         unsigned int                              workUnits,
         unsigned int                              streamDivisions)
{
  auto filter = FilterType::New();
  filter->SetInput(mesh);
  filter->SetOrigin(grid.origin);
  filter->SetSpacing(grid.spacing);
  filter->SetSize(grid.size);
  filter->SetDirection(grid.direction);
  filter->SetScanLineAcceleration(scanLines);
  filter->SetNumberOfWorkUnits(workUnits);
  setup(filter);
  RealImageType::Pointer output;
  if (streamDivisions > 1)
  {
    auto streamer = itk::StreamingImageFilter<RealImageType, RealImageType>::New();
    streamer->SetInput(filter->GetOutput());
    streamer->SetNumberOfStreamDivisions(streamDivisions);
    streamer->Update();
    output = streamer->GetOutput();
  }
  else
  {
    filter->Update();
    output = filter->GetOutput();
  }
  output->DisconnectPipeline();
  return output;
}

Grid
GridAround(const MeshType * mesh, double spacing, double margin)
{
  Grid grid;
  grid.spacing.Fill(spacing);
  FilterType::ComputeGeometryFromMeshBounds(mesh, grid.spacing, margin, grid.origin, grid.size);
  grid.direction.SetIdentity();
  return grid;
}

// A cube [-h, h]^3 of quadrilaterals (outward), optionally with one face left out.
MeshType::Pointer
MakeCube(double half, bool open)
{
  auto mesh = MeshType::New();
  for (unsigned int i = 0; i < 8; ++i)
  {
    MeshType::PointType p;
    p[0] = (i & 1) ? half : -half;
    p[1] = (i & 2) ? half : -half;
    p[2] = (i & 4) ? half : -half;
    mesh->SetPoint(i, p);
  }
  const unsigned int quads[6][4] = { { 0, 2, 3, 1 }, { 4, 5, 7, 6 }, { 0, 1, 5, 4 },
                                     { 2, 6, 7, 3 }, { 0, 4, 6, 2 }, { 1, 3, 7, 5 } };
  for (unsigned int f = 0; f < (open ? 5u : 6u); ++f)
  {
    MeshType::CellAutoPointer cell;
    cell.TakeOwnership(new itk::QuadrilateralCell<MeshType::CellType>);
    for (unsigned int k = 0; k < 4; ++k)
    {
      cell->SetPointId(k, quads[f][k]);
    }
    mesh->SetCell(f, cell);
  }
  return mesh;
}

// Two overlapping spheres in one mesh (self-intersecting surface, nested winding numbers).
MeshType::Pointer
MakeTwoSpheres()
{
  auto first = itk::VoxelizationTest::MakeSphere<MeshType>(3, 5.0, Vector3{ -1.5, 0.2, 0.1 });
  auto second = itk::VoxelizationTest::MakeSphere<MeshType>(3, 4.0, Vector3{ 2.0, -0.3, 0.4 });
  auto mesh =
    itk::VoxelizationTest::SelectTriangles(first.GetPointer(), [](const MeshType::PointType &) { return true; });
  const auto offset = first->GetNumberOfPoints();
  for (auto it = second->GetPoints()->Begin(); it != second->GetPoints()->End(); ++it)
  {
    mesh->SetPoint(offset + it.Index(), it.Value());
  }
  auto cellId = mesh->GetNumberOfCells();
  for (auto it = second->GetCells()->Begin(); it != second->GetCells()->End(); ++it)
  {
    MeshType::CellAutoPointer cell;
    cell.TakeOwnership(new itk::TriangleCell<MeshType::CellType>);
    for (unsigned int k = 0; k < 3; ++k)
    {
      cell->SetPointId(k, offset + it.Value()->PointIdsBegin()[k]);
    }
    mesh->SetCell(cellId++, cell);
  }
  return mesh;
}

int
CheckCrossingsAndBound()
{
  // A unit square in the plane x = 0 split along its diagonal; the row (y, z) = (0.5, 0.5) runs
  // exactly through the shared edge and must cross exactly one triangle; the row through the shared
  // vertex (0, 0) too. Rows are given in continuous-index coordinates.
  std::vector<itk::detail::IndexSpaceTriangle> triangles(2);
  const std::array<double, 3> p00{ { 0.0, 0.0, 0.0 } }, p10{ { 0.0, 1.0, 0.0 } }, p11{ { 0.0, 1.0, 1.0 } },
    p01{ { 0.0, 0.0, 1.0 } };
  const std::array<std::array<double, 3>, 3> corners[2] = { { { p00, p10, p11 } }, { { p00, p11, p01 } } };
  for (unsigned int t = 0; t < 2; ++t)
  {
    triangles[t].a = corners[t][0];
    triangles[t].b = corners[t][1];
    triangles[t].c = corners[t][2];
    for (unsigned int k = 0; k < 3; ++k)
    {
      triangles[t].lower[k] = std::min({ corners[t][0][k], corners[t][1][k], corners[t][2][k] });
      triangles[t].upper[k] = std::max({ corners[t][0][k], corners[t][1][k], corners[t][2][k] });
    }
  }
  const std::uint32_t                        ids[2] = { 0, 1 };
  std::vector<itk::detail::ScanLineCrossing> crossings;
  std::vector<std::pair<double, double>>     uncertain;
  int                                        status = EXIT_SUCCESS;
  const double                               rows[][2] = { { 0.5, 0.5 }, { 0.0, 0.0 }, { 1.0, 1.0 }, { 0.25, 0.75 },
                                                           { 0.0, 0.5 }, { 1.0, 0.5 }, { 2.0, 0.5 } };
  const size_t                               expected[] = { 1, 1, 0, 1, 1, 0, 0 };
  for (size_t r = 0; r < sizeof(expected) / sizeof(expected[0]); ++r)
  {
    itk::detail::ScanLineCrossings(rows[r][0], rows[r][1], triangles, ids, ids + 2, 1, crossings, uncertain);
    std::cout << "Row (" << rows[r][0] << ", " << rows[r][1] << "): " << crossings.size() << " crossings" << std::endl;
    if (crossings.size() != expected[r] || !uncertain.empty())
    {
      std::cerr << "  expected " << expected[r] << std::endl;
      status = EXIT_FAILURE;
    }
  }

  // The square alone is open (4 edges with a net current); closing it into a tetrahedron-free
  // double-sided sheet (the same two triangles reversed) cancels every edge.
  using Triangle = itk::detail::TriangleBoundingVolumeHierarchy::Triangle;
  std::vector<Triangle>                     sheet{ Triangle{ p00, p10, p11 }, Triangle{ p00, p11, p01 } };
  std::vector<std::array<std::uint32_t, 3>> sheetCorners{ { { 0, 1, 2 } }, { { 0, 2, 3 } } };
  itk::detail::WindingNumberGradientBound   bound;
  bound.Build(sheet, sheetCorners);
  ITK_TEST_EXPECT_EQUAL(bound.GetNumberOfEdges(), 4u);
  // Far from the sheet, the bound is at most the perimeter / (4 pi d^2).
  const std::array<double, 3> lower{ { 10.0, 0.0, 0.0 } }, upper{ { 11.0, 1.0, 1.0 } };
  const double                farBound = bound.Bound(lower, upper);
  std::cout << "Gradient bound 10 away from a unit square: " << farBound << std::endl;
  ITK_TEST_EXPECT_TRUE(farBound > 0.0 && farBound <= 4.0 / (4.0 * 3.14159265358979323846 * 100.0) + 1e-12);
  // The true gradient there (finite difference of the exact winding number) is below the bound.
  const double h = 1e-4;
  const double w0 = itk::VoxelizationTest::BruteForceWindingNumber(Vector3{ 10.0, 0.5, 0.5 }, sheet);
  const double w1 = itk::VoxelizationTest::BruteForceWindingNumber(Vector3{ 10.0 + h, 0.5, 0.5 }, sheet);
  ITK_TEST_EXPECT_TRUE(std::abs(w1 - w0) / h <= farBound);
  const std::array<double, 3> touching{ { -0.5, 0.5, 0.5 } }, touchingUpper{ { 0.5, 0.6, 0.6 } };
  ITK_TEST_EXPECT_TRUE(std::isfinite(bound.Bound(touching, touchingUpper)));
  const std::array<double, 3> onEdge{ { -0.5, -0.1, 0.4 } }, onEdgeUpper{ { 0.5, 0.1, 0.6 } };
  ITK_TEST_EXPECT_TRUE(!std::isfinite(bound.Bound(onEdge, onEdgeUpper)));
  sheet.push_back(Triangle{ p00, p11, p10 });
  sheet.push_back(Triangle{ p00, p01, p11 });
  sheetCorners.push_back({ { 0, 2, 1 } });
  sheetCorners.push_back({ { 0, 3, 2 } });
  bound.Build(sheet, sheetCorners);
  ITK_TEST_EXPECT_EQUAL(bound.GetNumberOfEdges(), 0u);
  return status;
}
} // namespace

int
itkTriangleMeshToVoxelImageFilterScanLineTest(int argc, char * argv[])
{
  if (argc != 1)
  {
    std::cerr << "Usage: " << itkNameOfTestExecutableMacro(argv) << std::endl;
    return EXIT_FAILURE;
  }
  int status = CheckCrossingsAndBound();

  const Vector3 centre{ 0.31, -0.17, 0.23 };
  auto          sphere = itk::VoxelizationTest::MakeSphere<MeshType>(3, 6.0, centre);
  auto          all = [](const MeshType::PointType &) { return true; };
  auto          holed = itk::VoxelizationTest::SelectTriangles(
    sphere.GetPointer(), [](const MeshType::PointType & p) { return !(p[2] > 4.0 || (p[0] > 3.0 && p[1] > 1.0)); });
  auto inverted = itk::VoxelizationTest::SelectTriangles(sphere.GetPointer(), all, true);
  // Half the triangles wound the other way: inconsistent orientation (they cancel, see the class doc).
  auto mixed = itk::VoxelizationTest::SelectTriangles(sphere.GetPointer(), all, false);
  {
    unsigned int flip = 0;
    for (auto it = mixed->GetCells()->Begin(); it != mixed->GetCells()->End(); ++it)
    {
      if (mixed->GetPoint(it.Value()->PointIdsBegin()[0])[0] > 2.0)
      {
        const auto first = it.Value()->PointIdsBegin()[1];
        it.Value()->SetPointId(1, it.Value()->PointIdsBegin()[2]);
        it.Value()->SetPointId(2, first);
        ++flip;
      }
    }
    std::cout << "Mixed orientation: " << flip << " triangles flipped" << std::endl;
  }
  auto cap = itk::VoxelizationTest::SelectTriangles(
    sphere.GetPointer(), [&centre](const MeshType::PointType & p) { return p[2] >= centre[2]; });
  auto cube = MakeCube(3.0, false);
  auto openCube = MakeCube(3.0, true);
  auto twoSpheres = MakeTwoSpheres();

  struct Case
  {
    std::string       name;
    MeshType::Pointer mesh;
    Grid              grid;
  };
  std::vector<Case> cases;
  cases.push_back({ "closed sphere", sphere, GridAround(sphere, 0.7, 2.0) });
  cases.push_back({ "holed sphere", holed, GridAround(holed, 0.7, 2.0) });
  cases.push_back({ "inverted sphere", inverted, GridAround(inverted, 0.7, 2.0) });
  cases.push_back({ "inconsistently oriented sphere", mixed, GridAround(mixed, 0.7, 2.0) });
  cases.push_back({ "open hemisphere", cap, GridAround(cap, 0.6, 3.0) });
  cases.push_back({ "two overlapping spheres", twoSpheres, GridAround(twoSpheres, 0.8, 2.0) });
  // Rows and voxel centres exactly on faces, edges and vertices: ties everywhere.
  Grid tied;
  tied.spacing.Fill(0.5);
  tied.origin.Fill(-4.0);
  tied.size.Fill(17);
  tied.direction.SetIdentity();
  cases.push_back({ "cube, grid on its faces and edges", cube, tied });
  cases.push_back({ "open cube, grid on its faces and edges", openCube, tied });
  // A rotated, anisotropic grid (solid and exact distance run by scan lines, the band per voxel).
  Grid rotated = GridAround(sphere, 0.8, 2.0);
  rotated.spacing[1] = 0.65;
  rotated.spacing[2] = 0.9;
  const double angle = 0.4;
  rotated.direction[0][0] = std::cos(angle);
  rotated.direction[0][1] = -std::sin(angle);
  rotated.direction[1][0] = std::sin(angle);
  rotated.direction[1][1] = std::cos(angle);
  cases.push_back({ "holed sphere, rotated anisotropic grid", holed, rotated });
  // An anisotropic axis-aligned grid (every mode by scan lines).
  Grid anisotropic = GridAround(holed, 0.8, 2.0);
  anisotropic.spacing[0] = 0.55;
  anisotropic.spacing[2] = 0.95;
  cases.push_back({ "holed sphere, anisotropic grid", holed, anisotropic });

  struct Setting
  {
    std::string                       name;
    std::function<void(FilterType *)> setup;
  };
  const std::vector<Setting> settings = {
    { "occupancy", [](FilterType * f) { f->SetMode(ModeEnum::Occupancy); } },
    { "occupancy 1.3",
      [](FilterType * f) {
        f->SetMode(ModeEnum::Occupancy);
        f->SetOccupancyDistance(1.3);
      } },
    { "solid", [](FilterType * f) { f->SetMode(ModeEnum::Solid); } },
    { "solid w > 1/2",
      [](FilterType * f) {
        f->SetMode(ModeEnum::Solid);
        f->AbsoluteWindingNumberOff();
      } },
    { "solid exact winding number",
      [](FilterType * f) {
        f->SetMode(ModeEnum::Solid);
        f->SetBeta(0.0);
      } },
    { "band mask", [](FilterType * f) { f->SetMode(ModeEnum::BandMask); } },
    { "sdf", [](FilterType * f) { f->SetMode(ModeEnum::SignedDistance); } },
    { "sdf band 1.7",
      [](FilterType * f) {
        f->SetMode(ModeEnum::SignedDistance);
        f->SetBandWidth(1.7);
      } },
    { "sdf unsigned",
      [](FilterType * f) {
        f->SetMode(ModeEnum::SignedDistance);
        f->UnsignedDistanceOn();
      } },
    { "sdf exact",
      [](FilterType * f) {
        f->SetMode(ModeEnum::SignedDistance);
        f->ExactDistanceOn();
      } },
  };

  // With a mask: the masked voxels hold the unmasked image's values, the others the far value, on the scan-line
  // path (1 and 2 threads, streamed) and the reference path. The mask has rows without a voxel, rows with gaps and
  // rows starting at varying voxels.
  const auto makeMask = [](const Grid & grid) {
    auto mask = FilterType::MaskImageType::New();
    mask->SetRegions(FilterType::MaskImageType::RegionType(grid.size));
    mask->SetOrigin(grid.origin);
    mask->SetSpacing(grid.spacing);
    mask->SetDirection(grid.direction);
    mask->Allocate();
    itk::ImageRegionIteratorWithIndex<FilterType::MaskImageType> it(mask, mask->GetLargestPossibleRegion());
    for (; !it.IsAtEnd(); ++it)
    {
      const auto & index = it.GetIndex();
      const bool   emptyRow = (index[1] + index[2]) % 5 == 0;
      const bool   gap = (index[0] * 7919 + index[1] * 31 + index[2] * 17) % 3 == 0;
      it.Set(!emptyRow && !gap && index[0] >= (index[1] + index[2]) % 4 ? 1 : 0);
    }
    return mask;
  };
  auto maskSettings = settings;
  maskSettings.erase(maskSettings.end() - 1); // Not with the exact distance (refused).
  maskSettings.push_back({ "winding number", [](FilterType * f) { f->SetMode(ModeEnum::WindingNumber); } });
  for (const auto & testCase : cases)
  {
    const auto mask = makeMask(testCase.grid);
    for (const auto & setting : maskSettings)
    {
      const auto unmasked = Voxelize(testCase.mesh, testCase.grid, setting.setup, true, 2, 1);
      auto       probe = FilterType::New();
      setting.setup(probe);
      const bool  distance = probe->GetMode() == ModeEnum::SignedDistance;
      const float band =
        probe->GetBandWidth() < 0.0
          ? static_cast<float>(
              3.0 * std::max({ testCase.grid.spacing[0], testCase.grid.spacing[1], testCase.grid.spacing[2] }))
          : static_cast<float>(probe->GetBandWidth());
      const float farValue = distance ? band : 0.0f;
      auto        expected = RealImageType::New();
      expected->CopyInformation(unmasked);
      expected->SetRegions(unmasked->GetLargestPossibleRegion());
      expected->Allocate();
      size_t masked = 0;
      for (size_t i = 0; i < unmasked->GetLargestPossibleRegion().GetNumberOfPixels(); ++i)
      {
        const bool in = mask->GetBufferPointer()[i] != 0;
        masked += in ? 1 : 0;
        expected->GetBufferPointer()[i] = in ? unmasked->GetBufferPointer()[i] : farValue;
      }
      const auto withMask = [&mask, &setting](FilterType * f) {
        setting.setup(f);
        f->SetMaskImage(mask);
      };
      size_t differences = 0;
      differences += CountDifferences(expected, Voxelize(testCase.mesh, testCase.grid, withMask, true, 2, 1));
      differences += CountDifferences(expected, Voxelize(testCase.mesh, testCase.grid, withMask, true, 1, 1));
      differences += CountDifferences(expected, Voxelize(testCase.mesh, testCase.grid, withMask, true, 2, 7));
      differences += CountDifferences(expected, Voxelize(testCase.mesh, testCase.grid, withMask, false, 2, 1));
      std::cout << testCase.name << ", " << setting.name << ", masked (" << masked << " of "
                << unmasked->GetLargestPossibleRegion().GetNumberOfPixels() << " voxels): differences " << differences
                << std::endl;
      if (differences != 0 || masked == 0)
      {
        status = EXIT_FAILURE;
      }
    }
  }

  for (const auto & testCase : cases)
  {
    for (const auto & setting : settings)
    {
      const auto   reference = Voxelize(testCase.mesh, testCase.grid, setting.setup, false, 2, 1);
      const auto   fast = Voxelize(testCase.mesh, testCase.grid, setting.setup, true, 2, 1);
      const auto   single = Voxelize(testCase.mesh, testCase.grid, setting.setup, true, 1, 1);
      const auto   streamed = Voxelize(testCase.mesh, testCase.grid, setting.setup, true, 2, 7);
      const size_t differences = CountDifferences(reference, fast);
      const size_t threadDifferences = CountDifferences(fast, single);
      const size_t streamDifferences = CountDifferences(fast, streamed);
      std::cout << testCase.name << ", " << setting.name << ": " << testCase.grid.size << ", differences from the "
                << "reference path " << differences << ", 1 vs 2 threads " << threadDifferences << ", streamed "
                << streamDifferences << std::endl;
      if (differences != 0 || threadDifferences != 0 || streamDifferences != 0)
      {
        status = EXIT_FAILURE;
      }
    }
  }
  std::cout << (status == EXIT_SUCCESS ? "Test finished." : "Test FAILED.") << std::endl;
  return status;
}
