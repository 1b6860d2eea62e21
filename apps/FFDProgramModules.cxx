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
#include "FFDProgramModules.h"

#include <dlfcn.h>
#include <unistd.h>

#include <map>
#include <mutex>
#include <stdexcept>
#include <vector>

// Set by apps/CMakeLists.txt: the library directory relative to the program's directory in an installation.
#ifndef FFD_PROGRAM_MODULE_INSTALL_DIR
#  error "FFD_PROGRAM_MODULE_INSTALL_DIR is not defined"
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
} // namespace

void *
LoadProgramModuleEntry(const std::string & file, const char * entryName, const std::string & what)
{
  static std::mutex                                            mutex;
  static std::map<std::pair<std::string, std::string>, void *> entries;
  const std::lock_guard<std::mutex>                            lock(mutex);
  const auto                                                   key = std::make_pair(file, std::string(entryName));
  const auto                                                   known = entries.find(key);
  if (known != entries.end())
  {
    return known->second;
  }
  const std::string        directory = ProgramDirectory();
  std::vector<std::string> candidates;
  if (!directory.empty())
  {
    candidates.push_back(directory + "/" + file);
    candidates.push_back(directory + "/" + FFD_PROGRAM_MODULE_INSTALL_DIR + "/" + file);
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
    void * symbol = dlsym(module, entryName);
    if (symbol == nullptr)
    {
      reasons += "; " + candidate + " has no " + entryName;
      continue;
    }
    entries[key] = symbol;
    return symbol;
  }
  throw std::runtime_error(what + " " + file + " (installed with the programs) is not in " +
                           (directory.empty() ? std::string("the library search path") : directory) + " or " +
                           FFD_PROGRAM_MODULE_INSTALL_DIR + " beside it" + reasons);
}
} // namespace ffd
