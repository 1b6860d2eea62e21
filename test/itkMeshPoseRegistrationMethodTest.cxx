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

// MeshPoseRegistrationMethod: a lumpy, non-symmetric blob and its benchmark-style central-box part, posed by known
// rotations (up to 180 degrees), scales (0.5 to 2) and shifts larger than the shape, recover the pose to within
// 1 degree and 1 % of scale, as does an open cap of it shrunk and grown; what a symmetric shape leaves undetermined;
// bad inputs.

#include "itkAffineTransform.h"
#include "itkMeshPoseRegistrationMethod.h"
#include "itkShapeMatchingTestMeshes.h"
#include "itkSimilarity3DTransform.h"
#include "itkTestingMacros.h"

#include <chrono>
#include <iostream>
#include <string>

namespace
{
using namespace ShapeMatchingTestMeshes;
using PoseType = itk::MeshPoseRegistrationMethod<MeshType>;
using PoseEnum = itk::FFDShapeMatchingEnums::InitialTransform;
using SimilarityType = itk::Similarity3DTransform<double>;
using CorrespondenceContainerType = itk::PointCorrespondenceErrorCalculator<MeshType>::CorrespondenceContainerType;

struct Pose
{
  double angle; // degrees
  double axis[3];
  double scale;
  double shift[3];
};

// P: source frame -> target frame, rotating and scaling about the source's centre (0, 0, 0).
SimilarityType::Pointer
MakePose(const Pose & pose)
{
  auto                     transform = SimilarityType::New();
  SimilarityType::AxisType axis;
  for (unsigned int d = 0; d < 3; ++d)
  {
    axis[d] = pose.axis[d];
  }
  axis.Normalize();
  transform->SetRotation(axis, pose.angle * itk::Math::pi / 180.0);
  transform->SetScale(pose.scale);
  SimilarityType::OutputVectorType shift;
  for (unsigned int d = 0; d < 3; ++d)
  {
    shift[d] = pose.shift[d];
  }
  transform->SetTranslation(shift);
  return transform;
}

// The errors of the found A (target -> source) against the truth P^-1: the rotation angle of A's rotation times
// P's (degrees), |scale(A) scale(P) - 1|, and the mean distance |A(P(x)) - x| over the part's vertices.
struct PoseError
{
  double angle;
  double scale;
  double vertices;
};

PoseError
ErrorOf(const PoseType * registration, const SimilarityType * pose, const MeshType * part)
{
  const auto &              m = registration->GetMatrix();
  const auto &              p = pose->GetMatrix();
  itk::Matrix<double, 3, 3> product = m * p; // A after P: scale(A) scale(P) times a rotation, ideally I
  const double              scale = registration->GetScale() * pose->GetScale();
  double                    trace = 0.0;
  for (unsigned int d = 0; d < 3; ++d)
  {
    trace += product(d, d) / scale;
  }
  PoseError error{};
  error.angle = std::acos(std::max(-1.0, std::min(1.0, 0.5 * (trace - 1.0)))) * 180.0 / itk::Math::pi;
  error.scale = std::abs(scale - 1.0);
  double sum = 0.0;
  for (auto it = part->GetPoints()->Begin(); it != part->GetPoints()->End(); ++it)
  {
    sum +=
      registration->GetTransform()->TransformPoint(pose->TransformPoint(it.Value())).EuclideanDistanceTo(it.Value());
  }
  error.vertices = sum / static_cast<double>(part->GetNumberOfPoints());
  return error;
}

// Poses \c part by each pose and checks the recovered pose.
bool
RecoversPoses(const MeshType *          source,
              const MeshType *          part,
              const char *              name,
              PoseEnum                  type,
              const std::vector<Pose> & poses,
              double                    maximumVertexError)
{
  bool ok = true;
  for (const auto & pose : poses)
  {
    const auto posed = TransformedCopy(part, MakePose(pose).GetPointer());
    auto       registration = PoseType::New();
    registration->SetFixedMesh(posed);
    registration->SetMovingMesh(source);
    registration->SetPoseType(type);
    const auto start = std::chrono::steady_clock::now();
    registration->Update();
    const double    seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const PoseError error = ErrorOf(registration, MakePose(pose), part);
    // Resolved: the best start elsewhere (at least 10 degrees away) scores clearly worse.
    const bool good = error.angle < 1.0 && error.scale < 0.01 && error.vertices < maximumVertexError &&
                      registration->GetRunnerUpScore() > 1.2 * registration->GetScore();
    std::cout << name << " " << itk::FFDShapeMatchingEnums::InitialTransformToString(type) << " posed by " << pose.angle
              << " deg, scale " << pose.scale << ": angle error " << error.angle << " deg, scale error "
              << 100.0 * error.scale << " %, vertex error " << error.vertices << " (score " << registration->GetScore()
              << ", runner-up " << registration->GetRunnerUpScore() << " at "
              << registration->GetRunnerUpRotationDistance() << " deg; " << registration->GetNumberOfStarts()
              << " starts, " << seconds << " s: search " << registration->GetSearchTime() << " s, refinement "
              << registration->GetRefinementTime() << " s)" << (good ? "" : "  FAILED") << std::endl;
    ok = ok && good;
  }
  return ok;
}

// The poses of the test: 180 degrees, 90, 30, an oblique 135; scales 0.5 to 2; shifts beyond the shape's size.
const std::vector<Pose> &
TestPoses(bool withScale)
{
  static const std::vector<Pose> scaled{ { 180.0, { 1.0, 1.0, 0.0 }, 1.0, { 150.0, -80.0, 60.0 } },
                                         { 90.0, { 0.3, -0.5, 0.8 }, 0.5, { -200.0, 0.0, 100.0 } },
                                         { 30.0, { 0.0, 0.0, 1.0 }, 2.0, { 0.0, 300.0, 0.0 } },
                                         { 135.0, { -0.7, 0.2, 0.4 }, 1.3, { 40.0, 40.0, -250.0 } } };
  static const std::vector<Pose> rigid{ { 180.0, { 0.0, 1.0, 0.0 }, 1.0, { 0.0, 0.0, 0.0 } },
                                        { 120.0, { 0.6, -0.2, 0.5 }, 1.0, { 120.0, 130.0, -140.0 } } };
  return withScale ? scaled : rigid;
}

// An open, one-sided part (the blob's top cap) shrunk and grown: a trimmed score lets such a part spread over a
// region larger than its own, the polish on exact distances with every sample counted brings the scale back.
const std::vector<Pose> &
CapPoses()
{
  static const std::vector<Pose> poses{ { 150.0, { 0.4, 0.8, -0.2 }, 0.6, { 120.0, -90.0, 40.0 } },
                                        { 60.0, { -0.3, 0.1, 0.9 }, 1.7, { -60.0, 200.0, 10.0 } } };
  return poses;
}

int
TestAffine(const MeshType * source)
{
  // A mild shear and anisotropic stretch on top of a rotation, on the whole shape: the affine stage recovers it.
  auto affine = itk::AffineTransform<double, 3>::New();
  auto pose = MakePose({ 70.0, { 0.2, 0.9, -0.3 }, 1.0, { 90.0, -60.0, 30.0 } });
  affine->SetMatrix(pose->GetMatrix());
  affine->SetOffset(pose->GetOffset());
  itk::AffineTransform<double, 3>::OutputVectorType stretch;
  stretch[0] = 1.15;
  stretch[1] = 0.92;
  stretch[2] = 1.0;
  affine->Scale(stretch, true);
  affine->Shear(0, 1, 0.08, true);
  const auto posed = TransformedCopy(source, affine.GetPointer());
  auto       registration = PoseType::New();
  registration->SetFixedMesh(posed);
  registration->SetMovingMesh(source);
  registration->SetPoseType(PoseEnum::Affine);
  registration->Update();
  double sum = 0.0;
  for (auto it = source->GetPoints()->Begin(); it != source->GetPoints()->End(); ++it)
  {
    sum +=
      registration->GetTransform()->TransformPoint(affine->TransformPoint(it.Value())).EuclideanDistanceTo(it.Value());
  }
  const double error = sum / static_cast<double>(source->GetNumberOfPoints());
  std::cout << "affine: mean vertex error " << error << " (" << registration->GetTransform()->GetNameOfClass() << ")"
            << std::endl;
  if (error > 0.5 || std::string(registration->GetTransform()->GetNameOfClass()) != "AffineTransform")
  {
    std::cerr << "the affine pose is not recovered" << std::endl;
    return EXIT_FAILURE;
  }
  return EXIT_SUCCESS;
}

int
TestSymmetricShape()
{
  // A sphere: its rotation is undetermined, its scale and centre are not. The runner-up says so: it scores as well
  // as the winner, far from it in rotation.
  const auto sphere = MakeSphere(40.0, 0.0, 0.0, 0.0);
  const auto pose = MakePose({ 60.0, { 1.0, 0.0, 0.0 }, 1.5, { 100.0, 0.0, 0.0 } });
  const auto posed = TransformedCopy(sphere, pose.GetPointer());
  auto       registration = PoseType::New();
  registration->SetFixedMesh(posed);
  registration->SetMovingMesh(sphere);
  registration->Update();
  const double          scaleError = std::abs(registration->GetScale() * pose->GetScale() - 1.0);
  itk::Point<double, 3> centre;
  centre.Fill(0.0);
  const double centreError =
    registration->GetTransform()->TransformPoint(pose->TransformPoint(centre)).EuclideanDistanceTo(centre);
  std::cout << "sphere: scale error " << 100.0 * scaleError << " %, centre error " << centreError << ", score "
            << registration->GetScore() << ", runner-up " << registration->GetRunnerUpScore() << " at "
            << registration->GetRunnerUpRotationDistance() << " deg" << std::endl;
  if (scaleError > 0.01 || centreError > 0.5 ||
      registration->GetRunnerUpScore() > 1.5 * registration->GetScore() + 0.05)
  {
    std::cerr << "the sphere's scale and centre are not recovered, or its ambiguity is not reported" << std::endl;
    return EXIT_FAILURE;
  }
  return EXIT_SUCCESS;
}

int
TestBadInputs(const MeshType * source)
{
  auto registration = PoseType::New();
  ITK_EXERCISE_BASIC_OBJECT_METHODS(registration, MeshPoseRegistrationMethod, MeshRegistrationMethodBase);
  ITK_TEST_SET_GET_VALUE(PoseEnum::Similarity, registration->GetPoseType());

  // No moving mesh.
  registration->SetFixedMesh(source);
  ITK_TRY_EXPECT_EXCEPTION(registration->Update());
  // Empty meshes.
  auto empty = MeshType::New();
  registration->SetMovingMesh(empty);
  ITK_TRY_EXPECT_EXCEPTION(registration->Update());
  registration->SetFixedMesh(empty);
  registration->SetMovingMesh(source);
  ITK_TRY_EXPECT_EXCEPTION(registration->Update());
  // All points at one place.
  auto                point = MeshType::New();
  MeshType::PointType p;
  p.Fill(3.0);
  for (unsigned int n = 0; n < 4; ++n)
  {
    point->SetPoint(n, p);
  }
  registration->SetFixedMesh(point);
  ITK_TRY_EXPECT_EXCEPTION(registration->Update());
  // A non-finite coordinate.
  auto nan = MeshType::New();
  p[1] = std::numeric_limits<double>::quiet_NaN();
  nan->SetPoint(0, p);
  registration->SetFixedMesh(nan);
  ITK_TRY_EXPECT_EXCEPTION(registration->Update());
  // No pose type.
  registration->SetFixedMesh(source);
  registration->SetPoseType(PoseEnum::None);
  ITK_TRY_EXPECT_EXCEPTION(registration->Update());
  registration->SetPoseType(static_cast<PoseEnum>(17));
  ITK_TRY_EXPECT_EXCEPTION(registration->Update());
  // A rigid pose of the shape onto itself is the identity.
  registration->SetPoseType(PoseEnum::Rigid);
  ITK_TRY_EXPECT_NO_EXCEPTION(registration->Update());
  if (registration->GetRotationAngle() > 0.5 || registration->GetTranslation().GetNorm() > 0.5 ||
      std::string(registration->GetTransform()->GetNameOfClass()) != "VersorRigid3DTransform")
  {
    std::cerr << "the pose of a shape onto itself is not the identity: " << registration->GetRotationAngle()
              << " deg, translation " << registration->GetTranslation() << std::endl;
    return EXIT_FAILURE;
  }
  return EXIT_SUCCESS;
}
} // namespace

