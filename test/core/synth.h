/* synth.h — synthetic force signals for the core tests (strike detector,
 * inverse fit): a model pulse at any sampling rate and sub-sample delay,
 * seeded white noise, mains hum, transducer offset and drift, clipping.
 *
 * Header-only (static inline), no allocation: the caller owns every buffer.
 * The generator is self-contained (splitmix64 + polar Box-Muller) so that a
 * seed gives the same signal on every platform and library version.
 *
 * Typical use:
 *     af_synth_pulse p;
 *     double fine[8192];
 *     af_synth_pulse_run(w, &params, 20e-6 / 64, fine, 8192, &p);
 *     af_synth_add_pulse(x, n, 20e-6, 0.0, &p, 0.0123456, 1.0);   F(t - t0)
 *     af_synth_add_noise(x, n, af_synth_noise_rms(p.res.peak_force_n, 40.0), &g);
 * Sample k of x is at time t_first_s + k dt_s throughout. */
#ifndef AF_SYNTH_H
#define AF_SYNTH_H

#include <math.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "impact.h"

/* ---- seeded generator ---------------------------------------------------- */

typedef struct {
  uint64_t state;
  bool has_spare; /* Box-Muller makes normals in pairs */
  double spare;
} af_synth_rng;

static inline void af_synth_rng_seed(af_synth_rng *g, uint64_t seed)
{
  g->state = seed;
  g->has_spare = false;
  g->spare = 0.0;
}

/* splitmix64 (Steele, Lea, Flood 2014): full period, passes BigCrush. */
static inline uint64_t af_synth_rng_next(af_synth_rng *g)
{
  uint64_t z = (g->state += 0x9E3779B97F4A7C15ULL);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  return z ^ (z >> 31);
}

/* Uniform in [0, 1), 53 bits. */
static inline double af_synth_uniform(af_synth_rng *g)
{
  return (double)(af_synth_rng_next(g) >> 11) * 0x1.0p-53;
}

/* Standard normal (Marsaglia's polar method). */
static inline double af_synth_gauss(af_synth_rng *g)
{
  if (g->has_spare) {
    g->has_spare = false;
    return g->spare;
  }
  double u, v, s;
  do {
    u = 2.0 * af_synth_uniform(g) - 1.0;
    v = 2.0 * af_synth_uniform(g) - 1.0;
    s = u * u + v * v;
  } while (s >= 1.0 || s == 0.0);
  double f = sqrt(-2.0 * log(s) / s);
  g->spare = v * f;
  g->has_spare = true;
  return u * f;
}

/* ---- model pulse ---------------------------------------------------------- */

/* The model's force on a fine grid, to be sampled at any rate and delay by
 * linear interpolation (at dt/64 of a 50 kHz stream the interpolation error
 * is ~1e-7 of the peak). */
typedef struct {
  const double *force_n; /* F(j fine_dt_s) [N], j = 0 .. n-1: the caller's buffer */
  size_t n;
  double fine_dt_s;
  af_impact_result res; /* the model's contact time, peak, restitution ... */
  double impulse_n_s;   /* momentum balance m1 v0 (1 + e_delivered) + m1 g t_c: the
                           exact integral of F, independent of the sampling */
} af_synth_pulse;

/* Runs the impact model at fine_dt_s into buf[0..cap) and describes it in
 * *out. Statuses of af_impact_run (AF_ESIZE when cap is too small). */
static inline af_status af_synth_pulse_run(af_impact *w, const af_impact_params *p,
                                           double fine_dt_s, double *buf, size_t cap,
                                           af_synth_pulse *out)
{
  af_status st = af_impact_run(w, p, fine_dt_s, buf, NULL, cap, &out->res);
  if (st != AF_OK)
    return st;
  out->force_n = buf;
  out->n = out->res.n_samples;
  out->fine_dt_s = fine_dt_s;
  out->impulse_n_s = p->hammer_mass_kg * (p->velocity_m_s * (1.0 + out->res.delivered_restitution) +
                                          p->gravity_m_s2 * out->res.contact_time_s);
  return AF_OK;
}

