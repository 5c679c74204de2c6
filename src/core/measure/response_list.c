/* response_list.c — af_response_execute_peaks: the damped modes of a band from one
 * analysis, strongest first, each read (one pole, two for a blend, or
 * af_response_execute's refinement), judged as af_response_execute judges
 * its peak, and subtracted exactly as the window holds it before the next is
 * sought; at the end backfitted (response_split.c), sorted by frequency. */
#include "response_private.h"

#include <math.h>
#include <string.h>

/* ---- peak list ---------------------------------------------------------------
 * The modes of one transform, strongest first (response.h has the rules):
 * each candidate is read by a fit that models the window exactly (one pole,
 * or two for a blend; af_response_execute's refinement where neither
 * holds), judged as af_response_execute judges its peak, and subtracted
 * before the next is sought: a weaker mode beside a louder one (a 0S2 at
 * 0.67x a 0S3 2.5x louder) may stand only ~5 dB above the valley that their
 * two skirts fill, and stands clear once the louder one is gone. All found,
 * each is read again on the transform less the others (backfitting). */

/* A listed mode stands at most 30 dB (power ratio) below the strongest. */
#define AF_RESPONSE_LIST_RANGE 1e-3
/* Most refinements per call: every listed mode plus as many rejected tries. */
#define AF_RESPONSE_LIST_TRIES (2 * AF_RESPONSE_MAX_PEAKS)
/* Bins a rejected candidate keeps others out of until the next mode is
 * subtracted (its top, so that the same maximum is not tried again). */
#define AF_RESPONSE_LIST_EXCLUDE 1

static int is_excluded(const size_t *excluded, size_t n_excluded, size_t k)
{
  for (size_t i = 0; i < n_excluded; ++i)
    if (k + AF_RESPONSE_LIST_EXCLUDE >= excluded[i] && k <= excluded[i] + AF_RESPONSE_LIST_EXCLUDE)
      return 1;
  return 0;
}

/* The strongest local maximum of r->power in [k_lo, k_hi] standing
 * AF_RESPONSE_PROMINENCE (6 dB) above its floor on one side and
 * AF_RESPONSE_NEIGHBOUR_PROMINENCE (3 dB) on the other: two modes ~10 %
 * apart fill the valley between them with their skirts to 4-5 dB below
 * either, which af_response_execute's 6 dB on both sides refuses; the
 * ripples and humps that rule keeps out belong to a stronger mode, taken
 * off (exactly, with its ripple) before they are looked at. Not excluded,
 * and whose top bin could still clear the threshold (a peak's reported
 * power is at most AF_RESPONSE_PEAK_BOUND times it); 0 if none. Its noise
 * floor into *noise; with rise_snr_db not NULL, the largest SNR of any
 * maximum's rise above its floor raised into *rise_snr_db. The side floors
 * (8 % of the list's instructions when read at every maximum) are read only
 * where they may decide: for a maximum that could be the best by the cheap
 * tests, or whose rise could raise *rise_snr_db (a rise is at most the top's
 * SNR; the 1e-9 dB spares that bound's rounding). A maximum whose top,
 * raised by the most a mode's peak may stand above it
 * (AF_RESPONSE_PEAK_BOUND), stays under min_power (the list's range below its
 * strongest mode, 0 while none is listed) is no candidate either: list_add
 * would refuse its mode unless a fit put the peak more than that bound above
 * the data, a pole extrapolated beyond them. Without this, every weak maximum
 * left after the modes were taken off was read by the fits and then refused
 * (on the 600-strike line bag 196 of the 204 refused candidates). */
static size_t list_candidate(const af_response *r, size_t k_lo, size_t k_hi, double band_floor,
                             double energy, double min_power, const size_t *excluded,
                             size_t n_excluded, double *noise, double *rise_snr_db)
{
  const double *p = r->power;
  double threshold = pow(10.0, 0.1 * r->cfg.snr_threshold_db);
  size_t best = 0;
  for (size_t k = k_lo; k <= k_hi; ++k) {
    if (!(p[k] > p[k - 1] && p[k] >= p[k + 1]))
      continue;
    double noise_k = af_response_list_noise(r, (double)k * r->bin_hz, band_floor, energy);
    int may_be_best = !(AF_RESPONSE_PEAK_BOUND * p[k] < threshold * noise_k) &&
                      !(AF_RESPONSE_PEAK_BOUND * p[k] < min_power) &&
                      (best == 0 || p[k] > p[best]) && !is_excluded(excluded, n_excluded, k);
    int may_rise =
        rise_snr_db != NULL && !(af_response_snr_db(p[k], noise_k) + 1e-9 < *rise_snr_db);
    if (!may_be_best && !may_rise)
      continue;
    double left, right;
    af_response_side_floors(r, k, &left, &right);
    double low = fmin(left, right), high = fmax(left, right);
    if (may_rise)
      *rise_snr_db = fmax(*rise_snr_db, af_response_snr_db(p[k] - high, noise_k));
    if (!may_be_best || p[k] < AF_RESPONSE_PROMINENCE * low ||
        p[k] < AF_RESPONSE_NEIGHBOUR_PROMINENCE * high)
      continue;
    best = k;
    *noise = noise_k;
  }
  return best;
}

