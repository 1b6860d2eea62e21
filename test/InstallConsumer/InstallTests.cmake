# Tests of the installed package (stand-alone mode only: inside ITK and in the external-module mode the
# module is installed in ITK's layout and found by ITK's own find_package(ITK COMPONENTS FFDShapeMatching),
# which these tests do not cover). In order, through fixtures:
#   FFDShapeMatchingInstall               cmake --install into a fresh temporary prefix; the files are there
#   FFDShapeMatchingInstalledProgram      <prefix>/bin/ffd-match --help runs and finds <prefix>'s libraries; the
#                                         snapshot renders (FFDShapeMatchingInstalledProgramSnapshot)
#   FFDShapeMatchingInstallConsumerBuild  configures and builds test/InstallConsumer with find_package against
#                                         the prefix, with this build's compilers, flags and ccache launcher
#   FFDShapeMatchingInstallConsumerRun    the consumer reads two meshes and voxelizes one
set(_ffd_consumer_source ${CMAKE_CURRENT_LIST_DIR})
set(_ffd_consumer_work ${CMAKE_BINARY_DIR}/InstallConsumer)
set(_ffd_prefix ${_ffd_consumer_work}/prefix)
set(_ffd_consumer_build ${_ffd_consumer_work}/build)

set(_ffd_expected_files
  ${CMAKE_INSTALL_LIBDIR}/cmake/FFDShapeMatching/FFDShapeMatchingConfig.cmake
  ${CMAKE_INSTALL_LIBDIR}/cmake/FFDShapeMatching/FFDShapeMatchingConfigVersion.cmake
  ${CMAKE_INSTALL_LIBDIR}/cmake/FFDShapeMatching/FFDShapeMatchingTargets.cmake
  ${CMAKE_INSTALL_INCLUDEDIR}/FFDShapeMatching/FFDShapeMatchingExport.h
  ${CMAKE_INSTALL_INCLUDEDIR}/FFDShapeMatching/itkTriangleMeshToVoxelImageFilter.hxx)
if(FFDShapeMatching_BUILD_APPLICATIONS)
  list(APPEND _ffd_expected_files ${CMAKE_INSTALL_BINDIR}/ffd-match ${CMAKE_INSTALL_BINDIR}/ffd-voxelize
    ${CMAKE_INSTALL_BINDIR}/ffd-templates)
endif()
add_test(NAME FFDShapeMatchingInstall
  COMMAND ${CMAKE_COMMAND} -DBUILD_DIR=${CMAKE_BINARY_DIR} -DPREFIX=${_ffd_prefix} -DCONFIG=$<CONFIG>
    "-DEXPECTED=${_ffd_expected_files}" -P ${_ffd_consumer_source}/InstallToPrefix.cmake)
set_tests_properties(FFDShapeMatchingInstall PROPERTIES FIXTURES_SETUP FFDShapeMatchingInstalled
  PASS_REGULAR_EXPRESSION "installed [0-9]+ files into")

if(FFDShapeMatching_BUILD_APPLICATIONS)
  add_test(NAME FFDShapeMatchingInstalledProgram
    COMMAND ${CMAKE_COMMAND} -DPROGRAM=${_ffd_prefix}/${CMAKE_INSTALL_BINDIR}/ffd-match
      -DLIBRARY_DIR=${_ffd_prefix}/${CMAKE_INSTALL_LIBDIR}
      -P ${_ffd_consumer_source}/CheckInstalledProgram.cmake)
  set_tests_properties(FFDShapeMatchingInstalledProgram PROPERTIES FIXTURES_REQUIRED FFDShapeMatchingInstalled
    PASS_REGULAR_EXPRESSION "ffd-match --help ok, libFFDShapeMatching from the prefix")
endif()

# The consumer is built as a user would, plus what this build's compiler needs: with Clang against Debian's
# GCC-built ITK, the compiler-detection header of CMake/FFDShapeMatchingClangWithDebianITK.cmake (an ITK 5.2
# matter that any Clang user of that ITK meets, with or without this module); the sanitizer flags; -march=native when
# the library was compiled for this processor (FFDShapeMatching_OPTIMIZE_FOR_BUILD_MACHINE), as a user matching the
# library's results would compile (the example below must write the program's bytes).
set(_ffd_consumer_cxx_flags "${CMAKE_CXX_FLAGS}")
if(FFDShapeMatching_OPTIMIZE_FOR_BUILD_MACHINE)
  string(APPEND _ffd_consumer_cxx_flags " -march=native")
endif()
if(CMAKE_CXX_COMPILER_ID STREQUAL "Clang" AND EXISTS "${CMAKE_BINARY_DIR}/ITKClangCompatibility/itk_compiler_detection.h")
  string(APPEND _ffd_consumer_cxx_flags " -include ${CMAKE_BINARY_DIR}/ITKClangCompatibility/itk_compiler_detection.h")
