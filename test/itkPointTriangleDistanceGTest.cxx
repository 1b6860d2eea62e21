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
#include "FFDShapeMatchingDetail/itkPointTriangleDistance.h"
#include "FFDShapeMatchingDetail/itkTriangleBoundingVolumeHierarchy.h"
#include "itkMath.h"
#include "itkPoint.h"
#include "gtest/gtest.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

namespace
{
using PointType = itk::Point<double, 3>;
using VectorType = itk::detail::TriangleBoundingVolumeHierarchy::VectorType;
using TriangleType = itk::detail::TriangleBoundingVolumeHierarchy::Triangle;

PointType
MakePoint(double x, double y, double z)
{
  PointType p;
  p[0] = x;
  p[1] = y;
  p[2] = z;
  return p;
}

PointType
RandomPoint(std::mt19937 & generator, double range)
{
  std::uniform_real_distribution<double> uniform(-range, range);
  return MakePoint(uniform(generator), uniform(generator), uniform(generator));
}

// Smallest squared distance from p to a dense barycentric sampling of the triangle (n steps per edge).
double
SampledSquaredDistance(const PointType & p, const PointType & a, const PointType & b, const PointType & c, int n)
{
  double best = std::numeric_limits<double>::infinity();
  for (int i = 0; i <= n; ++i)
  {
    for (int j = 0; i + j <= n; ++j)
    {
      const double v = static_cast<double>(i) / n;
      const double w = static_cast<double>(j) / n;
      double       d2 = 0.0;
      for (unsigned int k = 0; k < 3; ++k)
      {
        const double q = (1.0 - v - w) * a[k] + v * b[k] + w * c[k];
        d2 += (p[k] - q) * (p[k] - q);
      }
      best = std::min(best, d2);
    }
  }
  return best;
}

double
MaxEdge(const PointType & a, const PointType & b, const PointType & c)
{
  return std::max({ a.EuclideanDistanceTo(b), b.EuclideanDistanceTo(c), c.EuclideanDistanceTo(a) });
}

// Barycentric coordinates of q in (a, b, c) by least squares, to check q lies in the triangle.
void
ExpectOnTriangle(const PointType & q, const PointType & a, const PointType & b, const PointType & c)
{
  const auto   e0 = b - a;
  const auto   e1 = c - a;
  const auto   r = q - a;
  const double d00 = e0 * e0, d01 = e0 * e1, d11 = e1 * e1, d20 = r * e0, d21 = r * e1;
  const double denominator = d00 * d11 - d01 * d01;
  const double v = (d11 * d20 - d01 * d21) / denominator;
  const double w = (d00 * d21 - d01 * d20) / denominator;
  EXPECT_GE(v, -1e-9);
  EXPECT_GE(w, -1e-9);
  EXPECT_LE(v + w, 1.0 + 1e-9);
  const auto residual = r - (e0 * v + e1 * w);
  EXPECT_LT(residual.GetNorm(), 1e-9);
}
} // namespace

TEST(PointTriangleDistance, KnownRegions)
{
  const PointType a = MakePoint(0, 0, 0);
  const PointType b = MakePoint(1, 0, 0);
  const PointType c = MakePoint(0, 1, 0);
  PointType       closest;
  // Face region: straight above the interior.
  EXPECT_DOUBLE_EQ(itk::detail::ClosestPointOnTriangle(MakePoint(0.2, 0.3, 2.0), a, b, c, closest), 4.0);
  EXPECT_NEAR(closest.EuclideanDistanceTo(MakePoint(0.2, 0.3, 0.0)), 0.0, 1e-15);
  // Vertex regions.
  EXPECT_DOUBLE_EQ(itk::detail::ClosestPointOnTriangle(MakePoint(-1, -1, 0), a, b, c, closest), 2.0);
  EXPECT_EQ(closest, a);
  EXPECT_DOUBLE_EQ(itk::detail::ClosestPointOnTriangle(MakePoint(3, -1, 1), a, b, c, closest), 4.0 + 1.0 + 1.0);
  EXPECT_EQ(closest, b);
  EXPECT_DOUBLE_EQ(itk::detail::ClosestPointOnTriangle(MakePoint(0, 2, 0), a, b, c, closest), 1.0);
  EXPECT_EQ(closest, c);
  // Edge regions ab, ac and bc.
  EXPECT_DOUBLE_EQ(itk::detail::ClosestPointOnTriangle(MakePoint(0.5, -2, 0), a, b, c, closest), 4.0);
  EXPECT_NEAR(closest.EuclideanDistanceTo(MakePoint(0.5, 0, 0)), 0.0, 1e-15);
  EXPECT_DOUBLE_EQ(itk::detail::ClosestPointOnTriangle(MakePoint(-3, 0.25, 0), a, b, c, closest), 9.0);
  EXPECT_NEAR(closest.EuclideanDistanceTo(MakePoint(0, 0.25, 0)), 0.0, 1e-15);
  EXPECT_NEAR(itk::detail::ClosestPointOnTriangle(MakePoint(1, 1, 0), a, b, c, closest), 0.5, 1e-15);
  EXPECT_NEAR(closest.EuclideanDistanceTo(MakePoint(0.5, 0.5, 0)), 0.0, 1e-15);
  // A point on the triangle.
  EXPECT_DOUBLE_EQ(itk::detail::PointTriangleSquaredDistance(MakePoint(0.25, 0.25, 0), a, b, c), 0.0);
}

