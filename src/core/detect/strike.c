/* strike.c — the strike detector: the object (create, destroy, reset) and
 * its per-sample state machine (trackers, trigger, contact end, bounce,
 * emission countdown), which touches a handful of doubles per sample and,
 * once per event, copies the span out of the history ring for the pulse
 * measurement (strike_pulse.c). The offline priming is strike_prime.c, the
 * diagnosis of a missing strike strike_explain.c; the struct they share
 * strike_private.h. Definitions and their reasons are in strike.h. */
#include "strike.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "ring.h"
#include "samples.h"
#include "strike_private.h"
#include "strike_pulse.h"

/* Longest event span accepted [samples] (2^24: 5.6 min at 50 kHz). */
#define AF_STRIKE_MAX_SPAN ((size_t)1 << 24)
/* Samples handled per ring write: the ring holds the longest span plus one
 * block, so an event that completes anywhere inside a block is still whole. */
#define AF_STRIKE_BLOCK ((size_t)1024)
/* A contact is over once the signal stays below the release level this long
 * [s]: one noisy sample under it in the damped tail is not the end. */
#define AF_STRIKE_QUIET_S 1e-4

#include "af_defaults.h" /* the parameter table's defaults */
af_strike_config af_strike_config_default(void)
{
  return (af_strike_config){.sample_rate_hz = AF_DEFAULT_FORCE_SAMPLE_RATE_HZ,
                            .full_scale_n = AF_DEFAULT_STRIKE_FULL_SCALE_N,
                            .threshold_noise_factor = AF_DEFAULT_STRIKE_THRESHOLD_NOISE_FACTOR,
                            .threshold_min_n = AF_DEFAULT_STRIKE_THRESHOLD_MIN_N,
                            .pre_trigger_s = AF_DEFAULT_STRIKE_PRE_TRIGGER_S,
                            .baseline_time_constant_s = AF_DEFAULT_STRIKE_BASELINE_TIME_CONSTANT_S,
                            .baseline_window_s = AF_DEFAULT_STRIKE_BASELINE_WINDOW_S,
                            .double_hit_gap_s = AF_DEFAULT_STRIKE_DOUBLE_HIT_GAP_S,
                            .max_contact_s = AF_DEFAULT_STRIKE_MAX_CONTACT_S,
                            .post_s = AF_DEFAULT_STRIKE_POST_S,
                            .rise_fit_level = AF_DEFAULT_STRIKE_RISE_FIT_LEVEL,
                            .fall_fit_level = AF_DEFAULT_STRIKE_FALL_FIT_LEVEL};
}

/* ------------------------------------------------------------------------ */
/* configuration */

static bool positive(double v)
{
  return isfinite(v) && v > 0.0;
}

static bool fraction(double v)
{
  return isfinite(v) && v > 0.0 && v < 1.0;
}

/* Duration [s] -> samples, rounded up; 0 when beyond the span limit. */
static size_t samples_of(double seconds, double rate_hz)
{
  double n = ceil(seconds * rate_hz - 1e-9);
  return n >= 0.0 && n <= (double)AF_STRIKE_MAX_SPAN ? (size_t)n : 0;
}

static bool config_valid(const af_strike_config *c)
{
  return positive(c->sample_rate_hz) && positive(c->full_scale_n) &&
         positive(c->threshold_noise_factor) && isfinite(c->threshold_min_n) &&
         c->threshold_min_n > 0.0 && positive(c->pre_trigger_s) &&
         positive(c->baseline_time_constant_s) && positive(c->baseline_window_s) &&
         isfinite(c->double_hit_gap_s) && c->double_hit_gap_s >= 0.0 &&
         positive(c->max_contact_s) && positive(c->post_s) &&
         c->pre_trigger_s > c->baseline_window_s && c->post_s > c->baseline_window_s &&
         c->post_s >= c->double_hit_gap_s && fraction(c->rise_fit_level) &&
         fraction(c->fall_fit_level);
}

