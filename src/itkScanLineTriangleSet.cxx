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
#include "FFDShapeMatchingDetail/itkScanLineTriangleSet.h"
#include "FFDShapeMatchingDetail/itkPointTriangleDistance.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <ostream>
#include <string>
#include <utility>

namespace itk
{
namespace detail
{
void
ScanLineTriangleSet::SetTriangles(std::vector<TriangleType>                         triangles,
                                  const std::vector<std::array<std::uint32_t, 3>> & corners,
                                  bool                                              needInside)
{
  m_GradientBound.Build(needInside ? triangles : std::vector<TriangleType>{}, corners);
  m_Triangles = std::move(triangles);
  // Built on first use (GetHierarchy()): a closed surface's solid needs it only for voxels on the surface.
  m_HierarchyBuilt = false;
}

auto
ScanLineTriangleSet::GetHierarchy() const -> const HierarchyType &
{
  if (!m_HierarchyBuilt.load(std::memory_order_acquire))
  {
    const std::lock_guard<std::mutex> lock(m_HierarchyMutex);
    if (!m_HierarchyBuilt.load(std::memory_order_relaxed))
    {
      m_Hierarchy.Build(m_Triangles);
      m_HierarchyBuilt.store(true, std::memory_order_release);
    }
  }
  return m_Hierarchy;
}

void
ScanLineTriangleSet::Prepare(const GridGeometry & grid, bool needSign, double reachDistance, bool reachOnly)
{
  // Continuous index = M (p - origin), M = (direction * diag(spacing))^-1.
  const auto &          inverseDirection = grid.InverseDirection;
  const auto &          spacing = grid.Spacing;
  const auto &          origin = grid.Origin;
  double                matrix[3][3];
  std::array<double, 3> rowNorm{ { 0.0, 0.0, 0.0 } };
  for (unsigned int r = 0; r < 3; ++r)
  {
    for (unsigned int c = 0; c < 3; ++c)
    {
      matrix[r][c] = inverseDirection[r][c] / spacing[r];
      rowNorm[r] += matrix[r][c] * matrix[r][c];
    }
    rowNorm[r] = std::sqrt(rowNorm[r]);
  }
  const double determinant = matrix[0][0] * (matrix[1][1] * matrix[2][2] - matrix[1][2] * matrix[2][1]) -
                             matrix[0][1] * (matrix[1][0] * matrix[2][2] - matrix[1][2] * matrix[2][0]) +
                             matrix[0][2] * (matrix[1][0] * matrix[2][1] - matrix[1][1] * matrix[2][0]);
  m_OrientationSign = determinant < 0.0 ? -1 : 1;

  const auto & triangles = m_Triangles;
  m_IndexTriangles.resize(triangles.size());
  const auto toIndex = [&matrix, &origin](const std::array<double, 3> & p) {
    std::array<double, 3> result;
    for (unsigned int r = 0; r < 3; ++r)
    {
      result[r] =
        matrix[r][0] * (p[0] - origin[0]) + matrix[r][1] * (p[1] - origin[1]) + matrix[r][2] * (p[2] - origin[2]);
    }
    return result;
  };
  for (size_t t = 0; t < triangles.size(); ++t)
  {
    IndexSpaceTriangle & it = m_IndexTriangles[t];
    it.a = toIndex(triangles[t].a);
    it.b = toIndex(triangles[t].b);
    it.c = toIndex(triangles[t].c);
    for (unsigned int k = 0; k < 3; ++k)
    {
      it.lower[k] = std::min({ it.a[k], it.b[k], it.c[k] });
      it.upper[k] = std::max({ it.a[k], it.b[k], it.c[k] });
    }
  }
  // The planes the distance rows bound with, once per triangle rather than once per row.
  const double gridSpacing[3] = { spacing[0], spacing[1], spacing[2] };
  m_ScaledPlaneSpacing = { { spacing[0], spacing[1], spacing[2] } };
  m_ScaledPlanes.resize(reachDistance >= 0.0 ? m_IndexTriangles.size() : 0);
  for (size_t t = 0; t < m_ScaledPlanes.size(); ++t)
  {
    m_ScaledPlanes[t] = MakeScaledPlane(m_IndexTriangles[t], gridSpacing);
  }

  // Rows of the requested region only: a streamed piece bins the triangles of its own rows.
  const long j0 = grid.RegionIndex[1];
  const long j1 = j0 + static_cast<long>(grid.RegionSize[1]) - 1;
  const long k0 = grid.RegionIndex[2];
  const long k1 = k0 + static_cast<long>(grid.RegionSize[2]) - 1;
  m_CrossingBins.Build(needSign ? m_IndexTriangles : std::vector<IndexSpaceTriangle>{}, j0, j1, k0, k1, 0.0, 0.0);

  if (reachDistance >= 0.0)
  {
    // Grown a little so rounding never drops a voxel at exactly the reach distance.
    for (unsigned int k = 0; k < 3; ++k)
    {
      m_ReachMargin[k] = (reachDistance * (1.0 + 1e-9) + 1e-9) * rowNorm[k] * (1.0 + 1e-9) + 1e-9;
    }
  }
  m_RegionTriangles.clear();
  if (reachDistance >= 0.0 && reachOnly)
  {
    // Occupancy and band mask go triangle by triangle (GenerateReachByTriangles()): the triangles whose
    // grown bounding box meets the requested region.
    for (size_t t = 0; t < m_IndexTriangles.size(); ++t)
    {
      const IndexSpaceTriangle & triangle = m_IndexTriangles[t];
      bool                       meets = true;
      for (unsigned int d = 0; d < 3 && meets; ++d)
      {
        const double first = static_cast<double>(grid.RegionIndex[d]);
        const double last = first + static_cast<double>(grid.RegionSize[d]) - 1.0;
        meets = std::ceil(triangle.lower[d] - m_ReachMargin[d]) <= last &&
                std::floor(triangle.upper[d] + m_ReachMargin[d]) >= first;
      }
      if (meets)
      {
        m_RegionTriangles.push_back(static_cast<std::uint32_t>(t));
      }
    }
    m_ReachBins.Build(std::vector<IndexSpaceTriangle>{}, j0, j1, k0, k1, 0.0, 0.0);
  }
  else if (reachDistance >= 0.0)
  {
    m_ReachBins.Build(m_IndexTriangles, j0, j1, k0, k1, m_ReachMargin[1], m_ReachMargin[2]);
  }
  else
  {
    m_ReachBins.Build(std::vector<IndexSpaceTriangle>{}, j0, j1, k0, k1, 0.0, 0.0);
  }
}

void
ScanLineTriangleSet::ComputeRowSquaredDistances(long                            first,
                                                long                            j,
                                                long                            k,
                                                const double                    spacing[3],
                                                double                          radius,
                                                bool                            anyWithin,
                                                const std::vector<VectorType> & points,
                                                std::vector<double> &           squaredDistances) const
{
  // Physical coordinates across the row are (spacing[1] y, spacing[2] z) of continuous index space
  // (orthonormal direction), along the row spacing[0] x: the distance from a voxel to a triangle is at
  // least the distance between their projections across the row, combined with the gap between the
  // voxel and the triangle's extent along it. Triangles are visited nearest-first across the row, and
  // a voxel computes the exact distance to a triangle only when that lower bound can beat its best.
  const double unit = std::min({ spacing[0], spacing[1], spacing[2] });
  const double limit = radius * radius * (1.0 + 1e-9) + 1e-9 * unit * unit;
  const double radiusSquared = radius * radius;
  const long   count = static_cast<long>(squaredDistances.size());
  const double y = spacing[1] * static_cast<double>(j);
  const double z = spacing[2] * static_cast<double>(k);
  std::fill(squaredDistances.begin(), squaredDistances.end(), std::numeric_limits<double>::infinity());

  // Candidates sorted by distance across the row through one integer key: the bits of a non-negative
  // float order as its values do (the order only speeds the pruning up, it never changes a result).
  struct Candidate
  {
    double        across;
    double        lower;
    double        upper;
    double        planeOffset; // Signed distance to the triangle's plane at x = 0 of the row ...
    double        planeSlope;  // ... and its change per unit of x (physical units along the row).
    std::uint32_t triangle;
  };
  std::vector<Candidate>     candidates;
  std::vector<std::uint64_t> keys;
  const bool samePlanes = m_ScaledPlanes.size() == m_IndexTriangles.size() && spacing[0] == m_ScaledPlaneSpacing[0] &&
                          spacing[1] == m_ScaledPlaneSpacing[1] && spacing[2] == m_ScaledPlaneSpacing[2];
  // A triangle whose extent along the row, grown by the radius, misses the voxels asked for (a row's masked
  // span) is skipped before any other work; the slack of one voxel covers the rounding of the bounds below.
  const double reachAlong = std::sqrt(limit) / spacing[0];
  const double firstIndex = static_cast<double>(first) - 1.0;
  const double lastIndex = static_cast<double>(first + count);
  for (const std::uint32_t * it = m_ReachBins.Begin(j, k); it != m_ReachBins.End(j, k); ++it)
  {
    const IndexSpaceTriangle & t = m_IndexTriangles[*it];
    if (t.upper[0] + reachAlong < firstIndex || t.lower[0] - reachAlong > lastIndex)
    {
      continue;
    }
    const double gapY =
      spacing[1] * std::max({ t.lower[1] - static_cast<double>(j), static_cast<double>(j) - t.upper[1], 0.0 });
    const double gapZ =
      spacing[2] * std::max({ t.lower[2] - static_cast<double>(k), static_cast<double>(k) - t.upper[2], 0.0 });
    if ((gapY * gapY + gapZ * gapZ) * (1.0 - 1e-9) - 1e-9 * unit * unit >= limit)
    {
      continue;
    }
    const double a[2] = { spacing[1] * t.a[1], spacing[2] * t.a[2] };
    const double b[2] = { spacing[1] * t.b[1], spacing[2] * t.b[2] };
    const double c[2] = { spacing[1] * t.c[1], spacing[2] * t.c[2] };
    const double across = PlaneTriangleSquaredDistance(y, z, a, b, c);
    if (across * (1.0 - 1e-9) - 1e-9 * unit * unit >= limit)
    {
      continue;
    }
    // The triangle's plane in the grid's frame scaled to physical units: its distance is a second lower bound
    // (made by Prepare() for its grid's spacing).
    const ScaledPlane plane = samePlanes ? m_ScaledPlanes[*it] : MakeScaledPlane(t, spacing);
    const auto &      sa = plane.corner;
    const auto &      normal = plane.normal;
    const double      planeOffset = normal[1] * (y - sa[1]) + normal[2] * (z - sa[2]) - normal[0] * sa[0];
    const double      planeSlope = normal[0];
    const auto        rank = static_cast<float>(across);
    std::uint32_t     bits;
    std::memcpy(&bits, &rank, sizeof(bits));
    keys.push_back((static_cast<std::uint64_t>(bits) << 32) | candidates.size());
    candidates.push_back(
      Candidate{ across, spacing[0] * t.lower[0], spacing[0] * t.upper[0], planeOffset, planeSlope, *it });
  }
  std::sort(keys.begin(), keys.end());
  TriangleBoundingVolumeHierarchy::VectorType closest;
  for (const std::uint64_t key : keys)
  {
    const Candidate & candidate = candidates[key & 0xffffffffu];
    const double      reach = std::sqrt(std::max(0.0, limit - candidate.across)) / spacing[0];
    const double from = std::max(std::ceil(candidate.lower / spacing[0] - reach) - static_cast<double>(first), 0.0);
    const double to = std::min(std::floor(candidate.upper / spacing[0] + reach) - static_cast<double>(first),
                               static_cast<double>(count - 1));
    const auto & triangle = m_Triangles[candidate.triangle];
    for (double position = from; position <= to; position += 1.0)
    {
      const auto   i = static_cast<size_t>(position);
      double &     best = squaredDistances[i];
      const double x = spacing[0] * (static_cast<double>(first) + position);
      const double gap = std::max({ candidate.lower - x, x - candidate.upper, 0.0 });
      const double plane = candidate.planeOffset + candidate.planeSlope * x;
      const double lowerBound =
        std::max(candidate.across + gap * gap, plane * plane) * (1.0 - 1e-9) - 1e-9 * unit * unit;
      if (lowerBound >= std::min(best, limit) || (anyWithin && best <= radiusSquared))
      {
        continue;
      }
      best = std::min(best, ClosestPointOnTriangle(points[i], triangle.a, triangle.b, triangle.c, closest));
    }
  }
}

auto
ScanLineTriangleSet::MakeScaledPlane(const IndexSpaceTriangle & t, const double spacing[3]) -> ScaledPlane
{
  ScaledPlane plane;
  plane.corner = { { spacing[0] * t.a[0], spacing[1] * t.a[1], spacing[2] * t.a[2] } };
  double ab[3], ac[3];
  for (unsigned int d = 0; d < 3; ++d)
  {
    ab[d] = spacing[d] * t.b[d] - plane.corner[d];
    ac[d] = spacing[d] * t.c[d] - plane.corner[d];
  }
  plane.normal = { { ab[1] * ac[2] - ab[2] * ac[1], ab[2] * ac[0] - ab[0] * ac[2], ab[0] * ac[1] - ab[1] * ac[0] } };
  const double normalLength = std::sqrt(plane.normal[0] * plane.normal[0] + plane.normal[1] * plane.normal[1] +
                                        plane.normal[2] * plane.normal[2]);
  for (double & component : plane.normal)
  {
    component = normalLength > 0.0 ? component / normalLength : 0.0;
  }
  return plane;
}

void
ScanLineTriangleSet::ComputeRowInside(long                            first,
                                      long                            j,
                                      long                            k,
                                      const std::vector<VectorType> & points,
                                      double                          spacingAlongRow,
                                      double                          beta,
                                      bool                            absoluteWindingNumber,
                                      std::vector<char> &             inside) const
{
  const long count = static_cast<long>(inside.size());

  std::vector<ScanLineCrossing>          crossings;
  std::vector<std::pair<double, double>> uncertain;
  ScanLineCrossings(static_cast<double>(j),
                    static_cast<double>(k),
                    m_IndexTriangles,
                    m_CrossingBins.Begin(j, k),
                    m_CrossingBins.End(j, k),
                    m_OrientationSign,
                    crossings,
                    uncertain);

  // Signed crossing count before each voxel centre; voxels within rounding of a crossing, or along a
  // triangle seen edge-on, are ties that the winding number decides.
  constexpr double  tieTolerance = 1e-7;
  std::vector<int>  crossingCount(inside.size());
  std::vector<char> tie(inside.size(), 0);
  size_t            next = 0;
  int               running = 0;
  for (long i = 0; i < count; ++i)
  {
    const double x = static_cast<double>(first + i);
    while (next < crossings.size() && crossings[next].x < x)
    {
      running += crossings[next++].jump;
    }
    crossingCount[i] = running;
  }
  const auto markTies = [first, count, &tie](double lower, double upper) {
    const double from = std::max(std::ceil(lower - tieTolerance) - static_cast<double>(first), 0.0);
    const double to =
      std::min(std::floor(upper + tieTolerance) - static_cast<double>(first), static_cast<double>(count - 1));
    for (double i = from; i <= to; i += 1.0)
    {
      tie[static_cast<size_t>(i)] = 1;
    }
  };
  for (const auto & crossing : crossings)
  {
    markTies(crossing.x, crossing.x);
  }
  for (const auto & interval : uncertain)
  {
    markTies(interval.first, interval.second);
  }

  const auto windingNumber = [&](long i) { return this->GetHierarchy().WindingNumber(points[i], beta); };

  if (m_GradientBound.GetNumberOfEdges() == 0)
  {
    // No edge carries a net current: w is the signed crossing count between crossings.
    for (long i = 0; i < count; ++i)
    {
      inside[i] = IsInside(absoluteWindingNumber, tie[i] ? windingNumber(i) : static_cast<double>(crossingCount[i]));
    }
    return;
  }

  // Open or inconsistent surface: w = crossing count + c(x), c continuous with |c'| bounded by the
  // net-current edges. Bisection: evaluate w at the middle voxel of a range, predict the others with
  // that bound (plus the far-field tolerance), split where the prediction cannot decide.
  const double                       tolerance = beta > 0.0 ? 0.25 : 1e-6;
  const double                       step = spacingAlongRow;
  std::vector<std::pair<long, long>> ranges;
  ranges.emplace_back(0, count - 1);
  while (!ranges.empty())
  {
    const long a = ranges.back().first;
    const long b = ranges.back().second;
    ranges.pop_back();
    const long   m = a + (b - a) / 2;
    const double w = windingNumber(m);
    inside[m] = IsInside(absoluteWindingNumber, w);
    if (a == b)
    {
      continue;
    }
    if (tie[m])
    {
      // On (or along) the surface w is not the crossing count plus a continuous part: predict from no tie.
      if (m > a)
      {
        ranges.emplace_back(a, m - 1);
      }
      ranges.emplace_back(m + 1, b);
      continue;
    }
    const double       offset = w - static_cast<double>(crossingCount[m]);
    const VectorType & pa = points[a];
    const VectorType & pb = points[b];
    VectorType         lower;
    VectorType         upper;
    for (unsigned int d = 0; d < 3; ++d)
    {
      lower[d] = std::min(pa[d], pb[d]);
      upper[d] = std::max(pa[d], pb[d]);
    }
    const double gradient = m_GradientBound.Bound(lower, upper);
    long         leftFirst = -1, leftLast = -1, rightFirst = -1, rightLast = -1;
    for (long v = a; v <= b; ++v)
    {
      if (v == m)
      {
        continue;
      }
      const double value = static_cast<double>(crossingCount[v]) + offset;
      const double radius = gradient * step * static_cast<double>(std::abs(v - m)) + tolerance;
      if (!tie[v] && std::isfinite(radius) && IsDecided(absoluteWindingNumber, value, radius))
      {
        inside[v] = IsInside(absoluteWindingNumber, value);
      }
      else if (v < m)
      {
        leftFirst = leftFirst < 0 ? v : leftFirst;
        leftLast = v;
      }
      else
      {
        rightFirst = rightFirst < 0 ? v : rightFirst;
        rightLast = v;
      }
    }
    if (leftFirst >= 0)
    {
      ranges.emplace_back(leftFirst, leftLast);
    }
    if (rightFirst >= 0)
    {
      ranges.emplace_back(rightFirst, rightLast);
    }
  }
}

void
ScanLineTriangleSet::Print(std::ostream & os, Indent indent) const
{
  os << indent << "Edges with a net current (open or inconsistent surface; found in the modes deciding inside): "
     << m_GradientBound.GetNumberOfEdges() << std::endl;
  os << indent << "IndexTriangles: " << m_IndexTriangles.size() << std::endl;
  os << indent << "CrossingBins entries: " << m_CrossingBins.GetNumberOfEntries() << std::endl;
  os << indent << "ReachBins entries: " << m_ReachBins.GetNumberOfEntries() << std::endl;
  os << indent << "RegionTriangles: " << m_RegionTriangles.size() << std::endl;
  os << indent << "ReachMargin: " << m_ReachMargin[0] << ' ' << m_ReachMargin[1] << ' ' << m_ReachMargin[2]
     << std::endl;
  os << indent << "OrientationSign: " << m_OrientationSign << std::endl;
}
} // namespace detail
} // namespace itk