TEST(PointTriangleDistance, RandomCasesAgainstDenseSampling)
{
  std::mt19937 generator(20261122);
  const int    n = 300;
  for (int trial = 0; trial < 300; ++trial)
  {
    const PointType a = RandomPoint(generator, 1.0);
    const PointType b = RandomPoint(generator, 1.0);
    const PointType c = RandomPoint(generator, 1.0);
    const PointType p = RandomPoint(generator, 2.0);
    PointType       closest;
    const double    exact = itk::detail::ClosestPointOnTriangle(p, a, b, c, closest);
    const double    sampled = SampledSquaredDistance(p, a, b, c, n);
    // The exact minimum is below every sample, and a sample lies within maxEdge / n of the closest point.
    EXPECT_LE(exact, sampled + 1e-12) << "trial " << trial;
    EXPECT_LE(std::sqrt(sampled) - std::sqrt(exact), MaxEdge(a, b, c) / n + 1e-12) << "trial " << trial;
    EXPECT_NEAR(exact, p.SquaredEuclideanDistanceTo(closest), 1e-12);
    ExpectOnTriangle(closest, a, b, c);
  }
}

TEST(PointTriangleDistance, PointsNearTheTriangle)
{
  // Points at small distances, where region misclassification would show.
  std::mt19937                           generator(7);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int trial = 0; trial < 200; ++trial)
  {
    const PointType a = RandomPoint(generator, 1.0);
    const PointType b = RandomPoint(generator, 1.0);
    const PointType c = RandomPoint(generator, 1.0);
    const double    v = unit(generator) * 1.4 - 0.2;
    const double    w = unit(generator) * 1.4 - 0.2;
    PointType       p;
    for (unsigned int k = 0; k < 3; ++k)
    {
      p[k] = (1 - v - w) * a[k] + v * b[k] + w * c[k] + 0.01 * (unit(generator) - 0.5);
    }
    PointType    closest;
    const double exact = itk::detail::ClosestPointOnTriangle(p, a, b, c, closest);
    const double sampled = SampledSquaredDistance(p, a, b, c, 400);
    EXPECT_LE(exact, sampled + 1e-12);
    EXPECT_LE(std::sqrt(sampled) - std::sqrt(exact), MaxEdge(a, b, c) / 400 + 1e-12);
    ExpectOnTriangle(closest, a, b, c);
  }
}

TEST(PointTriangleDistance, DegenerateTriangles)
{
  std::mt19937 generator(11);
  for (int trial = 0; trial < 100; ++trial)
  {
    const PointType a = RandomPoint(generator, 1.0);
    const PointType b = RandomPoint(generator, 1.0);
    const PointType p = RandomPoint(generator, 2.0);
    // Collinear: c between a and b, or beyond b.
    PointType c;
    for (unsigned int k = 0; k < 3; ++k)
    {
      c[k] = a[k] + 1.7 * (b[k] - a[k]);
    }
    PointType    closest;
    PointType    segmentClosest;
    const double onSegment = itk::detail::ClosestPointOnSegment(p, a, c, segmentClosest);
    EXPECT_NEAR(itk::detail::ClosestPointOnTriangle(p, a, b, c, closest), onSegment, 1e-12);
    EXPECT_NEAR(closest.EuclideanDistanceTo(segmentClosest), 0.0, 1e-9);
    // Two coincident vertices: a segment.
    EXPECT_NEAR(itk::detail::PointTriangleSquaredDistance(p, a, b, b),
                itk::detail::ClosestPointOnSegment(p, a, b, segmentClosest),
                1e-12);
    // Three coincident vertices: a point.
    EXPECT_NEAR(itk::detail::ClosestPointOnTriangle(p, a, a, a, closest), p.SquaredEuclideanDistanceTo(a), 1e-12);
    EXPECT_EQ(closest, a);
  }
}

