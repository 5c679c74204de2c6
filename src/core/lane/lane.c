/* lane.c — one station lane without ROS (see lane.h). */
#include "lane.h"

#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "audio_clip.h"
#include "audio_lag.h"
#include "median.h"
#include "samples.h"
#include "onset.h"
#include "text.h"

/* AppleEstimates remembered for the match: a few seconds of a line. */
#define AF_LANE_APPLES 16
/* Force gaps remembered (the time after each): a strike among lost samples
 * leaves its apple without a strike, and the next strike must not take it
 * silently (at 80x replay, a dropped chunk's strike). */
#define AF_LANE_GAPS 16
/* Strikes over which the observed transit (strike minus estimate stamp) is
 * summarised: enough for a stable median, recent enough to follow a camera
 * that starts stamping late. */
#define AF_LANE_TRANSITS 32
/* A systematic lag is named once this many of the latest AF_LANE_TRANSITS
 * strikes found no estimate in their window. */
#define AF_LANE_UNMATCHED_WARN 8
/* Strikes remembered after their report, for estimates that come late. */
#define AF_LANE_REPORTED 16
/* A strike's impulse this far above the hammer's recent clean strikes [-]
 * (v0 from the impulse: the rig holds it within a few per cent, an apple's
 * restitution moves it by less), judged once the window holds this many. */
#define AF_LANE_BOUNCE_EXCESS 0.08
#define AF_LANE_BOUNCE_STRIKES 8
/* A detector made anew by a reconfigure is primed from this much of the
 * latest force [s]: several of its baseline windows, a fraction of a ring. */
#define AF_LANE_PRIME_S 0.5
/* Apple ids judged as counting up after this many steps of one; a jump of
 * more than AF_LANE_ID_GAP_MAX is a new numbering, not lost estimates. */
#define AF_LANE_ID_STEPS_MIN 8
#define AF_LANE_ID_GAP_MAX 1000u

typedef struct {
  af_strike_event ev; /* ev.pulse_n points at pulse */
  double *pulse;      /* pulse_capacity_samples, preallocated */
  int64_t start_ns;   /* contact start */
  int64_t queued_ns;  /* lane clock when queued, for the time-outs */
  uint64_t refused;   /* refused (non-finite) force samples in the measured span */
  bool lag_done;      /* its audio lag measured, or given up */
  double lag_s;       /* the sound's onset by the audio's stamps minus the contact start [s];
                         NaN: not measured */
  double applied_s;   /* the audio lag its window was moved by [s] */
  char frame_id[AF_STREAM_FRAME_MAX];
} af_pending;

/* A strike reported: when, and to which estimate (0: none). */
typedef struct {
  int64_t start_ns, apple_stamp_ns;
  uint32_t apple_id;
} af_lane_reported;

typedef struct {
  bool used;
  af_apple apple;
  af_prediction prediction; /* prediction.valid false: refused (prediction.why) */
  uint64_t strikes;         /* strikes matched to it so far */
  uint64_t order;           /* 1 for the first estimate received, 2 for the next ... */
  int64_t last_strike_ns;
  uint32_t late_after; /* its estimate came after its strike went to this apple (0: no) */
} af_apple_slot;

/* The audio of a pending strike: ready, to be waited for, or not coming. */
typedef enum { AF_WAIT = 0, AF_READY, AF_NONE } af_decision;

/* The parts af_lane_create makes (kept by af_lane_reset), then the state:
 * every field from `head` on is a memory of the streams, zeroed by
 * lane_clear at create and at every reset, so that a field added below is
 * reset without being named. */
struct af_lane {
  const af_lane_config *cfg;
  const af_strikes_config *mc;
  af_lane_strike_fn *fn;
  void *user;
  af_stream force, audio; /* reset by af_stream_reset: their counts are state too */
  af_strike *detector;
  af_strike_config detector_cfg; /* what the detector was made with */
  af_measure *measure;
  af_fastpath *model;       /* the prediction's: a handle on the process's shared table */
  af_factor_learn *factor;  /* the modulus factor learned from the reliable strikes */
  double factor_configured; /* cfg->model.modulus_factor when last seen (reconfigure) */
  af_hammer_health *health; /* the hammer's running statistics (hammer_health.h) */
  af_onset *onset;          /* tap-only: the strikes found in the audio (onset.h) */
  af_pending *pending;
  double *pulses;
  float *audio_buf, *noise_buf;
  float *lag_buf; /* audio searched for a strike's onset: lag_cap samples */
  size_t lag_cap;
  /* --- the state (lane_clear): nothing above this line --- */
  size_t head, count;
  af_apple_slot apples[AF_LANE_APPLES];
  size_t apple_next;
  uint64_t apples_received; /* estimates so far: the slots' order */
  int64_t now_ns;
  int64_t force_gap_ns[AF_LANE_GAPS]; /* stamps of the chunks after force gaps or restarts */
  size_t force_gaps;                  /* written so far (the newest AF_LANE_GAPS kept) */
  bool finished;
  af_lane_strike out; /* callback scratch */
  af_lane_stats stats;
  af_prediction refused;                /* the prediction of the latest estimate refused before
                                           the model */
  double transit_s[AF_LANE_TRANSITS];   /* strike minus stamp of the latest matched strikes [s] */
  double unmatched_s[AF_LANE_TRANSITS]; /* ... of the nearest estimate, unmatched strikes [s] */
  uint64_t transits, unmatched;         /* written so far into each */
  bool recent_unmatched[AF_LANE_TRANSITS]; /* the latest strikes: without an apple? */
  uint64_t recent;
  af_audio_lag lag;      /* the audio clock's lag behind the force's (audio_lag.h) */
  int64_t last_start_ns; /* the previous strike's contact start, for the search's reach */
  double v0_ref[AF_LANE_BOUNCE_STRIKES]; /* v0 from the impulse of the latest clean strikes */
  size_t v0_count;
  bool any_start;
  uint32_t last_id; /* the latest estimate's apple_id */
  bool last_id_set;
  uint64_t id_steps, id_steps_one; /* steps up between ids, and those of one */
  uint64_t force_origin; /* the force stream's first index (after a restart: that chunk's) */
  bool force_origin_set;
  af_lane_reported reported[AF_LANE_REPORTED]; /* the latest strikes reported */
  size_t reported_n;                           /* written so far */
};

/* --- the apple match -------------------------------------------------------- */

/* The lag [s] of a strike at t_ns behind the stamp of estimate a. */
static double lag_s(const af_apple_slot *a, int64_t t_ns)
{
  return (double)(t_ns - a->apple.stamp_ns) * 1e-9;
}

/* One apple a recording (the desk tools' single_apple): the newest apple
 * stamped at or before t_ns and at most apple_stale_after_s before it. */
static af_apple_slot *match_newest(af_lane *l, int64_t t_ns, const af_apple_slot **tie)
{
  const int64_t stale_ns = (int64_t)llround(l->mc->apple_stale_after_s * 1e9);
  af_apple_slot *best = NULL;
  *tie = NULL;
  for (size_t k = 0; k < AF_LANE_APPLES; k++) {
    af_apple_slot *a = &l->apples[k];
    if (!a->used || a->apple.stamp_ns > t_ns || t_ns - a->apple.stamp_ns > stale_ns)
      continue;
    if (best == NULL || a->apple.stamp_ns > best->apple.stamp_ns) {
      best = a;
      *tie = NULL;
    } else if (a->apple.stamp_ns == best->apple.stamp_ns &&
               a->apple.apple_id != best->apple.apple_id) {
      /* Two apples at one stamp: the match is ambiguous. The later
       * received is taken and the other named. */
      const bool later = a->order > best->order;
      *tie = later ? best : a;
      best = later ? a : best;
    } else if (a->apple.stamp_ns == best->apple.stamp_ns && a->order > best->order) {
      best = a; /* the same apple sent again: its newest estimate */
    }
  }
  return best;
}

/* A line: the estimate whose stamp + apple_transit_s lies nearest t_ns,
 * within apple_transit_tolerance_s (the latest received on a tie, an apple
 * sent again); NULL when none. *tie: another apple in the window too. With
 * several apples between the camera and the hammer, the newest estimate
 * before a strike is another apple's: only the transit tells them apart. */
