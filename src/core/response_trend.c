/* response_trend.c — the DC and mains-hum trend of the analysed samples:
 * fitted by least squares and removed before the window.
 *
 * A steady component (DC offset, mains hum and its harmonics) is cut by the
 * window's start into a transient whose spectrum is not flat: 1/f skirts and
 * broad interference humps across the range, tens of dB above white noise
 * for a strong hum, which a noise floor measured elsewhere would pass as
 * peaks. It is fitted by least squares over the analysed samples (unweighted:
 * the late samples, where the ringing has died, pin it) and subtracted before
 * the window. */
#include "response_private.h"

#include <math.h>

#include <gsl/gsl_errno.h>
#include <gsl/gsl_linalg.h>

/* Only harmonics at or below AF_RESPONSE_HUM_MARGIN f_lo are removed, clear
 * of any 0S2 the range allows (a harmonic inside the range cannot be told
 * from a mode by a fit over one window). */
#define AF_RESPONSE_HUM_MARGIN 0.8

/* Harmonics of the hum to remove for a range starting at f_lo_hz. */
size_t af_response_hum_harmonics(const af_response *r, double f_lo_hz)
{
  const af_response_config *c = &r->cfg;
  size_t h = 0;
  while (c->hum_hz > 0.0 && h < c->hum_harmonics &&
         (double)(h + 1) * c->hum_hz <= AF_RESPONSE_HUM_MARGIN * f_lo_hz)
    ++h;
  return h;
}

/* Phase of the hum's fundamental, advanced sample by sample by a rotation (a
 * recurrence: no trig per sample; real arithmetic, as a complex product
 * would call the C library's NaN-careful __muldc3 in this inner loop). */
typedef struct {
  double c, s;           /* cos, sin of the fundamental's phase at this sample */
  double step_c, step_s; /* cos, sin of its advance per sample */
} rotor;

static rotor rotor_start(const af_response *r)
{
  double w = 2.0 * AF_PI * r->cfg.hum_hz / r->cfg.sample_rate_hz;
  rotor rot = {1.0, 0.0, cos(w), sin(w)};
  return rot;
}

/* Basis of the trend at the rotor's sample: 1, cos(h phase), sin(h phase),
 * h = 1..harmonics; then advances the rotor by one sample. */
static void trend_basis(rotor *rot, size_t harmonics, double *phi)
{
  double c = rot->c, s = rot->s;
  phi[0] = 1.0;
  for (size_t h = 1; h <= harmonics; ++h) {
    phi[2 * h - 1] = c;
    phi[2 * h] = s;
    double ch = c * rot->c - s * rot->s;
    s = s * rot->c + c * rot->s;
    c = ch;
  }
  double next_c = rot->c * rot->step_c - rot->s * rot->step_s;
  rot->s = rot->s * rot->step_c + rot->c * rot->step_s;
  rot->c = next_c;
}

/* The basis over one hum period, row by row, by the same rotor as above: a
 * row's first 1 + 2 h terms are those trend_basis gives for h harmonics (each
 * harmonic's recurrence is independent of the count), so the table serves
 * every count up to the configured one, bit for bit. Made once at create:
 * the rotor was 4-5 % of firmness_report's CPU (issue 17). */
void af_response_fill_trend_table(af_response *r)
{
  size_t terms = 1 + 2 * r->cfg.hum_harmonics;
  rotor rot = rotor_start(r);
  for (size_t j = 0; j < r->hum_period; ++j)
    trend_basis(&rot, r->cfg.hum_harmonics, r->trend_table + j * terms);
}

/* sum_{k < m} cos(theta k) and sin(theta k), in closed form:
 * sum exp(i theta k) = exp(i theta (m - 1) / 2) sin(m theta / 2) / sin(theta / 2). */
static void phase_sums(double theta, size_t m, double *sum_cos, double *sum_sin)
{
  double half = sin(0.5 * theta);
  double d = fabs(half) < 1e-12 ? (double)m : sin(0.5 * theta * (double)m) / half;
  *sum_cos = cos(0.5 * theta * (double)(m - 1)) * d;
  *sum_sin = sin(0.5 * theta * (double)(m - 1)) * d;
}

/* Normal matrix of the basis 1, cos(h theta k), sin(h theta k) over m
 * samples (lower triangle), from the product-to-sum identities and closed
 * sums: no pass over the data. */
static void trend_gram(double theta, size_t m, size_t harmonics, gsl_matrix *g)
{
  double cs[2 * AF_RESPONSE_MAX_HUM_HARMONICS + 1][2];
  for (size_t j = 0; j <= 2 * harmonics; ++j)
    phase_sums(theta * (double)j, m, &cs[j][0], &cs[j][1]);
  gsl_matrix_set(g, 0, 0, (double)m);
  for (size_t h = 1; h <= harmonics; ++h) {
    gsl_matrix_set(g, 2 * h - 1, 0, cs[h][0]);
    gsl_matrix_set(g, 2 * h, 0, cs[h][1]);
    for (size_t q = 1; q <= h; ++q) {
      double cd = cs[h - q][0], sd = cs[h - q][1], cp = cs[h + q][0], sp = cs[h + q][1];
      gsl_matrix_set(g, 2 * h - 1, 2 * q - 1, 0.5 * (cd + cp)); /* cos h cos q */
      gsl_matrix_set(g, 2 * h, 2 * q, 0.5 * (cd - cp));         /* sin h sin q */
      gsl_matrix_set(g, 2 * h, 2 * q - 1, 0.5 * (sp + sd));     /* sin h cos q */
      if (q < h)
        gsl_matrix_set(g, 2 * h - 1, 2 * q, 0.5 * (sp - sd)); /* cos h sin q */
    }
  }
}

