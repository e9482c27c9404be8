# The consumer test (cmake/tests.cmake): installs this build into a new prefix,
# builds tests/consumer there as another project would (find_package(deflex),
# deflex::deflex), and checks that its compensation of the six-surface sample
# writes the command line's bytes and summary.json.
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

# The six-surface sample's compensation, as scripts/main.sh runs it, through
# the consumer and through the command line, both from the source folder
# (config.yaml there names the machine, the libraries and the material).
set(sample ${SRC}/samples)
set(args ${sample}/programs/six_surfaces.nc ${sample}/stock/six_surfaces_stock.stl ${sample}/parts/six_surfaces.stl)
run("the consumer" ${CMAKE_COMMAND} -E chdir ${SRC} ${WORK}/build/consumer ${args} ${WORK}/consumer.nc ${WORK}/consumer.json)
message(STATUS "consumer: ${out}")
list(GET args 0 program)
list(GET args 1 stock)
list(GET args 2 part)
run("deflex compensate" ${CMAKE_COMMAND} -E chdir ${SRC} ${DEFLEX} compensate ${program} --stock ${stock} --part ${part}
    -o ${WORK}/cli.nc --report ${WORK}/cli_report)
foreach(pair "consumer.nc;cli.nc" "consumer.json;cli_report/summary.json")
  list(GET pair 0 a)
  list(GET pair 1 b)
  execute_process(COMMAND ${CMAKE_COMMAND} -E compare_files ${WORK}/${a} ${WORK}/${b} RESULT_VARIABLE differ)
  if(differ)
    message(FATAL_ERROR "the consumer's ${a} differs from the command line's ${b} (in ${WORK})")
  endif()
endforeach()
file(SIZE ${WORK}/cli.nc size)
message(STATUS "consumer: the compensated program (${size} bytes) and summary.json are the command line's")
