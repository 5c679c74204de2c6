/* test_strike_pulse.c — the pure pulse measurement (strike_pulse.h) on
 * analytic pulses whose figures have closed forms, sampled here at 50 kHz:
 *  - half-sine F(t) = F0 sin(pi t / T): peak F0 at T/2, impulse 2 F0 T / pi,
 *    duration T;
 *  - Hertz-like F0 sin^1.5(pi t / T): peak F0 at T/2, impulse
 *    F0 T / pi * sqrt(pi) Gamma(5/4) / Gamma(7/4), duration T;
 *  - a half-sine clipped flat at C < F0: impulse
 *    2 F0 T / pi (1 - cos(pi u1)) + C T (1 - 2 u1), u1 = asin(C / F0) / pi;
 *  - each on a zero baseline, then on an offset with a linear drift.
 * Truth is the formula, never the code's earlier output. */
#include <math.h>
#include <stdbool.h>

#include "af_test.h"
#include "strike_pulse.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

#define RATE_HZ 50000.0
#define N_SPAN 600     /* span [samples]: 12 ms */
#define START 200.37   /* true contact start [samples]: 4 ms of quiet before it */
#define WINDOW 50      /* baseline window [samples]: 1 ms, the default */
#define F0_N 100.0     /* pulse amplitude [N] */
#define TRIGGER_N 0.5  /* trigger threshold above the baseline [N] (threshold_min_n) */
#define FULL_SCALE 500 /* [N]: the default; no analytic pulse here reaches it unless clipped */

typedef enum { HALF_SINE, HERTZ } shape;

/* One synthetic span: the analytic pulse on an analytic baseline. */
typedef struct {
  shape kind;
  double width;   /* T [samples] */
  double clip_n;  /* the pulse is flat above this [N] (INFINITY: not clipped) */
  double offset;  /* baseline at sample 0 [N] */
  double drift_n; /* baseline slope [N/sample] */
} pulse_spec;

static double pulse_at(const pulse_spec *p, double k)
{
  double u = (k - START) / p->width;
  if (u <= 0.0 || u >= 1.0)
    return 0.0;
  double s = sin(M_PI * u), f = F0_N * (p->kind == HERTZ ? s * sqrt(s) : s);
  return f < p->clip_n ? f : p->clip_n;
}

static double baseline_at(const pulse_spec *p, double k)
{
  return p->offset + p->drift_n * k;
}

/* Samples the span and measures it. The detector's knowledge (trigger, the
 * coarse contact's end, the baseline when it triggered) is taken from the
 * analytic pulse, as an ideal detector would have it. */
static af_status measure(const pulse_spec *p, double full_scale_n, af_strike_pulse *out)
{
  static double x[N_SPAN], r[N_SPAN];
  long trigger = -1, contact_end = N_SPAN;
  for (long k = 0; k < N_SPAN; k++) {
    double f = pulse_at(p, (double)k);
    x[k] = baseline_at(p, (double)k) + f;
    if (trigger < 0 && f > TRIGGER_N)
      trigger = k;
    if (trigger >= 0 && contact_end == N_SPAN && k > trigger && f < 0.5 * TRIGGER_N)
      contact_end = k;
  }
  af_strike_pulse_input in = {.x = x,
                              .n = N_SPAN,
                              .trigger = trigger,
                              .contact_end = contact_end,
                              .clean_end = N_SPAN,
                              .window = WINDOW,
                              .tracker_baseline_n = baseline_at(p, (double)trigger),
                              .release_n = 0.5 * TRIGGER_N,
                              .noise_rms_n = 0.0,
                              .rise_fit_level = 0.7,
                              .fall_fit_level = 0.5,
                              .sample_rate_hz = RATE_HZ,
                              .full_scale_n = full_scale_n};
  return af_strike_pulse_measure(&in, r, out);
}

/* ∫0^T sin^p(pi t / T) dt / T = Gamma((p + 1) / 2) / (sqrt(pi) Gamma(p / 2 + 1)). */
static double mean_of_sine_power(double p)
{
  return tgamma(0.5 * (p + 1.0)) / (sqrt(M_PI) * tgamma(0.5 * p + 1.0));
}

/* Checks shared by every unclipped well-sampled pulse of width T [samples]:
 * the closed forms, with the tolerances the method states (strike.h). */
