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
#ifndef itkScanLineWindingNumber_h
#define itkScanLineWindingNumber_h

#include "FFDShapeMatchingDetail/itkTriangleBoundingVolumeHierarchy.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

namespace itk
{
namespace detail
{
/** \brief A triangle in continuous-index coordinates (x, y, z) of an output grid, with its bounds.
 * \ingroup FFDShapeMatching
 */
struct IndexSpaceTriangle
{
  std::array<double, 3> a;
  std::array<double, 3> b;
  std::array<double, 3> c;
  std::array<double, 3> lower;
  std::array<double, 3> upper;
};

/** \brief Where a grid row crosses a triangle: the continuous x index and the jump of the winding number.
 * \ingroup FFDShapeMatching
 */
struct ScanLineCrossing
{
  double x;
  int    jump;
};

/** \class ScanLineTriangleBins
 * \brief The triangles whose (y, z) bounds, grown by a margin, hold each row (j, k) of a block of rows.
 *
 * Rows are lines of constant integer y = j and z = k in continuous-index space. Build() stores, for
 * every row of [j0, j1] x [k0, k1], the indices of the triangles with
 * \f$\lceil y_{min} - m_y \rceil \le j \le \lfloor y_{max} + m_y \rfloor\f$ (same in z), in compressed rows.
 * \ingroup FFDShapeMatching
 */
class ScanLineTriangleBins
{
public:
  void
  Build(const std::vector<IndexSpaceTriangle> & triangles,
        long                                    j0,
        long                                    j1,
        long                                    k0,
        long                                    k1,
        double                                  marginY,
        double                                  marginZ)
  {
    m_J0 = j0;
    m_K0 = k0;
    m_NumberOfJ = std::max(0L, j1 - j0 + 1);
    const long numberOfK = std::max(0L, k1 - k0 + 1);
    m_Offsets.assign(static_cast<std::size_t>(m_NumberOfJ * numberOfK) + 1, 0);
    m_Ids.clear();
    if (m_NumberOfJ == 0 || numberOfK == 0)
    {
      return;
    }
    const auto range = [](double lower, double upper, long first, long last, long & from, long & to) {
      const double low = std::max(std::ceil(lower), static_cast<double>(first));
      const double high = std::min(std::floor(upper), static_cast<double>(last));
      from = static_cast<long>(low);
      to = static_cast<long>(high);
      return low <= high;
    };
    for (int pass = 0; pass < 2; ++pass)
    {
      for (std::size_t t = 0; t < triangles.size(); ++t)
      {
        const IndexSpaceTriangle & triangle = triangles[t];
        long                       jFrom, jTo, kFrom, kTo;
        if (!range(triangle.lower[1] - marginY, triangle.upper[1] + marginY, j0, j1, jFrom, jTo) ||
            !range(triangle.lower[2] - marginZ, triangle.upper[2] + marginZ, k0, k1, kFrom, kTo))
        {
          continue;
        }
        for (long k = kFrom; k <= kTo; ++k)
        {
          for (long j = jFrom; j <= jTo; ++j)
          {
            const std::size_t row = static_cast<std::size_t>((k - k0) * m_NumberOfJ + (j - j0));
            if (pass == 0)
            {
              ++m_Offsets[row + 1];
            }
            else
            {
              m_Ids[m_Cursor[row]++] = static_cast<std::uint32_t>(t);
            }
          }
        }
      }
      if (pass == 0)
      {
        for (std::size_t i = 1; i < m_Offsets.size(); ++i)
        {
          m_Offsets[i] += m_Offsets[i - 1];
        }
        m_Ids.resize(m_Offsets.back());
        m_Cursor.assign(m_Offsets.begin(), m_Offsets.end() - 1);
      }
    }
    m_Cursor.clear();
    m_Cursor.shrink_to_fit();
  }

  /** The triangle indices of row (j, k), which must lie in the block given to Build(). */
  const std::uint32_t *
  Begin(long j, long k) const
  {
    return m_Ids.data() + m_Offsets[this->Row(j, k)];
  }

