/* modes.h — which microphone peak is the apple's 0S2.
 *
 * A struck fruit rings in several spheroidal modes whose frequencies stand in
 * fixed ratios to the 0S2 (lamb.h: 0S3 1.49x, 0S4 1.92x, 1S2 1.94x at
 * nu 0.35, whatever the size and modulus). The microphone may hear the 0S3
 * louder than the 0S2, and for soft or heavy fruit the 0S3 (even the
 * 0S4/1S2) lies inside the cultivar's 0S2 search range [f_lo, f_hi]: the
 * loudest peak in range is then a factor 1.49 off in frequency, 2.2 in
 * modulus. This module decides which listed peak is the 0S2 from what the
 * strike tells:
 *  - the prior: the 0S2 predicted from the modulus fitted to the force pulse,
 *    f_pred, with its relative uncertainty (NaN when the fit failed);
 *  - the comb: the other peaks that stand at the Lamb ratios of a candidate;
 *  - the peaks actually present (af_response_execute_peaks over a band wider than
 *    the range: af_modes_list_band).
 * Pure functions: no allocation, no state, thread-safe.
 *
 * Use, per strike (nothing allocates; the ratios are solved once per nu):
 *   af_lamb_sphere_modes_cached(&cache, nu, &modes);        at prepare
 *   af_modes_list_band(f_lo, f_hi, fs, &band_lo, &band_hi);
 *   af_response_execute_peaks(resp, audio, n, band_lo, band_hi, peaks,
 *                     AF_RESPONSE_MAX_PEAKS, &n_peaks);           AF_ENODATA: none
 *   f_pred = the fit held ? af_lamb_frequency_hz(xi, modulus_factor E2,
 *                                                     nu, rho, m) : NaN;
 *   s = 0.5 sqrt((E2_se / E2)^2 + s_cal^2)    (f ~ sqrt(E); s_cal the relative
 *        uncertainty of the pulse's E2 as a predictor of the dynamic modulus,
 *        e.g. 0.10: the fitted E2 within 20 % at 2 sigma)
 *   af_modes_execute(&cfg, &in, &id);  the resonance is peaks[id.peak]
 *   (AF_OK), unreliable when id.ambiguous; af_modes_format for the reason.
 *
 * ---- decision rules ---------------------------------------------------------
 * Candidates: the listed peaks with f in [f_lo, f_hi]. None: no
 * identification (AF_ENODATA, method NONE).
 *
 * Each candidate i gets a score L_i, the natural log of the Bayes factor of
 * "peak i is the 0S2" against "peak i is unrelated to the 0S2" (a support or
 * hammer mode, a partner of another peak): evidence adds.
 *  1. Prior (when f_pred is given): z_i = ln(f_i / f_pred) / s, s the
 *     relative standard uncertainty of f_pred;
 *       L_prior = ln(W / (s sqrt(2 pi))) - z_i^2 / 2,  W = ln(f_hi / f_lo):
 *     a Gaussian in ln f against a uniform spread over the range. With s
 *     0.05 (the modulus known to 10 %, 1 sigma), z = 0 gives +2.3, the 0S3 of
 *     a prior 20 % off in modulus (z >= 6) gives < -16.
 *  2. Partners, per group g = {0S3} and {0S4, 1S2} (the last two lie 1.2 %
 *     apart at nu 0.35 and merge into one peak at the apple's Q of 20-40):
 *     the window [f_i r_min (1 - tol), f_i r_max (1 + tol)], r the group's
 *     ratios. If it lies inside the listed band (checkable):
 *       a peak in it:    + ln(p_heard / p_random)          (+1.8 at defaults)
 *       none:            + ln((1 - p_heard) / (1 - p_random))  (-0.6)
 *     p_heard: chance that a partner is heard at all (the microphone may sit
 *     on its node, it may fall below the SNR threshold); p_random = 1 -
 *     exp(-density w): chance that some unrelated peak falls into the window
 *     of log-width w, density the unrelated peaks per unit of ln f.
 *  3. Below, per group g: a listed peak at f_i / r (within the same window
 *     scaled down) makes peak i look like that peak's 0S3 (0S4/1S2): the
 *     match score of 2 with the sign turned, - ln(p_heard / p_random). The
 *     0S2 is the lowest spheroidal mode: nothing of the apple's comb below it.
 *  The 0T2 (0.943 f) is not scored: torsional, barely heard, and a split 0S2
 *  may put a peak there as well; a peak there is only reported as matched.
 *  Loudness is not scored (the 0S3 may well be louder); it breaks exact ties.
 *
 * Method:
 *  - PRIOR_RATIOS: a prior and some ratio evidence (a partner found or a
 *    relation below, for any candidate);
 *  - PRIOR: a prior, no ratio evidence;
 *  - RATIOS: no prior (the fit failed), ratio evidence;
 *  - LOUDEST: neither: the highest-SNR candidate, af_response_execute's old
 *    reading, kept only where nothing better is known.
 * Choice: the highest L (ties: the higher SNR); LOUDEST: the highest SNR.
 *
 * Confidence: exp(L_best) / (1 + sum_i exp(L_i)), the posterior of the chosen
 * peak when the 0S2 may also be none of them (unheard, or outside the
 * range: the "1", L = 0). LOUDEST: every L is 0, so 1 / (1 + candidates):
 * 0.5 for a lone peak.
 *
 * Ambiguous (the strike is unreliable; the competing candidates are named):
 *  - CLOSE_CALL: the runner-up's L within ambiguity_margin (ln 4: it is at
 *    least a quarter as likely) of the best. Typical: a second mode within
 *    5 % of the 0S2 (a split 0S2, a mode of the support) with no partner to
 *    tell them apart — a prior whose uncertainty is +-5 % or more cannot
 *    separate them, and a prior sitting between two candidates favours
 *    neither;
 *  - PRIOR_VS_RATIOS: the ratios alone (scores 2 and 3) pick another
 *    candidate by ambiguity_margin or more: the fit and the comb disagree;
 *  - PRIOR_CONFLICT: the chosen peak lies more than conflict_sigmas (3) from
 *    f_pred and has no partner: nothing supports it but being the least bad
 *    (prior_conflict is also set, without ambiguity, when the chosen peak is
 *    that far but its partners confirm it: a fruit or calibration outside
 *    the model, worth reporting);
 *  - LOUDNESS_TIE: LOUDEST with a second candidate within loudest_margin_db
 *    (6 dB) of the loudest.
 *
 * Not done: an unheard 0S2 whose 0S3 and 0S4 are heard is not reconstructed
 * (their ratio 1.284 alone is too weak a fingerprint); its 0S3 is then a
 * candidate with no partner, and a prior rejects it (PRIOR_CONFLICT).
 */
