/* test_hammer_health.c — the hammer health (hammer_health.h) on short
 * sequences worked by hand: the momentum balance, the window's means and
 * spreads, each check at and around its limit, the first warning's strike,
 * strikes that are not clean, a new configuration, the reset and every
 * refused configuration.
 *
 * The hand figures use m1 = 10 g, g = 10 m/s2, e = 0.5, t_c = 1 ms: a
 * strike at v0 delivers J = m1 (v0 (1 + e) + g t_c) = 0.01 (1.5 v0 + 0.01)
 * N s. */
#include <math.h>
#include <string.h>

#include "af_test.h"
#include "hammer_health.h"

#define TC_S 0.001

static af_hammer_health_config config(void)
{
  af_hammer_health_config c = {
      .hammer_mass_kg = 0.01,
      .gravity_m_s2 = 10.0,
      .velocity_m_s = 1.0,
      .restitution = 0.5,
      .window = 4,
      .min_strikes = 3,
      .velocity_band = 0.045,
      .baseline_drift_limit_n = 0.12,
      .clip_rate_limit = 0.25,
  };
  return c;
}

/* A clean strike at v0 [m/s] with baseline b [N] and peak p [N]. */
static af_hammer_strike strike(double v0_m_s, double baseline_n, double peak_n)
{
  af_hammer_strike s = {
      .impulse_n_s = 0.01 * (1.5 * v0_m_s + 0.01),
      .contact_time_s = TC_S,
      .peak_force_n = peak_n,
      .baseline_n = baseline_n,
      .noise_rms_n = 0.01,
      .fitted_velocity_m_s = NAN,
      .fitted_restitution = NAN,
      .clipped = false,
      .clean = true,
  };
  return s;
}

static void test_momentum(void)
{
  const af_hammer_health_config c = config();
  /* 0.0151 N s over 1 ms: (1.51 - 0.01) / 1.5 = 1 m/s */
  AF_CHECK_ABS(af_hammer_health_velocity_m_s(&c, 0.0151, TC_S), 1.0, 1e-12);
  /* no gravity: J / (m1 (1 + e)) */
  af_hammer_health_config flat = c;
  flat.gravity_m_s2 = 0.0;
  AF_CHECK_ABS(af_hammer_health_velocity_m_s(&flat, 0.03, TC_S), 2.0, 1e-12);
}

/* v0 1.00, 1.02 ... 1.10: the window of 4 leaves the 4.5 % band at strike 5
 * (mean of 1.02 .. 1.08 = 1.05). */
static void test_velocity(void)
{
  const af_hammer_health_config c = config();
  af_hammer_health *h = NULL;
  AF_CHECK_STATUS(af_hammer_health_create(&c, &h), AF_OK);
  const af_hammer_health_stats *t = af_hammer_health_get_stats(h);
  AF_CHECK(t->strikes == 0 && t->warnings == 0 && isnan(t->velocity_m_s));
  const double mean[] = {1.00, 1.01, 1.02, 1.03, 1.05, 1.07};
  for (int k = 0; k < 6; k++) {
    af_hammer_strike s = strike(1.0 + 0.02 * k, 0.0, 10.0);
    AF_CHECK_STATUS(af_hammer_health_push(h, &s), AF_OK);
    AF_CHECK(t->strikes == (uint64_t)k + 1);
    AF_CHECK(t->window_strikes == (size_t)(k < 4 ? k + 1 : 4));
    AF_CHECK_ABS(t->last_velocity_m_s, 1.0 + 0.02 * k, 1e-12);
    AF_CHECK_ABS(t->velocity_m_s, mean[k], 1e-12);
    AF_CHECK_ABS(t->velocity_deviation, mean[k] - 1.0, 1e-12);
    AF_CHECK(((t->warnings & AF_HAMMER_WARN_VELOCITY) != 0) == (k >= 4));
  }
  AF_CHECK(t->first_warning_strike[0] == 5 && t->first_warning_strike[1] == 0 &&
           t->first_warning_strike[2] == 0);
  AF_CHECK(t->warned_strikes == 2);
  /* the last window: 1.04 .. 1.10, sample SD sqrt((0.03^2 + 0.01^2) 2 / 3) */
  AF_CHECK_ABS(t->velocity_sd_m_s, sqrt(0.002 / 3.0), 1e-12);
  AF_CHECK(strstr(t->text, "1.0700 m/s (+7.0 %, mean of 4 strikes") != NULL);
  AF_CHECK(strstr(t->text, "strike_velocity_m_s 1 m/s +- 4.5 % (hammer_health_velocity_band)") !=
           NULL);

  /* A faster set velocity: 1.07 is within 4.5 % of 1.05; the history stays. */
  af_hammer_health_config faster = c;
  faster.velocity_m_s = 1.05;
  AF_CHECK_STATUS(af_hammer_health_configure(h, &faster), AF_OK);
  af_hammer_strike s = strike(1.12, 0.0, 10.0); /* window 1.06 .. 1.12: mean 1.09 */
  AF_CHECK_STATUS(af_hammer_health_push(h, &s), AF_OK);
  AF_CHECK_ABS(t->velocity_m_s, 1.09, 1e-12);
  AF_CHECK(t->warnings == 0 && t->text[0] == '\0');
  AF_CHECK(t->first_warning_strike[0] == 5); /* kept */

  af_hammer_health_reset(h);
  AF_CHECK(t->strikes == 0 && t->warnings == 0 && t->first_warning_strike[0] == 0);
  AF_CHECK(isnan(t->velocity_m_s) && isnan(t->baseline_reference_n));
  af_hammer_health_destroy(h);
}

