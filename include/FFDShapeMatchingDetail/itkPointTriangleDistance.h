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
#ifndef itkPointTriangleDistance_h
#define itkPointTriangleDistance_h

#include <algorithm>
#include <type_traits>

namespace itk
{
namespace detail
{
/** \brief Closest point on a segment [a, b] to p, in three dimensions, computed in double.
 *
 * A zero-length segment is handled (its closest point is \c a). Returns the squared distance
 * and writes the closest point into \c closest.
 *
 * TPoint is any type with operator[] over three coordinates (itk::Point, itk::Vector,
 * itk::FixedArray, double[3] wrapped in a struct, ...).
 *
 * \ingroup FFDShapeMatching
 */
template <typename TPoint>
double
ClosestPointOnSegment(const TPoint & p, const TPoint & a, const TPoint & b, TPoint & closest)
{
  double ab[3];
  double ap[3];
  for (unsigned int i = 0; i < 3; ++i)
  {
    ab[i] = static_cast<double>(b[i]) - static_cast<double>(a[i]);
    ap[i] = static_cast<double>(p[i]) - static_cast<double>(a[i]);
  }
  const double abab = ab[0] * ab[0] + ab[1] * ab[1] + ab[2] * ab[2];
  double       t = 0.0;
  if (abab > 0.0)
  {
    t = (ab[0] * ap[0] + ab[1] * ap[1] + ab[2] * ap[2]) / abab;
    t = std::min(1.0, std::max(0.0, t));
  }
  double squaredDistance = 0.0;
  for (unsigned int i = 0; i < 3; ++i)
  {
    const double q = static_cast<double>(a[i]) + t * ab[i];
    closest[i] = static_cast<typename std::decay<decltype(closest[i])>::type>(q);
    const double d = static_cast<double>(p[i]) - q;
    squaredDistance += d * d;
  }
  return squaredDistance;
}

/** \brief Exact closest point on the triangle (a, b, c) to the point p, in three dimensions.
 *
 * Returns the squared Euclidean distance from p to the triangle (the filled, closed triangle,
 * not its plane) and writes the closest point into \c closest. The computation is done in
 * double precision whatever the coordinate type.
 *
 * Non-degenerate triangles use the Voronoi-region method of C. Ericson, "Real-Time Collision
 * Detection" (Morgan Kaufmann, 2005), section 5.1.5: the closest point is found by testing the
 * vertex regions, then the edge regions, then the face region, with barycentric coordinates
 * obtained from dot products only. Degenerate triangles (collinear or coincident vertices,
 * i.e. \f$|(b-a)\times(c-a)|^2 \le 10^{-24}\,\ell_{max}^4\f$ with \f$\ell_{max}\f$ the longest
 * edge) are treated as the union of their three edges (segments or a point).
 *
 * \code
 * itk::Point<double, 3> closest;
 * const double d2 = itk::detail::ClosestPointOnTriangle(p, a, b, c, closest);
 * \endcode
 *
 * \sa PointTriangleSquaredDistance
 * \ingroup FFDShapeMatching
 */
template <typename TPoint>
double
ClosestPointOnTriangle(const TPoint & p, const TPoint & a, const TPoint & b, const TPoint & c, TPoint & closest)
{
  double ab[3];
  double ac[3];
  double bc[3];
  double ap[3];
  double bp[3];
  double cp[3];
  for (unsigned int i = 0; i < 3; ++i)
  {
    const double ai = static_cast<double>(a[i]);
    const double bi = static_cast<double>(b[i]);
    const double ci = static_cast<double>(c[i]);
    const double pi = static_cast<double>(p[i]);
    ab[i] = bi - ai;
    ac[i] = ci - ai;
    bc[i] = ci - bi;
    ap[i] = pi - ai;
    bp[i] = pi - bi;
    cp[i] = pi - ci;
  }
  const auto dot = [](const double * u, const double * v) { return u[0] * v[0] + u[1] * v[1] + u[2] * v[2]; };

  // Degenerate triangle: the closest of its three edges.
  const double normal[3] = { ab[1] * ac[2] - ab[2] * ac[1],
                             ab[2] * ac[0] - ab[0] * ac[2],
                             ab[0] * ac[1] - ab[1] * ac[0] };
  const double maxEdgeSquared = std::max(dot(ab, ab), std::max(dot(ac, ac), dot(bc, bc)));
  if (dot(normal, normal) <= 1e-24 * maxEdgeSquared * maxEdgeSquared)
  {
    TPoint       candidate = closest;
    double       best = ClosestPointOnSegment(p, a, b, closest);
    const double dbc = ClosestPointOnSegment(p, b, c, candidate);
    if (dbc < best)
    {
      best = dbc;
      closest = candidate;
    }
    const double dca = ClosestPointOnSegment(p, c, a, candidate);
    if (dca < best)
    {
      best = dca;
      closest = candidate;
    }
    return best;
  }

  // Barycentric coordinates (u, v, w) of the closest point: closest = u a + v b + w c.
  double       u = 1.0;
  double       v = 0.0;
  double       w = 0.0;
  const double d1 = dot(ab, ap);
  const double d2 = dot(ac, ap);
  const double d3 = dot(ab, bp);
  const double d4 = dot(ac, bp);
  const double d5 = dot(ab, cp);
  const double d6 = dot(ac, cp);
  const double vc = d1 * d4 - d3 * d2;
  const double vb = d5 * d2 - d1 * d6;
  const double va = d3 * d6 - d5 * d4;
  if (d1 <= 0.0 && d2 <= 0.0)
  {
    // Vertex region of a.
  }
  else if (d3 >= 0.0 && d4 <= d3)
  {
    u = 0.0; // Vertex region of b.
    v = 1.0;
  }
  else if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0)
  {
    v = d1 / (d1 - d3); // Edge region of ab.
    u = 1.0 - v;
  }
  else if (d6 >= 0.0 && d5 <= d6)
  {
    u = 0.0; // Vertex region of c.
    w = 1.0;
  }
  else if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0)
  {
    w = d2 / (d2 - d6); // Edge region of ac.
    u = 1.0 - w;
  }
  else if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0)
  {
    w = (d4 - d3) / ((d4 - d3) + (d5 - d6)); // Edge region of bc.
    u = 0.0;
    v = 1.0 - w;
  }
  else
  {
    const double denominator = 1.0 / (va + vb + vc); // Face region.
    v = vb * denominator;
    w = vc * denominator;
    u = 1.0 - v - w;
  }

  double squaredDistance = 0.0;
  for (unsigned int i = 0; i < 3; ++i)
  {
    const double q = u * static_cast<double>(a[i]) + v * static_cast<double>(b[i]) + w * static_cast<double>(c[i]);
    closest[i] = static_cast<typename std::decay<decltype(closest[i])>::type>(q);
    const double d = static_cast<double>(p[i]) - q;
    squaredDistance += d * d;
  }
  return squaredDistance;
}

/** \brief Squared Euclidean distance from p to the triangle (a, b, c); see ClosestPointOnTriangle().
 * \ingroup FFDShapeMatching
 */
template <typename TPoint>
double
PointTriangleSquaredDistance(const TPoint & p, const TPoint & a, const TPoint & b, const TPoint & c)
{
  TPoint closest = p;
  return ClosestPointOnTriangle(p, a, b, c, closest);
}

} // namespace detail
} // namespace itk

#endif // itkPointTriangleDistance_h
