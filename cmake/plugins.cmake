# deflex's plugins: shared objects loaded with dlopen() on first use
# (src/plugin/load.cpp says why: start-up time), for what few runs need and
# whose libraries are large: OpenCASCADE (STEP and IGES files, the solid
# tool model), Ceres (the machine fit) and CHOLMOD (the solid models'
# factorisation).
#
#   deflex_plugin(NAME <name> FOR <module>... SOURCES <file>... LIBRARIES <lib>...)
#
# lib<name>.so, in build/plugins/ and installed in <libdir>/deflex/. Its
# sources live with the modules that load it (src/<module>/<folder>/, not
# globbed into the module's library); it compiles against those modules'
# headers, links the libraries it wraps and deflex_diag (deflex::Error), and
# exports its entry points only. Each module FOR builds it first, so every
# program linking the module (the CLI, the tests, the Python module, the
# fuzz targets) finds it built.
set(DEFLEX_PLUGIN_BUILD_DIR ${CMAKE_BINARY_DIR}/plugins)
set(DEFLEX_PLUGIN_INSTALL_DIR ${CMAKE_INSTALL_LIBDIR}/deflex)

function(deflex_plugin)
  cmake_parse_arguments(P "" "NAME" "FOR;SOURCES;LIBRARIES" ${ARGN})
  set(t deflex_${P_NAME})
  add_library(${t} MODULE ${P_SOURCES})
  foreach(m ${P_FOR})
    target_include_directories(${t} PRIVATE $<TARGET_PROPERTY:deflex_${m},INTERFACE_INCLUDE_DIRECTORIES>)
    add_dependencies(deflex_${m} ${t})
  endforeach()
  target_link_libraries(${t} PRIVATE deflex_diag ${P_LIBRARIES})
  set_target_properties(${t} PROPERTIES LIBRARY_OUTPUT_DIRECTORY ${DEFLEX_PLUGIN_BUILD_DIR}
                        CXX_VISIBILITY_PRESET hidden VISIBILITY_INLINES_HIDDEN ON)
  target_link_options(${t} PRIVATE -Wl,--exclude-libs,ALL)
  install(TARGETS ${t} LIBRARY DESTINATION ${DEFLEX_PLUGIN_INSTALL_DIR})
endfunction()

# Where src/plugin/load.cpp looks: the build tree's folder for the build
# tree's programs, else <prefix>/<libdir>/deflex beside the program.
set_source_files_properties(${CMAKE_SOURCE_DIR}/src/plugin/load.cpp PROPERTIES COMPILE_DEFINITIONS
  "DEFLEX_BUILD_DIR=\"${CMAKE_BINARY_DIR}\";DEFLEX_PLUGIN_BUILD_DIR=\"${DEFLEX_PLUGIN_BUILD_DIR}\";DEFLEX_PLUGIN_LIBDIR=\"${DEFLEX_PLUGIN_INSTALL_DIR}\";DEFLEX_PLUGIN_INSTALL_DIR=\"${CMAKE_INSTALL_FULL_LIBDIR}/deflex\"")
