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
#ifndef itkTriangleMeshToVoxelImageFilter_h
#define itkTriangleMeshToVoxelImageFilter_h

#include "itkFFDShapeMatchingCompatibility.h"
#include "itkImageSource.h"
#include "itkImage.h"
#include "itkImageBase.h"
#include "FFDShapeMatchingDetail/itkScanLineTriangleSet.h"

#include <array>
#include <atomic>
#include <cstdint>
#include <mutex>
#include <ostream>
#include <vector>

namespace itk
{
/** \class TriangleMeshToVoxelImageFilterEnums
 * \brief Enums of TriangleMeshToVoxelImageFilter.
 * \ingroup FFDShapeMatching
 */
class TriangleMeshToVoxelImageFilterEnums
{
public:
  /** \brief What a voxel holds.
   *
   * - Occupancy: InsideValue where the surface passes within OccupancyDistance of the voxel centre.
   * - Solid: InsideValue inside the surface (generalized winding number), OutsideValue elsewhere.
   * - SignedDistance: Euclidean distance to the surface, negative inside (floating-point output).
   * - BandMask: InsideValue within BandWidth of the surface.
   * - WindingNumber: the raw generalized winding number (floating-point output).
   */
  enum class Mode : std::uint8_t
  {
    Occupancy,
    Solid,
    SignedDistance,
    BandMask,
    WindingNumber
  };
};

/** Prints the qualified name of the mode. */
inline std::ostream &
operator<<(std::ostream & out, const TriangleMeshToVoxelImageFilterEnums::Mode value)
{
  switch (value)
  {
    case TriangleMeshToVoxelImageFilterEnums::Mode::Occupancy:
      return out << "itk::TriangleMeshToVoxelImageFilterEnums::Mode::Occupancy";
    case TriangleMeshToVoxelImageFilterEnums::Mode::Solid:
      return out << "itk::TriangleMeshToVoxelImageFilterEnums::Mode::Solid";
    case TriangleMeshToVoxelImageFilterEnums::Mode::SignedDistance:
      return out << "itk::TriangleMeshToVoxelImageFilterEnums::Mode::SignedDistance";
    case TriangleMeshToVoxelImageFilterEnums::Mode::BandMask:
      return out << "itk::TriangleMeshToVoxelImageFilterEnums::Mode::BandMask";
    case TriangleMeshToVoxelImageFilterEnums::Mode::WindingNumber:
      return out << "itk::TriangleMeshToVoxelImageFilterEnums::Mode::WindingNumber";
  }
  return out << "INVALID VALUE FOR itk::TriangleMeshToVoxelImageFilterEnums::Mode";
}

/** \class TriangleMeshToVoxelImageFilter
 * \brief Voxelizes a triangle mesh: surface occupancy, solid, signed distance, band mask or winding number.
 *
 * The input is a 3-D mesh of triangles. Quadrilaterals and polygons are split into triangle fans
 * (p0, pi, pi+1); vertex and line cells are ignored; volume cells (tetrahedra, hexahedra, ...) are
 * rejected. Triangles of zero area are skipped and counted (GetNumberOfDegenerateTriangles()).
 *
 * \par Output geometry
 * Either copied from a reference image (SetReferenceImage(): its LargestPossibleRegion, spacing,
 * origin and direction, read in GenerateOutputInformation(); its information must be current, i.e.
 * call UpdateOutputInformation() on it first when it comes from a pipeline; its pixels are never
 * read), or given by Origin, Spacing, Size and Direction (start index 0). SetGeometryFromMeshBounds()
 * and ComputeGeometryFromMeshBounds() derive a grid from the mesh bounds, a voxel size and a margin.
 *
 * \par Modes (SetMode())
 * - \c Occupancy: InsideValue where the exact point-to-triangle distance from the voxel centre to the
 *   surface is <= OccupancyDistance (default: half the voxel diagonal, so every voxel whose box the
 *   surface crosses is marked: conservative, as VTK's voxel modeller), OutsideValue elsewhere.
 * - \c Solid: InsideValue where the generalized winding number w of the surface satisfies
 *   \f$|w| > 1/2\f$ (AbsoluteWindingNumber On, the default) or \f$w > 1/2\f$ (Off).
 *   For a closed, consistently oriented surface w is 1 inside and 0 outside whatever the orientation
 *   convention when the absolute value is used (a surface wound inside out has w = -1 inside); nested
 *   shells, several components, self-intersections and small holes are handled as in Jacobson et al.
 *   Inconsistently oriented patches cancel each other: orientation is not repaired.
 *   For an open patch w is the fraction of the full solid angle the patch subtends, so the solid is
 *   the set of points from which the patch covers more than half the view: for an open hemisphere
 *   it is exactly the half ball bounded by the cap and the plane of its rim (the rim disk subtends
 *   less than half the view from any point off its plane).
 * - \c SignedDistance: exact Euclidean distance from the voxel centre to the closest triangle
 *   (point-to-triangle, see detail::ClosestPointOnTriangle()), negative inside (inside as in Solid),
 *   or unsigned when UnsignedDistance is On (for open meshes). With ExactDistance Off (default) the
 *   distance is exact within BandWidth and clamped to +/-BandWidth beyond it (the clamp keeps every
 *   voxel independent of the others, so the filter still streams); with ExactDistance On it is exact
 *   everywhere. Needs a floating-point output pixel type.
 * - \c BandMask: InsideValue where the distance to the surface is <= BandWidth.
 * - \c WindingNumber: the raw winding number w (floating-point output pixel type).
 *
 * \par Speed
 * With ScanLineAcceleration On (the default) the output is computed row by row along the first index
 * axis, and gives the same image as the reference path (Off), which computes every voxel on its own.
 * BeforeThreadedGenerateData() maps the triangles to continuous-index space and bins them by the rows
 * (j, k) of the requested region that their bounds reach (detail::ScanLineTriangleBins).
 * - Solid (and the sign of SignedDistance): along a row, w jumps by +/-1 where the row crosses a triangle
 *   and changes continuously elsewhere; the continuous part is the Biot-Savart field of the edges whose
 *   net "current" (the sum of the triangles' traversals) is not zero (detail::WindingNumberGradientBound).
 *   The crossings are found exactly once per row (detail::ScanLineCrossings(): edge functions computed
 *   the same way for the two triangles of an edge, ties broken by simulation of simplicity, so a row
 *   through an edge or vertex crosses once). A closed surface (no such edge, whatever its orientation,
 *   nesting or self-intersections) needs no winding number at all: w is the signed crossing count; a
 *   voxel within 1e-7 voxel of a crossing, or along a triangle seen edge-on, is a tie computed with the
 *   winding number. For an open or inconsistently oriented surface, w is evaluated at the middle voxel
 *   of a run and predicted elsewhere as crossing count + continuous part, within the gradient bound times
 *   the distance plus a tolerance of 0.25 for the far-field error (1e-6 with Beta = 0); voxels the
 *   prediction cannot decide split the run, down to single voxels, so the decision is the one the
 *   per-voxel winding number gives. Cost: about one winding number per row of a closed mesh's ties,
 *   more near an open mesh's boundary curve.
 * - Occupancy and BandMask: triangle by triangle (GenerateReachByTriangles()); each triangle whose bounding
 *   box grown by the reach meets the requested region visits the voxels of that box, on each row only those
 *   within the slab |distance to its plane| <= reach, skips voxels already marked, and marks a voxel when
 *   the exact point-to-triangle distance is within reach (the per-voxel test, so the result does not depend
 *   on the order of the triangles). Cost: proportional to the surface area in voxels, not to the grid.
 * - The banded SignedDistance: per row, the triangles within reach across the row
 *   are ordered by their distance across it; a voxel computes the exact point-to-triangle distance only
 *   for the triangles whose lower bound (across-row distance combined with the gap along the row) can
 *   improve its best, and voxels out of reach of every triangle are not visited.
 * - These three modes need an orthonormal direction (otherwise they run per voxel).
 * - The exact SignedDistance (ExactDistance On) queries the bounding-volume hierarchy per voxel, bounded
 *   by the previous voxel's distance plus the step.
 * - WindingNumber is per voxel.
 * The bounding-volume hierarchy of axis-aligned boxes over the triangles
 * (detail::TriangleBoundingVolumeHierarchy) is built on first use, once per change of the mesh or the
 * parameters (not once per streamed piece). Distances are band-limited queries; the winding number uses
 * exact solid angles for triangles near the voxel and the hierarchical far-field expansion (dipole and
 * second-order terms) of Barill et al. for far clusters, with accuracy parameter Beta (default 2; 0 gives
 * the exact sum). Measured on a 2048-triangle sphere, the largest error of w is 0.07 with Beta = 2 (deep
 * inside, where all clusters are at about twice their radius) and 0.02 with Beta = 4; far below the 1/2
 * that would flip a voxel of a closed surface. DynamicThreadedGenerateData() computes the requested
 * region only (rows are cut at its bounds; a row's crossings come from all its triangles): streamed and
 * multi-threaded results are bit-identical to a single update (tested on closed, holed, inverted,
 * inconsistent, self-intersecting and open meshes, with rows through edges and vertices).
 *
 * \par Mask
 * An optional mask image (SetMaskImage()) limits the work to the voxels where it is non-zero; the others hold the
 * value of a voxel far from the surface: OutsideValue (Occupancy, Solid, BandMask), +BandWidth (the banded
 * SignedDistance) or 0 (WindingNumber). The scan-line path computes each row only between its first and last
 * masked voxel, and skips the triangles out of reach of that span; a masked voxel gets the value it has without
 * a mask. A caller that samples the image only in part of the grid (a registration's moving image near the fixed
 * image's samples) saves the rest.
 *
 * \par Errors
 * Update() throws an ExceptionObject naming the problem for: no input; a mesh without points; no
 * triangle cells (or only degenerate ones); a volume cell; a cell referring to a missing point; NaN or
 * infinite coordinates; non-positive or non-finite spacing; a zero size; more voxels than
 * MaximumNumberOfVoxels (checked before any allocation); a distance or winding-number mode with an
 * integer pixel type; negative BandWidth or OccupancyDistance other than the automatic value; Beta
 * in (0, 1); a mask image whose largest region, spacing, origin or direction differs from the output's; a mask
 * with ExactDistance On.
 *
 * \par References
 * A. Jacobson, L. Kavan, O. Sorkine-Hornung, "Robust inside-outside segmentation using generalized
 * winding numbers", ACM TOG 32(4), 2013, doi:10.1145/2461912.2461916.
 * G. Barill, N. Dickson, R. Schmidt, D. I. W. Levin, A. Jacobson, "Fast winding numbers for soups
 * and clouds", ACM TOG 37(4), 2018, doi:10.1145/3197517.3201337.
 *
 * \code
 * using FilterType = itk::TriangleMeshToVoxelImageFilter<itk::Mesh<double, 3>, itk::Image<float, 3>>;
 * auto filter = FilterType::New();
 * filter->SetInput(mesh);
 * FilterType::SpacingType spacing;
 * spacing.Fill(1.0);
 * filter->SetGeometryFromMeshBounds(spacing, 5.0);
 * filter->SetMode(itk::TriangleMeshToVoxelImageFilterEnums::Mode::SignedDistance);
 * filter->Update();
 * \endcode
 *
 * \sa TriangleMeshToBinaryImageFilter, SignedMaurerDistanceMapImageFilter
 * \ingroup FFDShapeMatching
 */
template <typename TInputMesh, typename TOutputImage>
class ITK_TEMPLATE_EXPORT TriangleMeshToVoxelImageFilter : public ImageSource<TOutputImage>
{
public:
  ITK_DISALLOW_COPY_AND_MOVE(TriangleMeshToVoxelImageFilter);

