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
#ifndef itkMeshPoseRegistrationMethod_hxx
#define itkMeshPoseRegistrationMethod_hxx

#include "itkMeshPoseRegistrationMethod.h"
#include "itkAffineTransform.h"
#include "itkMath.h"
#include "itkMeshPolygonTriangles.h"
#include "itkMultiThreaderBase.h"
#include "FFDShapeMatchingDetail/itkPointCloudKdTree.h"
#include "itkSimilarity3DTransform.h"
#include "FFDShapeMatchingDetail/itkTriangleBoundingVolumeHierarchy.h"
#include "itkVersorRigid3DTransform.h"

#include "itk_eigen.h"
#include ITK_EIGEN(Dense)
#include ITK_EIGEN(Geometry)

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <numeric>
#include <random>

namespace itk
{
namespace detail
{
/** A pose y = Linear x + Translation from target to source space, the start it came from and its score. */
struct MeshPoseCandidate
{
  Eigen::Matrix3d Linear{ Eigen::Matrix3d::Identity() };
  Eigen::Vector3d Translation{ Eigen::Vector3d::Zero() };
  double          Score{ std::numeric_limits<double>::max() };
  unsigned int    Rotation{ 0 };
  unsigned int    Scale{ 0 };
  unsigned int    Offset{ 0 };
};

/** The nearest rotation to \c linear (its polar factor, determinant +1). */
inline Eigen::Matrix3d
MeshPoseRotationOf(const Eigen::Matrix3d & linear)
{
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(linear, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d                         u = svd.matrixU();
  const Eigen::Matrix3d                   v = svd.matrixV();
  if ((u * v.transpose()).determinant() < 0.0)
  {
    u.col(2) = -u.col(2);
  }
  return u * v.transpose();
}

/** The isotropic scale of \c linear: the cube root of the absolute determinant. */
inline double
MeshPoseScaleOf(const Eigen::Matrix3d & linear)
{
  return std::cbrt(std::abs(linear.determinant()));
}

/** A pose x -> L x + o decomposed for reports: the angle (degrees, 0 to 180) and unit axis of its rotation (the
 * polar factor of L), its isotropic scale (1 for a rigid pose, else the cube root of |det L|) and the translation of
 * \c center (where it goes, minus where it was). */
struct MeshPoseDecomposition
{
  double          Angle{ 0.0 };
  Eigen::Vector3d Axis{ 0.0, 0.0, 1.0 };
  double          Scale{ 1.0 };
  Eigen::Vector3d Translation{ 0.0, 0.0, 0.0 };
};

inline MeshPoseDecomposition
DecomposeMeshPose(const Eigen::Matrix3d & linear,
                  const Eigen::Vector3d & offset,
                  const Eigen::Vector3d & center,
                  bool                    rigid)
{
  MeshPoseDecomposition result;
  result.Translation = linear * center + offset - center;
  result.Scale = rigid ? 1.0 : MeshPoseScaleOf(linear);
  const Eigen::AngleAxisd angleAxis(MeshPoseRotationOf(linear));
  result.Angle = angleAxis.angle() * 180.0 / Math::pi;
  result.Axis = angleAxis.axis();
  return result;
}

/** The angle in degrees of the rotation \c a^T \c b. */
inline double
MeshPoseRotationDistance(const Eigen::Matrix3d & a, const Eigen::Matrix3d & b)
{
  const double cosine = std::max(-1.0, std::min(1.0, 0.5 * ((a.transpose() * b).trace() - 1.0)));
  return std::acos(cosine) * 180.0 / Math::pi;
}

/** Area-uniform random samples of a mesh's surface (its cells of three or more points, fanned into triangles), or
 * of its vertices when it has no cell of positive area, with their triangles' normals when \c normals is given and
 * a hierarchy of its triangles (for exact distances) built in \c surface when given. Throws on an empty mesh or a
 * non-finite coordinate. */
template <typename TMesh>
std::vector<Eigen::Vector3d>
SampleMeshSurface(const TMesh *                     mesh,
                  unsigned int                      count,
                  std::mt19937 &                    random,
                  const char *                      name,
                  std::vector<Eigen::Vector3d> *    normals = nullptr,
                  TriangleBoundingVolumeHierarchy * surface = nullptr)
{
  const auto numberOfPoints = mesh->GetNumberOfPoints();
  if (numberOfPoints == 0)
  {
    itkGenericExceptionMacro(<< "MeshPoseRegistrationMethod: the " << name << " mesh has no points");
  }
  std::vector<Eigen::Vector3d> vertices;
  vertices.reserve(numberOfPoints);
  for (auto it = mesh->GetPoints()->Begin(); it != mesh->GetPoints()->End(); ++it)
  {
    const auto &          p = it.Value();
    const Eigen::Vector3d v(p[0], p[1], p[2]);
    if (!v.allFinite())
    {
      itkGenericExceptionMacro(<< "MeshPoseRegistrationMethod: the " << name
                               << " mesh has a non-finite coordinate (point " << it.Index() << ")");
    }
    vertices.push_back(v);
  }
  std::vector<std::array<Eigen::Vector3d, 3>> triangles;
  std::vector<double>                         areas;
  const auto                                  corner = [mesh, name](typename TMesh::PointIdentifier id) {
    typename TMesh::PointType p;
    if (!mesh->GetPoint(id, &p))
    {
      itkGenericExceptionMacro(<< "MeshPoseRegistrationMethod: a cell of the " << name
                               << " mesh names a missing point (" << id << ")");
    }
    return Eigen::Vector3d(p[0], p[1], p[2]);
  };
  ForEachPolygonTriangle(mesh, [&](IdentifierType, const typename TMesh::PointIdentifier * ids) {
    const std::array<Eigen::Vector3d, 3> triangle{ { corner(ids[0]), corner(ids[1]), corner(ids[2]) } };
    const double area = 0.5 * (triangle[1] - triangle[0]).cross(triangle[2] - triangle[0]).norm();
    if (area > 0.0 && std::isfinite(area))
    {
      triangles.push_back(triangle);
      areas.push_back(area);
    }
  });
  if (surface != nullptr)
  {
    std::vector<TriangleBoundingVolumeHierarchy::Triangle> soup;
    soup.reserve(triangles.size());
    for (const auto & t : triangles)
    {
      soup.push_back(
        { { { t[0][0], t[0][1], t[0][2] } }, { { t[1][0], t[1][1], t[1][2] } }, { { t[2][0], t[2][1], t[2][2] } } });
    }
    surface->Build(std::move(soup), 4, false); // distances only
  }
  std::vector<Eigen::Vector3d> samples;
  samples.reserve(count);
  if (triangles.empty())
  {
    std::uniform_int_distribution<size_t> pick(0, vertices.size() - 1);
    for (unsigned int n = 0; n < count; ++n)
    {
      samples.push_back(vertices[pick(random)]);
    }
    return samples;
  }
  std::discrete_distribution<size_t>     pick(areas.begin(), areas.end());
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  if (normals != nullptr)
  {
    normals->clear();
    normals->reserve(count);
  }
  for (unsigned int n = 0; n < count; ++n)
  {
    const auto & t = triangles[pick(random)];
    if (normals != nullptr)
    {
      normals->push_back((t[1] - t[0]).cross(t[2] - t[0]).normalized());
    }
    double a = unit(random);
    double b = unit(random);
    if (a + b > 1.0)
    {
      a = 1.0 - a;
      b = 1.0 - b;
    }
    samples.push_back(t[0] + a * (t[1] - t[0]) + b * (t[2] - t[0]));
  }
  return samples;
}

/** Nearest source samples of mapped target samples, and the trimmed statistics the score and ICP use. */
class MeshPoseMatcher
{
public:
  using TreeType = PointCloudKdTree<Eigen::Vector3d>;

  MeshPoseMatcher(const std::vector<Eigen::Vector3d> &    source,
                  const std::vector<Eigen::Vector3d> &    normals,
                  double                                  minimumScale,
                  double                                  maximumScale,
                  const TriangleBoundingVolumeHierarchy * surface = nullptr)
    : m_Source(source)
    , m_Normals(normals)
    , m_Surface(surface)
    , m_MinimumScale(minimumScale)
    , m_MaximumScale(maximumScale)
    , m_Cloud{ source }
    , m_Tree(3, m_Cloud, nanoflann::KDTreeSingleIndexAdaptorParams(16))
  {
    m_Tree.buildIndex();
  }

  /** Trimmed mean distance (source units) from the first \c count of \c target, mapped, to the source. */
  double
  TrimmedDistance(const Eigen::Matrix3d &              linear,
                  const Eigen::Vector3d &              translation,
                  const std::vector<Eigen::Vector3d> & target,
                  size_t                               count,
                  double                               trim) const
  {
    std::vector<double> squares(count);
    for (size_t m = 0; m < count; ++m)
    {
      squares[m] = this->NearestSquare(linear * target[m] + translation, nullptr);
    }
    return TrimmedMean(squares, trim);
  }

  /** Squared distance from \c q to its nearest source sample, whose index goes to \c index when given. */
  double
  NearestSquare(const Eigen::Vector3d & q, size_t * index) const
  {
    size_t nearest = 0;
    double squared = 0.0;
    m_Tree.knnSearch(q.data(), 1, &nearest, &squared);
    if (index != nullptr)
    {
      *index = nearest;
    }
    return squared;
  }

  /** Mean of the square roots of the smallest \c trim fraction of \c squares (which is reordered). */
  static double
  TrimmedMean(std::vector<double> & squares, double trim)
  {
    const size_t kept = KeptCount(squares.size(), trim);
    std::nth_element(squares.begin(), squares.begin() + (kept - 1), squares.end());
    double sum = 0.0;
    for (size_t m = 0; m < kept; ++m)
    {
      sum += std::sqrt(squares[m]);
    }
    return sum / static_cast<double>(kept);
  }

  static size_t
  KeptCount(size_t count, double trim)
  {
    return std::max<size_t>(1, std::min(count, static_cast<size_t>(std::lround(trim * static_cast<double>(count)))));
  }

  /** Trimmed ICP from \c pose: rigid, similarity or affine closed-form steps on the \c trim closest pairs, until the
   * samples move less than \c tolerance or \c iterations are done; the similarity's scale stays within the search's
   * bounds. The pose's score follows (ScoreOf()). */
  void
  Refine(MeshPoseCandidate &                     pose,
         const std::vector<Eigen::Vector3d> &    target,
         FFDShapeMatchingEnums::InitialTransform type,
         double                                  trim,
         unsigned int                            iterations,
         double                                  tolerance) const
  {
    using PoseEnum = FFDShapeMatchingEnums::InitialTransform;
    const size_t        count = target.size();
    const size_t        kept = KeptCount(count, trim);
    std::vector<double> squares(count);
    std::vector<size_t> nearest(count);
    std::vector<size_t> order(count);
    Eigen::Matrix3Xd    from(3, kept);
    Eigen::Matrix3Xd    to(3, kept);
    const double        fixedScale = type == PoseEnum::Rigid ? MeshPoseScaleOf(pose.Linear) : 1.0;
    for (unsigned int iteration = 0; iteration < iterations; ++iteration)
    {
      for (size_t m = 0; m < count; ++m)
      {
        squares[m] = this->NearestSquare(pose.Linear * target[m] + pose.Translation, &nearest[m]);
      }
      std::iota(order.begin(), order.end(), size_t{ 0 });
      std::nth_element(order.begin(), order.begin() + (kept - 1), order.end(), [&squares](size_t a, size_t b) {
        return squares[a] < squares[b];
      });
      for (size_t k = 0; k < kept; ++k)
      {
        from.col(k) = fixedScale * target[order[k]];
        to.col(k) = m_Source[nearest[order[k]]];
      }
      Eigen::Matrix3d linear;
      Eigen::Vector3d translation;
      if (type == PoseEnum::Affine)
      {
        // Least squares [x 1] -> y on the kept pairs, by the normal equations of the centred problem.
        const Eigen::Vector3d  fromMean = from.rowwise().mean();
        const Eigen::Vector3d  toMean = to.rowwise().mean();
        const Eigen::Matrix3Xd fromCentred = from.colwise() - fromMean;
        const Eigen::Matrix3Xd toCentred = to.colwise() - toMean;
        const Eigen::Matrix3d  covariance = fromCentred * fromCentred.transpose();
        const Eigen::Matrix3d  cross = toCentred * fromCentred.transpose();
        linear = covariance.transpose().ldlt().solve(cross.transpose()).transpose();
        if (!linear.allFinite() || linear.determinant() <= 0.0)
        {
          break; // a flat or reflecting fit: keep the last proper pose
        }
        translation = toMean - linear * fromMean;
      }
      else
      {
        const Eigen::Matrix4d step = Eigen::umeyama(from, to, type == PoseEnum::Similarity);
        linear = fixedScale * step.topLeftCorner<3, 3>();
        translation = step.topRightCorner<3, 1>();
        if (type == PoseEnum::Similarity)
        {
          // The scale within the search's bounds; for a given rotation, the best translation follows in closed form.
          const double scale = MeshPoseScaleOf(linear);
          const double bounded = this->ClampScale(scale);
          if (bounded != scale)
          {
            linear *= bounded / scale;
            translation = to.rowwise().mean() - linear * from.rowwise().mean();
          }
        }
      }
      // How far the pose moved the target samples' bounding ball.
      const Eigen::Vector3d centre = from.rowwise().mean();
      const double          radius = std::sqrt((from.colwise() - centre).colwise().squaredNorm().mean());
      const double          change = ((linear - pose.Linear) * centre + translation - pose.Translation).norm() +
                            (linear - pose.Linear).norm() * radius;
      pose.Linear = linear;
      pose.Translation = translation;
      if (change < tolerance)
      {
        break;
      }
    }
    pose.Score = ScoreOf(this->TrimmedDistance(pose.Linear, pose.Translation, target, count, trim), pose.Linear);
  }

  /** The score of a pose: the trimmed mean distance over the geometric mean of the two frames' units (divided by
   * the square root of the scale), so that neither shrinking nor growing the target gains by itself. */
  static double
  ScoreOf(double trimmedDistance, const Eigen::Matrix3d & linear)
  {
    return trimmedDistance / std::sqrt(MeshPoseScaleOf(linear));
  }

  /** The squared distance from \c y to the source, its match there and the normal of the plane through it: the
   * exact closest point of the source's triangles (\c exact) or the nearest source sample and its triangle's
   * normal. */
  double
  Match(const Eigen::Vector3d & y, bool exact, Eigen::Vector3d & match, Eigen::Vector3d & normal) const
  {
    if (!exact)
    {
      size_t       nearest = 0;
      const double squared = this->NearestSquare(y, &nearest);
      match = m_Source[nearest];
      normal = m_Normals[nearest];
      return squared;
    }
    TriangleBoundingVolumeHierarchy::VectorType closest{ { y[0], y[1], y[2] } };
    size_t                                      triangle = 0;
    const double                                squared = m_Surface->SquaredDistance(
      { { y[0], y[1], y[2] } }, std::numeric_limits<double>::infinity(), &closest, &triangle);
    match = Eigen::Vector3d(closest[0], closest[1], closest[2]);
    const auto &          t = m_Surface->GetTriangles()[triangle];
    const Eigen::Vector3d a(t.a[0], t.a[1], t.a[2]);
    const Eigen::Vector3d face =
      (Eigen::Vector3d(t.b[0], t.b[1], t.b[2]) - a).cross(Eigen::Vector3d(t.c[0], t.c[1], t.c[2]) - a);
    const Eigen::Vector3d away = y - match;
    // Off the surface, the distance's gradient (exact at edges and corners too); on it, the face's normal.
    const double faceNorm = face.norm();
    if (away.squaredNorm() > 1e-12 * faceNorm || !(faceNorm > 0.0))
    {
      normal = away.normalized();
    }
    else
    {
      normal = face / faceNorm;
    }
    return squared;
  }

  /** \c scale within the search's bounds. */
  double
  ClampScale(double scale) const
  {
    return std::max(m_MinimumScale, std::min(m_MaximumScale, scale));
  }

  /** Trimmed point-to-plane steps from \c pose (linearized: a small rotation, translation and, for similarity,
   * scale, or a small affine update, solved by least squares), for a pose close to the truth already. Rigid and
   * similarity steps match each mapped target sample to the exact closest point of the source's triangles when the
   * matcher has them (the plane: the direction to that point, the triangle's normal on the surface), to the nearest
   * source sample and its triangle's normal otherwise (needed then; without them, \c pose is only scored). The
   * similarity's scale is fitted on residuals in target units (the distance over the scale), which do not gain by
   * shrinking the target: in source units the target's own deviation from the source (its deformation) shrinks
   * with it. */
  void
  Polish(MeshPoseCandidate &                     pose,
         const std::vector<Eigen::Vector3d> &    target,
         FFDShapeMatchingEnums::InitialTransform type,
         double                                  trim,
         unsigned int                            iterations,
         double                                  tolerance) const
  {
    using PoseEnum = FFDShapeMatchingEnums::InitialTransform;
    const size_t count = target.size();
    const size_t kept = KeptCount(count, trim);
    const int    unknowns = type == PoseEnum::Affine ? 12 : (type == PoseEnum::Similarity ? 7 : 6);
    const bool   exact = m_Surface != nullptr && m_Surface->GetNumberOfTriangles() > 0 && type != PoseEnum::Affine;
    std::vector<double>          squares(count);
    std::vector<Eigen::Vector3d> matched(count);
    std::vector<Eigen::Vector3d> planeNormals(count);
    std::vector<size_t>          order(count);
    for (unsigned int iteration = 0; (exact || m_Normals.size() == m_Source.size()) && iteration < iterations;
         ++iteration)
    {
      for (size_t m = 0; m < count; ++m)
      {
        squares[m] = this->Match(pose.Linear * target[m] + pose.Translation, exact, matched[m], planeNormals[m]);
      }
      std::iota(order.begin(), order.end(), size_t{ 0 });
      std::nth_element(order.begin(), order.begin() + (kept - 1), order.end(), [&squares](size_t a, size_t b) {
        return squares[a] < squares[b];
      });
      Eigen::MatrixXd normal = Eigen::MatrixXd::Zero(unknowns, unknowns);
      Eigen::VectorXd right = Eigen::VectorXd::Zero(unknowns);
      Eigen::VectorXd row(unknowns);
      double          sizeSquares = 0.0;
      for (size_t k = 0; k < kept; ++k)
      {
        const Eigen::Vector3d   y = pose.Linear * target[order[k]] + pose.Translation;
        const Eigen::Vector3d & n = planeNormals[order[k]];
        const double            residual = n.dot(y - matched[order[k]]);
        sizeSquares += y.squaredNorm();
        if (type == PoseEnum::Affine)
        {
          // y' = (I + D) y + tau: the residual changes by n . (D y) + n . tau.
          for (int a = 0; a < 3; ++a)
          {
            for (int b = 0; b < 3; ++b)
            {
              row[3 * a + b] = n[a] * y[b];
            }
            row[9 + a] = n[a];
          }
        }
        else
        {
          // y' = (1 + sigma) (y + omega x y) + tau: n . (omega x y) = omega . (y x n). In target units, the
          // residual over (1 + sigma) s: to first order, sigma's coefficient is n . (y - residual n) = n . matched.
          row.head<3>() = y.cross(n);
          row.segment<3>(3) = n;
          if (type == PoseEnum::Similarity)
          {
            row[6] = n.dot(matched[order[k]]);
          }
        }
        normal += row * row.transpose();
        right -= residual * row;
      }
      // A light ridge keeps the directions the surface does not fix (sliding along a symmetric patch) where they are.
      normal.diagonal().array() += 1e-9 * normal.trace() / unknowns;
      const Eigen::VectorXd step = normal.ldlt().solve(right);
      if (!step.allFinite())
      {
        break;
      }
      Eigen::Matrix3d update = Eigen::Matrix3d::Identity();
      Eigen::Vector3d tau;
      if (type == PoseEnum::Affine)
      {
        for (int a = 0; a < 3; ++a)
        {
          for (int b = 0; b < 3; ++b)
          {
            update(a, b) += step[3 * a + b];
          }
          tau[a] = step[9 + a];
        }
        if (update.determinant() <= 0.0)
        {
          break;
        }
      }
      else
      {
        const Eigen::Vector3d omega = step.head<3>();
        const double          angle = omega.norm();
        if (angle > 0.0)
        {
          update = Eigen::AngleAxisd(angle, omega / angle).toRotationMatrix();
        }
        tau = step.segment<3>(3);
        if (type == PoseEnum::Similarity)
        {
          const double scale = MeshPoseScaleOf(pose.Linear);
          update *= this->ClampScale(scale * (1.0 + step[6])) / scale;
        }
      }
      pose.Linear = update * pose.Linear;
      pose.Translation = update * pose.Translation + tau;
      const double radius = std::sqrt(sizeSquares / static_cast<double>(kept));
      if (tau.norm() + (update - Eigen::Matrix3d::Identity()).norm() * radius < tolerance)
      {
        break;
      }
    }
    pose.Score = ScoreOf(this->TrimmedDistance(pose.Linear, pose.Translation, target, count, trim), pose.Linear);
  }

private:
  const std::vector<Eigen::Vector3d> &    m_Source;
  const std::vector<Eigen::Vector3d> &    m_Normals;
  const TriangleBoundingVolumeHierarchy * m_Surface;
  double                                  m_MinimumScale;
  double                                  m_MaximumScale;
  PointCloudAdaptor<Eigen::Vector3d>      m_Cloud;
  TreeType                                m_Tree;
};

/** The rotations of a super-Fibonacci spiral of \c count unit quaternions: a low-discrepancy covering of SO(3). */
inline std::vector<Eigen::Matrix3d>
SuperFibonacciRotations(unsigned int count)
{
  const double                 phi = std::sqrt(2.0);
  const double                 psi = 1.533751168755204288118041;
  std::vector<Eigen::Matrix3d> rotations;
  rotations.reserve(count);
  for (unsigned int i = 0; i < count; ++i)
  {
    const double             s = i + 0.5;
    const double             r = std::sqrt(s / count);
    const double             big = std::sqrt(1.0 - s / count);
    const double             alpha = 2.0 * Math::pi * s / phi;
    const double             beta = 2.0 * Math::pi * s / psi;
    const Eigen::Quaterniond q(big * std::cos(beta), r * std::sin(alpha), r * std::cos(alpha), big * std::sin(beta));
    rotations.push_back(q.normalized().toRotationMatrix());
  }
  if (count == 1)
  {
    rotations.front().setIdentity();
  }
  return rotations;
}
} // namespace detail

template <typename TFixedMesh, typename TMovingMesh>
MeshPoseRegistrationMethod<TFixedMesh, TMovingMesh>::MeshPoseRegistrationMethod()
{
  m_RotationAxis.Fill(0.0);
  m_RotationAxis[2] = 1.0;
  m_Translation.Fill(0.0);
  m_Matrix.SetIdentity();
  m_Offset.Fill(0.0);
}

template <typename TFixedMesh, typename TMovingMesh>
void
MeshPoseRegistrationMethod<TFixedMesh, TMovingMesh>::VerifyPreconditions() const
{
  Superclass::VerifyPreconditions();
  if (m_PoseType != PoseTypeEnum::Rigid && m_PoseType != PoseTypeEnum::Similarity && m_PoseType != PoseTypeEnum::Affine)
  {
    itkExceptionMacro(<< "the pose type must be rigid, similarity or affine, not "
                      << FFDShapeMatchingEnums::InitialTransformToString(m_PoseType));
  }
}

template <typename TFixedMesh, typename TMovingMesh>
void
MeshPoseRegistrationMethod<TFixedMesh, TMovingMesh>::GenerateData()
{
  using ClockType = std::chrono::steady_clock;
  using detail::MeshPoseCandidate;
  const auto start = ClockType::now();

  // Samples of both surfaces; the first score samples of the target are also its first refinement samples.
  std::mt19937                       random(static_cast<std::mt19937::result_type>(this->GetRandomSeed()));
  const std::vector<Eigen::Vector3d> target = detail::SampleMeshSurface(
    this->GetFixedMesh(), std::max(m_NumberOfRefinementSamples, m_NumberOfScoreSamples), random, "fixed (target)");
  std::vector<Eigen::Vector3d>            normals;
  detail::TriangleBoundingVolumeHierarchy surface;
  const std::vector<Eigen::Vector3d>      source = detail::SampleMeshSurface(
    this->GetMovingMesh(), m_NumberOfSourceSamples, random, "moving (source)", &normals, &surface);
  const auto centroidAndRadius = [](const std::vector<Eigen::Vector3d> & points) {
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    for (const auto & p : points)
    {
      centroid += p;
    }
    centroid /= static_cast<double>(points.size());
    Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
    for (const auto & p : points)
    {
      covariance += (p - centroid) * (p - centroid).transpose();
    }
    covariance /= static_cast<double>(points.size());
    return std::make_pair(centroid, covariance);
  };
  const auto   targetMoments = centroidAndRadius(target);
  const auto   sourceMoments = centroidAndRadius(source);
  const double targetRadius = std::sqrt(targetMoments.second.trace());
  const double sourceRadius = std::sqrt(sourceMoments.second.trace());
  const double extent = std::max(targetRadius, sourceRadius);
  if (!(targetRadius > 1e-12 * std::max(1.0, targetMoments.first.norm())) ||
      !(sourceRadius > 1e-12 * std::max(1.0, sourceMoments.first.norm())))
  {
    itkExceptionMacro(<< "the " << (targetRadius > 0.0 ? "moving (source)" : "fixed (target)")
                      << " mesh has no extent (all its points coincide): its pose is undefined");
  }

  // The starts: rotations x scales x centroid offsets.
  const std::vector<Eigen::Matrix3d> rotations = detail::SuperFibonacciRotations(m_NumberOfRotations);
  std::vector<double>                scales;
  const double                       ratio = m_PoseType == PoseTypeEnum::Rigid ? 1.0 : sourceRadius / targetRadius;
  for (unsigned int k = 0; k < (m_PoseType == PoseTypeEnum::Rigid ? 1u : m_NumberOfScales); ++k)
  {
    scales.push_back(ratio * std::pow(m_ScaleStep, static_cast<double>(k)));
  }
  std::vector<Eigen::Vector3d> offsets{ Eigen::Vector3d::Zero() };
  if (m_TranslationOffsetFraction > 0.0)
  {
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> axes(sourceMoments.second);
    for (unsigned int d = 0; d < Dimension; ++d)
    {
      for (const double sign : { -1.0, 1.0 })
      {
        offsets.push_back(sign * m_TranslationOffsetFraction * sourceRadius * axes.eigenvectors().col(d));
      }
    }
  }
  const double minimumScale = m_PoseType == PoseTypeEnum::Rigid ? 1.0 : scales.back() * std::min(m_ScaleStep, 0.9);
  const double maximumScale = m_PoseType == PoseTypeEnum::Rigid ? 1.0 : 1.15 * scales.front();
  const detail::MeshPoseMatcher  matcher(source, normals, minimumScale, maximumScale, &surface);
  const size_t                   scoreCount = std::min<size_t>(m_NumberOfScoreSamples, target.size());
  const size_t                   perRotation = scales.size() * offsets.size();
  std::vector<MeshPoseCandidate> starts(rotations.size() * perRotation);
  MultiThreaderBase *            threader = this->GetMultiThreader();
  threader->SetNumberOfWorkUnits(this->GetNumberOfWorkUnits());
  threader->ParallelizeArray(
    0,
    rotations.size(),
    [&](SizeValueType i) {
      for (unsigned int k = 0; k < scales.size(); ++k)
      {
        for (unsigned int j = 0; j < offsets.size(); ++j)
        {
          MeshPoseCandidate & candidate = starts[i * perRotation + k * offsets.size() + j];
          candidate.Linear = scales[k] * rotations[i];
          candidate.Translation = sourceMoments.first + offsets[j] - candidate.Linear * targetMoments.first;
          candidate.Rotation = static_cast<unsigned int>(i);
          candidate.Scale = k;
          candidate.Offset = j;
          candidate.Score = detail::MeshPoseMatcher::ScoreOf(
            matcher.TrimmedDistance(candidate.Linear, candidate.Translation, target, scoreCount, m_TrimFraction),
            candidate.Linear);
        }
      }
    },
    nullptr);
  // The best StartRefinementFraction of the starts move by a few ICP steps at their own scale (rigid steps on the
  // score samples) before they are ranked: a start a few degrees or millimetres off a narrow basin (a patch of holes
  // among many alike) scores badly where it is, and well once it has slid in. The others are dropped.
  std::vector<size_t> order(starts.size());
  std::iota(order.begin(), order.end(), size_t{ 0 });
  const auto byScore = [&starts](size_t a, size_t b) { return starts[a].Score < starts[b].Score; };
  if (m_NumberOfStartIterations > 0)
  {
    std::sort(order.begin(), order.end(), byScore);
    const size_t moved = std::max<size_t>(
      1, static_cast<size_t>(std::lround(m_StartRefinementFraction * static_cast<double>(starts.size()))));
    const std::vector<Eigen::Vector3d> scoreTarget(target.begin(), target.begin() + scoreCount);
    threader->ParallelizeArray(
      0,
      moved,
      [&](SizeValueType i) {
        matcher.Refine(
          starts[order[i]], scoreTarget, PoseTypeEnum::Rigid, m_TrimFraction, m_NumberOfStartIterations, 1e-7 * extent);
      },
      nullptr);
    order.resize(moved);
  }
  m_NumberOfStarts = starts.size();

  // The best distinct starts: a start close in rotation (15 degrees), with the same scale and offset, to one kept
  // already is the same basin.
  std::sort(order.begin(), order.end(), byScore);
  std::vector<MeshPoseCandidate> candidates;
  for (const size_t index : order)
  {
    if (candidates.size() >= m_NumberOfCandidates)
    {
      break;
    }
    const MeshPoseCandidate & start = starts[index];
    const bool same = std::any_of(candidates.begin(), candidates.end(), [&](const MeshPoseCandidate & kept) {
      return kept.Scale == start.Scale && kept.Offset == start.Offset &&
             detail::MeshPoseRotationDistance(rotations[kept.Rotation], rotations[start.Rotation]) < 15.0;
    });
    if (!same)
    {
      candidates.push_back(start);
    }
  }
  m_SearchTime = std::chrono::duration<double>(ClockType::now() - start).count();

  // Refine each by trimmed ICP (rigid or similarity), keep the best; affine goes on from there.
  const auto   refineStart = ClockType::now();
  const double tolerance = 1e-7 * extent;
  const auto   firstType = m_PoseType == PoseTypeEnum::Rigid ? PoseTypeEnum::Rigid : PoseTypeEnum::Similarity;
  const std::vector<Eigen::Vector3d> candidateTarget(
    target.begin(), target.begin() + std::min<size_t>(target.size(), m_NumberOfCandidateSamples));
  threader->ParallelizeArray(
    0,
    candidates.size(),
    [&](SizeValueType c) {
      matcher.Refine(candidates[c], candidateTarget, firstType, m_TrimFraction, m_NumberOfIterations, tolerance);
    },
    nullptr);
  const auto best = std::min_element(
    candidates.begin(), candidates.end(), [](const auto & a, const auto & b) { return a.Score < b.Score; });
  MeshPoseCandidate         winner = *best;
  const Eigen::Matrix3d     winnerRotation = detail::MeshPoseRotationOf(winner.Linear);
  const MeshPoseCandidate * runnerUp = nullptr;
  for (const auto & candidate : candidates)
  {
    const double distance =
      detail::MeshPoseRotationDistance(winnerRotation, detail::MeshPoseRotationOf(candidate.Linear));
    if (distance >= 10.0 && (runnerUp == nullptr || candidate.Score < runnerUp->Score))
    {
      runnerUp = &candidate;
    }
  }
  // The runner-up's score, as refined on the candidate samples; the winner is polished point-to-plane on all.
  m_RunnerUpScore = runnerUp != nullptr ? runnerUp->Score : NumericTraits<double>::max();
  m_RunnerUpRotationDistance =
    runnerUp != nullptr ? detail::MeshPoseRotationDistance(winnerRotation, detail::MeshPoseRotationOf(runnerUp->Linear))
                        : 0.0;
  // The polish counts PolishTrimFraction of the samples (all by default: the whole target lies on the source at its
  // pose; trimming lets it slide or grow over a region larger than its own), on exact distances to the source.
  matcher.Polish(winner, target, firstType, m_PolishTrimFraction, m_NumberOfIterations, tolerance);
  winner.Score = detail::MeshPoseMatcher::ScoreOf(
    matcher.TrimmedDistance(winner.Linear, winner.Translation, target, target.size(), m_TrimFraction), winner.Linear);
  if (m_PoseType == PoseTypeEnum::Affine)
  {
    matcher.Refine(winner, target, PoseTypeEnum::Affine, m_TrimFraction, m_NumberOfIterations, tolerance);
    matcher.Polish(winner, target, PoseTypeEnum::Affine, m_TrimFraction, m_NumberOfIterations, tolerance);
  }
  m_Score = winner.Score;
  m_RefinementTime = std::chrono::duration<double>(ClockType::now() - refineStart).count();

  // The transform, centred at the target centroid: A(x) = M (x - c) + c + translation.
  const Eigen::Vector3d               c = targetMoments.first;
  const detail::MeshPoseDecomposition parts =
    detail::DecomposeMeshPose(winner.Linear, winner.Translation, c, m_PoseType == PoseTypeEnum::Rigid);
  const Eigen::Matrix3d rotation = detail::MeshPoseRotationOf(winner.Linear);
  PointType             center;
  VectorType            translationVector;
  for (unsigned int d = 0; d < Dimension; ++d)
  {
    center[d] = c[d];
    translationVector[d] = parts.Translation[d];
    m_Offset[d] = winner.Translation[d];
    m_RotationAxis[d] = parts.Axis[d];
    for (unsigned int e = 0; e < Dimension; ++e)
    {
      m_Matrix(d, e) = winner.Linear(d, e);
    }
  }
  m_Translation = translationVector;
  m_Scale = parts.Scale;
  m_RotationAngle = parts.Angle;
  Eigen::Quaterniond quaternion(rotation);
  quaternion.normalize();
  if (quaternion.w() < 0.0)
  {
    quaternion.coeffs() = -quaternion.coeffs();
  }
  typename TransformType::Pointer result;
  if (m_PoseType == PoseTypeEnum::Affine)
  {
    auto affine = AffineTransform<double, Dimension>::New();
    affine->SetCenter(center);
    affine->SetMatrix(m_Matrix);
    affine->SetTranslation(translationVector);
    result = affine;
  }
  else
  {
    Versor<double> versor;
    versor.Set(quaternion.x(), quaternion.y(), quaternion.z(), quaternion.w());
    if (m_PoseType == PoseTypeEnum::Rigid)
    {
      auto rigid = VersorRigid3DTransform<double>::New();
      rigid->SetCenter(center);
      rigid->SetRotation(versor);
      rigid->SetTranslation(translationVector);
      result = rigid;
    }
    else
    {
      auto similarity = Similarity3DTransform<double>::New();
      similarity->SetCenter(center);
      similarity->SetRotation(versor);
      similarity->SetScale(m_Scale);
      similarity->SetTranslation(translationVector);
      result = similarity;
    }
  }
  this->SetTransformOutputValue(result);
}

template <typename TFixedMesh, typename TMovingMesh>
void
MeshPoseRegistrationMethod<TFixedMesh, TMovingMesh>::PrintSelf(std::ostream & os, Indent indent) const
{
  Superclass::PrintSelf(os, indent);
  os << indent << "PoseType: " << m_PoseType << std::endl;
  os << indent << "NumberOfRotations: " << m_NumberOfRotations << std::endl;
  os << indent << "NumberOfScales: " << m_NumberOfScales << std::endl;
  os << indent << "ScaleStep: " << m_ScaleStep << std::endl;
  os << indent << "TranslationOffsetFraction: " << m_TranslationOffsetFraction << std::endl;
  os << indent << "NumberOfSourceSamples: " << m_NumberOfSourceSamples << std::endl;
  os << indent << "NumberOfScoreSamples: " << m_NumberOfScoreSamples << std::endl;
  os << indent << "NumberOfCandidateSamples: " << m_NumberOfCandidateSamples << std::endl;
  os << indent << "NumberOfRefinementSamples: " << m_NumberOfRefinementSamples << std::endl;
  os << indent << "NumberOfCandidates: " << m_NumberOfCandidates << std::endl;
  os << indent << "NumberOfStartIterations: " << m_NumberOfStartIterations << std::endl;
  os << indent << "StartRefinementFraction: " << m_StartRefinementFraction << std::endl;
  os << indent << "TrimFraction: " << m_TrimFraction << std::endl;
  os << indent << "PolishTrimFraction: " << m_PolishTrimFraction << std::endl;
  os << indent << "NumberOfIterations: " << m_NumberOfIterations << std::endl;
  os << indent << "RotationAngle: " << m_RotationAngle << std::endl;
  os << indent << "RotationAxis: " << m_RotationAxis << std::endl;
  os << indent << "Scale: " << m_Scale << std::endl;
  os << indent << "Translation: " << m_Translation << std::endl;
  os << indent << "Score: " << m_Score << std::endl;
  os << indent << "RunnerUpScore: " << m_RunnerUpScore << std::endl;
  os << indent << "RunnerUpRotationDistance: " << m_RunnerUpRotationDistance << std::endl;
  os << indent << "NumberOfStarts: " << m_NumberOfStarts << std::endl;
  os << indent << "SearchTime: " << m_SearchTime << std::endl;
  os << indent << "RefinementTime: " << m_RefinementTime << std::endl;
}
} // namespace itk

#endif // itkMeshPoseRegistrationMethod_hxx