static void check_pulse(const pulse_spec *p, double impulse_n_s, double duration_lo,
                        double duration_hi)
{
  af_strike_pulse m;
  AF_CHECK_STATUS(measure(p, FULL_SCALE, &m), AF_OK);
  double t_s = p->width / RATE_HZ;
  /* Peak: a least-squares quartic through the top 30 % of a smooth
   * symmetric top (+-0.8 rad of the sine): the Taylor remainder x^6/720 is
   * 4e-4 at the ends of that range and far less at its centre, so within
   * 0.01 % of F0 (seen: 0.002 %), at T/2 within 0.05 sample. */
  AF_CHECK_REL(m.peak_n, F0_N, 1e-4);
  AF_CHECK_ABS(m.peak_at, START + 0.5 * p->width, 0.05);
  /* Impulse: trapezoids at 50 samples per pulse (relative error about
   * (pi / 50)^2 / 12 = 0.03 %), feet included: within 0.05 % (seen
   * +0.013 % for the half-sine, -0.007 % for sin^1.5). */
  AF_CHECK_REL(m.impulse_n_s, impulse_n_s, 5e-4);
  /* Duration: the edge law a1 s^1.5 + a2 s^4 against the pulse's foot
   * (exact for s^1.5; a half-sine's linear foot moves the zeros outwards),
   * in [T (1 + duration_lo), T (1 + duration_hi)]. */
  AF_CHECK(m.contact_time_s >= t_s * (1.0 + duration_lo));
  AF_CHECK(m.contact_time_s <= t_s * (1.0 + duration_hi));
  AF_CHECK(m.start <= START + 0.05); /* outwards, if anything: not inside the pulse */
  AF_CHECK(m.start_edge == AF_STRIKE_EDGES_FIT && m.end_edge == AF_STRIKE_EDGES_FIT);
  AF_CHECK(!m.clipped);
  /* The baseline line removed is the one the signal was built on. */
  double t0 = m.start;
  AF_CHECK_ABS(m.baseline_n + m.baseline_slope_n * t0, baseline_at(p, t0), 1e-9);
  AF_CHECK_ABS(m.baseline_slope_n, p->drift_n, 1e-12);
  AF_CHECK(m.baseline_before_samples == WINDOW && m.baseline_after_samples == WINDOW);
}

static void test_half_sine(void)
{
  pulse_spec flat = {.kind = HALF_SINE, .width = 50.0, .clip_n = INFINITY};
  double impulse = 2.0 * F0_N * (flat.width / RATE_HZ) / M_PI;
  /* The linear foot: zeros outwards, the width longer by 0 to 6 % (strike.h
   * says about +3 %; seen +3.2 to +5.6 % over widths of 20-100 samples,
   * +4.7 % at 50). */
  check_pulse(&flat, impulse, 0.0, 0.06);
  /* The same on a 5 N offset drifting 200 N/s (0.004 N per sample): the
   * figures do not move. */
  pulse_spec drift = flat;
  drift.offset = 5.0;
  drift.drift_n = 200.0 / RATE_HZ;
  check_pulse(&drift, impulse, 0.0, 0.06);
  af_strike_pulse a, b;
  AF_CHECK_STATUS(measure(&flat, FULL_SCALE, &a), AF_OK);
  AF_CHECK_STATUS(measure(&drift, FULL_SCALE, &b), AF_OK);
  AF_CHECK_REL(b.impulse_n_s, a.impulse_n_s, 1e-9);
  AF_CHECK_REL(b.peak_n, a.peak_n, 1e-9);
  AF_CHECK_ABS(b.start, a.start, 1e-6);
  AF_CHECK_ABS(b.end, a.end, 1e-6);
}

static void test_hertz(void)
{
  pulse_spec flat = {.kind = HERTZ, .width = 50.0, .clip_n = INFINITY};
  double impulse = F0_N * (flat.width / RATE_HZ) * mean_of_sine_power(1.5);
  /* The foot is s^1.5 (1 - O(s^2)): the law's own; within 0.4 % (strike.h's
   * noise-free figure; seen +0.2 to +0.27 % over widths of 20-100 samples). */
  check_pulse(&flat, impulse, -0.004, 0.004);
  pulse_spec drift = flat;
  drift.offset = -3.0;
  drift.drift_n = -150.0 / RATE_HZ;
  check_pulse(&drift, impulse, -0.004, 0.004);
}

/* A short pulse (9.3 samples: a steel-tipped hammer at 50 kHz) takes its
 * edges from the crossings of L = 2 % of the peak. The continuous pulse
 * crosses L u_L = T asin(0.02^(2/3)) / pi = 0.22 sample inside each end; the
 * reconstruction of a pulse that is not band-limited differs from it by a
 * fraction of a sample (strike.h: start within 0.45 sample, duration within
 * 0.75 sample over phases and noise): the start within 0.1 sample of
 * [START, START + u_L], the duration of [T - 2 u_L, T]. */
