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
#ifndef itkVTKSurfaceFileChecks_h
#define itkVTKSurfaceFileChecks_h

/** \file itkVTKSurfaceFileChecks.h
 * \brief Private checks of the module library (not installed): what VTK's STL, PLY and XML PolyData readers do not
 * check before they use it (sizes, counts, indices, nesting), run on a file before VTK reads it, so that a damaged
 * file gives a clear error instead of a crash, a leak or a mesh with faces on missing vertices.
 *
 * Each returns the problem found in one line, or "" when the file may be given to VTK's reader.
 *
 * \ingroup FFDShapeMatching
 */

#include <string>

class vtkXMLDataElement;

namespace itk
{
namespace detail
{
/** The problem of a binary STL file whose size does not fit its triangle count, or "". */
std::string
CheckSTLFile(const std::string & fileName);

/** The problem of a PLY file's structure, or "": the signature; the header, split into words as VTK's PLY reader
 * splits it and compared with the header VTK's own parser builds; elements and properties VTK 9.1's reader can
 * read (no list property it does not ask for, no other element's data before the vertices' and faces'); every
 * announced value; face vertex indices in range. */
std::string
CheckPLYFile(const std::string & fileName);

/** The problem of a VTP file whose XML nests too deep for VTK's parser, or "". */
std::string
CheckVTPFile(const std::string & fileName);

/** The problem of a VTP file's element tree, as VTK's XML parser read it (vtkXMLReader::UpdateInformation(), before
 * any array is read), or "": every array of every Points element (of each piece) must have 3 components, as VTK
 * 9.1's vtkXMLPolyDataReader leaks the arrays it read otherwise. Comments, entities and repeated attributes are
 * resolved by the parser, not by this check. A null root is a problem. */
std::string
CheckVTPPointsArrays(vtkXMLDataElement * root);
} // namespace detail
} // namespace itk

#endif // itkVTKSurfaceFileChecks_h
