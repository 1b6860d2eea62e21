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
#ifndef FFDTransformFiles_h
#define FFDTransformFiles_h

// The programs' transform files, through ITK's transform file reader and writer, each file checked: read after
// itk::FindProblemInTextTransformFile() has found nothing wrong with it (ITK's reader builds B-spline grids from
// unchecked values), written and read back whole (ITK's text writer does not report a failed write).

#include "itkTransformBase.h"

#include <string>
#include <vector>

namespace ffd
{
using TransformListType = std::vector<itk::TransformBaseTemplate<double>::Pointer>;

/** The transforms of the text transform file \c fileName, the module's transforms registered. Throws
 * std::runtime_error with the problem (one sentence, without the file's name) when the file is damaged or cannot be
 * read. */
TransformListType
ReadTransformFile(const std::string & fileName);

/** Writes \c transform to \c fileName with ITK's transform file writer, then reads the file back and checks that it
 * holds one transform of as many parameters. Throws std::runtime_error with the problem otherwise. */
void
WriteTransformFile(const itk::TransformBaseTemplate<double> * transform, const std::string & fileName);

/** Whether ITK's transform IO can write a file of this name (by its extension: .tfm, .txt, ...). */
bool
IsWritableTransformFileName(const std::string & fileName);
} // namespace ffd

#endif // FFDTransformFiles_h
