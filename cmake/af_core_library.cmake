# af_core_library(NAME SOURCES file.c... [LINKS target...]): one layer of the
# core (src/core/<layer>/), a static library whose public headers are its own
# folder's. LINKS names the layers right below it: their folders reach this
# one through them, and nothing above does, so a header of a higher layer
# included here does not compile (doc/layout.md, "the layers").
function(af_core_library name)
  cmake_parse_arguments(A "" "" "SOURCES;LINKS" ${ARGN})
  add_library(${name} STATIC ${A_SOURCES})
  target_include_directories(${name} PUBLIC ${CMAKE_CURRENT_SOURCE_DIR})
  # af_defaults.h, generated from the table (CMakeLists.txt): for the core's
  # own sources.
  #catkin_lint: ignore_once missing_directory (made at build time)
  target_include_directories(${name} PRIVATE ${AF_DEFAULTS_DIR})
  target_compile_options(${name} PRIVATE ${AF_WARNINGS} -pedantic)
  # gcc's -O2 cost model ("very-cheap") vectorises no loop of unknown length;
  # the "dynamic" one does (the streams' SI conversion over every sample, the
  # window and the periodogram): the same results (no reassociation without
  # -ffast-math), fewer instructions. gcc's flag; clang's -O2 vectorises them.
  # -fno-math-errno: sqrt and the rounding functions inline, without a call
  # kept only to set errno, which the core never reads after a math function
  # (its errno checks follow strtod, which still sets it): the same results.
  target_compile_options(${name} PRIVATE $<$<C_COMPILER_ID:GNU>:-fvect-cost-model=dynamic> -fno-math-errno)
  target_link_libraries(${name} PUBLIC ${A_LINKS})
  add_dependencies(${name} af_defaults)
  set_target_properties(${name} PROPERTIES POSITION_INDEPENDENT_CODE ON)
endfunction()
