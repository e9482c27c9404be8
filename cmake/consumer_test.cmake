# The consumer test (cmake/tests.cmake): installs this build into a new prefix,
# builds tests/consumer there as another project would (find_package(deflex),
# deflex::deflex), and checks its count of motions against `deflex path`.
# -DBUILD=build folder -DSRC=source folder -DWORK=scratch folder -DDEFLEX=the
# binary -DGENERATOR=CMake generator [-DLAUNCHER=compiler launcher]
function(run what)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${what} failed (${rc}):\n${out}\n${err}")
  endif()
  set(out "${out}" PARENT_SCOPE)
endfunction()

file(REMOVE_RECURSE ${WORK})
run("cmake --install" ${CMAKE_COMMAND} --install ${BUILD} --prefix ${WORK}/prefix)
set(launcher "")
if(LAUNCHER)
  set(launcher -DCMAKE_CXX_COMPILER_LAUNCHER=${LAUNCHER})
endif()
# Only the prefix: nothing of the source or build tree may be needed.
run("configuring the consumer" ${CMAKE_COMMAND} -S ${SRC}/tests/consumer -B ${WORK}/build -G ${GENERATOR}
    -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH=${WORK}/prefix ${launcher})
run("building the consumer" ${CMAKE_COMMAND} --build ${WORK}/build)

set(program ${SRC}/samples/programs/six_surfaces.nc)
run("the consumer" ${WORK}/build/consumer ${program})
string(STRIP "${out}" got)
# --centre: every motion, the corner pieces of G41/G42 too, as the consumer counts.
run("deflex path" ${DEFLEX} path --dialect fanuc --centre ${program})
string(REGEX MATCHALL "\n" lines "${out}")
list(LENGTH lines want)
if(NOT got STREQUAL want OR want EQUAL 0)
  message(FATAL_ERROR "the consumer counts ${got} motions in ${program}, deflex path ${want}")
endif()
message(STATUS "consumer: ${got} motions, as deflex path")
