# The test tiers (doc/tests.md): every ctest test carries at least one of
# these labels, so that `ctest -L unit` (seconds) or `ctest -LE slow` picks a
# tier. A label outside this list is refused at configure time.
#   unit        the C unit tests of src/core (test/core), no ROS, seconds
#   cli         firmness_model's tests (test/cli)
#   report      firmness_report, capture_to_bag and the plotting module
#   ros         the rostests, the shim's tests, roslaunch-check, anything that
#               starts a ROS master
#   scripts     the package's scripts run end to end (test/scripts), lint,
#               the dependency map
#   hostile     the hostile-input suite and the fuzz corpora
#   docs        the README's and doc/*.md's own tests
#   slow        over about 60 s on a 2-core machine
#   rig_faults  the rig-fault suite (test/rig_faults)
#   lint, fuzz  the static checks and the libFuzzer tests (with one above)
set(AF_TEST_LABELS unit cli report ros scripts hostile docs slow rig_faults lint fuzz)
set(AF_TEST_TIER_LABELS unit cli report ros scripts hostile docs slow rig_faults)

# af_test_properties(NAME LABELS label... [TIMEOUT s] [RESOURCE_LOCK r...])
# Labels (and a timeout, a resource lock) for a test made elsewhere, e.g. by
# catkin's add_rostest or catkin_add_gtest, under the name catkin gave it.
function(af_test_properties name)
  cmake_parse_arguments(AT "" "TIMEOUT" "LABELS;RESOURCE_LOCK" ${ARGN})
  if(AT_UNPARSED_ARGUMENTS)
    message(FATAL_ERROR "af_test_properties(${name}): unknown arguments ${AT_UNPARSED_ARGUMENTS}")
  endif()
  if(NOT TEST ${name})
    message(FATAL_ERROR "af_test_properties: no test ${name}")
  endif()
  set(tier OFF)
  foreach(label ${AT_LABELS})
    if(NOT label IN_LIST AF_TEST_LABELS)
      message(FATAL_ERROR "test ${name}: label '${label}' is not one of ${AF_TEST_LABELS}")
    endif()
    if(label IN_LIST AF_TEST_TIER_LABELS)
      set(tier ON)
    endif()
  endforeach()
  if(NOT tier)
    message(FATAL_ERROR "test ${name}: needs one label of ${AF_TEST_TIER_LABELS}")
  endif()
  set_property(TEST ${name} APPEND PROPERTY LABELS ${AT_LABELS})
  # ctest -j starts the costliest first; until it has timed a run (in
  # Testing/Temporary/CTestCostData.txt: not on a fresh build) the slow ones
  # would start last and run on alone at the end.
  if("slow" IN_LIST AT_LABELS)
    set_tests_properties(${name} PROPERTIES COST 100)
  endif()
  if(AT_TIMEOUT)
    set_tests_properties(${name} PROPERTIES TIMEOUT ${AT_TIMEOUT})
  endif()
  if(AT_RESOURCE_LOCK)
    set_property(TEST ${name} APPEND PROPERTY RESOURCE_LOCK ${AT_RESOURCE_LOCK})
  endif()
endfunction()

