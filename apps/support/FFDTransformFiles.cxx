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
#include "FFDTransformFiles.h"

#include "itkRegisterFFDShapeMatchingTransforms.h"
#include "itkTransformFileChecks.h"
#include "itkTransformFileReader.h"
#include "itkTransformFileWriter.h"
#include "itkTransformIOFactory.h"

#include <stdexcept>

namespace ffd
{
TransformListType
ReadTransformFile(const std::string & fileName)
{
  itk::RegisterFFDShapeMatchingTransforms();
  const std::string problem = itk::FindProblemInTextTransformFile(fileName);
  if (!problem.empty())
  {
    throw std::runtime_error(problem);
  }
  auto reader = itk::TransformFileReaderTemplate<double>::New();
  reader->SetFileName(fileName);
  try
  {
    reader->Update();
  }
  catch (const itk::ExceptionObject & error)
  {
    throw std::runtime_error(error.GetDescription());
  }
  catch (const std::exception & error)
  {
    // ITK 5.2's text transform reader throws standard exceptions on some malformed files (found by fuzzing).
    throw std::runtime_error(std::string("malformed transform file (") + error.what() + ")");
  }
  return TransformListType(reader->GetTransformList()->begin(), reader->GetTransformList()->end());
}

void
WriteTransformFile(const itk::TransformBaseTemplate<double> * transform, const std::string & fileName)
{
  auto writer = itk::TransformFileWriterTemplate<double>::New();
  writer->SetInput(transform);
  writer->SetFileName(fileName);
  try
  {
    writer->Update();
  }
  catch (const itk::ExceptionObject & error)
  {
    throw std::runtime_error(error.GetDescription());
  }
  // Read back as written (any format ITK's transform IO writes): a cut file does not parse.
  auto reader = itk::TransformFileReaderTemplate<double>::New();
  reader->SetFileName(fileName);
  try
  {
    reader->Update();
  }
  catch (const std::exception & error) // itk::ExceptionObject and the reader's standard exceptions
  {
    throw std::runtime_error("the written file does not read back whole");
  }
  const auto * written = reader->GetTransformList();
  if (written->size() != 1 || written->front()->GetNumberOfParameters() != transform->GetNumberOfParameters())
  {
    throw std::runtime_error("the written file does not read back whole");
  }
}

bool
IsWritableTransformFileName(const std::string & fileName)
{
  return itk::TransformIOFactoryTemplate<double>::CreateTransformIO(fileName.c_str(), itk::IOFileModeEnum::WriteMode)
    .IsNotNull();
}
} // namespace ffd