/* Sample counts of a valid config; false when one is 0 or the span too long. */
static bool derive_counts(af_strike *d)
{
  const af_strike_config *c = &d->cfg;
  double fs = c->sample_rate_hz;
  d->pre = samples_of(c->pre_trigger_s, fs);
  d->post = samples_of(c->post_s, fs);
  d->window = samples_of(c->baseline_window_s, fs);
  d->gap = samples_of(c->double_hit_gap_s, fs);
  d->max_contact = samples_of(c->max_contact_s, fs);
  d->warmup = samples_of(c->baseline_time_constant_s, fs);
  d->quiet_needed = samples_of(AF_STRIKE_QUIET_S, fs);
  if (d->quiet_needed < 2)
    d->quiet_needed = 2;
  if (d->pre < 2 || d->post < 2 || d->window < 1 || d->max_contact < 2 || d->warmup < 1 ||
      d->pre <= d->window || d->post <= d->window)
    return false;
  /* One contact and one bounce of the longest kind, the gap between them. */
  double span = (double)d->pre + 2.0 * (double)d->max_contact + (double)d->gap + (double)d->post;
  if (span > (double)AF_STRIKE_MAX_SPAN)
    return false;
  d->span_cap = (size_t)span;
  d->alpha = -expm1(-1.0 / (c->baseline_time_constant_s * fs));
  d->factor2 = c->threshold_noise_factor * c->threshold_noise_factor;
  return true;
}

af_status af_strike_create(const af_strike_config *cfg, af_strike **out)
{
  if (out == NULL)
    return AF_EINVAL;
  *out = NULL;
  if (cfg == NULL || !config_valid(cfg))
    return AF_EINVAL;
  af_strike *d = calloc(1, sizeof *d);
  if (d == NULL)
    return AF_ENOMEM;
  d->cfg = *cfg;
  if (!derive_counts(d)) {
    free(d);
    return AF_EINVAL;
  }
  af_status st = af_ring_create(d->span_cap + AF_STRIKE_BLOCK, &d->ring);
  d->span_f = malloc(d->span_cap * sizeof *d->span_f);
  d->x = malloc(d->span_cap * sizeof *d->x);
  d->r = malloc(d->span_cap * sizeof *d->r);
  d->prime_ws = malloc(AF_STRIKE_PRIME_SAMPLES * sizeof *d->prime_ws);
  if (st != AF_OK || d->span_f == NULL || d->x == NULL || d->r == NULL || d->prime_ws == NULL) {
    af_strike_destroy(d);
    return AF_ENOMEM;
  }
  af_strike_reset(d);
  *out = d;
  return AF_OK;
}

void af_strike_destroy(af_strike *d)
{
  if (d == NULL)
    return;
  af_ring_destroy(d->ring);
  free(d->span_f);
  free(d->x);
  free(d->r);
  free(d->prime_ws);
  free(d);
}

/* Forgets the largest excursions (at a strike, or when the stream starts). */
static void clear_maxima(af_record *rec)
{
  rec->warm_max = rec->idle_max = rec->settle_max = -INFINITY;
  rec->warm_at = rec->idle_at = rec->settle_at = 0;
  rec->idle_ms = rec->settle_threshold = 0.0;
}

/* Trackers forget everything and learn again (running means first). */
static void restart_trackers(af_strike *d)
{
  d->phase = AF_PHASE_WARMUP;
  d->learned = 0;
  d->baseline_n = 0.0;
  d->mean_square = 0.0;
  d->primed = false;
  d->rec.armed_ever = false;
}

void af_strike_reset(af_strike *d)
{
  if (d == NULL)
    return;
  af_ring_reset(d->ring);
  d->started = false;
  d->next = 0;
  d->stream_first = 0;
  memset(&d->rec, 0, sizeof d->rec);
  clear_maxima(&d->rec);
  restart_trackers(d);
  memset(&d->ev, 0, sizeof d->ev);
}

void af_strike_get_tracker(const af_strike *d, af_strike_tracker *out)
{
  if (d == NULL || out == NULL)
    return;
  *out = (af_strike_tracker){.armed = d->phase != AF_PHASE_WARMUP && d->phase != AF_PHASE_SETTLE,
                             .baseline_n = d->baseline_n,
                             .noise_rms_n = sqrt(d->mean_square),
                             .threshold_n = threshold_now(d),
                             .next_sample = d->next};
}

/* ------------------------------------------------------------------------ */
/* the event's span, measured */

/* Fills d->out from the span [d->ev.begin, end) of the ring; false when the
 * ring does not hold it (cannot happen while the sizes hold). */