static af_apple_slot *match_transit(af_lane *l, int64_t t_ns, const af_apple_slot **tie)
{
  const double transit_s = l->mc->apple_transit_s, tol_s = l->mc->apple_transit_tolerance_s;
  af_apple_slot *best = NULL;
  double best_d = INFINITY;
  *tie = NULL;
  for (size_t k = 0; k < AF_LANE_APPLES; k++) {
    af_apple_slot *a = &l->apples[k];
    const double d = a->used ? fabs(lag_s(a, t_ns) - transit_s) : INFINITY;
    if (d > tol_s)
      continue;
    if (best == NULL || d < best_d || (d == best_d && a->order > best->order)) {
      best = a;
      best_d = d;
    }
  }
  for (size_t k = 0; best != NULL && k < AF_LANE_APPLES; k++) {
    const af_apple_slot *a = &l->apples[k];
    if (a->used && a->apple.apple_id != best->apple.apple_id &&
        fabs(lag_s(a, t_ns) - transit_s) <= tol_s)
      *tie = a;
  }
  return best;
}

static af_apple_slot *match_apple(af_lane *l, int64_t t_ns, const af_apple_slot **tie)
{
  return l->mc->single_apple ? match_newest(l, t_ns, tie) : match_transit(l, t_ns, tie);
}

/* The estimate stamped nearest t_ns in time, within apple_stale_after_s
 * beyond the transit window; NULL when none: what an unmatched strike names,
 * so that a camera stamping late or early shows its lag. */
/* The time [ns] just after the newest sample of s (its own data's clock). */
static int64_t data_end_ns(const af_stream *s)
{
  return af_stream_time_of_ns(s, af_ring_end(s->ring), 0.0);
}

/* How far from a strike an estimate can still bear on it [s]: its transit
 * window and apple_stale_after_s beyond. */
static double apple_reach_s(const af_strikes_config *mc)
{
  return fabs(mc->apple_transit_s) + mc->apple_transit_tolerance_s + mc->apple_stale_after_s;
}

static const af_apple_slot *nearest_apple(const af_lane *l, int64_t t_ns)
{
  const double reach_s = apple_reach_s(l->mc);
  const af_apple_slot *best = NULL;
  for (size_t k = 0; k < AF_LANE_APPLES; k++) {
    const af_apple_slot *a = &l->apples[k];
    if (a->used && fabs(lag_s(a, t_ns)) <= reach_s &&
        (best == NULL || fabs(lag_s(a, t_ns)) < fabs(lag_s(best, t_ns))))
      best = a;
  }
  return best;
}

/* Whether an estimate stamped after window_end_ns has come (estimates come
 * in stamp order, so none in the window can still come), within reach of
 * the strike at start_ns: an estimate stamped far off (a clock wrong by
 * hours, accepted before any data could show it) must not decide for the
 * strikes after it. */
static bool estimate_after(const af_lane *l, int64_t window_end_ns, int64_t start_ns)
{
  const int64_t reach_ns = start_ns + (int64_t)llround(apple_reach_s(l->mc) * 1e9);
  for (size_t k = 0; k < AF_LANE_APPLES; k++) {
    const af_apple_slot *a = &l->apples[k];
    if (a->used && a->apple.stamp_ns > window_end_ns && a->apple.stamp_ns <= reach_ns)
      return true;
  }
  return false;
}

/* Whether the apple of p can still change: not once an estimate stamped
 * after its window has come (estimates arrive in stamp order), nor once
 * apple_wait_s has passed after p, on the lane's clock since it was queued
 * or in the force stream's own data since its contact start, whichever
 * comes first: a clock that disagrees with the stamps, or stops (a replay's
 * simulated time after the bag), must not hold a strike forever. */
static bool apple_decided(const af_lane *l, const af_pending *p)
{
  const af_strikes_config *mc = l->mc;
  const int64_t window_end_ns =
      mc->single_apple
          ? p->start_ns
          : p->start_ns -
                (int64_t)llround((mc->apple_transit_s - mc->apple_transit_tolerance_s) * 1e9);
  if (l->finished || estimate_after(l, window_end_ns, p->start_ns))
    return true;
  const double wait_s = mc->apple_wait_s;
  const double data_after_s = (double)(data_end_ns(&l->force) - p->start_ns) * 1e-9;
  return (double)(l->now_ns - p->queued_ns) * 1e-9 >= wait_s || data_after_s >= wait_s;
}

/* An estimate that comes after a strike it should have taken was reported
 * (against another apple, or none) came too late: say so; a report cannot
 * be taken back. One apple a recording: a strike stamped after it went to
 * an older estimate. A line: a strike lay in its transit window. */
static uint32_t check_late(af_lane *l, const af_apple *a)
{
  const af_strikes_config *mc = l->mc;
  const af_lane_reported *hit = NULL;
  for (size_t k = 0; k < AF_LANE_REPORTED && k < l->reported_n; k++) {
    const af_lane_reported *r = &l->reported[k];
    const double lag = (double)(r->start_ns - a->stamp_ns) * 1e-9;
    const bool late = mc->single_apple
                          ? r->apple_id != 0 && r->apple_stamp_ns < a->stamp_ns && lag >= 0.0
                          : r->apple_id != a->apple_id &&
                                fabs(lag - mc->apple_transit_s) <= mc->apple_transit_tolerance_s;
    if (late && (hit == NULL || r->start_ns > hit->start_ns))
      hit = r;
  }
  if (hit == NULL)
    return 0;
  l->stats.late_apples++;
  if (hit->apple_id == 0)
    af_text(l->stats.last_late_apple, sizeof l->stats.last_late_apple,
            "apple %u's estimate arrived after its strike at %.3f s was reported without an "
            "apple",
            a->apple_id, (double)hit->start_ns * 1e-9);
  else
    af_text(l->stats.last_late_apple, sizeof l->stats.last_late_apple,
            "apple %u's estimate arrived after a strike it should have taken was reported "
            "against apple %u",
            a->apple_id, hit->apple_id);
  return hit->apple_id;
}

/* Estimates that never came: on a line whose apple ids count up by one (8
 * steps of one, at least 9 in 10 of all), an id further on than the next
 * says how many were lost on the way (a subscriber queue that overflowed, a
 * camera that dropped frames); counted and said. Ids that do not count up
 * (a tracker's, a hash) are never judged. */
static void check_skipped(af_lane *l, uint32_t id)
{
  af_lane_stats *s = &l->stats;
  if (l->last_id_set && id > l->last_id) {
    const uint32_t step = id - l->last_id;
    /* Judged on the steps before this one. */
    const bool counting =
        l->id_steps_one >= AF_LANE_ID_STEPS_MIN && 10 * l->id_steps_one >= 9 * l->id_steps;
    l->id_steps_one += step == 1;
    l->id_steps += 1;
    if (counting && step > 1 && step <= AF_LANE_ID_GAP_MAX) {
      s->apples_skipped += step - 1;
      af_text(s->last_apples_skipped, sizeof s->last_apples_skipped,
              "apple estimates %u..%u never came (apple %u followed apple %u): a dropped message "
              "or a camera that skipped them",
              l->last_id + 1, id - 1, id, l->last_id);
    }
  }
  l->last_id = id;
  l->last_id_set = true;
}

/* Why estimate a cannot be used ("" when it can): apple_id 0 is the
 * StrikeReport's "no apple", and a stamp further than apple_stale_after_s
 * from the newest data (force; tap-only: audio) is a clock far off, which
 * would take or hold strikes' matches. Before any data there is no strike
 * to match and no clock to judge by: the estimate is taken (its prediction
 * stands) and estimate_after keeps a far one from deciding anything. */
static bool refuse_apple(af_lane *l, const af_apple *a, char *why, size_t len)
{
  const af_stream *data = l->mc->tap_only ? &l->audio : &l->force;
  why[0] = '\0';
  const int64_t ref_ns = data->seen ? data_end_ns(data) : 0;
  const char *ref = l->mc->tap_only ? "the newest audio sample" : "the newest force sample";
  const double off_s = (double)(a->stamp_ns - ref_ns) * 1e-9;
  if (a->apple_id == 0)
    af_text(why, len, "apple_id 0 is reserved for \"no apple\"");
  else if (data->seen && fabs(off_s) > l->mc->apple_stale_after_s)
    af_text(why, len,
            "stamped %.3f s %s %s (apple_stale_after_s %g s): a clock that far off would "
            "mismatch strikes",
            fabs(off_s), off_s > 0.0 ? "after" : "before", ref, l->mc->apple_stale_after_s);
  return why[0] != '\0';
}

