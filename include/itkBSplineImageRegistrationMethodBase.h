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
#ifndef itkBSplineImageRegistrationMethodBase_h
#define itkBSplineImageRegistrationMethodBase_h

#include "itkFFDShapeMatchingCompatibility.h"
#include "itkBSplineTransform.h"
#include "itkDataObjectDecorator.h"
#include "itkImage.h"
#include "itkProcessObject.h"
#include "itkTransform.h"
#include <chrono>

namespace itk
{
/** \class BSplineImageRegistrationMethodBase
 * \brief What the module's B-spline image registrations (GO: BSplineFFDImageRegistrationMethod, MRF:
 * BSplineMRFImageRegistrationMethod) share: their inputs, their decorated transform output, the checks of their
 * images and the control grid of each resolution level.
 *
 * Inputs: the fixed image (index 0; in shape matching the target's voxel image), the moving image (the source's)
 * and an optional fixed-image mask (unsigned char, non-zero = used; e.g. a band around the target surface).
 * Output: the transform T, fixed space to moving space (ITK's convention), as a decorated
 * Transform<double, 3, 3> (GetTransformOutput()), ready to connect into ApplyTransformToMeshFilter.
 *
 * A run-time limit (MaximumRunTime) stops either method's optimization cleanly with the best transform reached so
 * far; GetTimeLimitReached() tells whether the last Update() stopped there.
 *
 * The final control grid (NumberOfControlPointsPerAxis) and the resolution levels (NumberOfLevels, with the grid of
 * each level from GetMeshSizeAtLevel()) are the same for every derived method; each passes its default number of
 * levels to this class's constructor. A derived class implements GenerateData() and sets its result with
 * SetTransformOutputValue(); its VerifyPreconditions() calls VerifyImageInputs(), which also checks the grid and
 * the levels; its GenerateData() starts the clock with StartRunTimeClock() and asks CheckRunTime() (or, from worker
 * threads, IsRunTimeExceeded()) where it can stop.
 *
 * \sa BSplineFFDImageRegistrationMethod, BSplineMRFImageRegistrationMethod
 * \ingroup FFDShapeMatching
 */
template <typename TFixedImage, typename TMovingImage = TFixedImage>
class ITK_TEMPLATE_EXPORT BSplineImageRegistrationMethodBase : public ProcessObject
{
public:
  ITK_DISALLOW_COPY_AND_MOVE(BSplineImageRegistrationMethodBase);

  using Self = BSplineImageRegistrationMethodBase;
  using Superclass = ProcessObject;
  using Pointer = SmartPointer<Self>;
  using ConstPointer = SmartPointer<const Self>;

  itkOverrideGetNameOfClassMacro(BSplineImageRegistrationMethodBase);

  static constexpr unsigned int ImageDimension = TFixedImage::ImageDimension;

  using FixedImageType = TFixedImage;
  using MovingImageType = TMovingImage;
  using MaskImageType = Image<unsigned char, ImageDimension>;
  using TransformType = Transform<double, ImageDimension, ImageDimension>;
  using BSplineTransformType = BSplineTransform<double, ImageDimension, 3>;
  using DecoratedTransformType = DataObjectDecorator<TransformType>;

  /** The fixed image (target). */
  itkSetInputMacro(FixedImage, FixedImageType);
  itkGetInputMacro(FixedImage, FixedImageType);

  /** The moving image (source). */
  itkSetInputMacro(MovingImage, MovingImageType);
  itkGetInputMacro(MovingImage, MovingImageType);

  /** Optional mask of the fixed image: only its non-zero voxels are used. */
  itkSetInputMacro(FixedImageMask, MaskImageType);
  itkGetInputMacro(FixedImageMask, MaskImageType);

  /** The estimated transform, fixed space to moving space. */
  const DecoratedTransformType *
  GetTransformOutput() const;

  /** The estimated transform itself (null before Update()). */
  const TransformType *
  GetTransform() const;

