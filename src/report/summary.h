/* summary.h — the figures of a session (session.h): counts, the share
 * reliable with a breakdown by verdict flag (verdict.h), the firmness
 * distribution as quantiles, the agreement of the modulus from the 0S2 with
 * the fitted E2 (what the cultivar's modulus_factor should be), strikes
 * without apple or audio and the streams' gaps. Pure: no I/O. */
#ifndef AF_REPORT_SUMMARY_H
#define AF_REPORT_SUMMARY_H

#include <stddef.h>

#include "session.h"

#define AF_SUMMARY_QUANTILES 7
#define AF_SUMMARY_FLAGS 32
#define AF_SUMMARY_AUDIO_CAUSES 16

/* The probabilities of af_quantiles.q: 0, 0.1, 0.25, 0.5, 0.75, 0.9, 1. */
extern const double af_summary_levels[AF_SUMMARY_QUANTILES];

typedef struct {
  size_t n;                       /* finite values behind q (0: q all NaN) */
  double q[AF_SUMMARY_QUANTILES]; /* linear interpolation between order statistics */
} af_quantiles;

typedef struct {
  size_t strikes, reliable, with_apple, without_apple, without_audio, doubtful;
  size_t apples, apples_refused, apples_without_strike, apples_predicted_reliable;
  size_t by_flag[AF_SUMMARY_FLAGS];               /* strikes with bit k of the verdict */
  size_t by_audio_cause[AF_SUMMARY_AUDIO_CAUSES]; /* strikes without audio, by cause */
  af_quantiles modulus_from_resonance_pa;         /* E from the 0S2 [Pa] */
  af_quantiles fitted_modulus_pa;                 /* E2 fitted to the pulse [Pa] */
  af_quantiles stiffness_factor;                  /* f^2 m^(2/3) [Hz^2 kg^(2/3)] */
  af_quantiles resonance_hz;                      /* measured 0S2 [Hz] */
  af_quantiles modulus_ratio;                     /* E(0S2) / fitted E2, per strike [-] */
  double modulus_ratio_spread;     /* 1.4826 MAD / median of the ratio: robust relative SD [-] */
  double modulus_factor_now;       /* the cultivar's, as run [-] */
  double modulus_factor_suggested; /* median of factor x ratio: makes the 0S2's modulus
                                      agree with the fitted E2 on the median strike [-] */
  af_factor_learn_state factor_learned; /* the lane's online estimate at the end of the bag
                                           (factor_learn.h): the newest window of reliable
                                           strikes, its 95 % interval, the applied value */
} af_summary;

/* The per-strike columns the quantiles are taken over: E(0S2), fitted E2,
 * stiffness factor, 0S2, their ratio, the suggested modulus factor. */
#define AF_SUMMARY_COLUMNS 6
void af_summary_columns_of(const af_session_strike *r, double out[AF_SUMMARY_COLUMNS]);

/* The quantiles, the ratio's spread and the suggested factor of *out from
 * the columns col[c][0..n) (af_summary_columns_of's order; each reordered in
 * place, the ratio's overwritten): a summary over several sessions. */
void af_summary_figures(af_summary *out, double *const col[AF_SUMMARY_COLUMNS], size_t n);

/* Fills *out from s. AF_OK; AF_ENOMEM (scratch for the quantiles). */
af_status af_summary_compute(const af_session *s, af_summary *out);

/* Quantiles of the finite x[0..n) (sorted in place; NaNs moved to the end). */
af_quantiles af_summary_quantiles(double *x, size_t n);

#endif
