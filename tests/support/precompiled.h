// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
// What every test program precompiles (cmake/HandeyePrecompile.cmake).
// glog, which Ceres brings, defines CHECK as Catch2 does: it comes first here
// and its CHECK goes, so CHECK in a test is Catch2's whatever the test includes.
#include <glog/logging.h>
#undef CHECK
#include <catch2/catch.hpp>
