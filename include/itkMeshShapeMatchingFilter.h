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
#ifndef itkMeshShapeMatchingFilter_h
#define itkMeshShapeMatchingFilter_h

#include "itkFFDShapeMatchingCompatibility.h"
#include "itkApplyTransformToMeshFilter.h"
#include "itkCompositeTransform.h"
#include "itkBSplineCoherentPointDriftRegistrationMethod.h"
#include "itkBSplineFFDImageRegistrationMethod.h"
#include "itkBSplineMRFImageRegistrationMethod.h"
#include "itkDataObjectDecorator.h"
#include "itkFFDShapeMatchingEnums.h"
#include "itkImage.h"
#include "itkMeshOpenBoundaryMaskImageFilter.h"
#include "itkMeshPoseRegistrationMethod.h"
#include "itkMeshSurfaceDistanceCalculator.h"
#include "itkMeshToMeshFilter.h"
#include "itkParametricTemplateRegistrationMethod.h"
#include "itkParametricTemplateTransform.h"
#include "FFDShapeMatchingDetail/itkPoseCorrection.h"
#include "itkTransform.h"
#include "itkTriangleMeshToVoxelImageFilter.h"

#include <algorithm>
#include <chrono>
#include <string>
#include <vector>

namespace itk
{
/** \class MeshShapeMatchingFilter
 * \brief Matches a source polygon mesh to a target mesh with a B-spline free-form deformation: the whole method.
 *
 * The source mesh (SetSourceMesh(), the same as SetInput()) is moved onto the target mesh (SetTargetMesh()), which
 * may be a partial, open surface patch. The filter is a mini-pipeline of the module's public filters:
 *
 * 0. with an InitialTransform (rigid, similarity or affine; default none), MeshPoseRegistrationMethod finds the pose
 *    A : target space -> source space from any start, and the target is moved into the source's frame by A
 *    (GetMatchingTargetMesh()); the deformation B below is estimated between the source and that moved target,
 *    and T = B o A (one CompositeTransform: A applied first) is the transform of the whole; with
 *    PoseRefinementRuns (method GOCPD), the pose is then refined by the deformation stage itself (below);
 * 1. both meshes are voxelized on the same voxel size (TriangleMeshToVoxelImageFilter; Voxelization: an unsigned
 *    distance band, surface occupancy or the solid), and the metric mask is the band around the target surface
 *    without the part near the target's open boundary (MeshOpenBoundaryMaskImageFilter); the source's grid covers
 *    only the target's grid grown by SourceGridMargin (the voxels of the source's whole grid, so their values are
 *    those of the whole grid), since the deformation takes the target's samples no farther;
 * 2. the chosen Method estimates T : target space -> source space (the target is the fixed image, the source the
 *    moving one): GO (BSplineFFDImageRegistrationMethod), MRF (BSplineMRFImageRegistrationMethod), Par
 *    (ParametricTemplateRegistrationMethod on the meshes themselves, with the TemplateTransform), GO / MRF
 *    refined by Par, or GO refined by BSplineCoherentPointDriftRegistrationMethod (soft correspondences between
 *    the meshes' vertices, from GO's result: GOCPD; the filter sets its Momentum to 0.9);
 * 3. ApplyTransformToMeshFilter applies T^-1 to the source's vertices (Newton inversion).
 *
 * GetOutput() is the deformed source: the source's vertex order, cells and point data, its points moved onto the
 * target. GetTransformOutput() is T as a decorated transform, ready for a TransformFileWriter or another mesh
 * filter. Progress is reported through a ProgressAccumulator.
 *
 * \par Pose refinement
 * The pose stage fits surfaces; a surface fit can slide along flat or symmetric parts of a deformed target by a few
 * degrees and millimetres, and the deformation stage does not slide such a start back (it converges to the nearest
 * of several fits). With PoseRefinementRuns N > 0 and the GOCPD method, the filter searches for a better start: it
 * runs the whole deformation stage from the pose A corrected by small similarities about the moved target's
 * centroid (rotations about the three axes, shifts along them, and for Similarity and Affine poses a scaling; a
 * pattern search from the steps PoseRefinementRotationStep, PoseRefinementShiftStep and PoseRefinementScaleStep,
 * moving to the best of each round of neighbours and halving the steps after a round without gain), and keeps the
 * start whose run ends with the lowest soft-correspondence residual of the CPD stage (the mean squared distance of
 * its final E-step, divided by the square of the correction's scaling so that all runs compare in the same units;
 * lower where the correspondences agree with the surfaces' detail). At most N runs are added to
 * the first, and one more when the best was not the last. GetPoseRefinementResiduals() gives each run's residual in
 * order, GetPoseTransform() the corrected pose. Under a MaximumRunTime, no refinement run starts after a third of it,
 * and each run gets the time left.
 *
 * The filter holds the module's tuned settings of every method, measured on the module's benchmark; these are its
 * defaults and the defaults of the ffd-match program. The internal filters are reachable
 * (GetModifiableGORegistration() and friends) for tuning beyond the settings offered here; the settings of this
 * filter are written onto them at every Update(), and so are the GO stage's settings that depend on the method
 * (UseMovingImageGradientFilter, UseTruncatedGaussianSmoothing and ConvergenceTolerance: 1e-4 as GOCPD's first
 * stage, 1e-5 for GO alone), so those are not tuned through GetModifiableGORegistration().
 *
 * \code
 * auto matching = itk::MeshShapeMatchingFilter<MeshType>::New();
 * matching->SetSourceMesh(source);
 * matching->SetTargetMesh(target);
 * matching->SetMethod(itk::FFDShapeMatchingEnums::Method::GOCPD); // the default
 * matching->SetNumberOfControlPointsPerAxis(20);
 * matching->SetVoxelSize(1.0);
 * matching->Update();
 * const MeshType * deformed = matching->GetOutput();
 * \endcode
 *
 * \sa TriangleMeshToVoxelImageFilter, BSplineFFDImageRegistrationMethod, BSplineMRFImageRegistrationMethod,
 * ParametricTemplateRegistrationMethod, ApplyTransformToMeshFilter
 * \ingroup FFDShapeMatching
 */
template <typename TMesh, typename TImage = Image<float, TMesh::PointDimension>>
class ITK_TEMPLATE_EXPORT MeshShapeMatchingFilter : public MeshToMeshFilter<TMesh, TMesh>
{
public:
  ITK_DISALLOW_COPY_AND_MOVE(MeshShapeMatchingFilter);

