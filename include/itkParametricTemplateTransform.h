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
#ifndef itkParametricTemplateTransform_h
#define itkParametricTemplateTransform_h

#include "itkFFDShapeMatchingCompatibility.h"
#include "itkBSplineTransform.h"
#include "FFDShapeMatchingDetail/itkPrincipalComponents.h"
#include "FFDShapeMatchingDetail/itkSpatialJacobianEvaluator.h"
#include "itkTransform.h"
#include <cctype>
#include <cstdint>
#include <ostream>
#include <string>
#include <vector>

namespace itk
{
/** \class ParametricTemplateTransformEnums
 * \brief Enumerations of ParametricTemplateTransform.
 *
 * \c TemplateSplit says how each given template is turned into the templates of the transform:
 * - \c None: kept whole (one weight per template),
 * - \c ControlPoint: one template per control point the template moves, keeping that point's displacement
 *   vector (its direction is known, its magnitude is the unknown weight: the paper's experimental setting),
 * - \c Axis: one template per control point and axis (each non-zero displacement component on its own).
 *
 * \ingroup FFDShapeMatching
 */
class ParametricTemplateTransformEnums
{
public:
  enum class TemplateSplit : uint8_t
  {
    None,
    ControlPoint,
    Axis
  };

  /** The command-line spelling of a split: "none", "control-point" or "axis". */
  static std::string
  TemplateSplitToString(TemplateSplit split)
  {
    switch (split)
    {
      case TemplateSplit::ControlPoint:
        return "control-point";
      case TemplateSplit::Axis:
        return "axis";
      case TemplateSplit::None:
      default:
        return "none";
    }
  }

  /** Parses "none", "control-point" or "axis" (case-insensitive). Returns false and leaves split unchanged
   * for any other text. */
  static bool
  TemplateSplitFromString(const std::string & text, TemplateSplit & split)
  {
    std::string lower = text;
    for (auto & character : lower)
    {
      character = static_cast<char>(std::tolower(static_cast<unsigned char>(character)));
    }
    for (const auto candidate : { TemplateSplit::None, TemplateSplit::ControlPoint, TemplateSplit::Axis })
    {
      if (lower == TemplateSplitToString(candidate))
      {
        split = candidate;
        return true;
      }
    }
    return false;
  }
};

/** Prints the qualified enumerator name. */
inline std::ostream &
operator<<(std::ostream & out, const ParametricTemplateTransformEnums::TemplateSplit value)
{
  switch (value)
  {
    case ParametricTemplateTransformEnums::TemplateSplit::None:
      return out << "itk::ParametricTemplateTransformEnums::TemplateSplit::None";
    case ParametricTemplateTransformEnums::TemplateSplit::ControlPoint:
      return out << "itk::ParametricTemplateTransformEnums::TemplateSplit::ControlPoint";
    case ParametricTemplateTransformEnums::TemplateSplit::Axis:
      return out << "itk::ParametricTemplateTransformEnums::TemplateSplit::Axis";
    default:
      return out << "INVALID VALUE FOR itk::ParametricTemplateTransformEnums::TemplateSplit";
  }
}

/** \class ParametricTemplateTransform
 * \brief Cubic B-spline deformation whose control displacements are a weighted sum of fixed templates.
 *
 * The transform lives on a cubic B-spline control grid with exactly the geometry conventions of
 * BSplineTransform (SetTransformDomain() or SetGridFromBSplineTransform()). Its control displacements
 * (coefficients, laid out as BSplineTransform's parameters: all x components, then all y, then all z) are
 * \f[ \Delta = \mathbf{b} + \sum_{k=1}^{K} \pi_k \boldsymbol{\delta}_k , \f]
 * where the templates \f$\boldsymbol{\delta}_k\f$ and the base \f$\mathbf{b}\f$ are fixed coefficient
 * vectors of the grid and the K weights \f$\pi_k\f$ are the transform's Parameters. The base is zero unless
 * set (SetBaseCoefficients(), SetBaseFromTransform(): e.g. the B-spline result of a voxel registration that
 * the templates refine). Templates are stored sparsely, so one template per control point (the split modes)
 * costs three numbers per template.
 *
 * TransformPoint() is that of BSplineTransform with the coefficients \f$\Delta\f$ (with one template per
 * coefficient, unit entries and no base, the transform equals BSplineTransform with Parameters = weights, bit
 * for bit). ComputeJacobianWithRespectToParameters() gives the 3 x K matrix
 * \f$\partial T/\partial \pi_k = \sum_{c} \beta_c(x) \boldsymbol{\delta}_{k,c}\f$ (B-spline weights of the 64
 * control points c supporting x); AccumulateJacobianTransposeProduct() adds \f$J^T v\f$ without forming J,
 * touching only the templates that move those control points. ComputeJacobianWithRespectToPosition() is the
 * analytic spatial Jacobian (detail::SpatialJacobianEvaluator), so the inverse mesh application by Newton
 * iteration works. Outside the grid's valid region the transform is the identity, as BSplineTransform is.
 *
 * \par Fixed parameters (transform files)
 * The FixedParameters hold everything but the weights, so Clone() and TransformFileWriter/Reader round-trip
 * the transform exactly: the BSplineTransform fixed parameters of the grid (\f$N(N+3)\f$ values: grid size,
 * origin, spacing, direction), then K, then the base and the K templates, each as a count m followed by m
 * pairs (coefficient index, value). To read such a file, register the transform once with
 * RegisterFFDShapeMatchingTransforms().
 *
 * \par Template sources
 * SetTemplates() (dense coefficient vectors, with a TemplateSplit), SetTemplatesFromBSplineTransforms() (the
 * coefficients of BSplineTransforms on the grid, e.g. read from a transform file), and
 * SetTemplatesFromPrincipalComponents() (principal components of example deformations by Eigen's SVD, the
 * active-shape-model route).
 *
 * \code
 * auto transform = itk::ParametricTemplateTransform<>::New();
 * transform->SetGridFromBSplineTransform(noise);
 * std::vector<const itk::BSplineTransform<double, 3, 3> *> sources{ noise };
 * transform->SetTemplatesFromBSplineTransforms(sources,
 * itk::ParametricTemplateTransformEnums::TemplateSplit::ControlPoint); \endcode
 *
 * \par References
 * The parametric model of "A comparative analysis of B-spline deformation models in 3D shape matching"
 * (section 3.3); D. Rueckert et al., "Nonrigid registration using free-form deformations", IEEE TMI 18(8),
 * 1999, doi:10.1109/42.796284.
 *
 * \sa BSplineTransform, MeshSurfaceDistanceMetricv4, ParametricTemplateRegistrationMethod
 * \ingroup FFDShapeMatching
 */
template <typename TParametersValueType = double, unsigned int NDimensions = 3>
class ITK_TEMPLATE_EXPORT ParametricTemplateTransform : public Transform<TParametersValueType, NDimensions, NDimensions>
{
public:
  ITK_DISALLOW_COPY_AND_MOVE(ParametricTemplateTransform);

