/* synth.c — seeded signal synthesis for tests, demos and benchmarks — not
 * used by the station's measurement. See synth.h. */
#include "synth.h"

#include <math.h>

/* ---- seeded generator ---------------------------------------------------- */

void af_synth_rng_seed(af_synth_rng *g, uint64_t seed)
{
  g->state = seed;
  g->has_spare = false;
  g->spare = 0.0;
}

uint64_t af_synth_rng_next(af_synth_rng *g)
{
  uint64_t z = (g->state += 0x9E3779B97F4A7C15ULL);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  return z ^ (z >> 31);
}

double af_synth_uniform(af_synth_rng *g)
{
  return (double)(af_synth_rng_next(g) >> 11) * 0x1.0p-53;
}

double af_synth_gauss(af_synth_rng *g)
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

af_status af_synth_pulse_run(af_impact *w, const af_impact_params *p, double fine_dt_s, double *buf,
                             size_t cap, af_synth_pulse *out)
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

double af_synth_pulse_at(const af_synth_pulse *p, double t_s)
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

void af_synth_add_pulse(double *x, size_t n, double dt_s, double t_first_s, const af_synth_pulse *p,
                        double t0_s, double scale)
{
  double t_end = t0_s + p->res.contact_time_s;
  for (size_t k = 0; k < n; k++) {
    double t = t_first_s + (double)k * dt_s;
    if (t > t0_s && t < t_end)
      x[k] += scale * af_synth_pulse_at(p, t - t0_s);
  }
}

/* ---- imperfections --------------------------------------------------------- */

double af_synth_noise_rms(double peak_n, double snr_db)
{
  return peak_n * pow(10.0, -snr_db / 20.0);
}

void af_synth_add_noise(double *x, size_t n, double rms, af_synth_rng *g)
{
  for (size_t k = 0; k < n; k++)
    x[k] += rms * af_synth_gauss(g);
}

void af_synth_add_hum(double *x, size_t n, double dt_s, double t_first_s, double amplitude,
                      double freq_hz, double phase_rad)
{
  const double two_pi = 6.283185307179586;
  for (size_t k = 0; k < n; k++)
    x[k] += amplitude * sin(two_pi * freq_hz * (t_first_s + (double)k * dt_s) + phase_rad);
}

void af_synth_add_drift(double *x, size_t n, double dt_s, double t_first_s, double offset,
                        double slope_per_s, double exp_amplitude, double exp_tau_s)
{
  for (size_t k = 0; k < n; k++) {
    double t = t_first_s + (double)k * dt_s;
    x[k] += offset + slope_per_s * t;
    if (exp_tau_s > 0.0)
      x[k] += exp_amplitude * exp(-t / exp_tau_s);
  }
}

void af_synth_clip(double *x, size_t n, double full_scale)
{
  for (size_t k = 0; k < n; k++)
    x[k] = x[k] > full_scale ? full_scale : x[k] < -full_scale ? -full_scale : x[k];
}

void af_synth_to_float(const double *x, size_t n, float *out)
{
  for (size_t k = 0; k < n; k++)
    out[k] = (float)x[k];
}
