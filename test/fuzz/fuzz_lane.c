/* fuzz_lane.c — libFuzzer harness: one core lane (src/core/lane/lane.h) per
 * input, without the tools' set-up. The fast one: fuzz_analyze goes through
 * the whole `firmness_model analyze` (files, YAML, a lane made per input);
 * here the configurations and the lanes are made once, at the first input,
 * from the parameter table's defaults and the shipped rig's hammer (as a
 * desk tool, af_lane_config_for_tool), and every input starts from
 * af_lane_reset.
 *
 * The input is a program: a header byte, then operations, each an op byte
 * and its arguments (a byte missing reads as 0, so every input is valid):
 *   header   bits 0-1 the lane: 0 and 3 the node's (force in N), 1 tap-only,
 *            2 a force in V; bit 2 one apple a recording (single_apple, the
 *            desk tools') instead of the transit match; bit 3 stamps from
 *            1.7e9 s instead of 0; bits 4-7 the noise level
 *   op & 3 = 0 / 1  a force / audio chunk:
 *            length byte (& 15: lengths of 0 to past the ring, oversized
 *            ones refused as the node refuses them off the wire);
 *            op bits 2-3 the rate (3: one more byte, a wrong or a
 *            non-finite rate), 4-5 the stamp (continuous, jitter, a step, any
 *            ROS time), 6-7 the first index (continuous, a gap, back: an
 *            overlap, a duplicate or a restart, any 64-bit index);
 *            the source byte: bits 0-1 synthetic (noise, offset, the latest
 *            event: a force pulse, an audio ring) or raw int16 / float32
 *            bytes; bit 2 a new event here (position, amplitude, shape
 *            bytes); bits 3-4 NaN, inf or -inf injected (position, run
 *            bytes); bits 5-6 the unit (accepted, the second accepted,
 *            wrong, none); bit 7 a frame id longer than the stream keeps
 *   op & 3 = 2  an apple estimate: id, stamp (near the data or any ROS
 *            time), mass, radii, confidence (special values: 0, negative,
 *            NaN, inf), stem axis and strike direction
 *   op & 3 = 3  the clock: poll later, a lag of the clock behind the chunks,
 *            a chunk refused on the wire, any ROS time
 * until the bytes, AF_FUZZ_OPS_MAX operations, the sample budget or the
 * strikes allowed (below) run out; then af_lane_finish. Synthetic samples are a function of their
 * index, so that a chunk sent again holds the same values (the duplicate and overlap paths). Stamps
 * and the clock stay ROS times ([0, 2^32) s, as the node's messages carry them).
 *
 * Checked: no crash, leak, sanitizer report or hang; every strike reported
 * has a NUL-terminated frame and reason, its apple id and estimate agree,
 * its event is given; every prediction is filled; nothing is pending after
 * af_lane_finish. */
#include <math.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "lane.h"
#include "lane_config.h"
#include "serialize.h"
#include "settings.h"
#include "tool_config.h"

#define AF_FUZZ_LANES 3
#define AF_FUZZ_OPS_MAX 256
/* Samples per input at most (both streams, and the NaN a gap writes into
 * a ring, weighed): 0.16 s of both at 50 and 48 kHz, room for a
 * strike, its audio window and an estimate stamped its transit before it;
 * beyond, the input ends. */
#define AF_FUZZ_SAMPLES_MAX ((size_t)1 << 14)
/* Strikes per input at most (reported or pending): the input ends once it
 * has made one (a chunk may still bring a second). Measuring one takes
 * milliseconds under the sanitizers (the pulse fit's ODE, the response's fit
 * of the audio), every other operation microseconds: at two, strikes took
 * over half the time (about 750 inputs per CPU second; one: about 1,000).
 * What needs several strikes (the same apple twice, the full queue, the
 * lag and transit statistics) is test_lane's, and fuzz_msgs' and
 * fuzz_analyze's, whose inputs are not capped. */
