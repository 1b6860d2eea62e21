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
#ifndef itkMRFLabelingSolverTestHelpers_h
#define itkMRFLabelingSolverTestHelpers_h

// Graphs and reference minima shared by the MRFLabelingSolver tests.
#include "itkIntTypes.h"
#include <algorithm>
#include <limits>
#include <utility>
#include <vector>

namespace itk
{
namespace testing
{
using MRFEdgeList = std::vector<std::pair<SizeValueType, SizeValueType>>;

/** The 6-neighbour edges of a cubic grid of side n (node x + n (y + n z)). */
inline MRFEdgeList
MRFGridEdges(SizeValueType n)
{
  MRFEdgeList edges;
  for (SizeValueType z = 0; z < n; ++z)
  {
    for (SizeValueType y = 0; y < n; ++y)
    {
      for (SizeValueType x = 0; x < n; ++x)
      {
        const SizeValueType p = x + n * (y + n * z);
        if (x + 1 < n)
        {
          edges.emplace_back(p, p + 1);
        }
        if (y + 1 < n)
        {
          edges.emplace_back(p, p + n);
        }
        if (z + 1 < n)
        {
          edges.emplace_back(p, p + n * n);
        }
      }
    }
  }
  return edges;
}

/** Global minimum of a chain (edge p joins nodes p and p + 1; tables[p][a * labels + b]) by dynamic programming. */
inline double
MRFChainMinimum(SizeValueType                            nodes,
                unsigned int                             labels,
                const std::vector<double> &              unary,
                const std::vector<std::vector<double>> & tables)
{
  std::vector<double> best(unary.begin(), unary.begin() + labels);
  std::vector<double> next(labels);
  for (SizeValueType p = 1; p < nodes; ++p)
  {
    for (unsigned int b = 0; b < labels; ++b)
    {
      double value = std::numeric_limits<double>::max();
      for (unsigned int a = 0; a < labels; ++a)
      {
        value = std::min(value, best[a] + tables[p - 1][a * labels + b]);
      }
      next[b] = value + unary[p * labels + b];
    }
    best.swap(next);
  }
  return *std::min_element(best.begin(), best.end());
}
} // namespace testing
} // namespace itk

#endif // itkMRFLabelingSolverTestHelpers_h
