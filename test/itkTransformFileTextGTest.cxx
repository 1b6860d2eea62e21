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
// The text transform files the module writes without ITK's transform IO (itkTransformFileText.h), against the
// files ITK's TransformFileWriter writes and what ITK's TransformFileReader reads back.

#include "itkTransformFileText.h"
#include "itkAffineTransform.h"
#include "itkBSplineTransform.h"
#include "itkCompositeTransform.h"
#include "itkEuler2DTransform.h"
#include "itkMersenneTwisterRandomVariateGenerator.h"
#include "itkParametricTemplateTransform.h"
#include "itkRegisterFFDShapeMatchingTransforms.h"
#include "itkSimilarity3DTransform.h"
#include "itkTransformFileReader.h"
#include "itkTransformFileWriter.h"
#include "itkTransformIOFactory.h"
#include "gtest/gtest.h"

#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>

namespace
{
using TransformBaseType = itk::TransformBaseTemplate<double>;
using BSplineType = itk::BSplineTransform<double, 3, 3>;

// What ITK's writer writes for \c transform.
std::string
WrittenByITK(const TransformBaseType * transform, const std::string & name)
{
  itk::RegisterFFDShapeMatchingTransforms();
  const std::string fileName = ::testing::TempDir() + name;
  auto              writer = itk::TransformFileWriterTemplate<double>::New();
  writer->SetInput(transform);
  writer->SetFileName(fileName);
  writer->Update();
  std::ifstream     file(fileName, std::ios::binary);
  std::stringstream content;
  content << file.rdbuf();
  return content.str();
}

// The transforms ITK's reader reads from \c text.
itk::TransformFileReaderTemplate<double>::TransformListType
ReadByITK(const std::string & text, const std::string & name)
{
  itk::RegisterFFDShapeMatchingTransforms();
  const std::string fileName = ::testing::TempDir() + name;
  std::ofstream(fileName, std::ios::binary) << text;
  auto reader = itk::TransformFileReaderTemplate<double>::New();
  reader->SetFileName(fileName);
  reader->Update();
  return *reader->GetTransformList();
}

// A 6 x 5 x 7 grid over a rotated box, with random coefficients and a few values whose decimal forms are hard
// (subnormal, huge, negative zero, 0.1, 1/3).
BSplineType::Pointer
RandomBSpline(unsigned int seed)
{
  auto                                grid = BSplineType::New();
  BSplineType::OriginType             origin;
  BSplineType::PhysicalDimensionsType extent;
  BSplineType::MeshSizeType           meshSize;
  for (unsigned int d = 0; d < 3; ++d)
  {
    origin[d] = -12.25 + 3.1 * d;
    extent[d] = 40.0 / 3.0 + 7.0 * d;
    meshSize[d] = 3 + (d + 2) % 3;
  }
  BSplineType::DirectionType direction;
  direction.SetIdentity();
  direction(0, 0) = std::cos(0.3);
  direction(0, 1) = -std::sin(0.3);
  direction(1, 0) = std::sin(0.3);
  direction(1, 1) = std::cos(0.3);
  grid->SetTransformDomainOrigin(origin);
  grid->SetTransformDomainPhysicalDimensions(extent);
  grid->SetTransformDomainDirection(direction);
  grid->SetTransformDomainMeshSize(meshSize);
  auto random = itk::Statistics::MersenneTwisterRandomVariateGenerator::New();
  random->SetSeed(seed);
  BSplineType::ParametersType parameters(grid->GetNumberOfParameters());
  for (unsigned int i = 0; i < parameters.Size(); ++i)
  {
    parameters[i] = 3.0 * random->GetNormalVariate();
  }
  parameters[0] = 0.1;
  parameters[1] = -0.0;
  parameters[2] = 1.0 / 3.0;
  parameters[3] = std::numeric_limits<double>::denorm_min();
  parameters[4] = -1.0e300;
  parameters[5] = 0.0;
  grid->SetParametersByValue(parameters);
  return grid;
}
} // namespace

TEST(TransformFileText, BSplineAsITKWritesIt)
{
  for (unsigned int seed = 1; seed <= 3; ++seed)
  {
    const BSplineType::Pointer transform = RandomBSpline(seed);
    const std::string          text = itk::MakeTextTransformFileContent(*transform);
    EXPECT_EQ(text, WrittenByITK(transform, "bspline.tfm"));
    const auto read = ReadByITK(text, "bspline-ours.tfm");
    ASSERT_EQ(read.size(), 1u);
    EXPECT_EQ(read.front()->GetTransformTypeAsString(), "BSplineTransform_double_3_3");
    EXPECT_EQ(read.front()->GetParameters(), transform->GetParameters());
    EXPECT_EQ(read.front()->GetFixedParameters(), transform->GetFixedParameters());
  }
}

