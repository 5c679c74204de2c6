/* strike.h — finds each hammer strike in the force-transducer stream and
 * measures it.
 *
 * A streaming object in the manner of liquid-dsp: af_strike_create validates
 * the configuration and allocates everything (the history ring, the
 * measurement buffers); af_strike_write takes one chunk of samples with its
 * running sample index and calls back once per complete strike; no
 * allocation while writing. Compressive force is positive (negate the stream
 * of a transducer wired the other way): only positive excursions trigger.
 *
 * Per sample (cheap): a baseline tracker (exponential average, time constant
 * baseline_time_constant_s) follows the offset and slow drift of the
 * AC-coupled piezo while idle, and a noise tracker the mean square of the
 * baseline-removed signal (white noise, hum, what the baseline does not
 * follow). A sample above the baseline by more than
 *     threshold = max(threshold_noise_factor * noise RMS, threshold_min_n)
 * triggers; both trackers freeze until the event is emitted. The contact is
 * over (coarsely) once the signal stays below threshold/2 for 0.1 ms. A
 * contact starting again (above threshold) within double_hit_gap_s of that
 * end is a hammer bounce: it joins the event and flags it. The event is
 * emitted post_s after the end of the last contact.
 *
 * Per event (the measurement, on the span pre_trigger_s before the trigger
 * to the emission):
 *  - Baseline: the straight line through the means of the baseline_window_s
 *    of quiet signal just before the contact and just after it (the offset
 *    and drift interpolated across the contact, as a piezo's cannot be seen
 *    under the pulse); the mean before alone when nothing clean follows
 *    (bounce, gap). Placed twice: around the coarse contact, then around the
 *    fitted one.
 *  - Contact start and end: near first and last touch a Hertz contact gives
 *    F = K d^1.5 with d growing linearly from zero, so the force leaves zero
 *    as s^1.5 (s the time from the touch) and the hammer's deceleration
 *    bends it by a term in s^4 (the next, s^6.5, would follow a heavily
 *    damped tail better but lets the fitted zero wander in noise).
 *    The start t0 is the zero of the edge law
 *        F = a1 s^1.5 + a2 s^4 for s = t - t0 > 0,   F = 0 before t0,
 *    fitted by least squares to the baseline-removed samples from the quiet
 *    signal before the contact up to rise_fit_level of the peak (a1, a2 by
 *    linear least squares for each trial t0; t0 by a half-sample scan and a
 *    golden section). The end t1 is the zero of the same law in s = t1 - t,
 *    fitted from fall_fit_level of the peak down to the quiet signal after
 *    the contact. Not a level crossing: any level above zero cuts the
 *    s^1.5 foot late (at 2 % of the peak, 1 sample on the rise and 4.5 on
 *    the damped fall of the default strike at 50 kHz: 8 % of t_c).
 *  - Peak: the maximum of a least-squares quartic through the samples above
 *    70 % of the largest one. Impulse: trapezoid integral of the
 *    baseline-removed samples from t0 to t1 (the force taken as 0 at both).
 *  - Flags (the measurements are still made, best effort, but are not to be
 *    trusted as clean): double_hit; clipped (a raw sample of the contact at
 *    or beyond +-full_scale_n); lost_samples (samples missing from the span,
 *    from gaps in the running index or non-finite input); truncated (the
 *    event was cut before its contact ended: a gap, a stream restart, or a
 *    contact longer than max_contact_s).
 *
 * Gaps (first_sample beyond the next expected index): an event in progress
 * is emitted at once with what came before the gap, the gap counted in
 * lost_samples; the detector then waits for the signal to be quiet before
 * it triggers again. A gap longer than the baseline time constant restarts
 * the trackers (the offset may have moved); a shorter one keeps them. A
 * first_sample before the next expected index is a restarted stream: as
 * af_strike_reset. After create, reset or a restart the trackers learn for
 * one baseline time constant (running means) before the detector arms.
 *
 * Precision (test/core/test_strike.c: the model's default strike, 50 kHz,
 * white noise at 40 dB SNR = 20 log10(peak / noise RMS), plus hum, offset
 * and drift): start 0.2 sample RMS; peak and impulse 0.4 % RMS; contact time
 * 1.0-1.2 % RMS, bias under 0.3 %. The contact time is limited by the damped
 * pulse's shallow tail (its last 5 samples carry under 2 % of the peak):
 * even the exact model shape, fitted with its four free parameters (start,
 * time scale, amplitude, damping), cannot do better than 0.67 % RMS at
 * 40 dB (Cramer-Rao bound). Without white noise the edge laws read the
 * contact time within 0.4 % for a delivered restitution e >= 0.6, 1 % at
 * e = 0.5 and 2 % at e = 0.4-0.45, where the tail fades faster than s^1.5.
 *
 * Not thread-safe: one af_strike per stream and thread. */