/* A refused estimate: counted and said, its prediction invalid, no slot
 * taken, so that it changes no other strike's match. */
static af_status refuse(af_lane *l, const af_apple *a, const char *why, const af_prediction **out)
{
  l->stats.apples++;
  l->stats.apples_refused++;
  l->stats.apples_implausible++;
  af_text(l->stats.last_implausible_apple, sizeof l->stats.last_implausible_apple,
          "apple %u refused: %s", a->apple_id, why);
  memset(&l->refused, 0, sizeof l->refused);
  l->refused.valid = false;
  af_text(l->refused.why, sizeof l->refused.why, "AppleEstimate refused: %s", why);
  if (out)
    *out = &l->refused;
  return AF_EINVAL;
}

af_status af_lane_apple(af_lane *l, const af_apple *a, int64_t now_ns, const af_prediction **out)
{
  l->now_ns = now_ns;
  char why[AF_LANE_TEXT_MAX];
  if (refuse_apple(l, a, why, sizeof why))
    return refuse(l, a, why, out);
  check_skipped(l, a->apple_id);
  const uint32_t late_after = check_late(l, a);
  af_apple_slot *s = &l->apples[l->apple_next];
  l->apple_next = (l->apple_next + 1) % AF_LANE_APPLES;
  memset(s, 0, sizeof *s);
  s->late_after = late_after;
  s->used = true;
  s->order = ++l->apples_received;
  s->apple = *a;
  const int64_t t0_ns = af_stage_begin(l->mc->measure.stages);
  af_status st = af_prediction_execute_fast(l->model, l->cfg, a, &s->prediction);
  af_stage_end(l->mc->measure.stages, AF_STAGE_PREDICT, t0_ns);
  l->stats.apples++;
  l->stats.apples_refused += st != AF_OK;
  if (out)
    *out = &s->prediction;
  return st;
}

/* --- the audio window ----------------------------------------------------------- */

/* The noise reference: the audio ending a guard before the contact, when held. */
static size_t read_noise(af_lane *l, const af_pending *p)
{
  const af_stream *s = &l->audio;
  const size_t nn = l->mc->noise_window_samples;
  const int64_t lag_ns = (int64_t)llround(p->applied_s * 1e9);
  uint64_t i;
  double f;
  if (nn == 0 || !af_stream_pos_at(s, p->start_ns + lag_ns, &i, &f))
    return 0;
  /* It ends at i + f - guard: j1 = floor of that, back from i. */
  const double back = l->mc->measure.noise_guard_s * l->mc->measure.response.sample_rate_hz - f;
  const uint64_t b = back > 0.0 ? (uint64_t)ceil(back) : 0;
  if (b > i || i - b < nn)
    return 0;
  const uint64_t j1 = i - b, j0 = j1 - nn;
  if (j0 < af_ring_begin(s->ring) || j1 > af_ring_end(s->ring) ||
      af_ring_read(s->ring, j0, nn, l->noise_buf) != AF_OK ||
      af_samples_nonfinite(l->noise_buf, nn) > 0)
    return 0;
  return nn;
}

/* How long a strike's audio is waited for [s]: the window is due delay +
 * window after the strike; after that it gets the stale time-out (a stream
 * far behind, or stamps that disagree). */
static double audio_wait_s(const af_lane *l)
{
  const af_measure_config *mc = &l->mc->measure;
  return l->cfg->stream_stale_after_s + mc->audio_delay_s + mc->audio_window_s;
}

/* Whether p's audio can no longer be waited for. */
static bool audio_timed_out(const af_lane *l, const af_pending *p)
{
  return l->finished || (double)(l->now_ns - p->queued_ns) * 1e-9 > audio_wait_s(l);
}

/* Whether p's audio window can be read now (into audio_buf), must be waited
 * for, or will not come (v says why). */
static af_decision audio_for(af_lane *l, const af_pending *p, af_verdict *v)
{
  const af_stream *s = &l->audio;
  const af_measure_config *mc = &l->mc->measure;
  const double wait_s = audio_wait_s(l);
  const bool timed_out = audio_timed_out(l, p);
  const size_t n = l->mc->audio_window_samples;
  v->audio_seconds = wait_s;
  if (!s->seen) {
    v->audio_cause = l->finished ? AF_AUDIO_NOT_GIVEN : AF_AUDIO_NONE_RECEIVED;
    return timed_out ? AF_NONE : AF_WAIT;
  }
  if (!l->finished && af_stream_stale(s, l->now_ns, l->cfg->stream_stale_after_s)) {
    v->audio_cause = AF_AUDIO_STREAM_STALE;
    v->audio_seconds = l->cfg->stream_stale_after_s;
    return AF_NONE;
  }
  const int64_t delay_ns = (int64_t)llround((mc->audio_delay_s + p->applied_s) * 1e9);
  uint64_t i0;
  double f;
  if (!af_stream_pos_at(s, p->start_ns + delay_ns, &i0, &f)) {
    const double first = af_stream_index_at(s, p->start_ns + delay_ns);
    if (first < -0.5) {
      v->audio_cause = AF_AUDIO_BEFORE_STREAM;
      v->audio_seconds = -first / s->cfg->sample_rate_hz;
      return AF_NONE;
    }
    i0 = 0; /* within half a sample of the first: that one */
  } else {
    i0 += f > 1e-6; /* the first sample at or after the window's start */
  }
  const uint64_t begin = af_ring_begin(s->ring), end = af_ring_end(s->ring);
  v->audio_first = i0;
  v->audio_last = i0 + n;
  v->audio_end = end;
  if (i0 + n > end) {
    v->audio_cause = l->finished ? AF_AUDIO_STREAM_ENDED : AF_AUDIO_NOT_RECEIVED;
    v->audio_seconds = (double)(l->now_ns - p->queued_ns) * 1e-9;
    return timed_out ? AF_NONE : AF_WAIT;
  }
  v->audio_seconds = s->cfg->buffer_s;
  v->audio_cause = AF_AUDIO_LEFT_RING;
  if (i0 < begin)
    return AF_NONE;
  v->audio_cause = AF_AUDIO_UNREADABLE;
  if (af_ring_read(s->ring, i0, n, l->audio_buf) != AF_OK)
    return AF_NONE;
  v->n_audio = af_samples_nonfinite(l->audio_buf, n);
  v->audio_cause = AF_AUDIO_LOST_IN_WINDOW;
  const uint64_t refused = af_stream_refused_in(s, i0, n);
  if (refused > 0) { /* the samples were there, but not finite */
    v->audio_cause = AF_AUDIO_REFUSED_IN_WINDOW;
    v->n_audio = (size_t)refused;
  }
  return v->n_audio > 0 ? AF_NONE : AF_READY;
}

/* --- the audio clock's lag ----------------------------------------------------- */

/* Searches p's sound onset within +-h of the contact start moved by the
 * applied lag, h = audio_lag_max_s, at most half the time since the previous
 * strike (whose own sound must not be taken); the lag then feeds the median.
 * AF_WAIT while the audio of the search has not come. */
