# Functions that declare the CTest tests of the command-line programs (test/Programs/CMakeLists.txt), one call per test,
# with the program's arguments as a real CMake list.

# The scripts the tests run (ExpectFailure.cmake and friends, beside this file).
set(_ffd_program_test_scripts ${CMAKE_CURRENT_LIST_DIR})

# ffd_add_rejection_test(<program> <case>
#                        [AFTER_PROGRESS] [MESH <argument>] [OUTPUT <file>] [SPECIAL_INPUT <kind> <file name>]
#                        ARGS <argument>...
#                        ERROR <regex> | ERROR_CONTAINS <regex> | PASS_REGULAR_EXPRESSION <regex>
#                        [PROPERTIES <property> <value>...])
#
# Adds the test <program>Rejects<case>: test/Programs/ExpectFailure.cmake runs `<program> MESH OUTPUT ARGS...` and passes if
# the program exits non-zero with exactly one line on stderr and leaves no OUTPUT file; CTest then matches that line.
# A failed check of the script fails the test even when the line matches.
#   <program>       the program's target, ffd-match or ffd-voxelize.
#   AFTER_PROGRESS  the refusal comes after the program has reported progress (the meshes read): progress lines
#                   may come first, and the error is the last line (ExpectFailure.cmake's AFTER_WORK).
#   MESH            the program's first argument: ffd-voxelize's input mesh. Default --output, so that ffd-match
#                   is run as `ffd-match --output OUTPUT ARGS...`.
#   OUTPUT          the output file that must not appear. Default ${ITK_TEST_OUTPUT_DIR}/<program>Rejects<case> with
#                   .vtp (ffd-match) or .mha (ffd-voxelize).
#   SPECIAL_INPUT   <kind> <file name>: test/Programs/ExpectFailureOnSpecialInput.cmake first makes the special file
#                   ${ITK_TEST_OUTPUT_DIR}/<file name> (kind fifo, zero-link, deep-vtp, bad-mha or bad-nrrd, see
#                   there) and checks that the refusal comes within a second; @SPECIAL@ in MESH and ARGS stands for
#                   the file's path.
#   ARGS            the program's further arguments.
#   ERROR           the error line is "<program>: error: " followed by <regex>.
#   ERROR_CONTAINS  the error line is "<program>: error: " and <regex> matches further on in it.
#   PASS_REGULAR_EXPRESSION  <regex> as the test's PASS_REGULAR_EXPRESSION, without the "<program>: error: " prefix.
#   PROPERTIES      further test properties, as in set_tests_properties() (TIMEOUT, FAIL_REGULAR_EXPRESSION, ...).
function(ffd_add_rejection_test program case)
  cmake_parse_arguments(PARSE_ARGV 2 _arg "AFTER_PROGRESS"
    "MESH;OUTPUT;ERROR;ERROR_CONTAINS;PASS_REGULAR_EXPRESSION" "SPECIAL_INPUT;ARGS;PROPERTIES")
  if(_arg_UNPARSED_ARGUMENTS)
    message(FATAL_ERROR "ffd_add_rejection_test(${program} ${case}): unknown arguments '${_arg_UNPARSED_ARGUMENTS}'")
  endif()
  set(_name ${program}Rejects${case})

  if(DEFINED _arg_ERROR)
    set(_pass "${program}: error: ${_arg_ERROR}")
  elseif(DEFINED _arg_ERROR_CONTAINS)
    set(_pass "${program}: error: .*(${_arg_ERROR_CONTAINS})")
  elseif(DEFINED _arg_PASS_REGULAR_EXPRESSION)
    set(_pass "${_arg_PASS_REGULAR_EXPRESSION}")
  else()
    message(FATAL_ERROR
      "ffd_add_rejection_test(${program} ${case}): give ERROR, ERROR_CONTAINS or PASS_REGULAR_EXPRESSION")
  endif()

  if(NOT DEFINED _arg_MESH)
    set(_arg_MESH --output)
  endif()
  if(NOT DEFINED _arg_OUTPUT)
    set(_arg_OUTPUT ${ITK_TEST_OUTPUT_DIR}/${_name}.vtp)
    if(program STREQUAL "ffd-voxelize")
      set(_arg_OUTPUT ${ITK_TEST_OUTPUT_DIR}/${_name}.mha)
    endif()
  endif()

  set(_script ${_ffd_program_test_scripts}/ExpectFailure.cmake)
  set(_special_definitions "")
  if(DEFINED _arg_SPECIAL_INPUT)
    list(LENGTH _arg_SPECIAL_INPUT _length)
    if(NOT _length EQUAL 2)
      message(FATAL_ERROR "ffd_add_rejection_test(${program} ${case}): SPECIAL_INPUT takes <kind> <file name>")
    endif()
    list(GET _arg_SPECIAL_INPUT 0 _kind)
    list(GET _arg_SPECIAL_INPUT 1 _special)
    set(_special ${ITK_TEST_OUTPUT_DIR}/${_special})
    string(REPLACE "@SPECIAL@" "${_special}" _arg_MESH "${_arg_MESH}")
    string(REPLACE "@SPECIAL@" "${_special}" _arg_ARGS "${_arg_ARGS}")
    set(_special_definitions -DKIND=${_kind} -DSPECIAL=${_special})
    set(_script ${_ffd_program_test_scripts}/ExpectFailureOnSpecialInput.cmake)
  endif()

  set(_after_progress "")
  if(_arg_AFTER_PROGRESS)
    set(_after_progress -DAFTER_WORK=ON)
  endif()
  add_test(NAME ${_name}
    COMMAND ${CMAKE_COMMAND} -DPROGRAM=$<TARGET_FILE:${program}> -DMESH=${_arg_MESH} -DOUTPUT=${_arg_OUTPUT}
      "-DARGUMENTS=${_arg_ARGS}" ${_special_definitions} ${_after_progress} -P ${_script})
  # A PASS_REGULAR_EXPRESSION alone would pass the test whatever the script's checks found: the script's own
  # failure ("CMake Error" with its message) fails the test, together with a FAIL_REGULAR_EXPRESSION in PROPERTIES.
  set(_fail "CMake Error")
  list(FIND _arg_PROPERTIES FAIL_REGULAR_EXPRESSION _fail_key)
  if(_fail_key GREATER_EQUAL 0)
    math(EXPR _fail_value "${_fail_key} + 1")
    list(GET _arg_PROPERTIES ${_fail_value} _given_fail)
    set(_fail "${_fail}|${_given_fail}")
    list(REMOVE_AT _arg_PROPERTIES ${_fail_value} ${_fail_key})
  endif()
  set_tests_properties(${_name} PROPERTIES PASS_REGULAR_EXPRESSION "${_pass}" FAIL_REGULAR_EXPRESSION "${_fail}"
    ${_arg_PROPERTIES})
endfunction()
