# SPDX-License-Identifier: Zlib
# Every dependency comes from Debian's packages (scripts/install-deps.sh); nothing is downloaded.
find_package(Eigen3 3.3 REQUIRED CONFIG)
find_package(assimp REQUIRED CONFIG)
find_package(PkgConfig REQUIRED)
pkg_check_modules(STB REQUIRED IMPORTED_TARGET stb)
# oneTBB (libtbb-dev): the threads of the Bullet plugin's controller (plugin/src/BodyThreads.cpp).
if(HYDROTEX_BUILD_PLUGIN)
  find_package(TBB CONFIG REQUIRED COMPONENTS tbb)
endif()