static af_decision measure_lag(af_lane *l, af_pending *p)
{
  const af_stream *s = &l->audio;
  p->applied_s = l->lag.applied_s;
  if (l->mc->tap_only || !s->seen) { /* tap-only: the onset is the strike */
    p->lag_done = true;
    return AF_READY;
  }
  const double fs = s->cfg->sample_rate_hz;
  const size_t block = (size_t)fmax(1.0, round(AF_AUDIO_LAG_BLOCK_S * fs));
  double h_s = l->mc->audio_lag_max_s;
  if (l->any_start)
    h_s = fmin(h_s, 0.5e-9 * (double)(p->start_ns - l->last_start_ns));
  const int64_t centre_ns = p->start_ns + (int64_t)llround(p->applied_s * 1e9);
  const int64_t h_ns = (int64_t)llround(h_s * 1e9);
  uint64_t i_lo, i_hi;
  double f;
  if (!af_stream_pos_at(s, centre_ns + h_ns, &i_hi, &f)) { /* all before the stream */
    p->lag_done = true;
    return AF_READY;
  }
  const uint64_t ref = (uint64_t)(AF_AUDIO_LAG_REF_BLOCKS * block);
  const uint64_t hi = i_hi + 1 + block;
  /* Waited for on the lane's clock, or until the force's own data is
   * apple_wait_s past the search (a replay's clock stops with the bag). */
  const double force_past_s = (double)(data_end_ns(&l->force) - (centre_ns + h_ns)) * 1e-9;
  if (hi > af_ring_end(s->ring) && !audio_timed_out(l, p) && !(force_past_s >= l->mc->apple_wait_s))
    return AF_WAIT;
  p->lag_done = true;
  const uint64_t lo =
      af_stream_pos_at(s, centre_ns - h_ns, &i_lo, &f) && i_lo > ref ? i_lo - ref : 0;
  const uint64_t begin = af_ring_begin(s->ring), end = af_ring_end(s->ring);
  const uint64_t i0 = lo > begin ? lo : begin, last = hi < end ? hi : end;
  if (last <= i0 || last - i0 < ref + block)
    return AF_READY;
  const size_t n = last - i0 < l->lag_cap ? (size_t)(last - i0) : l->lag_cap;
  size_t at;
  if (af_ring_read(s->ring, i0, n, l->lag_buf) != AF_OK ||
      af_samples_nonfinite(l->lag_buf, n) > 0 || !af_audio_onset_find(l->lag_buf, n, block, &at)) {
    l->stats.lag_no_onset++;
    return AF_READY;
  }
  p->lag_s = (double)(af_stream_time_of_ns(s, i0 + at, 0.0) - p->start_ns) * 1e-9;
  const bool moved = af_audio_lag_push(&l->lag, p->lag_s, l->mc->audio_lag_learn);
  /* Until the median is stable, a strike whose own onset was found is
   * aligned by its own lag (the first strikes of a shift, a lag that moved). */
  p->applied_s = l->lag.stable || !l->mc->audio_lag_learn   ? l->lag.applied_s
                 : fabs(p->lag_s) > AF_AUDIO_LAG_DEADBAND_S ? p->lag_s
                                                            : 0.0;
  if (moved) {
    l->stats.lag_moves++;
    af_text(l->stats.lag_warning, sizeof l->stats.lag_warning,
            "the audio lag moved: a strike's sound came %.1f ms after its contact by the audio's "
            "stamps, the median was %.1f ms",
            1e3 * p->lag_s, 1e3 * l->lag.median_s);
  }
  l->stats.lag_median_s = l->lag.median_s;
  l->stats.lag_mad_s = l->lag.mad_s;
  l->stats.lag_applied_s = l->lag.applied_s;
  l->stats.lag_strikes = l->lag.n;
  return AF_READY;
}

/* A strike whose own sound lies off the window it was judged by (the lag
 * not yet learned, or moved): its 0S2 was read where the ring was not, so
 * the fruit must not be blamed. */
static void check_lag(af_lane *l, const af_pending *p, af_verdict *v)
{
  if (isnan(p->lag_s) || fabs(p->lag_s - p->applied_s) < AF_AUDIO_LAG_MOVE_S)
    return;
  v->flags |= AF_VERDICT_CLOCK_FAULT;
  af_text(v->clock_why, sizeof v->clock_why,
          "its sound's onset lies %.1f ms after the contact by the audio's stamps, its audio "
          "window was taken %.1f ms after (%s)",
          1e3 * p->lag_s, 1e3 * p->applied_s,
          !l->mc->audio_lag_learn ? "audio_lag_learn false" : "the audio lag moved");
  l->stats.clock_faulted++;
}

/* --- one strike ------------------------------------------------------------------- */

/* Tap-only: the strike from its audio alone, judged against the prediction
 * for the configured hammer (measure.h, af_measure_execute_tap). */
static af_status measure_tap(af_lane *l, const af_prediction *pr, const af_measure_apple *apple,
                             size_t n_audio, size_t n_noise, af_measure_report *r)
{
  return af_measure_execute_tap(l->measure, apple, &pr->result, n_audio ? l->audio_buf : NULL,
                                n_audio, n_noise ? l->noise_buf : NULL, n_noise, r);
}

/* The measurement of p against its apple slot a (NULL: none). */
static void measure_with_apple(af_lane *l, const af_pending *p, af_apple_slot *a, size_t n_audio,
                               size_t n_noise, af_verdict *lane_v)
{
  af_measure_report *r = &l->out.report;
  const af_prediction *pr = a ? &a->prediction : NULL;
  af_status st = AF_EINVAL;
  if (pr && pr->valid) {
    af_measure_apple apple = {pr->params, l->cfg->modulus_min_pa, l->cfg->modulus_max_pa};
    apple.model.modulus_factor = l->out.modulus_factor;
    st = l->mc->tap_only
             ? measure_tap(l, pr, &apple, n_audio, n_noise, r)
             : af_measure_execute(l->measure, &p->ev, &apple, n_audio ? l->audio_buf : NULL,
                                  n_audio, n_noise ? l->noise_buf : NULL, n_noise, r);
    if (st != AF_OK) {
      l->stats.measure_errors++;
      lane_v->flags |= AF_VERDICT_MEASURE_FAILED;
      lane_v->measure_status = st;
    }
  }
  if (st != AF_OK && af_measure_execute_pulse(l->measure, &p->ev, l->cfg->model.band_level,
                                              l->cfg->model.lobe, r) != AF_OK)
    l->stats.measure_errors++;
  r->tap_only = l->mc->tap_only;
}

/* Adds the lane's flags to the measurement's verdict and words it again. */
static void merge_verdict(af_measure_report *r, const af_verdict *lane_v)
{
  af_verdict *v = &r->verdict;
  const uint32_t lane_flags = AF_VERDICT_NO_APPLE | AF_VERDICT_NO_PREDICTION |
                              AF_VERDICT_APPLE_DOUBTFUL | AF_VERDICT_MEASURE_FAILED |
                              AF_VERDICT_REFUSED_SAMPLES | AF_VERDICT_AUDIO_CLIPPED |
                              AF_VERDICT_CLOCK_FAULT;
  v->flags |= lane_v->flags & lane_flags;
  v->refused_samples = lane_v->refused_samples;
  v->audio_clip_samples = lane_v->audio_clip_samples;
  v->audio_clip_tops = lane_v->audio_clip_tops;
  v->audio_clip_max = lane_v->audio_clip_max;
  v->audio_clip_min = lane_v->audio_clip_min;
  r->audio_clipped = (v->flags & AF_VERDICT_AUDIO_CLIPPED) != 0;
  if ((v->flags & AF_VERDICT_REFUSED_SAMPLES) && (v->flags & AF_VERDICT_LOST_SAMPLES)) {
    /* The refused samples read as lost to the detector: said once, as refused. */
    v->lost_samples -= v->lost_samples < v->refused_samples ? v->lost_samples : v->refused_samples;
    if (v->lost_samples == 0)
      v->flags &= ~(uint32_t)AF_VERDICT_LOST_SAMPLES;
  }
  v->apple_id = lane_v->apple_id;
  v->apple_stale_s = lane_v->apple_stale_s;
  v->apple_transit_s = lane_v->apple_transit_s;
  v->apple_tolerance_s = lane_v->apple_tolerance_s;
  v->nearest_apple_id = lane_v->nearest_apple_id;
  v->nearest_apple_lag_s = lane_v->nearest_apple_lag_s;
  v->measure_status = lane_v->measure_status;
  memcpy(v->apple_why, lane_v->apple_why, sizeof v->apple_why);
  memcpy(v->doubtful_why, lane_v->doubtful_why, sizeof v->doubtful_why);
  memcpy(v->clock_why, lane_v->clock_why, sizeof v->clock_why);
  if (lane_v->flags & AF_VERDICT_NO_AUDIO) { /* the lane knows why there is none */
    v->flags |= AF_VERDICT_NO_AUDIO;
    v->audio_cause = lane_v->audio_cause;
    v->audio_first = lane_v->audio_first;
    v->audio_last = lane_v->audio_last;
    v->audio_end = lane_v->audio_end;
    v->audio_seconds = lane_v->audio_seconds;
    v->n_audio = lane_v->n_audio;
    v->queue_size = lane_v->queue_size;
  }
  r->reliable = r->reliable && v->flags == 0;
  af_verdict_format(v, r->reason, sizeof r->reason);
}

/* The stamp [ns] of a remembered force gap in (from_ns, to_ns], or 0: the
 * newest AF_LANE_GAPS gaps are kept, older ones are long settled. */
static int64_t force_lost_between(const af_lane *l, int64_t from_ns, int64_t to_ns)
{
  for (size_t k = 0; k < AF_LANE_GAPS && k < l->force_gaps; k++) {
    if (l->force_gap_ns[k] > from_ns && l->force_gap_ns[k] <= to_ns)
      return l->force_gap_ns[k];
  }
  return 0;
}

