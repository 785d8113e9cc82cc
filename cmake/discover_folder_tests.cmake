# Registers the test cases of one test executable (a test folder) with CTest,
# case by case under each file's own name, from one listing of the
# executable (tests/test_main.cpp, --list-tests-by-file). Run after each
# link (cmake/hapticbench.cmake, hb_test_folder) with
#   TEST_EXECUTABLE  the executable
#   FILES_CONFIG     a CMake file that sets hb_stems (the folder's *_test
#                    file stems, in order) and, per stem, hb_prefix_<stem>
#                    (the CTest name prefix, "end_to_end/run_command_test:")
#                    and hb_properties_<stem> (CTest properties of its cases)
#   WORKING_DIR      the tests' working folder
#   CTEST_FILE       the CTest script to write
# Every case runs with --warn NoTests: a name that matches nothing fails
# instead of passing without running anything. One listing per executable:
# registering file by file ran it twice per file.
include("${FILES_CONFIG}")

execute_process(COMMAND "${TEST_EXECUTABLE}" --list-tests-by-file
                OUTPUT_VARIABLE listing RESULT_VARIABLE result
                WORKING_DIRECTORY "${WORKING_DIR}")
if(NOT result EQUAL 0)
  message(FATAL_ERROR "${TEST_EXECUTABLE} --list-tests-by-file failed (${result}): ${listing}")
endif()
# A ';' would split a name in two CTest tests that match nothing.
if(listing MATCHES ";")
  message(FATAL_ERROR "${TEST_EXECUTABLE}: a test case name contains ';'")
endif()
string(REPLACE "\n" ";" lines "${listing}")

# Quotes an argument for the CTest script as a bracket argument.
function(quoted out value)
  set(${out} "[==[${value}]==]" PARENT_SCOPE)
endfunction()

set(script "")
foreach(stem IN LISTS hb_stems)
  set(count 0)
  foreach(line IN LISTS lines)
    string(FIND "${line}" "\t" tab)
    if(tab LESS 0)
      continue()
    endif()
    string(SUBSTRING "${line}" 0 ${tab} line_stem)
    if(NOT line_stem STREQUAL stem)
      continue()
    endif()
    math(EXPR start "${tab} + 1")
    string(SUBSTRING "${line}" ${start} -1 name)
    # Catch2 reads ',', '[' and ']' in a name as test-spec syntax.
    set(spec "${name}")
    foreach(char , [ ])
      string(REPLACE "${char}" "\\${char}" spec "${spec}")
    endforeach()
    quoted(test_name "${hb_prefix_${stem}}${name}")
    quoted(executable "${TEST_EXECUTABLE}")
    quoted(spec "${spec}")
    quoted(working_dir "${WORKING_DIR}")
    list(JOIN hb_properties_${stem} " " properties)
    string(APPEND script "add_test(${test_name} ${executable} ${spec} --warn NoTests)\n")
    string(APPEND script "set_tests_properties(${test_name} PROPERTIES WORKING_DIRECTORY "
                         "${working_dir} ${properties})\n")
    math(EXPR count "${count} + 1")
  endforeach()
  if(count EQUAL 0)
    message(WARNING "${TEST_EXECUTABLE}: no test case in ${stem}")
  endif()
endforeach()
file(WRITE "${CTEST_FILE}" "${script}")
