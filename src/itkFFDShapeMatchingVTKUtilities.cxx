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
#include "itkFFDShapeMatchingVTKUtilities.h"

#include "itkMacro.h"

#include "vtkCallbackCommand.h"
#include "vtkCellArray.h"
#include "vtkCommand.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkTriangleFilter.h"

#include <algorithm>

namespace itk
{
namespace detail
{
namespace
{
std::recursive_mutex &
VTKMessageMutex()
{
  static std::recursive_mutex mutex;
  return mutex;
}

/** Reduces one VTK message to its first meaningful line, without the "ERROR: In file, line N"
 * preamble and the "vtkClass (0x...): " prefix. */
std::string
CleanVTKMessage(const char * text)
{
  std::string message = text ? text : "";
  // Drop the "ERROR: In <file>, line <n>" / "Warning: In ..." preamble line.
  if (message.rfind("ERROR: In ", 0) == 0 || message.rfind("Warning: In ", 0) == 0 ||
      message.rfind("Generic Warning: In ", 0) == 0)
  {
    const std::string::size_type endOfLine = message.find('\n');
    message = endOfLine == std::string::npos ? std::string() : message.substr(endOfLine + 1);
  }
  // Drop the "vtkClass (0x...): " prefix.
  const std::string::size_type prefixEnd = message.find("): ");
  if (prefixEnd != std::string::npos && message.rfind("vtk", 0) == 0 && prefixEnd < message.find('\n'))
  {
    message = message.substr(prefixEnd + 3);
  }
  // Keep the first line only, trimmed.
  message = message.substr(0, message.find('\n'));
  const std::string::size_type first = message.find_first_not_of(" \t\r");
  const std::string::size_type last = message.find_last_not_of(" \t\r");
  return first == std::string::npos ? std::string() : message.substr(first, last - first + 1);
}

void
VTKMessageCallback(vtkObject * itkNotUsed(caller), unsigned long eventId, void * clientData, void * callData)
{
  auto * capture = static_cast<VTKMessageCapture *>(clientData);
  capture->AddMessage(static_cast<const char *>(callData), eventId == vtkCommand::ErrorEvent);
}

/** An output window that hands every message to a VTKMessageCapture instead of printing it. */
class CapturingOutputWindow : public vtkOutputWindow
{
public:
  static CapturingOutputWindow *
  New();
  vtkTypeMacro(CapturingOutputWindow, vtkOutputWindow);

  void
  SetCapture(VTKMessageCapture * capture)
  {
    m_Capture = capture;
  }

  void
  DisplayText(const char * text) override
  {
    this->Record(text, false);
  }
  void
  DisplayErrorText(const char * text) override
  {
    this->Record(text, true);
  }
  void
  DisplayWarningText(const char * text) override
  {
    this->Record(text, false);
  }
  void
  DisplayGenericWarningText(const char * text) override
  {
    this->Record(text, false);
  }
  void
  DisplayDebugText(const char * itkNotUsed(text)) override
  {}

protected:
  CapturingOutputWindow() = default;
  ~CapturingOutputWindow() override = default;

private:
  void
  Record(const char * text, bool isError)
  {
    if (m_Capture != nullptr)
    {
      m_Capture->AddMessage(text, isError);
    }
  }

