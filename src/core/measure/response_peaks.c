/* response_peaks.c — the peaks of a periodogram and their closed-form
 * reading: local floors, the prominent peak of a range, a neighbouring
 * maximum, and stage 1 (the 1/P parabola, or a log parabola for a peak
 * narrower than the bins) that seeds the fits of response_fit.c. */
#include "response_private.h"

#include <math.h>
#include <string.h>

/* The stage-1 parabola uses the bins above this fraction of the peak power
 * (-3 dB): there the mode dominates its neighbours' skirts and the noise. */
#define AF_RESPONSE_FIT_LEVEL 0.5

/* ---- peak ----------------------------------------------------------------- */

/* On each side of k the lowest power within AF_RESPONSE_FIT_MAX_HALF bins
 * before the spectrum climbs above p[k] again. A comparison, not fmin (a
 * call per bin): the bins compared are no NaN (each passed p <= p[k]) and no
 * power is -0, so both give the same value. */
void af_response_side_floors(const af_response *r, size_t k, double *left, double *right)
{
  const double *p = r->power;
  double lo = p[k], hi = p[k];
  for (size_t i = 1; i <= AF_RESPONSE_FIT_MAX_HALF && i < k && p[k - i] <= p[k]; ++i)
    lo = p[k - i] < lo ? p[k - i] : lo;
  for (size_t i = 1; i <= AF_RESPONSE_FIT_MAX_HALF && k + i < r->bins && p[k + i] <= p[k]; ++i)
    hi = p[k + i] < hi ? p[k + i] : hi;
  *left = lo;
  *right = hi;
}

/* The floor a peak at k rises from: the higher of its two side floors. */
static double local_floor(const af_response *r, size_t k)
{
  double left, right;
  af_response_side_floors(r, k, &left, &right);
  return fmax(left, right);
}

size_t af_response_find_peak(const af_response *r, double f_lo_hz, double f_hi_hz,
                             double *best_rise)
{
  size_t k_lo, k_hi, best = 0;
  af_response_band_bins(f_lo_hz, f_hi_hz, r->bin_hz, r->bins - 2, &k_lo, &k_hi);
  const double *p = r->power;
  *best_rise = 0.0;
  for (size_t k = k_lo; k <= k_hi; ++k) {
    if (!(p[k] > p[k - 1] && p[k] >= p[k + 1]))
      continue;
    double floor_k = local_floor(r, k);
    *best_rise = fmax(*best_rise, p[k] - floor_k);
    if (p[k] >= AF_RESPONSE_PROMINENCE * floor_k && (best == 0 || p[k] > p[best]))
      best = k;
  }
  return best;
}

/* Strongest local maximum j != k within two fit half-widths of k that clears
 * the SNR threshold and stands at least AF_RESPONSE_NEIGHBOUR_PROMINENCE
 * above the valley between it and k (a noise ripple on the skirt does not). */
int af_response_find_neighbour(const af_response *r, size_t k, size_t half, double min_power,
                               size_t *j_out)
{
  const double *p = r->power;
  size_t lo = k > 2 * half + 1 ? k - 2 * half : 1;
  size_t hi = k + 2 * half + 1 < r->bins - 1 ? k + 2 * half : r->bins - 2;
  size_t best = 0;
  for (size_t j = lo; j <= hi; ++j) {
    if (j == k || !(p[j] > p[j - 1] && p[j] >= p[j + 1]) || p[j] < min_power)
      continue;
    double valley = p[j];
    for (size_t i = j < k ? j : k; i <= (j < k ? k : j); ++i)
      valley = fmin(valley, p[i]);
    if (p[j] >= AF_RESPONSE_NEIGHBOUR_PROMINENCE * valley && (best == 0 || p[j] > p[best]))
      best = j;
  }
  *j_out = best;
  return best != 0;
}

/* ---- stage 1: the magnitude alone -------------------------------------------
 * The power spectrum of a windowed damped sinusoid near its peak is
 *   P = |c|^2 / ((1 - r)^2 + 4 r sin^2(pi x / N)),  r = exp(-sigma' / fs),
 * so 1/P is a parabola in the bin offset x (to 1e-5 over the peak). Closed
 * form, but biased by the skirts of nearby modes and by the mode's own
 * negative-frequency image (they add to the complex spectrum, not to P): it
 * seeds stage 2. */

/* Bins around k above AF_RESPONSE_FIT_LEVEL of p[k] and falling away from it
 * (a rise is the next peak), at least one each side. */
