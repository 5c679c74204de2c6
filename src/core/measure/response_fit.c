/* response_fit.c — the Levenberg-Marquardt fits of the complex spectrum
 * (solver: response_lm.c; the models' residual pass by variable projection:
 * response_vp.c), the bare pole pair of stage 2 and the truncated one- or
 * two-pole model of the peak list; stage 2 itself and its round with one
 * neighbour.
 *
 * Stage 2: the DFT of a damped cosine is the pole pair (response_mode.c).
 * An onset at sample d > 0 adds nothing new: the sum from d is
 * c z^d / (1 - z u) + conj(...) minus the transform of the d missing samples,
 * a polynomial in u, smooth across the peak (its width is fs / d). So are the
 * far modes' skirts and the hum's. Hence
 *   X_k ~ c / (1 - z u_k) + conj(c) / (1 - conj(z) u_k) + B(x_k),
 * B a complex quadratic in the bin offset x = (k - k*) / h, fitted on the
 * complex bins, unweighted (white noise has the same variance in every bin).
 * c = a (1 - r0) and the data are scaled by 1/|X_k*| so that every parameter
 * is of order 1 at the start.
 *
 * The truncated model (peak list): for m analysed samples a mode sums to
 * c T(z u) + conj(c) T(conj(z) u), T(a) = (1 - a^m) / (1 - a), so the ripple
 * the window's cut leaves is no misfit. Both models lay their parameters out
 * alike: per pole f0 [bins], sigma' [1/s], Re and Im of the scaled
 * amplitude; then the background's 6. */
#include "response_private.h"

#include <math.h>
#include <string.h>

/* The complex fit spans this many half-widths (sigma' / 2 pi) each side of
 * the peak, at least AF_RESPONSE_FIT_MIN_HALF bins: wide enough to pin the
 * background polynomial, narrow enough for a quadratic to follow it. */
#define AF_RESPONSE_FIT_HALFWIDTHS 2.5
#define AF_RESPONSE_FIT_MIN_HALF 4
/* Levenberg-Marquardt stops (response_lm.c): steps of f0 and sigma' below
 * 1e-8 relative, or gradient/cost changes at rounding level; at most 50
 * iterations (typically 3-15; a stage-2 fit that reaches the cap is refused:
 * status CAPPED). */
#define AF_RESPONSE_FIT_MAX_ITER 50
#define AF_RESPONSE_FIT_XTOL 1e-8
#define AF_RESPONSE_FIT_GTOL 1e-10
#define AF_RESPONSE_FIT_FTOL 1e-10
/* The truncated fits stop at steps below 1e-6 relative: 1e-6 of a bin is
 * far below the noise's scatter, and it halves their iterations. The
 * one-pole fits (these and stage 2) stop sooner where the noise allows
 * (af_response_fit_noise). */
#define AF_RESPONSE_SPLIT_XTOL 1e-6
/* Iteration cap of the truncated fits: from the stage-1 reading a one-pole
 * fit takes 3-4 (a misfit, well above the noise, up to ~20), a refit ~3; a
 * two-pole fit that has not settled in 25 is judged where it stands (status
 * CAPPED; most of the two-pole fits on a noisy comb, most then refused). */
#define AF_RESPONSE_SPLIT_MAX_ITER 25

/* Parameters of a pole and of the background that follows the poles. */
enum { P_BIN, P_SIGMA, P_ARE, P_AIM, P_POLE, P_BACKGROUND = 6 };

/* ---- the fit's bins and parameters ------------------------------------------ */

size_t af_response_fit_half(const af_response *r, double sigma_windowed)
{
  double halfwidth_bins = sigma_windowed / (2.0 * AF_PI * r->bin_hz);
  double span = ceil(AF_RESPONSE_FIT_HALFWIDTHS * halfwidth_bins);
  if (!(span > AF_RESPONSE_FIT_MIN_HALF))
    return AF_RESPONSE_FIT_MIN_HALF;
  return span > AF_RESPONSE_FIT_MAX_HALF ? AF_RESPONSE_FIT_MAX_HALF : (size_t)span;
}

void af_response_fit_around(const af_response *r, size_t k, size_t half, size_t *first,
                            size_t *last)
{
  *first = k > half ? k - half : 1;
  *last = k + half < r->bins - 1 ? k + half : r->bins - 1;
}

int af_response_fit_bins(af_response *r, const double complex *data, size_t first, size_t last,
                         double center, double half, size_t k, double sigma_windowed)
{
  r->ctx.data = data;
  r->ctx.first = first;
  r->ctx.count = last - first + 1;
  r->ctx.center = center;
  r->ctx.half = half;
  r->ctx.gain = 1.0 / cabs(data[k]);
  r->ctx.norm = 1.0 - exp(-sigma_windowed / r->cfg.sample_rate_hz);
  r->ctx.cost_floor = 0.0;
  r->ctx.cost_stop = 0.0;
  return isfinite(r->ctx.gain) && r->ctx.norm > 0.0;
}