  using Self = TriangleMeshToVoxelImageFilter;
  using Superclass = ImageSource<TOutputImage>;
  using Pointer = SmartPointer<Self>;
  using ConstPointer = SmartPointer<const Self>;

  itkNewMacro(Self);
  itkOverrideGetNameOfClassMacro(TriangleMeshToVoxelImageFilter);

  static constexpr unsigned int OutputImageDimension = TOutputImage::ImageDimension;

  using InputMeshType = TInputMesh;
  using OutputImageType = TOutputImage;
  using OutputPixelType = typename TOutputImage::PixelType;
  using OutputImageRegionType = typename TOutputImage::RegionType;
  using SizeType = typename TOutputImage::SizeType;
  using SpacingType = typename TOutputImage::SpacingType;
  using PointType = typename TOutputImage::PointType;
  using DirectionType = typename TOutputImage::DirectionType;
  using ReferenceImageType = ImageBase<OutputImageDimension>;
  using MaskImageType = Image<unsigned char, OutputImageDimension>;
  using ModeEnum = TriangleMeshToVoxelImageFilterEnums::Mode;

  static_assert(OutputImageDimension == 3, "TriangleMeshToVoxelImageFilter needs a 3-D output image.");
  static_assert(TInputMesh::PointDimension == 3, "TriangleMeshToVoxelImageFilter needs a 3-D mesh.");

