# The floors of harness/: each folder stands on one floor and may include
# only folders on lower floors (and itself), so that the harness reads from
# the ground up and no two folders need each other. A folder not listed is
# an error: a new folder says where it stands.
#
# Included by harness/CMakeLists.txt, which checks the includes at every
# build in which a harness source changed (hb_add_harness_floor_check). Run
# as a script, it checks them once:
#   cmake -DHARNESS_DIR=<source>/harness -P cmake/harness_floors.cmake

if(CMAKE_SCRIPT_MODE_FILE STREQUAL CMAKE_CURRENT_LIST_FILE)
  cmake_minimum_required(VERSION 3.25)  # the project's policies (IN_LIST)
endif()

# Read it from the ground up: processes, input files and progress; traces
# and the closed-loop device; meshes, ground truth, replay; metrics and the
# stability verdict; scenarios and run folders; the run pipeline,
# comparison and sweep jobs; history; the drivers over the run request (a
# sweep's jobs, the stability searches); the command line.
set(HB_HARNESS_FLOOR_process 0)
set(HB_HARNESS_FLOOR_progress 0)
set(HB_HARNESS_FLOOR_plugins 0)
set(HB_HARNESS_FLOOR_trace 1)
set(HB_HARNESS_FLOOR_closed_loop 1)
set(HB_HARNESS_FLOOR_mesh_io 2)
set(HB_HARNESS_FLOOR_reference 2)
set(HB_HARNESS_FLOOR_replay 2)
set(HB_HARNESS_FLOOR_metrics 3)
set(HB_HARNESS_FLOOR_scenario 4)
set(HB_HARNESS_FLOOR_output 4)
set(HB_HARNESS_FLOOR_run 5)
set(HB_HARNESS_FLOOR_compare 5)
set(HB_HARNESS_FLOOR_sweep 5)
set(HB_HARNESS_FLOOR_history 6)
set(HB_HARNESS_FLOOR_drivers 7)
set(HB_HARNESS_FLOOR_cli 8)

# hb_check_harness_floors(DIR): stops with FATAL_ERROR naming every
# `#include "harness/<folder>/..."` in a source of DIR/<name>/ whose folder
# is not on a lower floor than <name>, and every folder without a floor.
function(hb_check_harness_floors dir)
  file(GLOB entries LIST_DIRECTORIES true RELATIVE ${dir} ${dir}/*)
  list(SORT entries)
  set(errors "")
  foreach(folder ${entries})
    if(NOT IS_DIRECTORY ${dir}/${folder})
      continue()
    endif()
    if(NOT DEFINED HB_HARNESS_FLOOR_${folder})
      string(APPEND errors "\n  harness/${folder}/ has no floor (cmake/harness_floors.cmake)")
      continue()
    endif()
    set(floor ${HB_HARNESS_FLOOR_${folder}})
    file(GLOB_RECURSE sources ${dir}/${folder}/*.h ${dir}/${folder}/*.cpp)
    list(SORT sources)
    foreach(source ${sources})
      file(STRINGS ${source} lines REGEX "^[ \t]*#[ \t]*include[ \t]*[\"<]harness/")
      foreach(line ${lines})
        string(REGEX MATCH "[\"<]harness/([^/\">]+)/" quoted "${line}")
        set(other ${CMAKE_MATCH_1})
        if(other STREQUAL folder)
          continue()
        endif()
        if(DEFINED HB_HARNESS_FLOOR_${other})
          if(HB_HARNESS_FLOOR_${other} LESS floor)
            continue()
          endif()
        endif()
        file(RELATIVE_PATH name ${dir}/.. ${source})
        string(APPEND errors "\n  ${name}: includes harness/${other}/ (floor "
               "${HB_HARNESS_FLOOR_${other}}) from ${folder}/ (floor ${floor}): a folder "
               "includes only lower floors")
      endforeach()
    endforeach()
  endforeach()
  if(errors)
    message(FATAL_ERROR "A harness/ folder includes one on its own floor or above "
                        "(cmake/harness_floors.cmake):${errors}")
  endif()
endfunction()

# hb_add_harness_floor_check(DIR): checks DIR's includes at every build in
# which a harness source changed, before the command line links.
function(hb_add_harness_floor_check dir)
  file(GLOB_RECURSE sources CONFIGURE_DEPENDS ${dir}/*/*.h ${dir}/*/*.cpp)
  set(stamp ${CMAKE_CURRENT_BINARY_DIR}/harness_floors.checked)
  add_custom_command(OUTPUT ${stamp}
    COMMAND ${CMAKE_COMMAND} -DHARNESS_DIR=${dir} -P ${CMAKE_CURRENT_FUNCTION_LIST_FILE}
    COMMAND ${CMAKE_COMMAND} -E touch ${stamp}
    DEPENDS ${sources} ${CMAKE_CURRENT_FUNCTION_LIST_FILE}
    COMMENT "Checking that each harness/ folder includes only lower floors"
    VERBATIM)
  add_custom_target(hb_harness_floors ALL DEPENDS ${stamp})
endfunction()

if(CMAKE_SCRIPT_MODE_FILE STREQUAL CMAKE_CURRENT_LIST_FILE)
  if(NOT HARNESS_DIR)
    message(FATAL_ERROR "usage: cmake -DHARNESS_DIR=<source>/harness -P ${CMAKE_CURRENT_LIST_FILE}")
  endif()
  hb_check_harness_floors(${HARNESS_DIR})
endif()
