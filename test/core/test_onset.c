/* test_onset.c — the tap-only onset detector (onset.h) on signals of the
 * test's own making (af_test.h's seeded generator, a pink-noise filter and
 * decaying modes written here) and on the real captures in test/data.
 *  - false onsets in 10 minutes of white and of pink noise at 48 kHz, at
 *    the default 12 dB (asserted: none) and, for the figure, lower thresholds;
 *  - 200 taps whose ring starts 15 dB above white noise: every one found,
 *    its onset within one frame (1 ms) of the true start, nothing else;
 *  - the real response channels (strike 20 samples after the capture's
 *    start): one onset, within 1 ms of sample 20, after af_onset_prime;
 *  - a bad configuration, field by field. */
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "af_test.h"
#include "onset.h"

#define RATE_HZ 48000.0
#define PI 3.14159265358979323846
#define CHUNK 480 /* 10 ms chunks, as a node receives them */
#define N_THRESHOLDS 4

static const double thresholds_db[N_THRESHOLDS] = {4.0, 6.0, 9.0, 12.0};

typedef struct {
  uint64_t samples[512];
  size_t n;
} onsets;

static void on_onset(const af_onset_event *ev, void *user)
{
  onsets *o = user;
  if (o->n < sizeof o->samples / sizeof o->samples[0])
    o->samples[o->n] = ev->sample;
  o->n++;
}

/* Paul Kellet's economy pink filter (-3 dB/octave within 0.5 dB over
 * 10 Hz - 20 kHz at 44.1-48 kHz): white in, pink out. */
typedef struct {
  double b0, b1, b2;
} pink_state;

static double pink(pink_state *s, double white)
{
  s->b0 = 0.99765 * s->b0 + white * 0.0990460;
  s->b1 = 0.96300 * s->b1 + white * 0.2965164;
  s->b2 = 0.57000 * s->b2 + white * 1.0526913;
  return s->b0 + s->b1 + s->b2 + white * 0.1848;
}

/* Ten minutes of noise through detectors at each threshold; the counts. */
static void noise_run(bool is_pink, uint64_t seed, size_t counts[N_THRESHOLDS])
{
  af_test_rng rng = {seed};
  pink_state ps = {0.0, 0.0, 0.0};
  af_onset *d[N_THRESHOLDS];
  onsets found[N_THRESHOLDS];
  memset(found, 0, sizeof found);
  for (int k = 0; k < N_THRESHOLDS; k++) {
    af_onset_config c = af_onset_config_default();
    c.sample_rate_hz = RATE_HZ;
    c.snr_db = thresholds_db[k];
    d[k] = NULL;
    AF_CHECK_STATUS(af_onset_create(&c, &d[k]), AF_OK);
  }
  const uint64_t total = (uint64_t)(600.0 * RATE_HZ);
  float buf[CHUNK];
  for (uint64_t at = 0; at < total; at += CHUNK) {
    for (size_t j = 0; j < CHUNK; j++) {
      double w = 0.01 * af_test_gauss(&rng);
      buf[j] = (float)(is_pink ? 0.3 * pink(&ps, w) : w);
    }
    for (int k = 0; k < N_THRESHOLDS; k++)
      if (d[k] != NULL)
        (void)af_onset_write(d[k], at, buf, CHUNK, on_onset, &found[k]);
  }
  for (int k = 0; k < N_THRESHOLDS; k++) {
    counts[k] = found[k].n;
    af_onset_destroy(d[k]);
  }
}

static void test_false_onsets(void)
{
  for (int pinkness = 0; pinkness < 2; pinkness++) {
    size_t counts[N_THRESHOLDS];
    noise_run(pinkness == 1, 1000u + (uint64_t)pinkness, counts);
    for (int k = 0; k < N_THRESHOLDS; k++)
      printf("false onsets in 10 min of %s noise at onset_snr_db %.0f: %zu (%.2f per minute)\n",
             pinkness ? "pink" : "white", thresholds_db[k], counts[k], (double)counts[k] / 10.0);
    AF_CHECK(counts[N_THRESHOLDS - 1] == 0); /* the default 12 dB: none in 10 min */
    if (pinkness == 1)
      AF_CHECK(counts[0] > 0); /* the count can fail: 4 dB is too low for pink noise */
  }
}

/* A tap: three decaying modes (their own set, not the package's synth),
 * mean square at the start = ring_snr x noise variance. */
static double tap_sample(double t_s, double amp)
{
  static const double f_hz[3] = {612.0, 913.0, 1175.0}, q[3] = {25.0, 30.0, 35.0},
                      a[3] = {0.6, 1.0, 0.4};
  double y = 0.0;
  for (int k = 0; k < 3; k++)
    y += a[k] * exp(-PI * f_hz[k] * t_s / q[k]) * sin(2.0 * PI * f_hz[k] * t_s);
  return amp * y;
}

/* n_taps taps at ring_snr_db (their first millisecond's mean square over
 * the noise variance); found: how many onsets lie within 1 ms of a tap. */
