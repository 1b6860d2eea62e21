# Runs PROGRAM MESH OUTPUT ARGUMENTS... and checks that it fails cleanly: a non-zero exit code,
# exactly one line on stderr, and no OUTPUT file left behind. The stderr line is printed for the
# test's PASS_REGULAR_EXPRESSION. With -DAFTER_WORK=ON the failure comes after the program's work: its progress
# lines come first, and the last line, the error, is the one printed (the others are not).
file(REMOVE "${OUTPUT}")
execute_process(COMMAND "${PROGRAM}" "${MESH}" "${OUTPUT}" ${ARGUMENTS}
  RESULT_VARIABLE _result ERROR_VARIABLE _error OUTPUT_VARIABLE _output)
string(STRIP "${_error}" _stripped)
if(AFTER_WORK)
  string(FIND "${_stripped}" "\n" _last_newline REVERSE)
  math(EXPR _last_newline "${_last_newline} + 1")
  string(SUBSTRING "${_stripped}" ${_last_newline} -1 _stripped)
  set(_error "${_stripped}")
endif()
message("${_error}")
if(_result EQUAL 0)
  message(FATAL_ERROR "expected a non-zero exit code")
endif()
if(_stripped MATCHES "\n")
  message(FATAL_ERROR "expected a one-line error message")
endif()
if(EXISTS "${OUTPUT}")
  message(FATAL_ERROR "the output file was written although the program failed")
endif()
