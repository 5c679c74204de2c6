/* samples.c — tests over a block of float samples (samples.h). */
#include "samples.h"

#include <stdint.h>
#include <string.h>

/* Samples counted in one 32-bit count (the vectorised loop's lanes). */
#define AF_SAMPLES_COUNT_RUN ((size_t)1 << 16)

size_t af_samples_nonfinite(const float *x, size_t n)
{
  size_t bad = 0, k = 0;
  while (k < n) {
    const size_t end = n - k > AF_SAMPLES_COUNT_RUN ? k + AF_SAMPLES_COUNT_RUN : n;
    uint32_t run = 0;
    for (; k < end; k++) {
      uint32_t b;
      memcpy(&b, &x[k], sizeof b);
      run += (b & 0x7f800000u) == 0x7f800000u;
    }
    bad += run;
  }
  return bad;
}
