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
// ffd-benchmark-tool: the C++ helpers of the benchmark (benchmark/README.md).
//
//   ffd-benchmark-tool case --mesh M --out-dir DIR --truth-dir DIR --regime paper|smooth|short --seed S
//                           [--fraction F] [--grid N] [--margin MM]
//       scales M so its largest side is 100 mm (DIR/source.off), cuts the central box (F of each axis),
//       draws T_true (target space -> source space, RandomBSplineTransformGenerator, N^3 lattice around
//       the box), moves the box's vertices by T_true^-1 (ApplyTransformToMeshFilter, InverseOn), shuffles
//       their order and writes DIR/target.off (no arrays); the truth (target id -> source id), T_true and
//       the case description go to the truth folder, which no method sees.
//   ffd-benchmark-tool apply-field --source S --field F --output D [--report R.json]
//       moves S by the inverse of the displacement field F (a peer's target -> source field over the fixed
//       image) at the source vertices: DisplacementFieldTransform + ApplyTransformToMeshFilter InverseOn.
//   ffd-benchmark-tool score --deformed D --target T --truth TRUTH.txt --output SCORE.json
//                            [--transform T.tfm | --field F]
//       true vertex error over the region's vertices, mean directed and directed Hausdorff distances
//       target -> deformed source, symmetric Hausdorff between the target and the deformed region, and the
//       minimum Jacobian determinant of the transform or field over the target's bounding box (1 mm grid).
//
// Errors are one line on stderr ("ffd-benchmark-tool: error: ...") and exit code 1.

