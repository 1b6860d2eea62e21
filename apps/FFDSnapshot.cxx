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

#include "itkMeshVTKPolyDataConversion.h"

#include <vtkActor.h>
#include <vtkAutoInit.h>
#include <vtkCamera.h>
#include <vtkCommand.h>
#include <vtkDoubleArray.h>
#include <vtkLookupTable.h>
#include <vtkNew.h>
#include <vtkPNGWriter.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkPolyDataNormals.h>
#include <vtkProperty.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkScalarBarActor.h>
#include <vtkTextActor.h>
#include <vtkTextProperty.h>
#include <vtkWindowToImageFilter.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <stdexcept>

VTK_MODULE_INIT(vtkRenderingOpenGL2);
VTK_MODULE_INIT(vtkRenderingFreeType);

namespace ffd
{
namespace
{
/** What a snapshot shows (pointers to WriteSnapshot()'s arguments, valid for the call). */
struct SnapshotScene
{
  const DoubleCoordinateMeshType * source;
  const DoubleCoordinateMeshType * deformed;
  const DoubleCoordinateMeshType * target;
  const std::vector<double> *      beforeDistances;
  const std::vector<double> *      afterDistances;
  const std::string *              title;
  const std::string *              fileName;
};

// Turns VTK's error and warning events of one object into a flag instead of console text.
class ErrorObserver : public vtkCommand
{
public:
  static ErrorObserver *
  New()
  {
    return new ErrorObserver;
  }

  void
  Execute(vtkObject *, unsigned long, void * callData) override
  {
    failed = true;
    if (message.empty() && callData != nullptr)
    {
      message = static_cast<const char *>(callData);
    }
  }

