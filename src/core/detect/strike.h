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
 * Per event (the measurement, on the span from pre_trigger_s before the
 * trigger, or from the stream's first sample if that is later, to the
 * emission):
 *  - Baseline: the straight line through the means of the baseline_window_s
 *    of quiet signal just before the contact and just after it (the offset
 *    and drift interpolated across the contact, as a piezo's cannot be seen
 *    under the pulse), each kept 3 samples away from the contact (first
 *    placement: 2 samples + 10 % of the coarse contact). A window cut short
 *    by the span's start (a short pre-trigger) or by a bounce averages what
 *    it holds, down to 4 samples; with fewer, the other window alone (a
 *    constant); with neither, the tracker's baseline (after af_strike_prime:
 *    the recording's median). Placed twice: around the coarse contact, then
 *    around the measured one. baseline_before_samples and
 *    baseline_after_samples tell what was averaged.
 *  - Contact start and end, well-sampled pulses: near first and last touch
 *    a Hertz contact gives F = K d^1.5 with d growing linearly from zero, so
 *    the force leaves zero as s^1.5 (s the time from the touch) and the
 *    hammer's deceleration bends it by a term in s^4 (the next, s^6.5, would
 *    follow a heavily damped tail better but lets the fitted zero wander in
 *    noise). The start t0 is the zero of the edge law
 *        F = a1 s^1.5 + a2 s^4 for s = t - t0 > 0,   F = 0 before t0,
 *    fitted by least squares to the baseline-removed samples from the quiet
 *    signal before the contact up to rise_fit_level of the peak (a1, a2 by
 *    linear least squares for each trial t0; t0 by a half-sample scan and a
 *    golden section). The end t1 is the zero of the same law in s = t1 - t,
 *    fitted from fall_fit_level of the peak down to the quiet signal after
 *    the contact. Not a level crossing: any level above zero cuts the
 *    s^1.5 foot late (at 2 % of the peak, 1 sample on the rise and 4.5 on
 *    the damped fall of the default strike at 50 kHz: 8 % of t_c). A foot
 *    that is not a power law (a half-sine's linear one) biases the zeros
 *    outwards: +3.2 to +5.6 % of the width for 20-100 samples noise-free
 *    (+4.7 % at 50; test_strike_pulse).
 *  - Contact start and end, short pulses: fewer than 16 samples above the
 *    level L = max(3 noise RMS, 2 % of the peak) (a steel-tipped hammer's
 *    ~0.35 ms at 25.6-44.1 kHz) leave 1-3 samples on each edge for the three
 *    unknowns of the edge law, which then follow whatever lies beside the
 *    pulse (the real captures of test/data: an anti-alias filter's
 *    pre-ringing before, the struck structure's ringing after; the fitted
 *    contact came out 25-70 % longer than the pulse's own width). There t0
 *    and t1 are the crossings of L by the band-limited reconstruction of the
 *    samples (below), bracketed by the samples either side: the width at
 *    which the pulse leaves the noise. It misses the feet below L: 4.7 % of
 *    the width for a Hertz-like sin^1.5 pulse at 2 % (under 0.8 sample below
 *    16 samples, hence the limit), 1.3 % for a half-sine; noise raises L
 *    above 2 % of the peak below 44 dB SNR. The same crossing replaces a
 *    failed fit on a longer pulse: no fit (too few samples), or a fitted
 *    zero more than 0.5 sample inside the crossing or further out than 15 %
 *    of the width between the crossings plus 1 sample (the default strike's
 *    damped fall: 6 % at 2 %; at most 16 % in test_strike.c). start_edge and
 *    end_edge say which method gave each; edge_level_n is L.
 *  - Peak: the maximum of a least-squares quartic through the samples above
 *    70 % of the largest one. A pulse with too few of them for the quartic
 *    (under 7: short pulses) takes the maximum of the band-limited
 *    reconstruction, a Hann-windowed sinc over 16 samples either side, within
 *    a sample of the largest: an acquisition is band-limited by its
 *    anti-alias filter (the captures' pre-ringing at the Nyquist frequency
 *    shows a linear-phase one), so between samples the force is the sinc
 *    interpolation. The largest sample of a 9-sample pulse lies up to 2.2 %
 *    below its peak; a parabola through the top three overshoots an
 *    asymmetric top (capture 5: +1.1 % above its largest sample, the
 *    reconstruction +0.8 %). On a raw-sampled pulse with kinks (a half-sine
 *    without an anti-alias filter: not band-limited) the reconstruction's
 *    peak is off by up to 1 % at 8-10 samples, 0.4 % for a sin^1.5 pulse.
 *    Impulse: trapezoid integral of the baseline-removed samples from t0 to
 *    t1 (the force taken as 0 at both).
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
 * What a strike needs before it.
 *  - Live (a stream, no prime): after create, af_strike_reset, a restarted
 *    stream or a gap longer than baseline_time_constant_s, the warm-up:
 *    ceil(baseline_time_constant_s x rate) finite samples (20 ms: 512 samples
 *    at 25.6 kHz, 1000 at 50 kHz) learned before the detector arms. A strike
 *    inside it is not detected, and it is learned: the trackers arm with a
 *    raised noise floor (the real capture's 89 N strike 0.8 ms in gives a
 *    42 N threshold at arming, decaying with the time constant). After a cut
 *    event (gap, over-long contact): 0.1 ms below half the threshold. Then
 *    the contact itself: for the baseline line, at least 4 samples of quiet
 *    signal 3 samples before the contact (7 samples: 0.27 ms at 25.6 kHz;
 *    the full window takes baseline_window_s + 3 samples), else the window
 *    after it alone; the edge-law fit reaches 2 samples + 10 % of the
 *    contact into the quiet signal before it and uses what the span holds.
 *  - Offline (a whole recording, e.g. a triggered capture): af_strike_prime
 *    with the recording, then af_strike_write of it from its first sample:
 *    no warm-up, a strike triggers from the first sample on and is measured
 *    as above (tested down to 0.5 ms, 13 samples at 25.6 kHz); a recording
 *    that ends less than post_s after its strike needs af_strike_flush.
 *  - When no strike came, af_strike_get_diagnosis and af_strike_explain say
 *    why: still in the warm-up when the largest excursion came, never above
 *    the threshold (with the largest excursion and the threshold there),
 *    waiting for quiet, or a strike still pending.
 *
 * Precision (test/core/test_strike.c: the model's default strike, 50 kHz,
 * white noise at 40 dB SNR = 20 log10(peak / noise RMS), plus hum, offset
 * and drift): start 0.2 sample RMS; peak and impulse 0.4 % RMS; contact time
 * 1.0-1.2 % RMS, bias under 0.3 % (the same primed, 0.5 ms after the start
 * of a capture). The contact time is limited by the damped pulse's shallow
 * tail (its last 5 samples carry under 2 % of the peak): even the exact
 * model shape, fitted with its four free parameters (start, time scale,
 * amplitude, damping), cannot do better than 0.67 % RMS at 40 dB
 * (Cramer-Rao bound). Without white noise the edge laws read the contact
 * time within 0.4 % for a delivered restitution e >= 0.6, 1 % at e = 0.5 and
 * 2 % at e = 0.4-0.45, where the tail fades faster than s^1.5.
 * Short pulses (test/core/test_captures.c): the two real hammer captures
 * (25.6 kHz, ~72 dB, primed, no padding): contact time within 0.17 sample of
 * the linear-interpolated 2 % width, peak +0.1 % and +0.8 % from the largest
 * sample; synthetic sin^1.5 and half-sine pulses of 8-10 samples (widths
 * in 0.1-sample steps, 10 start phases each, 0.5 ms pre-trigger): start
 * within 0.45 sample and contact time within 0.75 sample of the true ones
 * at 40-80 dB, peak within 0.55 % (sin^1.5) and 1.05 % (half-sine) at 60 dB.
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
  double threshold_min_n;          /* > 0: ... and above this [N] (a noise floor of exact
                                      zeros is 0: this bounds the threshold below) */
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

/* How the contact start and end of an event were found (strike.h's header). */
typedef enum {
  AF_STRIKE_EDGES_FIT = 0, /* zeros of the edge law a1 s^1.5 + a2 s^4 (well-sampled pulse;
                              without a fit or a crossing: the coarse contact) */
  AF_STRIKE_EDGES_LEVEL    /* interpolated crossings of edge_level_n (short pulse) */
} af_strike_edges;

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
  /* The baseline-removed contact for af_spectrum_execute / af_fit_execute:
   * pulse_n[k] [N] at sample pulse_first_sample + k, k = 0 .. n_samples-1,
   * from the first sample at or after t0 to the last at or before t1. */
  const double *pulse_n;
  size_t n_samples;
  double dt_s;                    /* 1 / sample rate */
  uint64_t pulse_first_sample;    /* = ceil(t0) */
  uint64_t span_first, span_end;  /* the samples measured, [span_first, span_end): where
                                     lost_samples were counted */
  double pulse_t0_s;              /* t0 relative to pulse_n[0]'s time, in (-dt_s, 0] */
  af_strike_edges start_edge;     /* which method gave t0 ... */
  af_strike_edges end_edge;       /* ... and t1 */
  double edge_level_n;            /* level of the crossings (used or checked against) [N] */
  size_t baseline_before_samples; /* quiet samples averaged before the contact (0: none) */
  size_t baseline_after_samples;  /* ... and after it (0: none) */
  bool primed;                    /* the trackers came from af_strike_prime */
} af_strike_event;

/* Called once per strike, from inside af_strike_write. It must not call
 * af_strike_write or af_strike_reset on the same detector. It returns
 * nothing: the detector cannot stop half-way through a chunk without losing
 * its place in the stream. */
typedef void af_strike_fn(const af_strike_event *ev, void *user);

typedef struct af_strike af_strike;

/* Validates cfg (AF_EINVAL: a field outside its range, or a history beyond
 * 2^24 samples) before allocating the ring, the buffers and
 * af_strike_prime's workspace (64 KiB) (AF_ENOMEM). *out is NULL on error. */
af_status af_strike_create(const af_strike_config *cfg, af_strike **out);
void af_strike_destroy(af_strike *d); /* NULL-safe */

/* Forgets the stream: trackers (a prime too), history, the diagnosis and
 * any event in progress (not emitted). The next write starts a new stream
 * and a new warm-up. */
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

/* Offline: sets the trackers from robust statistics of a whole recording
 * x[0..n) [N] and arms the detector at once, with no warm-up, so that the
 * following af_strike_write of that recording from its first sample (any
 * running index) measures a strike however early it comes. Forgets the
 * stream first (as af_strike_reset). The baseline is the median, the noise
 * RMS the root mean square about it, of the quiet parts: up to 8192 evenly
 * strided finite samples, leaving out those within baseline_window_s + 0.1 ms
 * of a sample beyond the release level (half the trigger threshold) that the
 * median and MAD of all of them give: strikes, bounces, their ringing. When
 * fewer than a quarter of the samples are quiet, the median and MAD-based
 * RMS of all of them. The trackers then follow the signal as usual (offset
 * drift within the recording is followed from the median at the usual time
 * constant: a recording that starts further than a threshold from its median
 * triggers at once). AF_EINVAL for a NULL d, a NULL x with n > 0;
 * AF_ENODATA (the detector left as it was) for fewer than 16 finite samples.
 * No allocation (a workspace allocated at create), O(n). */
af_status af_strike_prime(af_strike *d, const float *x, size_t n);

/* Emits the event in progress, if any, at once with what has been written
 * (truncated when its contact had not ended; then as after a cut event, it
 * waits for quiet), instead of post_s after the contact: for a recording that
 * ends less than post_s after a strike. The stream may go on afterwards.
 * AF_EINVAL for a NULL d. No allocation. */
af_status af_strike_flush(af_strike *d, af_strike_fn *fn, void *user);

/* Whether an event is in progress (a contact, or the wait after one). */
bool af_strike_in_progress(const af_strike *d);

/* Why no strike was found (af_strike_diagnosis.why). */
typedef enum {
  AF_STRIKE_FOUND = 0,       /* at least one strike emitted since the stream started */
  AF_STRIKE_NO_SIGNAL,       /* nothing written since the stream started */
  AF_STRIKE_IN_WARMUP,       /* the warm-up never ended, or the largest excursion came in it
                                and was above the threshold the detector armed with */
  AF_STRIKE_BELOW_THRESHOLD, /* armed, and never above the threshold */
  AF_STRIKE_WAITING_QUIET,   /* the largest excursion came while waiting for quiet after a
                                cut event (or the detector was never armed but waiting) */
  AF_STRIKE_PENDING          /* a strike triggered and is not emitted yet */
} af_strike_why;

/* What the detector saw since the stream started (create, reset, restart,
 * prime); the largest excursions since then or the last strike emitted. An
 * excursion is a sample minus the tracker's baseline then [N]; NaN where
 * none was seen. */
typedef struct {
  af_strike_why why;               /* the verdict, in the order of the enum's checks:
                                      PENDING, FOUND, NO_SIGNAL, IN_WARMUP, WAITING_QUIET,
                                      BELOW_THRESHOLD */
  uint64_t strikes;                /* strikes emitted */
  uint64_t samples;                /* samples written (gaps not counted) */
  bool primed;                     /* the trackers came from af_strike_prime */
  bool armed;                      /* as af_strike_tracker.armed */
  uint64_t armed_sample;           /* first sample armed after the last warm-up (UINT64_MAX:
                                      never armed) */
  uint64_t warmup_samples;         /* warm-up length: baseline_time_constant_s [samples] */
  uint64_t warmup_learned;         /* finite samples learned in the current warm-up (all
                                      of them once armed) */
  double arm_threshold_n;          /* threshold when the detector armed [N] */
  double warmup_max_n;             /* largest excursion during the warm-up [N] ... */
  uint64_t warmup_max_sample;      /* ... and its sample */
  double armed_max_n;              /* largest excursion while armed and idle [N] ... */
  uint64_t armed_max_sample;       /* ... its sample ... */
  double armed_max_threshold_n;    /* ... and the threshold there [N] */
  double settle_max_n;             /* largest excursion while waiting for quiet [N] ... */
  uint64_t settle_max_sample;      /* ... its sample ... */
  double settle_max_threshold_n;   /* ... and the threshold there [N] */
  uint64_t pending_trigger_sample; /* AF_STRIKE_PENDING: trigger of the event in progress */
  double threshold_n;              /* trigger threshold now [N] */
  double noise_rms_n;              /* noise floor now [N] */
} af_strike_diagnosis;

/* Fills *out (nothing for a NULL d or out). O(1), no allocation. */
void af_strike_get_diagnosis(const af_strike *d, af_strike_diagnosis *out);

/* A short static phrase for why, e.g. "never above threshold". Never NULL. */
const char *af_strike_why_text(af_strike_why why);

/* One line (no newline) into buf[0..size): the verdict with its figures, for
 * a tool to print as "no strike found: <line>" when no strike came, e.g.
 *   never above threshold: largest excursion 0.09 N at sample 3130,
 *     threshold 0.5 N there (max(6 x noise RMS, 0.5 N); noise RMS now 0.02 N)
 *   still in warm-up when the largest excursion came (88.9 N at sample 22;
 *     armed from sample 512, threshold 41 N then); prime the detector or ...
 *   2 strikes found
 * AF_EINVAL for a NULL d or buf or a zero size; AF_ESIZE when the line was
 * cut to fit (still terminated). No allocation. */
af_status af_strike_explain(const af_strike *d, char *buf, size_t size);

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