/* Refines the maximum k and judges it as af_response_execute does: 1 if it
 * is a damped mode within [f_lo, f_hi] clearing the SNR threshold. *out and
 * *pk are filled in any case (the best rejected one is reported). */
static int list_refine(af_response *r, size_t k, double noise, double f_lo_hz, double f_hi_hz,
                       af_peak *pk, af_response_result *out)
{
  int fitted = af_response_read_peak(r, k, noise, pk, out);
  /* a ringing mode decays: no measurable decay (q +inf) is a steady tone or
   * what a subtraction left of a louder mode */
  return fitted && out->snr_db >= r->cfg.snr_threshold_db && out->frequency_hz >= f_lo_hz &&
         out->frequency_hz <= f_hi_hz && isfinite(out->q);
}

/* A mode of a truncated fit (one or two poles) judged as af_list_refine
 * judges one: the SNR of its own peak power (bounded by the periodogram at
 * its nearest bin), the band, the decay. */
static int list_judge(const af_response *r, const af_peak *pk, double noise, double f_lo_hz,
                      double f_hi_hz, af_response_result *out)
{
  size_t k = (size_t)lround(pk->bin);
  af_response_result_fill(r, pk, out);
  out->snr_db =
      af_response_snr_db(fmin(pk->peak_power, AF_RESPONSE_PEAK_BOUND * r->power[k]), noise);
  return out->snr_db >= r->cfg.snr_threshold_db && out->frequency_hz >= f_lo_hz &&
         out->frequency_hz <= f_hi_hz && isfinite(out->q);
}

/* Takes the mode pk off the spectrum and its power over [lo, hi], as the
 * transform holds it: less the share the trend fit took of it (its DC and
 * hum terms, response_trend.c), which would otherwise stay behind as false
 * peaks at the removed harmonics. */
static void list_subtract(af_response *r, const af_peak *pk, size_t lo, size_t hi)
{
  af_mode_k q = af_response_mode_consts(r, pk);
  af_response_add_trend_share(r, pk, lo, hi);
  af_response_mode_subtract(r, &q, lo, hi);
}

/* Sorts a[0..n) by frequency (insertion: n <= AF_RESPONSE_MAX_PEAKS). */
static void sort_by_frequency(af_response_result *a, size_t n)
{
  for (size_t i = 1; i < n; ++i) {
    af_response_result x = a[i];
    size_t j = i;
    for (; j > 0 && a[j - 1].frequency_hz > x.frequency_hz; --j)
      a[j] = a[j - 1];
    a[j] = x;
  }
}

/* Copies the max_peaks of highest SNR of list[0..n) to peaks, by frequency. */
static size_t list_output(af_response_result *list, size_t n, af_response_result *peaks,
                          size_t max_peaks)
{
  while (n > max_peaks) {
    size_t weakest = 0;
    for (size_t j = 1; j < n; ++j)
      if (list[j].snr_db < list[weakest].snr_db)
        weakest = j;
    list[weakest] = list[--n];
  }
  sort_by_frequency(list, n);
  memcpy(peaks, list, n * sizeof *list);
  return n;
}

/* The largest peak power of the n listed modes; 0 for none. */
static double list_strongest(const af_peak *modes, size_t n)
{
  double strongest = 0.0;
  for (size_t j = 0; j < n; ++j)
    strongest = fmax(strongest, modes[j].peak_power);
  return strongest;
}

