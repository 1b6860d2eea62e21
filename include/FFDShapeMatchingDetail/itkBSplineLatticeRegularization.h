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
#ifndef itkBSplineLatticeRegularization_h
#define itkBSplineLatticeRegularization_h

#include "itk_eigen.h"
#include ITK_EIGEN(Sparse)
#include <array>
#include <cmath>
#include <vector>

namespace itk
{
namespace detail
{
/** \file itkBSplineLatticeRegularization.h
 * \brief The discrete bending energy of a 3-D control lattice as a sparse quadratic form.
 *
 * For control values c on a lattice of size n0 x n1 x n2 (index i + n0 (j + n1 k), the layout of a
 * BSplineTransform's parameters per dimension), returns R = L^T L, where L stacks the second differences along
 * each axis and sqrt(2) times the mixed first differences of each pair of axes: c^T R c is the lattice form of the
 * thin-plate bending energy sum (c_xx^2 + c_yy^2 + c_zz^2 + 2 c_xy^2 + 2 c_xz^2 + 2 c_yz^2), in lattice units.
 * R annihilates constant and linear fields.
 * \ingroup FFDShapeMatching
 */
inline Eigen::SparseMatrix<double>
BSplineLatticeBendingMatrix(const std::array<size_t, 3> & size)
{
  using Triplet = Eigen::Triplet<double>;
  const auto index = [&size](size_t i, size_t j, size_t k) {
    return static_cast<int>(i + size[0] * (j + size[1] * k));
  };
  std::vector<Triplet> rows;
  int                  row = 0;
  const double         mixed = std::sqrt(2.0);
  for (size_t k = 0; k < size[2]; ++k)
  {
    for (size_t j = 0; j < size[1]; ++j)
    {
      for (size_t i = 0; i < size[0]; ++i)
      {
        const std::array<size_t, 3> at{ i, j, k };
        for (unsigned int a = 0; a < 3; ++a)
        {
          if (at[a] + 2 < size[a])
          {
            std::array<size_t, 3> p = at;
            rows.emplace_back(row, index(p[0], p[1], p[2]), 1.0);
            ++p[a];
            rows.emplace_back(row, index(p[0], p[1], p[2]), -2.0);
            ++p[a];
            rows.emplace_back(row, index(p[0], p[1], p[2]), 1.0);
            ++row;
          }
          for (unsigned int b = a + 1; b < 3; ++b)
          {
            if (at[a] + 1 < size[a] && at[b] + 1 < size[b])
            {
              std::array<size_t, 3> p = at;
              rows.emplace_back(row, index(p[0], p[1], p[2]), mixed);
              ++p[a];
              rows.emplace_back(row, index(p[0], p[1], p[2]), -mixed);
              ++p[b];
              rows.emplace_back(row, index(p[0], p[1], p[2]), mixed);
              --p[a];
              rows.emplace_back(row, index(p[0], p[1], p[2]), -mixed);
              ++row;
            }
          }
        }
      }
    }
  }
  Eigen::SparseMatrix<double> stencils(row, static_cast<int>(size[0] * size[1] * size[2]));
  stencils.setFromTriplets(rows.begin(), rows.end());
  return Eigen::SparseMatrix<double>(stencils.transpose() * stencils);
}

} // namespace detail
} // namespace itk

#endif // itkBSplineLatticeRegularization_h
