/* stream.h — one sampled input of a lane (force or audio): each chunk checked
 * (rate, unit, finite data), buffered in its ring (ring.h) and counted.
 *
 * Time <-> sample index: the stream keeps the stamp and first_sample of its
 * recent accepted chunks (the stamp is the time of the chunk's first
 * sample), and maps through the chunk that holds the sample or the time:
 * sample i is at stamp + (i - first_sample) / rate and time t at index
 * first_sample + (t - stamp) rate. The holding chunk, not the first: a gap
 * re-anchors the mapping and a clock that drifts against the sample counter
 * is followed chunk by chunk; not the latest either: the answer must not
 * depend on how far the stream has got when it is asked (the node and a desk
 * tool ask at different moments, and the stamps of consecutive chunks carry
 * their own rounding). A restart forgets the anchors. Times are integer
 * nanoseconds (a double of seconds since 1970 keeps only ~0.2 us).
 *
 * No ROS: the node converts SignalChunk messages, the desk tools recordings,
 * into af_chunk. No allocation after af_stream_create. */
#ifndef AF_STREAM_H
#define AF_STREAM_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "lane_config.h"
#include "ring.h"

#ifdef __cplusplus
extern "C" {
#endif

#define AF_STREAM_TEXT_MAX 256
#define AF_STREAM_FRAME_MAX 64
/* Chunk anchors kept for the mapping: 512 chunks of 1024 samples are 10 s
 * at 50 kHz, longer than a strike ever waits; older times map through the
 * oldest anchor kept. */
#define AF_STREAM_ANCHORS 512
/* Samples converted at a time when the stream's unit is not the lane's
 * (cfg->to_si != 1, a force in volts): the scratch made at init. */
#define AF_STREAM_BLOCK 4096
/* Spans of refused samples remembered for af_stream_refused_in: more than a
 * strike's pulse and audio window can ever meet between two strikes. */
#define AF_STREAM_SPANS 64
/* The stamps' rate is judged over this much of the stream [s], against the
 * rate sent with the chunks, with this tolerance [-]: far above a crystal's
 * 100 ppm and a capture stack's jitter over that span, far below the 8.8 %
 * of 44.1 kHz labelled 48 kHz. */
#define AF_STREAM_RATE_SPAN_S 2.0
#define AF_STREAM_RATE_TOL 0.01

typedef struct {
  int64_t stamp_ns;      /* time of the chunk's first sample [ns] */
  uint64_t first_sample; /* its running index */
} af_stream_anchor;

/* One chunk of samples, borrowed for the call. */
typedef struct {
  int64_t stamp_ns;      /* time of x[0] [ns] */
  uint64_t first_sample; /* running index of x[0] */
  double sample_rate_hz; /* as sent [Hz] */
  const char *unit;      /* as sent */
  const char *frame_id;  /* may be NULL */
  const float *x;        /* n samples */
  size_t n;
} af_chunk;

/* A run of refused (non-finite) samples [first, end) of one chunk. */
typedef struct {
  uint64_t first, end;
} af_stream_span;

typedef enum {
  AF_CHUNK_OK = 0,    /* accepted (its non-finite samples, if any, refused as spans) */
  AF_CHUNK_BAD_RATE,  /* sample_rate differs from the configured one */
  AF_CHUNK_BAD_UNIT,  /* unit not accepted for this stream */
  AF_CHUNK_BAD_INDEX, /* first_sample + n past 2^64 */
  AF_CHUNK_MALFORMED, /* n samples but no data */
  AF_CHUNK_DUPLICATE  /* every sample already held, the same values: ignored, not refused */
} af_chunk_verdict;

typedef struct {
  const char *name; /* "force" or "audio" */
  const af_stream_config *cfg;
  af_ring *ring;
  uint64_t chunks;            /* accepted */
  uint64_t gaps;              /* accepted chunks that followed lost samples */
  uint64_t lost_samples;      /* samples missing in those gaps */
  uint64_t restarts;          /* first_sample went backwards */
  uint64_t duplicates;        /* chunks repeating held samples (ignored) */
  uint64_t overlaps;          /* chunks whose head repeats the ring's last samples (tail kept) */
  uint64_t duplicate_samples; /* samples already held, sent again: of duplicates and overlaps */
  uint64_t bad_rate, bad_unit, bad_index; /* refused chunks, by reason */
  uint64_t malformed;                     /* refused before conversion: af_stream_refuse */
  uint64_t oversized;                     /* longer than the wire cap: af_stream_refuse */
  /* Non-finite samples (as sent or once converted to the lane's unit) of
   * accepted chunks: held as NaN in the ring (a lost sample to every reader),
   * counted, and their spans kept for af_stream_refused_in. */
  uint64_t refused_samples, refused_spans;
  uint64_t refused_chunks; /* accepted chunks with refused samples */
  uint64_t last_refused;   /* refused samples of the latest accepted chunk */
  size_t last_held;        /* samples at the head of the latest accepted chunk already held (an
                              overlap): its new samples start at x[last_held] */
  bool last_as_sent;       /* those new samples were held as sent (in the lane's unit, every
                              one finite): a reader may take them from the chunk itself */
  af_stream_span spans[AF_STREAM_SPANS]; /* newest at span_next - 1 */
  size_t span_next, span_count;
  bool seen;          /* a chunk was accepted */
  int64_t last_rx_ns; /* lane time of the last accepted chunk [ns] */
  char last_problem[AF_STREAM_TEXT_MAX];
  /* The recent accepted chunks (a ring, newest at anchor_next - 1) and the
   * latest one's frame. */
  af_stream_anchor anchors[AF_STREAM_ANCHORS];
  size_t anchor_next, anchor_count;
  char frame_id[AF_STREAM_FRAME_MAX];
  /* The clock (af_stream_push): each contiguous chunk's stamp against the
   * previous chunk's stamp + the samples between / rate. A difference beyond
   * cfg->clock_step_s is a step; a stamp that does not advance while the
   * samples do, frozen; stamps advancing at a rate beyond AF_STREAM_RATE_TOL
   * of the chunks' own over AF_STREAM_RATE_SPAN_S, a stamp clock that
   * contradicts the sample rate (a card running at 44.1 kHz labelled 48). */
  uint64_t clock_steps, clock_frozen;
  double clock_last_step_s;    /* the latest step [s]: stamp minus expected */
  double clock_rate_hz;        /* the rate the stamps advance at since the last fault; NaN: not
                                  yet AF_STREAM_RATE_SPAN_S of it */
  bool clock_rate_wrong;       /* clock_rate_hz beyond AF_STREAM_RATE_TOL of the rate */
  int64_t clock_fault_ns;      /* stamp of the latest fault's chunk; 0: none */
  af_stream_anchor clock_base; /* the chunk the rate is measured from */
  bool clock_based;
  char clock_problem[AF_STREAM_TEXT_MAX]; /* the latest clock fault in words; "" when none */
  float *si; /* AF_STREAM_BLOCK samples in the lane's unit, non-finite ones as NaN; then
                AF_STREAM_BLOCK of the ring's, to compare a duplicate */
} af_stream;

/* out[k] = x[k] * to_si, k < n: a sample as sent into the lane's unit (a
 * force in V times 1 / sensitivity [N/V] = N); NaN where that is not finite
 * (a refused sample). to_si 0 (a config made without a unit) counts as 1.
 * Returns the number of NaN written. out may be x. */
size_t af_stream_to_si(double to_si, const float *x, size_t n, float *out);

/* Makes the ring (capacity from cfg, which must outlive s) and the
 * conversion scratch. AF_ENOMEM. */
af_status af_stream_create(af_stream *s, const char *name, const af_stream_config *cfg);
void af_stream_destroy(af_stream *s); /* safe on a zeroed or finished stream */
/* Forgets every chunk: s as af_stream_create left it, its ring empty (the
 * ring and the scratch kept). No allocation. */
void af_stream_reset(af_stream *s);

/* Checks one chunk (as sent: its unit, its rate, its indices) and buffers
 * it, times cfg->to_si, when good; a refused chunk is counted and described
 * in s->last_problem. A non-finite sample does not refuse the chunk: it is
 * held as NaN and counted as refused (refused_samples, one span per run).
 * A chunk that starts inside the ring's last samples and runs past them,
 * with those samples as held (value for value, at the same time within half
 * a sample), is an overlap: the new tail is buffered, the repeated head
 * counted in duplicate_samples (not a restart). Otherwise a chunk that goes
 * back is a restart.
 * *info (may be NULL) tells of gaps and restarts. now_ns: the lane's clock
 * at arrival. No allocation. */
af_chunk_verdict af_stream_push(af_stream *s, const af_chunk *c, int64_t now_ns,
                                af_ring_write_info *info);

/* af_stream_time_ns and af_stream_time_of_ns saturate at +- this [ns] (2^62 - 1, 146
 * years; ROS times end at 2^32 s, 4.3e18 ns): an index far from every
 * anchor saturates, and the difference of two such times never overflows. */
#define AF_STREAM_TIME_MAX_NS ((int64_t)4611686018427387903)

/* Time [ns] of the (fractional) sample index, through the newest chunk
 * starting at or before it (the oldest kept for earlier indices); meaningful
 * once s->seen. */
int64_t af_stream_time_ns(const af_stream *s, double index);
/* The (fractional) sample index at time t_ns, through the newest chunk
 * stamped at or before it (the oldest kept for earlier times). */
double af_stream_index_at(const af_stream *s, int64_t t_ns);

/* The same two in integer sample indices, whole and fraction in [0, 1): a
 * running index beyond 2^53 (a DAQ's counter after a long run, or one that
 * starts high) keeps its sub-sample part, which a double would round away.
 * af_stream_pos_at: false when t_ns lies before sample 0. */
int64_t af_stream_time_of_ns(const af_stream *s, uint64_t index, double frac);
bool af_stream_pos_at(const af_stream *s, int64_t t_ns, uint64_t *index, double *frac);

/* Whether a clock fault of s (a step, frozen stamps, a wrong rate) lies
 * within margin_ns of t_ns, or the stamps' rate is wrong now. */
bool af_stream_clock_fault_near(const af_stream *s, int64_t t_ns, int64_t margin_ns);

/* Refused chunks so far, all kinds. */
uint64_t af_stream_bad_chunks(const af_stream *s);

/* Counts a chunk refused before it became an af_chunk (the wire: a cut or
 * empty message, oversized: longer than the cap) and describes it (why, a
 * line naming the lengths) in s->last_problem. */
void af_stream_refuse(af_stream *s, bool oversized, const char *why);

/* Refused samples of the remembered spans inside [first, first + n). */
uint64_t af_stream_refused_in(const af_stream *s, uint64_t first, uint64_t n);

/* A stream that delivered before and has been silent longer than
 * stale_after_s. A stream never seen is not stale: it may not be wired. */
bool af_stream_stale(const af_stream *s, int64_t now_ns, double stale_after_s);

#ifdef __cplusplus
}
#endif
#endif