TEST(PointTriangleDistance, FloatPoints)
{
  using FloatPointType = itk::Point<float, 3>;
  FloatPointType a;
  FloatPointType b;
  FloatPointType c;
  FloatPointType p;
  a.Fill(0.0f);
  b.Fill(0.0f);
  c.Fill(0.0f);
  b[0] = 2.0f;
  c[1] = 2.0f;
  p[0] = 0.5f;
  p[1] = 0.5f;
  p[2] = -3.0f;
  FloatPointType closest;
  EXPECT_DOUBLE_EQ(itk::detail::ClosestPointOnTriangle(p, a, b, c, closest), 9.0);
  EXPECT_FLOAT_EQ(closest[2], 0.0f);
}

TEST(TriangleBoundingVolumeHierarchy, QueriesMatchBruteForce)
{
  std::mt19937                           generator(3);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  std::vector<TriangleType>              soup(300);
  for (auto & t : soup)
  {
    const VectorType centre{ uniform(generator), uniform(generator), uniform(generator) };
    for (VectorType * v : { &t.a, &t.b, &t.c })
    {
      for (unsigned int k = 0; k < 3; ++k)
      {
        (*v)[k] = centre[k] + 0.2 * uniform(generator);
      }
    }
  }
  itk::detail::TriangleBoundingVolumeHierarchy hierarchy;
  hierarchy.Build(soup, 3);
  EXPECT_EQ(hierarchy.GetNumberOfTriangles(), soup.size());
  VectorType closest;
  for (int trial = 0; trial < 500; ++trial)
  {
    const VectorType q{ 1.5 * uniform(generator), 1.5 * uniform(generator), 1.5 * uniform(generator) };
    double           bruteDistance = std::numeric_limits<double>::infinity();
    double           bruteAngle = 0.0;
    for (const auto & t : soup)
    {
      bruteDistance = std::min(bruteDistance, itk::detail::ClosestPointOnTriangle(q, t.a, t.b, t.c, closest));
      bruteAngle += itk::detail::TriangleSolidAngle(q, t.a, t.b, t.c);
    }
    EXPECT_DOUBLE_EQ(hierarchy.SquaredDistance(q), bruteDistance);
    const double cap = 0.01;
    EXPECT_DOUBLE_EQ(hierarchy.SquaredDistance(q, cap), std::min(cap, bruteDistance));
    for (const double radius : { 0.02, 0.1, 0.3 })
    {
      if (std::abs(std::sqrt(bruteDistance) - radius) > 1e-12)
      {
        EXPECT_EQ(hierarchy.AnyTriangleWithin(q, radius), std::sqrt(bruteDistance) <= radius);
      }
    }
    EXPECT_NEAR(hierarchy.WindingNumber(q, 0.0), bruteAngle / (4.0 * itk::Math::pi), 1e-10);
  }
}

TEST(TriangleBoundingVolumeHierarchy, SolidAngleOfClosedSurface)
{
  // A regular tetrahedron, outward orientation: winding number 1 inside, 0 outside, -1 when flipped.
  const VectorType                             v0{ 1, 1, 1 }, v1{ 1, -1, -1 }, v2{ -1, 1, -1 }, v3{ -1, -1, 1 };
  std::vector<TriangleType>                    faces{ { v0, v1, v2 }, { v0, v3, v1 }, { v0, v2, v3 }, { v1, v3, v2 } };
  itk::detail::TriangleBoundingVolumeHierarchy hierarchy;
  hierarchy.Build(faces, 1);
  EXPECT_NEAR(hierarchy.WindingNumber(VectorType{ 0.1, -0.05, 0.02 }, 0.0), 1.0, 1e-12);
  EXPECT_NEAR(hierarchy.WindingNumber(VectorType{ 3, 2, 1 }, 0.0), 0.0, 1e-12);
  EXPECT_NEAR(hierarchy.WindingNumber(VectorType{ 30, 20, 10 }, 2.0), 0.0, 1e-6);
  for (auto & f : faces)
  {
    std::swap(f.b, f.c);
  }
  hierarchy.Build(faces, 1);
  EXPECT_NEAR(hierarchy.WindingNumber(VectorType{ 0.1, -0.05, 0.02 }, 0.0), -1.0, 1e-12);
}
