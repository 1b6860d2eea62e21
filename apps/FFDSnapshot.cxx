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
#include "FFDSnapshot.h"

#include "FFDProgramModules.h"
#include "FFDVTKMeshFormats.h"

#include <cstdlib>
#include <stdexcept>
#include <string>
#include <vector>

// Set by apps/CMakeLists.txt: the module's file name.
#ifndef FFD_SNAPSHOT_MODULE_FILE
#  error "FFD_SNAPSHOT_MODULE_FILE is not defined"
#endif

namespace ffd
{
bool
SnapshotPossible(std::string & why)
{
  const char * display = std::getenv("DISPLAY");
  if (display == nullptr || display[0] == '\0')
  {
    why = "--snapshot renders with VTK's X11 window and no DISPLAY is set: run ffd-match under xvfb-run "
          "(Debian package xvfb)";
    return false;
  }
  return true;
}

void
WriteSnapshot(const DoubleCoordinateMeshType * source,
              const DoubleCoordinateMeshType * deformed,
              const DoubleCoordinateMeshType * target,
              const std::vector<double> &      beforeDistances,
              const std::vector<double> &      afterDistances,
              const std::string &              title,
              const std::string &              fileName)
{
  std::string why;
  if (!SnapshotPossible(why))
  {
    throw std::runtime_error(why);
  }
  const SnapshotScene scene{ source, deformed, target, &beforeDistances, &afterDistances, &title, &fileName };
  // POSIX: a function's address is read from dlsym's object pointer.
  const auto render = reinterpret_cast<SnapshotEntryPoint>(
    LoadProgramModuleEntry(FFD_SNAPSHOT_MODULE_FILE, SnapshotEntryPointName, "the rendering module"));
  // VTK's formats module too: it sends VTK's messages where the program collects the libraries' messages.
  LoadVTKMeshFormats();
  render(scene);
}
} // namespace ffd
