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
#include "itkMRFLabelingSolver.h"

#include <maxflow/graph.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace itk
{
std::ostream &
operator<<(std::ostream & out, const MRFLabelingSolverEnums::Algorithm value)
{
  return out << [value] {
    switch (value)
    {
      case MRFLabelingSolverEnums::Algorithm::AlphaExpansion:
        return "itk::MRFLabelingSolverEnums::Algorithm::AlphaExpansion";
      case MRFLabelingSolverEnums::Algorithm::ICM:
        return "itk::MRFLabelingSolverEnums::Algorithm::ICM";
      case MRFLabelingSolverEnums::Algorithm::Exhaustive:
        return "itk::MRFLabelingSolverEnums::Algorithm::Exhaustive";
    }
    return "INVALID VALUE FOR itk::MRFLabelingSolverEnums::Algorithm";
  }();
}

void
MRFLabelingSolver::SetNumberOfNodes(SizeValueType numberOfNodes)
{
  if (numberOfNodes > static_cast<SizeValueType>(std::numeric_limits<int>::max()))
  {
    itkExceptionMacro(<< "Too many nodes: " << numberOfNodes);
  }
  m_NumberOfNodes = numberOfNodes;
  m_UnaryCosts.clear();
  m_Edges.clear();
  this->Modified();
}

void
MRFLabelingSolver::SetNumberOfLabels(LabelType numberOfLabels)
{
  if (numberOfLabels == 0)
  {
    itkExceptionMacro(<< "The number of labels must be at least 1");
  }
  m_NumberOfLabels = numberOfLabels;
  m_UnaryCosts.clear();
  this->Modified();
}

void
MRFLabelingSolver::SetUnaryCosts(std::vector<double> costs)
{
  if (costs.size() != m_NumberOfNodes * m_NumberOfLabels)
  {
    itkExceptionMacro(<< "Expected " << m_NumberOfNodes * m_NumberOfLabels << " unary costs (nodes x labels), got "
                      << costs.size());
  }
  m_UnaryCosts = std::move(costs);
  this->Modified();
}

SizeValueType
MRFLabelingSolver::AddEdge(SizeValueType first, SizeValueType second)
{
  if (first >= m_NumberOfNodes || second >= m_NumberOfNodes || first == second)
  {
    itkExceptionMacro(<< "Invalid edge (" << first << ", " << second << ") for " << m_NumberOfNodes << " nodes");
  }
  m_Edges.emplace_back(first, second);
  this->Modified();
  return m_Edges.size() - 1;
}

void
MRFLabelingSolver::ClearEdges()
{
  m_Edges.clear();
  this->Modified();
}

void
MRFLabelingSolver::SetPairwiseFunction(PairwiseFunctionType function)
{
  m_PairwiseFunction = std::move(function);
  this->Modified();
}

void
MRFLabelingSolver::CheckInput(const LabelingType & labeling, bool checkLabeling) const
{
  if (m_NumberOfNodes == 0)
  {
    itkExceptionMacro(<< "The graph has no node");
  }
  if (m_UnaryCosts.size() != m_NumberOfNodes * m_NumberOfLabels)
  {
    itkExceptionMacro(<< "The unary costs are not set");
  }
  if (!m_Edges.empty() && !m_PairwiseFunction)
  {
    itkExceptionMacro(<< "The graph has edges but no pairwise function");
  }
  if (!checkLabeling)
  {
    return;
  }
  if (labeling.size() != m_NumberOfNodes)
  {
    itkExceptionMacro(<< "The labeling has " << labeling.size() << " entries for " << m_NumberOfNodes << " nodes");
  }
  for (const LabelType label : labeling)
  {
    if (label >= m_NumberOfLabels)
    {
      itkExceptionMacro(<< "Label " << label << " out of range (" << m_NumberOfLabels << " labels)");
    }
  }
}

double
MRFLabelingSolver::ComputeEnergy(const LabelingType & labeling) const
{
  this->CheckInput(labeling, true);
  double energy = 0.0;
  for (SizeValueType p = 0; p < m_NumberOfNodes; ++p)
  {
    energy += m_UnaryCosts[p * m_NumberOfLabels + labeling[p]];
  }
  for (SizeValueType k = 0; k < m_Edges.size(); ++k)
  {
    energy += m_PairwiseFunction(k, labeling[m_Edges[k].first], labeling[m_Edges[k].second]);
  }
  return energy;
}

double
MRFLabelingSolver::Solve(LabelingType & labeling)
{
  m_NumberOfCyclesPerformed = 0;
  m_NumberOfAcceptedMoves = 0;
  m_NumberOfTruncatedTerms = 0;
  if (m_Algorithm == AlgorithmEnum::Exhaustive)
  {
    this->CheckInput(labeling, false);
    return this->SolveExhaustive(labeling);
  }
  this->CheckInput(labeling, true);
  if (m_Algorithm == AlgorithmEnum::ICM)
  {
    return this->SolveICM(labeling);
  }
  return this->SolveAlphaExpansion(labeling);
}

double
MRFLabelingSolver::SolveAlphaExpansion(LabelingType & labeling)
{
  using GraphType = maxflow::Graph<double, double, double>;
  const auto numberOfNodes = static_cast<int>(m_NumberOfNodes);
  GraphType  graph(numberOfNodes,
                  static_cast<int>(std::max<SizeValueType>(m_Edges.size(), 1)),
                  [](const char * message) { itkGenericExceptionMacro(<< "Max-flow error: " << message); });
  m_NodeEdges.assign(m_NumberOfNodes, {});
  for (SizeValueType k = 0; k < m_Edges.size(); ++k)
  {
    m_NodeEdges[m_Edges[k].first].push_back(k);
    m_NodeEdges[m_Edges[k].second].push_back(k);
  }
  // The pairwise cost of every edge under the current labeling, kept up to date.
  std::vector<double> edgeCost(m_Edges.size());
  for (SizeValueType k = 0; k < m_Edges.size(); ++k)
  {
    edgeCost[k] = m_PairwiseFunction(k, labeling[m_Edges[k].first], labeling[m_Edges[k].second]);
  }
  std::vector<double>        keepCost(m_NumberOfNodes);
  std::vector<double>        switchCost(m_NumberOfNodes);
  std::vector<SizeValueType> changedNodes;
  std::vector<SizeValueType> touchedEdges;
  std::vector<double>        touchedCosts;
  std::vector<unsigned int>  edgeStamp(m_Edges.size(), 0);
  unsigned int               stamp = 0;
  double                     energy = this->ComputeEnergy(labeling);

  for (unsigned int cycle = 0; cycle < m_MaximumNumberOfCycles; ++cycle)
  {
    ++m_NumberOfCyclesPerformed;
    bool improved = false;
    for (LabelType alpha = 0; alpha < m_NumberOfLabels; ++alpha)
    {
      graph.reset();
      graph.add_node(numberOfNodes);
      for (SizeValueType p = 0; p < m_NumberOfNodes; ++p)
      {
        keepCost[p] = m_UnaryCosts[p * m_NumberOfLabels + labeling[p]];
        switchCost[p] = m_UnaryCosts[p * m_NumberOfLabels + alpha];
      }
      for (SizeValueType k = 0; k < m_Edges.size(); ++k)
      {
        const SizeValueType p = m_Edges[k].first;
        const SizeValueType q = m_Edges[k].second;
        if (labeling[p] == alpha && labeling[q] == alpha)
        {
          continue; // every configuration costs the same
        }
        // y = 0 keeps the label, y = 1 switches to alpha: A = E(0,0), B = E(0,1), C = E(1,0), D = E(1,1).
        const double a = edgeCost[k];
        const double d = m_PairwiseFunction(k, alpha, alpha);
        double b = labeling[q] == alpha ? a : (labeling[p] == alpha ? d : m_PairwiseFunction(k, labeling[p], alpha));
        double c = labeling[p] == alpha ? a : (labeling[q] == alpha ? d : m_PairwiseFunction(k, alpha, labeling[q]));
        double coupling = b + c - a - d;
        if (coupling < 0.0)
        {
          // Not submodular: raise the mixed terms (truncation); the true energy decides acceptance below.
          b -= 0.5 * coupling;
          c -= 0.5 * coupling;
          coupling = 0.0;
          ++m_NumberOfTruncatedTerms;
        }
        // E = A + (C - A) y_p + (D - C) y_q + (B + C - A - D) (1 - y_p) y_q
        switchCost[p] += c - a;
        switchCost[q] += d - c;
        if (coupling > 0.0)
        {
          graph.add_edge(static_cast<int>(p), static_cast<int>(q), coupling, 0.0);
        }
      }
      for (SizeValueType p = 0; p < m_NumberOfNodes; ++p)
      {
        // The source capacity is paid when the node ends in the sink set (y = 1), and conversely.
        graph.add_tweights(static_cast<int>(p), switchCost[p], keepCost[p]);
      }
      graph.maxflow();

      // The true energy change of the move, over the switched nodes and their edges.
      changedNodes.clear();
      double delta = 0.0;
      for (SizeValueType p = 0; p < m_NumberOfNodes; ++p)
      {
        if (labeling[p] != alpha && graph.what_segment(static_cast<int>(p)) == GraphType::SINK)
        {
          changedNodes.push_back(p);
          delta += m_UnaryCosts[p * m_NumberOfLabels + alpha] - m_UnaryCosts[p * m_NumberOfLabels + labeling[p]];
        }
      }
      if (changedNodes.empty())
      {
        continue;
      }
      std::vector<LabelType> previous(changedNodes.size());
      for (size_t i = 0; i < changedNodes.size(); ++i)
      {
        previous[i] = labeling[changedNodes[i]];
        labeling[changedNodes[i]] = alpha;
      }
      ++stamp;
      touchedEdges.clear();
      touchedCosts.clear();
      for (const SizeValueType p : changedNodes)
      {
        for (const SizeValueType k : m_NodeEdges[p])
        {
          if (edgeStamp[k] == stamp)
          {
            continue;
          }
          edgeStamp[k] = stamp;
          const double cost = m_PairwiseFunction(k, labeling[m_Edges[k].first], labeling[m_Edges[k].second]);
          delta += cost - edgeCost[k];
          touchedEdges.push_back(k);
          touchedCosts.push_back(cost);
        }
      }
      if (delta < -1e-12 * std::max(1.0, std::abs(energy)))
      {
        for (size_t i = 0; i < touchedEdges.size(); ++i)
        {
          edgeCost[touchedEdges[i]] = touchedCosts[i];
        }
        energy += delta;
        improved = true;
        ++m_NumberOfAcceptedMoves;
      }
      else
      {
        for (size_t i = 0; i < changedNodes.size(); ++i)
        {
          labeling[changedNodes[i]] = previous[i];
        }
      }
    }
    if (!improved)
    {
      break;
    }
  }
  m_NodeEdges.clear();
  // Recomputed exactly, free of the accumulated rounding of the updates.
  return this->ComputeEnergy(labeling);
}

double
MRFLabelingSolver::SolveICM(LabelingType & labeling)
{
  m_NodeEdges.assign(m_NumberOfNodes, {});
  for (SizeValueType k = 0; k < m_Edges.size(); ++k)
  {
    m_NodeEdges[m_Edges[k].first].push_back(k);
    m_NodeEdges[m_Edges[k].second].push_back(k);
  }
  for (unsigned int sweep = 0; sweep < m_MaximumNumberOfCycles; ++sweep)
  {
    ++m_NumberOfCyclesPerformed;
    bool changed = false;
    for (SizeValueType p = 0; p < m_NumberOfNodes; ++p)
    {
      const auto localEnergy = [this, &labeling, p](LabelType label) {
        double value = m_UnaryCosts[p * m_NumberOfLabels + label];
        for (const SizeValueType k : m_NodeEdges[p])
        {
          const EdgeType & edge = m_Edges[k];
          value += edge.first == p ? m_PairwiseFunction(k, label, labeling[edge.second])
                                   : m_PairwiseFunction(k, labeling[edge.first], label);
        }
        return value;
      };
      LabelType best = labeling[p];
      double    bestValue = localEnergy(best);
      for (LabelType label = 0; label < m_NumberOfLabels; ++label)
      {
        const double value = localEnergy(label);
        if (value < bestValue - 1e-12 * std::max(1.0, std::abs(bestValue)))
        {
          best = label;
          bestValue = value;
        }
      }
      if (best != labeling[p])
      {
        labeling[p] = best;
        changed = true;
      }
    }
    if (!changed)
    {
      break;
    }
  }
  m_NodeEdges.clear();
  return this->ComputeEnergy(labeling);
}

double
MRFLabelingSolver::SolveExhaustive(LabelingType & labeling)
{
  const double count = std::pow(static_cast<double>(m_NumberOfLabels), static_cast<double>(m_NumberOfNodes));
  if (count > 16777216.0)
  {
    itkExceptionMacro(<< "Exhaustive search over " << count << " labelings refused (at most 2^24)");
  }
  LabelingType current(m_NumberOfNodes, 0);
  LabelingType best(current);
  double       bestEnergy = this->ComputeEnergy(current);
  while (true)
  {
    SizeValueType p = 0;
    while (p < m_NumberOfNodes && ++current[p] == m_NumberOfLabels)
    {
      current[p] = 0;
      ++p;
    }
    if (p == m_NumberOfNodes)
    {
      break;
    }
    const double energy = this->ComputeEnergy(current);
    if (energy < bestEnergy)
    {
      bestEnergy = energy;
      best = current;
    }
  }
  labeling = best;
  m_NumberOfCyclesPerformed = 1;
  return bestEnergy;
}

void
MRFLabelingSolver::PrintSelf(std::ostream & os, Indent indent) const
{
  Superclass::PrintSelf(os, indent);
  os << indent << "NumberOfNodes: " << m_NumberOfNodes << std::endl;
  os << indent << "NumberOfLabels: " << m_NumberOfLabels << std::endl;
  os << indent << "UnaryCosts: " << m_UnaryCosts.size() << " values" << std::endl;
  os << indent << "Edges: " << m_Edges.size() << std::endl;
  os << indent << "PairwiseFunction: " << (m_PairwiseFunction ? "set" : "not set") << std::endl;
  os << indent << "Algorithm: " << m_Algorithm << std::endl;
  os << indent << "MaximumNumberOfCycles: " << m_MaximumNumberOfCycles << std::endl;
  os << indent << "NumberOfCyclesPerformed: " << m_NumberOfCyclesPerformed << std::endl;
  os << indent << "NumberOfAcceptedMoves: " << m_NumberOfAcceptedMoves << std::endl;
  os << indent << "NumberOfTruncatedTerms: " << m_NumberOfTruncatedTerms << std::endl;
  os << indent << "NodeEdges: " << m_NodeEdges.size() << std::endl;
}
} // namespace itk