  using Self = MeshShapeMatchingFilter;
  using Superclass = MeshToMeshFilter<TMesh, TMesh>;
  using Pointer = SmartPointer<Self>;
  using ConstPointer = SmartPointer<const Self>;

  itkNewMacro(Self);
  itkOverrideGetNameOfClassMacro(MeshShapeMatchingFilter);

  static constexpr unsigned int Dimension = TMesh::PointDimension;
  static_assert(Dimension == 3, "MeshShapeMatchingFilter matches 3-D meshes.");

  using MeshType = TMesh;
  using ImageType = TImage;
  using MaskImageType = Image<unsigned char, Dimension>;
  using MethodEnum = FFDShapeMatchingEnums::Method;
  using VoxelizationEnum = FFDShapeMatchingEnums::Voxelization;
  using MRFSolverEnum = MRFLabelingSolverEnums::Algorithm;
  using TransformType = Transform<double, Dimension, Dimension>;
  using DistanceCalculatorType = MeshSurfaceDistanceCalculator<TMesh>;
  using DecoratedTransformType = DataObjectDecorator<TransformType>;
  using ParametricTransformType = ParametricTemplateTransform<double, Dimension>;
  using VoxelizerType = TriangleMeshToVoxelImageFilter<MeshType, ImageType>;
  using MaskVoxelizerType = TriangleMeshToVoxelImageFilter<MeshType, MaskImageType>;
  using OpenBoundaryMaskType = MeshOpenBoundaryMaskImageFilter<MaskImageType, MeshType>;
  using GORegistrationType = BSplineFFDImageRegistrationMethod<ImageType>;
  using MRFRegistrationType = BSplineMRFImageRegistrationMethod<ImageType>;
  using ParRegistrationType = ParametricTemplateRegistrationMethod<MeshType, MeshType, ImageType>;
  using CPDRegistrationType = BSplineCoherentPointDriftRegistrationMethod<MeshType, MeshType>;
  using MeshTransformFilterType = ApplyTransformToMeshFilter<MeshType, MeshType>;
  using InitialTransformEnum = FFDShapeMatchingEnums::InitialTransform;
  using PoseRegistrationType = MeshPoseRegistrationMethod<MeshType, MeshType>;
  using CompositeTransformType = CompositeTransform<double, Dimension>;
  using PoseVectorType = Vector<double, Dimension>;

