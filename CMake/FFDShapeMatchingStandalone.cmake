# Stand-alone configuration of the FFDShapeMatching module against an installed ITK
# that does not ship ITK's module scripts (ITKModuleExternal.cmake and friends), such as
# Debian 12's libinsighttoolkit5-dev (ITK 5.2.1).
#
# It emulates only the part of ITK's module API this module uses, with ITK's names and
# meanings, so that itk-module.cmake, src/CMakeLists.txt and test/CMakeLists.txt are the
# same in every configure mode:
#   itk_module(), itk_module_add_library(), itk_module_test(), CreateTestDriver(),
#   CreateGoogleTestDriver(), itk_add_test(), ITK_TEST_OUTPUT_DIR, the header test.

include(GNUInstallDirs)
include(GenerateExportHeader)
include(CMakeParseArguments)

# --- itk_module(): records the metadata as ITK's macro does -----------------------------
macro(itk_module _name)
  set(itk-module ${_name})
  set(itk-module-test ${_name}-Test)
  set(ITK_MODULE_${itk-module}_DEPENDS "")
  set(ITK_MODULE_${itk-module}_PUBLIC_DEPENDS "")
  set(ITK_MODULE_${itk-module}_COMPILE_DEPENDS "")
  set(ITK_MODULE_${itk-module}_PRIVATE_DEPENDS "")
  set(ITK_MODULE_${itk-module-test}_DEPENDS "${itk-module}")
  set(ITK_MODULE_${itk-module}_DESCRIPTION "")
  set(ITK_MODULE_${itk-module}_ENABLE_SHARED 0)
  set(_doing "")
  foreach(arg ${ARGN})
    if("${arg}" MATCHES "^((|COMPILE_|PRIVATE_|TEST_)DEPENDS|DESCRIPTION|FACTORY_NAMES)$")
      set(_doing "${arg}")
    elseif("${arg}" STREQUAL "EXCLUDE_FROM_DEFAULT")
      set(_doing "")
    elseif("${arg}" STREQUAL "ENABLE_SHARED")
      set(_doing "")
      set(ITK_MODULE_${itk-module}_ENABLE_SHARED 1)
    elseif("${_doing}" STREQUAL "DEPENDS")
      list(APPEND ITK_MODULE_${itk-module}_PUBLIC_DEPENDS "${arg}")
    elseif("${_doing}" STREQUAL "TEST_DEPENDS")
      list(APPEND ITK_MODULE_${itk-module-test}_DEPENDS "${arg}")
    elseif("${_doing}" STREQUAL "COMPILE_DEPENDS")
      list(APPEND ITK_MODULE_${itk-module}_COMPILE_DEPENDS "${arg}")
    elseif("${_doing}" STREQUAL "PRIVATE_DEPENDS")
      list(APPEND ITK_MODULE_${itk-module}_PRIVATE_DEPENDS "${arg}")
    elseif("${_doing}" STREQUAL "DESCRIPTION")
      set(_doing "")
      set(ITK_MODULE_${itk-module}_DESCRIPTION "${arg}")
    elseif("${_doing}" STREQUAL "FACTORY_NAMES")
    else()
      message(AUTHOR_WARNING "itk_module: unknown argument [${arg}]")
    endif()
  endforeach()
  set(ITK_MODULE_${itk-module}_DEPENDS
    ${ITK_MODULE_${itk-module}_PUBLIC_DEPENDS}
    ${ITK_MODULE_${itk-module}_COMPILE_DEPENDS}
    ${ITK_MODULE_${itk-module}_PRIVATE_DEPENDS})
endmacro()

include(${CMAKE_CURRENT_SOURCE_DIR}/itk-module.cmake)
option(BUILD_SHARED_LIBS "Build the module library as a shared library, like ITK's own." ON)
if(NOT CMAKE_POSITION_INDEPENDENT_CODE)
  set(CMAKE_POSITION_INDEPENDENT_CODE ON)
endif()

# --- ITK itself, limited to the modules the metadata names ------------------------------
# Debian's ITKGoogleTest is an empty stub; GoogleTest itself comes from find_package(GTest).
set(_FFDShapeMatching_itk_components ${ITK_MODULE_FFDShapeMatching_DEPENDS})
foreach(_dep IN LISTS ITK_MODULE_FFDShapeMatching-Test_DEPENDS)
  if(NOT _dep STREQUAL "FFDShapeMatching")
    list(APPEND _FFDShapeMatching_itk_components ${_dep})
  endif()
