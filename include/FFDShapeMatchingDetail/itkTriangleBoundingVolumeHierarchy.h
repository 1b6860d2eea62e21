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
#ifndef itkTriangleBoundingVolumeHierarchy_h
#define itkTriangleBoundingVolumeHierarchy_h

#include "FFDShapeMatchingDetail/itkPointTriangleDistance.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <vector>

namespace itk
{
namespace detail
{
/** \brief Signed solid angle subtended by the triangle (a, b, c) at q, in steradians.
 *
 * Van Oosterom and Strackee's formula, \f$\tan(\Omega/2) = \frac{\mathbf{a}\cdot(\mathbf{b}\times\mathbf{c})}
 * {|\mathbf{a}||\mathbf{b}||\mathbf{c}| + (\mathbf{a}\cdot\mathbf{b})|\mathbf{c}| + (\mathbf{b}\cdot\mathbf{c})
 * |\mathbf{a}| + (\mathbf{c}\cdot\mathbf{a})|\mathbf{b}|}\f$ with the vertices taken relative to q
 * (IEEE Trans. Biomed. Eng. 30(2):125-126, 1983, doi:10.1109/TBME.1983.325207). Positive when q
 * lies behind the triangle, on the side opposite its normal \f$(b-a)\times(c-a)\f$: inside a closed
 * surface whose normals point outwards.
 * \ingroup FFDShapeMatching
 */
inline double
TriangleSolidAngle(const std::array<double, 3> & q,
                   const std::array<double, 3> & a,
                   const std::array<double, 3> & b,
                   const std::array<double, 3> & c)
{
  const double ax = a[0] - q[0], ay = a[1] - q[1], az = a[2] - q[2];
  const double bx = b[0] - q[0], by = b[1] - q[1], bz = b[2] - q[2];
  const double cx = c[0] - q[0], cy = c[1] - q[1], cz = c[2] - q[2];
  const double la = std::sqrt(ax * ax + ay * ay + az * az);
  const double lb = std::sqrt(bx * bx + by * by + bz * bz);
  const double lc = std::sqrt(cx * cx + cy * cy + cz * cz);
  const double determinant = ax * (by * cz - bz * cy) - ay * (bx * cz - bz * cx) + az * (bx * cy - by * cx);
  const double denominator = la * lb * lc + (ax * bx + ay * by + az * bz) * lc + (bx * cx + by * cy + bz * cz) * la +
                             (cx * ax + cy * ay + cz * az) * lb;
  return 2.0 * std::atan2(determinant, denominator);
}

/** \class TriangleBoundingVolumeHierarchy
 * \brief Axis-aligned bounding-box tree over a triangle soup, for distance and winding-number queries.
 *
 * Built once (Build()), then queried concurrently from any number of threads (all queries are
 * const and allocate only on the stack). Each node stores its box and the far-field data of the
 * fast winding number: the area-weighted centre \f$\tilde{p}\f$, the radius r of the ball around
 * \f$\tilde{p}\f$ holding all its vertices, and the sum of area-weighted normals
 * \f$\mathbf{N} = \sum_i a_i \mathbf{n}_i\f$.
 *
 * - SquaredDistance() returns the exact squared distance to the closest triangle, pruned by an
 *   upper bound so a band-limited query only visits nodes whose box is within the band.
 * - AnyTriangleWithin() answers "is some triangle within distance r", stopping at the first one.
 * - WindingNumber() evaluates the generalized winding number
 *   \f$w(q) = \frac{1}{4\pi}\sum_i \Omega_i(q)\f$ (Jacobson et al. 2013) with the hierarchical
 *   far-field expansion of Barill et al. 2018: a node whose ball is far enough,
 *   \f$|q - \tilde{p}| > \beta r\f$, contributes the first two terms of the Taylor expansion of the
 *   dipole field around \f$\tilde{p}\f$: with \f$\mathbf{d} = \tilde{p} - q\f$ and the moment
 *   \f$M = \sum_i a_i \mathbf{n}_i (\mathbf{c}_i - \tilde{p})^T\f$ (\f$\mathbf{c}_i\f$ the centroids),
 *   \f$\frac{1}{4\pi}\left(\frac{\mathbf{N}\cdot\mathbf{d} + \mathrm{tr} M}{|\mathbf{d}|^3}
 *   - \frac{3\,\mathbf{d}^T M \mathbf{d}}{|\mathbf{d}|^5}\right)\f$;
 *   other nodes are opened, and the triangles of close leaves are summed exactly.
 *   \f$\beta = 0\f$ gives the exact sum.
 *
 * \par References
 * A. Jacobson, L. Kavan, O. Sorkine-Hornung, "Robust inside-outside segmentation using generalized
 * winding numbers", ACM TOG 32(4), 2013, doi:10.1145/2461912.2461916.
 * G. Barill, N. Dickson, R. Schmidt, D. I. W. Levin, A. Jacobson, "Fast winding numbers for soups
 * and clouds", ACM TOG 37(4), 2018, doi:10.1145/3197517.3201337.
 *
 * \ingroup FFDShapeMatching
 */
class TriangleBoundingVolumeHierarchy
{
public:
  using VectorType = std::array<double, 3>;

