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

// The transform files module (ffd-transform-files) that ffd-match loads the first time it reads a transform file
// (FFDTransformFiles.h): ITK's transform file reader, with the module's transforms registered and the file checked
// first.

#include "FFDTransformFiles.h"
#include "itkRegisterFFDShapeMatchingTransforms.h"
#include "itkTransformFileChecks.h"
#include "itkTransformFileReader.h"

// The entry point (ffd::TransformFileReaderEntryPoint).
extern "C" __attribute__((visibility("default"))) bool
FFDShapeMatchingReadTransformFile(const char * fileName, ffd::TransformListType * transforms, std::string * problem)
{
  try
  {
    itk::RegisterFFDShapeMatchingTransforms();
    // ITK's reader builds B-spline grids from unchecked values (a negative size is undefined behaviour).
    *problem = itk::FindProblemInTextTransformFile(fileName);
    if (!problem->empty())
    {
      return false;
    }
    auto reader = itk::TransformFileReaderTemplate<double>::New();
    reader->SetFileName(fileName);
    reader->Update();
    transforms->assign(reader->GetTransformList()->begin(), reader->GetTransformList()->end());
    return true;
  }
  catch (const itk::ExceptionObject & error)
  {
    *problem = error.GetDescription();
  }
  catch (const std::exception & error)
  {
    // ITK 5.2's text transform reader throws standard exceptions on some malformed files (found by fuzzing).
    *problem = std::string("malformed transform file (") + error.what() + ")";
  }
  return false;
}
