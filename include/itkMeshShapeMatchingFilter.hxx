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
#ifndef itkMeshShapeMatchingFilter_hxx
#define itkMeshShapeMatchingFilter_hxx

#include "itkMeshShapeMatchingFilter.h"
#include "itkBSplineTransformInitializer.h"
#include "itkImageRegionConstIteratorWithIndex.h"
#include "itkProgressAccumulator.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <sstream>

namespace itk
{
namespace detail
{
/** Seconds since \c start on the steady clock. */
inline double
SecondsSince(std::chrono::steady_clock::time_point start)
{
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}
} // namespace detail

template <typename TMesh, typename TImage>
MeshShapeMatchingFilter<TMesh, TImage>::MeshShapeMatchingFilter()
  : m_PoseRegistration(PoseRegistrationType::New())
  , m_PoseTransformFilter(MeshTransformFilterType::New())
  , m_PoseTransformInput(DecoratedTransformType::New())
  , m_ComposedTransform(DecoratedTransformType::New())
  , m_IdentityStart(DecoratedTransformType::New())
  , m_TargetVoxelizer(VoxelizerType::New())
  , m_SourceVoxelizer(VoxelizerType::New())
  , m_BandMaskVoxelizer(MaskVoxelizerType::New())
  , m_OpenBoundaryMask(OpenBoundaryMaskType::New())
  , m_GORegistration(GORegistrationType::New())
  , m_MRFRegistration(MRFRegistrationType::New())
  , m_ParRegistration(ParRegistrationType::New())
  , m_CPDRegistration(CPDRegistrationType::New())
  , m_MeshTransformFilter(MeshTransformFilterType::New())
{
  this->AddRequiredInputName("TargetMesh");
  this->SetNumberOfRequiredOutputs(2);
  // GOCPD's refinement slides the correspondences along the surface from GO's result: with momentum it gets further
  // in the same iterations (benchmark/PEERS_MESH.md, "Momentum as the default").
  m_CPDRegistration->SetMomentum(0.9);
  this->SetNthOutput(1, this->MakeOutput(1));
  this->DecomposePose(); // no pose yet: the identity's parts
}

template <typename TMesh, typename TImage>
ProcessObject::DataObjectPointer
MeshShapeMatchingFilter<TMesh, TImage>::MakeOutput(DataObjectPointerArraySizeType index)
{
  if (index == 1)
  {
    return DecoratedTransformType::New().GetPointer();
  }
  return Superclass::MakeOutput(index);
}

template <typename TMesh, typename TImage>
auto
MeshShapeMatchingFilter<TMesh, TImage>::GetTransformOutput() const -> const DecoratedTransformType *
{
  return static_cast<const DecoratedTransformType *>(this->ProcessObject::GetOutput(1));
}

template <typename TMesh, typename TImage>
auto
MeshShapeMatchingFilter<TMesh, TImage>::GetTransform() const -> const TransformType *
{
  return this->GetTransformOutput()->Get();
}

template <typename TMesh, typename TImage>
unsigned int
MeshShapeMatchingFilter<TMesh, TImage>::GetNumberOfIterationsOf(MethodEnum method) const
{
  if (m_NumberOfIterations > 0)
  {
    return m_NumberOfIterations;
  }
  // Measured on the benchmark's signed-distance pairs (benchmark/RESULTS.md).
  switch (method)
  {
    case MethodEnum::GO:
      return 50;
    case MethodEnum::MRF:
      return 8;
    default:
      return m_ParRegistration->GetNumberOfIterations();
  }
}

template <typename TMesh, typename TImage>
void
MeshShapeMatchingFilter<TMesh, TImage>::CheckOverlap(const MeshType * source, const MeshType * target, double margin)
{
  const auto sourceBox = source->GetBoundingBox();
  const auto targetBox = target->GetBoundingBox();
  for (unsigned int d = 0; d < Dimension; ++d)
  {
    if (targetBox->GetMinimum()[d] > sourceBox->GetMaximum()[d] + margin ||
        targetBox->GetMaximum()[d] < sourceBox->GetMinimum()[d] - margin)
    {
      itkGenericExceptionMacro(<< "the target does not overlap the source (their bounding boxes are apart along axis "
                               << d << "): shape matching estimates a deformation, not a placement; align them first");
    }
  }
}

template <typename TMesh, typename TImage>
void
MeshShapeMatchingFilter<TMesh, TImage>::VerifyPreconditions() const
{
  Superclass::VerifyPreconditions();
  const bool usesTemplates =
    m_Method == MethodEnum::Par || m_Method == MethodEnum::GOPar || m_Method == MethodEnum::MRFPar;
  if (usesTemplates && this->GetTemplateTransform() == nullptr)
  {
    itkExceptionMacro(<< "method " << FFDShapeMatchingEnums::MethodToString(m_Method)
                      << " needs templates (SetTemplateTransform())");
  }
}

template <typename TMesh, typename TImage>
void
MeshShapeMatchingFilter<TMesh, TImage>::FindPose()
{
  const MeshType * source = this->GetSourceMesh();
  const MeshType * target = this->GetTargetMesh();
  if (source->GetNumberOfPoints() == 0)
  {
    itkExceptionMacro(<< "the source mesh has no points");
  }
  if (target->GetNumberOfPoints() == 0)
  {
    itkExceptionMacro(<< "the target mesh has no points");
  }
  m_PoseRegistration->SetFixedMesh(target);
  m_PoseRegistration->SetMovingMesh(source);
  m_PoseRegistration->SetPoseType(m_InitialTransform);
  m_PoseRegistration->SetRandomSeed(m_RandomSeed);
  try
  {
    m_PoseRegistration->Update();
  }
  catch (const ExceptionObject & error)
  {
    itkExceptionMacro(<< "the pose stage failed: " << error.GetDescription());
  }
  this->MoveTarget(m_PoseRegistration->GetTransform());
}

template <typename TMesh, typename TImage>
void
MeshShapeMatchingFilter<TMesh, TImage>::DecomposePose()
{
  m_PoseRotationAngle = 0.0;
  m_PoseRotationAxis.Fill(0.0);
  m_PoseRotationAxis[2] = 1.0;
  m_PoseScale = 1.0;
  m_PoseTranslation.Fill(0.0);
  if (m_PoseTransform.IsNull())
  {
    return;
  }
  using LinearTransformType = MatrixOffsetTransformBase<double, Dimension, Dimension>;
  const auto * linear = dynamic_cast<const LinearTransformType *>(m_PoseTransform.GetPointer());
  if (linear == nullptr)
  {
    itkExceptionMacro(<< "the pose is not a matrix-and-offset transform");
  }
  Eigen::Matrix3d matrix;
  Eigen::Vector3d offset;
  Eigen::Vector3d center;
  for (unsigned int d = 0; d < Dimension; ++d)
  {
    offset[d] = linear->GetOffset()[d];
    center[d] = linear->GetCenter()[d];
    for (unsigned int e = 0; e < Dimension; ++e)
    {
      matrix(d, e) = linear->GetMatrix()(d, e);
    }
  }
  const detail::MeshPoseDecomposition parts =
    detail::DecomposeMeshPose(matrix, offset, center, m_InitialTransform == InitialTransformEnum::Rigid);
  m_PoseRotationAngle = parts.Angle;
  m_PoseScale = parts.Scale;
  for (unsigned int d = 0; d < Dimension; ++d)
  {
    m_PoseRotationAxis[d] = parts.Axis[d];
    m_PoseTranslation[d] = parts.Translation[d];
  }
}

template <typename TMesh, typename TImage>
void
MeshShapeMatchingFilter<TMesh, TImage>::MoveTarget(const TransformType * pose)
{
  // A moves the target into the source frame (forward: A maps target space to source space).
  m_PoseTransform = pose;
  m_PoseTransformInput->Set(pose);
  m_PoseTransformFilter->SetInput(this->GetTargetMesh());
  m_PoseTransformFilter->SetTransformInput(m_PoseTransformInput);
  m_PoseTransformFilter->InverseOff();
  m_PoseTransformFilter->Update();
  typename MeshType::Pointer moved = m_PoseTransformFilter->GetOutput();
  moved->DisconnectPipeline();
  m_MatchingTarget = moved;
}

template <typename TMesh, typename TImage>
auto
MeshShapeMatchingFilter<TMesh, TImage>::Deform(double timeLimit) -> const DecoratedTransformType *
{
  using ClockType = std::chrono::steady_clock;
  const bool refineByPar = m_Method == MethodEnum::GOPar || m_Method == MethodEnum::MRFPar;
  const bool refine = refineByPar || m_Method == MethodEnum::GOCPD;

  // Voxelize (every method: the target image is also the grid on which T is scored; the source only when a voxel
  // stage runs).
  auto       start = ClockType::now();
  const bool skipVoxelStage = this->DecideToSkipVoxelStage();
  this->VoxelizeMeshes(!skipVoxelStage);
  m_VoxelizationTime = detail::SecondsSince(start);

  // Register: T maps target (fixed) space to source (moving) space.
  start = ClockType::now();
  const DecoratedTransformType * transform = nullptr;
  if (m_Method == MethodEnum::Par)
  {
    transform = this->RegisterMeshes(nullptr, timeLimit);
  }
  else
  {
    transform = skipVoxelStage
                  ? this->MakeIdentityOnVoxelStageGrid()
                  : this->RegisterVoxels(m_Method == MethodEnum::MRF || m_Method == MethodEnum::MRFPar ? MethodEnum::MRF
                                                                                                       : MethodEnum::GO,
                                         timeLimit);
    const double remaining = timeLimit - detail::SecondsSince(start);
    if (refine && timeLimit > 0.0 && remaining <= 0.0)
    {
      // The voxel stage used up the time: its transform is the one reached so far, the refinement is not started.
      m_TimeLimitReached = true;
      m_StopConditionDescription += refineByPar ? "\npar: not started, the run-time limit was reached"
                                                : "\ncpd: not started, the run-time limit was reached";
    }
    else if (refine)
    {
      const bool   timeLimitReached = m_TimeLimitReached;
      const double limit = timeLimit > 0.0 ? remaining : 0.0;
      transform = refineByPar ? this->RegisterMeshes(transform, limit) : this->RegisterPoints(transform, limit);
      m_TimeLimitReached = m_TimeLimitReached || timeLimitReached;
    }
  }
  m_RegistrationTime = detail::SecondsSince(start);
  return transform;
}

template <typename TMesh, typename TImage>
auto
MeshShapeMatchingFilter<TMesh, TImage>::RefinePose(const DecoratedTransformType *        firstDeformation,
                                                   std::chrono::steady_clock::time_point start)
  -> const DecoratedTransformType *
{
  using ParametersType = detail::PoseCorrectionParameters;
  const typename TransformType::ConstPointer pose = m_PoseRegistration->GetTransform();
  // The corrections turn about the moved target's centroid; the shift step scales with its size.
  typename MeshType::PointType centroid;
  centroid.Fill(0.0);
  const MeshType * moved = m_MatchingTarget;
  for (auto it = moved->GetPoints()->Begin(); it != moved->GetPoints()->End(); ++it)
  {
    for (unsigned int d = 0; d < Dimension; ++d)
    {
      centroid[d] += it.Value()[d] / static_cast<double>(moved->GetNumberOfPoints());
    }
  }
  const double          diagonal = std::sqrt(moved->GetBoundingBox()->GetDiagonalLength2());
  std::array<double, 7> steps{};
  for (unsigned int d = 0; d < Dimension; ++d)
  {
    steps[d] = m_PoseRefinementRotationStep * Math::pi / 180.0;
    steps[Dimension + d] = m_PoseRefinementShiftStep * diagonal;
  }
  // A rigid pose keeps its scale.
  steps[6] = m_InitialTransform == InitialTransformEnum::Rigid ? 0.0 : std::log1p(m_PoseRefinementScaleStep);

  // The residual is a squared distance in the source frame: a correction that shrinks the moved target by e^s
  // shrinks it by e^2s with no better fit. Divided by e^2s, the runs compare in the units of the pose stage's target.
  const auto residualOfRun = [this](const ParametersType & correction) {
    const auto & values = m_CPDRegistration->GetMetricValues();
    return values.empty() ? NumericTraits<double>::max() : values.back() / std::exp(2.0 * correction[6]);
  };
  const auto elapsed = [start]() { return detail::SecondsSince(start); };
  // With a limit, a run gets the time left, and at least a millisecond (0 would mean no limit).
  const auto timeLeft = [this, &elapsed]() {
    return m_MaximumRunTime > 0.0 ? std::max(1e-3, m_MaximumRunTime - elapsed()) : 0.0;
  };
  const auto mayStart = [this, &elapsed]() { return m_MaximumRunTime <= 0.0 || elapsed() < m_MaximumRunTime / 3.0; };

  ParametersType best{};
  double         bestResidual = residualOfRun(best);
  m_PoseRefinementResiduals.assign(1, bestResidual);
  ParametersType last = best;
  unsigned int   runs = 0;
  bool           stepsLeft = true;
  while (runs < m_PoseRefinementRuns && stepsLeft && mayStart())
  {
    ParametersType roundBest = best;
    double         roundResidual = bestResidual;
    for (unsigned int k = 0; k < 7; ++k)
    {
      if (steps[k] <= 0.0)
      {
        continue;
      }
      for (const double sign : { 1.0, -1.0 })
      {
        if (runs >= m_PoseRefinementRuns || !mayStart())
        {
          break;
        }
        ParametersType candidate = best;
        candidate[k] += sign * steps[k];
        ++runs;
        last = candidate;
        double residual = NumericTraits<double>::max();
        try
        {
          this->MoveTarget(detail::ComposePoseCorrection<TransformType>(pose, centroid, candidate));
          m_TimeLimitReached = false;
          this->Deform(timeLeft());
          residual = residualOfRun(candidate);
        }
        catch (const ExceptionObject &)
        {
          // A corrected start the deformation stage cannot run from (e.g. moved off the source) is not kept.
        }
        m_PoseRefinementResiduals.push_back(residual);
        if (residual < roundResidual)
        {
          roundResidual = residual;
          roundBest = candidate;
        }
      }
    }
    if (roundResidual < bestResidual)
    {
      best = roundBest;
      bestResidual = roundResidual;
    }
    else
    {
      for (double & step : steps)
      {
        step *= 0.5;
      }
      // Below a tenth of a degree (and the other steps as much smaller), the runs no longer differ.
      stepsLeft = steps[0] > 0.1 * Math::pi / 180.0;
    }
  }
  if (runs == 0)
  {
    return firstDeformation;
  }
  // The internal filters end in the state of the best run: the last one, or a run again from the best pose.
  if (last != best)
  {
    this->MoveTarget(best == ParametersType{}
                       ? pose.GetPointer()
                       : detail::ComposePoseCorrection<TransformType>(pose, centroid, best).GetPointer());
    m_TimeLimitReached = false;
    return this->Deform(timeLeft());
  }
  return m_CPDRegistration->GetTransformOutput();
}

template <typename TMesh, typename TImage>
bool
MeshShapeMatchingFilter<TMesh, TImage>::DecideToSkipVoxelStage()
{
  m_VoxelStageSkipped = false;
  m_InitialDistances = nullptr;
  if (m_Method != MethodEnum::GOCPD || m_InitialTransform != InitialTransformEnum::None ||
      !(m_VoxelStageDistanceThreshold > 0.0))
  {
    return false;
  }
  auto distance = DistanceCalculatorType::New();
  distance->SetSourceMesh(this->GetMatchingTargetMesh());
  distance->SetTargetMesh(this->GetSourceMesh());
  distance->SetNumberOfWorkUnits(this->GetNumberOfWorkUnits());
  distance->Compute();
  m_InitialDistances = distance;
  m_VoxelStageSkipped = distance->GetMeanDistance() < m_VoxelStageDistanceThreshold * m_VoxelSize;
  return m_VoxelStageSkipped;
}

template <typename TMesh, typename TImage>
auto
MeshShapeMatchingFilter<TMesh, TImage>::MakeIdentityOnVoxelStageGrid() -> const DecoratedTransformType *
{
  // The grid GO's last level has: its initializer's domain (the target image's) at the final mesh size.
  using BSplineType = typename GORegistrationType::BSplineTransformType;
  using InitializerType = BSplineTransformInitializer<BSplineType, ImageType>;
  auto                               bspline = BSplineType::New();
  auto                               initializer = InitializerType::New();
  typename BSplineType::MeshSizeType meshSize;
  meshSize.Fill(
    GORegistrationType::ComputeMeshSizeAtLevel(m_NumberOfControlPointsPerAxis, m_NumberOfLevels, m_NumberOfLevels - 1));
  initializer->SetTransform(bspline);
  initializer->SetImage(m_TargetVoxelizer->GetOutput());
  initializer->SetTransformDomainMeshSize(meshSize);
  initializer->InitializeTransform();
  bspline->SetIdentity();
  m_IdentityStart->Set(bspline);
  m_MetricValues.clear();
  m_MetricName.clear();
  std::ostringstream stop;
  stop << "b-spline: not run (the target lies " << this->GetInitialMeanDistance()
       << " from the source surface on average, under VoxelStageDistanceThreshold = " << m_VoxelStageDistanceThreshold
       << " voxels): the point-drift stage starts from the identity";
  m_StopConditionDescription = stop.str();
  return m_IdentityStart;
}

template <typename TMesh, typename TImage>
void
MeshShapeMatchingFilter<TMesh, TImage>::VoxelizeMeshes(bool voxelizeSource)
{
  const MeshType * source = this->GetSourceMesh();
  const MeshType * target = this->GetMatchingTargetMesh();
  if (source->GetNumberOfPoints() == 0)
  {
    itkExceptionMacro(<< "the source mesh has no points");
  }
  if (target->GetNumberOfPoints() == 0)
  {
    itkExceptionMacro(<< "the target mesh has no points");
  }
  const double bandWidth = this->GetBandWidth();
  CheckOverlap(source, target, bandWidth);

  using ModeEnum = TriangleMeshToVoxelImageFilterEnums::Mode;
  const ModeEnum                      mode = m_Voxelization == VoxelizationEnum::Occupancy
                                               ? ModeEnum::Occupancy
                                               : (m_Voxelization == VoxelizationEnum::Solid ? ModeEnum::Solid : ModeEnum::SignedDistance);
  typename VoxelizerType::SpacingType spacing;
  spacing.Fill(m_VoxelSize);
  // The target first: its band decides the metric mask and where the source is voxelized.
  for (VoxelizerType * voxelizer : { m_TargetVoxelizer.GetPointer(), m_SourceVoxelizer.GetPointer() })
  {
    const bool isTarget = voxelizer == m_TargetVoxelizer.GetPointer();
    if (!isTarget && !voxelizeSource)
    {
      continue;
    }
    voxelizer->SetInput(isTarget ? target : source);
    voxelizer->SetMode(mode);
    voxelizer->SetBandWidth(bandWidth);
    voxelizer->SetUnsignedDistance(true); // open target patches have no inside
    try
    {
      voxelizer->SetGeometryFromMeshBounds(spacing, this->GetVoxelGridMargin());
      if (!isTarget)
      {
        this->CropSourceGridToTarget();
        this->MaskSourceGridNearTarget();
      }
      voxelizer->UpdateLargestPossibleRegion();
    }
    catch (const ExceptionObject & error)
    {
      itkExceptionMacro(<< "cannot voxelize the " << (isTarget ? "target" : "source")
                        << " mesh: " << error.GetDescription());
    }
    if (isTarget)
    {
      // The metric compares the band around the target surface, less the part near the target's open boundary:
      // there the distance to a cut-out patch differs from the distance to the whole source surface whatever the
      // deformation.
      m_BandMaskVoxelizer->SetInput(target);
      m_BandMaskVoxelizer->SetMode(ModeEnum::BandMask);
      m_BandMaskVoxelizer->SetBandWidth(bandWidth);
      m_BandMaskVoxelizer->SetReferenceImage(m_TargetVoxelizer->GetOutput());
      m_OpenBoundaryMask->SetInput(m_BandMaskVoxelizer->GetOutput());
      m_OpenBoundaryMask->SetMesh(target);
      m_OpenBoundaryMask->SetRadius(bandWidth + 0.5 * m_VoxelSize);
      m_OpenBoundaryMask->UpdateLargestPossibleRegion();
      m_NumberOfMetricVoxels = m_OpenBoundaryMask->GetNumberOfMaskVoxels();
      m_NumberOfOpenBoundaryEdges = m_OpenBoundaryMask->GetNumberOfOpenBoundaryEdges();
      if (m_NumberOfMetricVoxels == 0)
      {
        itkExceptionMacro(
          << "the target surface leaves no voxel to compare (too small for the voxel size, or all open boundary)");
      }
    }
  }
}

template <typename TMesh, typename TImage>
void
MeshShapeMatchingFilter<TMesh, TImage>::CropSourceGridToTarget()
{
  // The voxels of the source's own grid (same origin lattice) that lie within the target's grid grown by the margin.
  const auto * targetImage = m_TargetVoxelizer->GetOutput();
  const auto   targetSize = targetImage->GetLargestPossibleRegion().GetSize();
  const double margin = this->GetSourceGridMarginForTarget();
  auto         origin = m_SourceVoxelizer->GetOrigin();
  auto         size = m_SourceVoxelizer->GetSize();
  for (unsigned int d = 0; d < Dimension; ++d)
  {
    const double low = targetImage->GetOrigin()[d] - margin;
    const double high = targetImage->GetOrigin()[d] + static_cast<double>(targetSize[d] - 1) * m_VoxelSize + margin;
    const double first = std::max(0.0, std::floor((low - origin[d]) / m_VoxelSize));
    const double last = std::min(static_cast<double>(size[d]) - 1.0, std::ceil((high - origin[d]) / m_VoxelSize));
    // Grids apart along an axis (CheckOverlap allows a band's gap) keep one slice of the source's grid.
    const double count = std::max(1.0, last - first + 1.0);
    origin[d] += std::min(first, static_cast<double>(size[d]) - 1.0) * m_VoxelSize;
    size[d] = static_cast<SizeValueType>(count);
  }
  m_SourceVoxelizer->SetOrigin(origin);
  m_SourceVoxelizer->SetSize(size);
}

template <typename TMesh, typename TImage>
double
MeshShapeMatchingFilter<TMesh, TImage>::GetSourceGridMarginForTarget() const
{
  const auto targetSize = m_TargetVoxelizer->GetOutput()->GetLargestPossibleRegion().GetSize();
  double     largestSide = 0.0;
  for (unsigned int d = 0; d < Dimension; ++d)
  {
    largestSide = std::max(largestSide, static_cast<double>(targetSize[d]) * m_VoxelSize);
  }
  return this->GetEffectiveSourceGridMargin(largestSide);
}

template <typename TMesh, typename TImage>
void
MeshShapeMatchingFilter<TMesh, TImage>::MaskSourceGridNearTarget()
{
  // The target's band voxels, each at the nearest voxel of the source's grid (clamped into it), grown by the margin
  // plus two voxels along each axis: a sample of the band that a deformation moves by at most the margin, with its
  // linear interpolation's neighbours and the offset between the two lattices, stays in the mask. The growth is
  // separable: per row (j, k) of the grid the extent along the row of the band voxels in it, then the rows within
  // reach across (j, then k) merged, then each row's extent grown by the reach; a row holds one interval, so the
  // mask is a superset of the band's L-infinity neighbourhood.
  const auto * bandMask = m_BandMaskVoxelizer->GetOutput();
  const auto   origin = m_SourceVoxelizer->GetOrigin();
  const auto   size = m_SourceVoxelizer->GetSize();
  const double reach = std::ceil(this->GetSourceGridMarginForTarget() / m_VoxelSize) + 2.0;
  m_SourceVoxelizer->SetMaskImage(nullptr);
  bool coversGrid = true;
  for (unsigned int d = 0; d < Dimension; ++d)
  {
    coversGrid = coversGrid && reach >= static_cast<double>(size[d]);
  }
  if (coversGrid)
  {
    return; // Every voxel is within reach of any band voxel.
  }
  const auto r = static_cast<long>(reach);
  const auto nx = static_cast<long>(size[0]);
  const auto ny = static_cast<long>(size[1]);
  const auto nz = static_cast<long>(size[2]);

  constexpr long                                   none = std::numeric_limits<long>::max();
  std::vector<long>                                lower(static_cast<size_t>(ny * nz), none);
  std::vector<long>                                upper(static_cast<size_t>(ny * nz), -none);
  ImageRegionConstIteratorWithIndex<MaskImageType> it(bandMask, bandMask->GetLargestPossibleRegion());
  typename MaskImageType::PointType                point;
  for (; !it.IsAtEnd(); ++it)
  {
    if (!it.Get())
    {
      continue;
    }
    bandMask->TransformIndexToPhysicalPoint(it.GetIndex(), point);
    long index[3];
    for (unsigned int d = 0; d < Dimension; ++d)
    {
      // Clamping moves a voxel outside the grid onto its face, which only grows what it reaches inside.
      const double position = std::round((point[d] - origin[d]) / m_VoxelSize);
      index[d] = static_cast<long>(std::min(std::max(position, 0.0), static_cast<double>(size[d] - 1)));
    }
    const size_t row = static_cast<size_t>(index[1] + ny * index[2]);
    lower[row] = std::min(lower[row], index[0]);
    upper[row] = std::max(upper[row], index[0]);
  }
  // Merge the rows within reach across, along j then along k.
  const auto mergeAcross =
    [r](std::vector<long> & lo, std::vector<long> & hi, long count, long stride, long lines, long lineStride) {
      std::vector<long> lineLower(static_cast<size_t>(count));
      std::vector<long> lineUpper(static_cast<size_t>(count));
      for (long line = 0; line < lines; ++line)
      {
        const long base = line * lineStride;
        for (long a = 0; a < count; ++a)
        {
          lineLower[a] = lo[base + a * stride];
          lineUpper[a] = hi[base + a * stride];
        }
        for (long a = 0; a < count; ++a)
        {
          long low = none;
          long high = -none;
          for (long b = std::max(0L, a - r); b <= std::min(count - 1, a + r); ++b)
          {
            low = std::min(low, lineLower[b]);
            high = std::max(high, lineUpper[b]);
          }
          lo[base + a * stride] = low;
          hi[base + a * stride] = high;
        }
      }
    };
  mergeAcross(lower, upper, ny, 1, nz, ny);
  mergeAcross(lower, upper, nz, ny, ny, 1);

  auto mask = MaskImageType::New();
  mask->SetRegions(typename MaskImageType::RegionType(size));
  mask->SetOrigin(origin);
  typename MaskImageType::SpacingType spacing;
  spacing.Fill(m_VoxelSize);
  mask->SetSpacing(spacing);
  mask->Allocate(true);
  unsigned char * buffer = mask->GetBufferPointer();
  for (size_t row = 0; row < lower.size(); ++row)
  {
    if (lower[row] <= upper[row])
    {
      const long first = std::max(0L, lower[row] - r);
      const long last = std::min(nx - 1, upper[row] + r);
      std::fill(buffer + static_cast<long>(row) * nx + first, buffer + static_cast<long>(row) * nx + last + 1, 1);
    }
  }
  m_SourceVoxelizer->SetMaskImage(mask);
}

template <typename TMesh, typename TImage>
void
MeshShapeMatchingFilter<TMesh, TImage>::UpdateRegistration(ProcessObject * registration)
{
  try
  {
    registration->Update();
  }
  catch (const ExceptionObject & error)
  {
    itkExceptionMacro(<< "registration failed: " << error.GetDescription());
  }
}

template <typename TMesh, typename TImage>
auto
MeshShapeMatchingFilter<TMesh, TImage>::RegisterVoxels(MethodEnum method, double timeLimit)
  -> const DecoratedTransformType *
{
  const bool distances = m_Voxelization == VoxelizationEnum::SignedDistance;
  if (method == MethodEnum::GO)
  {
    using MetricEnum = FFDShapeMatchingEnums::ImageMetric;
    GORegistrationType * registration = m_GORegistration;
    registration->SetFixedImage(m_TargetVoxelizer->GetOutput());
    registration->SetMovingImage(m_SourceVoxelizer->GetOutput());
    registration->SetFixedImageMask(m_OpenBoundaryMask->GetOutput());
    registration->SetNumberOfControlPointsPerAxis(m_NumberOfControlPointsPerAxis);
    // Distances compare by their differences; occupancy and solid labels by their statistics.
    registration->SetMetric(distances ? MetricEnum::MeanSquares : MetricEnum::MattesMutualInformation);
    registration->SetNumberOfLevels(m_NumberOfLevels);
    registration->SetNumberOfIterations(this->GetNumberOfIterationsOf(MethodEnum::GO));
    registration->SetSamplingPercentage(m_SamplingPercentage);
    registration->SetRandomSeed(m_RandomSeed);
    registration->SetBendingEnergyWeight(m_BendingEnergyWeight);
    registration->SetFoldingPenaltyWeight(m_FoldingPenaltyWeight);
    // GO alone keeps ITK's filtered moving-image gradient (more accurate alone); as the first stage of GOCPD, whose
    // point-drift stage does the fine matching, the samples' central differences are as accurate and skip the
    // filter's passes over the whole source image (benchmark/PEERS_MESH.md).
    registration->SetUseMovingImageGradientFilter(m_Method != MethodEnum::GOCPD);
    // Likewise the coarse level's smoothing: the truncated Gaussian for GOCPD, ITK's recursive one for GO alone.
    registration->SetUseTruncatedGaussianSmoothing(m_Method == MethodEnum::GOCPD);
    // And its stopping rule: as GOCPD's first stage GO only brings the shapes near, so LBFGSB stops at a projected
    // gradient of 1e-4 instead of 1e-5 (3-5x fewer iterations, the same true errors; benchmark/PEERS_MESH.md).
    registration->SetConvergenceTolerance(m_Method == MethodEnum::GOCPD ? 1e-4 : 1e-5);
    registration->SetMaximumRunTime(timeLimit);
    this->UpdateRegistration(registration);
    m_MetricValues = registration->GetMetricValues();
    m_MetricName = distances ? "MeanSquares" : "MattesMutualInformation";
    m_StopConditionDescription = registration->GetStopConditionDescription();
    m_TimeLimitReached = registration->GetTimeLimitReached();
    return registration->GetTransformOutput();
  }

  using SimilarityEnum = typename MRFRegistrationType::SimilarityEnum;
  MRFRegistrationType * registration = m_MRFRegistration;
  registration->SetFixedImage(m_TargetVoxelizer->GetOutput());
  registration->SetMovingImage(m_SourceVoxelizer->GetOutput());
  registration->SetFixedImageMask(m_OpenBoundaryMask->GetOutput());
  registration->SetNumberOfControlPointsPerAxis(m_NumberOfControlPointsPerAxis);
  // Distances compare by the sum of squared differences; occupancy and solid labels by pointwise mutual
  // information. Settings measured on the benchmark's signed-distance pairs (1 mm voxels, band mask;
  // benchmark/README.md): 13 sparse labels (2 steps per direction; 3 steps gave the same errors in 1.25 times the
  // time) up to 0.4 x the control spacing, shrinking by 2/3 per iteration, the levels at full image resolution (a
  // shrunk image loses the thin band the distances live in), quadratic regularization, fold rejection.
  registration->SetSimilarity(distances ? SimilarityEnum::SumOfSquaredDifferences : SimilarityEnum::MutualInformation);
  registration->SetNumberOfLevels(m_NumberOfLevels);
  registration->SetNumberOfIterationsPerLevel(this->GetNumberOfIterationsOf(MethodEnum::MRF));
  registration->SetNumberOfLabelSteps(2);
  registration->SetMaximumDisplacementFactor(0.4);
  registration->SetLabelShrinkFactor(0.67);
  registration->SetRegularizationWeight(m_MRFRegularizationWeight);
  registration->SetRejectFoldingUpdates(true);
  registration->SetUseImagePyramid(m_MRFUseImagePyramid);
  registration->SetSolver(m_MRFSolver);
  // SpanningTree: the tree's exact minimum and two ICM sweeps; AlphaExpansion: one cycle; ICM: up to ten sweeps.
  registration->SetNumberOfSolverCycles(
    m_MRFSolver == MRFSolverEnum::SpanningTree ? 3 : (m_MRFSolver == MRFSolverEnum::ICM ? 10 : 1));
  registration->SetMaximumRunTime(timeLimit);
  this->UpdateRegistration(registration);
  m_MetricValues = registration->GetEnergyValues();
  m_MetricName = distances ? "MRF energy (SSD)" : "MRF energy (pointwise MI)";
  std::ostringstream stop;
  stop << "mrf ("
       << (m_MRFSolver == MRFSolverEnum::SpanningTree ? "spanning tree"
                                                      : (m_MRFSolver == MRFSolverEnum::ICM ? "ICM" : "alpha-expansion"))
       << "): " << registration->GetEnergyValues().size() << " iterations, "
       << registration->GetNumberOfRejectedUpdates() << " updates rejected";
  m_StopConditionDescription = stop.str();
  m_TimeLimitReached = registration->GetTimeLimitReached();
  return registration->GetTransformOutput();
}

template <typename TMesh, typename TImage>
void
MeshShapeMatchingFilter<TMesh, TImage>::RecordMeshStage(bool                        afterVoxelStage,
                                                        const std::vector<double> & metricValues,
                                                        const std::string &         metricName,
                                                        const std::string &         stopCondition)
{
  const std::string voxelName = afterVoxelStage && !m_MetricName.empty() ? m_MetricName + ", then " : std::string();
  const std::string voxelStop = afterVoxelStage ? m_StopConditionDescription : std::string();
  m_MetricValues = metricValues;
  m_MetricName = voxelName + metricName;
  m_StopConditionDescription = voxelStop + (voxelStop.empty() || voxelStop.back() == '\n' ? "" : "\n") + stopCondition;
}

template <typename TMesh, typename TImage>
auto
MeshShapeMatchingFilter<TMesh, TImage>::RegisterMeshes(const DecoratedTransformType * base, double timeLimit)
  -> const DecoratedTransformType *
{
  ParRegistrationType * registration = m_ParRegistration;
  registration->SetFixedMesh(this->GetMatchingTargetMesh());
  registration->SetMovingMesh(this->GetSourceMesh());
  registration->SetTemplateTransformInput(this->GetTemplateTransformInput());
  registration->SetBaseTransformInput(base);
  registration->SetDistanceMapSpacing(m_VoxelSize);
  if (m_NumberOfIterations > 0)
  {
    registration->SetNumberOfIterations(m_NumberOfIterations);
  }
  registration->SetRandomSeed(m_RandomSeed);
  registration->SetMaximumRunTime(timeLimit);
  this->UpdateRegistration(registration);
  m_TimeLimitReached = registration->GetTimeLimitReached();
  this->RecordMeshStage(base != nullptr,
                        registration->GetMetricValues(),
                        "mean squared distance to the source surface",
                        registration->GetStopConditionDescription());
  return registration->GetTransformOutput();
}

template <typename TMesh, typename TImage>
auto
MeshShapeMatchingFilter<TMesh, TImage>::RegisterPoints(const DecoratedTransformType * base, double timeLimit)
  -> const DecoratedTransformType *
{
  CPDRegistrationType * registration = m_CPDRegistration;
  registration->SetFixedMesh(this->GetMatchingTargetMesh());
  registration->SetMovingMesh(this->GetSourceMesh());
  // GO's B-spline is the start: its grid is kept. The EM iterations are the refinement's own.
  registration->SetInitialTransformInput(base);
  registration->SetRandomSeed(m_RandomSeed);
  registration->SetMaximumRunTime(timeLimit);
  this->UpdateRegistration(registration);
  m_TimeLimitReached = registration->GetTimeLimitReached();
  this->RecordMeshStage(base != nullptr,
                        registration->GetMetricValues(),
                        "mean squared soft-correspondence residual",
                        registration->GetStopConditionDescription());
  return registration->GetTransformOutput();
}

template <typename TMesh, typename TImage>
void
MeshShapeMatchingFilter<TMesh, TImage>::GenerateData()
{
  using ClockType = std::chrono::steady_clock;
  m_MetricValues.clear();
  m_MetricName.clear();
  m_StopConditionDescription.clear();
  m_TimeLimitReached = false;

  const bool voxelMethod = m_Method != MethodEnum::Par;
  const bool refineByPar = m_Method == MethodEnum::GOPar || m_Method == MethodEnum::MRFPar;
  const bool refineByCPD = m_Method == MethodEnum::GOCPD;
  const bool refine = refineByPar || refineByCPD;
  auto       progress = ProgressAccumulator::New();
  progress->SetMiniPipelineFilter(this);
  const bool posed = m_InitialTransform != InitialTransformEnum::None;
  if (posed)
  {
    progress->RegisterInternalFilter(m_PoseRegistration, 0.05f);
  }
  progress->RegisterInternalFilter(m_TargetVoxelizer, 0.04f);
  progress->RegisterInternalFilter(m_SourceVoxelizer, 0.04f);
  progress->RegisterInternalFilter(m_BandMaskVoxelizer, 0.01f);
  progress->RegisterInternalFilter(m_OpenBoundaryMask, 0.01f);
  const float registrationWeight = 0.85f;
  if (voxelMethod)
  {
    ProcessObject * voxelRegistration = m_Method == MethodEnum::MRF || m_Method == MethodEnum::MRFPar
                                          ? static_cast<ProcessObject *>(m_MRFRegistration)
                                          : static_cast<ProcessObject *>(m_GORegistration);
    progress->RegisterInternalFilter(voxelRegistration, refine ? 0.6f * registrationWeight : registrationWeight);
  }
  if (m_Method == MethodEnum::Par || refineByPar)
  {
    progress->RegisterInternalFilter(m_ParRegistration, refineByPar ? 0.4f * registrationWeight : registrationWeight);
  }
  if (refineByCPD)
  {
    progress->RegisterInternalFilter(m_CPDRegistration, 0.4f * registrationWeight);
  }
  progress->RegisterInternalFilter(m_MeshTransformFilter, 0.05f);

  // Pose: A maps target space to source space; the deformation stage matches the source to A(target).
  auto start = ClockType::now();
  m_MatchingTarget = nullptr;
  m_PoseTransform = nullptr;
  this->DecomposePose(); // no pose until the pose stage has run (a failed run leaves none)
  m_PoseTime = 0.0;
  m_PoseRefinementResiduals.clear();
  m_PoseRefinementTime = 0.0;
  if (posed)
  {
    this->FindPose();
    m_PoseTime = detail::SecondsSince(start);
  }

  start = ClockType::now();
  const DecoratedTransformType * transform = this->Deform(m_MaximumRunTime);
  if (posed && refineByCPD && m_PoseRefinementRuns > 0)
  {
    const auto refinementStart = ClockType::now();
    transform = this->RefinePose(transform, start);
    m_PoseRefinementTime = detail::SecondsSince(refinementStart);
  }
  m_DeformationTransform = transform;
  this->DecomposePose();
  if (posed)
  {
    // T = B o A: a CompositeTransform applies the transform added last first. It only reads its parts.
    auto composite = CompositeTransformType::New();
    composite->AddTransform(const_cast<TransformType *>(transform->Get()));
    composite->AddTransform(const_cast<TransformType *>(m_PoseTransform.GetPointer()));
    m_ComposedTransform->Set(composite);
    transform = m_ComposedTransform;
  }
  auto * transformOutput = static_cast<DecoratedTransformType *>(this->ProcessObject::GetOutput(1));
  transformOutput->Set(transform->Get());

  // Apply: T^-1 moves the source onto the target.
  start = ClockType::now();
  m_MeshTransformFilter->SetInput(this->GetSourceMesh());
  m_MeshTransformFilter->SetTransformInput(transform);
  m_MeshTransformFilter->InverseOn();
  m_MeshTransformFilter->SetInverseTolerance(m_InverseTolerance);
  m_MeshTransformFilter->Update();
  this->GraftOutput(m_MeshTransformFilter->GetOutput());
  m_MeshTransformTime = detail::SecondsSince(start);
  this->UpdateProgress(1.0f);
}

template <typename TMesh, typename TImage>
void
MeshShapeMatchingFilter<TMesh, TImage>::PrintSelf(std::ostream & os, Indent indent) const
{
  Superclass::PrintSelf(os, indent);
  os << indent << "Method: " << m_Method << std::endl;
  os << indent << "InitialTransform: " << m_InitialTransform << std::endl;
  os << indent << "Voxelization: " << m_Voxelization << std::endl;
  os << indent << "VoxelSize: " << m_VoxelSize << std::endl;
  os << indent << "BandWidthInVoxels: " << m_BandWidthInVoxels << std::endl;
  os << indent << "SourceGridMargin: " << m_SourceGridMargin << std::endl;
  os << indent << "NumberOfControlPointsPerAxis: " << m_NumberOfControlPointsPerAxis << std::endl;
  os << indent << "NumberOfLevels: " << m_NumberOfLevels << std::endl;
  os << indent << "NumberOfIterations: " << m_NumberOfIterations << std::endl;
  os << indent << "SamplingPercentage: " << m_SamplingPercentage << std::endl;
  os << indent << "BendingEnergyWeight: " << m_BendingEnergyWeight << std::endl;
  os << indent << "FoldingPenaltyWeight: " << m_FoldingPenaltyWeight << std::endl;
  os << indent << "MRFRegularizationWeight: " << m_MRFRegularizationWeight << std::endl;
  os << indent << "MRFUseImagePyramid: " << m_MRFUseImagePyramid << std::endl;
  os << indent << "MRFSolver: " << m_MRFSolver << std::endl;
  os << indent << "MaximumRunTime: " << m_MaximumRunTime << std::endl;
  os << indent << "RandomSeed: " << m_RandomSeed << std::endl;
  os << indent << "InverseTolerance: " << m_InverseTolerance << std::endl;
  os << indent << "PoseRefinementRuns: " << m_PoseRefinementRuns << std::endl;
  os << indent << "VoxelStageDistanceThreshold: " << m_VoxelStageDistanceThreshold << std::endl;
  os << indent << "VoxelStageSkipped: " << m_VoxelStageSkipped << std::endl;
  os << indent << "InitialMeanDistance: " << this->GetInitialMeanDistance() << std::endl;
  os << indent << "PoseRefinementRotationStep: " << m_PoseRefinementRotationStep << std::endl;
  os << indent << "PoseRefinementShiftStep: " << m_PoseRefinementShiftStep << std::endl;
  os << indent << "PoseRefinementScaleStep: " << m_PoseRefinementScaleStep << std::endl;
  os << indent << "NumberOfPoseRefinementResiduals: " << m_PoseRefinementResiduals.size() << std::endl;
  os << indent << "PoseRefinementTime: " << m_PoseRefinementTime << std::endl;
  os << indent << "PoseRotationAngle: " << m_PoseRotationAngle << std::endl;
  os << indent << "PoseRotationAxis: " << m_PoseRotationAxis << std::endl;
  os << indent << "PoseScale: " << m_PoseScale << std::endl;
  os << indent << "PoseTranslation: " << m_PoseTranslation << std::endl;
  os << indent << "MetricName: " << m_MetricName << std::endl;
  os << indent << "NumberOfMetricValues: " << m_MetricValues.size() << std::endl;
  os << indent << "TimeLimitReached: " << m_TimeLimitReached << std::endl;
  os << indent << "NumberOfMetricVoxels: " << m_NumberOfMetricVoxels << std::endl;
  os << indent << "NumberOfOpenBoundaryEdges: " << m_NumberOfOpenBoundaryEdges << std::endl;
  os << indent << "PoseTime: " << m_PoseTime << std::endl;
  os << indent << "VoxelizationTime: " << m_VoxelizationTime << std::endl;
  os << indent << "RegistrationTime: " << m_RegistrationTime << std::endl;
  os << indent << "MeshTransformTime: " << m_MeshTransformTime << std::endl;
  itkPrintSelfObjectMacro(PoseRegistration);
  itkPrintSelfObjectMacro(TargetVoxelizer);
  itkPrintSelfObjectMacro(SourceVoxelizer);
  itkPrintSelfObjectMacro(BandMaskVoxelizer);
  itkPrintSelfObjectMacro(OpenBoundaryMask);
  itkPrintSelfObjectMacro(GORegistration);
  itkPrintSelfObjectMacro(MRFRegistration);
  itkPrintSelfObjectMacro(ParRegistration);
  itkPrintSelfObjectMacro(CPDRegistration);
  itkPrintSelfObjectMacro(MeshTransformFilter);
}
} // namespace itk

#endif // itkMeshShapeMatchingFilter_hxx