/* Lists the mode res (spectral reading pk) unless the list is full or it
 * repeats a listed mode: within a bin of one, or within two windowed
 * half-widths of one and AF_RESPONSE_SPLIT_MIN_RATIO (-20 dB) below it in
 * peak power, or more than AF_RESPONSE_LIST_RANGE (30 dB) below the
 * strongest listed: what the subtractions leave of the modes
 * taken off (the window's cut of a mode whose decay is fitted 1 % off
 * leaves a ripple ~ -40 dB of it, with peaks every fs / m), not modes. 1 if
 * listed. */
static int list_add(af_response_result *list, af_peak *modes, size_t *n,
                    const af_response_result *res, const af_peak *pk, double bin_hz)
{
  if (*n >= AF_RESPONSE_MAX_PEAKS ||
      pk->peak_power < AF_RESPONSE_LIST_RANGE * list_strongest(modes, *n))
    return 0;
  for (size_t j = 0; j < *n; ++j) {
    double reach = 2.0 * modes[j].sigma_windowed / (2.0 * AF_PI * bin_hz);
    if (fabs(list[j].frequency_hz - res->frequency_hz) < bin_hz ||
        (fabs(modes[j].bin - pk->bin) <= reach &&
         pk->peak_power < AF_RESPONSE_SPLIT_MIN_RATIO * modes[j].peak_power))
      return 0;
  }
  list[*n] = *res;
  modes[(*n)++] = *pk;
  return 1;
}

/* r->phase_um[k] = u_k^m over [lo, hi], m the analysed samples: m is whole,
 * so u_k^m = u_j with j = k m mod N, read from the phase table u_0..u_N/2
 * (u_(N - j) = conj(u_j)) in place of a cexp per bin (a cexp of an argument
 * up to k m 2 pi / N ~ 3,000 rad, 2 % of firmness_report's instructions). */
static void list_phases_um(af_response *r, size_t m, size_t lo, size_t hi)
{
  size_t n_fft = r->cfg.fft_size, step = m % n_fft, j = (lo % n_fft) * step % n_fft;
  for (size_t k = lo; k <= hi; ++k) {
    r->phase_um[k] = j <= n_fft / 2 ? r->phase_u[j] : conj(r->phase_u[n_fft - j]);
    j += step;
    if (j >= n_fft)
      j -= n_fft;
  }
}