static void test_short(void)
{
  pulse_spec p = {.kind = HERTZ, .width = 9.3, .clip_n = INFINITY};
  af_strike_pulse m;
  AF_CHECK_STATUS(measure(&p, FULL_SCALE, &m), AF_OK);
  AF_CHECK(m.start_edge == AF_STRIKE_EDGES_LEVEL && m.end_edge == AF_STRIKE_EDGES_LEVEL);
  double u_l = p.width * asin(pow(0.02, 2.0 / 3.0)) / M_PI, width = m.contact_time_s * RATE_HZ;
  AF_CHECK(m.start >= START - 0.1 && m.start <= START + u_l + 0.1);
  AF_CHECK(width >= p.width - 2.0 * u_l - 0.1 && width <= p.width + 0.1);
  AF_CHECK_REL(m.edge_level_n, 0.02 * m.peak_n, 1e-12);
  /* Peak of the reconstruction: within 0.4 % for a raw-sampled sin^1.5 of
   * 8-10 samples (strike.h). */
  AF_CHECK_REL(m.peak_n, F0_N, 4e-3);
}

/* A half-sine of amplitude 100 N clipped flat at 60 N by a 60 N full scale:
 * flagged, its impulse the clipped shape's, its peak the flat top. */
static void test_clipped(void)
{
  const double c = 60.0;
  pulse_spec p = {.kind = HALF_SINE, .width = 50.0, .clip_n = c};
  af_strike_pulse m;
  AF_CHECK_STATUS(measure(&p, c, &m), AF_OK);
  AF_CHECK(m.clipped);
  double t_s = p.width / RATE_HZ, u1 = asin(c / F0_N) / M_PI;
  double impulse = 2.0 * F0_N * t_s / M_PI * (1.0 - cos(M_PI * u1)) + c * t_s * (1.0 - 2.0 * u1);
  AF_CHECK_REL(m.impulse_n_s, impulse, 5e-4); /* seen +0.012 % */
  /* The peak of a quartic through a flat top with kinks at its ends bulges
   * above the top (seen +2.3 %), but cannot restore the lost 100 N: between
   * C and C + 5 %. The flag says not to trust it. */
  AF_CHECK(m.peak_n >= c && m.peak_n <= 1.05 * c);
  /* The same pulse with the full scale above its samples is not clipped. */
  AF_CHECK_STATUS(measure(&p, c + 1e-6, &m), AF_OK);
  AF_CHECK(!m.clipped);
}

static void test_errors(void)
{
  double x[N_SPAN] = {0}, r[N_SPAN];
  af_strike_pulse m;
  af_strike_pulse_input in = {.x = x,
                              .n = N_SPAN,
                              .trigger = 10,
                              .contact_end = 20,
                              .clean_end = N_SPAN,
                              .window = WINDOW,
                              .release_n = 0.25,
                              .rise_fit_level = 0.7,
                              .fall_fit_level = 0.5,
                              .sample_rate_hz = RATE_HZ,
                              .full_scale_n = FULL_SCALE};
  AF_CHECK_STATUS(af_strike_pulse_measure(&in, r, &m), AF_OK); /* the valid reference */
  AF_CHECK_STATUS(af_strike_pulse_measure(NULL, r, &m), AF_EINVAL);
  AF_CHECK_STATUS(af_strike_pulse_measure(&in, NULL, &m), AF_EINVAL);
  AF_CHECK_STATUS(af_strike_pulse_measure(&in, r, NULL), AF_EINVAL);
  af_strike_pulse_input bad = in;
  bad.trigger = N_SPAN;
  AF_CHECK_STATUS(af_strike_pulse_measure(&bad, r, &m), AF_EINVAL);
  bad = in;
  bad.rise_fit_level = 1.0;
  AF_CHECK_STATUS(af_strike_pulse_measure(&bad, r, &m), AF_EINVAL);
  bad = in;
  bad.sample_rate_hz = NAN;
  AF_CHECK_STATUS(af_strike_pulse_measure(&bad, r, &m), AF_EINVAL);
  bad = in;
  bad.x = NULL;
  AF_CHECK_STATUS(af_strike_pulse_measure(&bad, r, &m), AF_EINVAL);
}

int main(void)
{
  test_half_sine();
  test_hertz();
  test_short();
  test_clipped();
  test_errors();
  return af_test_summary("test_strike_pulse");
}
