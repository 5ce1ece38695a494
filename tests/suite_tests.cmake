# Registers one CTest test per gtest suite, where gtest_discover_tests registers one per test (tests/CMakeLists.txt,
# VPLAB_CTEST_PER_SUITE). Run after each build of the test binary, in script mode:
#   cmake -D TEST_EXECUTABLE=... -D TEST_FILTER=... -D LABEL=... -D WORKING_DIRECTORY=... -D CTEST_FILE=...
#         [-D RESOURCE_LOCK=...] -P suite_tests.cmake
# Each CTest test runs its suite's tests that TEST_FILTER selects in one process, named by an explicit gtest filter;
# it is called "<suite> [<label>]", so that the same suite under two labels (its statistical tests, its OSMesa twins)
# gives two tests. gtest's DISABLED_ tests are left out, as gtest leaves them out of a run.
cmake_minimum_required(VERSION 3.20)
foreach(required TEST_EXECUTABLE TEST_FILTER LABEL WORKING_DIRECTORY CTEST_FILE)
  if(NOT DEFINED ${required})
    message(FATAL_ERROR "suite_tests.cmake: ${required} is not set")
  endif()
endforeach()
execute_process(COMMAND "${TEST_EXECUTABLE}" --gtest_list_tests "--gtest_filter=${TEST_FILTER}"
  WORKING_DIRECTORY "${WORKING_DIRECTORY}" OUTPUT_VARIABLE listing ERROR_VARIABLE errors RESULT_VARIABLE status
  TIMEOUT 120)
if(NOT status EQUAL 0)
  message(FATAL_ERROR "${TEST_EXECUTABLE} --gtest_list_tests failed (${status}):\n${listing}${errors}")
endif()

# The listing: "Suite." (parametrised: "Prefix/Suite.", typed: "Suite.  # TypeParam = ..."), then its tests indented
# by two spaces, a parameter's value after "  # ".
string(REPLACE ";" "\\;" listing "${listing}")
string(REPLACE "\n" ";" lines "${listing}")
set(suites "")
set(suite "")
foreach(line IN LISTS lines)
  if(line MATCHES "^([^ #][^ ]*)\\.(  #.*)?$")
    set(suite "${CMAKE_MATCH_1}")
    list(APPEND suites "${suite}")
    set("tests_${suite}" "")
  elseif(suite AND line MATCHES "^  ([^ ]+)")
    set(test "${CMAKE_MATCH_1}")
    if(NOT test MATCHES "^DISABLED_" AND NOT suite MATCHES "(^|/)DISABLED_")
      list(APPEND "tests_${suite}" "${suite}.${test}")
    endif()
  endif()
endforeach()

set(script "")
foreach(suite IN LISTS suites)
  if(NOT tests_${suite})
    continue()
  endif()
  list(JOIN "tests_${suite}" ":" filter)
  # CTest starts the costliest tests first when it has no timings of its own; a suite's count of tests stands in for
  # its time, so that a long suite does not start last and run alone.
  list(LENGTH "tests_${suite}" count)
  set(name "${suite} [${LABEL}]")
  string(APPEND script "add_test([==[${name}]==] [==[${TEST_EXECUTABLE}]==] [==[--gtest_filter=${filter}]==])\n")
  string(APPEND script "set_tests_properties([==[${name}]==] PROPERTIES LABELS [==[${LABEL}]==] "
                       "WORKING_DIRECTORY [==[${WORKING_DIRECTORY}]==] TIMEOUT 900 COST ${count}")
  if(RESOURCE_LOCK)
    string(APPEND script " RESOURCE_LOCK [==[${RESOURCE_LOCK}]==]")
  endif()
  string(APPEND script ")\n")
endforeach()
file(WRITE "${CTEST_FILE}" "${script}")
