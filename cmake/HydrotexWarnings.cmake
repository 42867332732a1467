# SPDX-License-Identifier: Zlib
# Warnings for our own targets only (not for users' code that includes our headers).
function(hydrotex_set_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Wshadow -Wconversion
    -Wno-sign-conversion -Wnon-virtual-dtor)
endfunction()
