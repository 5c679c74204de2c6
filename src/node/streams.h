/* streams.h — the force and audio inputs: each SignalChunk checked (rate,
 * unit, finite data), buffered in its ring (src/core/ring.h) and counted for
 * the diagnostics. The rings are where the measured strikes read their
 * audio windows (measured.h).
 *
 * Time <-> sample index: each stream keeps the stamp and first_sample of its
 * latest accepted chunk (SignalChunk.header.stamp is the time of data[0]), so
 * sample i is at stamp + (i - first_sample) / sample_rate and time t at index
 * first_sample + (t - stamp) sample_rate. The latest chunk, not the first:
 * a restart or a gap re-anchors the mapping, and a clock that drifts against
 * the sample counter is followed chunk by chunk. Times are integer
 * nanoseconds (a double of seconds since 1970 keeps only ~0.2 us). */
#ifndef AF_NODE_STREAMS_H
#define AF_NODE_STREAMS_H

#include <stdbool.h>
#include <stdint.h>

#include "af_msgs.h"
#include "params.h"
#include "ring.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum {
  AF_CHUNK_OK = 0,
  AF_CHUNK_BAD_RATE, /* sample_rate differs from the configured one */
  AF_CHUNK_BAD_UNIT, /* unit not accepted for this stream */
  AF_CHUNK_BAD_DATA  /* a NaN or infinite sample */
} af_chunk_verdict;

typedef struct {
  const char *name; /* "force" or "audio" */
  const af_stream_config *cfg;
  af_ring *ring;
  uint64_t chunks;                       /* accepted */
  uint64_t gaps;                         /* accepted chunks that followed lost samples */
  uint64_t lost_samples;                 /* samples missing in those gaps */
  uint64_t restarts;                     /* first_sample went backwards */
  uint64_t bad_rate, bad_unit, bad_data; /* refused chunks */
  bool seen;                             /* a chunk was accepted */
  double last_rx_s;                      /* ROS time of the last accepted chunk [s] */
  char last_problem[AF_TEXT_MAX];
  /* The latest accepted chunk: the time <-> index mapping and its frame. */
  int64_t map_stamp_ns;      /* header.stamp [ns] */
  uint64_t map_first_sample; /* its first_sample */
  char frame_id[AF_FRAME_ID_MAX];
} af_stream;

/* Makes the ring (capacity from cfg). AF_ENOMEM on failure. */
af_status af_stream_init(af_stream *s, const char *name, const af_stream_config *cfg);
void af_stream_fini(af_stream *s); /* safe on a zeroed or finished stream */

/* Checks one chunk and buffers it when good; a refused chunk is counted and
 * described in s->last_problem. *info (may be NULL) tells of gaps and
 * restarts. No allocation. */
af_chunk_verdict af_stream_push(af_stream *s, const af_signal_chunk *c, double now_s,
                                af_ring_write_info *info);

/* A ROS time in integer nanoseconds. */
int64_t af_time_to_ns(af_time t);
af_time af_time_from_ns(int64_t ns); /* ns >= 0 */

/* Time [ns] of the (fractional) sample index of s, by the latest chunk's
 * mapping (meaningful once s->seen). */
int64_t af_stream_time_ns(const af_stream *s, double index);
/* The (fractional) sample index of s at time t_ns, by the same mapping. */
double af_stream_index_at(const af_stream *s, int64_t t_ns);

/* Refused chunks so far, all kinds. */
uint64_t af_stream_bad_chunks(const af_stream *s);

/* A stream that delivered before and has been silent longer than
 * stale_after_s. A stream never seen is not stale: it may not be wired. */
bool af_stream_stale(const af_stream *s, double now_s, double stale_after_s);

#ifdef __cplusplus
}
#endif
#endif
