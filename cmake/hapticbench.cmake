# Helpers shared by every folder: one call adds a library, one call adds a test.

set(HAPTICBENCH_WARNINGS -Wall -Wextra -Wpedantic)
# Optimisation of test code (hb_test_folder); the libraries keep the build type's.
set(HB_TEST_OPTIMIZATION -O1)
# Test files compiled together in one unit (hb_test_folder).
set(HB_TEST_UNITY_BATCH 8)
# The quick sanitizer pass checks the code under test, which the libraries
# and the command line tool hold; the tests' own code (assertions, fixtures,
# the end-to-end tests that start the tool) goes uninstrumented: it was
# 60 % of a sanitized build's compile time. Its allocations still go
# through AddressSanitizer's allocator, so an overrun by library code into
# a test's buffer is still caught. Tests that start the tool find it, and
# whether it runs with AddressSanitizer, at run time
# (tests/support/cli_runner.h).
if(HAPTICBENCH_SANITIZE_SKIP_HEAVY)
  list(APPEND HB_TEST_OPTIMIZATION -fno-sanitize=all)
endif()
if(HAPTICBENCH_WERROR)
  list(APPEND HAPTICBENCH_WARNINGS -Werror)
endif()

# hb_library(NAME SOURCES ... DEPENDS ...): a static library for one source folder.
function(hb_library name)
  cmake_parse_arguments(ARG "POSITION_INDEPENDENT" "" "SOURCES;DEPENDS;PRIVATE_DEPENDS" ${ARGN})
  if(NOT ARG_SOURCES)  # a folder of headers only
    add_library(${name} INTERFACE)
    target_include_directories(${name} INTERFACE $<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}>
                                                 $<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}/include>)
    target_link_libraries(${name} INTERFACE ${ARG_DEPENDS})
    return()
  endif()
  add_library(${name} STATIC ${ARG_SOURCES})
  set_property(GLOBAL APPEND PROPERTY HB_LIBRARY_TARGETS ${name})
  # The public headers (include/hapticbench/) and, inside the build only,
  # the source tree.
  target_include_directories(${name} PUBLIC $<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}>
                                            $<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}/include>)
  target_compile_options(${name} PRIVATE ${HAPTICBENCH_WARNINGS})
  if(ARG_POSITION_INDEPENDENT)
    # Linked into plugin modules too (cmake/install.cmake). Calls inside the
    # library stay direct and inlinable as in the other libraries; the shared
    # precompiled header, built without -fPIC, would not apply.
    set_target_properties(${name} PROPERTIES POSITION_INDEPENDENT_CODE ON)
    target_compile_options(${name} PRIVATE -fno-semantic-interposition)
  else()
    hb_precompile(${name} library)
  endif()
  target_link_libraries(${name} PUBLIC ${ARG_DEPENDS} PRIVATE ${ARG_PRIVATE_DEPENDS})
endfunction()

# Precompiled headers: third-party headers that most units include
# (nlohmann/json takes 5 s to parse, Eigen 2 s, Catch2 2 s), parsed once for
# the whole build instead of once per unit. Two are built, each in its own
# object library, with the flags of the targets that reuse it: `library`
# (the build type's optimisation) and `test` (HB_TEST_OPTIMIZATION; Catch2
# too). A target built with other flags must not reuse one: g++ would reject
# it (-Winvalid-pch says so) and parse the headers itself.
# HAPTICBENCH_PCH=OFF compiles every unit on its own.
function(hb_add_precompiled_headers)
  if(NOT HAPTICBENCH_PCH)
    return()
  endif()
  set(common <Eigen/Core> <Eigen/Geometry> <nlohmann/json.hpp> <algorithm> <filesystem>
             <functional> <map> <memory> <optional> <string> <vector>)
  add_library(hb_pch_library OBJECT ${PROJECT_SOURCE_DIR}/cmake/precompiled_header.cpp)
  target_compile_options(hb_pch_library PRIVATE ${HAPTICBENCH_WARNINGS})
  target_link_libraries(hb_pch_library PRIVATE Eigen3::Eigen nlohmann_json::nlohmann_json)
  target_precompile_headers(hb_pch_library PRIVATE ${common})
  add_library(hb_pch_test OBJECT ${PROJECT_SOURCE_DIR}/cmake/precompiled_header.cpp)
  target_compile_options(hb_pch_test PRIVATE ${HAPTICBENCH_WARNINGS} ${HB_TEST_OPTIMIZATION})
  target_link_libraries(hb_pch_test PRIVATE Eigen3::Eigen nlohmann_json::nlohmann_json
                        Catch2::Catch2)
  target_precompile_headers(hb_pch_test PRIVATE <catch2/catch.hpp> ${common})
endfunction()

