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
// ffd-match --demo: a CAD-like part (a flange plate with a boss and a through hole), a target cut out of it and
// deformed by smooth random B-spline noise (the correspondences are kept), matched and scored.

#include "FFDMatch.h"
#include "FFDMatchPipeline.h"
#include "FFDOutputFiles.h"
#include "FFDProgramMeshIO.h"
#include "FFDProgramSupport.h"
#include "FFDSnapshot.h"
#include "itkRandomBSplineTransformGenerator.h"
#include "itkTriangleCell.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <limits>
#include <map>
#include <sstream>

namespace ffd
{
namespace
{ // ---------------------------------------------------------------------------------------------------
// Demo part: a rectangular flange plate with a rectangular boss on top and a round through hole.
// The surface is a tensor grid (profile curve around the hole x angle around the hole axis), so it is
// closed, watertight and of genus one by construction; square corners are sampled exactly.

// Distance from the origin to the rectangle [-hx, hx] x [-hy, hy] along the direction at angle theta.
double
RectangleRadius(double theta, double hx, double hy)
{
  const double c = std::abs(std::cos(theta));
  const double s = std::abs(std::sin(theta));
  double       r = std::numeric_limits<double>::infinity();
  if (c > 1e-12)
  {
    r = std::min(r, hx / c);
  }
  if (s > 1e-12)
  {
    r = std::min(r, hy / s);
  }
  return r;
}

MeshType::Pointer
MakeDemoPart()
{
  constexpr double holeRadius = 7.0;
  constexpr double flangeX = 50.0; // half sizes: 100 x 70 x 8 mm flange
  constexpr double flangeY = 35.0;
  constexpr double flangeHeight = 8.0;
  constexpr double bossX = 22.0; // 44 x 32 mm boss up to 24 mm
  constexpr double bossY = 16.0;
  constexpr double shoulderHeight = 24.0;
  constexpr double topX = 13.0; // 26 x 20 mm top boss up to 40 mm
  constexpr double topY = 10.0;
  constexpr double height = 40.0;

  // Angles: uniform, plus the rectangles' corners.
  std::vector<double>    angles;
  constexpr unsigned int uniformAngles = 128;
  for (unsigned int k = 0; k < uniformAngles; ++k)
  {
    angles.push_back(2.0 * itk::Math::pi * k / uniformAngles);
  }
  for (const auto & half :
       { std::make_pair(flangeX, flangeY), std::make_pair(bossX, bossY), std::make_pair(topX, topY) })
  {
    const double a = std::atan2(half.second, half.first);
    for (const double corner : { a, itk::Math::pi - a, itk::Math::pi + a, 2.0 * itk::Math::pi - a })
    {
      angles.push_back(corner);
    }
  }
  std::sort(angles.begin(), angles.end());
  angles.erase(std::unique(angles.begin(), angles.end(), [](double a, double b) { return std::abs(a - b) < 1e-3; }),
               angles.end());

  // Profile key points around the hole: (outline, z), 0 = hole circle, 1 = boss, 2 = flange, 3 = top boss; and
  // the number of segments to the next key point.
  struct Key
  {
    int          outline;
    double       z;
    unsigned int segments;
  };
  const std::vector<Key> keys{ { 0, 0.0, 10 },           { 2, 0.0, 2 },
                               { 2, flangeHeight, 5 },   { 1, flangeHeight, 8 },
                               { 1, shoulderHeight, 3 }, { 3, shoulderHeight, 8 },
                               { 3, height, 4 },         { 0, height, 16 } };
  const auto             position = [&](int outline, double z, double theta) {
    const double        r = outline == 0   ? holeRadius
                                        : outline == 1 ? RectangleRadius(theta, bossX, bossY)
                                        : outline == 2 ? RectangleRadius(theta, flangeX, flangeY)
                                                       : RectangleRadius(theta, topX, topY);
    MeshType::PointType p;
    p[0] = r * std::cos(theta);
    p[1] = r * std::sin(theta);
    p[2] = z;
    return p;
  };

  auto         mesh = MeshType::New();
  unsigned int profileSize = 0;
  for (const Key & key : keys)
  {
    profileSize += key.segments;
  }
  const auto          n = static_cast<unsigned int>(angles.size());
  itk::IdentifierType id = 0;
  for (std::size_t k = 0; k < keys.size(); ++k)
  {
    const Key & from = keys[k];
    const Key & to = keys[(k + 1) % keys.size()];
    for (unsigned int s = 0; s < from.segments; ++s)
    {
      const double t = static_cast<double>(s) / from.segments;
      for (const double theta : angles)
      {
        const auto          a = position(from.outline, from.z, theta);
        const auto          b = position(to.outline, to.z, theta);
        MeshType::PointType p;
        for (unsigned int d = 0; d < 3; ++d)
        {
          p[d] = (1.0 - t) * a[d] + t * b[d];
        }
        mesh->SetPoint(id++, p);
      }
    }
  }

  // Two triangles per grid quad; orientation fixed afterwards from the signed volume.
  std::vector<std::array<itk::IdentifierType, 3>> triangles;
  for (unsigned int i = 0; i < profileSize; ++i)
  {
    const unsigned int i1 = (i + 1) % profileSize;
    for (unsigned int k = 0; k < n; ++k)
    {
      const unsigned int k1 = (k + 1) % n;
      const auto v = [n](unsigned int a, unsigned int b) { return static_cast<itk::IdentifierType>(a * n + b); };
      triangles.push_back({ v(i, k), v(i1, k), v(i1, k1) });
      triangles.push_back({ v(i, k), v(i1, k1), v(i, k1) });
    }
  }
  double volume = 0.0;
  for (const auto & t : triangles)
  {
    const auto a = mesh->GetPoint(t[0]).GetVectorFromOrigin();
    const auto b = mesh->GetPoint(t[1]).GetVectorFromOrigin();
    const auto c = mesh->GetPoint(t[2]).GetVectorFromOrigin();
    volume += a * itk::CrossProduct(b, c) / 6.0;
  }
  using CellAutoPointer = MeshType::CellType::CellAutoPointer;
  using TriangleType = itk::TriangleCell<MeshType::CellType>;
  itk::IdentifierType cellId = 0;
  for (auto t : triangles)
  {
    if (volume < 0.0)
    {
      std::swap(t[1], t[2]);
    }
    CellAutoPointer cell;
    cell.TakeOwnership(new TriangleType);
    for (unsigned int j = 0; j < 3; ++j)
    {
      cell->SetPointId(j, t[j]);
    }
    mesh->SetCell(cellId++, cell);
  }
  return mesh;
}

} // namespace

int
RunDemo(Options options)
{
  const auto start = ClockType::now();
  // A small grid and coarse voxels: the demo runs in about a second.
  options.grid = options.grid.value_or(8);
  options.voxelSize = options.voxelSize.value_or(1.5);
  options.iterations = options.iterations.value_or(40);
  options.sampling = options.sampling.value_or(0.5);
  options.seed = options.seed.value_or(GetMatchingDefaults().seed);
  std::error_code error;
  std::filesystem::create_directories(options.outputDir, error);
  if (error || !std::filesystem::is_directory(options.outputDir))
  {
    throw Error("cannot create the output folder '" + options.outputDir + "'");
  }
  const std::string dir = options.outputDir + "/";

  // Source: the part, scaled so its largest side is 100 mm.
  MeshType::Pointer   source = MakeDemoPart();
  MeshType::PointType low = source->GetBoundingBox()->GetMinimum();
  MeshType::PointType high = source->GetBoundingBox()->GetMaximum();
  double              largest = 0.0;
  for (unsigned int d = 0; d < 3; ++d)
  {
    largest = std::max(largest, static_cast<double>(high[d] - low[d]));
  }
  const double scale = 100.0 / largest;
  for (auto it = source->GetPoints()->Begin(); it != source->GetPoints()->End(); ++it)
  {
    for (unsigned int d = 0; d < 3; ++d)
    {
      it.Value()[d] *= scale;
    }
  }
  source->GetPoints()->Modified();
  low = source->GetBoundingBox()->GetMinimum();
  high = source->GetBoundingBox()->GetMaximum();

  // Region: a central box, 60 % of the extent in x and y, 70 % in z (it keeps the flange's top face).
  MeshType::PointType regionMinimum;
  MeshType::PointType regionMaximum;
  const double        fraction[3] = { 0.6, 0.6, 0.7 };
  for (unsigned int d = 0; d < 3; ++d)
  {
    const double centre = 0.5 * (low[d] + high[d]);
    regionMinimum[d] = centre - 0.5 * fraction[d] * (high[d] - low[d]);
    regionMaximum[d] = centre + 0.5 * fraction[d] * (high[d] - low[d]);
  }

  // Deformation: smooth random B-spline noise around the region.
  using GeneratorType = itk::RandomBSplineTransformGenerator<double, 3>;
  auto                     generator = GeneratorType::New();
  GeneratorType::PointType domainMinimum;
  GeneratorType::PointType domainMaximum;
  for (unsigned int d = 0; d < 3; ++d)
  {
    domainMinimum[d] = regionMinimum[d] - 10.0;
    domainMaximum[d] = regionMaximum[d] + 10.0;
  }
  generator->SetDomainFromBoundingBox(domainMinimum, domainMaximum);
  generator->SetNumberOfControlPointsPerAxis(6);
  generator->SetNoise(GeneratorType::NoiseEnum::SmoothedGaussian);
  generator->SetSmoothingSigma(1.0);
  generator->SetRMSDisplacement(10.0);
  generator->SetSeed(static_cast<uint32_t>(*options.seed));
  generator->Generate();
  const auto * deformation = generator->GetTransform();

  // Target: the region's triangles (all three vertices inside), moved by the deformation; the vertex ids
  // of source and target are the ground-truth correspondences.
  const auto inside = [&](const MeshType::PointType & p) {
    for (unsigned int d = 0; d < 3; ++d)
    {
      if (p[d] < regionMinimum[d] || p[d] > regionMaximum[d])
      {
        return false;
      }
    }
    return true;
  };
  auto                                               target = MeshType::New();
  std::map<itk::IdentifierType, itk::IdentifierType> targetId;
  GroundTruth                                        truth;
  itk::IdentifierType                                targetCellId = 0;
  for (auto it = source->GetCells()->Begin(); it != source->GetCells()->End(); ++it)
  {
    const auto * ids = it.Value()->GetPointIds();
    bool         all = true;
    for (unsigned int j = 0; j < 3; ++j)
    {
      all = all && inside(source->GetPoint(ids[j]));
    }
    if (!all)
    {
      continue;
    }
    using TriangleType = itk::TriangleCell<MeshType::CellType>;
    MeshType::CellType::CellAutoPointer cell;
    cell.TakeOwnership(new TriangleType);
    for (unsigned int j = 0; j < 3; ++j)
    {
      auto found = targetId.find(ids[j]);
      if (found == targetId.end())
      {
        const itk::IdentifierType newId = targetId.size();
        found = targetId.emplace(ids[j], newId).first;
        target->SetPoint(newId, deformation->TransformPoint(source->GetPoint(ids[j])));
        truth.correspondences.emplace_back(ids[j], newId);
      }
      cell->SetPointId(j, found->second);
    }
    target->SetCell(targetCellId++, cell);
  }
  std::cerr << "ffd-match: demo: source " << source->GetNumberOfPoints() << " vertices, " << source->GetNumberOfCells()
            << " triangles; target " << target->GetNumberOfPoints() << " vertices, " << target->GetNumberOfCells()
            << " triangles; control displacement RMS 10 mm (seed " << *options.seed << "), min det J "
            << generator->GetMinimumJacobianDeterminant() << std::endl;

  // The meshes are written and read back by the ordinary pipeline.
  options.source = dir + "source.vtp";
  options.target = dir + "target.vtp";
  options.output = dir + "deformed.vtp";
  options.transformOut = dir + "transform.tfm";
  options.report = dir + "report.json";
  std::string noSnapshot;
  if (ffd::SnapshotPossible(noSnapshot))
  {
    options.snapshot = dir + "snapshot.png";
  }
  else
  {
    std::cerr << "ffd-match: demo: no snapshot.png: " << noSnapshot << std::endl;
  }
  options.method = Options::Enums::Method::GO;
  {
    OutputFiles       meshes("ffd-match");
    const std::string sourceTemporary = meshes.Add(options.source, "the demo's source", {}, false);
    const std::string targetTemporary = meshes.Add(options.target, "the demo's target", {}, false);
    WriteCheckedMeshFile<Error>(source.GetPointer(), sourceTemporary, options.source);
    WriteCheckedMeshFile<Error>(target.GetPointer(), targetTemporary, options.target);
    try
    {
      meshes.Commit();
    }
    catch (const std::runtime_error & error)
    {
      throw Error(error.what());
    }
  }
  std::ostringstream demoJson;
  demoJson << "{ \"source_triangles\": " << source->GetNumberOfCells()
           << ", \"target_triangles\": " << target->GetNumberOfCells() << ", \"region_fraction\": [0.6, 0.6, 0.7]"
           << ", \"deformation\": { \"control_points_per_axis\": 6, \"noise\": \"SmoothedGaussian\""
           << ", \"rms_control_displacement\": 10, \"seed\": " << *options.seed
           << ", \"min_jacobian_determinant\": " << JsonNumber(generator->GetMinimumJacobianDeterminant()) << " } }";
  const double ratio = Match(options, &truth, demoJson.str());
  std::cout << "ffd-match: demo finished in " << std::fixed << std::setprecision(1) << SecondsSince(start)
            << " s; files in " << options.outputDir << std::endl;
  return ratio < 1.0 ? EXIT_SUCCESS : EXIT_FAILURE;
}
} // namespace ffd
