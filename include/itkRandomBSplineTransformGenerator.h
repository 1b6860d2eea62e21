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
#ifndef itkRandomBSplineTransformGenerator_h
#define itkRandomBSplineTransformGenerator_h

#include "itkFFDShapeMatchingCompatibility.h"
#include "itkBSplineTransform.h"
#include "itkImageBase.h"
#include "itkObject.h"
#include "itkObjectFactory.h"
#include <cstdint>
#include <ostream>

namespace itk
{
/** \class RandomBSplineTransformGeneratorEnums
 * \brief Enumerations of RandomBSplineTransformGenerator.
 *
 * \c Noise selects how control displacements are drawn:
 * - \c ClippedGaussian: white Gaussian noise \f$N(0, \sigma^2)\f$ per component, clipped (clamped) to
 *   \f$[-a, a]\f$ (the noise of the paper's experiment),
 * - \c SmoothedGaussian: white \f$N(0, 1)\f$ noise smoothed over the control grid by a Gaussian of standard
 *   deviation SmoothingSigma (in control-point spacings), rescaled to the requested RMS displacement.
 *
 * \ingroup FFDShapeMatching
 */
class RandomBSplineTransformGeneratorEnums
{
public:
  enum class Noise : uint8_t
  {
    ClippedGaussian,
    SmoothedGaussian
  };
};

/** Prints the qualified enumerator name. */
inline std::ostream &
operator<<(std::ostream & out, const RandomBSplineTransformGeneratorEnums::Noise value)
{
  switch (value)
  {
    case RandomBSplineTransformGeneratorEnums::Noise::ClippedGaussian:
      return out << "itk::RandomBSplineTransformGeneratorEnums::Noise::ClippedGaussian";
    case RandomBSplineTransformGeneratorEnums::Noise::SmoothedGaussian:
      return out << "itk::RandomBSplineTransformGeneratorEnums::Noise::SmoothedGaussian";
    default:
      return out << "INVALID VALUE FOR itk::RandomBSplineTransformGeneratorEnums::Noise";
  }
}

/** \class RandomBSplineTransformGenerator
 * \brief Generates a cubic BSplineTransform with random, seedable control displacements.
 *
 * The transform covers a physical domain (Origin, PhysicalDimensions, Direction; or SetDomainFromImage() /
 * SetDomainFromBoundingBox()) with NumberOfControlPointsPerAxis control points per axis (default 20, i.e. an
 * ITK mesh size of N - 3). Its control displacements are drawn, component by component in parameter order, by a
 * Statistics::MersenneTwisterRandomVariateGenerator seeded with Seed (its own normal-variate algorithm, so the
 * result is the same on every platform):
 * - ClippedGaussian (default): \f$N(0, \sigma^2)\f$ with \f$\sigma\f$ = Sigma (mm, default 2), clamped to
 *   [-ClipAmplitude, ClipAmplitude] (mm, default 4);
 * - SmoothedGaussian: \f$N(0, 1)\f$ smoothed separably over the control grid with a Gaussian of standard
 *   deviation SmoothingSigma (control spacings, default 1; kernel truncated at 3 standard deviations and
 *   renormalized at the grid border), then scaled so that the root mean square of the control displacement
 *   vectors, \f$\sqrt{\frac{1}{n}\sum_k |\mathbf{d}_k|^2}\f$, equals RMSDisplacement (mm, default 2).
 *
 * Generate() builds the transform (GetTransform()) and checks it for folding: the Jacobian determinant
 * \f$\det(\partial T/\partial x)\f$ (analytic, detail::SpatialJacobianEvaluator) is sampled at the centres of a
 * regular grid of NumberOfJacobianSamplesPerAxis points per axis over the domain; GetMinimumJacobianDeterminant()
 * <= 0 means the transform folds.
 *
 * \code
 * auto generator = itk::RandomBSplineTransformGenerator<>::New();
 * generator->SetDomainFromImage(targetImage);
 * generator->SetSigma(3.0);
 * generator->SetSeed(42);
 * generator->Generate();
 * auto transform = generator->GetTransform();
 * \endcode
 *
 * \sa BSplineTransform, BSplineTransformInitializer, TransformToJacobianDeterminantImageFilter
 *
 * \ingroup FFDShapeMatching
 */
template <typename TParametersValueType = double, unsigned int NDimensions = 3>
class ITK_TEMPLATE_EXPORT RandomBSplineTransformGenerator : public Object
{
public:
  ITK_DISALLOW_COPY_AND_MOVE(RandomBSplineTransformGenerator);

  using Self = RandomBSplineTransformGenerator;
  using Superclass = Object;
  using Pointer = SmartPointer<Self>;
  using ConstPointer = SmartPointer<const Self>;

  itkNewMacro(Self);
  itkOverrideGetNameOfClassMacro(RandomBSplineTransformGenerator);

