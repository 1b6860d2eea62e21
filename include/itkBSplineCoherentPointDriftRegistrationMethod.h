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
#ifndef itkBSplineCoherentPointDriftRegistrationMethod_h
#define itkBSplineCoherentPointDriftRegistrationMethod_h

#include "itkFFDShapeMatchingCompatibility.h"
#include "itkMeshRegistrationMethodBase.h"
#include "itkBSplineTransform.h"
#include "itkDataObjectDecorator.h"
#include "itkTransform.h"
#include <chrono>
#include <string>
#include <vector>

namespace itk
{
/** \class BSplineCoherentPointDriftRegistrationMethod
 * \brief Matches a target mesh to a source mesh with a B-spline transform by soft point correspondences in both
 * directions: coherent point drift written on the B-spline coefficients (the "CPD" method of the FFDShapeMatching
 * pipeline).
 *
 * The transform T (target space to source space, the module's convention) is a cubic BSplineTransform. Samples
 * y_m of the target's vertices (the fixed mesh) and x_n of the source's vertices (the moving mesh) are matched by an
 * EM algorithm with Gaussian soft correspondences of width sigma:
 * - forward: each mapped target sample T(y_m) is drawn to the Gaussian-weighted mean of its nearest source samples
 *   (every target point has a counterpart on the source: the target is a part of it);
 * - reverse: each source sample x_n is shared among its nearest mapped target samples, with a uniform outlier
 *   term (weight OutlierWeight) for the source surface that the target does not cover, as in coherent point drift;
 *   source samples whose nearest mapped target sample lies within OpenBoundaryDistance of the target's open
 *   boundary (edges used by one cell) are left out, since beyond a cut-out patch's border there is no counterpart.
 * The two are mixed by ForwardWeight. The M-step is a sparse least-squares problem in the control displacements:
 * (B^T diag(P1) B + lambda (sigma/h)^2 s R) c = B^T (P X - diag(P1) Y), with B the B-spline weights of the target
 * samples (64 per sample), R the discrete bending energy of the control lattice (second differences), h the control
 * spacing and s the matched mass per thousand samples (so that lambda = RegularizationWeight does not depend on
 * the scale of the meshes nor on the number of samples). It is solved by Jacobi-preconditioned conjugate gradients,
 * the three coordinates side by side (detail::SolveConjugateGradient), with the matrix applied sample by sample
 * without being formed (detail::BSplineSampleNormalOperator) and a coarse-lattice correction added to the
 * preconditioner (detail::BSplineLatticeCoarseCorrection), warm-started from the previous iteration (a
 * generalized EM step). sigma starts at InitialSigma, follows the EM update and is
 * kept above MinimumSigma; by default 1.1 and 0.25 control spacings from the identity, and from an initial
 * transform (a voxel method's result) 10 x the RMS distance from the mapped target samples to their nearest source
 * sample, at most 0.4 control spacings, with a floor of at most 0.15 control spacings and half the start.
 * Once sigma is at its floor, each step is over-relaxed, and may carry heavy-ball momentum (OverRelaxation,
 * Momentum): what is left there is sliding along the surface, which plain EM does in many short steps.
 * Nearest neighbours are searched within 3 sigma (beyond it a weight is nil): each mapped target sample keeps a list
 * of the source samples within 1.25 times that of where it was (detail::NeighborCandidateLists, built from nanoflann's
 * k-d tree), searched until it has moved too far; the pairs closer than 3 sigma found from it are the reverse
 * direction's too, grouped by source sample. The run
 * ends after NumberOfIterations, or earlier once sigma is at its floor and the mapped target samples have stopped
 * moving (ConvergenceTolerance).
 * A step that would fold the transform at the target samples (det J below MinimumJacobianDeterminant) is solved
 * again with four times the regularization.
 *
 * Inputs: the fixed mesh (the target; its vertices are sampled and its cells give the open boundary and the area),
 * the moving mesh (the source; its vertices are sampled), and optionally an initial transform (a decorated
 * BSplineTransform<double, 3, 3>, e.g. the GO method's result: its grid and coefficients are the start). Without
 * one, the grid is NumberOfControlPointsPerAxis control points over TransformDomainOrigin /
 * TransformDomainPhysicalDimensions, or, when those are not set, over the target's bounding box grown by
 * DomainMargin.
 * Output: the transform T as a decorated Transform<double, 3, 3>.
 *
 * Progress is reported per iteration; an IterationEvent is invoked with each, and sigma and the mean squared
 * residual are kept per iteration. A run-time limit (MaximumRunTime) stops at the first iteration past it with the
 * transform reached. The E-step is threaded over the process object's NumberOfWorkUnits.
 *
 * \par References
 * A. Myronenko, X. Song, "Point set registration: coherent point drift", IEEE TPAMI 32(12), 2010 (the EM
 * algorithm, the outlier term and the sigma update); O. Hirose, "A Bayesian formulation of coherent point drift",
 * IEEE TPAMI 43(7), 2021 (motion coherence for partial shapes).
 *
 * \sa BSplineFFDImageRegistrationMethod, ParametricTemplateRegistrationMethod, MeshShapeMatchingFilter
 * \ingroup FFDShapeMatching
 */
template <typename TFixedMesh, typename TMovingMesh = TFixedMesh>
class ITK_TEMPLATE_EXPORT BSplineCoherentPointDriftRegistrationMethod
  : public MeshRegistrationMethodBase<TFixedMesh, TMovingMesh>
{
public:
  ITK_DISALLOW_COPY_AND_MOVE(BSplineCoherentPointDriftRegistrationMethod);

  using Self = BSplineCoherentPointDriftRegistrationMethod;
  using Superclass = MeshRegistrationMethodBase<TFixedMesh, TMovingMesh>;
  using Pointer = SmartPointer<Self>;
  using ConstPointer = SmartPointer<const Self>;

  itkNewMacro(Self);
  itkOverrideGetNameOfClassMacro(BSplineCoherentPointDriftRegistrationMethod);

  static constexpr unsigned int Dimension = 3;

  using FixedMeshType = TFixedMesh;
  using MovingMeshType = TMovingMesh;
  using TransformType = Transform<double, Dimension, Dimension>;
  using BSplineTransformType = BSplineTransform<double, Dimension, 3>;
  using DecoratedTransformType = DataObjectDecorator<TransformType>;
  using PointType = typename BSplineTransformType::InputPointType;
  using VectorType = typename BSplineTransformType::InputVectorType;

  // FixedMesh (its vertices are sampled, its cells give the open boundary) and MovingMesh (its vertices are
  // sampled), GetTransformOutput(), GetTransform() and RandomSeed (of the sampling): see the superclass.

  /** Optional start: a BSplineTransform (cubic), whose grid and coefficients are used. */
  itkSetGetDecoratedObjectInputMacro(InitialTransform, TransformType);

  /** Control points per axis when there is no initial transform (>= 4). Default: 20. */
  itkSetClampMacro(NumberOfControlPointsPerAxis, unsigned int, 4, 1000);
  itkGetConstMacro(NumberOfControlPointsPerAxis, unsigned int);

  /** The B-spline's domain when there is no initial transform; a zero size means the target's bounding box grown
   * by DomainMargin. */
  itkSetMacro(TransformDomainOrigin, PointType);
  itkGetConstReferenceMacro(TransformDomainOrigin, PointType);
  itkSetMacro(TransformDomainPhysicalDimensions, VectorType);
  itkGetConstReferenceMacro(TransformDomainPhysicalDimensions, VectorType);

  /** Growth of the target's bounding box (mm) when the domain is not given. Default: 5. */
  itkSetClampMacro(DomainMargin, double, 0.0, NumericTraits<double>::max());
  itkGetConstMacro(DomainMargin, double);

  /** lambda, the weight of the bending energy (see the class description). Default: 3. */
  itkSetClampMacro(RegularizationWeight, double, 0.0, NumericTraits<double>::max());
  itkGetConstMacro(RegularizationWeight, double);

  /** Share of the forward term (target to source) against the reverse term, in [0, 1]. Default: 0.5. */
  itkSetClampMacro(ForwardWeight, double, 0.0, 1.0);
  itkGetConstMacro(ForwardWeight, double);

  /** w of the reverse term's uniform outlier component, in [0, 1). Default: 0.3. */
  itkSetClampMacro(OutlierWeight, double, 0.0, 0.99);
  itkGetConstMacro(OutlierWeight, double);

  /** EM iterations at most. Default: 40. */
  itkSetClampMacro(NumberOfIterations, unsigned int, 1, NumericTraits<unsigned int>::max());
  itkGetConstMacro(NumberOfIterations, unsigned int);

  /** The run stops before NumberOfIterations once sigma is at its floor and an iteration moves the mapped target
   * samples by less than ConvergenceTolerance control spacings (root mean square over the samples); 0 turns this
   * test off (the run then stops after NumberOfIterations, or when no coefficient changes by 1e-4 control spacings).
   * Default: 1e-3 (2-4 um on the benchmark's cases, whose control spacings are 2-4 mm): where the surfaces already
   * correspond, as in the benchmark's paper regime, the true error is flat after 12-19 iterations and the run stops
   * there; where the samples still slide along the surface the moves stay above it and the run goes on
   * (benchmark/PEERS_MESH.md). */
  itkSetClampMacro(ConvergenceTolerance, double, 0.0, NumericTraits<double>::max());
  itkGetConstMacro(ConvergenceTolerance, double);

  /** Over-relaxation of the EM step once sigma is at its floor: the coefficients move OverRelaxation times the step
   * that the M-step solved (where that does not fold), at most 1.95; 1 (or less) is plain EM. 0 (default) means 1.8
   * from an initial transform (what is left after a voxel method is sliding along the surface, which plain EM does
   * in many short steps) and 1 from the identity. */
  itkSetClampMacro(OverRelaxation, double, 0.0, 1.95);
  itkGetConstMacro(OverRelaxation, double);
  /** Heavy-ball momentum of the EM step once sigma is at its floor, in [0, 0.99]: the coefficients move by
   * OverRelaxation times the M-step's step plus Momentum times their last change,
   * c <- c + w (M(c) - c) + Momentum (c - c_previous), where that does not fold. The momentum restarts (is left out for
   * one step) when the M-step's step turns back against the previous one, and a step that carried momentum and raised
   * the mean squared residual at the next E-step is taken back to its value without the momentum (one more E-step;
   * NumberOfMomentumRestarts). Default: 0, none (plain EM); MeshShapeMatchingFilter sets 0.9 for its GOCPD method.
   * Measured on the module's benchmark from GO's result, 0.9 lowers the smooth regime's true errors by a fifth to a
   * third and the surface distances as well (the sliding along the surface that is left converges in fewer
   * iterations; benchmark/PEERS_MESH.md). From the identity, and on a lattice too coarse to hold the target's
   * deformation (a sphere's cap matched with 6 control points per axis, where the soft fit at sigma's floor leaves the
   * correspondences free to slide), it moves further along the surface than plain EM does, which there is not better.
   */
  itkSetClampMacro(Momentum, double, 0.0, 0.99);
  itkGetConstMacro(Momentum, double);

  /** Initial and minimum Gaussian width (mm); 0 (default) means the widths in control spacings given above. */
  itkSetClampMacro(InitialSigma, double, 0.0, NumericTraits<double>::max());
  itkGetConstMacro(InitialSigma, double);
  itkSetClampMacro(MinimumSigma, double, 0.0, NumericTraits<double>::max());
  itkGetConstMacro(MinimumSigma, double);

  /** Source samples nearer to the target's open boundary than this (mm) are left out of the reverse term;
   * 0 means twice the minimum sigma. */
  itkSetClampMacro(OpenBoundaryDistance, double, 0.0, NumericTraits<double>::max());
  itkGetConstMacro(OpenBoundaryDistance, double);

  /** Samples drawn from the target's and the source's vertices (all of them when there are fewer). Defaults:
   * 20000 and 50000: on the benchmark's meshes, subsets of a few thousand vertices leave the soft correspondences
   * coarser than the minimum sigma and cost accuracy. */
  itkSetClampMacro(NumberOfFixedSamples, unsigned int, 10, NumericTraits<unsigned int>::max());
  itkGetConstMacro(NumberOfFixedSamples, unsigned int);
  itkSetClampMacro(NumberOfMovingSamples, unsigned int, 10, NumericTraits<unsigned int>::max());
  itkGetConstMacro(NumberOfMovingSamples, unsigned int);

  /** Nearest neighbours considered per sample. Default: 8. */
  itkSetClampMacro(NumberOfNeighbors, unsigned int, 1, 64);
  itkGetConstMacro(NumberOfNeighbors, unsigned int);

  /** A step whose det J at a target sample falls below this is solved again, more regularized. Default: 0.1. */
  itkSetMacro(MinimumJacobianDeterminant, double);
  itkGetConstMacro(MinimumJacobianDeterminant, double);

  /** Conjugate-gradient iterations per M-step, at most. Default: 30. */
  itkSetClampMacro(NumberOfSolverIterations, unsigned int, 1, NumericTraits<unsigned int>::max());
  itkGetConstMacro(NumberOfSolverIterations, unsigned int);

  /** An M-step's conjugate gradients stop once each coordinate's residual is below this fraction of its right-hand
   * side (or after NumberOfSolverIterations). Default: 1e-3 (measured on the module's benchmark: 13 % less CPU for
   * GOCPD than 1e-8, the mean true errors within 0.015 mm over 3 seeds; benchmark/PEERS_MESH.md). 0 takes
   * NumberOfSolverIterations every time. */
  itkSetClampMacro(SolverTolerance, double, 0.0, 1.0);
  itkGetConstMacro(SolverTolerance, double);

  /** Nodes per axis of the coarse lattice whose correction joins Jacobi's preconditioner in the M-step's conjugate
   * gradients (detail::BSplineLatticeCoarseCorrection); 0 or 1: Jacobi's alone. Default: 7 (measured on the module's
   * benchmark at 20 control points per axis, with the update interval below: 25-35 % fewer conjugate-gradient
   * iterations than 5, 5-9 % less CPU for GOCPD on the larger cases, the mean true error over the 24 case-seeds
   * unchanged; benchmark/PEERS_MESH.md). */
  itkSetMacro(NumberOfCoarseControlPointsPerAxis, unsigned int);
  itkGetConstMacro(NumberOfCoarseControlPointsPerAxis, unsigned int);

  /** The coarse correction's matrix is formed and factored again at most this many EM iterations apart (and
   * whenever sigma moved by more than 1 % or the regularizer's weight was raised); in between, the last
   * factorization serves as the preconditioner. 1 forms it at every M-step. Default: 10 (measured with
   * NumberOfCoarseControlPointsPerAxis; benchmark/PEERS_MESH.md). */
  itkSetClampMacro(CoarseCorrectionUpdateInterval, unsigned int, 1, NumericTraits<unsigned int>::max());
  itkGetConstMacro(CoarseCorrectionUpdateInterval, unsigned int);

  /** Whether the M-step's conjugate gradients are preconditioned by blocks of 2 x 2 x 2 coefficients
   * (detail::BSplineLatticeBlockJacobi) instead of Jacobi's diagonal, with the coarse correction added either way; the
   * blocks are formed again whenever the coarse correction is. Default: on (measured on the module's benchmark;
   * benchmark/PEERS_MESH.md). */
  itkSetMacro(UseBlockJacobiPreconditioner, bool);
  itkGetConstMacro(UseBlockJacobiPreconditioner, bool);
  itkBooleanMacro(UseBlockJacobiPreconditioner);

  /** Run-time limit (s) of Update(); 0 (default) means none. */
  itkSetClampMacro(MaximumRunTime, double, 0.0, NumericTraits<double>::max());
  itkGetConstMacro(MaximumRunTime, double);

  /** Whether the last Update() stopped at the run-time limit. */
  itkGetConstMacro(TimeLimitReached, bool);

  /** sigma (mm) and the mean squared residual (mm^2) of each iteration of the last Update(). */
  const std::vector<double> &
  GetSigmaValues() const
  {
    return m_SigmaValues;
  }
  const std::vector<double> &
  GetMetricValues() const
  {
    return m_MetricValues;
  }

  /** How many times a folding step raised the regularization, and the weight in the end. */
  itkGetConstMacro(NumberOfRegularizationIncreases, unsigned int);
  /** How many steps that carried momentum raised the residual and were taken back (see Momentum). */
  itkGetConstMacro(NumberOfMomentumRestarts, unsigned int);
  itkGetConstMacro(FinalRegularizationWeight, double);
  /** The conjugate-gradient iterations of all M-steps of the last Update(). */
  itkGetConstMacro(NumberOfSolverIterationsTaken, unsigned int);

  /** Why the last Update() stopped. */
  itkGetConstReferenceMacro(StopConditionDescription, std::string);

protected:
  BSplineCoherentPointDriftRegistrationMethod();
  ~BSplineCoherentPointDriftRegistrationMethod() override = default;

  void
  GenerateData() override;

  void
  PrintSelf(std::ostream & os, Indent indent) const override;

private:
  /** The transform to start from: the initial one's copy, or an identity on the grid described above. */
  typename BSplineTransformType::Pointer
  MakeStartTransform() const;

  unsigned int m_NumberOfControlPointsPerAxis{ 20 };
  PointType    m_TransformDomainOrigin{};
  VectorType   m_TransformDomainPhysicalDimensions{};
  double       m_DomainMargin{ 5.0 };
  double       m_RegularizationWeight{ 3.0 };
  double       m_ForwardWeight{ 0.5 };
  double       m_OutlierWeight{ 0.3 };
  unsigned int m_NumberOfIterations{ 40 };
  double       m_ConvergenceTolerance{ 1e-3 };
  double       m_OverRelaxation{ 0.0 };
  double       m_Momentum{ 0.0 };
  double       m_InitialSigma{ 0.0 };
  double       m_MinimumSigma{ 0.0 };
  double       m_OpenBoundaryDistance{ 0.0 };
  unsigned int m_NumberOfFixedSamples{ 20000 };
  unsigned int m_NumberOfMovingSamples{ 50000 };
  unsigned int m_NumberOfNeighbors{ 8 };
  double       m_MinimumJacobianDeterminant{ 0.1 };
  unsigned int m_NumberOfSolverIterations{ 30 };
  double       m_SolverTolerance{ 1e-3 };
  unsigned int m_NumberOfCoarseControlPointsPerAxis{ 7 };
  unsigned int m_CoarseCorrectionUpdateInterval{ 10 };
  bool         m_UseBlockJacobiPreconditioner{ true };
  double       m_MaximumRunTime{ 0.0 };

  bool                m_TimeLimitReached{ false };
  std::vector<double> m_SigmaValues{};
  std::vector<double> m_MetricValues{};
  unsigned int        m_NumberOfRegularizationIncreases{ 0 };
  unsigned int        m_NumberOfMomentumRestarts{ 0 };
  unsigned int        m_NumberOfSolverIterationsTaken{ 0 };
  double              m_FinalRegularizationWeight{ 0.0 };
  std::string         m_StopConditionDescription{};
};
} // namespace itk

#ifndef ITK_MANUAL_INSTANTIATION
#  include "itkBSplineCoherentPointDriftRegistrationMethod.hxx"
#endif

#endif // itkBSplineCoherentPointDriftRegistrationMethod_h
