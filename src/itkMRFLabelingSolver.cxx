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

#include <boost/graph/adjacency_list.hpp>
#include <boost/graph/boykov_kolmogorov_max_flow.hpp>
#include <boost/graph/compressed_sparse_row_graph.hpp>
#include <boost/graph/kruskal_min_spanning_tree.hpp>
#include <boost/property_map/property_map.hpp>
#include <boost/range/iterator_range.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <iterator>
#include <limits>

namespace itk
{
namespace
{
/** The graph of an alpha-expansion move, for Boost Graph's Boykov-Kolmogorov max-flow: the nodes, a source and a
 * sink, and for every node both terminal arcs and for every edge both directions, each arc paired with its reverse.
 * The topology is built once (compressed sparse rows) and serves every move: a move only sets the capacities,
 * zero where the move has no term. Arc pairs: node p's source arcs (s->p, p->s) are pair p, its sink arcs
 * (p->t, t->p) pair N + p, edge k's arcs (first->second, second->first) pair 2N + k; in a pair, the even arc is
 * the forward one. */
class ExpansionGraph
{
public:
  using GraphType = boost::compressed_sparse_row_graph<boost::directedS, boost::no_property, SizeValueType>;
  using VertexType = boost::graph_traits<GraphType>::vertex_descriptor;
  using ArcType = boost::graph_traits<GraphType>::edge_descriptor;

  ExpansionGraph(SizeValueType numberOfNodes, const std::vector<MRFLabelingSolver::EdgeType> & edges)
    : m_NumberOfNodes(numberOfNodes)
    , m_Source(static_cast<VertexType>(numberOfNodes))
    , m_Sink(static_cast<VertexType>(numberOfNodes + 1))
  {
    const SizeValueType                            numberOfArcs = 2 * (2 * numberOfNodes + edges.size());
    std::vector<std::pair<VertexType, VertexType>> arcs(numberOfArcs);
    std::vector<SizeValueType>                     arcNumbers(numberOfArcs);
    const auto setPair = [&arcs, &arcNumbers](SizeValueType pair, VertexType from, VertexType to) {
      arcs[2 * pair] = { from, to };
      arcs[2 * pair + 1] = { to, from };
      arcNumbers[2 * pair] = 2 * pair;
      arcNumbers[2 * pair + 1] = 2 * pair + 1;
    };
    for (SizeValueType p = 0; p < numberOfNodes; ++p)
    {
      setPair(p, m_Source, static_cast<VertexType>(p));
      setPair(numberOfNodes + p, static_cast<VertexType>(p), m_Sink);
    }
    for (SizeValueType k = 0; k < edges.size(); ++k)
    {
      setPair(2 * numberOfNodes + k, static_cast<VertexType>(edges[k].first), static_cast<VertexType>(edges[k].second));
    }
    // The graph stores the arcs grouped by tail; each keeps its number as its property.
    m_Graph = GraphType(boost::edges_are_unsorted_multi_pass,
                        arcs.begin(),
                        arcs.end(),
                        arcNumbers.begin(),
                        static_cast<VertexType>(numberOfNodes + 2));
    m_ArcOf.resize(numberOfArcs);
    for (const ArcType arc : boost::make_iterator_range(boost::edges(m_Graph)))
    {
      m_ArcOf[m_Graph[arc]] = arc;
    }
    m_Reverse.resize(numberOfArcs);
    for (SizeValueType number = 0; number < numberOfArcs; ++number)
    {
      m_Reverse[this->Index(m_ArcOf[number])] = m_ArcOf[number ^ 1];
    }
    m_Capacity.assign(numberOfArcs, 0.0);
    m_Residual.assign(numberOfArcs, 0.0);
    m_Predecessor.resize(numberOfNodes + 2);
    m_Color.resize(numberOfNodes + 2);
    m_Distance.resize(numberOfNodes + 2);
  }

  /** Clears all capacities before a move. */
  void
  Reset()
  {
    std::fill(m_Capacity.begin(), m_Capacity.end(), 0.0);
  }

  /** Terminal term of node p: \c cost is paid when p ends on the sink side (the source arc) if positive, its
   * opposite when p ends on the source side (the sink arc) if negative. */
  void
  SetTerminalCapacity(SizeValueType p, double cost)
  {
    if (cost > 0.0)
    {
      m_Capacity[this->Index(m_ArcOf[2 * p])] = cost;
    }
    else if (cost < 0.0)
    {
      m_Capacity[this->Index(m_ArcOf[2 * (m_NumberOfNodes + p)])] = -cost;
    }
  }

