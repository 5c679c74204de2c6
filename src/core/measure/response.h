/* response.h — the apple's 0S2 resonance from the microphone after a strike.
 *
 * One analysis per strike. The caller cuts the window from the stream at the
 * strike (by sample index) and passes it with the model's 0S2 range
 * [f_lo, f_hi] for this apple. The module
 *  1. starts the analysis at the ringing's onset (the first sample reaching
 *     onset_fraction of the window's largest |x|): the stamp jitter of a few
 *     ms then costs nothing;
 *  2. fits and subtracts DC and the mains hum (hum_hz and its harmonics below
 *     0.8 f_lo) by least squares over the analysed samples: a steady
 *     component cut by the window's start leaves a transient whose spectrum
 *     has skirts and humps across the range;
 *  3. windows, zero-pads to fft_size and transforms (FFTW r2c, planned once);
 *  4. picks the strongest PEAK with its top inside [f_lo, f_hi] — a local
 *     maximum standing at least 6 dB above its local floor — not the global
 *     maximum: other modes of the apple, the support or the hammer may be
 *     louder, and a ripple on their skirts is no peak;
 *  5. refines it in two stages (below) and reports frequency, Q, initial
 *     amplitude and SNR.
 *
 * Window (default exponential, w_k = exp(-k dt / tau_w), after a 1 ms
 * raised-cosine fade-in): the ringing is a sum of decaying exponentials, and
 * the exponential is the one window whose product with a decaying
 * exponential is again one, wherever the onset falls: each mode stays an
 * exact pole c / (1 - z u) in the spectrum, its decay rate the mode's plus
 * 1/tau_w, corrected exactly. It weights the samples as the signal does (a
 * matched filter when tau_w is the mode's decay time) and ends near zero (no
 * truncation leakage). The fade-in removes the step at the first sample,
 * whose 1/f skirt would lift the noise band. A Hann window is not offered: its
 * rising half discards the strongest part of an impact response, and its
 * shape on a decaying signal depends on where the onset falls. The
 * rectangular window (none) is exact only for ringing that dies (~40 dB)
 * within the window.
 *
 * Refinement:
 *  - stage 1: near its peak 1/|X|^2 of a windowed damped sinusoid is a
 *    parabola in frequency; a weighted least-squares parabola through the
 *    zero-padded bins above half the peak gives f0, the windowed decay rate
 *    and the peak power in closed form. It is biased by the mode's own
 *    negative-frequency image and by other modes' skirts (they add to the
 *    complex spectrum, not to the power) and only seeds
 *  - stage 2: a Levenberg-Marquardt fit (response_lm.c) of the complex
 *    bins within 2.5 half-widths to c / (1 - z u) + conj(c) / (1 - conj(z) u)
 *    plus a complex quadratic background, z = exp((-sigma' + i 2 pi f0) dt):
 *    the pole pair is exact; a late onset, the fade-in and the far modes'
 *    skirts are smooth across the peak and go into the background. A
 *    prominent neighbour close enough to reach into the fit (a weak mode in
 *    the range, a split 0S2) is fitted in turn and subtracted, and the 0S2
 *    refitted. A fit that fails or leaves the peak's top is no damped mode:
 *    AF_ENODATA.
 *
 * Definitions:
 *  - decay rate sigma [1/s]: the amplitude envelope is A exp(-sigma t);
 *    decay_time_s = 1/sigma; Q = pi f0 / sigma = pi f0 tau (= f0 over the
 *    -3 dB bandwidth of the unwindowed mode).
 *  - SNR [dB] = 10 log10(peak power / noise power per bin) on the windowed,
 *    zero-padded periodogram. Peak power: the fitted mode's own |X(f0)|^2
 *    through the window (other modes' skirts excluded), at most 1.5 dB above
 *    the periodogram there (a narrow pole fitted to a noise bump extrapolates
 *    above the data). Noise power per bin: the median periodogram level over a
 *    noise band divided by ln 2 (a noise bin is exponentially distributed,
 *    median = ln 2 x mean): the mean noise power per bin, robust against the
 *    peaks in the band. The band is, in order of preference, [f_lo, f_hi] of
 *    the mean periodogram of noise-only segments given to
 *    af_response_add_noise (e.g. the audio between strikes: right for
 *    coloured noise; one segment scatters by ~1.5 dB, m segments by
 *    1.5/sqrt(m) dB), else [noise_band_lo_hz, noise_band_hi_hz] of the
 *    analysed window itself (right for white noise; noise that rises towards
 *    low frequencies makes it overstate the SNR).
 *  - amplitude [audio units]: initial amplitude A of the mode's ringing at the
 *    first analysed sample (onset_index).
 *
 * Several modes at once: af_response_execute_peaks lists every damped mode of a band
 * from one analysis (subtracting each before seeking the next, with the
 * share of it the trend fit took; two poles for a blend), for modes.h to
 * decide which is the 0S2.
 *
 * From frequency to firmness (lamb.h, not repeated here): with the
 * apple's mass m [kg], the stiffness factor is
 * S = af_lamb_stiffness_factor(frequency_hz, m) = f^2 m^(2/3), and the
 * dynamic modulus E = af_lamb_modulus_pa(xi, frequency_hz, nu, rho, m)
 * with xi from af_lamb_root(nu), computed once per nu. As S and E go
 * as f^2, a relative frequency error e makes 2e on both.
 */