static bool measure(af_strike *d, uint64_t end)
{
  af_pending *ev = &d->ev;
  uint64_t begin = ev->begin < af_ring_begin(d->ring) ? af_ring_begin(d->ring) : ev->begin;
  if (end <= begin || end - begin > d->span_cap ||
      af_ring_read(d->ring, begin, (size_t)(end - begin), d->span_f) != AF_OK)
    return false;
  long n = (long)(end - begin);
  uint64_t lost = ev->lost + (begin - ev->begin) + af_samples_nonfinite(d->span_f, (size_t)n);
  for (long k = 0; k < n; k++)
    d->x[k] = d->span_f[k];
  af_strike_pulse_input in = {.x = d->x,
                              .n = n,
                              .trigger = (long)(ev->trigger - begin),
                              .contact_end = ev->ended ? (long)(ev->end - begin) : n,
                              .clean_end = ev->double_hit ? (long)(ev->bounce - begin) : n,
                              .window = (long)d->window,
                              .tracker_baseline_n = ev->baseline_n,
                              .release_n = ev->release_n,
                              .noise_rms_n = ev->noise_rms_n,
                              .rise_fit_level = d->cfg.rise_fit_level,
                              .fall_fit_level = d->cfg.fall_fit_level,
                              .sample_rate_hz = d->cfg.sample_rate_hz,
                              .full_scale_n = d->cfg.full_scale_n};
  af_strike_pulse p;
  if (af_strike_pulse_measure(&in, d->r, &p) != AF_OK)
    return false;
  double dt = 1.0 / d->cfg.sample_rate_hz, b = (double)begin;
  d->out = (af_strike_event){.start_sample = b + p.start,
                             .end_sample = b + p.end,
                             .peak_sample = b + p.peak_at,
                             .contact_time_s = p.contact_time_s,
                             .peak_force_n = p.peak_n,
                             .impulse_n_s = p.impulse_n_s,
                             .baseline_n = p.baseline_n + p.baseline_slope_n * p.start,
                             .noise_rms_n = ev->noise_rms_n,
                             .threshold_n = ev->threshold_n,
                             .trigger_sample = ev->trigger,
                             .double_hit = ev->double_hit,
                             .clipped = p.clipped,
                             .truncated = ev->truncated,
                             .lost_samples = lost,
                             .pulse_n = d->r + p.first,
                             .n_samples = p.n_samples,
                             .dt_s = dt,
                             .pulse_first_sample = begin + (uint64_t)p.first,
                             .span_first = begin,
                             .span_end = end,
                             .pulse_t0_s = (p.start - (double)p.first) * dt,
                             .start_edge = p.start_edge,
                             .end_edge = p.end_edge,
                             .edge_level_n = p.edge_level_n,
                             .baseline_before_samples = p.baseline_before_samples,
                             .baseline_after_samples = p.baseline_after_samples,
                             .primed = d->primed};
  return true;
}

/* ------------------------------------------------------------------------ */
/* per-sample state machine */

/* Measures the pending event over [begin, end) and hands it to fn. */
static void emit(af_strike *d, uint64_t end, af_strike_fn *fn, void *user)
{
  if (!measure(d, end))
    return;
  d->rec.strikes++;
  clear_maxima(&d->rec);
  if (fn != NULL)
    fn(&d->out, user);
}

/* One sample into the trackers: running means until the warm-up is done
 * (fast, unbiased start), then the exponential average. */
static void learn(af_strike *d, double x)
{
  double a = d->alpha;
  if (d->learned < d->warmup) {
    d->learned++;
    double mean_weight = 1.0 / (double)d->learned;
    a = mean_weight > a ? mean_weight : a;
  }
  d->baseline_n += a * (x - d->baseline_n);
  double e = x - d->baseline_n;
  d->mean_square += a * (e * e - d->mean_square);
}

static void trigger(af_strike *d, uint64_t at)
{
  af_pending *ev = &d->ev;
  double thr = threshold_now(d);
  uint64_t first = d->stream_first; /* the span never reaches before the stream */
  *ev = (af_pending){.begin = at > first + d->pre ? at - d->pre : first,
                     .trigger = at,
                     .contact_trigger = at,
                     .baseline_n = d->baseline_n,
                     .noise_rms_n = sqrt(d->mean_square),
                     .threshold_n = thr,
                     .release_n = AF_STRIKE_RELEASE * thr};
  d->phase = AF_PHASE_CONTACT;
}

static void settle(af_strike *d, uint64_t from)
{
  d->phase = AF_PHASE_SETTLE;
  d->quiet = 0;
  d->settle_since = from;
}

/* The armed idle state's trackers and its diagnosis (the largest
 * excursion, the mean square then, its index in the block; n: none). */
typedef struct {
  double b, ms, top, top_ms;
  size_t top_k;
} af_idle;

/* idle_run's loop over x[0..n): one multiply-add per tracker and sample
 * (this loop is nearly all of the streaming cost). Returns the samples
 * before the one that triggered (n: none did). check_finite: a lost
 * (non-finite) sample teaches nothing; without the check one would poison
 * the trackers, which the caller sees afterwards (see idle_run). */