  const std::uint32_t *
  End(long j, long k) const
  {
    return m_Ids.data() + m_Offsets[this->Row(j, k) + 1];
  }

  std::size_t
  GetNumberOfEntries() const
  {
    return m_Ids.size();
  }

private:
  std::size_t
  Row(long j, long k) const
  {
    return static_cast<std::size_t>((k - m_K0) * m_NumberOfJ + (j - m_J0));
  }

  long                       m_J0{ 0 };
  long                       m_K0{ 0 };
  long                       m_NumberOfJ{ 0 };
  std::vector<std::size_t>   m_Offsets;
  std::vector<std::uint32_t> m_Ids;
  std::vector<std::size_t>   m_Cursor;
};

/** \brief Sign of the edge function of the directed edge p -> q at the point (y, z), in the (y, z) plane.
 *
 * The value \f$(q_y - p_y)(z - p_z) - (q_z - p_z)(y - p_y)\f$ is computed with the edge's end points in
 * lexicographic order, so the two triangles sharing an edge see exactly opposite values (no point
 * falls between them). A zero value is resolved by simulation of simplicity, as if the point were moved
 * to \f$(y + \epsilon, z + \epsilon^2)\f$: the sign of the first non-zero term. Returns 0 only for an
 * edge whose projection is a point. The value itself goes to \c value.
 */
inline int
ScanLineEdgeSign(const std::array<double, 3> & p, const std::array<double, 3> & q, double y, double z, double & value)
{
  const bool                    ordered = p[1] < q[1] || (p[1] == q[1] && p[2] <= q[2]);
  const std::array<double, 3> & first = ordered ? p : q;
  const std::array<double, 3> & second = ordered ? q : p;
  const double                  dy = second[1] - first[1];
  const double                  dz = second[2] - first[2];
  double                        canonical = dy * (z - first[2]) - dz * (y - first[1]);
  int                           sign = canonical > 0.0 ? 1 : (canonical < 0.0 ? -1 : 0);
  if (sign == 0)
  {
    // d/d(eps) of dy * eps^2 - dz * eps: the eps term first, then the eps^2 term.
    sign = dz != 0.0 ? (dz > 0.0 ? -1 : 1) : (dy > 0.0 ? 1 : (dy < 0.0 ? -1 : 0));
    canonical = 0.0;
  }
  value = ordered ? canonical : -canonical;
  return ordered ? sign : -sign;
}

/** \brief Crossings of the row (y, z) = (j, k) of continuous-index space with the given triangles.
 *
 * A triangle is crossed when the row point lies inside its (y, z) projection (edges resolved by
 * ScanLineEdgeSign(), so a row through a shared edge or vertex crosses exactly one of the triangles
 * meeting there, as the slightly moved row would). Each crossing gets the jump of the winding number
 * along +x: -orientationSign when the projection is counter-clockwise, +orientationSign otherwise
 * (orientationSign is -1 when the index-to-physical map reverses orientation). Triangles whose
 * projection is (nearly) a segment, where the crossing point is ill-conditioned, add their x extent to
 * \c uncertain instead. The crossings are sorted by x.
 */
inline void
ScanLineCrossings(double                                   y,
                  double                                   z,
                  const std::vector<IndexSpaceTriangle> &  triangles,
                  const std::uint32_t *                    begin,
                  const std::uint32_t *                    end,
                  int                                      orientationSign,
                  std::vector<ScanLineCrossing> &          crossings,
                  std::vector<std::pair<double, double>> & uncertain)
{
  crossings.clear();
  uncertain.clear();
  for (const std::uint32_t * it = begin; it != end; ++it)
  {
    const IndexSpaceTriangle & t = triangles[*it];
    if (y < t.lower[1] || y > t.upper[1] || z < t.lower[2] || z > t.upper[2])
    {
      continue;
    }
    const double extentY = t.upper[1] - t.lower[1];
    const double extentZ = t.upper[2] - t.lower[2];
    const double area = (t.b[1] - t.a[1]) * (t.c[2] - t.a[2]) - (t.b[2] - t.a[2]) * (t.c[1] - t.a[1]);
    if (std::abs(area) <= 1e-10 * std::max(extentY, extentZ) * std::max(extentY, extentZ))
    {
      uncertain.emplace_back(t.lower[0], t.upper[0]);
      continue;
    }
    double    eab, ebc, eca;
    const int sab = ScanLineEdgeSign(t.a, t.b, y, z, eab);
    const int sbc = ScanLineEdgeSign(t.b, t.c, y, z, ebc);
    const int sca = ScanLineEdgeSign(t.c, t.a, y, z, eca);
    if (sab == 0 || sab != sbc || sbc != sca)
    {
      continue;
    }
    const double sum = eab + ebc + eca;
    if (sum == 0.0)
    {
      uncertain.emplace_back(t.lower[0], t.upper[0]);
      continue;
    }
    // Barycentric weights: a is weighted by the edge opposite to it.
    const double x = std::min(t.upper[0], std::max(t.lower[0], (ebc * t.a[0] + eca * t.b[0] + eab * t.c[0]) / sum));
    crossings.push_back(ScanLineCrossing{ x, sab > 0 ? -orientationSign : orientationSign });
  }
  std::sort(crossings.begin(), crossings.end(), [](const ScanLineCrossing & left, const ScanLineCrossing & right) {
    return left.x < right.x;
  });
}

/** \brief Squared distance from the point (y, z) to the filled triangle (a, b, c) of the plane. */
inline double
PlaneTriangleSquaredDistance(double y, double z, const double * a, const double * b, const double * c)
{
  const auto edge = [y, z](const double * p, const double * q) {
    return (q[0] - p[0]) * (z - p[1]) - (q[1] - p[1]) * (y - p[0]);
  };
  const double eab = edge(a, b);
  const double ebc = edge(b, c);
  const double eca = edge(c, a);
  if ((eab >= 0.0 && ebc >= 0.0 && eca >= 0.0) || (eab <= 0.0 && ebc <= 0.0 && eca <= 0.0))
  {
    return 0.0;
  }
  const auto segment = [y, z](const double * p, const double * q) {
    const double dy = q[0] - p[0];
    const double dz = q[1] - p[1];
    const double lengthSquared = dy * dy + dz * dz;
    double       t = lengthSquared > 0.0 ? ((y - p[0]) * dy + (z - p[1]) * dz) / lengthSquared : 0.0;
    t = std::min(1.0, std::max(0.0, t));
    const double ey = p[0] + t * dy - y;
    const double ez = p[1] + t * dz - z;
    return ey * ey + ez * ez;
  };
  return std::min({ segment(a, b), segment(b, c), segment(c, a) });
}

/** \class WindingNumberGradientBound
 * \brief Upper bound of the gradient of the generalized winding number of a triangle soup over a box.
 *
 * Away from the surface, the gradient of the winding number w is the Biot-Savart field of the
 * triangles' boundaries, each triangle a unit current loop: \f$\nabla w(q) = \frac{1}{4\pi}\sum_e I_e
 * \int_e \frac{(x - q) \times dx}{|x - q|^3}\f$, where the edges shared by triangles cancel and only
 * the edges with a non-zero net current \f$I_e\f$ remain (hole rims, cuts, seams between inconsistently
 * oriented patches). For a closed, consistently oriented surface there is no such edge and w is
 * constant between crossings of the surface. For an edge at distance at least d from the box,
 * \f$\frac{1}{4\pi}\int_e |x - q|^{-2}\,dx \le \frac{1}{4\pi}\min(\ell_e / d^2, 4 / d)\f$. Edges are
 * grouped in leaves of up to 16 (median splits), each bounded as a whole when it is farther than its
 * own diagonal, edge by edge otherwise.
 * \ingroup FFDShapeMatching
 */
class WindingNumberGradientBound
{
public:
  using VectorType = std::array<double, 3>;

