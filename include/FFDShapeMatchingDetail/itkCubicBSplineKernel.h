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
#ifndef itkCubicBSplineKernel_h
#define itkCubicBSplineKernel_h

#include <cmath>
#include <cstddef>

namespace itk
{
namespace detail
{
/** \file itkCubicBSplineKernel.h
 * \brief The centred cubic B-spline kernel, its first two derivatives and the four weights of a support, as plain
 * inline functions for the module's hot loops (the sparse B-spline metric, the MRF unary projection, the lattice
 * penalty and the point-set methods evaluate them per voxel and support point; ITK's BSplineKernelFunction is a
 * virtual-dispatch object). The module's one definition of the kernel.
 * \ingroup FFDShapeMatching
 */

/** Cubic B-spline kernel: (4 - 6u^2 + 3|u|^3)/6 for |u| < 1, (2 - |u|)^3/6 for |u| < 2, 0 beyond. */
inline double
CubicBSpline(double u)
{
  const double a = std::abs(u);
  if (a < 1.0)
  {
    return (4.0 - 6.0 * a * a + 3.0 * a * a * a) / 6.0;
  }
  if (a < 2.0)
  {
    const double b = 2.0 - a;
    return b * b * b / 6.0;
  }
  return 0.0;
}

/** Derivative of CubicBSpline(). */
inline double
CubicBSplineDerivative(double u)
{
  const double a = std::abs(u);
  if (a < 1.0)
  {
    return -2.0 * u + 1.5 * u * a;
  }
  if (a < 2.0)
  {
    const double b = 2.0 - a;
    return (u < 0.0 ? 0.5 : -0.5) * b * b;
  }
  return 0.0;
}

/** Second derivative of CubicBSpline(). */
inline double
CubicBSplineSecondDerivative(double u)
{
  const double a = std::abs(u);
  if (a < 1.0)
  {
    return -2.0 + 3.0 * a;
  }
  if (a < 2.0)
  {
    return 2.0 - a;
  }
  return 0.0;
}

/** CubicBSpline() (order 0), its first (1) or its second (2 or more) derivative. */
inline double
CubicBSplineOfOrder(double u, unsigned int order)
{
  switch (order)
  {
    case 0:
      return CubicBSpline(u);
    case 1:
      return CubicBSplineDerivative(u);
    default:
      return CubicBSplineSecondDerivative(u);
  }
}

/** The weights of the four control points at offsets -1, 0, 1, 2 from a point at fraction t in [0, 1) of its cell:
 * CubicBSpline(t + 1), CubicBSpline(t), CubicBSpline(t - 1), CubicBSpline(t - 2), written for the cell. */
inline void
CubicBSplineWeights(double t, double weights[4])
{
  const double s = 1.0 - t;
  weights[0] = s * s * s / 6.0;
  weights[1] = (4.0 - 6.0 * t * t + 3.0 * t * t * t) / 6.0;
  weights[2] = (4.0 - 6.0 * s * s + 3.0 * s * s * s) / 6.0;
  weights[3] = t * t * t / 6.0;
}
/** The index gradient G(d, j) = d displacement_d / d index_j of a 3-D cubic B-spline displacement at a point whose
 * 4 x 4 x 4 support starts at the linear index \c first of the coefficient buffers \c coefficients[d] (the first
 * axis fastest, \c stride1 and \c stride2 between neighbours along the second and third axes). \c weights and
 * \c derivatives hold the support's weights and their derivatives per axis, four per axis (weights[4 a + k]).
 * Contracted separably: each row of 4 coefficients along the first axis with that axis' weights and derivatives,
 * then the rows with the second axis' factors, then the planes with the third's (about a third of the products of
 * the 64-term sum). \c gradient is overwritten. */
template <typename TCoefficient>
void
CubicBSplineSupportIndexGradient(const TCoefficient * const coefficients[3],
                                 size_t                     first,
                                 size_t                     stride1,
                                 size_t                     stride2,
                                 const double *             weights,
                                 const double *             derivatives,
                                 double                     gradient[3][3])
{
  for (unsigned int d = 0; d < 3; ++d)
  {
    for (unsigned int j = 0; j < 3; ++j)
    {
      gradient[d][j] = 0.0;
    }
  }
  for (unsigned int c = 0; c < 4; ++c)
  {
    double plane[3][3] = {}; // [d][0: w_x w_y, 1: w'_x w_y, 2: w_x w'_y]
    for (unsigned int b = 0; b < 4; ++b)
    {
      const size_t rowStart = first + b * stride1 + c * stride2;
      for (unsigned int d = 0; d < 3; ++d)
      {
        const TCoefficient * row = coefficients[d] + rowStart;
        double               value = 0.0;
        double               slope = 0.0;
        for (unsigned int a = 0; a < 4; ++a)
        {
          value += weights[a] * static_cast<double>(row[a]);
          slope += derivatives[a] * static_cast<double>(row[a]);
        }
        plane[d][0] += weights[4 + b] * value;
        plane[d][1] += weights[4 + b] * slope;
        plane[d][2] += derivatives[4 + b] * value;
      }
    }
    for (unsigned int d = 0; d < 3; ++d)
    {
      gradient[d][0] += weights[8 + c] * plane[d][1];
      gradient[d][1] += weights[8 + c] * plane[d][2];
      gradient[d][2] += derivatives[8 + c] * plane[d][0];
    }
  }
}
} // namespace detail
} // namespace itk

#endif // itkCubicBSplineKernel_h
