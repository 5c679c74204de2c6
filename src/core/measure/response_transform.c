/* response_transform.c — from the analysed samples to their spectrum: the
 * onset, the window (exponential after a raised-cosine fade-in), the zero-pad
 * and the FFTW r2c transform planned once at create (response.h says why
 * this window). */
#include "response_private.h"

#include <math.h>
#include <stdbool.h>
#include <stdint.h>
#include <string.h>

#include "memo.h"

/* Mean of x[0..n) with its smallest and largest sample (the onset's largest
 * deviation from them, af_response_onset); AF_ENUMERIC for a non-finite
 * sample. Finiteness is tested once, on the sum: a sum of finite floats in
 * double stays finite (|x| < 3.5e38, n < 1e269), a NaN or an infinity makes
 * it NaN or infinite; one test per sample was 40 % of the loop. The range
 * comes in the mean's pass, whose chain of additions leaves the core idle
 * between them. */
af_status af_response_mean_range(const float *x, size_t n, double *mean, float *lo, float *hi)
{
  double sum = 0.0;
  float a = x[0], b = x[0];
  for (size_t k = 0; k < n; ++k) {
    sum += x[k];
    a = x[k] < a ? x[k] : a;
    b = x[k] > b ? x[k] : b;
  }
  if (!isfinite(sum))
    return AF_ENUMERIC;
  *mean = sum / (double)n;
  *lo = a;
  *hi = b;
  return AF_OK;
}

/* First sample whose |x - mean| reaches fraction of the largest, kept at
 * least AF_RESPONSE_MIN_SAMPLES from the end; 0 when fraction is 0. Starting
 * the analysis there makes the ringing start at the window's first sample,
 * where the exponential window and the model of the fit expect it; a start a
 * little after the true onset costs only amplitude. The largest |x - mean|
 * from the samples' range [lo, hi] (af_response_mean_range): rounding is
 * monotone, so the largest of the rounded x - mean is hi - mean rounded, the
 * largest of mean - x is mean - lo rounded, and |x - mean| rounded is one of
 * the two: the same double as the largest over every sample. */
size_t af_response_onset(const float *x, size_t n, double mean, double fraction, float lo, float hi)
{
  if (!(fraction > 0.0))
    return 0;
  double above = (double)hi - mean, below = mean - (double)lo, peak = 0.0;
  peak = above > peak ? above : peak;
  peak = below > peak ? below : peak;
  size_t k = 0;
  while (k + AF_RESPONSE_MIN_SAMPLES < n && fabs((double)x[k] - mean) < fraction * peak)
    ++k;
  return k;
}

/* w_k = exp(-k dt / tau_w) (or 1), times a raised-cosine fade-in over the
 * first fade_in_s. The fade-in removes the step at the first sample, whose
 * 1/f skirt would otherwise lift the noise band; it touches only the first
 * samples, whose effect on the spectrum is smooth across a peak (a polynomial
 * in u, like a late onset) and is taken by the fit's background. */
double af_response_fade(size_t k, size_t length)
{
  return k < length ? 0.5 * (1.0 - cos(AF_PI * ((double)k + 0.5) / (double)length)) : 1.0;
}

/* The window's arguments (no padding: the key is its bytes). */
typedef struct {
  uint64_t samples, fade_samples, exponential;
  double dt_over_tau; /* sample interval over the window's time constant [-] */
} window_key;

static af_status window_values(const void *key, void *out)
{
  const window_key *w = key;
  double *window = out;
  for (size_t k = 0; k < w->samples; ++k) {
    double e = w->exponential ? exp(-(double)k * w->dt_over_tau) : 1.0;
    window[k] = e * af_response_fade(k, w->fade_samples);
  }
  return AF_OK;
}

/* The window is the same for every response of a configuration: computed
 * once per process (memo.h; a window_samples exp calls per lane otherwise). */
