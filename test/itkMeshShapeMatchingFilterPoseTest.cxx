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

// MeshShapeMatchingFilter with a pose stage: a deformed part of a lumpy blob, posed by a known similarity far from
// the source (not overlapping), is matched as well as the same part in place (the aligned case), the output
// transform is T = B o A and maps the posed target onto the source; without a pose stage the filter refuses it. With
// GOCPD, the pose refinement runs the deformation from corrected poses and keeps the best run's state.

#include "itkMeshShapeMatchingFilter.h"
#include "FFDShapeMatchingDetail/itkMatrixDeterminant.h"
#include "itkShapeMatchingTestMeshes.h"
#include "itkSimilarity3DTransform.h"
#include "itkTestingMacros.h"

#include <algorithm>
#include <cmath>
#include <iostream>
#include <vector>

namespace
{
using namespace ShapeMatchingTestMeshes;
using FilterType = itk::MeshShapeMatchingFilter<MeshType>;
using CorrespondenceContainerType = itk::PointCorrespondenceErrorCalculator<MeshType>::CorrespondenceContainerType;
using InitialEnum = itk::FFDShapeMatchingEnums::InitialTransform;

FilterType::Pointer
NewFilter(const MeshType * source, const MeshType * target, InitialEnum initial)
{
  auto filter = FilterType::New();
  filter->SetSourceMesh(source);
  filter->SetTargetMesh(target);
  filter->SetMethod(itk::FFDShapeMatchingEnums::Method::GO);
  filter->SetInitialTransform(initial);
  filter->SetVoxelSize(1.5);
  filter->SetNumberOfControlPointsPerAxis(8);
  filter->SetNumberOfLevels(1);
  return filter;
}

} // namespace

