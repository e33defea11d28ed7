# cmake -DBUILD_DIR=... -DSOURCE_DIR=... -DEXAMPLE_DIR=... -DPREFIX=...
#       -DEXTERNAL_BUILD_DIR=... [-DCXX_COMPILER=...] [-DMAKE_PROGRAM=...]
#       [-DBUILD_TYPE=...] -P run_external.cmake
# (a) cmake --install BUILD_DIR into a clean PREFIX, (b) configure EXAMPLE_DIR
# as a separate Ninja project with CMAKE_PREFIX_PATH=PREFIX, (c) build it,
# (d) run it; each step must succeed. Also checks that the installed package
# and the external build refer to nothing in the source or build tree.
cmake_minimum_required(VERSION 3.25)
foreach(var BUILD_DIR SOURCE_DIR EXAMPLE_DIR PREFIX EXTERNAL_BUILD_DIR)
  if(NOT ${var})
    message(FATAL_ERROR "run_external.cmake: -D${var}=... is required")
  endif()
endforeach()
if(NOT BUILD_TYPE)
  set(BUILD_TYPE Release)
endif()

# Runs one step; on failure prints its command and output and stops.
function(run_step name)
  execute_process(COMMAND ${ARGN}
    RESULT_VARIABLE result OUTPUT_VARIABLE output ERROR_VARIABLE output)
  if(NOT result EQUAL 0)
    list(JOIN ARGN " " command)
    message(FATAL_ERROR "install test: step '${name}' failed (${result}):\n  ${command}\n${output}")
  endif()
  message(STATUS "install test: ${name}: ok")
  set(step_output "${output}" PARENT_SCOPE)
endfunction()

# Start from an empty prefix and external build every time.
file(REMOVE_RECURSE ${PREFIX} ${EXTERNAL_BUILD_DIR})

# (a) Install into a clean prefix.
run_step(install ${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${PREFIX} --config ${BUILD_TYPE})

# The installed CMake package must be relocatable: no path into the source or
# build tree (the headers and library it names must come from PREFIX).
file(GLOB_RECURSE package_files ${PREFIX}/*.cmake)
if(NOT package_files)
  message(FATAL_ERROR "install test: no CMake package files installed under ${PREFIX}")
endif()
foreach(file IN LISTS package_files)
  file(READ ${file} text)
  foreach(tree ${SOURCE_DIR} ${BUILD_DIR})
    string(FIND "${text}" "${tree}" at)
    if(NOT at EQUAL -1)
      message(FATAL_ERROR "install test: ${file} refers to ${tree}")
    endif()
  endforeach()
endforeach()

# (b) Configure the example as a separate project against PREFIX only.
set(configure_args -S ${EXAMPLE_DIR} -B ${EXTERNAL_BUILD_DIR} -G Ninja
  -DCMAKE_PREFIX_PATH=${PREFIX}
  -DCMAKE_BUILD_TYPE=${BUILD_TYPE}
  # never a package from a user or system package registry
  -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF
  -DCMAKE_FIND_USE_SYSTEM_PACKAGE_REGISTRY=OFF)
if(CXX_COMPILER)
  list(APPEND configure_args -DCMAKE_CXX_COMPILER=${CXX_COMPILER})
endif()
if(MAKE_PROGRAM)
  list(APPEND configure_args -DCMAKE_MAKE_PROGRAM=${MAKE_PROGRAM})
endif()
run_step(configure ${CMAKE_COMMAND} ${configure_args})

file(STRINGS ${EXTERNAL_BUILD_DIR}/CMakeCache.txt found_dir REGEX "^tensormass_DIR:")
string(REGEX REPLACE "^[^=]*=" "" found_dir "${found_dir}")
cmake_path(IS_PREFIX PREFIX "${found_dir}" NORMALIZE from_prefix)
if(NOT from_prefix)
  message(FATAL_ERROR "install test: find_package(tensormass) found '${found_dir}', not the package in ${PREFIX}")
endif()

# (c) Build it; its compile and link lines must not reach into the repository.
run_step(build ${CMAKE_COMMAND} --build ${EXTERNAL_BUILD_DIR})
file(READ ${EXTERNAL_BUILD_DIR}/build.ninja ninja_text)
# (EXTERNAL_BUILD_DIR itself lies under BUILD_DIR, so name the library's folder.)
foreach(tree ${SOURCE_DIR}/runtime ${SOURCE_DIR}/generated ${BUILD_DIR}/runtime)
  string(FIND "${ninja_text}" "${tree}" at)
  if(NOT at EQUAL -1)
    message(FATAL_ERROR "install test: the external build refers to ${tree}")
  endif()
endforeach()

# (d) Run it: exit 0 means a finite final state with the tip moved down.
run_step(run ${EXTERNAL_BUILD_DIR}/external_solver)
message("${step_output}")

# (e) The runtime's package: a scene stepped by tensormass::Simulation.
run_step(run_scene ${CMAKE_COMMAND} -E chdir ${EXTERNAL_BUILD_DIR} ${EXTERNAL_BUILD_DIR}/scene_runner)
message("${step_output}")
