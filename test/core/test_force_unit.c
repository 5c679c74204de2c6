/* test_force_unit.c — a force transducer read through a DAQ in volts
 * (force_unit V, force_sensitivity_v_per_n): the table's checks, and the
 * conversion at the lane's input against hand-computed newtons.
 *
 * The signal is written here (no package synthesis): a half-sine contact of
 * 100 N peak over 24 samples (0.48 ms at 50 kHz; sample 12 is the peak,
 * sin(pi/2) = 1), on seeded noise of 0.02 N RMS, sent in volts with a
 * sensitivity of 2.25 mV/N (an ICP impact hammer's). The ring must hold
 * V / 0.00225 = the newtons written here, in chunks smaller and larger than
 * the conversion block (AF_STREAM_BLOCK), and the strike detector must see
 * the 100 N peak: within 2 % (its parabolic refinement of a sampled peak). */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "af_test.h"
#include "lane.h"
#include "settings.h"

#define FS 50000.0
#define SENS_V_PER_N 0.00225
#define N_SAMPLES 40000 /* 0.8 s */
#define PULSE_AT 20000  /* the contact's first sample (0.4 s) */
#define PULSE_LEN 24
#define PEAK_N 100.0

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

static uint64_t rng_state = 42;
static double uniform(void) /* splitmix64 in (0, 1) */
{
  uint64_t z = (rng_state += 0x9e3779b97f4a7c15ULL);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return ((double)((z ^ (z >> 31)) >> 11) + 0.5) / 9007199254740992.0;
}

/* Settings of the shipped YAML plus sets; derive's status, its message in err. */
static af_status derive(const char *const *sets, size_t n, af_lane_config *cfg, char *err,
                        size_t len)
{
  af_settings st;
  af_settings_reset(&st);
  af_status s = af_settings_load_yaml(&st, "config/station.yaml", err, len);
  if (s == AF_OK)
    s = af_settings_load_yaml(&st, "config/jonagold.yaml", err, len);
  if (s == AF_OK)
    s = af_settings_set_arg(&st, "hammer_mass_kg=0.010", err, len);
  if (s == AF_OK)
    s = af_settings_set_arg(&st, "hammer_tip_radius_m=0", err, len);
  for (size_t k = 0; s == AF_OK && k < n; k++)
    s = af_settings_set_arg(&st, sets[k], err, len);
  return s == AF_OK ? af_lane_config_derive(&st, cfg, err, len) : s;
}

static void check_error(const char *const *sets, size_t n, const char *want)
{
  af_lane_config cfg;
  char err[512] = "";
  AF_CHECK(derive(sets, n, &cfg, err, sizeof err) == AF_EINVAL);
  if (strcmp(err, want) != 0) {
    fprintf(stderr, "got  '%s'\nwant '%s'\n", err, want);
    AF_CHECK(strcmp(err, want) == 0);
  }
}

static void test_table_checks(void)
{
  af_lane_config cfg;
  char err[512] = "";
  const char *volts[] = {"force_unit=V", "force_sensitivity_v_per_n=0.00225"};
  AF_CHECK(derive(volts, 2, &cfg, err, sizeof err) == AF_OK);
  AF_CHECK(strcmp(cfg.force.units[0], "V") == 0);
  AF_CHECK_REL(cfg.force.to_si, 444.444444444444, 1e-12); /* 1 / 0.00225 N/V */
  AF_CHECK(derive(NULL, 0, &cfg, err, sizeof err) == AF_OK);
  AF_CHECK(strcmp(cfg.force.units[0], "N") == 0 && cfg.force.to_si == 1.0);
  const char *no_sens[] = {"force_unit=V"};
  check_error(no_sens, 1,
              "force_sensitivity_v_per_n = 0 (none), but force_unit = V needs it: a number in "
              "0 or [1e-4, 10] V/N other than 0");
  const char *sens_with_n[] = {"force_sensitivity_v_per_n=0.01"};
  check_error(sens_with_n, 1,
              "force_sensitivity_v_per_n = 0.01 is given but force_unit = N (the sensitivity "
              "converts volts only)");
  const char *too_big[] = {"force_unit=V", "force_sensitivity_v_per_n=20"};
  check_error(too_big, 2,
              "force_sensitivity_v_per_n = 20 is outside the accepted range 0 or [1e-4, 10] V/N");
  const char *too_small[] = {"force_unit=V", "force_sensitivity_v_per_n=5e-5"};
  check_error(too_small, 2,
              "force_sensitivity_v_per_n = 5e-05 is outside the accepted range 0 or [1e-4, 10] "
              "V/N");
  const char *bad_unit[] = {"force_unit=kN"};
  check_error(bad_unit, 1, "force_unit = 'kN' is not one of: N, V");
}

