/* samples.h — tests over a block of float samples. */
#ifndef AF_SAMPLES_H
#define AF_SAMPLES_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/* The non-finite (lost: NaN or infinite) samples of x[0..n): those whose
 * exponent field is all ones, counted by integer tests on the bit patterns,
 * which the compiler vectorises (a float test per sample it does not). */
size_t af_samples_nonfinite(const float *x, size_t n);

#ifdef __cplusplus
}
#endif
#endif
