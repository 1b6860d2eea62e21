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
#ifndef itkTransformFileText_h
#define itkTransformFileText_h

#include "FFDShapeMatchingExport.h"
#include "itkTransformBase.h"
#include <string>

/** \file itkTransformFileText.h
 * \brief ITK's text transform files (.tfm, .txt) written without ITK's transform IO libraries.
 *
 * ITK's TransformFileWriter needs ITK's transform IO libraries (ITKIOTransformBase and the ITKTransformFactory it
 * loads, with every transform type instantiated): loading and relocating them is half of a command-line program's
 * start-up. A program that writes text transform files only makes the file's content with
 * MakeTextTransformFileContent(), byte for byte what ITK writes, and ITK's TransformFileReader reads it as usual.
 *
 * \code
 * if (!itk::IsTextTransformFileName(fileName)) { ... }
 * std::ofstream(fileName, std::ios::binary) << itk::MakeTextTransformFileContent(*transform);
 * \endcode
 *
 * \ingroup FFDShapeMatching
 */

namespace itk
{
/** Whether ITK's text transform IO (TxtTransformIOTemplate) reads and writes \c fileName: its last extension is
 * ".tfm" or ".txt" (as ITK compares it, case-sensitively). */
FFDShapeMatching_EXPORT bool
IsTextTransformFileName(const std::string & fileName);

/** The content of the text transform file (format "#Insight Transform File V1.0") that holds \c transform: what
 * TransformFileWriterTemplate<double> writes into a .tfm or .txt file, byte for byte. Each transform is a
 * "#Transform N" comment, its "Transform:" type name, and its "Parameters:" and "FixedParameters:" (the values in
 * ITK's shortest exact decimal form, NumberToString). A CompositeTransform of dimension 2 or 3 is written as ITK
 * writes it: its type name alone, then each of its transforms in order. Throws an ExceptionObject for a composite
 * transform inside a composite transform (ITK's writer refuses it too) and for a composite of another
 * dimension. */
FFDShapeMatching_EXPORT std::string
                        MakeTextTransformFileContent(const TransformBaseTemplate<double> & transform);
} // namespace itk

#endif // itkTransformFileText_h
