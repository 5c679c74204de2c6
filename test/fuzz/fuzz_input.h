/* fuzz_input.h — reading a libFuzzer input as a stream of typed values, for
 * the harnesses of test/fuzz/ (scripts/fuzz.sh). Past the end every read
 * gives 0, so any input is a complete run. Header-only. */
#ifndef AF_FUZZ_INPUT_H
#define AF_FUZZ_INPUT_H

#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

typedef struct {
  const uint8_t *p;
  size_t n;
} af_fuzz_in;

static inline uint8_t af_fuzz_u8(af_fuzz_in *in)
{
  if (in->n == 0)
    return 0;
  in->n--;
  return *in->p++;
}

static inline uint16_t af_fuzz_u16(af_fuzz_in *in)
{
  return (uint16_t)(af_fuzz_u8(in) | (unsigned)af_fuzz_u8(in) << 8);
}

static inline uint32_t af_fuzz_u32(af_fuzz_in *in)
{
  return (uint32_t)af_fuzz_u16(in) | (uint32_t)af_fuzz_u16(in) << 16;
}

static inline uint64_t af_fuzz_u64(af_fuzz_in *in)
{
  return (uint64_t)af_fuzz_u32(in) | (uint64_t)af_fuzz_u32(in) << 32;
}

/* Any double, NaN and infinities included. */
static inline double af_fuzz_double(af_fuzz_in *in)
{
  uint64_t u = af_fuzz_u64(in);
  double d;
  memcpy(&d, &u, sizeof d);
  return d;
}

/* A uniform value in [lo, hi] from 16 bits. */
static inline double af_fuzz_range(af_fuzz_in *in, double lo, double hi)
{
  return lo + (hi - lo) * (double)af_fuzz_u16(in) / 65535.0;
}

/* A finite sample: an int16 scaled by scale, or (1 in 8) any finite float. */
static inline float af_fuzz_sample(af_fuzz_in *in, float scale, int raw)
{
  if (raw) {
    uint32_t u = af_fuzz_u32(in);
    float f;
    memcpy(&f, &u, sizeof f);
    return isfinite(f) ? f : 0.0f;
  }
  return scale * (float)(int16_t)af_fuzz_u16(in);
}

#endif