/* F(t) [N]: 0 before contact (t <= 0) and after it (t >= t_c); between the
 * last fine sample and t_c the force falls linearly to 0. */
static inline double af_synth_pulse_at(const af_synth_pulse *p, double t_s)
{
  double tc = p->res.contact_time_s;
  if (!(t_s > 0.0) || !(t_s < tc) || p->n == 0)
    return 0.0;
  double u = t_s / p->fine_dt_s;
  size_t j = (size_t)u;
  if (j + 1 < p->n) {
    double f = u - (double)j;
    return p->force_n[j] + f * (p->force_n[j + 1] - p->force_n[j]);
  }
  double t_last = (double)(p->n - 1) * p->fine_dt_s; /* last fine sample .. t_c */
  return tc > t_last ? p->force_n[p->n - 1] * (tc - t_s) / (tc - t_last) : 0.0;
}

/* x[k] += scale F(t_first_s + k dt_s - t0_s): the pulse starting at t0_s
 * (any real time, so any sub-sample delay). */
static inline void af_synth_add_pulse(double *x, size_t n, double dt_s, double t_first_s,
                                      const af_synth_pulse *p, double t0_s, double scale)
{
  double t_end = t0_s + p->res.contact_time_s;
  for (size_t k = 0; k < n; k++) {
    double t = t_first_s + (double)k * dt_s;
    if (t > t0_s && t < t_end)
      x[k] += scale * af_synth_pulse_at(p, t - t0_s);
  }
}

/* ---- imperfections --------------------------------------------------------- */

/* Noise RMS [N] that gives snr_db = 20 log10(peak / noise RMS). */
static inline double af_synth_noise_rms(double peak_n, double snr_db)
{
  return peak_n * pow(10.0, -snr_db / 20.0);
}

/* White Gaussian noise of the given RMS. */
static inline void af_synth_add_noise(double *x, size_t n, double rms, af_synth_rng *g)
{
  for (size_t k = 0; k < n; k++)
    x[k] += rms * af_synth_gauss(g);
}

/* Mains hum amplitude sin(2 pi f t + phase). */
static inline void af_synth_add_hum(double *x, size_t n, double dt_s, double t_first_s,
                                    double amplitude, double freq_hz, double phase_rad)
{
  const double two_pi = 6.283185307179586;
  for (size_t k = 0; k < n; k++)
    x[k] += amplitude * sin(two_pi * freq_hz * (t_first_s + (double)k * dt_s) + phase_rad);
}

/* Transducer offset and drift: offset + slope t + exp_amplitude exp(-t/exp_tau)
 * (the charge of an AC-coupled piezo settling after power-up). exp_tau_s <= 0
 * leaves the exponential out. */
static inline void af_synth_add_drift(double *x, size_t n, double dt_s, double t_first_s,
                                      double offset, double slope_per_s, double exp_amplitude,
                                      double exp_tau_s)
{
  for (size_t k = 0; k < n; k++) {
    double t = t_first_s + (double)k * dt_s;
    x[k] += offset + slope_per_s * t;
    if (exp_tau_s > 0.0)
      x[k] += exp_amplitude * exp(-t / exp_tau_s);
  }
}

/* Saturates at +-full_scale, as the amplifier or the converter does. */
static inline void af_synth_clip(double *x, size_t n, double full_scale)
{
  for (size_t k = 0; k < n; k++)
    x[k] = x[k] > full_scale ? full_scale : x[k] < -full_scale ? -full_scale : x[k];
}

/* The float32 samples a SignalChunk carries. */
static inline void af_synth_to_float(const double *x, size_t n, float *out)
{
  for (size_t k = 0; k < n; k++)
    out[k] = (float)x[k];
}

#endif
