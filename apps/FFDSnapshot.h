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
#ifndef FFDSnapshot_h
#define FFDSnapshot_h

// ffd-match --snapshot: a before/after picture of a match, rendered off screen with VTK (OpenGL, FreeType, PNG).

#include "itkMesh.h"

#include <string>
#include <vector>

namespace ffd
{
/** The programs' mesh: double coordinates (itk::Mesh<double, 3> stores float coordinates, which move a vertex 1e7 mm
 * from the origin by up to 0.5 mm). */
using DoubleCoordinateMeshType =
  itk::Mesh<double, 3, itk::DefaultStaticMeshTraits<double, 3, 3, double, double, double>>;

/** Whether off-screen rendering can start here (VTK's X11 render window needs a display; run the
 * program under xvfb-run on a machine without one). On false, \c why says what is missing. */
bool
SnapshotPossible(std::string & why);

/** Renders two views side by side from one camera and writes them as a PNG file: left, the source (grey)
 * and the target before matching; right, the deformed source and the target. In both the target is
 * coloured, on one scale, by each of its vertices' distance to the (deformed) source surface:
 * \c beforeDistances and \c afterDistances, in the target's point order (the quantity behind the mean
 * directed distance that ffd-match reports). Throws std::runtime_error when there is no display, or rendering or
 * writing fails. */
void
WriteSnapshot(const DoubleCoordinateMeshType * source,
              const DoubleCoordinateMeshType * deformed,
              const DoubleCoordinateMeshType * target,
              const std::vector<double> &      beforeDistances,
              const std::vector<double> &      afterDistances,
              const std::string &              title,
              const std::string &              fileName);
} // namespace ffd

#endif