  /** Sets the input mesh. */
  virtual void
  SetInput(const InputMeshType * input);

  /** Returns the input mesh. */
  const InputMeshType *
  GetInput() const;

  /** What each voxel holds. Default: Solid. */
  itkSetEnumMacro(Mode, ModeEnum);
  itkGetEnumMacro(Mode, ModeEnum);

  /** Value of voxels in the shape (Occupancy, Solid, BandMask). Default: 1. */
  itkSetMacro(InsideValue, OutputPixelType);
  itkGetConstMacro(InsideValue, OutputPixelType);

  /** Value of the other voxels (Occupancy, Solid, BandMask). Default: 0. */
  itkSetMacro(OutsideValue, OutputPixelType);
  itkGetConstMacro(OutsideValue, OutputPixelType);

  /** Image whose geometry (largest region, spacing, origin, direction) the output copies: an optional input named
   * "ReferenceImage", updated by the pipeline like any input (only its information is used). Default: none, the
   * Origin, Spacing, Size and Direction parameters are used. */
  itkSetInputMacro(ReferenceImage, ReferenceImageType);
  itkGetInputMacro(ReferenceImage, ReferenceImageType);

  /** Optional input named "MaskImage": only the voxels where it is non-zero are voxelized, the others hold the
   * value of a voxel far from the surface (see Mask above). It must have the output's largest possible region,
   * spacing, origin and direction; its requested region is the output's. Not with ExactDistance. Default: none,
   * every voxel is voxelized. */
  itkSetInputMacro(MaskImage, MaskImageType);
  itkGetInputMacro(MaskImage, MaskImageType);