typedef struct {
  int strikes;
  double peak_n;
  double start_sample;
} seen;

static void on_strike(const af_lane_strike *s, void *user)
{
  seen *out = user;
  out->strikes++;
  out->peak_n = s->event->peak_force_n;
  out->start_sample = s->event->start_sample;
}

/* The session in volts through a lane of force_unit V, chunk samples at a time. */
static void run(size_t chunk, const double *newtons, const float *volts)
{
  af_lane_config cfg;
  char err[512] = "";
  const char *sets[] = {"force_unit=V", "force_sensitivity_v_per_n=0.00225"};
  if (derive(sets, 2, &cfg, err, sizeof err) != AF_OK) {
    fprintf(stderr, "derive: %s\n", err);
    AF_CHECK(0);
    return;
  }
  seen got = {0, 0.0, 0.0};
  af_lane *l = NULL;
  const char *what = "";
  AF_CHECK(af_lane_create(&cfg, on_strike, &got, &l, &what) == AF_OK);
  if (!l)
    return;
  for (size_t k = 0; k < N_SAMPLES; k += chunk) {
    size_t n = N_SAMPLES - k < chunk ? N_SAMPLES - k : chunk;
    af_chunk c = {(int64_t)llround((double)k / FS * 1e9), k, FS, "V", "hammer", volts + k, n};
    AF_CHECK(af_lane_force(l, &c, (int64_t)llround((double)(k + n) / FS * 1e9), NULL) ==
             AF_CHUNK_OK);
  }
  /* The ring holds newtons: the contact and the samples around it. */
  float ring[64];
  AF_CHECK(af_ring_read(af_lane_force_stream(l)->ring, PULSE_AT - 20, 64, ring) == AF_OK);
  double worst = 0.0;
  for (int k = 0; k < 64; k++)
    worst = fmax(worst, fabs(ring[k] - newtons[PULSE_AT - 20 + k]));
  AF_CHECK_ABS(worst, 0.0, 1e-5 * PEAK_N); /* float rounding of V and of V / sensitivity */
  AF_CHECK_REL(ring[20 + 12], PEAK_N, 1e-6);
  af_lane_finish(l);
  AF_CHECK(got.strikes == 1);
  AF_CHECK_REL(got.peak_n, PEAK_N, 0.02);
  AF_CHECK_ABS(got.start_sample, PULSE_AT, 2.0);
  af_lane_destroy(l);
}

static void test_lane_input(void)
{
  double *newtons = malloc(N_SAMPLES * sizeof *newtons);
  float *volts = malloc(N_SAMPLES * sizeof *volts);
  if (!newtons || !volts) {
    AF_CHECK(0);
    free(newtons);
    free(volts);
    return;
  }
  for (int k = 0; k < N_SAMPLES; k++) {
    /* Noise: the sum of 12 uniforms less 6 has unit variance. */
    double g = -6.0;
    for (int j = 0; j < 12; j++)
      g += uniform();
    double f = 0.02 * g;
    if (k >= PULSE_AT && k <= PULSE_AT + PULSE_LEN)
      f = PEAK_N * sin(M_PI * (k - PULSE_AT) / PULSE_LEN);
    volts[k] = (float)(f * SENS_V_PER_N);
    newtons[k] = f;
  }
  run(1000, newtons, volts);      /* chunks below the conversion block */
  run(N_SAMPLES, newtons, volts); /* one chunk of ~10 blocks */
  free(newtons);
  free(volts);
}

int main(void)
{
  test_table_checks();
  test_lane_input();
  return af_test_summary("test_force_unit");
}
