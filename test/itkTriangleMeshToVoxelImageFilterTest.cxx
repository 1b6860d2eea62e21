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
// Every mode of TriangleMeshToVoxelImageFilter checked voxel by voxel against brute force over all
// triangles: a polyhedral sphere (closed), an open hemisphere (documented open-patch result), a cube
// of quadrilaterals and polygons with degenerate and lower-dimensional cells, an inside-out sphere.

#include "itkTriangleMeshToVoxelImageFilter.h"
#include "itkTriangleMeshToVoxelImageFilterTestHelpers.h"

#include "itkImageRegionConstIteratorWithIndex.h"
#include "itkLineCell.h"
#include "itkPolygonCell.h"
#include "itkQuadrilateralCell.h"
#include "itkTestingMacros.h"
#include "itkVertexCell.h"

#include <cstring>

namespace
{
using MeshType = itk::Mesh<double, 3>;
using MaskImageType = itk::Image<unsigned char, 3>;
using RealImageType = itk::Image<float, 3>;
using MaskFilterType = itk::TriangleMeshToVoxelImageFilter<MeshType, MaskImageType>;
using RealFilterType = itk::TriangleMeshToVoxelImageFilter<MeshType, RealImageType>;
using ModeEnum = itk::TriangleMeshToVoxelImageFilterEnums::Mode;
using itk::VoxelizationTest::Vector3;

template <typename TImage>
Vector3
VoxelCentre(const TImage * image, const typename TImage::IndexType & index)
{
  typename TImage::PointType point;
  image->TransformIndexToPhysicalPoint(index, point);
  return Vector3{ point[0], point[1], point[2] };
}

// Brute-force references of every voxel of a grid.
struct Reference
{
  std::vector<double> distance;
  std::vector<double> winding;
  std::vector<bool>   insideByParity;
};

template <typename TImage>
Reference
ComputeReference(const TImage * image, const std::vector<itk::VoxelizationTest::Triangle> & triangles, bool parity)
{
  Reference                                      reference;
  itk::ImageRegionConstIteratorWithIndex<TImage> it(image, image->GetLargestPossibleRegion());
  for (; !it.IsAtEnd(); ++it)
  {
    const Vector3 q = VoxelCentre(image, it.GetIndex());
    reference.distance.push_back(itk::VoxelizationTest::BruteForceDistance(q, triangles));
    reference.winding.push_back(itk::VoxelizationTest::BruteForceWindingNumber(q, triangles));
    reference.insideByParity.push_back(parity && itk::VoxelizationTest::BruteForceInsideByParity(q, triangles));
  }
  return reference;
}

template <typename TImage>
std::vector<typename TImage::PixelType>
ToVector(const TImage * image)
{
  std::vector<typename TImage::PixelType>        values;
  itk::ImageRegionConstIteratorWithIndex<TImage> it(image, image->GetLargestPossibleRegion());
  for (; !it.IsAtEnd(); ++it)
  {
    values.push_back(it.Get());
  }
  return values;
}

// Closed sphere: every mode against brute force on a rotated, anisotropic reference grid.
int
TestClosedSphere()
{
  int           status = EXIT_SUCCESS;
  const Vector3 centre{ 0.3, -0.2, 0.1 };
  const double  radius = 10.0;
  auto          sphere = itk::VoxelizationTest::MakeSphere<MeshType>(4, radius, centre);
  const auto    triangles = itk::VoxelizationTest::ExtractTriangles(sphere.GetPointer());
  ITK_TEST_EXPECT_EQUAL(triangles.size(), 2048u);

  // A reference image (never allocated) with a rotated direction and anisotropic spacing, centred on the sphere.
  auto                       reference = RealImageType::New();
  RealImageType::SizeType    size = { { 24, 26, 23 } };
  RealImageType::SpacingType spacing;
  spacing[0] = 1.1;
  spacing[1] = 0.95;
  spacing[2] = 1.05;
  RealImageType::DirectionType direction;
  const double                 angle = 0.5;
  direction.SetIdentity();
  direction[0][0] = std::cos(angle);
  direction[0][1] = -std::sin(angle);
  direction[1][0] = std::sin(angle);
  direction[1][1] = std::cos(angle);
  RealImageType::PointType origin;
  for (unsigned int i = 0; i < 3; ++i)
  {
    origin[i] = centre[i];
    for (unsigned int j = 0; j < 3; ++j)
    {
      origin[i] -= direction[i][j] * 0.5 * (size[j] - 1) * spacing[j];
    }
  }
  reference->SetRegions(size);
  reference->SetSpacing(spacing);
  reference->SetOrigin(origin);
  reference->SetDirection(direction);

  auto realFilter = RealFilterType::New();
  realFilter->SetInput(sphere);
  realFilter->SetReferenceImage(reference);
  // Geometry is known before any data is generated.
  ITK_TRY_EXPECT_NO_EXCEPTION(realFilter->UpdateOutputInformation());
  ITK_TEST_EXPECT_EQUAL(realFilter->GetOutput()->GetLargestPossibleRegion(), reference->GetLargestPossibleRegion());
  ITK_TEST_EXPECT_EQUAL(realFilter->GetOutput()->GetSpacing(), spacing);
  ITK_TEST_EXPECT_EQUAL(realFilter->GetOutput()->GetOrigin(), origin);
  ITK_TEST_EXPECT_EQUAL(realFilter->GetOutput()->GetDirection(), direction);
  ITK_TEST_EXPECT_EQUAL(reference->GetBufferPointer(), static_cast<float *>(nullptr));

  const Reference ref = ComputeReference(reference.GetPointer(), triangles, true);
  const double    halfDiagonal = 0.5 * spacing.GetNorm();
  const double    band = 3.0 * 1.1; // default: three times the largest spacing

  // Winding number: beta = 0 is the exact sum; beta = 2 the fast approximation.
  realFilter->SetMode(ModeEnum::WindingNumber);
  realFilter->SetBeta(0.0);
  ITK_TRY_EXPECT_NO_EXCEPTION(realFilter->Update());
  const auto exactWinding = ToVector(realFilter->GetOutput());
  realFilter->SetBeta(2.0);
  ITK_TRY_EXPECT_NO_EXCEPTION(realFilter->Update());
  const auto fastWinding = ToVector(realFilter->GetOutput());
  double     maxExactError = 0.0;
  double     maxFastError = 0.0;
  for (size_t i = 0; i < ref.winding.size(); ++i)
  {
    maxExactError = std::max(maxExactError, std::abs(exactWinding[i] - ref.winding[i]));
    if (ref.distance[i] > 0.25)
    {
      maxFastError = std::max(maxFastError, std::abs(fastWinding[i] - ref.winding[i]));
    }
  }
  std::cout << "Sphere winding number: max error exact " << maxExactError << ", beta=2 " << maxFastError << std::endl;
  ITK_TEST_EXPECT_TRUE(maxExactError < 1e-5);
  ITK_TEST_EXPECT_TRUE(maxFastError < 0.1);
  // A larger beta opens more clusters: more accurate.
  realFilter->SetBeta(4.0);
  ITK_TRY_EXPECT_NO_EXCEPTION(realFilter->Update());
  const auto accurateWinding = ToVector(realFilter->GetOutput());
  double     maxAccurateError = 0.0;
  for (size_t i = 0; i < ref.winding.size(); ++i)
  {
    maxAccurateError = std::max(maxAccurateError, std::abs(accurateWinding[i] - ref.winding[i]));
  }
  std::cout << "Sphere winding number: max error beta=4 " << maxAccurateError << std::endl;
  ITK_TEST_EXPECT_TRUE(maxAccurateError < 0.025);
  realFilter->SetBeta(2.0);

  // Signed distance in the band (clamped beyond), then exact everywhere.
  realFilter->SetMode(ModeEnum::SignedDistance);
  ITK_TRY_EXPECT_NO_EXCEPTION(realFilter->Update());
  const auto banded = ToVector(realFilter->GetOutput());
  realFilter->ExactDistanceOn();
  ITK_TRY_EXPECT_NO_EXCEPTION(realFilter->Update());
  const auto exact = ToVector(realFilter->GetOutput());
  realFilter->ExactDistanceOff();
  realFilter->UnsignedDistanceOn();
  ITK_TRY_EXPECT_NO_EXCEPTION(realFilter->Update());
  const auto unsignedDistance = ToVector(realFilter->GetOutput());
  realFilter->UnsignedDistanceOff();

  size_t mismatches = 0;
  size_t insideCount = 0;
  double maxDistanceError = 0.0;
  for (size_t i = 0; i < ref.distance.size(); ++i)
  {
    const double d = ref.distance[i];
    const double sign = ref.insideByParity[i] ? -1.0 : 1.0;
    insideCount += ref.insideByParity[i];
    const double bandExpected = d < band ? sign * d : sign * band;
    if (std::abs(d - band) > 1e-6 && d > 1e-6)
    {
      maxDistanceError = std::max(maxDistanceError, std::abs(banded[i] - bandExpected));
      maxDistanceError = std::max(maxDistanceError, std::abs(exact[i] - sign * d));
    }
    maxDistanceError = std::max(maxDistanceError, std::abs(unsignedDistance[i] - std::min(d, band)));
  }
  std::cout << "Sphere signed distance: max error " << maxDistanceError << ", inside voxels " << insideCount << " of "
            << ref.distance.size() << std::endl;
  ITK_TEST_EXPECT_TRUE(maxDistanceError < 1e-4);
  ITK_TEST_EXPECT_TRUE(insideCount > 1000);

  // Binary modes.
  auto maskFilter = MaskFilterType::New();
  maskFilter->SetInput(sphere);
  maskFilter->SetReferenceImage(reference);
  maskFilter->SetInsideValue(200);
  maskFilter->SetOutsideValue(7);
  const std::pair<ModeEnum, const char *> modes[] = { { ModeEnum::Occupancy, "Occupancy" },
                                                      { ModeEnum::Solid, "Solid" },
                                                      { ModeEnum::BandMask, "BandMask" } };
  for (const auto & mode : modes)
  {
    maskFilter->SetMode(mode.first);
    ITK_TRY_EXPECT_NO_EXCEPTION(maskFilter->Update());
    const auto values = ToVector(maskFilter->GetOutput());
    mismatches = 0;
    size_t compared = 0;
    size_t marked = 0;
    for (size_t i = 0; i < values.size(); ++i)
    {
      const double d = ref.distance[i];
      bool         expected = false;
      bool         tie = false;
      switch (mode.first)
      {
        case ModeEnum::Occupancy:
          expected = d <= halfDiagonal;
          tie = std::abs(d - halfDiagonal) < 1e-9;
          break;
        case ModeEnum::BandMask:
          expected = d <= band;
          tie = std::abs(d - band) < 1e-9;
          break;
        default:
          expected = ref.insideByParity[i];
          tie = d < 1e-3;
          break;
      }
      if (values[i] != 200 && values[i] != 7)
      {
        ++mismatches;
      }
      if (!tie)
      {
        ++compared;
        marked += expected;
        mismatches += (values[i] == 200) != expected;
      }
    }
    std::cout << mode.second << ": " << marked << " of " << compared << " compared voxels marked, " << mismatches
              << " mismatches" << std::endl;
    ITK_TEST_EXPECT_EQUAL(mismatches, 0u);
    ITK_TEST_EXPECT_TRUE(marked > 100);
  }

  // Occupancy with a given distance.
  maskFilter->SetMode(ModeEnum::Occupancy);
  maskFilter->SetOccupancyDistance(1.7);
  ITK_TRY_EXPECT_NO_EXCEPTION(maskFilter->Update());
  const auto occupancy = ToVector(maskFilter->GetOutput());
  mismatches = 0;
  for (size_t i = 0; i < occupancy.size(); ++i)
  {
    if (std::abs(ref.distance[i] - 1.7) > 1e-9)
    {
      mismatches += (occupancy[i] == 200) != (ref.distance[i] <= 1.7);
    }
  }
  ITK_TEST_EXPECT_EQUAL(mismatches, 0u);
  return status;
}

// Open hemisphere: the documented result is the half ball bounded by the cap and its rim plane.
int
TestOpenHemisphere()
{
  const double radius = 10.0;
  auto         sphere = itk::VoxelizationTest::MakeSphere<MeshType>(4, radius, Vector3{ 0.0, 0.0, 0.0 });
  auto         cap = itk::VoxelizationTest::SelectTriangles(sphere.GetPointer(),
                                                    [](const MeshType::PointType & p) { return p[2] >= -1e-9; });
  const auto   triangles = itk::VoxelizationTest::ExtractTriangles(cap.GetPointer());
  ITK_TEST_EXPECT_EQUAL(triangles.size(), 1024u);
  double inscribedRadius = itk::VoxelizationTest::BruteForceDistance(Vector3{ 0.0, 0.0, 0.0 }, triangles);
  std::cout << "Hemisphere inscribed radius " << inscribedRadius << std::endl;

  auto filter = MaskFilterType::New();
  filter->SetInput(cap);
  MaskFilterType::SizeType  size = { { 25, 25, 25 } };
  MaskFilterType::PointType origin;
  origin.Fill(-12.0);
  MaskFilterType::SpacingType spacing;
  spacing.Fill(1.0);
  filter->SetSize(size);
  filter->SetOrigin(origin);
  filter->SetSpacing(spacing);
  filter->SetMode(ModeEnum::Solid);
  ITK_TRY_EXPECT_NO_EXCEPTION(filter->Update());
  const MaskImageType * output = filter->GetOutput();

  size_t                                                geometricMismatches = 0;
  size_t                                                windingMismatches = 0;
  size_t                                                inside = 0;
  itk::ImageRegionConstIteratorWithIndex<MaskImageType> it(output, output->GetLargestPossibleRegion());
  for (; !it.IsAtEnd(); ++it)
  {
    const Vector3 q = VoxelCentre(output, it.GetIndex());
    const double  r = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2]);
    const bool    marked = it.Get() == 1;
    inside += marked;
    if ((q[2] > 0.05 && r < inscribedRadius - 0.05 && !marked) || ((q[2] < -0.05 || r > radius + 0.05) && marked))
    {
      ++geometricMismatches;
    }
    const double w = itk::VoxelizationTest::BruteForceWindingNumber(q, triangles);
    if (std::abs(std::abs(w) - 0.5) > 1e-3 && (std::abs(w) > 0.5) != marked)
    {
      ++windingMismatches;
    }
  }
  std::cout << "Open hemisphere: " << inside << " voxels inside, mismatches geometric " << geometricMismatches
            << " winding " << windingMismatches << std::endl;
  ITK_TEST_EXPECT_EQUAL(geometricMismatches, 0u);
  ITK_TEST_EXPECT_EQUAL(windingMismatches, 0u);
  ITK_TEST_EXPECT_TRUE(inside > 1000);

  // At the centre of the rim the cap covers exactly half the view: w = 1/2.
  auto realFilter = RealFilterType::New();
  realFilter->SetInput(cap);
  realFilter->SetSize(size);
  realFilter->SetOrigin(origin);
  realFilter->SetSpacing(spacing);
  realFilter->SetMode(ModeEnum::WindingNumber);
  realFilter->SetBeta(0.0);
  ITK_TRY_EXPECT_NO_EXCEPTION(realFilter->Update());
  MaskImageType::IndexType centreIndex = { { 12, 12, 12 } };
  std::cout << "Winding number at the rim centre " << realFilter->GetOutput()->GetPixel(centreIndex) << std::endl;
  ITK_TEST_EXPECT_TRUE(std::abs(std::abs(realFilter->GetOutput()->GetPixel(centreIndex)) - 0.5) < 1e-4);

  // Unsigned distance of the open patch equals the brute-force distance.
  realFilter->SetMode(ModeEnum::SignedDistance);
  realFilter->UnsignedDistanceOn();
  realFilter->ExactDistanceOn();
  ITK_TRY_EXPECT_NO_EXCEPTION(realFilter->Update());
  double                                                maxError = 0.0;
  itk::ImageRegionConstIteratorWithIndex<RealImageType> rit(realFilter->GetOutput(),
                                                            realFilter->GetOutput()->GetLargestPossibleRegion());
  for (; !rit.IsAtEnd(); ++rit)
  {
    const Vector3 q = VoxelCentre(realFilter->GetOutput(), rit.GetIndex());
    maxError = std::max(maxError, std::abs(rit.Get() - itk::VoxelizationTest::BruteForceDistance(q, triangles)));
  }
  ITK_TEST_EXPECT_TRUE(maxError < 1e-4);
  return EXIT_SUCCESS;
}