  /** Finds the edges with a non-zero net current. \c corners gives each triangle's vertex numbers, equal
   * for equal coordinates (edges are matched by these numbers). */
  void
  Build(const std::vector<TriangleBoundingVolumeHierarchy::Triangle> & triangles,
        const std::vector<std::array<std::uint32_t, 3>> &              corners)
  {
    struct HalfEdge
    {
      std::uint32_t      upper;
      int                current;
      const VectorType * lowerPoint;
      const VectorType * upperPoint;
    };
    std::uint32_t numberOfVertices = 0;
    for (const auto & c : corners)
    {
      numberOfVertices = std::max({ numberOfVertices, c[0] + 1, c[1] + 1, c[2] + 1 });
    }
    // Half edges bucketed by their lower vertex number (counting sort), then summed per upper vertex.
    std::vector<std::size_t> offsets(static_cast<std::size_t>(numberOfVertices) + 1, 0);
    for (const auto & c : corners)
    {
      for (unsigned int e = 0; e < 3; ++e)
      {
        ++offsets[std::min(c[e], c[(e + 1) % 3]) + 1];
      }
    }
    for (std::size_t i = 1; i < offsets.size(); ++i)
    {
      offsets[i] += offsets[i - 1];
    }
    std::vector<HalfEdge>    halfEdges(offsets.back());
    std::vector<std::size_t> cursor(offsets.begin(), offsets.end() - 1);
    for (std::size_t t = 0; t < triangles.size(); ++t)
    {
      const VectorType * points[3] = { &triangles[t].a, &triangles[t].b, &triangles[t].c };
      for (unsigned int e = 0; e < 3; ++e)
      {
        const std::uint32_t from = corners[t][e];
        const std::uint32_t to = corners[t][(e + 1) % 3];
        const bool          forward = from < to;
        halfEdges[cursor[forward ? from : to]++] = HalfEdge{ forward ? to : from,
                                                             forward ? 1 : -1,
                                                             forward ? points[e] : points[(e + 1) % 3],
                                                             forward ? points[(e + 1) % 3] : points[e] };
      }
    }
    m_Edges.clear();
    m_Leaves.clear();
    std::vector<std::pair<std::uint32_t, int>> sums;
    for (std::uint32_t v = 0; v < numberOfVertices; ++v)
    {
      sums.clear();
      for (std::size_t i = offsets[v]; i < offsets[v + 1]; ++i)
      {
        if (halfEdges[i].upper == v)
        {
          continue; // Both ends on one vertex: no length, no field.
        }
        auto found = std::find_if(sums.begin(), sums.end(), [&](const std::pair<std::uint32_t, int> & entry) {
          return entry.first == halfEdges[i].upper;
        });
        if (found == sums.end())
        {
          sums.emplace_back(halfEdges[i].upper, halfEdges[i].current);
        }
        else
        {
          found->second += halfEdges[i].current;
        }
      }
      for (const auto & entry : sums)
      {
        if (entry.second == 0)
        {
          continue;
        }
        const HalfEdge & any = *std::find_if(halfEdges.begin() + offsets[v],
                                             halfEdges.begin() + offsets[v + 1],
                                             [&](const HalfEdge & h) { return h.upper == entry.first; });
        Edge             edge;
        edge.a = *any.lowerPoint;
        edge.b = *any.upperPoint;
        edge.weight = std::abs(entry.second);
        double lengthSquared = 0.0;
        for (unsigned int k = 0; k < 3; ++k)
        {
          edge.lower[k] = std::min(edge.a[k], edge.b[k]);
          edge.upper[k] = std::max(edge.a[k], edge.b[k]);
          lengthSquared += (edge.b[k] - edge.a[k]) * (edge.b[k] - edge.a[k]);
        }
        edge.length = std::sqrt(lengthSquared);
        m_Edges.push_back(edge);
      }
    }
    if (!m_Edges.empty())
    {
      this->BuildLeaves(0, m_Edges.size());
    }
  }

