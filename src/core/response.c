/* response.c — the 0S2 of a struck apple's ringing: onset, hum removal,
 * exponential window, prominent-peak picking, two-stage refinement (1/P
 * parabola, complex pole-pair fit) and SNR (see response.h for the method
 * and the definitions). */
#include "response.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* complex.h before fftw3.h: fftw_complex is then the C99 double complex. */
#include <complex.h>
#include <fftw3.h>
#include <gsl/gsl_errno.h>
#include <gsl/gsl_linalg.h>
#include <gsl/gsl_multifit_nlinear.h>
#include <gsl/gsl_statistics_double.h>

#define AF_PI 3.14159265358979323846
/* Shortest window or noise segment accepted [samples]: below this neither a
 * mean nor a spectral peak means anything. */
#define AF_RESPONSE_MIN_SAMPLES 8
/* Fewest bins a noise band must hold for its median to be a floor. */
#define AF_RESPONSE_MIN_NOISE_BINS 8
/* The Lorentzian fit uses the bins above this fraction of the peak power
 * (-3 dB): there the mode dominates its neighbours' skirts and the noise. */
#define AF_RESPONSE_FIT_LEVEL 0.5
/* At most this many bins each side of the peak enter a fit (a broad peak on
 * a fine grid needs no more). */
#define AF_RESPONSE_FIT_MAX_HALF 32
/* The complex fit spans this many half-widths (sigma' / 2 pi) each side of
 * the peak, at least AF_RESPONSE_FIT_MIN_HALF bins: wide enough to pin the
 * background polynomial, narrow enough for a quadratic to follow it. */
#define AF_RESPONSE_FIT_HALFWIDTHS 2.5
#define AF_RESPONSE_FIT_MIN_HALF 4
/* Parameters of the complex fit: f0 [bins], sigma' [1/s], the mode's complex
 * amplitude (2) and a complex quadratic background (6). */
#define AF_RESPONSE_FIT_PARAMS 10
#define AF_RESPONSE_FIT_ROWS (2 * (2 * AF_RESPONSE_FIT_MAX_HALF + 1))
/* The peak list's two-pole fit: two modes (4 each) and the background (6). */
#define AF_RESPONSE_SPLIT_PARAMS 14
/* Span sizes [bins] the truncated fits have workspaces for; the last is the
 * widest span, 2 AF_RESPONSE_FIT_MAX_HALF + 1. */
#define AF_RESPONSE_SPLIT_BUCKETS 4
static const size_t af_split_bins[AF_RESPONSE_SPLIT_BUCKETS] = {17, 33, 49,
                                                                2 * AF_RESPONSE_FIT_MAX_HALF + 1};
/* Levenberg-Marquardt stops (GSL's tests): steps below 1e-8 relative, or
 * gradient/cost changes at rounding level; 50 iterations are never needed
 * (typically 5-15). */
#define AF_RESPONSE_FIT_MAX_ITER 50
#define AF_RESPONSE_FIT_XTOL 1e-8
#define AF_RESPONSE_FIT_GTOL 1e-10
#define AF_RESPONSE_FIT_FTOL 1e-10
/* Hum removal: at most this many harmonics, and only those at or below
 * AF_RESPONSE_HUM_MARGIN f_lo, clear of any 0S2 the range allows (a harmonic
 * inside the range cannot be told from a mode by a fit over one window). */
#define AF_RESPONSE_MAX_HUM_HARMONICS 8
#define AF_RESPONSE_HUM_MARGIN 0.8
#define AF_RESPONSE_MAX_TERMS (1 + 2 * AF_RESPONSE_MAX_HUM_HARMONICS)
/* The mode's fitted peak power may exceed the periodogram's top bin by the
 * grid's scalloping (<= 0.6 dB here) and by a neighbour's skirt cancelling it
 * in the bin; beyond 1.5 dB it is a pole extrapolated above the data. */
#define AF_RESPONSE_PEAK_BOUND 1.41
/* A local maximum is a peak when it stands this far (power ratio, 6 dB)
 * above its local floor: an isolated mode stands >= 13 dB above its skirt
 * AF_RESPONSE_FIT_MAX_HALF bins away, a ripple or a hump where skirts
 * interfere stands 0.5-5 dB. */
#define AF_RESPONSE_PROMINENCE 4.0
/* A neighbouring maximum counts as a mode when it stands this far (power
 * ratio, 3 dB) above the valley between it and the peak. */
#define AF_RESPONSE_NEIGHBOUR_PROMINENCE 2.0

/* af_response_peaks with a noise reference: each peak's floor is the
 * reference's mean over f / 1.2 .. 1.2 f (coloured noise changes across a
 * wide list band; +-20 % holds ~70 bins at 700 Hz). */
#define AF_RESPONSE_LIST_NOISE_SPAN 1.2

/* What a fit works on: a complex spectrum, the bins used, the scales. */
typedef struct {
  const double complex *data; /* spectrum fitted: the transform, or it less a neighbour */
  size_t first, count;        /* bins fitted: first .. first + count - 1 */
  double center;              /* bin of the grid peak */
  double half;                /* bins per unit of the background's abscissa */
  double gain;                /* 1 / |X| at the grid peak: data of order 1 */
  double norm;                /* 1 - r of the seed: amplitude of order 1 */
} af_fit_ctx;

struct af_response {
  af_response_config cfg;
  size_t bins;                         /* fft_size / 2 + 1 */
  double bin_hz;                       /* sample_rate_hz / fft_size [Hz] */
  double *in;                          /* fft input, fft_size samples */
  double complex *spec;                /* fft output, bins values */
  fftw_plan plan;                      /* r2c, made once */
  double *window;                      /* window_samples weights */
  size_t fade_samples;                 /* length of the fade-in [samples] */
  double *power;                       /* periodogram |X_k|^2 of the last transform */
  double *noise_ref;                   /* mean reference periodogram per unit window energy */
  double *scratch;                     /* median workspace (noise band) */
  double complex *work;                /* spectrum less a fitted mode (near the peak only) */
  double *work_power;                  /* |work|^2 */
  double complex *orig;                /* the transform before the peak list took modes off */
  double complex *phase_u;             /* u_k = exp(-i 2 pi k / N), every bin */
  double complex *phase_ul;            /* u_k^L, L the fade-in length */
  double complex *phase_um;            /* u_k^m, m the analysed length of the peak list's call */
  double split_len;                    /* that m [samples] */
  double complex fade_e, fade_eh;      /* exp(i theta), exp(i theta / 2), theta = pi / L */
  size_t noise_segments;               /* segments averaged into noise_ref */
  gsl_multifit_nlinear_workspace *fit; /* complex peak fit, AF_RESPONSE_FIT_ROWS x PARAMS */
  gsl_vector *fit_start;               /* its starting point */
  /* truncated fits of the peak list: [poles - 1][bucket], rows 2 x
   * af_split_bins[bucket], 4 poles + 6 parameters (sized to the span: the
   * normal equations cost grows with the rows, used or zero) */
  gsl_multifit_nlinear_workspace *split_fit[2][AF_RESPONSE_SPLIT_BUCKETS];
  gsl_multifit_nlinear_workspace *split_last; /* the one the last truncated fit ran in */
  gsl_vector *fit2_start;                     /* their starting point (two poles' room) */
  size_t split_poles;                         /* poles of the truncated fit under way: 1 or 2 */
  af_fit_ctx ctx;                             /* the fit under way */
  gsl_matrix *trend_gram;                     /* DC + hum least squares, MAX_TERMS square */
  gsl_vector *trend_rhs, *trend_coef;         /* its right-hand side and solution */
  size_t trend_terms;                         /* terms of the last trend fit: 1 + 2 harmonics */
};

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

#include "af_defaults.h" /* the parameter table's defaults (issue 16) */
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
  return c;
}

static int af_is_power_of_two(size_t n)
{
  return n != 0 && (n & (n - 1)) == 0;
}

/* Bins of [lo_hz, hi_hz] on a grid of bin_hz, clipped to 1..last. */
static void af_band_bins(double lo_hz, double hi_hz, double bin_hz, size_t last, size_t *k_lo,
                         size_t *k_hi)
{
  double lo = ceil(lo_hz / bin_hz), hi = floor(hi_hz / bin_hz);
  *k_lo = lo < 1.0 ? 1 : (size_t)lo;
  *k_hi = hi > (double)last ? last : (size_t)hi;
}

