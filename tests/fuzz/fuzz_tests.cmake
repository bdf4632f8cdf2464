# The libFuzzer targets of tests/fuzz, built as a project of their own with clang and the
# sanitizers when clang's libFuzzer links here, and a short bounded run of each as a test.
# Longer runs: scripts/fuzz.
find_program(ACDR_CLANGXX NAMES clang++ clang++-14)
set(acdr_fuzz_links OFF)
if(ACDR_CLANGXX)
  set(probe_dir ${CMAKE_BINARY_DIR}/fuzz_probe)
  file(MAKE_DIRECTORY ${probe_dir})
  file(WRITE ${probe_dir}/probe.cpp
    "#include <cstddef>\n#include <cstdint>\n"
    "extern \"C\" int LLVMFuzzerTestOneInput(const std::uint8_t*, std::size_t) { return 0; }\n")
  execute_process(
    COMMAND ${ACDR_CLANGXX} -fsanitize=fuzzer,address,undefined probe.cpp -o probe
    WORKING_DIRECTORY ${probe_dir} RESULT_VARIABLE probe_result OUTPUT_QUIET ERROR_QUIET)
  if(probe_result EQUAL 0)
    set(acdr_fuzz_links ON)
  endif()
endif()
option(ACDR_FUZZ "Build and run the libFuzzer targets (needs clang++ and its libFuzzer)" ${acdr_fuzz_links})

if(NOT (ACDR_FUZZ AND acdr_fuzz_links))
  message(STATUS "fuzz targets: not built (clang++ with libFuzzer not found, or ACDR_FUZZ off)")
  return()
endif()

include(ExternalProject)
set(ACDR_FUZZ_BUILD ${CMAKE_BINARY_DIR}/fuzz)
ExternalProject_Add(acdr_fuzz
  SOURCE_DIR ${ACDR_SOURCE_DIR}/tests/fuzz
  BINARY_DIR ${ACDR_FUZZ_BUILD}
  CMAKE_ARGS -DCMAKE_CXX_COMPILER=${ACDR_CLANGXX} -DCMAKE_BUILD_TYPE=RelWithDebInfo
             -DCMAKE_CXX_COMPILER_LAUNCHER=${CMAKE_CXX_COMPILER_LAUNCHER}
  # One job: it builds beside the main build, which has the machine's cores already.
  BUILD_COMMAND ${CMAKE_COMMAND} --build <BINARY_DIR> -j 1
  BUILD_ALWAYS ON
  INSTALL_COMMAND "")

# Each target: a fresh corpus directory it may write to, then its seeds (read-only), at most
# `runs` inputs or `seconds` of fuzzing, whichever comes first; a crash, a sanitizer report or
# a leak fails the test.
function(acdr_fuzz_test target runs seconds max_len)
  set(corpus ${ACDR_FUZZ_BUILD}/corpus/${target})
  add_test(NAME fuzz.${target}
    COMMAND sh -c "rm -rf '${corpus}' && mkdir -p '${corpus}' && exec '${ACDR_FUZZ_BUILD}/${target}' -runs=${runs} -max_total_time=${seconds} -max_len=${max_len} -seed=1 -rss_limit_mb=2048 -timeout=10 -print_final_stats=1 '${corpus}' ${ARGN}")
  set_tests_properties(fuzz.${target} PROPERTIES TIMEOUT 60 LABELS fuzz)
endfunction()

set(seeds ${ACDR_SOURCE_DIR})
acdr_fuzz_test(scenario_loader_fuzz 4000 10 16384 '${seeds}/scenarios/modules' '${seeds}/tests/scenarios/data')
acdr_fuzz_test(trajectory_fuzz 20000 8 4096 '${seeds}/content/demonstrations')
acdr_fuzz_test(mesh_obj_fuzz 20000 8 8192 '${seeds}/tests/scenarios/data' '${seeds}/tests/fuzz/regressions')
acdr_fuzz_test(mesh_stl_fuzz 20000 8 8192 '${seeds}/tests/scenarios/data' '${seeds}/tests/fuzz/regressions')
# The decoder's seeds are written by a small program of the fuzz build.
set(udp_seeds ${ACDR_FUZZ_BUILD}/seeds/udp_bridge)
add_test(NAME fuzz.udp_bridge_seeds
  COMMAND sh -c "mkdir -p '${udp_seeds}' && exec '${ACDR_FUZZ_BUILD}/udp_bridge_seeds' '${udp_seeds}'")
set_tests_properties(fuzz.udp_bridge_seeds PROPERTIES FIXTURES_SETUP udp_seeds LABELS fuzz)
acdr_fuzz_test(udp_bridge_protocol_fuzz 50000 8 256 '${udp_seeds}')
set_tests_properties(fuzz.udp_bridge_protocol_fuzz PROPERTIES FIXTURES_REQUIRED udp_seeds)
