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
#ifndef itkMeshPoseRegistrationMethod_h
#define itkMeshPoseRegistrationMethod_h

#include "itkFFDShapeMatchingCompatibility.h"
#include "itkMeshRegistrationMethodBase.h"
#include "itkDataObjectDecorator.h"
#include "itkFFDShapeMatchingEnums.h"
#include "itkMatrix.h"
#include "itkTransform.h"
#include "itkVector.h"

#include <vector>

namespace itk
{
/** \class MeshPoseRegistrationMethod
 * \brief Finds the rigid, similarity or affine pose between a source mesh and a possibly partial target mesh, from
 * any start: a global search over rotations and scales, refined by trimmed ICP and polished on exact distances.
 *
 * The fixed mesh is the target (it may be a cut-out, open part of the source), the moving mesh the source. As every
 * stage of the module, the result maps **target space to source space** (ITK's fixed-to-moving convention): a
 * target point x is sent to A(x), its place on the source.
 *
 * The search works on area-uniform random samples of both surfaces:
 * 1. normalization: the area-weighted centroids c_t, c_s and RMS radii r_t, r_s of the samples;
 * 2. a multi-start: every rotation of a uniform covering of SO(3) (a super-Fibonacci spiral of unit quaternions,
 *    NumberOfRotations of them), every scale of a geometric ladder from r_s / r_t down (NumberOfScales, ScaleStep:
 *    a partial target has a smaller RMS radius than the source region it covers, so the true scale is at most
 *    about r_s / r_t), and the centroid c_t placed on c_s or on c_s moved along the source's principal axes
 *    (TranslationOffsetFraction of r_s, off by default), each scored by the trimmed mean distance from
 * NumberOfScoreSamples target samples, mapped, to their nearest source sample (target -> source, because the target is
 * a part of the source; trimmed, because the target's deformation and its open boundary have no exact counterpart);
 * 3. the StartRefinementFraction best starts are moved by NumberOfStartIterations rigid ICP steps at their own scale
 *    (on the score samples) and scored again, the others dropped: a start a few degrees off a narrow basin (a
 *    patch of holes among many alike, as in a block of cheese) scores badly where it is and well once it has slid in;
 * 4. the NumberOfCandidates best distinct starts are refined by trimmed ICP (closed-form Umeyama steps with
 *    Eigen, on NumberOfCandidateSamples target samples, the TrimFraction closest pairs kept, the scale kept
 *    between 0.9 x the smallest and 1.15 x the largest scale of the ladder), and the refined start with the
 *    lowest score wins: the trimmed mean distance divided by the square root of the scale (the geometric mean of
 *    the two frames' units, so that neither shrinking nor growing the target gains by itself);
 * 5. the winner is polished by point-to-plane steps (linearized, least squares) on NumberOfRefinementSamples
 *    target samples against the exact closest points of the source's triangles, counting PolishTrimFraction of
 *    them (all by default: the whole of a partial target lies on the source, though the source is not covered;
 *    trimming lets the part slide or spread over a larger region), the scale fitted on distances in target units
 *    (in source units a target shrinks its own deformation with it, which biases the scale down by a few %);
 * 6. for PoseType Affine, trimmed ICP with least-squares affine steps, then affine point-to-plane steps, go on
 *    from the best similarity.
 *
 * Nearest neighbours come from nanoflann's k-d tree over the source samples. The starts and the refinements run on
 * the process object's threads.
 *
 * Near-symmetric shapes: two poses related by a symmetry of the shape score alike. The search keeps the best
 * score; GetRunnerUpScore() and GetRunnerUpRotationDistance() give the best refined start at least 10 degrees
 * away from the winner (scored after its ICP refinement on the candidate samples), so that a caller can see when the
 * pose is ambiguous (a runner-up score close to the winner's). A pose differing only by an exact symmetry of the target
 * part cannot be resolved by any method.
 *
 * Output: GetTransformOutput(), a decorated VersorRigid3DTransform (Rigid), Similarity3DTransform (Similarity) or
 * AffineTransform (Affine), centred at the target centroid, ready for a CompositeTransform or a transform file. The
 * pose is also decomposed for reports: GetRotationAngle() (degrees) and GetRotationAxis() of the rotation (the
 * polar factor of the linear part for Affine), GetScale() (the cube root of its determinant for Affine) and
 * GetTranslation() (where the target centroid goes, minus where it was).
 *
 * \par References
 * P. J. Besl and N. D. McKay, "A method for registration of 3-D shapes", IEEE TPAMI 14(2), 1992, doi:10.1109/34.121791.
 * D. Chetverikov et al., "The trimmed iterative closest point algorithm", ICPR 2002, doi:10.1109/ICPR.2002.1047997.
 * S. Umeyama, "Least-squares estimation of transformation parameters between two point patterns", IEEE TPAMI 13(4),
 * 1991, doi:10.1109/34.88573.
 * M. Alexa, "Super-Fibonacci spirals: fast, low-discrepancy sampling of SO(3)", CVPR 2022.
 *
 * \sa MeshShapeMatchingFilter, Similarity3DTransform, AffineTransform
 * \ingroup FFDShapeMatching
 */
template <typename TFixedMesh, typename TMovingMesh = TFixedMesh>
class ITK_TEMPLATE_EXPORT MeshPoseRegistrationMethod : public MeshRegistrationMethodBase<TFixedMesh, TMovingMesh>
{
public:
  ITK_DISALLOW_COPY_AND_MOVE(MeshPoseRegistrationMethod);

