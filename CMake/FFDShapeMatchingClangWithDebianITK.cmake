# Lets Clang compile against an ITK that was built with GCC only (Debian's libinsighttoolkit5-dev): ITK's
# generated itk_compiler_detection.h knows just the compiler ITK was built with and stops every other one
# with "Unsupported compiler". The sanitizer and fuzzing builds (Utilities/SanitizerAndFuzzBuild.sh) use
# Clang, because libFuzzer comes with Clang. This writes the same header with CMake's
# write_compiler_detection_header for GNU and Clang, with the feature list of ITK 5.2's own
# Modules/Core/Common/CMake/itkGenerateNewCompilerFeatureDetectionHeaders.cmake, and includes it ahead of ITK's.
if(NOT CMAKE_CXX_COMPILER_ID STREQUAL "Clang")
  return()
endif()
find_file(_ffd_itk_detection itk_compiler_detection.h PATHS ${ITK_INCLUDE_DIRS} NO_DEFAULT_PATH)
if(NOT _ffd_itk_detection)
  return()
endif()
file(READ "${_ffd_itk_detection}" _ffd_itk_detection_text)
if(_ffd_itk_detection_text MATCHES "ITK_COMPILER_INFO_Clang_CXX")
  return()
endif()
set(_ffd_compat_dir "${CMAKE_BINARY_DIR}/ITKClangCompatibility")
cmake_policy(PUSH)
if(POLICY CMP0120)
  cmake_policy(SET CMP0120 OLD) # the module is deprecated in CMake 3.20+ but still does this job exactly
endif()
include(WriteCompilerDetectionHeader)
write_compiler_detection_header(
  FILE "${_ffd_compat_dir}/itk_compiler_detection.h"
  PREFIX ITK
  COMPILERS GNU Clang
  VERSION 3.10
  FEATURES
    cxx_aggregate_default_initializers cxx_alias_templates cxx_alignas cxx_alignof cxx_attributes
    cxx_attribute_deprecated cxx_auto_type cxx_binary_literals cxx_constexpr cxx_contextual_conversions
    cxx_decltype_incomplete_return_types cxx_decltype cxx_decltype_auto cxx_default_function_template_args
    cxx_defaulted_functions cxx_defaulted_move_initializers cxx_delegating_constructors cxx_deleted_functions
    cxx_digit_separators cxx_enum_forward_declarations cxx_explicit_conversions cxx_extended_friend_declarations
    cxx_extern_templates cxx_final cxx_func_identifier cxx_generalized_initializers cxx_generic_lambdas
    cxx_inheriting_constructors cxx_inline_namespaces cxx_lambdas cxx_lambda_init_captures
    cxx_local_type_template_args cxx_long_long_type cxx_noexcept cxx_nonstatic_member_init cxx_nullptr
    cxx_override cxx_range_for cxx_raw_string_literals cxx_reference_qualified_functions cxx_relaxed_constexpr
    cxx_return_type_deduction cxx_right_angle_brackets cxx_rvalue_references cxx_sizeof_member cxx_static_assert
    cxx_strong_enums cxx_thread_local cxx_trailing_return_types cxx_unicode_literals cxx_uniform_initialization
    cxx_unrestricted_unions cxx_user_literals cxx_variable_templates cxx_variadic_macros cxx_variadic_templates
    cxx_template_template_parameters)
cmake_policy(POP)
# ITK's itkConfigure.h includes the header with quotes, so its own copy would be found first; included ahead
# of every source file instead, the new header defines the include guard both share.
add_compile_options("SHELL:-include ${_ffd_compat_dir}/itk_compiler_detection.h")
message(STATUS "FFDShapeMatching: ITK's compiler-detection header written for Clang in ${_ffd_compat_dir}")
