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

#include "FFDProgramModules.h"

#include <stdexcept>

// Set by apps/CMakeLists.txt: the module's file name.
#ifndef FFD_TRANSFORM_FILES_MODULE_FILE
#  error "FFD_TRANSFORM_FILES_MODULE_FILE is not defined"
#endif

namespace ffd
{
TransformFileReaderEntryPoint
LoadTransformFileReader()
{
  // POSIX: a function's address is read from dlsym's object pointer.
  return reinterpret_cast<TransformFileReaderEntryPoint>(LoadProgramModuleEntry(
    FFD_TRANSFORM_FILES_MODULE_FILE, TransformFileReaderEntryPointName, "the transform files module"));
}

TransformListType
ReadTransformFile(const std::string & fileName)
{
  const TransformFileReaderEntryPoint read = LoadTransformFileReader();
  TransformListType                   transforms;
  std::string                         problem;
  if (!read(fileName.c_str(), &transforms, &problem))
  {
    throw std::runtime_error(problem);
  }
  return transforms;
}
} // namespace ffd