  /** Physical position of the centre of voxel 0 when no reference image is set. Default: 0. */
  itkSetMacro(Origin, PointType);
  itkGetConstReferenceMacro(Origin, PointType);

  /** Voxel size when no reference image is set. Default: 1. */
  itkSetMacro(Spacing, SpacingType);
  itkGetConstReferenceMacro(Spacing, SpacingType);

  /** Number of voxels per axis when no reference image is set. Default: 0 (must be set). */
  itkSetMacro(Size, SizeType);
  itkGetConstReferenceMacro(Size, SizeType);

  /** Direction cosines when no reference image is set. Default: identity. */
  itkSetMacro(Direction, DirectionType);
  itkGetConstReferenceMacro(Direction, DirectionType);

  /** Distance from a voxel centre within which the surface marks it (Occupancy). A negative value
   * means half the voxel diagonal. Default: -1. */
  itkSetMacro(OccupancyDistance, double);
  itkGetConstMacro(OccupancyDistance, double);

  /** Half width of the band, in physical units (SignedDistance, BandMask). A negative value means
   * three times the largest voxel spacing. Default: -1. */
  itkSetMacro(BandWidth, double);
  itkGetConstMacro(BandWidth, double);

  /** SignedDistance: exact distance everywhere instead of clamped beyond BandWidth. Default: Off. */
  itkSetMacro(ExactDistance, bool);
  itkGetConstMacro(ExactDistance, bool);
  itkBooleanMacro(ExactDistance);