# hb_precompile(TARGET library|test): TARGET's units include that shared
# precompiled header first.
function(hb_precompile target kind)
  if(HAPTICBENCH_PCH)
    target_precompile_headers(${target} REUSE_FROM hb_pch_${kind})
  endif()
endfunction()

# hb_test_folder(TARGET SOURCES ... DEPENDS ...): one Catch2 executable for
# the *_test.cpp files of one test folder (a link per folder, not per file),
# registered with CTest case by case under each file's own name:
# "algorithms/ccd/mesh_ccd_test:<case>" (cmake/discover_folder_tests.cmake,
# after each link, from one listing of the executable).
function(hb_test_folder target)
  cmake_parse_arguments(ARG "" "" "SOURCES;DEPENDS" ${ARGN})
  add_executable(${target} ${ARG_SOURCES})
  set_property(GLOBAL APPEND PROPERTY HB_TEST_TARGETS ${target})
  # The files of one folder are compiled together, up to HB_TEST_UNITY_BATCH
  # per unit (a unity build): each test unit paid seconds for the same
  # headers and template instantiations, and the tests' compile time
  # halved. A test file's helpers in its anonymous namespace therefore share
  # one scope with the other files of its batch: give them names of their
  # own, or take shared ones from tests/support/.
  set_target_properties(${target} PROPERTIES UNITY_BUILD ON
                        UNITY_BUILD_BATCH_SIZE ${HB_TEST_UNITY_BATCH})
  # The tests' own code (assertions, fixtures, JSON) is compiled at -O1:
  # optimising it at -O3 took 80 % of a test unit's compile time and buys
  # nothing, since the code under test comes optimised from its libraries.
  target_compile_options(${target} PRIVATE ${HAPTICBENCH_WARNINGS} ${HB_TEST_OPTIMIZATION})
  target_link_libraries(${target} PRIVATE hb_test_main ${ARG_DEPENDS})
  target_compile_definitions(${target} PRIVATE
    HAPTICBENCH_SOURCE_DIR="${PROJECT_SOURCE_DIR}"
    HAPTICBENCH_BIN="$<TARGET_FILE:hapticbench>")
  add_dependencies(${target} hapticbench)
  hb_precompile(${target} test)
  set(files_config "")
  set(stems "")
  foreach(source ${ARG_SOURCES})
    file(RELATIVE_PATH rel ${PROJECT_SOURCE_DIR}/tests ${source})
    string(REGEX REPLACE "\\.cpp$" "" rel "${rel}")
    get_filename_component(stem ${source} NAME_WE)
    list(APPEND stems ${stem})
    # A *_serial_test.cpp measures time or keeps every core busy: it runs
    # with no other test beside it. HB_TEST_PROPERTIES_<stem>, set by the
    # caller, adds CTest properties to every case of one file (e.g. a
    # fixture it needs).
    set(properties ${HB_TEST_PROPERTIES_${stem}})
    if(rel MATCHES "_serial_test$")
      list(APPEND properties RUN_SERIAL TRUE)
    endif()
    string(APPEND files_config "set(hb_prefix_${stem} [==[${rel}:]==])\n"
                               "set(hb_properties_${stem} ${properties})\n")
  endforeach()
  string(PREPEND files_config "set(hb_stems ${stems})\n")
  set(files_file "${CMAKE_CURRENT_BINARY_DIR}/${target}_files.cmake")
  set(ctest_file "${CMAKE_CURRENT_BINARY_DIR}/${target}_tests.cmake")
  set(include_file "${CMAKE_CURRENT_BINARY_DIR}/${target}_include.cmake")
  file(WRITE "${files_file}" "${files_config}")
  add_custom_command(TARGET ${target} POST_BUILD
    BYPRODUCTS "${ctest_file}"
    COMMAND "${CMAKE_COMMAND}" -D "TEST_EXECUTABLE=$<TARGET_FILE:${target}>"
            -D "FILES_CONFIG=${files_file}" -D "WORKING_DIR=${CMAKE_CURRENT_BINARY_DIR}"
            -D "CTEST_FILE=${ctest_file}"
            -P "${PROJECT_SOURCE_DIR}/cmake/discover_folder_tests.cmake"
    VERBATIM)
  file(WRITE "${include_file}"
    "if(EXISTS \"${ctest_file}\")\n"
    "  include(\"${ctest_file}\")\n"
    "else()\n"
    "  add_test(${target}_NOT_BUILT ${target}_NOT_BUILT)\n"
    "endif()\n")
  set_property(DIRECTORY APPEND PROPERTY TEST_INCLUDE_FILES "${include_file}")
endfunction()

