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
#include "itkMRFLabelingSolverTestHelpers.h"
#include "itkTestingMacros.h"
#include <chrono>
#include <random>
#include <sstream>

namespace
{
using SolverType = itk::MRFLabelingSolver;
using AlgorithmEnum = itk::MRFLabelingSolverEnums::Algorithm;

/** A random graph: random unary costs, random edges (a chain plus extra pairs), and a pairwise table per edge. */
struct RandomProblem
{
  itk::SizeValueType               Nodes;
  unsigned int                     Labels;
  std::vector<double>              Unary;
  std::vector<std::vector<double>> Tables; // per edge, Labels x Labels

  void
  Load(SolverType * solver, const std::vector<std::pair<itk::SizeValueType, itk::SizeValueType>> & edges) const
  {
    solver->SetNumberOfNodes(Nodes);
    solver->SetNumberOfLabels(Labels);
    solver->SetUnaryCosts(Unary);
    for (const auto & edge : edges)
    {
      solver->AddEdge(edge.first, edge.second);
    }
    const auto *       tables = &Tables;
    const unsigned int labels = Labels;
    solver->SetPairwiseFunction([tables, labels](itk::SizeValueType edge, unsigned int a, unsigned int b) {
      return (*tables)[edge][a * labels + b];
    });
  }
};

enum class PairwiseKind
{
  BinarySubmodular,
  Potts,
  Arbitrary
};

RandomProblem
MakeProblem(std::mt19937 &                                                   random,
            itk::SizeValueType                                               nodes,
            unsigned int                                                     labels,
            PairwiseKind                                                     kind,
            std::vector<std::pair<itk::SizeValueType, itk::SizeValueType>> & edges)
{
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  RandomProblem                          problem{ nodes, labels, {}, {} };
  for (itk::SizeValueType i = 0; i < nodes * labels; ++i)
  {
    problem.Unary.push_back(uniform(random));
  }
  edges.clear();
  for (itk::SizeValueType p = 0; p + 1 < nodes; ++p)
  {
    edges.emplace_back(p, p + 1);
  }
  for (itk::SizeValueType p = 0; p + 3 < nodes; p += 2)
  {
    edges.emplace_back(p, p + 3);
  }
  for (size_t k = 0; k < edges.size(); ++k)
  {
    std::vector<double> table(labels * labels, 0.0);
    if (kind == PairwiseKind::Potts)
    {
      const double weight = 0.8 * uniform(random);
      for (unsigned int a = 0; a < labels; ++a)
      {
        for (unsigned int b = 0; b < labels; ++b)
        {
          table[a * labels + b] = a == b ? 0.0 : weight;
        }
      }
    }
    else
    {
      for (auto & value : table)
      {
        value = uniform(random);
      }
      if (kind == PairwiseKind::BinarySubmodular)
      {
        // E(0,0) + E(1,1) <= E(0,1) + E(1,0)
        const double excess = table[0] + table[3] - table[1] - table[2];
        if (excess > 0.0)
        {
          table[1] += 0.5 * excess + 0.01;
          table[2] += 0.5 * excess + 0.01;
        }
      }
    }
    problem.Tables.push_back(table);
  }
  return problem;
}

double
SolveWith(const RandomProblem &                                                  problem,
          const std::vector<std::pair<itk::SizeValueType, itk::SizeValueType>> & edges,
          AlgorithmEnum                                                          algorithm,
          SolverType::LabelingType &                                             labeling)
{
  auto solver = SolverType::New();
  problem.Load(solver, edges);
  solver->SetAlgorithm(algorithm);
  const double energy = solver->Solve(labeling);
  if (std::abs(energy - solver->ComputeEnergy(labeling)) > 1e-9)
  {
    std::cerr << "Reported energy " << energy << " differs from the labeling's " << solver->ComputeEnergy(labeling)
              << std::endl;
    return std::numeric_limits<double>::max();
  }
  return energy;
}

/** A 3-D grid graph (6-neighbours) of side n, with random unary costs and, per edge, a random pairwise table that is
 * submodular for two labels (Potts-like with a random weight for more). */
RandomProblem
MakeGridProblem(std::mt19937 &                                                   random,
                itk::SizeValueType                                               n,
                unsigned int                                                     labels,
                std::vector<std::pair<itk::SizeValueType, itk::SizeValueType>> & edges)
{
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  RandomProblem                          problem{ n * n * n, labels, {}, {} };
  for (itk::SizeValueType i = 0; i < problem.Nodes * labels; ++i)
  {
    problem.Unary.push_back(uniform(random));
  }
  edges = itk::testing::MRFGridEdges(n);
  for (size_t k = 0; k < edges.size(); ++k)
  {
    const double        weight = 0.4 * uniform(random);
    std::vector<double> table(labels * labels, 0.0);
    for (unsigned int a = 0; a < labels; ++a)
    {
      for (unsigned int b = 0; b < labels; ++b)
      {
        table[a * labels + b] = a == b ? 0.0 : weight;
      }
    }
    problem.Tables.push_back(table);
  }
  return problem;
}

/** Global minimum of a chain problem (edges (p, p + 1) only) by dynamic programming. */
double
ChainMinimum(const RandomProblem & problem)
{
  return itk::testing::MRFChainMinimum(problem.Nodes, problem.Labels, problem.Unary, problem.Tables);
}
} // namespace

