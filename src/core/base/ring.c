/* ring.c — ring buffer of one stream, addressed by absolute sample index. */
#include "ring.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

struct af_ring {
  float *buf;      /* sample with absolute index i lives at buf[i % capacity] */
  size_t capacity; /* [samples] */
  bool empty;      /* nothing written since create or reset */
  uint64_t start;  /* index of the first sample written since the (re)start */
  uint64_t end;    /* one past the newest sample */
};

af_status af_ring_create(size_t capacity_samples, af_ring **out)
{
  if (!out)
    return AF_EINVAL;
  *out = NULL;
  if (capacity_samples == 0)
    return AF_EINVAL;
  af_ring *r = calloc(1, sizeof *r);
  if (!r)
    return AF_ENOMEM;
  r->buf = malloc(capacity_samples * sizeof *r->buf);
  if (!r->buf) {
    free(r);
    return AF_ENOMEM;
  }
  r->capacity = capacity_samples;
  af_ring_reset(r);
  *out = r;
  return AF_OK;
}

void af_ring_destroy(af_ring *r)
{
  if (!r)
    return;
  free(r->buf);
  free(r);
}

void af_ring_reset(af_ring *r)
{
  r->empty = true;
  r->start = 0;
  r->end = 0;
}

/* Copies src[0..n) to the slots of absolute indices [first, first + n), n <= capacity. */
static void put(af_ring *r, uint64_t first, const float *src, size_t n)
{
  size_t at = (size_t)(first % r->capacity);
  size_t head = r->capacity - at < n ? r->capacity - at : n;
  memcpy(r->buf + at, src, head * sizeof *src);
  memcpy(r->buf, src + head, (n - head) * sizeof *src);
}

/* Fills the slots of [first, first + n) with NaN, n <= capacity. */
static void put_nan(af_ring *r, uint64_t first, size_t n)
{
  for (size_t k = 0; k < n; k++)
    r->buf[(first + k) % r->capacity] = NAN;
}

af_status af_ring_write(af_ring *r, const float *data, size_t n, uint64_t first_sample,
                        af_ring_write_info *info)
{
  if (info)
    memset(info, 0, sizeof *info);
  if (!r || (!data && n > 0) || n > UINT64_MAX - first_sample)
    return AF_EINVAL;
  if (n == 0)
    return AF_OK;
  if (!r->empty && first_sample < r->end) {
    af_ring_reset(r);
    if (info)
      info->restarted = true;
  }
  if (r->empty) {
    r->empty = false;
    r->start = r->end = first_sample;
  }
  uint64_t gap = first_sample - r->end;
  if (info)
    info->gap_samples = gap;
  /* Only the part of the hole that can still be read needs its NaN. */
  size_t fill = gap < r->capacity ? (size_t)gap : r->capacity;
  put_nan(r, first_sample - fill, fill);
  size_t skip = n > r->capacity ? n - r->capacity : 0;
  put(r, first_sample + skip, data + skip, n - skip);
  r->end = first_sample + n;
  return AF_OK;
}

size_t af_ring_capacity(const af_ring *r)
{
  return r->capacity;
}

uint64_t af_ring_begin(const af_ring *r)
{
  uint64_t oldest = r->end >= r->capacity ? r->end - r->capacity : 0;
  return r->start > oldest ? r->start : oldest;
}

uint64_t af_ring_end(const af_ring *r)
{
  return r->end;
}

af_status af_ring_read(const af_ring *r, uint64_t first_sample, size_t n, float *out)
{
  if (!r || (!out && n > 0))
    return AF_EINVAL;
  if (n > r->capacity)
    return AF_ESIZE;
  if (first_sample < af_ring_begin(r) || first_sample > r->end || n > r->end - first_sample)
    return AF_ENODATA;
  size_t at = (size_t)(first_sample % r->capacity);
  size_t head = r->capacity - at < n ? r->capacity - at : n;
  memcpy(out, r->buf + at, head * sizeof *out);
  memcpy(out + head, r->buf, (n - head) * sizeof *out);
  return AF_OK;
}

af_status af_ring_read_latest(const af_ring *r, size_t n, float *out, uint64_t *first_sample)
{
  if (!r)
    return AF_EINVAL;
  if (n > r->capacity)
    return AF_ESIZE;
  if (n > r->end - af_ring_begin(r))
    return AF_ENODATA;
  uint64_t first = r->end - n;
  if (first_sample)
    *first_sample = first;
  return af_ring_read(r, first, n, out);
}
