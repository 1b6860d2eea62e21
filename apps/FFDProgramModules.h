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
#ifndef FFDProgramModules_h
#define FFDProgramModules_h

// The programs' loadable modules: code whose libraries most runs do not need (VTK's surface formats, the snapshot's
// rendering), built as shared objects that a program opens (dlopen) the first time it needs them, so that the
// other runs neither load nor relocate those libraries at start-up.

#include <string>

namespace ffd
{
/** The address of the function \c entryName of the module \c file, the module loaded (once; it stays loaded) from
 * the program's directory (a build tree) or from the installation's library directory beside it (\c
 * FFD_PROGRAM_MODULE_INSTALL_DIR, relative to the program's directory). Throws std::runtime_error, naming the
 * module (\c what, e.g. "the rendering module") and the loader's reasons, when neither holds a module that loads
 * and has that function. */
void *
LoadProgramModuleEntry(const std::string & file, const char * entryName, const std::string & what);
} // namespace ffd

#endif // FFDProgramModules_h
