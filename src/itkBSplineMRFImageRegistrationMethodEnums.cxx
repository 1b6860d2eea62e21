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
#include "itkBSplineMRFImageRegistrationMethodEnums.h"

namespace itk
{
std::ostream &
operator<<(std::ostream & out, const BSplineMRFImageRegistrationMethodEnums::Similarity value)
{
  return out << [value] {
    switch (value)
    {
      case BSplineMRFImageRegistrationMethodEnums::Similarity::MutualInformation:
        return "itk::BSplineMRFImageRegistrationMethodEnums::Similarity::MutualInformation";
      case BSplineMRFImageRegistrationMethodEnums::Similarity::SumOfSquaredDifferences:
        return "itk::BSplineMRFImageRegistrationMethodEnums::Similarity::SumOfSquaredDifferences";
      case BSplineMRFImageRegistrationMethodEnums::Similarity::SumOfAbsoluteDifferences:
        return "itk::BSplineMRFImageRegistrationMethodEnums::Similarity::SumOfAbsoluteDifferences";
      case BSplineMRFImageRegistrationMethodEnums::Similarity::NormalizedCrossCorrelation:
        return "itk::BSplineMRFImageRegistrationMethodEnums::Similarity::NormalizedCrossCorrelation";
    }
    return "INVALID VALUE FOR itk::BSplineMRFImageRegistrationMethodEnums::Similarity";
  }();
}

std::ostream &
operator<<(std::ostream & out, const BSplineMRFImageRegistrationMethodEnums::PairwiseFunction value)
{
  return out << [value] {
    switch (value)
    {
      case BSplineMRFImageRegistrationMethodEnums::PairwiseFunction::Quadratic:
        return "itk::BSplineMRFImageRegistrationMethodEnums::PairwiseFunction::Quadratic";
      case BSplineMRFImageRegistrationMethodEnums::PairwiseFunction::Absolute:
        return "itk::BSplineMRFImageRegistrationMethodEnums::PairwiseFunction::Absolute";
      case BSplineMRFImageRegistrationMethodEnums::PairwiseFunction::Truncated:
        return "itk::BSplineMRFImageRegistrationMethodEnums::PairwiseFunction::Truncated";
    }
    return "INVALID VALUE FOR itk::BSplineMRFImageRegistrationMethodEnums::PairwiseFunction";
  }();
}

std::ostream &
operator<<(std::ostream & out, const BSplineMRFImageRegistrationMethodEnums::LabelSet value)
{
  return out << [value] {
    switch (value)
    {
      case BSplineMRFImageRegistrationMethodEnums::LabelSet::Sparse:
        return "itk::BSplineMRFImageRegistrationMethodEnums::LabelSet::Sparse";
      case BSplineMRFImageRegistrationMethodEnums::LabelSet::SparseWithDiagonals:
        return "itk::BSplineMRFImageRegistrationMethodEnums::LabelSet::SparseWithDiagonals";
      case BSplineMRFImageRegistrationMethodEnums::LabelSet::Dense:
        return "itk::BSplineMRFImageRegistrationMethodEnums::LabelSet::Dense";
    }
    return "INVALID VALUE FOR itk::BSplineMRFImageRegistrationMethodEnums::LabelSet";
  }();
}
} // namespace itk
