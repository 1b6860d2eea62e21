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
#include "itkParametricTemplateTransform.h"
#include "itkRegisterFFDShapeMatchingTransforms.h"
#include "itkMersenneTwisterRandomVariateGenerator.h"
#include "itkTestingMacros.h"
#include "itkTransformFileReader.h"
#include "itkTransformFileWriter.h"
#include "itkTransformIOFactory.h"
#include "itkTranslationTransform.h"
#include <cmath>
#include <string>

namespace
{
constexpr unsigned int Dimension = 3;
using TransformType = itk::ParametricTemplateTransform<double, Dimension>;
using BSplineType = TransformType::BSplineTransformType;
using PointType = TransformType::InputPointType;
using CoefficientVectorType = TransformType::CoefficientVectorType;
using RandomType = itk::Statistics::MersenneTwisterRandomVariateGenerator;

/** A 7 x 6 x 5 control grid over a rotated 40 x 30 x 20 mm box. */
BSplineType::Pointer
MakeGrid()
{
  auto                                grid = BSplineType::New();
  BSplineType::OriginType             origin;
  BSplineType::PhysicalDimensionsType extent;
  BSplineType::MeshSizeType           meshSize;
  for (unsigned int d = 0; d < Dimension; ++d)
  {
    origin[d] = -5.0 + 3.0 * d;
    extent[d] = 40.0 - 10.0 * d;
    meshSize[d] = 4 - d;
  }
  BSplineType::DirectionType direction;
  direction.SetIdentity();
  const double angle = 0.3;
  direction(0, 0) = std::cos(angle);
  direction(0, 1) = -std::sin(angle);
  direction(1, 0) = std::sin(angle);
  direction(1, 1) = std::cos(angle);
  grid->SetTransformDomainOrigin(origin);
  grid->SetTransformDomainPhysicalDimensions(extent);
  grid->SetTransformDomainDirection(direction);
  grid->SetTransformDomainMeshSize(meshSize);
  return grid;
}

CoefficientVectorType
RandomCoefficients(std::size_t length, double sigma, RandomType * random)
{
  CoefficientVectorType values(length);
  for (auto & value : values)
  {
    value = sigma * random->GetNormalVariate();
  }
  return values;
}

/** Random points around the grid's domain (some outside it). */
std::vector<PointType>
RandomPoints(unsigned int count, RandomType * random)
{
  std::vector<PointType> points(count);
  for (auto & point : points)
  {
    point[0] = random->GetUniformVariate(-25.0, 45.0);
    point[1] = random->GetUniformVariate(-5.0, 45.0);
    point[2] = random->GetUniformVariate(-2.0, 30.0);
  }
  return points;
}

bool
Near(double a, double b, double tolerance)
{
  return std::abs(a - b) <= tolerance * std::max(1.0, std::max(std::abs(a), std::abs(b)));
}

/** One unit template per coefficient, in BSplineTransform's parameter order: equals BSplineTransform bit for bit. */
int
CheckReproducesBSpline(RandomType * random)
{
  int  status = EXIT_SUCCESS;
  auto grid = MakeGrid();
  auto transform = TransformType::New();
  transform->SetGridFromBSplineTransform(grid);
  const auto                                          numberOfCoefficients = transform->GetNumberOfCoefficients();
  std::vector<TransformType::SparseCoefficientVector> unit(numberOfCoefficients);
  for (itk::SizeValueType i = 0; i < numberOfCoefficients; ++i)
  {
    unit[i].Indices.push_back(i);
    unit[i].Values.push_back(1.0);
  }
  transform->SetSparseTemplates(unit);
  ITK_TEST_EXPECT_EQUAL(transform->GetNumberOfParameters(), grid->GetNumberOfParameters());

  const auto                  values = RandomCoefficients(numberOfCoefficients, 2.0, random);
  BSplineType::ParametersType parameters(numberOfCoefficients);
  std::copy(values.begin(), values.end(), parameters.begin());
  grid->SetParametersByValue(parameters);
  transform->SetParameters(parameters);

  TransformType::JacobianType ours;
  TransformType::JacobianType theirs;
  unsigned int                inside = 0;
  for (const auto & point : RandomPoints(300, random))
  {
    const auto expected = grid->TransformPoint(point);
    const auto actual = transform->TransformPoint(point);
    inside += (expected != point);
    if (expected != actual)
    {
      std::cerr << "TransformPoint differs from BSplineTransform at " << point << ": " << actual << " vs " << expected
                << std::endl;
      status = EXIT_FAILURE;
    }
    transform->ComputeJacobianWithRespectToParameters(point, ours);
    grid->ComputeJacobianWithRespectToParameters(point, theirs);
    if (ours != theirs)
    {
      std::cerr << "Parameter Jacobian differs from BSplineTransform's at " << point << std::endl;
      status = EXIT_FAILURE;
    }
  }
  std::cout << "Reproduction of BSplineTransform: " << inside << " of 300 points inside the grid" << std::endl;
  ITK_TEST_EXPECT_TRUE(inside > 50);
  // The equivalent B-spline transform holds the same coefficients.
  ITK_TEST_EXPECT_TRUE(transform->MakeBSplineTransform()->GetParameters() == grid->GetParameters());
  return status;
}

/** Parameter Jacobian, its transpose product and the spatial Jacobian against central differences. */
int
CheckJacobians(TransformType * transform, RandomType * random)
{
  int                           status = EXIT_SUCCESS;
  const auto                    numberOfParameters = transform->GetNumberOfParameters();
  TransformType::JacobianType   jacobian;
  TransformType::ParametersType parameters = transform->GetParameters();
  for (const auto & point : RandomPoints(40, random))
  {
    transform->ComputeJacobianWithRespectToParameters(point, jacobian);
    ITK_TEST_EXPECT_EQUAL(jacobian.cols(), numberOfParameters);
    for (unsigned int k = 0; k < numberOfParameters; ++k)
    {
      const double step = 1e-3;
      auto         shifted = parameters;
      shifted[k] += step;
      transform->SetParameters(shifted);
      const auto plus = transform->TransformPoint(point);
      shifted[k] = parameters[k] - step;
      transform->SetParameters(shifted);
      const auto minus = transform->TransformPoint(point);
      for (unsigned int d = 0; d < Dimension; ++d)
      {
        const double numeric = (plus[d] - minus[d]) / (2.0 * step);
        if (!Near(numeric, jacobian(d, k), 1e-7))
        {
          std::cerr << "dT/dpi mismatch at " << point << " (" << d << ", " << k << "): " << jacobian(d, k) << " vs "
                    << numeric << std::endl;
          status = EXIT_FAILURE;
        }
      }
    }
    transform->SetParameters(parameters);

    TransformType::OutputVectorType vector;
    for (unsigned int d = 0; d < Dimension; ++d)
    {
      vector[d] = random->GetNormalVariate();
    }
    TransformType::DerivativeType accumulated(numberOfParameters);
    accumulated.Fill(0.5);
    transform->AccumulateJacobianTransposeProduct(point, vector, -2.0, accumulated);
    for (unsigned int k = 0; k < numberOfParameters; ++k)
    {
      double expected = 0.5;
      for (unsigned int d = 0; d < Dimension; ++d)
      {
        expected -= 2.0 * jacobian(d, k) * vector[d];
      }
      if (!Near(expected, accumulated[k], 1e-12))
      {
        std::cerr << "J^T v mismatch at parameter " << k << ": " << accumulated[k] << " vs " << expected << std::endl;
        status = EXIT_FAILURE;
      }
    }

    TransformType::JacobianPositionType spatial;
    transform->ComputeJacobianWithRespectToPosition(point, spatial);
    for (unsigned int j = 0; j < Dimension; ++j)
    {
      const double step = 1e-5;
      PointType    forward = point;
      PointType    backward = point;
      forward[j] += step;
      backward[j] -= step;
      const auto plus = transform->TransformPoint(forward);
      const auto minus = transform->TransformPoint(backward);
      if (transform->TransformPoint(point) == point && (plus != forward || minus != backward))
      {
        continue; // at the border of the valid region
      }
      for (unsigned int i = 0; i < Dimension; ++i)
      {
        const double numeric = (plus[i] - minus[i]) / (2.0 * step);
        if (!Near(numeric, spatial(i, j), 1e-5))
        {
          std::cerr << "dT/dx mismatch at " << point << " (" << i << ", " << j << "): " << spatial(i, j) << " vs "
                    << numeric << std::endl;
          status = EXIT_FAILURE;
        }
      }
    }
  }
  return status;
}

/** Writes and reads the transform; everything must come back exactly. */
int
CheckFileRoundTrip(const TransformType * transform, const std::string & fileName, RandomType * random)
{
  auto writer = itk::TransformFileWriterTemplate<double>::New();
  writer->SetInput(transform);
  writer->SetFileName(fileName);
  ITK_TRY_EXPECT_NO_EXCEPTION(writer->Update());
  auto reader = itk::TransformFileReaderTemplate<double>::New();
  reader->SetFileName(fileName);
  ITK_TRY_EXPECT_NO_EXCEPTION(reader->Update());
  ITK_TEST_EXPECT_EQUAL(reader->GetTransformList()->size(), 1u);
  const auto * read = dynamic_cast<const TransformType *>(reader->GetTransformList()->front().GetPointer());
  ITK_TEST_EXPECT_TRUE(read != nullptr);
  if (read == nullptr)
  {
    return EXIT_FAILURE;
  }
  int status = EXIT_SUCCESS;
  if (read->GetFixedParameters() != transform->GetFixedParameters() ||
      read->GetParameters() != transform->GetParameters())
  {
    std::cerr << fileName << ": parameters differ after the round trip" << std::endl;
    status = EXIT_FAILURE;
  }
  for (const auto & point : RandomPoints(100, random))
  {
    if (read->TransformPoint(point) != transform->TransformPoint(point))
    {
      std::cerr << fileName << ": TransformPoint differs after the round trip at " << point << std::endl;
      status = EXIT_FAILURE;
    }
  }
  std::cout << fileName << ": round trip exact: " << (status == EXIT_SUCCESS ? "yes" : "no") << std::endl;
  return status;
}
} // namespace