  /** The mesh that is moved (the same as SetInput()). */
  void
  SetSourceMesh(const MeshType * source)
  {
    this->SetInput(source);
  }
  const MeshType *
  GetSourceMesh() const
  {
    return this->GetInput();
  }

  /** The mesh (or open surface patch) the source is matched to (required). */
  itkSetInputMacro(TargetMesh, MeshType);
  itkGetInputMacro(TargetMesh, MeshType);

  /** The templates of the Par methods (required by Par, GOPar and MRFPar; see ParametricTemplateTransform). */
  itkSetGetDecoratedObjectInputMacro(TemplateTransform, ParametricTransformType);

  /** The method. Default: GOCPD (GO refined by coherent point drift on the meshes), the most accurate on the
   * module's benchmark (benchmark/PEERS_MESH.md). */
  itkSetEnumMacro(Method, MethodEnum);
  itkGetEnumMacro(Method, MethodEnum);

  /** The pose stage before the deformation: None (default; the meshes must overlap), Rigid, Similarity or Affine
   * (MeshPoseRegistrationMethod, from any rotation, scale and translation, with a partial target). */
  itkSetEnumMacro(InitialTransform, InitialTransformEnum);
  itkGetEnumMacro(InitialTransform, InitialTransformEnum);

  /** Deformation runs added by the pose refinement (see the class documentation; GOCPD with a pose stage only).
   * Default: 84 (six rounds of the pattern search; measured on the benchmark's posed regime, PEERS_MESH.md, where
   * 14 and 42 leave cases short of the aligned accuracy). 0 turns it off. */
  itkSetMacro(PoseRefinementRuns, unsigned int);
  itkGetConstMacro(PoseRefinementRuns, unsigned int);

  /** The pose refinement's first steps: a rotation in degrees (default 3), a shift as a fraction of the moved
   * target's bounding-box diagonal (default 0.01) and a scaling as a relative change (default 0.02). */
  itkSetClampMacro(PoseRefinementRotationStep, double, 1e-6, 90.0);
  itkGetConstMacro(PoseRefinementRotationStep, double);
  itkSetClampMacro(PoseRefinementShiftStep, double, 1e-9, 1.0);
  itkGetConstMacro(PoseRefinementShiftStep, double);
  itkSetClampMacro(PoseRefinementScaleStep, double, 1e-9, 0.5);
  itkGetConstMacro(PoseRefinementScaleStep, double);

  /** How the meshes become images. Default: SignedDistance (an unsigned distance band; mean squares). */
  itkSetEnumMacro(Voxelization, VoxelizationEnum);
  itkGetEnumMacro(Voxelization, VoxelizationEnum);

  /** Edge length of the voxels, in mesh units. Default: 1. */
  itkSetClampMacro(VoxelSize, double, 1e-300, NumericTraits<double>::max());
  itkGetConstMacro(VoxelSize, double);