  using Self = MeshPoseRegistrationMethod;
  using Superclass = MeshRegistrationMethodBase<TFixedMesh, TMovingMesh>;
  using Pointer = SmartPointer<Self>;
  using ConstPointer = SmartPointer<const Self>;

  itkNewMacro(Self);
  itkOverrideGetNameOfClassMacro(MeshPoseRegistrationMethod);

  static constexpr unsigned int Dimension = TFixedMesh::PointDimension;
  static_assert(Dimension == 3 && TMovingMesh::PointDimension == 3, "MeshPoseRegistrationMethod poses 3-D meshes.");

  using FixedMeshType = TFixedMesh;
  using MovingMeshType = TMovingMesh;
  using PoseTypeEnum = FFDShapeMatchingEnums::InitialTransform;
  using TransformType = Transform<double, Dimension, Dimension>;
  using DecoratedTransformType = DataObjectDecorator<TransformType>;
  using PointType = Point<double, Dimension>;
  using VectorType = Vector<double, Dimension>;
  using MatrixType = Matrix<double, Dimension, Dimension>;

  // FixedMesh (target) and MovingMesh (source), GetTransformOutput() and GetTransform() (A : target space -> source
  // space) and RandomSeed (of the surface samples): see the superclass.

  /** Rigid, Similarity (default) or Affine; None is refused. */
  itkSetEnumMacro(PoseType, PoseTypeEnum);
  itkGetEnumMacro(PoseType, PoseTypeEnum);

  /** Rotations of the multi-start (a uniform covering of SO(3)). Default: 2048. */
  itkSetClampMacro(NumberOfRotations, unsigned int, 1, 1000000);
  itkGetConstMacro(NumberOfRotations, unsigned int);

  /** Scales of the multi-start (Similarity and Affine; Rigid uses 1): r_s / r_t times ScaleStep^k, k < this.
   * Default: 6. */
  itkSetClampMacro(NumberOfScales, unsigned int, 1, 100);
  itkGetConstMacro(NumberOfScales, unsigned int);

  /** Ratio of successive scales of the multi-start, (0, 1]. Default: 0.82. */
  itkSetClampMacro(ScaleStep, double, 1e-3, 1.0);
  itkGetConstMacro(ScaleStep, double);

  /** Offsets of the target centroid from the source centroid along the source's principal axes, as a fraction of
   * the source's RMS radius; 0 (default) tries the centroid only, a positive value the centroid and 6 offsets (7
   * times the starts). */
  itkSetClampMacro(TranslationOffsetFraction, double, 0.0, 10.0);
  itkGetConstMacro(TranslationOffsetFraction, double);

  /** Random surface samples of the source (the k-d tree). Default: 20000. */
  itkSetClampMacro(NumberOfSourceSamples, unsigned int, 16, 100000000);
  itkGetConstMacro(NumberOfSourceSamples, unsigned int);

  /** Target samples that score each start (and move it, see NumberOfStartIterations). Default: 128. */
  itkSetClampMacro(NumberOfScoreSamples, unsigned int, 8, 100000000);
  itkGetConstMacro(NumberOfScoreSamples, unsigned int);

  /** Target samples of the ICP refinement of each candidate start. Default: 800. */
  itkSetClampMacro(NumberOfCandidateSamples, unsigned int, 8, 100000000);
  itkGetConstMacro(NumberOfCandidateSamples, unsigned int);

  /** Target samples of the final point-to-plane refinement of the winner (and of the runner-up). Default: 4000. */
  itkSetClampMacro(NumberOfRefinementSamples, unsigned int, 8, 100000000);
  itkGetConstMacro(NumberOfRefinementSamples, unsigned int);

  /** Distinct best starts refined by ICP. Default: 24. */
  itkSetClampMacro(NumberOfCandidates, unsigned int, 1, 100000);
  itkGetConstMacro(NumberOfCandidates, unsigned int);

