/* test_fit.c — the inverse fit against pulses synthesised from the impact
 * model with known truth: noise-free recovery, 40 dB SNR accuracy with v0
 * measured and free, plausibility of the standard errors, garbage input.
 *
 * Synthesis by synth.h, independent of the fit's own sampling: the model is
 * run at dt / 200 and read by linear interpolation at k dt - t0. Windows as
 * the detector cuts them (af_strike_event): from the first sample at or
 * after the contact start to the last at or before its end, so t0 = -u dt
 * with u uniform in [0, 1); or padded, with the contact starting
 * SYNTH_PRE + u samples in and SYNTH_POST quiet samples after it. White
 * Gaussian noise of RMS peak / 100 (SNR = 20 log10(peak / RMS) = 40 dB),
 * seeded. The fit starts from the nominal apple (8 MPa, e 0.6, v0 1.4 m/s)
 * and the detector's contact start, off by up to half a sample. */
#include "fit.h"

#include <math.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdio.h>

#include "af_test.h"
#include "synth.h"

#define DT_S 20e-6 /* 50 kHz */
#define SYNTH_OVERSAMPLE 200
#define SYNTH_CAP 60000
#define SYNTH_PRE 5
#define SYNTH_POST 8
#define MAX_SAMPLES 256
#define SNR_DB 40.0
#ifndef TEST_SEED
#define TEST_SEED 20240611 /* any seed passes; this one is reported */
#endif
#define PI 3.14159265358979323846

static double synth_fine_n[SYNTH_CAP];

typedef struct {
  af_impact_params truth;
  double t0_s;           /* true contact start */
  double t0_guess_s;     /* the detector's estimate */
  double contact_time_s; /* true */
  double pulse_n[MAX_SAMPLES];
  size_t n;
} strike;

/* A pulse from truth in a detector's or a padded window, white noise at
 * snr_db (none when infinite). */
static void synth(af_impact *im, af_synth_rng *g, const af_impact_params *truth, bool padded,
                  double snr_db, strike *s)
{
  af_synth_pulse p;
  s->n = 0;
  af_status st =
      af_synth_pulse_model(im, truth, DT_S / SYNTH_OVERSAMPLE, synth_fine_n, SYNTH_CAP, &p);
  AF_CHECK_STATUS(st, AF_OK);
  if (st != AF_OK)
    return; /* n = 0: the fit refuses it and the test fails loudly */
  s->truth = *truth;
  s->contact_time_s = p.res.contact_time_s;
  double u = af_synth_uniform(g), end_dt;
  s->t0_s = (padded ? SYNTH_PRE + u : -u) * DT_S;
  s->t0_guess_s = s->t0_s + (af_synth_uniform(g) - 0.5) * DT_S;
  end_dt = (s->t0_s + p.res.contact_time_s) / DT_S;
  s->n = padded ? (size_t)ceil(end_dt) + SYNTH_POST : (size_t)floor(end_dt) + 1;
  for (size_t k = 0; k < s->n; k++)
    s->pulse_n[k] = 0.0;
  af_synth_add_pulse(s->pulse_n, s->n, DT_S, 0.0, &p, s->t0_s, 1.0);
  if (isfinite(snr_db))
    af_synth_add_noise(s->pulse_n, s->n, af_synth_noise_rms(p.res.peak_force_n, snr_db), g);
}

/* The test apples: E2 2..12 MPa x e 0.4..0.8, R2 40 mm, v0 1.4 m/s +- 10 %. */
#define N_APPLES 12
static af_impact_params apple(size_t i)
{
  static const double modulus_pa[] = {2e6, 5e6, 8e6, 12e6};
  static const double restitution[] = {0.4, 0.6, 0.8};
  static const double velocity_m_s[] = {1.26, 1.4, 1.54, 1.33, 1.47};
  af_impact_params p = af_impact_params_default();
  p.fruit_modulus_pa = modulus_pa[i % 4];
  p.restitution = restitution[(i / 4) % 3];
  p.velocity_m_s = velocity_m_s[i % 5];
  return p;
}

static double contact_time_of_fit(af_impact *im, const strike *s, const af_fit_result *r)
{
  af_impact_params p = s->truth;
  p.fruit_modulus_pa = r->modulus_pa;
  p.restitution = r->restitution;
  p.velocity_m_s = r->velocity_m_s;
  af_impact_result res;
  if (af_impact_execute(im, &p, 1e-6, NULL, NULL, SYNTH_CAP, &res) != AF_OK)
    return NAN;
  return res.contact_time_s;
}

