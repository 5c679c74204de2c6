/* test_fit_table.c — the fit on the pulse table (af_fit_config.use_table)
 * against the fit on the ODE (use_table false, the reference) on strikes the
 * package did not make, cut by the strike detector as the lane cuts them:
 *
 *  - Hidden-style captures: a damped Hertz strike integrated here by
 *    classical RK4 at 0.25 us in SI units (as test/cli/hertz_strike.py; not
 *    impact.c, not synth.c), its e the restitution it delivers without
 *    gravity (the exact law's definition, PHYSICS.md 2), sampled at 50 and
 *    25.6 kHz by linear interpolation of the fine pulse, with a sub-sample
 *    start, 40 dB white noise (seeded), a 1.5 N offset, a drift, 50 Hz hum,
 *    a short pre-trigger (1 ms); primed and written to af_strike as a
 *    triggered capture. Every event is fitted both ways from the nominal
 *    apple, v0 measured and free.
 *  - The two real impact-hammer captures of test/data (25.6 kHz).
 *  - The fallbacks: a strike beyond the table's chi (e 0.15), one beyond its
 *    gamma (heavy hammer, slow, soft fruit) and a check that must fail
 *    (table_check_se 0) rerun the ODE fit: the same result, bit for bit, the
 *    named path, the counts.
 * Asserted: the same status both ways; E2, e (and v0) of the two fits within
 * 0.25 of the fit's standard error (the check allows 0.1 to first order);
 * the table answering (no fallback) every in-range strike; the truth within
 * 4.5 standard errors. Printed: the errors against the truth both ways, the
 * fallbacks, the CPU time per fit (median; not asserted). */
#define _POSIX_C_SOURCE 200809L /* clock_gettime */
#include "fit.h"

#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "af_test.h"
#include "strike.h"

#define PI 3.14159265358979323846
#define RK4_STEP_S 0.25e-6 /* the synthesizer's step [s] */
#define FINE_CAP 40000     /* fine samples [RK4 steps]: 10 ms of contact */
#define CAPTURE_CAP 8192   /* capture samples */
#define PRE_TRIGGER_S 1e-3 /* strike this long after the capture starts [s] */
#define CAPTURE_S 0.1      /* capture length [s] */
#define CHUNK 1024         /* samples per write */
#define SNR_DB 40.0
#define OFFSET_N 1.5  /* DC offset [N] */
#define DRIFT_N_S 2.0 /* baseline drift [N/s] */
#define HUM_HZ 50.0   /* mains hum, amplitude = the noise's RMS */
#define AGREE_SE 0.25 /* table vs ODE, in standard errors */
#define Z_MAX 4.5     /* truth vs fit, in standard errors (as test_fit.c) */
#define MAX_FITS 512

static double fine_n[FINE_CAP];
static float capture[CAPTURE_CAP];

/* ---- the independent synthesizer -------------------------------------- */

typedef struct {
  double m1_kg, v0_m_s, e2_pa, nu2, r2_m, chi, g_m_s2;
} rk4_strike;

/* Hertz force with hysteresis damping, F = K d^1.5 (1 + chi v / v0). */
static double rk4_force(const rk4_strike *s, double k_stiff, double d, double v)
{
  if (d <= 0.0)
    return 0.0;
  double f = k_stiff * pow(d, 1.5) * (1.0 + s->chi * v / s->v0_m_s);
  return f > 0.0 ? f : 0.0;
}

/* Integrates the contact by RK4; fine_n[j] = F(j h). Returns the samples
 * written, *tc_s the contact time (linear crossing), *v_end_m_s the hammer's
 * velocity there (negative: leaving). */
