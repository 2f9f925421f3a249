# SPDX-License-Identifier: GPL-2.0-or-later
# Properties every handeye library shares: exported as handeye::<name>, file
# libhandeye_<name>, and versioned so that an installed program keeps loading
# the 1.x library it was linked against (SONAME libhandeye_<name>.so.1).
function(handeye_library_properties target export_name)
  set_target_properties(${target} PROPERTIES
    EXPORT_NAME ${export_name}
    VERSION ${PROJECT_VERSION}
    SOVERSION ${PROJECT_VERSION_MAJOR})
endfunction()

# A handeye library from the folder that calls it: its src/*.cc, public
# headers under include/ (installed as they are), exported as
# handeye::<export_name> with the properties above.
function(handeye_add_library target export_name)
  file(GLOB sources CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/src/*.cc)
  add_library(${target} ${sources})
  add_library(handeye::${export_name} ALIAS ${target})
  handeye_library_properties(${target} ${export_name})
  target_include_directories(${target} PUBLIC
    $<BUILD_INTERFACE:${CMAKE_CURRENT_SOURCE_DIR}/include>
    $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
endfunction()
