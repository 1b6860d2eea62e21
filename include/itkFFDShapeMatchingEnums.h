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
#ifndef itkFFDShapeMatchingEnums_h
#define itkFFDShapeMatchingEnums_h

#include "FFDShapeMatchingExport.h"
#include <cstdint>
#include <ostream>
#include <string>

namespace itk
{
/** \class FFDShapeMatchingEnums
 * \brief Enumerations shared by the FFDShapeMatching pipeline stages and programs.
 *
 * \c Method names a shape-matching method of the module, as the paper
 * "A comparative analysis of B-spline deformation models in 3D shape matching" names them:
 * - \c GO: gradient-based global optimization of a B-spline transform on voxel images,
 * - \c MRF: discrete Markov-random-field optimization of the B-spline control points,
 * - \c Par: parametric-template matching of the meshes themselves,
 * - \c GOPar and \c MRFPar: a voxel method refined by Par;
 * and, beyond the paper, the module's point-correspondence refinement:
 * - \c GOCPD: GO, refined by coherent point drift on the B-spline coefficients: soft correspondences between the
 *   meshes' vertices in both directions (BSplineCoherentPointDriftRegistrationMethod, started from GO's result).
 *
 * The command-line spelling of each method ("go", "mrf", "par", "go+par", "mrf+par", "go+cpd") is given by
 * MethodToString() and parsed back by MethodFromString().
 *
 * \ingroup FFDShapeMatching
 */
class FFDShapeMatching_EXPORT FFDShapeMatchingEnums
{
public:
  /** Shape-matching method. */
  enum class Method : uint8_t
  {
    GO,
    MRF,
    Par,
    GOPar,
    MRFPar,
    GOCPD
  };

  /** Image similarity measure of a voxel-image registration. */
  enum class ImageMetric : uint8_t
  {
    MattesMutualInformation,
    MeanSquares
  };

  /** How the meshes become voxel images for the voxel methods (GO, MRF):
   * - \c Occupancy: surface voxels, compared by Mattes mutual information (GO) or pointwise MI (MRF),
   * - \c Solid: inside voxels (generalized winding number), compared the same way,
   * - \c SignedDistance: the unsigned distance to the surface in a band, compared by mean squares (GO) or
   *   the sum of squared differences (MRF). */
  enum class Voxelization : uint8_t
  {
    Occupancy,
    Solid,
    SignedDistance
  };

  /** Gradient-based optimizer of a voxel-image registration. */
  enum class Optimizer : uint8_t
  {
    LBFGSB,
    RegularStepGradientDescent
  };

  /** The pose stage before the deformation (MeshPoseRegistrationMethod): none, or a global search for a rigid,
   * similarity (rigid and isotropic scale) or affine transform from any pose, with a partial target. */
  enum class InitialTransform : uint8_t
  {
    None,
    Rigid,
    Similarity,
    Affine
  };

  /** The command-line spelling of a method: "go", "mrf", "par", "go+par", "mrf+par" or "go+cpd". */
  static std::string
  MethodToString(Method method);

  /** Parses the command-line spelling of a method (case-insensitive). Returns false and
   * leaves \c method unchanged when \c text names no method. */
  static bool
  MethodFromString(const std::string & text, Method & method);

  /** The command-line spelling of a voxelization: "occupancy", "solid" or "sdf". */
  static std::string
  VoxelizationToString(Voxelization voxelization);

  /** Parses the command-line spelling of a voxelization (case-insensitive). Returns false and
   * leaves \c voxelization unchanged when \c text names none. */
  static bool
  VoxelizationFromString(const std::string & text, Voxelization & voxelization);

  /** The command-line spelling of a pose stage: "none", "rigid", "similarity" or "affine". */
  static std::string
  InitialTransformToString(InitialTransform initialTransform);

  /** Parses the command-line spelling of a pose stage (case-insensitive). Returns false and leaves
   * \c initialTransform unchanged when \c text names none. */
  static bool
  InitialTransformFromString(const std::string & text, InitialTransform & initialTransform);
};

/** Prints the qualified name of the enumerator, e.g. "itk::FFDShapeMatchingEnums::Method::GO". */
extern FFDShapeMatching_EXPORT std::ostream &
                               operator<<(std::ostream & out, const FFDShapeMatchingEnums::Method value);

/** Prints the qualified name of the enumerator. */
extern FFDShapeMatching_EXPORT std::ostream &
                               operator<<(std::ostream & out, const FFDShapeMatchingEnums::ImageMetric value);

/** Prints the qualified name of the enumerator. */
extern FFDShapeMatching_EXPORT std::ostream &
                               operator<<(std::ostream & out, const FFDShapeMatchingEnums::Optimizer value);

/** Prints the qualified name of the enumerator. */
extern FFDShapeMatching_EXPORT std::ostream &
                               operator<<(std::ostream & out, const FFDShapeMatchingEnums::Voxelization value);

/** Prints the qualified name of the enumerator. */
extern FFDShapeMatching_EXPORT std::ostream &
                               operator<<(std::ostream & out, const FFDShapeMatchingEnums::InitialTransform value);

} // namespace itk

#endif // itkFFDShapeMatchingEnums_h
