# CTest registration: the doctest suites one by one, so a failure names its
# module. Every test case belongs to one of these suites (a suite with no case
# would pass without testing anything).
set(DEFLEX_SUITES gcode interp writer profile cli diag stiffness force stock engage compensate part samples process report plan)
foreach(suite ${DEFLEX_SUITES})
  add_test(NAME ${suite} COMMAND deflex_tests --test-suite=${suite} --no-version)
endforeach()
set_tests_properties(${DEFLEX_SUITES} PROPERTIES WORKING_DIRECTORY ${CMAKE_SOURCE_DIR})
