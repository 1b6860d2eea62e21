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

#include <dlfcn.h>
#include <unistd.h>

#include <cstdlib>
#include <stdexcept>
#include <string>
#include <vector>

// Set by apps/CMakeLists.txt: the module's file name, and the library directory relative to the program's
// directory in an installation.
#ifndef FFD_SNAPSHOT_MODULE_FILE
#  error "FFD_SNAPSHOT_MODULE_FILE is not defined"
#endif
#ifndef FFD_SNAPSHOT_MODULE_INSTALL_DIR
#  error "FFD_SNAPSHOT_MODULE_INSTALL_DIR is not defined"
#endif

namespace ffd
{
namespace
{
/** The directory of the running program (Linux's /proc/self/exe), or empty when it cannot be told. */
std::string
ProgramDirectory()
{
  std::vector<char> path(4096);
  const ssize_t     length = readlink("/proc/self/exe", path.data(), path.size());
  if (length <= 0 || static_cast<std::size_t>(length) >= path.size())
  {
    return std::string();
  }
  const std::string program(path.data(), static_cast<std::size_t>(length));
  const auto        slash = program.rfind('/');
  return slash == std::string::npos ? std::string() : program.substr(0, slash);
}

/** The rendering module's entry point, the module loaded (once; it stays loaded) from the program's directory or
 * its installation's library directory. Throws std::runtime_error, with the loader's reasons, when neither holds
 * a module that loads. */
SnapshotEntryPoint
LoadRenderingModule()
{
  static SnapshotEntryPoint entryPoint = nullptr;
  if (entryPoint != nullptr)
  {
    return entryPoint;
  }
  const std::string        directory = ProgramDirectory();
  const std::string        file = FFD_SNAPSHOT_MODULE_FILE;
  std::vector<std::string> candidates;
  if (!directory.empty())
  {
    candidates.push_back(directory + "/" + file);
    candidates.push_back(directory + "/" + FFD_SNAPSHOT_MODULE_INSTALL_DIR + "/" + file);
  }
  else
  {
    candidates.push_back(file); // The loader's own search (the program's RUNPATH, LD_LIBRARY_PATH).
  }
  std::string reasons;
  for (const auto & candidate : candidates)
  {
    if (access(candidate.c_str(), F_OK) != 0 && candidate != file)
    {
      continue;
    }
    void * module = dlopen(candidate.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (module == nullptr)
    {
      const char * error = dlerror();
      reasons += std::string("; ") + (error != nullptr ? error : candidate + ": cannot be loaded");
      continue;
    }
    // POSIX: a function's address is read from dlsym's object pointer.
    void * symbol = dlsym(module, SnapshotEntryPointName);
    if (symbol == nullptr)
    {
      reasons += "; " + candidate + " has no " + SnapshotEntryPointName;
      continue;
    }
    entryPoint = reinterpret_cast<SnapshotEntryPoint>(symbol);
    return entryPoint;
  }
  throw std::runtime_error("the rendering module " + file + " (installed with ffd-match) is not in " +
                           (directory.empty() ? std::string("the library search path") : directory) + " or " +
                           FFD_SNAPSHOT_MODULE_INSTALL_DIR + " beside it" + reasons);
}
} // namespace

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
  LoadRenderingModule()(scene);
}
} // namespace ffd