static size_t rk4_pulse(const rk4_strike *s, double *tc_s, double *v_end_m_s)
{
  const double h = RK4_STEP_S, m = s->m1_kg;
  double k_stiff = 4.0 / 3.0 * s->e2_pa / (1.0 - s->nu2 * s->nu2) * sqrt(s->r2_m);
  double d = 0.0, v = s->v0_m_s, t = 0.0;
  size_t n = 1;
  fine_n[0] = 0.0;
  while (n < FINE_CAP) {
    double a1 = s->g_m_s2 - rk4_force(s, k_stiff, d, v) / m;
    double d2 = d + 0.5 * h * v, v2 = v + 0.5 * h * a1;
    double a2 = s->g_m_s2 - rk4_force(s, k_stiff, d2, v2) / m;
    double d3 = d + 0.5 * h * v2, v3 = v + 0.5 * h * a2;
    double a3 = s->g_m_s2 - rk4_force(s, k_stiff, d3, v3) / m;
    double d4 = d + h * v3, v4 = v + h * a3;
    double a4 = s->g_m_s2 - rk4_force(s, k_stiff, d4, v4) / m;
    double d_new = d + h / 6.0 * (v + 2.0 * v2 + 2.0 * v3 + v4);
    double v_new = v + h / 6.0 * (a1 + 2.0 * a2 + 2.0 * a3 + a4);
    if (d_new <= 0.0) {
      double frac = d / (d - d_new);
      *tc_s = t + frac * h;
      *v_end_m_s = v + frac * (v_new - v);
      return n;
    }
    d = d_new;
    v = v_new;
    t += h;
    fine_n[n++] = rk4_force(s, k_stiff, d, v);
  }
  *tc_s = NAN;
  return 0;
}

/* The restitution chi delivers without gravity (the exact law's e). */
static double rk4_restitution(rk4_strike s)
{
  double tc, v_end;
  s.g_m_s2 = 0.0;
  return rk4_pulse(&s, &tc, &v_end) > 0 ? -v_end / s.v0_m_s : NAN;
}

/* chi delivering e (bisection on rk4_restitution, which falls with chi). */
static double rk4_chi_for(rk4_strike s, double e)
{
  double lo = 0.0, hi = 12.0;
  for (int i = 0; i < 40; i++) {
    s.chi = 0.5 * (lo + hi);
    if (rk4_restitution(s) > e)
      lo = s.chi;
    else
      hi = s.chi;
  }
  return 0.5 * (lo + hi);
}

static double fine_at(size_t n_fine, double tc_s, double t_s)
{
  if (t_s <= 0.0 || t_s >= tc_s)
    return 0.0;
  double u = t_s / RK4_STEP_S;
  size_t j = (size_t)u;
  if (j + 1 < n_fine)
    return fine_n[j] + (u - (double)j) * (fine_n[j + 1] - fine_n[j]);
  return fine_n[n_fine - 1] * (tc_s - t_s) / (tc_s - (double)(n_fine - 1) * RK4_STEP_S);
}

/* splitmix64 + Box-Muller (af_test.h) */
static double gauss(af_test_rng *g)
{
  double u = af_test_uniform(g), v = af_test_uniform(g);
  return sqrt(-2.0 * log(u)) * cos(2.0 * PI * v);
}

/* The capture: pre-trigger, the strike at PRE_TRIGGER_S + frac / rate, the
 * offset, drift, hum and noise. Returns its length [samples]. */
static size_t make_capture(size_t n_fine, double tc_s, double peak_n, double rate_hz,
                           af_test_rng *g)
{
  size_t n = (size_t)(CAPTURE_S * rate_hz);
  double start_s = PRE_TRIGGER_S + af_test_uniform(g) / rate_hz;
  double sigma_n = peak_n * pow(10.0, -SNR_DB / 20.0);
  double hum_phase = 2.0 * PI * af_test_uniform(g);
  for (size_t k = 0; k < n && k < CAPTURE_CAP; k++) {
    double t = (double)k / rate_hz;
    capture[k] =
        (float)(OFFSET_N + DRIFT_N_S * t + sigma_n * sin(2.0 * PI * HUM_HZ * t + hum_phase) +
                sigma_n * gauss(g) + fine_at(n_fine, tc_s, t - start_s));
  }
  return n < CAPTURE_CAP ? n : CAPTURE_CAP;
}

/* ---- the two fits of every event ---------------------------------------- */

typedef struct {
  af_fit *table, *ode;
  af_impact_params start;
  size_t n;
  af_fit_result t[MAX_FITS], o[MAX_FITS];
  double cpu_table_s[MAX_FITS], cpu_ode_s[MAX_FITS];
} fits;