#define AF_FUZZ_STRIKES_MAX 1
#define AF_FUZZ_ROS_TIME_MAX_NS ((int64_t)UINT32_MAX * 1000000000 + 999999999)
#define AF_FUZZ_PI 3.14159265358979323846

/* The bytes of one input, read from the front; past the end reads 0. */
typedef struct {
  const uint8_t *p;
  size_t n;
} af_fuzz_bytes;

static uint8_t u8(af_fuzz_bytes *b)
{
  if (b->n == 0)
    return 0;
  b->n--;
  return *b->p++;
}

static uint64_t u64(af_fuzz_bytes *b, int bytes)
{
  uint64_t v = 0;
  for (int k = 0; k < bytes; k++)
    v |= (uint64_t)u8(b) << (8 * k);
  return v;
}

static int64_t clamp_ros_ns(int64_t t)
{
  return t < 0 ? 0 : t > AF_FUZZ_ROS_TIME_MAX_NS ? AF_FUZZ_ROS_TIME_MAX_NS : t;
}

/* Any ROS time: seconds (4 bytes) and nanoseconds below 1e9 (4 bytes). */
static int64_t ros_time_ns(af_fuzz_bytes *b)
{
  const int64_t sec = (int64_t)u64(b, 4);
  return sec * 1000000000 + (int64_t)(u64(b, 4) % 1000000000u);
}

/* ---- the lanes, made once ------------------------------------------------- */

typedef struct {
  af_lane_config cfg;
  af_lane *lane;
} af_fuzz_lane;

static af_fuzz_lane lanes[AF_FUZZ_LANES];
static float *samples; /* the longest chunk taken, + 1 (an oversized one is not filled) */
static size_t samples_cap;
static bool
    verbose; /* AF_FUZZ_LANE_VERBOSE set: a line per strike on stderr (what a seed reaches) */

static void on_strike(const af_lane_strike *s, void *user);

/* The table's defaults, the shipped rig's hammer, and the rows set[] on top. */
static void make_one(af_fuzz_lane *f, const char *const *set, size_t n_set)
{
  af_settings s;
  char err[512];
  const char *what = "";
  af_settings_reset(&s);
  for (size_t k = 0; k < n_set; k++)
    if (af_settings_set_arg(&s, set[k], err, sizeof err) != AF_OK)
      abort();
  if (af_lane_config_for_tool(&s, &f->cfg, err, sizeof err) != AF_OK ||
      af_lane_create(&f->cfg, on_strike, NULL, &f->lane, &what) != AF_OK)
    abort();
  const size_t longest = f->cfg.force.max_chunk_samples > f->cfg.audio.max_chunk_samples
                             ? f->cfg.force.max_chunk_samples
                             : f->cfg.audio.max_chunk_samples;
  if (longest > samples_cap)
    samples_cap = longest;
}

static void destroy_lanes(void)
{
  for (size_t k = 0; k < AF_FUZZ_LANES; k++)
    af_lane_destroy(lanes[k].lane);
  free(samples);
}

/* The node's lane, a microphone-only rig, a force transducer read in V. */
static void make_lanes(void)
{
  static const char *const tap[] = {"tap_only=true"};
  static const char *const volts[] = {"force_unit=V", "force_sensitivity_v_per_n=0.0225"};
  make_one(&lanes[0], NULL, 0);
  make_one(&lanes[1], tap, 1);
  make_one(&lanes[2], volts, 2);
  samples = malloc((samples_cap + 1) * sizeof *samples);
  if (samples == NULL)
    abort();
  atexit(destroy_lanes); /* libFuzzer ends with exit(): LeakSanitizer sees nothing held */
  verbose = getenv("AF_FUZZ_LANE_VERBOSE") != NULL;
}

/* ---- the strikes ---------------------------------------------------------- */

static bool has_nul(const char *s, size_t len)
{
  return memchr(s, '\0', len) != NULL;
}

/* What lane.h promises of every strike; the serializer's view of it is made
 * as the node's publisher makes it. */
static size_t strikes_reported; /* in this input */

