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
// Checks of B-spline grids and text transform files (itkTransformFileChecks.h), against the grids ITK's
// BSplineTransform accepts and the files ITK's writer writes.

#include "itkTransformFileChecks.h"
#include "itkBSplineTransform.h"
#include "itkRegisterFFDShapeMatchingTransforms.h"
#include "itkTransformFileReader.h"
#include "itkTransformFileWriter.h"
#include "gtest/gtest.h"

#include <cstdio>
#include <fstream>
#include <vector>

namespace
{
std::vector<double>
GoodGrid()
{
  return { 4, 5, 6, -10, -10, -10, 2, 2.5, 3, 1, 0, 0, 0, 1, 0, 0, 0, 1 };
}

std::string
WriteText(const std::string & name, const std::string & text)
{
  const std::string fileName = ::testing::TempDir() + name;
  std::ofstream(fileName, std::ios::binary) << text;
  return fileName;
}
} // namespace

TEST(TransformFileChecks, AcceptsGoodGrids)
{
  const std::vector<double> grid = GoodGrid();
  EXPECT_EQ(itk::FindProblemInBSplineFixedParameters(grid.data(), grid.size(), 3), "");
  EXPECT_EQ(itk::FindProblemInBSplineFixedParameters(grid.data(), grid.size(), 3, 3 * 4 * 5 * 6), "");
}

TEST(TransformFileChecks, RefusesBadGrids)
{
  const auto problemWith = [](std::size_t index, double value, long long parameters = -1) {
    std::vector<double> grid = GoodGrid();
    grid[index] = value;
    return itk::FindProblemInBSplineFixedParameters(grid.data(), grid.size(), 3, parameters);
  };
  EXPECT_NE(problemWith(0, -4).find("grid size along axis 0 is -4"), std::string::npos);
  EXPECT_NE(problemWith(1, 0).find("grid size along axis 1 is 0"), std::string::npos);
  EXPECT_NE(problemWith(2, 2.5).find("grid size along axis 2 is 2.5"), std::string::npos);
  EXPECT_NE(problemWith(0, 1e9).find("not a whole number in [1, 65536]"), std::string::npos);
  EXPECT_NE(problemWith(7, 0).find("spacing along axis 1 is 0, not positive"), std::string::npos);
  EXPECT_NE(problemWith(4, std::nan("")).find("fixed parameter 4 of the B-spline grid is not a finite number"),
            std::string::npos);
  EXPECT_NE(problemWith(0, 4, 7).find("the B-spline grid has 120 points, which need 360 parameters, there are 7"),
            std::string::npos);
  const std::vector<double> shortGrid(10, 1.0);
  EXPECT_NE(itk::FindProblemInBSplineFixedParameters(shortGrid.data(), shortGrid.size(), 3).find("needs 18"),
            std::string::npos);
}

TEST(TransformFileChecks, AcceptsWhatITKWrites)
{
  using BSplineType = itk::BSplineTransform<double, 3, 3>;
  auto                                bspline = BSplineType::New();
  BSplineType::MeshSizeType           meshSize;
  BSplineType::PhysicalDimensionsType dimensions;
  meshSize.Fill(3);
  dimensions.Fill(50.0);
  bspline->SetTransformDomainMeshSize(meshSize);
  bspline->SetTransformDomainPhysicalDimensions(dimensions);
  BSplineType::ParametersType parameters(bspline->GetNumberOfParameters());
  for (unsigned int i = 0; i < parameters.size(); ++i)
  {
    parameters[i] = 0.01 * i;
  }
  bspline->SetParameters(parameters);
  itk::RegisterFFDShapeMatchingTransforms();
  const std::string fileName = ::testing::TempDir() + "TransformFileChecksGood.tfm";
  auto              writer = itk::TransformFileWriterTemplate<double>::New();
  writer->SetInput(bspline);
  writer->SetFileName(fileName);
  writer->Update();
  EXPECT_EQ(itk::FindProblemInTextTransformFile(fileName), "");
  std::remove(fileName.c_str());
  EXPECT_EQ(itk::FindProblemInTextTransformFile(::testing::TempDir() + "no-such-file.tfm"), "");
}

TEST(TransformFileChecks, RefusesDamagedFiles)
{
  const std::string header = "#Insight Transform File V1.0\n#Transform 0\nTransform: BSplineTransform_double_3_3\n";
  const std::string fixed = "FixedParameters: 1 1 2 0 0 0 1 1 1 1 0 0 0 1 0 0 0 1\n";
  // Good: 2 points, 6 parameters, in either order, with spaces ITK trims.
  EXPECT_EQ(
    itk::FindProblemInTextTransformFile(WriteText("checks-good.tfm", header + "  Parameters: 0 1 2 3 4 5\n" + fixed)),
    "");
  EXPECT_EQ(
    itk::FindProblemInTextTransformFile(WriteText("checks-order.tfm", header + fixed + "Parameters: 0 1 2 3 4 5\n")),
    "");
  EXPECT_NE(itk::FindProblemInTextTransformFile(WriteText("checks-count.tfm", header + "Parameters: 0 1 2\n" + fixed))
              .find("transform BSplineTransform_double_3_3 (line 3): the B-spline grid has 2 points, which need 6 "
                    "parameters, there are 3"),
            std::string::npos);
  EXPECT_NE(itk::FindProblemInTextTransformFile(
              WriteText("checks-negative.tfm",
                        header + "Parameters: 0 1 2 3 4 5\nFixedParameters: -1 1 2 0 0 0 1 1 1 1 0 0 0 1 0 0 0 1\n"))
              .find("grid size along axis 0 is -1"),
            std::string::npos);
  EXPECT_NE(itk::FindProblemInTextTransformFile(WriteText("checks-nan.tfm", header + "Parameters: 0 nan 2\n" + fixed))
              .find("line 4: \"nan\" is not a finite number"),
            std::string::npos);
  // Other transforms' parameters are left to ITK.
  EXPECT_EQ(itk::FindProblemInTextTransformFile(WriteText(
              "checks-affine.tfm",
              "Transform: AffineTransform_double_3_3\nParameters: 1 0 0 0 1 0 0 0 1 0 0 0\nFixedParameters: -1 0 0\n")),
            "");
}