/* The apple flags of p: none, refused, or doubtful. */
static af_apple_slot *apple_flags(af_lane *l, const af_pending *p, af_verdict *v)
{
  const af_apple_slot *tie;
  af_apple_slot *a = match_apple(l, p->start_ns, &tie);
  if (a == NULL) {
    v->flags |= AF_VERDICT_NO_APPLE;
    v->apple_stale_s = l->mc->apple_stale_after_s;
    if (!l->mc->single_apple) {
      v->apple_transit_s = l->mc->apple_transit_s;
      v->apple_tolerance_s = l->mc->apple_transit_tolerance_s;
      const af_apple_slot *n = nearest_apple(l, p->start_ns);
      v->nearest_apple_id = n ? n->apple.apple_id : 0;
      v->nearest_apple_lag_s = n ? lag_s(n, p->start_ns) : NAN;
    }
    return NULL;
  }
  v->apple_id = a->apple.apple_id;
  if (!a->prediction.valid) {
    v->flags |= AF_VERDICT_NO_PREDICTION;
    af_text(v->apple_why, sizeof v->apple_why, "%s", a->prediction.why);
  } else if (tie != NULL && l->mc->single_apple) {
    v->flags |= AF_VERDICT_APPLE_DOUBTFUL;
    af_text(v->doubtful_why, sizeof v->doubtful_why,
            "apple %u has the same stamp %.9f s; the strike may be either's", tie->apple.apple_id,
            (double)a->apple.stamp_ns * 1e-9);
  } else if (tie != NULL) {
    v->flags |= AF_VERDICT_APPLE_DOUBTFUL;
    af_text(v->doubtful_why, sizeof v->doubtful_why,
            "apple %u, stamped %.3f s before the strike, fits apple_transit_s %g +- %g s too; "
            "the strike may be either's",
            tie->apple.apple_id, lag_s(tie, p->start_ns), l->mc->apple_transit_s,
            l->mc->apple_transit_tolerance_s);
  } else if (a->strikes > 0 && !l->mc->single_apple) {
    v->flags |= AF_VERDICT_APPLE_DOUBTFUL;
    af_text(v->doubtful_why, sizeof v->doubtful_why,
            "already struck %.3f s before; this strike's own estimate may be missing",
            (double)(p->start_ns - a->last_strike_ns) * 1e-9);
  } else if (a->late_after != 0 && !l->mc->single_apple) {
    /* Its estimate came late, after its own strike had gone to another
     * apple: this strike may well be the next apple's. */
    v->flags |= AF_VERDICT_APPLE_DOUBTFUL;
    af_text(v->doubtful_why, sizeof v->doubtful_why,
            "its estimate came after its own strike was judged against apple %u", a->late_after);
  } else if (!l->mc->single_apple) {
    /* Not struck yet, but force samples were lost after its estimate: its
     * own strike may have been among them, and this one another apple's. */
    /* Its own strike could only have been in its transit window. */
    const int64_t from_ns =
        a->apple.stamp_ns +
        (int64_t)llround((l->mc->apple_transit_s - l->mc->apple_transit_tolerance_s) * 1e9);
    const int64_t g = force_lost_between(l, from_ns, p->start_ns);
    if (g != 0) {
      v->flags |= AF_VERDICT_APPLE_DOUBTFUL;
      af_text(v->doubtful_why, sizeof v->doubtful_why,
              "force samples were lost %.3f s after its estimate; its own strike may be "
              "among them",
              (double)(g - a->apple.stamp_ns) * 1e-9);
    }
  }
  return a;
}

/* The strike's figures for the hammer health: the detector's pulse, the
 * fit's v0 and e; clean when nothing spoilt its impulse. */
static void watch_hammer(af_lane *l, const af_pending *p, const af_lane_strike *o)
{
  if (l->mc->tap_only) /* no pulse: nothing to watch */
    return;
  const af_strike_event *ev = &p->ev;
  const af_hammer_strike h = {
      .impulse_n_s = ev->impulse_n_s,
      .contact_time_s = ev->contact_time_s,
      .peak_force_n = ev->peak_force_n,
      .baseline_n = ev->baseline_n,
      .noise_rms_n = ev->noise_rms_n,
      .fitted_velocity_m_s = o->report.fitted_velocity_m_s,
      .fitted_restitution = o->report.fitted_restitution,
      .clipped = ev->clipped,
      .clean = !o->report.double_hit && !ev->clipped && !ev->truncated && ev->lost_samples == 0 &&
               p->refused == 0,
  };
  (void)af_hammer_health_push(l->health, &h); /* both pointers are the lane's own */
  l->stats.health = *af_hammer_health_get_stats(l->health);
}

static void count(af_lane *l, const af_pending *p, const af_lane_strike *o)
{
  af_lane_stats *s = &l->stats;
  watch_hammer(l, p, o);
  const uint32_t f = o->report.verdict.flags;
  s->strikes++;
  s->double_hits += o->report.double_hit;
  s->clipped += p->ev.clipped;
  s->truncated += p->ev.truncated;
  s->lost_force_samples += p->ev.lost_samples;
  s->no_resonance += isnan(o->report.resonance_hz);
  s->no_apple += (f & (AF_VERDICT_NO_APPLE | AF_VERDICT_NO_PREDICTION)) != 0;
  s->doubtful += (f & AF_VERDICT_APPLE_DOUBTFUL) != 0;
  s->unreliable += !o->report.reliable;
  if (!o->report.reliable)
    af_text(s->last_unreliable, sizeof s->last_unreliable, "apple %u: %s", o->apple_id,
            o->report.reason);
  if (!o->with_audio) {
    s->no_audio++;
    af_text(s->last_no_audio, sizeof s->last_no_audio, "strike at %.9f s: %s",
            (double)p->start_ns * 1e-9, o->report.reason);
  }
}

/* The transit words: a systematic lag once most recent strikes found no
 * estimate in their window, or a matched transit drifting from the table's. */
static void transit_words(af_lane *l)
{
  af_lane_stats *s = &l->stats;
  const double want_s = l->mc->apple_transit_s, tol_s = l->mc->apple_transit_tolerance_s;
  s->transit_warning[0] = '\0';
  if (s->unmatched_strikes >= AF_LANE_UNMATCHED_WARN && isfinite(s->unmatched_lag_s)) {
    const double lag = s->unmatched_lag_s;
    af_text(s->transit_warning, sizeof s->transit_warning,
            "%zu of the latest %zu strikes found no apple estimate stamped %g +- %g s before "
            "them; the nearest estimates are stamped %.0f ms %s their strikes%s (apple_transit_s "
            "%.3f would match them)",
            s->unmatched_strikes,
            (size_t)(l->recent < AF_LANE_TRANSITS ? l->recent : AF_LANE_TRANSITS), want_s, tol_s,
            1e3 * fabs(lag), lag >= 0.0 ? "before" : "after",
            lag < 0.0 ? ": is the camera stamping at publish time?"
                      : ": check apple_transit_s against the conveyor",
            lag);
  } else if (s->transit_strikes >= AF_LANE_UNMATCHED_WARN &&
             fabs(s->transit_observed_s - want_s) > 0.5 * tol_s) {
    af_text(s->transit_warning, sizeof s->transit_warning,
            "apple estimates lead their strikes by %.0f ms, apple_transit_s is %.0f ms (+- %.0f): "
            "the conveyor or the camera's stamps have drifted",
            1e3 * s->transit_observed_s, 1e3 * want_s, 1e3 * tol_s);
  }
}

/* What strike p's match tells of the transit (a line only; one apple a
 * recording has none), and p kept for the estimates that come late. */
