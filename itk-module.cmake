# The module's metadata: its name, what it depends on, and its description.
# This file is the one place that lists the module's ITK dependencies; every
# configure mode (inside ITK, external, stand-alone) reads it.
get_filename_component(_FFDShapeMatching_module_dir "${CMAKE_CURRENT_LIST_FILE}" PATH)
file(READ "${_FFDShapeMatching_module_dir}/README.md" _FFDShapeMatching_readme)
# The description is the README's first paragraph (after the title), without list separators.
string(REGEX REPLACE "^#[^\n]*\n+" "" _FFDShapeMatching_readme "${_FFDShapeMatching_readme}")
string(REGEX REPLACE "\n\n.*$" "" DOCUMENTATION "${_FFDShapeMatching_readme}")
string(REPLACE ";" "," DOCUMENTATION "${DOCUMENTATION}")

itk_module(FFDShapeMatching
  ENABLE_SHARED
  DEPENDS
    ITKCommon
    ITKEigen3
    ITKMesh
    ITKTransform
    ITKTransformFactory
    ITKImageFunction
    ITKImageGrid
    ITKImageFilterBase
    ITKDistanceMap
    ITKSmoothing
    ITKOptimizersv4
    ITKMetricsv4
    ITKRegistrationMethodsv4
    ITKIOImageBase
    ITKIOMeshBase
    ITKIOTransformBase
    ITKIOMeshOFF
    ITKIOMeshOBJ
    ITKIOMeshVTK
    ITKIOTransformInsightLegacy
  COMPILE_DEPENDS
    ITKImageSources
  TEST_DEPENDS
    ITKTestKernel
    ITKGoogleTest
    ITKIOMeta
    ITKIONRRD
  FACTORY_NAMES
    MeshIO::StrictText
    MeshIO::VTKSurface
  DESCRIPTION "${DOCUMENTATION}"
  EXCLUDE_FROM_DEFAULT
)
