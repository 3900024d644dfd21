# Fails when a ctest test has no label (tests/README.md: unit, cli, dem, detection, fuzz, report,
# install, nodeps), so that `ctest -L unit` and friends keep selecting every test they should.
# Run by the test suite.EveryTestHasALabel: cmake -DBUILD_DIR=... -P every_test_has_a_label.cmake
# Two questions to ctest itself, each a second at most (a loop over the tests' JSON with
# string(JSON) re-parsed the whole document per property: 31 s for 500 tests):
#  1. every label in use is a known one (ctest --print-labels);
#  2. no test is left once every known label is excluded (ctest -N -LE): those have none.
cmake_policy(SET CMP0057 NEW)  # if(... IN_LIST ...)
set(known unit cli dem detection fuzz report install nodeps)

execute_process(COMMAND ${CMAKE_CTEST_COMMAND} --print-labels
                WORKING_DIRECTORY ${BUILD_DIR} OUTPUT_VARIABLE out RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "ctest --print-labels failed in ${BUILD_DIR}")
endif()
# "All Labels:\n  cli\n  dem\n ..." (or "No Labels Exist")
string(REGEX REPLACE "^[^\n]*\n" "" body "${out}")
string(REGEX MATCHALL "[^ \n]+" labels "${body}")
set(unknown "")
foreach(label IN LISTS labels)
  if(NOT label IN_LIST known)
    list(APPEND unknown ${label})
  endif()
endforeach()

list(JOIN known "|" alternatives)
execute_process(COMMAND ${CMAKE_CTEST_COMMAND} -N -LE "^(${alternatives})$"
                WORKING_DIRECTORY ${BUILD_DIR} OUTPUT_VARIABLE listing RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "ctest -N -LE failed in ${BUILD_DIR}")
endif()
string(REGEX MATCHALL "Test +#[0-9]+: [^\n]+" unlabelled "${listing}")
execute_process(COMMAND ${CMAKE_CTEST_COMMAND} -N WORKING_DIRECTORY ${BUILD_DIR}
                OUTPUT_VARIABLE all)
string(REGEX MATCH "Total Tests: [0-9]+" total "${all}")

list(LENGTH unlabelled nu)
if(nu GREATER 0 OR unknown)
  string(REPLACE ";" "\n  " u "${unlabelled}")
  string(REPLACE ";" ", " k "${unknown}")
  message(FATAL_ERROR "${nu} tests have no known label:\n  ${u}\nunknown labels: ${k}")
endif()
message(STATUS "all tests (${total}) have a label among: ${known}")
