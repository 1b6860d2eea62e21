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
#ifndef itkBSplineMRFImageRegistrationMethod_h
#define itkBSplineMRFImageRegistrationMethod_h

#include "itkFFDShapeMatchingCompatibility.h"
#include "itkBSplineMRFImageRegistrationMethodEnums.h"
#include "itkBSplineImageRegistrationMethodBase.h"
#include "FFDShapeMatchingDetail/itkBSplineMRFUnaryCosts.h"
#include "itkMRFLabelingSolver.h"
#include <array>
#include <vector>

namespace itk
{
/** \class BSplineMRFImageRegistrationMethod
 * \brief Registers two voxel images with a cubic B-spline free-form deformation by discrete Markov-random-field
 * optimization (the "MRF" method of the FFDShapeMatching pipeline, after Glocker et al. 2008).
 *
 * Each control point of a cubic BSplineTransform takes one of a discrete set of displacements (labels) added to
 * its current displacement u. The energy of a labeling d is
 * \f[ E(d) = \sum_p U_p(d_p) + \lambda \sum_{(p,q)} \rho\left(\frac{u_p + d_p - u_q - d_q}{h}\right), \f]
 * over the 6-neighbour pairs (p, q) of the control grid (h: the mean control spacing of the level).
 * The unary cost of label d at control point p is the B-spline-weighted mean of the pointwise dissimilarity of
 * the fixed image F and the moving image M warped by the current transform T shifted by d,
 * \f$U_p(d) = \sum_x w_p(x)\, c(F(x), M(T(x) + d)) / \sum_x w_p(x)\f$ over the (masked) fixed voxels x. It is
 * computed efficiently: one pass over the voxels per label evaluates c, then a separable projection (the grid is
 * aligned with the fixed image) accumulates it onto all control points; labels are processed in parallel.
 * The solution updates u <- u + d; the label range then shrinks by LabelShrinkFactor, NumberOfIterationsPerLevel
 * times per level. An update is kept only if the registration energy (the zero-label energy, data plus
 * regularization) does not increase and, with RejectFoldingUpdates, if the sampled minimum Jacobian
 * determinant stays above FoldingThreshold: the energy of each level never increases (GetEnergyValues()).
 *
 * \par Solver
 * MRFLabelingSolver, chosen with SetSolver():
 * - AlphaExpansion (default) on Boost Graph's Boykov-Kolmogorov max-flow: a proven move-making method for
 *   multi-label energies, each move optimal over a very large neighbourhood of labelings (much stronger than
 *   ICM), for any pairwise term; the expansion terms that are not submodular (the regularization depends on u as
 *   well as on the labels) are truncated and a move is only accepted when the true energy decreases.
 * - SpanningTree: the exact minimum of the energy restricted to a minimum spanning tree of the control grid (the
 *   approach of deeds), then NumberOfSolverCycles - 1 ICM sweeps over the whole grid. The tree is chosen from the
 *   unary costs of each level's first iteration and kept through the level (as deeds does; choosing it again at
 *   every iteration gave the same errors on the benchmark's cases in 1.2 times the time). With 3 cycles it is as
 *   accurate as AlphaExpansion on the benchmark's shape-matching cases and about three times faster in total
 *   (benchmark/RESULTS.md); MeshShapeMatchingFilter and ffd-match use it.
 * - ICM, for comparison.
 * With the Quadratic pairwise function the solver evaluates the pairwise terms inline
 * (MRFLabelingSolver::SetQuadraticPairwise()); the others go through a callback.
 *
 * \par Multi-resolution
 * NumberOfLevels levels; level l (from 0) uses a control grid about 2^(L-1-l) times coarser
 * (GetMeshSizeAtLevel()), refined between levels with BSplineTransformParametersAdaptor. With UseImagePyramid
 * (default On) the level also smooths the images with a Gaussian of 0.5 s voxels and shrinks them by
 * s = 2^(L-1-l), as the GO method does; Off keeps the full-resolution images at every level (slower coarse
 * levels, no loss of the thin structures a shrink removes).
 *
 * \par Labels
 * LabelSet Sparse (default): zero and +-x, +-y, +-z at NumberOfLabelSteps steps (6K + 1 labels);
 * SparseWithDiagonals adds the 20 diagonal directions of the cube (26K + 1); Dense is the cube
 * (2K + 1)^3. The largest step at a level's first iteration is MaximumDisplacement (mm) if set (> 0), otherwise
 * MaximumDisplacementFactor (default 0.4) times the control spacing, which also keeps each update from folding.
 *
 * \par Similarities
 * MutualInformation (default; pointwise, from a Parzen-windowed joint histogram of NumberOfHistogramBins bins,
 * estimated at each level's start), SumOfSquaredDifferences, SumOfAbsoluteDifferences,
 * NormalizedCrossCorrelation (per control point, over its weighted support).
 *
 * Inputs: the fixed image (index 0; in shape matching the target's voxel image), the moving image (the source's)
 * and an optional fixed-image mask (unsigned char, non-zero = used; e.g. a band around the target surface).
 * Output: the BSplineTransform T, fixed space to moving space (ITK's convention), as a decorated
 * Transform<double, 3, 3> (GetTransformOutput()), ready to connect into a mesh-transform filter.
 * Progress is reported and an IterationEvent invoked after every iteration. The images must be 3-D.
 *
 * \par Run-time limit
 * With MaximumRunTime (superclass) set, the clock is checked before each level and each iteration, before each
 * label's pass of the unary costs and before each expansion move of the solver (MRFLabelingSolver's own limit, set
 * to the time left). Past the limit, an iteration whose unary costs are incomplete is dropped, one whose solver
 * stopped early keeps the labeling reached (it is checked as any update), and the remaining levels only refine
 * the control grid (so the output has the final grid). The transform is then the best reached: an update is only
 * kept if it lowers the energy. GetTimeLimitReached() is true.
 *
 * \par References
 * B. Glocker, N. Komodakis, G. Tziritas, N. Navab and N. Paragios, "Dense image registration through MRFs and
 * efficient linear programming", Medical Image Analysis 12(6):731-741, 2008, doi:10.1016/j.media.2008.03.006.
 * Y. Boykov, O. Veksler and R. Zabih, "Fast approximate energy minimization via graph cuts", IEEE TPAMI
 * 23(11):1222-1239, 2001, doi:10.1109/34.969114.
 *
 * \code
 * auto registration = itk::BSplineMRFImageRegistrationMethod<ImageType>::New();
 * registration->SetFixedImage(target);
 * registration->SetMovingImage(source);
 * registration->SetFixedImageMask(band);
 * registration->SetSimilarity(itk::BSplineMRFImageRegistrationMethodEnums::Similarity::SumOfSquaredDifferences);
 * registration->Update();
 * const auto * transform = registration->GetTransform();
 * \endcode
 *
 * \sa BSplineFFDImageRegistrationMethod, MRFLabelingSolver, BSplineTransform
 * \ingroup FFDShapeMatching
 */
template <typename TFixedImage, typename TMovingImage = TFixedImage>
class ITK_TEMPLATE_EXPORT BSplineMRFImageRegistrationMethod
  : public BSplineImageRegistrationMethodBase<TFixedImage, TMovingImage>
{
public:
  ITK_DISALLOW_COPY_AND_MOVE(BSplineMRFImageRegistrationMethod);

  using Self = BSplineMRFImageRegistrationMethod;
  using Superclass = BSplineImageRegistrationMethodBase<TFixedImage, TMovingImage>;
  using Pointer = SmartPointer<Self>;
  using ConstPointer = SmartPointer<const Self>;

  itkNewMacro(Self);
  itkOverrideGetNameOfClassMacro(BSplineMRFImageRegistrationMethod);

  static constexpr unsigned int ImageDimension = TFixedImage::ImageDimension;
  static_assert(ImageDimension == 3 && TMovingImage::ImageDimension == 3, "The MRF registration is 3-D");

  using typename Superclass::BSplineTransformType;
  using typename Superclass::DecoratedTransformType;
  using typename Superclass::FixedImageType;
  using typename Superclass::MaskImageType;
  using typename Superclass::MovingImageType;
  using typename Superclass::TransformType;
  using SimilarityEnum = BSplineMRFImageRegistrationMethodEnums::Similarity;
  using PairwiseFunctionEnum = BSplineMRFImageRegistrationMethodEnums::PairwiseFunction;
  using LabelSetEnum = BSplineMRFImageRegistrationMethodEnums::LabelSet;
  using SolverEnum = MRFLabelingSolverEnums::Algorithm;
  using DisplacementType = Vector<double, ImageDimension>;
  using InternalImageType = Image<float, ImageDimension>;

  // Inputs (fixed image, moving image, fixed-image mask) and the decorated transform output: see the superclass.

  // NumberOfControlPointsPerAxis (default 20) and NumberOfLevels (default 3; image pyramid with UseImagePyramid and
  // control-grid refinement): see the superclass.

  /** MRF iterations (label range shrinking after each) per level, at least 1. Default: 5. */
  itkSetMacro(NumberOfIterationsPerLevel, unsigned int);
  itkGetConstMacro(NumberOfIterationsPerLevel, unsigned int);

  /** Shape of the label set. Default: Sparse. */
  itkSetEnumMacro(LabelSet, LabelSetEnum);
  itkGetEnumMacro(LabelSet, LabelSetEnum);

  /** Steps K per direction of the label set, at least 1. Default: 3. */
  itkSetMacro(NumberOfLabelSteps, unsigned int);
  itkGetConstMacro(NumberOfLabelSteps, unsigned int);

  /** Largest label displacement at a level's first iteration, as a fraction of the control spacing; in (0, 1].
   * Default: 0.4. */
  itkSetMacro(MaximumDisplacementFactor, double);
  itkGetConstMacro(MaximumDisplacementFactor, double);

  /** Largest label displacement (mm) at the first level's first iteration, halved at each further level;
   * 0 uses MaximumDisplacementFactor. Default: 0. */
  itkSetMacro(MaximumDisplacement, double);
  itkGetConstMacro(MaximumDisplacement, double);

  /** Factor applied to the label range after each iteration, in (0, 1]. Default: 0.67. */
  itkSetMacro(LabelShrinkFactor, double);
  itkGetConstMacro(LabelShrinkFactor, double);

  /** Pointwise dissimilarity of the unary costs. Default: MutualInformation. */
  itkSetEnumMacro(Similarity, SimilarityEnum);
  itkGetEnumMacro(Similarity, SimilarityEnum);

  /** Bins per image of the joint histogram of MutualInformation, at least 4. Default: 32. */
  itkSetMacro(NumberOfHistogramBins, unsigned int);
  itkGetConstMacro(NumberOfHistogramBins, unsigned int);

  /** Weight lambda of the pairwise regularization, >= 0. Default: 0.5. */
  itkSetMacro(RegularizationWeight, double);
  itkGetConstMacro(RegularizationWeight, double);

  /** Regularization function rho. Default: Quadratic. */
  itkSetEnumMacro(PairwiseFunction, PairwiseFunctionEnum);
  itkGetEnumMacro(PairwiseFunction, PairwiseFunctionEnum);

  /** Truncation value tau of the Truncated pairwise function (control spacings), > 0. Default: 0.5. */
  itkSetMacro(TruncationValue, double);
  itkGetConstMacro(TruncationValue, double);

  /** Reject an update whose sampled minimum Jacobian determinant is below FoldingThreshold. Default: On. */
  /** Whether coarse levels smooth and shrink the images (On, default) or keep them at full resolution. */
  itkSetMacro(UseImagePyramid, bool);
  itkGetConstMacro(UseImagePyramid, bool);
  itkBooleanMacro(UseImagePyramid);

  itkSetMacro(RejectFoldingUpdates, bool);
  itkGetConstMacro(RejectFoldingUpdates, bool);
  itkBooleanMacro(RejectFoldingUpdates);

  /** Smallest Jacobian determinant an accepted update may have. Default: 0.05. */
  itkSetMacro(FoldingThreshold, double);
  itkGetConstMacro(FoldingThreshold, double);

  /** Alpha-expansion cycles (ICM: sweeps; SpanningTree: the tree's minimum, then this number minus one ICM sweeps)
   * per iteration, at least 1. Default: 2. */
  itkSetMacro(NumberOfSolverCycles, unsigned int);
  itkGetConstMacro(NumberOfSolverCycles, unsigned int);

  /** Discrete solver. Default: AlphaExpansion (ICM for comparison; Exhaustive is refused). */
  itkSetEnumMacro(Solver, SolverEnum);
  itkGetEnumMacro(Solver, SolverEnum);

  /** Registration energy after each iteration, over all levels, of the last Update(). */
  const std::vector<double> &
  GetEnergyValues() const
  {
    return m_EnergyValues;
  }

  /** Level of each entry of GetEnergyValues(). */
  const std::vector<unsigned int> &
  GetEnergyLevels() const
  {
    return m_EnergyLevels;
  }

  /** Energy of the MRF labeling found by the solver at each iteration (its own energy model). */
  const std::vector<double> &
  GetLabelingEnergyValues() const
  {
    return m_LabelingEnergyValues;
  }

  /** Updates rejected (energy increase or folding) by the last Update(). */
  itkGetConstMacro(NumberOfRejectedUpdates, unsigned int);

  /** Smallest Jacobian determinant of the result, sampled at 2 points per axis in each control cell. */
  itkGetConstMacro(MinimumJacobianDeterminant, double);

  /** The label displacements (mm) for a largest step \c maximumDisplacement; the first is zero. */
  std::vector<DisplacementType>
  MakeLabels(double maximumDisplacement) const;

  /** Unary costs of \c labels (node-major, control point p * labels + l, control points in the transform's
   * parameter order) for \c transform on the given fixed image (with an optional mask) and moving image, as the
   * registration computes them. Exposed for tests and analysis. */
  std::vector<double>
  ComputeUnaryCosts(const InternalImageType *             fixed,
                    const MaskImageType *                 mask,
                    const InternalImageType *             moving,
                    const BSplineTransformType *          transform,
                    const std::vector<DisplacementType> & labels);

  /** Pointwise dissimilarity of a fixed and a moving intensity, with the current histogram for
   * MutualInformation (set by ComputeUnaryCosts()). Not used for NormalizedCrossCorrelation. */
  double
  PointwiseCost(double fixedValue, double movingValue) const;

protected:
  BSplineMRFImageRegistrationMethod()
    : Superclass(3)
  {}
  ~BSplineMRFImageRegistrationMethod() override = default;

  void
  VerifyPreconditions() const override;

  void
  GenerateData() override;

  void
  PrintSelf(std::ostream & os, Indent indent) const override;

private:
  using InternalImagePointer = typename InternalImageType::Pointer;

  using Voxel = detail::BSplineMRFUnaryCosts::Voxel;
  using LevelData = detail::BSplineMRFUnaryCosts::LevelData;

  void
  PrepareLevel(const InternalImageType *    fixed,
               const MaskImageType *        mask,
               const InternalImageType *    moving,
               const BSplineTransformType * transform,
               LevelData &                  level) const;

  void
  ComputeMovingIndices(const LevelData &            level,
                       const BSplineTransformType * transform,
                       std::vector<float> &         indices) const;

  /** Unary costs of the labels (BSplineMRFUnaryCosts::ComputeUnaries()); with stopAtTimeLimit, an empty vector once
   * MaximumRunTime has passed (checked before each label). */
  std::vector<double>
  ComputeUnaries(const LevelData &                     level,
                 const std::vector<float> &            indices,
                 const std::vector<DisplacementType> & labels,
                 bool                                  stopAtTimeLimit = false) const;

  /** Hands the similarity, the number of histogram bins and of work units to m_UnaryCosts. */
  void
  ConfigureUnaryCosts();

  double
  Pairwise(const DisplacementType & difference, double inverseSpacing) const;

  double
  RegularizationEnergy(const BSplineTransformType * transform) const;

  double
  MinimumJacobianDeterminantOf(const BSplineTransformType * transform) const;

  template <typename TImage>
  static InternalImagePointer
  MakeLevelImage(const TImage * input, unsigned int factor);

  void
  RunLevel(unsigned int level, BSplineTransformType * transform, unsigned int & iterationCount);

  unsigned int         m_NumberOfIterationsPerLevel{ 5 };
  LabelSetEnum         m_LabelSet{ LabelSetEnum::Sparse };
  unsigned int         m_NumberOfLabelSteps{ 3 };
  double               m_MaximumDisplacementFactor{ 0.4 };
  double               m_MaximumDisplacement{ 0.0 };
  double               m_LabelShrinkFactor{ 0.67 };
  SimilarityEnum       m_Similarity{ SimilarityEnum::MutualInformation };
  unsigned int         m_NumberOfHistogramBins{ 32 };
  double               m_RegularizationWeight{ 0.5 };
  PairwiseFunctionEnum m_PairwiseFunction{ PairwiseFunctionEnum::Quadratic };
  double               m_TruncationValue{ 0.5 };
  bool                 m_RejectFoldingUpdates{ true };
  bool                 m_UseImagePyramid{ true };
  double               m_FoldingThreshold{ 0.05 };
  unsigned int         m_NumberOfSolverCycles{ 2 };
  SolverEnum           m_Solver{ SolverEnum::AlphaExpansion };

  std::vector<double>       m_EnergyValues{};
  std::vector<unsigned int> m_EnergyLevels{};
  std::vector<double>       m_LabelingEnergyValues{};
  unsigned int              m_NumberOfRejectedUpdates{ 0 };
  double                    m_MinimumJacobianDeterminant{ 1.0 };

  // The unary costs and, for mutual information, the cost table over histogram bins.
  detail::BSplineMRFUnaryCosts m_UnaryCosts{};
};
} // namespace itk

#ifndef ITK_MANUAL_INSTANTIATION
#  include "itkBSplineMRFImageRegistrationMethod.hxx"
#endif

#endif // itkBSplineMRFImageRegistrationMethod_h
