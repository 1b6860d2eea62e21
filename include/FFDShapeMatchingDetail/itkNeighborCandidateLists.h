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
#ifndef itkNeighborCandidateLists_h
#define itkNeighborCandidateLists_h

#include "itkMacro.h"
#include "FFDShapeMatchingDetail/itkPointCloudKdTree.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <type_traits>
#include <vector>

namespace itk
{
namespace detail
{

/** \class NeighborCandidateLists
 * \brief Radius searches for queries that move a little between rounds of searches among fixed points: each query
 * keeps a list of candidates (a Verlet list) and is answered from it instead of a tree search.
 *
 * Query n's list holds the points that were within its list radius R_n = (1 + skin) r of the query when the list
 * was built (by a radius search of a k-d tree over the points, Rebuild()). Once the query has moved by a (its
 * distance from where the list was built), a point within r of it was within r + a of the query then; while
 * r + a < R_n the list holds every point within r, and ForEachWithin() visits exactly the points within r (with their
 * squared distances computed as nanoflann's L2 adaptor computes them), and Search() picks the k nearest of them, as
 * SearchNearestWithinRadius() on the tree would. NeedsRebuild() says when that no longer holds, and also when r has
 * shrunk below a quarter of R_n (a list that long costs more to scan than to build again). Tested against brute
 * force.
 *
 * The lists of different queries are independent: a round may rebuild and search different queries concurrently.
 * \ingroup FFDShapeMatching */
class NeighborCandidateLists
{
public:
  /** \c numberOfQueries lists, none built; \c skin > 0 is the list radius's excess over the search radius, relative
   * to it. */
  NeighborCandidateLists(size_t numberOfQueries, double skin)
    : m_Skin(skin)
    , m_Candidates(numberOfQueries)
    , m_BuiltAt(numberOfQueries)
    , m_ListRadius(numberOfQueries, -1.0)
  {
    if (!(skin > 0.0))
    {
      itkGenericExceptionMacro(<< "NeighborCandidateLists: the skin must be positive, not " << skin);
    }
  }

  /** Whether query n at \c query (3 coordinates) needs its list built again before a search within \c radius. */
  bool
  NeedsRebuild(size_t n, const double * query, double radius) const
  {
    const double listRadius = m_ListRadius[n];
    if (listRadius < 0.0)
    {
      return true;
    }
    double squaredMove = 0.0;
    for (unsigned int d = 0; d < 3; ++d)
    {
      const double difference = query[d] - m_BuiltAt[n][d];
      squaredMove += difference * difference;
    }
    const double reach = radius + std::sqrt(squaredMove);
    return !(reach * (1.0 + 1e-9) < listRadius) || radius < 0.25 * listRadius;
  }

  /** Builds query n's list: the points of \c tree (a nanoflann k-d tree over the points) within (1 + skin)
   * \c radius of \c query. */
  template <typename TTree>
  void
  Rebuild(size_t n, const TTree & tree, const double * query, double radius)
  {
    const double listRadius = (1.0 + m_Skin) * radius;
    auto &       candidates = m_Candidates[n];
    candidates.clear();
    CollectWithinRadius collector{ listRadius * listRadius, candidates };
    tree.findNeighbors(collector, query, {});
    for (unsigned int d = 0; d < 3; ++d)
    {
      m_BuiltAt[n][d] = query[d];
    }
    m_ListRadius[n] = listRadius;
  }

  /** Calls visit(index, squaredDistance) for each of query n's candidates at a squared distance below
   * \c squaredRadius from \c query, \c points being indexable by a point's index, each by coordinate. While
   * NeedsRebuild() is false, these are all the points within the radius. */
  template <typename TPoints, typename TVisit>
  void
  ForEachWithin(size_t n, const TPoints & points, const double * query, double squaredRadius, TVisit && visit) const
  {
    // A chunk of candidates at a time: the distances first, the ones within kept without a branch, then visited in
    // list order (whether a candidate is within is a coin toss the branch predictor loses).
    constexpr size_t                  chunk = 64;
    const std::vector<unsigned int> & candidates = m_Candidates[n];
    std::array<unsigned int, chunk>   keptIndices;
    std::array<double, chunk>         keptDistances;
    for (size_t start = 0; start < candidates.size(); start += chunk)
    {
      const size_t end = std::min(start + chunk, candidates.size());
      size_t       kept = 0;
      for (size_t c = start; c < end; ++c)
      {
        const unsigned int index = candidates[c];
        double             squaredDistance = 0.0;
        for (unsigned int d = 0; d < 3; ++d)
        {
          const double difference = query[d] - points[index][d];
          squaredDistance += difference * difference;
        }
        keptIndices[kept] = index;
        keptDistances[kept] = squaredDistance;
        kept += squaredDistance < squaredRadius ? 1 : 0;
      }
      for (size_t j = 0; j < kept; ++j)
      {
        visit(static_cast<size_t>(keptIndices[j]), keptDistances[j]);
      }
    }
  }

  /** The at most k points nearest to \c query among query n's candidates at a squared distance below
   * \c squaredRadius, nearest first: SearchNearestWithinRadius()'s answer while NeedsRebuild() is false. Returns
   * how many were found. \c visitWithin, when given, is also called as visitWithin(index, squaredDistance) for every
   * candidate within the radius (the k nearest among them or not), in list order. */
  template <typename TPoints, typename TVisit = std::nullptr_t>
  size_t
  Search(size_t          n,
         const TPoints & points,
         const double *  query,
         size_t          k,
         double          squaredRadius,
         size_t *        indices,
         double *        squaredDistances,
         TVisit &&       visitWithin = nullptr) const
  {
    NearestWithinRadiusResultSet result(k, squaredRadius, indices, squaredDistances);
    this->ForEachWithin(n, points, query, squaredRadius, [&](size_t index, double squaredDistance) {
      if (k > 0)
      {
        result.addPoint(squaredDistance, index);
      }
      if constexpr (!std::is_same_v<std::decay_t<TVisit>, std::nullptr_t>)
      {
        visitWithin(index, squaredDistance);
      }
    });
    return result.size();
  }

  /** The number of candidates in query n's list. */
  size_t
  GetNumberOfCandidates(size_t n) const
  {
    return m_Candidates[n].size();
  }

private:
  /** nanoflann's result set that keeps every point within a radius, in the order found. */
  struct CollectWithinRadius
  {
    using DistanceType = double;
    using IndexType = size_t;
    using CountType = size_t;
    double                      SquaredRadius;
    std::vector<unsigned int> & Indices;
    size_t
    size() const
    {
      return Indices.size();
    }
    bool
    empty() const
    {
      return Indices.empty();
    }
    bool
    full() const
    {
      return true;
    }
    double
    worstDist() const
    {
      return SquaredRadius;
    }
    bool
    addPoint(double squaredDistance, size_t index)
    {
      if (squaredDistance < SquaredRadius)
      {
        Indices.push_back(static_cast<unsigned int>(index));
      }
      return true;
    }
    void
    sort()
    {}
  };

  double                                 m_Skin;
  std::vector<std::vector<unsigned int>> m_Candidates;
  std::vector<std::array<double, 3>>     m_BuiltAt;
  std::vector<double>                    m_ListRadius;
};

} // namespace detail
} // namespace itk

#endif // itkNeighborCandidateLists_h