  struct Triangle
  {
    VectorType a;
    VectorType b;
    VectorType c;
  };

  /** Builds the tree over the given triangles (copied; their order is changed). Leaves hold at most
   * \c leafSize triangles. With \c farField false, the nodes get their boxes only, not the winding number's
   * far-field terms (centre, radius, dipole, moment): enough for SquaredDistance() and AnyTriangleWithin(), about
   * three times cheaper to build; WindingNumber() then throws. The tree itself (the split, the order of the
   * triangles, the boxes) is the same either way. */
  void
  Build(std::vector<Triangle> triangles, unsigned int leafSize = 4, bool farField = true)
  {
    m_FarField = farField;
    m_Triangles = std::move(triangles);
    m_Nodes.clear();
    m_LeafSize = std::max(1u, leafSize);
    if (m_Triangles.empty())
    {
      return;
    }
    // A split halves a node of more than m_LeafSize triangles, so every leaf holds at least half of
    // m_LeafSize + 1 of them (rounded down, at least one): that bounds the leaves, and a binary tree has fewer than
    // twice as many nodes as leaves. Reserved once, the nodes are never moved while the tree grows.
    const std::size_t fewestPerLeaf = std::max<std::size_t>(1, (m_LeafSize + 1) / 2);
    m_Nodes.reserve(2 * (m_Triangles.size() / fewestPerLeaf) + 1);
    // The splits reorder triangle numbers (keyed by their corners' coordinate sums), not the triangles themselves;
    // the triangles are put in the final order once, at the end (the same order as moving them at each split).
    const auto count = static_cast<std::uint32_t>(m_Triangles.size());
    m_Order.resize(count);
    m_CornerSums.resize(count);
    for (std::uint32_t i = 0; i < count; ++i)
    {
      const Triangle & t = m_Triangles[i];
      m_Order[i] = i;
      for (unsigned int k = 0; k < 3; ++k)
      {
        m_CornerSums[i][k] = t.a[k] + t.b[k] + t.c[k];
      }
    }
    this->BuildNode(0, count);
    std::vector<Triangle> ordered;
    ordered.reserve(count);
    for (const std::uint32_t i : m_Order)
    {
      ordered.push_back(m_Triangles[i]);
    }
    m_Triangles = std::move(ordered);
    m_Order = {};
    m_CornerSums = {};
  }

  std::size_t
  GetNumberOfTriangles() const
  {
    return m_Triangles.size();
  }

  std::size_t
  GetNumberOfNodes() const
  {
    return m_Nodes.size();
  }

  const std::vector<Triangle> &
  GetTriangles() const
  {
    return m_Triangles;
  }