  using TransformType = BSplineTransform<TParametersValueType, NDimensions, 3>;
  using TransformPointer = typename TransformType::Pointer;
  using PointType = typename TransformType::OriginType;
  using PhysicalDimensionsType = typename TransformType::PhysicalDimensionsType;
  using DirectionType = typename TransformType::DirectionType;
  using ImageBaseType = ImageBase<NDimensions>;
  using NoiseEnum = RandomBSplineTransformGeneratorEnums::Noise;

  /** Corner of the domain (mm). Default: 0. */
  itkSetMacro(Origin, PointType);
  itkGetConstReferenceMacro(Origin, PointType);

  /** Extent of the domain along each direction (mm). Default: 100. */
  itkSetMacro(PhysicalDimensions, PhysicalDimensionsType);
  itkGetConstReferenceMacro(PhysicalDimensions, PhysicalDimensionsType);

  /** Axes of the domain. Default: identity. */
  itkSetMacro(Direction, DirectionType);
  itkGetConstReferenceMacro(Direction, DirectionType);

  /** Domain = the image's extent, from the outer corner of its first voxel to that of its last. */
  void
  SetDomainFromImage(const ImageBaseType * image);

  /** Domain = the axis-aligned box [minimum, maximum]. */
  void
  SetDomainFromBoundingBox(const PointType & minimum, const PointType & maximum);

  /** Control points per axis, at least 4. Default: 20. */
  itkSetClampMacro(NumberOfControlPointsPerAxis, unsigned int, 4, NumericTraits<unsigned int>::max());
  itkGetConstMacro(NumberOfControlPointsPerAxis, unsigned int);

  /** How displacements are drawn. Default: ClippedGaussian. */
  itkSetEnumMacro(Noise, NoiseEnum);
  itkGetEnumMacro(Noise, NoiseEnum);

  /** Standard deviation of the clipped Gaussian noise (mm). Default: 2. */
  itkSetClampMacro(Sigma, double, 0.0, NumericTraits<double>::max());
  itkGetConstMacro(Sigma, double);

  /** Clip amplitude a of the clipped Gaussian noise (mm). Default: 4. */
  itkSetClampMacro(ClipAmplitude, double, 0.0, NumericTraits<double>::max());
  itkGetConstMacro(ClipAmplitude, double);

  /** Standard deviation of the smoothing of SmoothedGaussian noise (control spacings). Default: 1. */
  itkSetClampMacro(SmoothingSigma, double, 0.0, NumericTraits<double>::max());
  itkGetConstMacro(SmoothingSigma, double);

  /** RMS length of the control displacement vectors in SmoothedGaussian mode (mm). Default: 2. */
  itkSetClampMacro(RMSDisplacement, double, 0.0, NumericTraits<double>::max());
  itkGetConstMacro(RMSDisplacement, double);

  /** Seed of the random generator. Default: 0. */
  itkSetMacro(Seed, uint32_t);
  itkGetConstMacro(Seed, uint32_t);

  /** Samples per axis of the Jacobian-determinant check (0 skips it). Default: 40. */
  itkSetMacro(NumberOfJacobianSamplesPerAxis, unsigned int);
  itkGetConstMacro(NumberOfJacobianSamplesPerAxis, unsigned int);

  /** Builds a new transform. Throws for an empty domain. */
  void
  Generate();

  /** The transform of the last Generate(). */
  itkGetModifiableObjectMacro(Transform, TransformType);

  /** Smallest sampled Jacobian determinant of the last Generate() (<= 0: folding). */
  itkGetConstMacro(MinimumJacobianDeterminant, double);

  /** Largest sampled Jacobian determinant of the last Generate(). */
  itkGetConstMacro(MaximumJacobianDeterminant, double);

protected:
  RandomBSplineTransformGenerator();
  ~RandomBSplineTransformGenerator() override = default;
  void
  PrintSelf(std::ostream & os, Indent indent) const override;

  /** Separable Gaussian smoothing of one displacement component stored on the control grid. */
  void
  SmoothComponent(TParametersValueType * values) const;

  /** Samples the Jacobian determinant on the check grid. */
  void
  CheckJacobianDeterminant();

private:
  PointType              m_Origin{};
  PhysicalDimensionsType m_PhysicalDimensions{};
  DirectionType          m_Direction{ DirectionType::GetIdentity() };
  unsigned int           m_NumberOfControlPointsPerAxis{ 20 };
  NoiseEnum              m_Noise{ NoiseEnum::ClippedGaussian };
  double                 m_Sigma{ 2.0 };
  double                 m_ClipAmplitude{ 4.0 };
  double                 m_SmoothingSigma{ 1.0 };
  double                 m_RMSDisplacement{ 2.0 };
  uint32_t               m_Seed{ 0 };
  unsigned int           m_NumberOfJacobianSamplesPerAxis{ 40 };
  TransformPointer       m_Transform;
  double                 m_MinimumJacobianDeterminant{ 1.0 };
  double                 m_MaximumJacobianDeterminant{ 1.0 };
};
} // namespace itk

#ifndef ITK_MANUAL_INSTANTIATION
#  include "itkRandomBSplineTransformGenerator.hxx"
#endif

#endif // itkRandomBSplineTransformGenerator_h