/* Worst errors over a set, and z = error / standard error. */
typedef struct {
  double modulus_rel, restitution, velocity_rel, contact_time_rel, offset_dt;
  double z_modulus, z_restitution, z_velocity, z_contact_time, z2_sum;
  size_t z_count, runs, fits;
} worst;

static void worst_add(worst *w, af_impact *im, const strike *s, const af_fit_result *r)
{
  const af_impact_params *t = &s->truth;
  double d_mod = r->modulus_pa - t->fruit_modulus_pa, d_e = r->restitution - t->restitution;
  double d_v = r->velocity_m_s - t->velocity_m_s;
  w->modulus_rel = fmax(w->modulus_rel, fabs(d_mod) / t->fruit_modulus_pa);
  w->restitution = fmax(w->restitution, fabs(d_e));
  w->velocity_rel = fmax(w->velocity_rel, fabs(d_v) / t->velocity_m_s);
  w->offset_dt = fmax(w->offset_dt, fabs(r->time_offset_s - s->t0_s) / DT_S);
  double tc = contact_time_of_fit(im, s, r);
  w->contact_time_rel = fmax(w->contact_time_rel, fabs(tc / s->contact_time_s - 1.0));
  w->z_contact_time = fmax(w->z_contact_time, fabs(tc - s->contact_time_s) / r->contact_time_se_s);
  double z[3] = {d_mod / r->modulus_se_pa, d_e / r->restitution_se,
                 r->velocity_se_m_s > 0.0 ? d_v / r->velocity_se_m_s : 0.0};
  w->z_modulus = fmax(w->z_modulus, fabs(z[0]));
  w->z_restitution = fmax(w->z_restitution, fabs(z[1]));
  w->z_velocity = fmax(w->z_velocity, fabs(z[2]));
  w->z2_sum += z[0] * z[0] + z[1] * z[1];
  w->z_count += 2;
  w->runs += r->model_runs;
  w->fits++;
}

static void worst_print(const char *name, const worst *w)
{
  printf("%s: worst |dE2| %.4f %%, |de| %.5f, |dv0| %.4f %%, |dt_c| %.4f %%, |dt0| %.4f dt; "
         "max |z| E2 %.2f e %.2f v0 %.2f t_c %.2f, rms z %.2f; %.1f model runs per fit\n",
         name, 100.0 * w->modulus_rel, w->restitution, 100.0 * w->velocity_rel,
         100.0 * w->contact_time_rel, w->offset_dt, w->z_modulus, w->z_restitution, w->z_velocity,
         w->z_contact_time, sqrt(w->z2_sum / (double)w->z_count),
         (double)w->runs / (double)w->fits);
}

static const char *window_name(bool padded)
{
  return padded ? "padded window" : "detector's window";
}

/* Noise-free pulses, everything free: the truth to 0.1 % (measured ~1e-5). */
static void test_noise_free(af_impact *im, af_synth_rng *rng, bool padded)
{
  af_fit_config cfg = af_fit_config_default();
  af_fit *f = NULL;
  AF_CHECK_STATUS(af_fit_create(&cfg, &f), AF_OK);
  af_impact_params start = af_impact_params_default();
  worst w = {0};
  for (size_t i = 0; i < N_APPLES; i++) {
    strike s;
    af_impact_params truth = apple(i);
    synth(im, rng, &truth, padded, INFINITY, &s);
    af_fit_result r;
    AF_CHECK_STATUS(af_fit_execute(f, &start, s.pulse_n, s.n, DT_S, s.t0_guess_s, &r), AF_OK);
    AF_CHECK(r.status == AF_OK);
    AF_CHECK_REL(r.modulus_pa, truth.fruit_modulus_pa, 1e-3);
    AF_CHECK_ABS(r.restitution, truth.restitution, 1e-3 * truth.restitution);
    AF_CHECK_REL(r.velocity_m_s, truth.velocity_m_s, 1e-3);
    AF_CHECK_ABS(r.time_offset_s, s.t0_s, 1e-3 * DT_S);
    AF_CHECK_REL(r.contact_time_s, s.contact_time_s, 1e-3);
    AF_CHECK(r.relative_residual < 1e-4);
    worst_add(&w, im, &s, &r);
  }
  char name[96];
  snprintf(name, sizeof name, "noise-free, v0 and t0 free, %s", window_name(padded));
  worst_print(name, &w);
  af_fit_destroy(f);
}

