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
#ifndef itkRandomBSplineTransformGenerator_hxx
#define itkRandomBSplineTransformGenerator_hxx

#include "itkRandomBSplineTransformGenerator.h"
#include "itkMersenneTwisterRandomVariateGenerator.h"
#include "FFDShapeMatchingDetail/itkSpatialJacobianEvaluator.h"
#include "FFDShapeMatchingDetail/itkMatrixDeterminant.h"
#include <cmath>
#include <limits>
#include <vector>

namespace itk
{
template <typename TParametersValueType, unsigned int NDimensions>
RandomBSplineTransformGenerator<TParametersValueType, NDimensions>::RandomBSplineTransformGenerator()
{
  m_PhysicalDimensions.Fill(100.0);
  m_Transform = TransformType::New();
}

template <typename TParametersValueType, unsigned int NDimensions>
void
RandomBSplineTransformGenerator<TParametersValueType, NDimensions>::SetDomainFromImage(const ImageBaseType * image)
{
  if (image == nullptr)
  {
    itkExceptionMacro(<< "The image is null");
  }
  const auto &                         region = image->GetLargestPossibleRegion();
  ContinuousIndex<double, NDimensions> corner;
  for (unsigned int d = 0; d < NDimensions; ++d)
  {
    corner[d] = static_cast<SpacePrecisionType>(region.GetIndex()[d]) - 0.5;
    m_PhysicalDimensions[d] = static_cast<double>(region.GetSize()[d]) * image->GetSpacing()[d];
  }
  image->TransformContinuousIndexToPhysicalPoint(corner, m_Origin);
  m_Direction = image->GetDirection();
  this->Modified();
}

template <typename TParametersValueType, unsigned int NDimensions>
void
RandomBSplineTransformGenerator<TParametersValueType, NDimensions>::SetDomainFromBoundingBox(const PointType & minimum,
                                                                                             const PointType & maximum)
{
  m_Origin = minimum;
  for (unsigned int d = 0; d < NDimensions; ++d)
  {
    m_PhysicalDimensions[d] = maximum[d] - minimum[d];
  }
  m_Direction.SetIdentity();
  this->Modified();
}

template <typename TParametersValueType, unsigned int NDimensions>
void
RandomBSplineTransformGenerator<TParametersValueType, NDimensions>::Generate()
{
  for (unsigned int d = 0; d < NDimensions; ++d)
  {
    if (!(m_PhysicalDimensions[d] > 0.0))
    {
      itkExceptionMacro(<< "The domain is empty along axis " << d << ": PhysicalDimensions " << m_PhysicalDimensions);
    }
  }
  m_Transform = TransformType::New();
  typename TransformType::MeshSizeType meshSize;
  meshSize.Fill(m_NumberOfControlPointsPerAxis - 3);
  m_Transform->SetTransformDomainOrigin(m_Origin);
  m_Transform->SetTransformDomainPhysicalDimensions(m_PhysicalDimensions);
  m_Transform->SetTransformDomainDirection(m_Direction);
  m_Transform->SetTransformDomainMeshSize(meshSize);

  const SizeValueType                    numberOfParameters = m_Transform->GetNumberOfParameters();
  const SizeValueType                    numberOfControlPoints = numberOfParameters / NDimensions;
  typename TransformType::ParametersType parameters(numberOfParameters);

  auto random = Statistics::MersenneTwisterRandomVariateGenerator::New();
  random->SetSeed(m_Seed);
  if (m_Noise == NoiseEnum::ClippedGaussian)
  {
    const double variance = m_Sigma * m_Sigma;
    for (SizeValueType i = 0; i < numberOfParameters; ++i)
    {
      const double value = (variance > 0.0) ? random->GetNormalVariate(0.0, variance) : 0.0;
      parameters[i] = static_cast<TParametersValueType>(std::min(m_ClipAmplitude, std::max(-m_ClipAmplitude, value)));
    }
  }
  else
  {
    for (SizeValueType i = 0; i < numberOfParameters; ++i)
    {
      parameters[i] = static_cast<TParametersValueType>(random->GetNormalVariate(0.0, 1.0));
    }
    for (unsigned int d = 0; d < NDimensions; ++d)
    {
      this->SmoothComponent(parameters.data_block() + d * numberOfControlPoints);
    }
    double sumOfSquares = 0.0;
    for (SizeValueType i = 0; i < numberOfParameters; ++i)
    {
      sumOfSquares += static_cast<double>(parameters[i]) * static_cast<double>(parameters[i]);
    }
    const double rms = std::sqrt(sumOfSquares / static_cast<double>(numberOfControlPoints));
    const double scale = (rms > 0.0) ? m_RMSDisplacement / rms : 0.0;
    for (SizeValueType i = 0; i < numberOfParameters; ++i)
    {
      parameters[i] = static_cast<TParametersValueType>(scale * parameters[i]);
    }
  }
  m_Transform->SetParametersByValue(parameters);
  this->CheckJacobianDeterminant();
  this->Modified();
}

template <typename TParametersValueType, unsigned int NDimensions>
void
RandomBSplineTransformGenerator<TParametersValueType, NDimensions>::SmoothComponent(TParametersValueType * values) const
{
  if (!(m_SmoothingSigma > 0.0))
  {
    return;
  }
  const int           radius = static_cast<int>(std::ceil(3.0 * m_SmoothingSigma));
  std::vector<double> kernel(2 * radius + 1);
  for (int k = -radius; k <= radius; ++k)
  {
    kernel[k + radius] = std::exp(-0.5 * k * k / (m_SmoothingSigma * m_SmoothingSigma));
  }
  const SizeValueType n = m_NumberOfControlPointsPerAxis;
  SizeValueType       total = 1;
  for (unsigned int d = 0; d < NDimensions; ++d)
  {
    total *= n;
  }
  std::vector<double> line(n);
  SizeValueType       stride = 1;
  for (unsigned int axis = 0; axis < NDimensions; ++axis, stride *= n)
  {
    // Every line along this axis starts at an index whose coordinate along the axis is 0.
    for (SizeValueType start = 0; start < total; ++start)
    {
      if ((start / stride) % n != 0)
      {
        continue;
      }
      for (SizeValueType i = 0; i < n; ++i)
      {
        line[i] = static_cast<double>(values[start + i * stride]);
      }
      for (SizeValueType i = 0; i < n; ++i)
      {
        double sum = 0.0;
        double weight = 0.0;
        for (int k = -radius; k <= radius; ++k)
        {
          const long long j = static_cast<long long>(i) + k;
          if (j >= 0 && j < static_cast<long long>(n))
          {
            sum += kernel[k + radius] * line[j];
            weight += kernel[k + radius];
          }
        }
        values[start + i * stride] = static_cast<TParametersValueType>(sum / weight);
      }
    }
  }
}

template <typename TParametersValueType, unsigned int NDimensions>
void
RandomBSplineTransformGenerator<TParametersValueType, NDimensions>::CheckJacobianDeterminant()
{
  m_MinimumJacobianDeterminant = 1.0;
  m_MaximumJacobianDeterminant = 1.0;
  const unsigned int samples = m_NumberOfJacobianSamplesPerAxis;
  if (samples == 0)
  {
    return;
  }
  detail::SpatialJacobianEvaluator<TParametersValueType, NDimensions> evaluator;
  evaluator.Initialize(m_Transform.GetPointer());
  m_MinimumJacobianDeterminant = std::numeric_limits<double>::max();
  m_MaximumJacobianDeterminant = std::numeric_limits<double>::lowest();
  SizeValueType total = 1;
  for (unsigned int d = 0; d < NDimensions; ++d)
  {
    total *= samples;
  }
  typename detail::SpatialJacobianEvaluator<TParametersValueType, NDimensions>::MatrixType jacobian;
  for (SizeValueType k = 0; k < total; ++k)
  {
    Vector<double, NDimensions> local;
    SizeValueType               rest = k;
    for (unsigned int d = 0; d < NDimensions; ++d)
    {
      local[d] = (static_cast<double>(rest % samples) + 0.5) / samples * m_PhysicalDimensions[d];
      rest /= samples;
    }
    const Vector<double, NDimensions> offset = m_Direction * local;
    PointType                         point = m_Origin + offset;
    evaluator.Evaluate(point, jacobian);
    const double determinant = detail::MatrixDeterminant(jacobian);
    m_MinimumJacobianDeterminant = std::min(m_MinimumJacobianDeterminant, determinant);
    m_MaximumJacobianDeterminant = std::max(m_MaximumJacobianDeterminant, determinant);
  }
}

template <typename TParametersValueType, unsigned int NDimensions>
void
RandomBSplineTransformGenerator<TParametersValueType, NDimensions>::PrintSelf(std::ostream & os, Indent indent) const
{
  Superclass::PrintSelf(os, indent);
  os << indent << "Origin: " << m_Origin << std::endl;
  os << indent << "PhysicalDimensions: " << m_PhysicalDimensions << std::endl;
  os << indent << "Direction: " << m_Direction << std::endl;
  os << indent << "NumberOfControlPointsPerAxis: " << m_NumberOfControlPointsPerAxis << std::endl;
  os << indent << "Noise: " << m_Noise << std::endl;
  os << indent << "Sigma: " << m_Sigma << std::endl;
  os << indent << "ClipAmplitude: " << m_ClipAmplitude << std::endl;
  os << indent << "SmoothingSigma: " << m_SmoothingSigma << std::endl;
  os << indent << "RMSDisplacement: " << m_RMSDisplacement << std::endl;
  os << indent << "Seed: " << m_Seed << std::endl;
  os << indent << "NumberOfJacobianSamplesPerAxis: " << m_NumberOfJacobianSamplesPerAxis << std::endl;
  itkPrintSelfObjectMacro(Transform);
  os << indent << "MinimumJacobianDeterminant: " << m_MinimumJacobianDeterminant << std::endl;
  os << indent << "MaximumJacobianDeterminant: " << m_MaximumJacobianDeterminant << std::endl;
}
} // namespace itk

#endif // itkRandomBSplineTransformGenerator_hxx
