# The core's SIMD kernels (src/core/simd.h): Google Highway with runtime dispatch when found
# (Debian 12: libhwy-dev), plain C++ loops otherwise (Ubuntu 20.04 has no libhwy-dev and rosdep
# no key for it). Used by the catkin build and by the aarch64 cross build (cmake/arm64).
find_package(hwy QUIET)
if(hwy_FOUND AND hwy_VERSION VERSION_LESS 1.0)
  # (the kernels use 1.0's ops and targets; 1.0.3, Debian 12's, is the version built and tested)
  message(WARNING "Highway ${hwy_VERSION} is older than 1.0: not used.")
  set(hwy_FOUND FALSE)
endif()
if(hwy_FOUND)
  message(STATUS "Highway ${hwy_VERSION}: SIMD kernels dispatched at run time (x86: SSE4, AVX2, "
                 "AVX-512; aarch64: NEON; the plain loops elsewhere)")
else()
  message(WARNING "Highway (libhwy-dev) not found: the detector's kernels are plain C++ loops, "
                  "about 5x slower than with it. Install libhwy-dev 1.0 or later (Debian 12 "
                  "has 1.0.3) for the SIMD path.")
endif()

# Compile a target's kernels: its private headers (src/core), no FMA contraction (every target
# gives the scalar code's bits), and with Highway every attainable target (SSSE3 and the SVE
# variants are left out: SSE4 and NEON are the 128-bit targets). EMU128 is Highway's baseline and
# is compiled, but simd.h never chooses it and no test runs it: its emulated double->float
# demotion saturates infinity to FLT_MAX, so the NCC flat-window rule (1 / sqrt(inf) = 0) would
# not hold; the plain loops (kScalar) are the scalar target. Highway 1.0.3 swaps EMU128 for the
# one-lane HWY_SCALAR under GCC < 12.3 (GCC bug 106322, 16-bit MulHigh); HWY_BROKEN_EMU128=0
# keeps the baseline EMU128 so the dispatch tables stay the same on every compiler.
function(rld_simd_setup target)
  target_include_directories(${target} PRIVATE ${PROJECT_SOURCE_DIR}/src/core)
  target_compile_options(${target} PRIVATE -ffp-contract=off)
  if(hwy_FOUND)
    target_compile_definitions(${target} PRIVATE RLD_HAVE_HWY HWY_COMPILE_ALL_ATTAINABLE HWY_BROKEN_EMU128=0
      "HWY_DISABLED_TARGETS=(HWY_SSSE3|HWY_SVE|HWY_SVE2|HWY_SVE_256|HWY_SVE2_128)")
    target_link_libraries(${target} hwy::hwy)
  endif()
endfunction()
