# SPDX-License-Identifier: Zlib
# Every source file states its licence in one SPDX line near its top (LICENSE: zlib). Lists the
# files that do not, and fails.
file(GLOB_RECURSE sources RELATIVE "${SOURCE_DIR}"
     "${SOURCE_DIR}/core/*" "${SOURCE_DIR}/gpu/*" "${SOURCE_DIR}/plugin/*" "${SOURCE_DIR}/demos/*"
     "${SOURCE_DIR}/tests/*" "${SOURCE_DIR}/data/*" "${SOURCE_DIR}/fuzz/*" "${SOURCE_DIR}/cmake/*"
     "${SOURCE_DIR}/scripts/*")
set(missing "")
foreach(source ${sources})
  if(NOT source MATCHES "(\\.(cpp|hpp|h|comp|glsl|cmake|in|sh)|CMakeLists\\.txt)$")
    continue()
  endif()
  file(READ "${SOURCE_DIR}/${source}" head LIMIT 400)
  if(NOT head MATCHES "SPDX-License-Identifier: Zlib")
    list(APPEND missing "${source}")
  endif()
endforeach()
if(missing)
  list(JOIN missing "\n  " listed)
  message(FATAL_ERROR "no 'SPDX-License-Identifier: Zlib' line near the top of:\n  ${listed}")
endif()
