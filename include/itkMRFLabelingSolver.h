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
#ifndef itkMRFLabelingSolver_h
#define itkMRFLabelingSolver_h

#include "itkFFDShapeMatchingCompatibility.h"
#include "FFDShapeMatchingExport.h"
#include "itkNumericTraits.h"
#include "itkObject.h"
#include "itkObjectFactory.h"
#include <array>
#include <chrono>
#include <cstdint>
#include <functional>
#include <ostream>
#include <utility>
#include <vector>

namespace itk
{
/** \class MRFLabelingSolverEnums
 * \brief Enumerations of MRFLabelingSolver.
 *
 * \c Algorithm selects the minimizer:
 * - \c AlphaExpansion: alpha-expansion moves (Boykov, Veksler and Zabih 2001), each solved exactly by the
 *   Boykov-Kolmogorov max-flow algorithm;
 * - \c ICM: iterated conditional modes (greedy coordinate descent, node by node), for comparison;
 * - \c Exhaustive: enumeration of every labeling (tiny graphs only, for tests);
 * - \c SpanningTree: the exact minimum over a minimum spanning tree of the graph (min-sum belief propagation,
 *   the approach of deeds, Heinrich et al. 2013), then ICM sweeps over the edges the tree left out.
 *
 * \ingroup FFDShapeMatching
 */
class FFDShapeMatching_EXPORT MRFLabelingSolverEnums
{
public:
  enum class Algorithm : uint8_t
  {
    AlphaExpansion,
    ICM,
    Exhaustive,
    SpanningTree
  };
};

/** Prints the qualified enumerator name, e.g. "itk::MRFLabelingSolverEnums::Algorithm::ICM". */
extern FFDShapeMatching_EXPORT std::ostream &
                               operator<<(std::ostream & out, const MRFLabelingSolverEnums::Algorithm value);

/** \class MRFLabelingSolver
 * \brief Minimizes a pairwise discrete Markov-random-field energy (unary table, edge callback).
 *
 * The energy of a labeling \f$x\f$ of N nodes with L labels is
 * \f[ E(x) = \sum_p U_p(x_p) + \sum_{(p,q) \in \mathcal{E}} V_{pq}(x_p, x_q), \f]
 * with the unary table \f$U\f$ (SetUnaryCosts(), node-major: entry p * L + l) and, for each edge added with
 * AddEdge(), a pairwise cost given by the callback of SetPairwiseFunction() (edge index, label of its first
 * node, label of its second node). Pairwise costs need not be metric: the energies of B-spline registration
 * are not (their cost depends on the current control displacements as well as on the labels).
 *
 * \par Alpha-expansion (default)
 * Each move lets every node keep its label or switch to label alpha; the best such move is a binary problem,
 * cut exactly by max-flow when it is submodular. Where an edge's expansion term is not submodular
 * (\f$V(x_p,x_q) + V(\alpha,\alpha) > V(x_p,\alpha) + V(\alpha,x_q)\f$), its two mixed terms are raised until it
 * is (truncation, Rother et al. 2005), and the move is accepted only if the true energy decreases: the energy
 * never increases. Cycles over all labels repeat until none improves or MaximumNumberOfCycles is reached.
 * Max-flow is Boykov and Kolmogorov's, from Boost Graph (boykov_kolmogorov_max_flow on a compressed-sparse-row
 * graph built once per Solve() and reused by every move; used by this class's source file only).
 *
 * \par Spanning tree
 * Kruskal's algorithm (Boost Graph) picks a minimum spanning forest of the edges, each edge weighted by the L1
 * distance between its two nodes' unary cost vectors, so that the tree keeps the couplings of nodes whose data
 * agree. Two passes of min-sum belief propagation (leaves to roots, then back) give the exact minimum of the energy
 * restricted to the forest, in O(N L^2) pairwise evaluations whatever the pairwise costs; on a graph that is a tree
 * or a forest this is the global minimum. The edges left out are then taken into account by at most
 * MaximumNumberOfCycles - 1 ICM sweeps over the whole graph; if the result's energy on the whole graph exceeds the
 * start's, the start is returned. MaximumRunTime is checked before each node of the first pass: past it the start
 * is returned. GetSpanningTreeEdges() lists the edges of the last tree.
 *
 * \par ICM and exhaustive search
 * ICM sweeps the nodes in order, giving each the label of least conditional energy, until a sweep changes
 * nothing or MaximumNumberOfCycles sweeps are done. Exhaustive search enumerates all \f$L^N\f$ labelings
 * (refused above 2^24 of them) and returns a global minimum.
 *
 * \par References
 * Y. Boykov, O. Veksler and R. Zabih, "Fast approximate energy minimization via graph cuts", IEEE TPAMI
 * 23(11):1222-1239, 2001, doi:10.1109/34.969114.
 * Y. Boykov and V. Kolmogorov, "An experimental comparison of min-cut/max-flow algorithms for energy
 * minimization in vision", IEEE TPAMI 26(9):1124-1137, 2004, doi:10.1109/TPAMI.2004.60.
 * C. Rother, S. Kumar, V. Kolmogorov and A. Blake, "Digital tapestry", CVPR 2005, doi:10.1109/CVPR.2005.130.
 * M. P. Heinrich, M. Jenkinson, M. Brady and J. A. Schnabel, "MRF-based deformable registration and ventilation
 * estimation of lung CT", IEEE TMI 32(7):1239-1248, 2013, doi:10.1109/TMI.2013.2246577.
 *
 * \code
 * auto solver = itk::MRFLabelingSolver::New();
 * solver->SetNumberOfNodes(n);
 * solver->SetNumberOfLabels(l);
 * solver->SetUnaryCosts(costs); // n * l values
 * solver->AddEdge(0, 1);
 * solver->SetPairwiseFunction([](itk::SizeValueType, unsigned int a, unsigned int b) { return a == b ? 0.0 : 1.0; });
 * std::vector<unsigned int> labels(n, 0);
 * solver->Solve(labels);
 * \endcode
 *
 * \sa BSplineMRFImageRegistrationMethod
 * \ingroup FFDShapeMatching
 */
class FFDShapeMatching_EXPORT MRFLabelingSolver : public Object
{
public:
  ITK_DISALLOW_COPY_AND_MOVE(MRFLabelingSolver);

