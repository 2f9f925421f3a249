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
