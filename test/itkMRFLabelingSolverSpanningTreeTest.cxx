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
// The SpanningTree algorithm of MRFLabelingSolver and its quadratic pairwise model, checked against exhaustive
// search, dynamic programming and a brute-force minimum spanning tree.
#include "itkMRFLabelingSolver.h"
#include "itkMRFLabelingSolverTestHelpers.h"
#include "itkTestingMacros.h"
#include <algorithm>
#include <chrono>
#include <numeric>
#include <random>
#include <sstream>

namespace
{
using SolverType = itk::MRFLabelingSolver;
using AlgorithmEnum = itk::MRFLabelingSolverEnums::Algorithm;
using EdgeList = std::vector<std::pair<itk::SizeValueType, itk::SizeValueType>>;
using VectorType = SolverType::VectorType;

/** Unary costs and one arbitrary (not submodular, not metric) pairwise table per edge. */
struct TableProblem
{
  itk::SizeValueType               Nodes{ 0 };
  unsigned int                     Labels{ 0 };
  EdgeList                         Edges;
  std::vector<double>              Unary;
  std::vector<std::vector<double>> Tables;

  SolverType::Pointer
  MakeSolver(AlgorithmEnum algorithm) const
  {
    auto solver = SolverType::New();
    solver->SetNumberOfNodes(Nodes);
    solver->SetNumberOfLabels(Labels);
    solver->SetUnaryCosts(Unary);
    for (const auto & edge : Edges)
    {
      solver->AddEdge(edge.first, edge.second);
    }
    const auto *       tables = &Tables;
    const unsigned int labels = Labels;
    solver->SetPairwiseFunction([tables, labels](itk::SizeValueType edge, unsigned int a, unsigned int b) {
      return (*tables)[edge][a * labels + b];
    });
    solver->SetAlgorithm(algorithm);
    return solver;
  }
};

TableProblem
MakeTableProblem(std::mt19937 & random, itk::SizeValueType nodes, unsigned int labels, EdgeList edges)
{
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  TableProblem                           problem;
  problem.Nodes = nodes;
  problem.Labels = labels;
  problem.Edges = std::move(edges);
  for (itk::SizeValueType i = 0; i < nodes * labels; ++i)
  {
    problem.Unary.push_back(uniform(random));
  }
  for (size_t k = 0; k < problem.Edges.size(); ++k)
  {
    std::vector<double> table(labels * labels);
    for (auto & value : table)
    {
      value = uniform(random);
    }
    problem.Tables.push_back(table);
  }
  return problem;
}

/** A random tree: node p > 0 hangs from a random earlier node, the edge's orientation drawn at random too. */
EdgeList
RandomTree(std::mt19937 & random, itk::SizeValueType nodes, itk::SizeValueType firstNode = 0)
{
  EdgeList edges;
  for (itk::SizeValueType p = 1; p < nodes; ++p)
  {
    const itk::SizeValueType parent = firstNode + random() % p;
    if (random() % 2)
    {
      edges.emplace_back(parent, firstNode + p);
    }
    else
    {
      edges.emplace_back(firstNode + p, parent);
    }
  }
  return edges;
}

double
Solve(SolverType * solver, SolverType::LabelingType & labeling)
{
  const double energy = solver->Solve(labeling);
  if (std::abs(energy - solver->ComputeEnergy(labeling)) > 1e-9 * std::max(1.0, std::abs(energy)))
  {
    std::cerr << "Reported energy " << energy << " differs from the labeling's " << solver->ComputeEnergy(labeling)
              << std::endl;
    return std::numeric_limits<double>::max();
  }
  return energy;
}

/** The L1 distance of two nodes' unary cost vectors: the weight the solver gives an edge. */
double
EdgeWeight(const TableProblem & problem, itk::SizeValueType p, itk::SizeValueType q)
{
  double weight = 0.0;
  for (unsigned int l = 0; l < problem.Labels; ++l)
  {
    weight += std::abs(problem.Unary[p * problem.Labels + l] - problem.Unary[q * problem.Labels + l]);
  }
  return weight;
}

/** Whether the edges (by index) connect all nodes without a cycle (union-find). */
bool
IsSpanningTree(const TableProblem & problem, const std::vector<itk::SizeValueType> & chosen)
{
  if (chosen.size() + 1 != problem.Nodes)
  {
    return false;
  }
  std::vector<itk::SizeValueType> root(problem.Nodes);
  std::iota(root.begin(), root.end(), itk::SizeValueType{ 0 });
  const auto find = [&root](itk::SizeValueType p) {
    while (root[p] != p)
    {
      p = root[p];
    }
    return p;
  };
  for (const itk::SizeValueType k : chosen)
  {
    const itk::SizeValueType a = find(problem.Edges[k].first);
    const itk::SizeValueType b = find(problem.Edges[k].second);
    if (a == b)
    {
      return false;
    }
    root[a] = b;
  }
  return true;
}
} // namespace

