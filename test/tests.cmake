# Every test, with its tier labels (cmake/af_tests.cmake), included by the
# top-level CMakeLists.txt in its scope (not a subdirectory: catkin names the
# rostests and gtests after their paths from the package root).
if(CATKIN_ENABLE_TESTING)
  find_package(roslaunch REQUIRED)
  find_package(rostest REQUIRED)
  # Core unit tests: one C program per module, test/core/test_<module>.c,
  # exit status 0 = pass. Built by `make tests`, run by ctest.
  file(GLOB AF_CORE_TESTS CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/test/core/test_*.c)
  foreach(src ${AF_CORE_TESTS})
    get_filename_component(name ${src} NAME_WE)
    add_executable(${name} EXCLUDE_FROM_ALL ${src})
    target_include_directories(${name} PRIVATE ${PROJECT_SOURCE_DIR}/test/core)
    # af_defaults.h (test_defaults checks it against the table)
    #catkin_lint: ignore_once missing_directory (made at build time, above)
    target_include_directories(${name} PRIVATE ${AF_DEFAULTS_DIR})
    target_compile_options(${name} PRIVATE ${AF_WARNINGS})
    target_link_libraries(${name} af_core)
    add_dependencies(tests ${name})
    af_add_test(NAME core_${name} COMMAND ${name} WORKING_DIRECTORY ${PROJECT_SOURCE_DIR}
                LABELS unit)
  endforeach()
  # CLI tests: shell scripts that call the built firmness_model.
  file(GLOB AF_CLI_TESTS CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/test/cli/test_*.sh)
  foreach(src ${AF_CLI_TESTS})
    get_filename_component(name ${src} NAME_WE)
    af_add_test(NAME cli_${name} COMMAND bash ${src} $<TARGET_FILE:firmness_model> LABELS cli)
  endforeach()
  add_dependencies(tests firmness_model)
  # analyze's session (the fuzz harness's way in) against analyze alone.
  add_executable(test_analyze_session EXCLUDE_FROM_ALL
                 ${PROJECT_SOURCE_DIR}/test/cli/test_analyze_session.c)
  target_include_directories(test_analyze_session PRIVATE ${PROJECT_SOURCE_DIR}/test/core)
  target_compile_options(test_analyze_session PRIVATE ${AF_WARNINGS})
  target_link_libraries(test_analyze_session af_analyze af_core)
  add_dependencies(tests test_analyze_session)
  af_add_test(NAME cli_test_analyze_session COMMAND test_analyze_session
              WORKING_DIRECTORY ${PROJECT_SOURCE_DIR} LABELS cli)
  # firmness_report on a small strike_bag against its truth, and every kind of
  # bad input; the bad bags are written with rosbag's Python (devel space env).
  if(TARGET firmness_report AND TARGET strike_bag)
    # Every tool's --help against its flag table, bad flags and missing values.
    af_add_test(NAME report_test_help
                COMMAND bash ${PROJECT_SOURCE_DIR}/test/report/test_help.sh
                        $<TARGET_FILE:firmness_model> $<TARGET_FILE:firmness_report>
                        $<TARGET_FILE:strike_bag> $<TARGET_FILE:capture_to_bag>
                LABELS report cli)
    # Every other test/report/test_*.sh takes (firmness_report, strike_bag) and
    # runs in the devel space (the bad bags are written with rosbag's Python):
    # the report against strike_bag's truth, grades, many bags, the hammer's
    # health, the learned factor, a tap-only bag, a truncated bag (what each checks: its header).
    file(GLOB AF_REPORT_TESTS CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/test/report/test_*.sh)
    list(FILTER AF_REPORT_TESTS EXCLUDE REGEX "/test_help\\.sh$")
    foreach(src ${AF_REPORT_TESTS})
      get_filename_component(name ${src} NAME_WE)
      af_add_test(NAME report_${name}
                  COMMAND ${CATKIN_ENV} bash ${src}
                          $<TARGET_FILE:firmness_report> $<TARGET_FILE:strike_bag>
                  LABELS report)
    endforeach()
  endif()
  # capture_to_bag on WAVs of the real captures with an apple CSV: the bag read
  # back with rosbag's Python, firmness_report on it, every refusal.
  if(TARGET capture_to_bag AND TARGET firmness_report AND TARGET strike_bag)
    af_add_test(NAME convert_test_capture_to_bag
                COMMAND ${CATKIN_ENV} bash ${PROJECT_SOURCE_DIR}/test/convert/test_capture_to_bag.sh
                        $<TARGET_FILE:capture_to_bag> $<TARGET_FILE:firmness_report>
                        $<TARGET_FILE:strike_bag>
                LABELS report)
  endif()
  # Plot tests (test/plot/test_*.c): the plotting module without ROS, e.g.
  # the node's live strike picture rendered in memory 1000 times (time, RSS).
  file(GLOB AF_PLOT_TESTS CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/test/plot/test_*.c)
  foreach(src ${AF_PLOT_TESTS})
    get_filename_component(name ${src} NAME_WE)
    add_executable(${name} EXCLUDE_FROM_ALL ${src})
    target_include_directories(${name} PRIVATE ${PROJECT_SOURCE_DIR}/test/core)
    target_compile_options(${name} PRIVATE ${AF_WARNINGS})
    target_link_libraries(${name} af_plot af_core)
    add_dependencies(tests ${name})
    af_add_test(NAME plot_${name} COMMAND ${name} WORKING_DIRECTORY ${PROJECT_SOURCE_DIR}
                LABELS report)
  endforeach()
  # Static checks: clang-format, cppcheck, catkin_lint.
  af_add_test(NAME lint COMMAND bash ${PROJECT_SOURCE_DIR}/scripts/lint.sh LABELS scripts lint)
  # The one dependency list (package.xml -> the rosdep rules of rosdep/ and
  # test/data/rosdep_upstream.yaml -> the Debian package that ships each ROS
  # package's package.xml), and rosdep resolving every key from a local database.
  af_add_test(NAME deps_map COMMAND bash ${PROJECT_SOURCE_DIR}/test/deps/test_dependency_map.sh
              LABELS scripts)
  af_add_test(NAME rosdep_keys COMMAND bash ${PROJECT_SOURCE_DIR}/test/deps/test_rosdep.sh
              LABELS scripts)

  # Shim unit tests: C programs over the C API (test/shim/test_*.c) and C++
  # gtests of the conversions (test/shim/test_*.cpp).
  if(TARGET af_shim)
    file(GLOB AF_SHIM_C_TESTS CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/test/shim/test_*.c)
    foreach(src ${AF_SHIM_C_TESTS})
      get_filename_component(name ${src} NAME_WE)
      add_executable(${name} EXCLUDE_FROM_ALL ${src})
      target_include_directories(${name} PRIVATE ${PROJECT_SOURCE_DIR}/test/core)
      target_compile_options(${name} PRIVATE ${AF_WARNINGS})
      target_link_libraries(${name} af_shim af_core)
      set_target_properties(${name} PROPERTIES LINKER_LANGUAGE CXX)
      add_dependencies(tests ${name})
      af_add_test(NAME shim_${name} COMMAND ${name} WORKING_DIRECTORY ${PROJECT_SOURCE_DIR}
                  LABELS ros)
    endforeach()
    file(GLOB AF_SHIM_GTESTS CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/test/shim/test_*.cpp)
    foreach(src ${AF_SHIM_GTESTS})
      get_filename_component(name ${src} NAME_WE)
      catkin_add_gtest(${name} ${src} WORKING_DIRECTORY ${PROJECT_SOURCE_DIR})
      target_include_directories(${name} SYSTEM PRIVATE ${catkin_INCLUDE_DIRS})
      target_compile_options(${name} PRIVATE ${AF_WARNINGS})
      target_link_libraries(${name} af_shim af_core)
      # catkin names the test _ctest_<package>_gtest_<target> (none without gtest)
      if(TARGET ${name})
        af_test_properties(_ctest_${PROJECT_NAME}_gtest_${name} LABELS ros)
      endif()
    endforeach()
  endif()

  # Node integration tests: rostest launch files in test/node/.
  if(TARGET firmness_node)
    # The rostests import the generated Python messages, but catkin snapshots
    # the test environment (env_cached.sh) in find_package(catkin), before
    # generate_messages() has made the devel Python directory, and so leaves
    # it out of PYTHONPATH on a first configure. Refresh the snapshot now that
    # the directory exists, as catkin_python_setup() does.
    file(MAKE_DIRECTORY "${CATKIN_DEVEL_PREFIX}/${PYTHON_INSTALL_DIR}")
    safe_execute_process(COMMAND ${GENERATE_ENVIRONMENT_CACHE_COMMAND})
    file(GLOB AF_ROSTESTS CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/test/node/*.test)
    set(AF_ROSTEST_DEPENDENCIES firmness_node firmness_model)
    if(TARGET strike_bag)
      list(APPEND AF_ROSTEST_DEPENDENCIES strike_bag) # test/node/strikes.test makes its bag
    endif()
    if(TARGET firmness_report)
      # test_strikes.py: the node and firmness_report (the core lane offline)
      # must judge the strikes rostest's bag alike.
      list(APPEND AF_ROSTEST_DEPENDENCIES firmness_report)
    endif()
    # C programs the rostests may run (test/node/*.c). Test programs: not installed.
    file(GLOB AF_NODE_TEST_TOOLS CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/test/node/*.c)
    foreach(src ${AF_NODE_TEST_TOOLS})
      get_filename_component(name ${src} NAME_WE)
      add_executable(${name} EXCLUDE_FROM_ALL ${src})
      target_compile_options(${name} PRIVATE ${AF_WARNINGS})
      target_link_libraries(${name} af_shim af_core)
      set_target_properties(${name} PROPERTIES LINKER_LANGUAGE CXX)
      add_dependencies(tests ${name})
      list(APPEND AF_ROSTEST_DEPENDENCIES ${name})
    endforeach()
    foreach(t ${AF_ROSTESTS})
      file(RELATIVE_PATH rel ${PROJECT_SOURCE_DIR} ${t})
      add_rostest(${rel} DEPENDENCIES ${AF_ROSTEST_DEPENDENCIES})
      # catkin names the test _ctest_<package>_rostest_<path with / as _>;
      # rostest starts a master of its own on a port the system picks (free)
      string(REPLACE "/" "_" rostest_name ${rel})
      af_test_properties(_ctest_${PROJECT_NAME}_rostest_${rostest_name} LABELS ros)
    endforeach()
    # Every launch file parses and names only packages and nodes that exist.
    # roslaunch-check itself, run by the build's Python rather than through
    # roslaunch_add_file_check: its "env python3" shebang can find another
    # interpreter first in PATH. -i: replay.launch's bag has no default.
    file(GLOB AF_LAUNCH_FILES CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/launch/*.launch)
    foreach(launch ${AF_LAUNCH_FILES})
      get_filename_component(name ${launch} NAME_WE)
      af_add_test(NAME roslaunch_check_${name}
                  COMMAND ${CATKIN_ENV} ${PYTHON_EXECUTABLE} ${roslaunch_check_script} -i
                          -o ${CATKIN_TEST_RESULTS_DIR}/${PROJECT_NAME}/roslaunch-check_${name}.xml
                          ${launch}
                  LABELS ros)
    endforeach()
    # Script tests (test/scripts/test_*.sh): the main command end to end
    # (scripts/run.sh, 3 strikes, on a free master port), every rosrun and
    # roslaunch line and every example of README.md and doc/*.md, the
    # generated parameter reference, against this build and its devel space.
    # Labels: scripts, and ros (each starts masters of its own, on free
    # ports: test/scripts/harness.sh) but for the two below that start none;
    # docs for the tests of the README's and doc/*.md's commands and figures;
    # slow for those over ~60 s on a 2-core machine.
    if(TARGET strike_bag)
      set(AF_SCRIPT_TESTS_NO_MASTER scripts_doc_parameters scripts_stray_numbers scripts_workspace)
      set(AF_SCRIPT_TESTS_DOCS scripts_doc_examples scripts_doc_parameters scripts_readme_ros_lines
                               scripts_readme_scripts scripts_quick_start scripts_stray_numbers)
      set(AF_SCRIPT_TESTS_SLOW scripts_doc_examples scripts_readme_scripts scripts_valgrind
                               scripts_workspace)
      file(GLOB AF_SCRIPT_TESTS CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/test/scripts/test_*.sh)
      foreach(src ${AF_SCRIPT_TESTS})
        get_filename_component(name ${src} NAME_WE)
        string(REGEX REPLACE "^test_" "scripts_" name ${name})
        set(labels scripts)
        if(NOT name IN_LIST AF_SCRIPT_TESTS_NO_MASTER)
          list(APPEND labels ros)
        endif()
        if(name IN_LIST AF_SCRIPT_TESTS_DOCS)
          list(APPEND labels docs)
        endif()
        if(name IN_LIST AF_SCRIPT_TESTS_SLOW)
          list(APPEND labels slow)
        endif()
        set(timeout 120)
        if(name STREQUAL "scripts_valgrind")
          # memcheck slows the node ~30x (scripts/valgrind.sh --short)
          set(timeout 300)
        elseif(name STREQUAL "scripts_workspace")
          # a whole catkin_make of the package, then its unit tier twice
          set(timeout 900)
        elseif(name STREQUAL "scripts_doc_examples")
          # the demo of the README (20 strikes at real time) and every other example
          set(timeout 300)
        elseif(name STREQUAL "scripts_readme_scripts")
          # three replays, and rviz (installed by setup.sh --rviz on first use)
          set(timeout 600)
        endif()
        af_add_test(NAME ${name} COMMAND env AF_BUILD_DIR=${CMAKE_BINARY_DIR}
                                             AF_DEVEL_DIR=${CATKIN_DEVEL_PREFIX} bash ${src}
                    LABELS ${labels} TIMEOUT ${timeout})
      endforeach()
    endif()
  endif()

  # The hostile-input suite (test/hostile/test_*.sh, ctest hostile_*): each
  # case a hostile input with its exit code, line, time and memory bound; run
  # in both CI stages (AF_SANITIZED=1 under the sanitizers: no RSS bound).
  if(TARGET firmness_model AND TARGET firmness_report)
    file(GLOB AF_HOSTILE_TESTS CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/test/hostile/test_*.sh)
    if(ACOUSTIC_FIRMNESS_SANITIZE)
      set(AF_SANITIZED 1)
    else()
      set(AF_SANITIZED 0)
    endif()
    foreach(src ${AF_HOSTILE_TESTS})
      get_filename_component(name ${src} NAME_WE)
      string(REGEX REPLACE "^test_" "hostile_" name ${name})
      set(labels hostile)
      if(name STREQUAL "hostile_big_message")
        list(APPEND labels ros) # a master of its own on a free port (big_message.py)
      endif()
      af_add_test(NAME ${name} COMMAND env AF_BUILD_DIR=${CMAKE_BINARY_DIR}
                                           AF_DEVEL_DIR=${CATKIN_DEVEL_PREFIX}
                                           AF_SANITIZED=${AF_SANITIZED} bash ${src}
                  LABELS ${labels} TIMEOUT 300)
    endforeach()
  endif()

  # The rig-fault suite (test/rig_faults/test_*.sh, ctest rig_faults_*): a real
  # rig's faults (late camera stamps, clock offsets, clipping, bounces, full
  # disks, settings that cannot work together) injected into signals the
  # station did not make; each case states what must be said and that no
  # strike is reliable and wrong in silence. Run in both CI stages.
  if(TARGET firmness_model AND TARGET firmness_report)
    file(GLOB AF_RIG_FAULT_TESTS CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/test/rig_faults/test_*.sh)
    foreach(src ${AF_RIG_FAULT_TESTS})
      get_filename_component(name ${src} NAME_WE)
      string(REGEX REPLACE "^test_" "rig_faults_" name ${name})
      af_add_test(NAME ${name} COMMAND env AF_BUILD_DIR=${CMAKE_BINARY_DIR}
                                           AF_DEVEL_DIR=${CATKIN_DEVEL_PREFIX}
                                           AF_SANITIZED=${AF_SANITIZED} bash ${src}
                  LABELS rig_faults TIMEOUT 600)
    endforeach()
  endif()

  # libFuzzer harnesses (-DACOUSTIC_FIRMNESS_FUZZ=ON, clang):
  # test/fuzz/fuzz_<name>.c(pp), each with its seed corpus and the inputs that once failed in
  # test/fuzz/<name>/. The ctest test fuzz_<name>_corpus runs every one of
  # them once (each within a second, no sanitizer report); scripts/fuzz.sh
  # fuzzes for a bounded time.
  if(ACOUSTIC_FIRMNESS_FUZZ)
    file(GLOB AF_FUZZERS CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/test/fuzz/fuzz_*.c
         ${PROJECT_SOURCE_DIR}/test/fuzz/fuzz_*.cpp)
    foreach(src ${AF_FUZZERS})
      get_filename_component(name ${src} NAME_WE)
      string(REGEX REPLACE "^fuzz_" "" corpus ${name})
      add_executable(${name} EXCLUDE_FROM_ALL ${src})
      target_include_directories(${name} PRIVATE ${PROJECT_SOURCE_DIR}/src/tools)
      target_include_directories(${name} SYSTEM PRIVATE ${catkin_INCLUDE_DIRS})
      target_compile_options(${name} PRIVATE ${AF_WARNINGS})
      target_link_options(${name} PRIVATE -fsanitize=fuzzer)
      target_link_libraries(${name} af_shim af_core)
      set_target_properties(${name} PROPERTIES LINKER_LANGUAGE CXX)
      # The CLI's own libraries (src/tools), as firmness_model links them.
      if(name STREQUAL "fuzz_cli")
        target_link_libraries(${name} af_cli_flags)
      elseif(name STREQUAL "fuzz_analyze")
        target_link_libraries(${name} af_analyze)
      elseif(name STREQUAL "fuzz_wav")
        target_link_libraries(${name} af_recording)
      endif()
      add_dependencies(tests ${name})
      af_add_test(NAME ${name}_corpus
                  COMMAND bash ${PROJECT_SOURCE_DIR}/test/fuzz/run_corpus.sh $<TARGET_FILE:${name}>
                          ${PROJECT_SOURCE_DIR}/test/fuzz/${corpus}
                  LABELS hostile fuzz)
    endforeach()
    # scripts/fuzz.sh in its short mode: every harness fuzzed for 3 s, from a
    # fixed seed (the gate's verdict depends on the code, not on the run).
    af_add_test(NAME fuzz_script_short
                COMMAND env AF_SAN_BUILD_DIR=${CMAKE_BINARY_DIR} AF_DEVEL_DIR=${CATKIN_DEVEL_PREFIX}
                        bash ${PROJECT_SOURCE_DIR}/scripts/fuzz.sh --seconds 3 --seed 1 --no-build
                LABELS hostile fuzz scripts TIMEOUT 300)
  endif()

  # Every test above has a tier label (cmake/af_tests.cmake), or the
  # configure stops naming it.
  af_check_test_labels()
endif()