  /** Half-width of the distance band and of the metric mask around the target surface, in voxels. Default: 2. */
  itkSetClampMacro(BandWidthInVoxels, double, 0.5, 1000.0);
  itkGetConstMacro(BandWidthInVoxels, double);

  /** How far (mesh units) the source's voxel grid reaches beyond the target's: the source is voxelized only on the
   * part of its grid within the target's grid grown by this margin, as the voxel methods sample the source image
   * only at the deformed target samples. A sample that a deformation moves beyond it is left out of the metric
   * (outside the moving image). Within that grid, distances are computed only for the voxels within the margin
   * plus two voxels (along each axis) of the target's band; the other voxels hold the value of a voxel far from
   * the source (TriangleMeshToVoxelImageFilter's mask), which a sample reaches only when a deformation moves it
   * by more than the margin. A negative value (default -1) means the larger of 10 voxels and 15 % of the
   * target grid's largest side (GetEffectiveSourceGridMargin()): on the benchmark's cases, 10 mm gives the same
   * results as the whole source grid (benchmark/PEERS_MESH.md). A very large value voxelizes the whole source. */
  itkSetMacro(SourceGridMargin, double);
  itkGetConstMacro(SourceGridMargin, double);

  /** Method GOCPD without a pose stage: the voxel stage (GO, and the source's voxelization) runs only when the
   * target's vertices lie, on average, at least this many voxels (VoxelSize) from the source surface; when the
   * shapes are closer, GO on those voxels has nothing to resolve and the CPD stage starts from the identity on GO's
   * control grid. On the benchmark's cases (target 0.18-0.20 mm from the source in the paper regime, 1.0-1.1 mm in
   * the smooth one) GO's start and the identity gave the same CPD errors within 0.001 mm in the paper regime
   * (benchmark/PEERS_MESH.md). Default 0.5; 0 always runs GO. */
  itkSetClampMacro(VoxelStageDistanceThreshold, double, 0.0, NumericTraits<double>::max());
  itkGetConstMacro(VoxelStageDistanceThreshold, double);

  /** Whether the last Update() left the voxel stage out (VoxelStageDistanceThreshold), and the target's mean
   * distance to the source surface it was decided on (mesh units; -1 when it was not measured: other methods, a
   * pose stage, or a threshold of 0). */
  itkGetConstMacro(VoxelStageSkipped, bool);
  double
  GetInitialMeanDistance() const
  {
    return m_InitialDistances ? m_InitialDistances->GetMeanDistance() : -1.0;
  }

  /** The distances from the target's vertices to the source surface that the voxel stage's decision measured (the
   * calculator, after Compute(): mean, maximum, per vertex), or null when it was not measured; a program reporting
   * them need not compute them again. */
  const DistanceCalculatorType *
  GetInitialDistances() const
  {
    return m_InitialDistances.GetPointer();
  }

  /** Control points per axis of the final B-spline grid (ITK mesh size minus 3). Default: 20. */
  itkSetClampMacro(NumberOfControlPointsPerAxis, unsigned int, 4, 1000);
  itkGetConstMacro(NumberOfControlPointsPerAxis, unsigned int);

  /** Control-grid levels of the voxel methods. Default: 2. */
  itkSetClampMacro(NumberOfLevels, unsigned int, 1, 8);
  itkGetConstMacro(NumberOfLevels, unsigned int);

  /** Iterations per level (GO: optimizer iterations, MRF: label iterations, Par: optimizer iterations; the
   * refinement of GOCPD keeps its own, BSplineCoherentPointDriftRegistrationMethod's). 0 (default) means the
   * method's tuned number: GO 50, MRF 8, Par ParametricTemplateRegistrationMethod's. */
  itkSetMacro(NumberOfIterations, unsigned int);
  itkGetConstMacro(NumberOfIterations, unsigned int);

