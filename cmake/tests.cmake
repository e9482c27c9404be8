# CTest registration: the doctest suites one by one, so a failure names its
# module. Every test case belongs to one of these suites: `suites` below fails
# on a case outside them, and a suite that runs no case fails (it would pass
# without testing anything).
set(DEFLEX_SUITES gcode interp writer profile job cli diag plugin stiffness force stock engage compensate part samples process report plan measure fit stability)
# Cases that need a program the machine may lack (scripts/install-deps.sh
# --test installs it) are suites of their own, <module>_<what>: where the
# program is missing the case carries doctest::skip(), the entry runs nothing
# and ctest reports it skipped, not passed.
set(DEFLEX_TOOL_SUITES report_browser cli_completion stiffness_calculix)
foreach(suite ${DEFLEX_SUITES} ${DEFLEX_TOOL_SUITES})
  add_test(NAME ${suite} COMMAND deflex_tests --test-suite=${suite} --no-version)
  set_tests_properties(${suite} PROPERTIES WORKING_DIRECTORY ${CMAKE_SOURCE_DIR})
endforeach()
# doctest's summary line; a count of 0 means nothing ran.
set(DEFLEX_NONE_RAN "test cases: +0 \\|")
set_tests_properties(${DEFLEX_SUITES} PROPERTIES FAIL_REGULAR_EXPRESSION "${DEFLEX_NONE_RAN}")
if(DEFLEX_TOOL_SUITES)
  set_tests_properties(${DEFLEX_TOOL_SUITES} PROPERTIES SKIP_REGULAR_EXPRESSION "${DEFLEX_NONE_RAN}")
endif()
# The cases in none of the suites above (those outside any TEST_SUITE are in
# doctest's unnamed suite), skipped ones included: there must be none, or they
# would never run under CTest.
string(REPLACE ";" "," DEFLEX_SUITES_COMMA "${DEFLEX_SUITES};${DEFLEX_TOOL_SUITES}")
add_test(NAME suites COMMAND deflex_tests --count --no-skip --no-version --test-suite-exclude=${DEFLEX_SUITES_COMMA})
set_tests_properties(suites PROPERTIES PASS_REGULAR_EXPRESSION "passing the current filters: 0\n")
# A program built on the installed library as another project builds it
# (tests/consumer): cmake --install into a new prefix, find_package(deflex),
# build and run it.
add_test(NAME consumer COMMAND ${CMAKE_COMMAND} -DBUILD=${CMAKE_BINARY_DIR} -DSRC=${CMAKE_SOURCE_DIR}
  -DWORK=${CMAKE_BINARY_DIR}/consumer -DDEFLEX=$<TARGET_FILE:deflex> "-DGENERATOR=${CMAKE_GENERATOR}"
  -DLAUNCHER=${CMAKE_CXX_COMPILER_LAUNCHER} -P ${CMAKE_SOURCE_DIR}/cmake/consumer_test.cmake)
set_tests_properties(consumer PROPERTIES TIMEOUT 300)
