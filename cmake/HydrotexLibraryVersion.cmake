# SPDX-License-Identifier: Zlib
# Gives a hydrotex library its file version and SONAME: libhydrotex_X.so.MAJOR.MINOR. Before 1.0
# a minor release may change the ABI, so the minor number is part of the SONAME.
function(hydrotex_set_library_version target)
  set_target_properties(${target} PROPERTIES
    VERSION "${PROJECT_VERSION}"
    SOVERSION "${PROJECT_VERSION_MAJOR}.${PROJECT_VERSION_MINOR}")
endfunction()