  /** SignedDistance: unsigned distance (for open surfaces). Default: Off. */
  itkSetMacro(UnsignedDistance, bool);
  itkGetConstMacro(UnsignedDistance, bool);
  itkBooleanMacro(UnsignedDistance);

  /** Inside means |w| > 1/2 (On) or w > 1/2 (Off), w the winding number. Default: On. */
  itkSetMacro(AbsoluteWindingNumber, bool);
  itkGetConstMacro(AbsoluteWindingNumber, bool);
  itkBooleanMacro(AbsoluteWindingNumber);

  /** Far-field accuracy of the fast winding number: clusters farther than Beta times their radius
   * use the far-field expansion; larger is more accurate and slower. 0 means exact; otherwise at
   * least 1. Default: 2. */
  itkSetMacro(Beta, double);
  itkGetConstMacro(Beta, double);

  /** Scan-line acceleration (see Speed): On computes the winding number only where the signed count of
   * surface crossings along the grid rows cannot decide, and distances only within reach of a
   * triangle; Off computes every voxel on its own (the reference path, much slower). Both give the
   * same image. Default: On. */
  itkSetMacro(ScanLineAcceleration, bool);
  itkGetConstMacro(ScanLineAcceleration, bool);
  itkBooleanMacro(ScanLineAcceleration);

  /** Largest number of output voxels accepted, checked before allocation. Default: 2^30. */
  itkSetMacro(MaximumNumberOfVoxels, SizeValueType);
  itkGetConstMacro(MaximumNumberOfVoxels, SizeValueType);

  /** Number of triangles used in the last update (after fan triangulation, without the degenerate ones). */
  itkGetConstMacro(NumberOfTriangles, SizeValueType);

  /** Number of zero-area triangles skipped in the last update. */
  itkGetConstMacro(NumberOfDegenerateTriangles, SizeValueType);

  /** Computes a grid holding the bounding box of the mesh's points grown by margin on each side, with
   * the given voxel spacing: size = ceil((extent + 2 margin) / spacing) (at least 1) per axis, centred
   * on the box, identity direction. Throws for a null or empty mesh, non-finite coordinates or a
   * non-positive spacing. */
  static void
  ComputeGeometryFromMeshBounds(const InputMeshType * mesh,
                                const SpacingType &   spacing,
                                double                margin,
                                PointType &           origin,
                                SizeType &            size);

  /** Sets Origin, Spacing, Size and Direction (identity) from the bounds of the current input mesh
   * (ComputeGeometryFromMeshBounds()); the mesh's points must be present (update it first). */
  void
  SetGeometryFromMeshBounds(const SpacingType & spacing, double margin);

protected:
  TriangleMeshToVoxelImageFilter();
  ~TriangleMeshToVoxelImageFilter() override = default;

  void
  PrintSelf(std::ostream & os, Indent indent) const override;

  void
  VerifyPreconditions() const override;

  void
  GenerateOutputInformation() override;

  /** The mask image, when set, is requested over the output's requested region. */
  void
  GenerateInputRequestedRegion() override;

  void
  BeforeThreadedGenerateData() override;