/* Rate, lengths and window. */
static af_status af_config_check_window(const af_response_config *c)
{
  if (!isfinite(c->sample_rate_hz) || c->sample_rate_hz <= 0.0)
    return AF_EINVAL;
  if (c->window_samples < AF_RESPONSE_MIN_SAMPLES || !af_is_power_of_two(c->fft_size) ||
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
static af_status af_config_check_levels(const af_response_config *c)
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
  size_t k_lo, k_hi;
  af_band_bins(c->noise_band_lo_hz, c->noise_band_hi_hz, c->sample_rate_hz / (double)c->fft_size,
               c->fft_size / 2, &k_lo, &k_hi);
  if (k_hi < k_lo || k_hi - k_lo + 1 < AF_RESPONSE_MIN_NOISE_BINS)
    return AF_EINVAL;
  return AF_OK;
}

/* ---- lifetime ------------------------------------------------------------- */

/* w_k = exp(-k dt / tau_w) (or 1), times a raised-cosine fade-in over the
 * first fade_in_s. The fade-in removes the step at the first sample, whose
 * 1/f skirt would otherwise lift the noise band; it touches only the first
 * samples, whose effect on the spectrum is smooth across a peak (a polynomial
 * in u, like a late onset) and is taken by the fit's background. */
static double af_fade(size_t k, size_t length)
{
  return k < length ? 0.5 * (1.0 - cos(AF_PI * ((double)k + 0.5) / (double)length)) : 1.0;
}

static void af_response_fill_window(af_response *r)
{
  const af_response_config *c = &r->cfg;
  double dt_over_tau = 1.0 / (c->sample_rate_hz * c->window_time_constant_s);
  r->fade_samples = (size_t)floor(c->fade_in_s * c->sample_rate_hz);
  for (size_t k = 0; k < c->window_samples; ++k) {
    double w = c->window == AF_RESPONSE_WINDOW_EXPONENTIAL ? exp(-(double)k * dt_over_tau) : 1.0;
    r->window[k] = w * af_fade(k, r->fade_samples);
  }
}

/* The phase factors of the peak list's exact mode spectra (u_k, u_k^L) and
 * the fade-in's constants. */
static void af_response_fill_phases(af_response *r)
{
  double n_fft = (double)r->cfg.fft_size, length = (double)r->fade_samples;
  for (size_t k = 0; k < r->bins; ++k) {
    double w = -2.0 * AF_PI * (double)k / n_fft;
    r->phase_u[k] = cexp(I * w);
    r->phase_ul[k] = cexp(I * w * length);
  }
  double theta = r->fade_samples > 0 ? AF_PI / length : 0.0;
  r->fade_e = cexp(I * theta);
  r->fade_eh = cexp(0.5 * I * theta);
}

af_status af_response_create(const af_response_config *cfg, af_response **out)
{
  if (cfg == NULL || out == NULL)
    return AF_EINVAL;
  *out = NULL;
  af_status s = af_config_check_window(cfg);
  if (s == AF_OK)
    s = af_config_check_levels(cfg);
  if (s != AF_OK)
    return s;
  af_status_init();
  af_response *r = calloc(1, sizeof *r);
  if (r == NULL)
    return AF_ENOMEM;
  r->cfg = *cfg;
  r->bins = cfg->fft_size / 2 + 1;
  r->bin_hz = cfg->sample_rate_hz / (double)cfg->fft_size;
  r->in = fftw_alloc_real(cfg->fft_size);
  r->spec = fftw_alloc_complex(r->bins);
  r->window = fftw_alloc_real(cfg->window_samples);
  r->power = fftw_alloc_real(r->bins);
  r->noise_ref = fftw_alloc_real(r->bins);
  r->scratch = fftw_alloc_real(r->bins);
  r->work = fftw_alloc_complex(r->bins);
  r->work_power = fftw_alloc_real(r->bins);
  r->orig = fftw_alloc_complex(r->bins);
  r->phase_u = fftw_alloc_complex(r->bins);
  r->phase_ul = fftw_alloc_complex(r->bins);
  r->phase_um = fftw_alloc_complex(r->bins);
  gsl_multifit_nlinear_parameters fit_params = gsl_multifit_nlinear_default_parameters();
  /* normal equations: J is 130 x 10 and well scaled (parameters of order 1),
   * so Cholesky is safe and several times cheaper than the default QR */
  fit_params.solver = gsl_multifit_nlinear_solver_cholesky;
  r->fit = gsl_multifit_nlinear_alloc(gsl_multifit_nlinear_trust, &fit_params, AF_RESPONSE_FIT_ROWS,
                                      AF_RESPONSE_FIT_PARAMS);
  r->fit_start = gsl_vector_alloc(AF_RESPONSE_FIT_PARAMS);
  int split_ok = 1;
  for (size_t q = 0; q < 2; ++q)
    for (size_t b = 0; b < AF_RESPONSE_SPLIT_BUCKETS; ++b) {
      r->split_fit[q][b] = gsl_multifit_nlinear_alloc(gsl_multifit_nlinear_trust, &fit_params,
                                                      2 * af_split_bins[b], 4 * (q + 1) + 6);
      split_ok = split_ok && r->split_fit[q][b] != NULL;
    }
  r->fit2_start = gsl_vector_alloc(AF_RESPONSE_SPLIT_PARAMS);
  r->trend_gram = gsl_matrix_alloc(AF_RESPONSE_MAX_TERMS, AF_RESPONSE_MAX_TERMS);
  r->trend_rhs = gsl_vector_alloc(AF_RESPONSE_MAX_TERMS);
  r->trend_coef = gsl_vector_alloc(AF_RESPONSE_MAX_TERMS);
  if (r->in == NULL || r->spec == NULL || r->window == NULL || r->power == NULL ||
      r->noise_ref == NULL || r->scratch == NULL || r->work == NULL || r->work_power == NULL ||
      r->orig == NULL || r->phase_u == NULL || r->phase_ul == NULL || r->phase_um == NULL ||
      r->fit == NULL || r->fit_start == NULL || !split_ok || r->fit2_start == NULL ||
      r->trend_gram == NULL || r->trend_rhs == NULL || r->trend_coef == NULL) {
    af_response_destroy(r);
    return AF_ENOMEM;
  }
  /* FFTW_ESTIMATE: no measurement, so no buffer is overwritten and the plan
   * takes microseconds; the transform is a small fraction of the budget. */
  r->plan = fftw_plan_dft_r2c_1d((int)cfg->fft_size, r->in, r->spec, FFTW_ESTIMATE);
  if (r->plan == NULL) {
    af_response_destroy(r);
    return AF_ENOMEM;
  }
  af_response_fill_window(r);
  af_response_fill_phases(r);
  *out = r;
  return AF_OK;
}

void af_response_destroy(af_response *r)
{
  if (r == NULL)
    return;
  if (r->plan != NULL)
    fftw_destroy_plan(r->plan);
  fftw_free(r->in);
  fftw_free(r->spec);
  fftw_free(r->window);
  fftw_free(r->power);
  fftw_free(r->noise_ref);
  fftw_free(r->scratch);
  fftw_free(r->work);
  fftw_free(r->work_power);
  fftw_free(r->orig);
  fftw_free(r->phase_u);
  fftw_free(r->phase_ul);
  fftw_free(r->phase_um);
  if (r->fit != NULL)
    gsl_multifit_nlinear_free(r->fit);
  for (size_t q = 0; q < 2; ++q)
    for (size_t b = 0; b < AF_RESPONSE_SPLIT_BUCKETS; ++b)
      if (r->split_fit[q][b] != NULL)
        gsl_multifit_nlinear_free(r->split_fit[q][b]);
  if (r->fit2_start != NULL)
    gsl_vector_free(r->fit2_start);
  if (r->fit_start != NULL)
    gsl_vector_free(r->fit_start);
  if (r->trend_gram != NULL)
    gsl_matrix_free(r->trend_gram);
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

/* ---- transform ------------------------------------------------------------ */

/* Mean of x[0..n); AF_ENUMERIC for a non-finite sample. */
static af_status af_mean(const float *x, size_t n, double *mean)
{
  double sum = 0.0;
  for (size_t k = 0; k < n; ++k) {
    if (!isfinite(x[k]))
      return AF_ENUMERIC;
    sum += x[k];
  }
  *mean = sum / (double)n;
  return AF_OK;
}

/* First sample whose |x - mean| reaches fraction of the largest, kept at
 * least AF_RESPONSE_MIN_SAMPLES from the end; 0 when fraction is 0. Starting
 * the analysis there makes the ringing start at the window's first sample,
 * where the exponential window and the model of the fit expect it; a start a
 * little after the true onset costs only amplitude. */
static size_t af_onset(const float *x, size_t n, double mean, double fraction)
{
  if (!(fraction > 0.0))
    return 0;
  double peak = 0.0;
  for (size_t k = 0; k < n; ++k)
    peak = fmax(peak, fabs((double)x[k] - mean));
  size_t k = 0;
  while (k + AF_RESPONSE_MIN_SAMPLES < n && fabs((double)x[k] - mean) < fraction * peak)
    ++k;
  return k;
}

/* ---- trend: DC and hum ------------------------------------------------------
 * A steady component (DC offset, mains hum and its harmonics) is cut by the
 * window's start into a transient whose spectrum is not flat: 1/f skirts and
 * broad interference humps across the range, tens of dB above white noise
 * for a strong hum, which a noise floor measured elsewhere would pass as
 * peaks. It is fitted by least squares over the analysed samples (unweighted:
 * the late samples, where the ringing has died, pin it) and subtracted before
 * the window. */

/* Harmonics of the hum to remove for a range starting at f_lo_hz. */
static size_t af_hum_harmonics(const af_response *r, double f_lo_hz)
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
} af_rotor;

static af_rotor af_rotor_start(const af_response *r)
{
  double w = 2.0 * AF_PI * r->cfg.hum_hz / r->cfg.sample_rate_hz;
  af_rotor rot = {1.0, 0.0, cos(w), sin(w)};
  return rot;
}

/* Basis of the trend at the rotor's sample: 1, cos(h phase), sin(h phase),
 * h = 1..harmonics; then advances the rotor by one sample. */
static void af_trend_basis(af_rotor *rot, size_t harmonics, double *phi)
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

/* Least-squares DC + harmonics of x[start..n) into r->trend_coef; falls back
 * to the mean alone when the normal equations are singular (a segment far
 * shorter than a hum period). */
/* sum_{k < m} cos(theta k) and sin(theta k), in closed form:
 * sum exp(i theta k) = exp(i theta (m - 1) / 2) sin(m theta / 2) / sin(theta / 2). */
static void af_phase_sums(double theta, size_t m, double *sum_cos, double *sum_sin)
{
  double half = sin(0.5 * theta);
  double d = fabs(half) < 1e-12 ? (double)m : sin(0.5 * theta * (double)m) / half;
  *sum_cos = cos(0.5 * theta * (double)(m - 1)) * d;
  *sum_sin = sin(0.5 * theta * (double)(m - 1)) * d;
}

/* Normal matrix of the basis 1, cos(h theta k), sin(h theta k) over m
 * samples (lower triangle), from the product-to-sum identities and closed
 * sums: no pass over the data. */
static void af_trend_gram(double theta, size_t m, size_t harmonics, gsl_matrix *g)
{
  double cs[2 * AF_RESPONSE_MAX_HUM_HARMONICS + 1][2];
  for (size_t j = 0; j <= 2 * harmonics; ++j)
    af_phase_sums(theta * (double)j, m, &cs[j][0], &cs[j][1]);
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

/* Least-squares DC + harmonics of x[start..n) into r->trend_coef; falls back
 * to the mean alone when the normal equations are singular (a segment far
 * shorter than a hum period). */
static void af_trend_fit(af_response *r, const float *x, size_t start, size_t n, size_t harmonics)
{
  size_t p = 1 + 2 * harmonics;
  af_rotor rot = af_rotor_start(r);
  double phi[AF_RESPONSE_MAX_TERMS], rhs[AF_RESPONSE_MAX_TERMS] = {0};
  for (size_t k = start; k < n; ++k) {
    af_trend_basis(&rot, harmonics, phi);
    for (size_t i = 0; i < p; ++i)
      rhs[i] += phi[i] * (double)x[k];
  }
  gsl_matrix_view g = gsl_matrix_submatrix(r->trend_gram, 0, 0, p, p);
  gsl_vector_view b = gsl_vector_subvector(r->trend_rhs, 0, p);
  gsl_vector_view a = gsl_vector_subvector(r->trend_coef, 0, p);
  for (size_t i = 0; i < p; ++i)
    gsl_vector_set(&b.vector, i, rhs[i]);
  r->trend_terms = p;
  if (p > 1) {
    af_trend_gram(2.0 * AF_PI * r->cfg.hum_hz / r->cfg.sample_rate_hz, n - start, harmonics,
                  &g.matrix);
    if (gsl_linalg_cholesky_decomp1(&g.matrix) == GSL_SUCCESS &&
        gsl_linalg_cholesky_solve(&g.matrix, &b.vector, &a.vector) == GSL_SUCCESS)
      return;
  }
  r->trend_terms = 1;
  gsl_vector_set(r->trend_coef, 0, rhs[0] / (double)(n - start));
}

/* Periodogram of x[start..n), less its fitted trend, into r->power: windowed
 * from start, zero-padded. The window energy sum w_k^2 into *window_energy. */
static void af_response_transform(af_response *r, const float *x, size_t n, size_t start,
                                  double *window_energy)
{
  size_t m = n - start, harmonics = (r->trend_terms - 1) / 2;
  af_rotor rot = af_rotor_start(r);
  double phi[AF_RESPONSE_MAX_TERMS], coef[AF_RESPONSE_MAX_TERMS], energy = 0.0;
  for (size_t i = 0; i < r->trend_terms; ++i)
    coef[i] = gsl_vector_get(r->trend_coef, i);
  for (size_t k = 0; k < m; ++k) {
    af_trend_basis(&rot, harmonics, phi);
    double trend = 0.0;
    for (size_t i = 0; i < r->trend_terms; ++i)
      trend += phi[i] * coef[i];
    r->in[k] = ((double)x[start + k] - trend) * r->window[k];
    energy += r->window[k] * r->window[k];
  }
  memset(r->in + m, 0, (r->cfg.fft_size - m) * sizeof *r->in);
  fftw_execute(r->plan);
  for (size_t k = 0; k < r->bins; ++k)
    r->power[k] = creal(r->spec[k] * conj(r->spec[k]));
  *window_energy = energy;
}

/* ---- noise floor ---------------------------------------------------------- */

af_status af_response_add_noise(af_response *r, const float *noise, size_t n)
{
  if (r == NULL || noise == NULL || n < AF_RESPONSE_MIN_SAMPLES)
    return AF_EINVAL;
  if (n > r->cfg.window_samples)
    return AF_ESIZE;
  double mean = 0.0, energy = 0.0;
  af_status s = af_mean(noise, n, &mean);
  if (s != AF_OK)
    return s;
  /* the reference does not know the range: every configured harmonic goes */
  af_trend_fit(r, noise, 0, n, r->cfg.hum_hz > 0.0 ? r->cfg.hum_harmonics : 0);
  af_response_transform(r, noise, n, 0, &energy);
  /* running mean: one segment's floor over a range of a few hundred Hz
   * scatters by ~1.5 dB, the mean of m segments by ~1.5/sqrt(m) dB */
  if (r->noise_segments == 0) /* fresh, or after a clear: no mean to update */
    memset(r->noise_ref, 0, r->bins * sizeof *r->noise_ref);
  double weight = 1.0 / (double)(r->noise_segments + 1);
  for (size_t k = 0; k < r->bins; ++k)
    r->noise_ref[k] += weight * (r->power[k] / energy - r->noise_ref[k]);
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
static double af_band_floor(af_response *r)
{
  size_t k_lo, k_hi;
  af_band_bins(r->cfg.noise_band_lo_hz, r->cfg.noise_band_hi_hz, r->bin_hz, r->bins - 1, &k_lo,
               &k_hi);
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
static double af_reference_floor(const af_response *r, double f_lo_hz, double f_hi_hz,
                                 double energy)
{
  size_t k_lo, k_hi;
  af_band_bins(f_lo_hz, f_hi_hz, r->bin_hz, r->bins - 1, &k_lo, &k_hi);
  if (k_hi < k_lo)
    k_hi = k_lo;
  double sum = 0.0;
  for (size_t k = k_lo; k <= k_hi; ++k)
    sum += r->noise_ref[k];
  return energy * sum / (double)(k_hi - k_lo + 1);
}

/* Noise power per bin of the last transform (window energy 'energy'). */
static double af_response_noise_power(af_response *r, double f_lo_hz, double f_hi_hz, double energy,
                                      size_t *segments)
{
  *segments = r->noise_segments;
  if (r->noise_segments > 0)
    return af_reference_floor(r, f_lo_hz, f_hi_hz, energy);
  return af_band_floor(r);
}

/* ---- peak ----------------------------------------------------------------- */

/* The floor a peak at k rises from: on each side the lowest power within
 * AF_RESPONSE_FIT_MAX_HALF bins before the spectrum climbs above p[k] again;
 * the higher of the two. */
static double af_local_floor(const af_response *r, size_t k)
{
  const double *p = r->power;
  double left = p[k], right = p[k];
  for (size_t i = 1; i <= AF_RESPONSE_FIT_MAX_HALF && i < k && p[k - i] <= p[k]; ++i)
    left = fmin(left, p[k - i]);
  for (size_t i = 1; i <= AF_RESPONSE_FIT_MAX_HALF && k + i < r->bins && p[k + i] <= p[k]; ++i)
    right = fmin(right, p[k + i]);
  return fmax(left, right);
}

/* Strongest peak of r->power with its top bin in [f_lo, f_hi] (its
 * neighbours may lie outside: a peak is judged by where its top is): a local
 * maximum standing AF_RESPONSE_PROMINENCE above its local floor. A band edge
 * on the skirt of an outside mode is not a maximum; a ripple on a skirt, or a
 * broad hump where skirts interfere, is not prominent. 0 if none; then the
 * largest rise of a local maximum above its floor into *best_rise. */
static size_t af_response_find_peak(const af_response *r, double f_lo_hz, double f_hi_hz,
                                    double *best_rise)
{
  size_t k_lo, k_hi, best = 0;
  af_band_bins(f_lo_hz, f_hi_hz, r->bin_hz, r->bins - 2, &k_lo, &k_hi);
  const double *p = r->power;
  *best_rise = 0.0;
  for (size_t k = k_lo; k <= k_hi; ++k) {
    if (!(p[k] > p[k - 1] && p[k] >= p[k + 1]))
      continue;
    double floor_k = af_local_floor(r, k);
    *best_rise = fmax(*best_rise, p[k] - floor_k);
    if (p[k] >= AF_RESPONSE_PROMINENCE * floor_k && (best == 0 || p[k] > p[best]))
      best = k;
  }
  return best;
}

/* A mode of the spectrum as the refinement sees it, before the window's decay
 * is taken off. */
typedef struct {
  double bin;            /* frequency [bins, fractional] */
  double sigma_windowed; /* decay rate of the windowed mode [1/s]; NaN if unknown */
  double complex c;      /* complex amplitude: the ringing is c z^n + conj; NaN if unknown */
  double peak_power;     /* the mode's |X|^2 at its frequency */
  double span_lo;        /* bins of the peak's top (stage 1): a refined frequency */
  double span_hi;        /*   outside them belongs to something else */
} af_peak;

/* ---- stage 1: the magnitude alone -------------------------------------------
 * The power spectrum of a windowed damped sinusoid near its peak is
 *   P = |c|^2 / ((1 - r)^2 + 4 r sin^2(pi x / N)),  r = exp(-sigma' / fs),
 * so 1/P is a parabola in the bin offset x (to 1e-5 over the peak). Closed
 * form, but biased by the skirts of nearby modes and by the mode's own
 * negative-frequency image (they add to the complex spectrum, not to P): it
 * seeds stage 2. */

/* Bins around k above AF_RESPONSE_FIT_LEVEL of p[k] and falling away from it
 * (a rise is the next peak), at least one each side. */
static void af_fit_span(const af_response *r, const double *p, size_t k, size_t *first,
                        size_t *last)
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

static double af_det3(double m[3][3])
{
  return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
         m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
         m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
}

/* Solves the 3x3 system m x = v by Cramer's rule; 0 if singular. */
static int af_solve3(double m[3][3], const double v[3], double x[3])
{
  double det = af_det3(m);
  if (!(fabs(det) > 0.0) || !isfinite(det))
    return 0;
  for (int c = 0; c < 3; ++c) {
    double t[3][3];
    memcpy(t, m, sizeof t);
    for (int i = 0; i < 3; ++i)
      t[i][c] = v[i];
    x[c] = af_det3(t) / det;
  }
  return 1;
}

/* Weighted least-squares parabola y = c0 + c1 x + c2 x^2 through 1/p at
 * x = j - k. Weights p^2: the residual in 1/p times p^2 is the residual in p
 * relative to p, so the top bins (highest SNR) count most. */
static int af_inverse_parabola(const double *p, size_t k, size_t first, size_t last, double c[3])
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
  return af_solve3(m, v, c);
}

/* Stage 1 on the power p of the spectrum x at its local maximum k. With the
 * parabola y_v + c2 (x - x_v)^2, c2 = 4 pi^2 r / (N^2 |c|^2), hence
 * (1 - r)^2 / r = q := 4 pi^2 y_v / (N^2 c2), whose root below 1 is r.
 * 0 when the parabola is not a peak. */
static int af_stage1(const af_response *r, const double *p, const double complex *x, size_t k,
                     af_peak *out)
{
  size_t first, last;
  double c[3];
  af_fit_span(r, p, k, &first, &last);
  if (!af_inverse_parabola(p, k, first, last, c) || !(c[2] > 0.0))
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
static void af_log_parabola(const af_response *r, size_t k, af_peak *out)
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

/* ---- stage 2: complex fit --------------------------------------------------
 * A real damped cosine c z^n + conj(c z^n), z = exp((-sigma' + i w0) dt),
 * n >= 0, has the DFT (u = exp(-i w dt))
 *   X(u) = c / (1 - z u) + conj(c) / (1 - conj(z) u):
 * the peak and its negative-frequency image, exact under the exponential
 * window. An onset at sample d > 0 adds nothing new: the sum from d is
 * c z^d / (1 - z u) + conj(...) minus the transform of the d missing samples,
 * a polynomial in u, smooth across the peak (its width is fs / d). So are the
 * far modes' skirts and the hum's. Hence
 *   X_k ~ c / (1 - z u_k) + conj(c) / (1 - conj(z) u_k) + B(x_k),
 * B a complex quadratic in the bin offset x = (k - k*) / h, fitted on the
 * complex bins, unweighted (white noise has the same variance in every bin).
 * c = a (1 - r0) and the data are scaled by 1/|X_k*| so that every parameter
 * is of order 1 at the start. */

enum { AF_P_BIN, AF_P_SIGMA, AF_P_ARE, AF_P_AIM, AF_P_B0 };

/* c / (1 - z u) + conj(c) / (1 - conj(z) u) at bin k. */
static double complex af_pole_pair(const af_response *r, double bin, double sigma_windowed,
                                   double complex c, size_t k)
{
  double n_fft = (double)r->cfg.fft_size;
  double complex u = cexp(-I * 2.0 * AF_PI * (double)k / n_fft);
  double complex z = cexp(-sigma_windowed / r->cfg.sample_rate_hz + I * 2.0 * AF_PI * bin / n_fft);
  return c / (1.0 - z * u) + conj(c) / (1.0 - conj(z) * u);
}

typedef struct {
  double complex model;                     /* model value */
  double complex d[AF_RESPONSE_FIT_PARAMS]; /* its derivatives */
} af_fit_point;

/* Model and derivatives at (fractional) bin k for parameters x. */
static void af_fit_eval(const af_response *r, const gsl_vector *x, double k, af_fit_point *pt)
{
  const af_fit_ctx *f = &r->ctx;
  double n_fft = (double)r->cfg.fft_size, fs = r->cfg.sample_rate_hz;
  double complex u = cexp(-I * 2.0 * AF_PI * k / n_fft);
  double complex z = cexp(-gsl_vector_get(x, AF_P_SIGMA) / fs +
                          I * 2.0 * AF_PI * gsl_vector_get(x, AF_P_BIN) / n_fft);
  double complex zc = conj(z);
  double complex c = f->norm * (gsl_vector_get(x, AF_P_ARE) + I * gsl_vector_get(x, AF_P_AIM));
  double complex d1 = 1.0 / (1.0 - z * u), d2 = 1.0 / (1.0 - zc * u);
  double xb = (k - f->center) / f->half;
  double complex bg = 0.0;
  double xp = 1.0;
  for (size_t j = 0; j < 3; ++j, xp *= xb) {
    bg += xp * (gsl_vector_get(x, AF_P_B0 + 2 * j) + I * gsl_vector_get(x, AF_P_B0 + 2 * j + 1));
    pt->d[AF_P_B0 + 2 * j] = xp;
    pt->d[AF_P_B0 + 2 * j + 1] = I * xp;
  }
  /* d/dz of c / (1 - z u) is c u / (1 - z u)^2 */
  double complex gz = c * u * d1 * d1, gzc = conj(c) * u * d2 * d2;
  pt->model = c * d1 + conj(c) * d2 + bg;
  pt->d[AF_P_BIN] = (gz * z - gzc * zc) * (I * 2.0 * AF_PI / n_fft);
  pt->d[AF_P_SIGMA] = -(gz * z + gzc * zc) / fs;
  pt->d[AF_P_ARE] = f->norm * (d1 + d2);
  pt->d[AF_P_AIM] = f->norm * I * (d1 - d2);
}

/* Residuals, real and imaginary parts of each fitted bin; the rows beyond
 * them stay 0 (the workspace is sized for the widest fit at create). */
static int af_fit_f(const gsl_vector *x, void *params, gsl_vector *f)
{
  const af_response *r = params;
  gsl_vector_set_zero(f);
  for (size_t i = 0; i < r->ctx.count; ++i) {
    size_t k = r->ctx.first + i;
    af_fit_point pt;
    af_fit_eval(r, x, (double)k, &pt);
    double complex res = pt.model - r->ctx.gain * r->ctx.data[k];
    if (!isfinite(creal(res)) || !isfinite(cimag(res)))
      return GSL_EBADFUNC;
    gsl_vector_set(f, 2 * i, creal(res));
    gsl_vector_set(f, 2 * i + 1, cimag(res));
  }
  return GSL_SUCCESS;
}

static int af_fit_df(const gsl_vector *x, void *params, gsl_matrix *jac)
{
  const af_response *r = params;
  gsl_matrix_set_zero(jac);
  for (size_t i = 0; i < r->ctx.count; ++i) {
    af_fit_point pt;
    af_fit_eval(r, x, (double)(r->ctx.first + i), &pt);
    for (size_t j = 0; j < AF_RESPONSE_FIT_PARAMS; ++j) {
      gsl_matrix_set(jac, 2 * i, j, creal(pt.d[j]));
      gsl_matrix_set(jac, 2 * i + 1, j, cimag(pt.d[j]));
    }
  }
  return GSL_SUCCESS;
}

/* Half-width of the fit around a peak of this windowed decay rate [bins]. */
static size_t af_fit_half(const af_response *r, double sigma_windowed)
{
  double halfwidth_bins = sigma_windowed / (2.0 * AF_PI * r->bin_hz);
  double span = ceil(AF_RESPONSE_FIT_HALFWIDTHS * halfwidth_bins);
  if (!(span > AF_RESPONSE_FIT_MIN_HALF))
    return AF_RESPONSE_FIT_MIN_HALF;
  return span > AF_RESPONSE_FIT_MAX_HALF ? AF_RESPONSE_FIT_MAX_HALF : (size_t)span;
}

/* Bins of the fit and the scales of its parameters. */
static void af_fit_setup(af_response *r, const double complex *x, size_t k, const af_peak *seed)
{
  size_t half = af_fit_half(r, seed->sigma_windowed);
  size_t first = k > half ? k - half : 1;
  size_t last = k + half < r->bins - 1 ? k + half : r->bins - 1;
  r->ctx.data = x;
  r->ctx.first = first;
  r->ctx.count = last - first + 1;
  r->ctx.center = (double)k;
  r->ctx.half = (double)half;
  r->ctx.gain = 1.0 / cabs(x[k]);
  r->ctx.norm = 1.0 - exp(-seed->sigma_windowed / r->cfg.sample_rate_hz);
}

/* |X(f0)|^2 of the mode alone through the window, fade-in included (the
 * fit puts the fade-in into the background): the ringing f_k c z^k sums at
 * its own frequency to c (1 / (1 - r) - sum_{k < L} (1 - f_k) r^k). */
static double af_mode_peak_power(const af_response *r, double complex c, double sigma_windowed)
{
  double rr = exp(-sigma_windowed / r->cfg.sample_rate_hz);
  double sum = 1.0 / (1.0 - rr), rk = 1.0;
  for (size_t k = 0; k < r->fade_samples; ++k, rk *= rr)
    sum -= (1.0 - af_fade(k, r->fade_samples)) * rk;
  return creal(c * conj(c)) * sum * sum;
}

/* Stage 2 on the spectrum x near its local maximum k, from the seed in *pk;
 * 0 (*pk untouched) if the fit fails or its frequency leaves the peak's top
 * (it went for a neighbour or the background). */
static int af_stage2(af_response *r, const double complex *x, size_t k, af_peak *pk)
{
  af_fit_setup(r, x, k, pk);
  if (!isfinite(r->ctx.gain) || !(r->ctx.norm > 0.0))
    return 0;
  gsl_vector *p0 = r->fit_start;
  gsl_vector_set_zero(p0);
  gsl_vector_set(p0, AF_P_BIN, pk->bin);
  gsl_vector_set(p0, AF_P_SIGMA, pk->sigma_windowed);
  gsl_vector_set(p0, AF_P_ARE, r->ctx.gain * creal(pk->c) / r->ctx.norm);
  gsl_vector_set(p0, AF_P_AIM, r->ctx.gain * cimag(pk->c) / r->ctx.norm);
  gsl_multifit_nlinear_fdf fdf = {
      af_fit_f, af_fit_df, NULL, AF_RESPONSE_FIT_ROWS, AF_RESPONSE_FIT_PARAMS, r, 0, 0, 0};
  int info = 0;
  if (gsl_multifit_nlinear_init(p0, &fdf, r->fit) != GSL_SUCCESS ||
      gsl_multifit_nlinear_driver(AF_RESPONSE_FIT_MAX_ITER, AF_RESPONSE_FIT_XTOL,
                                  AF_RESPONSE_FIT_GTOL, AF_RESPONSE_FIT_FTOL, NULL, NULL, &info,
                                  r->fit) != GSL_SUCCESS)
    return 0;
  const gsl_vector *p = gsl_multifit_nlinear_position(r->fit);
  double bin = gsl_vector_get(p, AF_P_BIN), sigma = gsl_vector_get(p, AF_P_SIGMA);
  if (!(bin >= pk->span_lo && bin <= pk->span_hi) || !(sigma > 0.0))
    return 0;
  pk->bin = bin;
  pk->sigma_windowed = sigma;
  pk->c =
      r->ctx.norm / r->ctx.gain * (gsl_vector_get(p, AF_P_ARE) + I * gsl_vector_get(p, AF_P_AIM));
  pk->peak_power = af_mode_peak_power(r, pk->c, sigma);
  return 1;
}

/* ---- one neighbour ---------------------------------------------------------
 * A mode close enough for its peak to reach into the fit (a weak mode in the
 * range, a split 0S2, a loud mode just outside) is not smooth there and biases
 * the quadratic background. It is fitted in turn and taken off: fit the 0S2,
 * fit the neighbour on the spectrum less the 0S2, fit the 0S2 again on the
 * spectrum less the neighbour (one round of alternating fits). */

/* Strongest local maximum j != k within two fit half-widths of k that clears
 * the SNR threshold and stands at least AF_RESPONSE_NEIGHBOUR_PROMINENCE
 * above the valley between it and k (a noise ripple on the skirt does not). */
static int af_find_neighbour(const af_response *r, size_t k, size_t half, double min_power,
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

/* work = spec - the mode pk, with its power, over the bins any fit around k
 * or j can read. */
static void af_subtract(af_response *r, const af_peak *pk, size_t k, size_t j)
{
  size_t a = k < j ? k : j, b = k < j ? j : k, reach = AF_RESPONSE_FIT_MAX_HALF + 2;
  size_t lo = a > reach ? a - reach : 0;
  size_t hi = b + reach < r->bins ? b + reach : r->bins - 1;
  for (size_t i = lo; i <= hi; ++i) {
    r->work[i] = r->spec[i] - af_pole_pair(r, pk->bin, pk->sigma_windowed, pk->c, i);
    r->work_power[i] = creal(r->work[i] * conj(r->work[i]));
  }
}

/* The mode at the local maximum k, refined as far as the data allow; 1 if
 * the complex fit (stage 2) holds, 0 for a stage-1 or log-parabola estimate. */
static int af_refine(af_response *r, size_t k, double min_power, af_peak *out)
{
  if (!af_stage1(r, r->power, r->spec, k, out)) {
    af_log_parabola(r, k, out);
    return 0;
  }
  if (!af_stage2(r, r->spec, k, out))
    return 0;
  size_t j;
  if (!af_find_neighbour(r, k, af_fit_half(r, out->sigma_windowed), min_power, &j))
    return 1;
  af_peak nb, again = *out;
  af_subtract(r, out, k, j);
  if (!(r->work_power[j] > r->work_power[j - 1] && r->work_power[j] >= r->work_power[j + 1]) ||
      !af_stage1(r, r->work_power, r->work, j, &nb) || !af_stage2(r, r->work, j, &nb))
    return 1;
  af_subtract(r, &nb, k, j);
  if (af_stage2(r, r->work, k, &again))
    *out = again;
  return 1;
}

/* ---- analysis ------------------------------------------------------------- */

/* 10 log10(peak / noise) [dB]; +-inf for digital silence. */
static double af_snr_db(double peak_power, double noise_power)
{
  if (noise_power > 0.0)
    return 10.0 * log10(peak_power / noise_power); /* -inf for a silent band */
  return peak_power > 0.0 ? INFINITY : -INFINITY;
}

static void af_result_clear(af_response_result *out, double bin_hz)
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

/* Frequency, decay, amplitude of the refined peak into out; the exponential
 * window's decay 1/tau_w is taken off the windowed mode's. */
static void af_result_fill(const af_response *r, const af_peak *pk, af_response_result *out)
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

af_status af_response_analyze(af_response *r, const float *audio, size_t n, double f_lo_hz,
                              double f_hi_hz, af_response_result *out)
{
  if (r == NULL || audio == NULL || out == NULL || n < AF_RESPONSE_MIN_SAMPLES)
    return AF_EINVAL;
  if (!(f_lo_hz > 0.0) || !(f_hi_hz > f_lo_hz) || !(f_hi_hz < 0.5 * r->cfg.sample_rate_hz))
    return AF_EINVAL;
  if (n > r->cfg.window_samples)
    return AF_ESIZE;
  double mean = 0.0, energy = 0.0, rise = 0.0;
  af_status s = af_mean(audio, n, &mean);
  if (s != AF_OK)
    return s;
  size_t start = af_onset(audio, n, mean, r->cfg.onset_fraction);
  af_trend_fit(r, audio, start, n, af_hum_harmonics(r, f_lo_hz));
  af_response_transform(r, audio, n, start, &energy);
  af_result_clear(out, r->bin_hz);
  out->onset_index = start;
  double noise = af_response_noise_power(r, f_lo_hz, f_hi_hz, energy, &out->noise_segments);
  size_t k = af_response_find_peak(r, f_lo_hz, f_hi_hz, &rise);
  if (k == 0) {
    out->snr_db = af_snr_db(rise, noise);
    return AF_ENODATA;
  }
  af_peak pk;
  int fitted = af_refine(r, k, noise * pow(10.0, 0.1 * r->cfg.snr_threshold_db), &pk);
  af_result_fill(r, &pk, out);
  /* The peak power is the mode's own fitted peak (free of other modes'
   * skirts, which may add to or cancel it in the periodogram), bounded by
   * AF_RESPONSE_PEAK_BOUND times the periodogram there: a narrow pole fitted
   * to a noise bump may extrapolate far above the data, a mode does not. */
  double peak_power = r->power[k];
  if (fitted)
    peak_power = fmin(pk.peak_power, AF_RESPONSE_PEAK_BOUND * r->power[k]);
  out->snr_db = af_snr_db(peak_power, noise);
  /* a top refined out of the range was the edge of something outside it */
  if (out->snr_db < r->cfg.snr_threshold_db || !(out->frequency_hz >= f_lo_hz) ||
      !(out->frequency_hz <= f_hi_hz))
    return AF_ENODATA;
  return fitted ? AF_OK : AF_ENODATA; /* a top that is no damped mode */
}

/* ---- peak list ---------------------------------------------------------------
 * The modes of one transform, strongest first (response.h has the rules):
 * each candidate is read by a fit that models the window exactly (one pole,
 * or two for a blend; af_response_analyze's refinement where neither
 * holds), judged as af_response_analyze judges its peak, and subtracted
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

/* Noise power per bin at frequency f_hz of the last transform: the
 * reference's mean over f / AF_RESPONSE_LIST_NOISE_SPAN .. f x it, else the
 * band floor (band_floor, computed once). */
static double af_list_noise(const af_response *r, double f_hz, double band_floor, double energy)
{
  if (r->noise_segments == 0)
    return band_floor;
  return af_reference_floor(r, f_hz / AF_RESPONSE_LIST_NOISE_SPAN,
                            f_hz * AF_RESPONSE_LIST_NOISE_SPAN, energy);
}

static int af_excluded(const size_t *excluded, size_t n_excluded, size_t k)
{
  for (size_t i = 0; i < n_excluded; ++i)
    if (k + AF_RESPONSE_LIST_EXCLUDE >= excluded[i] && k <= excluded[i] + AF_RESPONSE_LIST_EXCLUDE)
      return 1;
  return 0;
}

/* The floors a maximum at k rises from on its two sides (as
 * af_local_floor), the lower and the higher. */
static void af_side_floors(const af_response *r, size_t k, double *low, double *high)
{
  const double *p = r->power;
  double left = p[k], right = p[k];
  for (size_t i = 1; i <= AF_RESPONSE_FIT_MAX_HALF && i < k && p[k - i] <= p[k]; ++i)
    left = fmin(left, p[k - i]);
  for (size_t i = 1; i <= AF_RESPONSE_FIT_MAX_HALF && k + i < r->bins && p[k + i] <= p[k]; ++i)
    right = fmin(right, p[k + i]);
  *low = fmin(left, right);
  *high = fmax(left, right);
}

/* The strongest local maximum of r->power in [k_lo, k_hi] standing
 * AF_RESPONSE_PROMINENCE (6 dB) above its floor on one side and
 * AF_RESPONSE_NEIGHBOUR_PROMINENCE (3 dB) on the other: two modes ~10 %
 * apart fill the valley between them with their skirts to 4-5 dB below
 * either, which af_response_analyze's 6 dB on both sides refuses; the
 * ripples and humps that rule keeps out belong to a stronger mode, taken
 * off (exactly, with its ripple) before they are looked at. Not excluded,
 * and whose top bin could still clear the threshold (a peak's reported
 * power is at most AF_RESPONSE_PEAK_BOUND times it); 0 if none. Its noise
 * floor into *noise; the largest SNR of any maximum's rise above its floor
 * raised into *rise_snr_db. */
static size_t af_list_candidate(const af_response *r, size_t k_lo, size_t k_hi, double band_floor,
                                double energy, const size_t *excluded, size_t n_excluded,
                                double *noise, double *rise_snr_db)
{
  const double *p = r->power;
  double threshold = pow(10.0, 0.1 * r->cfg.snr_threshold_db);
  size_t best = 0;
  for (size_t k = k_lo; k <= k_hi; ++k) {
    if (!(p[k] > p[k - 1] && p[k] >= p[k + 1]))
      continue;
    double low, high;
    af_side_floors(r, k, &low, &high);
    double noise_k = af_list_noise(r, (double)k * r->bin_hz, band_floor, energy);
    *rise_snr_db = fmax(*rise_snr_db, af_snr_db(p[k] - high, noise_k));
    if (p[k] < AF_RESPONSE_PROMINENCE * low || p[k] < AF_RESPONSE_NEIGHBOUR_PROMINENCE * high ||
        AF_RESPONSE_PEAK_BOUND * p[k] < threshold * noise_k || af_excluded(excluded, n_excluded, k))
      continue;
    if (best == 0 || p[k] > p[best]) {
      best = k;
      *noise = noise_k;
    }
  }
  return best;
}

/* Refines the maximum k and judges it as af_response_analyze does: 1 if it
 * is a damped mode within [f_lo, f_hi] clearing the SNR threshold. *out and
 * *pk are filled in any case (the best rejected one is reported). */
static int af_list_refine(af_response *r, size_t k, double noise, double f_lo_hz, double f_hi_hz,
                          af_peak *pk, af_response_result *out)
{
  int fitted = af_refine(r, k, noise * pow(10.0, 0.1 * r->cfg.snr_threshold_db), pk);
  af_result_fill(r, pk, out);
  double peak_power = r->power[k];
  if (fitted)
    peak_power = fmin(pk->peak_power, AF_RESPONSE_PEAK_BOUND * r->power[k]);
  out->snr_db = af_snr_db(peak_power, noise);
  /* a ringing mode decays: no measurable decay (q +inf) is a steady tone or
   * what a subtraction left of a louder mode */
  return fitted && out->snr_db >= r->cfg.snr_threshold_db && out->frequency_hz >= f_lo_hz &&
         out->frequency_hz <= f_hi_hz && isfinite(out->q);
}

/* A mode of a truncated fit (one or two poles) judged as af_list_refine
 * judges one: the SNR of its own peak power (bounded by the periodogram at
 * its nearest bin), the band, the decay. */
static int af_list_judge(const af_response *r, const af_peak *pk, double noise, double f_lo_hz,
                         double f_hi_hz, af_response_result *out)
{
  size_t k = (size_t)lround(pk->bin);
  af_result_fill(r, pk, out);
  out->snr_db = af_snr_db(fmin(pk->peak_power, AF_RESPONSE_PEAK_BOUND * r->power[k]), noise);
  return out->snr_db >= r->cfg.snr_threshold_db && out->frequency_hz >= f_lo_hz &&
         out->frequency_hz <= f_hi_hz && isfinite(out->q);
}

/* 1 / b without the C library's careful complex division (b is never near
 * 0 or overflow here: 1 - a with |a| < 1 bounded away from 1 by the decay). */
static double complex af_recip(double complex b)
{
  return conj(b) / (creal(b) * creal(b) + cimag(b) * cimag(b));
}

/* The part of sum_k a^k the fade-in removes, F(a) = sum_{k < L} (1 - f_k) a^k
 * with 1 - f_k = (1 + cos(theta (k + 1/2))) / 2, theta = pi / L, in closed
 * form (three geometric sums; (a e^{+-i theta})^L = -a^L). With al = a^L,
 * e = e^{i theta}, h = e^{i theta / 2}, inv_1a = 1 / (1 - a):
 *   F = (1 - al) / (2 (1 - a)) + (1 + al) / 4 (h / (1 - a e) + conj(h) / (1 - a conj(e))). */
static double complex af_fade_sum(const af_response *r, double complex a, double complex al,
                                  double complex inv_1a)
{
  if (r->fade_samples == 0)
    return 0.0;
  double complex e = r->fade_e, eh = r->fade_eh;
  return 0.5 * (1.0 - al) * inv_1a +
         0.25 * (1.0 + al) * (eh * af_recip(1.0 - a * e) + conj(eh) * af_recip(1.0 - a * conj(e)));
}

/* A listed mode as its exact spectrum needs it: c and the powers of z. */
typedef struct {
  double complex c, z, zm, zl; /* z^m (m = r->split_len), z^L (the fade-in) */
} af_mode_k;

static af_mode_k af_mode_consts(const af_response *r, const af_peak *pk)
{
  double complex lz = -pk->sigma_windowed / r->cfg.sample_rate_hz +
                      I * 2.0 * AF_PI * pk->bin / (double)r->cfg.fft_size;
  af_mode_k q = {pk->c, cexp(lz), cexp(r->split_len * lz), cexp((double)r->fade_samples * lz)};
  return q;
}

/* The mode q as the window holds it over the m analysed samples, at bin i
 * (r->phase_um filled there):
 *   c (T(z u) - F(z u)) + conj,  T(a) = (1 - a^m) / (1 - a),
 * F the fade-in's part (af_fade_sum). The fits see the pole alone (the
 * fade-in and the cut are smooth or small across a peak, taken by the
 * background), but far from the peak both matter: the cut leaves a ripple of
 * period fs / m (~ -36 dB at 40 ms), the fade-in a broad term ~ -25 dB of
 * the peak; a bare pole subtracted would leave them as false peaks beside the
 * mode and as a raised floor under the weaker modes sought next. */
static double complex af_mode_at(const af_response *r, const af_mode_k *q, size_t i)
{
  double complex u = r->phase_u[i], um = r->phase_um[i], ul = r->phase_ul[i];
  double complex a = q->z * u, ac = conj(q->z) * u;
  double complex inv = af_recip(1.0 - a), invc = af_recip(1.0 - ac);
  double complex t = (1.0 - q->zm * um) * inv - af_fade_sum(r, a, q->zl * ul, inv);
  double complex tc = (1.0 - conj(q->zm) * um) * invc - af_fade_sum(r, ac, conj(q->zl) * ul, invc);
  return q->c * t + conj(q->c) * tc;
}

/* Takes the mode pk off the spectrum and its power over [lo, hi]. */
static void af_list_subtract(af_response *r, const af_peak *pk, size_t lo, size_t hi)
{
  af_mode_k q = af_mode_consts(r, pk);
  for (size_t i = lo; i <= hi; ++i) {
    r->spec[i] -= af_mode_at(r, &q, i);
    r->power[i] = creal(r->spec[i] * conj(r->spec[i]));
  }
}

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
/* The weaker pole's peak power is at least this fraction (-20 dB) of the
 * stronger's: below it, it is a misfit of the stronger (the fade-in, a
 * neighbour's skirt the quadratic background does not follow) and would not
 * move the stronger's frequency anyway. */
#define AF_RESPONSE_SPLIT_MIN_RATIO 0.01
/* The two-pole fit spans this many times the one-pole fit's half-span
 * beyond the outer poles (at most the fit's rows). */
#define AF_RESPONSE_SPLIT_SPAN 2
/* The truncated fits stop at steps below 1e-6 relative: 1e-6 of a bin is
 * far below the noise's scatter, and it halves their iterations. */
#define AF_RESPONSE_SPLIT_XTOL 1e-6
/* Iteration cap of the truncated fits: from the stage-1 reading a one-pole
 * fit takes ~15, a refit ~6; a two-pole fit that has not settled in 25 is
 * judged where it stands (and usually refused). */
#define AF_RESPONSE_SPLIT_MAX_ITER 25
/* Starting offsets of the two poles from the one-pole frequency, in
 * half-widths of the one-pole fit. */
static const double af_split_offsets[] = {0.5, 1.0};

/* The powers of z each pole of a truncated fit needs, from the parameters. */
typedef struct {
  double complex z, zm, zm1; /* z, z^m, z^(m - 1) */
  double complex c;          /* complex amplitude */
} af_pole_k;

static void af_split_poles_k(const af_response *r, const gsl_vector *x, af_pole_k *pc)
{
  double n_fft = (double)r->cfg.fft_size, fs = r->cfg.sample_rate_hz, m = r->split_len;
  for (size_t j = 0; j < r->split_poles; ++j) {
    const double *q = gsl_vector_const_ptr(x, 4 * j);
    double complex lz = -q[1] / fs + I * 2.0 * AF_PI * q[0] / n_fft;
    pc[j].z = cexp(lz);
    pc[j].zm = cexp(m * lz);
    pc[j].zm1 = pc[j].zm / pc[j].z;
    pc[j].c = r->ctx.norm * (q[2] + I * q[3]);
  }
}

/* T(a) = (1 - a^m) / (1 - a) = sum_{k < m} a^k and dT/da, from a^m and
 * a^(m - 1). */
static double complex af_trunc_sum(double complex a, double complex am, double complex am1,
                                   double m, double complex *d)
{
  double complex inv = af_recip(1.0 - a);
  double complex t = (1.0 - am) * inv;
  *d = (t - m * am1) * inv;
  return t;
}

/* The truncated model of r->split_poles poles (constants pc) plus the
 * background at bin k, and its derivatives (layout: per pole bin, sigma',
 * Re, Im; then the background's 6). r->phase_um must hold bin k. */
static double complex af_split_eval(const af_response *r, const af_pole_k *pc, const gsl_vector *x,
                                    size_t k, double complex *d)
{
  const af_fit_ctx *f = &r->ctx;
  double n_fft = (double)r->cfg.fft_size, fs = r->cfg.sample_rate_hz, m = r->split_len;
  double complex u = r->phase_u[k], um = r->phase_um[k], um1 = um * conj(u), model = 0.0;
  size_t nb = 4 * r->split_poles;
  for (size_t j = 0; j < r->split_poles; ++j) {
    double complex a = pc[j].z * u, ac = conj(pc[j].z) * u, c = pc[j].c, dt, dtc;
    double complex t = af_trunc_sum(a, pc[j].zm * um, pc[j].zm1 * um1, m, &dt);
    double complex tc = af_trunc_sum(ac, conj(pc[j].zm) * um, conj(pc[j].zm1) * um1, m, &dtc);
    double complex ga = c * dt * a, gac = conj(c) * dtc * ac;
    model += c * t + conj(c) * tc;
    d[4 * j] = (ga - gac) * (I * 2.0 * AF_PI / n_fft);
    d[4 * j + 1] = -(ga + gac) / fs;
    d[4 * j + 2] = f->norm * (t + tc);
    d[4 * j + 3] = f->norm * I * (t - tc);
  }
  double xb = ((double)k - f->center) / f->half, xp = 1.0;
  for (size_t j = 0; j < 3; ++j, xp *= xb) {
    model += xp * (gsl_vector_get(x, nb + 2 * j) + I * gsl_vector_get(x, nb + 2 * j + 1));
    d[nb + 2 * j] = xp;
    d[nb + 2 * j + 1] = I * xp;
  }
  return model;
}

static int af_split_f(const gsl_vector *x, void *params, gsl_vector *f)
{
  const af_response *r = params;
  double complex d[AF_RESPONSE_SPLIT_PARAMS];
  af_pole_k pc[2];
  af_split_poles_k(r, x, pc);
  gsl_vector_set_zero(f);
  for (size_t i = 0; i < r->ctx.count; ++i) {
    size_t k = r->ctx.first + i;
    double complex res = af_split_eval(r, pc, x, k, d) - r->ctx.gain * r->ctx.data[k];
    if (!isfinite(creal(res)) || !isfinite(cimag(res)))
      return GSL_EBADFUNC;
    gsl_vector_set(f, 2 * i, creal(res));
    gsl_vector_set(f, 2 * i + 1, cimag(res));
  }
  return GSL_SUCCESS;
}

static int af_split_df(const gsl_vector *x, void *params, gsl_matrix *jac)
{
  const af_response *r = params;
  double complex d[AF_RESPONSE_SPLIT_PARAMS];
  af_pole_k pc[2];
  size_t p = 4 * r->split_poles + 6;
  af_split_poles_k(r, x, pc);
  gsl_matrix_set_zero(jac);
  for (size_t i = 0; i < r->ctx.count; ++i) {
    (void)af_split_eval(r, pc, x, r->ctx.first + i, d);
    for (size_t j = 0; j < p; ++j) {
      gsl_matrix_set(jac, 2 * i, j, creal(d[j]));
      gsl_matrix_set(jac, 2 * i + 1, j, cimag(d[j]));
    }
  }
  return GSL_SUCCESS;
}

/* Runs the truncated fit of 'poles' poles from 'start' on r->ctx; its
 * residual sum of squares (scaled data) into *rss. 0 if it fails; a driver
 * that stops at its iteration cap or for want of progress leaves a usable
 * point (the caller's acceptance rules judge it). */
static int af_split_run(af_response *r, size_t poles, const gsl_vector *start, double *rss)
{
  size_t b = 0;
  while (b + 1 < AF_RESPONSE_SPLIT_BUCKETS && af_split_bins[b] < r->ctx.count)
    ++b;
  gsl_multifit_nlinear_workspace *w = r->split_fit[poles - 1][b];
  r->split_poles = poles;
  r->split_last = w;
  gsl_multifit_nlinear_fdf fdf = {
      af_split_f, af_split_df, NULL, 2 * af_split_bins[b], 4 * poles + 6, r, 0, 0, 0};
  int info = 0;
  if (gsl_multifit_nlinear_init(start, &fdf, w) != GSL_SUCCESS)
    return 0;
  int st =
      gsl_multifit_nlinear_driver(AF_RESPONSE_SPLIT_MAX_ITER, AF_RESPONSE_SPLIT_XTOL,
                                  AF_RESPONSE_FIT_GTOL, AF_RESPONSE_FIT_FTOL, NULL, NULL, &info, w);
  if (st != GSL_SUCCESS && st != GSL_EMAXITER && st != GSL_ENOPROG)
    return 0;
  const gsl_vector *res = gsl_multifit_nlinear_residual(w);
  double sum = 0.0;
  for (size_t i = 0; i < 2 * r->ctx.count; ++i)
    sum += gsl_vector_get(res, i) * gsl_vector_get(res, i);
  *rss = sum;
  return isfinite(sum);
}

/* Pole j of a fit's parameters p as a mode of the spectrum, spanning the
 * fit's bins; 0 unless it lies in the span and decays. */
static int af_split_pole(const af_response *r, const gsl_vector *p, size_t j, af_peak *out)
{
  double bin = gsl_vector_get(p, 4 * j), sigma = gsl_vector_get(p, 4 * j + 1);
  double sigma_window =
      r->cfg.window == AF_RESPONSE_WINDOW_EXPONENTIAL ? 1.0 / r->cfg.window_time_constant_s : 0.0;
  double first = (double)r->ctx.first, last = first + (double)r->ctx.count - 1.0;
  if (!(bin >= first && bin <= last) || !(sigma > sigma_window))
    return 0;
  out->bin = bin;
  out->sigma_windowed = sigma;
  out->c =
      r->ctx.norm / r->ctx.gain * (gsl_vector_get(p, 4 * j + 2) + I * gsl_vector_get(p, 4 * j + 3));
  out->peak_power = af_mode_peak_power(r, out->c, sigma);
  out->span_lo = first;
  out->span_hi = last;
  return 1;
}

/* The bins of a two-pole fit around k (and the neighbour j, 0 if none):
 * twice the one-pole fit's half-span beyond both (two poles and the
 * background need more bins than one), at most the fit's rows. */
static void af_split_setup(af_response *r, size_t k, size_t j, const af_peak *pk)
{
  size_t half = AF_RESPONSE_SPLIT_SPAN * af_fit_half(r, pk->sigma_windowed);
  size_t a = j != 0 && j < k ? j : k, b = j > k ? j : k;
  /* at most 2 AF_RESPONSE_FIT_MAX_HALF + 1 bins: the rows of the fit (the
   * neighbour search keeps b - a within 4 fit half-spans <= 2 MAX_HALF) */
  size_t cap =
      b - a < 2 * AF_RESPONSE_FIT_MAX_HALF ? (2 * AF_RESPONSE_FIT_MAX_HALF - (b - a)) / 2 : 0;
  if (half > cap)
    half = cap;
  size_t first = a > half ? a - half : 1;
  size_t last = b + half < r->bins - 1 ? b + half : r->bins - 1;
  r->ctx.data = r->spec;
  r->ctx.first = first;
  r->ctx.count = last - first + 1;
  r->ctx.center = 0.5 * (double)(first + last);
  r->ctx.half = 0.5 * (double)(last - first);
  r->ctx.gain = 1.0 / cabs(r->spec[k]);
  r->ctx.norm = 1.0 - exp(-pk->sigma_windowed / r->cfg.sample_rate_hz);
}

/* Starting point of a pole in r->fit2_start (slot j): bin, sigma', and the
 * complex amplitude c scaled as the fit's parameters. */
static void af_split_seed(af_response *r, size_t slot, double bin, double sigma, double complex c)
{
  gsl_vector *x0 = r->fit2_start;
  gsl_vector_set(x0, 4 * slot, bin);
  gsl_vector_set(x0, 4 * slot + 1, sigma);
  gsl_vector_set(x0, 4 * slot + 2, r->ctx.gain * creal(c) / r->ctx.norm);
  gsl_vector_set(x0, 4 * slot + 3, r->ctx.gain * cimag(c) / r->ctx.norm);
}

/* Checks the two poles of the last two-pole fit (rules above); 1 with them
 * in a[0], a[1], lower first. */
static int af_split_accept(const af_response *r, double threshold, af_peak a[2])
{
  af_peak lo, hi;
  const gsl_vector *p = gsl_multifit_nlinear_position(r->split_last);
  if (!af_split_pole(r, p, 0, &lo) || !af_split_pole(r, p, 1, &hi) ||
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
static int af_split(af_response *r, size_t k, const af_peak *pk, double noise, af_peak a[2])
{
  double threshold = noise * pow(10.0, 0.1 * r->cfg.snr_threshold_db);
  size_t j = 0;
  if (!af_find_neighbour(r, k, af_fit_half(r, pk->sigma_windowed), threshold, &j))
    j = 0;
  af_split_setup(r, k, j, pk);
  if (!isfinite(r->ctx.gain) || !(r->ctx.norm > 0.0))
    return 0;
  gsl_vector_set_zero(r->fit2_start);
  af_split_seed(r, 0, pk->bin, pk->sigma_windowed, pk->c);
  gsl_vector_view one = gsl_vector_subvector(r->fit2_start, 0, AF_RESPONSE_FIT_PARAMS);
  double rss1, expected = (double)r->ctx.count * noise * r->ctx.gain * r->ctx.gain;
  if (!af_split_run(r, 1, &one.vector, &rss1))
    return 0;
  if (!(rss1 > AF_RESPONSE_SPLIT_MISFIT * expected))
    return j == 0 && af_split_pole(r, gsl_multifit_nlinear_position(r->split_last), 0, &a[0]) &&
           a[0].bin >= pk->span_lo && a[0].bin <= pk->span_hi;
  double sigma_window =
      r->cfg.window == AF_RESPONSE_WINDOW_EXPONENTIAL ? 1.0 / r->cfg.window_time_constant_s : 0.0;
  double sigma0 = fmax(0.6 * pk->sigma_windowed, sigma_window + 0.1 * pk->sigma_windowed);
  double halfwidth_bins = pk->sigma_windowed / (2.0 * AF_PI * r->bin_hz);
  size_t tries = sizeof af_split_offsets / sizeof af_split_offsets[0];
  /* the neighbour's maximum first (when there is one), then the offsets; the
   * first start that passes is taken */
  for (size_t t = j != 0 ? 0 : 1; t <= tries; ++t) {
    gsl_vector_set_zero(r->fit2_start);
    if (t == 0) {
      af_split_seed(r, 0, pk->bin, pk->sigma_windowed, pk->c);
      af_split_seed(r, 1, (double)j, pk->sigma_windowed,
                    cabs(pk->c) * sqrt(r->power[j] / r->power[k]) * cexp(I * carg(r->spec[j])));
    } else {
      double d = af_split_offsets[t - 1] * halfwidth_bins;
      af_split_seed(r, 0, pk->bin - d, sigma0, 0.5 * pk->c);
      af_split_seed(r, 1, pk->bin + d, sigma0, 0.5 * pk->c);
    }
    double rss2;
    if (af_split_run(r, 2, r->fit2_start, &rss2) && rss2 <= AF_RESPONSE_SPLIT_GAIN * rss1 &&
        rss2 <= AF_RESPONSE_SPLIT_MISFIT * expected && af_split_accept(r, threshold, a))
      return 2;
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
static int af_backfit_one(af_response *r, af_peak *modes, af_mode_k *consts, size_t n, size_t i)
{
  size_t half = af_fit_half(r, modes[i].sigma_windowed);
  double centre = round(modes[i].bin);
  if (!(centre >= 1.0 && centre <= (double)(r->bins - 2)))
    return 0;
  size_t k = (size_t)centre;
  size_t first = k > half ? k - half : 1;
  size_t last = k + half < r->bins - 1 ? k + half : r->bins - 1;
  for (size_t b = first; b <= last; ++b) {
    r->work[b] = r->orig[b];
    for (size_t j = 0; j < n; ++j)
      if (j != i)
        r->work[b] -= af_mode_at(r, &consts[j], b);
  }
  r->ctx.data = r->work;
  r->ctx.first = first;
  r->ctx.count = last - first + 1;
  r->ctx.center = (double)k;
  r->ctx.half = (double)half;
  r->ctx.gain = 1.0 / cabs(r->work[k]);
  r->ctx.norm = 1.0 - exp(-modes[i].sigma_windowed / r->cfg.sample_rate_hz);
  if (!isfinite(r->ctx.gain) || !(r->ctx.norm > 0.0))
    return 0;
  gsl_vector_set_zero(r->fit2_start);
  af_split_seed(r, 0, modes[i].bin, modes[i].sigma_windowed, modes[i].c);
  gsl_vector_view one = gsl_vector_subvector(r->fit2_start, 0, AF_RESPONSE_FIT_PARAMS);
  double rss;
  af_peak pk;
  if (!af_split_run(r, 1, &one.vector, &rss) ||
      !af_split_pole(r, gsl_multifit_nlinear_position(r->split_last), 0, &pk))
    return 0;
  double halfwidth_bins = modes[i].sigma_windowed / (2.0 * AF_PI * r->bin_hz);
  if (!(fabs(pk.bin - modes[i].bin) <= halfwidth_bins))
    return 0;
  modes[i] = pk;
  consts[i] = af_mode_consts(r, &pk);
  return 1;
}

/* Backfits the n listed modes; their records (frequency, decay, amplitude,
 * SNR against noise[i], bounded by the original periodogram) follow. */
static void af_list_backfit(af_response *r, af_response_result *list, af_peak *modes,
                            const double *noise, size_t n)
{
  af_mode_k consts[AF_RESPONSE_MAX_PEAKS];
  if (n < 2)
    return;
  for (size_t i = 0; i < n; ++i)
    consts[i] = af_mode_consts(r, &modes[i]);
  for (int pass = 0; pass < AF_RESPONSE_BACKFIT_PASSES; ++pass)
    for (size_t i = 0; i < n; ++i) {
      if (!af_backfit_one(r, modes, consts, n, i))
        continue;
      size_t k = (size_t)lround(modes[i].bin);
      double top = creal(r->orig[k] * conj(r->orig[k]));
      af_result_fill(r, &modes[i], &list[i]);
      list[i].snr_db = af_snr_db(fmin(modes[i].peak_power, AF_RESPONSE_PEAK_BOUND * top), noise[i]);
    }
}

/* Sorts a[0..n) by frequency (insertion: n <= AF_RESPONSE_MAX_PEAKS). */
static void af_sort_by_frequency(af_response_result *a, size_t n)
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
static size_t af_list_output(af_response_result *list, size_t n, af_response_result *peaks,
                             size_t max_peaks)
{
  while (n > max_peaks) {
    size_t weakest = 0;
    for (size_t j = 1; j < n; ++j)
      if (list[j].snr_db < list[weakest].snr_db)
        weakest = j;
    list[weakest] = list[--n];
  }
  af_sort_by_frequency(list, n);
  memcpy(peaks, list, n * sizeof *list);
  return n;
}

/* Lists the mode res (spectral reading pk) unless the list is full or it
 * repeats a listed mode: within a bin of one, or within two windowed
 * half-widths of one and AF_RESPONSE_SPLIT_MIN_RATIO (-20 dB) below it in
 * peak power, or more than AF_RESPONSE_LIST_RANGE (30 dB) below the
 * strongest listed: what the subtractions leave of the modes
 * taken off (the window's cut of a mode whose decay is fitted 1 % off
 * leaves a ripple ~ -40 dB of it, with peaks every fs / m), not modes. 1 if
 * listed. */
static int af_list_add(af_response_result *list, af_peak *modes, size_t *n,
                       const af_response_result *res, const af_peak *pk, double bin_hz)
{
  double strongest = 0.0;
  for (size_t j = 0; j < *n; ++j)
    strongest = fmax(strongest, modes[j].peak_power);
  if (*n >= AF_RESPONSE_MAX_PEAKS || pk->peak_power < AF_RESPONSE_LIST_RANGE * strongest)
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

af_status af_response_peaks(af_response *r, const float *audio, size_t n, double f_lo_hz,
                            double f_hi_hz, af_response_result *peaks, size_t max_peaks,
                            size_t *n_peaks)
{
  if (r == NULL || audio == NULL || peaks == NULL || n_peaks == NULL || max_peaks == 0 ||
      n < AF_RESPONSE_MIN_SAMPLES)
    return AF_EINVAL;
  if (!(f_lo_hz > 0.0) || !(f_hi_hz > f_lo_hz) || !(f_hi_hz < 0.5 * r->cfg.sample_rate_hz))
    return AF_EINVAL;
  if (n > r->cfg.window_samples)
    return AF_ESIZE;
  double mean = 0.0, energy = 0.0;
  af_status s = af_mean(audio, n, &mean);
  if (s != AF_OK)
    return s;
  *n_peaks = 0;
  size_t start = af_onset(audio, n, mean, r->cfg.onset_fraction);
  af_trend_fit(r, audio, start, n, af_hum_harmonics(r, f_lo_hz));
  af_response_transform(r, audio, n, start, &energy);
  memcpy(r->orig, r->spec, r->bins * sizeof *r->orig);
  af_response_result base, list[AF_RESPONSE_MAX_PEAKS], res;
  af_peak modes[AF_RESPONSE_MAX_PEAKS];
  double noises[AF_RESPONSE_MAX_PEAKS];
  af_result_clear(&base, r->bin_hz);
  base.onset_index = start;
  base.noise_segments = r->noise_segments;
  double band_floor = r->noise_segments > 0 ? NAN : af_band_floor(r);
  size_t k_lo, k_hi;
  af_band_bins(f_lo_hz, f_hi_hz, r->bin_hz, r->bins - 2, &k_lo, &k_hi);
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
  for (size_t k = ph_lo; k <= ph_hi; ++k)
    r->phase_um[k] = cexp(-I * 2.0 * AF_PI * (double)k * r->split_len / (double)r->cfg.fft_size);
  size_t excluded[AF_RESPONSE_LIST_TRIES], n_excluded = 0, kept = 0;
  af_response_result best_rejected = base;
  double rise_snr_db = -INFINITY;
  for (size_t tries = 0; tries < AF_RESPONSE_LIST_TRIES && kept < AF_RESPONSE_MAX_PEAKS; ++tries) {
    double noise = NAN;
    size_t k = af_list_candidate(r, k_lo, k_hi, band_floor, energy, excluded, n_excluded, &noise,
                                 &rise_snr_db);
    if (k == 0)
      break;
    /* the truncated fits from the stage-1 reading (one pole, or two for a
     * blend or a close neighbour); where neither holds, the one-pole
     * refinement of af_response_analyze with its neighbour */
    af_peak seed, pk, two[2];
    res = base;
    int got = af_stage1(r, r->power, r->spec, k, &seed) ? af_split(r, k, &seed, noise, two) : 0;
    if (got == 2) {
      for (size_t j = 0; j < 2; ++j) {
        res = base;
        if (af_list_judge(r, &two[j], noise, f_lo_hz, f_hi_hz, &res) &&
            af_list_add(list, modes, &kept, &res, &two[j], r->bin_hz))
          noises[kept - 1] = noise;
        af_list_subtract(r, &two[j], sub_lo, sub_hi);
      }
    } else {
      int ok;
      if (got == 1) {
        pk = two[0];
        ok = af_list_judge(r, &pk, noise, f_lo_hz, f_hi_hz, &res);
      } else {
        ok = af_list_refine(r, k, noise, f_lo_hz, f_hi_hz, &pk, &res);
      }
      if (!ok || !af_list_add(list, modes, &kept, &res, &pk, r->bin_hz)) {
        if (isnan(best_rejected.frequency_hz) || res.snr_db > best_rejected.snr_db)
          best_rejected = res;
        excluded[n_excluded++] = k;
        continue;
      }
      noises[kept - 1] = noise;
      af_list_subtract(r, &pk, sub_lo, sub_hi);
    }
    n_excluded = 0; /* a maximum refused beside this mode may stand alone now */
  }
  if (kept == 0) {
    if (isnan(best_rejected.frequency_hz))
      best_rejected.snr_db = rise_snr_db;
    peaks[0] = best_rejected;
    return AF_ENODATA;
  }
  af_list_backfit(r, list, modes, noises, kept);
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
  *n_peaks = af_list_output(list, out, peaks, max_peaks);
  return AF_OK;
}
