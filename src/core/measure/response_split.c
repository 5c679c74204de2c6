/* response_split.c — the peak list's refinements beyond one pole: two close
 * modes read as two poles (the split), and every listed mode read again on
 * the transform less the others (the backfit). The fits are response_fit.c's
 * truncated fits. */
#include "response_private.h"

#include <math.h>
#include <string.h>

/* ---- two close modes (peak list) ---------------------------------------------
 * Two modes closer than their windowed width (a split 0S2, the 0T2 or a
 * support mode a few per cent from it) make one peak: no second maximum for
 * the neighbour fit to find, and one pole fitted to the blend lands between
 * them. A peak whose one-pole fit leaves a misfit well above the noise is
 * fitted again with two poles; two poles that explain the data far better,
 * both decaying, both clearing the threshold and neither negligible against
 * the other, replace it. Both fits model the window's end exactly: for m
 * analysed samples a mode sums to c T(z u) + conj(c) T(conj(z) u),
 * T(a) = (1 - a^m) / (1 - a): the ripple the cut leaves (~ -36 dB at 40 ms)
 * is no misfit then. */

/* The one-pole fit leaves this many times the noise's expected residual
 * before two poles are tried: a mode alone leaves ~1x. */
#define AF_RESPONSE_SPLIT_MISFIT 4.0
/* Two poles must cut the one-pole residual to this fraction (-10 dB). */
#define AF_RESPONSE_SPLIT_GAIN 0.1
/* The two-pole fit spans this many times the one-pole fit's half-span
 * beyond the outer poles (at most the fit's rows). */
#define AF_RESPONSE_SPLIT_SPAN 2
/* Starting offsets of the two poles from the one-pole frequency, in
 * half-widths of the one-pole fit. */
static const double split_offsets[] = {0.5, 1.0};

/* The truncated one-pole fit of the mode pk on r->ctx; its residual sum of
 * squares into *rss; 0 if it fails. It stops within a small fraction of the
 * pole's standard errors under noise of power 'noise' per bin
 * (af_response_fit_noise). Not the two-pole fits: two poles a few bins apart
 * trade amplitude for position, their J^T J is near singular and its
 * standard errors large, and a linearised test there would stop them short of
 * the minimum (a split 0S3 left in the spectrum hid the 0S2 beside it).
 * cost_stop > 0 also ends it at a cost (the scaled bins' residual sum of
 * squares) of at most cost_stop: every step lowers the cost, so the minimum
 * lies below it. */
static int one_pole(af_response *r, const af_peak *pk, double noise, double cost_stop, double *rss)
{
  memset(r->fit_start, 0, sizeof r->fit_start);
  af_response_fit_seed(r, r->fit_start, 0, pk->bin, pk->sigma_windowed, pk->c);
  af_response_fit_noise(r, noise);
  r->ctx.cost_stop = cost_stop;
  int ok = af_response_split_run(r, 1, r->fit_start, rss);
  af_response_fit_noise(r, 0.0);
  r->ctx.cost_stop = 0.0;
  return ok;
}

/* The bins of a two-pole fit around k (and the neighbour j, 0 if none):
 * twice the one-pole fit's half-span beyond both (two poles and the
 * background need more bins than one), at most the fit's rows. */
static int split_setup(af_response *r, size_t k, size_t j, const af_peak *pk)
{
  size_t half = AF_RESPONSE_SPLIT_SPAN * af_response_fit_half(r, pk->sigma_windowed);
  size_t a = j != 0 && j < k ? j : k, b = j > k ? j : k;
  /* at most 2 AF_RESPONSE_FIT_MAX_HALF + 1 bins: the rows of the fit (the
   * neighbour search keeps b - a within 4 fit half-spans <= 2 MAX_HALF) */
  size_t cap =
      b - a < 2 * AF_RESPONSE_FIT_MAX_HALF ? (2 * AF_RESPONSE_FIT_MAX_HALF - (b - a)) / 2 : 0;
  if (half > cap)
    half = cap;
  size_t first = a > half ? a - half : 1;
  size_t last = b + half < r->bins - 1 ? b + half : r->bins - 1;
  return af_response_fit_bins(r, r->spec, first, last, 0.5 * (double)(first + last),
                              0.5 * (double)(last - first), k, pk->sigma_windowed);
}
/* Checks the two poles of the last two-pole fit (rules above); 1 with them
 * in a[0], a[1], lower first. */