#ifndef AF_RESPONSE_H
#define AF_RESPONSE_H

#include <stddef.h>

#include "stage.h"
#include "status.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum {
  AF_RESPONSE_WINDOW_EXPONENTIAL = 0, /* w_k = exp(-k dt / tau_w), the default */
  AF_RESPONSE_WINDOW_RECTANGULAR      /* no window: only for ringing that dies in the window */
} af_response_window;

/* "exponential", "rectangular". */
const char *af_response_window_name(af_response_window window);
/* AF_EINVAL for NULL or an unknown name. */
af_status af_response_window_parse(const char *name, af_response_window *window);

typedef struct {
  double sample_rate_hz;         /* microphone sampling rate [Hz] */
  size_t window_samples;         /* longest analysed window [samples] */
  size_t fft_size;               /* zero-padded transform length, power of two >= window_samples */
  af_response_window window;     /* window shape */
  double window_time_constant_s; /* tau_w of the exponential window [s], > 0 */
  double fade_in_s;              /* raised-cosine fade-in at the window start [s], >= 0 */
  double hum_hz;                 /* mains frequency removed with its harmonics [Hz]; 0 = off */
  size_t hum_harmonics;          /* harmonics removed, 0..8 (only those <= 0.8 f_lo) */
  double onset_fraction;         /* analysis starts where |x| first reaches this fraction of
                                    its maximum, in [0, 1); 0 = at the first sample */
  double snr_threshold_db;       /* a peak below this SNR is not a resonance [dB] */
  double noise_band_lo_hz;       /* band of the window's own noise floor, used when no */
  double noise_band_hi_hz;       /*   reference is set [Hz]; clipped to Nyquist */
  const af_stage_hook *stages;   /* times the transform (stage.h); NULL = not timed */
} af_response_config;

/* 48 kHz; 4096-sample window (85 ms, four 1024-sample chunks), fft_size 8192
 * (5.9 Hz bins); exponential window, tau_w 20 ms (-37 dB at the window's end;
 * a shorter tau_w widens the peaks until a weak mode 1.3 f0 away merges with
 * a 300 Hz 0S2: with 2048 samples and 10 ms, errors reached 30 % and 1 % of
 * the test strikes were refused; 3072 and 15 ms still held); fade-in 1 ms;
 * hum measure_hum_hz with measure_hum_harmonics; onset at 25 % of the
 * largest |x|; SNR threshold measure_snr_threshold_db (noise-only windows:
 * the best candidate of a 300-1300 Hz range passes 12 dB in ~0.1 %, the
 * shipped threshold in none of 2e4; a strike at a 10 dB synthesis SNR reads
 * ~25 dB); noise band measure_noise_band_low_hz to _high_hz (above the
 * apple's modes, below a microphone's roll-off). Those rows' defaults come
 * from the parameter table (af_defaults.h). */