static void on_strike(const af_lane_strike *s, void *user)
{
  (void)user;
  strikes_reported++;
  if (!has_nul(s->frame_id, sizeof s->frame_id) ||
      !has_nul(s->report.reason, sizeof s->report.reason) || s->event == NULL ||
      (s->apple == NULL) != (s->apple_id == 0) ||
      (s->apple != NULL && s->apple->apple_id != s->apple_id))
    abort();
  const af_serial_strike v = af_serial_of_lane(s);
  (void)v;
  if (verbose)
    fprintf(stderr, "strike at %.6f s, apple %u, 0S2 %g Hz: %s\n", (double)s->start_ns * 1e-9,
            s->apple_id, s->report.resonance_hz, s->report.reason);
}

/* ---- one input ------------------------------------------------------------ */

/* One stream as the input drives it: where it goes on, and its event (a force
 * pulse or an audio ring) that synthetic samples carry. */
typedef struct {
  bool force;
  const af_stream_config *cfg;
  uint64_t next_index;
  int64_t next_stamp_ns;
  uint64_t event_index; /* UINT64_MAX: none */
  double event_amp, event_shape;
} af_fuzz_stream;

typedef struct {
  af_fuzz_lane *f;
  af_fuzz_bytes in;
  af_fuzz_stream force, audio;
  double noise;
  int64_t now_ns, lag_ns;
  size_t samples_left;
} af_fuzz_run;

/* Noise that is a function of the index (a hash to [-1, 1)). */
static double noise_at(uint64_t i)
{
  i ^= i >> 33;
  i *= 0xff51afd7ed558ccdULL;
  i ^= i >> 33;
  return (double)(i >> 11) / (double)(1ULL << 52) - 1.0;
}

/* The latest event at sample i: a Hertz-like sin^1.5 pulse of event_shape
 * samples (force), or a ring decaying with Q 30 at event_shape Hz (audio). */
static double event_at(const af_fuzz_stream *s, uint64_t i)
{
  if (s->event_index == UINT64_MAX || i < s->event_index)
    return 0.0;
  const double u = (double)(i - s->event_index);
  if (s->force)
    return u < s->event_shape ? s->event_amp * pow(sin(AF_FUZZ_PI * u / s->event_shape), 1.5) : 0.0;
  const double t = u / s->cfg->sample_rate_hz;
  if (t > 0.5)
    return 0.0;
  return s->event_amp * exp(-AF_FUZZ_PI * s->event_shape / 30.0 * t) *
         sin(2.0 * AF_FUZZ_PI * s->event_shape * t);
}

static void synthetic(const af_fuzz_run *r, const af_fuzz_stream *s, uint64_t first, size_t n)
{
  const double offset = s->force ? 0.3 : 0.0, scale = s->force ? 1.0 : 0.05;
  /* A force in V: the lane divides by the sensitivity (to_si), so the
   * samples are made in V. */
  const double to_v = s->cfg->to_si > 0.0 ? 1.0 / s->cfg->to_si : 1.0;
  for (size_t k = 0; k < n; k++) {
    const uint64_t i = first + k;
    const double x =
        offset + scale * r->noise * noise_at(i ^ (s->force ? 0 : 0x5bd1e995)) + event_at(s, i);
    samples[k] = (float)(x * (s->force ? to_v : 1.0));
  }
}

/* Raw samples from the input: int16 (times a scale byte's power of two) or
 * float32 bytes as they are (any pattern: NaN, inf, denormals); past the
 * input's end, zeros. */
static void raw(af_fuzz_run *r, bool float32, size_t n)
{
  const double scale = ldexp(1.0, (int)u8(&r->in) / 8 - 20);
  for (size_t k = 0; k < n; k++) {
    if (r->in.n == 0) {
      samples[k] = 0.0f;
      continue;
    }
    const uint32_t w = (uint32_t)u64(&r->in, float32 ? 4 : 2);
    float v;
    memcpy(&v, &w, sizeof v);
    samples[k] = float32 ? v : (float)((double)(int16_t)w * scale);
  }
}