int
itkParametricTemplateTransformTest(int argc, char * argv[])
{
  if (argc != 2)
  {
    std::cerr << "Usage: " << itkNameOfTestExecutableMacro(argv) << " outputDirectory" << std::endl;
    return EXIT_FAILURE;
  }
  const std::string outputDirectory = argv[1];
  itk::RegisterFFDShapeMatchingTransforms();
  itk::RegisterFFDShapeMatchingTransforms(); // a second call changes nothing
  auto random = RandomType::New();
  random->SetSeed(20261122);

  auto transform = TransformType::New();
  ITK_EXERCISE_BASIC_OBJECT_METHODS(transform, ParametricTemplateTransform, Transform);
  ITK_TEST_EXPECT_EQUAL(transform->GetNumberOfParameters(), 0u);
  ITK_TEST_EXPECT_EQUAL(std::string(transform->GetTransformTypeAsString()),
                        std::string("ParametricTemplateTransform_double_3_3"));

  int status = CheckReproducesBSpline(random);

  // Three dense random templates and a base on the rotated grid.
  auto grid = MakeGrid();
  transform->SetGridFromBSplineTransform(grid);
  const auto                         length = transform->GetNumberOfCoefficients();
  std::vector<CoefficientVectorType> templates;
  for (unsigned int k = 0; k < 3; ++k)
  {
    templates.push_back(RandomCoefficients(length, 1.0, random));
  }
  transform->SetTemplates(templates);
  transform->SetBaseCoefficients(RandomCoefficients(length, 0.5, random));
  ITK_TEST_EXPECT_EQUAL(transform->GetNumberOfParameters(), 3u);
  TransformType::ParametersType weights(3);
  weights[0] = 0.7;
  weights[1] = -1.2;
  weights[2] = 0.4;
  transform->SetParameters(weights);
  // Coefficients = base + sum_k pi_k delta_k.
  const auto base = transform->GetBaseCoefficients();
  for (itk::SizeValueType i = 0; i < length; i += 7)
  {
    const double expected = base[i] + 0.7 * templates[0][i] - 1.2 * templates[1][i] + 0.4 * templates[2][i];
    ITK_TEST_EXPECT_TRUE(Near(transform->GetCoefficients()[i], expected, 1e-14));
  }
  if (CheckJacobians(transform, random) != EXIT_SUCCESS)
  {
    status = EXIT_FAILURE;
  }
  std::cout << "Jacobians checked against central differences (3 dense templates)" << std::endl;

  // Exact text and HDF5 round trips, dense templates and base; then sparse per-control-point templates.
  for (const std::string extension : { ".tfm", ".h5" })
  {
    const std::string fileName = outputDirectory + "/itkParametricTemplateTransformTestDense" + extension;
    if (extension == ".h5" && itk::TransformIOFactoryTemplate<double>::CreateTransformIO(
                                fileName.c_str(), itk::IOFileModeEnum::WriteMode) == nullptr)
    {
      std::cout << "No HDF5 transform IO linked: .h5 round trip skipped" << std::endl;
      continue;
    }
    if (CheckFileRoundTrip(transform, fileName, random) != EXIT_SUCCESS)
    {
      status = EXIT_FAILURE;
    }
  }

  // Per-control-point split: one template per control point that moves, keeping its vector.
  auto       noise = MakeGrid();
  auto       noiseValues = RandomCoefficients(length, 1.5, random);
  const auto numberOfNodes = length / Dimension;
  for (itk::SizeValueType node = 0; node < numberOfNodes; node += 3)
  {
    for (unsigned int d = 0; d < Dimension; ++d)
    {
      noiseValues[d * numberOfNodes + node] = 0.0; // some still control points
    }
  }
  noiseValues[1 * numberOfNodes + 1] = 0.0; // and one with a zero component
  BSplineType::ParametersType noiseParameters(length);
  std::copy(noiseValues.begin(), noiseValues.end(), noiseParameters.begin());
  noise->SetParametersByValue(noiseParameters);
  const itk::SizeValueType         movingNodes = numberOfNodes - (numberOfNodes + 2) / 3;
  auto                             split = TransformType::New();
  std::vector<const BSplineType *> sources{ noise.GetPointer() };
  split->SetTemplatesFromBSplineTransforms(sources, itk::ParametricTemplateTransformEnums::TemplateSplit::ControlPoint);
  ITK_TEST_EXPECT_EQUAL(split->GetNumberOfTemplates(), movingNodes);
  TransformType::ParametersType ones(split->GetNumberOfParameters());
  ones.Fill(1.0);
  split->SetParameters(ones);
  ITK_TEST_EXPECT_TRUE(split->GetCoefficients() == noise->GetParameters());
  for (const auto & point : RandomPoints(50, random))
  {
    ITK_TEST_EXPECT_TRUE((split->TransformPoint(point) - noise->TransformPoint(point)).GetNorm() < 1e-12);
  }
  if (CheckJacobians(split, random) != EXIT_SUCCESS)
  {
    status = EXIT_FAILURE;
  }
  if (CheckFileRoundTrip(split, outputDirectory + "/itkParametricTemplateTransformTestSplit.tfm", random) !=
      EXIT_SUCCESS)
  {
    status = EXIT_FAILURE;
  }
  auto axis = TransformType::New();
  axis->SetTemplatesFromBSplineTransforms(sources, itk::ParametricTemplateTransformEnums::TemplateSplit::Axis);
  ITK_TEST_EXPECT_EQUAL(axis->GetNumberOfTemplates(), Dimension * movingNodes - 1);
  TransformType::ParametersType axisOnes(axis->GetNumberOfParameters());
  axisOnes.Fill(1.0);
  axis->SetParameters(axisOnes);
  ITK_TEST_EXPECT_TRUE(axis->GetCoefficients() == noise->GetParameters());
  auto whole = TransformType::New();
  whole->SetTemplatesFromBSplineTransforms(sources);
  ITK_TEST_EXPECT_EQUAL(whole->GetNumberOfTemplates(), 1u);

  // Split names for the command line.
  auto parsed = itk::ParametricTemplateTransformEnums::TemplateSplit::None;
  ITK_TEST_EXPECT_TRUE(itk::ParametricTemplateTransformEnums::TemplateSplitFromString("Control-Point", parsed));
  ITK_TEST_EXPECT_EQUAL(parsed, itk::ParametricTemplateTransformEnums::TemplateSplit::ControlPoint);
  ITK_TEST_EXPECT_TRUE(!itk::ParametricTemplateTransformEnums::TemplateSplitFromString("voxel", parsed));
  std::cout << itk::ParametricTemplateTransformEnums::TemplateSplit::Axis << std::endl;

  // Principal components: examples = mean + a e1 + b e2 span two components; the templates reproduce them.
  std::vector<CoefficientVectorType> examples;
  const auto                         mean = RandomCoefficients(length, 1.0, random);
  const auto                         e1 = RandomCoefficients(length, 1.0, random);
  const auto                         e2 = RandomCoefficients(length, 0.3, random);
  for (unsigned int n = 0; n < 6; ++n)
  {
    const double          a = random->GetNormalVariate();
    const double          b = random->GetNormalVariate();
    CoefficientVectorType example(length);
    for (itk::SizeValueType i = 0; i < length; ++i)
    {
      example[i] = mean[i] + a * e1[i] + b * e2[i];
    }
    examples.push_back(example);
  }
  CoefficientVectorType              pcaMean;
  std::vector<CoefficientVectorType> components;
  std::vector<double>                deviations;
  TransformType::ComputePrincipalComponents(examples, 5, pcaMean, components, deviations);
  ITK_TEST_EXPECT_EQUAL(components.size(), 2u); // rank 2 after centring
  auto pca = TransformType::New();
  pca->SetGridFromBSplineTransform(grid);
  pca->SetTemplatesFromPrincipalComponents(examples, 5);
  pca->SetBaseCoefficients(pcaMean);
  ITK_TEST_EXPECT_EQUAL(pca->GetNumberOfTemplates(), 2u);
  // Least-squares weights of example 0 reproduce it (templates are orthogonal).
  TransformType::ParametersType pcaWeights(2);
  for (unsigned int k = 0; k < 2; ++k)
  {
    const auto component = pca->GetTemplate(k);
    double     dot = 0.0;
    double     norm = 0.0;
    for (itk::SizeValueType i = 0; i < length; ++i)
    {
      dot += component[i] * (examples[0][i] - pcaMean[i]);
      norm += component[i] * component[i];
    }
    pcaWeights[k] = dot / norm;
  }
  pca->SetParameters(pcaWeights);
  double largestResidual = 0.0;
  for (itk::SizeValueType i = 0; i < length; ++i)
  {
    largestResidual = std::max(largestResidual, std::abs(pca->GetCoefficients()[i] - examples[0][i]));
  }
  std::cout << "PCA: deviations " << deviations[0] << ", " << deviations[1] << "; residual " << largestResidual
            << std::endl;
  ITK_TEST_EXPECT_TRUE(largestResidual < 1e-9);

  // Base from other transforms: a B-spline on the grid exactly, a translation through the decomposition.
  auto based = TransformType::New();
  based->SetTemplatesFromBSplineTransforms(sources);
  based->SetBaseFromTransform(noise);
  ITK_TEST_EXPECT_TRUE(based->GetCoefficients() == noise->GetParameters());
  auto                            translation = itk::TranslationTransform<double, Dimension>::New();
  TransformType::OutputVectorType offset;
  offset[0] = 1.5;
  offset[1] = -2.0;
  offset[2] = 0.25;
  translation->Translate(offset);
  based->SetBaseFromTransform(translation);
  double largestError = 0.0;
  for (double u = 0.0; u <= 1.0; u += 0.125)
  {
    PointType point; // inside the rotated box
    point[0] = -5.0 + 30.0 * u * std::cos(0.3) - 20.0 * (1.0 - u) * std::sin(0.3);
    point[1] = -2.0 + 30.0 * u * std::sin(0.3) + 20.0 * (1.0 - u) * std::cos(0.3);
    point[2] = 1.0 + 18.0 * u;
    largestError = std::max(largestError, (based->TransformPoint(point) - (point + offset)).GetNorm());
  }
  std::cout << "Base from a translation: largest error " << largestError << " mm" << std::endl;
  ITK_TEST_EXPECT_TRUE(largestError < 1e-9);
  based->SetBaseFromTransform(nullptr);
  ITK_TEST_EXPECT_TRUE(based->GetBaseCoefficients() == CoefficientVectorType(length, 0.0));

  // Bad input.
  TransformType::ParametersType wrongSize(2);
  ITK_TRY_EXPECT_EXCEPTION(split->SetParameters(wrongSize));
  ITK_TRY_EXPECT_EXCEPTION(transform->SetBaseCoefficients(CoefficientVectorType(length + 1, 0.0)));
  ITK_TRY_EXPECT_EXCEPTION(transform->SetTemplates({ CoefficientVectorType(length - 1, 1.0) }));
  ITK_TRY_EXPECT_EXCEPTION(transform->SetTemplates({ CoefficientVectorType(length, 0.0) }));
  ITK_TRY_EXPECT_EXCEPTION(transform->SetTemplates({}));
  std::vector<const BSplineType *> noSources;
  ITK_TRY_EXPECT_EXCEPTION(transform->SetTemplatesFromBSplineTransforms(noSources));
  auto                             otherGrid = BSplineType::New(); // default grid: not the templates' one
  std::vector<const BSplineType *> mixed{ noise.GetPointer(), otherGrid.GetPointer() };
  ITK_TRY_EXPECT_EXCEPTION(split->SetTemplatesFromBSplineTransforms(mixed));
  ITK_TRY_EXPECT_EXCEPTION(
    TransformType::ComputePrincipalComponents({ examples[0] }, 2, pcaMean, components, deviations));
  ITK_TRY_EXPECT_EXCEPTION(pca->SetTemplatesFromPrincipalComponents({ examples[0], CoefficientVectorType(3, 1.0) }, 2));
  auto                               fixed = split->GetFixedParameters();
  TransformType::FixedParametersType truncated(fixed.GetSize() - 1);
  std::copy(fixed.begin(), fixed.end() - 1, truncated.begin());
  ITK_TRY_EXPECT_EXCEPTION(split->SetFixedParameters(truncated));
  auto badIndex = fixed;
  badIndex[TransformType::NumberOfGridFixedParameters + 3] = 1e9; // first template's first index
  ITK_TRY_EXPECT_EXCEPTION(split->SetFixedParameters(badIndex));
  // Counts larger than the values left (found by fuzzing: 1e40 does not fit a size type).
  for (const double count : { 1e40, 1e9 })
  {
    auto badCount = fixed;
    badCount[TransformType::NumberOfGridFixedParameters] = count; // number of templates
    ITK_TRY_EXPECT_EXCEPTION(split->SetFixedParameters(badCount));
    badCount = fixed;
    badCount[TransformType::NumberOfGridFixedParameters + 1] = count; // entries of the base
    ITK_TRY_EXPECT_EXCEPTION(split->SetFixedParameters(badCount));
  }
  ITK_TEST_EXPECT_TRUE(split->GetFixedParameters() == fixed); // unchanged by the failures
  TransformType::FixedParametersType tooFew(5);
  ITK_TRY_EXPECT_EXCEPTION(split->SetFixedParameters(tooFew));

  // Clone() carries everything.
  auto clone = split->Clone();
  ITK_TEST_EXPECT_TRUE(clone->GetFixedParameters() == split->GetFixedParameters());
  ITK_TEST_EXPECT_TRUE(clone->GetCoefficients() == split->GetCoefficients());
  return status;
}
