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

af_status af_synth_pulse_model(af_impact *w, const af_impact_params *p, double fine_dt_s,
                               double *buf, size_t cap, af_synth_pulse *out)
{
  af_status st = af_impact_execute(w, p, fine_dt_s, buf, NULL, cap, &out->res);
  if (st != AF_OK)
    return st;
  out->force_n = buf;
  out->n = out->res.n_samples;
  out->fine_dt_s = fine_dt_s;
  out->impulse_n_s = p->hammer_mass_kg * (p->velocity_m_s * (1.0 + out->res.delivered_restitution) +
                                          p->gravity_m_s2 * out->res.contact_time_s);
  return AF_OK;
}

/* d'' [m/s2] and F [N] of the RK4 below. */
typedef struct {
  double k, chi, v0, m1, g;
} rk4_law;

static double rk4_force(const rk4_law *l, double d, double v)
{
  return d > 0.0 ? l->k * pow(d, 1.5) * (1.0 + l->chi * v / l->v0) : 0.0;
}

static double rk4_accel(const rk4_law *l, double d, double v)
{
  return l->g - rk4_force(l, d, v) / l->m1;
}

/* One classical RK4 step of (d, v) by h [s]. */
static void rk4_step(const rk4_law *l, double h, double *d, double *v)
{
  double d0 = *d, v0 = *v;
  double kd1 = v0, kv1 = rk4_accel(l, d0, v0);
  double kd2 = v0 + 0.5 * h * kv1, kv2 = rk4_accel(l, d0 + 0.5 * h * kd1, kd2);
  double kd3 = v0 + 0.5 * h * kv2, kv3 = rk4_accel(l, d0 + 0.5 * h * kd2, kd3);
  double kd4 = v0 + h * kv3, kv4 = rk4_accel(l, d0 + h * kd3, kd4);
  *d = d0 + h / 6.0 * (kd1 + 2.0 * kd2 + 2.0 * kd3 + kd4);
  *v = v0 + h / 6.0 * (kv1 + 2.0 * kv2 + 2.0 * kv3 + kv4);
}

af_status af_synth_pulse_rk4(const af_impact *w, const af_impact_params *p, double fine_dt_s,
                             double *buf, size_t cap, af_synth_pulse *out)
{
  if (p == NULL || buf == NULL || out == NULL || cap < 2 || !(fine_dt_s > 0.0) ||
      !(p->hammer_mass_kg > 0.0) || !(p->velocity_m_s > 0.0) || !(p->gravity_m_s2 >= 0.0))
    return AF_EINVAL;
  rk4_law l = {af_impact_stiffness(p), 0.0, p->velocity_m_s, p->hammer_mass_kg, p->gravity_m_s2};
  af_status st = af_impact_chi(w, p->damping, p->restitution, &l.chi);
  if (st != AF_OK || !(l.k > 0.0) || !isfinite(l.k))
    return st != AF_OK ? st : AF_EINVAL;
  af_impact_result *r = &out->res;
  *r = (af_impact_result){.chi = l.chi, .dt_s = fine_dt_s};
  double d = 0.0, v = p->velocity_m_s;
  size_t j = 0;
  buf[j++] = 0.0;
  for (;;) {
    double d_prev = d, v_prev = v;
    rk4_step(&l, fine_dt_s, &d, &v);
    if (d <= 0.0) { /* back at the surface within this step */
      double f = d_prev / (d_prev - d);
      r->contact_time_s = ((double)(j - 1) + f) * fine_dt_s;
      r->delivered_restitution = -(v_prev + f * (v - v_prev)) / p->velocity_m_s;
      break;
    }
    if (j == cap)
      return AF_ESIZE;
    buf[j] = fmax(rk4_force(&l, d, v), 0.0);
    if (buf[j] > r->peak_force_n) {
      r->peak_force_n = buf[j];
      r->time_of_peak_s = (double)j * fine_dt_s;
    }
    r->max_deformation_m = fmax(r->max_deformation_m, d);
    j++;
  }
  r->n_samples = j;
  out->force_n = buf;
  out->n = j;
  out->fine_dt_s = fine_dt_s;
  out->impulse_n_s = p->hammer_mass_kg * (p->velocity_m_s * (1.0 + r->delivered_restitution) +
                                          p->gravity_m_s2 * r->contact_time_s);
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
