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

#include "itkTransformFileText.h"
#include "itkCompositeTransform.h"
#include "itkNumberToString.h"
#include "itksys/SystemTools.hxx"

#include <vector>

namespace itk
{
namespace
{
using TransformBaseType = TransformBaseTemplate<double>;

bool
IsCompositeTypeName(const std::string & typeName)
{
  return typeName.find("CompositeTransform") != std::string::npos;
}

// The transforms of a composite of dimension TDimension, in the order ITK's writer lists them; false when
// \c transform is not one.
template <unsigned int TDimension>
bool
AppendCompositeParts(const TransformBaseType & transform, std::vector<const TransformBaseType *> & parts)
{
  const auto * composite = dynamic_cast<const CompositeTransform<double, TDimension> *>(&transform);
  if (composite == nullptr)
  {
    return false;
  }
  for (unsigned int i = 0; i < composite->GetNumberOfTransforms(); ++i)
  {
    parts.push_back(composite->GetNthTransformConstPointer(i));
  }
  return true;
}

template <typename TArray>
void
AppendValues(std::string & text, const char * name, const TArray & values)
{
  NumberToString<double> convert;
  text += name;
  for (unsigned int i = 0; i < values.Size(); ++i)
  {
    if (i > 0)
    {
      text += ' ';
    }
    text += convert(values[i]);
  }
  text += '\n';
}
} // namespace

bool
IsTextTransformFileName(const std::string & fileName)
{
  const std::string extension = itksys::SystemTools::GetFilenameLastExtension(fileName);
  return extension == ".tfm" || extension == ".txt";
}

std::string
MakeTextTransformFileContent(const TransformBaseType & transform)
{
  std::vector<const TransformBaseType *> list{ &transform };
  if (IsCompositeTypeName(transform.GetTransformTypeAsString()) && !AppendCompositeParts<3>(transform, list) &&
      !AppendCompositeParts<2>(transform, list))
  {
    itkGenericExceptionMacro("cannot write " << transform.GetTransformTypeAsString()
                                             << " as text: only composite transforms of dimension 2 or 3");
  }
  std::string text = "#Insight Transform File V1.0\n";
  for (std::size_t i = 0; i < list.size(); ++i)
  {
    const std::string typeName = list[i]->GetTransformTypeAsString();
    text += "#Transform " + std::to_string(i) + "\nTransform: " + typeName + '\n';
    if (IsCompositeTypeName(typeName))
    {
      if (i > 0)
      {
        itkGenericExceptionMacro("cannot write "
                                 << transform.GetTransformTypeAsString()
                                 << " as text: a composite transform holds another composite transform");
      }
      continue;
    }
    AppendValues(text, "Parameters: ", list[i]->GetParameters());
    AppendValues(text, "FixedParameters: ", list[i]->GetFixedParameters());
  }
  return text;
}
} // namespace itk