/* Checks one noisy fit against its truth. The fixed bounds of the station's
 * requirement (E2 within 3 %, e within 0.05, the fitted model's contact time
 * within 1 %) are applied where the fit's own standard error makes them
 * bounds of at least 3 standard errors, and counted. The truth lies within
 * Z_MAX standard errors everywhere: the standard errors' honesty is tested
 * by the rms z of the set, Z_MAX bounds single outliers (a run makes ~600
 * such checks; for Gaussian errors P(|z| > 4.5) = 7e-6 each, 0.4 % per run;
 * over 1000 random apples the largest |z| seen was 4.1). */
#define Z_MAX 4.5
typedef struct {
  size_t fits, modulus_bounded, restitution_bounded, contact_time_bounded;
} bounds;

static void check_noisy(af_impact *im, const strike *s, const af_fit_result *r, bounds *b)
{
  const af_impact_params *t = &s->truth;
  double tc = contact_time_of_fit(im, s, r);
  AF_CHECK_ABS(r->modulus_pa, t->fruit_modulus_pa, Z_MAX * r->modulus_se_pa);
  AF_CHECK_ABS(r->restitution, t->restitution, Z_MAX * r->restitution_se);
  AF_CHECK_ABS(r->velocity_m_s, t->velocity_m_s, Z_MAX * r->velocity_se_m_s);
  AF_CHECK_ABS(r->time_offset_s, s->t0_s, Z_MAX * r->time_offset_se_s);
  AF_CHECK_ABS(tc, s->contact_time_s, Z_MAX * r->contact_time_se_s);
  AF_CHECK_ABS(r->relative_residual, 0.01, 0.003); /* the noise: RMS / peak = 1 % */
  if (3.0 * r->modulus_se_pa <= 0.03 * r->modulus_pa) {
    AF_CHECK_REL(r->modulus_pa, t->fruit_modulus_pa, 0.03);
    b->modulus_bounded++;
  }
  if (3.0 * r->restitution_se <= 0.05) {
    AF_CHECK_ABS(r->restitution, t->restitution, 0.05);
    b->restitution_bounded++;
  }
  if (3.0 * r->contact_time_se_s <= 0.01 * r->contact_time_s) {
    AF_CHECK_REL(tc, s->contact_time_s, 0.01);
    b->contact_time_bounded++;
  }
  b->fits++;
}

/* 40 dB SNR, 2 x 12 apples, v0 measured or free (t0 free in both), in the
 * detector's or a padded window. With v0
 * free, E2, e and v0 trade off through the pulse's amplitude, width and
 * asymmetry and E2's standard error reaches 5 % at e = 0.4; even with v0
 * measured the contact time of a soft, damped apple is known to ~0.4 % only
 * (its unloading tail is small and slow). The standard errors must be
 * neither inflated nor optimistic: rms z near 1. */
static void test_noisy(af_impact *im, af_synth_rng *rng, bool fit_velocity, bool padded)
{
  af_fit_config cfg = af_fit_config_default();
  cfg.fit_velocity = fit_velocity;
  af_fit *f = NULL;
  AF_CHECK_STATUS(af_fit_create(&cfg, &f), AF_OK);
  worst w = {0};
  bounds b = {0};
  for (size_t i = 0; i < 2 * N_APPLES; i++) {
    strike s;
    af_impact_params truth = apple(i);
    synth(im, rng, &truth, padded, SNR_DB, &s);
    af_impact_params start = af_impact_params_default();
    if (!fit_velocity)
      start.velocity_m_s = truth.velocity_m_s; /* measured */
    af_fit_result r;
    AF_CHECK_STATUS(af_fit_execute(f, &start, s.pulse_n, s.n, DT_S, s.t0_guess_s, &r), AF_OK);
    if (!fit_velocity)
      AF_CHECK(r.velocity_m_s == truth.velocity_m_s && r.velocity_se_m_s == 0.0);
    check_noisy(im, &s, &r, &b);
    worst_add(&w, im, &s, &r);
  }
  AF_CHECK_ABS(sqrt(w.z2_sum / (double)w.z_count), 1.0, 0.5);
  /* the fixed bounds are not vacuous (applied over 31 seeds: E2 to 20-24 of
   * 24 with v0 measured, 8-10 free; e to all measured, 21-24 free; t_c to
   * 14-16 measured, 6-8 free) */
  AF_CHECK(b.modulus_bounded >= b.fits / 6 && b.contact_time_bounded >= b.fits / 6);
  AF_CHECK(b.restitution_bounded >= (fit_velocity ? b.fits / 2 : b.fits));
  char name[160];
  snprintf(name, sizeof name, "40 dB, v0 %s, %s (bounds applied: E2 %zu, e %zu, t_c %zu of %zu)",
           fit_velocity ? "free" : "measured", window_name(padded), b.modulus_bounded,
           b.restitution_bounded, b.contact_time_bounded, b.fits);
  worst_print(name, &w);
  af_fit_destroy(f);
}

