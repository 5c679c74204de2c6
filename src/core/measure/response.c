/* response.c — the 0S2 of a struck apple's ringing: the analysis object
 * (configuration, create, destroy), the result record and the one-peak
 * analysis af_response_execute (see response.h for the method and the
 * definitions; response_private.h for the file that does each step). */
#include "response_private.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* ---- names and configuration --------------------------------------------- */

const char *af_response_window_name(af_response_window window)
{
  switch (window) {
  case AF_RESPONSE_WINDOW_EXPONENTIAL: return "exponential";
  case AF_RESPONSE_WINDOW_RECTANGULAR: return "rectangular";
  }
  return "unknown";
}

af_status af_response_window_parse(const char *name, af_response_window *window)
{
  if (name == NULL || window == NULL)
    return AF_EINVAL;
  if (strcmp(name, "exponential") == 0) {
    *window = AF_RESPONSE_WINDOW_EXPONENTIAL;
    return AF_OK;
  }
  if (strcmp(name, "rectangular") == 0) {
    *window = AF_RESPONSE_WINDOW_RECTANGULAR;
    return AF_OK;
  }
  return AF_EINVAL;
}

#include "af_defaults.h" /* the parameter table's defaults */
af_response_config af_response_config_default(void)
{
  af_response_config c;
  c.sample_rate_hz = AF_DEFAULT_AUDIO_SAMPLE_RATE_HZ;
  c.window_samples = 4096;
  c.fft_size = 8192;
  c.window = AF_RESPONSE_WINDOW_EXPONENTIAL;
  c.window_time_constant_s = 0.020;
  c.fade_in_s = 0.001;
  c.hum_hz = AF_DEFAULT_MEASURE_HUM_HZ;
  c.hum_harmonics = AF_DEFAULT_MEASURE_HUM_HARMONICS;
  c.onset_fraction = 0.25;
  c.snr_threshold_db = AF_DEFAULT_MEASURE_SNR_THRESHOLD_DB;
  c.noise_band_lo_hz = AF_DEFAULT_MEASURE_NOISE_BAND_LOW_HZ;
  c.noise_band_hi_hz = AF_DEFAULT_MEASURE_NOISE_BAND_HIGH_HZ;
  c.stages = NULL;
  return c;
}

static int is_power_of_two(size_t n)
{
  return n != 0 && (n & (n - 1)) == 0;
}

/* Rate, lengths and window. */
static af_status config_check_window(const af_response_config *c)
{
  if (!isfinite(c->sample_rate_hz) || c->sample_rate_hz <= 0.0)
    return AF_EINVAL;
  if (c->window_samples < AF_RESPONSE_MIN_SAMPLES || !is_power_of_two(c->fft_size) ||
      c->fft_size < c->window_samples)
    return AF_EINVAL;
  if (c->window != AF_RESPONSE_WINDOW_EXPONENTIAL && c->window != AF_RESPONSE_WINDOW_RECTANGULAR)
    return AF_EINVAL;
  if (!isfinite(c->window_time_constant_s) || c->window_time_constant_s <= 0.0)
    return AF_EINVAL;
  /* the fade-in may take at most a quarter of the window */
  double fade_samples = c->fade_in_s * c->sample_rate_hz;
  if (!(fade_samples >= 0.0) || fade_samples > 0.25 * (double)c->window_samples)
    return AF_EINVAL;
  return AF_OK;
}

/* Hum, onset, threshold and noise band (the rate already checked). */
static af_status config_check_levels(const af_response_config *c)
{
  double nyquist_hz = 0.5 * c->sample_rate_hz;
  if (!(c->hum_hz >= 0.0 && c->hum_hz < nyquist_hz) ||
      c->hum_harmonics > AF_RESPONSE_MAX_HUM_HARMONICS)
    return AF_EINVAL;
  if (!(c->onset_fraction >= 0.0 && c->onset_fraction < 1.0) || !isfinite(c->snr_threshold_db))
    return AF_EINVAL;
  if (!(c->noise_band_lo_hz >= 0.0) || !(c->noise_band_hi_hz > c->noise_band_lo_hz) ||
      c->noise_band_lo_hz >= nyquist_hz)
    return AF_EINVAL;
  if (af_response_noise_band_bins(c) < AF_RESPONSE_MIN_NOISE_BINS)
    return AF_EINVAL;
  return AF_OK;
}