  using Self = MRFLabelingSolver;
  using Superclass = Object;
  using Pointer = SmartPointer<Self>;
  using ConstPointer = SmartPointer<const Self>;

  itkNewMacro(Self);
  itkOverrideGetNameOfClassMacro(MRFLabelingSolver);

  using LabelType = unsigned int;
  using LabelingType = std::vector<LabelType>;
  using EdgeType = std::pair<SizeValueType, SizeValueType>;
  using PairwiseFunctionType = std::function<double(SizeValueType edge, LabelType first, LabelType second)>;
  using AlgorithmEnum = MRFLabelingSolverEnums::Algorithm;
  using VectorType = std::array<double, 3>;

  /** Number of nodes. Setting it removes all edges and unary costs. Default: 0. */
  void
  SetNumberOfNodes(SizeValueType numberOfNodes);
  itkGetConstMacro(NumberOfNodes, SizeValueType);

  /** Number of labels, at least 1. Setting it removes the unary costs. Default: 1. */
  void
  SetNumberOfLabels(LabelType numberOfLabels);
  itkGetConstMacro(NumberOfLabels, LabelType);

  /** Unary costs, node-major (entry p * L + l); NumberOfNodes * NumberOfLabels values. */
  void
  SetUnaryCosts(std::vector<double> costs);
  const std::vector<double> &
  GetUnaryCosts() const
  {
    return m_UnaryCosts;
  }

  /** Adds the edge (first, second), two distinct nodes; returns its index. */
  SizeValueType
  AddEdge(SizeValueType first, SizeValueType second);

  /** Removes all edges. */
  void
  ClearEdges();

  const std::vector<EdgeType> &
  GetEdges() const
  {
    return m_Edges;
  }