# hb_builder_sources_hash(SOURCE FILES f...): compiles SOURCE with
# HB_BUILDER_SOURCES_HASH, a hash of the files that build a structure kept in
# a disk cache, which the cache key includes: when the code that builds it
# changes, old cache files stop matching instead of serving stale results.
# CMake re-runs when one of the files changes.
function(hb_builder_sources_hash source)
  cmake_parse_arguments(ARG "" "" "FILES" ${ARGN})
  set(text "")
  foreach(file ${ARG_FILES})
    file(SHA256 ${file} file_hash)
    string(APPEND text "${file_hash}")
  endforeach()
  string(SHA256 all "${text}")
  string(SUBSTRING "${all}" 0 16 all)
  set_property(SOURCE ${source} APPEND PROPERTY COMPILE_DEFINITIONS
    "HB_BUILDER_SOURCES_HASH=\"${all}\"")
  set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS ${ARG_FILES})
endfunction()

# hb_heavy_sources(FILES...): translation units that mostly instantiate a
# heavy library (CGAL, OpenVDB, Catch2's runner). With HAPTICBENCH_SANITIZE_SKIP_HEAVY (the
# quick sanitizer pass, scripts/sanitize --quick) they are compiled without
# sanitizers and without debug information: one such unit took over six
# minutes and 3.6 GB to compile sanitized with -g. Our code in every other
# unit is still checked.
# They never use a target's precompiled headers, whose flags may differ.
function(hb_heavy_sources)
  set_property(GLOBAL APPEND PROPERTY HB_HEAVY_SOURCES ${ARGN})
  # Nor are they compiled together with other test files: each takes as long
  # as a whole batch and runs beside the others on the second core.
  set_source_files_properties(${ARGN} PROPERTIES SKIP_PRECOMPILE_HEADERS ON
                                                 SKIP_UNITY_BUILD_INCLUSION ON)
  if(HAPTICBENCH_SANITIZE_SKIP_HEAVY)
    set_source_files_properties(${ARGN} PROPERTIES COMPILE_OPTIONS "-fno-sanitize=all;-g0")
  endif()
endfunction()

# hb_release_batches(TARGET SOURCES SOURCE_DIR RELEASE_TARGET_DIR OBJECTS_VAR
# FILES_VAR): the objects of the Release build's batches of TARGET's test
# files (hb_test_folder's unity build) that hold exactly the files this
# build would put in them, and those files. CMake fills batches in source
# order with the files not excluded from them; a batch the Release build
# made differently (a file added or removed since) is compiled here.
function(hb_release_batches target sources source_dir release_dir objects_var files_var)
  get_target_property(size ${target} UNITY_BUILD_BATCH_SIZE)
  set(batch "")
  set(batches "")
  set(count 0)
  foreach(source ${sources})
    cmake_path(ABSOLUTE_PATH source BASE_DIRECTORY ${source_dir} OUTPUT_VARIABLE path)
    get_source_file_property(skip ${path} TARGET_DIRECTORY ${target} SKIP_UNITY_BUILD_INCLUSION)
    if(NOT path MATCHES "\\.cpp$" OR skip)
      continue()
    endif()
    list(APPEND batch ${path})
    math(EXPR count "${count} + 1")
    if(count EQUAL size)
      string(REPLACE ";" "|" joined "${batch}")
      list(APPEND batches "${joined}")
      set(batch "")
      set(count 0)
    endif()
  endforeach()
  if(batch)
    string(REPLACE ";" "|" joined "${batch}")
    list(APPEND batches "${joined}")
  endif()
  set(objects "")
  set(files "")
  set(index 0)
  foreach(joined ${batches})
    string(REPLACE "|" ";" batch "${joined}")
    set(unit "${release_dir}/Unity/unity_${index}_cxx.cxx")
    math(EXPR index "${index} + 1")
    if(NOT EXISTS "${unit}" OR NOT EXISTS "${unit}.o")
      continue()
    endif()
    file(STRINGS "${unit}" lines REGEX "^#include \"")
    set(included "")
    foreach(line ${lines})
      string(REGEX REPLACE "^#include \"(.*)\"$" "\\1" included_path "${line}")
      list(APPEND included "${included_path}")
    endforeach()
    if(included STREQUAL batch)
      list(APPEND objects "${unit}.o")
      list(APPEND files ${batch})
    endif()
  endforeach()
  set(${objects_var} ${objects} PARENT_SCOPE)
  set(${files_var} ${files} PARENT_SCOPE)
endfunction()

# hb_reuse_release_objects(): in a quick sanitizer build (scripts/sanitize
# --quick) given HAPTICBENCH_REUSE_OBJECTS, a Release build of the same tree,
# the units this build leaves uninstrumented are linked from that build's
# objects instead of compiled a second time: the heavy units
# (hb_heavy_sources), the tests' own code (a test that starts the command
# line tool finds the one of the build it is linked into,
# tests/support/cli_runner.h), and the harness libraries other than
# HB_QUICK_SANITIZE_HARNESS. The quick pass checks the algorithms and the
# code that reads the user's files or drives the haptic loop; the rest of
# the harness (run folders, reports' inputs, sweeps, comparisons, the
# references, the command line) is checked by the full pass
# (scripts/sanitize without --quick). Only objects that exist are taken
# (the script builds the Release tree first, so they are current); the rest
# is compiled here. Called once, after every target is defined.
set(HB_QUICK_SANITIZE_HARNESS hb_json_fields hb_scenario hb_mesh_io hb_trace hb_replay
    hb_metrics hb_metric_table)
