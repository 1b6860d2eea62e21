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

#include "itkMersenneTwisterRandomVariateGenerator.h"
#include "itkMesh.h"
#include "itkMeshSurfaceDistanceCalculator.h"
#include "itkQuadrilateralCell.h"
#include "itkTestingMacros.h"
#include "itkTimeProbe.h"
#include "itkTriangleCell.h"
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <vector>

namespace
{
using MeshTraitsType = itk::DefaultStaticMeshTraits<double, 3, 2, double, double, double>;
using MeshType = itk::Mesh<double, 3, MeshTraitsType>;
using CellType = MeshType::CellType;
using TriangleType = itk::TriangleCell<CellType>;
using QuadrilateralType = itk::QuadrilateralCell<CellType>;
using CalculatorType = itk::MeshSurfaceDistanceCalculator<MeshType>;
using RandomType = itk::Statistics::MersenneTwisterRandomVariateGenerator;
using Vector3 = std::array<double, 3>;

void
AddTriangle(MeshType * mesh, itk::IdentifierType a, itk::IdentifierType b, itk::IdentifierType c)
{
  MeshType::CellAutoPointer cell;
  cell.TakeOwnership(new TriangleType);
  cell->SetPointId(0, a);
  cell->SetPointId(1, b);
  cell->SetPointId(2, c);
  mesh->SetCell(mesh->GetNumberOfCells(), cell);
}

void
AddQuadrilateral(MeshType *          mesh,
                 itk::IdentifierType a,
                 itk::IdentifierType b,
                 itk::IdentifierType c,
                 itk::IdentifierType d)
{
  MeshType::CellAutoPointer cell;
  cell.TakeOwnership(new QuadrilateralType);
  cell->SetPointId(0, a);
  cell->SetPointId(1, b);
  cell->SetPointId(2, c);
  cell->SetPointId(3, d);
  mesh->SetCell(mesh->GetNumberOfCells(), cell);
}

MeshType::PointType
MakePoint(double x, double y, double z)
{
  MeshType::PointType point;
  point[0] = x;
  point[1] = y;
  point[2] = z;
  return point;
}

// Reference point-to-segment and point-to-triangle distances, written independently of the module's
// (plane projection with barycentric coordinates from the 2 x 2 normal equations, else the closest edge).
double
ReferenceSegmentDistance(const Vector3 & p, const Vector3 & a, const Vector3 & b)
{
  Vector3 ab{ b[0] - a[0], b[1] - a[1], b[2] - a[2] };
  double  length2 = ab[0] * ab[0] + ab[1] * ab[1] + ab[2] * ab[2];
  double  t = 0.0;
  if (length2 > 0.0)
  {
    t = ((p[0] - a[0]) * ab[0] + (p[1] - a[1]) * ab[1] + (p[2] - a[2]) * ab[2]) / length2;
    t = std::max(0.0, std::min(1.0, t));
  }
  double squared = 0.0;
  for (unsigned int i = 0; i < 3; ++i)
  {
    const double d = p[i] - (a[i] + t * ab[i]);
    squared += d * d;
  }
  return std::sqrt(squared);
}

double
ReferenceTriangleDistance(const Vector3 & p, const Vector3 & a, const Vector3 & b, const Vector3 & c)
{
  double        best = std::min(ReferenceSegmentDistance(p, a, b),
                         std::min(ReferenceSegmentDistance(p, b, c), ReferenceSegmentDistance(p, c, a)));
  const Vector3 e0{ b[0] - a[0], b[1] - a[1], b[2] - a[2] };
  const Vector3 e1{ c[0] - a[0], c[1] - a[1], c[2] - a[2] };
  const Vector3 w{ p[0] - a[0], p[1] - a[1], p[2] - a[2] };
  const auto    dot = [](const Vector3 & u, const Vector3 & v) { return u[0] * v[0] + u[1] * v[1] + u[2] * v[2]; };
  const double  a00 = dot(e0, e0);
  const double  a01 = dot(e0, e1);
  const double  a11 = dot(e1, e1);
  const double  determinant = a00 * a11 - a01 * a01;
  if (determinant > 1e-12 * a00 * a11 && determinant > 0.0)
  {
    const double s = (a11 * dot(w, e0) - a01 * dot(w, e1)) / determinant;
    const double t = (a00 * dot(w, e1) - a01 * dot(w, e0)) / determinant;
    if (s >= 0.0 && t >= 0.0 && s + t <= 1.0)
    {
      double squared = 0.0;
      for (unsigned int i = 0; i < 3; ++i)
      {
        const double d = p[i] - (a[i] + s * e0[i] + t * e1[i]);
        squared += d * d;
      }
      best = std::min(best, std::sqrt(squared));
    }
  }
  return best;
}

Vector3
ToVector(const MeshType::PointType & point)
{
  return Vector3{ point[0], point[1], point[2] };
}

/** Checks the calculator against brute force (the module's own point-triangle distance, no hierarchy: exact
 * equality) and against the independent reference (1e-9 relative). */
bool
CheckAgainstBruteForce(const MeshType * source, const MeshType * target, const char * label)
{
  auto calculator = CalculatorType::New();
  calculator->SetSourceMesh(source);
  calculator->SetTargetMesh(target);
  calculator->Compute();
  const auto   triangles = CalculatorType::ExtractTriangles(target);
  const auto & distances = calculator->GetDistances();
  double       maximumRelative = 0.0;
  bool         ok = distances.size() == source->GetNumberOfPoints();
  for (itk::IdentifierType i = 0; ok && i < source->GetNumberOfPoints(); ++i)
  {
    const Vector3 p = ToVector(source->GetPoint(i));
    double        bruteForce = std::numeric_limits<double>::infinity();
    double        reference = std::numeric_limits<double>::infinity();
    Vector3       closest;
    for (const auto & t : triangles)
    {
      bruteForce = std::min(bruteForce, itk::detail::ClosestPointOnTriangle(p, t.a, t.b, t.c, closest));
      reference = std::min(reference, ReferenceTriangleDistance(p, t.a, t.b, t.c));
    }
    bruteForce = std::sqrt(bruteForce);
    if (distances[i] != bruteForce)
    {
      std::cerr << label << ": vertex " << i << " hierarchy " << distances[i] << " != brute force " << bruteForce
                << std::endl;
      ok = false;
    }
    const double difference = std::abs(distances[i] - reference);
    if (reference > 1e-9)
    {
      maximumRelative = std::max(maximumRelative, difference / reference);
    }
    if (difference > 1e-9 * reference + 1e-12)
    {
      std::cerr << label << ": vertex " << i << " distance " << distances[i] << " != reference " << reference
                << std::endl;
      ok = false;
    }
  }
  std::cout << label << ": " << source->GetNumberOfPoints() << " vertices, " << triangles.size()
            << " triangles, largest relative difference to the reference " << maximumRelative << std::endl;
  return ok;
}

/** The hierarchy built with boxes only (as the calculator builds it) is the same tree as with the winding number's
 * far-field terms: the same triangle order, nodes and distances; its WindingNumber() refuses. */
bool
CheckDistanceOnlyHierarchy(const MeshType * target)
{
  using HierarchyType = itk::detail::TriangleBoundingVolumeHierarchy;
  HierarchyType full;
  HierarchyType boxes;
  full.Build(CalculatorType::ExtractTriangles(target));
  boxes.Build(CalculatorType::ExtractTriangles(target), 4, false);
  bool ok =
    full.GetNumberOfNodes() == boxes.GetNumberOfNodes() && full.GetTriangles().size() == boxes.GetTriangles().size();
  for (size_t i = 0; ok && i < full.GetTriangles().size(); ++i)
  {
    ok = full.GetTriangles()[i].a == boxes.GetTriangles()[i].a && full.GetTriangles()[i].c == boxes.GetTriangles()[i].c;
  }
  for (int q = -20; ok && q <= 20; ++q)
  {
    const HierarchyType::VectorType point{ { 2.0 * q, 1.5 * q - 3.0, 0.7 * q } };
    ok = full.SquaredDistance(point) == boxes.SquaredDistance(point);
  }
  bool refused = false;
  try
  {
    boxes.WindingNumber(HierarchyType::VectorType{ { 0.0, 0.0, 0.0 } }, 2.0);
  }
  catch (const std::logic_error &)
  {
    refused = true;
  }
  std::cout << "distance-only hierarchy: " << boxes.GetNumberOfNodes() << " nodes, the same tree and distances: " << ok
            << ", winding number refused: " << refused << std::endl;
  return ok && refused;
}

/** The hierarchy reserves its nodes once: for every number of triangles up to 300 and leaf sizes 1-8, the tree
 * built (median splits) has no more nodes than Build() reserves, 2 floor(n / max(1, floor((leafSize + 1) / 2))) + 1,
 * so it never moves them while it grows. The triangles lie along a line, in shuffled order. */
bool
CheckHierarchyNodeBound()
{
  using HierarchyType = itk::detail::TriangleBoundingVolumeHierarchy;
  bool          ok = true;
  std::size_t   largestRatioCount = 0;
  double        largestRatio = 0.0;
  std::uint32_t state = 12345u;
  for (std::size_t count = 1; count <= 300 && ok; ++count)
  {
    std::vector<HierarchyType::Triangle> triangles;
    for (std::size_t t = 0; t < count; ++t)
    {
      state = state * 1664525u + 1013904223u;
      const double x = static_cast<double>(state % 1000u);
      triangles.push_back(
        HierarchyType::Triangle{ { { x, 0.0, 0.0 } }, { { x + 1.0, 0.0, 0.0 } }, { { x, 1.0, 0.0 } } });
    }
    for (unsigned int leafSize = 1; leafSize <= 8 && ok; ++leafSize)
    {
      HierarchyType hierarchy;
      hierarchy.Build(triangles, leafSize, false);
      const std::size_t fewestPerLeaf = std::max<std::size_t>(1, (leafSize + 1) / 2);
      const std::size_t bound = 2 * (count / fewestPerLeaf) + 1;
      if (hierarchy.GetNumberOfNodes() > bound)
      {
        std::cerr << count << " triangles, leaf size " << leafSize << ": " << hierarchy.GetNumberOfNodes()
                  << " nodes, more than the " << bound << " reserved" << std::endl;
        ok = false;
      }
      const double ratio = static_cast<double>(hierarchy.GetNumberOfNodes()) / static_cast<double>(bound);
      if (count > leafSize && ratio > largestRatio)
      {
        largestRatio = ratio;
        largestRatioCount = count;
      }
    }
  }
  std::cout << "hierarchy nodes within the reserved bound: " << ok << " (largest share of it used by a split tree "
            << largestRatio << ", at " << largestRatioCount << " triangles)" << std::endl;
  return ok;
}

/** A torus (major radius R, minor radius r) of nu x nv quads split into triangles, radially perturbed. */
MeshType::Pointer
MakeTorus(unsigned int nu, unsigned int nv, double perturbation, double shift)
{
  auto         mesh = MeshType::New();
  const double pi = 3.14159265358979323846;
  for (unsigned int i = 0; i < nu; ++i)
  {
    for (unsigned int j = 0; j < nv; ++j)
    {
      const double u = 2.0 * pi * i / nu;
      const double v = 2.0 * pi * j / nv;
      const double r = 10.0 + perturbation * std::sin(3.0 * u) * std::sin(2.0 * v);
      mesh->SetPoint(i * nv + j,
                     MakePoint((30.0 + r * std::cos(v)) * std::cos(u) + shift,
                               (30.0 + r * std::cos(v)) * std::sin(u),
                               r * std::sin(v) + 0.5 * shift));
    }
  }
  for (unsigned int i = 0; i < nu; ++i)
  {
    for (unsigned int j = 0; j < nv; ++j)
    {
      const itk::IdentifierType a = i * nv + j;
      const itk::IdentifierType b = ((i + 1) % nu) * nv + j;
      const itk::IdentifierType c = ((i + 1) % nu) * nv + (j + 1) % nv;
      const itk::IdentifierType d = i * nv + (j + 1) % nv;
      AddTriangle(mesh, a, b, c);
      AddTriangle(mesh, a, c, d);
    }
  }
  return mesh;
}
} // namespace