  /** The number of iterations \c method uses (NumberOfIterations, or its tuned number when that is 0). */
  unsigned int
  GetNumberOfIterationsOf(MethodEnum method) const;

  /** Fraction of the band voxels sampled by GO's metric, (0, 1]. Default: 0.25. */
  itkSetClampMacro(SamplingPercentage, double, 1e-6, 1.0);
  itkGetConstMacro(SamplingPercentage, double);

  /** GO: weight of the B-spline bending energy added to the metric. Default: 1. */
  itkSetClampMacro(BendingEnergyWeight, double, 0.0, NumericTraits<double>::max());
  itkGetConstMacro(BendingEnergyWeight, double);

  /** GO: weight of the folding (negative Jacobian) penalty added to the metric. Default: 0. */
  itkSetClampMacro(FoldingPenaltyWeight, double, 0.0, NumericTraits<double>::max());
  itkGetConstMacro(FoldingPenaltyWeight, double);

  /** MRF: weight lambda of the pairwise regularization. Default: 1. */
  itkSetClampMacro(MRFRegularizationWeight, double, 0.0, NumericTraits<double>::max());
  itkGetConstMacro(MRFRegularizationWeight, double);

  /** MRF: the discrete solver. SpanningTree (default): the exact minimum over a minimum spanning tree of the control
   * grid, then two ICM sweeps over the whole grid; AlphaExpansion: alpha-expansion by max-flow, one cycle per
   * iteration (about three times the registration time for the same accuracy on the benchmark); ICM: up to ten sweeps.
   * Exhaustive is refused by the MRF registration. */
  itkSetEnumMacro(MRFSolver, MRFSolverEnum);
  itkGetEnumMacro(MRFSolver, MRFSolverEnum);

  /** MRF: smooth and shrink the images at coarse levels (faster, less accurate on thin bands). Default: off. */
  itkSetMacro(MRFUseImagePyramid, bool);
  itkGetConstMacro(MRFUseImagePyramid, bool);
  itkBooleanMacro(MRFUseImagePyramid);

  /** Seconds the registration may run, 0 = no limit (default). Past the limit, the transform reached so far is
   * used and GetTimeLimitReached() is true. */
  itkSetClampMacro(MaximumRunTime, double, 0.0, NumericTraits<double>::max());
  itkGetConstMacro(MaximumRunTime, double);

  /** Seed of the metric sampling and of the randomized optimizers. Default: 121212. */
  itkSetMacro(RandomSeed, int);
  itkGetConstMacro(RandomSeed, int);

  /** Residual (mesh units) below which the inverse of a vertex has converged. Default: 1e-4. */
  itkSetClampMacro(InverseTolerance, double, 0.0, NumericTraits<double>::max());
  itkGetConstMacro(InverseTolerance, double);

  /** T : target space -> source space, as a decorated pipeline output. */
  const DecoratedTransformType *
  GetTransformOutput() const;

  /** T itself (after Update()). */
  const TransformType *
  GetTransform() const;

  /** The deformation stage's transform B : (posed) target space -> source space; T itself without a pose stage. The
   * Jacobian of the deformation is that of B, on the grid of the target voxelizer's output. */
  const DecoratedTransformType *
  GetDeformationTransformOutput() const
  {
    return m_DeformationTransform.GetPointer();
  }

  /** The pose A : target space -> source space that the deformation started from (after Update() with a pose
   * stage): the pose stage's, corrected by the pose refinement when it ran; nullptr without a pose stage. */
  const TransformType *
  GetPoseTransform() const
  {
    return m_PoseTransform.GetPointer();
  }

  /** The final soft-correspondence residual of each deformation run of the pose refinement, in order (the first is
   * the pose stage's own pose), and the seconds the refinement took, in the last Update(). Empty and 0 when it did
   * not run. */
  itkGetConstReferenceMacro(PoseRefinementResiduals, std::vector<double>);
  itkGetConstMacro(PoseRefinementTime, double);

