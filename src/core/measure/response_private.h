/* response_private.h — what the files of the response module share and no
 * caller sees: the object's layout, the constants more than one file reads,
 * the peak record, and the functions one file offers another. Included only
 * by src/core/response*.c; the API is response.h.
 *
 * The files, one job each:
 *  response.c           the object (create, destroy, configuration), the
 *                       result record and af_response_execute;
 *  response_trend.c     DC and mains-hum trend: least-squares fit, removal,
 *                       and its share of a listed mode;
 *  response_transform.c onset, window, zero-pad, the FFTW r2c transform;
 *  response_noise.c     the noise floor: the reference, the band's median;
 *  response_peaks.c     peak finding and the closed-form stage-1 reading;
 *  response_mode.c      a mode's spectrum through the window (exact sums);
 *  response_fit.c       the complex fits' bins, seeds and poles, stage 2 and
 *                       the neighbour's round;
 *  response_lm.c        their Levenberg-Marquardt solver (caps, statuses);
 *  response_vp.c        the fits' residual pass by variable projection;
 *  response_split.c     the peak list's two-pole split and backfit;
 *  response_list.c      af_response_execute_peaks: the list of a band's modes.
 *
 * Static helpers carry no prefix; the functions shared here are
 * af_response_*, as they are symbols of the library. */
#ifndef AF_RESPONSE_PRIVATE_H
#define AF_RESPONSE_PRIVATE_H

#include "response.h"

/* complex.h before fftw3.h: fftw_complex is then the C99 double complex. */
#include <complex.h>
#include <fftw3.h>
#include <gsl/gsl_matrix.h>
#include <gsl/gsl_vector.h>

#include "fft_plan.h"
#include "numeric.h"

#define AF_PI 3.14159265358979323846
/* Shortest window or noise segment accepted [samples]: below this neither a
 * mean nor a spectral peak means anything. */
#define AF_RESPONSE_MIN_SAMPLES 8
/* At most this many bins each side of the peak enter a fit (a broad peak on
 * a fine grid needs no more). */
#define AF_RESPONSE_FIT_MAX_HALF 32
/* Parameters of the complex fit: f0 [bins], sigma' [1/s], the mode's complex
 * amplitude (2) and a complex quadratic background (6). */
#define AF_RESPONSE_FIT_PARAMS 10
#define AF_RESPONSE_FIT_ROWS (2 * (2 * AF_RESPONSE_FIT_MAX_HALF + 1))
/* The peak list's two-pole fit: two modes (4 each) and the background (6). */
#define AF_RESPONSE_SPLIT_PARAMS 14
/* Hum removal: at most this many harmonics (response_trend.c). */
#define AF_RESPONSE_MAX_HUM_HARMONICS 8
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
/* The weaker pole's peak power is at least this fraction (-20 dB) of the
 * stronger's: below it, it is a misfit of the stronger (the fade-in, a
 * neighbour's skirt the quadratic background does not follow) and would not
 * move the stronger's frequency anyway (two-pole split, peak list). */
#define AF_RESPONSE_SPLIT_MIN_RATIO 0.01

/* What a fit works on: a complex spectrum, the bins used, the scales. */
typedef struct {
  const double complex *data; /* spectrum fitted: the transform, or it less a neighbour */
  size_t first, count;        /* bins fitted: first .. first + count - 1 */
  double center;              /* bin of the grid peak */
  double half;                /* bins per unit of the background's abscissa */
  double gain;                /* 1 / |X| at the grid peak: data of order 1 */
  double norm;                /* 1 - r of the seed: amplitude of order 1 */
  double cost_floor;          /* a step lowering the cost by at most this ends the fit
                                 (af_response_fit_noise); 0 = only the solver's tolerances */
  double cost_stop;           /* a point of cost at most this ends the fit: its caller asks
                                 only whether the minimum lies below; 0 = none */
} af_fit_ctx;

/* An fft input buffer (fft_size samples, FFTW's alignment) and how far
 * its last transform wrote: samples[written..fft_size) hold zeros. */
typedef struct {
  double *samples;
  size_t written;
} af_response_input;

