# CTest registration: the doctest suites one by one, so a failure names its module.
set(DEFLEX_SUITES gcode interp writer profile cli diag stiffness force stock engage compensate samples)
foreach(suite ${DEFLEX_SUITES})
  add_test(NAME ${suite} COMMAND deflex_tests --test-suite=${suite} --no-version)
endforeach()
# Everything not in a named suite.
string(REPLACE ";" "," DEFLEX_SUITE_LIST "${DEFLEX_SUITES}")
add_test(NAME other COMMAND deflex_tests --test-suite-exclude=${DEFLEX_SUITE_LIST} --no-version)
set_tests_properties(${DEFLEX_SUITES} other PROPERTIES WORKING_DIRECTORY ${CMAKE_SOURCE_DIR})