  /** Exact squared distance from q to the closest triangle when it is smaller than
   * \c maxSquaredDistance, otherwise \c maxSquaredDistance. When \c closestPoint is given, the closest point of that
   * triangle goes there and the triangle's index (in GetTriangles()) to \c closestTriangle (when given); both are
   * left unchanged when no triangle is closer than \c maxSquaredDistance. */
  double
  SquaredDistance(const VectorType & q,
                  double             maxSquaredDistance = std::numeric_limits<double>::infinity(),
                  VectorType *       closestPoint = nullptr,
                  std::size_t *      closestTriangle = nullptr) const
  {
    double best = maxSquaredDistance;
    if (m_Nodes.empty() || BoxSquaredDistance(m_Nodes[0], q) >= best)
    {
      return best;
    }
    std::uint32_t stack[StackSize];
    unsigned int  top = 0;
    stack[top++] = 0;
    VectorType closest;
    while (top > 0)
    {
      const Node & node = m_Nodes[stack[--top]];
      if (BoxSquaredDistance(node, q) >= best)
      {
        continue;
      }
      if (node.count > 0)
      {
        for (std::uint32_t i = node.first; i < node.first + node.count; ++i)
        {
          const Triangle & t = m_Triangles[i];
          const double     squared = ClosestPointOnTriangle(q, t.a, t.b, t.c, closest);
          if (squared < best)
          {
            best = squared;
            if (closestPoint != nullptr)
            {
              *closestPoint = closest;
            }
            if (closestTriangle != nullptr)
            {
              *closestTriangle = i;
            }
          }
        }
        continue;
      }
      const double leftDistance = BoxSquaredDistance(m_Nodes[node.left], q);
      const double rightDistance = BoxSquaredDistance(m_Nodes[node.right], q);
      // Push the farther child first so the closer one is visited first and tightens the bound.
      if (leftDistance < rightDistance)
      {
        if (rightDistance < best)
        {
          stack[top++] = node.right;
        }
        stack[top++] = node.left;
      }
      else
      {
        if (leftDistance < best)
        {
          stack[top++] = node.left;
        }
        if (rightDistance < best)
        {
          stack[top++] = node.right;
        }
      }
    }
    return best;
  }

  /** True when some triangle lies at distance <= radius from q. */
  bool
  AnyTriangleWithin(const VectorType & q, double radius) const
  {
    const double radiusSquared = radius * radius;
    if (m_Nodes.empty() || BoxSquaredDistance(m_Nodes[0], q) > radiusSquared)
    {
      return false;
    }
    std::uint32_t stack[StackSize];
    unsigned int  top = 0;
    stack[top++] = 0;
    VectorType closest;
    while (top > 0)
    {
      const Node & node = m_Nodes[stack[--top]];
      if (node.count > 0)
      {
        for (std::uint32_t i = node.first; i < node.first + node.count; ++i)
        {
          const Triangle & t = m_Triangles[i];
          if (ClosestPointOnTriangle(q, t.a, t.b, t.c, closest) <= radiusSquared)
          {
            return true;
          }
        }
        continue;
      }
      if (BoxSquaredDistance(m_Nodes[node.right], q) <= radiusSquared)
      {
        stack[top++] = node.right;
      }
      if (BoxSquaredDistance(m_Nodes[node.left], q) <= radiusSquared)
      {
        stack[top++] = node.left;
      }
    }
    return false;
  }

  /** Generalized winding number at q, with the far-field accuracy parameter beta (0: exact). */
  double
  WindingNumber(const VectorType & q, double beta) const
  {
    if (!m_FarField)
    {
      throw std::logic_error(
        "TriangleBoundingVolumeHierarchy: WindingNumber() on a tree built without far-field terms");
    }
    if (m_Nodes.empty())
    {
      return 0.0;
    }
    double        solidAngle = 0.0;
    std::uint32_t stack[StackSize];
    unsigned int  top = 0;
    stack[top++] = 0;
    while (top > 0)
    {
      const Node &     node = m_Nodes[stack[--top]];
      const VectorType d = { node.center[0] - q[0], node.center[1] - q[1], node.center[2] - q[2] };
      const double     distanceSquared = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
      if (beta > 0.0 && distanceSquared > beta * beta * node.radius * node.radius)
      {
        // First order N.d / |d|^3, second order tr(M) / |d|^3 - 3 d'Md / |d|^5, with d = p~ - q.
        const double distance = std::sqrt(distanceSquared);
        const double inverseCube = 1.0 / (distanceSquared * distance);
        const auto & m = node.moment;
        const double dMd = d[0] * (m[0] * d[0] + m[1] * d[1] + m[2] * d[2]) +
                           d[1] * (m[3] * d[0] + m[4] * d[1] + m[5] * d[2]) +
                           d[2] * (m[6] * d[0] + m[7] * d[1] + m[8] * d[2]);
        solidAngle += inverseCube * (d[0] * node.dipole[0] + d[1] * node.dipole[1] + d[2] * node.dipole[2] + m[0] +
                                     m[4] + m[8] - 3.0 * dMd / distanceSquared);
      }
      else if (node.count > 0)
      {
        for (std::uint32_t i = node.first; i < node.first + node.count; ++i)
        {
          const Triangle & t = m_Triangles[i];
          solidAngle += TriangleSolidAngle(q, t.a, t.b, t.c);
        }
      }
      else
      {
        stack[top++] = node.left;
        stack[top++] = node.right;
      }
    }
    return solidAngle / (4.0 * 3.14159265358979323846);
  }

private:
  static constexpr unsigned int StackSize = 128;