struct af_response {
  af_response_config cfg;
  size_t bins;                    /* fft_size / 2 + 1 */
  double bin_hz;                  /* sample_rate_hz / fft_size [Hz] */
  af_response_input in;           /* the analysed window's fft input */
  af_response_input noise_in;     /* the noise reference's: its own, so that the padding of
                                     one is not rewritten after the other's transform */
  double complex *spec;           /* fft output, bins values */
  af_fft_r2c plan;                /* r2c, shared by the process (fft_plan.h) */
  double *window;                 /* window_samples weights */
  double *window_energy;          /* window_energy[m] = sum_{k < m} window[k]^2, summed in
                                     order: the energy of an m-sample transform */
  size_t fade_samples;            /* length of the fade-in [samples] */
  double *fade_rest;              /* 1 - the fade-in's weight, fade_samples of them (window
                                     samples allocated: the fade-in is at most a quarter) */
  double *power;                  /* periodogram |X_k|^2 of the last transform */
  double *noise_ref;              /* mean reference periodogram per unit window energy */
  double *scratch;                /* median workspace (noise band) */
  double complex *work;           /* spectrum less a fitted mode (near the peak only) */
  double *work_power;             /* |work|^2 */
  double complex *orig;           /* the transform before the peak list took modes off */
  size_t orig_lo, orig_hi;        /* the bins of orig the last peak list copied */
  double complex *phase_u;        /* u_k = exp(-i 2 pi k / N), every bin */
  double complex *phase_ul;       /* u_k^L, L the fade-in length */
  double complex *phase_um;       /* u_k^m, m the analysed length of the peak list's call */
  double split_len;               /* that m [samples] */
  double complex fade_e, fade_eh; /* exp(i theta), exp(i theta / 2), theta = pi / L */
  size_t noise_segments;          /* segments averaged into noise_ref */
  size_t noise_bins;              /* bins of noise_ref and noise_cum (+ 1) that hold it */
  double fit_start[AF_RESPONSE_SPLIT_PARAMS]; /* a fit's starting point */
  double split_x[AF_RESPONSE_SPLIT_PARAMS];   /* the last truncated fit's solution */
  size_t split_poles;                    /* model of the fit under way: 0 the pole pair of stage 2,
                                            1 or 2 the poles of a truncated fit */
  af_response_fit_status split_status;   /* how the last truncated fit ended (response.h) */
  af_fit_ctx ctx;                        /* the fit under way */
  gsl_matrix *trend_gram;                /* DC + hum least squares, MAX_TERMS square */
  gsl_matrix *noise_gram;                /* the same for the noise reference, factored */
  size_t noise_gram_m, noise_gram_terms; /* its samples and terms; terms 0: none */
  gsl_vector *trend_rhs, *trend_coef;    /* its right-hand side and solution */
  size_t trend_terms;                    /* terms of the last trend fit: 1 + 2 harmonics */
  size_t hum_period;                     /* af_response_hum_period; 0 = none */
  double *trend_fold;                    /* one hum period: folded samples, then the trend */
  double *trend_table;                   /* the basis over one hum period (NULL without one):
                                            row j holds sample j's 1 + 2 hum_harmonics terms */
  double *trend_cols;                    /* the same by term: column i's hum_period values in a
                                            row of its own (contiguous loops over the samples) */
  double *noise_cum;               /* noise_ref's running sum: cum[k] = sum_{j < k}, bins + 1 */
  size_t share_terms;              /* the trend's terms as windowed poles: the DC and
                                      hum_harmonics (with a hum), 0 without the exponential
                                      window */
  const double complex *share_g;   /* bin by bin, per term and side (its pole, then the
                                      conjugate): 1 / (1 - z u) less the fade-in's part */
  const double complex *share_p;   /*   and 1 / (1 - z u) (af_response_add_trend_share);
                                      both the process's (memo.h), or in share_own */
  double complex *share_own;       /* the tables when the process could not keep them */
  af_response_fit_stats fit_stats; /* the fits run, by status (response.h) */
};

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

/* A listed mode as its exact spectrum needs it: c and the powers of z. */
typedef struct {
  double complex c, z, zm, zl; /* z^m (m = r->split_len), z^L (the fade-in) */
} af_mode_k;

/* af_v2d (numeric.h): a loop over two bins at once written as the scalar
 * complex arithmetic expands (GCC under -fcx-limited-range: (a + ib)(c + id)
 * = (ac - bd) + i(ad + bc), a real operand acting on each part alone) gives
 * its doubles bit for bit. */
/* Complex values of two bins, real and imaginary parts apart. */
typedef struct {
  af_v2d re, im;
} af_cv2;

