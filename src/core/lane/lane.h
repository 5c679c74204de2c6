/* lane.h — one station lane, everything but ROS: the force and audio
 * streams, the strike detector, the queue of strikes waiting for their audio
 * and their apple, the match of a strike to its apple, the audio window, the
 * per-apple prediction, the measured verdict and the strike's firmness grade.
 *
 * The node (src/node) converts messages into af_chunk / af_apple and
 * publishes what the lane calls back with; the desk tools (firmness_model
 * analyze) feed recordings through the same calls, so that a recording is
 * judged exactly as the node judges it live.
 *
 *   force chunk ──> af_stream_push ──> af_strike_write ──> strike: contact
 *       start time = chunk stamp + (start_sample - first_sample) / rate (the
 *       latest force chunk's mapping, stream.h); the event and its pulse are
 *       copied into a preallocated pending slot
 *   audio chunk, force chunk, poll ──> every pending strike, oldest first, is
 *       measured once BOTH are decided:
 *        - its audio: the window [start + delay, start + delay + window]
 *          (sample indices by the audio stream's mapping; the first sample
 *          at or after the window's start) is in the ring; or it will not
 *          come (af_audio_cause: the stream is stale, the window left the
 *          ring, holds lost samples, lies before the stream began, or has
 *          not come stream_stale_after_s + delay + window after the strike);
 *        - its apple: an AppleEstimate stamped after the strike's transit
 *          window has arrived (estimates arrive in stamp order, so none in
 *          the window can still come), or apple_wait_s has passed since the
 *          strike, on the lane's clock or in the force stream's own data (a
 *          replay's simulated clock stops with the bag). The strike then
 *          belongs to the estimate stamped nearest apple_transit_s before its
 *          contact start, within apple_transit_tolerance_s: on a line with
 *          several apples between the camera and the hammer, the newest
 *          estimate before a strike is another apple's. (The desk tools'
 *          one apple a recording, single_apple: the newest estimate stamped
 *          at or before the contact start, at most apple_stale_after_s.)
 *       A full queue measures its oldest strike at once, with what there is.
 *   apple ──> af_prediction_execute (prediction.h) and a short history of
 *       predictions, so that a late strike still finds its own apple. An
 *       estimate with apple_id 0 (the StrikeReport's "no apple") or stamped
 *       further than apple_stale_after_s from the newest data is refused and
 *       counted (apples_implausible): it never takes or decides a match.
 *
 * The transit is watched: the median lag of the matched strikes, and of the
 * estimate nearest each strike that found none; a systematic lag (a camera
 * stamping at publish time) is put in words (af_lane_stats.transit_warning).
 *
 * A doubtful match is never silent: an apple that already has a strike gets
 * AF_VERDICT_APPLE_DOUBTFUL on the next one (its own estimate may be the one
 * missing), and an estimate arriving after a strike it should have taken was
 * reported is counted (af_lane_stats.late_apples) with a line saying which.
 *
 * Clock: every call takes now_ns, the lane's clock (the node: ROS time, which
 * is the bag's under replay; the desk tools: the recording's time, i.e. the
 * end of the latest chunk). Everything is allocated in af_lane_create;
 * nothing per chunk, apple or strike. Not thread-safe. */
#ifndef AF_LANE_H
#define AF_LANE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "factor_learn.h"
#include "lane_config.h"
#include "measure.h"
#include "prediction.h"
#include "stream.h"