void af_response_fill_window(af_response *r)
{
  const af_response_config *c = &r->cfg;
  r->fade_samples = (size_t)floor(c->fade_in_s * c->sample_rate_hz);
  const window_key key = {c->window_samples, r->fade_samples,
                          c->window == AF_RESPONSE_WINDOW_EXPONENTIAL,
                          1.0 / (c->sample_rate_hz * c->window_time_constant_s)};
  static const char kind[] = "response window";
  (void)af_memo_get(kind, &key, sizeof key, window_values, r->window,
                    c->window_samples * sizeof *r->window);
  /* the energy of every length, summed in the order the transform summed
   * it (the same doubles): the window loop is then a product alone, which
   * the compiler vectorises (a sum kept in order is not) */
  r->window_energy[0] = 0.0;
  for (size_t k = 0; k < c->window_samples; ++k)
    r->window_energy[k + 1] = r->window_energy[k] + r->window[k] * r->window[k];
  /* what the fade-in takes of each of its samples, for a mode's own peak
   * power (af_response_mode_peak_power: a cos per sample per mode read) */
  for (size_t k = 0; k < r->fade_samples; ++k)
    r->fade_rest[k] = 1.0 - af_response_fade(k, r->fade_samples);
}

/* The phase tables' arguments (no padding: the key is its bytes). */
typedef struct {
  size_t fft_size, fade_samples, bins;
} phase_key;

double complex af_response_phase(size_t k, size_t fft_size, double power)
{
  double w = -2.0 * AF_PI * (double)k / (double)fft_size;
  return cexp(I * w * power);
}

void af_response_fade_phases(size_t fade_samples, double complex *e, double complex *eh)
{
  double theta = fade_samples > 0 ? AF_PI / (double)fade_samples : 0.0;
  *e = cexp(I * theta);
  *eh = cexp(0.5 * I * theta);
}

/* u_k = exp(-2 pi i k / N), or (faded) u_k^L with L = fade_samples, for
 * k < bins, into out. */
static af_status phases(const phase_key *key, bool faded, double complex *out)
{
  double power = faded ? (double)key->fade_samples : 1.0;
  for (size_t k = 0; k < key->bins; ++k)
    out[k] = af_response_phase(k, key->fft_size, power);
  return AF_OK;
}

static af_status phases_u(const void *key, void *out)
{
  return phases(key, false, out);
}

static af_status phases_ul(const void *key, void *out)
{
  return phases(key, true, out);
}

/* The phase factors of the peak list's exact mode spectra (u_k, u_k^L) and
 * the fade-in's constants. The tables depend on the configuration alone:
 * computed once per process (memo.h: most of a lane's making otherwise). */
void af_response_fill_phases(af_response *r)
{
  static const char kind_u[] = "response phase u", kind_ul[] = "response phase u^L";
  const phase_key key = {r->cfg.fft_size, r->fade_samples, r->bins};
  const size_t size = r->bins * sizeof *r->phase_u;
  (void)af_memo_get(kind_u, &key, sizeof key, phases_u, r->phase_u, size);
  (void)af_memo_get(kind_ul, &key, sizeof key, phases_ul, r->phase_ul, size);
  af_response_fade_phases(r->fade_samples, &r->fade_e, &r->fade_eh);
}

/* Bins of [lo_hz, hi_hz] on a grid of bin_hz, clipped to 1..last. */
void af_response_band_bins(double lo_hz, double hi_hz, double bin_hz, size_t last, size_t *k_lo,
                           size_t *k_hi)
{
  double lo = ceil(lo_hz / bin_hz), hi = floor(hi_hz / bin_hz);
  *k_lo = lo < 1.0 ? 1 : (size_t)lo;
  *k_hi = hi > (double)last ? last : (size_t)hi;
}

/* Periodogram of x[start..n), less its fitted trend, into r->power[0..bins):
 * windowed from start, zero-padded, through the input buffer in. The window
 * energy sum w_k^2 into *window_energy. */
void af_response_transform(af_response *r, af_response_input *in, const float *x, size_t n,
                           size_t start, size_t bins, double *window_energy)
{
  size_t m = n - start;
  double *samples = in->samples;
  af_response_trend_remove(r, x, start, m, r->window, samples);
  /* the padding: only what an earlier, longer transform left there (FFTW's
   * out-of-place r2c preserves its input); a whole 16384-point buffer per
   * call was 1.8 % of firmness_report's instructions */
  if (in->written > m)
    memset(samples + m, 0, (in->written - m) * sizeof *samples);
  in->written = m;
  af_fft_r2c_execute(&r->plan, samples, r->spec);
  for (size_t k = 0; k < bins; ++k) {
    double re = creal(r->spec[k]), im = cimag(r->spec[k]);
    r->power[k] = re * re + im * im;
  }
  *window_energy = r->window_energy[m];
}
