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
#ifndef itkBSplineCoherentPointDriftRegistrationMethod_hxx
#define itkBSplineCoherentPointDriftRegistrationMethod_hxx

#include "itkBSplineCoherentPointDriftRegistrationMethod.h"
#include "FFDShapeMatchingDetail/itkBSplineLatticeRegularization.h"
#include "FFDShapeMatchingDetail/itkBSplineLatticeBlockJacobi.h"
#include "FFDShapeMatchingDetail/itkBSplineLatticeCoarseCorrection.h"
#include "FFDShapeMatchingDetail/itkBSplineSampleNormalOperator.h"
#include "FFDShapeMatchingDetail/itkSparseMultipleRightHandConjugateGradient.h"
#include "itkContinuousIndex.h"
#include "FFDShapeMatchingDetail/itkCubicBSplineKernel.h"
#include "itkMultiThreaderBase.h"
#include "FFDShapeMatchingDetail/itkNeighborCandidateLists.h"
#include "FFDShapeMatchingDetail/itkPointCloudKdTree.h"
#include "itkPointsLocator.h"
#include "itkVectorContainer.h"

#include "itk_eigen.h"
#include ITK_EIGEN(Sparse)

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <memory>
#include <random>
#include <sstream>
#include <utility>

namespace itk
{
namespace detail
{
/** The indices 0..count-1 in an order drawn from \c seed (Fisher-Yates with the portable mt19937 engine, so that
 * the samples are the same on every platform), cut to \c wanted. */
inline std::vector<IdentifierType>
DrawSampleIndices(std::vector<IdentifierType> candidates, unsigned int wanted, int seed)
{
  std::mt19937 engine(static_cast<std::mt19937::result_type>(seed));
  for (size_t i = candidates.size(); i > 1; --i)
  {
    const size_t j = static_cast<size_t>(engine() % i);
    std::swap(candidates[i - 1], candidates[j]);
  }
  if (candidates.size() > wanted)
  {
    candidates.resize(wanted);
  }
  std::sort(candidates.begin(), candidates.end());
  return candidates;
}

/** \c values reordered: the i-th becomes the \c order[i]-th of before (\c order a permutation of its indices). */
template <typename T>
void
ApplySampleOrder(const std::vector<size_t> & order, std::vector<T> & values)
{
  std::vector<T> reordered;
  reordered.reserve(values.size());
  for (const size_t i : order)
  {
    reordered.push_back(values[i]);
  }
  values.swap(reordered);
}

/** The cubic B-spline support of \c point on the control lattice \c coefficients (a coefficient image of the
 * transform), separably: the support is the 4 x 4 x 4 block of coefficients from the corner \c first (an index
 * i + n0 (j + n1 k) in a BSplineTransform's per-dimension parameter layout), with the weight
 * weights[a] weights[4 + b] weights[8 + c] at (i + a, j + b, k + c); \c derivatives, when given, receives the
 * weights' derivatives with respect to the continuous index along their axis, in the same layout. False, and nothing
 * written, when the support leaves the lattice (the point is outside the transform's domain). */
template <typename TImage, typename TPoint>
bool
BSplineSeparableSupport(const TImage *           coefficients,
                        const TPoint &           point,
                        unsigned int &           first,
                        std::array<double, 12> & weights,
                        std::array<double, 12> * derivatives = nullptr)
{
  ContinuousIndex<double, 3> u;
  coefficients->TransformPhysicalPointToContinuousIndex(point, u);
  const auto          size = coefficients->GetLargestPossibleRegion().GetSize();
  std::array<long, 3> corner{};
  for (unsigned int d = 0; d < 3; ++d)
  {
    if (!(std::abs(u[d]) < 1e9)) // far outside (or not a number): no support, and no overflowing conversion
    {
      return false;
    }
    corner[d] = static_cast<long>(std::floor(u[d])) - 1;
    if (corner[d] < 0 || corner[d] + 3 >= static_cast<long>(size[d]))
    {
      return false;
    }
  }
  for (unsigned int d = 0; d < 3; ++d)
  {
    for (long a = 0; a < 4; ++a)
    {
      weights[4 * d + a] = CubicBSpline(u[d] - static_cast<double>(corner[d] + a));
      if (derivatives != nullptr)
      {
        (*derivatives)[4 * d + a] = CubicBSplineDerivative(u[d] - static_cast<double>(corner[d] + a));
      }
    }
  }
  first = static_cast<unsigned int>(corner[0] +
                                    static_cast<long>(size[0]) * (corner[1] + static_cast<long>(size[1]) * corner[2]));
  return true;
}

/** The 64 weights and coefficient indices of a separable support (corner \c first, \c separable weights as
 * BSplineSeparableSupport gives them) on a lattice whose first two axes have \c size0 and \c size1 coefficients, the
 * first axis fastest. */
inline void
ExpandSeparableSupport(size_t                         size0,
                       size_t                         size1,
                       unsigned int                   first,
                       const std::array<double, 12> & separable,
                       std::array<double, 64> &       weights,
                       std::array<unsigned int, 64> & indices)
{
  unsigned int n = 0;
  for (unsigned int c = 0; c < 4; ++c)
  {
    for (unsigned int b = 0; b < 4; ++b)
    {
      for (unsigned int a = 0; a < 4; ++a, ++n)
      {
        weights[n] = separable[a] * separable[4 + b] * separable[8 + c];
        indices[n] = first + a + static_cast<unsigned int>(size0) * (b + static_cast<unsigned int>(size1) * c);
      }
    }
  }
}

/** The 64 weights and coefficient indices (in a BSplineTransform's per-dimension parameter layout) of the cubic
 * B-spline support of \c point on the control lattice \c coefficients (a coefficient image of the transform):
 * T(point) = point + sum_j weights[j] c[indices[j]], the first axis fastest. False, and nothing written, when the
 * support leaves the lattice (the point is outside the transform's domain). */
template <typename TImage, typename TPoint>
bool
BSplineSupportWeights(const TImage *                 coefficients,
                      const TPoint &                 point,
                      std::array<double, 64> &       weights,
                      std::array<unsigned int, 64> & indices)
{
  unsigned int           first = 0;
  std::array<double, 12> separable{};
  if (!BSplineSeparableSupport(coefficients, point, first, separable))
  {
    return false;
  }
  const auto size = coefficients->GetLargestPossibleRegion().GetSize();
  ExpandSeparableSupport(size[0], size[1], first, separable, weights, indices);
  return true;
}

/** The determinant of a 3 x 3 matrix. */
template <typename TMatrix>
double
Determinant3(const TMatrix & a)
{
  return a(0, 0) * (a(1, 1) * a(2, 2) - a(1, 2) * a(2, 1)) - a(0, 1) * (a(1, 0) * a(2, 2) - a(1, 2) * a(2, 0)) +
         a(0, 2) * (a(1, 0) * a(2, 1) - a(1, 1) * a(2, 0));
}

/** The determinant of the spatial Jacobian of x -> x + sum_j w_j(x) c_j at a sample whose separable support (corner
 * \c first on a lattice whose first two axes have \c size0 and \c size1 coefficients, \c weights and their index
 * derivatives \c derivatives as BSplineSeparableSupport gives them) is fixed: the coefficients of coordinate d are
 * \c coefficients[d] (a BSplineTransform's per-dimension layout), and \c indexFromPhysical is d index / d x of the
 * lattice. Contracted separably, as detail::SpatialJacobianEvaluator does for a BSplineTransform. */
inline double
SeparableSupportJacobianDeterminant(size_t                                       size0,
                                    size_t                                       size1,
                                    unsigned int                                 first,
                                    const std::array<double, 12> &               weights,
                                    const std::array<double, 12> &               derivatives,
                                    const std::array<const double *, 3> &        coefficients,
                                    const std::array<std::array<double, 3>, 3> & indexFromPhysical)
{
  // gradient[d][j] = d displacement_d / d index_j
  double gradient[3][3];
  CubicBSplineSupportIndexGradient(
    coefficients.data(), first, size0, size0 * size1, weights.data(), derivatives.data(), gradient);
  Eigen::Matrix3d jacobian;
  for (unsigned int d = 0; d < 3; ++d)
  {
    for (unsigned int k = 0; k < 3; ++k)
    {
      double sum = d == k ? 1.0 : 0.0;
      for (unsigned int j = 0; j < 3; ++j)
      {
        sum += gradient[d][j] * indexFromPhysical[j][k];
      }
      jacobian(d, k) = sum;
    }
  }
  return Determinant3(jacobian);
}

} // namespace detail

template <typename TFixedMesh, typename TMovingMesh>
BSplineCoherentPointDriftRegistrationMethod<TFixedMesh, TMovingMesh>::BSplineCoherentPointDriftRegistrationMethod()
{
  m_TransformDomainOrigin.Fill(0.0);
  m_TransformDomainPhysicalDimensions.Fill(0.0);
  this->AddOptionalInputName("InitialTransform", 2);
}

template <typename TFixedMesh, typename TMovingMesh>
auto
BSplineCoherentPointDriftRegistrationMethod<TFixedMesh, TMovingMesh>::MakeStartTransform() const ->
  typename BSplineTransformType::Pointer
{
  auto transform = BSplineTransformType::New();
  if (const TransformType * initial = this->GetInitialTransform())
  {
    const auto * bspline = dynamic_cast<const BSplineTransformType *>(initial);
    if (bspline == nullptr)
    {
      itkExceptionMacro(<< "the initial transform must be a cubic BSplineTransform<double, 3, 3>, not a "
                        << initial->GetNameOfClass());
    }
    transform->SetFixedParameters(bspline->GetFixedParameters());
    transform->SetParameters(bspline->GetParameters());
    return transform;
  }
  PointType  origin = m_TransformDomainOrigin;
  VectorType extent = m_TransformDomainPhysicalDimensions;
  bool       given = true;
  for (unsigned int d = 0; d < Dimension; ++d)
  {
    given = given && extent[d] > 0.0;
  }
  if (!given)
  {
    const auto box = this->GetFixedMesh()->GetBoundingBox();
    for (unsigned int d = 0; d < Dimension; ++d)
    {
      origin[d] = box->GetMinimum()[d] - m_DomainMargin;
      extent[d] = std::max(box->GetMaximum()[d] - box->GetMinimum()[d] + 2.0 * m_DomainMargin, 1e-3);
    }
  }
  typename BSplineTransformType::PhysicalDimensionsType dimensions;
  typename BSplineTransformType::MeshSizeType           meshSize;
  for (unsigned int d = 0; d < Dimension; ++d)
  {
    dimensions[d] = extent[d];
    meshSize[d] = m_NumberOfControlPointsPerAxis - 3;
  }
  typename BSplineTransformType::DirectionType direction;
  direction.SetIdentity();
  transform->SetTransformDomainOrigin(origin);
  transform->SetTransformDomainPhysicalDimensions(dimensions);
  transform->SetTransformDomainMeshSize(meshSize);
  transform->SetTransformDomainDirection(direction);
  transform->SetIdentity();
  return transform;
}

template <typename TFixedMesh, typename TMovingMesh>
void
BSplineCoherentPointDriftRegistrationMethod<TFixedMesh, TMovingMesh>::GenerateData()
{
  using ClockType = std::chrono::steady_clock;
  using RowMajorCoefficients = Eigen::Matrix<double, Eigen::Dynamic, Dimension, Eigen::RowMajor>;
  const auto start = ClockType::now();
  m_TimeLimitReached = false;
  m_SigmaValues.clear();
  m_MetricValues.clear();
  m_NumberOfRegularizationIncreases = 0;
  m_NumberOfMomentumRestarts = 0;
  m_NumberOfSolverIterationsTaken = 0;
  m_StopConditionDescription.clear();

  const FixedMeshType *  fixedMesh = this->GetFixedMesh();
  const MovingMeshType * movingMesh = this->GetMovingMesh();
  if (fixedMesh->GetNumberOfPoints() == 0 || movingMesh->GetNumberOfPoints() == 0)
  {
    itkExceptionMacro(<< "the " << (fixedMesh->GetNumberOfPoints() == 0 ? "fixed (target)" : "moving (source)")
                      << " mesh has no points");
  }
  typename BSplineTransformType::Pointer transform = this->MakeStartTransform();
  const auto                             coefficients = transform->GetCoefficientImages();
  const auto                             gridSize = coefficients[0]->GetLargestPossibleRegion().GetSize();
  const auto                             gridSpacing = coefficients[0]->GetSpacing();
  const double                           spacing = std::min({ gridSpacing[0], gridSpacing[1], gridSpacing[2] });
  const size_t                           numberOfCoefficients = transform->GetNumberOfParametersPerDimension();
  // Default widths, in control spacings, measured on the module's benchmark (benchmark/RESULTS.md): from the
  // identity a wide start (the deformation is not known), from a voxel method's result a narrow one.
  const bool   refining = this->GetInitialTransform() != nullptr;
  const double sigmaCeiling = m_InitialSigma > 0.0 ? m_InitialSigma : (refining ? 0.4 : 1.1) * spacing;

  // The target's area and open boundary, from its polygons.
  std::map<std::pair<IdentifierType, IdentifierType>, unsigned int> edgeUses;
  double                                                            area = 0.0;
  for (auto cell = fixedMesh->GetCells()->Begin(); cell != fixedMesh->GetCells()->End(); ++cell)
  {
    const auto * points = cell.Value()->GetPointIds();
    const auto   count = cell.Value()->GetNumberOfPoints();
    if (count < 3)
    {
      continue;
    }
    const PointType first = fixedMesh->GetPoint(points[0]);
    for (unsigned int i = 0; i < count; ++i)
    {
      const IdentifierType a = points[i];
      const IdentifierType b = points[(i + 1) % count];
      ++edgeUses[std::make_pair(std::min(a, b), std::max(a, b))];
      if (i + 2 < count)
      {
        const VectorType u = fixedMesh->GetPoint(points[i + 1]) - first;
        const VectorType v = fixedMesh->GetPoint(points[i + 2]) - first;
        area += 0.5 * CrossProduct(u, v).GetNorm();
      }
    }
  }
  if (!(area > 0.0))
  {
    itkExceptionMacro(<< "the fixed (target) mesh has no polygon of non-zero area");
  }
  using PointsContainer = VectorContainer<IdentifierType, PointType>;
  using LocatorType = PointsLocator<PointsContainer>;
  auto boundaryPoints = PointsContainer::New();
  {
    std::vector<IdentifierType> boundaryIds;
    for (const auto & edge : edgeUses)
    {
      if (edge.second == 1)
      {
        boundaryIds.push_back(edge.first.first);
        boundaryIds.push_back(edge.first.second);
      }
    }
    std::sort(boundaryIds.begin(), boundaryIds.end());
    boundaryIds.erase(std::unique(boundaryIds.begin(), boundaryIds.end()), boundaryIds.end());
    for (const IdentifierType id : boundaryIds)
    {
      boundaryPoints->push_back(fixedMesh->GetPoint(id));
    }
  }

  // The samples: target vertices inside the B-spline's domain, source vertices near it.
  std::vector<PointType>              y;
  std::vector<unsigned int>           firsts;
  std::vector<std::array<double, 12>> weights;
  std::vector<std::array<double, 12>> derivativeWeights; // for the fold checks' Jacobians
  {
    std::vector<IdentifierType> candidates(fixedMesh->GetNumberOfPoints());
    for (IdentifierType i = 0; i < candidates.size(); ++i)
    {
      candidates[i] = i;
    }
    for (const IdentifierType id : detail::DrawSampleIndices(candidates, m_NumberOfFixedSamples, this->GetRandomSeed()))
    {
      const PointType        p = fixedMesh->GetPoint(id);
      unsigned int           first = 0;
      std::array<double, 12> w{};
      std::array<double, 12> dw{};
      if (!detail::BSplineSeparableSupport(coefficients[0].GetPointer(), p, first, w, &dw))
      {
        continue;
      }
      y.push_back(p);
      firsts.push_back(first);
      weights.push_back(w);
      derivativeWeights.push_back(dw);
    }
    // The samples in the order of their supports' corners (the lattice's memory order), so that consecutive samples
    // gather and scatter mostly the same coefficients: a shuffled target's vertices would visit the lattice at
    // random.
    std::vector<size_t> order(firsts.size());
    for (size_t i = 0; i < order.size(); ++i)
    {
      order[i] = i;
    }
    std::stable_sort(order.begin(), order.end(), [&firsts](size_t a, size_t b) { return firsts[a] < firsts[b]; });
    detail::ApplySampleOrder(order, y);
    detail::ApplySampleOrder(order, firsts);
    detail::ApplySampleOrder(order, weights);
    detail::ApplySampleOrder(order, derivativeWeights);
  }
  const size_t numberOfFixed = y.size();
  if (numberOfFixed < 10)
  {
    itkExceptionMacro(<< "fewer than 10 target vertices lie inside the B-spline's domain (" << numberOfFixed << ")");
  }
  std::vector<PointType> x;
  {
    PointType  low = transform->GetTransformDomainOrigin();
    PointType  high = low;
    const auto dimensions = transform->GetTransformDomainPhysicalDimensions();
    for (unsigned int d = 0; d < Dimension; ++d)
    {
      low[d] -= 3.0 * sigmaCeiling;
      high[d] += dimensions[d] + 3.0 * sigmaCeiling;
    }
    std::vector<IdentifierType> candidates;
    for (IdentifierType i = 0; i < movingMesh->GetNumberOfPoints(); ++i)
    {
      const PointType p = movingMesh->GetPoint(i);
      bool            near = true;
      for (unsigned int d = 0; d < Dimension; ++d)
      {
        near = near && p[d] >= low[d] && p[d] <= high[d];
      }
      if (near)
      {
        candidates.push_back(i);
      }
    }
    for (const IdentifierType id :
         detail::DrawSampleIndices(candidates, m_NumberOfMovingSamples, this->GetRandomSeed() + 1))
    {
      x.push_back(movingMesh->GetPoint(id));
    }
  }
  const size_t numberOfMoving = x.size();
  if (numberOfMoving < 10)
  {
    itkExceptionMacro(<< "fewer than 10 source vertices lie near the B-spline's domain (" << numberOfMoving
                      << "): the meshes do not overlap");
  }
  // Target samples per unit area (the uniform outlier term is measured against it).
  const double density = static_cast<double>(numberOfFixed) / area;

  // The M-step's matrix B^T diag(P1) B + s (R + 1e-3 I), applied without being formed (R by its one-axis factors).
  detail::BSplineSampleNormalOperator normalOperator(
    { gridSize[0], gridSize[1], gridSize[2] },
    std::move(firsts), // the operator keeps the supports: it also applies B (the samples' weights) and B^T
    std::move(weights),
    1e-3);
  // The preconditioner: Jacobi's, plus a coarse-lattice correction for the smooth errors that Jacobi damps slowly.
  std::unique_ptr<detail::BSplineLatticeCoarseCorrection> coarseCorrection;
  if (m_NumberOfCoarseControlPointsPerAxis >= 2)
  {
    coarseCorrection =
      std::make_unique<detail::BSplineLatticeCoarseCorrection>(normalOperator, m_NumberOfCoarseControlPointsPerAxis);
  }
  // Its fine level: the blocks of 2 x 2 x 2 coefficients, or Jacobi's diagonal.
  std::unique_ptr<detail::BSplineLatticeBlockJacobi> blockJacobi;
  if (m_UseBlockJacobiPreconditioner)
  {
    blockJacobi = std::make_unique<detail::BSplineLatticeBlockJacobi>(normalOperator);
  }

  // d index / d x of the control lattice, for the fold checks.
  std::array<std::array<double, 3>, 3> indexFromPhysical{};
  for (unsigned int j = 0; j < Dimension; ++j)
  {
    for (unsigned int k = 0; k < Dimension; ++k)
    {
      indexFromPhysical[j][k] = coefficients[0]->GetInverseDirection()(j, k) / gridSpacing[j];
    }
  }

  // The coefficients c (one column per dimension) and the mapped samples Y + B c.
  Eigen::MatrixXd coefficient(numberOfCoefficients, Dimension);
  {
    const auto & parameters = transform->GetParameters();
    for (unsigned int d = 0; d < Dimension; ++d)
    {
      for (size_t k = 0; k < numberOfCoefficients; ++k)
      {
        coefficient(k, d) = parameters[d * numberOfCoefficients + k];
      }
    }
  }
  Eigen::MatrixXd target(numberOfFixed, Dimension);
  for (size_t m = 0; m < numberOfFixed; ++m)
  {
    for (unsigned int d = 0; d < Dimension; ++d)
    {
      target(m, d) = y[m][d];
    }
  }

  const detail::PointCloudAdaptor<PointType> movingCloud{ x };
  detail::PointCloudKdTree<PointType> movingTree(Dimension, movingCloud, nanoflann::KDTreeSingleIndexAdaptorParams(16));
  movingTree.buildIndex();

  // The widths. From the identity: 1.1 and 0.25 control spacings. From a voxel method's result, whose surfaces
  // already meet: at most 0.4 and 0.15 control spacings, and less when the surfaces are closer: 10 x the RMS
  // distance from the mapped target samples to their nearest source sample, the floor at most half the start.
  // Y + B c for coefficients c (B applied by the operator).
  const auto mappedBy = [&normalOperator, &target](const Eigen::MatrixXd & values) {
    RowMajorCoefficients samples;
    normalOperator.ApplyBasis(RowMajorCoefficients(values), samples);
    return Eigen::MatrixXd(target + samples);
  };
  // The mapped target samples Y + B c, kept current with the coefficients.
  Eigen::MatrixXd mapped = mappedBy(coefficient);
  double          startDistance = NumericTraits<double>::max();
  if (refining)
  {
    double startSquares = 0.0;
    for (size_t m = 0; m < numberOfFixed; ++m)
    {
      const std::array<double, 3> q{ mapped(m, 0), mapped(m, 1), mapped(m, 2) };
      size_t                      nearest = 0;
      double                      squared = 0.0;
      movingTree.knnSearch(q.data(), 1, &nearest, &squared);
      startSquares += squared;
    }
    startDistance = std::sqrt(startSquares / static_cast<double>(numberOfFixed));
  }
  const double sigmaStart =
    m_InitialSigma > 0.0
      ? m_InitialSigma
      : (refining ? std::min(sigmaCeiling, std::max(10.0 * startDistance, 1e-3 * spacing)) : sigmaCeiling);
  const double sigmaFloor =
    m_MinimumSigma > 0.0 ? m_MinimumSigma : (refining ? std::min(0.15 * spacing, 0.5 * sigmaStart) : 0.25 * spacing);
  // Over-relaxation: measured on the benchmark from GO's result, where what is left is sliding along the surface
  // (1.8); from the identity, where the shape is still being found, plain EM.
  const double overRelaxation = m_OverRelaxation > 0.0 ? m_OverRelaxation : (refining ? 1.8 : 1.0);
  const double boundaryDistance = m_OpenBoundaryDistance > 0.0 ? m_OpenBoundaryDistance : 2.0 * sigmaFloor;

  // Target samples near the open boundary.
  std::vector<bool> nearBoundary(numberOfFixed, false);
  if (!boundaryPoints->empty())
  {
    auto locator = LocatorType::New();
    locator->SetPoints(boundaryPoints);
    locator->Initialize();
    for (size_t m = 0; m < numberOfFixed; ++m)
    {
      const PointType & b = boundaryPoints->ElementAt(locator->FindClosestPoint(y[m]));
      nearBoundary[m] = b.EuclideanDistanceTo(y[m]) < boundaryDistance;
    }
  }


  const unsigned int  forwardNeighbors = std::min<unsigned int>(m_NumberOfNeighbors, numberOfMoving);
  const unsigned int  reverseNeighbors = std::min<unsigned int>(m_NumberOfNeighbors, numberOfFixed);
  double              lambda = m_RegularizationWeight;
  double              sigma2 = sigmaStart * sigmaStart;
  const double        w = m_OutlierWeight;
  MultiThreaderBase * threader = this->GetMultiThreader();
  threader->SetMaximumNumberOfThreads(this->GetNumberOfWorkUnits());

  std::ostringstream stop;
  unsigned int       iteration = 0;

  // The E-step's sums and the reverse direction's shares, allocated once for every iteration.
  std::vector<double>                mass(numberOfFixed);
  std::vector<std::array<double, 3>> pulled(numberOfFixed);
  std::vector<double>                squares(numberOfFixed);
  std::vector<unsigned int>          shareCounts; // a source sample's shares: its first pairs in reversePairs
  // The neighbour searches: each mapped target sample's candidate list of source samples (it moves, they do not;
  // a list reaches 1.25 times the search radius), the pairs closer than the search radius found from them (per
  // target sample), and the same pairs per source sample for the reverse direction (pairStart[n] to
  // pairStart[n + 1] in reversePairs).
  detail::NeighborCandidateLists                            forwardLists(numberOfFixed, 0.25);
  std::vector<std::vector<std::pair<unsigned int, double>>> pairs(numberOfFixed);
  std::vector<unsigned int>                                 pairStart(numberOfMoving + 1);
  std::vector<std::pair<unsigned int, double>>              reversePairs;
  // The momentum's memory: the coefficients before the last step, and that step's plain EM part.
  Eigen::MatrixXd previousCoefficient;
  Eigen::MatrixXd previousPlainStep;
  bool            previousStepAtFloor = false;
  Eigen::MatrixXd withoutMomentum;
  bool            momentumCarried = false;
  double          coarseSigma2 = NumericTraits<double>::quiet_NaN(); // sigma^2 when the coarse matrix was formed
  unsigned int    coarseIteration = 0;

  for (; iteration < m_NumberOfIterations; ++iteration)
  {
    if (m_MaximumRunTime > 0.0 && std::chrono::duration<double>(ClockType::now() - start).count() > m_MaximumRunTime)
    {
      m_TimeLimitReached = true;
      stop << "cpd: the run-time limit was reached after " << iteration << " iterations";
      break;
    }
    const double radius2 = 9.0 * sigma2;
    const double radius = std::sqrt(radius2);

    // E-step. Per target sample m: the matched mass P1_m, sum_n P_mn x_n and sum_n P_mn |x_n|^2.
    // Returns the total matched mass.
    const auto expectation = [&]() {
      std::fill(mass.begin(), mass.end(), 0.0);
      std::fill(pulled.begin(), pulled.end(), std::array<double, 3>{ 0.0, 0.0, 0.0 });
      std::fill(squares.begin(), squares.end(), 0.0);
      const double forward = m_ForwardWeight;
      const bool   reverse = forward < 1.0;
      // Forward: each mapped target sample's nearest source samples within 3 sigma (beyond it a weight is nil),
      // from its candidate list. The pairs closer than 3 sigma are kept for the reverse direction: they are the same
      // pairs seen from the source samples.
      threader->ParallelizeArray(
        0,
        numberOfFixed,
        [&](SizeValueType m) {
          const std::array<double, 3> q{ mapped(m, 0), mapped(m, 1), mapped(m, 2) };
          if (forwardLists.NeedsRebuild(m, q.data(), radius))
          {
            forwardLists.Rebuild(m, movingTree, q.data(), radius);
          }
          std::array<size_t, 64> neighbors{};
          std::array<double, 64> squaredDistances{};
          auto &                 within = pairs[m];
          within.clear();
          const size_t           found = forwardLists.Search(m,
                                                   x,
                                                   q.data(),
                                                   forwardNeighbors,
                                                   radius2,
                                                   neighbors.data(),
                                                   squaredDistances.data(),
                                                   [&](size_t n, double d2) {
                                                     if (reverse)
                                                     {
                                                       within.emplace_back(static_cast<unsigned int>(n), d2);
                                                     }
                                                   });
          double                 total = 0.0;
          std::array<double, 64> g{};
          for (size_t j = 0; j < found; ++j)
          {
            const double d2 = squaredDistances[j];
            g[j] = std::exp(-0.5 * d2 / sigma2);
            total += g[j];
          }
          if (total <= 0.0)
          {
            return;
          }
          for (size_t j = 0; j < found; ++j)
          {
            const double      p = forward * g[j] / total;
            const PointType & xn = x[neighbors[j]];
            mass[m] += p;
            for (unsigned int d = 0; d < Dimension; ++d)
            {
              pulled[m][d] += p * xn[d];
            }
            squares[m] += p * xn.GetVectorFromOrigin().GetSquaredNorm();
          }
        },
        nullptr);
      if (reverse)
      {
        // The same pairs grouped by source sample (counting sort, so each group is in target-sample order).
        std::fill(pairStart.begin(), pairStart.end(), 0u);
        for (size_t m = 0; m < numberOfFixed; ++m)
        {
          for (const auto & pair : pairs[m])
          {
            ++pairStart[pair.first + 1];
          }
        }
        for (size_t n = 0; n < numberOfMoving; ++n)
        {
          pairStart[n + 1] += pairStart[n];
        }
        reversePairs.resize(pairStart[numberOfMoving]);
        std::vector<unsigned int> next(pairStart.begin(), pairStart.end() - 1);
        for (size_t m = 0; m < numberOfFixed; ++m)
        {
          for (const auto & pair : pairs[m])
          {
            reversePairs[next[pair.first]++] = { static_cast<unsigned int>(m), pair.second };
          }
        }
        const double outlier = w / (1.0 - w) * 2.0 * Math::pi * sigma2 * density;
        shareCounts.assign(numberOfMoving, 0);
        threader->ParallelizeArray(
          0,
          numberOfMoving,
          [&](SizeValueType n) {
            // A source sample with no mapped target sample within 3 sigma takes no share (most of the source, where
            // the target is a patch).
            if (pairStart[n] == pairStart[n + 1])
            {
              return;
            }
            std::array<size_t, 64>               neighbors{};
            std::array<double, 64>               squaredDistances{};
            detail::NearestWithinRadiusResultSet nearest(
              reverseNeighbors, radius2, neighbors.data(), squaredDistances.data());
            for (unsigned int j = pairStart[n]; j < pairStart[n + 1]; ++j)
            {
              nearest.addPoint(reversePairs[j].second, reversePairs[j].first);
            }
            const size_t found = nearest.size();
            if (found == 0 || nearBoundary[neighbors[0]])
            {
              return;
            }
            // The shares overwrite the first of the source sample's own pairs, all read by now (found is at most
            // their number): (target sample, share).
            auto * const share = reversePairs.data() + pairStart[n];
            double       total = outlier;
            for (size_t j = 0; j < found; ++j)
            {
              share[j] = { static_cast<unsigned int>(neighbors[j]), std::exp(-0.5 * squaredDistances[j] / sigma2) };
              total += share[j].second;
            }
            for (size_t j = 0; j < found; ++j)
            {
              share[j].second *= (1.0 - forward) / total;
            }
            shareCounts[n] = static_cast<unsigned int>(found);
          },
          nullptr);
        for (size_t n = 0; n < numberOfMoving; ++n)
        {
          const double xx = x[n].GetVectorFromOrigin().GetSquaredNorm();
          for (unsigned int j = 0; j < shareCounts[n]; ++j)
          {
            const unsigned int m = reversePairs[pairStart[n] + j].first;
            const double       p = reversePairs[pairStart[n] + j].second;
            mass[m] += p;
            for (unsigned int d = 0; d < Dimension; ++d)
            {
              pulled[m][d] += p * x[n][d];
            }
            squares[m] += p * xx;
          }
        }
      }
      double total = 0.0;
      for (size_t m = 0; m < numberOfFixed; ++m)
      {
        total += mass[m];
      }
      return total;
    };
    double totalMass = expectation();
    // sum_mn P_mn |x_n - z_m|^2 for target samples at z.
    const auto residualAt = [&](const Eigen::MatrixXd & z) {
      double sum = 0.0;
      for (size_t m = 0; m < numberOfFixed; ++m)
      {
        double dot = 0.0;
        double norm = 0.0;
        for (unsigned int d = 0; d < Dimension; ++d)
        {
          dot += pulled[m][d] * z(m, d);
          norm += z(m, d) * z(m, d);
        }
        sum += squares[m] - 2.0 * dot + mass[m] * norm;
      }
      return sum;
    };
    // A step that carried momentum and raised the residual is taken back: the coefficients return to that step
    // without the momentum, and the momentum restarts.
    if (momentumCarried && totalMass > 0.0 && !m_MetricValues.empty() &&
        residualAt(mapped) / totalMass > m_MetricValues.back())
    {
      Eigen::MatrixXd back = mappedBy(withoutMomentum);
      mapped.swap(back);
      coefficient = withoutMomentum;
      previousStepAtFloor = false;
      ++m_NumberOfMomentumRestarts;
      totalMass = expectation();
    }
    momentumCarried = false;
    const double residual = residualAt(mapped);
    if (!(totalMass > 0.0))
    {
      stop << "cpd: no correspondence within 3 sigma after " << iteration << " iterations";
      break;
    }
    m_SigmaValues.push_back(std::sqrt(sigma2));
    m_MetricValues.push_back(residual / totalMass);

    // M-step: (B^T diag(P1) B + lambda (sigma/h)^2 s (R + 1e-3 I)) c = B^T (P X - diag(P1) Y).
    Eigen::VectorXd massVector(numberOfFixed);
    Eigen::MatrixXd right(numberOfFixed, Dimension);
    for (size_t m = 0; m < numberOfFixed; ++m)
    {
      massVector[m] = mass[m];
      for (unsigned int d = 0; d < Dimension; ++d)
      {
        right(m, d) = pulled[m][d] - mass[m] * target(m, d);
      }
    }
    RowMajorCoefficients rhs;
    normalOperator.ApplyBasisTranspose(RowMajorCoefficients(right), rhs);
    const double    scale = sigma2 / (spacing * spacing) * totalMass / 1000.0;
    Eigen::MatrixXd solved = coefficient;
    // The smallest det J at the target samples, from their fixed supports (in chunks over the work units).
    const auto minimumDeterminantOf = [&](const Eigen::MatrixXd & values) {
      const std::array<const double *, Dimension> columns{ values.col(0).data(),
                                                           values.col(1).data(),
                                                           values.col(2).data() };
      const size_t                                chunks = std::min<size_t>(numberOfFixed, 64);
      std::vector<double>                         chunkMinimum(chunks, NumericTraits<double>::max());
      threader->ParallelizeArray(
        0,
        chunks,
        [&](SizeValueType c) {
          for (size_t m = c * numberOfFixed / chunks; m < (c + 1) * numberOfFixed / chunks; ++m)
          {
            chunkMinimum[c] = std::min(chunkMinimum[c],
                                       detail::SeparableSupportJacobianDeterminant(gridSize[0],
                                                                                   gridSize[1],
                                                                                   normalOperator.GetFirsts()[m],
                                                                                   normalOperator.GetWeights()[m],
                                                                                   derivativeWeights[m],
                                                                                   columns,
                                                                                   indexFromPhysical));
          }
        },
        nullptr);
      return *std::min_element(chunkMinimum.begin(), chunkMinimum.end());
    };
    for (unsigned int attempt = 0;; ++attempt)
    {
      normalOperator.SetWeighting(massVector, lambda * scale);
      // The preconditioner's parts are formed again when the regularizer's weight was raised, when sigma moved
      // by more than 1 % since they were formed, or every CoarseCorrectionUpdateInterval iterations; in between, the
      // last ones serve (a preconditioner need only be close: at the minimum sigma the masses change little from one
      // iteration to the next).
      if ((coarseCorrection || blockJacobi) && (attempt > 0 || !(std::abs(sigma2 - coarseSigma2) <= 0.01 * sigma2) ||
                                                iteration >= coarseIteration + m_CoarseCorrectionUpdateInterval))
      {
        if (coarseCorrection)
        {
          coarseCorrection->Update();
        }
        if (blockJacobi)
        {
          blockJacobi->Update();
        }
        coarseSigma2 = sigma2;
        coarseIteration = iteration;
      }
      // The Dimension right-hand sides side by side: one pass over the samples per iteration serves all of them.
      RowMajorCoefficients columns = coefficient;
      const auto           apply = [&normalOperator](const RowMajorCoefficients & in, RowMajorCoefficients & out) {
        normalOperator.Apply(in, out);
      };
      const auto correct = [&coarseCorrection](const RowMajorCoefficients & residual, RowMajorCoefficients & z) {
        if (coarseCorrection)
        {
          coarseCorrection->AddCorrection(residual, z);
        }
      };
      if (blockJacobi)
      {
        m_NumberOfSolverIterationsTaken += detail::SolvePreconditionedConjugateGradient<Dimension>(
          apply,
          [&blockJacobi, &correct](const RowMajorCoefficients & residual, RowMajorCoefficients & z) {
            blockJacobi->Apply(residual, z);
            correct(residual, z);
          },
          rhs,
          columns,
          m_NumberOfSolverIterations,
          m_SolverTolerance);
      }
      else
      {
        m_NumberOfSolverIterationsTaken += detail::SolveConjugateGradient<Dimension>(
          apply, normalOperator.GetDiagonal(), rhs, columns, m_NumberOfSolverIterations, m_SolverTolerance, correct);
      }
      solved = columns;
      // Fold check at the target samples.
      if (minimumDeterminantOf(solved) >= m_MinimumJacobianDeterminant || attempt >= 6)
      {
        break;
      }
      lambda *= 4.0;
      ++m_NumberOfRegularizationIncreases;
    }
    const Eigen::MatrixXd plainStep = solved - coefficient;
    const double          change = plainStep.cwiseAbs().maxCoeff();
    // Over-relaxed step with momentum, once sigma is at its floor: EM at a small width slides along the surface in
    // many short steps; going further along each step's direction (over-relaxation) and keeping part of the last
    // step (heavy-ball momentum) converge in fewer iterations. The momentum restarts when the plain step turns back
    // against the previous one (an overshoot); where a longer step would fold, the shorter one is kept. (While sigma
    // still shrinks, a longer step overshoots.)
    const bool stepAtFloor = std::sqrt(sigma2) <= sigmaFloor * (1.0 + 1e-6);
    if (stepAtFloor)
    {
      const Eigen::MatrixXd relaxed = coefficient + overRelaxation * plainStep;
      if (overRelaxation > 1.0 && minimumDeterminantOf(relaxed) >= m_MinimumJacobianDeterminant)
      {
        solved = relaxed;
      }
      if (m_Momentum > 0.0 && previousStepAtFloor && plainStep.cwiseProduct(previousPlainStep).sum() >= 0.0)
      {
        const Eigen::MatrixXd pushed = solved + m_Momentum * (coefficient - previousCoefficient);
        if (minimumDeterminantOf(pushed) >= m_MinimumJacobianDeterminant)
        {
          withoutMomentum = solved;
          momentumCarried = true;
          solved = pushed;
        }
      }
    }
    if (m_Momentum > 0.0)
    {
      previousCoefficient = coefficient;
      previousPlainStep = plainStep;
      previousStepAtFloor = stepAtFloor;
    }
    coefficient = solved;
    // sigma^2 from the new positions.
    Eigen::MatrixXd moved = mappedBy(coefficient);
    const double    newResidual = residualAt(moved);
    const double    move = std::sqrt((moved - mapped).squaredNorm() / static_cast<double>(numberOfFixed));
    mapped.swap(moved);
    sigma2 = std::max(newResidual / (Dimension * totalMass), sigmaFloor * sigmaFloor);
    this->UpdateProgress(static_cast<float>(iteration + 1) / static_cast<float>(m_NumberOfIterations));
    this->InvokeEvent(IterationEvent());
    const bool atFloor = std::sqrt(sigma2) <= sigmaFloor * (1.0 + 1e-6);
    if (atFloor && change < 1e-4 * spacing)
    {
      ++iteration;
      stop << "cpd: converged after " << iteration << " iterations (largest coefficient change below 1e-4 x the "
           << "control spacing at the minimum sigma)";
      break;
    }
    if (atFloor && move < m_ConvergenceTolerance * spacing)
    {
      ++iteration;
      stop << "cpd: converged after " << iteration << " iterations (the mapped target samples moved " << move
           << " mm RMS, below " << m_ConvergenceTolerance << " x the control spacing, at the minimum sigma)";
      break;
    }
  }
  if (stop.str().empty())
  {
    stop << "cpd: " << iteration << " iterations (the maximum), sigma " << std::sqrt(sigma2) << " mm";
  }
  m_StopConditionDescription = stop.str();
  m_FinalRegularizationWeight = lambda;

  // The transform's parameters from the coefficient columns (SetParameters copies them).
  typename BSplineTransformType::ParametersType parameters(transform->GetNumberOfParameters());
  for (unsigned int d = 0; d < Dimension; ++d)
  {
    for (size_t k = 0; k < numberOfCoefficients; ++k)
    {
      parameters[d * numberOfCoefficients + k] = coefficient(k, d);
    }
  }
  transform->SetParameters(parameters);
  this->SetTransformOutputValue(transform);
  this->UpdateProgress(1.0f);
}

template <typename TFixedMesh, typename TMovingMesh>
void
BSplineCoherentPointDriftRegistrationMethod<TFixedMesh, TMovingMesh>::PrintSelf(std::ostream & os, Indent indent) const
{
  Superclass::PrintSelf(os, indent);
  os << indent << "NumberOfControlPointsPerAxis: " << m_NumberOfControlPointsPerAxis << std::endl;
  os << indent << "TransformDomainOrigin: " << m_TransformDomainOrigin << std::endl;
  os << indent << "TransformDomainPhysicalDimensions: " << m_TransformDomainPhysicalDimensions << std::endl;
  os << indent << "DomainMargin: " << m_DomainMargin << std::endl;
  os << indent << "RegularizationWeight: " << m_RegularizationWeight << std::endl;
  os << indent << "ForwardWeight: " << m_ForwardWeight << std::endl;
  os << indent << "OutlierWeight: " << m_OutlierWeight << std::endl;
  os << indent << "NumberOfIterations: " << m_NumberOfIterations << std::endl;
  os << indent << "ConvergenceTolerance: " << m_ConvergenceTolerance << std::endl;
  os << indent << "OverRelaxation: " << m_OverRelaxation << std::endl;
  os << indent << "Momentum: " << m_Momentum << std::endl;
  os << indent << "InitialSigma: " << m_InitialSigma << std::endl;
  os << indent << "MinimumSigma: " << m_MinimumSigma << std::endl;
  os << indent << "OpenBoundaryDistance: " << m_OpenBoundaryDistance << std::endl;
  os << indent << "NumberOfFixedSamples: " << m_NumberOfFixedSamples << std::endl;
  os << indent << "NumberOfMovingSamples: " << m_NumberOfMovingSamples << std::endl;
  os << indent << "NumberOfNeighbors: " << m_NumberOfNeighbors << std::endl;
  os << indent << "MinimumJacobianDeterminant: " << m_MinimumJacobianDeterminant << std::endl;
  os << indent << "NumberOfSolverIterations: " << m_NumberOfSolverIterations << std::endl;
  os << indent << "SolverTolerance: " << m_SolverTolerance << std::endl;
  os << indent << "NumberOfCoarseControlPointsPerAxis: " << m_NumberOfCoarseControlPointsPerAxis << std::endl;
  os << indent << "CoarseCorrectionUpdateInterval: " << m_CoarseCorrectionUpdateInterval << std::endl;
  os << indent << "UseBlockJacobiPreconditioner: " << (m_UseBlockJacobiPreconditioner ? "On" : "Off") << std::endl;
  os << indent << "MaximumRunTime: " << m_MaximumRunTime << std::endl;
  os << indent << "TimeLimitReached: " << m_TimeLimitReached << std::endl;
  os << indent << "NumberOfIterationsRun: " << m_SigmaValues.size() << std::endl;
  os << indent << "NumberOfRegularizationIncreases: " << m_NumberOfRegularizationIncreases << std::endl;
  os << indent << "NumberOfMomentumRestarts: " << m_NumberOfMomentumRestarts << std::endl;
  os << indent << "NumberOfSolverIterationsTaken: " << m_NumberOfSolverIterationsTaken << std::endl;
  os << indent << "FinalRegularizationWeight: " << m_FinalRegularizationWeight << std::endl;
  os << indent << "StopConditionDescription: " << m_StopConditionDescription << std::endl;
}
} // namespace itk

#endif // itkBSplineCoherentPointDriftRegistrationMethod_hxx