size_t af_response_noise_band_bins(const af_response_config *c)
{
  size_t k_lo, k_hi;
  if (c == NULL || c->fft_size < 2 || !(c->sample_rate_hz > 0.0))
    return 0;
  af_response_band_bins(c->noise_band_lo_hz, c->noise_band_hi_hz,
                        c->sample_rate_hz / (double)c->fft_size, c->fft_size / 2, &k_lo, &k_hi);
  return k_hi < k_lo ? 0 : k_hi - k_lo + 1;
}

/* ---- lifetime ------------------------------------------------------------- */

af_status af_response_create(const af_response_config *cfg, af_response **out)
{
  if (cfg == NULL || out == NULL)
    return AF_EINVAL;
  *out = NULL;
  af_status s = config_check_window(cfg);
  if (s == AF_OK)
    s = config_check_levels(cfg);
  if (s != AF_OK)
    return s;
  af_status_init();
  af_response *r = calloc(1, sizeof *r);
  if (r == NULL)
    return AF_ENOMEM;
  r->cfg = *cfg;
  r->bins = cfg->fft_size / 2 + 1;
  r->bin_hz = cfg->sample_rate_hz / (double)cfg->fft_size;
  r->in.samples = fftw_alloc_real(cfg->fft_size);
  r->in.written = cfg->fft_size; /* not zeroed yet: the first transform pads it */
  r->noise_in.samples = fftw_alloc_real(cfg->fft_size);
  r->noise_in.written = cfg->fft_size;
  r->spec = fftw_alloc_complex(r->bins);
  r->window = fftw_alloc_real(cfg->window_samples);
  r->window_energy = fftw_alloc_real(cfg->window_samples + 1);
  r->fade_rest = fftw_alloc_real(cfg->window_samples);
  r->power = fftw_alloc_real(r->bins);
  r->noise_ref = fftw_alloc_real(r->bins);
  r->scratch = fftw_alloc_real(r->bins);
  r->work = fftw_alloc_complex(r->bins);
  r->work_power = fftw_alloc_real(r->bins);
  r->orig = fftw_alloc_complex(r->bins);
  r->phase_u = fftw_alloc_complex(r->bins);
  r->phase_ul = fftw_alloc_complex(r->bins);
  r->phase_um = fftw_alloc_complex(r->bins);
  r->hum_period = af_response_hum_period(cfg);
  r->trend_fold = fftw_alloc_real(cfg->window_samples);
  if (r->hum_period > 0) {
    r->trend_table = fftw_alloc_real(r->hum_period * (1 + 2 * cfg->hum_harmonics));
    r->trend_cols = fftw_alloc_real(r->hum_period * (1 + 2 * cfg->hum_harmonics));
  }
  r->noise_cum = fftw_alloc_real(r->bins + 1);
  r->share_terms = af_response_share_terms(cfg);
  r->trend_gram = gsl_matrix_alloc(AF_RESPONSE_MAX_TERMS, AF_RESPONSE_MAX_TERMS);
  r->noise_gram = gsl_matrix_alloc(AF_RESPONSE_MAX_TERMS, AF_RESPONSE_MAX_TERMS);
  r->trend_rhs = gsl_vector_alloc(AF_RESPONSE_MAX_TERMS);
  r->trend_coef = gsl_vector_alloc(AF_RESPONSE_MAX_TERMS);
  if (r->in.samples == NULL || r->noise_in.samples == NULL || r->spec == NULL ||
      r->window == NULL || r->window_energy == NULL || r->fade_rest == NULL || r->power == NULL ||
      r->noise_ref == NULL || r->scratch == NULL || r->work == NULL || r->work_power == NULL ||
      r->orig == NULL || r->phase_u == NULL || r->phase_ul == NULL || r->phase_um == NULL ||
      r->trend_fold == NULL ||
      (r->hum_period > 0 && (r->trend_table == NULL || r->trend_cols == NULL)) ||
      r->noise_cum == NULL || r->trend_gram == NULL || r->noise_gram == NULL ||
      r->trend_rhs == NULL || r->trend_coef == NULL) {
    af_response_destroy(r);
    return AF_ENOMEM;
  }
  /* FFTW_ESTIMATE (no measurement, so no buffer is overwritten), one plan
   * per size for the whole process (fft_plan.h); the transform is a small
   * fraction of the budget. */
  af_status st = af_fft_r2c_acquire(cfg->fft_size, &r->plan);
  if (st != AF_OK) {
    af_response_destroy(r);
    return st;
  }
  af_response_fill_window(r);
  af_response_fill_phases(r);
  af_response_fill_trend_table(r);
  if (r->share_terms > 0 && af_response_fill_share_tables(r) != AF_OK) {
    af_response_destroy(r);
    return AF_ENOMEM;
  }
  *out = r;
  return AF_OK;
}

