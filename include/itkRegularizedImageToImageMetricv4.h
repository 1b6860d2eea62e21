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
#ifndef itkRegularizedImageToImageMetricv4_h
#define itkRegularizedImageToImageMetricv4_h

#include "itkFFDShapeMatchingCompatibility.h"
#include "itkBSplineDeformationPenalty.h"
#include "itkCompositeTransform.h"

namespace itk
{
/** \class RegularizedImageToImageMetricv4
 * \brief An ITK v4 image metric plus the regularization terms of a B-spline deformation.
 *
 * The class derives from the image metric it regularizes (\c TImageToImageMetric, e.g.
 * MattesMutualInformationImageToImageMetricv4 or MeanSquaresImageToImageMetricv4), so it plugs into
 * ImageRegistrationMethodv4 and every v4 optimizer unchanged. Its value is the image metric's value plus
 * the weighted BSplineDeformationPenalty (bending energy and folding penalty) of the cubic BSplineTransform
 * being optimized; its derivative adds the penalty's exact derivative (with the v4 sign: the derivative
 * points downhill).
 *
 * The B-spline transform is the moving transform itself, or the most recent transform of a moving
 * CompositeTransform (as ImageRegistrationMethodv4 sets it up). When both weights are zero the metric is the
 * image metric exactly. With a positive weight and no cubic BSplineTransform to regularize,
 * Initialize() throws.
 *
 * \code
 * using MetricType = itk::RegularizedImageToImageMetricv4<
 *   itk::MattesMutualInformationImageToImageMetricv4<ImageType, ImageType>>;
 * auto metric = MetricType::New();
 * metric->GetModifiablePenalty()->SetBendingEnergyWeight(0.01);
 * registration->SetMetric(metric);
 * \endcode
 *
 * \sa BSplineDeformationPenalty, ImageRegistrationMethodv4
 * \ingroup FFDShapeMatching
 */
template <typename TImageToImageMetric>
class ITK_TEMPLATE_EXPORT RegularizedImageToImageMetricv4 : public TImageToImageMetric
{
public:
  ITK_DISALLOW_COPY_AND_MOVE(RegularizedImageToImageMetricv4);

  using Self = RegularizedImageToImageMetricv4;
  using Superclass = TImageToImageMetric;
  using Pointer = SmartPointer<Self>;
  using ConstPointer = SmartPointer<const Self>;

  itkNewMacro(Self);
  itkOverrideGetNameOfClassMacro(RegularizedImageToImageMetricv4);

  using MeasureType = typename Superclass::MeasureType;
  using DerivativeType = typename Superclass::DerivativeType;
  using ParametersValueType = typename Superclass::ParametersValueType;
  static constexpr unsigned int ImageDimension = Superclass::VirtualImageDimension;
  using PenaltyType = BSplineDeformationPenalty<ParametersValueType, ImageDimension>;
  using BSplineTransformType = typename PenaltyType::BSplineTransformType;

  /** The regularization terms and their weights (both zero by default). */
  itkGetModifiableObjectMacro(Penalty, PenaltyType);

  /** Image metric value of the last evaluation, without the penalty. */
  itkGetConstMacro(LastImageMetricValue, MeasureType);

  /** Weighted penalty of the last evaluation. */
  itkGetConstMacro(LastPenaltyValue, MeasureType);

  void
  Initialize() override;

  MeasureType
  GetValue() const override;

  void
  GetDerivative(DerivativeType & derivative) const override;

  void
  GetValueAndDerivative(MeasureType & value, DerivativeType & derivative) const override;

  /** The cubic B-spline transform being optimized, or null when there is none. */
  const BSplineTransformType *
  GetRegularizedTransform() const;

protected:
  RegularizedImageToImageMetricv4();
  ~RegularizedImageToImageMetricv4() override = default;
  void
  PrintSelf(std::ostream & os, Indent indent) const override;

private:
  typename PenaltyType::Pointer m_Penalty;
  mutable MeasureType           m_LastImageMetricValue{ 0.0 };
  mutable MeasureType           m_LastPenaltyValue{ 0.0 };
};
} // namespace itk

#ifndef ITK_MANUAL_INSTANTIATION
#  include "itkRegularizedImageToImageMetricv4.hxx"
#endif

#endif // itkRegularizedImageToImageMetricv4_h