  /** Number of edges with a non-zero net current; 0 for a closed, consistently oriented surface. */
  std::size_t
  GetNumberOfEdges() const
  {
    return m_Edges.size();
  }

  /** An upper bound of |grad w| over the box [lower, upper]; infinite when an edge touches the box. */
  double
  Bound(const VectorType & lower, const VectorType & upper) const
  {
    constexpr double inverseFourPi = 1.0 / (4.0 * 3.14159265358979323846);
    double           sum = 0.0;
    for (const Leaf & leaf : m_Leaves)
    {
      const double d = BoxDistance(leaf.lower, leaf.upper, lower, upper);
      if (d > leaf.diagonal)
      {
        sum += std::min(leaf.weightedLength / (d * d), 4.0 * leaf.weight / d);
        continue;
      }
      for (std::size_t i = leaf.first; i < leaf.first + leaf.count; ++i)
      {
        const Edge & edge = m_Edges[i];
        const double edgeDistance = BoxDistance(edge.lower, edge.upper, lower, upper);
        if (!(edgeDistance > 0.0))
        {
          return std::numeric_limits<double>::infinity();
        }
        sum += edge.weight * std::min(edge.length / (edgeDistance * edgeDistance), 4.0 / edgeDistance);
      }
    }
    return sum * inverseFourPi;
  }

private:
  struct Edge
  {
    VectorType a;
    VectorType b;
    VectorType lower;
    VectorType upper;
    double     length;
    double     weight;
  };