  /** GetPoseTransform() decomposed, after Update() with a pose stage: the angle in degrees (0 to 180) and the unit
   * axis of its rotation (the polar factor of its linear part), its isotropic scale (1 for a rigid pose, else the
   * cube root of the absolute determinant of its linear part) and the translation of its center (where the center
   * goes, minus where it was). Without a pose stage: angle 0, axis (0, 0, 1), scale 1, no translation. */
  itkGetConstMacro(PoseRotationAngle, double);
  itkGetConstReferenceMacro(PoseRotationAxis, PoseVectorType);
  itkGetConstMacro(PoseScale, double);
  itkGetConstReferenceMacro(PoseTranslation, PoseVectorType);

  /** The target as the deformation stage sees it: moved into the source frame by the pose (the target itself
   * without a pose stage). */
  const MeshType *
  GetMatchingTargetMesh() const
  {
    return m_MatchingTarget.GetPointer() != nullptr ? m_MatchingTarget.GetPointer() : this->GetTargetMesh();
  }

  /** The margin (mesh units) laid around each mesh's bounds by its voxel grid. */
  double
  GetVoxelGridMargin() const
  {
    return (m_BandWidthInVoxels + 2.0) * m_VoxelSize;
  }

  /** SourceGridMargin, or its automatic value for a target grid of the given largest side (mesh units). */
  double
  GetEffectiveSourceGridMargin(double targetGridLargestSide) const
  {
    return m_SourceGridMargin >= 0.0 ? m_SourceGridMargin : std::max(10.0 * m_VoxelSize, 0.15 * targetGridLargestSide);
  }

  /** Half-width of the band in mesh units. */
  double
  GetBandWidth() const
  {
    return m_BandWidthInVoxels * m_VoxelSize;
  }

  /** The record of the last Update(): the metric (or energy) value per iteration of the registration, the
   * name of what was minimized, why it stopped and whether the time limit stopped it. */
  itkGetConstReferenceMacro(MetricValues, std::vector<double>);
  itkGetConstReferenceMacro(MetricName, std::string);
  itkGetConstReferenceMacro(StopConditionDescription, std::string);
  itkGetConstMacro(TimeLimitReached, bool);

  /** Voxels of the metric mask (the band around the target less its open boundary) and the target's open
   * boundary edges, in the last Update(). */
  itkGetConstMacro(NumberOfMetricVoxels, SizeValueType);
  itkGetConstMacro(NumberOfOpenBoundaryEdges, SizeValueType);

  /** Wall-clock seconds of the stages of the last Update(). */
  itkGetConstMacro(PoseTime, double);
  itkGetConstMacro(VoxelizationTime, double);
  itkGetConstMacro(RegistrationTime, double);
  itkGetConstMacro(MeshTransformTime, double);

  /** The internal filters, for tuning and for their results (e.g. the voxel images, the inverse's convergence). */
  itkGetModifiableObjectMacro(PoseRegistration, PoseRegistrationType);
  itkGetModifiableObjectMacro(TargetVoxelizer, VoxelizerType);
  itkGetModifiableObjectMacro(SourceVoxelizer, VoxelizerType);
  itkGetModifiableObjectMacro(BandMaskVoxelizer, MaskVoxelizerType);
  itkGetModifiableObjectMacro(OpenBoundaryMask, OpenBoundaryMaskType);
  itkGetModifiableObjectMacro(GORegistration, GORegistrationType);
  itkGetModifiableObjectMacro(MRFRegistration, MRFRegistrationType);
  itkGetModifiableObjectMacro(ParRegistration, ParRegistrationType);
  itkGetModifiableObjectMacro(CPDRegistration, CPDRegistrationType);
  itkGetModifiableObjectMacro(MeshTransformFilter, MeshTransformFilterType);

