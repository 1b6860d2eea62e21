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
// the program's one line: call CollectLibraryMessages() at the start of main.

#include <string>

namespace ffd
{
/** Replaces ITK's output window (itk::OutputWindow::SetInstance) and VTK's (vtkOutputWindow::SetInstance) by ones
 * that collect the messages instead of printing them, and turns VTK's logger's stderr output off. VTK's global
 * warning display stays on: VTK 9.1 sends an object's ErrorEvent only when it is on, and the module's readers
 * observe those events to turn VTK's errors into exceptions. */
void
CollectLibraryMessages();

/** Keeps one library message (what the collecting output windows receive). */
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