  /** Wall-clock limit of Update() in seconds; 0 (the default) means none, and a negative value is clamped to 0.
   * When it is reached the optimization stops at the next point where the method checks it (see the derived
   * class), keeping the best transform reached so far, and GetTimeLimitReached() is true. */
  itkSetClampMacro(MaximumRunTime, double, 0.0, NumericTraits<double>::max());
  itkGetConstMacro(MaximumRunTime, double);

  /** Whether the last Update() stopped at MaximumRunTime. */
  itkGetConstMacro(TimeLimitReached, bool);

  /** Control points per axis of the final B-spline grid (ITK mesh size N - 3), 4 to 1000 (Update() refuses others).
   * Default: 20. */
  itkSetMacro(NumberOfControlPointsPerAxis, unsigned int);
  itkGetConstMacro(NumberOfControlPointsPerAxis, unsigned int);

  /** Resolution levels, 1 to 8 (Update() refuses others): level l (from 0) uses a control grid about 2^(L-1-l)
   * times coarser than the final one (GetMeshSizeAtLevel()); the derived class says what else a level changes.
   * Default: the derived class's (GO 1, MRF 3). */
  itkSetMacro(NumberOfLevels, unsigned int);
  itkGetConstMacro(NumberOfLevels, unsigned int);

  /** Control-grid mesh size (control points minus 3) used at a level of this method's schedule. */
  unsigned int
  GetMeshSizeAtLevel(unsigned int level) const
  {
    return ComputeMeshSizeAtLevel(m_NumberOfControlPointsPerAxis, m_NumberOfLevels, level);
  }

  /** Control-grid mesh size (control points minus 3) of a level of a schedule with numberOfLevels levels ending
   * with numberOfControlPointsPerAxis control points per axis: the final mesh size halved per coarser level,
   * rounded, at least 1. */
  static unsigned int
  ComputeMeshSizeAtLevel(unsigned int numberOfControlPointsPerAxis, unsigned int numberOfLevels, unsigned int level);

protected:
  /** \c numberOfLevels: the derived method's default NumberOfLevels. */
  explicit BSplineImageRegistrationMethodBase(unsigned int numberOfLevels);
  ~BSplineImageRegistrationMethodBase() override = default;

  /** Checks the grid (4 to 1000 control points per axis) and the levels (1 to 8), that the fixed and moving images
   * are not empty, the mask (if any) is not empty, and both images have at least 2^NumberOfLevels voxels along every
   * axis; throws an ExceptionObject naming the problem. */
  void
  VerifyImageInputs() const;

  /** Starts the clock of MaximumRunTime (at the start of GenerateData()) and clears TimeLimitReached. */
  void
  StartRunTimeClock();

  /** Seconds since StartRunTimeClock(). */
  double
  GetElapsedRunTime() const;

  /** Whether MaximumRunTime is set and has passed since StartRunTimeClock(). Changes nothing: safe from worker
   * threads. */
  bool
  IsRunTimeExceeded() const;

  /** Records (TimeLimitReached) that MaximumRunTime has passed, if it has; returns TimeLimitReached. */
  bool
  CheckRunTime();

  void
  PrintSelf(std::ostream & os, Indent indent) const override;

  /** Sets the decorated output's transform. */
  void
  SetTransformOutputValue(TransformType * transform);

  using Superclass::MakeOutput;
  DataObjectPointer MakeOutput(DataObjectPointerArraySizeType) override;

private:
  unsigned int                          m_NumberOfControlPointsPerAxis{ 20 };
  unsigned int                          m_NumberOfLevels;
  double                                m_MaximumRunTime{ 0.0 };
  bool                                  m_TimeLimitReached{ false };
  std::chrono::steady_clock::time_point m_StartTime{};
};
} // namespace itk

#ifndef ITK_MANUAL_INSTANTIATION
#  include "itkBSplineImageRegistrationMethodBase.hxx"
#endif

#endif // itkBSplineImageRegistrationMethodBase_h