  /** Pairwise cost of an edge given the labels of its first and second node. Required with edges, unless
   * SetQuadraticPairwise() is used; setting it discards the quadratic model. */
  void
  SetPairwiseFunction(PairwiseFunctionType function);

  /** The quadratic pairwise model instead of a function: \f$V_k(a, b) = w \, |o_k + v_a - v_b|^2\f$ for edge k of
   * offset o_k (one per edge, in edge order) and labels a, b of vectors v_a, v_b (one per label). It is evaluated
   * inline, and SpanningTree computes its messages with a table of |v_a - v_b|^2: several times faster than a
   * function. \c weight must be finite and >= 0. Setting it discards the pairwise function. */
  void
  SetQuadraticPairwise(std::vector<VectorType> labelVectors, std::vector<VectorType> edgeOffsets, double weight);

  /** The minimizer. Default: AlphaExpansion. */
  itkSetEnumMacro(Algorithm, AlgorithmEnum);
  itkGetEnumMacro(Algorithm, AlgorithmEnum);

  /** Maximum alpha-expansion cycles or ICM sweeps. Default: 10. */
  itkSetClampMacro(MaximumNumberOfCycles, unsigned int, 1, NumericTraits<unsigned int>::max());
  itkGetConstMacro(MaximumNumberOfCycles, unsigned int);

  /** Wall-clock limit of Solve() in seconds; 0 (the default) means none. AlphaExpansion checks it before each
   * expansion move, ICM before each node; past it Solve() returns the labeling reached (whose energy never
   * exceeds the start's) and GetTimeLimitReached() is true. Exhaustive search ignores it. A negative value is
   * clamped to 0. */
  itkSetClampMacro(MaximumRunTime, double, 0.0, NumericTraits<double>::max());
  itkGetConstMacro(MaximumRunTime, double);

  /** Whether the last Solve() stopped at MaximumRunTime. */
  itkGetConstMacro(TimeLimitReached, bool);

  /** Energy of a labeling. Throws for a labeling of the wrong size or with a label out of range. */
  double
  ComputeEnergy(const LabelingType & labeling) const;

  /** Minimizes the energy with the chosen algorithm, starting from \c labeling (ignored by Exhaustive), which
   * receives the result; returns its energy. The result's energy never exceeds the start's. Throws for
   * inconsistent input. */
  double
  Solve(LabelingType & labeling);

  /** Cycles (expansion) or sweeps (ICM) done by the last Solve(). */
  itkGetConstMacro(NumberOfCyclesPerformed, unsigned int);

  /** Alpha-expansion moves accepted by the last Solve(). */
  itkGetConstMacro(NumberOfAcceptedMoves, SizeValueType);

  /** Edge terms made submodular by truncation during the last Solve(). */
  itkGetConstMacro(NumberOfTruncatedTerms, SizeValueType);

  /** Whether a SpanningTree Solve() keeps the spanning forest of the previous one instead of choosing it again from
   * the new unary costs, as long as the graph is unchanged (SetNumberOfNodes(), AddEdge() and ClearEdges() discard
   * it). For a sequence of problems on one graph whose data change little from one to the next, such as the
   * iterations of a registration level (deeds builds its tree once per level); the minimum found is still exact on
   * the kept forest. Default: Off. */
  itkSetMacro(ReuseSpanningTree, bool);
  itkGetConstMacro(ReuseSpanningTree, bool);
  itkBooleanMacro(ReuseSpanningTree);

  /** Edges (indices into GetEdges(), ascending) of the spanning forest of the last SpanningTree Solve(). */
  const std::vector<SizeValueType> &
  GetSpanningTreeEdges() const
  {
    return m_SpanningTreeEdges;
  }

protected:
  MRFLabelingSolver() = default;
  ~MRFLabelingSolver() override = default;
  void
  PrintSelf(std::ostream & os, Indent indent) const override;

private:
  void
  CheckInput(const LabelingType & labeling, bool checkLabeling) const;

