# SPDX-License-Identifier: Zlib
# Runs hydrotex_demo --window and checks what it did.
#   MODE=no_display: DISPLAY and WAYLAND_DISPLAY unset; it must exit 2 with a one-line message
#                    naming the display, and write nothing under OUT_DIR.
#   MODE=xvfb:       under xvfb-run (24-bit screen) with --window-check (the window's picture is read
#                    back and compared with each frame); it must exit 0 and write every frame and
#                    the contact sheet.
# Usage: cmake -DMODE=... -DDEMO=<hydrotex_demo> -DOUT_DIR=<dir> [-DXVFB_RUN=<xvfb-run>] -P CheckWindowRun.cmake
file(REMOVE_RECURSE "${OUT_DIR}")
set(run "${DEMO}" ball --frames 3 --size 160x90 --no-video --out "${OUT_DIR}")
if(MODE STREQUAL "no_display")
  execute_process(COMMAND "${CMAKE_COMMAND}" -E env --unset=DISPLAY --unset=WAYLAND_DISPLAY ${run} --window
                  RESULT_VARIABLE result OUTPUT_VARIABLE output ERROR_VARIABLE errors)
  if(NOT result EQUAL 2)
    message(FATAL_ERROR "expected exit 2 without a display, got ${result}:\n${output}\n${errors}")
  endif()
  string(STRIP "${errors}" message)
  if(message MATCHES "\n" OR NOT message MATCHES "display")
    message(FATAL_ERROR "expected one line naming the display, got:\n${errors}")
  endif()
  if(EXISTS "${OUT_DIR}")
    message(FATAL_ERROR "${OUT_DIR} was written although the window could not open")
  endif()
  message(STATUS "refused as expected: ${message}")
elseif(MODE STREQUAL "xvfb")
  # xvfb-run's default screen is 8 bits deep: no GL visual with 8-bit channels to compare with.
  execute_process(COMMAND "${XVFB_RUN}" -a -s "-screen 0 640x480x24" ${run} --window-check
                  RESULT_VARIABLE result OUTPUT_VARIABLE output ERROR_VARIABLE errors)
  if(NOT result EQUAL 0)
    message(FATAL_ERROR "--window-check under xvfb-run failed (${result}):\n${output}\n${errors}")
  endif()
  foreach(file frames/frame_0000.png frames/frame_0001.png frames/frame_0002.png ball_contact.png)
    if(NOT EXISTS "${OUT_DIR}/${file}")
      message(FATAL_ERROR "${OUT_DIR}/${file} was not written:\n${output}\n${errors}")
    endif()
  endforeach()
  message(STATUS "window showed 3 frames as written:\n${output}")
else()
  message(FATAL_ERROR "unknown MODE '${MODE}'")
endif()
