/* test_ring.c — the stream ring: writes and reads by absolute index across
 * the wrap, gaps held as NaN and reported, restarts, oversize blocks, and
 * the error cases; the lost samples of a block (samples.h) against
 * isfinite. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "af_test.h"
#include "ring.h"
#include "samples.h"

/* Sample value of absolute index i: lets every read be checked exactly. */
static float value(uint64_t i)
{
  return (float)(i % 1000) + 0.5f;
}

static void fill(float *buf, uint64_t first, size_t n)
{
  for (size_t k = 0; k < n; k++)
    buf[k] = value(first + k);
}

static int window_ok(const float *w, uint64_t first, size_t n)
{
  for (size_t k = 0; k < n; k++)
    if (w[k] != value(first + k))
      return 0;
  return 1;
}

static void test_errors(void)
{
  af_ring *r = (af_ring *)1;
  AF_CHECK_STATUS(af_ring_create(0, &r), AF_EINVAL);
  AF_CHECK(r == NULL);
  AF_CHECK_STATUS(af_ring_create(8, NULL), AF_EINVAL);
  af_ring_destroy(NULL);
  AF_CHECK_STATUS(af_ring_create(8, &r), AF_OK);
  float w[16];
  AF_CHECK_STATUS(af_ring_write(r, NULL, 3, 0, NULL), AF_EINVAL);
  AF_CHECK_STATUS(af_ring_write(r, w, 2, UINT64_MAX, NULL), AF_EINVAL);
  AF_CHECK_STATUS(af_ring_read_latest(r, 1, w, NULL), AF_ENODATA); /* empty */
  AF_CHECK_STATUS(af_ring_read(r, 0, 9, w), AF_ESIZE);
  AF_CHECK_STATUS(af_ring_read_latest(r, 9, w, NULL), AF_ESIZE);
  AF_CHECK_STATUS(af_ring_write(r, w, 0, 5, NULL), AF_OK); /* an empty block changes nothing */
  AF_CHECK(af_ring_begin(r) == af_ring_end(r));
  af_ring_destroy(r);
}

static void test_stream_and_wrap(void)
{
  af_ring *r;
  AF_CHECK_STATUS(af_ring_create(10, &r), AF_OK);
  AF_CHECK(af_ring_capacity(r) == 10);
  float chunk[7], w[10];
  af_ring_write_info info;
  uint64_t next = 1000; /* a stream need not start at 0 */
  for (int k = 0; k < 9; k++) {
    fill(chunk, next, 7);
    AF_CHECK_STATUS(af_ring_write(r, chunk, 7, next, &info), AF_OK);
    AF_CHECK(info.gap_samples == 0 && !info.restarted);
    next += 7;
  }
  AF_CHECK(af_ring_end(r) == next);
  AF_CHECK(af_ring_begin(r) == next - 10);
  uint64_t first = 0;
  AF_CHECK_STATUS(af_ring_read_latest(r, 10, w, &first), AF_OK);
  AF_CHECK(first == next - 10);
  AF_CHECK(window_ok(w, first, 10));
  AF_CHECK_STATUS(af_ring_read(r, next - 6, 4, w), AF_OK);
  AF_CHECK(window_ok(w, next - 6, 4));
  AF_CHECK_STATUS(af_ring_read(r, next - 11, 2, w), AF_ENODATA); /* overwritten */
  AF_CHECK_STATUS(af_ring_read(r, next - 2, 3, w), AF_ENODATA);  /* not yet written */
  AF_CHECK_STATUS(af_ring_read(r, next, 0, w), AF_OK);
  af_ring_destroy(r);
}

static void test_first_block_partial(void)
{
  af_ring *r;
  AF_CHECK_STATUS(af_ring_create(10, &r), AF_OK);
  float chunk[4], w[10];
  fill(chunk, 50, 4);
  AF_CHECK_STATUS(af_ring_write(r, chunk, 4, 50, NULL), AF_OK);
  AF_CHECK(af_ring_begin(r) == 50 && af_ring_end(r) == 54);
  AF_CHECK_STATUS(af_ring_read_latest(r, 5, w, NULL), AF_ENODATA); /* only 4 held */
  AF_CHECK_STATUS(af_ring_read(r, 49, 2, w), AF_ENODATA);          /* before the stream */
  AF_CHECK_STATUS(af_ring_read_latest(r, 4, w, NULL), AF_OK);
  AF_CHECK(window_ok(w, 50, 4));
  af_ring_destroy(r);
}