// One part of the test per CTest test (each registration is seconds in a release build, minutes under the
// sanitizers): "whole", "part", "cap" or "other" (bad inputs, the affine pose, the symmetric shape); none runs all.
int
itkMeshPoseRegistrationMethodTest(int argc, char * argv[])
{
  const std::string part = argc > 1 ? argv[1] : "all";
  if (part != "all" && part != "whole" && part != "part" && part != "cap" && part != "other")
  {
    std::cerr << "usage: itkMeshPoseRegistrationMethodTest [whole|part|cap|other]" << std::endl;
    return EXIT_FAILURE;
  }
  const auto                  runs = [&part](const char * name) { return part == "all" || part == name; };
  const auto                  source = MakeLumpyShape(0.0, 0.0, 0.0);
  CorrespondenceContainerType truth;
  const auto                  region = MakeCentralBoxRegion(source, 0.8, truth);
  // The benchmark's target region is the central box of 0.6 of each axis; of this convex blob it holds 4 % of the
  // surface, of the benchmark's meshes 15 to 40 %: the box of 0.8 (40 % of the vertices) is the comparable part.
  CorrespondenceContainerType capTruth;
  const auto                  cap = MakeDeformedPatch(source, 12.0, capTruth, 0.0);
  std::cout << "source " << source->GetNumberOfPoints() << " vertices; central-box part " << region->GetNumberOfPoints()
            << " vertices; top cap " << cap->GetNumberOfPoints() << " vertices" << std::endl;

  int result = EXIT_SUCCESS;
  if (runs("whole") && !RecoversPoses(source, source, "whole", PoseEnum::Similarity, TestPoses(true), 1.0))
  {
    result = EXIT_FAILURE;
  }
  if (runs("part") && (!RecoversPoses(source, region, "part", PoseEnum::Similarity, TestPoses(true), 1.0) ||
                       !RecoversPoses(source, region, "part", PoseEnum::Rigid, TestPoses(false), 1.0)))
  {
    result = EXIT_FAILURE;
  }
  if (runs("cap") && !RecoversPoses(source, cap, "cap", PoseEnum::Similarity, CapPoses(), 1.0))
  {
    result = EXIT_FAILURE;
  }
  if (runs("other") && (TestBadInputs(source) != EXIT_SUCCESS || TestAffine(source) != EXIT_SUCCESS ||
                        TestSymmetricShape() != EXIT_SUCCESS))
  {
    result = EXIT_FAILURE;
  }
  return result;
}
