# SPDX-License-Identifier: GPL-2.0-or-later
# `cmake --install` into a fresh prefix, then the installed `handeye` package
# imports from there alone (no build tree on PYTHONPATH) and solves a small
# simulated problem with the installed libraries (found through its RUNPATH).
foreach(var HANDEYE_BUILD_DIR PREFIX PYTHON PACKAGE_DIR)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "installed_module.cmake needs -D${var}=...")
  endif()
endforeach()
file(REMOVE_RECURSE "${PREFIX}")
execute_process(COMMAND ${CMAKE_COMMAND} --install "${HANDEYE_BUILD_DIR}" --prefix "${PREFIX}"
                RESULT_VARIABLE code OUTPUT_QUIET ERROR_VARIABLE err)
if(NOT code EQUAL 0)
  message(FATAL_ERROR "cmake --install failed: ${err}")
endif()
set(script "import handeye, os, sys
assert handeye.__file__.startswith(sys.argv[1]), handeye.__file__
sim = handeye.simulate(sys.argv[2], cell='small', cameras=2, poses=6, visible_only=True, image_size=(640, 480))
print(handeye.Dataset.load(sim['dataset']))")
execute_process(COMMAND ${CMAKE_COMMAND} -E env --unset=PYTHONPATH
                        "PYTHONPATH=${PREFIX}/${PACKAGE_DIR}" ${PYTHON} -c "${script}"
                        "${PREFIX}/${PACKAGE_DIR}" "${PREFIX}/sim"
                RESULT_VARIABLE code OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT code EQUAL 0)
  message(FATAL_ERROR "the installed module failed (${code}):\n${out}\n${err}")
endif()
message(STATUS "installed module: ${out}")