endif()
add_test(NAME FFDShapeMatchingInstallConsumerBuild
  COMMAND ${CMAKE_COMMAND} -DSOURCE=${_ffd_consumer_source} -DBINARY=${_ffd_consumer_build} -DPREFIX=${_ffd_prefix}
    "-DGENERATOR=${CMAKE_GENERATOR}" -DMAKE_PROGRAM=${CMAKE_MAKE_PROGRAM} -DBUILD_TYPE=${CMAKE_BUILD_TYPE}
    -DC_COMPILER=${CMAKE_C_COMPILER} -DCXX_COMPILER=${CMAKE_CXX_COMPILER} "-DC_FLAGS=${CMAKE_C_FLAGS}"
    "-DCXX_FLAGS=${_ffd_consumer_cxx_flags}" "-DLINKER_FLAGS=${CMAKE_EXE_LINKER_FLAGS}"
    -DLAUNCHER=${CMAKE_CXX_COMPILER_LAUNCHER} -P ${_ffd_consumer_source}/BuildConsumer.cmake)
set_tests_properties(FFDShapeMatchingInstallConsumerBuild PROPERTIES
  FIXTURES_REQUIRED FFDShapeMatchingInstalled FIXTURES_SETUP FFDShapeMatchingInstallConsumerBuilt TIMEOUT 900)

# Through cmake -E env: the program exists only once the fixture has built it.
add_test(NAME FFDShapeMatchingInstallConsumerRun
  COMMAND ${CMAKE_COMMAND} -E env ${_ffd_consumer_build}/InstallConsumer ${CMAKE_CURRENT_LIST_DIR}/../Input/cube.off
    ${CMAKE_CURRENT_LIST_DIR}/box.ply)
set_tests_properties(FFDShapeMatchingInstallConsumerRun PROPERTIES FIXTURES_REQUIRED FFDShapeMatchingInstallConsumerBuilt
  PASS_REGULAR_EXPRESSION "cube.off: 8 points, 12 cells\n.*box.ply: 8 points, 12 cells\nvoxelized 12x12x8, 256 inside")

# The README's example built against the prefix writes the same mesh, byte for byte, as the installed ffd-match
# with its default method (go+cpd), the same grid and voxel size (on the demo's meshes).
if(FFDShapeMatching_BUILD_APPLICATIONS)
  set(_ffd_demo ${ITK_TEST_OUTPUT_DIR}/ffd-match-demo)
  add_test(NAME FFDShapeMatchingInstalledExample
    COMMAND ${CMAKE_COMMAND} -E env ${_ffd_consumer_build}/MatchMeshes ${_ffd_demo}/source.vtp ${_ffd_demo}/target.vtp
      ${_ffd_consumer_work}/example.off 8 2)
  add_test(NAME FFDShapeMatchingInstalledExampleProgram
    COMMAND ${_ffd_prefix}/${CMAKE_INSTALL_BINDIR}/ffd-match --source ${_ffd_demo}/source.vtp
      --target ${_ffd_demo}/target.vtp --grid 8 --voxel-size 2 --output ${_ffd_consumer_work}/program.off)
  add_test(NAME FFDShapeMatchingInstalledExampleSameAsProgram
    COMMAND ${CMAKE_COMMAND} -E compare_files ${_ffd_consumer_work}/example.off ${_ffd_consumer_work}/program.off)
  set_tests_properties(FFDShapeMatchingInstalledExample PROPERTIES DEPENDS ffd-matchDemo
    FIXTURES_REQUIRED FFDShapeMatchingInstallConsumerBuilt TIMEOUT 120)
  set_tests_properties(FFDShapeMatchingInstalledExampleProgram PROPERTIES DEPENDS ffd-matchDemo
    FIXTURES_REQUIRED FFDShapeMatchingInstalled TIMEOUT 120)
  set_tests_properties(FFDShapeMatchingInstalledExampleSameAsProgram PROPERTIES
    DEPENDS "FFDShapeMatchingInstalledExample;FFDShapeMatchingInstalledExampleProgram")

  # The installed ffd-match renders a snapshot from the prefix (under xvfb-run, as
  # ffd-matchSnapshot in the build tree).
  find_program(FFDShapeMatching_XVFB_RUN xvfb-run)
  if(NOT FFDShapeMatching_XVFB_RUN)
    set(FFDShapeMatching_XVFB_RUN xvfb-run-is-missing-install-the-xvfb-package)
  endif()
  set(_ffd_snapshot_command ${FFDShapeMatching_XVFB_RUN} -a ${_ffd_prefix}/${CMAKE_INSTALL_BINDIR}/ffd-match
    --source ${_ffd_demo}/source.vtp --target ${_ffd_demo}/target.vtp --method go --grid 6 --voxel-size 2
    --levels 1 --iterations 10 --output ${_ffd_consumer_work}/snapshot.vtp --snapshot ${_ffd_consumer_work}/snapshot.png)
  add_test(NAME FFDShapeMatchingInstalledProgramSnapshot
    COMMAND ${CMAKE_COMMAND} -DPNG=${_ffd_consumer_work}/snapshot.png "-DCOMMAND=${_ffd_snapshot_command}"
      -P ${CMAKE_CURRENT_LIST_DIR}/../Programs/CheckSnapshot.cmake)
  set_tests_properties(FFDShapeMatchingInstalledProgramSnapshot PROPERTIES DEPENDS ffd-matchDemo
    FIXTURES_REQUIRED FFDShapeMatchingInstalled PASS_REGULAR_EXPRESSION "snapshot ok: 1400 x 700" TIMEOUT 120
    ENVIRONMENT "ASAN_OPTIONS=detect_leaks=0")
endif()
