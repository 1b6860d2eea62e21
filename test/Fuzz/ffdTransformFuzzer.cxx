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
// libFuzzer target: reading ITK transform files (the --transform-out / --templates path of ffd-match, with the
// module's ParametricTemplateTransform registered), then using what was read. Whatever the bytes, reading must end in
// transforms or an itk::ExceptionObject, and a transform that was read must map a point (and its B-spline Jacobian)
// without a crash or undefined behaviour.

#include "itkBSplineTransform.h"
#include "itkParametricTemplateTransform.h"
#include "itkRegisterFFDShapeMatchingTransforms.h"
#include "itkTransformFileChecks.h"
#include "itkTransformFileReader.h"
#include "itkTransformFactory.h"

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <exception>
#include <fstream>
#include <string>
#include <unistd.h>

extern "C" int
LLVMFuzzerInitialize(int *, char ***)
{
  itk::TransformFactory<itk::BSplineTransform<double, 3, 3>>::RegisterTransform();
  itk::RegisterFFDShapeMatchingTransforms();
  return 0;
}

extern "C" int
LLVMFuzzerTestOneInput(const uint8_t * data, size_t size)
{
  const std::string fileName = "/tmp/ffd-transform-fuzz-" + std::to_string(getpid()) + ".tfm";
  {
    std::ofstream file(fileName, std::ios::binary);
    file.write(reinterpret_cast<const char *>(data), static_cast<std::streamsize>(size));
  }
  try
  {
    // As the module's programs do: the file's B-spline grids are checked before ITK's reader builds them.
    if (!itk::FindProblemInTextTransformFile(fileName).empty())
    {
      std::remove(fileName.c_str());
      return 0;
    }
    auto reader = itk::TransformFileReaderTemplate<double>::New();
    reader->SetFileName(fileName);
    reader->Update();
    for (const auto & transform : *reader->GetTransformList())
    {
      itk::Point<double, 3> origin;
      origin.Fill(0.5);
      if (auto * parametric = dynamic_cast<itk::ParametricTemplateTransform<double, 3> *>(transform.GetPointer()))
      {
        parametric->TransformPoint(origin);
        itk::ParametricTemplateTransform<double, 3>::JacobianType jacobian;
        parametric->ComputeJacobianWithRespectToParameters(origin, jacobian);
      }
      using BSplineType = itk::BSplineTransform<double, 3, 3>;
      if (auto * bspline = dynamic_cast<BSplineType *>(transform.GetPointer()))
      {
        BSplineType::InputPointType point;
        point.Fill(0.5);
        bspline->TransformPoint(point);
        BSplineType::JacobianType jacobian;
        bspline->ComputeJacobianWithRespectToParameters(point, jacobian);
      }
    }
  }
  catch (const itk::ExceptionObject &)
  {
    // Refused with a message: the expected outcome for damaged input.
  }
  catch (const std::exception &)
  {
    // ITK 5.2's TxtTransformIO throws std::out_of_range on some malformed files (Findings/
    // ffdTransformFuzzer-std-out_of_range); the module's programs catch it and report the file as malformed.
  }
  std::remove(fileName.c_str());
  return 0;
}