/* The complex re + i im with its parts set, not computed (C11: a complex is
 * laid out as the array of its two parts); glibc's CMPLX, which does the
 * same, is defined for GCC alone. */
static inline double complex complex_of(double re, double im)
{
  union {
    double parts[2];
    double complex z;
  } u = {{re, im}};
  return u.z;
}

/* a b as the scalar complex product expands: (ac - bd) + i(ad + bc). */
static inline af_cv2 cv2_mul(af_cv2 a, af_cv2 b)
{
  af_cv2 p = {a.re * b.re - a.im * b.im, a.re * b.im + a.im * b.re};
  return p;
}

/* z in both lanes. */
static inline af_cv2 cv2_splat(double complex z)
{
  af_cv2 p = {{creal(z), creal(z)}, {cimag(z), cimag(z)}};
  return p;
}

/* t[0], t[1] apart into real and imaginary parts. */
static inline af_cv2 cv2_load(const double complex *t)
{
  af_cv2 p = {{creal(t[0]), creal(t[1])}, {cimag(t[0]), cimag(t[1])}};
  return p;
}

/* 1 / b without the C library's careful complex division (b is never near
 * 0 or overflow here: 1 - a with |a| < 1 bounded away from 1 by the decay).
 * Inline: it sits in the innermost loops of the fits and the subtractions. */
static inline double complex complex_recip(double complex b)
{
  return conj(b) / (creal(b) * creal(b) + cimag(b) * cimag(b));
}

/* ---- response.c: the result record and the analysis's first steps ---- */
/* Checks the band and the length, then onset, trend, transform of
 * audio[0..n): the analysed start into *start, the window energy into
 * *energy. AF_EINVAL, AF_ESIZE, AF_ENUMERIC as af_response_execute. */
af_status af_response_begin(af_response *r, const float *audio, size_t n, double f_lo_hz,
                            double f_hi_hz, size_t *start, double *energy);
/* 10 log10(peak / noise) [dB]; +-inf for digital silence. */
double af_response_snr_db(double peak_power, double noise_power);
void af_response_result_clear(af_response_result *out, double bin_hz);
/* Frequency, decay, amplitude of the refined peak into out. */
void af_response_result_fill(const af_response *r, const af_peak *pk, af_response_result *out);
/* Refines the local maximum k (af_response_refine, noise: power per bin)
 * and reads it into out, its SNR from the mode's own peak power bounded by
 * AF_RESPONSE_PEAK_BOUND times the periodogram (the top bin's power when the
 * complex fit failed); 1 if the complex fit held. */
int af_response_read_peak(af_response *r, size_t k, double noise, af_peak *pk,
                          af_response_result *out);

/* ---- response_trend.c ---- */
/* Harmonics of the hum to remove for a range starting at f_lo_hz. */
size_t af_response_hum_harmonics(const af_response *r, double f_lo_hz);
/* Least-squares DC + harmonics of x[start..n) into r->trend_coef (the mean
 * alone when the normal equations are singular); 'noise': the noise
 * reference's fit, on its own normal matrix (r->noise_gram, kept between
 * calls), else on r->trend_gram (af_response_add_trend_share reads its
 * factor). AF_ENUMERIC, r's trend untouched, for a non-finite sample. */
af_status af_response_trend_fit(af_response *r, const float *x, size_t start, size_t n,
                                size_t harmonics, int noise);
/* dst[k] = (x[start + k] less the fitted trend) w[k], k < m: the window's
 * product in the same pass (the same doubles as a pass of its own after). */
void af_response_trend_remove(af_response *r, const float *x, size_t start, size_t m,
                              const double *w, double *dst);
/* The hum's period [samples] when whole and at most window_samples (48 kHz
 * and 50 or 60 Hz: 960, 800), else 0: the trend then repeats exactly. */
size_t af_response_hum_period(const af_response_config *c);
/* Fills r->trend_table (made at create when r->hum_period > 0). */
void af_response_fill_trend_table(af_response *r);
/* The trend's windowed poles (share_terms of them) for af_response_add_trend_share. */
size_t af_response_share_terms(const af_response_config *c);
/* Points r->share_g and r->share_p at the process's tables for r's
 * configuration (or fills r->share_own); AF_ENOMEM. At create, when
 * share_terms > 0. */