endforeach()
list(REMOVE_DUPLICATES _FFDShapeMatching_itk_components)
find_package(ITK 5.2 REQUIRED COMPONENTS ${_FFDShapeMatching_itk_components})
ffd_use_itk()

# Libraries of a list of ITK modules, as ITK's <module>_LIBRARIES variables give them.
function(_ffd_module_libraries _out)
  set(_libs "")
  foreach(_module IN LISTS ARGN)
    list(APPEND _libs ${${_module}_LIBRARIES})
  endforeach()
  if(_libs)
    list(REMOVE_DUPLICATES _libs)
  endif()
  set(${_out} "${_libs}" PARENT_SCOPE)
endfunction()

include(CTest)
set(ITK_TEST_OUTPUT_DIR "${CMAKE_BINARY_DIR}/Testing/Temporary")
file(MAKE_DIRECTORY "${ITK_TEST_OUTPUT_DIR}")

# Test data: DATA{} references resolve to committed files in the source tree.
include(ExternalData)
set(ExternalData_OBJECT_STORES "${CMAKE_BINARY_DIR}/ExternalData/Objects")
set(ExternalData_SOURCE_ROOT "${CMAKE_CURRENT_SOURCE_DIR}")

# --- the module's include folders and library ------------------------------------------
set(FFDShapeMatching_INCLUDE_DIRS
  ${CMAKE_CURRENT_SOURCE_DIR}/include
  ${CMAKE_CURRENT_BINARY_DIR}/include)
include_directories(${FFDShapeMatching_INCLUDE_DIRS})

macro(itk_module_add_library _name)
  add_library(${_name} ${ARGN})
  _ffd_module_libraries(_ffd_public_libs ${ITK_MODULE_${itk-module}_PUBLIC_DEPENDS})
  _ffd_module_libraries(_ffd_private_libs ${ITK_MODULE_${itk-module}_PRIVATE_DEPENDS})
  target_link_libraries(${_name} LINK_PUBLIC ${_ffd_public_libs} LINK_PRIVATE ${_ffd_private_libs})
  target_include_directories(${_name} PUBLIC
    "$<BUILD_INTERFACE:${FFDShapeMatching_INCLUDE_DIRS}>"
    "$<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}/${itk-module}>")
  set_target_properties(${_name} PROPERTIES VERSION ${PROJECT_VERSION} SOVERSION 1)
  generate_export_header(${_name}
    EXPORT_FILE_NAME ${CMAKE_CURRENT_BINARY_DIR}/../include/${itk-module}Export.h
    EXPORT_MACRO_NAME ${itk-module}_EXPORT
    NO_EXPORT_MACRO_NAME ${itk-module}_HIDDEN
    STATIC_DEFINE ITK_STATIC)
  install(TARGETS ${_name} EXPORT ${itk-module}Targets
    RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR}
    LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
    ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR})
  install(FILES ${CMAKE_CURRENT_BINARY_DIR}/../include/${itk-module}Export.h
    DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/${itk-module})
endmacro()

install(DIRECTORY include/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/${itk-module})
if(EXISTS ${CMAKE_CURRENT_SOURCE_DIR}/src/CMakeLists.txt)
  add_subdirectory(src)
endif()
if(TARGET ${itk-module})
  # The CMake package: find_package(FFDShapeMatching) + FFDShapeMatching::FFDShapeMatching (docs/building.md, "Install
  # and use from your project"). The configuration finds ITK (the module's DEPENDS), VTK and Eigen again.
  include(CMakePackageConfigHelpers)
  set(_ffd_package_dir ${CMAKE_INSTALL_LIBDIR}/cmake/${itk-module})
  install(EXPORT ${itk-module}Targets NAMESPACE ${itk-module}:: DESTINATION ${_ffd_package_dir})
  string(REPLACE ";" " " FFDShapeMatching_CONFIG_ITK_COMPONENTS "${ITK_MODULE_${itk-module}_DEPENDS}")
  string(REPLACE ";" " " FFDShapeMatching_CONFIG_VTK_COMPONENTS "${FFDShapeMatching_VTK_COMPONENTS}")
  set(FFDShapeMatching_CONFIG_INCLUDE_DIR ${CMAKE_INSTALL_INCLUDEDIR}/${itk-module})
  configure_package_config_file(${CMAKE_CURRENT_SOURCE_DIR}/CMake/${itk-module}Config.cmake.in
    ${CMAKE_CURRENT_BINARY_DIR}/${itk-module}Config.cmake
    INSTALL_DESTINATION ${_ffd_package_dir}
    PATH_VARS FFDShapeMatching_CONFIG_INCLUDE_DIR CMAKE_INSTALL_BINDIR)
  write_basic_package_version_file(${CMAKE_CURRENT_BINARY_DIR}/${itk-module}ConfigVersion.cmake
    VERSION ${PROJECT_VERSION} COMPATIBILITY SameMajorVersion)
  install(FILES ${CMAKE_CURRENT_BINARY_DIR}/${itk-module}Config.cmake
    ${CMAKE_CURRENT_BINARY_DIR}/${itk-module}ConfigVersion.cmake DESTINATION ${_ffd_package_dir})
  set(FFDShapeMatching_PACKAGE_CONFIGURED TRUE)