#ifndef AF_STRIKE_H
#define AF_STRIKE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "spectrum.h"
#include "status.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct {
  double sample_rate_hz;           /* > 0 */
  double full_scale_n;             /* > 0: a raw sample with |F| >= this is clipped [N] */
  double threshold_noise_factor;   /* > 0: trigger above this many noise RMS ... */
  double threshold_min_n;          /* >= 0: ... and above this [N] */
  double pre_trigger_s;            /* > baseline_window_s: history kept before the trigger */
  double baseline_time_constant_s; /* > 0: idle baseline and noise trackers; also the warm-up */
  double baseline_window_s;        /* > 0: quiet signal averaged before and after the contact */
  double double_hit_gap_s; /* >= 0: a contact starting this soon after the end is a bounce */
  double max_contact_s;    /* > 0: a longer contact is not a strike (truncated) */
  double post_s;           /* >= double_hit_gap_s, > baseline_window_s: wait after the end */
  double rise_fit_level;   /* (0, 1): rising-edge fit up to this fraction of the peak */
  double fall_fit_level;   /* (0, 1): falling-edge fit from this fraction of the peak; the
                              lower the level, the smaller the law's bias, the larger the
                              noise (0.5: -0.2 % bias, 1.0-1.2 % RMS at 40 dB) */
} af_strike_config;

/* 50 kHz, full scale 500 N, threshold max(6 noise RMS, 0.5 N), pre-trigger
 * 2 ms, baseline time constant 20 ms, baseline windows 1 ms, double-hit gap
 * 5 ms, max contact 10 ms, post 5 ms, fit levels 0.7 (rise) and 0.5 (fall). */
af_strike_config af_strike_config_default(void);

/* One strike, as passed to the callback. The pointers are borrowed: valid
 * during the callback only. Sample indices are the stream's running index
 * (first_sample of the chunks), fractional where sub-sample. */
typedef struct {
  double start_sample;     /* contact start t0 [samples] */
  double end_sample;       /* contact end t1 [samples] */
  double peak_sample;      /* time of the peak [samples] */
  double contact_time_s;   /* (t1 - t0) / sample rate */
  double peak_force_n;     /* refined peak of the baseline-removed force */
  double impulse_n_s;      /* integral of the baseline-removed force over [t0, t1] */
  double baseline_n;       /* baseline removed, at t0 [N] */
  double noise_rms_n;      /* noise floor when the strike triggered [N] */
  double threshold_n;      /* trigger threshold used [N] */
  uint64_t trigger_sample; /* first sample above the threshold */
  bool double_hit;         /* a bounce started within double_hit_gap_s of the end */
  bool clipped;            /* a raw sample of the contact at or beyond +-full_scale_n */
  bool truncated;          /* cut before the contact ended (gap, restart, max_contact_s) */
  uint64_t lost_samples;   /* samples missing from pre-trigger .. emission */
  /* The baseline-removed contact for af_spectrum_execute / af_fit_pulse:
   * pulse_n[k] [N] at sample pulse_first_sample + k, k = 0 .. n_samples-1,
   * from the first sample at or after t0 to the last at or before t1. */
  const double *pulse_n;
  size_t n_samples;
  double dt_s;                 /* 1 / sample rate */
  uint64_t pulse_first_sample; /* = ceil(t0) */
  double pulse_t0_s;           /* t0 relative to pulse_n[0]'s time, in (-dt_s, 0] */
} af_strike_event;

/* Called once per strike, from inside af_strike_write. It must not call
 * af_strike_write or af_strike_reset on the same detector. It returns
 * nothing: the detector cannot stop half-way through a chunk without losing
 * its place in the stream. */
typedef void af_strike_fn(const af_strike_event *ev, void *user);

typedef struct af_strike af_strike;

/* Validates cfg (AF_EINVAL: a field outside its range, or a history beyond
 * 2^24 samples) before allocating the ring and the buffers (AF_ENOMEM).
 * *out is NULL on error. */
af_status af_strike_create(const af_strike_config *cfg, af_strike **out);
void af_strike_destroy(af_strike *d); /* NULL-safe */

/* Forgets the stream: trackers, history and any event in progress (not
 * emitted). The next write starts a new stream and a new warm-up. */
void af_strike_reset(af_strike *d);

/* Processes x[0..n) [N], whose first sample has the running index
 * first_sample, calling fn(ev, user) for every strike completed in it (fn
 * may be NULL: strikes are then detected and dropped). Chunks of any length.
 * AF_EINVAL for a NULL d, a NULL x with n > 0, or first_sample + n beyond
 * 2^63. No allocation. */
af_status af_strike_write(af_strike *d, uint64_t first_sample, const float *x, size_t n,
                          af_strike_fn *fn, void *user);

typedef struct {
  bool armed;           /* past the warm-up and not waiting for quiet */
  double baseline_n;    /* current baseline [N] */
  double noise_rms_n;   /* current noise floor [N] */
  double threshold_n;   /* the trigger threshold it gives [N] */
  uint64_t next_sample; /* index the next chunk is expected to start at */
} af_strike_tracker;

/* The trackers' state, for diagnostics. */
void af_strike_get_tracker(const af_strike *d, af_strike_tracker *out);

/* Runs the spectrum on ev's pulse (af_spectrum_execute: the code path of the
 * model's spectrum) and gives lobe number `lobe` (1 = main lobe) with its
 * band at `level` in *band, and the number of lobes found in *lobe_count
 * (may be NULL; set whenever the spectrum ran). Statuses of
 * af_spectrum_execute (AF_ESIZE: pulse longer than the spectrum's
 * max_samples) and af_spectrum_lobe (AF_ENOLOBE); AF_EINVAL for NULL
 * pointers. No allocation. */
af_status af_strike_measure_band(af_spectrum *s, const af_strike_event *ev, af_band_level level,
                                 unsigned lobe, af_lobe *band, size_t *lobe_count);

#ifdef __cplusplus
}
#endif
#endif