static double cpu_s(void)
{
  struct timespec ts;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static void fit_event(const af_strike_event *ev, void *user)
{
  fits *f = user;
  if (f->n >= MAX_FITS)
    return;
  size_t i = f->n++;
  double c0 = cpu_s();
  af_fit_execute(f->table, &f->start, ev->pulse_n, ev->n_samples, ev->dt_s, ev->pulse_t0_s,
                 &f->t[i]);
  double c1 = cpu_s();
  af_fit_execute(f->ode, &f->start, ev->pulse_n, ev->n_samples, ev->dt_s, ev->pulse_t0_s, &f->o[i]);
  f->cpu_table_s[i] = c1 - c0;
  f->cpu_ode_s[i] = cpu_s() - c1;
}

static void detect(fits *f, const float *x, size_t n, double rate_hz)
{
  af_strike_config cfg = af_strike_config_default();
  cfg.sample_rate_hz = rate_hz;
  af_strike *d = NULL;
  AF_CHECK_STATUS(af_strike_create(&cfg, &d), AF_OK);
  if (d == NULL)
    return;
  AF_CHECK_STATUS(af_strike_prime(d, x, n), AF_OK);
  for (size_t k = 0; k < n; k += CHUNK)
    AF_CHECK_STATUS(af_strike_write(d, k, x + k, n - k < CHUNK ? n - k : CHUNK, fit_event, f),
                    AF_OK);
  AF_CHECK_STATUS(af_strike_flush(d, fit_event, f), AF_OK);
  af_strike_destroy(d);
}

/* |a - b| in units of se (0 when equal). */
static double in_se(double a, double b, double se)
{
  return a == b ? 0.0 : fabs(a - b) / se;
}

/* The two results of one event agree: the same status and, when fitted,
 * parameters within AF_AGREE_SE of their standard errors. Returns the
 * largest distance in standard errors. */
static double check_agree(const af_fit_result *t, const af_fit_result *o, bool fit_velocity)
{
  AF_CHECK(t->status == o->status);
  if (t->status != AF_OK || o->status != AF_OK)
    return 0.0;
  double dz = fmax(in_se(t->modulus_pa, o->modulus_pa, o->modulus_se_pa),
                   in_se(t->restitution, o->restitution, o->restitution_se));
  if (fit_velocity)
    dz = fmax(dz, in_se(t->velocity_m_s, o->velocity_m_s, o->velocity_se_m_s));
  AF_CHECK(dz <= AGREE_SE);
  AF_CHECK_ABS(t->contact_time_s, o->contact_time_s, AGREE_SE * o->contact_time_se_s);
  return dz;
}

static int cmp_double(const void *a, const void *b)
{
  double x = *(const double *)a, y = *(const double *)b;
  return (x > y) - (x < y);
}

static double median(double *v, size_t n)
{
  qsort(v, n, sizeof *v, cmp_double);
  return n == 0 ? NAN : n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/* ---- hidden-style strikes ------------------------------------------------ */

typedef struct {
  double e2_rel, e_abs, z; /* worst |error| vs the truth; worst |z| */
  double e2_rel2, e_abs2;  /* sums of squares */
  size_t n;
} errs;

static void errs_add(errs *w, const af_fit_result *r, double e2_pa, double e)
{
  if (r->status != AF_OK)
    return;
  double de2 = r->modulus_pa / e2_pa - 1.0, de = r->restitution - e;
  w->e2_rel = fmax(w->e2_rel, fabs(de2));
  w->e_abs = fmax(w->e_abs, fabs(de));
  w->z = fmax(w->z,
              fmax(fabs(r->modulus_pa - e2_pa) / r->modulus_se_pa, fabs(de) / r->restitution_se));
  w->e2_rel2 += de2 * de2;
  w->e_abs2 += de * de;
  w->n++;
}

static void errs_print(const char *name, const errs *w)
{
  printf("  %-6s E2 error worst %.3f %% rms %.3f %%, e error worst %.4f rms %.4f, max |z| %.2f "
         "(%zu fits)\n",
         name, 100.0 * w->e2_rel, 100.0 * sqrt(w->e2_rel2 / (double)w->n), w->e_abs,
         sqrt(w->e_abs2 / (double)w->n), w->z, w->n);
}

static void test_hidden_style(bool fit_velocity, double rate_hz)
{
  static const double modulus_pa[] = {2e6, 4e6, 8e6, 12e6};
  static const double restitution[] = {0.4, 0.6, 0.8};
  af_fit_config cfg = af_fit_config_default();
  cfg.fit_velocity = fit_velocity;
  static fits f;
  memset(&f, 0, sizeof f);
  AF_CHECK_STATUS(af_fit_create(&cfg, &f.table), AF_OK);
  cfg.use_table = false;
  AF_CHECK_STATUS(af_fit_create(&cfg, &f.ode), AF_OK);
  af_test_rng g = {fit_velocity ? 1711u : 1712u};
  errs et = {0}, eo = {0};
  double worst_dz = 0.0, worst_shift = 0.0;
  size_t strikes = 0, table_paths = 0;
  for (int rep = 0; rep < 3; rep++) {
    for (size_t i = 0; i < 12; i++) {
      rk4_strike s = {.m1_kg = 0.010,
                      .v0_m_s = 1.4 * (0.9 + 0.2 * af_test_uniform(&g)),
                      .e2_pa = modulus_pa[i % 4],
                      .nu2 = 0.35,
                      .r2_m = 0.04,
                      .g_m_s2 = 9.80665};
      double e = restitution[i / 4];
      s.chi = rk4_chi_for(s, e);
      double tc_s, v_end;
      size_t n_fine = rk4_pulse(&s, &tc_s, &v_end);
      AF_CHECK(n_fine > 0);
      double peak_n = 0.0;
      for (size_t j = 0; j < n_fine; j++)
        peak_n = fmax(peak_n, fine_n[j]);
      size_t n = make_capture(n_fine, tc_s, peak_n, rate_hz, &g);
      f.start = af_impact_params_default();
      f.start.velocity_m_s = fit_velocity ? 1.4 : s.v0_m_s;
      size_t before = f.n;
      detect(&f, capture, n, rate_hz);
      AF_CHECK(f.n == before + 1);
      if (f.n != before + 1)
        continue;
      const af_fit_result *t = &f.t[before], *o = &f.o[before];
      strikes++;
      table_paths += t->path == AF_FIT_PATH_TABLE;
      AF_CHECK(t->path == AF_FIT_PATH_TABLE); /* every one in range */
      AF_CHECK(o->path == AF_FIT_PATH_ODE);
      worst_dz = fmax(worst_dz, check_agree(t, o, fit_velocity));
      if (t->path == AF_FIT_PATH_TABLE)
        worst_shift = fmax(worst_shift, t->check_shift);
      errs_add(&et, t, s.e2_pa, e);
      errs_add(&eo, o, s.e2_pa, e);
    }
  }
  size_t from_table = 0, fallbacks = 0;
  af_fit_counts(f.table, &from_table, &fallbacks);
  AF_CHECK(from_table == table_paths && from_table + fallbacks == strikes);
  printf("hidden-style, %.1f kHz, v0 %s: %zu strikes, %zu on the table, %zu fallbacks; table vs "
         "ODE at most %.3f SE apart (check's shift at most %.3f SE)\n",
         rate_hz / 1e3, fit_velocity ? "free" : "measured", strikes, from_table, fallbacks,
         worst_dz, worst_shift);
  errs_print("ODE", &eo);
  errs_print("table", &et);
  size_t it_t = 0, it_o = 0, runs_o = 0;
  for (size_t k = 0; k < f.n; k++) {
    it_t += f.t[k].iterations;
    it_o += f.o[k].iterations;
    runs_o += f.o[k].model_runs;
  }
  printf("  af_fit_execute CPU median: table %.1f us (%.1f iterations, 1 ODE run), ODE %.1f us "
         "(%.1f iterations, %.1f ODE runs)\n",
         1e6 * median(f.cpu_table_s, f.n), (double)it_t / (double)f.n,
         1e6 * median(f.cpu_ode_s, f.n), (double)it_o / (double)f.n, (double)runs_o / (double)f.n);
  af_fit_destroy(f.table);
  af_fit_destroy(f.ode);
}

/* ---- the real captures ----------------------------------------------------- */

#define REAL_RATE_HZ 25600.0
#define REAL_SAMPLES 25600

static void test_real_captures(void)
{
  const char *names[2] = {"test/data/hammer_capture_4.force.f32",
                          "test/data/hammer_capture_5.force.f32"};
  static float x[REAL_SAMPLES];
  af_fit_config cfg = af_fit_config_default();
  static fits f;
  memset(&f, 0, sizeof f);
  AF_CHECK_STATUS(af_fit_create(&cfg, &f.table), AF_OK);
  cfg.use_table = false;
  AF_CHECK_STATUS(af_fit_create(&cfg, &f.ode), AF_OK);
  /* the captures' hammer (test/data/README.md: an impact hammer on a
   * structure, not an apple): only the agreement of the two fits is tested */
  f.start = af_impact_params_default();
  for (int i = 0; i < 2; i++) {
    FILE *fp = fopen(names[i], "rb");
    AF_CHECK(fp != NULL);
    if (fp == NULL) {
      fprintf(stderr, "test_fit_table: cannot open %s (run from the repository root)\n", names[i]);
      continue;
    }
    size_t got = fread(x, sizeof *x, REAL_SAMPLES, fp);
    fclose(fp);
    AF_CHECK(got == REAL_SAMPLES);
    size_t before = f.n;
    detect(&f, x, got, REAL_RATE_HZ);
    AF_CHECK(f.n == before + 1);
    for (size_t k = before; k < f.n; k++) {
      double dz = check_agree(&f.t[k], &f.o[k], true);
      printf("real capture %d: status %s / %s, path %s; E2 %.4g / %.4g MPa, e %.4f / %.4f, "
             "t_c %.4f / %.4f ms, %.3f SE apart\n",
             i + 4, af_strerror(f.t[k].status), af_strerror(f.o[k].status),
             af_fit_path_name(f.t[k].path), f.t[k].modulus_pa / 1e6, f.o[k].modulus_pa / 1e6,
             f.t[k].restitution, f.o[k].restitution, 1e3 * f.t[k].contact_time_s,
             1e3 * f.o[k].contact_time_s, dz);
    }
  }
  af_fit_destroy(f.table);
  af_fit_destroy(f.ode);
}

/* ---- the fallbacks ----------------------------------------------------------- */

/* The table result is the ODE fit's, bit for bit (and not NaN). */
static void check_same(const af_fit_result *t, const af_fit_result *o)
{
  AF_CHECK(t->status == o->status && t->iterations == o->iterations);
  AF_CHECK(t->modulus_pa == o->modulus_pa && t->restitution == o->restitution &&
           t->velocity_m_s == o->velocity_m_s && t->modulus_se_pa == o->modulus_se_pa &&
           t->contact_time_s == o->contact_time_s);
  AF_CHECK(isfinite(t->modulus_pa));
}

/* One noise-free strike of the synthesizer in a detector-like window: the
 * contact from sample 2.3, 6 quiet samples after it, sampled every dt. */
static size_t window_of(const rk4_strike *s, double dt, double *pulse_n, size_t cap, double *t0_s)
{
  double tc_s, v_end;
  size_t n_fine = rk4_pulse(s, &tc_s, &v_end);
  *t0_s = 2.3 * dt;
  size_t n = (size_t)ceil((*t0_s + tc_s) / dt) + 6;
  n = n < cap ? n : cap;
  for (size_t k = 0; k < n; k++)
    pulse_n[k] = fine_at(n_fine, tc_s, (double)k * dt - *t0_s);
  return n_fine > 0 ? n : 0;
}

static void test_fallbacks(void)
{
  af_fit_config cfg = af_fit_config_default();
  af_fit *table = NULL, *ode = NULL, *strict = NULL;
  AF_CHECK_STATUS(af_fit_create(&cfg, &table), AF_OK);
  cfg.table_check_se = 0.0; /* every check fails */
  AF_CHECK_STATUS(af_fit_create(&cfg, &strict), AF_OK);
  cfg = af_fit_config_default();
  cfg.use_table = false;
  AF_CHECK_STATUS(af_fit_create(&cfg, &ode), AF_OK);
  static double pulse_n[256];
  af_fit_result rt, ro;
  double t0_s;
  size_t from_table, fallbacks;

  /* beyond chi: e 0.15 (chi 6.6 by the exact law) */
  rk4_strike s = {
      .m1_kg = 0.010, .v0_m_s = 1.4, .e2_pa = 5e6, .nu2 = 0.35, .r2_m = 0.04, .g_m_s2 = 9.80665};
  s.chi = rk4_chi_for(s, 0.15);
  size_t n = window_of(&s, 20e-6, pulse_n, 256, &t0_s);
  af_impact_params start = af_impact_params_default();
  start.restitution = 0.2;
  af_fit_execute(table, &start, pulse_n, n, 20e-6, t0_s, &rt);
  af_fit_execute(ode, &start, pulse_n, n, 20e-6, t0_s, &ro);
  AF_CHECK(rt.path == AF_FIT_PATH_FALLBACK_RANGE);
  AF_CHECK_STATUS(rt.status, AF_OK);
  AF_CHECK_ABS(rt.restitution, 0.15, 0.005);
  check_same(&rt, &ro);
  AF_CHECK(rt.model_runs >= ro.model_runs); /* the table's check (none here), then the ODE fit's */
  af_fit_counts(table, &from_table, &fallbacks);
  AF_CHECK(from_table == 0 && fallbacks == 1);

  /* beyond gamma: 100 g at 0.4 m/s on 1.5 MPa (gamma 0.07; a 10 ms contact,
   * sampled at 10 kHz) */
  s = (rk4_strike){
      .m1_kg = 0.1, .v0_m_s = 0.4, .e2_pa = 1.5e6, .nu2 = 0.35, .r2_m = 0.04, .g_m_s2 = 9.80665};
  s.chi = rk4_chi_for(s, 0.7);
  n = window_of(&s, 100e-6, pulse_n, 256, &t0_s);
  start = af_impact_params_default();
  start.hammer_mass_kg = 0.1;
  start.velocity_m_s = 0.4;
  start.fruit_modulus_pa = 1.5e6;
  af_fit_execute(table, &start, pulse_n, n, 100e-6, t0_s, &rt);
  af_fit_execute(ode, &start, pulse_n, n, 100e-6, t0_s, &ro);
  AF_CHECK(rt.path == AF_FIT_PATH_FALLBACK_RANGE);
  AF_CHECK_STATUS(rt.status, AF_OK);
  AF_CHECK_REL(rt.modulus_pa, 1.5e6, 0.01);
  check_same(&rt, &ro);
  af_fit_counts(table, &from_table, &fallbacks);
  AF_CHECK(from_table == 0 && fallbacks == 2);

  /* in range, the same strike through the table, then a check that fails */
  s = (rk4_strike){
      .m1_kg = 0.010, .v0_m_s = 1.4, .e2_pa = 6e6, .nu2 = 0.35, .r2_m = 0.04, .g_m_s2 = 9.80665};
  s.chi = rk4_chi_for(s, 0.65);
  n = window_of(&s, 20e-6, pulse_n, 256, &t0_s);
  start = af_impact_params_default();
  af_fit_execute(table, &start, pulse_n, n, 20e-6, t0_s, &rt);
  AF_CHECK(rt.path == AF_FIT_PATH_TABLE && rt.model_runs == 1);
  AF_CHECK(rt.check_shift <= 0.1);
  AF_CHECK_STATUS(rt.status, AF_OK);
  AF_CHECK_REL(rt.modulus_pa, 6e6, 1e-3); /* noise-free */
  AF_CHECK_ABS(rt.restitution, 0.65, 1e-3);
  af_fit_counts(table, &from_table, &fallbacks);
  AF_CHECK(from_table == 1 && fallbacks == 2);
  af_fit_execute(strict, &start, pulse_n, n, 20e-6, t0_s, &rt);
  af_fit_execute(ode, &start, pulse_n, n, 20e-6, t0_s, &ro);
  AF_CHECK(rt.path == AF_FIT_PATH_FALLBACK_CHECK && rt.check_shift > 0.0);
  check_same(&rt, &ro);
  af_fit_counts(strict, &from_table, &fallbacks);
  AF_CHECK(from_table == 0 && fallbacks == 1);
  AF_CHECK(strcmp(af_fit_path_name(AF_FIT_PATH_FALLBACK_CHECK), "fallback-check") == 0);
  /* the check's tolerance: >= 0 and finite */
  af_fit *bad = (af_fit *)&bad;
  cfg = af_fit_config_default();
  cfg.table_check_se = -0.1;
  AF_CHECK_STATUS(af_fit_create(&cfg, &bad), AF_EINVAL);
  AF_CHECK(bad == NULL);
  cfg.table_check_se = NAN;
  AF_CHECK_STATUS(af_fit_create(&cfg, &bad), AF_EINVAL);
  af_fit_counts(NULL, &from_table, &fallbacks);
  AF_CHECK(from_table == 0 && fallbacks == 0);
  printf("fallbacks: beyond chi, beyond gamma and a failed check give the ODE fit's result\n");
  af_fit_destroy(table);
  af_fit_destroy(strict);
  af_fit_destroy(ode);
}

int main(void)
{
  test_hidden_style(false, 50000.0);
  test_hidden_style(true, 50000.0);
  test_hidden_style(false, 25600.0);
  test_real_captures();
  test_fallbacks();
  return af_test_summary("test_fit_table");
}
