# Finds VTK and the system Eigen for FFDShapeMatching, in every configure mode.
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

# ITK 5.2 bundles an older Eigen under the same names; ITK_USE_SYSTEM_EIGEN (set on
# every target through the module library) makes ITK's headers use this one.
find_package(Eigen3 3.4 REQUIRED NO_MODULE)

# Boykov-Kolmogorov max-flow (Debian's libmaxflow-dev) for the MRF solver's alpha-expansion moves.
# Used by src/itkMRFLabelingSolver.cxx only and linked privately: no public header includes it.
find_path(FFDShapeMatching_MAXFLOW_INCLUDE_DIR maxflow/graph.h PATH_SUFFIXES maxflow-3.0)
find_library(FFDShapeMatching_MAXFLOW_LIBRARY NAMES maxflow)
if(NOT FFDShapeMatching_MAXFLOW_INCLUDE_DIR OR NOT FFDShapeMatching_MAXFLOW_LIBRARY)
  message(FATAL_ERROR "The max-flow library was not found (Debian: apt-get install libmaxflow-dev); "
    "set FFDShapeMatching_MAXFLOW_INCLUDE_DIR and FFDShapeMatching_MAXFLOW_LIBRARY.")
endif()

set(_FFDShapeMatching_export_code "
find_package(VTK 9.1 REQUIRED COMPONENTS ${FFDShapeMatching_VTK_COMPONENTS})
find_package(Eigen3 3.4 REQUIRED NO_MODULE)
")
set(FFDShapeMatching_EXPORT_CODE_BUILD "${_FFDShapeMatching_export_code}")
set(FFDShapeMatching_EXPORT_CODE_INSTALL "${_FFDShapeMatching_export_code}")