  void
  DynamicThreadedGenerateData(const OutputImageRegionType & outputRegionForThread) override;

private:
  /** Region, spacing, origin and direction of the output, from the reference image or the parameters. */
  void
  ComputeOutputGeometry(OutputImageRegionType & region,
                        SpacingType &           spacing,
                        PointType &             origin,
                        DirectionType &         direction) const;

  /** Extracts the triangles of the input and builds the hierarchy; throws on bad input. */
  void
  BuildTriangleHierarchy();

  /** The bounding-volume hierarchy over the triangles, built on first use (thread-safe). */
  const detail::TriangleBoundingVolumeHierarchy &
  GetHierarchy() const;

  bool
  IsInside(double windingNumber) const;

  /** Triangles in continuous-index space and the scan-line bins of the requested region's rows. */
  void
  PrepareScanLines();

  /** The reference path: every voxel of the region on its own. */
  void
  GeneratePerVoxel(const OutputImageRegionType & region);

  /** The scan-line path: row by row. */
  void
  GenerateByScanLines(const OutputImageRegionType & region);

  /** Occupancy and band mask with the scan-line acceleration: triangle by triangle, every triangle of the
   * requested region marks the voxels of the region, within its bounding box grown by the reach distance,
   * whose centre lies within that distance of it (the same exact point-to-triangle test as the per-voxel
   * path, so the image does not depend on the order, the threads or the streamed pieces). */
  void
  GenerateReachByTriangles(const OutputImageRegionType & region);

  /** True when this update runs row by row (GenerateByScanLines()). */
  bool
  UsesScanLines() const;

  /** The value of a voxel far from the surface, which the voxels outside the mask hold. */
  OutputPixelType
  GetFarValue() const;

  /** Sets the voxels of the region outside the mask (when a mask is set) to GetFarValue(). */
  void
  ClearVoxelsOutsideMask(const OutputImageRegionType & region);

  /** True for the modes that need the inside/outside sign (Solid, signed SignedDistance). */
  bool
  ModeNeedsSign() const
  {
    return m_Mode == ModeEnum::Solid || (m_Mode == ModeEnum::SignedDistance && !m_UnsignedDistance);
  }

  /** True for the modes that only mark the voxels within a distance of the surface (Occupancy, BandMask). */
  bool
  ModeIsReachOnly() const
  {
    return m_Mode == ModeEnum::Occupancy || m_Mode == ModeEnum::BandMask;
  }

  ModeEnum        m_Mode{ ModeEnum::Solid };
  OutputPixelType m_InsideValue{ NumericTraits<OutputPixelType>::OneValue() };
  OutputPixelType m_OutsideValue{ NumericTraits<OutputPixelType>::ZeroValue() };

  PointType     m_Origin{};  // Filled with 0 in the constructor.
  SpacingType   m_Spacing{}; // Filled with 1 in the constructor.
  SizeType      m_Size{ { 0 } };
  DirectionType m_Direction{}; // Identity, set in the constructor.

  double        m_OccupancyDistance{ -1.0 };
  double        m_BandWidth{ -1.0 };
  bool          m_ExactDistance{ false };
  bool          m_UnsignedDistance{ false };
  bool          m_AbsoluteWindingNumber{ true };
  double        m_Beta{ 2.0 };
  bool          m_ScanLineAcceleration{ true };
  SizeValueType m_MaximumNumberOfVoxels{ SizeValueType{ 1 } << 30 };

  SizeValueType m_NumberOfTriangles{ 0 };
  SizeValueType m_NumberOfDegenerateTriangles{ 0 };

  detail::ScanLineTriangleSet m_TriangleSet{};
  bool                        m_HierarchyIsCurrent{ false };
  double                      m_EffectiveOccupancyDistance{ 0.0 };
  double                      m_EffectiveBandWidth{ 0.0 };
};
} // namespace itk

#ifndef ITK_MANUAL_INSTANTIATION
#  include "itkTriangleMeshToVoxelImageFilter.hxx"
#endif

#endif // itkTriangleMeshToVoxelImageFilter_h