  /** Capacity of edge k from its first to its second node (paid when the first is on the source side and the
   * second on the sink side). */
  void
  SetEdgeCapacity(SizeValueType k, double capacity)
  {
    m_Capacity[this->Index(m_ArcOf[2 * (2 * m_NumberOfNodes + k)])] = capacity;
  }

  void
  Cut()
  {
    const auto arcIndex = boost::get(boost::edge_index, m_Graph);
    const auto vertexIndex = boost::get(boost::vertex_index, m_Graph);
    boost::boykov_kolmogorov_max_flow(m_Graph,
                                      boost::make_iterator_property_map(m_Capacity.begin(), arcIndex),
                                      boost::make_iterator_property_map(m_Residual.begin(), arcIndex),
                                      boost::make_iterator_property_map(m_Reverse.begin(), arcIndex),
                                      boost::make_iterator_property_map(m_Predecessor.begin(), vertexIndex),
                                      boost::make_iterator_property_map(m_Color.begin(), vertexIndex),
                                      boost::make_iterator_property_map(m_Distance.begin(), vertexIndex),
                                      vertexIndex,
                                      m_Source,
                                      m_Sink);
  }

  /** Whether node p ends in the sink's search tree. The nodes in neither tree (free) join the source side, so the
   * sink side is the smallest of the minimum cuts' sink sides: a move changes as few labels as it can. */
  bool
  IsOnSinkSide(SizeValueType p) const
  {
    return m_Color[p] == boost::color_traits<boost::default_color_type>::white();
  }

private:
  SizeValueType
  Index(const ArcType & arc) const
  {
    return boost::get(boost::edge_index, m_Graph, arc);
  }

  SizeValueType                          m_NumberOfNodes;
  VertexType                             m_Source;
  VertexType                             m_Sink;
  GraphType                              m_Graph;
  std::vector<ArcType>                   m_ArcOf;   // CSR arc of each arc number
  std::vector<ArcType>                   m_Reverse; // by CSR arc index
  std::vector<double>                    m_Capacity;
  std::vector<double>                    m_Residual;
  std::vector<ArcType>                   m_Predecessor;
  std::vector<boost::default_color_type> m_Color;
  std::vector<long>                      m_Distance;
};
} // namespace

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
      case MRFLabelingSolverEnums::Algorithm::SpanningTree:
        return "itk::MRFLabelingSolverEnums::Algorithm::SpanningTree";
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
  this->ClearGraphCaches();
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
  this->ClearGraphCaches();
  this->Modified();
  return m_Edges.size() - 1;
}

void
MRFLabelingSolver::ClearEdges()
{
  m_Edges.clear();
  this->ClearGraphCaches();
  this->Modified();
}

void
MRFLabelingSolver::SetPairwiseFunction(PairwiseFunctionType function)
{
  m_PairwiseFunction = std::move(function);
  m_QuadraticWeight = -1.0;
  m_LabelVectors.clear();
  m_EdgeOffsets.clear();
  this->Modified();
}

void
MRFLabelingSolver::SetQuadraticPairwise(std::vector<VectorType> labelVectors,
                                        std::vector<VectorType> edgeOffsets,
                                        double                  weight)
{
  if (!(weight >= 0.0) || !std::isfinite(weight))
  {
    itkExceptionMacro(<< "The quadratic pairwise weight must be finite and >= 0, is " << weight);
  }
  m_LabelVectors = std::move(labelVectors);
  m_EdgeOffsets = std::move(edgeOffsets);
  m_QuadraticWeight = weight;
  m_PairwiseFunction = nullptr;
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
  if (m_QuadraticWeight >= 0.0)
  {
    if (m_LabelVectors.size() != m_NumberOfLabels || m_EdgeOffsets.size() != m_Edges.size())
    {
      itkExceptionMacro(<< "The quadratic pairwise model has " << m_LabelVectors.size() << " label vectors and "
                        << m_EdgeOffsets.size() << " edge offsets for " << m_NumberOfLabels << " labels and "
                        << m_Edges.size() << " edges");
    }
  }
  else if (!m_Edges.empty() && !m_PairwiseFunction)
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
    energy += this->Pairwise(k, labeling[m_Edges[k].first], labeling[m_Edges[k].second]);
  }
  return energy;
}