static int split_accept(const af_response *r, double threshold, af_peak a[2])
{
  af_peak lo, hi;
  const double *p = r->split_x;
  if (!af_response_split_pole(r, p, 0, &lo) || !af_response_split_pole(r, p, 1, &hi) ||
      !(fabs(lo.bin - hi.bin) >= 1.0))
    return 0;
  double weak = fmin(lo.peak_power, hi.peak_power), strong = fmax(lo.peak_power, hi.peak_power);
  if (!(weak >= threshold) || !(weak >= AF_RESPONSE_SPLIT_MIN_RATIO * strong))
    return 0;
  a[0] = lo.bin < hi.bin ? lo : hi;
  a[1] = lo.bin < hi.bin ? hi : lo;
  return 1;
}

/* The truncated reading of the peak at bin k whose one-pole refinement is pk
 * (noise: power per bin there; m analysed samples):
 *  2  two modes in a[0], a[1] (lower first) replace it (rules above);
 *  1  one mode in a[0]: the truncated one-pole fit, more exact than pk (it
 *     fits to the noise, no neighbour in the span, the pole on the peak's
 *     top, decaying);
 *  0  nothing better than pk.
 * A prominent neighbouring maximum within two fit half-widths (a mode the
 * one-pole refinement fitted and took off in one round of alternation,
 * biased when the two overlap) seeds the second pole; without one, the
 * second pole starts on either side of the first. */
int af_response_split(af_response *r, size_t k, const af_peak *pk, double noise, af_peak a[2])
{
  double threshold = noise * pow(10.0, 0.1 * r->cfg.snr_threshold_db);
  size_t j = 0;
  if (!af_response_find_neighbour(r, k, af_response_fit_half(r, pk->sigma_windowed), threshold, &j))
    j = 0;
  if (!split_setup(r, k, j, pk))
    return 0;
  double rss1, expected = (double)r->ctx.count * noise * r->ctx.gain * r->ctx.gain;
  /* with a neighbour the one-pole fit only asks whether the misfit calls for
   * two poles: once its cost is under that, its minimum is (every step
   * lowers the cost) and the answer is 0 whatever the end; it ends there
   * (the weak candidates beside a mode, most of them rejected: 37 % of the
   * model passes' instructions on the 600-strike line bag) */
  if (!one_pole(r, pk, noise, j != 0 ? AF_RESPONSE_SPLIT_MISFIT * expected : 0.0, &rss1))
    return 0;
  if (!(rss1 > AF_RESPONSE_SPLIT_MISFIT * expected))
    return j == 0 && af_response_split_pole(r, r->split_x, 0, &a[0]) && a[0].bin >= pk->span_lo &&
           a[0].bin <= pk->span_hi;
  double sigma_window =
      r->cfg.window == AF_RESPONSE_WINDOW_EXPONENTIAL ? 1.0 / r->cfg.window_time_constant_s : 0.0;
  double sigma0 = fmax(0.6 * pk->sigma_windowed, sigma_window + 0.1 * pk->sigma_windowed);
  double halfwidth_bins = pk->sigma_windowed / (2.0 * AF_PI * r->bin_hz);
  size_t tries = sizeof split_offsets / sizeof split_offsets[0];
  /* the neighbour's maximum first (when there is one), then the offsets; the
   * first start that passes is taken. A start whose fit converged and was
   * refused ends the split: the other starts reach the same minimum or none
   * that passes (the real captures' blends: 8 of 9 later starts at the first
   * one's cost; the close-modes, comb and hum sets: no later start passed
   * after one converged and was refused), and each is a two-pole fit of up to
   * AF_RESPONSE_SPLIT_MAX_ITER passes. Only a start cut short by the cap
   * (or a failed one) leaves the next to try. */
  double *x0 = r->fit_start;
  for (size_t t = j != 0 ? 0 : 1; t <= tries; ++t) {
    memset(x0, 0, sizeof r->fit_start);
    if (t == 0) {
      af_response_fit_seed(r, x0, 0, pk->bin, pk->sigma_windowed, pk->c);
      af_response_fit_seed(r, x0, 1, (double)j, pk->sigma_windowed,
                           cabs(pk->c) * sqrt(r->power[j] / r->power[k]) *
                               cexp(I * carg(r->spec[j])));
    } else {
      double d = split_offsets[t - 1] * halfwidth_bins;
      af_response_fit_seed(r, x0, 0, pk->bin - d, sigma0, 0.5 * pk->c);
      af_response_fit_seed(r, x0, 1, pk->bin + d, sigma0, 0.5 * pk->c);
    }
    double rss2;
    int ran = af_response_split_run(r, 2, x0, &rss2);
    if (ran && rss2 <= AF_RESPONSE_SPLIT_GAIN * rss1 &&
        rss2 <= AF_RESPONSE_SPLIT_MISFIT * expected && split_accept(r, threshold, a))
      return 2;
    if (ran && r->split_status == AF_RESPONSE_FIT_CONVERGED)
      break;
  }
  return 0;
}