int
itkMRFLabelingSolverSpanningTreeTest(int argc, char * argv[])
{
  if (argc != 1)
  {
    std::cerr << "Usage: " << itkNameOfTestExecutableMacro(argv) << std::endl;
    return EXIT_FAILURE;
  }
  int          testStatus = EXIT_SUCCESS;
  std::mt19937 random(20261203);

  std::ostringstream printed;
  printed << AlgorithmEnum::SpanningTree;
  ITK_TEST_EXPECT_EQUAL(printed.str(), std::string("itk::MRFLabelingSolverEnums::Algorithm::SpanningTree"));

  // On trees and forests, with arbitrary pairwise tables, the result is the global minimum (exhaustive search),
  // whatever the start, and the spanning forest is the whole graph.
  for (unsigned int trial = 0; trial < 40; ++trial)
  {
    const itk::SizeValueType nodes = 5 + trial % 4;
    const unsigned int       labels = 3 + trial % 3;
    EdgeList                 edges = RandomTree(random, nodes);
    if (trial % 4 == 3)
    {
      // A forest: the last two nodes form a tree of their own.
      edges = RandomTree(random, nodes - 2);
      edges.emplace_back(nodes - 1, nodes - 2);
    }
    const auto               problem = MakeTableProblem(random, nodes, labels, edges);
    auto                     tree = problem.MakeSolver(AlgorithmEnum::SpanningTree);
    auto                     exhaustive = problem.MakeSolver(AlgorithmEnum::Exhaustive);
    SolverType::LabelingType found(nodes), optimum;
    for (auto & label : found)
    {
      label = random() % labels;
    }
    const double treeEnergy = Solve(tree, found);
    const double optimalEnergy = Solve(exhaustive, optimum);
    if (std::abs(treeEnergy - optimalEnergy) > 1e-9 || tree->GetSpanningTreeEdges().size() != edges.size())
    {
      std::cerr << "Tree trial " << trial << ": spanning tree " << treeEnergy << ", exhaustive " << optimalEnergy
                << ", " << tree->GetSpanningTreeEdges().size() << " of " << edges.size() << " edges in the forest"
                << std::endl;
      testStatus = EXIT_FAILURE;
    }
  }

  // On graphs with cycles: the forest is a spanning tree of minimum weight (brute force over every subset of N - 1
  // edges), the result never exceeds the start's energy nor undercuts the global minimum, and the ICM sweeps over
  // the left-out edges never raise the energy of the tree's own minimum (compared with one cycle: no sweep).
  unsigned int improvedBySweeps = 0;
  for (unsigned int trial = 0; trial < 30; ++trial)
  {
    const itk::SizeValueType nodes = 6;
    EdgeList                 edges = RandomTree(random, nodes);
    edges.emplace_back(0, 5);
    edges.emplace_back(2, 4);
    edges.emplace_back(1, 3);
    const auto problem = MakeTableProblem(random, nodes, 3, edges);
    auto       tree = problem.MakeSolver(AlgorithmEnum::SpanningTree);
    tree->SetMaximumNumberOfCycles(4);
    SolverType::LabelingType start(nodes), found;
    for (auto & label : start)
    {
      label = random() % 3;
    }
    found = start;
    const double startEnergy = tree->ComputeEnergy(start);
    const double treeEnergy = Solve(tree, found);
    const auto   chosen = tree->GetSpanningTreeEdges();

    double chosenWeight = 0.0;
    for (const auto k : chosen)
    {
      chosenWeight += EdgeWeight(problem, edges[k].first, edges[k].second);
    }
    double                          lightest = std::numeric_limits<double>::max();
    const unsigned int              numberOfEdges = static_cast<unsigned int>(edges.size());
    std::vector<itk::SizeValueType> subset;
    for (unsigned int mask = 0; mask < (1u << numberOfEdges); ++mask)
    {
      subset.clear();
      double weight = 0.0;
      for (unsigned int k = 0; k < numberOfEdges; ++k)
      {
        if (mask & (1u << k))
        {
          subset.push_back(k);
          weight += EdgeWeight(problem, edges[k].first, edges[k].second);
        }
      }
      if (IsSpanningTree(problem, subset))
      {
        lightest = std::min(lightest, weight);
      }
    }

    auto                     exhaustive = problem.MakeSolver(AlgorithmEnum::Exhaustive);
    SolverType::LabelingType optimum;
    const double             optimalEnergy = Solve(exhaustive, optimum);
    auto                     treeOnly = problem.MakeSolver(AlgorithmEnum::SpanningTree);
    treeOnly->SetMaximumNumberOfCycles(1);
    SolverType::LabelingType withoutSweeps = start;
    const double             treeOnlyEnergy = Solve(treeOnly, withoutSweeps);
    improvedBySweeps += treeEnergy < treeOnlyEnergy - 1e-12;
    if (!IsSpanningTree(problem, chosen) || std::abs(chosenWeight - lightest) > 1e-12 ||
        treeEnergy > startEnergy + 1e-12 || treeEnergy < optimalEnergy - 1e-12 || treeEnergy > treeOnlyEnergy + 1e-12)
    {
      std::cerr << "Loopy trial " << trial << ": forest weight " << chosenWeight << " (lightest " << lightest
                << "), energy " << treeEnergy << " (start " << startEnergy << ", optimum " << optimalEnergy
                << ", without sweeps " << treeOnlyEnergy << ")" << std::endl;
      testStatus = EXIT_FAILURE;
    }
  }
  std::cout << "Graphs with cycles: the ICM sweeps lowered the tree's result in " << improvedBySweeps << " of 30 trials"
            << std::endl;
  ITK_TEST_EXPECT_TRUE(improvedBySweeps > 0);

  // A chain of 3000 nodes with 6 labels: the exact minimum, checked against dynamic programming.
  {
    const itk::SizeValueType nodes = 3000;
    const unsigned int       labels = 6;
    EdgeList                 edges;
    for (itk::SizeValueType p = 0; p + 1 < nodes; ++p)
    {
      edges.emplace_back(p, p + 1);
    }
    const auto               problem = MakeTableProblem(random, nodes, labels, edges);
    const double             programmed = itk::testing::MRFChainMinimum(nodes, labels, problem.Unary, problem.Tables);
    auto                     tree = problem.MakeSolver(AlgorithmEnum::SpanningTree);
    SolverType::LabelingType found(nodes, 0);
    const double             treeEnergy = Solve(tree, found);
    std::cout << "Chain of 3000 nodes, 6 labels: spanning tree " << treeEnergy << ", dynamic programming " << programmed
              << std::endl;
    ITK_TEST_EXPECT_TRUE(std::abs(treeEnergy - programmed) <= 1e-9 * std::abs(programmed));
  }

  // ReuseSpanningTree: the next Solve() keeps the forest chosen from the first unary costs, and its minimum with new
  // costs (no ICM sweep) is the exhaustive minimum of the energy restricted to that forest; a change of the graph
  // discards the forest, and Off chooses it again from the new costs.
  {
    const unsigned int labels = 3;
    const EdgeList     edges = itk::testing::MRFGridEdges(2); // a cube of 8 nodes
    const auto         first = MakeTableProblem(random, 8, labels, edges);
    auto               second = MakeTableProblem(random, 8, labels, edges);
    second.Tables = first.Tables;
    auto reusing = first.MakeSolver(AlgorithmEnum::SpanningTree);
    ITK_TEST_SET_GET_BOOLEAN(reusing, ReuseSpanningTree, true);
    reusing->SetMaximumNumberOfCycles(1);
    SolverType::LabelingType labeling(first.Nodes, 0);
    Solve(reusing, labeling);
    const std::vector<itk::SizeValueType> firstTree = reusing->GetSpanningTreeEdges();
    auto                                  fresh = second.MakeSolver(AlgorithmEnum::SpanningTree);
    SolverType::LabelingType              freshLabeling(second.Nodes, 0);
    Solve(fresh, freshLabeling);
    const std::vector<itk::SizeValueType> secondTree = fresh->GetSpanningTreeEdges();
    ITK_TEST_EXPECT_TRUE(firstTree != secondTree); // the two cost tables choose different trees

    reusing->SetUnaryCosts(second.Unary);
    std::fill(labeling.begin(), labeling.end(), 0);
    const double reused = Solve(reusing, labeling);
    ITK_TEST_EXPECT_TRUE(reusing->GetSpanningTreeEdges() == firstTree);
    TableProblem onTree = second;
    onTree.Edges.clear();
    onTree.Tables.clear();
    for (const itk::SizeValueType k : firstTree)
    {
      onTree.Edges.push_back(second.Edges[k]);
      onTree.Tables.push_back(second.Tables[k]);
    }
    auto                     exhaustive = onTree.MakeSolver(AlgorithmEnum::Exhaustive);
    SolverType::LabelingType optimum;
    const double             treeMinimum = Solve(exhaustive, optimum);
    std::cout << "Reused spanning tree: energy on the tree " << exhaustive->ComputeEnergy(labeling)
              << ", exhaustive minimum on the tree " << treeMinimum << ", on the grid " << reused << std::endl;
    ITK_TEST_EXPECT_TRUE(std::abs(exhaustive->ComputeEnergy(labeling) - treeMinimum) <= 1e-9);

    // A graph change discards the kept forest: the same edges added again give the fresh solver's tree.
    reusing->ClearEdges();
    for (const auto & edge : edges)
    {
      reusing->AddEdge(edge.first, edge.second);
    }
    ITK_TEST_EXPECT_TRUE(reusing->GetSpanningTreeEdges().empty());
    Solve(reusing, labeling);
    ITK_TEST_EXPECT_TRUE(reusing->GetSpanningTreeEdges() == secondTree);
    reusing->SetNumberOfNodes(second.Nodes);
    ITK_TEST_EXPECT_TRUE(reusing->GetSpanningTreeEdges().empty());

    // Off: each Solve() chooses the tree from its own costs.
    auto choosing = first.MakeSolver(AlgorithmEnum::SpanningTree);
    choosing->SetReuseSpanningTree(false);
    Solve(choosing, labeling);
    choosing->SetUnaryCosts(second.Unary);
    Solve(choosing, labeling);
    ITK_TEST_EXPECT_TRUE(choosing->GetSpanningTreeEdges() == secondTree);
  }

  // The quadratic model w |o_k + v_a - v_b|^2 gives the same energies as the same costs through a function, and the
  // same minimum with every algorithm (the spanning tree computes it through its table of label distances, ICM in
  // closed form per node).
  {
    const itk::SizeValueType               side = 4;
    const itk::SizeValueType               nodes = side * side;
    const unsigned int                     labels = 7;
    std::uniform_real_distribution<double> uniform(-1.0, 1.0);
    EdgeList                               edges;
    for (itk::SizeValueType y = 0; y < side; ++y)
    {
      for (itk::SizeValueType x = 0; x < side; ++x)
      {
        if (x + 1 < side)
        {
          edges.emplace_back(x + side * y, x + 1 + side * y);
        }
        if (y + 1 < side)
        {
          edges.emplace_back(x + side * (y + 1), x + side * y); // reversed, to exercise the orientation
        }
      }
    }
    std::vector<VectorType> labelVectors(labels), offsets(edges.size());
    for (auto & v : labelVectors)
    {
      v = { { uniform(random), uniform(random), uniform(random) } };
    }
    for (auto & o : offsets)
    {
      o = { { uniform(random), uniform(random), uniform(random) } };
    }
    const double weight = 0.7;
    auto         problem = MakeTableProblem(random, nodes, labels, edges);
    for (size_t k = 0; k < edges.size(); ++k)
    {
      for (unsigned int a = 0; a < labels; ++a)
      {
        for (unsigned int b = 0; b < labels; ++b)
        {
          double squared = 0.0;
          for (unsigned int d = 0; d < 3; ++d)
          {
            const double value = offsets[k][d] + labelVectors[a][d] - labelVectors[b][d];
            squared += value * value;
          }
          problem.Tables[k][a * labels + b] = weight * squared;
        }
      }
    }
    for (const AlgorithmEnum algorithm :
         { AlgorithmEnum::SpanningTree, AlgorithmEnum::AlphaExpansion, AlgorithmEnum::ICM })
    {
      auto withFunction = problem.MakeSolver(algorithm);
      auto withModel = problem.MakeSolver(algorithm);
      withModel->SetQuadraticPairwise(labelVectors, offsets, weight);
      SolverType::LabelingType probe(nodes);
      for (unsigned int repeat = 0; repeat < 20; ++repeat)
      {
        for (auto & label : probe)
        {
          label = random() % labels;
        }
        if (std::abs(withFunction->ComputeEnergy(probe) - withModel->ComputeEnergy(probe)) > 1e-9)
        {
          std::cerr << "Quadratic model: energy " << withModel->ComputeEnergy(probe)
                    << " != " << withFunction->ComputeEnergy(probe) << std::endl;
          testStatus = EXIT_FAILURE;
        }
      }
      SolverType::LabelingType a(nodes, 0), b(nodes, 0);
      const double             functionEnergy = Solve(withFunction, a);
      const double             modelEnergy = Solve(withModel, b);
      std::cout << algorithm << ": function " << functionEnergy << ", quadratic model " << modelEnergy << std::endl;
      // ICM's closed form of the quadratic model (per node, O(1) per label) chooses the labels the callback does.
      if (std::abs(functionEnergy - modelEnergy) > 1e-9 || a != b)
      {
        std::cerr << algorithm << ": the quadratic model's labeling differs from the callback's" << std::endl;
        testStatus = EXIT_FAILURE;
      }
    }

    // A tree of the same costs: the model's messages give the exhaustive minimum.
    TableProblem small = problem;
    small.Nodes = 7;
    small.Unary.resize(small.Nodes * labels);
    small.Edges = RandomTree(random, small.Nodes);
    small.Tables.resize(small.Edges.size());
    std::vector<VectorType> smallOffsets(offsets.begin(), offsets.begin() + small.Edges.size());
    for (size_t k = 0; k < small.Edges.size(); ++k)
    {
      small.Tables[k] = problem.Tables[k];
    }
    auto tree = small.MakeSolver(AlgorithmEnum::SpanningTree);
    tree->SetQuadraticPairwise(labelVectors, smallOffsets, weight);
    auto                     exhaustive = small.MakeSolver(AlgorithmEnum::Exhaustive);
    SolverType::LabelingType found(small.Nodes, 0), optimum;
    ITK_TEST_EXPECT_TRUE(std::abs(Solve(tree, found) - Solve(exhaustive, optimum)) < 1e-9);

    // Bad input: a negative or non-finite weight, vectors that do not match the labels or the edges.
    ITK_TRY_EXPECT_EXCEPTION(tree->SetQuadraticPairwise(labelVectors, smallOffsets, -1.0));
    ITK_TRY_EXPECT_EXCEPTION(
      tree->SetQuadraticPairwise(labelVectors, smallOffsets, std::numeric_limits<double>::quiet_NaN()));
    tree->SetQuadraticPairwise(std::vector<VectorType>(labels - 1), smallOffsets, weight);
    ITK_TRY_EXPECT_EXCEPTION(tree->Solve(found));
    tree->SetQuadraticPairwise(labelVectors, std::vector<VectorType>(small.Edges.size() + 1), weight);
    ITK_TRY_EXPECT_EXCEPTION(tree->Solve(found));
  }

  // A 20^3 grid with 19 labels (the size of the MRF registration's problems): a run-time limit far below the run
  // time returns the start; without it the result is below the start's energy.
  {
    const itk::SizeValueType               side = 20;
    const EdgeList                         edges = itk::testing::MRFGridEdges(side);
    const itk::SizeValueType               nodes = side * side * side;
    const unsigned int                     labels = 19;
    std::uniform_real_distribution<double> uniform(0.0, 1.0);
    auto                                   solver = SolverType::New();
    solver->SetNumberOfNodes(nodes);
    solver->SetNumberOfLabels(labels);
    std::vector<double> unary(nodes * labels);
    for (auto & value : unary)
    {
      value = uniform(random);
    }
    solver->SetUnaryCosts(unary);
    for (const auto & edge : edges)
    {
      solver->AddEdge(edge.first, edge.second);
    }
    std::vector<VectorType> labelVectors(labels);
    for (unsigned int l = 1; l < labels; ++l)
    {
      const unsigned int axis = (l - 1) % 3;
      const double       step = ((l - 1) / 3 % 2 ? -1.0 : 1.0) * (1 + (l - 1) / 6);
      labelVectors[l][axis] = step;
    }
    solver->SetQuadraticPairwise(labelVectors, std::vector<VectorType>(edges.size()), 0.1);
    solver->SetAlgorithm(AlgorithmEnum::SpanningTree);
    solver->SetMaximumNumberOfCycles(3);
    SolverType::LabelingType start(nodes, 0);
    const double             startEnergy = solver->ComputeEnergy(start);
    solver->SetMaximumRunTime(1e-6);
    SolverType::LabelingType limited = start;
    ITK_TEST_EXPECT_TRUE(solver->Solve(limited) == startEnergy);
    ITK_TEST_EXPECT_TRUE(solver->GetTimeLimitReached());
    ITK_TEST_EXPECT_TRUE(limited == start);
    solver->SetMaximumRunTime(0.0);
    SolverType::LabelingType found = start;
    const auto               begin = std::chrono::steady_clock::now();
    const double             energy = Solve(solver, found);
    const double             elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
    std::cout << "20^3 grid, 19 labels: " << energy << " from " << startEnergy << " in " << elapsed << " s, "
              << solver->GetSpanningTreeEdges().size() << " tree edges of " << edges.size() << std::endl;
    ITK_TEST_EXPECT_TRUE(!solver->GetTimeLimitReached());
    ITK_TEST_EXPECT_TRUE(energy < startEnergy);
    ITK_TEST_EXPECT_TRUE(solver->GetSpanningTreeEdges().size() == nodes - 1);
    std::cout << solver;
  }
  return testStatus;
}