static void observe_transit(af_lane *l, const af_pending *p, const af_apple_slot *a)
{
  af_lane_reported *r = &l->reported[l->reported_n++ % AF_LANE_REPORTED];
  r->start_ns = p->start_ns;
  r->apple_id = a ? a->apple.apple_id : 0;
  r->apple_stamp_ns = a ? a->apple.stamp_ns : 0;
  if (l->mc->single_apple)
    return;
  af_lane_stats *s = &l->stats;
  const af_apple_slot *n = a ? NULL : nearest_apple(l, p->start_ns);
  if (a)
    l->transit_s[l->transits++ % AF_LANE_TRANSITS] = lag_s(a, p->start_ns);
  else if (n)
    l->unmatched_s[l->unmatched++ % AF_LANE_TRANSITS] = lag_s(n, p->start_ns);
  l->recent_unmatched[l->recent++ % AF_LANE_TRANSITS] = a == NULL && n != NULL;
  s->transit_strikes = l->transits < AF_LANE_TRANSITS ? l->transits : AF_LANE_TRANSITS;
  s->transit_observed_s = af_median_small(l->transit_s, s->transit_strikes);
  const size_t nu = l->unmatched < AF_LANE_TRANSITS ? l->unmatched : AF_LANE_TRANSITS;
  s->unmatched_lag_s = af_median_small(l->unmatched_s, nu);
  s->unmatched_strikes = 0;
  for (size_t k = 0; k < AF_LANE_TRANSITS && k < l->recent; k++)
    s->unmatched_strikes += l->recent_unmatched[k];
  transit_words(l);
}

/* A second impact inside the contact that has the first one's shape fits
 * the impact model (with another E2 and e, no structured residual), but it
 * adds its impulse: the strike's v0 from its impulse then lies above that of
 * the latest AF_LANE_BOUNCE_STRIKES clean strikes (hammer_health.h's v0;
 * the rig holds it within a few per cent, an apple's restitution moves it
 * less) by more than AF_LANE_BOUNCE_EXCESS and four of their standard
 * deviations. The reference is the lane's own, of strikes that passed, so
 * that a run of bounces cannot empty it. */
static void check_impulse(af_lane *l, const af_pending *p, af_measure_report *r)
{
  if (l->mc->tap_only || !(p->ev.impulse_n_s > 0.0))
    return;
  const double v0 =
      af_hammer_health_velocity_m_s(&l->cfg->health, p->ev.impulse_n_s, p->ev.contact_time_s);
  const size_t n = l->v0_count < AF_LANE_BOUNCE_STRIKES ? l->v0_count : AF_LANE_BOUNCE_STRIKES;
  if (!r->double_hit && n == AF_LANE_BOUNCE_STRIKES) {
    double mean = 0.0, var = 0.0;
    for (size_t k = 0; k < n; k++)
      mean += l->v0_ref[k] / (double)n;
    for (size_t k = 0; k < n; k++)
      var += (l->v0_ref[k] - mean) * (l->v0_ref[k] - mean) / (double)(n - 1);
    const double excess = v0 / mean - 1.0;
    if (excess > fmax(AF_LANE_BOUNCE_EXCESS, 4.0 * sqrt(var) / mean)) {
      r->double_hit = true;
      r->verdict.flags |= AF_VERDICT_DOUBLE_HIT;
      r->verdict.bounce_impulse_excess = excess;
    }
  }
  const af_strike_event *ev = &p->ev;
  if (!r->double_hit && !ev->clipped && !ev->truncated && ev->lost_samples == 0 &&
      p->refused == 0 && isfinite(v0))
    l->v0_ref[l->v0_count++ % AF_LANE_BOUNCE_STRIKES] = v0;
}

/* A saturated microphone in the strike's audio window: flagged and counted
 * (its 0S2 and Q would be read off a distorted ring). */
static void check_clipping(af_lane *l, size_t n_audio, af_verdict *v)
{
  af_audio_clip c;
  af_audio_clip_check(n_audio ? l->audio_buf : NULL, n_audio, &c);
  if (!c.clipped)
    return;
  v->flags |= AF_VERDICT_AUDIO_CLIPPED;
  v->audio_clip_samples = c.at_extremes;
  v->audio_clip_tops = c.flat_tops;
  v->audio_clip_max = c.max;
  v->audio_clip_min = c.min;
  l->stats.audio_clipped++;
}

/* A strike within stream_stale_after_s of a clock fault of either stream
 * (or while a stream's stamps contradict its rate): its window and its
 * apple were found by stamps that cannot be trusted. Flagged, so that the
 * fruit is not blamed. */
static void check_clocks(af_lane *l, const af_pending *p, af_verdict *v)
{
  const int64_t margin_ns = (int64_t)llround(l->cfg->stream_stale_after_s * 1e9);
  const af_stream *s = NULL;
  if (!l->mc->tap_only && af_stream_clock_fault_near(&l->force, p->start_ns, margin_ns))
    s = &l->force;
  else if (af_stream_clock_fault_near(&l->audio, p->start_ns, margin_ns))
    s = &l->audio;
  if (s == NULL)
    return;
  v->flags |= AF_VERDICT_CLOCK_FAULT;
  af_text(v->clock_why, sizeof v->clock_why, "%s", s->clock_problem);
  l->stats.clock_faulted++;
}

/* Measures p with its audio (n_audio 0: none, lane_v says why) and calls back. */
static void measure_one(af_lane *l, const af_pending *p, size_t n_audio, af_verdict *lane_v)
{
  af_lane_strike *o = &l->out;
  const af_stage_hook *h = l->mc->measure.stages;
  af_apple_slot *a = apple_flags(l, p, lane_v);
  if (p->refused > 0) {
    lane_v->flags |= AF_VERDICT_REFUSED_SAMPLES;
    lane_v->refused_samples = p->refused;
  }
  check_clipping(l, n_audio, lane_v);
  check_clocks(l, p, lane_v);
  if (!(lane_v->flags & AF_VERDICT_CLOCK_FAULT))
    check_lag(l, p, lane_v);
  int64_t t0_ns = af_stage_begin(h);
  size_t n_noise = n_audio ? read_noise(l, p) : 0;
  af_stage_end(h, AF_STAGE_WINDOW, t0_ns);
  o->modulus_factor = af_factor_learn_get(l->factor)->applied;
  measure_with_apple(l, p, a, n_audio, n_noise, lane_v);
  check_impulse(l, p, &o->report);
  t0_ns = af_stage_begin(h);
  merge_verdict(&o->report, lane_v);
  af_grade_strike(&l->cfg->grade, &o->report, &o->grade); /* after the lane's flags */
  af_stage_end(h, AF_STAGE_VERDICT, t0_ns);
  o->start_ns = p->start_ns;
  memcpy(o->frame_id, p->frame_id, sizeof o->frame_id);
  o->apple_id = a ? a->apple.apple_id : 0;
  o->apple = a ? &a->apple : NULL;
  o->prediction = a ? &a->prediction : NULL;
  o->with_audio = n_audio > 0;
  o->event = &p->ev;
  o->report.audio_lag_s = p->lag_s;
  o->report.audio_lag_applied_s = p->applied_s;
  l->last_start_ns = p->start_ns;
  l->any_start = true;
  if (a && a->prediction.valid) {
    a->strikes++;
    a->last_strike_ns = p->start_ns;
  }
  count(l, p, o);
  observe_transit(l, p, a);
  /* Only a strike whose 0S2 and E2 were both measured and judged reliable
   * feeds the learned factor (af_factor_learn_push refuses the others). */
  (void)af_factor_learn_push(l->factor, o->report.reliable && o->with_audio,
                             o->report.modulus_from_resonance_pa, o->report.fitted_modulus_pa,
                             o->modulus_factor, &o->factor_changed);
  if (l->fn)
    l->fn(o, l->user);
}

/* Measures the oldest pending strikes that are decided, in order. */
static void process(af_lane *l)
{
  while (l->count > 0) {
    af_pending *p = &l->pending[l->head];
    af_verdict v;
    af_verdict_clear(&v);
    if (!apple_decided(l, p))
      return;
    const int64_t t0_ns = af_stage_begin(l->mc->measure.stages);
    if (!p->lag_done && measure_lag(l, p) == AF_WAIT)
      return;
    af_decision d = audio_for(l, p, &v);
    if (d == AF_WAIT)
      return;
    af_stage_end(l->mc->measure.stages, AF_STAGE_WINDOW, t0_ns);
    if (d == AF_NONE)
      v.flags |= AF_VERDICT_NO_AUDIO;
    measure_one(l, p, d == AF_READY ? l->mc->audio_window_samples : 0, &v);
    l->head = (l->head + 1) % l->mc->pending_size;
    l->count--;
  }
}

/* --- the detector's strikes ------------------------------------------------------ */

