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
#ifndef itkParametricTemplateTransform_hxx
#define itkParametricTemplateTransform_hxx

#include "itkParametricTemplateTransform.h"
#include "itkBSplineDecompositionImageFilter.h"
#include "itkTransformFileChecks.h"
#include "itkImageRegionIteratorWithIndex.h"
#include "FFDShapeMatchingDetail/itkPrincipalComponents.h"
#include "itk_eigen.h"
#include ITK_EIGEN(IterativeLinearSolvers)
#include ITK_EIGEN(Sparse)
#include <algorithm>
#include <cmath>

namespace itk
{
template <typename TParametersValueType, unsigned int NDimensions>
ParametricTemplateTransform<TParametersValueType, NDimensions>::ParametricTemplateTransform()
  : Superclass(0)
{
  m_GridTransform = BSplineTransformType::New();
  const FixedParametersType gridParameters = m_GridTransform->GetFixedParameters();
  this->SetGridFixedParameters(gridParameters);
  this->TemplatesChanged();
}

template <typename TParametersValueType, unsigned int NDimensions>
void
ParametricTemplateTransform<TParametersValueType, NDimensions>::SetTransformDomain(
  const OriginType &             origin,
  const PhysicalDimensionsType & physicalDimensions,
  const MeshSizeType &           meshSize,
  const DirectionType &          direction)
{
  auto grid = BSplineTransformType::New();
  grid->SetTransformDomainOrigin(origin);
  grid->SetTransformDomainPhysicalDimensions(physicalDimensions);
  grid->SetTransformDomainDirection(direction);
  grid->SetTransformDomainMeshSize(meshSize);
  this->SetGridFromBSplineTransform(grid);
}

template <typename TParametersValueType, unsigned int NDimensions>
void
ParametricTemplateTransform<TParametersValueType, NDimensions>::SetGridFromBSplineTransform(
  const BSplineTransformType * transform)
{
  if (transform == nullptr)
  {
    itkExceptionMacro(<< "The B-spline transform giving the grid is null");
  }
  if (this->IsOnSameGrid(transform))
  {
    return;
  }
  m_Templates.clear();
  m_Base = SparseCoefficientVector();
  this->SetGridFixedParameters(transform->GetFixedParameters());
  this->TemplatesChanged();
}

template <typename TParametersValueType, unsigned int NDimensions>
bool
ParametricTemplateTransform<TParametersValueType, NDimensions>::IsOnSameGrid(
  const BSplineTransformType * transform) const
{
  if (transform == nullptr)
  {
    return false;
  }
  const auto & other = transform->GetFixedParameters();
  const auto & mine = m_GridTransform->GetFixedParameters();
  if (other.GetSize() != mine.GetSize())
  {
    return false;
  }
  for (unsigned int i = 0; i < mine.GetSize(); ++i)
  {
    if (other[i] != mine[i])
    {
      return false;
    }
  }
  return true;
}

template <typename TParametersValueType, unsigned int NDimensions>
void
ParametricTemplateTransform<TParametersValueType, NDimensions>::SetGridFixedParameters(
  const FixedParametersType & gridParameters)
{
  if (gridParameters.GetSize() != NumberOfGridFixedParameters)
  {
    itkExceptionMacro(<< "The grid needs " << NumberOfGridFixedParameters << " fixed parameters, got "
                      << gridParameters.GetSize());
  }
  SizeValueType numberOfNodes = 1;
  for (unsigned int d = 0; d < NDimensions; ++d)
  {
    const double size = gridParameters[d];
    if (!(size >= 4.0) || size != std::floor(size) || !(gridParameters[2 * NDimensions + d] > 0.0))
    {
      itkExceptionMacro(<< "Bad grid: " << size << " control points (at least 4) and spacing "
                        << gridParameters[2 * NDimensions + d] << " along axis " << d);
    }
    numberOfNodes *= static_cast<SizeValueType>(size);
  }
  m_GridTransform->SetFixedParameters(gridParameters);
  m_NumberOfNodes = numberOfNodes;
  m_Coefficients.SetSize(NDimensions * numberOfNodes);
  m_Coefficients.Fill(0.0);
  m_GridTransform->SetParameters(m_Coefficients);
  m_JacobianEvaluator.Initialize(m_GridTransform);
}

template <typename TParametersValueType, unsigned int NDimensions>
auto
ParametricTemplateTransform<TParametersValueType, NDimensions>::MakeSparse(const CoefficientVectorType & dense)
  -> SparseCoefficientVector
{
  SparseCoefficientVector sparse;
  for (SizeValueType i = 0; i < dense.size(); ++i)
  {
    if (dense[i] != 0.0)
    {
      sparse.Indices.push_back(i);
      sparse.Values.push_back(dense[i]);
    }
  }
  return sparse;
}

template <typename TParametersValueType, unsigned int NDimensions>
void
ParametricTemplateTransform<TParametersValueType, NDimensions>::SetTemplates(
  const std::vector<CoefficientVectorType> & templates,
  TemplateSplitEnum                          split)
{
  const SizeValueType                  numberOfCoefficients = this->GetNumberOfCoefficients();
  std::vector<SparseCoefficientVector> result;
  for (SizeValueType k = 0; k < templates.size(); ++k)
  {
    if (templates[k].size() != numberOfCoefficients)
    {
      itkExceptionMacro(<< "Template " << k << " has " << templates[k].size() << " coefficients; the grid has "
                        << numberOfCoefficients);
    }
    const SparseCoefficientVector sparse = MakeSparse(templates[k]);
    if (sparse.Indices.empty())
    {
      continue;
    }
    if (split == TemplateSplitEnum::None)
    {
      result.push_back(sparse);
    }
    else if (split == TemplateSplitEnum::Axis)
    {
      // Per control point, then axis: order the non-zero components by node.
      std::vector<std::pair<SizeValueType, SizeValueType>> order; // (node * N + axis, position in sparse)
      for (SizeValueType i = 0; i < sparse.Indices.size(); ++i)
      {
        const SizeValueType axis = sparse.Indices[i] / m_NumberOfNodes;
        const SizeValueType node = sparse.Indices[i] % m_NumberOfNodes;
        order.emplace_back(node * NDimensions + axis, i);
      }
      std::sort(order.begin(), order.end());
      for (const auto & entry : order)
      {
        SparseCoefficientVector piece;
        piece.Indices.push_back(sparse.Indices[entry.second]);
        piece.Values.push_back(sparse.Values[entry.second]);
        result.push_back(piece);
      }
    }
    else
    {
      for (SizeValueType node = 0; node < m_NumberOfNodes; ++node)
      {
        SparseCoefficientVector piece;
        for (unsigned int d = 0; d < NDimensions; ++d)
        {
          const SizeValueType index = d * m_NumberOfNodes + node;
          if (templates[k][index] != 0.0)
          {
            piece.Indices.push_back(index);
            piece.Values.push_back(templates[k][index]);
          }
        }
        if (!piece.Indices.empty())
        {
          result.push_back(piece);
        }
      }
    }
  }
  if (result.empty())
  {
    itkExceptionMacro(<< "No non-zero template among the " << templates.size() << " given");
  }
  m_Templates = std::move(result);
  this->TemplatesChanged();
}

template <typename TParametersValueType, unsigned int NDimensions>
void
ParametricTemplateTransform<TParametersValueType, NDimensions>::SetSparseTemplates(
  const std::vector<SparseCoefficientVector> & templates)
{
  const SizeValueType numberOfCoefficients = this->GetNumberOfCoefficients();
  for (SizeValueType k = 0; k < templates.size(); ++k)
  {
    const auto & sparse = templates[k];
    if (sparse.Indices.size() != sparse.Values.size())
    {
      itkExceptionMacro(<< "Template " << k << " has " << sparse.Indices.size() << " indices and "
                        << sparse.Values.size() << " values");
    }
    for (SizeValueType i = 0; i < sparse.Indices.size(); ++i)
    {
      if (sparse.Indices[i] >= numberOfCoefficients || (i > 0 && sparse.Indices[i] <= sparse.Indices[i - 1]))
      {
        itkExceptionMacro(<< "Template " << k << ": coefficient indices must increase and be below "
                          << numberOfCoefficients);
      }
    }
  }
  m_Templates = templates;
  this->TemplatesChanged();
}

template <typename TParametersValueType, unsigned int NDimensions>
void
ParametricTemplateTransform<TParametersValueType, NDimensions>::SetTemplatesFromBSplineTransforms(
  const std::vector<const BSplineTransformType *> & transforms,
  TemplateSplitEnum                                 split)
{
  if (transforms.empty() || transforms[0] == nullptr)
  {
    itkExceptionMacro(<< "No B-spline transform to take templates from");
  }
  if (m_Templates.empty())
  {
    this->SetGridFromBSplineTransform(transforms[0]);
  }
  std::vector<CoefficientVectorType> templates;
  for (SizeValueType i = 0; i < transforms.size(); ++i)
  {
    if (!this->IsOnSameGrid(transforms[i]))
    {
      itkExceptionMacro(<< "B-spline transform " << i << " is not on the grid of the templates (fixed parameters "
                        << (transforms[i] ? transforms[i]->GetFixedParameters() : FixedParametersType()) << " vs "
                        << m_GridTransform->GetFixedParameters() << ")");
    }
    const auto & parameters = transforms[i]->GetParameters();
    templates.emplace_back(parameters.begin(), parameters.end());
  }
  this->SetTemplates(templates, split);
}

template <typename TParametersValueType, unsigned int NDimensions>
void
ParametricTemplateTransform<TParametersValueType, NDimensions>::SetTemplatesFromPrincipalComponents(
  const std::vector<CoefficientVectorType> & examples,
  unsigned int                               numberOfComponents)
{
  for (const auto & example : examples)
  {
    if (example.size() != this->GetNumberOfCoefficients())
    {
      itkExceptionMacro(<< "An example has " << example.size() << " coefficients; the grid has "
                        << this->GetNumberOfCoefficients());
    }
  }
  CoefficientVectorType              mean;
  std::vector<CoefficientVectorType> components;
  std::vector<double>                deviations;
  ComputePrincipalComponents(examples, numberOfComponents, mean, components, deviations);
  for (std::size_t k = 0; k < components.size(); ++k)
  {
    for (auto & value : components[k])
    {
      value *= deviations[k];
    }
  }
  this->SetTemplates(components, TemplateSplitEnum::None);
}

template <typename TParametersValueType, unsigned int NDimensions>
auto
ParametricTemplateTransform<TParametersValueType, NDimensions>::GetTemplate(SizeValueType k) const
  -> CoefficientVectorType
{
  const auto &          sparse = m_Templates.at(k);
  CoefficientVectorType dense(this->GetNumberOfCoefficients(), 0.0);
  for (SizeValueType i = 0; i < sparse.Indices.size(); ++i)
  {
    dense[sparse.Indices[i]] = sparse.Values[i];
  }
  return dense;
}

template <typename TParametersValueType, unsigned int NDimensions>
void
ParametricTemplateTransform<TParametersValueType, NDimensions>::SetBaseCoefficients(const CoefficientVectorType & base)
{
  if (base.size() != this->GetNumberOfCoefficients())
  {
    itkExceptionMacro(<< "The base has " << base.size() << " coefficients; the grid has "
                      << this->GetNumberOfCoefficients());
  }
  m_Base = MakeSparse(base);
  this->UpdateFixedParameters();
  this->UpdateCoefficients();
}

template <typename TParametersValueType, unsigned int NDimensions>
void
ParametricTemplateTransform<TParametersValueType, NDimensions>::SetBaseFromTransform(const TransformType * transform)
{
  if (transform == nullptr)
  {
    this->SetBaseCoefficients(CoefficientVectorType(this->GetNumberOfCoefficients(), 0.0));
    return;
  }
  this->SetBaseCoefficients(this->ComputeCoefficientsOfTransform(transform));
}

template <typename TParametersValueType, unsigned int NDimensions>
auto
ParametricTemplateTransform<TParametersValueType, NDimensions>::ComputeCoefficientsOfTransform(
  const TransformType * transform) const -> CoefficientVectorType
{
  if (transform == nullptr)
  {
    itkExceptionMacro(<< "The transform is null");
  }
  const auto * bspline = dynamic_cast<const BSplineTransformType *>(transform);
  if (bspline != nullptr && this->IsOnSameGrid(bspline))
  {
    const auto & parameters = bspline->GetParameters();
    return CoefficientVectorType(parameters.begin(), parameters.end());
  }
  // Sample the displacement at the control points, then B-spline-decompose each component.
  using ComponentImageType = Image<double, NDimensions>;
  const auto            grid = m_GridTransform->GetCoefficientImages()[0]; // a copy: the array is a temporary
  CoefficientVectorType coefficients(this->GetNumberOfCoefficients(), 0.0);
  for (unsigned int d = 0; d < NDimensions; ++d)
  {
    auto samples = ComponentImageType::New();
    samples->CopyInformation(grid);
    samples->SetRegions(grid->GetLargestPossibleRegion());
    samples->Allocate();
    ImageRegionIteratorWithIndex<ComponentImageType> it(samples, samples->GetLargestPossibleRegion());
    for (; !it.IsAtEnd(); ++it)
    {
      InputPointType point;
      samples->TransformIndexToPhysicalPoint(it.GetIndex(), point);
      it.Set(transform->TransformPoint(point)[d] - point[d]);
    }
    using DecompositionType = BSplineDecompositionImageFilter<ComponentImageType, ComponentImageType>;
    auto decomposition = DecompositionType::New();
    decomposition->SetSplineOrder(3);
    decomposition->SetInput(samples);
    decomposition->Update();
    const double * values = decomposition->GetOutput()->GetBufferPointer();
    std::copy(values, values + m_NumberOfNodes, coefficients.begin() + d * m_NumberOfNodes);
  }
  return coefficients;
}

template <typename TParametersValueType, unsigned int NDimensions>
auto
ParametricTemplateTransform<TParametersValueType, NDimensions>::ProjectCoefficients(
  const CoefficientVectorType & coefficients) const -> ParametersType
{
  if (coefficients.size() != this->GetNumberOfCoefficients())
  {
    itkExceptionMacro(<< "Got " << coefficients.size() << " coefficients; the grid has "
                      << this->GetNumberOfCoefficients());
  }
  // The templates as the columns of a sparse matrix A; the weights solve min |A w - (c - base)|.
  const SizeValueType                 numberOfTemplates = m_Templates.size();
  std::vector<Eigen::Triplet<double>> entries;
  Eigen::VectorXd                     target =
    Eigen::Map<const Eigen::VectorXd>(coefficients.data(), static_cast<Eigen::Index>(coefficients.size()));
  for (SizeValueType i = 0; i < m_Base.Indices.size(); ++i)
  {
    target[static_cast<Eigen::Index>(m_Base.Indices[i])] -= m_Base.Values[i];
  }
  for (SizeValueType k = 0; k < numberOfTemplates; ++k)
  {
    for (SizeValueType i = 0; i < m_Templates[k].Indices.size(); ++i)
    {
      entries.emplace_back(
        static_cast<Eigen::Index>(m_Templates[k].Indices[i]), static_cast<Eigen::Index>(k), m_Templates[k].Values[i]);
    }
  }
  Eigen::SparseMatrix<double> templates(static_cast<Eigen::Index>(coefficients.size()),
                                        static_cast<Eigen::Index>(numberOfTemplates));
  templates.setFromTriplets(entries.begin(), entries.end());
  // Conjugate gradients on the normal equations with the Jacobi preconditioner diag(A^T A).
  Eigen::LeastSquaresConjugateGradient<Eigen::SparseMatrix<double>> solver;
  solver.setMaxIterations(500);
  solver.setTolerance(1e-14);
  solver.compute(templates);
  const Eigen::VectorXd weights = solver.solve(target);
  ParametersType        result(numberOfTemplates);
  std::copy(weights.data(), weights.data() + weights.size(), result.begin());
  return result;
}

template <typename TParametersValueType, unsigned int NDimensions>
auto
ParametricTemplateTransform<TParametersValueType, NDimensions>::GetBaseCoefficients() const -> CoefficientVectorType
{
  CoefficientVectorType dense(this->GetNumberOfCoefficients(), 0.0);
  for (SizeValueType i = 0; i < m_Base.Indices.size(); ++i)
  {
    dense[m_Base.Indices[i]] = m_Base.Values[i];
  }
  return dense;
}

template <typename TParametersValueType, unsigned int NDimensions>
auto
ParametricTemplateTransform<TParametersValueType, NDimensions>::MakeBSplineTransform() const ->
  typename BSplineTransformType::Pointer
{
  auto result = BSplineTransformType::New();
  result->SetFixedParameters(m_GridTransform->GetFixedParameters());
  result->SetParametersByValue(m_Coefficients);
  return result;
}

template <typename TParametersValueType, unsigned int NDimensions>
void
ParametricTemplateTransform<TParametersValueType, NDimensions>::TemplatesChanged()
{
  // Per control point: the templates moving it and their displacement vectors there.
  std::vector<SizeValueType>                       counts(m_NumberOfNodes + 1, 0);
  std::vector<NodeEntry>                           entries;
  std::vector<std::pair<SizeValueType, NodeEntry>> unsorted;
  for (SizeValueType k = 0; k < m_Templates.size(); ++k)
  {
    const auto & sparse = m_Templates[k];
    // Group the template's entries by node (indices are sorted by axis, then node).
    std::vector<std::pair<SizeValueType, SizeValueType>> byNode;
    for (SizeValueType i = 0; i < sparse.Indices.size(); ++i)
    {
      byNode.emplace_back(sparse.Indices[i] % m_NumberOfNodes, i);
    }
    std::sort(byNode.begin(), byNode.end());
    for (SizeValueType i = 0; i < byNode.size();)
    {
      NodeEntry entry;
      entry.Template = k;
      std::fill(entry.Value, entry.Value + NDimensions, 0.0);
      const SizeValueType node = byNode[i].first;
      for (; i < byNode.size() && byNode[i].first == node; ++i)
      {
        entry.Value[sparse.Indices[byNode[i].second] / m_NumberOfNodes] = sparse.Values[byNode[i].second];
      }
      unsorted.emplace_back(node, entry);
      ++counts[node + 1];
    }
  }
  for (SizeValueType n = 0; n < m_NumberOfNodes; ++n)
  {
    counts[n + 1] += counts[n];
  }
  m_NodeOffsets = counts;
  m_NodeEntries.resize(unsorted.size());
  std::vector<SizeValueType> next(counts.begin(), counts.end() - 1);
  for (const auto & item : unsorted)
  {
    m_NodeEntries[next[item.first]++] = item.second;
  }
  if (this->m_Parameters.GetSize() != m_Templates.size())
  {
    this->m_Parameters.SetSize(m_Templates.size());
  }
  this->m_Parameters.Fill(0.0);
  this->UpdateFixedParameters();
  this->UpdateCoefficients();
}

template <typename TParametersValueType, unsigned int NDimensions>
void
ParametricTemplateTransform<TParametersValueType, NDimensions>::UpdateFixedParameters()
{
  SizeValueType size = NumberOfGridFixedParameters + 2 + 2 * m_Base.Indices.size();
  for (const auto & sparse : m_Templates)
  {
    size += 1 + 2 * sparse.Indices.size();
  }
  FixedParametersType fixed(size);
  const auto &        grid = m_GridTransform->GetFixedParameters();
  SizeValueType       position = 0;
  for (; position < NumberOfGridFixedParameters; ++position)
  {
    fixed[position] = grid[position];
  }
  fixed[position++] = static_cast<double>(m_Templates.size());
  const auto append = [&fixed, &position](const SparseCoefficientVector & sparse) {
    fixed[position++] = static_cast<double>(sparse.Indices.size());
    for (SizeValueType i = 0; i < sparse.Indices.size(); ++i)
    {
      fixed[position++] = static_cast<double>(sparse.Indices[i]);
      fixed[position++] = sparse.Values[i];
    }
  };
  append(m_Base);
  for (const auto & sparse : m_Templates)
  {
    append(sparse);
  }
  this->m_FixedParameters = fixed;
}

template <typename TParametersValueType, unsigned int NDimensions>
void
ParametricTemplateTransform<TParametersValueType, NDimensions>::UpdateCoefficients()
{
  m_Coefficients.Fill(0.0);
  for (SizeValueType i = 0; i < m_Base.Indices.size(); ++i)
  {
    m_Coefficients[m_Base.Indices[i]] = m_Base.Values[i];
  }
  for (SizeValueType k = 0; k < m_Templates.size(); ++k)
  {
    const double weight = this->m_Parameters[k];
    if (weight == 0.0)
    {
      continue;
    }
    const auto & sparse = m_Templates[k];
    for (SizeValueType i = 0; i < sparse.Indices.size(); ++i)
    {
      m_Coefficients[sparse.Indices[i]] += weight * sparse.Values[i];
    }
  }
  m_GridTransform->SetParameters(m_Coefficients);
  m_JacobianEvaluator.Initialize(m_GridTransform);
  this->Modified();
}

template <typename TParametersValueType, unsigned int NDimensions>
void
ParametricTemplateTransform<TParametersValueType, NDimensions>::SetParameters(const ParametersType & parameters)
{
  if (parameters.GetSize() != m_Templates.size())
  {
    itkExceptionMacro(<< "Got " << parameters.GetSize() << " parameters; the transform has " << m_Templates.size()
                      << " templates");
  }
  if (&parameters != &(this->m_Parameters))
  {
    this->m_Parameters = parameters;
  }
  this->UpdateCoefficients();
}

template <typename TParametersValueType, unsigned int NDimensions>
void
ParametricTemplateTransform<TParametersValueType, NDimensions>::SetFixedParameters(
  const FixedParametersType & fixedParameters)
{
  const SizeValueType size = fixedParameters.GetSize();
  if (size < NumberOfGridFixedParameters + 2)
  {
    itkExceptionMacro(<< "Too few fixed parameters (" << size << ") for a parametric-template transform");
  }
  FixedParametersType grid(NumberOfGridFixedParameters);
  for (unsigned int i = 0; i < NumberOfGridFixedParameters; ++i)
  {
    grid[i] = fixedParameters[i];
  }
  // ITK's BSplineTransform converts the grid sizes to unsigned sizes and allocates the grid without checks.
  const std::string gridProblem =
    FindProblemInBSplineFixedParameters(grid.data_block(), NumberOfGridFixedParameters, NDimensions);
  if (!gridProblem.empty())
  {
    itkExceptionMacro(<< "Bad grid in the fixed parameters: " << gridProblem);
  }
  // Parse into temporaries first: a bad vector leaves the transform unchanged.
  auto candidate = BSplineTransformType::New();
  candidate->SetFixedParameters(grid);
  SizeValueType numberOfCoefficients = NDimensions;
  for (unsigned int d = 0; d < NDimensions; ++d)
  {
    numberOfCoefficients *= static_cast<SizeValueType>(std::max(0.0, grid[d]));
  }
  SizeValueType position = NumberOfGridFixedParameters;
  const auto    readCount = [&fixedParameters, &position, size, this](const char * what) {
    if (position >= size)
    {
      itkExceptionMacro(<< "Fixed parameters end before the " << what);
    }
    const double value = fixedParameters[position++];
    // Every counted item takes at least one of the values left, so a larger count is bad (and not converted).
    if (!(value >= 0.0) || value != std::floor(value) || value > static_cast<double>(size - position))
    {
      itkExceptionMacro(<< "Bad count " << value << " of the " << what << " in the fixed parameters");
    }
    return static_cast<SizeValueType>(value);
  };
  const auto readSparse = [&](const char * what) {
    SparseCoefficientVector sparse;
    const SizeValueType     count = readCount(what);
    if (position + 2 * count > size)
    {
      itkExceptionMacro(<< "Fixed parameters end inside the " << what);
    }
    for (SizeValueType i = 0; i < count; ++i)
    {
      const double index = fixedParameters[position++];
      if (!(index >= 0.0) || index != std::floor(index) || index >= static_cast<double>(numberOfCoefficients) ||
          (!sparse.Indices.empty() && static_cast<SizeValueType>(index) <= sparse.Indices.back()))
      {
        itkExceptionMacro(<< "Bad coefficient index " << index << " in the " << what);
      }
      sparse.Indices.push_back(static_cast<SizeValueType>(index));
      sparse.Values.push_back(fixedParameters[position++]);
    }
    return sparse;
  };
  const SizeValueType                  numberOfTemplates = readCount("number of templates");
  SparseCoefficientVector              base = readSparse("base");
  std::vector<SparseCoefficientVector> templates;
  for (SizeValueType k = 0; k < numberOfTemplates; ++k)
  {
    templates.push_back(readSparse("templates"));
  }
  if (position != size)
  {
    itkExceptionMacro(<< "Fixed parameters have " << size - position << " values after the last template");
  }
  if (!this->IsOnSameGrid(candidate))
  {
    this->SetGridFixedParameters(grid);
  }
  m_Base = std::move(base);
  m_Templates = std::move(templates);
  this->TemplatesChanged();
}

template <typename TParametersValueType, unsigned int NDimensions>
void
ParametricTemplateTransform<TParametersValueType, NDimensions>::CopyInParameters(
  const ParametersValueType * const begin,
  const ParametersValueType * const end)
{
  ParametersType parameters(static_cast<SizeValueType>(end - begin));
  std::copy(begin, end, parameters.data_block());
  this->SetParameters(parameters);
}

template <typename TParametersValueType, unsigned int NDimensions>
void
ParametricTemplateTransform<TParametersValueType, NDimensions>::CopyInFixedParameters(
  const FixedParametersValueType * const begin,
  const FixedParametersValueType * const end)
{
  FixedParametersType fixedParameters(static_cast<SizeValueType>(end - begin));
  std::copy(begin, end, fixedParameters.data_block());
  this->SetFixedParameters(fixedParameters);
}

template <typename TParametersValueType, unsigned int NDimensions>
auto
ParametricTemplateTransform<TParametersValueType, NDimensions>::TransformPoint(const InputPointType & point) const
  -> OutputPointType
{
  return m_GridTransform->TransformPoint(point);
}

template <typename TParametersValueType, unsigned int NDimensions>
void
ParametricTemplateTransform<TParametersValueType, NDimensions>::ComputeJacobianWithRespectToParameters(
  const InputPointType & point,
  JacobianType &         jacobian) const
{
  jacobian.SetSize(NDimensions, this->GetNumberOfParameters());
  jacobian.Fill(0.0);
  detail::BSplineSupportArrays<BSplineTransformType> support(*m_GridTransform);
  if (!support.Evaluate(*m_GridTransform, point))
  {
    return;
  }
  const auto & weights = support.Weights;
  const auto & indices = support.Indices;
  for (unsigned int j = 0; j < weights.Size(); ++j)
  {
    const SizeValueType node = indices[j];
    const double        weight = weights[j];
    for (SizeValueType e = m_NodeOffsets[node]; e < m_NodeOffsets[node + 1]; ++e)
    {
      const NodeEntry & entry = m_NodeEntries[e];
      for (unsigned int d = 0; d < NDimensions; ++d)
      {
        jacobian(d, entry.Template) += weight * entry.Value[d];
      }
    }
  }
}

template <typename TParametersValueType, unsigned int NDimensions>
void
ParametricTemplateTransform<TParametersValueType, NDimensions>::AccumulateJacobianTransposeProduct(
  const InputPointType &   point,
  const OutputVectorType & vector,
  double                   factor,
  DerivativeType &         derivative) const
{
  if (derivative.GetSize() != this->GetNumberOfParameters())
  {
    itkExceptionMacro(<< "The derivative has " << derivative.GetSize() << " entries, not "
                      << this->GetNumberOfParameters());
  }
  detail::BSplineSupportArrays<BSplineTransformType> support(*m_GridTransform);
  if (!support.Evaluate(*m_GridTransform, point))
  {
    return;
  }
  const auto & weights = support.Weights;
  const auto & indices = support.Indices;
  for (unsigned int j = 0; j < weights.Size(); ++j)
  {
    const SizeValueType node = indices[j];
    const double        weight = factor * weights[j];
    for (SizeValueType e = m_NodeOffsets[node]; e < m_NodeOffsets[node + 1]; ++e)
    {
      const NodeEntry & entry = m_NodeEntries[e];
      double            dot = 0.0;
      for (unsigned int d = 0; d < NDimensions; ++d)
      {
        dot += entry.Value[d] * vector[d];
      }
      derivative[entry.Template] += weight * dot;
    }
  }
}

template <typename TParametersValueType, unsigned int NDimensions>
void
ParametricTemplateTransform<TParametersValueType, NDimensions>::ComputeJacobianWithRespectToPosition(
  const InputPointType & point,
  JacobianPositionType & jacobian) const
{
  typename detail::SpatialJacobianEvaluator<TParametersValueType, NDimensions>::MatrixType matrix;
  m_JacobianEvaluator.Evaluate(point, matrix);
  for (unsigned int i = 0; i < NDimensions; ++i)
  {
    for (unsigned int j = 0; j < NDimensions; ++j)
    {
      jacobian(i, j) = matrix(i, j);
    }
  }
}

template <typename TParametersValueType, unsigned int NDimensions>
void
ParametricTemplateTransform<TParametersValueType, NDimensions>::PrintSelf(std::ostream & os, Indent indent) const
{
  Superclass::PrintSelf(os, indent);
  os << indent << "GridFixedParameters: " << m_GridTransform->GetFixedParameters() << std::endl;
  os << indent << "NumberOfNodes: " << m_NumberOfNodes << std::endl;
  SizeValueType entries = 0;
  for (const auto & sparse : m_Templates)
  {
    entries += sparse.Indices.size();
  }
  os << indent << "Templates: " << m_Templates.size() << " (" << entries << " non-zero coefficients)" << std::endl;
  os << indent << "Base: " << m_Base.Indices.size() << " non-zero coefficients" << std::endl;
  os << indent << "NodeEntries: " << m_NodeEntries.size() << std::endl;
  os << indent << "Coefficients: " << m_Coefficients.GetSize() << " values" << std::endl;
}
} // namespace itk

#endif // itkParametricTemplateTransform_hxx