/* A new event in this chunk: at a fraction of it, its amplitude and shape. */
static void new_event(af_fuzz_run *r, af_fuzz_stream *s, uint64_t first, size_t n)
{
  s->event_index = first + (uint64_t)u8(&r->in) * n / 256;
  const uint8_t amp = u8(&r->in), shape = u8(&r->in);
  s->event_amp = s->force ? 0.25 * amp : 0.01 * amp;
  /* a contact of 4 to 89 samples (0.1 to 1.8 ms at 50 kHz); a ring of 200
   * to 2750 Hz */
  s->event_shape = s->force ? 4.0 + shape / 3.0 : 200.0 + 10.0 * shape;
}

/* NaN, inf or -inf over a run of the chunk. */
static void inject(af_fuzz_run *r, int what, size_t n)
{
  const size_t at = n * u8(&r->in) / 256, run = 1 + u8(&r->in);
  const float v = what == 1 ? NAN : what == 2 ? INFINITY : -INFINITY;
  for (size_t k = at; k < n && k < at + run; k++)
    samples[k] = v;
}

/* The unit: the accepted one, the second accepted (when there is one), a
 * wrong one, none. */
static const char *unit_of(const af_fuzz_stream *s, int which)
{
  switch (which) {
  case 1: return s->cfg->units[1][0] != '\0' ? s->cfg->units[1] : s->cfg->units[0];
  case 2: return "furlong";
  case 3: return NULL;
  default: return s->cfg->units[0];
  }
}

/* The chunk's rate: the configured one, or (op bits 2-3 = 3) one of those a
 * sender gets wrong. */
static double rate_of(af_fuzz_run *r, const af_fuzz_stream *s, uint8_t op)
{
  const double rate = s->cfg->sample_rate_hz;
  if (((op >> 2) & 3) != 3)
    return rate;
  const double other = (s->force ? r->audio.cfg : r->force.cfg)->sample_rate_hz;
  const double wrong[8] = {0.0, -rate, NAN, INFINITY, rate * (1.0 + 1e-5), other, 44100.0, 1e6};
  return wrong[u8(&r->in) & 7];
}

/* The stamp of a chunk starting at first: where the stream's own clock puts
 * it (a gap or a step back in the index moves it by the samples), jittered,
 * stepped, or any ROS time. */
static int64_t stamp_of(af_fuzz_run *r, const af_fuzz_stream *s, uint8_t op, uint64_t first)
{
  const double samples_s = ((double)first - (double)s->next_index) / s->cfg->sample_rate_hz;
  /* bounded by the span of ROS times, so that the sum cannot overflow */
  const double span_ns = (double)AF_FUZZ_ROS_TIME_MAX_NS;
  const int64_t along =
      clamp_ros_ns(s->next_stamp_ns + (int64_t)fmax(fmin(samples_s * 1e9, span_ns), -span_ns));
  switch ((op >> 4) & 3) {
  case 1: /* jitter of +-1.28 ms */
    return clamp_ros_ns(along + (int64_t)(int8_t)u8(&r->in) * 10000);
  case 2: /* a step of +-32 s */
    return clamp_ros_ns(along + (int64_t)(int16_t)u64(&r->in, 2) * 1000000);
  case 3: return ros_time_ns(&r->in);
  default: return along;
  }
}

static uint64_t index_of(af_fuzz_run *r, const af_fuzz_stream *s, uint8_t op)
{
  switch ((op >> 6) & 3) {
  case 1: /* a gap */ return s->next_index + u64(&r->in, 2);
  case 2: { /* back: an overlap, a duplicate or a restart */
    const uint64_t back = u64(&r->in, 2);
    return back < s->next_index ? s->next_index - back : 0;
  }
  case 3: return u64(&r->in, 8);
  default: return s->next_index;
  }
}

