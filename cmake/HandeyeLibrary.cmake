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