af_response_config af_response_config_default(void);

/* Fewest FFT bins the noise band must hold for its median to be a floor. */
#define AF_RESPONSE_MIN_NOISE_BINS 8

/* The FFT bins of c's noise band [noise_band_lo_hz, noise_band_hi_hz], clipped
 * to the Nyquist frequency, on c's grid (sample_rate_hz / fft_size); 0 when
 * empty. af_response_create refuses fewer than AF_RESPONSE_MIN_NOISE_BINS. */
size_t af_response_noise_band_bins(const af_response_config *c);

typedef struct af_response af_response;

/* Validates cfg (AF_EINVAL: sample_rate_hz or window_time_constant_s not
 * finite and > 0; window_samples < 8; fft_size not a power of two >=
 * window_samples; unknown window; fade-in < 0 or over a quarter of the
 * window; hum_hz < 0 or >= Nyquist; hum_harmonics > 8; onset_fraction outside
 * [0, 1); snr_threshold_db not finite; noise band not 0 <= lo < hi, lo >=
 * Nyquist or under 8 bins), then takes every buffer (fftw_alloc_*, the trend's
 * least-squares workspace) and takes the process's FFTW plan (fft_plan.h).
 * AF_ENOMEM if allocation or planning fails; nothing leaks, *out is NULL on
 * any failure. Not thread-safe (FFTW planning). */
af_status af_response_create(const af_response_config *cfg, af_response **out);
void af_response_destroy(af_response *r); /* NULL-safe */

/* The configuration r was created with; NULL for NULL. */
const af_response_config *af_response_get_config(const af_response *r);

/* Adds the noise-only segment noise[0..n) (e.g. audio between strikes; DC and
 * every configured hum harmonic removed, same window, normalised by its
 * window energy, so n may differ from the analysed length) to the reference:
 * later analyses take their noise floor from the mean of the segments added
 * since the last clear, over their own [f_lo, f_hi]. AF_EINVAL for a NULL
 * pointer or n < 8, AF_ESIZE for n > window_samples, AF_ENUMERIC for a
 * non-finite sample (the reference is then unchanged). No allocation. */
af_status af_response_add_noise(af_response *r, const float *noise, size_t n);
/* The same for analyses whose band ends at or below f_max_hz (f_hi of
 * af_response_execute, band_hi of af_response_execute_peaks): the same
 * floors at a fraction of the cost, as only the bins those read are
 * transformed into the reference. A later analysis above f_max_hz takes the
 * floor of the highest bins held. AF_EINVAL also for f_max_hz <= 0 or NaN;
 * INFINITY: every bin (af_response_add_noise). */
af_status af_response_add_noise_below(af_response *r, const float *noise, size_t n,
                                      double f_max_hz);
/* Forgets the reference: the noise floor comes from the noise band again.
 * NULL-safe. */
void af_response_clear_noise(af_response *r);

typedef struct {
  double frequency_hz;   /* 0S2 frequency, sub-bin [Hz]; NaN if no peak in range */
  double q;              /* quality factor pi f0 / sigma; +inf if no decay is measurable */
  double decay_time_s;   /* amplitude decay time 1/sigma [s]; +inf likewise */
  double amplitude;      /* initial amplitude at onset_index [audio units] */
  double snr_db;         /* peak power over noise power per bin [dB] */
  double bin_width_hz;   /* bin of the zero-padded transform [Hz] */
  size_t noise_segments; /* reference segments behind the noise floor; 0 = noise band */
  size_t onset_index;    /* first analysed sample of the window (the detected onset) */
} af_response_result;