TEST(TransformFileText, CompositeAsITKWritesIt)
{
  // ffd-match's transform with a pose stage: the pose, then the deformation.
  auto pose = itk::Similarity3DTransform<double>::New();
  auto parameters = pose->GetParameters();
  for (unsigned int i = 0; i < parameters.Size(); ++i)
  {
    parameters[i] = 0.05 * (i + 1);
  }
  parameters[6] = 1.1;
  pose->SetParameters(parameters);
  auto center = pose->GetFixedParameters();
  center[0] = 12.5;
  pose->SetFixedParameters(center);
  auto affine = itk::AffineTransform<double, 3>::New();
  affine->Rotate3D(itk::Vector<double, 3>(1.0), 0.2);
  auto composite = itk::CompositeTransform<double, 3>::New();
  composite->AddTransform(pose);
  composite->AddTransform(RandomBSpline(4));
  composite->AddTransform(affine);
  const std::string text = itk::MakeTextTransformFileContent(*composite);
  EXPECT_EQ(text, WrittenByITK(composite, "composite.tfm"));
  const auto read = ReadByITK(text, "composite-ours.tfm");
  ASSERT_EQ(read.size(), 1u);
  const auto * readComposite = dynamic_cast<const itk::CompositeTransform<double, 3> *>(read.front().GetPointer());
  ASSERT_NE(readComposite, nullptr);
  ASSERT_EQ(readComposite->GetNumberOfTransforms(), 3u);
  EXPECT_EQ(readComposite->GetParameters(), composite->GetParameters());
  EXPECT_EQ(readComposite->GetFixedParameters(), composite->GetFixedParameters());

  // Two dimensions.
  auto planar = itk::CompositeTransform<double, 2>::New();
  auto euler = itk::Euler2DTransform<double>::New();
  euler->SetAngle(0.7);
  planar->AddTransform(euler);
  EXPECT_EQ(itk::MakeTextTransformFileContent(*planar), WrittenByITK(planar, "planar.txt"));
}

TEST(TransformFileText, ParametricTemplateAsITKWritesIt)
{
  using ParametricType = itk::ParametricTemplateTransform<double, 3>;
  auto transform = ParametricType::New();
  transform->SetGridFromBSplineTransform(RandomBSpline(5));
  std::vector<ParametricType::SparseCoefficientVector> templates(3);
  for (unsigned int k = 0; k < templates.size(); ++k)
  {
    templates[k].Indices = { k, 10 + k, 40 + 2 * k };
    templates[k].Values = { 1.0, -0.5 / (k + 1), 0.25 };
  }
  transform->SetSparseTemplates(templates);
  ParametricType::ParametersType weights(transform->GetNumberOfParameters());
  for (unsigned int i = 0; i < weights.Size(); ++i)
  {
    weights[i] = 0.3 * i - 0.1;
  }
  transform->SetParameters(weights);
  const std::string text = itk::MakeTextTransformFileContent(*transform);
  EXPECT_EQ(text, WrittenByITK(transform, "templates.tfm"));
  const auto read = ReadByITK(text, "templates-ours.tfm");
  ASSERT_EQ(read.size(), 1u);
  EXPECT_EQ(read.front()->GetParameters(), transform->GetParameters());
  EXPECT_EQ(read.front()->GetFixedParameters(), transform->GetFixedParameters());
}

TEST(TransformFileText, RefusesWhatITKRefuses)
{
  auto inner = itk::CompositeTransform<double, 3>::New();
  inner->AddTransform(RandomBSpline(6));
  auto outer = itk::CompositeTransform<double, 3>::New();
  outer->AddTransform(inner);
  EXPECT_THROW(itk::MakeTextTransformFileContent(*outer), itk::ExceptionObject);
  EXPECT_THROW(WrittenByITK(outer, "nested.tfm"), itk::ExceptionObject);
}

TEST(TransformFileText, NamesTheFilesITKsTextIOWrites)
{
  itk::RegisterFFDShapeMatchingTransforms();
  for (const char * name :
       { "a.tfm", "dir.d/a.txt", "/x/y.b.tfm", "a.TFM", "a.tfm.h5", "a", "tfm", "a.mat", "dir.tfm/a" })
  {
    auto       io = itk::TransformIOFactoryTemplate<double>::CreateTransformIO(name, itk::IOFileModeEnum::WriteMode);
    const bool itkTextIO = io.IsNotNull() && std::string(io->GetNameOfClass()) == "TxtTransformIOTemplate";
    EXPECT_EQ(itk::IsTextTransformFileName(name), itkTextIO) << name;
  }
}
