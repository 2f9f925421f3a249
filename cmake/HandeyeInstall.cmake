# SPDX-License-Identifier: GPL-2.0-or-later
# `cmake --install`: headers under include/handeye/, the five libraries and
# the program, and a CMake package (handeyeConfig.cmake, its version file and
# the exported targets handeye::core, handeye::detectors, handeye::io,
# handeye::all (the three, <handeye/handeye.h>), handeye::sim,
# handeye::report, handeye::handeye). Included from the
# top-level CMakeLists.txt after the targets exist.
include(CMakePackageConfigHelpers)

set(HANDEYE_INSTALL_CMAKEDIR "${CMAKE_INSTALL_LIBDIR}/cmake/handeye"
    CACHE STRING "Where handeyeConfig.cmake is installed, relative to the prefix")

# Every public header of every module, whatever files are added later:
# core/include/handeye/core/*.h → include/handeye/core/*.h, and so on.
foreach(module core detectors io sim report)
  install(DIRECTORY "${PROJECT_SOURCE_DIR}/${module}/include/"
          DESTINATION "${CMAKE_INSTALL_INCLUDEDIR}"
          COMPONENT handeye_development
          FILES_MATCHING PATTERN "*.h")
endforeach()

set(HANDEYE_INSTALLED_TARGETS handeye_core handeye_detectors handeye_io handeye_all handeye_sim handeye_report handeye)
# The internal worker pool is linked into the libraries; static ones pass it on
# to their users' link lines, so then it is installed (no header) and exported.
if(NOT BUILD_SHARED_LIBS)
  list(APPEND HANDEYE_INSTALLED_TARGETS handeye_parallel)
endif()
install(TARGETS ${HANDEYE_INSTALLED_TARGETS}
        EXPORT handeyeTargets
        RUNTIME DESTINATION "${CMAKE_INSTALL_BINDIR}" COMPONENT handeye_runtime
        LIBRARY DESTINATION "${CMAKE_INSTALL_LIBDIR}" COMPONENT handeye_runtime
                NAMELINK_COMPONENT handeye_development
        ARCHIVE DESTINATION "${CMAKE_INSTALL_LIBDIR}" COMPONENT handeye_development
        INCLUDES DESTINATION "${CMAKE_INSTALL_INCLUDEDIR}")

install(EXPORT handeyeTargets
        NAMESPACE handeye::
        DESTINATION "${HANDEYE_INSTALL_CMAKEDIR}"
        COMPONENT handeye_development)

# What a consumer of static libraries has to find again (handeyeConfig.cmake.in).
set(HANDEYE_OPENCV_COMPONENTS core imgproc imgcodecs calib3d video photo)
if(TARGET opencv_aruco)
  list(APPEND HANDEYE_OPENCV_COMPONENTS aruco)
endif()
string(REPLACE ";" " " HANDEYE_OPENCV_COMPONENTS "${HANDEYE_OPENCV_COMPONENTS}")
if(TARGET PkgConfig::APRILTAG)
  set(HANDEYE_USES_APRILTAG TRUE)
else()
  set(HANDEYE_USES_APRILTAG FALSE)
endif()
configure_package_config_file(
  "${PROJECT_SOURCE_DIR}/cmake/handeyeConfig.cmake.in"
  "${PROJECT_BINARY_DIR}/handeyeConfig.cmake"
  INSTALL_DESTINATION "${HANDEYE_INSTALL_CMAKEDIR}")
# 1.x releases keep the API of 1.0: a request for 1.0 accepts any 1.y.
write_basic_package_version_file(
  "${PROJECT_BINARY_DIR}/handeyeConfigVersion.cmake"
  VERSION "${PROJECT_VERSION}"
  COMPATIBILITY SameMajorVersion)
install(FILES "${PROJECT_BINARY_DIR}/handeyeConfig.cmake"
              "${PROJECT_BINARY_DIR}/handeyeConfigVersion.cmake"
        DESTINATION "${HANDEYE_INSTALL_CMAKEDIR}"
        COMPONENT handeye_development)
