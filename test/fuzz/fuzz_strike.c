/* fuzz_strike.c — libFuzzer harness: the strike detector (src/core/detect/strike.h)
 * fed an arbitrary sequence of chunks (any length up to 4096 samples, any
 * finite values, contiguous or after a gap of any size or a restart), primes
 * and flushes, at one of four DAQ rates. Every event must lie inside what was
 * written and carry a pulse of at most the detector's span; no input may
 * crash, hang or trip a sanitizer. */
#include <stdlib.h>

#include "fuzz_input.h"
#include "strike.h"

#define AF_FUZZ_CHUNK_MAX 4096

typedef struct {
  uint64_t end; /* one past the furthest sample written (a restart goes back; an event
                   of the old stream may still come) */
  size_t events;
} af_fuzz_state;

static void on_strike(const af_strike_event *ev, void *user)
{
  af_fuzz_state *s = user;
  s->events++;
  if (!(ev->start_sample <= (double)s->end + 1.0) || (ev->n_samples > 0 && ev->pulse_n == NULL))
    abort();
  for (size_t k = 0; k < ev->n_samples; k++)
    if (!isfinite(ev->pulse_n[k]))
      abort();
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
  static const double rates[] = {25600.0, 44100.0, 48000.0, 50000.0};
  static float x[AF_FUZZ_CHUNK_MAX];
  af_fuzz_in in = {data, size};
  af_strike_config cfg = af_strike_config_default();
  uint8_t head = af_fuzz_u8(&in);
  cfg.sample_rate_hz = rates[head & 3];
  if (head & 4)
    cfg.threshold_min_n = af_fuzz_range(&in, 1e-6, 50.0);
  af_strike *d = NULL;
  if (af_strike_create(&cfg, &d) != AF_OK)
    abort();
  af_fuzz_state s = {0, 0};
  uint64_t next = af_fuzz_u16(&in);
  for (int op = 0; op < 256 && in.n > 0; op++) {
    uint8_t kind = af_fuzz_u8(&in);
    if (kind == 0xff) {
      (void)af_strike_flush(d, on_strike, &s);
      continue;
    }
    size_t n = af_fuzz_u16(&in) % (AF_FUZZ_CHUNK_MAX + 1);
    float scale = (float)af_fuzz_range(&in, 0.0, 0.01);
    int raw = (kind & 7) == 7;
    for (size_t k = 0; k < n; k++)
      x[k] = af_fuzz_sample(&in, scale, raw);
    if (kind == 0xfe) {
      (void)af_strike_prime(d, x, n);
      continue;
    }
    if ((kind & 0x30) == 0x30) /* a gap of any size */
      next += af_fuzz_u64(&in) >> (kind & 0x0f) * 4;
    else if ((kind & 0x30) == 0x20) /* a restart: backwards */
      next = next > 1000 ? next - af_fuzz_u16(&in) % 1000 : 0;
    if (n > UINT64_MAX - next)
      next = 0;
    if (next + n > s.end)
      s.end = next + n;
    (void)af_strike_write(d, next, x, n, on_strike, &s);
    next += n;
  }
  (void)af_strike_flush(d, on_strike, &s);
  af_strike_destroy(d);
  return 0;
}
