/* test_onset_silence.c — the onset detector (onset.h) on what real sound
 * cards write between sounds, signals made here (af_test.h's seeded
 * generator and a decaying 680 Hz tap written here), 48 kHz in 10 ms chunks:
 *  - 10 s of exact zeros: no onset;
 *  - a tap after 10 s of zeros: one onset, within 1 ms of its start;
 *  - a noise gate that opens onto noise 20 ms before a tap, with and without
 *    the room's noise heard before the gate closed: one onset, at the tap;
 *  - five taps quantized to 16 bits, with and without +-1 LSB dither, the
 *    quantum known: five onsets;
 *  - a DC step (exact, and under noise): no onset; a tap 0.5 s after it:
 *    one, at the tap. */
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "af_test.h"
#include "onset.h"

#define RATE_HZ 48000.0
#define PI 3.14159265358979323846
#define CHUNK 480           /* 10 ms chunks, as a node receives them */
#define LSB (1.0 / 32768.0) /* one step of 16-bit PCM at full scale 1 */

typedef struct {
  uint64_t samples[64];
  size_t n;
} onsets;

static void on_onset(const af_onset_event *ev, void *user)
{
  onsets *o = user;
  if (o->n < sizeof o->samples / sizeof o->samples[0])
    o->samples[o->n] = ev->sample;
  o->n++;
}

/* A tap: one decaying 680 Hz mode, Q 30, amplitude amp [unit] at t = 0. */
static double tap(double t_s, double amp)
{
  return t_s < 0.0 ? 0.0 : amp * exp(-PI * 680.0 * t_s / 30.0) * sin(2.0 * PI * 680.0 * t_s);
}

static size_t samples(double t_s)
{
  return (size_t)llround(t_s * RATE_HZ);
}

/* x[0..n) through a detector (quantum [unit], 0 = unknown) in chunks. */
static onsets run(const float *x, size_t n, double quantum)
{
  af_onset_config c = af_onset_config_default();
  c.sample_rate_hz = RATE_HZ;
  c.quantum = quantum;
  af_onset *d = NULL;
  onsets found;
  memset(&found, 0, sizeof found);
  AF_CHECK_STATUS(af_onset_create(&c, &d), AF_OK);
  for (size_t at = 0; d != NULL && at < n; at += CHUNK)
    (void)af_onset_write(d, at, x + at, n - at < CHUNK ? n - at : CHUNK, on_onset, &found);
  af_onset_destroy(d);
  return found;
}

/* Exactly one onset, within 1 ms of sample at. */
static void check_one_at(const char *what, const onsets *f, size_t at)
{
  const double err_ms =
      f->n >= 1 ? fabs((double)f->samples[0] - (double)at) / RATE_HZ * 1e3 : INFINITY;
  printf("%s: %zu onsets, the first %.3f ms from the tap\n", what, f->n, err_ms);
  AF_CHECK(f->n == 1);
  AF_CHECK(err_ms <= 1.0);
}

static void test_zeros(void)
{
  const size_t n = samples(10.0);
  float *x = calloc(n, sizeof *x);
  onsets f = run(x, n, 0.0);
  printf("10 s of exact zeros: %zu onsets\n", f.n);
  AF_CHECK(f.n == 0);
  f = run(x, n, LSB);
  AF_CHECK(f.n == 0);
  free(x);
}

static void test_tap_after_zeros(void)
{
  const size_t at = samples(10.0), n = samples(11.0);
  float *x = calloc(n, sizeof *x);
  for (size_t i = at; i < n; i++)
    x[i] = (float)tap((double)(i - at) / RATE_HZ, 0.3);
  onsets f = run(x, n, 0.0);
  check_one_at("a tap after 10 s of zeros", &f, at);
  free(x);
}

/* Zeros; the gate opens onto noise of sigma RMS 20 ms before a tap at 2 s;
 * with heard_before, 1 s of that noise first, then the gate closed. */