size_t af_response_hum_period(const af_response_config *c)
{
  if (!(c->hum_hz > 0.0))
    return 0;
  double p = c->sample_rate_hz / c->hum_hz, q = round(p);
  if (!(fabs(p - q) <= 1e-9 * p) || q < 2.0 || q > (double)c->window_samples)
    return 0;
  return (size_t)q;
}

/* The basis at sample k of a run that started at 0, the rotor at k: the
 * table's row when k is within its period (the rotor not advanced: the
 * caller uses one or the other for the whole run); else the rotor's, into
 * phi. No hum: the constant alone. */
static const double *basis_at(const af_response *r, rotor *rot, size_t harmonics, size_t k,
                              double *phi)
{
  static const double dc = 1.0;
  if (harmonics == 0)
    return &dc;
  if (r->hum_period > 0 && k < r->hum_period)
    return r->trend_table + k * (1 + 2 * r->cfg.hum_harmonics);
  trend_basis(rot, harmonics, phi);
  return phi;
}

/* rhs_i = sum_k phi_i(k) x[start + k], k < m. With a whole hum period P the
 * basis repeats every P samples: x is first folded onto one period
 * (y_j = sum of the samples k = j mod P), then the basis runs over P samples
 * only (~4x fewer for 4096 samples at 48 kHz and a 960-sample period); else
 * over all m. The basis from the table (basis_at). */
static void trend_rhs(af_response *r, const float *x, size_t start, size_t m, size_t harmonics,
                      double *rhs)
{
  size_t p = 1 + 2 * harmonics, period = r->hum_period;
  rotor rot = rotor_start(r);
  double phi[AF_RESPONSE_MAX_TERMS];
  if (harmonics > 0 && period > 0 && period < m) {
    double *y = r->trend_fold;
    for (size_t j = 0; j < period; ++j)
      y[j] = 0.0;
    for (size_t k0 = 0; k0 < m; k0 += period) /* period by period: no wrap test per sample */
      for (size_t j = 0, len = m - k0 < period ? m - k0 : period; j < len; ++j)
        y[j] += (double)x[start + k0 + j];
    for (size_t j = 0; j < period; ++j) {
      const double *t = basis_at(r, &rot, harmonics, j, phi);
      for (size_t i = 0; i < p; ++i)
        rhs[i] += t[i] * y[j];
    }
    return;
  }
  for (size_t k = 0; k < m; ++k) {
    const double *t = basis_at(r, &rot, harmonics, k, phi);
    for (size_t i = 0; i < p; ++i)
      rhs[i] += t[i] * (double)x[start + k];
  }
}

/* Least-squares DC + harmonics of x[start..n) into r->trend_coef; falls back
 * to the mean alone when the normal equations are singular (a segment far
 * shorter than a hum period). */
void af_response_trend_fit(af_response *r, const float *x, size_t start, size_t n, size_t harmonics)
{
  size_t p = 1 + 2 * harmonics;
  double rhs[AF_RESPONSE_MAX_TERMS] = {0};
  trend_rhs(r, x, start, n - start, harmonics, rhs);
  gsl_matrix_view g = gsl_matrix_submatrix(r->trend_gram, 0, 0, p, p);
  gsl_vector_view b = gsl_vector_subvector(r->trend_rhs, 0, p);
  gsl_vector_view a = gsl_vector_subvector(r->trend_coef, 0, p);
  for (size_t i = 0; i < p; ++i)
    gsl_vector_set(&b.vector, i, rhs[i]);
  r->trend_terms = p;
  if (p > 1) {
    trend_gram(2.0 * AF_PI * r->cfg.hum_hz / r->cfg.sample_rate_hz, n - start, harmonics,
               &g.matrix);
    if (gsl_linalg_cholesky_decomp1(&g.matrix) == GSL_SUCCESS &&
        gsl_linalg_cholesky_solve(&g.matrix, &b.vector, &a.vector) == GSL_SUCCESS)
      return;
  }
  r->trend_terms = 1;
  gsl_vector_set(r->trend_coef, 0, rhs[0] / (double)(n - start));
}

/* The trend of the last fit at sample k (basis_at). */
static double trend_at(const af_response *r, rotor *rot, size_t harmonics, size_t k,
                       const double *coef)
{
  double phi[AF_RESPONSE_MAX_TERMS], trend = 0.0;
  const double *t = basis_at(r, rot, harmonics, k, phi);
  for (size_t i = 0; i < r->trend_terms; ++i)
    trend += t[i] * coef[i];
  return trend;
}

/* dst[k] = x[start + k] less the trend of the last fit, k < m: the DC and
 * harmonics of r->trend_coef, the rotor restarted at start (the fit's phase
 * origin); with a whole hum period, one period of the trend computed and
 * repeated. */
void af_response_trend_remove(af_response *r, const float *x, size_t start, size_t m, double *dst)
{
  size_t harmonics = (r->trend_terms - 1) / 2, period = r->hum_period;
  rotor rot = rotor_start(r);
  double coef[AF_RESPONSE_MAX_TERMS];
  for (size_t i = 0; i < r->trend_terms; ++i)
    coef[i] = gsl_vector_get(r->trend_coef, i);
  if (harmonics > 0 && period > 0 && period < m) {
    double *t = r->trend_fold;
    for (size_t j = 0; j < period; ++j)
      t[j] = trend_at(r, &rot, harmonics, j, coef);
    for (size_t k0 = 0; k0 < m; k0 += period)
      for (size_t j = 0, len = m - k0 < period ? m - k0 : period; j < len; ++j)
        dst[k0 + j] = (double)x[start + k0 + j] - t[j];
    return;
  }
  for (size_t k = 0; k < m; ++k)
    dst[k] = (double)x[start + k] - trend_at(r, &rot, harmonics, k, coef);
}
