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
namespace
{
// The transforms of \c fileName as ITK's transform file reader reads it (any format its transform IO reads); its
// failures as std::runtime_error.
TransformListType
ReadWithTransformFileReader(const std::string & fileName)
{
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
} // namespace

TransformListType
ReadTransformFile(const std::string & fileName)
{
  itk::RegisterFFDShapeMatchingTransforms();
  const std::string problem = itk::FindProblemInTextTransformFile(fileName);
  if (!problem.empty())
  {
    throw std::runtime_error(problem);
  }
  return ReadWithTransformFileReader(fileName);
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
  // Read back as written: a cut file does not parse.
  TransformListType written;
  try
  {
    written = ReadWithTransformFileReader(fileName);
  }
  catch (const std::runtime_error &)
  {
    throw std::runtime_error("the written file does not read back whole");
  }
  if (written.size() != 1 || written.front()->GetNumberOfParameters() != transform->GetNumberOfParameters())
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
