# SPDX-License-Identifier: Zlib
# Makes a scratch root holding an installed hydrotex, then configures, builds and runs tests/package
# as a separate project against it: find_package(hydrotex CONFIG) must work from either
#   MODE=install  `cmake --install` into a prefix, or
#   MODE=deb      the Debian package `cpack -G DEB` makes, unpacked with dpkg-deb into a root
#                 (its control file must name Debian packages as dependencies, its libraries carry
#                 a SONAME, and its `hydrotex --version` prints the project's version).
set(work "${BUILD_DIR}/package-test-${MODE}")
set(consumer_build "${work}/consumer")
file(REMOVE_RECURSE "${work}")
file(MAKE_DIRECTORY "${work}")

function(run_or_fail what)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${what} failed (${rc}):\n${out}\n${err}")
  endif()
  set(output "${out}" PARENT_SCOPE)
endfunction()

if(MODE STREQUAL "install")
  set(prefix "${work}/prefix")
  run_or_fail("cmake --install" "${CMAKE_COMMAND}" --install "${BUILD_DIR}" --prefix "${prefix}")
elseif(MODE STREQUAL "deb")
  run_or_fail("cpack -G DEB" "${CPACK_COMMAND}" -G DEB -B "${work}/cpack" --config "${BUILD_DIR}/CPackConfig.cmake")
  file(GLOB deb "${work}/cpack/hydrotex_${VERSION}_*.deb")
  if(NOT deb)
    message(FATAL_ERROR "cpack made no hydrotex_${VERSION}_*.deb in ${work}/cpack")
  endif()
  run_or_fail("dpkg-deb -f" dpkg-deb -f "${deb}" Depends)
  # Run-time libraries by their Debian names (dpkg-shlibdeps), and the headers users compile with.
  foreach(package libassimp5 libeigen3-dev libstdc\\+\\+6)
    if(NOT output MATCHES "(^|, )${package}( |,|$)")
      message(FATAL_ERROR "the package's Depends lacks ${package}: ${output}")
    endif()
  endforeach()
  run_or_fail("dpkg-deb -x" dpkg-deb -x "${deb}" "${work}/root")
  set(prefix "${work}/root/usr")
  file(GLOB soname "${prefix}/lib*/libhydrotex_core.so.${VERSION_MAJOR_MINOR}")
  if(NOT soname)
    message(FATAL_ERROR "no libhydrotex_core.so.${VERSION_MAJOR_MINOR} (the SONAME) in the package")
  endif()
  run_or_fail("readelf -d" readelf -d "${soname}")
  if(NOT output MATCHES "SONAME[^\n]*libhydrotex_core\\.so\\.${VERSION_MAJOR_MINOR}\\]")
    message(FATAL_ERROR "libhydrotex_core's SONAME is not libhydrotex_core.so.${VERSION_MAJOR_MINOR}:\n${output}")
  endif()
  get_filename_component(libdir "${soname}" DIRECTORY)
  set(ENV{LD_LIBRARY_PATH} "${libdir}")
  if(EXISTS "${prefix}/bin/hydrotex")
    run_or_fail("hydrotex --version" "${prefix}/bin/hydrotex" --version)
    if(NOT output MATCHES "${VERSION}")
      message(FATAL_ERROR "the packaged hydrotex --version printed '${output}', not ${VERSION}")
    endif()
  endif()
else()
  message(FATAL_ERROR "MODE must be install or deb, not '${MODE}'")
endif()

run_or_fail("configuring the consumer project" "${CMAKE_COMMAND}" -S "${SOURCE_DIR}/tests/package"
            -B "${consumer_build}" "-DCMAKE_PREFIX_PATH=${prefix}" -DCMAKE_BUILD_TYPE=Release)
run_or_fail("building the consumer project" "${CMAKE_COMMAND}" --build "${consumer_build}")
run_or_fail("the consumer" "${consumer_build}/consumer")
message(STATUS "${output}")
