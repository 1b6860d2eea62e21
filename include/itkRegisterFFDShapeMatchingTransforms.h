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

#include "itkObjectFactoryBase.h"
#include "itkParametricTemplateTransform.h"
#include "itkTransformFactory.h"
#include "itkTxtTransformIOFactory.h"

#include <mutex>

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
 * Inline, so that the module's library itself links none of ITK's transform IO libraries (ITKIOTransformBase,
 * ITKIOTransformInsightLegacy, ITKTransformFactory: half of a program's start-up when loaded): a program that
 * calls it links them, as the module's dependencies they are in its link interface.
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
inline void
RegisterFFDShapeMatchingTransforms()
{
  static std::once_flag registered;
  std::call_once(registered, []() {
    TransformFactory<ParametricTemplateTransform<double, 3>>::RegisterTransform();
    TransformFactory<ParametricTemplateTransform<float, 3>>::RegisterTransform();
    // ITK's text transform IO (.tfm, .txt), which programs built without UseITK's factory registration lack.
    bool haveTextIO = false;
    for (ObjectFactoryBase * factory : ObjectFactoryBase::GetRegisteredFactories())
    {
      haveTextIO = haveTextIO || dynamic_cast<TxtTransformIOFactory *>(factory) != nullptr;
    }
    if (!haveTextIO)
    {
      TxtTransformIOFactory::RegisterOneFactory();
    }
  });
}
} // namespace itk

#endif // itkRegisterFFDShapeMatchingTransforms_h