/* Analyses audio[0..n), n <= window_samples samples cut from the stream at the
 * strike, for the 0S2 peak in [f_lo_hz, f_hi_hz]. Shorter windows are
 * zero-padded. Fills *out and returns
 *  AF_OK       a damped mode in range clears snr_threshold_db;
 *  AF_ENODATA  none does: *out holds the best candidate and its SNR, or, when
 *              the range holds no peak at all (frequency NaN), the SNR of the
 *              largest rise of a local maximum above its floor (-inf for
 *              digital silence); also when the candidate does not fit a damped
 *              mode (frequency, SNR from stage 1 / the periodogram) or its
 *              refined frequency leaves the range;
 *  AF_EINVAL   NULL pointer, n < 8, or not 0 < f_lo_hz < f_hi_hz < Nyquist
 *              (*out untouched);
 *  AF_ESIZE    n > window_samples; AF_ENUMERIC for a non-finite sample.
 * No allocation. r holds the buffers: one analysis at a time per r. */
af_status af_response_execute(af_response *r, const float *audio, size_t n, double f_lo_hz,
                              double f_hi_hz, af_response_result *out);

/* Most peaks af_response_execute_peaks lists per call: the apple's few audible
 * modes (0S2, 0S3, 0S4/1S2), the support's and the hammer's, with room to
 * spare. */
#define AF_RESPONSE_MAX_PEAKS 16

/* Lists the damped modes of audio[0..n) in [f_lo_hz, f_hi_hz] from ONE
 * analysis (onset, DC and hum, window, transform as af_response_execute;
 * the hum harmonics removed are those <= 0.8 f_lo_hz): for mode
 * identification (modes.h), over a band wider than the 0S2 range
 * (af_modes_list_band). The modes are taken strongest first, each read and
 * then subtracted from the spectrum before the next is sought:
 *  - candidate: the strongest local maximum with its top bin in the band
 *    standing 6 dB above its floor on one side and 3 dB on the other (two
 *    modes ~10 % apart fill the valley between them to 4-5 dB below either,
 *    which af_response_execute's 6 dB on both sides refuses; the ripples and
 *    humps that rule keeps out belong to a stronger mode, already
 *    subtracted), whose top bin could still clear snr_threshold_db and,
 *    once a mode is listed, stand within 30 dB of the strongest listed (a
 *    top bin raised by the 1.5 dB a fitted peak may stand above it);
 *  - reading: a fit of one pole (plus a quadratic background) whose model
 *    includes the window's end; if it leaves a misfit above 4x the noise's,
 *    two poles (a split 0S2, the 0T2 or a support mode a few per cent away:
 *    one peak for two modes, which one pole reads between them), accepted
 *    when they cut the residual 10x, to the noise, both decay, both clear
 *    the threshold and the weaker is within 20 dB of the stronger (up to
 *    three starts, the next only when a fit was cut short by its cap); where
 *    neither holds, af_response_execute's refinement (one neighbour);
 *  - listed when it decays (Q finite), clears snr_threshold_db, lies in the
 *    band, repeats no listed mode (within a bin, or within two half-widths
 *    and 20 dB below it: what a subtraction leaves), and stands within
 *    30 dB of the strongest listed. A candidate that fails is NOT listed
 *    (the best of them is reported when nothing is, below) and the next
 *    maximum is tried; one listed is subtracted exactly as the window holds
 *    it (the window's cut and fade-in included: a bare pole would leave a
 *    ripple of false peaks every fs / n and a raised floor);
 *  - finally every listed mode is read again on the spectrum less all the
 *    others (two passes): a comparable mode 10-30 % away otherwise bends
 *    the background and pulls the reading by 1-3 %;
 *  - noise floor per peak: with a reference (af_response_add_noise) its mean
 *    over f/1.2 .. 1.2 f around each peak (coloured noise varies across a
 *    wide band), else the window's own noise band, one floor for all;
 *  - out: peaks[0..*n_peaks), sorted by rising frequency, at most max_peaks
 *    (if more qualify, those of highest SNR); each record as
 *    af_response_result for that mode (onset_index, bin_width_hz and
 *    noise_segments the same in all).
 * The readings differ from af_response_execute's for the same peak by its
 * neighbours' share (the list takes them off; at 30 dB, within ~0.1 % on a
 * clean apple's modes) and the SNR by the floor (af_response_execute takes
 * the reference's mean over its whole range).
 * Returns
 *  AF_OK       at least one mode listed;
 *  AF_ENODATA  none: *n_peaks = 0 and peaks[0] holds the best rejected
 *              candidate (its frequency and SNR), or, when no candidate got
 *              as far, frequency NaN and the SNR of the largest rise of a local
 *              maximum above its floor (-inf for digital silence);
 *  AF_EINVAL   NULL pointer, max_peaks 0, n < 8, or not
 *              0 < f_lo_hz < f_hi_hz < Nyquist (nothing written);
 *  AF_ESIZE    n > window_samples; AF_ENUMERIC for a non-finite sample.
 * No allocation (the buffers are taken at create; the list and the fits'
 * normal equations live on the stack). Cost: a dozen small fits; on a
 * line-rate bag ~0.1 ms CPU median per strike with the transform, on a
 * three-mode comb in noise ~0.35 ms (doc/performance.md, "The response fits"). The same
 * buffers as af_response_execute: one call at a time per r. */
