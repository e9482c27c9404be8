# The consumer test (cmake/tests.cmake): installs this build into a new prefix,
# builds tests/consumer there as another project would (find_package(deflex),
# deflex::deflex), and checks that its compensation of the six-surface sample
# writes the command line's bytes and summary.json; then the same from a
# Python script (tests/consumer/consumer.py) through the installed package.
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

# The same from Python through the installed package, where the build has it
# (python/: built when pybind11 is installed). Debian's python3: the module is
# built for it (a python3 of pyenv or a venv may come first in PATH).
file(GLOB_RECURSE init ${WORK}/prefix/__init__.py)
list(FILTER init INCLUDE REGEX "/deflex/__init__\\.py$")
if(init)
  list(GET init 0 init)
  get_filename_component(pkg ${init} DIRECTORY)
  get_filename_component(site ${pkg} DIRECTORY)
  set(py /usr/bin/python3)
  if(NOT EXISTS ${py})
    find_program(py python3 REQUIRED)
  endif()
  run("the Python consumer" ${CMAKE_COMMAND} -E chdir ${SRC} ${CMAKE_COMMAND} -E env PYTHONPATH=${site}
      ${py} ${SRC}/tests/consumer/consumer.py ${args} ${WORK}/python.nc ${WORK}/python.json)
  message(STATUS "Python consumer: ${out}")
  execute_process(COMMAND ${CMAKE_COMMAND} -E compare_files ${WORK}/python.nc ${WORK}/cli.nc RESULT_VARIABLE differ)
  if(differ)
    message(FATAL_ERROR "the Python consumer's program differs from the command line's (in ${WORK})")
  endif()
  # The same document, whatever the two JSON writers' spacing.
  run("comparing summary.json" ${py} -c
      "import json,sys; a,b=(json.load(open(f)) for f in sys.argv[1:]); sys.exit(a!=b)"
      ${WORK}/python.json ${WORK}/cli_report/summary.json)
  message(STATUS "Python consumer: the program and summary.json are the command line's")
else()
  message(STATUS "no Python package in the install (pybind11 missing): the Python consumer not run")
endif()
file(SIZE ${WORK}/cli.nc size)
message(STATUS "consumer: the compensated program (${size} bytes) and summary.json are the command line's")
