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
#include "itkFFDShapeMatchingEnums.h"
#include "gtest/gtest.h"

#include <sstream>

namespace
{
using MethodEnum = itk::FFDShapeMatchingEnums::Method;
}

TEST(FFDShapeMatchingEnums, PrintsQualifiedNames)
{
  const std::pair<MethodEnum, const char *> expected[] = {
    { MethodEnum::GO, "itk::FFDShapeMatchingEnums::Method::GO" },
    { MethodEnum::MRF, "itk::FFDShapeMatchingEnums::Method::MRF" },
    { MethodEnum::Par, "itk::FFDShapeMatchingEnums::Method::Par" },
    { MethodEnum::GOPar, "itk::FFDShapeMatchingEnums::Method::GOPar" },
    { MethodEnum::MRFPar, "itk::FFDShapeMatchingEnums::Method::MRFPar" },
    { MethodEnum::GOCPD, "itk::FFDShapeMatchingEnums::Method::GOCPD" },
  };
  for (const auto & entry : expected)
  {
    std::ostringstream stream;
    stream << entry.first;
    EXPECT_EQ(stream.str(), entry.second);
  }
  std::ostringstream invalid;
  invalid << static_cast<MethodEnum>(200);
  EXPECT_EQ(invalid.str(), "INVALID VALUE FOR itk::FFDShapeMatchingEnums::Method");
}

TEST(FFDShapeMatchingEnums, SpellingRoundTrips)
{
  for (const auto method :
       { MethodEnum::GO, MethodEnum::MRF, MethodEnum::Par, MethodEnum::GOPar, MethodEnum::MRFPar, MethodEnum::GOCPD })
  {
    MethodEnum        parsed = MethodEnum::GO;
    const std::string spelling = itk::FFDShapeMatchingEnums::MethodToString(method);
    ASSERT_TRUE(itk::FFDShapeMatchingEnums::MethodFromString(spelling, parsed)) << spelling;
    EXPECT_EQ(parsed, method);
  }
  MethodEnum parsed = MethodEnum::MRF;
  EXPECT_TRUE(itk::FFDShapeMatchingEnums::MethodFromString("GO+Par", parsed));
  EXPECT_EQ(parsed, MethodEnum::GOPar);
  EXPECT_TRUE(itk::FFDShapeMatchingEnums::MethodFromString("go+cpd", parsed));
  EXPECT_EQ(parsed, MethodEnum::GOCPD);
}

TEST(FFDShapeMatchingEnums, RejectsUnknownSpellings)
{
  MethodEnum parsed = MethodEnum::Par;
  for (const char * text : { "", "gd", "go+", "mrf+go", " go", "elastix" })
  {
    EXPECT_FALSE(itk::FFDShapeMatchingEnums::MethodFromString(text, parsed)) << '"' << text << '"';
    EXPECT_EQ(parsed, MethodEnum::Par);
  }
}

TEST(FFDShapeMatchingEnums, PrintsMetricAndOptimizerNames)
{
  std::ostringstream stream;
  stream << itk::FFDShapeMatchingEnums::ImageMetric::MeanSquares << ' '
         << itk::FFDShapeMatchingEnums::Optimizer::RegularStepGradientDescent << ' '
         << static_cast<itk::FFDShapeMatchingEnums::ImageMetric>(9);
  EXPECT_EQ(stream.str(),
            "itk::FFDShapeMatchingEnums::ImageMetric::MeanSquares "
            "itk::FFDShapeMatchingEnums::Optimizer::RegularStepGradientDescent "
            "INVALID VALUE FOR itk::FFDShapeMatchingEnums::ImageMetric");
}

TEST(FFDShapeMatchingEnums, InitialTransformSpellingRoundTrips)
{
  using InitialEnum = itk::FFDShapeMatchingEnums::InitialTransform;
  for (const auto pose : { InitialEnum::None, InitialEnum::Rigid, InitialEnum::Similarity, InitialEnum::Affine })
  {
    InitialEnum       parsed = InitialEnum::None;
    const std::string spelling = itk::FFDShapeMatchingEnums::InitialTransformToString(pose);
    ASSERT_TRUE(itk::FFDShapeMatchingEnums::InitialTransformFromString(spelling, parsed)) << spelling;
    EXPECT_EQ(parsed, pose);
  }
  InitialEnum parsed = InitialEnum::Rigid;
  EXPECT_TRUE(itk::FFDShapeMatchingEnums::InitialTransformFromString("Similarity", parsed));
  EXPECT_EQ(parsed, InitialEnum::Similarity);
  EXPECT_FALSE(itk::FFDShapeMatchingEnums::InitialTransformFromString("moments", parsed));
  EXPECT_EQ(parsed, InitialEnum::Similarity);
  std::ostringstream stream;
  stream << InitialEnum::Affine << ' ' << static_cast<InitialEnum>(9);
  EXPECT_EQ(stream.str(),
            "itk::FFDShapeMatchingEnums::InitialTransform::Affine "
            "INVALID VALUE FOR itk::FFDShapeMatchingEnums::InitialTransform");
}