af_status af_response_execute_peaks(af_response *r, const float *audio, size_t n, double f_lo_hz,
                                    double f_hi_hz, af_response_result *peaks, size_t max_peaks,
                                    size_t *n_peaks)
{
  if (r == NULL || audio == NULL || peaks == NULL || n_peaks == NULL || max_peaks == 0 ||
      n < AF_RESPONSE_MIN_SAMPLES)
    return AF_EINVAL;
  size_t start = 0;
  double energy = 0.0;
  const int64_t t0_ns = af_stage_begin(r->cfg.stages);
  af_status s = af_response_begin(r, audio, n, f_lo_hz, f_hi_hz, &start, &energy);
  af_stage_end(r->cfg.stages, AF_STAGE_FFT, t0_ns);
  if (s != AF_OK)
    return s;
  *n_peaks = 0;
  af_response_result base, list[AF_RESPONSE_MAX_PEAKS], res;
  af_peak modes[AF_RESPONSE_MAX_PEAKS];
  double noises[AF_RESPONSE_MAX_PEAKS];
  af_response_result_clear(&base, r->bin_hz);
  base.onset_index = start;
  base.noise_segments = r->noise_segments;
  double band_floor = r->noise_segments > 0 ? NAN : af_response_band_floor(r);
  size_t k_lo, k_hi;
  af_response_band_bins(f_lo_hz, f_hi_hz, r->bin_hz, r->bins - 2, &k_lo, &k_hi);
  /* the subtraction reaches every bin a local floor or a fit near the band reads */
  size_t reach = AF_RESPONSE_FIT_MAX_HALF + 2;
  size_t sub_lo = k_lo > reach ? k_lo - reach : 1;
  size_t sub_hi = k_hi + reach < r->bins - 1 ? k_hi + reach : r->bins - 1;
  /* u^m over every bin a fit, a subtraction or a refit of this call reads:
   * the band and two fit half-spans beyond it */
  r->split_len = (double)(n - start);
  size_t ph_reach = 2 * AF_RESPONSE_FIT_MAX_HALF + 2;
  size_t ph_lo = k_lo > ph_reach ? k_lo - ph_reach : 0;
  size_t ph_hi = k_hi + ph_reach < r->bins - 1 ? k_hi + ph_reach : r->bins - 1;
  list_phases_um(r, n - start, ph_lo, ph_hi);
  /* the transform before the list takes modes off, for the backfit: it refits
   * a listed mode (whose bin lies in a fit of the u^m range) over at most
   * AF_RESPONSE_FIT_MAX_HALF bins each side; not every bin (a 16384-point
   * spectrum copied whole was 1.5 % of firmness_report's instructions) */
  size_t or_lo = ph_lo > AF_RESPONSE_FIT_MAX_HALF ? ph_lo - AF_RESPONSE_FIT_MAX_HALF : 0;
  size_t or_hi = ph_hi + AF_RESPONSE_FIT_MAX_HALF < r->bins - 1 ? ph_hi + AF_RESPONSE_FIT_MAX_HALF
                                                                : r->bins - 1;
  memcpy(r->orig + or_lo, r->spec + or_lo, (or_hi - or_lo + 1) * sizeof *r->orig);
  r->orig_lo = or_lo;
  r->orig_hi = or_hi;
  size_t excluded[AF_RESPONSE_LIST_TRIES], n_excluded = 0, kept = 0;
  af_response_result best_rejected = base;
  double rise_snr_db = -INFINITY;
  for (size_t tries = 0; tries < AF_RESPONSE_LIST_TRIES && kept < AF_RESPONSE_MAX_PEAKS; ++tries) {
    double noise = NAN;
    /* the rise is reported only when no mode is listed, and a listed one stays */
    size_t k = list_candidate(r, k_lo, k_hi, band_floor, energy,
                              AF_RESPONSE_LIST_RANGE * list_strongest(modes, kept), excluded,
                              n_excluded, &noise, kept == 0 ? &rise_snr_db : NULL);
    if (k == 0)
      break;
    /* the truncated fits from the stage-1 reading (one pole, or two for a
     * blend or a close neighbour); where neither holds, the one-pole
     * refinement of af_response_execute with its neighbour */
    af_peak seed, pk, two[2];
    res = base;
    int got = af_response_stage1(r, r->power, r->spec, k, &seed)
                  ? af_response_split(r, k, &seed, noise, two)
                  : 0;
    if (got == 2) {
      for (size_t j = 0; j < 2; ++j) {
        res = base;
        if (list_judge(r, &two[j], noise, f_lo_hz, f_hi_hz, &res) &&
            list_add(list, modes, &kept, &res, &two[j], r->bin_hz))
          noises[kept - 1] = noise;
        list_subtract(r, &two[j], sub_lo, sub_hi);
      }
    } else {
      int ok;
      if (got == 1) {
        pk = two[0];
        ok = list_judge(r, &pk, noise, f_lo_hz, f_hi_hz, &res);
      } else {
        ok = list_refine(r, k, noise, f_lo_hz, f_hi_hz, &pk, &res);
      }
      if (!ok || !list_add(list, modes, &kept, &res, &pk, r->bin_hz)) {
        if (isnan(best_rejected.frequency_hz) || res.snr_db > best_rejected.snr_db)
          best_rejected = res;
        excluded[n_excluded++] = k;
        continue;
      }
      noises[kept - 1] = noise;
      list_subtract(r, &pk, sub_lo, sub_hi);
    }
    n_excluded = 0; /* a maximum refused beside this mode may stand alone now */
  }
  if (kept == 0) {
    if (isnan(best_rejected.frequency_hz))
      best_rejected.snr_db = rise_snr_db;
    peaks[0] = best_rejected;
    return AF_ENODATA;
  }
  af_response_list_backfit(r, list, modes, noises, kept);
  /* a mode the joint reading moved out of the band, below the threshold or
   * onto another (within a bin: the stronger stays) goes */
  size_t out = 0;
  for (size_t i = 0; i < kept; ++i) {
    if (!(list[i].frequency_hz >= f_lo_hz && list[i].frequency_hz <= f_hi_hz &&
          list[i].snr_db >= r->cfg.snr_threshold_db && isfinite(list[i].q)))
      continue;
    size_t j = 0;
    while (j < out && !(fabs(list[j].frequency_hz - list[i].frequency_hz) < r->bin_hz))
      ++j;
    if (j == out)
      list[out++] = list[i];
    else if (list[i].snr_db > list[j].snr_db)
      list[j] = list[i];
  }
  if (out == 0) {
    peaks[0] = list[0];
    return AF_ENODATA;
  }
  *n_peaks = list_output(list, out, peaks, max_peaks);
  return AF_OK;
}