  struct Leaf
  {
    VectorType  lower;
    VectorType  upper;
    double      diagonal;
    double      weight;
    double      weightedLength;
    std::size_t first;
    std::size_t count;
  };

  static double
  BoxDistance(const VectorType & lowerA,
              const VectorType & upperA,
              const VectorType & lowerB,
              const VectorType & upperB)
  {
    double result = 0.0;
    for (unsigned int k = 0; k < 3; ++k)
    {
      const double gap = std::max({ lowerA[k] - upperB[k], lowerB[k] - upperA[k], 0.0 });
      result += gap * gap;
    }
    return std::sqrt(result);
  }

  void
  BuildLeaves(std::size_t first, std::size_t count)
  {
    VectorType lower = m_Edges[first].lower;
    VectorType upper = m_Edges[first].upper;
    for (std::size_t i = first; i < first + count; ++i)
    {
      for (unsigned int k = 0; k < 3; ++k)
      {
        lower[k] = std::min(lower[k], m_Edges[i].lower[k]);
        upper[k] = std::max(upper[k], m_Edges[i].upper[k]);
      }
    }
    if (count <= 16)
    {
      Leaf leaf{ lower, upper, 0.0, 0.0, 0.0, first, count };
      for (unsigned int k = 0; k < 3; ++k)
      {
        leaf.diagonal += (upper[k] - lower[k]) * (upper[k] - lower[k]);
      }
      leaf.diagonal = std::sqrt(leaf.diagonal);
      for (std::size_t i = first; i < first + count; ++i)
      {
        leaf.weight += m_Edges[i].weight;
        leaf.weightedLength += m_Edges[i].weight * m_Edges[i].length;
      }
      m_Leaves.push_back(leaf);
      return;
    }
    unsigned int axis = 0;
    for (unsigned int k = 1; k < 3; ++k)
    {
      if (upper[k] - lower[k] > upper[axis] - lower[axis])
      {
        axis = k;
      }
    }
    const std::size_t half = count / 2;
    std::nth_element(m_Edges.begin() + first,
                     m_Edges.begin() + first + half,
                     m_Edges.begin() + first + count,
                     [axis](const Edge & left, const Edge & right) {
                       return left.lower[axis] + left.upper[axis] < right.lower[axis] + right.upper[axis];
                     });
    this->BuildLeaves(first, half);
    this->BuildLeaves(first + half, count - half);
  }

  std::vector<Edge> m_Edges;
  std::vector<Leaf> m_Leaves;
};

} // namespace detail
} // namespace itk

#endif // itkScanLineWindingNumber_h
