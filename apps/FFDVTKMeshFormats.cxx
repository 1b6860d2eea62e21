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
#include "FFDVTKMeshFormats.h"

#include "FFDProgramMessages.h"
#include "FFDProgramModules.h"
#include "itkObjectFactoryBase.h"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <mutex>

// Set by apps/CMakeLists.txt: the module's file name.
#ifndef FFD_VTK_FORMATS_MODULE_FILE
#  error "FFD_VTK_FORMATS_MODULE_FILE is not defined"
#endif

namespace ffd
{
std::string
LowerCaseExtension(const std::string & fileName)
{
  std::string extension = std::filesystem::path(fileName).extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(), [](unsigned char c) {
    return static_cast<char>(std::tolower(c));
  });
  return extension;
}

bool
IsVTKMeshFormat(const std::string & fileName)
{
  const std::string extension = LowerCaseExtension(fileName);
  return extension == ".stl" || extension == ".ply" || extension == ".vtp";
}

void
LoadVTKMeshFormats()
{
  static std::once_flag loaded;
  std::call_once(loaded, [] {
    // POSIX: a function's address is read from dlsym's object pointer.
    const auto entry = reinterpret_cast<VTKMeshFormatsEntryPoint>(
      LoadProgramModuleEntry(FFD_VTK_FORMATS_MODULE_FILE, VTKMeshFormatsEntryPointName, "the VTK formats module"));
    entry(&AddLibraryMessage);
  });
}

bool
VTKMeshFormatsRegistered()
{
  for (itk::ObjectFactoryBase * factory : itk::ObjectFactoryBase::GetRegisteredFactories())
  {
    if (std::string(factory->GetNameOfClass()) == "VTKSurfaceMeshIOFactory")
    {
      return true;
    }
  }
  return false;
}

void
PrepareMeshFormat(const std::string & fileName)
{
  if (IsVTKMeshFormat(fileName) && !VTKMeshFormatsRegistered())
  {
    LoadVTKMeshFormats();
  }
}
} // namespace ffd