int
itkMeshShapeMatchingFilterPoseTest(int, char *[])
{
  const auto                  source = MakeLumpyShape(0.0, 0.0, 0.0, 30, 60);
  CorrespondenceContainerType truth;
  const auto                  target = MakeDeformedPatch(source, -8.0, truth);

  // The aligned case.
  auto aligned = NewFilter(source, target, InitialEnum::None);
  aligned->Update();
  const double alignedError = MeanTrueError(aligned->GetOutput(), target, truth);

  // The posed case: rotated 150 degrees about an oblique axis, scaled by 1.25, moved 250 units away.
  auto                   pose = itk::Similarity3DTransform<double>::New();
  itk::Vector<double, 3> axis;
  axis[0] = 0.4;
  axis[1] = -0.8;
  axis[2] = 0.45;
  axis.Normalize();
  pose->SetRotation(axis, 150.0 * itk::Math::pi / 180.0);
  pose->SetScale(1.25);
  itk::Vector<double, 3> shift;
  shift[0] = 250.0;
  shift[1] = -40.0;
  shift[2] = 30.0;
  pose->SetTranslation(shift);
  const auto posedTarget = TransformedCopy(target, pose.GetPointer());

  // Without a pose stage: refused, the meshes are apart.
  auto unposed = NewFilter(source, posedTarget, InitialEnum::None);
  ITK_TRY_EXPECT_EXCEPTION(unposed->Update());

  auto posed = NewFilter(source, posedTarget, InitialEnum::Similarity);
  ITK_TEST_SET_GET_VALUE(InitialEnum::Similarity, posed->GetInitialTransform());
  ITK_TRY_EXPECT_NO_EXCEPTION(posed->Update());
  const double startError = MeanTrueError(source, posedTarget, truth);
  const double posedError = MeanTrueError(posed->GetOutput(), posedTarget, truth);
  const auto * composite = dynamic_cast<const FilterType::CompositeTransformType *>(posed->GetTransform());
  const double transformError = TransformTrueError(posed->GetTransform(), source, posedTarget, truth);
  const double alignedTransformError = TransformTrueError(aligned->GetTransform(), source, target, truth);
  const auto * poseStage = posed->GetModifiablePoseRegistration();
  std::cout << "aligned: true error " << alignedError << " (T: " << alignedTransformError << ")" << std::endl;
  std::cout << "posed: start " << startError << ", true error " << posedError << " (aligned x scale "
            << 1.25 * alignedError << "; T: " << transformError << "); pose " << poseStage->GetRotationAngle()
            << " deg, scale " << poseStage->GetScale() << " in " << posed->GetPoseTime() << " s; "
            << posed->GetModifiableMeshTransformFilter()->GetNumberOfNonConvergedPoints() << " non-converged"
            << std::endl;
  int result = EXIT_SUCCESS;
  if (composite == nullptr || composite->GetNumberOfTransforms() != 2 ||
      composite->GetNthTransformConstPointer(1) != poseStage->GetTransform() ||
      composite->GetNthTransformConstPointer(0) != posed->GetDeformationTransformOutput()->Get())
  {
    std::cerr << "the output transform is not the composite B o A" << std::endl;
    result = EXIT_FAILURE;
  }
  if (std::abs(poseStage->GetRotationAngle() - 150.0) > 3.0 || std::abs(poseStage->GetScale() * 1.25 - 1.0) > 0.02)
  {
    std::cerr << "the pose stage did not find the pose" << std::endl;
    result = EXIT_FAILURE;
  }
  // The goal of the pose stage: the aligned case's accuracy, within 1.25 x (scale x) its true error.
  if (!(posedError < 1.25 * 1.25 * alignedError + 0.05) || !(transformError < 1.25 * alignedTransformError + 0.05) ||
      !(posedError < 0.1 * startError))
  {
    std::cerr << "the posed case is not matched as well as the aligned one" << std::endl;
    result = EXIT_FAILURE;
  }
  if (posed->GetMatchingTargetMesh() == posedTarget.GetPointer() ||
      aligned->GetMatchingTargetMesh() != target.GetPointer())
  {
    std::cerr << "the deformation stage's target is not the target moved by the pose" << std::endl;
    result = EXIT_FAILURE;
  }

  // The pose refinement (GOCPD): four more deformation runs from corrected poses; the filter ends in the state of the
  // run with the lowest final soft-correspondence residual, and T = B o A' with A' the corrected pose.
  auto refined = NewFilter(source, posedTarget, InitialEnum::Similarity);
  refined->SetMethod(itk::FFDShapeMatchingEnums::Method::GOCPD);
  ITK_TEST_SET_GET_VALUE(84u, refined->GetPoseRefinementRuns());
  refined->SetPoseRefinementRuns(4);
  ITK_TEST_SET_GET_VALUE(4u, refined->GetPoseRefinementRuns());
  refined->SetPoseRefinementRotationStep(500.0);
  ITK_TEST_SET_GET_VALUE(90.0, refined->GetPoseRefinementRotationStep());
  refined->SetPoseRefinementRotationStep(3.0);
  refined->SetPoseRefinementShiftStep(0.01);
  ITK_TEST_SET_GET_VALUE(0.01, refined->GetPoseRefinementShiftStep());
  refined->SetPoseRefinementScaleStep(0.02);
  ITK_TEST_SET_GET_VALUE(0.02, refined->GetPoseRefinementScaleStep());
  ITK_TRY_EXPECT_NO_EXCEPTION(refined->Update());
  const std::vector<double> residuals = refined->GetPoseRefinementResiduals();
  const auto                best = std::min_element(residuals.begin(), residuals.end());
  const double              refinedError = MeanTrueError(refined->GetOutput(), posedTarget, truth);
  const auto * refinedComposite = dynamic_cast<const FilterType::CompositeTransformType *>(refined->GetTransform());
  std::cout << "refined: " << residuals.size() << " runs, residual " << residuals.front() << " -> " << *best << " (run "
            << best - residuals.begin() << "), true error " << refinedError << " in "
            << refined->GetPoseRefinementTime() << " s" << std::endl;
  if (residuals.size() != 5 || !(refined->GetPoseRefinementTime() > 0.0))
  {
    std::cerr << "the refinement did not make 1 + 4 runs" << std::endl;
    result = EXIT_FAILURE;
  }
  // The residuals compare in the pose stage's units: the CPD stage's own is divided by the square of the scaling
  // the correction added.
  const auto scaleOf = [](const FilterType::TransformType * transform) {
    const auto * linear = dynamic_cast<const itk::MatrixOffsetTransformBase<double, 3, 3> *>(transform);
    return std::cbrt(std::abs(itk::detail::MatrixDeterminant(linear->GetMatrix())));
  };
  const double addedScale =
    scaleOf(refined->GetPoseTransform()) / scaleOf(refined->GetModifiablePoseRegistration()->GetTransform());
  const double finalResidual =
    refined->GetModifiableCPDRegistration()->GetMetricValues().back() / (addedScale * addedScale);
  if (!(std::abs(finalResidual - *best) <= 1e-9 * *best))
  {
    std::cerr << "the filter does not end in the state of the best run" << std::endl;
    result = EXIT_FAILURE;
  }
  const bool correctedPose = refined->GetPoseTransform() != refined->GetModifiablePoseRegistration()->GetTransform();
  if (refinedComposite == nullptr || refinedComposite->GetNthTransformConstPointer(1) != refined->GetPoseTransform() ||
      correctedPose != (best != residuals.begin()))
  {
    std::cerr << "the output transform is not B o A' with the pose of the best run" << std::endl;
    result = EXIT_FAILURE;
  }
  if (!(refinedError < 1.25 * 1.25 * alignedError + 0.05))
  {
    std::cerr << "the refined case is not matched as well as the aligned one" << std::endl;
    result = EXIT_FAILURE;
  }
  // Under a time limit, no refinement run starts after a third of it.
  refined->SetMaximumRunTime(1e-6);
  ITK_TRY_EXPECT_NO_EXCEPTION(refined->Update());
  if (refined->GetPoseRefinementResiduals().size() != 1 ||
      refined->GetPoseTransform() != refined->GetModifiablePoseRegistration()->GetTransform())
  {
    std::cerr << "the refinement ran past its time limit" << std::endl;
    result = EXIT_FAILURE;
  }
  // Without a pose stage, or with another method, there is no refinement.
  aligned->SetMethod(itk::FFDShapeMatchingEnums::Method::GOCPD);
  ITK_TRY_EXPECT_NO_EXCEPTION(aligned->Update());
  if (!aligned->GetPoseRefinementResiduals().empty() || aligned->GetPoseTransform() != nullptr ||
      !posed->GetPoseRefinementResiduals().empty())
  {
    std::cerr << "a refinement ran without a pose stage or with GO" << std::endl;
    result = EXIT_FAILURE;
  }
  return result;
}