af_status af_response_fill_share_tables(af_response *r);
/* Adds to r->spec over [lo, hi] what the last trend fit (over the
 * r->split_len analysed samples) took of the mode pk with the trend, as the
 * window holds it: its DC and hum terms, which the transform lacks of the
 * mode. r->phase_um must hold [lo, hi]. Nothing without share tables. */
void af_response_add_trend_share(af_response *r, const af_peak *pk, size_t lo, size_t hi);

/* ---- response_transform.c ---- */
/* u_k^power, u_k = exp(-2 pi i k / fft_size): the phase of bin k after
 * power samples (the phase tables' entries). */
double complex af_response_phase(size_t k, size_t fft_size, double power);
/* exp(i theta) and exp(i theta / 2), theta = pi / L, of a fade-in of L
 * samples (theta 0 without one): the constants of af_response_fade_part. */
void af_response_fade_phases(size_t fade_samples, double complex *e, double complex *eh);
/* Mean of x[0..n) and its smallest and largest sample into *lo, *hi (n > 0);
 * AF_ENUMERIC for a non-finite sample. */
af_status af_response_mean_range(const float *x, size_t n, double *mean, float *lo, float *hi);
/* First sample whose |x - mean| reaches fraction of the largest (the
 * samples' range [lo, hi], from af_response_mean_range). */
size_t af_response_onset(const float *x, size_t n, double mean, double fraction, float lo,
                         float hi);
/* The raised-cosine fade-in's weight at sample k of length samples (1 beyond). */
double af_response_fade(size_t k, size_t length);
/* Fills r->window and the phase factors (at create). */
void af_response_fill_window(af_response *r);
void af_response_fill_phases(af_response *r);
/* Bins of [lo_hz, hi_hz] on a grid of bin_hz, clipped to 1..last. */
void af_response_band_bins(double lo_hz, double hi_hz, double bin_hz, size_t last, size_t *k_lo,
                           size_t *k_hi);
/* Periodogram of x[start..n), less its fitted trend, into r->power, bins
 * below 'bins' (at most r->bins), through the fft input 'in'. */
void af_response_transform(af_response *r, af_response_input *in, const float *x, size_t n,
                           size_t start, size_t bins, double *window_energy);

/* ---- response_noise.c ---- */
/* Mean noise power per bin of the window's own noise band. */
double af_response_band_floor(af_response *r);
/* Noise power per bin of the last transform over [f_lo, f_hi] (reference or
 * band); the reference's segments into *segments. */
double af_response_noise_power(af_response *r, double f_lo_hz, double f_hi_hz, double energy,
                               size_t *segments);
/* The peak list's floor at f_hz (reference near f, else band_floor). */
double af_response_list_noise(const af_response *r, double f_hz, double band_floor, double energy);

/* ---- response_peaks.c ---- */
/* The floors a maximum at k rises from on its left and right. */
void af_response_side_floors(const af_response *r, size_t k, double *left, double *right);
/* Strongest prominent peak with its top in [f_lo, f_hi]; 0 if none. */
size_t af_response_find_peak(const af_response *r, double f_lo_hz, double f_hi_hz,
                             double *best_rise);
/* Strongest prominent maximum j != k within two fit half-widths of k. */
int af_response_find_neighbour(const af_response *r, size_t k, size_t half, double min_power,
                               size_t *j_out);
/* Stage 1 (the 1/P parabola) at the local maximum k of p (spectrum x). */
int af_response_stage1(const af_response *r, const double *p, const double complex *x, size_t k,
                       af_peak *out);
/* Fallback when stage 1 fails: a three-point parabola on log P. */
void af_response_log_parabola(const af_response *r, size_t k, af_peak *out);

/* ---- response_mode.c ---- */
/* The pole z = exp(-sigma' / fs + i 2 pi bin / N) of a mode at bin (fractional). */
double complex af_response_pole(const af_response *r, double bin, double sigma_windowed);
/* c / (1 - z u) + conj(c) / (1 - conj(z) u) at bin k. */
double complex af_response_pole_pair(const af_response *r, double complex z, double complex c,
                                     size_t k);
/* The fade-in's part F(a) of sum_k a^k (al = a^L, inv_1a = 1 / (1 - a);
 * e, eh: exp(i pi / L), exp(i pi / 2L)); 0 without a fade-in. */
double complex af_response_fade_part(size_t fade_samples, double complex e, double complex eh,
                                     double complex a, double complex al, double complex inv_1a);
