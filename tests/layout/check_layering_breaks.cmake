# Runs check_layering.cmake on copies of the core, each with one rule broken, and fails if
# the check passes any of them.
set(breaks
  "src/map/ndt_map.cpp|#include \"insertion/scan_updater.h\"|a folder includes a later one"
  "include/ndtom/map/ndt_map.h|#include \"map/map_block.h\"|a public header includes a private one"
  "include/ndtom/map/ndt_map.h|#include \"ndtom_internal/crc32.h\"|a public header includes an internal one"
  "src/insertion/free_rays.cpp|#include \"../map/map_block.h\"|an include through ../"
  "src/registration/registration.cpp|#include \"scan_levels.h\"|an include without its folder"
  "src/map/gaussian.cpp|#include <mrpt/core/exceptions.h>|MRPT in the core")
foreach(entry IN LISTS breaks)
  string(REPLACE "|" ";" parts "${entry}")
  list(GET parts 0 file)
  list(GET parts 1 line)
  list(GET parts 2 what)
  file(REMOVE_RECURSE ${SCRATCH})
  file(COPY ${CORE}/ DESTINATION ${SCRATCH})
  file(READ ${SCRATCH}/${file} text)
  file(WRITE ${SCRATCH}/${file} "${line}\n${text}")
  execute_process(COMMAND ${CMAKE_COMMAND} -DCORE=${SCRATCH} "-DFOLDERS=${FOLDERS}" -P ${CHECK}
                  RESULT_VARIABLE rc OUTPUT_QUIET ERROR_QUIET)
  if(rc EQUAL 0)
    message(FATAL_ERROR "check_layering.cmake passed a core with ${what} (${file})")
  endif()
endforeach()
file(REMOVE_RECURSE ${SCRATCH})
# ... and passes the core as it is.
execute_process(COMMAND ${CMAKE_COMMAND} -DCORE=${CORE} "-DFOLDERS=${FOLDERS}" -P ${CHECK}
                RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "check_layering.cmake fails on the core as it is")
endif()
