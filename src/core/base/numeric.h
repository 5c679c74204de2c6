/* numeric.h — what the numeric kernels share: their mark for the fuzzing
 * build, and two doubles in one register. */
#ifndef AF_NUMERIC_H
#define AF_NUMERIC_H

/* A numeric kernel (a model's pass over bins or samples, a solver, a table's
 * interpolation) carries no coverage instrumentation in the fuzzing build:
 * libFuzzer's hook on every loop comparison made them several times slower
 * there, and their branches are arithmetic, not input structure. ASan and
 * UBSan still check them. */
#if defined(__clang__) /* clang's spelling; gcc builds no fuzzer */
#define AF_NUMERIC_KERNEL __attribute__((no_sanitize("coverage")))
#else
#define AF_NUMERIC_KERNEL
#endif

/* The small loops' unroll pragmas (#pragma GCC unroll) are for GCC, the
 * build whose speed counts; clang (the sanitizer and fuzzing build) takes
 * them as a count to unroll by and warns where a bound is not a constant:
 * there it may leave them rolled. */
#if defined(__clang__)
#pragma clang diagnostic ignored "-Wpass-failed"
#endif

/* Two doubles in one SSE2 register (the vector extension of GCC and clang):
 * each lane gets the IEEE operation a scalar would, and the baseline x86-64
 * target has no FMA to contract it differently, so a loop over two values at
 * once gives the scalar loop's doubles bit for bit. */
typedef double af_v2d __attribute__((vector_size(16)));

#endif
