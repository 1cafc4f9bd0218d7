# The interactive window under a virtual X display (DESIGN §7): bake a tiny Cornell box,
# run `walkthrough --interactive` for a scripted number of frames (VLF_INTERACTIVE_FRAMES)
# and check that it exits 0, renders both progressive paths (texture while moving, raytrace
# once still; VLF §6.3) and leaves a screenshot that is not blank.
# Variables: PROPAGATE, WALKTHROUGH, PNG_STATS, XVFB_RUN, SOURCE_DIR, WORK_DIR.
file(REMOVE_RECURSE "${WORK_DIR}")
file(MAKE_DIRECTORY "${WORK_DIR}")

function(run_or_fail what)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${what}: exit ${rc}: ${ARGN}\nstdout: ${out}\nstderr: ${err}")
  endif()
  set(LAST_OUT "${out}" PARENT_SCOPE)
endfunction()

set(BAKE "${WORK_DIR}/t.vlf")
set(SHOT "${WORK_DIR}/shot.png")
run_or_fail("propagate" ${PROPAGATE} "${SOURCE_DIR}/scenes/cornell.json" -o "${BAKE}"
            -l 33 -N 32 -m 8 -c 2 -q)

set(ENV{VLF_INTERACTIVE_FRAMES} 12)
set(ENV{VLF_INTERACTIVE_SCREENSHOT} "${SHOT}")
run_or_fail("walkthrough --interactive" ${XVFB_RUN} -a -s "-screen 0 640x480x24"
            ${WALKTHROUGH} "${BAKE}" --interactive --size 320x240)
message(STATUS "${LAST_OUT}")
# The summary line: "interactive: frames=12 size=320x240 renders: texture=6 (..) raytrace=1 (..) fps=.."
foreach(expect "frames=12" "size=320x240" "texture=[1-9]" "raytrace=[1-9]")
  if(NOT LAST_OUT MATCHES "${expect}")
    message(FATAL_ERROR "walkthrough summary lacks '${expect}': ${LAST_OUT}")
  endif()
endforeach()

if(NOT EXISTS "${SHOT}")
  message(FATAL_ERROR "no screenshot at ${SHOT}")
endif()
run_or_fail("png_stats" ${PNG_STATS} "${SHOT}")
message(STATUS "screenshot: ${LAST_OUT}")
if(NOT LAST_OUT MATCHES "nonblack=([0-9.]+) colours=([0-9]+) size=([0-9]+)x([0-9]+)")
  message(FATAL_ERROR "png_stats output not understood: ${LAST_OUT}")
endif()
set(nonblack ${CMAKE_MATCH_1})
set(colours ${CMAKE_MATCH_2})
if(NOT CMAKE_MATCH_3 EQUAL 320 OR NOT CMAKE_MATCH_4 EQUAL 240)
  message(FATAL_ERROR "screenshot is ${CMAKE_MATCH_3}x${CMAKE_MATCH_4}, expected 320x240")
endif()
if(NOT nonblack GREATER 0.2)  # if() compares numbers as doubles
  message(FATAL_ERROR "screenshot is mostly black: ${nonblack} of the pixels are non-black (need > 0.2)")
endif()
if(NOT colours GREATER 50)
  message(FATAL_ERROR "screenshot has only ${colours} distinct colours (need > 50)")
endif()
