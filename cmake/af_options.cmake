# The build's options (scripts/sanitize.sh, scripts/fuzz.sh, the benchmarks),
# included by CMakeLists.txt before any target.
# Sanitizer and fuzzing builds (scripts/sanitize.sh, scripts/fuzz.sh):
# -DACOUSTIC_FIRMNESS_SANITIZE=address,undefined instruments every target
# built here (any report aborts: no recovery); -DACOUSTIC_FIRMNESS_FUZZ=ON
# (clang) adds coverage for libFuzzer and the harnesses of test/fuzz/ with
# their corpus tests.
#catkin_lint: ignore_once global_var_collision
set(ACOUSTIC_FIRMNESS_SANITIZE "" CACHE STRING "sanitizers for every target, e.g. address,undefined")
#catkin_lint: ignore_once global_var_collision
option(ACOUSTIC_FIRMNESS_FUZZ "build the libFuzzer harnesses of test/fuzz (clang)" OFF)
if(ACOUSTIC_FIRMNESS_SANITIZE)
  add_compile_options(-fsanitize=${ACOUSTIC_FIRMNESS_SANITIZE} -fno-sanitize-recover=all
                      -fno-omit-frame-pointer)
  add_link_options(-fsanitize=${ACOUSTIC_FIRMNESS_SANITIZE})
endif()
if(ACOUSTIC_FIRMNESS_FUZZ)
  add_compile_options(-fsanitize=fuzzer-no-link)
endif()
# Benchmark build (doc/performance.md): -DACOUSTIC_FIRMNESS_BENCH=ON keeps
# the frame pointer in every function, so that `perf record --call-graph fp`
# reads whole call stacks (the default -O2 build omits it); the code is the
# same otherwise.
#catkin_lint: ignore_once global_var_collision
option(ACOUSTIC_FIRMNESS_BENCH "keep frame pointers for perf call graphs" OFF)
if(ACOUSTIC_FIRMNESS_BENCH)
  add_compile_options(-fno-omit-frame-pointer -mno-omit-leaf-frame-pointer)
endif()
