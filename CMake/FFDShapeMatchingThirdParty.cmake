# Finds VTK, Boost (Graph, header-only) and nanoflann for FFDShapeMatching, in every configure mode.
#
# Sets FFDShapeMatching_VTK_LIBRARIES (what the module library links) and
# FFDShapeMatching_EXPORT_CODE_BUILD / _INSTALL, which ITK's module system writes
# into the module's CMake file so that find_package(ITK COMPONENTS FFDShapeMatching)
# finds the same packages for users.

set(FFDShapeMatching_VTK_COMPONENTS
  CommonCore
  CommonDataModel
  CommonExecutionModel
  FiltersCore
  FiltersGeneral
  IOGeometry
  IOLegacy
  IOPLY
  IOXML)
# The programs' snapshot (ffd-match --snapshot) renders off screen; the benchmark's peers use VTK's voxelizers
# (Imaging*) and its Hausdorff distance filter (FiltersModeling). VTK's targets are imported once, here,
# with every component the project uses, so that their own dependencies (X11, GLEW, ...) resolve in one
# directory scope; the module library links only the components above.
set(FFDShapeMatching_VTK_PROGRAM_COMPONENTS
  FiltersModeling
  ImagingHybrid
  ImagingStencil
  IOImage
  RenderingAnnotation
  RenderingCore
  RenderingFreeType
  RenderingOpenGL2)
find_package(VTK 9.1 REQUIRED COMPONENTS ${FFDShapeMatching_VTK_COMPONENTS} ${FFDShapeMatching_VTK_PROGRAM_COMPONENTS})
set(FFDShapeMatching_VTK_LIBRARIES)
foreach(_component IN LISTS FFDShapeMatching_VTK_COMPONENTS)
  list(APPEND FFDShapeMatching_VTK_LIBRARIES VTK::${_component})
endforeach()

# Boost Graph's Boykov-Kolmogorov max-flow (header-only; Debian's libboost-graph-dev) for the MRF solver's
# alpha-expansion moves. Used by src/itkMRFLabelingSolver.cxx only, through its include directory: nothing is
# linked and no public header includes it.
find_package(Boost REQUIRED)
if(NOT EXISTS "${Boost_INCLUDE_DIRS}/boost/graph/boykov_kolmogorov_max_flow.hpp")
  message(FATAL_ERROR "Boost Graph's boost/graph/boykov_kolmogorov_max_flow.hpp was not found in "
    "${Boost_INCLUDE_DIRS} (Debian: apt-get install libboost-graph-dev); set Boost_ROOT.")
endif()

# nanoflann (header-only, BSD licence; Debian's libnanoflann-dev): the k-d tree of the CPD method's nearest-neighbour
# searches. Its header is included by include/itkBSplineCoherentPointDriftRegistrationMethod.hxx, so the
# library carries it to its users.
find_package(nanoflann 1.4 REQUIRED)

set(_FFDShapeMatching_export_code "
find_package(VTK 9.1 REQUIRED COMPONENTS ${FFDShapeMatching_VTK_COMPONENTS})
find_package(nanoflann 1.4 REQUIRED)
")
set(FFDShapeMatching_EXPORT_CODE_BUILD "${_FFDShapeMatching_export_code}")
set(FFDShapeMatching_EXPORT_CODE_INSTALL "${_FFDShapeMatching_export_code}")
