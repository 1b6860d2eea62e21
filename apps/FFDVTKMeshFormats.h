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
#ifndef FFDVTKMeshFormats_h
#define FFDVTKMeshFormats_h

// The mesh formats the programs read and write through VTK (STL, PLY, VTP: itk::VTKSurfaceMeshIO) live, with VTK's
// libraries, in a module of their own, ffd-vtk-formats (FFDVTKFormatsModule.cxx), that the programs load when a file
// needs them: linked into the programs, VTK's libraries (some 50 shared objects with those they load) were loaded
// and relocated on every run, half of ffd-match's start-up. OFF, OBJ and legacy VTK files need no VTK library
// (itk::RegisterFFDShapeMatchingTextMeshIOFactories()).

#include <string>

namespace ffd
{
/** The VTK formats module's entry point: its name, and its type. It registers every mesh IO factory of the module
 * (itk::RegisterFFDShapeMatchingMeshIOFactories()) and sends VTK's messages (its output window and its logger's
 * stderr output) to \c addMessage instead of stderr. */
constexpr const char * VTKMeshFormatsEntryPointName = "FFDShapeMatchingLoadVTKMeshFormats";
using VTKMeshFormatsEntryPoint = void (*)(void (*addMessage)(const char *));

/** \c fileName's extension in lower case (".stl" for "part.STL"; "" when there is none). */
std::string
LowerCaseExtension(const std::string & fileName);

/** Whether \c fileName's format is one of VTK's: its extension is .stl, .ply or .vtp (any case). */
bool
IsVTKMeshFormat(const std::string & fileName);

/** Loads the VTK formats module and calls its entry point, once; its messages go to ffd::AddLibraryMessage().
 * Throws std::runtime_error, naming the module, when it cannot be loaded. */
void
LoadVTKMeshFormats();

/** Whether VTK's formats are registered with ITK's object factory already (a VTKSurfaceMeshIOFactory: by the module,
 * or by a program linked with the FFDShapeMatchingVTKIO library that called
 * itk::RegisterFFDShapeMatchingMeshIOFactories()). */
bool
VTKMeshFormatsRegistered();

/** LoadVTKMeshFormats() when \c fileName is in one of VTK's formats and they are not registered yet; nothing
 * otherwise. */
void
PrepareMeshFormat(const std::string & fileName);
} // namespace ffd

#endif // FFDVTKMeshFormats_h