af_status af_response_execute_peaks(af_response *r, const float *audio, size_t n, double f_lo_hz,
                                    double f_hi_hz, af_response_result *peaks, size_t max_peaks,
                                    size_t *n_peaks);

/* How a nonlinear fit of the response ended (every fit is capped: stage 2
 * at 50 iterations, the peak list's truncated fits at 25):
 *  CONVERGED  the step, gradient or cost test met, or (the one-pole fits)
 *             the point within 0.1 standard error of the minimum under the
 *             peak's noise (response_lm.c, response_fit.c);
 *  CAPPED     the iteration cap reached (stage 2 then refuses the fit; a
 *             truncated fit is judged where it stands, its residual decides);
 *  STALLED    15 steps in a row raised the cost (as CAPPED);
 *  FAILED     the start could not be evaluated, a residual was not finite,
 *             or the solver failed: refused. */
typedef enum {
  AF_RESPONSE_FIT_CONVERGED = 0,
  AF_RESPONSE_FIT_CAPPED,
  AF_RESPONSE_FIT_STALLED,
  AF_RESPONSE_FIT_FAILED,
  AF_RESPONSE_FIT_STATUSES /* count */
} af_response_fit_status;

/* "converged", "capped", "stalled", "failed"; "unknown" otherwise. */
const char *af_response_fit_status_name(af_response_fit_status status);

/* The fits an object ran since its create or the last reset: how many ended
 * in each status, their iterations in all and the most in one. */
typedef struct {
  size_t fits[AF_RESPONSE_FIT_STATUSES];
  size_t iterations;
  size_t max_iterations;
} af_response_fit_stats;

/* r's counts into *out (zeros for NULL r); reset zeroes them (NULL-safe). */
void af_response_get_fit_stats(const af_response *r, af_response_fit_stats *out);

/* Bytes of the tables a response made with c keeps for the peak list's
 * subtraction of the trend's share (response_trend.c): 64 (1 +
 * hum_harmonics) per FFT bin with the exponential window and a transform of
 * at most 65,536 points, else 0; for the lane's memory bound
 * (lane_config.c). */
size_t af_response_share_table_bytes(const af_response_config *c);
void af_response_reset_fit_stats(af_response *r);

#ifdef __cplusplus
}
#endif
#endif
