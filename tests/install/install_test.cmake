# The install test, run by CTest as a script (cmake -P): installs the dawnforge build into
# a fresh prefix, then configures, builds and runs the consumer project beside this file
# against that prefix alone. Fails when:
# - an installed CMake file or header names the source or build tree (the package must
#   stand on its own: shaders, for one, are embedded into the runtime library);
# - find_package(dawnforge) fails, or finds a dawnforge other than the one installed;
# - the consumer does not compile or link (a dependency missing from the package config);
# - the consumer's calls into sim, exporters and runtime fail.
#
# Variables (-D): BUILD_DIR (the dawnforge build), SOURCE_ROOT (its source), WORK_DIR
# (wiped first, removed after success), GENERATOR, BUILD_TYPE, CXX_COMPILER, CXX_FLAGS (sanitizer flags the
# libraries were built with: the consumer must use them too), LAUNCHER (ccache or empty).
foreach(var BUILD_DIR SOURCE_ROOT WORK_DIR GENERATOR BUILD_TYPE CXX_COMPILER)
  if(NOT ${var})
    message(FATAL_ERROR "install_test.cmake: ${var} is not set")
  endif()
endforeach()

# Runs a command; on failure prints its output and stops.
function(step what)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "install test: ${what} failed (${rc}):\n${out}")
  endif()
  set(step_output "${out}" PARENT_SCOPE)
endfunction()

set(prefix ${WORK_DIR}/prefix)
set(consumer ${WORK_DIR}/consumer)
file(REMOVE_RECURSE ${WORK_DIR})

step("cmake --install" ${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${prefix})

file(GLOB_RECURSE package_files ${prefix}/lib/cmake/* ${prefix}/include/*)
foreach(file IN LISTS package_files)
  file(READ ${file} text)
  foreach(tree ${SOURCE_ROOT} ${BUILD_DIR})
    string(FIND "${text}" "${tree}" at)
    if(NOT at EQUAL -1)
      message(FATAL_ERROR "install test: ${file} names ${tree}: the package must not point into the tree it came from")
    endif()
  endforeach()
endforeach()

step("configuring the consumer" ${CMAKE_COMMAND} -S ${CMAKE_CURRENT_LIST_DIR} -B ${consumer} -G ${GENERATOR}
  -DCMAKE_BUILD_TYPE=${BUILD_TYPE} -DCMAKE_CXX_COMPILER=${CXX_COMPILER} -DCMAKE_CXX_COMPILER_LAUNCHER=${LAUNCHER}
  "-DCMAKE_CXX_FLAGS=${CXX_FLAGS}" "-DCMAKE_EXE_LINKER_FLAGS=${CXX_FLAGS}"
  -DCMAKE_PREFIX_PATH=${prefix} -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF -Wno-dev)
file(STRINGS ${consumer}/CMakeCache.txt found REGEX "^dawnforge_DIR:")
if(NOT found STREQUAL "dawnforge_DIR:PATH=${prefix}/lib/cmake/dawnforge")
  message(FATAL_ERROR "install test: the consumer found another dawnforge: ${found}")
endif()

step("building the consumer" ${CMAKE_COMMAND} --build ${consumer})
step("running the consumer" ${consumer}/consumer)
message("${step_output}")
# Kept when a step fails, to look into; gone when all is well (a sanitized build's prefix
# is about a gigabyte).
file(REMOVE_RECURSE ${WORK_DIR})