# af_catkin_run_test(name labels command working_dir): the test as catkin's
# `catkin_make run_tests` runs it too, its JUnit result (test/harness/junit.sh)
# in build/test_results/<package>/af-<name>.xml, where `catkin_test_results`
# reads it; one target per tier too: `catkin_make run_tests_<package>_af_unit`.
# (catkin_run_tests_target would register a second ctest test of it.)
function(af_catkin_run_test name labels command working_dir)
  if(NOT DEFINED CATKIN_ENV OR NOT CATKIN_ENABLE_TESTING)
    return()
  endif()
  set(result ${CATKIN_TEST_RESULTS_DIR}/${PROJECT_NAME}/af-${name}.xml)
  # add_test finds an executable target named first; a custom command's
  # argument is only text: its path, then.
  list(GET command 0 first)
  if(TARGET ${first})
    list(REMOVE_AT command 0)
    list(INSERT command 0 $<TARGET_FILE:${first}>)
  endif()
  set(run ${CATKIN_ENV} bash ${PROJECT_SOURCE_DIR}/test/harness/junit.sh --zero ${result} ${name}
          ${command})
  if(NOT working_dir)
    set(working_dir ${CMAKE_CURRENT_BINARY_DIR})
  endif()
  set(target run_tests_${PROJECT_NAME}_af_${name})
  add_custom_target(${target} COMMAND ${run} WORKING_DIRECTORY ${working_dir} VERBATIM)
  add_custom_target(_${target} COMMAND ${run} WORKING_DIRECTORY ${working_dir} VERBATIM)
  foreach(meta run_tests_${PROJECT_NAME} _run_tests_${PROJECT_NAME})
    if(NOT TARGET ${meta})
      add_custom_target(${meta})
    endif()
  endforeach()
  if(NOT TARGET clean_test_results_${PROJECT_NAME})
    add_custom_target(clean_test_results_${PROJECT_NAME}
      COMMAND ${PYTHON_EXECUTABLE} "${catkin_EXTRAS_DIR}/test/remove_test_results.py"
              "${CATKIN_TEST_RESULTS_DIR}/${PROJECT_NAME}" VERBATIM)
  endif()
  get_property(hooked GLOBAL PROPERTY AF_RUN_TESTS_HOOKED)
  if(NOT hooked)
    add_dependencies(run_tests _run_tests_${PROJECT_NAME})
    set_property(GLOBAL PROPERTY AF_RUN_TESTS_HOOKED ON)
  endif()
  add_dependencies(_${target} clean_test_results_${PROJECT_NAME} tests)
  add_dependencies(run_tests_${PROJECT_NAME} ${target})
  add_dependencies(_run_tests_${PROJECT_NAME} _${target})
  foreach(label ${labels})
    if(NOT TARGET run_tests_${PROJECT_NAME}_af_${label})
      add_custom_target(run_tests_${PROJECT_NAME}_af_${label})
    endif()
    add_dependencies(run_tests_${PROJECT_NAME}_af_${label} ${target})
  endforeach()
endfunction()

# af_add_test(NAME name COMMAND cmd... LABELS label... [TIMEOUT s]
#             [WORKING_DIRECTORY dir] [RESOURCE_LOCK r...])
# add_test with the labels (at least one tier label) and the options above.
function(af_add_test)
  cmake_parse_arguments(AT "" "NAME;TIMEOUT;WORKING_DIRECTORY" "COMMAND;LABELS;RESOURCE_LOCK"
                        ${ARGN})
  if(NOT AT_NAME OR NOT AT_COMMAND OR NOT AT_LABELS OR AT_UNPARSED_ARGUMENTS)
    message(FATAL_ERROR "af_add_test: needs NAME, COMMAND and LABELS (${ARGN})")
  endif()
  if(AT_WORKING_DIRECTORY)
    add_test(NAME ${AT_NAME} COMMAND ${AT_COMMAND} WORKING_DIRECTORY ${AT_WORKING_DIRECTORY})
  else()
    add_test(NAME ${AT_NAME} COMMAND ${AT_COMMAND})
  endif()
  set(extra)
  if(AT_TIMEOUT)
    list(APPEND extra TIMEOUT ${AT_TIMEOUT})
  endif()
  if(AT_RESOURCE_LOCK)
    list(APPEND extra RESOURCE_LOCK ${AT_RESOURCE_LOCK})
  endif()
  af_test_properties(${AT_NAME} LABELS ${AT_LABELS} ${extra})
  af_catkin_run_test(${AT_NAME} "${AT_LABELS}" "${AT_COMMAND}" "${AT_WORKING_DIRECTORY}")
endfunction()

# af_check_test_labels(): fails the configure when a test of this directory
# has no tier label (one registered with a bare add_test, or by catkin and
# never given its labels).
function(af_check_test_labels)
  get_property(tests DIRECTORY PROPERTY TESTS)
  foreach(t ${tests})
    get_test_property(${t} LABELS labels)
    set(tier OFF)
    foreach(label ${labels})
      if(label IN_LIST AF_TEST_TIER_LABELS)
        set(tier ON)
      endif()
    endforeach()
    if(NOT tier)
      message(FATAL_ERROR "test ${t} has no tier label (${AF_TEST_TIER_LABELS}): "
                          "register it with af_add_test or af_test_properties (cmake/af_tests.cmake)")
    endif()
  endforeach()
endfunction()