#ifndef AF_MODES_H
#define AF_MODES_H

#include <stdbool.h>
#include <stddef.h>

#include "lamb.h"
#include "response.h"
#include "status.h"

#ifdef __cplusplus
extern "C" {
#endif

/* "No peak" in an index field. */
#define AF_MODES_NO_PEAK ((size_t)-1)
/* Candidates named when ambiguous (the chosen first). */
#define AF_MODES_MAX_COMPETING 4

typedef struct {
  double ratio_tolerance;   /* relative window around a predicted partner, in (0, 0.2) */
  double p_heard;           /* chance that a partner mode is heard, in (0, 1) */
  double random_density;    /* unrelated peaks per unit of ln f, > 0 */
  double ambiguity_margin;  /* runner-up within this of the best score: ambiguous, > 0 */
  double conflict_sigmas;   /* |z| beyond this: prior conflict, > 0 */
  double loudest_margin_db; /* LOUDEST: a second candidate within this: ambiguous [dB], >= 0 */
} af_modes_config;

/* tol 0.03: the measured frequencies hold 0.5 % at 30 dB, nu over 0.25-0.40
 * moves the 0S3 ratio by +-0.4 %, a real fruit is no perfect sphere; 3 %
 * keeps the 0T2 (5.7 % below) and the comb's other members (>= 28 % apart)
 * out of each other's windows. p_heard 0.5, density 1.5 (a list band of 2
 * units of ln f holds the 3-4 apple modes and a few others): a partner found
 * +1.77 (0S3) / +1.59 (0S4/1S2), missed -0.60 / -0.59. Margin ln 4; conflict
 * 3 sigma; loudest margin 6 dB. */
af_modes_config af_modes_config_default(void);

/* The band to list the peaks over for the range [f_lo, f_hi] at this audio
 * rate: [0.8 f_lo (the f/1.49 of the lowest candidates, the 0T2 of f_lo),
 * max(f_hi, min(2 f_hi (the 0S4/1S2 of f_hi within tol), 0.9 Nyquist))].
 * AF_EINVAL unless 0 < f_lo < f_hi < Nyquist. */
af_status af_modes_list_band(double f_lo_hz, double f_hi_hz, double sample_rate_hz,
                             double *band_lo_hz, double *band_hi_hz);

typedef struct {
  const af_response_result *peaks; /* listed peaks (af_response_execute_peaks), any order */
  size_t n_peaks;                  /*   their count; 0 allowed */
  double band_lo_hz, band_hi_hz;   /* the band they were listed over [Hz] */
  double f_lo_hz, f_hi_hz;         /* the 0S2 search range, inside the band [Hz] */
  const af_sphere_modes *modes;    /* ratios for the apple's nu (lamb.h) */
  double f_pred_hz;                /* 0S2 predicted from the fitted modulus [Hz]; NaN: none */
  double f_pred_rel_sd;            /* relative standard uncertainty of f_pred (ln f), > 0 */
} af_modes_input;

typedef enum {
  AF_MODES_METHOD_NONE = 0,     /* no candidate in range: no identification */
  AF_MODES_METHOD_PRIOR_RATIOS, /* the fitted modulus and the comb */
  AF_MODES_METHOD_PRIOR,        /* the fitted modulus alone (no comb relation heard) */
  AF_MODES_METHOD_RATIOS,       /* the comb alone (no prior: the fit failed) */
  AF_MODES_METHOD_LOUDEST       /* fallback: loudest in range, nothing better known */
} af_modes_method;

/* "none", "prior+ratios", "prior", "ratios", "loudest in range". */
const char *af_modes_method_name(af_modes_method method);

typedef enum {
  AF_MODES_CLEAR = 0,       /* not ambiguous */
  AF_MODES_CLOSE_CALL,      /* runner-up within the margin */
  AF_MODES_PRIOR_VS_RATIOS, /* prior and comb pick different peaks */
  AF_MODES_PRIOR_CONFLICT,  /* chosen far from the prior, no partner */
  AF_MODES_LOUDNESS_TIE     /* LOUDEST with a second candidate within the margin */
} af_modes_ambiguity;

typedef struct {
  af_sphere_mode mode; /* the mode this peak is taken for */
  size_t peak;         /* index into in->peaks */
  double frequency_hz; /* measured [Hz] */
  double ratio_error;  /* f / (f_0S2 x ratio of the mode) - 1; 0 for the 0S2 itself */
} af_modes_match;

typedef struct {
  size_t peak;         /* index into in->peaks */
  double frequency_hz; /* [Hz] */
  double score;        /* L (see above) */
  /* the relation that argues against this peak being the 0S2: it looks like
   * mode 'looks_like' (0S3, or 0S4/1S2 as the nearer) of the peak at
   * base_hz; AF_MODE_COUNT and NaN when none */
  af_sphere_mode looks_like;
  double base_hz;
} af_modes_candidate;

typedef struct {
  af_modes_method method;
  size_t peak;         /* chosen 0S2: index into in->peaks; AF_MODES_NO_PEAK: none */
  double frequency_hz; /* its frequency [Hz]; NaN: none */
  double confidence;   /* [0, 1], see above; 0 when none */
  bool ambiguous;      /* ambiguity != AF_MODES_CLEAR: unreliable */
  af_modes_ambiguity ambiguity;
  bool prior_conflict; /* chosen peak beyond conflict_sigmas from f_pred */
  double prior_z;      /* ln(f / f_pred) / s of the chosen peak; NaN without prior or peak */
  double f_pred_hz;    /* copied from the input, for the text */
  double f_lo_hz, f_hi_hz;
  size_t n_candidates;                                  /* peaks in the range */
  size_t n_matched;                                     /* modes matched for the chosen 0S2, */
  af_modes_match matched[AF_MODE_COUNT];                /*   rising frequency, the 0S2 among them */
  size_t n_competing;                                   /* when ambiguous: the candidates named, */
  af_modes_candidate competing[AF_MODES_MAX_COMPETING]; /* the chosen first */
} af_modes_id;

/* Decides the 0S2 among in->peaks (rules above) into *out.
 *  AF_OK       a peak chosen (check out->ambiguous, out->method);
 *  AF_ENODATA  no listed peak in [f_lo, f_hi]: method NONE, peak
 *              AF_MODES_NO_PEAK, frequency NaN, confidence 0;
 *  AF_EINVAL   a NULL pointer (peaks may be NULL when n_peaks is 0), a config
 *              outside its ranges, not 0 < band_lo <= f_lo < f_hi <= band_hi,
 *              a non-finite mode ratio, f_pred finite but not > 0, or a
 *              prior whose f_pred_rel_sd is not finite and > 0 (*out untouched).
 * Peaks with a non-finite frequency are ignored. No allocation; at most a
 * few hundred operations for AF_RESPONSE_MAX_PEAKS peaks. */
af_status af_modes_execute(const af_modes_config *cfg, const af_modes_input *in, af_modes_id *out);

/* One short line for a reason text or a log, e.g.
 *   "0S2 612 Hz (prior+ratios: 0S3 913 Hz, 0S4 1172 Hz; confidence 0.98)"
 *   "ambiguous 0S2: 612 Hz or 913 Hz (0S3 of 612 Hz?)"
 *   "0S2 700 Hz (loudest in range, nothing better known; confidence 0.50)"
 *   "no 0S2 candidate in [300, 1200] Hz"
 * snprintf semantics: writes at most size bytes (NUL included; buf may be
 * NULL when size is 0) and returns the length the whole line needs. */
size_t af_modes_format(const af_modes_id *id, char *buf, size_t size);

#ifdef __cplusplus
}
#endif
#endif
