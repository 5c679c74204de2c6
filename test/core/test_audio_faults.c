/* test_audio_faults.c — the audio's own faults, from the samples alone
 * (audio_lag.h: the sound's onset and the lag learned from it; audio_clip.h:
 * a saturated microphone), on signals made here: decaying sinusoids (a 0S2
 * at 682 Hz, Q 30) in seeded Gaussian noise or exact zeros, clipped at a
 * level, quantized to 16 bits. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "af_test.h"
#include "audio_clip.h"
#include "audio_lag.h"

#define FS 48000.0
#define N 24000 /* 0.5 s */
#define PI 3.14159265358979323846

static af_test_rng rng = {20261128};

/* A 682 Hz ring of amplitude amp from sample at on, noise of RMS sd. */
static void ring(float *x, size_t n, size_t at, double amp, double sd)
{
  for (size_t k = 0; k < n; k++) {
    double v = sd * af_test_gauss(&rng);
    if (k >= at) {
      const double t = (double)(k - at) / FS;
      v += amp * exp(-PI * 682.0 / 30.0 * t) * sin(2.0 * PI * 682.0 * t);
    }
    x[k] = (float)v;
  }
}

static void test_onset(void)
{
  static float x[N];
  size_t at = 0;
  /* 30 dB over the noise: found within a block (48 samples) after the true onset. */
  ring(x, N, 12000, 1.0, 1.0 / sqrt(2.0) / pow(10.0, 1.5));
  AF_CHECK(af_audio_onset_find(x, N, 48, &at));
  AF_CHECK(at >= 12000 && at <= 12000 + 48);
  printf("onset at 30 dB: sample %zu (true 12000)\n", at);
  /* Exact zeros before it: found at its first non-zero sample. */
  ring(x, N, 7000, 0.5, 0.0);
  AF_CHECK(af_audio_onset_find(x, N, 48, &at) && at >= 7000 && at <= 7002);
  /* Noise alone, and a constant level: no onset. */
  ring(x, N, N, 1.0, 0.01);
  AF_CHECK(!af_audio_onset_find(x, N, 48, &at));
  for (size_t k = 0; k < N; k++)
    x[k] = 0.25f;
  AF_CHECK(!af_audio_onset_find(x, N, 48, &at));
  /* Too short for the reference and a block: none. */
  AF_CHECK(!af_audio_onset_find(x, 10 * 48, 48, &at));
  AF_CHECK(!af_audio_onset_find(NULL, N, 48, &at));
}

static void test_learn(void)
{
  af_audio_lag g;
  af_audio_lag_reset(&g);
  AF_CHECK(isnan(g.median_s) && g.applied_s == 0.0);
  /* 4 strikes: not judged yet, nothing applied. */
  const double lags[] = {0.0500, 0.0502, 0.0499, 0.0501, 0.0500, 0.0503};
  for (size_t k = 0; k < 4; k++)
    AF_CHECK(!af_audio_lag_push(&g, lags[k], true));
  AF_CHECK(isnan(g.median_s) && !g.stable && g.applied_s == 0.0);
  /* The 5th: median 0.0500, MAD 0.0001 s: stable, applied. */
  AF_CHECK(!af_audio_lag_push(&g, lags[4], true));
  AF_CHECK_ABS(g.median_s, 0.0500, 1e-12);
  AF_CHECK_ABS(g.mad_s, 0.0001, 1e-12);
  AF_CHECK(g.stable && g.applied_s == g.median_s);
  /* A strike 6 ms off a stable median: a move, counted. */
  AF_CHECK(af_audio_lag_push(&g, 0.056, true) && g.moves == 1);
  /* Learning off: measured, never applied. */
  af_audio_lag_reset(&g);
  for (size_t k = 0; k < 6; k++)
    (void)af_audio_lag_push(&g, lags[k], false);
  AF_CHECK(g.stable && g.applied_s == 0.0);
  /* A median inside the 2 ms dead band is not applied. */
  af_audio_lag_reset(&g);
  for (size_t k = 0; k < 6; k++)
    (void)af_audio_lag_push(&g, 0.001, true);
  AF_CHECK(g.stable && g.applied_s == 0.0);
}

static void test_clip(void)
{
  static float x[N];
  af_audio_clip c;
  /* Clean, loud: not clipped. */
  ring(x, 2400, 100, 0.8, 1e-3);
  af_audio_clip_check(x, 2400, &c);
  AF_CHECK(!c.clipped && c.flat_tops < AF_AUDIO_CLIP_MIN_TOPS);
  /* Clipped at half its peak: flat tops in many cycles. */
  for (size_t k = 0; k < 2400; k++)
    x[k] = x[k] > 0.4f ? 0.4f : x[k] < -0.4f ? -0.4f : x[k];
  af_audio_clip_check(x, 2400, &c);
  AF_CHECK(c.clipped && c.flat_tops >= AF_AUDIO_CLIP_MIN_TOPS);
  AF_CHECK(c.max == (double)0.4f && c.min == (double)-0.4f);
  printf("clipped at 0.4: %zu samples at the extremes, %zu flat tops\n", c.at_extremes,
         c.flat_tops);
  /* Pinned at full scale: most samples at it (the 46,881 of 48,000),
   * the others anywhere below. */
  for (size_t k = 0; k < 2400; k++)
    x[k] = k % 40 == 0 ? (float)(2.0 * af_test_uniform(&rng) - 1.0) : 1.0f;
  af_audio_clip_check(x, 2400, &c);
  AF_CHECK(c.clipped);
  /* A quiet 16-bit ring of a few codes (peak 40 LSB): not judged. */
  ring(x, 2400, 100, 40.0 / 32768.0, 0.0);
  for (size_t k = 0; k < 2400; k++)
    x[k] = (float)(round(x[k] * 32768.0) / 32768.0);
  af_audio_clip_check(x, 2400, &c);
  AF_CHECK(!c.clipped);
  /* A loud 16-bit ring, not clipped: not clipped. */
  ring(x, 2400, 100, 0.9, 0.0);
  for (size_t k = 0; k < 2400; k++)
    x[k] = (float)(round(x[k] * 32767.0) / 32767.0);
  af_audio_clip_check(x, 2400, &c);
  AF_CHECK(!c.clipped);
  /* +-1 LSB of a 16-bit card's noise: three codes, its extremes held by a
   * third of the samples, not saturation: not judged. */
  for (size_t k = 0; k < 2400; k++)
    x[k] = (float)((double)((int)floor(3.0 * af_test_uniform(&rng)) - 1) / 32768.0);
  af_audio_clip_check(x, 2400, &c);
  AF_CHECK(!c.clipped && c.at_extremes == 0);
  af_audio_clip_check(NULL, 0, &c);
  AF_CHECK(!c.clipped);
}

int main(void)
{
  test_onset();
  test_learn();
  test_clip();
  return af_test_summary("test_audio_faults");
}
