/* test_lane_shared.c — lanes made while the process's shared tables are
 * built and used (the exact damping law's table, the FFTW plans, the
 * response's phase tables, Lamb's roots: impact.c, fft_plan.h, memo.h):
 * two lanes made and run on two threads at once, while the tables are built
 * for the first time, measure a strike to the same bits as each other and as
 * a lane made alone afterwards, and the figures are the physics' (the
 * resonance of the microphone's tone).
 *
 * Signals made here, as test_lane.c makes them (not by the measurement's
 * code): a half-sine force pulse (40 N, 0.5 ms) on a 0.3 N offset with
 * seeded Gaussian noise at 50 kHz; the microphone one decaying sinusoid
 * (682 Hz, Q 30) with noise 40 dB down at 48 kHz. */
#include <math.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <threads.h>

#include "af_test.h"
#include "lane.h"
#include "settings.h"

#define FS_FORCE 50000.0
#define FS_AUDIO 48000.0
#define SPAN_S 1.0
#define STRIKE_S 0.3
#define TONE_HZ 682.0
#define TONE_Q 30.0
#define CHUNK 1024
#define PI 3.14159265358979323846

static float *force, *audio;
static size_t n_force, n_audio;
static af_lane_config cfg;

static af_test_rng rng = {20261124}; /* test noise (af_test.h) */

static void make_signals(void)
{
  n_force = (size_t)(SPAN_S * FS_FORCE);
  n_audio = (size_t)(SPAN_S * FS_AUDIO);
  force = malloc(n_force * sizeof *force);
  audio = malloc(n_audio * sizeof *audio);
  for (size_t k = 0; k < n_force; k++) {
    double u = (double)k / FS_FORCE - STRIKE_S, x = 0.3 + 0.02 * af_test_gauss(&rng);
    if (u > 0.0 && u < 0.5e-3)
      x += 40.0 * sin(PI * u / 0.5e-3);
    force[k] = (float)x;
  }
  for (size_t k = 0; k < n_audio; k++) {
    double u = (double)k / FS_AUDIO - STRIKE_S, x = 0.01 * af_test_gauss(&rng);
    if (u >= 0.0)
      x += exp(-PI * TONE_HZ / TONE_Q * u) * sin(2.0 * PI * TONE_HZ * u);
    audio[k] = (float)x;
  }
}

static void make_config(void)
{
  af_settings st;
  char err[512] = "";
  af_settings_reset(&st);
  if (af_settings_load_yaml(&st, "config/station.yaml", err, sizeof err) != AF_OK ||
      af_settings_load_yaml(&st, "config/jonagold.yaml", err, sizeof err) != AF_OK ||
      af_settings_set_arg(&st, "hammer_mass_kg=0.010", err, sizeof err) != AF_OK ||
      af_settings_set_arg(&st, "hammer_tip_radius_m=0", err, sizeof err) != AF_OK ||
      af_lane_config_derive(&st, &cfg, err, sizeof err) != AF_OK) {
    fprintf(stderr, "config: %s\n", err);
    exit(1);
  }
}

/* What one lane made of the session: its strikes and their reports. */
typedef struct {
  size_t strikes;
  af_measure_report report; /* the first strike's */
  af_status created;
} outcome;

static void on_strike(const af_lane_strike *s, void *user)
{
  outcome *o = user;
  if (o->strikes++ == 0)
    o->report = s->report;
}

/* Makes a lane, feeds the session in chunks (force then audio, by time),
 * with one apple before the strike, and finishes it. */
static int run_lane(void *arg)
{
  outcome *o = arg;
  af_lane *l = NULL;
  const char *what = "";
  memset(o, 0, sizeof *o);
  o->created = af_lane_create(&cfg, on_strike, o, &l, &what);
  if (o->created != AF_OK)
    return 1;
  af_apple a;
  memset(&a, 0, sizeof a);
  a.apple_id = 1;
  a.stamp_ns = (int64_t)llround(0.1 * 1e9);
  a.mass_kg = 0.175;
  a.equatorial_radius_m = 0.0370;
  a.strike_radius_m = 0.040;
  a.confidence = 1.0;
  (void)af_lane_apple(l, &a, a.stamp_ns, NULL);
  for (size_t kf = 0, ka = 0; kf < n_force || ka < n_audio;) {
    const bool take_force = ka >= n_audio || (kf < n_force && kf / FS_FORCE <= ka / FS_AUDIO);
    size_t *k = take_force ? &kf : &ka, end = take_force ? n_force : n_audio;
    size_t n = end - *k < CHUNK ? end - *k : CHUNK;
    double rate = take_force ? FS_FORCE : FS_AUDIO;
    af_chunk c = {(int64_t)llround((double)*k / rate * 1e9),
                  *k,
                  rate,
                  take_force ? "N" : "Pa",
                  take_force ? "force_transducer" : "microphone",
                  (take_force ? force : audio) + *k,
                  n};
    int64_t now = (int64_t)llround((double)(*k + n) / rate * 1e9);
    if (take_force)
      (void)af_lane_force(l, &c, now, NULL);
    else
      (void)af_lane_audio(l, &c, now, NULL);
    *k += n;
  }
  af_lane_finish(l);
  af_lane_destroy(l);
  return 0;
}

/* The figures of a report, bit for bit (NaN equal to NaN). */
static bool same_figures(const af_measure_report *a, const af_measure_report *b)
{
  const double fa[] = {a->resonance_hz,      a->resonance_q,         a->snr_db,
                       a->stiffness_factor,  a->fitted_modulus_pa,   a->fitted_restitution,
                       a->fit_residual,      a->max_shear_stress_pa, a->band_high_hz,
                       a->modes.frequency_hz};
  const double fb[] = {b->resonance_hz,      b->resonance_q,         b->snr_db,
                       b->stiffness_factor,  b->fitted_modulus_pa,   b->fitted_restitution,
                       b->fit_residual,      b->max_shear_stress_pa, b->band_high_hz,
                       b->modes.frequency_hz};
  return memcmp(fa, fb, sizeof fa) == 0 && a->reliable == b->reliable;
}

int main(void)
{
  make_signals();
  make_config();
  outcome o[3];
  thrd_t t[2];
  for (int i = 0; i < 2; i++)
    AF_CHECK(thrd_create(&t[i], run_lane, &o[i]) == thrd_success);
  for (int i = 0; i < 2; i++)
    AF_CHECK(thrd_join(t[i], NULL) == thrd_success);
  run_lane(&o[2]); /* alone, every table built */
  for (int i = 0; i < 3; i++) {
    AF_CHECK_STATUS(o[i].created, AF_OK);
    AF_CHECK(o[i].strikes == 1);
  }
  AF_CHECK(same_figures(&o[0].report, &o[1].report));
  AF_CHECK(same_figures(&o[0].report, &o[2].report));
  /* the physics: the tone's frequency, to its bin's order (1 %) */
  AF_CHECK_REL(o[2].report.resonance_hz, TONE_HZ, 0.01);
  /* the fit runs (its residual compared above; a half-sine is no Hertz
   * pulse, so the lane refuses its E2 and e, which stay NaN) */
  AF_CHECK(o[2].report.fit_residual > 0.0 && o[2].report.fit_residual < 1.0);
  printf("three lanes (two at once on two threads, one alone): resonance %.3f Hz, "
         "fit residual %.4f of the peak, the same bits in all three\n",
         o[2].report.resonance_hz, o[2].report.fit_residual);
  free(force);
  free(audio);
  return af_test_summary("test_lane_shared");
}