  /** Pairwise cost of edge k for labels a (its first node) and b (its second), from the model in use. */
  double
  Pairwise(SizeValueType k, LabelType a, LabelType b) const
  {
    if (m_QuadraticWeight >= 0.0)
    {
      const VectorType & o = m_EdgeOffsets[k];
      const VectorType & u = m_LabelVectors[a];
      const VectorType & v = m_LabelVectors[b];
      const double       x = o[0] + u[0] - v[0];
      const double       y = o[1] + u[1] - v[1];
      const double       z = o[2] + u[2] - v[2];
      return m_QuadraticWeight * (x * x + y * y + z * z);
    }
    return m_PairwiseFunction(k, a, b);
  }

  /** Whether MaximumRunTime has passed since Solve() started (and records it). */
  bool
  IsPastTimeLimit();

  double
  SolveAlphaExpansion(LabelingType & labeling);

  double
  SolveICM(LabelingType & labeling);

  /** At most \c maximumNumberOfSweeps ICM sweeps (until one changes nothing or the time is up). */
  void
  SweepICM(LabelingType & labeling, unsigned int maximumNumberOfSweeps);

  /** The edges of each node in increasing index order (compressed rows), built once per graph. */
  void
  UpdateNodeEdges();

  /** The edges of node p (after UpdateNodeEdges()). */
  struct EdgeRange
  {
    const SizeValueType * First;
    const SizeValueType * Last;
    const SizeValueType *
    begin() const
    {
      return First;
    }
    const SizeValueType *
    end() const
    {
      return Last;
    }
    size_t
    size() const
    {
      return static_cast<size_t>(Last - First);
    }
  };
  EdgeRange
  NodeEdges(SizeValueType p) const
  {
    return { m_NodeEdgeIndices.data() + m_NodeEdgeOffsets[p], m_NodeEdgeIndices.data() + m_NodeEdgeOffsets[p + 1] };
  }

  /** Discards what is derived from the graph (the node edges and the spanning forest). */
  void
  ClearGraphCaches()
  {
    m_NodeEdgeOffsets.clear();
    m_NodeEdgeIndices.clear();
    m_SpanningTreeEdges.clear();
    m_SpanningTreeOrder.clear();
    m_SpanningTreeParentEdge.clear();
  }

  /** Fills m_SpanningTreeEdges with a minimum spanning forest of the edges, and its breadth-first node order and
   * parent edges. */
  void
  ComputeSpanningTree();

  double
  SolveSpanningTree(LabelingType & labeling);

  double
  SolveExhaustive(LabelingType & labeling);

  SizeValueType                         m_NumberOfNodes{ 0 };
  LabelType                             m_NumberOfLabels{ 1 };
  std::vector<double>                   m_UnaryCosts{};
  std::vector<EdgeType>                 m_Edges{};
  PairwiseFunctionType                  m_PairwiseFunction{};
  AlgorithmEnum                         m_Algorithm{ AlgorithmEnum::AlphaExpansion };
  unsigned int                          m_MaximumNumberOfCycles{ 10 };
  double                                m_MaximumRunTime{ 0.0 };
  bool                                  m_TimeLimitReached{ false };
  std::chrono::steady_clock::time_point m_StartTime{};
  unsigned int                          m_NumberOfCyclesPerformed{ 0 };
  SizeValueType                         m_NumberOfAcceptedMoves{ 0 };
  SizeValueType                         m_NumberOfTruncatedTerms{ 0 };
  std::vector<SizeValueType> m_NodeEdgeOffsets{}; // node p's edges: m_NodeEdgeIndices[offsets[p], offsets[p+1])
  std::vector<SizeValueType> m_NodeEdgeIndices{};
  std::vector<SizeValueType> m_SpanningTreeEdges{};
  std::vector<SizeValueType> m_SpanningTreeOrder{};      // the forest's nodes, breadth first from each root
  std::vector<SizeValueType> m_SpanningTreeParentEdge{}; // per node, the edge to its parent (none for a root)
  bool                       m_ReuseSpanningTree{ false };
  double                     m_QuadraticWeight{ -1.0 }; // < 0: the function is used
  std::vector<VectorType>    m_LabelVectors{};
  std::vector<VectorType>    m_EdgeOffsets{};
};
} // namespace itk

#endif // itkMRFLabelingSolver_h
