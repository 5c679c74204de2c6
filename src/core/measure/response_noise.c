/* response_noise.c — the noise floor an SNR is measured against: the mean
 * periodogram of noise-only segments (the reference) or, without one, the
 * median of the analysed window's own noise band (response.h: definitions). */
#include "response_private.h"

#include <math.h>

#include <gsl/gsl_statistics_double.h>

/* af_response_execute_peaks with a noise reference: each peak's floor is the
 * reference's mean over f / 1.2 .. 1.2 f (coloured noise changes across a
 * wide list band; +-20 % holds ~70 bins at 700 Hz). */
#define AF_RESPONSE_LIST_NOISE_SPAN 1.2

/* A fresh reference (none yet, or after a clear: the lane clears it at every
 * strike and adds one segment): the segment's periodogram per unit window
 * energy, written once, with its running sum. The same values as the
 * running mean from zeros (0 + 1 x (x - 0) = x exactly), without clearing
 * every bin first and reading it back. */
static void reference_start(af_response *r, double per_energy, size_t bins)
{
  r->noise_bins = bins;
  r->noise_cum[0] = 0.0;
  for (size_t k = 0; k < bins; ++k) {
    r->noise_ref[k] = r->power[k] * per_energy;
    r->noise_cum[k + 1] = r->noise_cum[k] + r->noise_ref[k];
  }
}

/* One more segment into the running mean of the r->noise_segments before it
 * (the bins all of them hold). */
static void reference_update(af_response *r, double per_energy, size_t bins)
{
  double weight = 1.0 / (double)(r->noise_segments + 1);
  r->noise_bins = bins < r->noise_bins ? bins : r->noise_bins;
  r->noise_cum[0] = 0.0;
  for (size_t k = 0; k < r->noise_bins; ++k) {
    r->noise_ref[k] += weight * (r->power[k] * per_energy - r->noise_ref[k]);
    r->noise_cum[k + 1] = r->noise_cum[k] + r->noise_ref[k];
  }
}

/* Bins the reference needs for analyses that end at or below f_max_hz: up
 * to the list's floor at the top of its band (f x AF_RESPONSE_LIST_NOISE_SPAN,
 * floored as af_response_band_bins floors), one more against rounding; all
 * of them for an infinite f_max_hz. */
static size_t reference_bins(const af_response *r, double f_max_hz)
{
  double k = floor(f_max_hz * AF_RESPONSE_LIST_NOISE_SPAN / r->bin_hz) + 2.0;
  return k < (double)r->bins ? (size_t)k : r->bins;
}

af_status af_response_add_noise(af_response *r, const float *noise, size_t n)
{
  return af_response_add_noise_below(r, noise, n, INFINITY);
}

af_status af_response_add_noise_below(af_response *r, const float *noise, size_t n, double f_max_hz)
{
  if (r == NULL || noise == NULL || n < AF_RESPONSE_MIN_SAMPLES || !(f_max_hz > 0.0))
    return AF_EINVAL;
  if (n > r->cfg.window_samples)
    return AF_ESIZE;
  double energy = 0.0;
  /* the reference does not know the range: every configured harmonic goes;
   * the fit checks the samples' finiteness (its sum of them: no pass of its
   * own) */
  af_status s =
      af_response_trend_fit(r, noise, 0, n, r->cfg.hum_hz > 0.0 ? r->cfg.hum_harmonics : 0, 1);
  if (s != AF_OK)
    return s;
  /* only the bins read: the rest of the periodogram and the running mean
   * (~80 % of the bins for the peak list's band at the default rate) is
   * not computed; the bins computed are the same doubles */
  size_t bins = reference_bins(r, f_max_hz);
  af_response_transform(r, &r->noise_in, noise, n, 0, bins, &energy);
  /* running mean: one segment's floor over a range of a few hundred Hz
   * scatters by ~1.5 dB, the mean of m segments by ~1.5/sqrt(m) dB */
  double per_energy = 1.0 / energy;
  if (r->noise_segments == 0)
    reference_start(r, per_energy, bins);
  else
    reference_update(r, per_energy, bins);
  r->noise_segments++;
  return AF_OK;
}

void af_response_clear_noise(af_response *r)
{
  if (r != NULL)
    r->noise_segments = 0;
}

/* Mean noise power per bin of the analysed window from the median of its
 * periodogram over the noise band: for complex Gaussian noise |X_k|^2 is
 * exponential, median = ln 2 x mean; the median ignores the few peaks. */
double af_response_band_floor(af_response *r)
{
  size_t k_lo, k_hi;
  af_response_band_bins(r->cfg.noise_band_lo_hz, r->cfg.noise_band_hi_hz, r->bin_hz, r->bins - 1,
                        &k_lo, &k_hi);
  /* every zero-padding factor-th bin: the bins between are interpolations
   * of these, no new information, only more work for the median */
  size_t stride = r->cfg.fft_size / r->cfg.window_samples, m = 0;
  for (size_t k = k_lo; k <= k_hi; k += stride)
    r->scratch[m++] = r->power[k];
  return gsl_stats_median(r->scratch, 1, m) / log(2.0);
}

/* Mean noise power per bin from the reference over [f_lo, f_hi], for a
 * window of energy 'energy'. The mean, not the median: the reference holds
 * no peaks, and its bins, averaged over segments, are no longer exponential
 * (the ln 2 of one segment becomes ~0.96 for eight). An empty range takes its
 * nearest bin. */
static double reference_floor(const af_response *r, double f_lo_hz, double f_hi_hz, double energy)
{
  size_t k_lo, k_hi;
  /* clipped to the bins the reference holds (af_response_add_noise_below:
   * a band that ends below its f_max never reaches past them) */
  size_t last = r->noise_bins - 1;
  af_response_band_bins(f_lo_hz, f_hi_hz, r->bin_hz, last, &k_lo, &k_hi);
  k_lo = k_lo > last ? last : k_lo;
  if (k_hi < k_lo)
    k_hi = k_lo;
  /* from the running sum: one subtraction per peak, not a loop over its
   * +-20 % (the peak list asks at every local maximum of the band) */
  double sum = r->noise_cum[k_hi + 1] - r->noise_cum[k_lo];
  return energy * sum / (double)(k_hi - k_lo + 1);
}

/* Noise power per bin of the last transform (window energy 'energy'). */
double af_response_noise_power(af_response *r, double f_lo_hz, double f_hi_hz, double energy,
                               size_t *segments)
{
  *segments = r->noise_segments;
  if (r->noise_segments > 0)
    return reference_floor(r, f_lo_hz, f_hi_hz, energy);
  return af_response_band_floor(r);
}

/* Noise power per bin at frequency f_hz of the last transform: the
 * reference's mean over f / AF_RESPONSE_LIST_NOISE_SPAN .. f x it, else the
 * band floor (band_floor, computed once). */
double af_response_list_noise(const af_response *r, double f_hz, double band_floor, double energy)
{
  if (r->noise_segments == 0)
    return band_floor;
  return reference_floor(r, f_hz / AF_RESPONSE_LIST_NOISE_SPAN, f_hz * AF_RESPONSE_LIST_NOISE_SPAN,
                         energy);
}