/* Fixed parameters stay fixed; a 40 MPa hammer (E* < E2) and the paper's
 * damping law are fitted through the same path. Noise-free. */
static void test_variants(af_impact *im, af_synth_rng *rng)
{
  af_fit_config cfg = af_fit_config_default();
  cfg.fit_velocity = false;
  cfg.fit_time_offset = false;
  cfg.damping = AF_DAMPING_PAPER;
  af_fit *f = NULL;
  AF_CHECK_STATUS(af_fit_create(&cfg, &f), AF_OK);
  af_impact_params truth = apple(5);
  truth.damping = AF_DAMPING_PAPER;
  truth.hammer_modulus_pa = 40e6;
  strike s;
  synth(im, rng, &truth, true, INFINITY, &s);
  af_impact_params start = af_impact_params_default(); /* exact law: overridden by cfg */
  start.hammer_modulus_pa = 40e6;
  start.velocity_m_s = truth.velocity_m_s;
  af_fit_result r;
  AF_CHECK_STATUS(af_fit_execute(f, &start, s.pulse_n, s.n, DT_S, s.t0_s, &r), AF_OK);
  AF_CHECK_REL(r.modulus_pa, truth.fruit_modulus_pa, 1e-3);
  AF_CHECK_ABS(r.restitution, truth.restitution, 1e-3);
  AF_CHECK(r.time_offset_s == s.t0_s && r.time_offset_se_s == 0.0);
  AF_CHECK(r.velocity_m_s == truth.velocity_m_s && r.velocity_se_m_s == 0.0);
  af_fit_destroy(f);
}

/* One workspace, pulses of different lengths in turn: no state leaks from
 * one fit into the next (the same pulse gives the same bits). */
static void test_reuse(af_impact *im, af_synth_rng *rng)
{
  af_fit_config cfg = af_fit_config_default();
  af_fit *f = NULL;
  AF_CHECK_STATUS(af_fit_create(&cfg, &f), AF_OK);
  af_impact_params start = af_impact_params_default();
  af_impact_params soft = apple(0), hard = apple(3);
  strike a, b;
  synth(im, rng, &soft, false, SNR_DB, &a);
  synth(im, rng, &hard, false, SNR_DB, &b);
  AF_CHECK(a.n != b.n);
  af_fit_result r1, r2, r3;
  AF_CHECK_STATUS(af_fit_execute(f, &start, a.pulse_n, a.n, DT_S, a.t0_guess_s, &r1), AF_OK);
  AF_CHECK_STATUS(af_fit_execute(f, &start, b.pulse_n, b.n, DT_S, b.t0_guess_s, &r2), AF_OK);
  AF_CHECK_STATUS(af_fit_execute(f, &start, a.pulse_n, a.n, DT_S, a.t0_guess_s, &r3), AF_OK);
  AF_CHECK(r1.modulus_pa == r3.modulus_pa && r1.restitution == r3.restitution &&
           r1.model_runs == r3.model_runs);
  af_fit_destroy(f);
}

/* A contact cut short (the detector's truncated flag): the fitted contact
 * reaches beyond the window, AF_ENODATA with the estimate still out. */