static inline size_t idle_loop(af_idle *s, const float *x, size_t n, double a, double keep,
                               double min_n, double factor2, bool check_finite)
{
  double b = s->b, ms = s->ms, top = s->top, top_ms = s->top_ms;
  /* Both tests below need r above top or above min_n: one compare a sample
   * (top soon stops growing between strikes). */
  double gate = fmin(top, min_n);
  size_t k = 0, top_k = s->top_k;
  for (; k < n; k++) {
    double v = x[k], r = v - b;
    if (r > gate) {
      if (r > top) {
        top = r;
        top_ms = ms;
        top_k = k;
        gate = fmin(top, min_n);
      }
      if (r > min_n && r * r > factor2 * ms)
        break;
    }
    if (check_finite && !isfinite(v))
      continue;
    b = keep * b + a * v;
    double e = v - b;
    ms = keep * ms + a * e * e;
  }
  *s = (af_idle){.b = b, .ms = ms, .top = top, .top_ms = top_ms, .top_k = top_k};
  return k;
}

/* The armed idle state over x[0..n) (x[0] has index at), the trackers in
 * registers. Returns the samples consumed: n, or up to and including the
 * one that triggered. The block is first run without the per-sample test
 * for lost samples: a finite block gives the same doubles as with it, and
 * a lost one leaves a tracker non-finite (NaN or -inf taught; a trigger
 * against a poisoned baseline leaves it so too), so the block is then run
 * again from the start with the test. Float samples cannot overflow the
 * trackers: a non-finite tracker means a lost sample. */
static size_t idle_run(af_strike *d, uint64_t at, const float *x, size_t n)
{
  const double a = d->alpha, keep = 1.0 - d->alpha, min_n = d->cfg.threshold_min_n;
  const af_idle start = {.b = d->baseline_n,
                         .ms = d->mean_square,
                         .top = d->rec.idle_max,
                         .top_ms = d->rec.idle_ms,
                         .top_k = n};
  af_idle s = start;
  size_t k = idle_loop(&s, x, n, a, keep, min_n, d->factor2, false);
  if (!(isfinite(s.b) && isfinite(s.ms))) {
    s = start;
    k = idle_loop(&s, x, n, a, keep, min_n, d->factor2, true);
  }
  d->baseline_n = s.b;
  d->mean_square = s.ms;
  if (s.top_k < n) {
    d->rec.idle_max = s.top;
    d->rec.idle_ms = s.top_ms;
    d->rec.idle_at = at + s.top_k;
  }
  if (k == n)
    return n;
  trigger(d, at + k);
  return k + 1;
}

/* Cut the event: emitted now with what the span holds. */
static void cut(af_strike *d, uint64_t end, af_strike_fn *fn, void *user)
{
  d->ev.truncated = true;
  emit(d, end, fn, user);
}

static void step_contact(af_strike *d, uint64_t at, double x, af_strike_fn *fn, void *user)
{
  af_pending *ev = &d->ev;
  double r = x - ev->baseline_n;
  if (r < ev->release_n) {
    if (++ev->quiet >= d->quiet_needed) {
      uint64_t end = at + 1 - ev->quiet;
      if (!ev->ended) {
        ev->ended = true;
        ev->end = end;
      }
      ev->last_end = end;
      d->phase = AF_PHASE_AFTER;
    }
  } else {
    ev->quiet = 0;
  }
  if (d->phase == AF_PHASE_CONTACT && at - ev->contact_trigger >= d->max_contact) {
    /* Too long for a strike (a step in the offset, the hammer resting):
     * reported, then the trackers learn the new level. */
    cut(d, at + 1, fn, user);
    restart_trackers(d);
  } else if (d->phase == AF_PHASE_CONTACT && at + 1 - ev->begin >= d->span_cap) {
    cut(d, at + 1, fn, user);
    settle(d, at + 1);
  }
}

static void step_after(af_strike *d, uint64_t at, double x, af_strike_fn *fn, void *user)
{
  af_pending *ev = &d->ev;
  double r = x - ev->baseline_n;
  if (r > ev->threshold_n) {
    if (at - ev->last_end <= d->gap && at + 1 - ev->begin < d->span_cap) {
      if (!ev->double_hit)
        ev->bounce = at;
      ev->double_hit = true;
      ev->contact_trigger = at;
      ev->quiet = 0;
      d->phase = AF_PHASE_CONTACT;
    } else { /* a new strike: this one ends where it starts */
      emit(d, at, fn, user);
      trigger(d, at);
    }
  } else if (at + 1 - ev->last_end >= d->post || at + 1 - ev->begin >= d->span_cap) {
    emit(d, at + 1, fn, user);
    d->phase = AF_PHASE_IDLE;
  }
}

