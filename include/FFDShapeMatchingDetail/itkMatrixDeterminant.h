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
#ifndef itkMatrixDeterminant_h
#define itkMatrixDeterminant_h

#include "itkMatrix.h"
#include "itk_eigen.h"
#include ITK_EIGEN(Core)
#include ITK_EIGEN(LU)

namespace itk
{
namespace detail
{
/** \file itkMatrixDeterminant.h
 * \brief The determinant of a small square itk::Matrix (a spatial Jacobian), computed by ITK's Eigen: vnl's
 * determinant functions are deprecated in ITK 6, and the module builds against ITK 5.2 to 6.
 * \ingroup FFDShapeMatching
 */
template <typename T, unsigned int VDimension>
T
MatrixDeterminant(const Matrix<T, VDimension, VDimension> & matrix)
{
  Eigen::Matrix<T, VDimension, VDimension, Eigen::RowMajor> dense;
  for (unsigned int r = 0; r < VDimension; ++r)
  {
    for (unsigned int c = 0; c < VDimension; ++c)
    {
      dense(r, c) = matrix[r][c];
    }
  }
  return dense.determinant();
}
} // namespace detail
} // namespace itk

#endif
