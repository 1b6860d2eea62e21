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

#include "itkAffineTransform.h"
#include "itkIdentityTransform.h"
#include "itkImageRegionConstIteratorWithIndex.h"
#include "itkRandomBSplineTransformGenerator.h"
#include "FFDShapeMatchingDetail/itkSpatialJacobianEvaluator.h"
#include "itkTestingMacros.h"
#include "itkTransformToJacobianDeterminantImageFilter.h"

namespace
{
// The reference: the 3x3 determinant written out by the rule of Sarrus.
double
SarrusDeterminant(const itk::Matrix<double, 3, 3> & m)
{
  return m(0, 0) * m(1, 1) * m(2, 2) + m(0, 1) * m(1, 2) * m(2, 0) + m(0, 2) * m(1, 0) * m(2, 1) -
         m(0, 2) * m(1, 1) * m(2, 0) - m(0, 0) * m(1, 2) * m(2, 1) - m(0, 1) * m(1, 0) * m(2, 2);
}
} // namespace

int
itkTransformToJacobianDeterminantImageFilterTest(int argc, char * argv[])
{
  if (argc != 1)
  {
    std::cerr << "Usage: " << itkNameOfTestExecutableMacro(argv) << std::endl;
    return EXIT_FAILURE;
  }
  using ImageType = itk::Image<double, 3>;
  using FilterType = itk::TransformToJacobianDeterminantImageFilter<ImageType>;

  auto filter = FilterType::New();
  ITK_EXERCISE_BASIC_OBJECT_METHODS(filter, TransformToJacobianDeterminantImageFilter, ImageSource);
  ITK_TEST_SET_GET_BOOLEAN(filter, UseReferenceImage, false);
  ITK_TEST_SET_GET_VALUE(1e-3, (filter->SetFiniteDifferenceStep(1e-3), filter->GetFiniteDifferenceStep()));
  filter->SetFiniteDifferenceStep(1e-4);

  ImageType::SizeType    size = { { 12, 10, 8 } };
  ImageType::SpacingType spacing;
  spacing[0] = 7.0;
  spacing[1] = 9.0;
  spacing[2] = 11.0;
  ImageType::PointType origin;
  origin.Fill(5.0);
  filter->SetSize(size);
  filter->SetOutputSpacing(spacing);
  filter->SetOutputOrigin(origin);
  ITK_TEST_SET_GET_VALUE(size, filter->GetSize());
  ITK_TEST_SET_GET_VALUE(spacing, filter->GetOutputSpacing());
  ITK_TEST_SET_GET_VALUE(origin, filter->GetOutputOrigin());

  // No transform.
  ITK_TRY_EXPECT_EXCEPTION(filter->Update());

  // Identity: 1 everywhere.
  auto identity = itk::IdentityTransform<double, 3>::New();
  filter->SetTransform(identity);
  ITK_TRY_EXPECT_NO_EXCEPTION(filter->Update());
  ITK_TEST_EXPECT_EQUAL(filter->GetMinimumDeterminant(), 1.0);
  ITK_TEST_EXPECT_EQUAL(filter->GetMaximumDeterminant(), 1.0);

  // Affine: det(A) everywhere.
  auto                      affine = itk::AffineTransform<double, 3>::New();
  itk::Matrix<double, 3, 3> matrix;
  matrix(0, 0) = 1.2;
  matrix(0, 1) = 0.3;
  matrix(0, 2) = -0.2;
  matrix(1, 0) = 0.1;
  matrix(1, 1) = 0.8;
  matrix(1, 2) = 0.05;
  matrix(2, 0) = -0.1;
  matrix(2, 1) = 0.2;
  matrix(2, 2) = 1.1;
  affine->SetMatrix(matrix);
  const double expected = SarrusDeterminant(matrix);
  filter->SetTransform(affine);
  ITK_TRY_EXPECT_NO_EXCEPTION(filter->Update());
  double maximumError = 0.0;
  for (itk::ImageRegionConstIteratorWithIndex<ImageType> it(filter->GetOutput(),
                                                            filter->GetOutput()->GetLargestPossibleRegion());
       !it.IsAtEnd();
       ++it)
  {
    maximumError = std::max(maximumError, std::abs(it.Get() - expected));
  }
  std::cout << "Affine: det(A) = " << expected << ", max error " << maximumError << std::endl;
  ITK_TEST_EXPECT_TRUE(maximumError < 1e-12);
  ITK_TEST_EXPECT_TRUE(std::abs(filter->GetMinimumDeterminant() - expected) < 1e-12);

  // Random B-spline, geometry from a reference image: determinant of the finite-difference Jacobian.
  using GeneratorType = itk::RandomBSplineTransformGenerator<double, 3>;
  auto generator = GeneratorType::New();
  generator->SetNumberOfControlPointsPerAxis(8);
  generator->SetSigma(6.0);
  generator->SetClipAmplitude(12.0);
  generator->SetSeed(5);
  generator->Generate();
  auto bspline = generator->GetModifiableTransform();

  auto reference = ImageType::New();
  reference->SetRegions(size);
  reference->SetSpacing(spacing);
  reference->SetOrigin(origin);
  filter->SetReferenceImage(reference);
  filter->UseReferenceImageOn();
  filter->SetSize(ImageType::SizeType{ { 1, 1, 1 } }); // ignored: the reference image rules
  filter->SetTransform(bspline);
  ITK_TRY_EXPECT_NO_EXCEPTION(filter->Update());
  ITK_TEST_EXPECT_EQUAL(filter->GetOutput()->GetLargestPossibleRegion().GetSize(), size);
  maximumError = 0.0;
  double minimum = std::numeric_limits<double>::max();
  for (itk::ImageRegionConstIteratorWithIndex<ImageType> it(filter->GetOutput(),
                                                            filter->GetOutput()->GetLargestPossibleRegion());
       !it.IsAtEnd();
       ++it)
  {
    ImageType::PointType point;
    filter->GetOutput()->TransformIndexToPhysicalPoint(it.GetIndex(), point);
    itk::Matrix<double, 3, 3> jacobian;
    constexpr double          h = 1e-4;
    for (unsigned int j = 0; j < 3; ++j)
    {
      auto forward = point;
      auto backward = point;
      forward[j] += h;
      backward[j] -= h;
      const auto difference = bspline->TransformPoint(forward) - bspline->TransformPoint(backward);
      for (unsigned int i = 0; i < 3; ++i)
      {
        jacobian(i, j) = difference[i] / (2.0 * h);
      }
    }
    const double determinant = SarrusDeterminant(jacobian);
    minimum = std::min(minimum, determinant);
    maximumError = std::max(maximumError, std::abs(it.Get() - determinant));
  }
  std::cout << "B-spline: max |det - det(finite differences)| = " << maximumError << ", min det "
            << filter->GetMinimumDeterminant() << " (finite differences " << minimum << "), max det "
            << filter->GetMaximumDeterminant() << std::endl;
  ITK_TEST_EXPECT_TRUE(maximumError < 1e-6);
  ITK_TEST_EXPECT_TRUE(std::abs(filter->GetMinimumDeterminant() - minimum) < 1e-6);

  // The evaluator's rows against its points one by one: rows along the lattice's first axis (contracted once per
  // row) that cross both ends of the valid region, lie outside it, or are short, and slanted rows (point by point).
  {
    itk::detail::SpatialJacobianEvaluator<double, 3> evaluator;
    evaluator.Initialize(bspline);
    const auto   lattice = bspline->GetCoefficientImages()[0];
    const auto   latticeOrigin = lattice->GetOrigin();
    const auto   latticeSpacing = lattice->GetSpacing();
    const auto   latticeSize = lattice->GetLargestPossibleRegion().GetSize();
    double       rowError = 0.0;
    size_t       rows = 0;
    size_t       deformedPoints = 0;
    const double extent = latticeSpacing[0] * static_cast<double>(latticeSize[0]);
    for (unsigned int kind = 0; kind < 4; ++kind)
    {
      for (unsigned int r = 0; r < 12; ++r)
      {
        // kind 0: inside across, 1: outside across (beyond the third axis), 2: short, 3: slanted.
        const size_t                           count = kind == 2 ? 5 : 61;
        std::vector<itk::Point<double, 3>>     points(count);
        std::vector<itk::Matrix<double, 3, 3>> byRow(count);
        for (size_t k = 0; k < count; ++k)
        {
          const double t = static_cast<double>(k) / static_cast<double>(count - 1);
          points[k][0] = latticeOrigin[0] - 0.2 * extent + 1.4 * extent * t;
          points[k][1] = latticeOrigin[1] + latticeSpacing[1] * (1.3 + 0.37 * r);
          points[k][2] = kind == 1 ? latticeOrigin[2] - 3.0 * latticeSpacing[2]
                                   : latticeOrigin[2] + latticeSpacing[2] * (1.1 + 0.41 * r);
          if (kind == 3)
          {
            points[k][1] += 2.0 * latticeSpacing[1] * t;
          }
        }
        evaluator.EvaluateRow(points.data(), count, byRow.data());
        for (size_t k = 0; k < count; ++k)
        {
          itk::Matrix<double, 3, 3> single;
          evaluator.Evaluate(points[k], single);
          bool identity = true;
          for (unsigned int i = 0; i < 3; ++i)
          {
            for (unsigned int j = 0; j < 3; ++j)
            {
              rowError = std::max(rowError, std::abs(byRow[k](i, j) - single(i, j)));
              identity = identity && single(i, j) == (i == j ? 1.0 : 0.0);
            }
          }
          deformedPoints += identity ? 0 : 1;
        }
        ++rows;
      }
    }
    std::cout << "Evaluator rows: " << rows << " rows, " << deformedPoints
              << " points inside the valid region, max |row - point| = " << rowError << std::endl;
    ITK_TEST_EXPECT_TRUE(rowError < 1e-12);
    ITK_TEST_EXPECT_TRUE(deformedPoints > 500);
  }

  // The pipeline re-runs when the transform changes.
  generator->SetSeed(6);
  generator->Generate();
  bspline->SetParametersByValue(generator->GetTransform()->GetParameters());
  const double before = filter->GetMinimumDeterminant();
  filter->Update();
  std::cout << "After changing the transform: min det " << filter->GetMinimumDeterminant() << " (was " << before << ")"
            << std::endl;
  ITK_TEST_EXPECT_TRUE(filter->GetMinimumDeterminant() != before);

  std::cout << "Test finished." << std::endl;
  return EXIT_SUCCESS;
}
