/* verdict.h — why a strike is not reliable, as data: one flag per reason,
 * the values each reason names, and one function that words them.
 *
 * The measurement (measure.h) sets the flags of the strike itself (a dirty
 * pulse, a failed fit, no resonance, an ambiguous mode, the criteria); the
 * lane (lane.h) adds those of the station (no apple, a doubtful match, no
 * audio and why). A reason is never built as text and patched: the node, the
 * desk tools and the tests read the flags, and af_verdict_format gives the
 * one wording everyone prints. */
#ifndef AF_VERDICT_H
#define AF_VERDICT_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "status.h"

#ifdef __cplusplus
extern "C" {
#endif

/* In the order the reason lists them. */
typedef enum {
  AF_VERDICT_NO_APPLE = 1u << 0,         /* no AppleEstimate matches the strike */
  AF_VERDICT_NO_PREDICTION = 1u << 1,    /* its apple was refused (apple_why) */
  AF_VERDICT_APPLE_DOUBTFUL = 1u << 2,   /* matched, but its own estimate may not have come */
  AF_VERDICT_MEASURE_FAILED = 1u << 3,   /* af_measure_execute refused (measure_status) */
  AF_VERDICT_DOUBLE_HIT = 1u << 4,       /* the hammer bounced */
  AF_VERDICT_CLIPPED = 1u << 5,          /* a force sample at full scale */
  AF_VERDICT_LOST_SAMPLES = 1u << 6,     /* force samples missing (lost_samples) */
  AF_VERDICT_TRUNCATED = 1u << 7,        /* the contact was cut */
  AF_VERDICT_SPECTRUM_FAILED = 1u << 8,  /* the pulse's spectrum (spectrum_status) */
  AF_VERDICT_FIT_FAILED = 1u << 9,       /* the inverse fit (fit_status, fit_residual) */
  AF_VERDICT_POISSON = 1u << 10,         /* Lamb's root or the shear ratio (judge_status) */
  AF_VERDICT_NO_AUDIO = 1u << 11,        /* no audio window (audio_cause) */
  AF_VERDICT_NO_RESONANCE = 1u << 12,    /* no 0S2 above the SNR threshold */
  AF_VERDICT_RANGE_NYQUIST = 1u << 13,   /* the 0S2 range lies beyond Nyquist */
  AF_VERDICT_AUDIO_FAILED = 1u << 14,    /* the audio analysis (audio_status) */
  AF_VERDICT_MODE_AMBIGUOUS = 1u << 15,  /* two candidates for the 0S2 (mode_text) */
  AF_VERDICT_NO_LOBE = 1u << 16,         /* the configured lobe does not exist */
  AF_VERDICT_OUTSIDE_BAND = 1u << 17,    /* the 0S2 outside the lobe's half-power band */
  AF_VERDICT_DAMAGE = 1u << 18,          /* the shear reaches the yield: bruise */
  AF_VERDICT_REFUSED_SAMPLES = 1u << 19, /* non-finite force samples measured (refused_samples) */
  AF_VERDICT_AUDIO_CLIPPED = 1u << 20,   /* the microphone saturated (audio_clip_*) */
  AF_VERDICT_CLOCK_FAULT = 1u << 21, /* a stream's clock stepped, froze or ran off (clock_why) */
  AF_VERDICT_NOT_FRUIT = 1u << 22    /* the heard mode's Q is not fruit flesh's (fruit_q_*) */
} af_verdict_flag;

/* Why a strike went without audio (AF_VERDICT_NO_AUDIO). */
typedef enum {
  AF_AUDIO_NOT_GIVEN = 0,    /* no window passed (offline: none recorded) */
  AF_AUDIO_TOO_SHORT,        /* n_audio samples, fewer than the analysis needs */
  AF_AUDIO_NONE_RECEIVED,    /* no audio chunk within wait_s of the strike */
  AF_AUDIO_STREAM_STALE,     /* silent for more than wait_s */
  AF_AUDIO_BEFORE_STREAM,    /* the window starts seconds_before before the first sample */
  AF_AUDIO_NOT_RECEIVED,     /* samples first..last not there within wait_s (stream at end) */
  AF_AUDIO_LEFT_RING,        /* sample first no longer in the ring of ring_s */
  AF_AUDIO_UNREADABLE,       /* first..last could not be read */
  AF_AUDIO_LOST_IN_WINDOW,   /* the window holds lost (non-finite) samples */
  AF_AUDIO_QUEUE_FULL,       /* measured early: queue_size strikes were waiting */
  AF_AUDIO_STREAM_ENDED,     /* offline: the recording ends before the window does */
  AF_AUDIO_REFUSED_IN_WINDOW /* the window holds n_audio refused (non-finite) samples */
} af_audio_cause;

#define AF_VERDICT_TEXT_MAX 160

/* How far outside the 0S2 search range a peak is still named as the
 * resonance of a fruit outside the cultivar's range (a frequency ratio: 1.5
 * is a modulus 2.25 times off; farther, a peak is more likely another mode
 * or the support than this fruit's 0S2). */
#define AF_VERDICT_OUTSIDE_FACTOR 1.5

/* What made a heard mode not fruit's (AF_VERDICT_NOT_FRUIT), in af_verdict.not_fruit. */
typedef enum {
  AF_NOT_FRUIT_Q = 1u << 0,          /* its Q outside fruit_q_min..fruit_q_max */
  AF_NOT_FRUIT_NEIGHBOURS = 1u << 1, /* a stray partial where the sphere's comb would be */
  AF_NOT_FRUIT_CONFIDENCE = 1u << 2  /* identified below fruit_confidence_min */
} af_verdict_not_fruit;

/* What a tap-only strike (no force input, onset.h) judged from the model's
 * prediction for the configured hammer instead of a measurement: notes, not
 * reasons (a strike may be reliable with them), in af_verdict.model_only. */
typedef enum {
  AF_VERDICT_MODEL_EXCITATION = 1u << 0, /* the band: the prediction's, not a measured pulse's */
  AF_VERDICT_MODEL_SHEAR = 1u << 1       /* the shear: the prediction's, no measured force */
} af_verdict_model_only;

typedef struct {
  uint32_t flags; /* af_verdict_flag bits; 0 = reliable */
  /* The values the reasons name (meaningful when their flag is set). */
  uint32_t apple_id;
  double apple_stale_s;                      /* NO_APPLE, one apple a recording: the window [s] */
  double apple_transit_s, apple_tolerance_s; /* NO_APPLE: the estimate expected this long
                                                before the strike, within that [s]; NaN: one
                                                apple a recording */
  uint32_t nearest_apple_id;  /* NO_APPLE: the estimate stamped nearest the strike; 0 = none */
  double nearest_apple_lag_s; /* ... the strike's contact start minus its stamp [s] */
  char apple_why[AF_VERDICT_TEXT_MAX];    /* NO_PREDICTION: why the apple was refused */
  char doubtful_why[AF_VERDICT_TEXT_MAX]; /* APPLE_DOUBTFUL */
  char clock_why[AF_VERDICT_TEXT_MAX];    /* CLOCK_FAULT: the stream's fault in words */
  af_status measure_status, spectrum_status, fit_status, judge_status, audio_status;
  bool bounce_inside;           /* DOUBLE_HIT: a second impact inside the contact (the fit's
                                   residual structured); else the detector's bounce after it */
  double bounce_noise_ratio;    /* the inside test, whenever it ran (NaN: not run): the fit's
                                   residual, smoothed, in mean square against white noise's
                                   (about 1 for a clean strike) ... */
  double bounce_peak_ratio;     /* ... and the smoothed residual's RMS / the peak [-] */
  double bounce_impulse_excess; /* DOUBLE_HIT by the impulse (the lane): the strike's v0 from its
                                   impulse over the hammer's recent mean, - 1; NaN: not [-] */
  double fit_residual;          /* RMS / peak; NaN when the fit did not run */
  uint64_t lost_samples;
  uint64_t refused_samples; /* REFUSED_SAMPLES: non-finite force samples in the span */
  af_audio_cause audio_cause;
  uint64_t audio_first, audio_last, audio_end; /* sample indices of the window, stream end */
  double audio_seconds;                        /* wait_s, seconds_before or ring_s */
  size_t n_audio, queue_size;
  double snr_db, snr_threshold_db; /* NO_RESONANCE: best candidate (NaN/-inf: none) */
  double f_lo_hz, f_hi_hz;         /* the 0S2 search range [Hz] */
  /* NO_RESONANCE with a resonance just outside the range (a fruit softer or
   * firmer than the cultivar's, or a wrong mass): the strongest listed peak
   * above the SNR threshold within AF_VERDICT_OUTSIDE_FACTOR of the range
   * [Hz], its SNR [dB] and the E2 Lamb's law gives it [Pa]; NaN: none. */
  double outside_hz, outside_snr_db, outside_modulus_pa;
  double modulus_min_pa, modulus_max_pa; /* ... the cultivar's E2 range [Pa] */
  char mode_text[AF_VERDICT_TEXT_MAX];   /* MODE_AMBIGUOUS: af_modes_format's line */
  unsigned lobe;
  double resonance_hz, band_low_hz, band_high_hz; /* OUTSIDE_BAND */
  double resonance_q, fruit_q_min, fruit_q_max;   /* NOT_FRUIT */
  uint32_t not_fruit;                             /* ... af_verdict_not_fruit bits: what failed */
  double stray_hz, stray_db;                      /* ... NEIGHBOURS: the stray partial [Hz], its SNR
                                                     over the 0S2's [dB] */
  double mode_confidence, fruit_confidence_min;   /* ... CONFIDENCE: the identification's, the
                                                     least to grade [-] */
  double max_shear_pa, yield_shear_pa;            /* DAMAGE */
  size_t audio_clip_samples, audio_clip_tops;     /* AUDIO_CLIPPED: at the extremes, flat tops */
  double audio_clip_max, audio_clip_min;          /* ... the extremes, in the audio's unit */
  uint32_t model_only; /* af_verdict_model_only bits: judged from the model only; 0 = measured */
} af_verdict;

/* Clears v: no flag, every value NaN or 0. */
void af_verdict_clear(af_verdict *v);

/* The reason in words, "; "-separated in flag order, into buf ("" when no
 * flag is set); never overflows (a cut reason ends within buf). */
void af_verdict_format(const af_verdict *v, char *buf, size_t len);

/* The model-only notes in words, "; "-separated ("excitation judged from the
 * model only; shear judged from the model only"; "" when none). */
void af_verdict_format_model_only(const af_verdict *v, char *buf, size_t len);

/* The short name of one flag ("no_audio", ...), for counters and JSON;
 * "unknown" for anything else. */
const char *af_verdict_flag_name(af_verdict_flag f);

/* The words of one audio cause, without values ("audio stream stale"). */
const char *af_audio_cause_name(af_audio_cause c);

#ifdef __cplusplus
}
#endif
#endif