/* The samples of a chunk: synthetic or raw, an event, an injection. */
static void fill(af_fuzz_run *r, af_fuzz_stream *s, uint8_t src, uint64_t first, size_t n)
{
  if ((src & 3) >= 2)
    raw(r, (src & 3) == 3, n);
  if (src & 4)
    new_event(r, s, first, n);
  if ((src & 3) < 2)
    synthetic(r, s, first, n);
  if ((src >> 3) & 3)
    inject(r, (src >> 3) & 3, n);
}

static const size_t af_fuzz_lengths[16] = {0,   1,    2,    17,   64,   100,  256, 480,
                                           512, 1000, 1024, 1024, 2048, 4096, 0,   0};

static size_t length_of(af_fuzz_run *r, const af_fuzz_stream *s)
{
  const int k = u8(&r->in) & 15;
  /* the longest chunk taken (the ring), and one longer */
  return k == 14   ? s->cfg->max_chunk_samples
         : k == 15 ? s->cfg->max_chunk_samples + 1
                   : af_fuzz_lengths[k];
}

static void chunk(af_fuzz_run *r, uint8_t op)
{
  af_fuzz_stream *s = (op & 3) == 0 ? &r->force : &r->audio;
  const size_t n = length_of(r, s);
  const double rate = rate_of(r, s, op);
  const uint64_t first = index_of(r, s, op);
  const int64_t stamp = stamp_of(r, s, op, first);
  const uint8_t src = u8(&r->in);
  if (n > s->cfg->max_chunk_samples) { /* the node refuses it off the wire */
    af_lane_refuse(r->f->lane, s->force, true, "fuzz: a chunk longer than the ring");
    return;
  }
  /* A gap costs the ring its NaN, up to the ring's length: a sample's
   * sixteenth (a fill, against the conversion, the detector, the checks). */
  const uint64_t gap = first > s->next_index ? first - s->next_index : 0;
  const size_t hole = (size_t)(gap < s->cfg->capacity_samples ? gap : s->cfg->capacity_samples);
  const size_t cost = n + hole / 16;
  if (cost > r->samples_left) {
    r->in.n = 0; /* the input's budget is spent: it ends here */
    return;
  }
  r->samples_left -= cost;
  fill(r, s, src, first, n);
  static const char long_frame[] = "a_frame_id_longer_than_the_stream_keeps_0123456789_0123456789_"
                                   "0123456789_0123456789";
  const af_chunk c = {stamp,
                      first,
                      rate,
                      unit_of(s, (src >> 5) & 3),
                      (src & 0x80) ? long_frame : "fuzz",
                      n > 0 ? samples : NULL,
                      n};
  r->now_ns =
      clamp_ros_ns(stamp + (int64_t)llround((double)n / s->cfg->sample_rate_hz * 1e9) + r->lag_ns);
  if (s->force)
    (void)af_lane_force(r->f->lane, &c, r->now_ns, NULL);
  else
    (void)af_lane_audio(r->f->lane, &c, r->now_ns, NULL);
  s->next_index = first + n < first ? UINT64_MAX : first + n;
  s->next_stamp_ns =
      clamp_ros_ns(stamp + (int64_t)llround((double)n / s->cfg->sample_rate_hz * 1e9));
}

/* A byte into a figure of an estimate: lo + b / 249 of [lo, hi] for b < 250,
 * else a value no camera should send. */
static double figure(uint8_t b, double lo, double hi)
{
  static const double bad[6] = {0.0, -0.05, NAN, INFINITY, 1e300, 1e-300};
  return b < 250 ? lo + (hi - lo) * b / 249.0 : bad[b - 250];
}

/* -1, 0 or 1 for each axis, from two bits each. */
static void axis(uint8_t b, double v[3])
{
  for (int k = 0; k < 3; k++)
    v[k] = (double)((b >> (2 * k)) & 3) - 1.0 - (((b >> (2 * k)) & 3) == 3);
}

