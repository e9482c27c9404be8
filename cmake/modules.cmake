# One static library per module src/<name>/ (+ include/deflex/<name>/):
#
#   deflex_module(NAME <name> [PUBLIC <dep>...] [PRIVATE <dep>...] [SOURCES <file>...] [FRONT_END])
#
# A dep is another module (declared before this one) or any target or library
# name. PUBLIC: the module's public headers include the dep's; PRIVATE: only
# its .cpp files do. Modules are declared in dependency order, which is also a
# check that the graph has no cycle.
#
# The build enforces the graph: each module's include root
# (build/modules/<name>/) holds only deflex/<name>, a link to its headers, so a
# file that includes the headers of a module its module does not depend on
# fails to compile. Headers under src/<name>/internal/ are shared with the
# modules of this build but never installed: they may name third-party types
# the public headers keep out (yaml-cpp).
#
# The .cpp files are globbed per folder, so a new file needs no edit here.
# FRONT_END: a program's front end (cli), neither installed nor in deflex::deflex.
function(deflex_module)
  cmake_parse_arguments(M "FRONT_END" "NAME" "PUBLIC;PRIVATE;SOURCES" ${ARGN})
  set(t deflex_${M_NAME})
  file(GLOB srcs CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/src/${M_NAME}/*.cpp)
  # A program's main() is the executable's, not the library's.
  list(FILTER srcs EXCLUDE REGEX "/main\\.cpp$")
  add_library(${t} STATIC ${srcs} ${M_SOURCES})
  add_library(deflex::${M_NAME} ALIAS ${t})
  set_target_properties(${t} PROPERTIES EXPORT_NAME ${M_NAME})

  set(root ${PROJECT_BINARY_DIR}/modules/${M_NAME})
  file(MAKE_DIRECTORY ${root}/deflex)
  if(EXISTS ${PROJECT_SOURCE_DIR}/include/deflex/${M_NAME})
    file(CREATE_LINK ${PROJECT_SOURCE_DIR}/include/deflex/${M_NAME} ${root}/deflex/${M_NAME} SYMBOLIC)
  endif()
  target_include_directories(${t} PUBLIC $<BUILD_INTERFACE:${root}>
                                         $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
  if(EXISTS ${PROJECT_SOURCE_DIR}/src/${M_NAME}/internal)
    target_include_directories(${t} PUBLIC $<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}/src/${M_NAME}/internal>)
  endif()

  foreach(scope PUBLIC PRIVATE)
    foreach(d ${M_${scope}})
      if(TARGET deflex_${d})
        target_link_libraries(${t} ${scope} deflex_${d})
      elseif(EXISTS ${PROJECT_SOURCE_DIR}/src/${d})
        message(FATAL_ERROR "deflex_module(${M_NAME}): module ${d} is not declared yet (declare modules in dependency order)")
      else()
        target_link_libraries(${t} ${scope} ${d})
      endif()
    endforeach()
  endforeach()

  if(NOT M_FRONT_END)
    set_property(GLOBAL APPEND PROPERTY DEFLEX_LIBRARY_MODULES ${M_NAME})
  endif()
endfunction()