#include "itkFFDShapeMatchingCompatibility.h"
#include "FFDProgramMeshIO.h"
#include "FFDProgramSupport.h"
#include "itkApplyTransformToMeshFilter.h"
#include "itkDisplacementFieldTransform.h"
#include "itkImageFileReader.h"
#include "itkMesh.h"
#include "itkMeshFileReader.h"
#include "itkMeshFileWriter.h"
#include "itkMeshSurfaceDistanceCalculator.h"
#include "itkPointCorrespondenceErrorCalculator.h"
#include "itkRandomBSplineTransformGenerator.h"
#include "itkRegisterFFDShapeMatchingMeshIOFactories.h"
#include "itkTransformFactory.h"
#include "itkTransformFileReader.h"
#include "itkTransformFileWriter.h"
#include "itkTransformToJacobianDeterminantImageFilter.h"
#include "itkTriangleCell.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <limits>
#include <map>
#include <numeric>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace
{
using MeshType = itk::Mesh<double, 3>;
using PointType = MeshType::PointType;
using TransformBaseType = itk::Transform<double, 3, 3>;
using ApplyType = itk::ApplyTransformToMeshFilter<MeshType, MeshType>;
using GeneratorType = itk::RandomBSplineTransformGenerator<double, 3>;
using FieldImageType = itk::DisplacementFieldTransform<double, 3>::DisplacementFieldType;
using JacobianImageType = itk::Image<float, 3>;
using JacobianFilterType = itk::TransformToJacobianDeterminantImageFilter<JacobianImageType>;
using SurfaceDistanceType = itk::MeshSurfaceDistanceCalculator<MeshType>;
using CorrespondenceErrorType = itk::PointCorrespondenceErrorCalculator<MeshType>;
using TriangleType = itk::TriangleCell<MeshType::CellType>;
using CorrespondenceContainerType = CorrespondenceErrorType::CorrespondenceContainerType;
using ffd::JsonString;
using ffd::OneLine;

const char * const Usage =
  "usage: ffd-benchmark-tool case --mesh M --out-dir DIR --truth-dir DIR --regime paper|smooth|short --seed S\n"
  "                               [--fraction 0.6] [--grid 20] [--margin 5]\n"
  "       ffd-benchmark-tool apply-field --source S --field F --output D [--report R.json]\n"
  "       ffd-benchmark-tool score --deformed D --target T --truth TRUTH.txt --output SCORE.json\n"
  "                                [--transform T.tfm | --field F]\n"
  "  case         scaled source, deformed and shuffled central region as target, ground truth, T_true\n"
  "  apply-field  source moved by the inverse of a target -> source displacement field\n"
  "  score        true error, mean directed / Hausdorff distances, minimum Jacobian determinant (JSON)\n"
  "  --fraction   region = central box covering this fraction of each axis, (0, 1] (default 0.6)\n"
  "  --grid       control points per axis of T_true's lattice around the region (default 20)\n"
  "  --margin     the lattice's domain = region grown by this many mm on every side (default 5)\n";

struct Error : std::runtime_error
{
  using std::runtime_error::runtime_error;
};

/** A DisplacementFieldTransform whose spatial Jacobian is the identity outside the field's buffer, where its
 * displacement is zero (ITK 5.2's reads outside the buffer there). The inverse application's Newton iterates may
 * leave the field. */
class BoundedDisplacementFieldTransform : public itk::DisplacementFieldTransform<double, 3>
{
public:
  ITK_DISALLOW_COPY_AND_MOVE(BoundedDisplacementFieldTransform);

  using Self = BoundedDisplacementFieldTransform;
  using Superclass = itk::DisplacementFieldTransform<double, 3>;
  using Pointer = itk::SmartPointer<Self>;

  itkNewMacro(Self);
  itkOverrideGetNameOfClassMacro(BoundedDisplacementFieldTransform);

  using Superclass::ComputeJacobianWithRespectToPosition;

  void
  ComputeJacobianWithRespectToPosition(const InputPointType & point, JacobianPositionType & jacobian) const override
  {
    const auto * field = this->GetDisplacementField();
    IndexType    index;
    if (field != nullptr && field->TransformPhysicalPointToIndex(point, index) &&
        field->GetBufferedRegion().IsInside(index))
    {
      Superclass::ComputeJacobianWithRespectToPosition(point, jacobian);
      return;
    }
    jacobian.set_identity();
  }

protected:
  BoundedDisplacementFieldTransform() = default;
  ~BoundedDisplacementFieldTransform() override = default;
};
using FieldTransformType = BoundedDisplacementFieldTransform;

// Options as name -> value; every option takes one value.
using ArgumentMap = std::map<std::string, std::string>;

ArgumentMap
ParseOptions(int argc, char * argv[], const std::vector<std::string> & known)
{
  ArgumentMap options;
  for (int i = 2; i < argc; ++i)
  {
    const std::string argument = argv[i];
    if (std::find(known.begin(), known.end(), argument) == known.end())
    {
      throw Error("unknown argument '" + argument + "' for " + argv[1] + " (see --help)");
    }
    if (i + 1 >= argc)
    {
      throw Error(argument + " needs a value");
    }
    options[argument] = argv[++i];
  }
  return options;
}

std::string
Required(const ArgumentMap & options, const std::string & name)
{
  const auto found = options.find(name);
  if (found == options.end() || found->second.empty())
  {
    throw Error(name + " is required (see --help)");
  }
  return found->second;
}

double
NumberOr(const ArgumentMap & options, const std::string & name, double fallback)
{
  const auto found = options.find(name);
  return found == options.end() ? fallback : ffd::ParseNumber<Error>(name, found->second);
}

MeshType::Pointer
ReadMesh(const std::string & fileName, const std::string & role)
{
  return ffd::ReadCheckedMesh<Error, MeshType>(fileName, role);
}

void
WriteMesh(const MeshType * mesh, const std::string & fileName)
{
  ffd::WriteMeshFile<Error>(mesh, fileName, fileName);
}

void
WriteText(const std::string & fileName, const std::string & text)
{
  std::ofstream out(fileName);
  out << text;
  out.close();
  if (!out)
  {
    throw Error("cannot write '" + fileName + "'");
  }
}

void
BoundingBox(const MeshType * mesh, PointType & low, PointType & high)
{
  low.Fill(std::numeric_limits<float>::max());
  high.Fill(std::numeric_limits<float>::lowest());
  for (auto it = mesh->GetPoints()->Begin(); it != mesh->GetPoints()->End(); ++it)
  {
    for (unsigned int d = 0; d < 3; ++d)
    {
      low[d] = std::min(low[d], it.Value()[d]);
      high[d] = std::max(high[d], it.Value()[d]);
    }
  }
}

// The triangles of a mesh (polygon cells fan-triangulated) as vertex id triples.
std::vector<std::array<itk::IdentifierType, 3>>
Triangles(const MeshType * mesh)
{
  std::vector<std::array<itk::IdentifierType, 3>> triangles;
  for (auto it = mesh->GetCells()->Begin(); it != mesh->GetCells()->End(); ++it)
  {
    const auto *       ids = it.Value()->GetPointIds();
    const unsigned int n = it.Value()->GetNumberOfPoints();
    for (unsigned int j = 1; j + 1 < n; ++j)
    {
      triangles.push_back({ ids[0], ids[j], ids[j + 1] });
    }
  }
  return triangles;
}

// A mesh of the given points (ids 0..n-1) and triangles, with no point or cell data.
MeshType::Pointer
MakeMesh(const std::vector<PointType> & points, const std::vector<std::array<itk::IdentifierType, 3>> & triangles)
{
  auto mesh = MeshType::New();
  for (itk::IdentifierType i = 0; i < points.size(); ++i)
  {
    mesh->SetPoint(i, points[i]);
  }
  itk::IdentifierType cellId = 0;
  for (const auto & triangle : triangles)
  {
    MeshType::CellType::CellAutoPointer cell;
    cell.TakeOwnership(new TriangleType);
    for (unsigned int j = 0; j < 3; ++j)
    {
      cell->SetPointId(j, triangle[j]);
    }
    mesh->SetCell(cellId++, cell);
  }
  return mesh;
}

// ---------------------------------------------------------------------------------------------------
// case

int
RunCase(const ArgumentMap & options)
{
  const std::string meshName = Required(options, "--mesh");
  const std::string outDir = Required(options, "--out-dir") + "/";
  const std::string truthDir = Required(options, "--truth-dir") + "/";
  const std::string regime = Required(options, "--regime");
  const double      seedNumber = ffd::ParseNumber<Error>("--seed", Required(options, "--seed"));
  const double      fraction = NumberOr(options, "--fraction", 0.6);
  const double      grid = NumberOr(options, "--grid", 20);
  const double      margin = NumberOr(options, "--margin", 5.0);
  if (regime != "paper" && regime != "smooth" && regime != "short")
  {
    throw Error("--regime must be paper, smooth or short, not '" + regime + "'");
  }
  // smooth: Gaussian noise smoothed over 2.5 control spacings; short (a second noise model, to check that what is
  // chosen on smooth holds): over 1.25 control spacings, the same RMS target.
  const double smoothingSigma = regime == "short" ? 1.25 : 2.5;
  if (seedNumber < 0 || seedNumber != std::floor(seedNumber) || seedNumber > 4.0e9)
  {
    throw Error("--seed must be a whole number >= 0");
  }
  if (!(fraction > 0.0 && fraction <= 1.0))
  {
    throw Error("--fraction must be in (0, 1]");
  }
  if (grid < 4 || grid != std::floor(grid) || grid > 200)
  {
    throw Error("--grid must be a whole number in [4, 200]");
  }
  if (!(margin >= 0.0))
  {
    throw Error("--margin must be >= 0");
  }
  const auto seed = static_cast<uint32_t>(seedNumber);

  // Source: scaled so that its largest side is 100 mm, its bounding box starting at the origin.
  MeshType::Pointer input = ReadMesh(meshName, "input");
  PointType         low;
  PointType         high;
  BoundingBox(input, low, high);
  double largest = 0.0;
  for (unsigned int d = 0; d < 3; ++d)
  {
    largest = std::max(largest, static_cast<double>(high[d] - low[d]));
  }
  if (!(largest > 0.0) || !std::isfinite(largest))
  {
    throw Error("input mesh '" + meshName + "' has no extent or non-finite coordinates");
  }
  const double                                       scale = 100.0 / largest;
  std::vector<PointType>                             sourcePoints(input->GetNumberOfPoints());
  std::map<itk::IdentifierType, itk::IdentifierType> inputToSource;
  {
    itk::IdentifierType next = 0;
    for (auto it = input->GetPoints()->Begin(); it != input->GetPoints()->End(); ++it, ++next)
    {
      inputToSource[it.Index()] = next;
      for (unsigned int d = 0; d < 3; ++d)
      {
        sourcePoints[next][d] = (it.Value()[d] - low[d]) * scale;
      }
    }
  }
  auto sourceTriangles = Triangles(input);
  for (auto & triangle : sourceTriangles)
  {
    for (auto & id : triangle)
    {
      id = inputToSource.at(id);
    }
  }
  const MeshType::Pointer source = MakeMesh(sourcePoints, sourceTriangles);
  BoundingBox(source, low, high);

  // Region: the central box.
  PointType regionLow;
  PointType regionHigh;
  for (unsigned int d = 0; d < 3; ++d)
  {
    const double centre = 0.5 * (low[d] + high[d]);
    regionLow[d] = centre - 0.5 * fraction * (high[d] - low[d]);
    regionHigh[d] = centre + 0.5 * fraction * (high[d] - low[d]);
  }
  const auto inside = [&](const PointType & p) {
    for (unsigned int d = 0; d < 3; ++d)
    {
      if (p[d] < regionLow[d] || p[d] > regionHigh[d])
      {
        return false;
      }
    }
    return true;
  };
  // The region's triangles (all three vertices inside) and their vertices, in source order.
  std::vector<std::array<itk::IdentifierType, 3>> regionTriangles;
  std::vector<char>                               used(sourcePoints.size(), 0);
  for (const auto & triangle : sourceTriangles)
  {
    if (inside(sourcePoints[triangle[0]]) && inside(sourcePoints[triangle[1]]) && inside(sourcePoints[triangle[2]]))
    {
      regionTriangles.push_back(triangle);
      for (const auto id : triangle)
      {
        used[id] = 1;
      }
    }
  }
  std::vector<itk::IdentifierType> regionVertices;
  for (itk::IdentifierType i = 0; i < used.size(); ++i)
  {
    if (used[i])
    {
      regionVertices.push_back(i);
    }
  }
  if (regionTriangles.empty())
  {
    throw Error("the region holds no triangle of the mesh (increase --fraction)");
  }

  // T_true on a grid^3 lattice over the region grown by the margin. The smooth regime must not fold, and every
  // region vertex must have a preimage (a large displacement near the domain's edge can leave a gap there):
  // new draws (seed + 7919 k), then smaller amplitudes, until min det J > 0.2 and every inverse converges.
  PointType domainLow;
  PointType domainHigh;
  for (unsigned int d = 0; d < 3; ++d)
  {
    domainLow[d] = regionLow[d] - margin;
    domainHigh[d] = regionHigh[d] + margin;
  }
  // Target vertices: T_true^-1 of the region's source vertices, so that T_true maps them back exactly.
  std::vector<PointType> regionPoints;
  for (const auto id : regionVertices)
  {
    regionPoints.push_back(sourcePoints[id]);
  }
  const MeshType::Pointer regionMesh = MakeMesh(regionPoints, {});
  ApplyType::Pointer      apply;
  const auto              invertRegion = [&apply, &regionMesh](GeneratorType::TransformType * transform) {
    apply = ApplyType::New();
    apply->SetInput(regionMesh);
    apply->SetTransform(transform);
    apply->InverseOn();
    apply->SetInverseTolerance(1e-6);
    apply->Update();
    return apply->GetNumberOfNonConvergedPoints() == 0;
  };
  auto generator = GeneratorType::New();
  generator->SetDomainFromBoundingBox(domainLow, domainHigh);
  generator->SetNumberOfControlPointsPerAxis(static_cast<unsigned int>(grid));
  double       rms = 3.0;
  uint32_t     usedSeed = seed;
  unsigned int attempts = 0;
  unsigned int drawsWithoutPreimage = 0; // Smooth regimes: draws replaced because a region vertex had no preimage.
  if (regime == "paper")
  {
    generator->SetNoise(GeneratorType::NoiseEnum::ClippedGaussian);
    generator->SetSigma(1.0);
    generator->SetClipAmplitude(1.0);
    generator->SetSeed(seed);
    generator->Generate();
    attempts = 1;
    if (!invertRegion(generator->GetModifiableTransform()))
    {
      throw Error(std::to_string(apply->GetNumberOfNonConvergedPoints()) +
                  " region vertices have no preimage under T_true (increase --margin)");
    }
  }
  else
  {
    generator->SetNoise(GeneratorType::NoiseEnum::SmoothedGaussian);
    generator->SetSmoothingSigma(smoothingSigma);
    for (;;)
    {
      generator->SetRMSDisplacement(rms);
      generator->SetSeed(usedSeed);
      generator->Generate();
      ++attempts;
      if (generator->GetMinimumJacobianDeterminant() > 0.2)
      {
        if (invertRegion(generator->GetModifiableTransform()))
        {
          break;
        }
        ++drawsWithoutPreimage;
      }
      if (attempts % 5 == 0)
      {
        rms *= 0.9;
      }
      usedSeed = seed + 7919u * attempts;
    }
  }
  GeneratorType::TransformType::Pointer trueTransform = generator->GetModifiableTransform();

  // Shuffle: target vertex k is region vertex order[k].
  std::vector<std::size_t> order(regionVertices.size());
  std::iota(order.begin(), order.end(), 0);
  std::mt19937 random(seed);
  std::shuffle(order.begin(), order.end(), random);
  std::vector<itk::IdentifierType>                   newId(regionVertices.size());
  std::vector<PointType>                             targetPoints(regionVertices.size());
  std::map<itk::IdentifierType, itk::IdentifierType> sourceToRegion;
  for (std::size_t i = 0; i < regionVertices.size(); ++i)
  {
    sourceToRegion[regionVertices[i]] = i;
  }
  for (std::size_t k = 0; k < order.size(); ++k)
  {
    newId[order[k]] = k;
    targetPoints[k] = apply->GetOutput()->GetPoint(order[k]);
  }
  std::vector<std::array<itk::IdentifierType, 3>> targetTriangles(regionTriangles.size());
  std::vector<std::size_t>                        triangleOrder(regionTriangles.size());
  std::iota(triangleOrder.begin(), triangleOrder.end(), 0);
  std::shuffle(triangleOrder.begin(), triangleOrder.end(), random);
  for (std::size_t t = 0; t < regionTriangles.size(); ++t)
  {
    for (unsigned int j = 0; j < 3; ++j)
    {
      targetTriangles[t][j] = newId[sourceToRegion.at(regionTriangles[triangleOrder[t]][j])];
    }
  }
  const MeshType::Pointer target = MakeMesh(targetPoints, targetTriangles);

  // Displacement statistics of the region's vertices (the true error of doing nothing).
  double sum2 = 0.0;
  double maximum = 0.0;
  for (std::size_t k = 0; k < targetPoints.size(); ++k)
  {
    const double distance = targetPoints[k].EuclideanDistanceTo(sourcePoints[regionVertices[order[k]]]);
    sum2 += distance * distance;
    maximum = std::max(maximum, distance);
  }

  WriteMesh(source, outDir + "source.off");
  WriteMesh(target, outDir + "target.off");
  std::ostringstream truth;
  truth << "# target_vertex_id source_vertex_id\n";
  for (std::size_t k = 0; k < order.size(); ++k)
  {
    truth << k << ' ' << regionVertices[order[k]] << '\n';
  }
  WriteText(truthDir + "truth.txt", truth.str());
  auto transformWriter = itk::TransformFileWriterTemplate<double>::New();
  transformWriter->SetInput(trueTransform);
  transformWriter->SetFileName(truthDir + "T_true.tfm");
  transformWriter->Update();

  std::ostringstream json;
  json << std::setprecision(10) << "{\n  \"mesh\": " << JsonString(meshName)
       << ",\n  \"regime\": " << JsonString(regime) << ",\n  \"seed\": " << seed
       << ",\n  \"generator_seed\": " << usedSeed << ",\n  \"attempts\": " << attempts
       << ",\n  \"draws_without_preimage\": " << drawsWithoutPreimage << ",\n  \"scale\": " << scale
       << ",\n  \"fraction\": " << fraction << ",\n  \"grid\": " << grid << ",\n  \"margin\": " << margin
       << ",\n  \"noise\": "
       << (regime == "paper" ? "{ \"type\": \"ClippedGaussian\", \"sigma\": 1, \"clip\": 1 }"
                             : "{ \"type\": \"SmoothedGaussian\", \"smoothing_sigma\": " +
                                 ffd::JsonNumber(smoothingSigma) + ", \"rms_control\": " + ffd::JsonNumber(rms) + " }")
       << ",\n  \"min_jacobian_determinant\": " << ffd::JsonNumber(generator->GetMinimumJacobianDeterminant())
       << ",\n  \"max_jacobian_determinant\": " << ffd::JsonNumber(generator->GetMaximumJacobianDeterminant())
       << ",\n  \"region_low\": [" << regionLow[0] << ", " << regionLow[1] << ", " << regionLow[2] << "]"
       << ",\n  \"region_high\": [" << regionHigh[0] << ", " << regionHigh[1] << ", " << regionHigh[2] << "]"
       << ",\n  \"source_vertices\": " << sourcePoints.size() << ",\n  \"source_triangles\": " << sourceTriangles.size()
       << ",\n  \"target_vertices\": " << targetPoints.size() << ",\n  \"target_triangles\": " << targetTriangles.size()
       << ",\n  \"vertex_displacement_rms\": " << ffd::JsonNumber(std::sqrt(sum2 / targetPoints.size()))
       << ",\n  \"vertex_displacement_max\": " << ffd::JsonNumber(maximum) << "\n}\n";
  WriteText(truthDir + "case.json", json.str());
  std::cout << "ffd-benchmark-tool: case " << regime << " seed " << seed << ": source " << sourcePoints.size()
            << " vertices, target " << targetPoints.size() << " vertices, vertex displacement RMS "
            << std::setprecision(3) << std::sqrt(sum2 / targetPoints.size()) << " mm, min det J "
            << generator->GetMinimumJacobianDeterminant() << std::endl;
  return EXIT_SUCCESS;
}

// ---------------------------------------------------------------------------------------------------
// apply-field

FieldTransformType::Pointer
ReadFieldTransform(const std::string & fileName)
{
  if (!std::ifstream(fileName).good())
  {
    throw Error("cannot read displacement field '" + fileName + "': no such readable file");
  }
  auto reader = itk::ImageFileReader<FieldImageType>::New();
  reader->SetFileName(fileName);
  try
  {
    reader->Update();
  }
  catch (const itk::ExceptionObject & error)
  {
    throw Error("cannot read displacement field '" + fileName + "': " + OneLine(error.GetDescription()));
  }
  auto transform = FieldTransformType::New();
  transform->SetDisplacementField(reader->GetOutput());
  return transform;
}

int
RunApplyField(const ArgumentMap & options)
{
  const MeshType::Pointer source = ReadMesh(Required(options, "--source"), "source");
  const auto              field = ReadFieldTransform(Required(options, "--field"));
  const std::string       output = Required(options, "--output");
  auto                    apply = ApplyType::New();
  apply->SetInput(source);
  apply->SetTransform(field);
  apply->InverseOn();
  apply->SetInverseTolerance(1e-4);
  apply->Update();
  WriteMesh(apply->GetOutput(), output);
  const auto report = options.find("--report");
  if (report != options.end())
  {
    WriteText(report->second,
              "{ \"non_converged_inverse_vertices\": " + std::to_string(apply->GetNumberOfNonConvergedPoints()) +
                ", \"max_inverse_residual\": " + ffd::JsonNumber(apply->GetMaximumInverseResidual()) + " }\n");
  }
  std::cout << "ffd-benchmark-tool: apply-field: wrote " << output << " (" << apply->GetNumberOfNonConvergedPoints()
            << " non-converged inverse vertices)" << std::endl;
  return EXIT_SUCCESS;
}

// ---------------------------------------------------------------------------------------------------
// score

CorrespondenceContainerType
ReadTruth(const std::string & fileName)
{
  std::ifstream in(fileName);
  if (!in)
  {
    throw Error("cannot read the truth '" + fileName + "'");
  }
  CorrespondenceContainerType correspondences; // (deformed source id, target id)
  std::string                 line;
  while (std::getline(in, line))
  {
    if (line.empty() || line[0] == '#')
    {
      continue;
    }
    std::istringstream  fields(line);
    itk::IdentifierType targetId = 0;
    itk::IdentifierType sourceId = 0;
    if (!(fields >> targetId >> sourceId))
    {
      throw Error("bad line in the truth '" + fileName + "': " + line);
    }
    correspondences.emplace_back(sourceId, targetId);
  }
  if (correspondences.empty())
  {
    throw Error("the truth '" + fileName + "' is empty");
  }
  return correspondences;
}

// Minimum Jacobian determinant of a transform over the bounding box of the target (1 mm grid).
double
MinimumJacobianDeterminant(const TransformBaseType * transform, const MeshType * target, double & maximum)
{
  PointType low;
  PointType high;
  BoundingBox(target, low, high);
  JacobianImageType::SizeType    size;
  JacobianImageType::SpacingType spacing;
  JacobianImageType::PointType   origin;
  for (unsigned int d = 0; d < 3; ++d)
  {
    spacing[d] = 1.0;
    origin[d] = low[d];
    size[d] = static_cast<itk::SizeValueType>(std::floor(high[d] - low[d])) + 1;
  }
  auto filter = JacobianFilterType::New();
  filter->SetTransform(transform);
  filter->SetSize(size);
  filter->SetOutputSpacing(spacing);
  filter->SetOutputOrigin(origin);
  filter->Update();
  maximum = filter->GetMaximumDeterminant();
  return filter->GetMinimumDeterminant();
}

int
RunScore(const ArgumentMap & options)
{
  const MeshType::Pointer deformed = ReadMesh(Required(options, "--deformed"), "deformed");
  const MeshType::Pointer target = ReadMesh(Required(options, "--target"), "target");
  const auto              correspondences = ReadTruth(Required(options, "--truth"));
  const std::string       output = Required(options, "--output");

  auto trueError = CorrespondenceErrorType::New();
  trueError->SetMovedMesh(deformed);
  trueError->SetReferenceMesh(target);
  trueError->SetCorrespondences(correspondences);
  trueError->Compute();

  auto directed = SurfaceDistanceType::New();
  directed->SetSourceMesh(target);
  directed->SetTargetMesh(deformed);
  directed->Compute();

  // The deformed region: the deformed source's triangles whose three vertices are region vertices, as a mesh of
  // its own (only those vertices, renumbered), so that the rest of the source does not count.
  std::vector<itk::IdentifierType> regionId(deformed->GetNumberOfPoints(),
                                            itk::NumericTraits<itk::IdentifierType>::max());
  std::vector<PointType>           regionPoints;
  for (const auto & correspondence : correspondences)
  {
    if (correspondence.first >= regionId.size())
    {
      throw Error("the truth names source vertex " + std::to_string(correspondence.first) +
                  " but the deformed source has " + std::to_string(regionId.size()) + " vertices");
    }
    if (regionId[correspondence.first] == itk::NumericTraits<itk::IdentifierType>::max())
    {
      regionId[correspondence.first] = regionPoints.size();
      regionPoints.push_back(deformed->GetPoint(correspondence.first));
    }
  }
  std::vector<std::array<itk::IdentifierType, 3>> regionTriangles;
  for (auto triangle : Triangles(deformed))
  {
    bool all = true;
    for (auto & id : triangle)
    {
      all = all && regionId[id] != itk::NumericTraits<itk::IdentifierType>::max();
      id = all ? regionId[id] : id;
    }
    if (all)
    {
      regionTriangles.push_back(triangle);
    }
  }
  if (regionTriangles.empty())
  {
    throw Error("the deformed source has no triangle in the region");
  }
  const MeshType::Pointer deformedRegion = MakeMesh(regionPoints, regionTriangles);
  const double symmetricHausdorff = SurfaceDistanceType::ComputeSymmetricHausdorffDistance(target, deformedRegion);

  double      minimumDeterminant = std::numeric_limits<double>::quiet_NaN();
  double      maximumDeterminant = std::numeric_limits<double>::quiet_NaN();
  std::string jacobianSource = "none";
  const auto  transformFile = options.find("--transform");
  const auto  fieldFile = options.find("--field");
  if (transformFile != options.end())
  {
    try
    {
      auto reader = itk::TransformFileReaderTemplate<double>::New();
      reader->SetFileName(transformFile->second);
      reader->Update();
      const auto * list = reader->GetTransformList();
      if (list->size() == 1)
      {
        const auto * transform = dynamic_cast<const TransformBaseType *>(list->front().GetPointer());
        if (transform != nullptr)
        {
          minimumDeterminant = MinimumJacobianDeterminant(transform, target, maximumDeterminant);
          jacobianSource = "transform";
        }
      }
    }
    catch (const itk::ExceptionObject & error)
    {
      std::cerr << "ffd-benchmark-tool: score: no Jacobian from '" << transformFile->second
                << "': " << OneLine(error.GetDescription()) << std::endl;
    }
  }
  else if (fieldFile != options.end())
  {
    const auto field = ReadFieldTransform(fieldFile->second);
    minimumDeterminant = MinimumJacobianDeterminant(field, target, maximumDeterminant);
    jacobianSource = "field";
  }

  std::ostringstream json;
  json << "{\n  \"true_error\": { \"mean\": " << ffd::JsonNumber(trueError->GetMeanError())
       << ", \"median\": " << ffd::JsonNumber(trueError->GetMedianError())
       << ", \"p95\": " << ffd::JsonNumber(trueError->GetPercentile95Error())
       << ", \"max\": " << ffd::JsonNumber(trueError->GetMaximumError())
       << ", \"rms\": " << ffd::JsonNumber(trueError->GetRootMeanSquareError()) << " },\n"
       << "  \"region_vertices\": " << correspondences.size() << ",\n"
       << "  \"mean_directed_hausdorff\": " << ffd::JsonNumber(directed->GetMeanDistance()) << ",\n"
       << "  \"directed_hausdorff\": " << ffd::JsonNumber(directed->GetMaximumDistance()) << ",\n"
       << "  \"symmetric_hausdorff_region\": " << ffd::JsonNumber(symmetricHausdorff) << ",\n"
       << "  \"min_jacobian_determinant\": " << ffd::JsonNumber(minimumDeterminant) << ",\n"
       << "  \"max_jacobian_determinant\": " << ffd::JsonNumber(maximumDeterminant) << ",\n"
       << "  \"jacobian_from\": " << JsonString(jacobianSource) << "\n}\n";
  WriteText(output, json.str());
  std::cout << "ffd-benchmark-tool: score: true error mean " << std::setprecision(4) << trueError->GetMeanError()
            << " mm, mean directed Hausdorff " << directed->GetMeanDistance() << " mm" << std::endl;
  return EXIT_SUCCESS;
}
} // namespace

