# CTest registration: the doctest suites one by one, so a failure names its module.
foreach(suite gcode interp writer profile cli diag stiffness force)
  add_test(NAME ${suite} COMMAND deflex_tests --test-suite=${suite} --no-version)
endforeach()
# Everything not in a named suite.
add_test(NAME other COMMAND deflex_tests --test-suite-exclude=gcode,interp,writer,profile,cli,diag,stiffness,force --no-version)
set_tests_properties(gcode interp writer profile cli diag stiffness force other PROPERTIES WORKING_DIRECTORY ${CMAKE_SOURCE_DIR})
