# The SIMD path the project is compiled for (docs/performance.md, "The SIMD path").
#   auto      what the machine that builds it has: avx2 where it runs x86-64-v3, else baseline
#   avx2      x86-64-v3 (AVX2, BMI2, ...) without fused multiply-add
#   baseline  any x86-64 (SSE2)
# Every path gives the same bits: -ffp-contract=off and -mno-fma keep each operation as the
# source writes it, so wider registers change how many lanes an instruction fills, not what it
# computes (the golden-hash and demonstration-physics tests check it on the path built).
# AVX-512 is not offered: Eigen 3.4 refuses it without FMA, and FMA rounds differently.
set(ACDR_SIMD "auto" CACHE STRING "SIMD path: auto, avx2 or baseline")
set_property(CACHE ACDR_SIMD PROPERTY STRINGS auto avx2 baseline)

set(acdr_simd_path "${ACDR_SIMD}")
if(acdr_simd_path STREQUAL "auto")
  set(acdr_simd_path "baseline")
  if(CMAKE_SYSTEM_PROCESSOR MATCHES "^(x86_64|AMD64|amd64)$" AND NOT CMAKE_CROSSCOMPILING)
    try_run(acdr_simd_run acdr_simd_compiled
            SOURCES ${CMAKE_CURRENT_LIST_DIR}/simd_probe.cpp
            RUN_OUTPUT_VARIABLE acdr_simd_probe)
    if(acdr_simd_compiled AND acdr_simd_run EQUAL 0)
      string(STRIP "${acdr_simd_probe}" acdr_simd_path)
    endif()
  endif()
endif()

if(acdr_simd_path STREQUAL "avx2")
  add_compile_options(-march=x86-64-v3 -mno-fma)
elseif(NOT acdr_simd_path STREQUAL "baseline")
  message(FATAL_ERROR "ACDR_SIMD must be auto, avx2 or baseline, not '${ACDR_SIMD}'")
endif()
set(ACDR_SIMD_PATH "${acdr_simd_path}")
# Named by `acdr --version` and the bench's machine line.
add_compile_definitions(ACDR_SIMD_PATH="${ACDR_SIMD_PATH}")
message(STATUS "SIMD path: ${ACDR_SIMD_PATH} (ACDR_SIMD=${ACDR_SIMD})")