/* The next pending slot; a full queue measures its oldest strike first. */
static af_pending *next_slot(af_lane *l)
{
  const size_t size = l->mc->pending_size;
  if (l->count == size) {
    /* Full: the oldest goes now, with whatever there is. */
    af_verdict v;
    af_verdict_clear(&v);
    l->stats.overflows++;
    v.flags |= AF_VERDICT_NO_AUDIO;
    v.audio_cause = AF_AUDIO_QUEUE_FULL;
    v.queue_size = size;
    measure_one(l, &l->pending[l->head], 0, &v);
    l->head = (l->head + 1) % size;
    l->count--;
  }
  return &l->pending[(l->head + l->count) % size];
}

/* The time [ns] of a detector's (fractional) index: the detector counts
 * from the force stream's origin, so that its indices stay small and exact
 * in a double whatever the stream's running index (2^53, 2^63 and beyond). */
static int64_t force_time_ns(const af_lane *l, double rel)
{
  const double whole = floor(rel);
  const uint64_t back = whole < 0.0 ? (uint64_t)(-whole) : 0;
  const uint64_t index = whole >= 0.0              ? l->force_origin + (uint64_t)whole
                         : back <= l->force_origin ? l->force_origin - back
                                                   : 0;
  return af_stream_time_of_ns(&l->force, index, rel - whole);
}

/* The detector's callback: a strike, copied into the next pending slot. */
static void on_strike(const af_strike_event *ev, void *user)
{
  af_lane *l = user;
  af_pending *p = next_slot(l);
  double *pulse = p->pulse;
  p->ev = *ev;
  size_t n = ev->n_samples;
  if (n > l->mc->pulse_capacity_samples) {
    n = l->mc->pulse_capacity_samples; /* cannot happen with the detector's span; counted */
    l->stats.pulse_cut++;
  }
  if (n > 0)
    memcpy(pulse, ev->pulse_n, n * sizeof *pulse);
  p->ev.pulse_n = pulse;
  p->ev.n_samples = n;
  p->start_ns = force_time_ns(l, ev->start_sample);
  p->queued_ns = l->now_ns;
  p->refused = af_stream_refused_in(&l->force, l->force_origin + ev->span_first,
                                    ev->span_end - ev->span_first);
  p->lag_done = false;
  p->lag_s = NAN;
  p->applied_s = 0.0;
  memcpy(p->frame_id, l->force.frame_id, sizeof p->frame_id);
  l->count++;
}

/* An accepted force chunk into the detector, in newtons (a force in V
 * converted), block by block in the stream's scratch, a refused
 * (non-finite) sample as NaN: a lost sample to the detector; samples the
 * stream held as sent (stream.h, last_as_sent) straight from the chunk.
 * Only the chunk's new samples: the head of an overlap (last_held) was
 * held, and detected, with the chunk before. */
static void detect(af_lane *l, const af_chunk *c)
{
  for (size_t at = l->force.last_held; at < c->n; at += AF_STREAM_BLOCK) {
    size_t m = c->n - at < AF_STREAM_BLOCK ? c->n - at : AF_STREAM_BLOCK;
    const float *x = c->x + at;
    if (!l->force.last_as_sent) {
      (void)af_stream_to_si(l->cfg->force.to_si, x, m, l->force.si);
      x = l->force.si;
    }
    (void)af_strike_write(l->detector, c->first_sample + at - l->force_origin, x, m, on_strike, l);
  }
}

af_chunk_verdict af_lane_force(af_lane *l, const af_chunk *c, int64_t now_ns,
                               af_ring_write_info *info)
{
  l->now_ns = now_ns;
  af_ring_write_info own;
  if (info == NULL)
    info = &own;
  memset(info, 0, sizeof *info);
  af_chunk_verdict v = af_stream_push(&l->force, c, now_ns, info);
  if (v == AF_CHUNK_OK && (!l->force_origin_set || info->restarted)) {
    l->force_origin = c->first_sample; /* the detector's index 0 */
    l->force_origin_set = true;
  }
  if (v == AF_CHUNK_OK && (info->gap_samples > 0 || info->restarted))
    l->force_gap_ns[l->force_gaps++ % AF_LANE_GAPS] = c->stamp_ns;
  if (v == AF_CHUNK_OK) {
    const int64_t t0_ns = af_stage_begin(l->mc->measure.stages);
    detect(l, c);
    af_stage_end(l->mc->measure.stages, AF_STAGE_DETECT, t0_ns);
  }
  /* The audio may lead the force: what is complete goes now. */
  process(l);
  return v;
}

/* --- tap-only: the strikes found in the audio ------------------------------------ */

/* The onset detector's callback: a strike without a pulse (every pulse
 * figure NaN), its contact start the onset's time by the audio stream's
 * mapping, into the next pending slot. */
static void on_onset(const af_onset_event *ev, void *user)
{
  af_lane *l = user;
  af_pending *p = next_slot(l);
  double *pulse = p->pulse;
  memset(&p->ev, 0, sizeof p->ev);
  p->ev.pulse_n = pulse;
  p->ev.dt_s = 1.0 / l->cfg->audio.sample_rate_hz;
  p->ev.start_sample = (double)ev->sample;
  p->ev.contact_time_s = p->ev.peak_force_n = p->ev.impulse_n_s = NAN;
  p->ev.baseline_n = p->ev.noise_rms_n = NAN;
  p->start_ns = af_stream_time_of_ns(&l->audio, ev->sample, 0.0);
  p->queued_ns = l->now_ns;
  p->refused = 0;
  p->lag_done = false;
  p->lag_s = NAN;
  p->applied_s = 0.0;
  memcpy(p->frame_id, l->audio.frame_id, sizeof p->frame_id);
  l->count++;
}

/* An accepted audio chunk into the onset detector (tap-only). */
static void detect_onsets(af_lane *l, const af_chunk *c)
{
  const int64_t t0_ns = af_stage_begin(l->mc->measure.stages);
  const size_t held = l->audio.last_held; /* an overlap's head: seen already */
  /* Nothing new: an empty chunk's x may be NULL, and NULL + 0 is undefined
   * (found by test/fuzz/fuzz_lane.c: a zero-length audio chunk, tap-only). */
  if (c->n <= held)
    return;
  (void)af_onset_write(l->onset, c->first_sample + held, c->x + held, c->n - held, on_onset, l);
  af_stage_end(l->mc->measure.stages, AF_STAGE_DETECT, t0_ns);
}

af_status af_lane_prime_audio(af_lane *l, const float *x, size_t n)
{
  if (l == NULL || (x == NULL && n > 0))
    return AF_EINVAL;
  return af_onset_prime(l->onset, x, n);
}

/* A force stream that stalls inside a contact must not hold its strike
 * until data comes back: after stream_stale_after_s on the lane's clock the
 * strike goes, cut (truncated: the contact had not ended). */
static void check_stall(af_lane *l)
{
  if (!l->mc->tap_only && af_stream_stale(&l->force, l->now_ns, l->cfg->stream_stale_after_s) &&
      af_strike_in_progress(l->detector)) {
    l->stats.force_stalls++;
    (void)af_strike_flush(l->detector, on_strike, l);
  }
}

af_chunk_verdict af_lane_audio(af_lane *l, const af_chunk *c, int64_t now_ns,
                               af_ring_write_info *info)
{
  l->now_ns = now_ns;
  check_stall(l);
  af_chunk_verdict v = af_stream_push(&l->audio, c, now_ns, info);
  if (v == AF_CHUNK_OK && l->mc->tap_only)
    detect_onsets(l, c);
  process(l);
  return v;
}

void af_lane_poll(af_lane *l, int64_t now_ns)
{
  l->now_ns = now_ns;
  check_stall(l);
  process(l);
}

void af_lane_finish(af_lane *l)
{
  (void)af_strike_flush(l->detector, on_strike, l);
  l->finished = true;
  process(l);
}

void af_lane_refuse(af_lane *l, bool force, bool oversized, const char *why)
{
  af_stream_refuse(force ? &l->force : &l->audio, oversized, why);
}

af_status af_lane_prime_force(af_lane *l, const float *x, size_t n)
{
  if (l->cfg->force.to_si == 1.0 || l->cfg->force.to_si == 0.0)
    return af_strike_prime(l->detector, x, n); /* it passes over non-finite samples */
  /* A recording in V: its copy in N (offline, once per recording). */
  float *si = malloc((n ? n : 1) * sizeof *si);
  if (si == NULL)
    return AF_ENOMEM;
  af_stream_to_si(l->cfg->force.to_si, x, n, si);
  af_status s = af_strike_prime(l->detector, si, n);
  free(si);
  return s;
}

