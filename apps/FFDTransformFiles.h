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

// Reading ITK transform files needs ITK's transform IO libraries (ITKIOTransformBase, ITKIOTransformInsightLegacy
// and the ITKTransformFactory they load, which instantiates every transform type): linked into ffd-match, loading
// and relocating them was half of its start-up, for the few runs that read a transform file (--templates). They
// live in a module of their own, ffd-transform-files (FFDTransformFilesModule.cxx), that ffd-match loads the first
// time it reads one. Writing needs none of them (itk::MakeTextTransformFileContent()).

#include "itkTransformBase.h"

#include <string>
#include <vector>

namespace ffd
{
using TransformListType = std::vector<itk::TransformBaseTemplate<double>::Pointer>;

/** The transform files module's entry point: its name, and its type. It registers the module's transforms and ITK's
 * text transform IO (itk::RegisterFFDShapeMatchingTransforms()), checks \c fileName
 * (itk::FindProblemInTextTransformFile()) and reads it with ITK's TransformFileReaderTemplate<double>. It returns
 * true with the transforms read in \c transforms, or false with the problem in \c problem. */
constexpr const char * TransformFileReaderEntryPointName = "FFDShapeMatchingReadTransformFile";
using TransformFileReaderEntryPoint = bool (*)(const char *        fileName,
                                               TransformListType * transforms,
                                               std::string *       problem);

/** The transform files module's entry point, the module loaded (once). Throws std::runtime_error, naming the module,
 * when it cannot be loaded. */
TransformFileReaderEntryPoint
LoadTransformFileReader();

/** The transforms of the file \c fileName, read by the transform files module (loaded once). Throws
 * std::runtime_error with the problem (the module missing, or the file's problem) when they cannot be read. */
TransformListType
ReadTransformFile(const std::string & fileName);
} // namespace ffd

#endif // FFDTransformFiles_h
