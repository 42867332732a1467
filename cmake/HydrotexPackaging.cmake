# SPDX-License-Identifier: Zlib
# CPack: `cpack -G DEB` (run in the build folder) makes hydrotex_<version>_<arch>.deb holding what
# `cmake --install` installs: the shared libraries (with their SONAMEs), the public headers, the
# CMake package files for find_package(hydrotex) and the `hydrotex` tool, under /usr.
# Its dependencies are Debian's package names: the run-time libraries found by dpkg-shlibdeps from
# what the binaries link (libassimp5, libbullet3.24, libepoxy0, ...), plus the development packages
# that find_package(hydrotex) looks for (Eigen's headers are part of hydrotex::core's interface,
# Bullet's of hydrotex::bullet's). tests/package/RunPackageTest.cmake installs it into a scratch
# root and builds a consumer against it.
set(CPACK_PACKAGE_NAME hydrotex)
set(CPACK_PACKAGE_VERSION "${PROJECT_VERSION}")
set(CPACK_PACKAGE_VENDOR "the hydrotex authors")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY
    "Rigid and soft bodies that float, flood and get wet, computed in texture space (library, Bullet plugin, tool)")
set(CPACK_RESOURCE_FILE_LICENSE "${PROJECT_SOURCE_DIR}/LICENSE")
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_GENERATOR DEB)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_MAINTAINER "the hydrotex authors")
set(CPACK_DEBIAN_PACKAGE_SECTION libdevel)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
# Our own libraries are in the package: dpkg-shlibdeps looks for them in the staged library folder.
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS_PRIVATE_DIRS "${CMAKE_INSTALL_FULL_LIBDIR}")
set(_hydrotex_dev_depends "libeigen3-dev")
if(TARGET hydrotex_bullet)
  string(APPEND _hydrotex_dev_depends ", libbullet-dev")
endif()
set(CPACK_DEBIAN_PACKAGE_DEPENDS "${_hydrotex_dev_depends}")
include(CPack)
