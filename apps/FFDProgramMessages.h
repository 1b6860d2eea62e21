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
#ifndef FFDProgramMessages_h
#define FFDProgramMessages_h

// Keeps VTK's and ITK's own messages off the stderr of the module's command-line programs, so that a refusal is
// the program's one line: call CollectLibraryMessages() at the start of main (ITK's messages); VTK's come through
// AddLibraryMessage() from the VTK formats module, which the programs load only when VTK is needed.

#include <string>

namespace ffd
{
/** Replaces ITK's output window (itk::OutputWindow::SetInstance) by one that collects the messages instead of
 * printing them. (VTK's output window and logger are set the same way by the VTK formats module when it loads.) */
void
CollectLibraryMessages();

/** Keeps one library message (VTK's, handed on by the VTK formats module, FFDVTKMeshFormats.h). */
void
AddLibraryMessage(const char * text);

/** The first message VTK or ITK gave since CollectLibraryMessages() or the last ClearLibraryMessages(), on one
 * line without VTK's "In file, line" preamble, or "" when there was none. */
std::string
FirstLibraryMessage();

/** Forgets the messages collected so far. */
void
ClearLibraryMessages();
} // namespace ffd

#endif // FFDProgramMessages_h
