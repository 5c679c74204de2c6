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
#include <stdint.h>
#include <string.h>

#include <gsl/gsl_errno.h>
#include <gsl/gsl_linalg.h>

#include "af_defaults.h" /* the parameter table's defaults */
#include "memo.h"

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
 * the rotor was 4-5 % of firmness_report's CPU. */
void af_response_fill_trend_table(af_response *r)
{
  size_t terms = 1 + 2 * r->cfg.hum_harmonics;
  rotor rot = rotor_start(r);
  for (size_t j = 0; j < r->hum_period; ++j)
    trend_basis(&rot, r->cfg.hum_harmonics, r->trend_table + j * terms);
  for (size_t j = 0; j < r->hum_period; ++j)
    for (size_t i = 0; i < terms; ++i)
      r->trend_cols[i * r->hum_period + j] = r->trend_table[j * terms + i];
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

/* The samples x[start..start + m) onto one hum period, into r->trend_fold:
 * y_j = the sum of the samples k = j mod P when the run is longer than a
 * period, else the samples themselves (a run of a period or less: the
 * default noise reference is one hum period long). Its length back. */
static size_t trend_fold(af_response *r, const float *x, size_t start, size_t m)
{
  size_t period = r->hum_period;
  double *y = r->trend_fold;
  if (m <= period) {
    for (size_t j = 0; j < m; ++j)
      y[j] = (double)x[start + j];
    return m;
  }
  for (size_t j = 0; j < period; ++j) /* the first period onto zeros, as one loop */
    y[j] = 0.0 + (double)x[start + j];
  for (size_t k0 = period; k0 < m; k0 += period) /* period by period: no wrap test per sample */
    for (size_t j = 0, len = m - k0 < period ? m - k0 : period; j < len; ++j)
      y[j] += (double)x[start + k0 + j];
  return period;
}

/* rhs[0] += sum_j y[j] and, per harmonic h < 'harmonics', (rhs[2h + 1],
 * rhs[2h + 2]) += sum_j (cos, sin)_h(j) y[j], j < len, each sum in order: one
 * pass over y, a harmonic's two sums in one register (af_v2d: the same
 * doubles) from the table's row j, where its cos and sin stand side by side.
 * Inlined with the count constant (table_sums), so the sums stay in
 * registers. */
static inline __attribute__((always_inline)) void
table_sums_n(const af_response *r, const double *y, size_t len, size_t harmonics, double *rhs)
{
  size_t terms = 1 + 2 * r->cfg.hum_harmonics;
  af_v2d acc[AF_RESPONSE_MAX_HUM_HARMONICS];
  double sum = rhs[0];
  for (size_t h = 0; h < harmonics; ++h)
    acc[h] = (af_v2d){rhs[2 * h + 1], rhs[2 * h + 2]};
  for (size_t j = 0; j < len; ++j) {
    const double *row = r->trend_table + j * terms + 1;
    const af_v2d yj = {y[j], y[j]};
    sum += y[j]; /* the DC's column: 1 x y_j is y_j */
#pragma GCC unroll 8
    for (size_t h = 0; h < harmonics; ++h) {
      af_v2d t;
      memcpy(&t, row + 2 * h, sizeof t); /* rows of odd length: unaligned */
      acc[h] += t * yj;
    }
  }
  rhs[0] = sum;
  for (size_t h = 0; h < harmonics; ++h) {
    rhs[2 * h + 1] = acc[h][0];
    rhs[2 * h + 2] = acc[h][1];
  }
}

/* table_sums_n, the configuration's default count of harmonics apart. */
static void table_sums(const af_response *r, const double *y, size_t len, size_t harmonics,
                       double *rhs)
{
  if (harmonics == AF_DEFAULT_MEASURE_HUM_HARMONICS)
    table_sums_n(r, y, len, AF_DEFAULT_MEASURE_HUM_HARMONICS, rhs);
  else
    table_sums_n(r, y, len, harmonics, rhs);
}

/* rhs_i = sum_k phi_i(k) x[start + k], k < m. With a whole hum period P the
 * basis repeats every P samples: x is first folded onto one period
 * (trend_fold), then the basis runs over P samples only (~4x fewer for 4096
 * samples at 48 kHz and a 960-sample period), all terms in one pass
 * (table_sums: each rhs_i the same products in the same order as term by
 * term); else the rotor over all m. */
static void trend_rhs(af_response *r, const float *x, size_t start, size_t m, size_t harmonics,
                      double *rhs)
{
  size_t p = 1 + 2 * harmonics, period = r->hum_period;
  if (harmonics > 0 && period > 0) {
    table_sums(r, r->trend_fold, trend_fold(r, x, start, m), harmonics, rhs);
    return;
  }
  if (harmonics == 0) { /* the constant alone: the sum (1 x sample is the sample) */
    for (size_t k = 0; k < m; ++k)
      rhs[0] += (double)x[start + k];
    return;
  }
  rotor rot = rotor_start(r);
  double phi[AF_RESPONSE_MAX_TERMS];
  for (size_t k = 0; k < m; ++k) {
    const double *t = basis_at(r, &rot, harmonics, k, phi);
    for (size_t i = 0; i < p; ++i)
      rhs[i] += t[i] * (double)x[start + k];
  }
}

/* The Cholesky factor of the normal matrix of 1 + 2 harmonics terms over m
 * samples into gram's leading block; 0 if it is singular. With 'kept' (the
 * noise reference's matrix, whose segment has the same length every strike)
 * the factor of the last call is reused when m and the terms are the same:
 * the same doubles, without the trigonometry and the factoring (5 k
 * instructions a strike). */
static int gram_factor(af_response *r, gsl_matrix *gram, size_t m, size_t harmonics, int kept)
{
  size_t p = 1 + 2 * harmonics;
  if (kept && r->noise_gram_terms == p && r->noise_gram_m == m)
    return 1;
  gsl_matrix_view g = gsl_matrix_submatrix(gram, 0, 0, p, p);
  trend_gram(2.0 * AF_PI * r->cfg.hum_hz / r->cfg.sample_rate_hz, m, harmonics, &g.matrix);
  int ok = gsl_linalg_cholesky_decomp1(&g.matrix) == GSL_SUCCESS;
  if (kept) {
    r->noise_gram_terms = ok ? p : 0;
    r->noise_gram_m = m;
  }
  return ok;
}

af_status af_response_trend_fit(af_response *r, const float *x, size_t start, size_t n,
                                size_t harmonics, int noise)
{
  size_t p = 1 + 2 * harmonics;
  double rhs[AF_RESPONSE_MAX_TERMS] = {0};
  trend_rhs(r, x, start, n - start, harmonics, rhs);
  /* rhs[0] sums the samples themselves (the constant's column is 1): a sum
   * of finite floats in double stays finite, a NaN or an infinity does not */
  if (!isfinite(rhs[0]))
    return AF_ENUMERIC;
  gsl_matrix *gram = noise ? r->noise_gram : r->trend_gram;
  gsl_matrix_view g = gsl_matrix_submatrix(gram, 0, 0, p, p);
  gsl_vector_view b = gsl_vector_subvector(r->trend_rhs, 0, p);
  gsl_vector_view a = gsl_vector_subvector(r->trend_coef, 0, p);
  for (size_t i = 0; i < p; ++i)
    gsl_vector_set(&b.vector, i, rhs[i]);
  r->trend_terms = p;
  if (p > 1 && gram_factor(r, gram, n - start, harmonics, noise) &&
      gsl_linalg_cholesky_solve(&g.matrix, &b.vector, &a.vector) == GSL_SUCCESS)
    return AF_OK;
  r->trend_terms = 1;
  gsl_vector_set(r->trend_coef, 0, rhs[0] / (double)(n - start));
  return AF_OK;
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

/* The trend of the last fit (coef, terms of them) at samples j..j + 1 of
 * the hum period from the table's columns (dc, period apart): trend_at's
 * sum, 0 + 1 x coef_0, then each harmonic's cos and sin in order, two
 * samples a register (af_v2d: the same doubles). Inlined with the count
 * constant (trend_period), so the coefficients stay in registers. */
static inline __attribute__((always_inline)) af_v2d
trend_pair(const double *dc, size_t period, const af_v2d *coef, size_t terms, size_t j)
{
  af_v2d t = (af_v2d){0.0, 0.0} + (af_v2d){dc[j], dc[j + 1]} * coef[0];
#pragma GCC unroll 16
  for (size_t i = 1; i + 1 < terms; i += 2) {
    const double *c = dc + i * period + j, *s = c + period;
    t = (t + (af_v2d){c[0], c[1]} * coef[i]) + (af_v2d){s[0], s[1]} * coef[i + 1];
  }
  return t;
}

/* The trend of the last fit (coef) at samples 0..len of one hum period, len
 * <= the period, into r->trend_fold: all terms in one pass over the samples
 * (trend_pair; an odd last sample by trend_at's sum alone), each value the
 * same sum in the same order as trend_at's. */
static void trend_period(af_response *r, const double *coef, size_t len)
{
  double *t = r->trend_fold;
  const double *dc = r->trend_cols;
  size_t period = r->hum_period, terms = r->trend_terms, j = 0;
  af_v2d k[AF_RESPONSE_MAX_TERMS];
  for (size_t i = 0; i < terms; ++i)
    k[i] = (af_v2d){coef[i], coef[i]};
  if (terms == 1 + 2 * AF_DEFAULT_MEASURE_HUM_HARMONICS)
    for (; j + 1 < len; j += 2) {
      af_v2d v = trend_pair(dc, period, k, 1 + 2 * AF_DEFAULT_MEASURE_HUM_HARMONICS, j);
      memcpy(t + j, &v, sizeof v);
    }
  for (; j + 1 < len; j += 2) {
    af_v2d v = trend_pair(dc, period, k, terms, j);
    memcpy(t + j, &v, sizeof v);
  }
  for (; j < len; ++j) { /* an odd last sample */
    double v = 0.0 + dc[j] * coef[0];
    for (size_t i = 1; i + 1 < terms; i += 2)
      v = (v + dc[i * period + j] * coef[i]) + dc[(i + 1) * period + j] * coef[i + 1];
    t[j] = v;
  }
}

/* dst[k] = (x[start + k] less the trend of the last fit) w[k], k < m: the
 * DC and harmonics of r->trend_coef, the rotor restarted at start (the fit's
 * phase origin); with a whole hum period, one period of the trend computed
 * and repeated. The window's product w[k] in the same pass: each value the
 * same two roundings as a pass of its own after, one pass over the samples
 * fewer. */
void af_response_trend_remove(af_response *r, const float *x, size_t start, size_t m,
                              const double *w, double *dst)
{
  size_t harmonics = (r->trend_terms - 1) / 2, period = r->hum_period;
  double coef[AF_RESPONSE_MAX_TERMS];
  for (size_t i = 0; i < r->trend_terms; ++i)
    coef[i] = gsl_vector_get(r->trend_coef, i);
  if (harmonics > 0 && period > 0) {
    const double *t = r->trend_fold;
    trend_period(r, coef, m < period ? m : period);
    for (size_t k0 = 0; k0 < m; k0 += period)
      for (size_t j = 0, len = m - k0 < period ? m - k0 : period; j < len; ++j)
        dst[k0 + j] = ((double)x[start + k0 + j] - t[j]) * w[k0 + j];
    return;
  }
  if (harmonics == 0) { /* the constant alone: trend_at's 0 + 1 x coef, once */
    const double t0 = 0.0 + coef[0];
    for (size_t k = 0; k < m; ++k)
      dst[k] = ((double)x[start + k] - t0) * w[k];
    return;
  }
  rotor rot = rotor_start(r);
  for (size_t k = 0; k < m; ++k)
    dst[k] = ((double)x[start + k] - trend_at(r, &rot, harmonics, k, coef)) * w[k];
}

/* ---- the trend's share of a mode (peak list) -----------------------------------
 * The least-squares trend is fitted to the analysed samples with the ringing
 * in them, so it takes a little of each mode with it: the mode's projection
 * onto the DC and the hum's harmonics over the m samples. The transform holds
 * each mode less that share, a steady tone per term, windowed: a false peak
 * at every removed harmonic and skirts that rise towards the list band's
 * lower edge. A mode subtracted without its share leaves them behind as
 * maxima that no decaying pole fits (on the line-rate bag they drew
 * 87 % of the peak list's two-pole attempts, 220 of 221 refused, and its
 * slowest analyses).
 *
 * Each term is a pole on the window's decay, z = exp(-dt / tau_w + i h theta)
 * (h = 0 the DC), and its conjugate; as the window holds it over m samples it
 * sums at bin k to T(z u) - F(z u), T(a) = (1 - a^m) / (1 - a), F the fade-in's
 * part (response_mode.c). 1 / (1 - z u) and F depend on the configuration
 * alone, so they are tabled once per process (memo.h); the cut's a^m =
 * z^m u^m is the call's. */

/* The tables are kept for transforms up to this size [points]: 8 MiB with
 * the default 3 harmonics (48 kHz: windows up to 0.34 s at the default
 * padding). A larger transform (a rate of several hundred kHz, or windows
 * of seconds) would need tens to hundreds of MiB per lane; its list takes
 * the modes off without their share, as before 2026-11-28. */
#define AF_RESPONSE_SHARE_MAX_FFT 65536

size_t af_response_share_terms(const af_response_config *c)
{
  if (c->window != AF_RESPONSE_WINDOW_EXPONENTIAL || c->fft_size > AF_RESPONSE_SHARE_MAX_FFT)
    return 0; /* a pole on the unit circle: not modelled; or tables too large */
  return 1 + (c->hum_hz > 0.0 ? c->hum_harmonics : 0);
}

size_t af_response_share_table_bytes(const af_response_config *c)
{
  return c == NULL
             ? 0
             : 4 * af_response_share_terms(c) * (c->fft_size / 2 + 1) * sizeof(double complex);
}

/* The tables' arguments (no padding: the key is its bytes). */
typedef struct {
  uint64_t fft_size, fade_samples, terms;
  double sample_rate_hz, window_time_constant_s, hum_hz;
} share_key;

/* log z of term h's pole: the h-th harmonic of hum_hz (h = 0 the DC) on the
 * window's decay 1 / tau_s. */
static double complex term_log_pole(double fs_hz, double tau_s, double hum_hz, size_t h)
{
  double w = 2.0 * AF_PI * (double)h * hum_hz / fs_hz;
  return -1.0 / (fs_hz * tau_s) + I * w;
}

static af_status share_values(const void *key, void *out)
{
  const share_key *k = key;
  size_t bins = k->fft_size / 2 + 1, length = k->fade_samples;
  double complex e, eh;
  af_response_fade_phases(length, &e, &eh);
  size_t sides = 2 * k->terms;
  double complex *g = out, *pinv = g + sides * bins;
  for (size_t t = 0; t < sides; ++t) {
    double complex lz =
        term_log_pole(k->sample_rate_hz, k->window_time_constant_s, k->hum_hz, t / 2);
    lz = t % 2 ? conj(lz) : lz; /* side 0 the pole, 1 its conjugate */
    double complex z = cexp(lz), zl = cexp((double)length * lz);
    for (size_t i = 0; i < bins; ++i) {
      double complex a = z * af_response_phase(i, k->fft_size, 1.0), inv = 1.0 / (1.0 - a);
      double complex al = zl * af_response_phase(i, k->fft_size, (double)length);
      pinv[i * sides + t] = inv; /* bin by bin: a bin's terms side by side */
      g[i * sides + t] = inv - af_response_fade_part(length, e, eh, a, al, inv);
    }
  }
  return AF_OK;
}

af_status af_response_fill_share_tables(af_response *r)
{
  const af_response_config *c = &r->cfg;
  const share_key key = {c->fft_size,       r->fade_samples,           r->share_terms,
                         c->sample_rate_hz, c->window_time_constant_s, c->hum_hz};
  static const char kind[] = "response trend share";
  const size_t size = af_response_share_table_bytes(c);
  /* shared read-only: 1 MiB by default, a copy per lane was most of making one */
  const double complex *t = af_memo_ref(kind, &key, sizeof key, share_values, size);
  if (t == NULL) {
    if ((r->share_own = fftw_alloc_complex(size / sizeof *r->share_own)) == NULL)
      return AF_ENOMEM;
    (void)share_values(&key, r->share_own);
    t = r->share_own;
  }
  r->share_g = t;
  r->share_p = t + 2 * r->share_terms * r->bins;
  return AF_OK;
}

/* T(a) = sum_{k < m} a^k = (1 - a^m) / (1 - a), a = exp(la). */
static double complex geometric_sum(double complex la, double m)
{
  return (1.0 - cexp(m * la)) / (1.0 - cexp(la));
}

/* The trend fit's coefficients of the mode pk's own samples (c zeta^k +
 * conj, k < m, zeta its pole without the window's decay) into a[0..p); 0 if
 * they are not finite. */
static int share_coefficients(const af_response *r, const af_peak *pk, double *a)
{
  const af_response_config *c = &r->cfg;
  size_t p = r->trend_terms, harmonics = (p - 1) / 2;
  double fs = c->sample_rate_hz, m = r->split_len, theta = 2.0 * AF_PI * c->hum_hz / fs;
  double complex lz = -(pk->sigma_windowed - 1.0 / c->window_time_constant_s) / fs +
                      I * 2.0 * AF_PI * pk->bin / (double)c->fft_size;
  double b[AF_RESPONSE_MAX_TERMS];
  /* the inner products with the basis 1, cos(h theta k), sin(h theta k) */
  b[0] = 2.0 * creal(pk->c * geometric_sum(lz, m));
  for (size_t h = 1; h <= harmonics; ++h) {
    double complex tp = geometric_sum(lz + I * theta * (double)h, m);
    double complex tm = geometric_sum(lz - I * theta * (double)h, m);
    b[2 * h - 1] = creal(pk->c * (tp + tm));
    b[2 * h] = cimag(pk->c * (tp - tm));
  }
  if (p == 1) {
    a[0] = b[0] / m; /* the fit's fallback: the mean alone */
  } else {
    /* the fit's normal matrix, Cholesky-factored in place by it */
    gsl_matrix_const_view g = gsl_matrix_const_submatrix(r->trend_gram, 0, 0, p, p);
    gsl_vector_const_view bv = gsl_vector_const_view_array(b, p);
    gsl_vector_view av = gsl_vector_view_array(a, p);
    if (gsl_linalg_cholesky_solve(&g.matrix, &bv.vector, &av.vector) != GSL_SUCCESS)
      return 0;
  }
  for (size_t i = 0; i < p; ++i)
    if (!isfinite(a[i]))
      return 0;
  return 1;
}

/* z as (re, im) and its swap (im, re) in one register each. */
static inline af_v2d v2d_of(double complex z)
{
  af_v2d v = {creal(z), cimag(z)};
  return v;
}

static inline af_v2d v2d_swap(af_v2d v)
{
  af_v2d s = {v[1], v[0]};
  return s;
}

/* The share's coefficients per side, one complex in a register: k_re =
 * (cr, cr) and k_im = (-ci, ci), so that k_re x + k_im swap(x) is, part by
 * part, the scalar c x = (cr xr - ci xi) + i (cr xi + ci xr) ((-ci) xi is
 * -(ci xi) exactly). */
typedef struct {
  af_v2d c_re[2 * (AF_RESPONSE_MAX_HUM_HARMONICS + 1)],
      c_im[2 * (AF_RESPONSE_MAX_HUM_HARMONICS + 1)];
  af_v2d p_re[2 * (AF_RESPONSE_MAX_HUM_HARMONICS + 1)],
      p_im[2 * (AF_RESPONSE_MAX_HUM_HARMONICS + 1)];
} share_k;

/* Side s's terms of a bin (its tables' row gt, pt) added to the sums g, p. */
AF_NUMERIC_KERNEL static inline void share_side(const share_k *k, size_t s,
                                                const double complex *gt, const double complex *pt,
                                                af_v2d *g, af_v2d *p)
{
  af_v2d x = v2d_of(gt[s]), y = v2d_of(pt[s]);
  *g += k->c_re[s] * x + k->c_im[s] * v2d_swap(x);
  *p += k->p_re[s] * y + k->p_im[s] * v2d_swap(y);
}

/* r->spec[i] += sum_t c[t] g_t(i) - u_i^m sum_t czm[t] p_t(i) over the first
 * n sides (n even: a pole and its conjugate), i in [lo, hi]: each sum in the
 * order of the scalar loop it replaces, with each bin's complex in one
 * register (response_private.h on af_v2d: the same doubles, 2.5 times fewer
 * instructions). */
static inline __attribute__((always_inline)) void share_apply_n(af_response *r, const share_k *k,
                                                                size_t n, size_t lo, size_t hi)
{
  size_t sides = 2 * r->share_terms;
  for (size_t i = lo; i <= hi; ++i) {
    const double complex *gt = r->share_g + i * sides, *pt = r->share_p + i * sides;
    af_v2d g = {0.0, 0.0}, p = {0.0, 0.0};
#pragma GCC unroll 9
    for (size_t t = 0; t < n; t += 2) { /* a pole and its conjugate a pass */
      share_side(k, t, gt, pt, &g, &p);
      share_side(k, t + 1, gt, pt, &g, &p);
    }
    af_v2d u = v2d_of(r->phase_um[i]);
    af_v2d up = (af_v2d){u[0], u[0]} * p + (af_v2d){-u[1], u[1]} * v2d_swap(p);
    af_v2d x = v2d_of(r->spec[i]) + (g - up);
    r->spec[i] = complex_of(x[0], x[1]);
  }
}

/* share_apply_n, inlined with the sides of the default count of harmonics
 * constant (the loop over them unrolled: 7 k instructions a strike). */
AF_NUMERIC_KERNEL static void share_apply(af_response *r, const share_k *k, size_t n, size_t lo,
                                          size_t hi)
{
  if (n == 2 * (1 + AF_DEFAULT_MEASURE_HUM_HARMONICS))
    share_apply_n(r, k, 2 * (1 + AF_DEFAULT_MEASURE_HUM_HARMONICS), lo, hi);
  else
    share_apply_n(r, k, n, lo, hi);
}

void af_response_add_trend_share(af_response *r, const af_peak *pk, size_t lo, size_t hi)
{
  size_t terms = (r->trend_terms - 1) / 2 + 1;
  double a[AF_RESPONSE_MAX_TERMS];
  if (r->share_terms == 0 || terms > r->share_terms || !share_coefficients(r, pk, a))
    return;
  /* per term and side: its amplitude c (the DC a_0 is c = a_0 / 2 on a real
   * pole; a_c cos + a_s sin is c = (a_c - i a_s) / 2) and c z^m */
  share_k k;
  const af_response_config *cf = &r->cfg;
  double m = r->split_len;
  for (size_t h = 0; h < terms; ++h) {
    double complex ch = h == 0 ? 0.5 * a[0] : 0.5 * (a[2 * h - 1] - I * a[2 * h]);
    double complex zm =
        cexp(m * term_log_pole(cf->sample_rate_hz, cf->window_time_constant_s, cf->hum_hz, h));
    double complex czm = ch * zm;
    for (size_t s = 0; s < 2; ++s) { /* the pole, then its conjugate */
      double sign = s == 0 ? 1.0 : -1.0;
      k.c_re[2 * h + s] = (af_v2d){creal(ch), creal(ch)};
      k.c_im[2 * h + s] = (af_v2d){-sign * cimag(ch), sign * cimag(ch)};
      k.p_re[2 * h + s] = (af_v2d){creal(czm), creal(czm)};
      k.p_im[2 * h + s] = (af_v2d){-sign * cimag(czm), sign * cimag(czm)};
    }
  }
  share_apply(r, &k, 2 * terms, lo, hi);
}
