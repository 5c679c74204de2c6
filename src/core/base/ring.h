/* ring.h — a ring buffer of one sampled stream, addressed by absolute
 * sample index (SignalChunk.first_sample), for the strike detector to read.
 *
 * In the manner of liquid-dsp's windows: create with a fixed capacity, write
 * blocks, read windows; all memory in create, none in write or read.
 *
 * Gaps: a block that starts after the newest sample held means lost samples;
 * the hole is filled with NaN (so a window across it is recognisably
 * incomplete) and reported. A block that starts before the newest sample
 * held means the stream restarted (a driver restart, a bag played again):
 * the ring is emptied and starts again at that block, and that is reported.
 * Not thread-safe; one writer, readers on the same thread.
 */
#ifndef AF_RING_H
#define AF_RING_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "status.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct af_ring af_ring;

/* A ring holding the latest capacity_samples (>= 1) samples. AF_EINVAL for
 * 0, AF_ENOMEM when the allocation fails. */
af_status af_ring_create(size_t capacity_samples, af_ring **out);
void af_ring_destroy(af_ring *r); /* NULL-safe */

/* Forgets every sample; the next write starts the stream afresh. */
void af_ring_reset(af_ring *r);

typedef struct {
  uint64_t gap_samples; /* samples lost before this block (held as NaN) */
  bool restarted;       /* the block went back in time: the ring restarted at it */
} af_ring_write_info;

/* Writes data[0..n) whose first sample has the absolute index first_sample.
 * When n exceeds the capacity only the newest capacity samples are kept.
 * info (may be NULL) tells what happened. AF_EINVAL when data is NULL with
 * n > 0, or first_sample + n overflows. No allocation. */
af_status af_ring_write(af_ring *r, const float *data, size_t n, uint64_t first_sample,
                        af_ring_write_info *info);

size_t af_ring_capacity(const af_ring *r);
/* Absolute index of the oldest sample held (== end when empty). */
uint64_t af_ring_begin(const af_ring *r);
/* Absolute index one past the newest sample held. */
uint64_t af_ring_end(const af_ring *r);

/* Copies samples [first_sample, first_sample + n) into out. AF_ESIZE when n
 * exceeds the capacity, AF_ENODATA when not all of them are held (too old
 * or not yet written). Samples lost in a gap read as NaN. */
af_status af_ring_read(const af_ring *r, uint64_t first_sample, size_t n, float *out);

/* Copies the newest n samples into out; *first_sample (may be NULL) receives
 * the absolute index of out[0]. AF_ESIZE / AF_ENODATA as af_ring_read. */
af_status af_ring_read_latest(const af_ring *r, size_t n, float *out, uint64_t *first_sample);

#ifdef __cplusplus
}
#endif
#endif