function(hb_reuse_release_objects)
  if(NOT HAPTICBENCH_SANITIZE_SKIP_HEAVY OR NOT HAPTICBENCH_REUSE_OBJECTS)
    return()
  endif()
  set(release ${HAPTICBENCH_REUSE_OBJECTS})
  # Anything else than a Release build of this tree: everything is compiled here.
  if(NOT EXISTS "${release}/CMakeCache.txt")
    message(WARNING "HAPTICBENCH_REUSE_OBJECTS: ${release} holds no CMake build; compiling all")
    return()
  endif()
  file(STRINGS "${release}/CMakeCache.txt" home REGEX "^CMAKE_HOME_DIRECTORY:")
  file(STRINGS "${release}/CMakeCache.txt" type REGEX "^CMAKE_BUILD_TYPE:")
  string(REGEX REPLACE "^[^=]*=" "" home "${home}")
  file(REAL_PATH "${home}" home_real)
  file(REAL_PATH "${PROJECT_SOURCE_DIR}" source_real)
  if(NOT home_real STREQUAL source_real OR NOT type STREQUAL "CMAKE_BUILD_TYPE:STRING=Release")
    message(WARNING "HAPTICBENCH_REUSE_OBJECTS: ${release} is not a Release build of "
                    "${PROJECT_SOURCE_DIR} (${home}, ${type}); compiling all")
    return()
  endif()
  get_property(heavy GLOBAL PROPERTY HB_HEAVY_SOURCES)
  get_property(libraries GLOBAL PROPERTY HB_LIBRARY_TARGETS)
  get_property(tests GLOBAL PROPERTY HB_TEST_TARGETS)
  set(reused 0)
  set(compiled 0)
  foreach(target ${libraries} ${tests} hb_test_main)
    if(NOT TARGET ${target})
      continue()
    endif()
    get_target_property(sources ${target} SOURCES)
    get_target_property(source_dir ${target} SOURCE_DIR)
    get_target_property(binary_dir ${target} BINARY_DIR)
    file(RELATIVE_PATH binary_rel ${PROJECT_BINARY_DIR} ${binary_dir})
    file(RELATIVE_PATH source_rel_dir ${PROJECT_SOURCE_DIR} ${source_dir})
    set(uninstrumented_library FALSE)
    if(target IN_LIST libraries AND source_rel_dir MATCHES "^harness/" AND
       NOT target IN_LIST HB_QUICK_SANITIZE_HARNESS)
      set(uninstrumented_library TRUE)
    endif()
    set(kept "")
    set(batched "")
    get_target_property(unity ${target} UNITY_BUILD)
    if(unity AND NOT target IN_LIST libraries)
      hb_release_batches(${target} "${sources}" "${source_dir}"
                         "${release}/${binary_rel}/CMakeFiles/${target}.dir" objects batched)
      list(APPEND kept ${objects})
      list(LENGTH objects count)
      math(EXPR reused "${reused} + ${count}")
    endif()
    foreach(source ${sources})
      cmake_path(ABSOLUTE_PATH source BASE_DIRECTORY ${source_dir} OUTPUT_VARIABLE path)
      if(path IN_LIST batched)
        continue()
      endif()
      set(take FALSE)
      if(path MATCHES "\\.cpp$" AND (path IN_LIST heavy OR NOT target IN_LIST libraries OR
                                       uninstrumented_library))
        set(take TRUE)
      endif()
      if(take)
        file(RELATIVE_PATH source_rel ${source_dir} ${path})
        set(object "${release}/${binary_rel}/CMakeFiles/${target}.dir/${source_rel}.o")
        cmake_path(NORMAL_PATH object)
        if(EXISTS "${object}")
          list(APPEND kept "${object}")
          math(EXPR reused "${reused} + 1")
          continue()
        endif()
        math(EXPR compiled "${compiled} + 1")
      endif()
      list(APPEND kept "${source}")
    endforeach()
    set_property(TARGET ${target} PROPERTY SOURCES ${kept})
    # A target left with objects alone names its language itself.
    set_property(TARGET ${target} PROPERTY LINKER_LANGUAGE CXX)
  endforeach()
  message(STATUS "Linking ${reused} uninstrumented objects of ${release}; "
                 "${compiled} not found there are compiled")
endfunction()