/* Strikes that are not clean: no v0, no peak, but counted (and clipped ones
 * in the clipping rate); the fit's figures averaged where finite. */
static void test_not_clean(void)
{
  af_hammer_health_config c = config();
  c.clip_rate_limit = 1.0; /* not this test's */
  af_hammer_health *h = NULL;
  AF_CHECK_STATUS(af_hammer_health_create(&c, &h), AF_OK);
  const af_hammer_health_stats *t = af_hammer_health_get_stats(h);
  af_hammer_strike a = strike(1.0, 0.0, 10.0), b = strike(1.0, 0.0, 30.0);
  af_hammer_strike d = strike(5.0, 0.0, 99.0); /* a double hit: its impulse is two */
  d.clean = false;
  a.fitted_restitution = 0.4;
  b.fitted_restitution = 0.6;
  b.fitted_velocity_m_s = 1.2;
  AF_CHECK_STATUS(af_hammer_health_push(h, &a), AF_OK);
  AF_CHECK_STATUS(af_hammer_health_push(h, &d), AF_OK);
  AF_CHECK(isnan(t->last_velocity_m_s));
  AF_CHECK_STATUS(af_hammer_health_push(h, &b), AF_OK);
  AF_CHECK(t->window_strikes == 3 && t->velocity_strikes == 2);
  AF_CHECK_ABS(t->velocity_m_s, 1.0, 1e-12);
  AF_CHECK(t->warnings == 0); /* 2 clean strikes: below min_strikes for the velocity */
  AF_CHECK_ABS(t->peak_force_n, 20.0, 1e-12);
  AF_CHECK_ABS(t->peak_force_sd_n, sqrt(200.0), 1e-12);
  AF_CHECK(t->peak_force_min_n == 10.0 && t->peak_force_max_n == 30.0);
  AF_CHECK_ABS(t->restitution, 0.5, 1e-12);
  AF_CHECK(t->restitution_strikes == 2);
  AF_CHECK_ABS(t->fit_velocity_m_s, 1.2, 1e-12);
  AF_CHECK(t->fit_velocity_strikes == 1);
  AF_CHECK_ABS(t->noise_rms_n, 0.01, 1e-15);
  AF_CHECK_STATUS(af_hammer_health_push(h, NULL), AF_EINVAL);
  AF_CHECK_STATUS(af_hammer_health_push(NULL, &a), AF_EINVAL);
  af_hammer_health_destroy(h);
  af_hammer_health_destroy(NULL);
}

/* Baselines 0, 0, 0 (the reference, after 3 strikes: 0), then 0.2 N: the
 * window's mean 0.05, 0.10, 0.15 N; the limit 0.12 N is passed at strike 6. */
static void test_baseline(void)
{
  const af_hammer_health_config c = config();
  af_hammer_health *h = NULL;
  AF_CHECK_STATUS(af_hammer_health_create(&c, &h), AF_OK);
  const af_hammer_health_stats *t = af_hammer_health_get_stats(h);
  const double b[] = {0.0, 0.0, 0.0, 0.2, 0.2, 0.2, 0.2};
  const double drift[] = {NAN, NAN, 0.0, 0.05, 0.10, 0.15, 0.20};
  for (int k = 0; k < 7; k++) {
    af_hammer_strike s = strike(1.0, b[k], 10.0);
    AF_CHECK_STATUS(af_hammer_health_push(h, &s), AF_OK);
    if (k < 2)
      AF_CHECK(isnan(t->baseline_reference_n) && isnan(t->baseline_drift_n));
    else
      AF_CHECK_ABS(t->baseline_drift_n, drift[k], 1e-12);
    AF_CHECK(((t->warnings & AF_HAMMER_WARN_BASELINE) != 0) == (k >= 5));
  }
  AF_CHECK(t->baseline_reference_n == 0.0 && t->first_warning_strike[1] == 6);
  AF_CHECK(t->warnings == AF_HAMMER_WARN_BASELINE);
  AF_CHECK(strcmp(t->text, "force baseline drifted +0.200 N (mean 0.200 N of 4 strikes, reference "
                           "0.000 N) beyond hammer_health_baseline_drift_n 0.12 N") == 0);
  af_hammer_health_destroy(h);
}

