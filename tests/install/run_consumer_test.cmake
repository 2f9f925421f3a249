# SPDX-License-Identifier: GPL-2.0-or-later
# The installed package works for a project outside this tree:
#  1. `cmake --install` the build tree into a fresh prefix;
#     with no internals in its headers;
#  2. the installed CMake files point into that prefix only (no path of the
#     source or build tree leaks into what users get);
#  3. the installed program runs (it finds its libraries through RUNPATH);
#  4. tests/install/consumer configures against the prefix with
#     find_package(handeye 1.0) and builds the README's "Use as a library"
#     example and the programs of examples/;
#  5. they run: the in-memory calibration, the custom target plugin (render,
#     detect, calibrate), and the README example on a dataset simulated by
#     the installed program.
# Called by ctest with -DHANDEYE_SOURCE_DIR, -DHANDEYE_BUILD_DIR, -DWORK_DIR,
# -DGENERATOR; -DHANDEYE_README=FILE reads the example from another file
# than the source tree's README.md (to try a change to it).
cmake_minimum_required(VERSION 3.18)

foreach(var HANDEYE_SOURCE_DIR HANDEYE_BUILD_DIR WORK_DIR GENERATOR)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "run_consumer_test.cmake needs -D${var}=...")
  endif()
endforeach()

function(run what)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE code OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT code EQUAL 0)
    message(FATAL_ERROR "${what} failed (${code}):\n${ARGN}\n${out}\n${err}")
  endif()
  message(STATUS "${what}: ok")
  set(last_output "${out}${err}" PARENT_SCOPE)
endfunction()

file(REMOVE_RECURSE "${WORK_DIR}")
file(MAKE_DIRECTORY "${WORK_DIR}")
set(prefix "${WORK_DIR}/prefix")

# 1. Install.
run("cmake --install" "${CMAKE_COMMAND}" --install "${HANDEYE_BUILD_DIR}" --prefix "${prefix}")
foreach(installed include/handeye/handeye.h include/handeye/core/calibration.h include/handeye/detectors/registry.h
                  include/handeye/io/export.h lib/cmake/handeye/handeyeConfig.cmake
                  lib/cmake/handeye/handeyeConfigVersion.cmake bin/handeye)
  if(NOT EXISTS "${prefix}/${installed}")
    message(FATAL_ERROR "cmake --install did not install ${installed}")
  endif()
endforeach()

# No internals in the installed headers: no namespace of implementation
# details (`internal`, `cost_internal`, `detail`) is declared in one.
file(GLOB_RECURSE installed_headers "${prefix}/include/handeye/*.h")
foreach(header ${installed_headers})
  file(STRINGS "${header}" internals REGEX "namespace [A-Za-z_:]*(internal|detail)")
  if(internals)
    message(FATAL_ERROR "the installed header ${header} declares internals: ${internals}")
  endif()
endforeach()

# 2. No path of this tree in the installed package files.
file(GLOB package_files "${prefix}/lib/cmake/handeye/*.cmake")
foreach(file ${package_files})
  file(READ "${file}" text)
  foreach(tree "${HANDEYE_SOURCE_DIR}" "${HANDEYE_BUILD_DIR}")
    string(FIND "${text}" "${tree}" at)
    if(NOT at EQUAL -1)
      message(FATAL_ERROR "${file} refers to ${tree}; an installed package must not")
    endif()
  endforeach()
endforeach()

# 3. The installed program.
run("installed handeye --help" "${prefix}/bin/handeye" --help)

# 4. The README's example: the first ```cpp block under "## Use as a library".
if(NOT DEFINED HANDEYE_README)
  set(HANDEYE_README "${HANDEYE_SOURCE_DIR}/README.md")
endif()
file(READ "${HANDEYE_README}" readme)
string(FIND "${readme}" "## Use as a library" section)
if(section EQUAL -1)
  message(FATAL_ERROR "${HANDEYE_README} has no '## Use as a library' section")
endif()
string(SUBSTRING "${readme}" ${section} -1 readme)
string(FIND "${readme}" "```cpp\n" open)
if(open EQUAL -1)
  message(FATAL_ERROR "README.md's 'Use as a library' section has no ```cpp block")
endif()
math(EXPR open "${open} + 7")
string(SUBSTRING "${readme}" ${open} -1 readme)
string(FIND "${readme}" "```" close)
string(SUBSTRING "${readme}" 0 ${close} example)
string(REGEX MATCHALL "\n" newlines "${example}")
list(LENGTH newlines lines)
if(lines GREATER 15)
  message(FATAL_ERROR "README.md's library example has ${lines} lines; the README promises 15 at most")
endif()
file(WRITE "${WORK_DIR}/readme_example.cc" "${example}")

run("configure the consumer project"
    "${CMAKE_COMMAND}" -S "${HANDEYE_SOURCE_DIR}/tests/install/consumer" -B "${WORK_DIR}/build" -G "${GENERATOR}"
    -DCMAKE_BUILD_TYPE=Release "-DCMAKE_PREFIX_PATH=${prefix}" -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF
    "-DHANDEYE_EXPECTED_PREFIX=${prefix}" "-DHANDEYE_README_EXAMPLE=${WORK_DIR}/readme_example.cc"
    "-DHANDEYE_EXAMPLES_DIR=${HANDEYE_SOURCE_DIR}/examples")
run("build the consumer project" "${CMAKE_COMMAND}" --build "${WORK_DIR}/build" -j 2)

# 5. Run what was built.
run("examples/calibrate_in_memory" "${WORK_DIR}/build/examples/calibrate_in_memory")
message(STATUS "${last_output}")
run("examples/custom_target" "${WORK_DIR}/build/examples/custom_target" "${WORK_DIR}/dot_grid_cell")
message(STATUS "${last_output}")
run("installed handeye simulate" "${prefix}/bin/handeye" simulate "${WORK_DIR}/sim" --cell small --cameras 2
    --poses 8 --image-size 960x720 --seed 3)
run("README example" "${WORK_DIR}/build/readme_example" "${WORK_DIR}/sim/dataset.json")
message(STATUS "${last_output}")
string(FIND "${last_output}" "cam1" at)
if(at EQUAL -1)
  message(FATAL_ERROR "the README example printed no result for cam1")
endif()