void af_response_destroy(af_response *r)
{
  if (r == NULL)
    return;
  af_fft_r2c_release(&r->plan);
  fftw_free(r->in.samples);
  fftw_free(r->noise_in.samples);
  fftw_free(r->spec);
  fftw_free(r->window);
  fftw_free(r->window_energy);
  fftw_free(r->fade_rest);
  fftw_free(r->power);
  fftw_free(r->noise_ref);
  fftw_free(r->scratch);
  fftw_free(r->work);
  fftw_free(r->work_power);
  fftw_free(r->orig);
  fftw_free(r->phase_u);
  fftw_free(r->phase_ul);
  fftw_free(r->phase_um);
  fftw_free(r->trend_fold);
  fftw_free(r->trend_table);
  fftw_free(r->trend_cols);
  fftw_free(r->share_own);
  fftw_free(r->noise_cum);
  if (r->trend_gram != NULL)
    gsl_matrix_free(r->trend_gram);
  if (r->noise_gram != NULL)
    gsl_matrix_free(r->noise_gram);
  if (r->trend_rhs != NULL)
    gsl_vector_free(r->trend_rhs);
  if (r->trend_coef != NULL)
    gsl_vector_free(r->trend_coef);
  free(r);
}

const af_response_config *af_response_get_config(const af_response *r)
{
  return r == NULL ? NULL : &r->cfg;
}

const char *af_response_fit_status_name(af_response_fit_status status)
{
  switch (status) {
  case AF_RESPONSE_FIT_CONVERGED: return "converged";
  case AF_RESPONSE_FIT_CAPPED: return "capped";
  case AF_RESPONSE_FIT_STALLED: return "stalled";
  case AF_RESPONSE_FIT_FAILED: return "failed";
  case AF_RESPONSE_FIT_STATUSES: break;
  }
  return "unknown";
}

void af_response_get_fit_stats(const af_response *r, af_response_fit_stats *out)
{
  if (out == NULL)
    return;
  memset(out, 0, sizeof *out);
  if (r != NULL)
    *out = r->fit_stats;
}

void af_response_reset_fit_stats(af_response *r)
{
  if (r != NULL)
    memset(&r->fit_stats, 0, sizeof r->fit_stats);
}

/* ---- result and analysis --------------------------------------------------- */

double af_response_snr_db(double peak_power, double noise_power)
{
  if (noise_power > 0.0)
    return 10.0 * log10(peak_power / noise_power); /* -inf for a silent band */
  return peak_power > 0.0 ? INFINITY : -INFINITY;
}

void af_response_result_clear(af_response_result *out, double bin_hz)
{
  out->frequency_hz = NAN;
  out->q = NAN;
  out->decay_time_s = NAN;
  out->amplitude = NAN;
  out->snr_db = -INFINITY;
  out->bin_width_hz = bin_hz;
  out->noise_segments = 0;
  out->onset_index = 0;
}

/* The exponential window's decay 1/tau_w is taken off the windowed mode's. */
void af_response_result_fill(const af_response *r, const af_peak *pk, af_response_result *out)
{
  const af_response_config *c = &r->cfg;
  out->frequency_hz = pk->bin * r->bin_hz;
  /* the ringing c z^n + conj(c z^n) has the amplitude 2 |c| at n = 0 */
  out->amplitude = 2.0 * cabs(pk->c);
  if (!isfinite(pk->sigma_windowed))
    return;
  double sigma = pk->sigma_windowed;
  if (c->window == AF_RESPONSE_WINDOW_EXPONENTIAL)
    sigma -= 1.0 / c->window_time_constant_s;
  out->decay_time_s = sigma > 0.0 ? 1.0 / sigma : INFINITY;
  out->q = sigma > 0.0 ? AF_PI * out->frequency_hz / sigma : INFINITY;
}