static void step_settle(af_strike *d, uint64_t at, double x)
{
  double r = x - d->baseline_n, thr = threshold_now(d);
  if (r > d->rec.settle_max) {
    d->rec.settle_max = r;
    d->rec.settle_at = at;
    d->rec.settle_threshold = thr;
  }
  if (r < AF_STRIKE_RELEASE * thr) {
    if (++d->quiet >= d->quiet_needed)
      d->phase = AF_PHASE_IDLE;
  } else {
    d->quiet = 0;
  }
  if (d->phase == AF_PHASE_SETTLE && at - d->settle_since >= d->max_contact)
    restart_trackers(d); /* never quiet again: the level moved */
}

/* One sample in any state but IDLE. */
static void step(af_strike *d, uint64_t at, double x, af_strike_fn *fn, void *user)
{
  switch (d->phase) {
  case AF_PHASE_WARMUP:
    if (isfinite(x)) {
      double r = d->learned > 0 ? x - d->baseline_n : 0.0; /* against what came before */
      learn(d, x);
      if (r > d->rec.warm_max) {
        d->rec.warm_max = r;
        d->rec.warm_at = at;
      }
      if (d->learned >= d->warmup)
        arm(d, at);
    }
    break;
  case AF_PHASE_IDLE: break; /* idle_run's */
  case AF_PHASE_CONTACT: step_contact(d, at, x, fn, user); break;
  case AF_PHASE_AFTER: step_after(d, at, x, fn, user); break;
  case AF_PHASE_SETTLE: step_settle(d, at, x); break;
  }
}

/* x[0..n) through the state machine, idle stretches in idle_run. */
static void process(af_strike *d, uint64_t at, const float *x, size_t n, af_strike_fn *fn,
                    void *user)
{
  size_t k = 0;
  while (k < n) {
    if (d->phase == AF_PHASE_IDLE) {
      k += idle_run(d, at + k, x + k, n - k);
    } else {
      step(d, at + k, x[k], fn, user);
      k++;
    }
  }
}

/* first_sample is not d->next: a gap (lost samples) or a restarted stream.
 * An event in progress is emitted from what the ring holds, before the
 * chunk is written. */
static void discontinuity(af_strike *d, uint64_t first_sample, af_strike_fn *fn, void *user)
{
  if (first_sample < d->next) { /* restarted stream */
    if (in_event(d))
      cut(d, d->next, fn, user);
    af_strike_reset(d);
    return;
  }
  uint64_t gap = first_sample - d->next;
  bool was_in_event = in_event(d);
  if (was_in_event) {
    d->ev.lost += gap;
    if (d->phase == AF_PHASE_CONTACT)
      d->ev.truncated = true;
    emit(d, d->next, fn, user);
  }
  if (gap > (uint64_t)d->warmup)
    restart_trackers(d); /* longer than the trackers remember */
  else if (was_in_event || d->phase == AF_PHASE_SETTLE)
    settle(d, first_sample);
}

af_status af_strike_write(af_strike *d, uint64_t first_sample, const float *x, size_t n,
                          af_strike_fn *fn, void *user)
{
  if (d == NULL || (x == NULL && n > 0) || first_sample > ((uint64_t)1 << 63) ||
      (uint64_t)n > ((uint64_t)1 << 63) - first_sample)
    return AF_EINVAL;
  if (n == 0)
    return AF_OK;
  if (d->started && first_sample != d->next)
    discontinuity(d, first_sample, fn, user);
  if (!d->started) {
    d->started = true;
    d->next = first_sample;
    d->stream_first = first_sample;
    if (d->primed)
      d->rec.armed_at = first_sample; /* armed from the first sample written */
  }
  d->rec.samples += n;
  for (size_t done = 0; done < n;) {
    size_t block = n - done < AF_STRIKE_BLOCK ? n - done : AF_STRIKE_BLOCK;
    uint64_t at = first_sample + done;
    (void)af_ring_write(d->ring, x + done, block, at, NULL); /* fails on bad arguments only */
    process(d, at, x + done, block, fn, user);
    done += block;
  }
  d->next = first_sample + n;
  return AF_OK;
}

bool af_strike_in_progress(const af_strike *d)
{
  return d != NULL && (d->phase == AF_PHASE_CONTACT || d->phase == AF_PHASE_AFTER);
}

af_status af_strike_flush(af_strike *d, af_strike_fn *fn, void *user)
{
  if (d == NULL)
    return AF_EINVAL;
  if (d->phase == AF_PHASE_CONTACT) {
    cut(d, d->next, fn, user);
    settle(d, d->next);
  } else if (d->phase == AF_PHASE_AFTER) {
    emit(d, d->next, fn, user);
    d->phase = AF_PHASE_IDLE;
  }
  return AF_OK;
}