endif()

# --- the test API -----------------------------------------------------------------------
macro(itk_module_test)
  _ffd_module_libraries(_ffd_test_itk_libs ${ITK_MODULE_${itk-module-test}_DEPENDS})
  set(${itk-module-test}_LIBRARIES ${FFDShapeMatching_LIBRARIES} ${_ffd_test_itk_libs})
endmacro()

macro(CreateTestDriver KIT KIT_LIBS KitTests)
  set(CMAKE_TESTDRIVER_BEFORE_TESTMAIN "#include \"itkTestDriverBeforeTest.inc\"")
  set(CMAKE_TESTDRIVER_AFTER_TESTMAIN "#include \"itkTestDriverAfterTest.inc\"")
  create_test_sourcelist(Tests ${KIT}TestDriver.cxx ${KitTests}
    EXTRA_INCLUDE itkTestDriverIncludeRequiredIOFactories.h
    FUNCTION ProcessArgumentsAndRegisterRequiredFactories)
  add_executable(${KIT}TestDriver ${KIT}TestDriver.cxx ${Tests} ${ARGN})
  target_link_libraries(${KIT}TestDriver LINK_PUBLIC ${KIT_LIBS} ${ITKTestKernel_LIBRARIES})
endmacro()

macro(CreateGoogleTestDriver KIT KIT_LIBS KitTests)
  add_executable(${KIT}GTestDriver ${KitTests})
  target_link_libraries(${KIT}GTestDriver ${KIT_LIBS} GTest::gtest GTest::gtest_main)
  include(GoogleTest)
  gtest_discover_tests(${KIT}GTestDriver DISCOVERY_TIMEOUT 30)
endmacro()

function(itk_add_test)
  ExternalData_add_test(FFDShapeMatchingData ${ARGN})
  if("NAME" STREQUAL "${ARGV0}")
    set(_test_name ${ARGV1})
  else()
    set(_test_name ${ARGV0})
  endif()
  set_property(TEST ${_test_name} PROPERTY LABELS ${itk-module})
endfunction()

if(BUILD_TESTING AND EXISTS "${CMAKE_CURRENT_SOURCE_DIR}/test/CMakeLists.txt")
  add_subdirectory(test)
  ExternalData_add_target(FFDShapeMatchingData)

  # Header test: every header compiles, as ITK's header test checks: the public ones and the internal ones of
  # include/FFDShapeMatchingDetail/ (which ITK's header test, on include/*.h, does not see).
  file(GLOB _ffd_headers RELATIVE "${CMAKE_CURRENT_SOURCE_DIR}/include" "${CMAKE_CURRENT_SOURCE_DIR}/include/*.h"
    "${CMAKE_CURRENT_SOURCE_DIR}/include/FFDShapeMatchingDetail/*.h")
  set(_ffd_header_test_source "${CMAKE_CURRENT_BINARY_DIR}/test/FFDShapeMatchingHeaderTest.cxx")
  set(_ffd_header_test_text "// Generated: includes every header of the module.\n")
  foreach(_header IN LISTS _ffd_headers)
    string(APPEND _ffd_header_test_text "#include \"${_header}\"\n")
  endforeach()
  string(APPEND _ffd_header_test_text "int\nmain()\n{\n  return 0;\n}\n")
  file(CONFIGURE OUTPUT "${_ffd_header_test_source}" CONTENT "${_ffd_header_test_text}")
  add_executable(FFDShapeMatchingHeaderTest "${_ffd_header_test_source}")
  target_link_libraries(FFDShapeMatchingHeaderTest ${FFDShapeMatching_LIBRARIES})
  add_test(NAME FFDShapeMatchingHeaderTest COMMAND FFDShapeMatchingHeaderTest)
endif()