static void apple(af_fuzz_run *r)
{
  af_apple a;
  memset(&a, 0, sizeof a);
  const uint8_t id = u8(&r->in);
  a.apple_id = id < 255 ? id : (uint32_t)u64(&r->in, 4);
  const uint8_t when = u8(&r->in);
  const af_fuzz_stream *data = r->f->cfg.strikes.tap_only ? &r->audio : &r->force;
  /* near the data: -1.28 to +1.26 s of the stream's next stamp; or any */
  a.stamp_ns = when < 255 ? clamp_ros_ns(data->next_stamp_ns + ((int64_t)when - 128) * 10000000)
                          : ros_time_ns(&r->in);
  a.mass_kg = figure(u8(&r->in), 0.02, 0.6);
  a.equatorial_radius_m = figure(u8(&r->in), 0.015, 0.07);
  a.strike_radius_m = figure(u8(&r->in), 0.0, 0.08);
  a.confidence = figure(u8(&r->in), 0.0, 1.0);
  axis(u8(&r->in), a.stem_axis);
  axis(u8(&r->in), a.strike_direction);
  const af_prediction *pr = NULL;
  (void)af_lane_apple(r->f->lane, &a, r->now_ns, &pr);
  if (pr == NULL)
    abort(); /* always filled (lane.h) */
}

static void clock_op(af_fuzz_run *r, uint8_t op)
{
  switch ((op >> 2) & 3) {
  case 0: /* later by up to 655 ms */
    r->now_ns = clamp_ros_ns(r->now_ns + (int64_t)u64(&r->in, 2) * 10000);
    af_lane_poll(r->f->lane, r->now_ns);
    break;
  case 1: /* the clock behind (or ahead of) the chunks' ends by up to 1.28 s */
    r->lag_ns = (int64_t)(int8_t)u8(&r->in) * 10000000;
    break;
  case 2: {
    const uint8_t b = u8(&r->in);
    af_lane_refuse(r->f->lane, b & 1, b & 2, "fuzz: a message cut on the wire");
    break;
  }
  default: r->now_ns = ros_time_ns(&r->in); af_lane_poll(r->f->lane, r->now_ns);
  }
}

static void start(af_fuzz_run *r, const uint8_t *data, size_t size)
{
  memset(r, 0, sizeof *r);
  r->in = (af_fuzz_bytes){data, size};
  const uint8_t h = u8(&r->in);
  r->f = &lanes[(h & 3) == 3 ? 0 : h & 3];
  /* The lane reads it at every match (nothing holds a copy): the owner's to set. */
  r->f->cfg.strikes.single_apple = (h & 4) != 0;
  const int64_t t0 = (h & 8) ? (int64_t)1700000000 * 1000000000 : 0;
  r->force = (af_fuzz_stream){true, &r->f->cfg.force, 0, t0, UINT64_MAX, 0.0, 1.0};
  r->audio = (af_fuzz_stream){false, &r->f->cfg.audio, 0, t0, UINT64_MAX, 0.0, 1.0};
  r->noise = 0.02 * (h >> 4);
  r->now_ns = t0;
  r->samples_left = AF_FUZZ_SAMPLES_MAX;
  af_lane_reset(r->f->lane);
  strikes_reported = 0;
}

/* The input goes on while it has bytes, operations and strikes left. */
static bool more(const af_fuzz_run *r, int ops)
{
  return r->in.n > 0 && ops < AF_FUZZ_OPS_MAX &&
         strikes_reported + af_lane_pending(r->f->lane) < AF_FUZZ_STRIKES_MAX;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
  if (samples == NULL)
    make_lanes();
  af_fuzz_run r;
  start(&r, data, size);
  for (int k = 0; more(&r, k); k++) {
    const uint8_t op = u8(&r.in);
    if ((op & 3) < 2)
      chunk(&r, op);
    else if ((op & 3) == 2)
      apple(&r);
    else
      clock_op(&r, op);
  }
  af_lane_finish(r.f->lane);
  if (af_lane_pending(r.f->lane) != 0)
    abort(); /* finish measures every pending strike (lane.h) */
  return 0;
}