  struct Node
  {
    VectorType boxMin;
    VectorType boxMax;
    VectorType center;
    VectorType dipole;
    // Second-order moment M(j, k) = sum_i a_i n_i(j) (c_i - p~)(k), row-major.
    std::array<double, 9> moment;
    double                radius;
    std::uint32_t         first;
    std::uint32_t         count; // > 0 for leaves
    std::uint32_t         left;
    std::uint32_t         right;
  };

  static double
  BoxSquaredDistance(const Node & node, const VectorType & q)
  {
    double result = 0.0;
    for (unsigned int i = 0; i < 3; ++i)
    {
      const double d = std::max(std::max(node.boxMin[i] - q[i], q[i] - node.boxMax[i]), 0.0);
      result += d * d;
    }
    return result;
  }

  /** The centroid of a triangle. */
  static VectorType
  Centroid(const Triangle & t)
  {
    return { (t.a[0] + t.b[0] + t.c[0]) / 3.0, (t.a[1] + t.b[1] + t.c[1]) / 3.0, (t.a[2] + t.b[2] + t.c[2]) / 3.0 };
  }

  /** Half the cross product of a triangle's edges: its area-weighted normal. */
  static VectorType
  AreaNormal(const Triangle & t)
  {
    VectorType ab;
    VectorType ac;
    for (unsigned int k = 0; k < 3; ++k)
    {
      ab[k] = t.b[k] - t.a[k];
      ac[k] = t.c[k] - t.a[k];
    }
    return { 0.5 * (ab[1] * ac[2] - ab[2] * ac[1]),
             0.5 * (ab[2] * ac[0] - ab[0] * ac[2]),
             0.5 * (ab[0] * ac[1] - ab[1] * ac[0]) };
  }

  /** Grows a node's box by a triangle's vertices and the centroids' bounds by its centroid. */
  static void
  GrowBounds(const Triangle & t, Node & node, VectorType & centroidMin, VectorType & centroidMax)
  {
    const VectorType centroid = Centroid(t);
    for (unsigned int k = 0; k < 3; ++k)
    {
      node.boxMin[k] = std::min({ node.boxMin[k], t.a[k], t.b[k], t.c[k] });
      node.boxMax[k] = std::max({ node.boxMax[k], t.a[k], t.b[k], t.c[k] });
      centroidMin[k] = std::min(centroidMin[k], centroid[k]);
      centroidMax[k] = std::max(centroidMax[k], centroid[k]);
    }
  }

