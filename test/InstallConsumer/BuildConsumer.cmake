# cmake -DSOURCE=<consumer> -DBINARY=<build> -DPREFIX=<prefix> -DGENERATOR=... -DMAKE_PROGRAM=... -DBUILD_TYPE=...
#   -DC_COMPILER=... -DCXX_COMPILER=... -DC_FLAGS=... -DCXX_FLAGS=... -DLINKER_FLAGS=... [-DLAUNCHER=...]
#   -P BuildConsumer.cmake
# Configures (in a fresh BINARY, nothing cached from an earlier run) and builds the consumer project against the installed PREFIX and checks that its
# find_package(FFDShapeMatching) found the package there.
file(REMOVE_RECURSE "${BINARY}")
set(_options -G "${GENERATOR}" -DCMAKE_MAKE_PROGRAM=${MAKE_PROGRAM} -DCMAKE_PREFIX_PATH=${PREFIX}
  -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF -DCMAKE_BUILD_TYPE=${BUILD_TYPE}
  -DCMAKE_C_COMPILER=${C_COMPILER} -DCMAKE_CXX_COMPILER=${CXX_COMPILER}
  "-DCMAKE_C_FLAGS=${C_FLAGS}" "-DCMAKE_CXX_FLAGS=${CXX_FLAGS}" "-DCMAKE_EXE_LINKER_FLAGS=${LINKER_FLAGS}")
if(LAUNCHER)
  list(APPEND _options -DCMAKE_C_COMPILER_LAUNCHER=${LAUNCHER} -DCMAKE_CXX_COMPILER_LAUNCHER=${LAUNCHER})
endif()
execute_process(COMMAND "${CMAKE_COMMAND}" -S "${SOURCE}" -B "${BINARY}" ${_options}
  RESULT_VARIABLE _result OUTPUT_VARIABLE _output ERROR_VARIABLE _output)
if(NOT _result EQUAL 0)
  message(FATAL_ERROR "configuring the consumer failed (${_result}):\n${_output}")
endif()
string(REGEX MATCH "FFDShapeMatching [0-9.]+ found in [^\n]*" _found "${_output}")
message(STATUS "${_found}")
string(FIND "${_found}" " found in ${PREFIX}/" _at)
if(_at EQUAL -1)
  message(FATAL_ERROR "the consumer did not find FFDShapeMatching in ${PREFIX}:\n${_output}")
endif()
execute_process(COMMAND "${CMAKE_COMMAND}" --build "${BINARY}" --config "${BUILD_TYPE}"
  RESULT_VARIABLE _result OUTPUT_VARIABLE _output ERROR_VARIABLE _output)
if(NOT _result EQUAL 0)
  message(FATAL_ERROR "building the consumer failed (${_result}):\n${_output}")
endif()
message(STATUS "consumer built in ${BINARY}")