/* A detector made anew learns its baseline and noise from the force ring's
 * latest AF_LANE_PRIME_S instead of a warm-up, during which every strike
 * would pass unseen. Allocates (a reconfigure, not a chunk or a strike). */
static void prime_from_ring(af_lane *l, af_strike *d)
{
  const af_ring *r = l->force.ring;
  const uint64_t end = af_ring_end(r), begin = af_ring_begin(r);
  const uint64_t want = (uint64_t)ceil(AF_LANE_PRIME_S * l->cfg->force.sample_rate_hz);
  const uint64_t n = end - begin < want ? end - begin : want;
  float *x = n > 0 ? malloc((size_t)n * sizeof *x) : NULL;
  if (x != NULL && af_ring_read(r, end - n, (size_t)n, x) == AF_OK)
    (void)af_strike_prime(d, x, (size_t)n); /* too little signal: the warm-up, as before */
  free(x);
}

af_status af_lane_reconfigured(af_lane *l, const char **what)
{
  af_measure *m = NULL;
  af_strike *d = NULL;
  /* The measurement holds a copy of its configuration: made anew (an
   * operator's change, not a chunk or a strike). */
  *what = "the strike measurement";
  char err[AF_HAMMER_HEALTH_TEXT_MAX];
  af_status s = af_hammer_health_check(&l->cfg->health, err, sizeof err);
  if (s != AF_OK) {
    *what = "the hammer health";
    return s;
  }
  s = af_measure_create(&l->mc->measure, &m);
  if (s == AF_OK)
    s = af_measure_prepare(m, &l->cfg->model);
  if (s == AF_OK && memcmp(&l->detector_cfg, &l->mc->strike, sizeof l->detector_cfg) != 0) {
    *what = "the strike detector";
    s = af_strike_create(&l->mc->strike, &d);
  }
  if (s != AF_OK) {
    af_measure_destroy(m);
    af_strike_destroy(d);
    return s;
  }
  af_measure_destroy(l->measure);
  l->measure = m;
  (void)af_hammer_health_configure(l->health, &l->cfg->health); /* checked above */
  if (l->cfg->model.modulus_factor != l->factor_configured) {   /* the operator's value wins */
    l->factor_configured = l->cfg->model.modulus_factor;
    af_factor_learn_set_applied(l->factor, l->factor_configured);
  }
  if (d) {
    /* A strike in the old detector is lost with it: counted, said. */
    if (af_strike_in_progress(l->detector)) {
      l->stats.reconfigure_lost++;
      af_text(l->stats.last_reconfigure_lost, sizeof l->stats.last_reconfigure_lost,
              "a strike in progress at %.3f s was lost to a reconfigure of the strike detector",
              (double)l->now_ns * 1e-9);
    }
    prime_from_ring(l, d);
    af_strike_destroy(l->detector);
    l->detector = d;
    l->detector_cfg = l->mc->strike;
  }
  return AF_OK;
}

/* --- life cycle and queries ------------------------------------------------------- */

/* The state as a new lane has it: every field from `head` on zeroed (the
 * queue empty, no apple, no strike reported), then the figures that start
 * as NaN (none yet). The parts must exist (stats.health is the hammer's). */
static void lane_clear(af_lane *l)
{
  memset(&l->head, 0, sizeof *l - offsetof(af_lane, head));
  l->stats.health = *af_hammer_health_get_stats(l->health);
  l->stats.transit_observed_s = l->stats.unmatched_lag_s = NAN;
  af_audio_lag_reset(&l->lag);
  l->stats.lag_median_s = l->stats.lag_mad_s = NAN;
}

void af_lane_reset(af_lane *l)
{
  af_stream_reset(&l->force);
  af_stream_reset(&l->audio);
  af_strike_reset(l->detector); /* a strike in progress is dropped, not emitted */
  af_onset_reset(l->onset);     /* NULL-safe: tap-only lanes only */
  af_hammer_health_reset(l->health);
  af_factor_learn_reset(l->factor);
  /* The factor learned starts again from the configured one (a reconfigure's, if any). */
  af_factor_learn_set_applied(l->factor, l->factor_configured);
  lane_clear(l);
}

af_status af_lane_create(const af_lane_config *cfg, af_lane_strike_fn *fn, void *user,
                         af_lane **out, const char **what)
{
  *out = NULL;
  *what = "the lane";
  af_lane *l = calloc(1, sizeof *l);
  if (!l)
    return AF_ENOMEM;
  l->cfg = cfg;
  l->mc = &cfg->strikes;
  l->fn = fn;
  l->user = user;
  af_status s;
  *what = "the force stream";
  if ((s = af_stream_create(&l->force, "force", &cfg->force)) != AF_OK)
    goto fail;
  *what = "the audio stream";
  if ((s = af_stream_create(&l->audio, "audio", &cfg->audio)) != AF_OK)
    goto fail;
  *what = "the strike detector";
  if ((s = af_strike_create(&l->mc->strike, &l->detector)) != AF_OK)
    goto fail;
  l->detector_cfg = l->mc->strike;
  *what = "the strike measurement";
  if ((s = af_measure_create(&l->mc->measure, &l->measure)) != AF_OK ||
      (s = af_measure_prepare(l->measure, &cfg->model)) != AF_OK)
    goto fail;
  *what = "the model";
  if ((s = af_fastpath_create(&l->model)) != AF_OK)
    goto fail;
  *what = "the onset detector";
  if (l->mc->tap_only && (s = af_onset_create(&l->mc->onset, &l->onset)) != AF_OK)
    goto fail;
  *what = "the hammer health";
  if ((s = af_hammer_health_create(&cfg->health, &l->health)) != AF_OK)
    goto fail;
  *what = "the learned modulus factor";
  if ((s = af_factor_learn_create(&cfg->factor_learn, &l->factor)) != AF_OK)
    goto fail;
  l->factor_configured = cfg->model.modulus_factor;
  *what = "the strike queue";
  s = AF_ENOMEM;
  const size_t n = l->mc->pending_size, cap = l->mc->pulse_capacity_samples;
  if (n == 0 || cap == 0) {
    s = AF_EINVAL;
    goto fail;
  }
  l->pending = calloc(n, sizeof *l->pending);
  l->pulses = calloc(n * cap, sizeof *l->pulses);
  l->audio_buf = calloc(l->mc->audio_window_samples + 1, sizeof *l->audio_buf);
  l->noise_buf = calloc(l->mc->noise_window_samples + 1, sizeof *l->noise_buf);
  /* The onset search: +-audio_lag_max_s, the reference before it, a block. */
  const double lag_blocks = AF_AUDIO_LAG_REF_BLOCKS + 2;
  l->lag_cap = (size_t)ceil((2.0 * l->mc->audio_lag_max_s + lag_blocks * AF_AUDIO_LAG_BLOCK_S) *
                            cfg->audio.sample_rate_hz) +
               (size_t)lag_blocks + 1;
  l->lag_buf = calloc(l->lag_cap, sizeof *l->lag_buf);
  if (!l->pending || !l->pulses || !l->audio_buf || !l->noise_buf || !l->lag_buf)
    goto fail;
  for (size_t k = 0; k < n; k++)
    l->pending[k].pulse = l->pulses + k * cap;
  lane_clear(l);
  *out = l;
  return AF_OK;
fail:
  af_lane_destroy(l);
  return s;
}

void af_lane_destroy(af_lane *l)
{
  if (!l)
    return;
  af_stream_destroy(&l->force);
  af_stream_destroy(&l->audio);
  af_strike_destroy(l->detector);
  af_measure_destroy(l->measure);
  af_fastpath_destroy(l->model);
  af_hammer_health_destroy(l->health);
  af_factor_learn_destroy(l->factor);
  af_onset_destroy(l->onset);
  free(l->pending);
  free(l->pulses);
  free(l->audio_buf);
  free(l->noise_buf);
  free(l->lag_buf);
  free(l);
}

const af_stream *af_lane_force_stream(const af_lane *l)
{
  return &l->force;
}

const af_stream *af_lane_audio_stream(const af_lane *l)
{
  return &l->audio;
}

const af_strike *af_lane_detector(const af_lane *l)
{
  return l->detector;
}

size_t af_lane_pending(const af_lane *l)
{
  return l->count;
}

const af_lane_stats *af_lane_get_stats(const af_lane *l)
{
  return &l->stats;
}

const af_factor_learn_state *af_lane_factor(const af_lane *l)
{
  return af_factor_learn_get(l->factor);
}