  std::uint32_t
  BuildNode(std::uint32_t first, std::uint32_t count)
  {
    const auto index = static_cast<std::uint32_t>(m_Nodes.size());
    m_Nodes.emplace_back();
    Node         node{};
    const double infinity = std::numeric_limits<double>::infinity();
    node.boxMin = { infinity, infinity, infinity };
    node.boxMax = { -infinity, -infinity, -infinity };
    VectorType centroidMin = node.boxMin;
    VectorType centroidMax = node.boxMax;
    for (std::uint32_t i = first; i < first + count; ++i)
    {
      GrowBounds(m_Triangles[m_Order[i]], node, centroidMin, centroidMax);
    }
    if (!m_FarField)
    {
      return this->FinishNode(index, node, first, count, centroidMin, centroidMax);
    }
    double     totalArea = 0.0;
    VectorType weightedCenter = { 0.0, 0.0, 0.0 };
    VectorType plainCenter = { 0.0, 0.0, 0.0 };
    node.dipole = { 0.0, 0.0, 0.0 };
    for (std::uint32_t i = first; i < first + count; ++i)
    {
      const Triangle & t = m_Triangles[m_Order[i]];
      const VectorType areaNormal = AreaNormal(t);
      const VectorType centroid = Centroid(t);
      const double     area =
        std::sqrt(areaNormal[0] * areaNormal[0] + areaNormal[1] * areaNormal[1] + areaNormal[2] * areaNormal[2]);
      totalArea += area;
      for (unsigned int k = 0; k < 3; ++k)
      {
        node.dipole[k] += areaNormal[k];
        weightedCenter[k] += area * centroid[k];
        plainCenter[k] += centroid[k];
      }
    }
    for (unsigned int k = 0; k < 3; ++k)
    {
      node.center[k] = totalArea > 0.0 ? weightedCenter[k] / totalArea : plainCenter[k] / count;
    }
    node.radius = 0.0;
    node.moment.fill(0.0);
    for (std::uint32_t i = first; i < first + count; ++i)
    {
      const Triangle & t = m_Triangles[m_Order[i]];
      const VectorType areaNormal = AreaNormal(t);
      const VectorType centroid = Centroid(t);
      for (unsigned int j = 0; j < 3; ++j)
      {
        for (unsigned int k = 0; k < 3; ++k)
        {
          node.moment[3 * j + k] += areaNormal[j] * (centroid[k] - node.center[k]);
        }
      }
      for (const VectorType * v : { &t.a, &t.b, &t.c })
      {
        const double dx = (*v)[0] - node.center[0];
        const double dy = (*v)[1] - node.center[1];
        const double dz = (*v)[2] - node.center[2];
        node.radius = std::max(node.radius, std::sqrt(dx * dx + dy * dy + dz * dz));
      }
    }

    return this->FinishNode(index, node, first, count, centroidMin, centroidMax);
  }

  /** Stores \c node at \c index: a leaf, or split at the median of the centroids along the longest axis of their
   * bounds, with both halves built. */
  std::uint32_t
  FinishNode(std::uint32_t      index,
             Node &             node,
             std::uint32_t      first,
             std::uint32_t      count,
             const VectorType & centroidMin,
             const VectorType & centroidMax)
  {
    if (count <= m_LeafSize)
    {
      node.first = first;
      node.count = count;
      m_Nodes[index] = node;
      return index;
    }
    // Median split of the centroids along the longest axis of their bounds.
    unsigned int axis = 0;
    for (unsigned int k = 1; k < 3; ++k)
    {
      if (centroidMax[k] - centroidMin[k] > centroidMax[axis] - centroidMin[axis])
      {
        axis = k;
      }
    }
    const std::uint32_t half = count / 2;
    std::nth_element(
      m_Order.begin() + first,
      m_Order.begin() + first + half,
      m_Order.begin() + first + count,
      [this, axis](std::uint32_t x, std::uint32_t y) { return m_CornerSums[x][axis] < m_CornerSums[y][axis]; });
    node.count = 0;
    node.first = first;
    m_Nodes[index] = node;
    const std::uint32_t left = this->BuildNode(first, half);
    const std::uint32_t right = this->BuildNode(first + half, count - half);
    m_Nodes[index].left = left;
    m_Nodes[index].right = right;
    return index;
  }

  std::vector<Triangle> m_Triangles;
  // While Build() runs: the triangles' numbers in tree order and their corners' coordinate sums per axis.
  std::vector<std::uint32_t>         m_Order;
  std::vector<std::array<double, 3>> m_CornerSums;
  bool                               m_FarField{ true };
  std::vector<Node>                  m_Nodes;
  unsigned int                       m_LeafSize{ 4 };
};

} // namespace detail
} // namespace itk

#endif // itkTriangleBoundingVolumeHierarchy_h