int
itkMRFLabelingSolverTest(int argc, char * argv[])
{
  if (argc != 1)
  {
    std::cerr << "Usage: " << itkNameOfTestExecutableMacro(argv) << std::endl;
    return EXIT_FAILURE;
  }
  int testStatus = EXIT_SUCCESS;

  auto solver = SolverType::New();
  ITK_EXERCISE_BASIC_OBJECT_METHODS(solver, MRFLabelingSolver, Object);
  ITK_TEST_SET_GET_VALUE(AlgorithmEnum::AlphaExpansion, solver->GetAlgorithm());
  solver->SetAlgorithm(AlgorithmEnum::ICM);
  ITK_TEST_SET_GET_VALUE(AlgorithmEnum::ICM, solver->GetAlgorithm());
  solver->SetMaximumNumberOfCycles(0);
  ITK_TEST_SET_GET_VALUE(1u, solver->GetMaximumNumberOfCycles());
  solver->SetMaximumNumberOfCycles(10);
  std::ostringstream printed;
  printed << AlgorithmEnum::AlphaExpansion;
  ITK_TEST_EXPECT_EQUAL(printed.str(), std::string("itk::MRFLabelingSolverEnums::Algorithm::AlphaExpansion"));

  // Bad input.
  SolverType::LabelingType labeling;
  ITK_TRY_EXPECT_EXCEPTION(solver->Solve(labeling)); // no node
  ITK_TRY_EXPECT_EXCEPTION(solver->SetNumberOfLabels(0));
  solver->SetNumberOfNodes(3);
  solver->SetNumberOfLabels(2);
  ITK_TRY_EXPECT_EXCEPTION(solver->SetUnaryCosts(std::vector<double>(5, 0.0)));
  ITK_TRY_EXPECT_EXCEPTION(solver->AddEdge(0, 3));
  ITK_TRY_EXPECT_EXCEPTION(solver->AddEdge(1, 1));
  solver->SetUnaryCosts(std::vector<double>(6, 0.0));
  solver->AddEdge(0, 1);
  labeling.assign(3, 0);
  ITK_TRY_EXPECT_EXCEPTION(solver->Solve(labeling)); // edges without pairwise function
  solver->SetPairwiseFunction([](itk::SizeValueType, unsigned int a, unsigned int b) { return a == b ? 0.0 : 1.0; });
  labeling.assign(2, 0);
  ITK_TRY_EXPECT_EXCEPTION(solver->Solve(labeling)); // wrong labeling size
  labeling.assign(3, 2);
  ITK_TRY_EXPECT_EXCEPTION(solver->Solve(labeling)); // label out of range
  solver->SetNumberOfNodes(30);
  solver->SetNumberOfLabels(2);
  solver->SetUnaryCosts(std::vector<double>(60, 0.0));
  solver->SetAlgorithm(AlgorithmEnum::Exhaustive);
  ITK_TRY_EXPECT_EXCEPTION(solver->Solve(labeling)); // 2^30 labelings refused

  std::mt19937                                                   random(20260522);
  std::vector<std::pair<itk::SizeValueType, itk::SizeValueType>> edges;

  // Two labels, submodular pairwise terms: one expansion move is an exact graph cut, so alpha-expansion finds the
  // global minimum from any start.
  for (unsigned int trial = 0; trial < 40; ++trial)
  {
    const auto               problem = MakeProblem(random, 6 + trial % 7, 2, PairwiseKind::BinarySubmodular, edges);
    SolverType::LabelingType exhaustive, expansion(problem.Nodes, trial % 2);
    const double             optimum = SolveWith(problem, edges, AlgorithmEnum::Exhaustive, exhaustive);
    const double             found = SolveWith(problem, edges, AlgorithmEnum::AlphaExpansion, expansion);
    if (std::abs(found - optimum) > 1e-9)
    {
      std::cerr << "Binary trial " << trial << ": expansion " << found << " != exhaustive " << optimum << std::endl;
      testStatus = EXIT_FAILURE;
    }
  }

  // Potts model, 3 and 4 labels: expansion is within a factor 2 of the optimum (Boykov et al. 2001) and no worse
  // than ICM from the same start.
  unsigned int strictlyBetter = 0;
  for (unsigned int trial = 0; trial < 30; ++trial)
  {
    const unsigned int       labels = 3 + trial % 2;
    const auto               problem = MakeProblem(random, labels == 3 ? 9 : 8, labels, PairwiseKind::Potts, edges);
    SolverType::LabelingType exhaustive, expansion(problem.Nodes, 0), icm(problem.Nodes, 0);
    const double             optimum = SolveWith(problem, edges, AlgorithmEnum::Exhaustive, exhaustive);
    const double             found = SolveWith(problem, edges, AlgorithmEnum::AlphaExpansion, expansion);
    const double             greedy = SolveWith(problem, edges, AlgorithmEnum::ICM, icm);
    if (found > 2.0 * optimum + 1e-9 || found < optimum - 1e-9 || found > greedy + 1e-9)
    {
      std::cerr << "Potts trial " << trial << ": optimum " << optimum << ", expansion " << found << ", ICM " << greedy
                << std::endl;
      testStatus = EXIT_FAILURE;
    }
    strictlyBetter += found < greedy - 1e-9;
  }
  std::cout << "Potts: expansion strictly better than ICM in " << strictlyBetter << " of 30 trials" << std::endl;

  // Arbitrary (non-submodular) pairwise tables: truncated moves are only accepted when the true energy decreases,
  // so the result never exceeds the start's energy, and never undercuts the global minimum.
  itk::SizeValueType truncated = 0;
  for (unsigned int trial = 0; trial < 30; ++trial)
  {
    const auto problem = MakeProblem(random, 7, 3, PairwiseKind::Arbitrary, edges);
    auto       arbitrary = SolverType::New();
    problem.Load(arbitrary, edges);
    SolverType::LabelingType start(problem.Nodes);
    for (auto & label : start)
    {
      label = random() % 3;
    }
    SolverType::LabelingType result(start), exhaustive;
    const double             startEnergy = arbitrary->ComputeEnergy(start);
    const double             found = arbitrary->Solve(result);
    truncated += arbitrary->GetNumberOfTruncatedTerms();
    const double optimum = SolveWith(problem, edges, AlgorithmEnum::Exhaustive, exhaustive);
    if (found > startEnergy + 1e-12 || found < optimum - 1e-9)
    {
      std::cerr << "Arbitrary trial " << trial << ": start " << startEnergy << ", expansion " << found << ", optimum "
                << optimum << std::endl;
      testStatus = EXIT_FAILURE;
    }
  }
  ITK_TEST_EXPECT_TRUE(truncated > 0);
  std::cout << "Arbitrary tables: " << truncated << " truncated expansion terms" << std::endl;

  // Large graphs, where max-flow grows and repairs its search trees over many augmenting paths.
  // A chain of 5000 nodes, two labels, submodular terms (strong couplings make long augmenting paths): the
  // expansion is exact, checked against dynamic programming.
  {
    std::uniform_real_distribution<double> uniform(0.0, 1.0);
    RandomProblem                          chain{ 5000, 2, {}, {} };
    for (itk::SizeValueType i = 0; i < 2 * chain.Nodes; ++i)
    {
      chain.Unary.push_back(uniform(random));
    }
    edges.clear();
    for (itk::SizeValueType p = 0; p + 1 < chain.Nodes; ++p)
    {
      edges.emplace_back(p, p + 1);
      const double same00 = 0.5 * uniform(random);
      const double same11 = 0.5 * uniform(random);
      const double different = std::max(same00, same11) + 2.0 * uniform(random);
      chain.Tables.push_back({ same00, different, different, same11 });
    }
    for (const unsigned int start : { 0u, 1u })
    {
      SolverType::LabelingType expansion(chain.Nodes, start);
      const double             found = SolveWith(chain, edges, AlgorithmEnum::AlphaExpansion, expansion);
      const double             optimum = ChainMinimum(chain);
      std::cout << "Chain of 5000 nodes from all " << start << ": expansion " << found << ", optimum " << optimum
                << std::endl;
      if (std::abs(found - optimum) > 1e-9 * std::abs(optimum))
      {
        std::cerr << "Chain: expansion " << found << " != dynamic programming " << optimum << std::endl;
        testStatus = EXIT_FAILURE;
      }
    }
  }
  // A 24^3 grid (13824 nodes, 39744 edges), two labels, submodular: the global minimum whatever the start (the
  // three starts give different flow problems), strictly below ICM's, with no single label change improving it.
  {
    const auto               grid = MakeGridProblem(random, 24, 2, edges);
    SolverType::LabelingType zeros(grid.Nodes, 0), ones(grid.Nodes, 1), mixed(grid.Nodes), icm(grid.Nodes, 0);
    for (auto & label : mixed)
    {
      label = random() % 2;
    }
    const double fromZeros = SolveWith(grid, edges, AlgorithmEnum::AlphaExpansion, zeros);
    const double fromOnes = SolveWith(grid, edges, AlgorithmEnum::AlphaExpansion, ones);
    const double fromMixed = SolveWith(grid, edges, AlgorithmEnum::AlphaExpansion, mixed);
    const double greedy = SolveWith(grid, edges, AlgorithmEnum::ICM, icm);
    std::cout << "Binary 24^3 grid: expansion " << fromZeros << ", " << fromOnes << ", " << fromMixed << "; ICM "
              << greedy << std::endl;
    const double tolerance = 1e-9 * std::abs(fromZeros);
    if (std::abs(fromZeros - fromOnes) > tolerance || std::abs(fromZeros - fromMixed) > tolerance ||
        !(fromZeros < greedy - tolerance))
    {
      std::cerr << "Binary grid: the expansions disagree or do not beat ICM" << std::endl;
      testStatus = EXIT_FAILURE;
    }
    auto check = SolverType::New();
    grid.Load(check, edges);
    for (itk::SizeValueType p = 0; p < grid.Nodes; p += 97)
    {
      auto flipped = zeros;
      flipped[p] = 1 - flipped[p];
      if (check->ComputeEnergy(flipped) < fromZeros - tolerance)
      {
        std::cerr << "Binary grid: changing node " << p << " improves the expansion's result" << std::endl;
        testStatus = EXIT_FAILURE;
      }
    }
  }
  // The same grid with 8 labels (Potts): expansion beats ICM; with a run-time limit far below its run time, Solve()
  // stops early with a labeling no worse than the start.
  {
    const auto               grid = MakeGridProblem(random, 24, 8, edges);
    SolverType::LabelingType expansion(grid.Nodes, 0), icm(grid.Nodes, 0);
    const double             found = SolveWith(grid, edges, AlgorithmEnum::AlphaExpansion, expansion);
    const double             greedy = SolveWith(grid, edges, AlgorithmEnum::ICM, icm);
    std::cout << "Potts 24^3 grid, 8 labels: expansion " << found << ", ICM " << greedy << std::endl;
    ITK_TEST_EXPECT_TRUE(found < greedy);

    auto limited = SolverType::New();
    grid.Load(limited, edges);
    limited->SetMaximumRunTime(-1.0);
    ITK_TEST_SET_GET_VALUE(0.0, limited->GetMaximumRunTime()); // clamped: no limit
    limited->SetMaximumRunTime(1e-4);
    ITK_TEST_SET_GET_VALUE(1e-4, limited->GetMaximumRunTime());
    SolverType::LabelingType start(grid.Nodes, 0);
    const double             startEnergy = limited->ComputeEnergy(start);
    const auto               begin = std::chrono::steady_clock::now();
    const double             stopped = limited->Solve(start);
    const double             elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
    std::cout << "Limited to 1e-4 s: " << elapsed << " s, energy " << stopped << " (start " << startEnergy << ")"
              << std::endl;
    ITK_TEST_EXPECT_TRUE(limited->GetTimeLimitReached());
    ITK_TEST_EXPECT_TRUE(stopped <= startEnergy && stopped >= found - 1e-9);
    ITK_TEST_EXPECT_TRUE(limited->GetNumberOfCyclesPerformed() == 1);
    limited->SetMaximumRunTime(0.0);
    SolverType::LabelingType unlimited(grid.Nodes, 0);
    ITK_TEST_EXPECT_TRUE(std::abs(limited->Solve(unlimited) - found) < 1e-9 * std::abs(found));
    ITK_TEST_EXPECT_TRUE(!limited->GetTimeLimitReached());
  }
  std::cout << solver;
  return testStatus;
}