/* A fit's cost is the residual sum of squares of the scaled bins; noise of
 * power 'noise' per bin puts sigma_r^2 = noise gain^2 / 2 on each real
 * component, and the poles' parameters scatter with covariance
 * sigma_r^2 (J^T J)^-1. The Gauss-Newton step from a point, dx =
 * -(J^T J)^-1 g, would lower the cost by g^T (J^T J)^-1 g = sigma_r^2 d^2, d
 * the distance to the (linearised) minimum in those standard errors: at most
 * AF_RESPONSE_FIT_STOP^2 sigma_r^2 (response_lm.c) puts the point within
 * AF_RESPONSE_FIT_STOP standard errors of the minimum, a small fraction of the
 * reading's own scatter under that noise. xtol (1e-6 relative) alone takes
 * one to three steps more, each a pass over the bins. */
#define AF_RESPONSE_FIT_STOP 0.1

void af_response_fit_noise(af_response *r, double noise)
{
  double floor =
      AF_RESPONSE_FIT_STOP * AF_RESPONSE_FIT_STOP * 0.5 * noise * r->ctx.gain * r->ctx.gain;
  r->ctx.cost_floor = isfinite(floor) && floor > 0.0 ? floor : 0.0;
}

void af_response_fit_seed(const af_response *r, double *x0, size_t slot, double bin, double sigma,
                          double complex c)
{
  x0[P_POLE * slot + P_BIN] = bin;
  x0[P_POLE * slot + P_SIGMA] = sigma;
  x0[P_POLE * slot + P_ARE] = r->ctx.gain * creal(c) / r->ctx.norm;
  x0[P_POLE * slot + P_AIM] = r->ctx.gain * cimag(c) / r->ctx.norm;
}

/* Pole j of the parameters p as a mode of the spectrum (its span untouched). */
static void pole_at(const af_response *r, const double *p, size_t j, af_peak *out)
{
  out->bin = p[P_POLE * j + P_BIN];
  out->sigma_windowed = p[P_POLE * j + P_SIGMA];
  out->c = r->ctx.norm / r->ctx.gain * (p[P_POLE * j + P_ARE] + I * p[P_POLE * j + P_AIM]);
  out->peak_power = af_response_mode_peak_power(r, out->c, out->sigma_windowed);
}

/* Runs the fit of r->ctx (model r->split_poles, params 10 or 14, laid out
 * as above) from x (the solution into x), at most max_iter iterations; its
 * cost (residual sum of squares) into *rss. The solver (response_lm.c) moves
 * only each pole's f0 and sigma'; the amplitudes and the background are
 * solved at every point (variable projection, response_vp.c), so x's
 * starting amplitudes are not used. Counted in r->fit_stats. */
static af_response_fit_status run(af_response *r, size_t params, double *x, size_t max_iter,
                                  double xtol, double *rss)
{
  size_t poles = (params - P_BACKGROUND) / P_POLE, iter = 0;
  double theta[4], beta[AF_RESPONSE_SPLIT_PARAMS];
  for (size_t j = 0; j < poles; ++j) {
    theta[2 * j] = x[P_POLE * j + P_BIN];
    theta[2 * j + 1] = x[P_POLE * j + P_SIGMA];
  }
  af_response_fit_status st =
      af_response_lm(r, 2 * poles, theta, beta, max_iter, xtol, AF_RESPONSE_FIT_GTOL,
                     AF_RESPONSE_FIT_FTOL, rss, &iter);
  r->fit_stats.fits[st]++;
  r->fit_stats.iterations += iter;
  if (iter > r->fit_stats.max_iterations)
    r->fit_stats.max_iterations = iter;
  if (st == AF_RESPONSE_FIT_FAILED)
    return st;
  for (size_t j = 0; j < poles; ++j) {
    x[P_POLE * j + P_BIN] = theta[2 * j];
    x[P_POLE * j + P_SIGMA] = theta[2 * j + 1];
    x[P_POLE * j + P_ARE] = beta[2 * j];
    x[P_POLE * j + P_AIM] = beta[2 * j + 1];
  }
  memcpy(x + P_POLE * poles, beta + 2 * poles, P_BACKGROUND * sizeof *x);
  return st;
}

/* ---- stage 2 ------------------------------------------------------------------ */

/* Stage 2 on the spectrum x near its local maximum k, from the seed in *pk,
 * ending within a small fraction of the pole's standard errors under noise of
 * power 'noise' per bin (af_response_fit_noise); 0 (*pk untouched) if the fit
 * fails or its frequency leaves the peak's top (it went for a neighbour or the
 * background). */
