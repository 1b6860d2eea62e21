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
#ifndef itkRegisterFFDShapeMatchingTransforms_h
#define itkRegisterFFDShapeMatchingTransforms_h

#include "FFDShapeMatchingExport.h"

/** \file itkRegisterFFDShapeMatchingTransforms.h
 * \brief One call that makes TransformFileReader read the module's transforms.
 *
 * \ingroup FFDShapeMatching
 */

namespace itk
{
/** Registers ParametricTemplateTransform<double, 3> and ParametricTemplateTransform<float, 3> with ITK's
 * TransformFactory, once per process (later calls change nothing), so that TransformFileReaderTemplate<double>
 * and <float> create them from "ParametricTemplateTransform_double_3_3" / "_float_3_3" entries of .tfm, .txt or
 * .h5 files. It also registers ITK's text transform IO (TxtTransformIOFactory: .tfm, .txt) when no factory of
 * that type is registered yet, so programs and tests built without UseITK's automatic IO registration read and
 * write .tfm files too. Not to be called concurrently with the creation of transforms or transform IOs.
 *
 * \code
 * itk::RegisterFFDShapeMatchingTransforms();
 * auto reader = itk::TransformFileReaderTemplate<double>::New();
 * reader->SetFileName("templates.tfm");
 * reader->Update();
 * \endcode
 *
 * \sa ParametricTemplateTransform, TransformFactory
 * \ingroup FFDShapeMatching
 */
FFDShapeMatching_EXPORT void
RegisterFFDShapeMatchingTransforms();
} // namespace itk

#endif // itkRegisterFFDShapeMatchingTransforms_h