// Cube made of quadrilaterals and polygons, with degenerate, vertex and line cells: analytic answers,
// and identical to the same cube given as triangles.
int
TestCubeOfPolygons()
{
  using CellType = MeshType::CellType;
  using CellAutoPointer = MeshType::CellAutoPointer;
  const double half = 4.0;
  auto         polygons = MeshType::New();
  auto         triangles = MeshType::New();
  for (unsigned int i = 0; i < 8; ++i)
  {
    MeshType::PointType p;
    p[0] = (i & 1) ? half : -half;
    p[1] = (i & 2) ? half : -half;
    p[2] = (i & 4) ? half : -half;
    polygons->SetPoint(i, p);
    triangles->SetPoint(i, p);
  }
  // Outward quads (counter-clockwise seen from outside).
  const unsigned int       quads[6][4] = { { 0, 2, 3, 1 }, { 4, 5, 7, 6 }, { 0, 1, 5, 4 },
                                           { 2, 6, 7, 3 }, { 0, 4, 6, 2 }, { 1, 3, 7, 5 } };
  MeshType::CellIdentifier polygonCellId = 0;
  MeshType::CellIdentifier triangleCellId = 0;
  for (unsigned int f = 0; f < 6; ++f)
  {
    CellAutoPointer cell;
    if (f % 2 == 0)
    {
      cell.TakeOwnership(new itk::QuadrilateralCell<CellType>);
      for (unsigned int k = 0; k < 4; ++k)
      {
        cell->SetPointId(k, quads[f][k]);
      }
    }
    else
    {
      auto * polygon = new itk::PolygonCell<CellType>;
      for (unsigned int k = 0; k < 4; ++k)
      {
        polygon->AddPointId(quads[f][k]);
      }
      cell.TakeOwnership(polygon);
    }
    polygons->SetCell(polygonCellId++, cell);
    for (unsigned int t = 0; t < 2; ++t)
    {
      CellAutoPointer triangle;
      triangle.TakeOwnership(new itk::TriangleCell<CellType>);
      triangle->SetPointId(0, quads[f][0]);
      triangle->SetPointId(1, quads[f][1 + t]);
      triangle->SetPointId(2, quads[f][2 + t]);
      triangles->SetCell(triangleCellId++, triangle);
    }
  }
  // Degenerate triangles: a repeated vertex, and three collinear points.
  MeshType::PointType middle;
  middle[0] = 0.0;
  middle[1] = -half;
  middle[2] = -half;
  polygons->SetPoint(8, middle);
  const unsigned int degenerate[2][3] = { { 0, 0, 5 }, { 0, 8, 1 } };
  for (const auto & ids : degenerate)
  {
    CellAutoPointer cell;
    cell.TakeOwnership(new itk::TriangleCell<CellType>);
    for (unsigned int k = 0; k < 3; ++k)
    {
      cell->SetPointId(k, ids[k]);
    }
    polygons->SetCell(polygonCellId++, cell);
  }
  CellAutoPointer vertex;
  vertex.TakeOwnership(new itk::VertexCell<CellType>);
  vertex->SetPointId(0, 3);
  polygons->SetCell(polygonCellId++, vertex);
  CellAutoPointer line;
  line.TakeOwnership(new itk::LineCell<CellType>);
  line->SetPointId(0, 3);
  line->SetPointId(1, 6);
  polygons->SetCell(polygonCellId++, line);

  auto polygonFilter = MaskFilterType::New();
  auto triangleFilter = MaskFilterType::New();
  polygonFilter->SetInput(polygons);
  triangleFilter->SetInput(triangles);
  MaskFilterType::SpacingType spacing;
  spacing.Fill(1.0);
  // Margin 1.6 around [-4, 4]: ceil(11.2) = 12 voxels of size 1, centres at -5.5, ..., 5.5, never on a face.
  ITK_TRY_EXPECT_NO_EXCEPTION(polygonFilter->SetGeometryFromMeshBounds(spacing, 1.6));
  MaskFilterType::SizeType expectedSize = { { 12, 12, 12 } };
  ITK_TEST_EXPECT_EQUAL(polygonFilter->GetSize(), expectedSize);
  ITK_TEST_EXPECT_TRUE(std::abs(polygonFilter->GetOrigin()[0] + 5.5) < 1e-12);
  triangleFilter->SetSize(polygonFilter->GetSize());
  triangleFilter->SetOrigin(polygonFilter->GetOrigin());
  triangleFilter->SetSpacing(spacing);
  // Half the voxel diagonal would tie at the corners (distance sqrt(3) / 2 exactly).
  polygonFilter->SetOccupancyDistance(0.8);
  triangleFilter->SetOccupancyDistance(0.8);

  for (const auto mode : { ModeEnum::Solid, ModeEnum::Occupancy })
  {
    polygonFilter->SetMode(mode);
    triangleFilter->SetMode(mode);
    ITK_TRY_EXPECT_NO_EXCEPTION(polygonFilter->Update());
    ITK_TRY_EXPECT_NO_EXCEPTION(triangleFilter->Update());
    ITK_TEST_EXPECT_EQUAL(polygonFilter->GetNumberOfTriangles(), 12u);
    ITK_TEST_EXPECT_EQUAL(polygonFilter->GetNumberOfDegenerateTriangles(), 2u);
    ITK_TEST_EXPECT_EQUAL(triangleFilter->GetNumberOfDegenerateTriangles(), 0u);
    const auto fromPolygons = ToVector(polygonFilter->GetOutput());
    ITK_TEST_EXPECT_TRUE(fromPolygons == ToVector(triangleFilter->GetOutput()));
    size_t                                                mismatches = 0;
    itk::ImageRegionConstIteratorWithIndex<MaskImageType> it(polygonFilter->GetOutput(),
                                                             polygonFilter->GetOutput()->GetLargestPossibleRegion());
    for (; !it.IsAtEnd(); ++it)
    {
      const Vector3 q = VoxelCentre(polygonFilter->GetOutput(), it.GetIndex());
      const double  maxAbs = std::max({ std::abs(q[0]), std::abs(q[1]), std::abs(q[2]) });
      double        outsideSquared = 0.0;
      for (unsigned int k = 0; k < 3; ++k)
      {
        const double excess = std::max(0.0, std::abs(q[k]) - half);
        outsideSquared += excess * excess;
      }
      const double distance = maxAbs < half ? half - maxAbs : std::sqrt(outsideSquared);
      const bool   expected = mode == ModeEnum::Solid ? maxAbs < half : distance <= 0.8;
      mismatches += (it.Get() == 1) != expected;
    }
    std::cout << "Cube " << mode << ": " << mismatches << " mismatches" << std::endl;
    ITK_TEST_EXPECT_EQUAL(mismatches, 0u);
  }
  return EXIT_SUCCESS;
}