/* Clipped: no, no, yes -> 1 of 3 (33 %) > 25 % at strike 3; then no -> 1 of
 * 4 = 25 %, not beyond: the warning clears. */
static void test_clipping(void)
{
  const af_hammer_health_config c = config();
  af_hammer_health *h = NULL;
  AF_CHECK_STATUS(af_hammer_health_create(&c, &h), AF_OK);
  const af_hammer_health_stats *t = af_hammer_health_get_stats(h);
  const bool clipped[] = {false, false, true, false, false};
  const bool warn[] = {false, false, true, false, false};
  for (int k = 0; k < 5; k++) {
    af_hammer_strike s = strike(1.0, 0.0, 10.0);
    s.clipped = clipped[k];
    s.clean = !clipped[k];
    AF_CHECK_STATUS(af_hammer_health_push(h, &s), AF_OK);
    AF_CHECK(((t->warnings & AF_HAMMER_WARN_CLIPPING) != 0) == warn[k]);
    if (k == 2)
      AF_CHECK(strcmp(t->text, "clipping in 1 of 3 strikes (33.3 %) beyond "
                               "hammer_health_clip_rate 25.0 %") == 0);
  }
  AF_CHECK_ABS(t->clip_rate, 0.25, 1e-15);
  AF_CHECK(t->clipped_strikes == 1 && t->first_warning_strike[2] == 3 && t->warned_strikes == 1);
  AF_CHECK(t->text[0] == '\0');
  af_hammer_health_destroy(h);
}

/* Every refused field: AF_EINVAL, one line naming it and its range. */
static void test_refused(void)
{
  char err[512];
  af_hammer_health *h = NULL;
  af_hammer_health_config c = config();
  c.window = 1;
  AF_CHECK_STATUS(af_hammer_health_check(&c, err, sizeof err), AF_EINVAL);
  AF_CHECK(strcmp(err, "hammer health: hammer_health_window = 1 is outside the accepted range "
                       "[2, 1000] strikes") == 0);
  AF_CHECK_STATUS(af_hammer_health_create(&c, &h), AF_EINVAL);
  AF_CHECK(h == NULL);
  c = config();
  c.min_strikes = 5;
  AF_CHECK_STATUS(af_hammer_health_check(&c, err, sizeof err), AF_EINVAL);
  AF_CHECK(strstr(err, "hammer_health_min_strikes = 5") != NULL);
  c = config();
  c.velocity_band = 0.0;
  AF_CHECK_STATUS(af_hammer_health_check(&c, err, sizeof err), AF_EINVAL);
  AF_CHECK(strstr(err, "hammer_health_velocity_band = 0 ") != NULL);
  c = config();
  c.clip_rate_limit = 1.5;
  AF_CHECK_STATUS(af_hammer_health_check(&c, err, sizeof err), AF_EINVAL);
  AF_CHECK(strstr(err, "hammer_health_clip_rate = 1.5") != NULL);
  c = config();
  c.baseline_drift_limit_n = NAN;
  AF_CHECK_STATUS(af_hammer_health_check(&c, err, sizeof err), AF_EINVAL);
  AF_CHECK(strstr(err, "hammer_health_baseline_drift_n") != NULL);
  c = config();
  c.hammer_mass_kg = 0.0;
  AF_CHECK_STATUS(af_hammer_health_check(&c, err, sizeof err), AF_EINVAL);
  AF_CHECK(strstr(err, "hammer_mass_kg = 0") != NULL);
  c = config();
  c.restitution = 1.2;
  AF_CHECK_STATUS(af_hammer_health_check(&c, err, sizeof err), AF_EINVAL);
  AF_CHECK(strstr(err, "restitution = 1.2") != NULL);
  AF_CHECK_STATUS(af_hammer_health_check(NULL, err, sizeof err), AF_EINVAL);
  /* a refused configure keeps the old one */
  c = config();
  AF_CHECK_STATUS(af_hammer_health_create(&c, &h), AF_OK);
  af_hammer_health_config bad = c;
  bad.window = 0;
  AF_CHECK_STATUS(af_hammer_health_configure(h, &bad), AF_EINVAL);
  af_hammer_health_destroy(h);
}

int main(void)
{
  test_momentum();
  test_velocity();
  test_not_clean();
  test_baseline();
  test_clipping();
  test_refused();
  return af_test_summary("test_hammer_health");
}