static void test_gap(void)
{
  af_ring *r;
  AF_CHECK_STATUS(af_ring_create(16, &r), AF_OK);
  float chunk[4], w[16];
  af_ring_write_info info;
  fill(chunk, 0, 4);
  af_ring_write(r, chunk, 4, 0, &info);
  fill(chunk, 7, 4); /* samples 4, 5, 6 lost */
  AF_CHECK_STATUS(af_ring_write(r, chunk, 4, 7, &info), AF_OK);
  AF_CHECK(info.gap_samples == 3 && !info.restarted);
  AF_CHECK(af_ring_end(r) == 11);
  AF_CHECK_STATUS(af_ring_read(r, 0, 11, w), AF_OK);
  AF_CHECK(window_ok(w, 0, 4));
  AF_CHECK(isnan(w[4]) && isnan(w[5]) && isnan(w[6]));
  AF_CHECK(window_ok(w + 7, 7, 4));
  /* A gap longer than the ring: everything older is unreadable or NaN. */
  fill(chunk, 1000, 4);
  AF_CHECK_STATUS(af_ring_write(r, chunk, 4, 1000, &info), AF_OK);
  AF_CHECK(info.gap_samples == 1000 - 11);
  AF_CHECK(af_ring_begin(r) == 1004 - 16);
  AF_CHECK_STATUS(af_ring_read_latest(r, 16, w, NULL), AF_OK);
  int nans = 0;
  for (int k = 0; k < 12; k++)
    nans += isnan(w[k]) != 0;
  AF_CHECK(nans == 12);
  AF_CHECK(window_ok(w + 12, 1000, 4));
  af_ring_destroy(r);
}

static void test_restart_and_oversize(void)
{
  af_ring *r;
  AF_CHECK_STATUS(af_ring_create(8, &r), AF_OK);
  float big[20], w[8];
  af_ring_write_info info;
  fill(big, 100, 20);
  AF_CHECK_STATUS(af_ring_write(r, big, 20, 100, &info), AF_OK); /* keeps the newest 8 */
  AF_CHECK(af_ring_begin(r) == 112 && af_ring_end(r) == 120);
  AF_CHECK_STATUS(af_ring_read_latest(r, 8, w, NULL), AF_OK);
  AF_CHECK(window_ok(w, 112, 8));
  fill(big, 3, 5); /* back in time: the stream restarted */
  AF_CHECK_STATUS(af_ring_write(r, big, 5, 3, &info), AF_OK);
  AF_CHECK(info.restarted && info.gap_samples == 0);
  AF_CHECK(af_ring_begin(r) == 3 && af_ring_end(r) == 8);
  AF_CHECK_STATUS(af_ring_read(r, 3, 5, w), AF_OK);
  AF_CHECK(window_ok(w, 3, 5));
  af_ring_reset(r);
  AF_CHECK(af_ring_begin(r) == af_ring_end(r));
  AF_CHECK_STATUS(af_ring_read_latest(r, 1, w, NULL), AF_ENODATA);
  af_ring_destroy(r);
}

/* af_samples_nonfinite against a count by isfinite over random bit
 * patterns (every exponent, NaN payloads of both signs, infinities,
 * zeros, subnormals), over lengths about its 2^16-sample runs. */
static void test_nonfinite_count(void)
{
  const size_t n = 3 * ((size_t)1 << 16) + 17;
  float *x = malloc(n * sizeof *x);
  AF_CHECK(x != NULL);
  if (x == NULL)
    return;
  uint32_t state = 12345u;
  for (size_t k = 0; k < n; k++) {
    state = state * 1664525u + 1013904223u;
    uint32_t b = state;
    if (k % 5 == 0) /* a fifth with the exponent all ones: NaN or infinity */
      b |= 0x7f800000u;
    if (k % 7 == 0)
      b &= ~0x7f800000u; /* zeros and subnormals */
    memcpy(&x[k], &b, sizeof b);
  }
  const size_t lengths[] = {0, 1, 5, 65535, 65536, 65537, 131072, n};
  for (size_t i = 0; i < sizeof lengths / sizeof lengths[0]; i++) {
    for (size_t off = 0; off < 3 && off + lengths[i] <= n; off++) {
      size_t expect = 0;
      for (size_t k = off; k < off + lengths[i]; k++)
        expect += !isfinite(x[k]);
      AF_CHECK(af_samples_nonfinite(x + off, lengths[i]) == expect);
    }
  }
  free(x);
}

int main(void)
{
  test_nonfinite_count();
  test_errors();
  test_stream_and_wrap();
  test_first_block_partial();
  test_gap();
  test_restart_and_oversize();
  return af_test_summary("test_ring");
}
