# cmake -DBUILD_DIR=<build> -DPREFIX=<prefix> [-DCONFIG=<config>] -DEXPECTED=<files relative to prefix>
#   -P InstallToPrefix.cmake
# Installs the build into a fresh PREFIX (removed first) and checks that the EXPECTED files are there.
file(REMOVE_RECURSE "${PREFIX}")
set(_config)
if(CONFIG)
  set(_config --config "${CONFIG}")
endif()
execute_process(COMMAND "${CMAKE_COMMAND}" --install "${BUILD_DIR}" --prefix "${PREFIX}" ${_config}
  RESULT_VARIABLE _result OUTPUT_VARIABLE _output ERROR_VARIABLE _output)
if(NOT _result EQUAL 0)
  message(FATAL_ERROR "cmake --install failed (${_result}):\n${_output}")
endif()
foreach(_file IN LISTS EXPECTED)
  if(NOT EXISTS "${PREFIX}/${_file}")
    message(FATAL_ERROR "cmake --install did not install ${_file}:\n${_output}")
  endif()
endforeach()
file(GLOB_RECURSE _installed LIST_DIRECTORIES false "${PREFIX}/*")
list(LENGTH _installed _count)
message(STATUS "installed ${_count} files into ${PREFIX}")
