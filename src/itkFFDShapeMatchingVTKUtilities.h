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
#ifndef itkFFDShapeMatchingVTKUtilities_h
#define itkFFDShapeMatchingVTKUtilities_h

/** \file itkFFDShapeMatchingVTKUtilities.h
 * \brief Private helpers of the module library for its use of VTK (not installed).
 *
 * - VTKMessageCapture collects the errors and warnings VTK raises while it is alive, instead
 *   of letting VTK print them, so that the callers can turn them into an ExceptionObject.
 * - TriangulateVTKPolyData() gives a polygon mesh whose cells are triangles only.
 *
 * \ingroup FFDShapeMatching
 */

#include "vtkCommand.h"
#include "vtkDataArray.h"
#include "vtkOutputWindow.h"
#include "vtkPolyData.h"
#include "vtkSmartPointer.h"

#include <memory>
#include <mutex>
#include <string>
#include <vector>

class vtkObject;

namespace itk
{
namespace detail
{
/** \class VTKMessageCapture
 * \brief Collects what VTK reports while it lives, and keeps it from VTK's output window.
 *
 * While an instance lives, VTK's output window is replaced by one that records the messages
 * (the previous window is restored by the destructor), and objects passed to Observe() have
 * their ErrorEvent and WarningEvent observed. VTK 9 also sends the messages of objects
 * without an observer to its logger (stderr), which the window cannot stop: observe every
 * object that may report (the algorithm, its executive, an XML reader's parser). The window
 * replacement is process-wide: instances serialize on a process-wide recursive mutex, so VTK
 * input/output of this module runs one file at a time.
 *
 * Messages are stored without VTK's "In file, line" preamble and the object address, one
 * line each.
 *
 * \ingroup FFDShapeMatching
 */
class VTKMessageCapture
{
public:
  VTKMessageCapture();
  ~VTKMessageCapture();
  VTKMessageCapture(const VTKMessageCapture &) = delete;
  VTKMessageCapture &
  operator=(const VTKMessageCapture &) = delete;

  /** Observes the error and warning events of a VTK object (a reader or a writer, and its
   * executive: messages of observed objects go neither to VTK's logger nor to its window). */
  void
  Observe(vtkObject * object);

  /** The command that records the events it observes, for objects that take an observer
   * command (vtkXMLReader::SetParserErrorObserver). */
  vtkCommand *
  GetCommand() const
  {
    return m_Command;
  }

  /** Records a message; isError tells an error from a warning. */
  void
  AddMessage(const char * text, bool isError);

  /** True when an error was reported. */
  bool
  HasErrors() const
  {
    return !m_Errors.empty();
  }

  /** True when a warning was reported. */
  bool
  HasWarnings() const
  {
    return !m_Warnings.empty();
  }

  /** The errors, or if there are none the warnings, joined by "; ", without the executive's
   * generic "returned failure for request" report. Empty when nothing else was reported. */
  std::string
  GetSummary() const;

private:
  std::unique_lock<std::recursive_mutex>  m_Lock;
  std::vector<std::string>                m_Errors;
  std::vector<std::string>                m_Warnings;
  vtkSmartPointer<vtkOutputWindow>        m_PreviousWindow;
  vtkSmartPointer<vtkOutputWindow>        m_Window;
  vtkSmartPointer<vtkCommand>             m_Command;
  std::vector<vtkSmartPointer<vtkObject>> m_ObservedObjects;
  std::vector<unsigned long>              m_ObserverTags;
};

/** Returns a polygon mesh with the points (same ids, same coordinates) and the point data of
 * the input, whose cells are the triangles of its polygons and triangle strips (polygons with
 * more than three points are triangulated, degenerate ones may vanish). Vertex and line cells,
 * and polygons of fewer than three points, are dropped; their number is added to
 * numberOfDroppedCells when it is given. When the input holds triangles only, it is returned
 * as it is (no copy). The point ids of the cells must be valid. */
vtkSmartPointer<vtkPolyData>
TriangulateVTKPolyData(vtkPolyData * input, std::size_t * numberOfDroppedCells = nullptr);

/** The problem of a vtkPolyData with a cell on a missing point ("a cell refers to point i of
 * n"), or "". */
std::string
CheckVTKPolyDataPointIds(vtkPolyData * polyData);

/** The single-component point data array a mesh should carry: the array named arrayName when
 * arrayName is not empty and such an array exists with one component, otherwise the active
 * scalars when they have one component, otherwise nullptr. */
vtkDataArray *
SelectScalarPointData(vtkPolyData * polyData, const std::string & arrayName);

} // namespace detail
} // namespace itk

#endif // itkFFDShapeMatchingVTKUtilities_h