#ifdef __cplusplus
extern "C" {
#endif

#define AF_LANE_TEXT_MAX 256

/* One measured strike, the whole result, as passed to the callback (borrowed
 * for the call; serialize.h writes it). */
typedef struct {
  int64_t start_ns;                   /* contact start [ns] */
  char frame_id[AF_STREAM_FRAME_MAX]; /* the force chunk's */
  uint32_t apple_id;                  /* the matched apple; 0 when none */
  const af_apple *apple;              /* the matched estimate; NULL when none */
  const af_prediction *prediction;    /* its prediction; NULL when none */
  bool with_audio;                    /* an audio window was analysed */
  af_measure_report report;           /* figures; report.verdict holds every flag (the
                                         lane's too), report.reason its words */
  af_grade grade; /* the firmness grade of report (grade.h) by the configuration's grade:
                     what the StrikeReport carries and the desk tools print */
  const af_strike_event *event; /* the detector's event (pulse included) */
  double modulus_factor;        /* the factor this strike's 0S2 was turned into a modulus with:
                                   the cultivar's, or the learned one applied [-] */
  bool factor_changed; /* the learned factor applied from the next strike on changed with this
                          one (af_lane_factor: the new value and the previous) */
} af_lane_strike;

typedef void af_lane_strike_fn(const af_lane_strike *s, void *user);

/* Counters for diagnostics and reports. */
typedef struct {
  uint64_t strikes, double_hits, clipped, truncated, lost_force_samples;
  uint64_t no_resonance, no_apple, no_audio, doubtful, unreliable;
  uint64_t overflows, measure_errors, pulse_cut, late_apples;
  uint64_t audio_clipped;    /* strikes whose audio window the microphone saturated */
  uint64_t clock_faulted;    /* strikes judged across a stream's clock fault */
  uint64_t force_stalls;     /* strikes emitted cut because the force stream stalled in them */
  uint64_t reconfigure_lost; /* strikes in progress lost to a reconfigure of the detector */
  char last_reconfigure_lost[AF_LANE_TEXT_MAX];
  /* The audio clock's lag behind the force's (audio_lag.h): the median and
   * its median absolute deviation over the latest strikes, the lag the
   * windows are moved by, the strikes whose onset was not found, the moves. */
  double lag_median_s, lag_mad_s, lag_applied_s;
  size_t lag_strikes;
  uint64_t lag_no_onset, lag_moves;
  char lag_warning[AF_LANE_TEXT_MAX]; /* the latest move, in words; "" when none */
  uint64_t apples, apples_refused;
  uint64_t apples_implausible; /* of apples_refused: apple_id 0, or stamped far off the data */
  uint64_t apples_skipped;     /* ids that never came, on a line whose ids count up by one */
  char last_apples_skipped[AF_LANE_TEXT_MAX];
  char last_implausible_apple[AF_LANE_TEXT_MAX];
  /* The transit observed: the median of strike minus estimate stamp over the
   * latest matched strikes (NaN: none yet), and, over the latest strikes
   * without an apple, the median lag of the estimate nearest each. */
  double transit_observed_s;
  size_t transit_strikes;
  double unmatched_lag_s;
  size_t unmatched_strikes;               /* of the latest AF_LANE_TRANSITS strikes */
  char transit_warning[AF_LANE_TEXT_MAX]; /* a systematic lag, in words; "" when none */
  char last_no_audio[AF_LANE_TEXT_MAX];   /* the latest strike without audio, and why */
  char last_late_apple[AF_LANE_TEXT_MAX]; /* the latest estimate that came too late */
  char last_unreliable[AF_LANE_TEXT_MAX]; /* "apple N: reason" */
  af_hammer_health_stats health;          /* the hammer over the latest strikes and its verdict
                                             (hammer_health.h): every measured strike feeds it */
} af_lane_stats;

typedef struct af_lane af_lane;

/* Makes every part (streams, detector, measurement, model, queue) from cfg
 * (which must outlive the lane). fn is called once per measured strike.
 * AF_EINVAL / AF_ENOMEM with *what naming the part that failed; *out NULL. */
af_status af_lane_create(const af_lane_config *cfg, af_lane_strike_fn *fn, void *user,
                         af_lane **out, const char **what);
void af_lane_destroy(af_lane *l); /* NULL-safe */

/* A force or an audio chunk, as sent (a force in V, force_unit, is turned
 * into newtons here: x / force_sensitivity_v_per_n, for the ring and the
 * detector alike). Returns the stream's verdict (a refused chunk
 * is counted in the stream and not used); *info (may be NULL) tells of gaps
 * and restarts. A force chunk runs the detector; both then measure what is
 * decided. */
af_chunk_verdict af_lane_force(af_lane *l, const af_chunk *c, int64_t now_ns,
                               af_ring_write_info *info);
af_chunk_verdict af_lane_audio(af_lane *l, const af_chunk *c, int64_t now_ns,
                               af_ring_write_info *info);

/* An apple estimate: its prediction (always filled; see prediction.h for the
 * statuses), remembered for the strikes that follow. */
af_status af_lane_apple(af_lane *l, const af_apple *a, int64_t now_ns, const af_prediction **out);

/* Measures what has become due on the clock (time-outs, stale audio). */
void af_lane_poll(af_lane *l, int64_t now_ns);

/* The configuration the lane was created with has been changed in place by
 * its owner (dynamic_reconfigure: criteria, thresholds, grades; never a size:
 * rates, rings, windows and the queue must stay as they were). The parts
 * that hold a copy are made anew: the measurement always, the strike
 * detector when its settings changed (it then learns its baseline again, a
 * warm-up of strike_baseline_time_constant_s; a strike in progress is
 * lost). Apples already predicted keep their prediction. Allocates (not per
 * chunk or strike). AF_OK; AF_ENOMEM / AF_EINVAL with *what naming the part,
 * the old parts kept: the owner then restores its configuration. */
af_status af_lane_reconfigured(af_lane *l, const char **what);

/* The recording has ended (desk tools): a strike still in the detector is
 * emitted (af_strike_flush), and every pending strike is measured now with
 * what there is (a window past the end of the audio: AF_AUDIO_STREAM_ENDED). */
void af_lane_finish(af_lane *l);

/* Forgets every chunk, apple and strike: the lane as af_lane_create left it
 * (streams and queue empty, counters and learned figures at their start,
 * the detector in its warm-up; a strike still pending or in the detector is
 * dropped, not reported), with the parts it made kept: for a tool or a test
 * that runs many recordings through one lane. The parts a reconfigure made
 * stay as it made them. No allocation. */
void af_lane_reset(af_lane *l);

/* Offline only: the detector's baseline and noise from the whole force
 * recording x[0..n) [N, or V with force_unit V: converted in a copy made
 * here] (af_strike_prime), before it is written from its
 * first sample, so that a strike a fraction of a millisecond after the start
 * of a triggered capture is measured. Statuses of af_strike_prime. */
af_status af_lane_prime_force(af_lane *l, const float *x, size_t n);

/* Offline, tap-only: the onset detector's noise floor from the whole audio
 * recording x[0..n) (af_onset_prime), so that a tap a few milliseconds
 * after the start of a triggered capture is found. Statuses of
 * af_onset_prime. */
af_status af_lane_prime_audio(af_lane *l, const float *x, size_t n);
const af_stream *af_lane_force_stream(const af_lane *l);
/* A force (force true) or audio chunk refused before it became an af_chunk
 * (on the wire: oversized, cut, empty), counted in its stream (see
 * af_stream_refuse). */
void af_lane_refuse(af_lane *l, bool force, bool oversized, const char *why);
const af_stream *af_lane_audio_stream(const af_lane *l);
const af_strike *af_lane_detector(const af_lane *l);
size_t af_lane_pending(const af_lane *l);
const af_lane_stats *af_lane_get_stats(const af_lane *l);
/* The modulus factor learned from this lane's reliable strikes
 * (factor_learn.h): estimate, 95 % interval, count, applied value. */
const af_factor_learn_state *af_lane_factor(const af_lane *l);

#ifdef __cplusplus
}
#endif
#endif