  /** Throws an ExceptionObject unless the target's bounding box, grown by \c margin, meets the source's: the
   * methods estimate a deformation, not a placement. */
  static void
  CheckOverlap(const MeshType * source, const MeshType * target, double margin);

protected:
  MeshShapeMatchingFilter();
  ~MeshShapeMatchingFilter() override = default;

  void
  PrintSelf(std::ostream & os, Indent indent) const override;

  using DataObjectPointerArraySizeType = ProcessObject::DataObjectPointerArraySizeType;
  using Superclass::MakeOutput;
  ProcessObject::DataObjectPointer
  MakeOutput(DataObjectPointerArraySizeType index) override;

  void
  VerifyPreconditions() const override;

  void
  GenerateData() override;

private:
  /** Runs the pose stage and moves the target into the source frame (m_MatchingTarget). */
  void
  FindPose();

  /** Decomposes m_PoseTransform into m_PoseRotationAngle, m_PoseRotationAxis, m_PoseScale and m_PoseTranslation,
   * or resets them to the identity's when there is no pose. */
  void
  DecomposePose();

  /** Moves the target into the source frame by the pose \c pose (m_MatchingTarget, m_PoseTransform). */
  void
  MoveTarget(const TransformType * pose);

  /** Voxelizes, registers and refines (the deformation stage, from m_MatchingTarget) with \c timeLimit seconds for
   * the registration (0: none); returns the deformation and keeps the stage times. */
  const DecoratedTransformType *
  Deform(double timeLimit);

  /** The pose refinement: the pattern search over corrections of the pose stage's pose. Leaves the internal filters
   * in the state of the best run and returns its deformation. */
  const DecoratedTransformType *
  RefinePose(const DecoratedTransformType * firstDeformation, std::chrono::steady_clock::time_point start);

  /** Voxelizes both meshes and builds the metric mask. */
  void
  VoxelizeMeshes(bool voxelizeSource = true);

  /** Method GOCPD without a pose stage: measures the target's mean distance to the source surface
   * (InitialMeanDistance) and returns whether it is under VoxelStageDistanceThreshold voxels. */
  bool
  DecideToSkipVoxelStage();

  /** The identity on the control grid GO's last level has: CPD's start when the voxel stage is skipped. */
  const DecoratedTransformType *
  MakeIdentityOnVoxelStageGrid();

  /** Limits the source voxelizer's grid (set from the source's bounds) to the target's grid grown by the margin. */
  void
  CropSourceGridToTarget();

  /** The source voxelizer's mask: the voxels of its grid within SourceGridMargin plus two voxels (L-infinity) of
   * the target's band voxels; none when that is every voxel. */
  void
  MaskSourceGridNearTarget();

  /** The margin (mesh units) of the source's grid around the target's voxelized grid. */
  double
  GetSourceGridMarginForTarget() const;

  /** Updates one of the registration methods; its failure becomes this filter's exception. */
  void
  UpdateRegistration(ProcessObject * registration);

  /** Runs the voxel method GO or MRF with \c timeLimit seconds (0: none); returns its transform output. */
  const DecoratedTransformType *
  RegisterVoxels(MethodEnum method, double timeLimit);

  /** Runs Par, from \c base when given. */
  const DecoratedTransformType *
  RegisterMeshes(const DecoratedTransformType * base, double timeLimit);

  /** Keeps the record of a stage on the meshes (Par or the point refinement): its metric values, and its name and
   * stop condition after the voxel stage's when it followed one. */
  void
  RecordMeshStage(bool                        afterVoxelStage,
                  const std::vector<double> & metricValues,
                  const std::string &         metricName,
                  const std::string &         stopCondition);

  /** Runs the coherent point drift refinement from \c base (GO's result). */
  const DecoratedTransformType *
  RegisterPoints(const DecoratedTransformType * base, double timeLimit);