static void test_truncated(af_impact *im, af_synth_rng *rng)
{
  af_fit_config cfg = af_fit_config_default();
  af_fit *f = NULL;
  AF_CHECK_STATUS(af_fit_create(&cfg, &f), AF_OK);
  af_impact_params start = af_impact_params_default(), truth = apple(6);
  strike s;
  synth(im, rng, &truth, false, SNR_DB, &s);
  af_fit_result r;
  AF_CHECK_STATUS(af_fit_execute(f, &start, s.pulse_n, s.n * 6 / 10, DT_S, s.t0_guess_s, &r),
                  AF_ENODATA);
  AF_CHECK(isfinite(r.modulus_pa) && r.time_offset_s + r.contact_time_s > (double)s.n * 0.6 * DT_S);
  af_fit_destroy(f);
}

static void test_create_errors(void)
{
  af_fit *f = (af_fit *)&f; /* must be reset to NULL on error */
  af_fit_config cfg = af_fit_config_default();
  AF_CHECK_STATUS(af_fit_create(NULL, &f), AF_EINVAL);
  AF_CHECK(f == NULL);
  AF_CHECK_STATUS(af_fit_create(&cfg, NULL), AF_EINVAL);
  cfg.max_samples = AF_FIT_MIN_SAMPLES - 1;
  AF_CHECK_STATUS(af_fit_create(&cfg, &f), AF_EINVAL);
  cfg = af_fit_config_default();
  cfg.oversample = 0;
  AF_CHECK_STATUS(af_fit_create(&cfg, &f), AF_EINVAL);
  cfg = af_fit_config_default();
  cfg.step_tol = NAN;
  AF_CHECK_STATUS(af_fit_create(&cfg, &f), AF_EINVAL);
  cfg = af_fit_config_default();
  cfg.max_iterations = 0;
  AF_CHECK_STATUS(af_fit_create(&cfg, &f), AF_EINVAL);
  cfg = af_fit_config_default();
  cfg.damping = (af_damping_law)42;
  AF_CHECK_STATUS(af_fit_create(&cfg, &f), AF_EINVAL);
  af_fit_destroy(NULL);
}

/* Bad arguments: AF_EINVAL / AF_ESIZE before any work, values NaN. */
static void test_bad_input(af_impact *im, af_synth_rng *rng)
{
  af_fit_config cfg = af_fit_config_default();
  af_fit *f = NULL;
  AF_CHECK_STATUS(af_fit_create(&cfg, &f), AF_OK);
  af_impact_params start = af_impact_params_default(), truth = apple(2);
  strike s;
  synth(im, rng, &truth, false, SNR_DB, &s);
  af_fit_result r;
  AF_CHECK_STATUS(af_fit_execute(f, &start, s.pulse_n, s.n, DT_S, s.t0_s, NULL), AF_EINVAL);
  AF_CHECK_STATUS(af_fit_execute(NULL, &start, s.pulse_n, s.n, DT_S, s.t0_s, &r), AF_EINVAL);
  AF_CHECK_STATUS(af_fit_execute(f, NULL, s.pulse_n, s.n, DT_S, s.t0_s, &r), AF_EINVAL);
  AF_CHECK_STATUS(af_fit_execute(f, &start, NULL, s.n, DT_S, s.t0_s, &r), AF_EINVAL);
  AF_CHECK_STATUS(af_fit_execute(f, &start, s.pulse_n, 0, DT_S, s.t0_s, &r), AF_EINVAL);
  AF_CHECK_STATUS(af_fit_execute(f, &start, s.pulse_n, AF_FIT_MIN_SAMPLES - 1, DT_S, s.t0_s, &r),
                  AF_EINVAL);
  AF_CHECK(r.status == AF_EINVAL && isnan(r.modulus_pa) && r.model_runs == 0);
  AF_CHECK_STATUS(af_fit_execute(f, &start, s.pulse_n, s.n, 0.0, s.t0_s, &r), AF_EINVAL);
  AF_CHECK_STATUS(af_fit_execute(f, &start, s.pulse_n, s.n, NAN, s.t0_s, &r), AF_EINVAL);
  AF_CHECK_STATUS(af_fit_execute(f, &start, s.pulse_n, s.n, DT_S, INFINITY, &r), AF_EINVAL);
  static double too_long_n[MAX_SAMPLES + 1];
  for (size_t k = 0; k <= MAX_SAMPLES; k++)
    too_long_n[k] = k < s.n ? s.pulse_n[k] : 0.0;
  AF_CHECK_STATUS(af_fit_execute(f, &start, too_long_n, MAX_SAMPLES + 1, DT_S, s.t0_s, &r),
                  AF_ESIZE);
  af_impact_params bad = start;
  bad.restitution = 1.0; /* the logit needs an inner start */
  AF_CHECK_STATUS(af_fit_execute(f, &bad, s.pulse_n, s.n, DT_S, s.t0_s, &r), AF_EINVAL);
  bad = start;
  bad.hammer_mass_kg = -1.0; /* rejected by the impact model */
  AF_CHECK_STATUS(af_fit_execute(f, &bad, s.pulse_n, s.n, DT_S, s.t0_s, &r), AF_EINVAL);
  double saved = s.pulse_n[3];
  s.pulse_n[3] = NAN;
  AF_CHECK_STATUS(af_fit_execute(f, &start, s.pulse_n, s.n, DT_S, s.t0_s, &r), AF_EINVAL);
  s.pulse_n[3] = saved;
  /* sampled at 1 MHz the start model is 1300 samples: more than the buffer */
  AF_CHECK_STATUS(af_fit_execute(f, &start, s.pulse_n, s.n, 1e-6, s.t0_s, &r), AF_ESIZE);
  af_fit_destroy(f);
}

