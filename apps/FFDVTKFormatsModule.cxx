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
// The VTK formats module (ffd-vtk-formats) that the programs load when a mesh file is in one of VTK's formats (STL,
// PLY, VTP) or a snapshot is rendered (FFDVTKMeshFormats.h): the VTK surface mesh IO's factory, and VTK's messages
// sent to the program instead of stderr.

#include "itkRegisterFFDShapeMatchingMeshIOFactories.h"

#include <vtkLogger.h>
#include <vtkObjectFactory.h>
#include <vtkOutputWindow.h>
#include <vtkSmartPointer.h>

namespace
{
void (*MessageSink)(const char *) = nullptr;

/** VTK's output window, each message handed to the program's collector instead of printed. */
class ForwardingVTKOutputWindow : public vtkOutputWindow
{
public:
  vtkTypeMacro(ForwardingVTKOutputWindow, vtkOutputWindow);
  static ForwardingVTKOutputWindow *
  New();

  void
  DisplayText(const char * text) override
  {
    if (MessageSink != nullptr)
    {
      MessageSink(text);
    }
  }

protected:
  ForwardingVTKOutputWindow() = default;
  ~ForwardingVTKOutputWindow() override = default;
};
vtkStandardNewMacro(ForwardingVTKOutputWindow);
} // namespace

// The entry point (ffd::VTKMeshFormatsEntryPoint). VTK's logger's stderr output (the coloured "ERR|" lines) is
// turned off; VTK's global warning display stays on: VTK 9.1 sends an object's ErrorEvent only when it is on, and
// the module's readers observe those events to turn VTK's errors into exceptions.
extern "C" __attribute__((visibility("default"))) void
FFDShapeMatchingLoadVTKMeshFormats(void (*addMessage)(const char *))
{
  MessageSink = addMessage;
  vtkLogger::SetStderrVerbosity(vtkLogger::VERBOSITY_OFF);
  auto window = vtkSmartPointer<ForwardingVTKOutputWindow>::New();
  vtkOutputWindow::SetInstance(window);
  itk::RegisterFFDShapeMatchingMeshIOFactories();
}