  using Self = ParametricTemplateTransform;
  using Superclass = Transform<TParametersValueType, NDimensions, NDimensions>;
  using Pointer = SmartPointer<Self>;
  using ConstPointer = SmartPointer<const Self>;

  itkNewMacro(Self);
  itkOverrideGetNameOfClassMacro(ParametricTemplateTransform);

  static constexpr unsigned int SpaceDimension = NDimensions;

  using typename Superclass::ScalarType;
  using typename Superclass::ParametersType;
  using typename Superclass::ParametersValueType;
  using typename Superclass::FixedParametersType;
  using typename Superclass::FixedParametersValueType;
  using typename Superclass::NumberOfParametersType;
  using typename Superclass::JacobianType;
  using typename Superclass::JacobianPositionType;
  using typename Superclass::InputPointType;
  using typename Superclass::OutputPointType;
  using typename Superclass::OutputVectorType;
  using typename Superclass::DerivativeType;
  using typename Superclass::TransformCategoryEnum;
  using TransformType = Superclass;
  using BSplineTransformType = BSplineTransform<TParametersValueType, NDimensions, 3>;
  using PhysicalDimensionsType = typename BSplineTransformType::PhysicalDimensionsType;
  using MeshSizeType = typename BSplineTransformType::MeshSizeType;
  using OriginType = typename BSplineTransformType::OriginType;
  using DirectionType = typename BSplineTransformType::DirectionType;
  using TemplateSplitEnum = ParametricTemplateTransformEnums::TemplateSplit;

  /** A dense coefficient vector of the grid (BSplineTransform parameter layout). */
  using CoefficientVectorType = std::vector<double>;

  /** A sparse coefficient vector: sorted, distinct coefficient indices and their values. */
  struct SparseCoefficientVector
  {
    std::vector<SizeValueType> Indices;
    std::vector<double>        Values;
  };