static int stage2(af_response *r, const double complex *x, size_t k, af_peak *pk, double noise)
{
  size_t half = af_response_fit_half(r, pk->sigma_windowed), first, last;
  af_response_fit_around(r, k, half, &first, &last);
  if (!af_response_fit_bins(r, x, first, last, (double)k, (double)half, k, pk->sigma_windowed))
    return 0;
  af_response_fit_noise(r, noise);
  double *p0 = r->fit_start, rss;
  memset(p0, 0, sizeof r->fit_start);
  af_response_fit_seed(r, p0, 0, pk->bin, pk->sigma_windowed, pk->c);
  r->split_poles = 0;
  /* stage 2 must converge: a capped or stalled fit is no damped mode here */
  if (run(r, AF_RESPONSE_FIT_PARAMS, p0, AF_RESPONSE_FIT_MAX_ITER, AF_RESPONSE_FIT_XTOL, &rss) !=
      AF_RESPONSE_FIT_CONVERGED)
    return 0;
  af_peak got = *pk;
  pole_at(r, p0, 0, &got);
  if (!(got.bin >= pk->span_lo && got.bin <= pk->span_hi) || !(got.sigma_windowed > 0.0))
    return 0;
  *pk = got;
  return 1;
}

/* ---- the truncated fits (peak list) ------------------------------------------ */

int af_response_split_run(af_response *r, size_t poles, const double *start, double *rss)
{
  size_t params = P_POLE * poles + P_BACKGROUND;
  r->split_poles = poles;
  memcpy(r->split_x, start, params * sizeof *start);
  /* a truncated fit that reaches its cap or stalls is judged where it
   * stands (its residual decides); only a failed one is refused */
  r->split_status =
      run(r, params, r->split_x, AF_RESPONSE_SPLIT_MAX_ITER, AF_RESPONSE_SPLIT_XTOL, rss);
  if (r->split_status == AF_RESPONSE_FIT_FAILED)
    return 0;
  return isfinite(*rss);
}

int af_response_split_pole(const af_response *r, const double *p, size_t j, af_peak *out)
{
  double sigma_window =
      r->cfg.window == AF_RESPONSE_WINDOW_EXPONENTIAL ? 1.0 / r->cfg.window_time_constant_s : 0.0;
  double first = (double)r->ctx.first, last = first + (double)r->ctx.count - 1.0;
  af_peak q;
  pole_at(r, p, j, &q);
  if (!(q.bin >= first && q.bin <= last) || !(q.sigma_windowed > sigma_window))
    return 0;
  q.span_lo = first;
  q.span_hi = last;
  *out = q;
  return 1;
}

/* ---- one neighbour -------------------------------------------------------------
 * A mode close enough for its peak to reach into the fit (a weak mode in the
 * range, a split 0S2, a loud mode just outside) is not smooth there and biases
 * the quadratic background. It is fitted in turn and taken off: fit the 0S2,
 * fit the neighbour on the spectrum less the 0S2, fit the 0S2 again on the
 * spectrum less the neighbour (one round of alternating fits). */

/* work = spec - the mode pk, with its power, over the bins any fit around k
 * or j can read. */
static void subtract(af_response *r, const af_peak *pk, size_t k, size_t j)
{
  size_t a = k < j ? k : j, b = k < j ? j : k, reach = AF_RESPONSE_FIT_MAX_HALF + 2;
  size_t lo = a > reach ? a - reach : 0;
  size_t hi = b + reach < r->bins ? b + reach : r->bins - 1;
  double complex z = af_response_pole(r, pk->bin, pk->sigma_windowed);
  for (size_t i = lo; i <= hi; ++i) {
    r->work[i] = r->spec[i] - af_response_pole_pair(r, z, pk->c, i);
    r->work_power[i] = creal(r->work[i] * conj(r->work[i]));
  }
}

/* The mode at the local maximum k, refined as far as the data allow; 1 if
 * the complex fit (stage 2) holds, 0 for a stage-1 or log-parabola estimate. */
int af_response_refine(af_response *r, size_t k, double noise, af_peak *out)
{
  if (!af_response_stage1(r, r->power, r->spec, k, out)) {
    af_response_log_parabola(r, k, out);
    return 0;
  }
  if (!stage2(r, r->spec, k, out, noise))
    return 0;
  double min_power = noise * pow(10.0, 0.1 * r->cfg.snr_threshold_db);
  size_t j;
  if (!af_response_find_neighbour(r, k, af_response_fit_half(r, out->sigma_windowed), min_power,
                                  &j))
    return 1;
  af_peak nb, again = *out;
  subtract(r, out, k, j);
  if (!(r->work_power[j] > r->work_power[j - 1] && r->work_power[j] >= r->work_power[j + 1]) ||
      !af_response_stage1(r, r->work_power, r->work, j, &nb) || !stage2(r, r->work, j, &nb, noise))
    return 1;
  subtract(r, &nb, k, j);
  if (stage2(r, r->work, k, &again, noise))
    *out = again;
  return 1;
}
