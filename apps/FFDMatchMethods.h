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
#ifndef FFDMatchMethods_h
#define FFDMatchMethods_h

// The registration stage of ffd-match, one function per method, each in its own translation unit
// (the methods' template code compiles in parallel and apart from the program's input/output code).
// Every method estimates T : target space -> source space (fixed -> moving) and hands it on as a
// decorated transform, ready for the mesh-transform filter.

#include "FFDProgramSupport.h"
#include "itkDataObjectDecorator.h"
#include "itkEventObject.h"
#include "itkImage.h"
#include "itkMesh.h"
#include "itkTransform.h"

#include <iomanip>
#include <iostream>
#include <stdexcept>
#include <string>
#include <vector>

namespace ffd
{
// Double coordinates from reading to writing (itk::Mesh<double, 3> stores float coordinates, which move a vertex
// 1e7 mm from the origin by up to 0.5 mm); the same type as FFDSnapshot.h's DoubleCoordinateMeshType.
using MeshType = itk::Mesh<double, 3, itk::DefaultStaticMeshTraits<double, 3, 3, double, double, double>>;
using ImageType = itk::Image<float, 3>;
using MaskImageType = itk::Image<unsigned char, 3>;
using TransformType = itk::Transform<double, 3, 3>;
using DecoratedTransformType = itk::DataObjectDecorator<TransformType>;

/** A failure of the run: one line for the user, exit code 1. */
struct Error : std::runtime_error
{
  using std::runtime_error::runtime_error;
};

/** The command line of ffd-match. */
struct Options
{
  std::string  source;
  std::string  target;
  std::string  method;
  std::string  output;
  unsigned int grid{ 20 };
  double       voxelSize{ 1.0 };
  std::string  voxelization{ "sdf" };
  std::string  transformOut;
  std::string  report;
  std::string  snapshot;
  std::string  templates;
  std::string  templateSplit{ "control-point" };
  int          threads{ 0 };
  int          seed{ 121212 };
  unsigned int levels{ 2 };
  unsigned int iterations{ 50 };
  double       sampling{ 0.25 };
  double       bendingWeight{ 1.0 };
  double       foldingWeight{ 0.0 };
  double       mrfWeight{ 1.0 };
  bool         mrfPyramid{ false }; // method mrf: smooth and shrink the images at coarse levels
  double       timeLimit{ 0.0 };    // seconds of registration, 0 = none
  double       memoryLimit{ 0.0 };  // MB, 0 = from the available memory
  bool         demo{ false };
  std::string  outputDir{ "demo-output" };
  bool         gridGiven{ false };
  bool         voxelSizeGiven{ false };
  bool         levelsGiven{ false };
  bool         iterationsGiven{ false };
  bool         samplingGiven{ false };
};

/** What a registration stage gets: the voxel images (target = fixed, source = moving), the metric mask
 * (a band around the target surface) and the meshes themselves (for the mesh-distance methods). */
struct RegistrationInputs
{
  const ImageType *     fixed{ nullptr };
  const ImageType *     moving{ nullptr };
  const MaskImageType * mask{ nullptr };
  const MeshType *      source{ nullptr };
  const MeshType *      target{ nullptr };
};

/** What a registration stage gives: T (target space -> source space) and its record. */
struct RegistrationResult
{
  DecoratedTransformType::ConstPointer transform;
  std::vector<double>                  metricValues;
  std::string                          metricName;
  std::string                          stopCondition;
  bool                                 timeLimitReached{ false };
};

/** Whether this build of ffd-match has \c method (go, mrf, par, go+par or mrf+par). */
inline bool
MethodAvailable(const std::string & method)
{
  return method == "go" || method == "mrf" || method == "par" || method == "go+par" || method == "mrf+par";
}

/** Prints "ffd-match: register: <step> N <quantity> V (T s)" on stderr at the first IterationEvent of
 * \c registration and at every \c every-th, with the values that \c values() returns at that moment. */
template <typename TRegistration, typename TValues>
void
PrintRegistrationProgress(TRegistration *     registration,
                          TValues             values,
                          const std::string & step,
                          const std::string & quantity,
                          std::size_t         every)
{
  const auto start = ClockType::now();
  registration->AddObserver(itk::IterationEvent(), [=](const itk::EventObject &) {
    const auto &      list = values();
    const std::size_t n = list.size();
    if (n == 1 || (n > 0 && n % every == 0))
    {
      std::cerr << "ffd-match: register: " << step << ' ' << n << ' ' << quantity << ' ' << std::setprecision(6)
                << std::defaultfloat << list.back() << " (" << std::fixed << std::setprecision(1) << SecondsSince(start)
                << " s)" << std::endl;
    }
  });
}

/** Gradient-based global optimization of a B-spline FFD on the voxel images (method go). */
RegistrationResult
RegisterGO(const RegistrationInputs & inputs, const Options & options);

/** Discrete MRF optimization of a B-spline FFD on the voxel images (method mrf). */
RegistrationResult
RegisterMRF(const RegistrationInputs & inputs, const Options & options);

/** Parametric-template matching of the meshes (method par; go+par and mrf+par with the voxel result as \c base). */
RegistrationResult
RegisterPar(const RegistrationInputs & inputs, const Options & options, const DecoratedTransformType * base);

/** The printed name of the image metric that method go uses with the chosen voxelization. */
std::string
GOMetricName(const Options & options);
} // namespace ffd

#endif