int
itkMeshSurfaceDistanceCalculatorTest(int argc, char * argv[])
{
  if (argc != 1)
  {
    std::cerr << "Usage: " << itkNameOfTestExecutableMacro(argv) << std::endl;
    return EXIT_FAILURE;
  }
  int testStatus = EXIT_SUCCESS;

  auto calculator = CalculatorType::New();
  ITK_EXERCISE_BASIC_OBJECT_METHODS(calculator, MeshSurfaceDistanceCalculator, Object);
  ITK_TEST_SET_GET_VALUE(2u, (calculator->SetNumberOfWorkUnits(2), calculator->GetNumberOfWorkUnits()));
  calculator->SetNumberOfWorkUnits(0);

  // Missing inputs, empty target.
  ITK_TRY_EXPECT_EXCEPTION(calculator->Compute());
  auto pointsOnly = MeshType::New();
  pointsOnly->SetPoint(0, MakePoint(0, 0, 0));
  calculator->SetSourceMesh(pointsOnly);
  calculator->SetTargetMesh(pointsOnly);
  ITK_TEST_SET_GET_VALUE(pointsOnly.GetPointer(), calculator->GetSourceMesh());
  ITK_TEST_SET_GET_VALUE(pointsOnly.GetPointer(), calculator->GetTargetMesh());
  ITK_TRY_EXPECT_EXCEPTION(calculator->Compute());

  // 1. Random small meshes with degenerate triangles, query points on vertices, edges and faces.
  {
    auto random = RandomType::New();
    random->SetSeed(1234);
    auto target = MeshType::New();
    for (itk::IdentifierType i = 0; i < 40; ++i)
    {
      target->SetPoint(i,
                       MakePoint(random->GetUniformVariate(0, 10),
                                 random->GetUniformVariate(0, 10),
                                 random->GetUniformVariate(0, 10)));
    }
    for (unsigned int k = 0; k < 30; ++k)
    {
      AddTriangle(target, random->GetIntegerVariate(39), random->GetIntegerVariate(39), random->GetIntegerVariate(39));
    }
    // Degenerate triangles: two coincident vertices, three coincident vertices, collinear vertices.
    AddTriangle(target, 3, 3, 7);
    AddTriangle(target, 5, 5, 5);
    const auto a = target->GetPoint(8);
    const auto b = target->GetPoint(9);
    target->SetPoint(40, MakePoint(0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1]), 0.5 * (a[2] + b[2])));
    target->SetPoint(41, MakePoint(2 * b[0] - a[0], 2 * b[1] - a[1], 2 * b[2] - a[2]));
    AddTriangle(target, 8, 40, 9);
    AddTriangle(target, 8, 9, 41);

    auto                source = MeshType::New();
    itk::IdentifierType id = 0;
    for (unsigned int k = 0; k < 300; ++k)
    {
      source->SetPoint(id++,
                       MakePoint(random->GetUniformVariate(-3, 13),
                                 random->GetUniformVariate(-3, 13),
                                 random->GetUniformVariate(-3, 13)));
    }
    // Vertices of the target and points exactly on edges (ends, midpoints, exact fractions).
    for (itk::IdentifierType i = 0; i < target->GetNumberOfPoints(); ++i)
    {
      source->SetPoint(id++, target->GetPoint(i));
    }
    for (itk::IdentifierType c = 0; c < target->GetNumberOfCells(); ++c)
    {
      MeshType::CellAutoPointer cell;
      target->GetCell(c, cell);
      const auto * ids = cell->PointIdsBegin();
      for (unsigned int e = 0; e < 3; ++e)
      {
        const auto p = target->GetPoint(ids[e]);
        const auto q = target->GetPoint(ids[(e + 1) % 3]);
        source->SetPoint(id++, MakePoint(0.5 * (p[0] + q[0]), 0.5 * (p[1] + q[1]), 0.5 * (p[2] + q[2])));
        source->SetPoint(id++,
                         MakePoint(0.75 * p[0] + 0.25 * q[0], 0.75 * p[1] + 0.25 * q[1], 0.75 * p[2] + 0.25 * q[2]));
      }
    }
    // On the line of the collinear triangles, beyond their ends.
    source->SetPoint(id++, MakePoint(3 * b[0] - 2 * a[0], 3 * b[1] - 2 * a[1], 3 * b[2] - 2 * a[2]));
    source->SetPoint(id++, MakePoint(2 * a[0] - b[0], 2 * a[1] - b[1], 2 * a[2] - b[2]));
    if (!CheckAgainstBruteForce(source, target, "Random soup with degenerate triangles"))
    {
      testStatus = EXIT_FAILURE;
    }
  }

  // 2. Two parallel planar grids: A over [0, 10]^2 at z = 0 (triangles), B over [2, 8]^2 at z = 3 (quads).
  //    Exact answer: d(x, y) = sqrt(9 + dx^2 + dy^2), dx = max(0, 2 - x, x - 8); from B to A: 3.
  {
    auto gridA = MeshType::New();
    auto gridB = MeshType::New();
    for (unsigned int j = 0; j <= 10; ++j)
    {
      for (unsigned int i = 0; i <= 10; ++i)
      {
        gridA->SetPoint(j * 11 + i, MakePoint(i, j, 0.0));
      }
    }
    for (unsigned int j = 0; j < 10; ++j)
    {
      for (unsigned int i = 0; i < 10; ++i)
      {
        AddTriangle(gridA, j * 11 + i, j * 11 + i + 1, (j + 1) * 11 + i + 1);
        AddTriangle(gridA, j * 11 + i, (j + 1) * 11 + i + 1, (j + 1) * 11 + i);
      }
    }
    for (unsigned int j = 0; j <= 6; ++j)
    {
      for (unsigned int i = 0; i <= 6; ++i)
      {
        gridB->SetPoint(j * 7 + i, MakePoint(2.0 + i, 2.0 + j, 3.0));
      }
    }
    for (unsigned int j = 0; j < 6; ++j)
    {
      for (unsigned int i = 0; i < 6; ++i)
      {
        AddQuadrilateral(gridB, j * 7 + i, j * 7 + i + 1, (j + 1) * 7 + i + 1, (j + 1) * 7 + i);
      }
    }
    std::vector<double> expected;
    double              expectedMean = 0.0;
    double              maximumError = 0.0;
    calculator->SetSourceMesh(gridA);
    calculator->SetTargetMesh(gridB);
    ITK_TRY_EXPECT_NO_EXCEPTION(calculator->Compute());
    for (itk::IdentifierType i = 0; i < gridA->GetNumberOfPoints(); ++i)
    {
      const auto   p = gridA->GetPoint(i);
      const double dx = std::max(0.0, std::max(2.0 - p[0], p[0] - 8.0));
      const double dy = std::max(0.0, std::max(2.0 - p[1], p[1] - 8.0));
      expected.push_back(std::sqrt(9.0 + dx * dx + dy * dy));
      expectedMean += expected.back() / gridA->GetNumberOfPoints();
      maximumError = std::max(maximumError, std::abs(calculator->GetDistances()[i] - expected.back()));
    }
    std::sort(expected.begin(), expected.end());
    const auto percentile = [&expected](double q) {
      const double      position = q * (expected.size() - 1);
      const std::size_t lower = static_cast<std::size_t>(position);
      return expected[lower] +
             (position - lower) * (expected[std::min(lower + 1, expected.size() - 1)] - expected[lower]);
    };
    std::cout << "Parallel grids: max |d - exact| = " << maximumError << ", mean " << calculator->GetMeanDistance()
              << " (exact " << expectedMean << "), Hausdorff " << calculator->GetMaximumDistance() << " (exact "
              << std::sqrt(17.0) << "), median " << calculator->GetMedianDistance() << ", p95 "
              << calculator->GetPercentile95Distance() << std::endl;
    ITK_TEST_EXPECT_TRUE(maximumError < 1e-12);
    ITK_TEST_EXPECT_TRUE(std::abs(calculator->GetMeanDistance() - expectedMean) < 1e-12);
    ITK_TEST_EXPECT_TRUE(std::abs(calculator->GetMaximumDistance() - std::sqrt(17.0)) < 1e-12);
    ITK_TEST_EXPECT_TRUE(std::abs(calculator->GetMedianDistance() - percentile(0.5)) < 1e-12);
    ITK_TEST_EXPECT_TRUE(std::abs(calculator->GetPercentile95Distance() - percentile(0.95)) < 1e-12);
    ITK_TEST_EXPECT_TRUE(std::abs(calculator->GetDistancePercentile(1.0) - std::sqrt(17.0)) < 1e-12);
    ITK_TEST_EXPECT_TRUE(std::abs(calculator->GetDistancePercentile(0.0) - 3.0) < 1e-12);

    // Per-vertex distances as point data.
    const auto pointData = calculator->MakePointData();
    ITK_TEST_EXPECT_EQUAL(pointData->Size(), gridA->GetNumberOfPoints());
    ITK_TEST_EXPECT_TRUE(std::abs(pointData->ElementAt(0) - std::sqrt(17.0)) < 1e-12);

    // From B to A: 3 everywhere; symmetric Hausdorff: sqrt(17).
    calculator->SetSourceMesh(gridB);
    calculator->SetTargetMesh(gridA);
    ITK_TRY_EXPECT_NO_EXCEPTION(calculator->Compute());
    ITK_TEST_EXPECT_TRUE(std::abs(calculator->GetMaximumDistance() - 3.0) < 1e-12);
    ITK_TEST_EXPECT_TRUE(std::abs(calculator->GetMeanDistance() - 3.0) < 1e-12);
    const double symmetric = CalculatorType::ComputeSymmetricHausdorffDistance(gridA, gridB);
    ITK_TEST_EXPECT_TRUE(std::abs(symmetric - std::sqrt(17.0)) < 1e-12);
    if (!CheckAgainstBruteForce(gridA, gridB, "Parallel grids"))
    {
      testStatus = EXIT_FAILURE;
    }
  }

  // 3. Two ~50 000-triangle tori: timing, self distance 0, a sample checked against brute force.
  {
    const auto torusA = MakeTorus(250, 100, 0.0, 0.0);
    const auto torusB = MakeTorus(250, 100, 1.0, 0.7);
    ITK_TEST_EXPECT_TRUE(CheckDistanceOnlyHierarchy(torusB));
    ITK_TEST_EXPECT_TRUE(CheckHierarchyNodeBound());
    const double self = CalculatorType::ComputeSymmetricHausdorffDistance(torusA, torusA);
    std::cout << "Torus to itself: symmetric Hausdorff " << self << std::endl;
    ITK_TEST_EXPECT_EQUAL(self, 0.0);

    itk::TimeProbe clock;
    calculator->SetSourceMesh(torusA);
    calculator->SetTargetMesh(torusB);
    clock.Start();
    ITK_TRY_EXPECT_NO_EXCEPTION(calculator->Compute());
    clock.Stop();
    std::cout << "Tori (" << torusA->GetNumberOfPoints() << " vertices -> " << torusB->GetNumberOfCells()
              << " triangles): " << clock.GetTotal() << " s, mean " << calculator->GetMeanDistance() << ", median "
              << calculator->GetMedianDistance() << ", p95 " << calculator->GetPercentile95Distance() << ", max "
              << calculator->GetMaximumDistance() << std::endl;
    itk::TimeProbe symmetricClock;
    symmetricClock.Start();
    const double hausdorff = CalculatorType::ComputeSymmetricHausdorffDistance(torusA, torusB);
    symmetricClock.Stop();
    std::cout << "Tori symmetric Hausdorff " << hausdorff << " in " << symmetricClock.GetTotal() << " s" << std::endl;
    ITK_TEST_EXPECT_TRUE(hausdorff >= calculator->GetMaximumDistance());

    // Brute force on every 97th vertex.
    const auto triangles = CalculatorType::ExtractTriangles(torusB.GetPointer());
    bool       sampleOk = true;
    for (itk::IdentifierType i = 0; i < torusA->GetNumberOfPoints(); i += 97)
    {
      const Vector3 p = ToVector(torusA->GetPoint(i));
      double        best = std::numeric_limits<double>::infinity();
      Vector3       closest;
      for (const auto & t : triangles)
      {
        best = std::min(best, itk::detail::ClosestPointOnTriangle(p, t.a, t.b, t.c, closest));
      }
      sampleOk = sampleOk && std::sqrt(best) == calculator->GetDistances()[i];
    }
    ITK_TEST_EXPECT_TRUE(sampleOk);
  }

  std::cout << "Test finished." << std::endl;
  return testStatus;
}