  /** Number of BSplineTransform fixed parameters describing the grid. */
  static constexpr unsigned int NumberOfGridFixedParameters = NDimensions * (NDimensions + 3);

  /** Control grid covering a domain, as BSplineTransform::SetTransformDomain*(): mesh size = control points per
   * axis - 3. Clears templates and base. */
  void
  SetTransformDomain(const OriginType &             origin,
                     const PhysicalDimensionsType & physicalDimensions,
                     const MeshSizeType &           meshSize,
                     const DirectionType &          direction);

  /** Control grid of a BSplineTransform (its fixed parameters). Clears templates and base when the grid changes. */
  void
  SetGridFromBSplineTransform(const BSplineTransformType * transform);

  /** True if the BSplineTransform is on exactly this transform's grid. */
  bool
  IsOnSameGrid(const BSplineTransformType * transform) const;

  /** Number of coefficients of the grid: NDimensions times the number of control points. */
  SizeValueType
  GetNumberOfCoefficients() const
  {
    return static_cast<SizeValueType>(m_Coefficients.GetSize());
  }

  /** Number of templates K, the number of parameters. */
  SizeValueType
  GetNumberOfTemplates() const
  {
    return static_cast<SizeValueType>(m_Templates.size());
  }

  /** Sets the templates from dense coefficient vectors, each split as requested (zero entries are dropped;
   * all-zero templates and empty split pieces are skipped). Parameters are reset to zero. Throws for a
   * vector of the wrong length or without any non-zero template. */
  void
  SetTemplates(const std::vector<CoefficientVectorType> & templates, TemplateSplitEnum split = TemplateSplitEnum::None);

  /** Sets the templates from sparse coefficient vectors, used as they are. Parameters are reset to zero. */
  void
  SetSparseTemplates(const std::vector<SparseCoefficientVector> & templates);

  /** Sets the templates from the coefficients of BSplineTransforms on this grid (none set yet: the first one's
   * grid is taken), split as requested. Throws for an empty list, a null transform or a grid mismatch. */
  void
  SetTemplatesFromBSplineTransforms(const std::vector<const BSplineTransformType *> & transforms,
                                    TemplateSplitEnum                                 split = TemplateSplitEnum::None);

  /** Principal components of example coefficient vectors (Eigen's JacobiSVD of the centred examples):
   * their mean, the numberOfComponents leading unit components, and the standard deviation along each
   * (singular value / sqrt(n - 1)). Components with zero deviation are dropped. Throws for fewer than two
   * examples or vectors of unequal length. */
  static void
  ComputePrincipalComponents(const std::vector<CoefficientVectorType> & examples,
                             unsigned int                               numberOfComponents,
                             CoefficientVectorType &                    mean,
                             std::vector<CoefficientVectorType> &       components,
                             std::vector<double> &                      standardDeviations)
  {
    detail::ComputePrincipalComponents(examples, numberOfComponents, mean, components, standardDeviations);
  }

  /** Templates = the leading principal components of example deformations (coefficient vectors of this grid),
   * each scaled by its standard deviation, so weights are in standard deviations. The base is not changed:
   * SetBaseCoefficients() with the mean of ComputePrincipalComponents() if the examples are not centred. */
  void
  SetTemplatesFromPrincipalComponents(const std::vector<CoefficientVectorType> & examples,
                                      unsigned int                               numberOfComponents);

  /** Template k as a dense coefficient vector. */
  CoefficientVectorType
  GetTemplate(SizeValueType k) const;

  /** Template k as stored. */
  const SparseCoefficientVector &
  GetSparseTemplate(SizeValueType k) const
  {
    return m_Templates.at(k);
  }

  /** Sets the base deformation (a dense coefficient vector of the grid). Throws for a wrong length. */
  void
  SetBaseCoefficients(const CoefficientVectorType & base);

  /** Base from a transform: a BSplineTransform on the same grid gives its coefficients exactly; any other
   * transform (another grid, a composite, ...) is sampled at the control points and turned into cubic B-spline
   * coefficients that interpolate those displacements (BSplineDecompositionImageFilter). Null clears the base. */
  void
  SetBaseFromTransform(const TransformType * transform);

  /** The control displacements (coefficient vector of this grid) of a transform: a BSplineTransform on the same grid
   * exactly, any other transform sampled at the control points and B-spline-decomposed (see SetBaseFromTransform()). */
  CoefficientVectorType
  ComputeCoefficientsOfTransform(const TransformType * transform) const;