  /** ICP steps at the start's own scale (rigid steps, on the score samples) that move each of the best starts
   * before they are ranked; 0 ranks the starts where they are. Default: 6. */
  itkSetClampMacro(NumberOfStartIterations, unsigned int, 0, 1000);
  itkGetConstMacro(NumberOfStartIterations, unsigned int);

  /** Fraction of the starts, those of best score where they are, that NumberOfStartIterations move; the others
   * are dropped. (0, 1]. Default: 0.25. */
  itkSetClampMacro(StartRefinementFraction, double, 1e-6, 1.0);
  itkGetConstMacro(StartRefinementFraction, double);

  /** Fraction of the target samples, the closest, that count in the score and in each ICP step, (0, 1].
   * Default: 0.85. */
  itkSetClampMacro(TrimFraction, double, 0.05, 1.0);
  itkGetConstMacro(TrimFraction, double);

  /** Fraction of the target samples, the closest, that count in the final point-to-plane polish on exact
   * distances, (0, 1]. Default: 1 (all: a partial target lies on the source at its pose, but the source need not
   * be covered). */
  itkSetClampMacro(PolishTrimFraction, double, 0.05, 1.0);
  itkGetConstMacro(PolishTrimFraction, double);

  /** Maximum ICP iterations per refined start (and again for the polish and the affine stage). Default: 50. */
  itkSetClampMacro(NumberOfIterations, unsigned int, 1, 100000);
  itkGetConstMacro(NumberOfIterations, unsigned int);

  /** The pose of the last Update(), decomposed: the rotation angle in degrees (0 to 180) and its unit axis, the
   * (isotropic) scale, the translation of the target centroid, and the linear part and offset (A(x) = M x + o). */
  itkGetConstMacro(RotationAngle, double);
  itkGetConstReferenceMacro(RotationAxis, VectorType);
  itkGetConstMacro(Scale, double);
  itkGetConstReferenceMacro(Translation, VectorType);
  itkGetConstReferenceMacro(Matrix, MatrixType);
  itkGetConstReferenceMacro(Offset, VectorType);

  /** The trimmed mean distance (target units) from the mapped target samples to the source samples at the pose
   * found, and that of the best refined start at least 10 degrees of rotation away (the largest double when there
   * is none) with its rotation distance from the winner in degrees. */
  itkGetConstMacro(Score, double);
  itkGetConstMacro(RunnerUpScore, double);
  itkGetConstMacro(RunnerUpRotationDistance, double);

  /** Starts scored, and wall-clock seconds of the search and of the refinement in the last Update(). */
  itkGetConstMacro(NumberOfStarts, SizeValueType);
  itkGetConstMacro(SearchTime, double);
  itkGetConstMacro(RefinementTime, double);

protected:
  MeshPoseRegistrationMethod();
  ~MeshPoseRegistrationMethod() override = default;

  void
  PrintSelf(std::ostream & os, Indent indent) const override;

  void
  VerifyPreconditions() const override;

  void
  GenerateData() override;

private:
  PoseTypeEnum m_PoseType{ PoseTypeEnum::Similarity };
  unsigned int m_NumberOfRotations{ 2048 };
  unsigned int m_NumberOfScales{ 6 };
  double       m_ScaleStep{ 0.82 };
  double       m_TranslationOffsetFraction{ 0.0 };
  unsigned int m_NumberOfSourceSamples{ 20000 };
  unsigned int m_NumberOfScoreSamples{ 128 };
  unsigned int m_NumberOfCandidateSamples{ 800 };
  unsigned int m_NumberOfRefinementSamples{ 4000 };
  unsigned int m_NumberOfCandidates{ 24 };
  unsigned int m_NumberOfStartIterations{ 6 };
  double       m_StartRefinementFraction{ 0.25 };
  double       m_TrimFraction{ 0.85 };
  double       m_PolishTrimFraction{ 1.0 };
  unsigned int m_NumberOfIterations{ 50 };

  double        m_RotationAngle{ 0.0 };
  VectorType    m_RotationAxis{};
  double        m_Scale{ 1.0 };
  VectorType    m_Translation{};
  MatrixType    m_Matrix{};
  VectorType    m_Offset{};
  double        m_Score{ 0.0 };
  double        m_RunnerUpScore{ 0.0 };
  double        m_RunnerUpRotationDistance{ 0.0 };
  SizeValueType m_NumberOfStarts{ 0 };
  double        m_SearchTime{ 0.0 };
  double        m_RefinementTime{ 0.0 };
};
} // namespace itk

#ifndef ITK_MANUAL_INSTANTIATION
#  include "itkMeshPoseRegistrationMethod.hxx"
#endif

#endif // itkMeshPoseRegistrationMethod_h