int
main(int argc, char * argv[])
{
  try
  {
    const std::string command = argc > 1 ? argv[1] : "";
    if (command.empty() || command == "--help" || command == "-h")
    {
      std::cout << Usage;
      return command.empty() ? EXIT_FAILURE : EXIT_SUCCESS;
    }
    itk::RegisterFFDShapeMatchingMeshIOFactories();
    itk::TransformFactoryBase::RegisterDefaultTransforms();
    if (command == "case")
    {
      return RunCase(ParseOptions(
        argc,
        argv,
        { "--mesh", "--out-dir", "--truth-dir", "--regime", "--seed", "--fraction", "--grid", "--margin" }));
    }
    if (command == "apply-field")
    {
      return RunApplyField(ParseOptions(argc, argv, { "--source", "--field", "--output", "--report" }));
    }
    if (command == "score")
    {
      return RunScore(
        ParseOptions(argc, argv, { "--deformed", "--target", "--truth", "--output", "--transform", "--field" }));
    }
    throw Error("unknown command '" + command + "' (expected case, apply-field or score)");
  }
  catch (const itk::ExceptionObject & error)
  {
    std::cerr << "ffd-benchmark-tool: error: " << OneLine(error.GetDescription()) << std::endl;
  }
  catch (const std::exception & error)
  {
    std::cerr << "ffd-benchmark-tool: error: " << OneLine(error.what()) << std::endl;
  }
  return EXIT_FAILURE;
}
