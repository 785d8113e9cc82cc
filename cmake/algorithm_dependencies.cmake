# Which folders of algorithms/ each folder may depend on, and the checks
# that hold them to it. An algorithm's folder (god_object/,
# constrained_dynamics/, ...) may include and link only the shared folders,
# core/, proxy/, ccd/ and contact/, and itself: never another algorithm's
# folder, harness/ or the registry. The shared folders are layered: core/
# depends on nothing, proxy/ and ccd/ on core/, contact/ on core/ and ccd/.
# Folder algorithms/<name>/ builds the library hb_<name>.
#
# Included by algorithms/CMakeLists.txt, which checks the libraries' links
# at configure time (hb_check_algorithm_links) and the includes at every
# build (hb_add_algorithm_include_check). Run as a script, it checks the
# includes:
#   cmake -DALGORITHMS_DIR=<source>/algorithms -P cmake/algorithm_dependencies.cmake

if(CMAKE_SCRIPT_MODE_FILE STREQUAL CMAKE_CURRENT_LIST_FILE)
  cmake_minimum_required(VERSION 3.25)  # the project's policies (IN_LIST)
endif()

set(HB_SHARED_ALGORITHM_FOLDERS core proxy ccd contact)
set(HB_ALGORITHM_FOLDER_DEPENDS_core "")
set(HB_ALGORITHM_FOLDER_DEPENDS_proxy core)
set(HB_ALGORITHM_FOLDER_DEPENDS_ccd core)
set(HB_ALGORITHM_FOLDER_DEPENDS_contact core ccd)

# hb_allowed_algorithm_folders(OUT FOLDER): the folders FOLDER may depend on, itself included.
function(hb_allowed_algorithm_folders out folder)
  if(folder IN_LIST HB_SHARED_ALGORITHM_FOLDERS)
    set(allowed ${HB_ALGORITHM_FOLDER_DEPENDS_${folder}})
  else()
    set(allowed ${HB_SHARED_ALGORITHM_FOLDERS})
  endif()
  list(APPEND allowed ${folder})
  set(${out} ${allowed} PARENT_SCOPE)
endfunction()

# hb_algorithm_folders(OUT DIR): the folders of DIR (algorithms/).
function(hb_algorithm_folders out dir)
  file(GLOB entries LIST_DIRECTORIES true RELATIVE ${dir} ${dir}/*)
  set(folders "")
  foreach(entry ${entries})
    if(IS_DIRECTORY ${dir}/${entry})
      list(APPEND folders ${entry})
    endif()
  endforeach()
  list(SORT folders)
  set(${out} ${folders} PARENT_SCOPE)
endfunction()

# hb_check_algorithm_includes(DIR): stops with FATAL_ERROR naming every
# `#include "algorithms/<folder>/..."` (or of harness/, or of a file at the
# top of algorithms/) in a source of DIR/<name>/ that <name> may not depend on.
function(hb_check_algorithm_includes dir)
  hb_algorithm_folders(folders ${dir})
  set(errors "")
  foreach(folder ${folders})
    hb_allowed_algorithm_folders(allowed ${folder})
    file(GLOB_RECURSE sources ${dir}/${folder}/*.h ${dir}/${folder}/*.cpp)
    list(SORT sources)
    foreach(source ${sources})
      file(STRINGS ${source} lines
           REGEX "^[ \t]*#[ \t]*include[ \t]*[\"<](algorithms|harness)/")
      foreach(line ${lines})
        string(REGEX MATCH "[\"<]([^\">]+)[\">]" quoted "${line}")
        set(path ${CMAKE_MATCH_1})
        if(path MATCHES "^algorithms/([^/]+)/")
          if(CMAKE_MATCH_1 IN_LIST allowed)
            continue()
          endif()
        endif()
        file(RELATIVE_PATH name ${dir}/.. ${source})
        list(JOIN allowed ", " may)
        string(APPEND errors "\n  ${name}: #include \"${path}\" (${folder}/ may include ${may})")
      endforeach()
    endforeach()
  endforeach()
  if(errors)
    message(FATAL_ERROR "An algorithms/ folder includes one it may not depend on "
                        "(cmake/algorithm_dependencies.cmake):${errors}")
  endif()
endfunction()

# hb_check_algorithm_links(DIR): stops with FATAL_ERROR when the library of a
# folder of DIR links a project library (hb_*) of a folder it may not depend
# on (another algorithm's, harness/'s, the registry). Call after every
# folder's library is declared.
function(hb_check_algorithm_links dir)
  hb_algorithm_folders(folders ${dir})
  set(errors "")
  foreach(folder ${folders})
    if(NOT TARGET hb_${folder})
      string(APPEND errors "\n  algorithms/${folder}/ declares no library hb_${folder}")
      continue()
    endif()
    hb_allowed_algorithm_folders(allowed ${folder})
    get_target_property(type hb_${folder} TYPE)
    if(type STREQUAL "INTERFACE_LIBRARY")
      get_target_property(links hb_${folder} INTERFACE_LINK_LIBRARIES)
    else()
      get_target_property(links hb_${folder} LINK_LIBRARIES)
    endif()
    foreach(link ${links})
      if(link MATCHES "^hb_(.+)$")
        if(NOT CMAKE_MATCH_1 IN_LIST allowed)
          list(JOIN allowed ", " may)
          string(APPEND errors "\n  hb_${folder} links ${link} (${folder}/ may link ${may})")
        endif()
      endif()
    endforeach()
  endforeach()
  if(errors)
    message(FATAL_ERROR "An algorithms/ library links one its folder may not depend on "
                        "(cmake/algorithm_dependencies.cmake):${errors}")
  endif()
endfunction()

# hb_add_algorithm_include_check(DIR): checks the includes of DIR's folders
# at every build in which one of their sources changed, before any of
# their libraries compiles (the build fails on a forbidden include).
function(hb_add_algorithm_include_check dir)
  hb_algorithm_folders(folders ${dir})
  file(GLOB_RECURSE sources CONFIGURE_DEPENDS ${dir}/*/*.h ${dir}/*/*.cpp)
  set(stamp ${CMAKE_CURRENT_BINARY_DIR}/algorithm_includes.checked)
  add_custom_command(OUTPUT ${stamp}
    COMMAND ${CMAKE_COMMAND} -DALGORITHMS_DIR=${dir} -P ${CMAKE_CURRENT_FUNCTION_LIST_FILE}
    COMMAND ${CMAKE_COMMAND} -E touch ${stamp}
    DEPENDS ${sources} ${CMAKE_CURRENT_FUNCTION_LIST_FILE}
    COMMENT "Checking that no algorithms/ folder includes another algorithm's folder"
    VERBATIM)
  add_custom_target(hb_algorithm_includes DEPENDS ${stamp})
  foreach(folder ${folders})
    if(TARGET hb_${folder})
      add_dependencies(hb_${folder} hb_algorithm_includes)
    endif()
  endforeach()
endfunction()

if(CMAKE_SCRIPT_MODE_FILE STREQUAL CMAKE_CURRENT_LIST_FILE)
  if(NOT ALGORITHMS_DIR)
    message(FATAL_ERROR "usage: cmake -DALGORITHMS_DIR=<source>/algorithms -P ${CMAKE_CURRENT_LIST_FILE}")
  endif()
  hb_check_algorithm_includes(${ALGORITHMS_DIR})
endif()
