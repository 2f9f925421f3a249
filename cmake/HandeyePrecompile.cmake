# SPDX-License-Identifier: GPL-2.0-or-later
# Precompiled headers: parsing Eigen, Ceres, OpenCV, nlohmann::json and Catch2
# is most of a handeye file's compile time (GCC's -ftime-report on
# core/src/residuals.cc: parsing 70 %, code generation 12 %), and a clean
# build compiles them again in each of some 240 files. Each target that calls
# handeye_precompile() parses its list once. -DHANDEYE_PRECOMPILE_HEADERS=OFF
# builds without them (every file still includes what it uses).
option(HANDEYE_PRECOMPILE_HEADERS "Precompile the third-party headers of each target" ON)

# The standard and Eigen headers every target uses, then the target's own.
function(handeye_precompile target)
  if(HANDEYE_PRECOMPILE_HEADERS)
    target_precompile_headers(${target} PRIVATE
      <algorithm> <cmath> <map> <memory> <optional> <sstream> <string> <vector>
      <Eigen/Geometry> ${ARGN})
  endif()
endfunction()

# Unity builds: each file that includes CLI11, pybind11 or Catch2 compiles the
# headers' namespace-scope objects and the inline functions it calls again, so
# a file with a few lines of its own takes 12 s (tools/interrupt.cc at -O3;
# GCC's -ftime-report on tools/plan.cc: code generation 76 %). Compiled eight
# at a time they are compiled once per eight. A Release build on 2 cores
# (compile seconds of each target's files, from ninja's log): the tests 952 s
# one by one, 428 s eight at a time; the program 367 s and 63 s; the Python
# module 241 s and 72 s. Only the program, module and test targets are built
# this way; the libraries keep one object per file (tests read which object
# of handeye_core references what). Every file of such a target must keep its
# internal names apart from the other files' (the anonymous namespaces of
# eight files are one), and a using-directive at file scope reaches the files
# after it. -DHANDEYE_UNITY_BUILD=OFF compiles them one by one.
option(HANDEYE_UNITY_BUILD "Compile the program's, the Python module's and the tests' files eight at a time" ON)

function(handeye_unity target)
  if(HANDEYE_UNITY_BUILD)
    set_target_properties(${target} PROPERTIES UNITY_BUILD ON UNITY_BUILD_BATCH_SIZE 8)
  endif()
endfunction()
