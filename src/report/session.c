/* session.c — a bag through the core lane (see session.h). */
#define _POSIX_C_SOURCE 200809L
#include "session.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "af_bag.h"
#include "text.h"

#define AF_NS_PER_S 1000000000LL

enum { AF_TOPIC_FORCE = 0, AF_TOPIC_AUDIO, AF_TOPIC_APPLE, AF_TOPICS };

typedef struct {
  const af_session_options *o;
  af_session *s;
  af_lane *lane;
  bool out_of_memory;
} af_session_ctx;

static double clock_s(clockid_t id)
{
  struct timespec ts;
  clock_gettime(id, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static int64_t ns_of(af_time t)
{
  return (int64_t)t.sec * AF_NS_PER_S + (int64_t)t.nsec;
}

/* Room for one more of n elements of size bytes at *p (capacity *cap). */
static bool grow(void **p, size_t *cap, size_t n, size_t size)
{
  if (n < *cap)
    return true;
  size_t want = *cap ? 2 * *cap : 64;
  void *q = realloc(*p, want * size);
  if (!q)
    return false;
  *p = q;
  *cap = want;
  return true;
}

static af_session_apple *find_apple(af_session *s, uint32_t id)
{
  for (size_t k = s->n_apples; k-- > 0;) /* the newest estimate of that id */
    if (s->apples[k].apple_id == id)
      return &s->apples[k];
  return NULL;
}

/* The lane's callback: one row per measured strike. */
static void on_lane_strike(const af_lane_strike *ls, void *user)
{
  af_session_ctx *c = user;
  af_session *s = c->s;
  if (!grow((void **)&s->strikes, &s->cap_strikes, s->n_strikes, sizeof *s->strikes)) {
    c->out_of_memory = true;
    return;
  }
  af_session_strike *r = &s->strikes[s->n_strikes++];
  memset(r, 0, sizeof *r);
  r->start_ns = ls->start_ns;
  memcpy(r->frame_id, ls->frame_id, sizeof r->frame_id);
  r->apple_id = ls->apple_id;
  r->has_apple = ls->apple != NULL;
  r->mass_kg = NAN;
  r->predicted_band_low_hz = r->predicted_band_high_hz = r->predicted_resonance_hz = NAN;
  r->modulus_factor = ls->modulus_factor; /* the cultivar's or the learned one applied */
  const af_hammer_health_stats *h = &af_lane_get_stats(c->lane)->health; /* after this strike */
  r->hammer_velocity_m_s = h->last_velocity_m_s;
  r->hammer_velocity_mean_m_s = h->velocity_m_s;
  r->hammer_warnings = h->warnings;
  const af_factor_learn_state *f = af_lane_factor(c->lane); /* after this strike */
  r->factor_true = af_factor_learn_true(ls->modulus_factor, ls->report.modulus_from_resonance_pa,
                                        ls->report.fitted_modulus_pa);
  r->factor_estimate = f->estimate;
  r->factor_ci_low_95 = f->ci_low_95;
  r->factor_ci_high_95 = f->ci_high_95;
  r->factor_applied = f->applied;
  if (ls->apple) {
    r->apple_stamp_ns = ls->apple->stamp_ns;
    r->mass_kg = ls->apple->mass_kg;
  }
  const af_prediction *pr = ls->prediction;
  if (pr && pr->valid) {
    r->predicted = true;
    r->predicted_band_low_hz = pr->result.band.band_low_hz;
    r->predicted_band_high_hz = pr->result.band.band_high_hz;
    r->predicted_resonance_hz = pr->result.resonance_hz;
    r->predicted_reliable = pr->reliable;
    af_text(r->predicted_reason, sizeof r->predicted_reason, "%s", pr->reason);
  }
  r->with_audio = ls->with_audio;
  r->report = ls->report;
  r->grade = ls->grade;
  af_session_apple *a = ls->apple_id ? find_apple(s, ls->apple_id) : NULL;
  if (a)
    a->strikes++;
  if (c->o->on_strike)
    c->o->on_strike(ls, c->lane, c->o->user);
}

af_serial_strike af_session_serial(const af_session_strike *r)
{
  af_serial_strike v = {r->start_ns,   r->frame_id, r->apple_id,
                        r->with_audio, &r->report,  &r->grade};
  return v;
}

static bool add_apple(af_session_ctx *c, const af_apple *a, const af_prediction *pr)
{
  af_session *s = c->s;
  if (!grow((void **)&s->apples, &s->cap_apples, s->n_apples, sizeof *s->apples))
    return false;
  af_session_apple *r = &s->apples[s->n_apples++];
  memset(r, 0, sizeof *r);
  r->apple_id = a->apple_id;
  r->stamp_ns = a->stamp_ns;
  r->mass_kg = a->mass_kg;
  r->valid = pr && pr->valid;
  r->band_low_hz = r->valid ? pr->result.band.band_low_hz : NAN;
  r->band_high_hz = r->valid ? pr->result.band.band_high_hz : NAN;
  r->resonance_hz = r->valid ? pr->result.resonance_hz : NAN;
  r->reliable = r->valid && pr->reliable;
  if (pr)
    af_text(r->reason, sizeof r->reason, "%s", r->valid ? pr->reason : pr->why);
  return true;
}

/* The lane's view of an estimate: the node's conversion (station.c), the
 * strike direction unknown. */
static af_apple apple_of(const af_apple_estimate *e)
{
  af_apple a;
  memset(&a, 0, sizeof a);
  a.apple_id = e->apple_id;
  a.stamp_ns = ns_of(e->header.stamp);
  a.mass_kg = e->mass_kg;
  a.equatorial_radius_m = e->equatorial_radius_m;
  a.strike_radius_m = e->strike_radius_m;
  a.stem_axis[0] = e->stem_axis.x;
  a.stem_axis[1] = e->stem_axis.y;
  a.stem_axis[2] = e->stem_axis.z;
  a.confidence = e->confidence;
  af_text(a.direction_note, sizeof a.direction_note, "offline: strike direction unknown");
  return a;
}

static void note_stream(af_session_stream *st, const af_signal_chunk *c)
{
  int64_t t0 = ns_of(c->header.stamp);
  int64_t t1 = t0 + (int64_t)((double)c->n / c->sample_rate_hz * 1e9 + 0.5);
  if (st->first_ns == 0 || t0 < st->first_ns)
    st->first_ns = t0;
  if (t1 > st->end_ns)
    st->end_ns = t1;
}

static void copy_stream(af_session_stream *out, const af_stream *s)
{
  out->chunks = s->chunks;
  out->gaps = s->gaps;
  out->lost_samples = s->lost_samples;
  out->restarts = s->restarts;
  out->bad_rate = s->bad_rate;
  out->bad_unit = s->bad_unit;
  out->duplicates = s->duplicates;
  out->overlaps = s->overlaps;
  out->duplicate_samples = s->duplicate_samples;
  out->bad_index = s->bad_index;
  out->malformed = s->malformed;
  out->oversized = s->oversized;
  out->refused_samples = s->refused_samples;
  out->refused_spans = s->refused_spans;
  out->clock_steps = s->clock_steps;
  out->clock_frozen = s->clock_frozen;
  out->clock_rate_hz = s->clock_rate_hz;
  out->clock_rate_wrong = s->clock_rate_wrong;
  memcpy(out->clock_problem, s->clock_problem, sizeof out->clock_problem);
}

static void show_progress(uint64_t done, uint64_t total, bool final)
{
  const int width = 40;
  int filled = total ? (int)((double)done / (double)total * width) : width;
  char bar[64];
  for (int k = 0; k < width; k++)
    bar[k] = k < filled ? '#' : '.';
  bar[width] = '\0';
  fprintf(stderr, "\r[%s] %3.0f %% (%llu of %llu messages)%s", bar,
          total ? 100.0 * (double)done / (double)total : 100.0, (unsigned long long)done,
          (unsigned long long)total, final ? "\n" : "");
  fflush(stderr);
}

static const char *type_name(af_msg_type t)
{
  switch (t) {
  case AF_MSG_SIGNAL_CHUNK: return "acoustic_firmness/SignalChunk";
  case AF_MSG_APPLE_ESTIMATE: return "acoustic_firmness/AppleEstimate";
  case AF_MSG_STRIKE_REPORT: return "acoustic_firmness/StrikeReport";
  case AF_MSG_RELIABILITY: return "acoustic_firmness/Reliability";
  default: return "another type";
  }
}

/* A message the reader refused (too long, not its type): counted in its
 * stream (an apple's among the session's), one line on stderr for the 1st,
 * 2nd, 4th ... */
static uint64_t count_refused(af_session_ctx *c, int which, bool oversized, const char *why)
{
  uint64_t n = ++c->s->refused_messages;
  if (which == AF_TOPIC_APPLE)
    c->s->refused_apples++;
  else
    af_lane_refuse(c->lane, which == AF_TOPIC_FORCE, oversized, why);
  return n;
}

static void refused(af_session_ctx *c, int which, bool oversized, const char *why)
{
  uint64_t n = count_refused(c, which, oversized, why);
  if ((n & (n - 1)) == 0)
    fprintf(stderr, "firmness_report: %s: refused %s (%llu messages refused so far)\n",
            c->o->bag_path, why, (unsigned long long)n);
}

/* The longest chunk the stream of topic 'which' takes (the node's cap on
 * the wire for that stream). */
static size_t stream_cap(const af_session_ctx *c, int which)
{
  return which == AF_TOPIC_FORCE ? c->o->cfg->force.max_chunk_samples
                                 : c->o->cfg->audio.max_chunk_samples;
}

/* Every message of the three topics into the lane. */
static int feed(af_session_ctx *c, af_bag_reader *bag, char topics[AF_TOPICS][AF_SESSION_TOPIC_MAX],
                uint64_t total, char *err, size_t len)
{
  af_session *s = c->s;
  af_bag_message m;
  af_status st;
  uint64_t step = total / 200 + 1;
  /* Per topic: messages of its own type, those of another (the first's
   * type). A stray message of another type is refused alone, counted, and
   * said once per topic at the end; a topic with nothing but other types is
   * a wrong topic, and the bag is refused. */
  uint64_t own[AF_TOPICS] = {0}, others[AF_TOPICS] = {0};
  af_msg_type other[AF_TOPICS];
  while ((st = af_bag_read_next(bag, &m)) == AF_OK || st == AF_ESIZE || st == AF_EINVAL) {
    int64_t now = ns_of(m.bag_time);
    int which = strcmp(m.topic, topics[AF_TOPIC_FORCE]) == 0   ? AF_TOPIC_FORCE
                : strcmp(m.topic, topics[AF_TOPIC_AUDIO]) == 0 ? AF_TOPIC_AUDIO
                                                               : AF_TOPIC_APPLE;
    if (st != AF_OK) { /* one message refused: counted, said, the bag goes on */
      refused(c, which, st == AF_ESIZE, af_bag_reader_error(bag));
      continue;
    }
    af_msg_type want = which == AF_TOPIC_APPLE ? AF_MSG_APPLE_ESTIMATE : AF_MSG_SIGNAL_CHUNK;
    if (m.type != want) { /* one message of another type: refused, said at the end */
      if (others[which]++ == 0)
        other[which] = m.type;
      (void)count_refused(c, which, false, "a message of another type on this topic");
      continue;
    }
    own[which]++;
    s->messages++;
    if (which == AF_TOPIC_FORCE && c->o->cfg->strikes.tap_only)
      continue; /* tap-only: the strikes are the audio's onsets (said once by open) */
    if (which == AF_TOPIC_APPLE) {
      af_apple a = apple_of(&m.msg.apple);
      const af_prediction *pr = NULL;
      (void)af_lane_apple(c->lane, &a, now, &pr);
      if (!add_apple(c, &a, pr))
        c->out_of_memory = true;
    } else if (m.msg.chunk.n > stream_cap(c, which)) {
      char why[160];
      af_text(why, sizeof why,
              "a SignalChunk of %zu samples, above the cap of %zu (the ring; a longer chunk can "
              "never be used)",
              m.msg.chunk.n, stream_cap(c, which));
      refused(c, which, true, why);
    } else {
      const af_signal_chunk *k = &m.msg.chunk;
      af_chunk ch = {ns_of(k->header.stamp),
                     k->first_sample,
                     k->sample_rate_hz,
                     k->unit,
                     k->header.frame_id,
                     k->data,
                     k->n};
      if (which == AF_TOPIC_FORCE) {
        if (af_lane_force(c->lane, &ch, now, NULL) == AF_CHUNK_OK)
          note_stream(&s->force, k);
      } else if (af_lane_audio(c->lane, &ch, now, NULL) == AF_CHUNK_OK)
        note_stream(&s->audio, k);
    }
    if (c->out_of_memory) {
      af_text(err, len, "out of memory after %llu messages", (unsigned long long)s->messages);
      return AF_SESSION_FAILED;
    }
    if (c->o->progress && s->messages % step == 0)
      show_progress(s->messages, total, false);
  }
  af_lane_finish(c->lane);
  if (c->o->progress)
    show_progress(s->messages, total, true);
  for (int k = 0; k < AF_TOPICS; k++) {
    const char *want = type_name(k == AF_TOPIC_APPLE ? AF_MSG_APPLE_ESTIMATE : AF_MSG_SIGNAL_CHUNK);
    if (others[k] > 0 && own[k] == 0) {
      af_text(err, len, "topic %s carries %s, not %s", topics[k], type_name(other[k]), want);
      return AF_SESSION_BAD_INPUT;
    }
    if (others[k] > 0)
      fprintf(stderr,
              "firmness_report: %s: refused %llu message%s of another type on %s, which carries "
              "%s (the first: %s): counted, the rest of the bag read\n",
              c->o->bag_path, (unsigned long long)others[k], others[k] == 1 ? "" : "s", topics[k],
              want, type_name(other[k]));
  }
  if (c->out_of_memory) {
    af_text(err, len, "out of memory at the end of the bag");
    return AF_SESSION_FAILED;
  }
  if (st != AF_ENODATA) {
    af_text(err, len, "%s: the bag breaks after %llu messages (truncated?): %s", c->o->bag_path,
            (unsigned long long)s->messages, af_bag_reader_error(bag));
    return AF_SESSION_BAD_INPUT;
  }
  return AF_SESSION_OK;
}

/* Opens the bag and checks its topics; NULL with err on bad input. */
static af_bag_reader *open(const af_session_options *o,
                           char topics[AF_TOPICS][AF_SESSION_TOPIC_MAX], uint64_t *total, char *err,
                           size_t len)
{
  static const char *const names[AF_TOPICS] = {"force", "audio", "apple"};
  const char *list[AF_TOPICS];
  for (int k = 0; k < AF_TOPICS; k++) {
    af_text(topics[k], AF_SESSION_TOPIC_MAX, "/%s/%s", o->ns, names[k]);
    list[k] = topics[k];
  }
  af_bag_reader *bag = NULL;
  af_status st = af_bag_open_read(o->bag_path, list, AF_TOPICS, &bag);
  if (st != AF_OK) { /* the reader's line names the bag (and rosbag reindex when it helps) */
    af_text(err, len, "%s", af_bag_reader_error(NULL));
    return NULL;
  }
  /* A chunk longer than its ring can never be used: the reader's cap is the
   * longer stream's, and feed refuses each stream's longer chunks as the
   * node does on the wire (lane_config.h, max_chunk_samples). */
  size_t cap = o->cfg->force.max_chunk_samples > o->cfg->audio.max_chunk_samples
                   ? o->cfg->force.max_chunk_samples
                   : o->cfg->audio.max_chunk_samples;
  af_bag_reader_limit(bag, cap);
  *total = 0;
  const bool tap_only = o->cfg->strikes.tap_only;
  for (int k = 0; k < AF_TOPICS; k++) {
    size_t n = af_bag_topic_count(bag, topics[k]);
    if (k == AF_TOPIC_FORCE && tap_only) { /* a microphone-only rig: none expected */
      if (n > 0)
        fprintf(stderr,
                "firmness_report: %s: tap_only is set: the %zu messages on %s are not read\n",
                o->bag_path, n, topics[k]);
      *total += n;
      continue;
    }
    if (n == 0) {
      af_text(err, len, "%s: no message on %s (is the lane namespace --ns %s right?%s)",
              o->bag_path, topics[k], o->ns,
              k == AF_TOPIC_FORCE ? " A microphone-only rig: --set tap_only=true" : "");
      af_bag_close_read(bag);
      return NULL;
    }
    *total += n;
  }
  return bag;
}

/* Takes (enter) or gives back the options' setup lock, when there is one. */
static void setup(const af_session_options *o, bool enter)
{
  if (o->setup_lock != NULL)
    (void)(enter ? pthread_mutex_lock(o->setup_lock) : pthread_mutex_unlock(o->setup_lock));
}

int af_session_execute(const af_session_options *o, af_session *out, char *err, size_t len)
{
  memset(out, 0, sizeof *out);
  double wall0 = clock_s(CLOCK_MONOTONIC), cpu0 = clock_s(CLOCK_THREAD_CPUTIME_ID);
  char topics[AF_TOPICS][AF_SESSION_TOPIC_MAX];
  uint64_t total = 0;
  af_session_ctx c = {o, out, NULL, false};
  const char *what = "the lane";
  setup(o, true);
  af_bag_reader *bag = open(o, topics, &total, err, len);
  const int64_t t0_ns = af_stage_begin(o->cfg->strikes.measure.stages);
  af_status st = bag ? af_lane_create(o->cfg, on_lane_strike, &c, &c.lane, &what) : AF_EINVAL;
  af_stage_end(o->cfg->strikes.measure.stages, AF_STAGE_SETUP, t0_ns);
  if (bag && st != AF_OK) {
    af_text(err, len, "could not create %s: %s", what, af_strerror(st));
    af_bag_close_read(bag);
  }
  setup(o, false);
  if (!bag)
    return AF_SESSION_BAD_INPUT;
  if (st != AF_OK)
    return AF_SESSION_FAILED;
  int code = feed(&c, bag, topics, total, err, len);
  out->stats = *af_lane_get_stats(c.lane);
  out->health_cfg = o->cfg->health;
  out->factor = *af_lane_factor(c.lane);
  copy_stream(&out->force, af_lane_force_stream(c.lane));
  copy_stream(&out->audio, af_lane_audio_stream(c.lane));
  setup(o, true);
  af_lane_destroy(c.lane);
  af_bag_close_read(bag);
  setup(o, false);
  const af_session_stream *timed = o->cfg->strikes.tap_only ? &out->audio : &out->force;
  out->recorded_s = (double)(timed->end_ns - timed->first_ns) * 1e-9;
  out->tap_only = o->cfg->strikes.tap_only;
  out->wall_s = clock_s(CLOCK_MONOTONIC) - wall0;
  out->cpu_s = clock_s(CLOCK_THREAD_CPUTIME_ID) - cpu0;
  return code;
}

void af_session_destroy(af_session *s)
{
  if (!s)
    return;
  free(s->strikes);
  free(s->apples);
  memset(s, 0, sizeof *s);
}
