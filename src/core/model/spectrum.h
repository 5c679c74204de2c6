/* spectrum.h — excitation spectrum of a force pulse, split into lobes.
 *
 * X(f) = sum_k x_k exp(-i 2 pi f t_k) dt  [N s], t_k = k dt: the sampled
 * estimate of the continuous Fourier transform of the pulse (FFTW r2c,
 * zero-padded, plan made once at create time, scaled by dt). Lobes are split
 * at the local minima of |X| (found on the FFT grid, refined by direct
 * evaluation of X(f) at single frequencies), numbered 1, 2, ... from DC as in
 * the paper. Band edges are refined the same way, so they converge far finer
 * than the FFT bin. The same code serves the model's pulse and a measured one.
 *
 * Half-power level (PHYSICS.md 4): the paper's "half of the maximum of the
 * lobe" read on a power spectrum is |X| = max/sqrt 2 (AF_BAND_POWER_HALF,
 * -3 dB); read on an amplitude spectrum it is |X| = max/2
 * (AF_BAND_AMPLITUDE_HALF, -6 dB). The band of a lobe is the interval around
 * the lobe's peak where |X| stays at or above that level, clipped to the lobe.
 */
#ifndef AF_SPECTRUM_H
#define AF_SPECTRUM_H

#include <stddef.h>

#include "status.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum { AF_BAND_POWER_HALF = 0, AF_BAND_AMPLITUDE_HALF } af_band_level;

/* "power-half", "amplitude-half". */
const char *af_band_level_name(af_band_level level);
af_status af_band_level_parse(const char *name, af_band_level *level);
/* The magnitude ratio of a level: 1/sqrt 2 or 1/2. */
double af_band_level_ratio(af_band_level level);

typedef struct {
  size_t max_samples; /* longest pulse accepted [samples] */
  size_t fft_size;    /* zero-padded transform length [samples], >= 2 max_samples */
  size_t max_lobes;   /* lobes located at most */
} af_spectrum_config;

/* max_samples 1024, fft_size 4096, max_lobes 8. */
af_spectrum_config af_spectrum_config_default(void);

typedef struct af_spectrum af_spectrum;

/* Validates cfg, allocates buffers with fftw_alloc_real and makes the plan
 * (FFTW_ESTIMATE). Not thread-safe (FFTW planning). */
af_status af_spectrum_create(const af_spectrum_config *cfg, af_spectrum **out);
void af_spectrum_destroy(af_spectrum *s); /* NULL-safe */

/* Transforms the pulse x[0..n) sampled every dt_s and locates its lobes.
 * The pulse is copied; x need not outlive the call. AF_ESIZE when
 * n > max_samples, AF_EINVAL for dt_s <= 0 or n < 2, AF_ENUMERIC for a
 * non-finite sample. No allocation. */
af_status af_spectrum_execute(af_spectrum *s, const double *x, size_t n, double dt_s);

typedef struct {
  unsigned index;            /* 1-based, 1 = main lobe from DC */
  double start_hz, end_hz;   /* the local minima that bound the lobe (start 0 for lobe 1) */
  double peak_hz;            /* frequency of the lobe's maximum (0 for lobe 1) */
  double peak_magnitude_n_s; /* |X| at peak_hz [N s] */
  double band_low_hz;        /* half-power band at the requested level */
  double band_high_hz;
} af_lobe;

/* Lobes located by the last execute (complete lobes only: both ends found
 * below the Nyquist frequency and the max_lobes limit). */
size_t af_spectrum_lobe_count(const af_spectrum *s);
/* Lobe number index (1-based) with its band at level. AF_ENOLOBE when absent. */
af_status af_spectrum_lobe(const af_spectrum *s, unsigned index, af_band_level level, af_lobe *out);

/* |X(f)| [N s] of the last pulse at any f >= 0, evaluated directly. */
double af_spectrum_magnitude(const af_spectrum *s, double f_hz);
/* Global maximum of |X| [N s] (at DC for a one-signed pulse). */
double af_spectrum_max_magnitude(const af_spectrum *s);
/* 20 log10(|X(f)| / max|X|) [dB]; -inf at an exact null. */
double af_spectrum_level_db(const af_spectrum *s, double f_hz);

#ifdef __cplusplus
}
#endif
#endif