/* ---- joint refinement (peak list) --------------------------------------------
 * Each mode was read with only the stronger ones taken off, and with a
 * quadratic background for the rest: a comparable mode 10-30 % away bends
 * that background more than a quadratic follows and pulls the reading by
 * 1-3 %. Once all are found, each is fitted again (truncated one-pole fit)
 * on the transform less every other listed mode, exactly as the window holds
 * them (backfitting); AF_RESPONSE_BACKFIT_PASSES passes. A refit that fails,
 * leaves its span, stops decaying or moves by more than a half-width keeps
 * the previous reading. */
#define AF_RESPONSE_BACKFIT_PASSES 2

/* Refits listed mode i on r->orig less the others; 1 if its reading moved. */
static int backfit_one(af_response *r, af_peak *modes, af_mode_k *consts, size_t n, size_t i,
                       double noise)
{
  size_t half = af_response_fit_half(r, modes[i].sigma_windowed), first, last;
  double centre = round(modes[i].bin);
  if (!(centre >= 1.0 && centre <= (double)(r->bins - 2)))
    return 0;
  size_t k = (size_t)centre;
  af_response_fit_around(r, k, half, &first, &last);
  if (first < r->orig_lo || last > r->orig_hi) /* beyond the bins copied: not refitted */
    return 0;
  for (size_t b = first; b <= last; ++b) {
    r->work[b] = r->orig[b];
    for (size_t j = 0; j < n; ++j)
      if (j != i)
        r->work[b] -= af_response_mode_at(r, &consts[j], b);
  }
  if (!af_response_fit_bins(r, r->work, first, last, (double)k, (double)half, k,
                            modes[i].sigma_windowed))
    return 0;
  double rss;
  af_peak pk;
  if (!one_pole(r, &modes[i], noise, 0.0, &rss) || !af_response_split_pole(r, r->split_x, 0, &pk))
    return 0;
  double halfwidth_bins = modes[i].sigma_windowed / (2.0 * AF_PI * r->bin_hz);
  if (!(fabs(pk.bin - modes[i].bin) <= halfwidth_bins))
    return 0;
  modes[i] = pk;
  consts[i] = af_response_mode_consts(r, &pk);
  return 1;
}

/* Backfits the n listed modes; their records (frequency, decay, amplitude,
 * SNR against noise[i], bounded by the original periodogram) follow. */
void af_response_list_backfit(af_response *r, af_response_result *list, af_peak *modes,
                              const double *noise, size_t n)
{
  af_mode_k consts[AF_RESPONSE_MAX_PEAKS];
  if (n < 2)
    return;
  for (size_t i = 0; i < n; ++i)
    consts[i] = af_response_mode_consts(r, &modes[i]);
  for (int pass = 0; pass < AF_RESPONSE_BACKFIT_PASSES; ++pass)
    for (size_t i = 0; i < n; ++i) {
      if (!backfit_one(r, modes, consts, n, i, noise[i]))
        continue;
      size_t k = (size_t)lround(modes[i].bin);
      double top = creal(r->orig[k] * conj(r->orig[k]));
      af_response_result_fill(r, &modes[i], &list[i]);
      list[i].snr_db =
          af_response_snr_db(fmin(modes[i].peak_power, AF_RESPONSE_PEAK_BOUND * top), noise[i]);
    }
}