/* Bins of the periodogram an analysis up to f_hi_hz reads: with a noise
 * reference, the range's and those a peak in it reads around itself (its
 * side floors and stage 1 within AF_RESPONSE_FIT_MAX_HALF, a neighbour
 * within two fit half-spans and its top's slopes, a split pole's nearest
 * bin), with room to spare; every bin without one (the noise band's median,
 * af_response_band_floor). At the defaults and a 0S2 range of a few hundred
 * Hz, a tenth of them: the rest of the |X|^2 loop was 20 k instructions a
 * strike. */
static size_t periodogram_bins(const af_response *r, double f_hi_hz)
{
  if (r->noise_segments == 0)
    return r->bins;
  double k = floor(f_hi_hz / r->bin_hz) + (double)(4 * AF_RESPONSE_FIT_MAX_HALF + 8);
  return k < (double)r->bins ? (size_t)k : r->bins;
}

af_status af_response_begin(af_response *r, const float *audio, size_t n, double f_lo_hz,
                            double f_hi_hz, size_t *start, double *energy)
{
  if (!(f_lo_hz > 0.0) || !(f_hi_hz > f_lo_hz) || !(f_hi_hz < 0.5 * r->cfg.sample_rate_hz))
    return AF_EINVAL;
  if (n > r->cfg.window_samples)
    return AF_ESIZE;
  double mean = 0.0;
  float lo = 0.0f, hi = 0.0f;
  af_status s = af_response_mean_range(audio, n, &mean, &lo, &hi);
  if (s != AF_OK)
    return s;
  *start = af_response_onset(audio, n, mean, r->cfg.onset_fraction, lo, hi);
  /* the samples are finite (af_response_mean_range): the fit's status is AF_OK */
  (void)af_response_trend_fit(r, audio, *start, n, af_response_hum_harmonics(r, f_lo_hz), 0);
  af_response_transform(r, &r->in, audio, n, *start, periodogram_bins(r, f_hi_hz), energy);
  return AF_OK;
}

int af_response_read_peak(af_response *r, size_t k, double noise, af_peak *pk,
                          af_response_result *out)
{
  int fitted = af_response_refine(r, k, noise, pk);
  af_response_result_fill(r, pk, out);
  /* The peak power is the mode's own fitted peak (free of other modes'
   * skirts, which may add to or cancel it in the periodogram), bounded by
   * AF_RESPONSE_PEAK_BOUND times the periodogram there: a narrow pole fitted
   * to a noise bump may extrapolate far above the data, a mode does not. */
  double peak_power = r->power[k];
  if (fitted)
    peak_power = fmin(pk->peak_power, AF_RESPONSE_PEAK_BOUND * r->power[k]);
  out->snr_db = af_response_snr_db(peak_power, noise);
  return fitted;
}

af_status af_response_execute(af_response *r, const float *audio, size_t n, double f_lo_hz,
                              double f_hi_hz, af_response_result *out)
{
  if (r == NULL || audio == NULL || out == NULL || n < AF_RESPONSE_MIN_SAMPLES)
    return AF_EINVAL;
  size_t start = 0;
  double energy = 0.0, rise = 0.0;
  af_status s = af_response_begin(r, audio, n, f_lo_hz, f_hi_hz, &start, &energy);
  if (s != AF_OK)
    return s;
  af_response_result_clear(out, r->bin_hz);
  out->onset_index = start;
  double noise = af_response_noise_power(r, f_lo_hz, f_hi_hz, energy, &out->noise_segments);
  size_t k = af_response_find_peak(r, f_lo_hz, f_hi_hz, &rise);
  if (k == 0) {
    out->snr_db = af_response_snr_db(rise, noise);
    return AF_ENODATA;
  }
  af_peak pk;
  int fitted = af_response_read_peak(r, k, noise, &pk, out);
  /* a top refined out of the range was the edge of something outside it */
  if (out->snr_db < r->cfg.snr_threshold_db || !(out->frequency_hz >= f_lo_hz) ||
      !(out->frequency_hz <= f_hi_hz))
    return AF_ENODATA;
  return fitted ? AF_OK : AF_ENODATA; /* a top that is no damped mode */
}
