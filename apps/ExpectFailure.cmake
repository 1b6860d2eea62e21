# Runs PROGRAM MESH OUTPUT ARGUMENTS... and checks that it fails cleanly: a non-zero exit code,
# exactly one line on stderr, and no OUTPUT file left behind. The stderr line is printed for the
# test's PASS_REGULAR_EXPRESSION.
file(REMOVE "${OUTPUT}")
execute_process(COMMAND "${PROGRAM}" "${MESH}" "${OUTPUT}" ${ARGUMENTS}
  RESULT_VARIABLE _result ERROR_VARIABLE _error OUTPUT_VARIABLE _output)
message("${_error}")
if(_result EQUAL 0)
  message(FATAL_ERROR "expected a non-zero exit code")
endif()
string(STRIP "${_error}" _stripped)
if(_stripped MATCHES "\n")
  message(FATAL_ERROR "expected a one-line error message")
endif()
if(EXISTS "${OUTPUT}")
  message(FATAL_ERROR "the output file was written although the program failed")
endif()