  /** Least-squares weights: the pi minimizing |base + sum_k pi_k delta_k - coefficients|^2 (Jacobi-preconditioned
   * conjugate gradients on the normal equations, touching only the templates' non-zero entries; exact in one step
   * for templates with disjoint supports such as the split ones). */
  ParametersType
  ProjectCoefficients(const CoefficientVectorType & coefficients) const;

  /** The base as a dense coefficient vector (zeros when unset). */
  CoefficientVectorType
  GetBaseCoefficients() const;

  /** Current control displacements base + sum_k pi_k delta_k (BSplineTransform parameter layout). */
  const ParametersType &
  GetCoefficients() const
  {
    return m_Coefficients;
  }

  /** A new BSplineTransform on the grid with the current control displacements (equal to this transform). */
  typename BSplineTransformType::Pointer
  MakeBSplineTransform() const;

  /** The internal B-spline on the grid, holding the current coefficients. */
  const BSplineTransformType *
  GetGridTransform() const
  {
    return m_GridTransform.GetPointer();
  }

  void
  SetParameters(const ParametersType & parameters) override;

  void
  SetFixedParameters(const FixedParametersType & fixedParameters) override;

  /** Copies the range into the parameters (the size must be K), then SetParameters(). */
  void
  CopyInParameters(const ParametersValueType * const begin, const ParametersValueType * const end) override;

  /** Copies the range (of any valid length) into the fixed parameters, then SetFixedParameters(). */
  void
  CopyInFixedParameters(const FixedParametersValueType * const begin,
                        const FixedParametersValueType * const end) override;

  using Superclass::TransformPoint;
  OutputPointType
  TransformPoint(const InputPointType & point) const override;

  void
  ComputeJacobianWithRespectToParameters(const InputPointType & point, JacobianType & jacobian) const override;

  /** Adds factor * J(point)^T vector to derivative (length K), J the Jacobian with respect to the parameters,
   * touching only templates that move the control points supporting the point. */
  void
  AccumulateJacobianTransposeProduct(const InputPointType &   point,
                                     const OutputVectorType & vector,
                                     double                   factor,
                                     DerivativeType &         derivative) const;

  using Superclass::ComputeJacobianWithRespectToPosition;
  void
  ComputeJacobianWithRespectToPosition(const InputPointType & point, JacobianPositionType & jacobian) const override;

  /** Not linear, no local support: a global transform with K parameters. */
  TransformCategoryEnum
  GetTransformCategory() const override
  {
    return TransformCategoryEnum::UnknownTransformCategory;
  }

  NumberOfParametersType
  GetNumberOfParameters() const override
  {
    return static_cast<NumberOfParametersType>(m_Templates.size());
  }

protected:
  ParametricTemplateTransform();
  ~ParametricTemplateTransform() override = default;

  void
  PrintSelf(std::ostream & os, Indent indent) const override;

private:
  /** Sets the grid from BSplineTransform fixed parameters; resizes coefficients; keeps templates if compatible. */
  void
  SetGridFixedParameters(const FixedParametersType & gridParameters);

  /** Rebuilds the per-control-point index of templates, the fixed parameters and the coefficients. */
  void
  TemplatesChanged();

  /** Writes the grid, K, base and templates into m_FixedParameters. */
  void
  UpdateFixedParameters();

  /** Recomputes the coefficients from base, templates and weights. */
  void
  UpdateCoefficients();

  static SparseCoefficientVector
  MakeSparse(const CoefficientVectorType & dense);

  struct NodeEntry
  {
    SizeValueType Template;
    double        Value[NDimensions];
  };

  typename BSplineTransformType::Pointer                              m_GridTransform;
  SizeValueType                                                       m_NumberOfNodes{ 0 };
  std::vector<SparseCoefficientVector>                                m_Templates;
  SparseCoefficientVector                                             m_Base;
  std::vector<SizeValueType>                                          m_NodeOffsets;
  std::vector<NodeEntry>                                              m_NodeEntries;
  ParametersType                                                      m_Coefficients;
  detail::SpatialJacobianEvaluator<TParametersValueType, NDimensions> m_JacobianEvaluator;
};
} // namespace itk

#ifndef ITK_MANUAL_INSTANTIATION
#  include "itkParametricTemplateTransform.hxx"
#endif

#endif // itkParametricTemplateTransform_h