static void test_taps(double ring_snr_db, size_t min_found)
{
  const double sigma = 0.01, spacing_s = 0.3;
  /* mean square of the first millisecond of the unit tap, from the samples */
  double ms = 0.0;
  for (int j = 0; j < 48; j++)
    ms += tap_sample(j / RATE_HZ, 1.0) * tap_sample(j / RATE_HZ, 1.0);
  ms /= 48.0;
  const double amp = sqrt(sigma * sigma * pow(10.0, ring_snr_db / 10.0) / ms);
  const size_t n_taps = 200;
  const size_t n = (size_t)((0.5 + spacing_s * (double)n_taps) * RATE_HZ);
  float *x = malloc(n * sizeof *x);
  uint64_t *truth = malloc(n_taps * sizeof *truth);
  af_test_rng rng = {77};
  for (size_t i = 0; i < n; i++)
    x[i] = (float)(sigma * af_test_gauss(&rng));
  for (size_t k = 0; k < n_taps; k++) {
    /* 0.5 s of noise first (the warm-up), then a tap every 0.3 s +- 20 ms */
    truth[k] = (uint64_t)((0.5 + spacing_s * (double)k + 0.02 * af_test_uniform(&rng)) * RATE_HZ);
    for (size_t j = 0; j < (size_t)(0.25 * RATE_HZ) && truth[k] + j < n; j++)
      x[truth[k] + j] += (float)tap_sample((double)j / RATE_HZ, amp);
  }
  af_onset_config c = af_onset_config_default();
  c.sample_rate_hz = RATE_HZ;
  af_onset *d = NULL;
  AF_CHECK_STATUS(af_onset_create(&c, &d), AF_OK);
  onsets found;
  memset(&found, 0, sizeof found);
  for (size_t at = 0; at < n; at += CHUNK)
    (void)af_onset_write(d, at, x + at, n - at < CHUNK ? n - at : CHUNK, on_onset, &found);
  /* each tap's onset: the nearest; within 1 ms counts as found */
  size_t hits = 0;
  double worst_ms = 0.0;
  for (size_t k = 0, j = 0; k < n_taps; k++) {
    while (j + 1 < found.n && j + 1 < 512 && found.samples[j + 1] <= truth[k] + 48)
      j++;
    const double err_ms = fabs((double)found.samples[j] - (double)truth[k]) / RATE_HZ * 1e3;
    if (j < found.n && err_ms <= 1.0) {
      hits++;
      worst_ms = fmax(worst_ms, err_ms);
    }
  }
  printf("taps at %.0f dB ring SNR (first ms): %zu of %zu found within 1 ms (worst %.3f ms), "
         "%zu onsets in all\n",
         ring_snr_db, hits, n_taps, worst_ms, found.n);
  AF_CHECK(hits >= min_found);
  AF_CHECK(found.n <= n_taps); /* nothing but the taps */
  af_onset_destroy(d);
  free(x);
  free(truth);
}

/* The real response channels: 25,600 Hz, strike at sample 20. */
static void test_real_captures(void)
{
  for (int cap = 4; cap <= 5; cap++) {
    char path[256];
    snprintf(path, sizeof path, "test/data/hammer_capture_%d.response.f32", cap);
    FILE *f = fopen(path, "rb");
    AF_CHECK(f != NULL);
    if (f == NULL)
      continue;
    float *x = malloc(25600 * sizeof *x);
    size_t n = fread(x, sizeof *x, 25600, f);
    fclose(f);
    AF_CHECK(n == 25600);
    af_onset_config c = af_onset_config_default();
    c.sample_rate_hz = 25600.0;
    af_onset *d = NULL;
    AF_CHECK_STATUS(af_onset_create(&c, &d), AF_OK);
    AF_CHECK_STATUS(af_onset_prime(d, x, n), AF_OK);
    onsets found;
    memset(&found, 0, sizeof found);
    (void)af_onset_write(d, 0, x, n, on_onset, &found);
    printf("capture %d: %zu onset(s), first at sample %lld (strike at 20)\n", cap, found.n,
           found.n ? (long long)found.samples[0] : -1LL);
    AF_CHECK(found.n == 1);
    AF_CHECK(found.n >= 1 && fabs((double)found.samples[0] - 20.0) <= 0.001 * 25600.0);
    af_onset_destroy(d);
    free(x);
  }
}

static void test_config(void)
{
  const af_onset_config d = af_onset_config_default();
  af_onset_config c;
  af_onset *o = NULL;
  const char *field = NULL;
  AF_CHECK_STATUS(af_onset_config_check(&d, &field), AF_OK);
  c = d, c.frame_s = 3.0 / d.sample_rate_hz;
  AF_CHECK(af_onset_config_check(&c, &field) == AF_EINVAL && strcmp(field, "onset_frame_s") == 0);
  c = d, c.snr_db = 0.0;
  AF_CHECK(af_onset_config_check(&c, &field) == AF_EINVAL && strcmp(field, "onset_snr_db") == 0);
  c = d, c.holdoff_s = d.frame_s / 2.0;
  AF_CHECK(af_onset_config_check(&c, &field) == AF_EINVAL && strcmp(field, "onset_holdoff_s") == 0);
  c = d, c.floor_time_constant_s = NAN;
  AF_CHECK(af_onset_config_check(&c, &field) == AF_EINVAL &&
           strcmp(field, "onset_floor_time_constant_s") == 0);
  AF_CHECK_STATUS(af_onset_create(&c, &o), AF_EINVAL);
  AF_CHECK(o == NULL);
  AF_CHECK_STATUS(af_onset_write(NULL, 0, NULL, 0, NULL, NULL), AF_EINVAL);
  AF_CHECK(isnan(af_onset_floor(NULL)));
}

int main(void)
{
  test_config();
  test_real_captures();
  test_taps(18.0, 200); /* every one */
  test_taps(15.0, 190); /* a tap split over two frames may stay below 12 dB in both */
  test_false_onsets();
  return af_test_summary("test_onset");
}