  bool        failed{ false };
  std::string message;
};

// The mesh for rendering, with \c values (one per vertex, if given) as its scalars.
vtkSmartPointer<vtkPolyData>
ToPolyData(const DoubleCoordinateMeshType * mesh, const std::vector<double> * values = nullptr)
{
  auto polyData = vtkSmartPointer<vtkPolyData>::New();
  itk::MeshToVTKPolyData(mesh, polyData, "");
  polyData->GetPointData()->SetScalars(nullptr);
  if (values != nullptr)
  {
    if (values->size() != static_cast<std::size_t>(polyData->GetNumberOfPoints()))
    {
      throw std::runtime_error("snapshot: one distance per target vertex is needed");
    }
    vtkNew<vtkDoubleArray> distance;
    distance->SetName("distance");
    distance->SetNumberOfValues(polyData->GetNumberOfPoints());
    for (vtkIdType i = 0; i < polyData->GetNumberOfPoints(); ++i)
    {
      distance->SetValue(i, (*values)[static_cast<std::size_t>(i)]);
    }
    polyData->GetPointData()->SetScalars(distance);
  }
  // Smooth shading of faceted CAD parts without blending their sharp edges.
  vtkNew<vtkPolyDataNormals> normals;
  normals->SetInputData(polyData);
  normals->SetFeatureAngle(40.0);
  normals->SplittingOn();
  normals->ConsistencyOn();
  normals->Update();
  auto result = vtkSmartPointer<vtkPolyData>::New();
  result->ShallowCopy(normals->GetOutput());
  return result;
}

vtkSmartPointer<vtkActor>
SurfaceActor(vtkPolyData * polyData, double red, double green, double blue, double opacity)
{
  vtkNew<vtkPolyDataMapper> mapper;
  mapper->SetInputData(polyData);
  mapper->ScalarVisibilityOff();
  auto actor = vtkSmartPointer<vtkActor>::New();
  actor->SetMapper(mapper);
  actor->GetProperty()->SetColor(red, green, blue);
  actor->GetProperty()->SetOpacity(opacity);
  return actor;
}

vtkSmartPointer<vtkTextActor>
Label(const std::string & text, int size, double x, double y)
{
  auto label = vtkSmartPointer<vtkTextActor>::New();
  label->SetInput(text.c_str());
  label->GetTextProperty()->SetFontSize(size);
  label->GetTextProperty()->SetColor(0.1, 0.1, 0.1);
  label->GetPositionCoordinate()->SetCoordinateSystemToNormalizedViewport();
  label->GetPositionCoordinate()->SetValue(x, y);
  return label;
}

// The target coloured by per-vertex distances.
vtkSmartPointer<vtkActor>
ColouredActor(const DoubleCoordinateMeshType * mesh, const std::vector<double> & values, vtkLookupTable * colours)
{
  const auto                polyData = ToPolyData(mesh, &values);
  vtkNew<vtkPolyDataMapper> mapper;
  mapper->SetInputData(polyData);
  mapper->SetLookupTable(colours);
  mapper->UseLookupTableScalarRangeOn();
  mapper->ScalarVisibilityOn();
  auto actor = vtkSmartPointer<vtkActor>::New();
  actor->SetMapper(mapper);
  return actor;
}

/** The picture WriteSnapshot() describes (FFDSnapshot.h), rendered and written. */
void
RenderSnapshot(const SnapshotScene & scene)
{
  const DoubleCoordinateMeshType * const source = scene.source;
  const DoubleCoordinateMeshType * const target = scene.target;
  const std::vector<double> &            beforeDistances = *scene.beforeDistances;
  const std::vector<double> &            afterDistances = *scene.afterDistances;
  const std::string &                    title = *scene.title;
  const std::string &                    fileName = *scene.fileName;
  const auto                             sourceData = ToPolyData(source);
  const auto                             deformedData = ToPolyData(scene.deformed);

  // One colour scale for both views: up to the 95th percentile of the distances before, at least 1 mm.
  std::vector<double> sorted(beforeDistances);
  std::sort(sorted.begin(), sorted.end());
  const double           top = sorted.empty() ? 1.0 : std::max(1.0, sorted[(sorted.size() - 1) * 95 / 100]);
  vtkNew<vtkLookupTable> colours;
  colours->SetHueRange(0.667, 0.0);
  colours->SetTableRange(0.0, top);
  colours->SetNanColor(0.5, 0.5, 0.5, 1.0);
  colours->Build();

  // Each view: the (deformed) source in translucent grey and the target coloured by its distances.
  const auto view =
    [&](double left, vtkPolyData * sourceSurface, const std::vector<double> & distances, const std::string & caption) {
      auto renderer = vtkSmartPointer<vtkRenderer>::New();
      renderer->SetViewport(left, 0.0, left + 0.5, 1.0);
      const double shade = left > 0.0 ? 0.97 : 1.0;
      renderer->SetBackground(shade, shade, 1.0);
      renderer->AddActor(SurfaceActor(sourceSurface, 0.8, 0.8, 0.8, 0.35));
      renderer->AddActor(ColouredActor(target, distances, colours));
      renderer->AddActor2D(Label(caption, 16, 0.02, 0.02));
      return renderer;
    };
  const auto                before = view(0.0, sourceData, beforeDistances, "before: source (grey) and target");
  const auto                after = view(0.5, deformedData, afterDistances, "after: deformed source (grey) and target");
  vtkNew<vtkScalarBarActor> bar;
  bar->SetLookupTable(colours);
  bar->SetTitle("distance, mm");
  bar->SetNumberOfLabels(5);
  bar->SetWidth(0.1);
  bar->SetHeight(0.5);
  bar->SetPosition(0.86, 0.25);
  bar->UnconstrainedFontSizeOn();
  bar->GetTitleTextProperty()->SetFontSize(14);
  bar->GetLabelTextProperty()->SetFontSize(13);
  bar->GetTitleTextProperty()->SetColor(0.1, 0.1, 0.1);
  bar->GetTitleTextProperty()->ItalicOff();
  bar->GetTitleTextProperty()->ShadowOff();
  bar->GetLabelTextProperty()->SetColor(0.1, 0.1, 0.1);
  bar->GetLabelTextProperty()->ItalicOff();
  bar->GetLabelTextProperty()->ShadowOff();
  after->AddActor2D(bar);
  if (!title.empty())
  {
    before->AddActor2D(Label(title, 17, 0.02, 0.94));
  }

  // One camera for both views, looking at the target region from above and the side.
  const auto targetData = ToPolyData(target);
  double     bounds[6];
  targetData->GetBounds(bounds);
  before->ResetCamera(bounds);
  vtkCamera * camera = before->GetActiveCamera();
  camera->Elevation(35.0);
  camera->Azimuth(30.0);
  camera->OrthogonalizeViewUp();
  before->ResetCamera(bounds);
  camera->Zoom(1.15);
  after->SetActiveCamera(camera);
  before->ResetCameraClippingRange(sourceData->GetBounds());

  vtkNew<vtkRenderWindow> window;
  window->SetOffScreenRendering(1);
  window->SetSize(1400, 700);
  window->SetMultiSamples(4);
  window->AddRenderer(before);
  window->AddRenderer(after);
  vtkNew<ErrorObserver> windowErrors;
  window->AddObserver(vtkCommand::ErrorEvent, windowErrors);
  window->Render();
  if (windowErrors->failed)
  {
    throw std::runtime_error("snapshot: rendering failed: " + windowErrors->message);
  }

  vtkNew<vtkWindowToImageFilter> grab;
  grab->SetInput(window);
  grab->ReadFrontBufferOff();
  grab->Update();
  vtkNew<vtkPNGWriter>  writer;
  vtkNew<ErrorObserver> writerErrors;
  writer->AddObserver(vtkCommand::ErrorEvent, writerErrors);
  writer->SetFileName(fileName.c_str());
  writer->SetInputConnection(grab->GetOutputPort());
  writer->Write();
  if (writerErrors->failed)
  {
    throw std::runtime_error("snapshot: cannot write the PNG file: " + writerErrors->message);
  }
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
  RenderSnapshot(SnapshotScene{ source, deformed, target, &beforeDistances, &afterDistances, &title, &fileName });
}
} // namespace ffd