/* Garbage: no strike in the window. An error status, never AF_OK, within a
 * bounded number of model runs. */
static void test_garbage(af_synth_rng *rng)
{
  af_fit_config cfg = af_fit_config_default();
  af_fit *f = NULL;
  AF_CHECK_STATUS(af_fit_create(&cfg, &f), AF_OK);
  af_impact_params start = af_impact_params_default();
  double pulse_n[MAX_SAMPLES] = {0};
  af_fit_result r;
  AF_CHECK_STATUS(af_fit_execute(f, &start, pulse_n, 65, DT_S, 5 * DT_S, &r), AF_ENODATA);
  for (size_t k = 0; k < 65; k++)
    pulse_n[k] = -20.0 * sin(PI * (double)k / 64.0); /* a pull, not a push */
  AF_CHECK_STATUS(af_fit_execute(f, &start, pulse_n, 65, DT_S, 5 * DT_S, &r), AF_ENODATA);
  /* white noise, with and without an offset, in windows of 5 to 200 samples */
  static const size_t lengths[] = {5, 8, 30, 65, 120, 200};
  size_t ok = 0, max_runs = 0;
  for (size_t i = 0; i < 24; i++) {
    size_t n = lengths[i % 6];
    for (size_t k = 0; k < n; k++)
      pulse_n[k] = 0.4 * af_synth_gauss(rng) + (i % 2 ? 0.3 : 0.0);
    af_status st = af_fit_execute(f, &start, pulse_n, n, DT_S, -0.5 * DT_S, &r);
    ok += st == AF_OK;
    AF_CHECK(st == AF_ENODATA || st == AF_EBUDGET_FIT_ITER || st == AF_ENOCONV ||
             st == AF_ENUMERIC);
    AF_CHECK(r.status == st);
    max_runs = r.model_runs > max_runs ? r.model_runs : max_runs;
  }
  AF_CHECK(ok == 0);
  /* each iteration costs at most 16 trial runs and 3 Jacobian runs */
  AF_CHECK(max_runs <= 2 + 3 + cfg.max_iterations * (16 + 3));
  printf("garbage: at most %zu model runs per noise window\n", max_runs);
  af_fit_destroy(f);
}

int main(void)
{
  af_impact *im = NULL;
  AF_CHECK_STATUS(af_impact_create(&im), AF_OK);
  if (im == NULL)
    return af_test_summary("test_fit");
  af_synth_rng g;
  af_synth_rng_seed(&g, TEST_SEED);
  af_synth_rng *rng = &g;
  test_create_errors();
  test_noise_free(im, rng, false);
  test_noise_free(im, rng, true);
  test_noisy(im, rng, false, false);
  test_noisy(im, rng, true, false);
  test_noisy(im, rng, false, true);
  test_noisy(im, rng, true, true);
  test_truncated(im, rng);
  test_variants(im, rng);
  test_reuse(im, rng);
  test_bad_input(im, rng);
  test_garbage(rng);
  af_impact_destroy(im);
  return af_test_summary("test_fit");
}
