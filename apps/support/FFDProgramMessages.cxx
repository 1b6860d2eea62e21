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
#include "itkFFDShapeMatchingCompatibility.h"
#include "FFDProgramMessages.h"

#include "FFDProgramSupport.h"
#include "itkObjectFactory.h"
#include "itkOutputWindow.h"

#include <vtkLogger.h>
#include <vtkObjectFactory.h>
#include <vtkOutputWindow.h>
#include <vtkSmartPointer.h>

#include <mutex>
#include <vector>

namespace ffd
{
namespace
{
std::mutex &
MessagesMutex()
{
  static std::mutex mutex;
  return mutex;
}

std::vector<std::string> &
Messages()
{
  static std::vector<std::string> messages;
  return messages;
}

class CollectingITKOutputWindow : public itk::OutputWindow
{
public:
  ITK_DISALLOW_COPY_AND_MOVE(CollectingITKOutputWindow);
  using Self = CollectingITKOutputWindow;
  using Superclass = itk::OutputWindow;
  using Pointer = itk::SmartPointer<Self>;
  itkNewMacro(Self);
  itkOverrideGetNameOfClassMacro(CollectingITKOutputWindow);

  void
  DisplayText(const char * text) override
  {
    AddLibraryMessage(text);
  }

protected:
  CollectingITKOutputWindow() = default;
  ~CollectingITKOutputWindow() override = default;
};

class CollectingVTKOutputWindow : public vtkOutputWindow
{
public:
  vtkTypeMacro(CollectingVTKOutputWindow, vtkOutputWindow);
  static CollectingVTKOutputWindow *
  New();

  void
  DisplayText(const char * text) override
  {
    AddLibraryMessage(text);
  }

protected:
  CollectingVTKOutputWindow() = default;
  ~CollectingVTKOutputWindow() override = default;
};
vtkStandardNewMacro(CollectingVTKOutputWindow);
} // namespace

void
AddLibraryMessage(const char * text)
{
  if (text == nullptr)
  {
    return;
  }
  std::string message = text;
  // VTK's "ERROR: In /path/file.cxx, line 123\n" preamble and ITK's "WARNING: In ..." say nothing to a user.
  if (message.compare(0, 4, "ERR") == 0 || message.compare(0, 4, "WARN") == 0 || message.find(": In ") < 16)
  {
    const std::size_t newline = message.find('\n');
    if (newline != std::string::npos)
    {
      message.erase(0, newline + 1);
    }
  }
  // VTK's "vtkClassName (0x...): " prefix: an address means nothing to a user.
  const std::size_t open = message.find(" (0x");
  const std::size_t close = message.find("): ");
  if (open != std::string::npos && close != std::string::npos && open < close && message.find(' ') == open)
  {
    message.erase(0, close + 3);
  }
  message = OneLine(message);
  if (message.empty())
  {
    return;
  }
  const std::lock_guard<std::mutex> lock(MessagesMutex());
  if (Messages().size() < 100)
  {
    Messages().push_back(message);
  }
}

void
CollectLibraryMessages()
{
  itk::OutputWindow::SetInstance(CollectingITKOutputWindow::New());
  vtkLogger::SetStderrVerbosity(vtkLogger::VERBOSITY_OFF);
  vtkOutputWindow::SetInstance(vtkSmartPointer<CollectingVTKOutputWindow>::New());
}

std::string
FirstLibraryMessage()
{
  const std::lock_guard<std::mutex> lock(MessagesMutex());
  return Messages().empty() ? std::string() : Messages().front();
}

void
ClearLibraryMessages()
{
  const std::lock_guard<std::mutex> lock(MessagesMutex());
  Messages().clear();
}
} // namespace ffd