  VTKMessageCapture * m_Capture{ nullptr };
};

vtkStandardNewMacro(CapturingOutputWindow);
} // namespace

VTKMessageCapture::VTKMessageCapture()
  : m_Lock(VTKMessageMutex())
{
  m_PreviousWindow = vtkOutputWindow::GetInstance();
  auto window = vtkSmartPointer<CapturingOutputWindow>::New();
  window->SetCapture(this);
  m_Window = window;
  vtkOutputWindow::SetInstance(window);
  auto callback = vtkSmartPointer<vtkCallbackCommand>::New();
  callback->SetCallback(VTKMessageCallback);
  callback->SetClientData(this);
  m_Command = callback;
}

VTKMessageCapture::~VTKMessageCapture()
{
  for (std::size_t i = 0; i < m_ObservedObjects.size(); ++i)
  {
    m_ObservedObjects[i]->RemoveObserver(m_ObserverTags[i]);
  }
  static_cast<CapturingOutputWindow *>(m_Window.GetPointer())->SetCapture(nullptr);
  vtkOutputWindow::SetInstance(m_PreviousWindow);
}

void
VTKMessageCapture::Observe(vtkObject * object)
{
  if (object == nullptr)
  {
    return;
  }
  for (const unsigned long eventId : { vtkCommand::ErrorEvent, vtkCommand::WarningEvent })
  {
    m_ObservedObjects.emplace_back(object);
    m_ObserverTags.push_back(object->AddObserver(eventId, m_Command));
  }
}

void
VTKMessageCapture::AddMessage(const char * text, bool isError)
{
  const std::string message = CleanVTKMessage(text);
  if (message.empty())
  {
    return;
  }
  std::vector<std::string> & messages = isError ? m_Errors : m_Warnings;
  if (std::find(messages.begin(), messages.end(), message) == messages.end())
  {
    messages.push_back(message);
  }
}

std::string
VTKMessageCapture::GetSummary() const
{
  const std::vector<std::string> & messages = m_Errors.empty() ? m_Warnings : m_Errors;
  // The executive's report that an algorithm failed says nothing of why (and names addresses):
  // it is left out, so the summary is empty when nothing else was reported.
  std::vector<std::string> specific;
  for (const std::string & message : messages)
  {
    if (message.find("returned failure for request") == std::string::npos)
    {
      specific.push_back(message);
    }
  }
  std::string summary;
  for (const std::string & message : specific)
  {
    summary += (summary.empty() ? "" : "; ") + message;
  }
  return summary;
}

vtkSmartPointer<vtkPolyData>
TriangulateVTKPolyData(vtkPolyData * input, std::size_t * numberOfDroppedCells)
{
  const vtkIdType numberOfDropped = input->GetNumberOfVerts() + input->GetNumberOfLines();
  if (numberOfDroppedCells != nullptr)
  {
    *numberOfDroppedCells += static_cast<std::size_t>(numberOfDropped);
  }
  const bool trianglesOnly = numberOfDropped == 0 && input->GetNumberOfStrips() == 0 &&
                             (input->GetNumberOfPolys() == 0 || input->GetPolys()->IsHomogeneous() == 3);
  if (trianglesOnly)
  {
    return input;
  }
  auto triangleFilter = vtkSmartPointer<vtkTriangleFilter>::New();
  triangleFilter->SetInputData(input);
  triangleFilter->PassVertsOff();
  triangleFilter->PassLinesOff();
  triangleFilter->Update();
  vtkSmartPointer<vtkPolyData> output = triangleFilter->GetOutput();
  if (output->GetNumberOfPolys() > 0 && output->GetPolys()->IsHomogeneous() != 3)
  {
    // Degenerate polygons (fewer than three points) may come through: keep the triangles only.
    auto              triangles = vtkSmartPointer<vtkCellArray>::New();
    vtkIdType         numberOfCellPoints = 0;
    const vtkIdType * cellPoints = nullptr;
    vtkCellArray *    polys = output->GetPolys();
    for (polys->InitTraversal(); polys->GetNextCell(numberOfCellPoints, cellPoints);)
    {
      if (numberOfCellPoints == 3)
      {
        triangles->InsertNextCell(3, cellPoints);
      }
      else if (numberOfDroppedCells != nullptr)
      {
        ++*numberOfDroppedCells;
      }
    }
    auto copy = vtkSmartPointer<vtkPolyData>::New();
    copy->SetPoints(output->GetPoints());
    copy->GetPointData()->ShallowCopy(output->GetPointData());
    copy->SetPolys(triangles);
    output = copy;
  }
  return output;
}

/** The problem of a mesh with a cell on a missing point, or "". */
std::string
CheckVTKPolyDataPointIds(vtkPolyData * polyData)
{
  const vtkIdType numberOfPoints = polyData->GetNumberOfPoints();
  for (vtkCellArray * cells :
       { polyData->GetVerts(), polyData->GetLines(), polyData->GetPolys(), polyData->GetStrips() })
  {
    if (cells == nullptr)
    {
      continue;
    }
    vtkIdType         numberOfCellPoints = 0;
    const vtkIdType * cellPoints = nullptr;
    vtkIdType         cellId = 0;
    for (cells->InitTraversal(); cells->GetNextCell(numberOfCellPoints, cellPoints); ++cellId)
    {
      for (vtkIdType j = 0; j < numberOfCellPoints; ++j)
      {
        if (cellPoints[j] < 0 || cellPoints[j] >= numberOfPoints)
        {
          return "a cell refers to point " + std::to_string(cellPoints[j]) + " of " + std::to_string(numberOfPoints);
        }
      }
    }
  }
  return "";
}

vtkDataArray *
SelectScalarPointData(vtkPolyData * polyData, const std::string & arrayName)
{
  vtkPointData * pointData = polyData->GetPointData();
  if (pointData == nullptr)
  {
    return nullptr;
  }
  if (!arrayName.empty())
  {
    vtkDataArray * named = pointData->GetArray(arrayName.c_str());
    if (named != nullptr && named->GetNumberOfComponents() == 1)
    {
      return named;
    }
  }
  vtkDataArray * scalars = pointData->GetScalars();
  if (scalars != nullptr && scalars->GetNumberOfComponents() == 1)
  {
    return scalars;
  }
  return nullptr;
}

} // namespace detail
} // namespace itk