  MethodEnum           m_Method{ MethodEnum::GOCPD };
  InitialTransformEnum m_InitialTransform{ InitialTransformEnum::None };
  VoxelizationEnum     m_Voxelization{ VoxelizationEnum::SignedDistance };
  double               m_VoxelSize{ 1.0 };
  double               m_BandWidthInVoxels{ 2.0 };
  double               m_SourceGridMargin{ -1.0 };
  double               m_VoxelStageDistanceThreshold{ 0.5 };
  bool                 m_VoxelStageSkipped{ false };
  unsigned int         m_NumberOfControlPointsPerAxis{ 20 };
  unsigned int         m_NumberOfLevels{ 2 };
  unsigned int         m_NumberOfIterations{ 0 };
  double               m_SamplingPercentage{ 0.25 };
  double               m_BendingEnergyWeight{ 1.0 };
  double               m_FoldingPenaltyWeight{ 0.0 };
  double               m_MRFRegularizationWeight{ 1.0 };
  bool                 m_MRFUseImagePyramid{ false };
  MRFSolverEnum        m_MRFSolver{ MRFSolverEnum::SpanningTree };
  double               m_MaximumRunTime{ 0.0 };
  int                  m_RandomSeed{ 121212 };
  double               m_InverseTolerance{ 1e-4 };
  unsigned int         m_PoseRefinementRuns{ 84 };
  double               m_PoseRefinementRotationStep{ 3.0 };
  double               m_PoseRefinementShiftStep{ 0.01 };
  double               m_PoseRefinementScaleStep{ 0.02 };

  std::vector<double> m_MetricValues;
  std::string         m_MetricName;
  std::string         m_StopConditionDescription;
  bool                m_TimeLimitReached{ false };
  SizeValueType       m_NumberOfMetricVoxels{ 0 };
  SizeValueType       m_NumberOfOpenBoundaryEdges{ 0 };
  double              m_PoseTime{ 0.0 };
  double              m_VoxelizationTime{ 0.0 };
  double              m_RegistrationTime{ 0.0 };
  double              m_MeshTransformTime{ 0.0 };
  std::vector<double> m_PoseRefinementResiduals;
  double              m_PoseRefinementTime{ 0.0 };
  double              m_PoseRotationAngle{ 0.0 };
  PoseVectorType      m_PoseRotationAxis;
  double              m_PoseScale{ 1.0 };
  PoseVectorType      m_PoseTranslation;

  typename PoseRegistrationType::Pointer        m_PoseRegistration;
  typename MeshTransformFilterType::Pointer     m_PoseTransformFilter;
  typename MeshType::ConstPointer               m_MatchingTarget;
  typename TransformType::ConstPointer          m_PoseTransform;
  typename DecoratedTransformType::Pointer      m_PoseTransformInput;
  typename DecoratedTransformType::Pointer      m_ComposedTransform;
  typename DecoratedTransformType::Pointer      m_IdentityStart; // CPD's start when the voxel stage is skipped
  typename DistanceCalculatorType::Pointer      m_InitialDistances;
  typename DecoratedTransformType::ConstPointer m_DeformationTransform;
  typename VoxelizerType::Pointer               m_TargetVoxelizer;
  typename VoxelizerType::Pointer               m_SourceVoxelizer;
  typename MaskVoxelizerType::Pointer           m_BandMaskVoxelizer;
  typename OpenBoundaryMaskType::Pointer        m_OpenBoundaryMask;
  typename GORegistrationType::Pointer          m_GORegistration;
  typename MRFRegistrationType::Pointer         m_MRFRegistration;
  typename ParRegistrationType::Pointer         m_ParRegistration;
  typename CPDRegistrationType::Pointer         m_CPDRegistration;
  typename MeshTransformFilterType::Pointer     m_MeshTransformFilter;
};
} // namespace itk

#ifndef ITK_MANUAL_INSTANTIATION
#  include "itkMeshShapeMatchingFilter.hxx"
#endif

#endif // itkMeshShapeMatchingFilter_h
