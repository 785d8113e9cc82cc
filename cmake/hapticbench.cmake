# Helpers shared by every folder: one call adds a library, one call adds a test.

set(HAPTICBENCH_WARNINGS -Wall -Wextra -Wpedantic)
if(HAPTICBENCH_WERROR)
  list(APPEND HAPTICBENCH_WARNINGS -Werror)
endif()

# hb_library(NAME SOURCES ... DEPENDS ...): a static library for one source folder.
function(hb_library name)
  cmake_parse_arguments(ARG "" "" "SOURCES;DEPENDS;PRIVATE_DEPENDS" ${ARGN})
  if(NOT ARG_SOURCES)  # a folder of headers only
    add_library(${name} INTERFACE)
    target_include_directories(${name} INTERFACE ${PROJECT_SOURCE_DIR})
    target_link_libraries(${name} INTERFACE ${ARG_DEPENDS})
    return()
  endif()
  add_library(${name} STATIC ${ARG_SOURCES})
  target_include_directories(${name} PUBLIC ${PROJECT_SOURCE_DIR})
  target_compile_options(${name} PRIVATE ${HAPTICBENCH_WARNINGS})
  target_link_libraries(${name} PUBLIC ${ARG_DEPENDS} PRIVATE ${ARG_PRIVATE_DEPENDS})
endfunction()

# hb_test(SOURCE DEPENDS ...): one Catch2 executable per test source file,
# named after its path under tests/, registered with CTest case by case.
function(hb_test source)
  cmake_parse_arguments(ARG "" "" "DEPENDS" ${ARGN})
  file(RELATIVE_PATH rel ${PROJECT_SOURCE_DIR}/tests ${source})
  string(REGEX REPLACE "\\.cpp$" "" rel "${rel}")
  string(REPLACE "/" "_" target "test_${rel}")
  add_executable(${target} ${source})
  target_compile_options(${target} PRIVATE ${HAPTICBENCH_WARNINGS})
  target_link_libraries(${target} PRIVATE hb_test_main ${ARG_DEPENDS})
  target_compile_definitions(${target} PRIVATE
    HAPTICBENCH_SOURCE_DIR="${PROJECT_SOURCE_DIR}"
    HAPTICBENCH_SHARED_DIR="${PROJECT_SOURCE_DIR}/../shared"
    HAPTICBENCH_BIN="$<TARGET_FILE:hapticbench>")
  add_dependencies(${target} hapticbench)
  # A *_serial_test.cpp measures time or keeps every core busy: it runs with
  # no other test beside it. --warn NoTests: a test whose name the filter
  # does not match (a ';' in a TEST_CASE name splits it into two CTest
  # tests) fails instead of passing without running anything.
  if(rel MATCHES "_serial_test$")
    catch_discover_tests(${target} TEST_PREFIX "${rel}: " EXTRA_ARGS --warn NoTests
                         PROPERTIES RUN_SERIAL TRUE)
  else()
    catch_discover_tests(${target} TEST_PREFIX "${rel}: " EXTRA_ARGS --warn NoTests)
  endif()
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
# heavy library (CGAL, OpenVDB). With HAPTICBENCH_SANITIZE_SKIP_HEAVY (the
# quick sanitizer pass, scripts/sanitize --quick) they are compiled without
# sanitizers and without debug information: one such unit took over six
# minutes and 3.6 GB to compile sanitized with -g. Our code in every other
# unit is still checked.
function(hb_heavy_sources)
  if(HAPTICBENCH_SANITIZE_SKIP_HEAVY)
    set_source_files_properties(${ARGN} PROPERTIES COMPILE_OPTIONS "-fno-sanitize=all;-g0")
  endif()
endfunction()
