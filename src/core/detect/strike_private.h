/* strike_private.h — what the strike detector's files share (strike.c, the
 * state machine; strike_prime.c, the offline priming; strike_explain.c, the
 * diagnosis and its text): the detector's struct and its small helpers. Not
 * for callers outside them: the public interface is strike.h, the pure pulse
 * measurement strike_pulse.h. */
#ifndef AF_STRIKE_PRIVATE_H
#define AF_STRIKE_PRIVATE_H

#include <math.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "ring.h"
#include "strike.h"

/* Release level as a fraction of the trigger threshold (hysteresis). */
#define AF_STRIKE_RELEASE 0.5
/* af_strike_prime: at most this many samples of the recording (evenly
 * strided) enter the median; the workspace is allocated at create. */
#define AF_STRIKE_PRIME_SAMPLES ((size_t)8192)

typedef enum {
  AF_PHASE_WARMUP, /* learning the trackers, not armed */
  AF_PHASE_IDLE,   /* armed, trackers following the signal */
  AF_PHASE_CONTACT,
  AF_PHASE_AFTER, /* contact over: watching for a bounce, counting down */
  AF_PHASE_SETTLE /* after a cut event: waiting for quiet before arming */
} af_phase;

/* The event being collected, in running sample indices. */
typedef struct {
  uint64_t begin;           /* first sample of the span: trigger - pre-trigger */
  uint64_t trigger;         /* first sample above threshold */
  uint64_t contact_trigger; /* trigger of the current contact (first or bounce) */
  bool ended;               /* the first contact ended (end is valid) */
  uint64_t end;             /* first quiet sample after the first contact */
  uint64_t last_end;        /* same, for the last contact */
  bool double_hit;
  uint64_t bounce; /* trigger of the first bounce (when double_hit) */
  bool truncated;
  uint64_t lost; /* samples lost in a gap that cut the event */
  size_t quiet;  /* consecutive samples below release */
  double baseline_n, noise_rms_n, threshold_n, release_n; /* frozen at the trigger */
} af_pending;

/* What the detector saw, for af_strike_get_diagnosis: counts since the
 * stream started, largest excursions since then or the last strike. */
typedef struct {
  uint64_t strikes, samples;
  bool armed_ever;
  uint64_t armed_at;    /* first sample armed after the last warm-up */
  double arm_threshold; /* threshold when it armed [N] */
  double warm_max;      /* largest excursion in the warm-up [N] (-inf: none) */
  uint64_t warm_at;
  double idle_max, idle_ms; /* largest armed excursion, mean square then */
  uint64_t idle_at;
  double settle_max, settle_threshold; /* largest while waiting for quiet */
  uint64_t settle_at;
} af_record;

struct af_strike {
  af_strike_config cfg;
  /* derived sample counts */
  size_t pre, post, window, gap, max_contact, quiet_needed, warmup, span_cap;
  double alpha;   /* tracker weight per sample, 1 - exp(-1 / (tau fs)) */
  double factor2; /* threshold_noise_factor^2 */
  af_ring *ring;  /* raw history */
  float *span_f;  /* span read from the ring */
  double *x;      /* span, raw [N] */
  double *r;      /* span, baseline removed [N] */
  /* stream */
  bool started;
  uint64_t next; /* index expected next */
  af_phase phase;
  double baseline_n;  /* tracker: offset and drift */
  double mean_square; /* tracker: mean square of the residual [N^2] */
  size_t learned;     /* samples learned since the trackers restarted */
  size_t quiet;       /* SETTLE: consecutive quiet samples */
  uint64_t settle_since;
  uint64_t stream_first; /* first sample of the stream: no span reaches before it */
  bool primed;           /* trackers set by af_strike_prime for this stream */
  double *prime_ws;      /* af_strike_prime's sample of the recording */
  af_record rec;
  af_pending ev;
  af_strike_event out;
};

/* Trigger threshold of the trackers now [N]. */
static inline double threshold_now(const af_strike *d)
{
  double t = d->cfg.threshold_noise_factor * sqrt(d->mean_square);
  return t > d->cfg.threshold_min_n ? t : d->cfg.threshold_min_n;
}

/* The warm-up is over at sample `at`: armed from the next one. */
static inline void arm(af_strike *d, uint64_t at)
{
  d->phase = AF_PHASE_IDLE;
  d->rec.armed_ever = true;
  d->rec.armed_at = at + 1;
  d->rec.arm_threshold = threshold_now(d);
}

/* An event is being collected (its contact, or the wait after it). */
static inline bool in_event(const af_strike *d)
{
  return d->phase == AF_PHASE_CONTACT || d->phase == AF_PHASE_AFTER;
}

#endif