bool
MRFLabelingSolver::IsPastTimeLimit()
{
  if (m_MaximumRunTime > 0.0 && !m_TimeLimitReached &&
      std::chrono::duration<double>(std::chrono::steady_clock::now() - m_StartTime).count() > m_MaximumRunTime)
  {
    m_TimeLimitReached = true;
  }
  return m_TimeLimitReached;
}

double
MRFLabelingSolver::Solve(LabelingType & labeling)
{
  m_StartTime = std::chrono::steady_clock::now();
  m_TimeLimitReached = false;
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
  if (m_Algorithm == AlgorithmEnum::SpanningTree)
  {
    return this->SolveSpanningTree(labeling);
  }
  return this->SolveAlphaExpansion(labeling);
}

double
MRFLabelingSolver::SolveAlphaExpansion(LabelingType & labeling)
{
  ExpansionGraph graph(m_NumberOfNodes, m_Edges);
  this->UpdateNodeEdges();
  // The pairwise cost of every edge under the current labeling, kept up to date.
  std::vector<double> edgeCost(m_Edges.size());
  for (SizeValueType k = 0; k < m_Edges.size(); ++k)
  {
    edgeCost[k] = this->Pairwise(k, labeling[m_Edges[k].first], labeling[m_Edges[k].second]);
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
    for (LabelType alpha = 0; alpha < m_NumberOfLabels && !this->IsPastTimeLimit(); ++alpha)
    {
      graph.Reset();
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
        const double d = this->Pairwise(k, alpha, alpha);
        double       b = labeling[q] == alpha ? a : (labeling[p] == alpha ? d : this->Pairwise(k, labeling[p], alpha));
        double       c = labeling[p] == alpha ? a : (labeling[q] == alpha ? d : this->Pairwise(k, alpha, labeling[q]));
        double       coupling = b + c - a - d;
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
          graph.SetEdgeCapacity(k, coupling);
        }
      }
      for (SizeValueType p = 0; p < m_NumberOfNodes; ++p)
      {
        // The switch cost is paid when the node ends on the sink side (y = 1), the keep cost on the source side;
        // only their difference matters to the cut.
        graph.SetTerminalCapacity(p, switchCost[p] - keepCost[p]);
      }
      graph.Cut();

      // The true energy change of the move, over the switched nodes and their edges.
      changedNodes.clear();
      double delta = 0.0;
      for (SizeValueType p = 0; p < m_NumberOfNodes; ++p)
      {
        if (labeling[p] != alpha && graph.IsOnSinkSide(p))
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
        for (const SizeValueType k : this->NodeEdges(p))
        {
          if (edgeStamp[k] == stamp)
          {
            continue;
          }
          edgeStamp[k] = stamp;
          const double cost = this->Pairwise(k, labeling[m_Edges[k].first], labeling[m_Edges[k].second]);
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
    if (!improved || m_TimeLimitReached)
    {
      break;
    }
  }
  // Recomputed exactly, free of the accumulated rounding of the updates.
  return this->ComputeEnergy(labeling);
}

double
MRFLabelingSolver::SolveICM(LabelingType & labeling)
{
  this->SweepICM(labeling, m_MaximumNumberOfCycles);
  return this->ComputeEnergy(labeling);
}

void
MRFLabelingSolver::SweepICM(LabelingType & labeling, unsigned int maximumNumberOfSweeps)
{
  this->UpdateNodeEdges();
  const bool          quadratic = m_QuadraticWeight >= 0.0;
  std::vector<double> labelSquaredNorms(quadratic ? m_NumberOfLabels : 0);
  for (LabelType label = 0; quadratic && label < m_NumberOfLabels; ++label)
  {
    const VectorType & v = m_LabelVectors[label];
    labelSquaredNorms[label] = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
  }
  for (unsigned int sweep = 0; sweep < maximumNumberOfSweeps; ++sweep)
  {
    ++m_NumberOfCyclesPerformed;
    bool changed = false;
    for (SizeValueType p = 0; p < m_NumberOfNodes && !this->IsPastTimeLimit(); ++p)
    {
      // Quadratic model: each edge's term is w |v_label + c|^2 with c fixed by the neighbour's label (c = o - v_n
      // when p is the edge's first node, -(o + v_n) when it is the second), so the sum over p's edges is
      // w (degree |v_label|^2 + 2 v_label . sum(c) + sum(|c|^2)): O(1) per label instead of O(degree).
      double sumC[3] = { 0.0, 0.0, 0.0 };
      double sumSquaredC = 0.0;
      if (quadratic)
      {
        for (const SizeValueType k : this->NodeEdges(p))
        {
          const EdgeType &   edge = m_Edges[k];
          const VectorType & o = m_EdgeOffsets[k];
          const bool         first = edge.first == p;
          const VectorType & v = m_LabelVectors[labeling[first ? edge.second : edge.first]];
          for (unsigned int d = 0; d < 3; ++d)
          {
            const double c = first ? o[d] - v[d] : -(o[d] + v[d]);
            sumC[d] += c;
            sumSquaredC += c * c;
          }
        }
      }
      const double degree = static_cast<double>(this->NodeEdges(p).size());
      const auto   localEnergy = [&, p](LabelType label) {
        double value = m_UnaryCosts[p * m_NumberOfLabels + label];
        if (quadratic)
        {
          const VectorType & v = m_LabelVectors[label];
          return value + m_QuadraticWeight * (degree * labelSquaredNorms[label] +
                                              2.0 * (v[0] * sumC[0] + v[1] * sumC[1] + v[2] * sumC[2]) + sumSquaredC);
        }
        for (const SizeValueType k : this->NodeEdges(p))
        {
          const EdgeType & edge = m_Edges[k];
          value += edge.first == p ? this->Pairwise(k, label, labeling[edge.second])
                                     : this->Pairwise(k, labeling[edge.first], label);
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
    if (!changed || m_TimeLimitReached)
    {
      break;
    }
  }
}

void
MRFLabelingSolver::UpdateNodeEdges()
{
  if (m_NodeEdgeOffsets.size() == m_NumberOfNodes + 1)
  {
    return;
  }
  m_NodeEdgeOffsets.assign(m_NumberOfNodes + 1, 0);
  for (const EdgeType & edge : m_Edges)
  {
    ++m_NodeEdgeOffsets[edge.first + 1];
    ++m_NodeEdgeOffsets[edge.second + 1];
  }
  for (SizeValueType p = 0; p < m_NumberOfNodes; ++p)
  {
    m_NodeEdgeOffsets[p + 1] += m_NodeEdgeOffsets[p];
  }
  m_NodeEdgeIndices.resize(2 * m_Edges.size());
  std::vector<SizeValueType> next(m_NodeEdgeOffsets.begin(), m_NodeEdgeOffsets.end() - 1);
  for (SizeValueType k = 0; k < m_Edges.size(); ++k)
  {
    m_NodeEdgeIndices[next[m_Edges[k].first]++] = k;
    m_NodeEdgeIndices[next[m_Edges[k].second]++] = k;
  }
}

void
MRFLabelingSolver::ComputeSpanningTree()
{
  // Kruskal's minimum spanning forest (Boost Graph) over the edges weighted by how much their two nodes' unary
  // costs differ: the tree keeps the couplings of nodes whose data agree.
  using EdgeProperties =
    boost::property<boost::edge_weight_t, double, boost::property<boost::edge_index_t, SizeValueType>>;
  using GraphType = boost::adjacency_list<boost::vecS,
                                          boost::vecS,
                                          boost::undirectedS,
                                          boost::no_property,
                                          EdgeProperties,
                                          boost::no_property,
                                          boost::vecS>;
  GraphType graph(m_NumberOfNodes);
  for (SizeValueType k = 0; k < m_Edges.size(); ++k)
  {
    const double * first = &m_UnaryCosts[m_Edges[k].first * m_NumberOfLabels];
    const double * second = &m_UnaryCosts[m_Edges[k].second * m_NumberOfLabels];
    double         difference = 0.0;
    for (LabelType l = 0; l < m_NumberOfLabels; ++l)
    {
      difference += std::abs(first[l] - second[l]);
    }
    boost::add_edge(m_Edges[k].first, m_Edges[k].second, EdgeProperties(difference, k), graph);
  }
  std::vector<boost::graph_traits<GraphType>::edge_descriptor> tree;
  boost::kruskal_minimum_spanning_tree(graph, std::back_inserter(tree));
  // The tree's edges in increasing index order.
  std::vector<std::uint8_t> inTree(m_Edges.size(), 0);
  for (const auto & treeEdge : tree)
  {
    inTree[boost::get(boost::edge_index, graph, treeEdge)] = 1;
  }
  m_SpanningTreeEdges.clear();
  m_SpanningTreeEdges.reserve(tree.size());
  for (SizeValueType k = 0; k < m_Edges.size(); ++k)
  {
    if (inTree[k])
    {
      m_SpanningTreeEdges.push_back(k);
    }
  }

  // Root each tree of the forest at its first node; order the nodes breadth first (a node's tree edges in
  // increasing index order), each with the edge to its parent.
  this->UpdateNodeEdges();
  constexpr SizeValueType   none = std::numeric_limits<SizeValueType>::max();
  std::vector<std::uint8_t> visited(m_NumberOfNodes, 0);
  m_SpanningTreeParentEdge.assign(m_NumberOfNodes, none);
  m_SpanningTreeOrder.clear();
  m_SpanningTreeOrder.reserve(m_NumberOfNodes);
  for (SizeValueType root = 0; root < m_NumberOfNodes; ++root)
  {
    if (visited[root])
    {
      continue;
    }
    visited[root] = 1;
    size_t head = m_SpanningTreeOrder.size();
    m_SpanningTreeOrder.push_back(root);
    for (; head < m_SpanningTreeOrder.size(); ++head)
    {
      const SizeValueType p = m_SpanningTreeOrder[head];
      for (const SizeValueType k : this->NodeEdges(p))
      {
        const SizeValueType q = m_Edges[k].first == p ? m_Edges[k].second : m_Edges[k].first;
        if (inTree[k] && !visited[q])
        {
          visited[q] = 1;
          m_SpanningTreeParentEdge[q] = k;
          m_SpanningTreeOrder.push_back(q);
        }
      }
    }
  }
}

double
MRFLabelingSolver::SolveSpanningTree(LabelingType & labeling)
{
  const LabelingType start = labeling;
  const double       startEnergy = this->ComputeEnergy(labeling);
  if (!m_ReuseSpanningTree || m_SpanningTreeEdges.empty())
  {
    this->ComputeSpanningTree();
  }

  constexpr SizeValueType none = std::numeric_limits<SizeValueType>::max();
  const auto &            order = m_SpanningTreeOrder;
  const auto &            parentEdge = m_SpanningTreeParentEdge;

  // Upward pass (min-sum): belief(c) = unary(c) + the messages of c's children; the message to the parent is
  // min over c's label of belief(c) + pairwise, with the minimizing label kept for the downward pass.
  const LabelType     L = m_NumberOfLabels;
  std::vector<double> belief(m_UnaryCosts);
  std::vector<double> shifted(L);
  std::vector<double> labelDistances; // |v_a - v_b|^2 of the quadratic model
  if (m_QuadraticWeight >= 0.0)
  {
    labelDistances.resize(static_cast<size_t>(L) * L);
    for (LabelType a = 0; a < L; ++a)
    {
      for (LabelType b = 0; b < L; ++b)
      {
        double squared = 0.0;
        for (unsigned int d = 0; d < 3; ++d)
        {
          const double difference = m_LabelVectors[a][d] - m_LabelVectors[b][d];
          squared += difference * difference;
        }
        labelDistances[a * L + b] = squared;
      }
    }
  }
  std::vector<LabelType> bestChildLabel(m_NumberOfNodes * L, 0);
  for (size_t i = order.size(); i-- > 0;)
  {
    if (this->IsPastTimeLimit())
    {
      labeling = start;
      return startEnergy;
    }
    const SizeValueType c = order[i];
    const SizeValueType k = parentEdge[c];
    if (k == none)
    {
      continue;
    }
    const bool          childFirst = m_Edges[k].first == c;
    const SizeValueType parent = childFirst ? m_Edges[k].second : m_Edges[k].first;
    const double *      childBelief = &belief[c * L];
    double *            parentBelief = &belief[parent * L];
    LabelType *         best = &bestChildLabel[c * L];
    if (m_QuadraticWeight >= 0.0)
    {
      // V = w (|o|^2 + |v_a - v_b|^2 + 2 s o.(v_b - v_a)), with a the parent's label, b the child's and s = +1 when
      // the child is the edge's first node: the terms of b alone are added to the belief once.
      const VectorType & offset = m_EdgeOffsets[k];
      const double       sign = childFirst ? 1.0 : -1.0;
      const double       w = m_QuadraticWeight;
      const double       offsetSquared = offset[0] * offset[0] + offset[1] * offset[1] + offset[2] * offset[2];
      for (LabelType b = 0; b < L; ++b)
      {
        const VectorType & v = m_LabelVectors[b];
        shifted[b] = childBelief[b] + 2.0 * sign * w * (offset[0] * v[0] + offset[1] * v[1] + offset[2] * v[2]);
      }
      for (LabelType a = 0; a < L; ++a)
      {
        const double * distances = &labelDistances[a * L];
        double         minimum = std::numeric_limits<double>::infinity();
        LabelType      argument = 0;
        for (LabelType b = 0; b < L; ++b)
        {
          const double value = shifted[b] + w * distances[b];
          if (value < minimum)
          {
            minimum = value;
            argument = b;
          }
        }
        const VectorType & v = m_LabelVectors[a];
        parentBelief[a] +=
          minimum + w * offsetSquared - 2.0 * sign * w * (offset[0] * v[0] + offset[1] * v[1] + offset[2] * v[2]);
        best[a] = argument;
      }
      continue;
    }
    for (LabelType a = 0; a < L; ++a)
    {
      double    minimum = std::numeric_limits<double>::infinity();
      LabelType argument = 0;
      for (LabelType b = 0; b < L; ++b)
      {
        const double value = childBelief[b] + (childFirst ? this->Pairwise(k, b, a) : this->Pairwise(k, a, b));
        if (value < minimum)
        {
          minimum = value;
          argument = b;
        }
      }
      parentBelief[a] += minimum;
      best[a] = argument;
    }
  }
  // Downward pass: each root takes its best label, each child the label that minimized its message.
  for (const SizeValueType p : order)
  {
    const SizeValueType k = parentEdge[p];
    if (k == none)
    {
      const double * rootBelief = &belief[p * L];
      labeling[p] = static_cast<LabelType>(std::min_element(rootBelief, rootBelief + L) - rootBelief);
    }
    else
    {
      const SizeValueType parent = m_Edges[k].first == p ? m_Edges[k].second : m_Edges[k].first;
      labeling[p] = bestChildLabel[p * L + labeling[parent]];
    }
  }
  m_NumberOfCyclesPerformed = 1;

  // The edges left out of the tree: ICM sweeps on the whole graph from the tree's optimum.
  if (m_SpanningTreeEdges.size() < m_Edges.size() && m_MaximumNumberOfCycles > 1)
  {
    this->SweepICM(labeling, m_MaximumNumberOfCycles - 1);
  }
  const double energy = this->ComputeEnergy(labeling);
  if (energy > startEnergy)
  {
    labeling = start;
    return startEnergy;
  }
  return energy;
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
  os << indent << "QuadraticWeight: " << m_QuadraticWeight << (m_QuadraticWeight < 0.0 ? " (not used)" : "")
     << std::endl;
  os << indent << "Algorithm: " << m_Algorithm << std::endl;
  os << indent << "MaximumNumberOfCycles: " << m_MaximumNumberOfCycles << std::endl;
  os << indent << "MaximumRunTime: " << m_MaximumRunTime << std::endl;
  os << indent << "TimeLimitReached: " << (m_TimeLimitReached ? "true" : "false") << std::endl;
  os << indent << "NumberOfCyclesPerformed: " << m_NumberOfCyclesPerformed << std::endl;
  os << indent << "NumberOfAcceptedMoves: " << m_NumberOfAcceptedMoves << std::endl;
  os << indent << "NumberOfTruncatedTerms: " << m_NumberOfTruncatedTerms << std::endl;
  os << indent << "SpanningTreeEdges: " << m_SpanningTreeEdges.size() << std::endl;
  os << indent << "ReuseSpanningTree: " << (m_ReuseSpanningTree ? "On" : "Off") << std::endl;
  os << indent << "NodeEdgeOffsets: " << m_NodeEdgeOffsets.size() << std::endl;
}
} // namespace itk
