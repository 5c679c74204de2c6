/* test_pulse_table.c — the normalised pulse table against the ODE it
 * interpolates, at points between its nodes: the pulse f(tau) = F / F0
 * (every 1/512 of the contact), the contact time, the impulse against its
 * closed form m1 v0 (1 + e) + m1 g t_c, the peak, and the slopes in tau, chi
 * and gamma against central differences of ODE runs. The strikes are
 * dimensional (a 10 g to 100 g hammer, 0.7 to 2 m/s, E2 1.5 to 15 MPa, the
 * exact or Hu-Guo law): the scaling that maps them onto the table is
 * tested with it. Also: the build's cost, the edges of the grid and the
 * elastic pulse's closed forms. */
#define _POSIX_C_SOURCE 200809L /* clock_gettime */
#include "pulse_table.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include "af_test.h"
#include "impact.h"

#define FINE 512  /* ODE samples per contact */
#define CAP 4096  /* ODE buffer [samples] */
#define CASES 200 /* random strikes */

static double ode_n[CAP];

static double cpu_s(void)
{
  struct timespec ts;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* The scales of p (impact.h's definitions, written out here). */
typedef struct {
  double d_m, t_s, f0_n, chi, gamma;
} scales;

static scales scales_of(af_impact *im, const af_impact_params *p)
{
  scales s;
  double m1 = p->hammer_mass_kg, v0 = p->velocity_m_s;
  s.d_m = pow(1.25 * m1 * v0 * v0 / af_impact_stiffness(p), 0.4);
  s.t_s = s.d_m / v0;
  s.f0_n = m1 * v0 * v0 / s.d_m;
  s.gamma = p->gravity_m_s2 * s.d_m / (v0 * v0);
  af_impact_chi(im, p->damping, p->restitution, &s.chi);
  return s;
}

/* A random strike; chi and gamma inside the grid. */
static af_impact_params strike(af_test_rng *g)
{
  af_impact_params p = af_impact_params_default();
  p.hammer_mass_kg = 0.01 * exp(af_test_uniform(g) * log(10.0));
  p.velocity_m_s = 0.7 + 1.3 * af_test_uniform(g);
  p.fruit_modulus_pa = 1.5e6 * exp(af_test_uniform(g) * log(10.0));
  p.restitution = 0.25 + 0.7 * af_test_uniform(g);
  p.damping = af_test_uniform(g) < 0.5 ? AF_DAMPING_EXACT : AF_DAMPING_HU_GUO;
  return p;
}

typedef struct {
  double f, f_moderate, tau_c, impulse, peak, slope_tau, slope_chi, slope_gamma;
} errors;

/* The fit's usual range: e >= 0.4 by the exact law. */
#define CHI_MODERATE 2.1

/* df/dchi and df/dgamma at tau by central differences of ODE runs (chi set
 * through Hu-Guo's law, gamma through g), at the samples k = 1 .. FINE - 1
 * of the contact; the largest error against the table's, relative to the
 * largest slope. */
static void check_slopes(af_impact *im, const af_pulse_table *t, const af_impact_params *p,
                         const scales *s, errors *worst)
{
  static double plus_n[CAP], minus_n[CAP];
  af_pulse_shape sh;
  if (af_pulse_table_shape(t, s->chi, s->gamma, &sh) != AF_OK)
    return;
  double dt_s = sh.tau_c * s->t_s / FINE;
  for (int which = 0; which < 2; which++) {
    const double h = 1e-4; /* the chi or gamma step [-] */
    af_impact_params a = *p, b = *p;
    a.damping = b.damping = AF_DAMPING_HU_GUO;
    double chi_a = s->chi + (which == 0 ? h : 0.0), chi_b = s->chi - (which == 0 ? h : 0.0);
    a.restitution = 3.0 / (3.0 + 2.0 * chi_a);
    b.restitution = 3.0 / (3.0 + 2.0 * chi_b);
    double g_per_gamma = p->velocity_m_s * p->velocity_m_s / s->d_m;
    a.gravity_m_s2 = (s->gamma + (which == 1 ? h : 0.0)) * g_per_gamma;
    b.gravity_m_s2 = (s->gamma - (which == 1 ? h : 0.0)) * g_per_gamma;
    af_impact_result ra, rb;
    AF_CHECK_STATUS(af_impact_execute(im, &a, dt_s, plus_n, NULL, CAP, &ra), AF_OK);
    AF_CHECK_STATUS(af_impact_execute(im, &b, dt_s, minus_n, NULL, CAP, &rb), AF_OK);
    size_t n = ra.n_samples < rb.n_samples ? ra.n_samples : rb.n_samples;
    double err = 0.0, scale = 0.0;
    for (size_t k = 1; k + 1 < n && k < FINE; k++) {
      double tau = (double)k * dt_s / s->t_s, f, fc, fg;
      af_pulse_shape_eval(&sh, tau, &f, NULL, &fc, &fg);
      double ode = (plus_n[k] - minus_n[k]) / (2.0 * h * s->f0_n);
      double tab = which == 0 ? fc : fg;
      err = fmax(err, fabs(tab - ode));
      scale = fmax(scale, fabs(ode));
    }
    if (which == 0)
      worst->slope_chi = fmax(worst->slope_chi, err / fmax(scale, 1e-3));
    else
      worst->slope_gamma = fmax(worst->slope_gamma, err / fmax(scale, 1e-3));
  }
}

static void check_strike(af_impact *im, const af_pulse_table *t, const af_impact_params *p,
                         errors *worst, bool slopes)
{
  scales s = scales_of(im, p);
  af_pulse_shape sh;
  AF_CHECK_STATUS(af_pulse_table_shape(t, s.chi, s.gamma, &sh), AF_OK);
  af_impact_result res;
  double dt_s = af_impact_hertz_contact_time_s(p) / FINE;
  AF_CHECK_STATUS(af_impact_execute(im, p, dt_s, ode_n, NULL, CAP, &res), AF_OK);
  double peak = res.peak_force_n / s.f0_n, err = 0.0, err_slope = 0.0;
  size_t n = res.n_samples;
  for (size_t k = 1; k + 1 < n; k++) {
    double tau = (double)k * dt_s / s.t_s, f, f_tau;
    af_pulse_shape_eval(&sh, tau, &f, &f_tau, NULL, NULL);
    err = fmax(err, fabs(f - ode_n[k] / s.f0_n));
    /* the slope against a five-point difference, away from the ends (2 %),
     * where f ~ s^1.5 makes any difference quotient wrong */
    if (k < 2 || k + 2 >= n || k < n / 50 || k > n - n / 50)
      continue;
    double ode_slope = (-ode_n[k + 2] + 8.0 * ode_n[k + 1] - 8.0 * ode_n[k - 1] + ode_n[k - 2]) /
                       (12.0 * dt_s) * s.t_s / s.f0_n;
    err_slope = fmax(err_slope, fabs(f_tau - ode_slope));
  }
  double tau_c = res.contact_time_s / s.t_s;
  double impulse = 1.0 + res.delivered_restitution + s.gamma * tau_c; /* [m1 v0] */
  if (getenv("AF_TEST_VERBOSE") && err / peak > 1e-5)
    printf("chi %.3f gamma %.4f err %.2e\n", s.chi, s.gamma, err / peak);
  worst->f = fmax(worst->f, err / peak);
  if (s.chi <= CHI_MODERATE)
    worst->f_moderate = fmax(worst->f_moderate, err / peak);
  worst->slope_tau = fmax(worst->slope_tau, err_slope / peak);
  worst->tau_c = fmax(worst->tau_c, fabs(sh.tau_c / tau_c - 1.0));
  worst->impulse = fmax(worst->impulse, fabs(sh.impulse / impulse - 1.0));
  worst->peak = fmax(worst->peak, fabs(sh.peak / peak - 1.0));
  double f_after;
  af_pulse_shape_eval(&sh, 1.0001 * sh.tau_c, &f_after, NULL, NULL, NULL);
  AF_CHECK(f_after == 0.0);
  if (slopes)
    check_slopes(im, t, p, &s, worst);
}

int main(void)
{
  const af_pulse_table *t = NULL;
  double t0 = cpu_s();
  AF_CHECK_STATUS(af_pulse_table_get(&t), AF_OK);
  double build_s = cpu_s() - t0;
  t0 = cpu_s();
  const af_pulse_table *again = NULL;
  AF_CHECK_STATUS(af_pulse_table_get(&again), AF_OK);
  AF_CHECK(again == t); /* built once, shared */
  double again_s = cpu_s() - t0;
  if (t == NULL)
    return af_test_summary("test_pulse_table");
  printf("table: %d nodes (chi 0..5 x gamma 0..0.06), %d intervals per contact, "
         "%zu bytes; built in %.1f ms CPU, then %.2f us\n",
         AF_PULSE_TABLE_NCHI * AF_PULSE_TABLE_NGAMMA, AF_PULSE_TABLE_INTERVALS,
         sizeof(double) * (size_t)AF_PULSE_TABLE_NCHI * AF_PULSE_TABLE_NGAMMA *
             (AF_PULSE_TABLE_NODES + 3),
         1e3 * build_s, 1e6 * again_s);

  af_impact *im = NULL;
  AF_CHECK_STATUS(af_impact_create(&im), AF_OK);
  af_test_rng g = {20261125};
  errors worst = {0};
  for (int i = 0; i < CASES; i++) {
    af_impact_params p = strike(&g);
    check_strike(im, t, &p, &worst, i < CASES / 4);
  }
  /* the station's strike and one at strong gravity (heavy hammer, slow, soft) */
  af_impact_params p = af_impact_params_default();
  check_strike(im, t, &p, &worst, true);
  p.hammer_mass_kg = 0.1;
  p.velocity_m_s = 0.5;
  p.fruit_modulus_pa = 2e6;
  p.restitution = 0.25;
  scales s = scales_of(im, &p);
  printf("strong gravity: chi %.3f gamma %.4f\n", s.chi, s.gamma);
  check_strike(im, t, &p, &worst, true);
  printf("worst over %d strikes, relative to the peak: f %.2e (%.2e at chi <= %.1f, e >= 0.4), "
         "df/dtau %.2e; tau_c %.2e, impulse %.2e, peak %.2e (relative); df/dchi %.2e, df/dgamma "
         "%.2e (relative to their largest)\n",
         CASES + 2, worst.f, worst.f_moderate, CHI_MODERATE, worst.slope_tau, worst.tau_c,
         worst.impulse, worst.peak, worst.slope_chi, worst.slope_gamma);
  /* bounds about twice the worst seen (seed 20261125) */
  AF_CHECK(worst.f < 2e-4 && worst.f_moderate < 4e-5);
  AF_CHECK(worst.slope_tau < 1e-2); /* the Jacobian's: it steers the search, not the optimum */
  AF_CHECK(worst.tau_c < 4e-5 && worst.impulse < 4e-6 && worst.peak < 4e-6);
  AF_CHECK(worst.slope_chi < 6e-3 && worst.slope_gamma < 2e-2);

  /* off the grid: chi beyond 5 (e < 0.2 by the exact law), gamma beyond
   * 0.06 or negative; its corners on it */
  af_pulse_shape sh;
  AF_CHECK_STATUS(af_pulse_table_shape(t, 5.01, 0.01, &sh), AF_EINVAL);
  AF_CHECK_STATUS(af_pulse_table_shape(t, 1.0, -0.001, &sh), AF_EINVAL);
  AF_CHECK_STATUS(af_pulse_table_shape(t, 1.0, 0.061, &sh), AF_EINVAL);
  AF_CHECK_STATUS(af_pulse_table_shape(t, NAN, 0.01, &sh), AF_EINVAL);
  AF_CHECK_STATUS(af_pulse_table_shape(NULL, 1.0, 0.01, &sh), AF_EINVAL);
  AF_CHECK(!af_pulse_table_covers(5.01, 0.0) && af_pulse_table_covers(5.0, 0.06));
  AF_CHECK_STATUS(af_pulse_table_shape(t, 5.0, 0.06, &sh), AF_OK);
  AF_CHECK_STATUS(af_pulse_table_shape(t, 0.0, 0.0, &sh), AF_OK);
  /* the elastic pulse: tau_c = (4/5) B(2/5, 1/2), peak 5/4 (impact.c) */
  AF_CHECK_REL(sh.tau_c, 2.9432751843, 1e-8);
  AF_CHECK_REL(sh.peak, 1.25, 1e-8);
  AF_CHECK_REL(sh.impulse, 2.0, 1e-8);
  af_impact_destroy(im);
  return af_test_summary("test_pulse_table");
}
