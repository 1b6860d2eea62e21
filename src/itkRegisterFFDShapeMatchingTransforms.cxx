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
#include "itkRegisterFFDShapeMatchingTransforms.h"
#include "itkParametricTemplateTransform.h"
#include "itkObjectFactoryBase.h"
#include "itkTransformFactory.h"
#include "itkTxtTransformIOFactory.h"
#include <mutex>

namespace itk
{
void
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
