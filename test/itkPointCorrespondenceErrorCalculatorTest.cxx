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

#include "itkMesh.h"
#include "itkPointCorrespondenceErrorCalculator.h"
#include "itkTestingMacros.h"

int
itkPointCorrespondenceErrorCalculatorTest(int argc, char * argv[])
{
  if (argc != 1)
  {
    std::cerr << "Usage: " << itkNameOfTestExecutableMacro(argv) << std::endl;
    return EXIT_FAILURE;
  }
  using MeshType = itk::Mesh<float, 3>;
  using CalculatorType = itk::PointCorrespondenceErrorCalculator<MeshType>;

  auto calculator = CalculatorType::New();
  ITK_EXERCISE_BASIC_OBJECT_METHODS(calculator, PointCorrespondenceErrorCalculator, Object);
  ITK_TRY_EXPECT_EXCEPTION(calculator->Compute());

  // Vertex i of the moved mesh is displaced by i + 1 mm along a direction that changes with i.
  auto moved = MeshType::New();
  auto reference = MeshType::New();
  for (itk::IdentifierType i = 0; i < 100; ++i)
  {
    MeshType::PointType truth;
    truth[0] = 0.5f * i;
    truth[1] = -0.25f * i;
    truth[2] = 3.0f;
    MeshType::PointType displaced = truth;
    displaced[i % 3] += static_cast<float>(i + 1);
    reference->SetPoint(i, truth);
    moved->SetPoint(i, displaced);
  }
  calculator->SetMovedMesh(moved);
  calculator->SetReferenceMesh(reference);
  ITK_TEST_SET_GET_VALUE(moved.GetPointer(), calculator->GetMovedMesh());
  ITK_TEST_SET_GET_VALUE(reference.GetPointer(), calculator->GetReferenceMesh());
  ITK_TRY_EXPECT_NO_EXCEPTION(calculator->Compute());

  // Errors 1, 2, ..., 100: mean 50.5, median 50.5, p95 at position 94.05 -> 95.05, max 100,
  // RMS sqrt(sum i^2 / 100) = sqrt(3383.5).
  std::cout << "mean " << calculator->GetMeanError() << " median " << calculator->GetMedianError() << " p95 "
            << calculator->GetPercentile95Error() << " max " << calculator->GetMaximumError() << " rms "
            << calculator->GetRootMeanSquareError() << std::endl;
  ITK_TEST_EXPECT_TRUE(itk::Math::FloatAlmostEqual(calculator->GetMeanError(), 50.5, 4, 1e-4));
  ITK_TEST_EXPECT_TRUE(itk::Math::FloatAlmostEqual(calculator->GetMedianError(), 50.5, 4, 1e-4));
  ITK_TEST_EXPECT_TRUE(itk::Math::FloatAlmostEqual(calculator->GetPercentile95Error(), 95.05, 4, 1e-4));
  ITK_TEST_EXPECT_TRUE(itk::Math::FloatAlmostEqual(calculator->GetMaximumError(), 100.0, 4, 1e-4));
  ITK_TEST_EXPECT_TRUE(itk::Math::FloatAlmostEqual(calculator->GetRootMeanSquareError(), std::sqrt(3383.5), 4, 1e-4));
  ITK_TEST_EXPECT_EQUAL(calculator->GetErrors().size(), 100);

  // An explicit vertex-id map: moved vertex i corresponds to reference vertex 99 - i.
  CalculatorType::CorrespondenceContainerType pairs;
  for (itk::IdentifierType i = 0; i < 100; ++i)
  {
    pairs.emplace_back(i, 99 - i);
  }
  calculator->SetCorrespondences(pairs);
  ITK_TEST_EXPECT_EQUAL(calculator->GetCorrespondences().size(), 100);
  ITK_TRY_EXPECT_NO_EXCEPTION(calculator->Compute());
  const double expected0 = moved->GetPoint(0).EuclideanDistanceTo(reference->GetPoint(99));
  ITK_TEST_EXPECT_TRUE(itk::Math::FloatAlmostEqual(calculator->GetErrors()[0], expected0, 4, 1e-9));

  // A map to a missing vertex is an error.
  pairs.emplace_back(0, 1000);
  calculator->SetCorrespondences(pairs);
  ITK_TRY_EXPECT_EXCEPTION(calculator->Compute());

  std::cout << "Test finished." << std::endl;
  return EXIT_SUCCESS;
}