/* |X(f0)|^2 of the mode alone through the window, fade-in included. */
double af_response_mode_peak_power(const af_response *r, double complex c, double sigma_windowed);
af_mode_k af_response_mode_consts(const af_response *r, const af_peak *pk);
/* The mode q as the window holds it over the m analysed samples, at bin i. */
double complex af_response_mode_at(const af_response *r, const af_mode_k *q, size_t i);
/* r->spec[i] -= af_response_mode_at(r, q, i) and r->power[i] = |r->spec[i]|^2
 * over [lo, hi]: the same doubles, two bins at a time. */
void af_response_mode_subtract(af_response *r, const af_mode_k *q, size_t lo, size_t hi);
/* The same by the fade-in's three geometric sums (af_response_fade_part),
 * which af_response_mode_at rearranges over one denominator. */
double complex af_response_mode_at_sums(const af_response *r, const af_mode_k *q, size_t i);

/* ---- response_fit.c ---- */
/* Half-width of the fit around a peak of this windowed decay rate [bins]. */
size_t af_response_fit_half(const af_response *r, double sigma_windowed);
/* The bins half each side of k, clipped to 1 .. bins - 1. */
void af_response_fit_around(const af_response *r, size_t k, size_t half, size_t *first,
                            size_t *last);
/* r->ctx over data[first..last]: the background's abscissa centred on
 * center [bins] in units of half [bins], the data scaled by 1 / |data[k]|,
 * the amplitudes by 1 - exp(-sigma_windowed / fs). 0 if a scale is unusable
 * (a zero bin, no decay). */
int af_response_fit_bins(af_response *r, const double complex *data, size_t first, size_t last,
                         double center, double half, size_t k, double sigma_windowed);
/* Lets the fit on r->ctx (set up by af_response_fit_bins) stop within a small
 * fraction of its poles' standard errors under noise of power 'noise' per bin
 * (response_fit.c); 0 = only the solver's tolerances. The one-pole fits
 * (stage 2, the peak list's truncated fits), not the two-pole ones. */
void af_response_fit_noise(af_response *r, double noise);
/* Starting point of pole 'slot' in x0, scaled as the fit's parameters. */
void af_response_fit_seed(const af_response *r, double *x0, size_t slot, double bin, double sigma,
                          double complex c);
/* The truncated fit of 'poles' poles from start on r->ctx; rss into *rss,
 * how it ended into r->split_status. */
int af_response_split_run(af_response *r, size_t poles, const double *start, double *rss);
/* Pole j of a truncated fit's parameters p; 0 unless in the span and decaying. */
int af_response_split_pole(const af_response *r, const double *p, size_t j, af_peak *out);
/* The mode at the local maximum k, refined as far as the data allow (noise:
 * power per bin there; a neighbour must clear snr_threshold_db over it). */
int af_response_refine(af_response *r, size_t k, double noise, af_peak *out);

/* ---- response_vp.c ---- */
/* The cost (residual sum of squares) of the model under way at theta (each
 * pole's f0 [bins] and sigma' [1/s]) with its linear parameters solved
 * (into beta: each pole's scaled amplitude, then the background's 6) and,
 * when a is not NULL, the projected normal equations a = J^T J (p x p, p =
 * 2 per pole, full, row-major) and g = J^T f (variable projection); 0 if a
 * value is not finite or the linear least squares is singular. */
int af_response_fit_eval(const af_response *r, const double *theta, double *cost, double *a,
                         double *g, double *beta);

/* ---- response_lm.c ---- */
/* Levenberg-Marquardt on r->ctx from x (params nonlinear values; the
 * solution into x, the linear parameters solved there into beta), at most
 * max_iter steps; the final cost (residual sum of squares) into *cost, the
 * steps taken into *iterations; the status says how it ended. */
af_response_fit_status af_response_lm(af_response *r, size_t params, double *x, double *beta,
                                      size_t max_iter, double xtol, double gtol, double ftol,
                                      double *cost, size_t *iterations);

/* ---- response_split.c ---- */
/* The truncated reading of the peak at k (one or two poles; 0 none). */
int af_response_split(af_response *r, size_t k, const af_peak *pk, double noise, af_peak a[2]);
/* Backfits the n listed modes on r->orig less the others. */
void af_response_list_backfit(af_response *r, af_response_result *list, af_peak *modes,
                              const double *noise, size_t n);

#endif