// A sphere wound inside out: same solid with AbsoluteWindingNumber On, empty with Off; float mesh agrees.
int
TestOrientationAndFloatMesh()
{
  const Vector3 centre{ 0.0, 0.0, 0.0 };
  auto          sphere = itk::VoxelizationTest::MakeSphere<MeshType>(3, 5.0, centre);
  auto          all = [](const MeshType::PointType &) { return true; };
  auto          same = itk::VoxelizationTest::SelectTriangles(sphere.GetPointer(), all, false);
  auto          flipped = itk::VoxelizationTest::SelectTriangles(sphere.GetPointer(), all, true);
  const double  w =
    itk::VoxelizationTest::BruteForceWindingNumber(centre, itk::VoxelizationTest::ExtractTriangles(same.GetPointer()));
  std::cout << "Winding number at the sphere centre: " << w << std::endl;
  ITK_TEST_EXPECT_TRUE(std::abs(std::abs(w) - 1.0) < 1e-9);
  auto outward = w > 0 ? same : flipped;
  auto inward = w > 0 ? flipped : same;

  MaskFilterType::SpacingType spacing;
  spacing.Fill(0.7);
  auto a = MaskFilterType::New();
  auto b = MaskFilterType::New();
  a->SetInput(outward);
  b->SetInput(inward);
  a->SetGeometryFromMeshBounds(spacing, 1.0);
  b->SetGeometryFromMeshBounds(spacing, 1.0);
  ITK_TRY_EXPECT_NO_EXCEPTION(a->Update());
  ITK_TRY_EXPECT_NO_EXCEPTION(b->Update());
  const auto solid = ToVector(a->GetOutput());
  ITK_TEST_EXPECT_TRUE(solid == ToVector(b->GetOutput()));
  ITK_TEST_EXPECT_TRUE(std::count(solid.begin(), solid.end(), 1) > 100);
  b->AbsoluteWindingNumberOff();
  ITK_TRY_EXPECT_NO_EXCEPTION(b->Update());
  const auto empty = ToVector(b->GetOutput());
  ITK_TEST_EXPECT_EQUAL(std::count(empty.begin(), empty.end(), 1), 0);
  a->AbsoluteWindingNumberOff();
  ITK_TRY_EXPECT_NO_EXCEPTION(a->Update());
  ITK_TEST_EXPECT_TRUE(solid == ToVector(a->GetOutput()));

  // The same sphere as a float mesh gives the same signed distances up to float rounding.
  using FloatMeshType = itk::Mesh<float, 3>;
  using FloatFilterType = itk::TriangleMeshToVoxelImageFilter<FloatMeshType, RealImageType>;
  auto floatSphere = itk::VoxelizationTest::MakeSphere<FloatMeshType>(3, 5.0, centre);
  auto floatFilter = FloatFilterType::New();
  auto doubleFilter = RealFilterType::New();
  floatFilter->SetInput(floatSphere);
  doubleFilter->SetInput(sphere);
  FloatFilterType::SpacingType floatSpacing;
  floatSpacing.Fill(0.7);
  floatFilter->SetGeometryFromMeshBounds(floatSpacing, 1.0);
  doubleFilter->SetGeometryFromMeshBounds(floatSpacing, 1.0);
  floatFilter->SetMode(ModeEnum::SignedDistance);
  doubleFilter->SetMode(ModeEnum::SignedDistance);
  ITK_TRY_EXPECT_NO_EXCEPTION(floatFilter->Update());
  ITK_TRY_EXPECT_NO_EXCEPTION(doubleFilter->Update());
  const auto fromFloat = ToVector(floatFilter->GetOutput());
  const auto fromDouble = ToVector(doubleFilter->GetOutput());
  ITK_TEST_EXPECT_EQUAL(fromFloat.size(), fromDouble.size());
  double maxDifference = 0.0;
  for (size_t i = 0; i < fromFloat.size(); ++i)
  {
    maxDifference = std::max(maxDifference, static_cast<double>(std::abs(fromFloat[i] - fromDouble[i])));
  }
  ITK_TEST_EXPECT_TRUE(maxDifference < 1e-5);
  return EXIT_SUCCESS;
}
} // namespace