static void test_gate(double sigma, bool heard_before)
{
  const size_t at = samples(2.0), open = samples(1.98), n = samples(3.0);
  af_test_rng rng = {31};
  float *x = calloc(n, sizeof *x);
  for (size_t i = 0; i < n; i++) {
    const bool passing = i >= open || (heard_before && i < samples(1.0));
    const double noise = sigma * af_test_gauss(&rng);
    x[i] = passing ? (float)(noise + tap(((double)i - (double)at) / RATE_HZ, 0.3)) : 0.0f;
  }
  char what[96];
  snprintf(what, sizeof what, "a gate opening onto %g RMS 20 ms before a tap%s", sigma,
           heard_before ? ", its noise heard before" : "");
  onsets f = run(x, n, 0.0);
  check_one_at(what, &f, at);
  free(x);
}

/* Five taps 0.5 s apart over zeros, rounded to 16 bits, with or without
 * +-1 LSB of uniform dither. */
static void test_16bit(bool dither)
{
  const size_t n = samples(3.0);
  af_test_rng rng = {5};
  float *x = malloc(n * sizeof *x);
  for (size_t i = 0; i < n; i++) {
    double v = 0.0;
    for (int k = 0; k < 5; k++)
      v += tap((double)i / RATE_HZ - 0.5 - 0.5 * k, 0.05);
    const double d = dither ? floor(3.0 * af_test_uniform(&rng)) - 1.0 : 0.0;
    x[i] = (float)(LSB * (round(v / LSB) + d));
  }
  onsets f = run(x, n, LSB);
  size_t near = 0;
  for (size_t k = 0; k < f.n && k < 64; k++)
    for (int j = 0; j < 5; j++)
      near += fabs((double)f.samples[k] - (0.5 + 0.5 * j) * RATE_HZ) <= 48.0;
  printf("five 16-bit taps over zeros%s: %zu onsets, %zu within 1 ms of a tap\n",
         dither ? ", +-1 LSB dither" : "", f.n, near);
  AF_CHECK(f.n == 5 && near == 5);
  free(x);
}

/* Zeros (or noise of sigma RMS) with a step to 0.1 at 1 s; a tap at 1.5 s
 * when with_tap. */
static void test_dc_step(double sigma, bool with_tap)
{
  const size_t step = samples(1.0), at = samples(1.5), n = samples(3.0);
  af_test_rng rng = {11};
  float *x = malloc(n * sizeof *x);
  for (size_t i = 0; i < n; i++) {
    double v = (i >= step ? 0.1 : 0.0) + sigma * af_test_gauss(&rng);
    if (with_tap)
      v += tap(((double)i - (double)at) / RATE_HZ, 0.3);
    x[i] = (float)v;
  }
  onsets f = run(x, n, 0.0);
  if (with_tap) {
    char what[96];
    snprintf(what, sizeof what, "a DC step of 0.1 over %g RMS, a tap 0.5 s after", sigma);
    check_one_at(what, &f, at);
  } else {
    printf("a DC step of 0.1 over %g RMS: %zu onsets\n", sigma, f.n);
    AF_CHECK(f.n == 0);
  }
  free(x);
}

static void test_config(void)
{
  af_onset_config c = af_onset_config_default();
  const char *field = NULL;
  c.floor_rms = 0.0;
  AF_CHECK(af_onset_config_check(&c, &field) == AF_EINVAL && strcmp(field, "onset_floor") == 0);
  c = af_onset_config_default();
  c.quantum = -1.0;
  AF_CHECK(af_onset_config_check(&c, &field) == AF_EINVAL && strcmp(field, "quantum") == 0);
}

int main(void)
{
  test_zeros();
  test_tap_after_zeros();
  test_gate(1e-3, false);
  test_gate(1e-3, true);
  test_gate(1e-2, false);
  test_16bit(false);
  test_16bit(true);
  test_dc_step(0.0, false);
  test_dc_step(1e-3, false);
  test_dc_step(0.0, true);
  test_dc_step(1e-3, true);
  test_config();
  return af_test_summary("test_onset_silence");
}