static void fit_span(const af_response *r, const double *p, size_t k, size_t *first, size_t *last)
{
  double level = AF_RESPONSE_FIT_LEVEL * p[k];
  size_t a = k - 1, b = k + 1;
  while (a > 1 && k - a < AF_RESPONSE_FIT_MAX_HALF && p[a - 1] >= level && p[a - 1] <= p[a])
    --a;
  while (b + 1 < r->bins && b - k < AF_RESPONSE_FIT_MAX_HALF && p[b + 1] >= level &&
         p[b + 1] <= p[b])
    ++b;
  *first = a;
  *last = b;
}

static double det3(double m[3][3])
{
  return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
         m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
         m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
}

/* Solves the 3x3 system m x = v by Cramer's rule; 0 if singular. */
static int solve3(double m[3][3], const double v[3], double x[3])
{
  double det = det3(m);
  if (!(fabs(det) > 0.0) || !isfinite(det))
    return 0;
  for (int c = 0; c < 3; ++c) {
    double t[3][3];
    memcpy(t, m, sizeof t);
    for (int i = 0; i < 3; ++i)
      t[i][c] = v[i];
    x[c] = det3(t) / det;
  }
  return 1;
}

/* Weighted least-squares parabola y = c0 + c1 x + c2 x^2 through 1/p at
 * x = j - k. Weights p^2: the residual in 1/p times p^2 is the residual in p
 * relative to p, so the top bins (highest SNR) count most. */
static int inverse_parabola(const double *p, size_t k, size_t first, size_t last, double c[3])
{
  double m[3][3] = {{0}}, v[3] = {0};
  for (size_t j = first; j <= last; ++j) {
    double x = (double)j - (double)k, w = p[j] * p[j];
    const double xp[5] = {1.0, x, x * x, x * x * x, x * x * x * x};
    for (int a = 0; a < 3; ++a) {
      v[a] += w * xp[a] / p[j];
      for (int b = 0; b < 3; ++b)
        m[a][b] += w * xp[a + b];
    }
  }
  return solve3(m, v, c);
}

/* Stage 1 on the power p of the spectrum x at its local maximum k. With the
 * parabola y_v + c2 (x - x_v)^2, c2 = 4 pi^2 r / (N^2 |c|^2), hence
 * (1 - r)^2 / r = q := 4 pi^2 y_v / (N^2 c2), whose root below 1 is r.
 * 0 when the parabola is not a peak. */
int af_response_stage1(const af_response *r, const double *p, const double complex *x, size_t k,
                       af_peak *out)
{
  size_t first, last;
  double c[3];
  fit_span(r, p, k, &first, &last);
  if (!inverse_parabola(p, k, first, last, c) || !(c[2] > 0.0))
    return 0;
  double xv = -c[1] / (2.0 * c[2]);
  double yv = c[0] - c[1] * c[1] / (4.0 * c[2]);
  if (!(yv > 0.0) || !(xv > (double)first - (double)k && xv < (double)last - (double)k))
    return 0;
  double n_fft = (double)r->cfg.fft_size;
  double q = 4.0 * AF_PI * AF_PI * yv / (n_fft * n_fft * c[2]);
  double rr = 0.5 * ((2.0 + q) - sqrt(q * (4.0 + q)));
  if (!(rr > 0.0 && rr < 1.0))
    return 0;
  out->bin = (double)k + xv;
  out->span_lo = (double)first;
  out->span_hi = (double)last;
  out->sigma_windowed = -log(rr) * r->cfg.sample_rate_hz;
  out->peak_power = 1.0 / yv;
  /* at the peak X = c / (1 - r): the modulus from the fit, the phase from the bin */
  out->c = sqrt(out->peak_power) * (1.0 - rr) * cexp(I * carg(x[k]));
  return 1;
}

/* Fallback when even stage 1 fails (a peak narrower than the bins): a
 * three-point parabola on log P (Gaussian interpolation); no decay. */
void af_response_log_parabola(const af_response *r, size_t k, af_peak *out)
{
  double a = log(r->power[k - 1]), b = log(r->power[k]), g = log(r->power[k + 1]);
  double den = a - 2.0 * b + g;
  double x = den < 0.0 ? 0.5 * (a - g) / den : 0.0;
  out->bin = (double)k + x;
  out->span_lo = (double)k - 1.0;
  out->span_hi = (double)k + 1.0;
  out->sigma_windowed = NAN;
  out->c = NAN;
  out->peak_power = exp(b - 0.25 * (a - g) * x);
}