int
itkTriangleMeshToVoxelImageFilterTest(int argc, char * argv[])
{
  if (argc != 1)
  {
    std::cerr << "Usage: " << itkNameOfTestExecutableMacro(argv) << std::endl;
    return EXIT_FAILURE;
  }

  auto filter = MaskFilterType::New();
  ITK_EXERCISE_BASIC_OBJECT_METHODS(filter, TriangleMeshToVoxelImageFilter, ImageSource);

  ITK_TEST_SET_GET_VALUE(ModeEnum::Solid, filter->GetMode());
  filter->SetMode(ModeEnum::Occupancy);
  ITK_TEST_SET_GET_VALUE(ModeEnum::Occupancy, filter->GetMode());
  ITK_TEST_SET_GET_VALUE(1, filter->GetInsideValue());
  filter->SetInsideValue(255);
  ITK_TEST_SET_GET_VALUE(255, filter->GetInsideValue());
  filter->SetOutsideValue(3);
  ITK_TEST_SET_GET_VALUE(3, filter->GetOutsideValue());
  ITK_TEST_SET_GET_VALUE(-1.0, filter->GetOccupancyDistance());
  filter->SetOccupancyDistance(0.25);
  ITK_TEST_SET_GET_VALUE(0.25, filter->GetOccupancyDistance());
  ITK_TEST_SET_GET_VALUE(-1.0, filter->GetBandWidth());
  filter->SetBandWidth(2.5);
  ITK_TEST_SET_GET_VALUE(2.5, filter->GetBandWidth());
  ITK_TEST_SET_GET_VALUE(2.0, filter->GetBeta());
  filter->SetBeta(3.0);
  ITK_TEST_SET_GET_VALUE(3.0, filter->GetBeta());
  ITK_TEST_SET_GET_BOOLEAN(filter, ExactDistance, true);
  ITK_TEST_SET_GET_BOOLEAN(filter, UnsignedDistance, true);
  ITK_TEST_SET_GET_BOOLEAN(filter, AbsoluteWindingNumber, false);
  ITK_TEST_SET_GET_BOOLEAN(filter, ScanLineAcceleration, true);
  filter->SetMaximumNumberOfVoxels(1000);
  ITK_TEST_SET_GET_VALUE(1000u, filter->GetMaximumNumberOfVoxels());
  MaskFilterType::SizeType size = { { 4, 5, 6 } };
  filter->SetSize(size);
  ITK_TEST_SET_GET_VALUE(size, filter->GetSize());
  MaskFilterType::SpacingType spacing;
  spacing.Fill(0.5);
  filter->SetSpacing(spacing);
  ITK_TEST_SET_GET_VALUE(spacing, filter->GetSpacing());
  MaskFilterType::PointType origin;
  origin.Fill(-2.0);
  filter->SetOrigin(origin);
  ITK_TEST_SET_GET_VALUE(origin, filter->GetOrigin());
  MaskFilterType::DirectionType direction;
  direction.SetIdentity();
  direction[0][0] = -1.0;
  filter->SetDirection(direction);
  ITK_TEST_SET_GET_VALUE(direction, filter->GetDirection());
  auto referenceImage = MaskImageType::New();
  filter->SetReferenceImage(referenceImage);
  ITK_TEST_SET_GET_VALUE(referenceImage.GetPointer(), filter->GetReferenceImage());
  filter->SetReferenceImage(nullptr);

  const std::pair<ModeEnum, const char *> modeNames[] = { { ModeEnum::Occupancy, "Occupancy" },
                                                          { ModeEnum::Solid, "Solid" },
                                                          { ModeEnum::SignedDistance, "SignedDistance" },
                                                          { ModeEnum::BandMask, "BandMask" },
                                                          { ModeEnum::WindingNumber, "WindingNumber" } };
  for (const auto & modeName : modeNames)
  {
    std::ostringstream printed;
    printed << modeName.first;
    ITK_TEST_EXPECT_EQUAL(printed.str(),
                          std::string("itk::TriangleMeshToVoxelImageFilterEnums::Mode::") + modeName.second);
  }

  // Progress reaches 1 through the total progress reporter.
  auto sphere = itk::VoxelizationTest::MakeSphere<MeshType>(2, 3.0, Vector3{ 0.0, 0.0, 0.0 });
  auto progressFilter = MaskFilterType::New();
  progressFilter->SetInput(sphere);
  ITK_TEST_EXPECT_EQUAL(progressFilter->GetInput(), sphere.GetPointer());
  progressFilter->SetGeometryFromMeshBounds(spacing, 0.5);
  unsigned int progressEvents = 0;
  progressFilter->AddObserver(itk::ProgressEvent(), [&progressEvents](const itk::EventObject &) { ++progressEvents; });
  ITK_TRY_EXPECT_NO_EXCEPTION(progressFilter->Update());
  ITK_TEST_EXPECT_TRUE(progressEvents > 1);
  ITK_TEST_EXPECT_TRUE(itk::Math::FloatAlmostEqual(progressFilter->GetProgress(), 1.0f));
  std::cout << progressFilter << std::endl;

  int status = EXIT_SUCCESS;
  for (const auto test : { TestClosedSphere, TestOpenHemisphere, TestCubeOfPolygons, TestOrientationAndFloatMesh })
  {
    if (test() != EXIT_SUCCESS)
    {
      status = EXIT_FAILURE;
    }
  }
  std::cout << (status == EXIT_SUCCESS ? "Test finished." : "Test FAILED.") << std::endl;
  return status;
}
