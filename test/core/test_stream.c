/* test_stream.c — one input stream (stream.h) fed hand-built chunk
 * sequences: gaps and lost samples counted against the hand-summed holes,
 * restarts, partial overlaps (the new tail kept), refused chunks (rate, unit, index overflow,
 * wire), refused non-finite samples as counted spans with their one-line messages, the unit
 * conversion across its blocks (ring contents against x times to_si), the time <-> index mapping
 * through the holding chunk against hand-computed stamps, the anchor ring's limit, and staleness
 * around its threshold. */
#include <math.h>
#include <stdint.h>
#include <string.h>

#include "af_test.h"
#include "stream.h"

#define RATE_HZ 50000.0
#define CHUNK 100

static af_stream_config config(size_t capacity, double to_si)
{
  af_stream_config c;
  memset(&c, 0, sizeof c);
  c.sample_rate_hz = RATE_HZ;
  c.buffer_s = (double)capacity / RATE_HZ;
  c.capacity_samples = capacity;
  strcpy(c.units[0], "N");
  strcpy(c.units[1], "V");
  c.to_si = to_si;
  return c;
}

static float samples[3 * 4096 + 7];

/* x[k] = first + k + 0.25: every sample's index readable from its value. */
static af_chunk chunk(uint64_t first, size_t n, int64_t stamp_ns)
{
  for (size_t k = 0; k < n; k++)
    samples[k] = (float)((double)(first + k) + 0.25);
  af_chunk c = {stamp_ns, first, RATE_HZ, "N", "hammer", samples, n};
  return c;
}

static void test_gaps_and_restarts(void)
{
  af_stream_config cfg = config(1000, 1.0);
  af_stream s;
  AF_CHECK_STATUS(af_stream_create(&s, "force", &cfg), AF_OK);
  AF_CHECK(!s.seen && s.chunks == 0);
  af_ring_write_info w;
  af_chunk c = chunk(0, CHUNK, 1000);
  AF_CHECK(af_stream_push(&s, &c, 5, &w) == AF_CHUNK_OK);
  AF_CHECK(s.seen && s.chunks == 1 && s.last_rx_ns == 5 && strcmp(s.frame_id, "hammer") == 0);
  AF_CHECK(w.gap_samples == 0 && !w.restarted && s.last_problem[0] == '\0');
  c = chunk(100, CHUNK, 0);
  AF_CHECK(af_stream_push(&s, &c, 6, &w) == AF_CHUNK_OK && w.gap_samples == 0);
  AF_CHECK(s.gaps == 0 && s.lost_samples == 0);
  /* Holes of 7 and 93 samples: 2 gaps, 100 lost. */
  c = chunk(207, CHUNK, 0);
  AF_CHECK(af_stream_push(&s, &c, 7, &w) == AF_CHUNK_OK && w.gap_samples == 7);
  AF_CHECK(s.gaps == 1 && s.lost_samples == 7);
  AF_CHECK(strcmp(s.last_problem, "force: 7 samples lost before sample 207") == 0);
  c = chunk(400, 50, 0);
  AF_CHECK(af_stream_push(&s, &c, 8, NULL) == AF_CHUNK_OK);
  AF_CHECK(s.gaps == 2 && s.lost_samples == 100 && s.chunks == 4);
  /* The hole reads as NaN, the samples around it as sent. */
  float r[4];
  AF_CHECK_STATUS(af_ring_read(s.ring, 198, 4, r), AF_OK);
  AF_CHECK(r[0] == 198.25f && r[1] == 199.25f && isnan(r[2]) && isnan(r[3]));
  /* One sample of overlap: a restart, not a gap; the anchors are forgotten. */
  c = chunk(449, 10, 0);
  AF_CHECK(af_stream_push(&s, &c, 9, &w) == AF_CHUNK_OK && w.restarted && w.gap_samples == 0);
  AF_CHECK(s.restarts == 1 && s.gaps == 2 && s.lost_samples == 100 && s.anchor_count == 1);
  AF_CHECK(strcmp(s.last_problem, "force: stream restarted at sample 449 (went backwards)") == 0);
  /* The same chunk again, at its own stamp (a bag with every
   * chunk twice): a duplicate, ignored, not a restart; one value changed,
   * or another stamp: a restart. */
  c = chunk(449, 10, 0);
  AF_CHECK(af_stream_push(&s, &c, 9, &w) == AF_CHUNK_DUPLICATE && s.duplicates == 1);
  AF_CHECK(s.restarts == 1 && s.chunks == 5 && af_stream_bad_chunks(&s) == 0);
  AF_CHECK(strcmp(s.last_problem,
                  "force chunk at sample 449: 10 samples already held (a duplicate, ignored)") ==
           0);
  c = chunk(449, 10, 40000); /* 2 samples later */
  AF_CHECK(af_stream_push(&s, &c, 9, &w) == AF_CHUNK_OK && w.restarted && s.restarts == 2);
  c = chunk(449, 10, 40000);
  samples[3] += 1.0f;
  AF_CHECK(af_stream_push(&s, &c, 9, &w) == AF_CHUNK_OK && w.restarted && s.restarts == 3);
  AF_CHECK(s.duplicates == 1 && s.chunks == 7);
  /* An empty chunk is accepted and counted, with no gap. */
  c = chunk(459, 0, 0);
  AF_CHECK(af_stream_push(&s, &c, 10, &w) == AF_CHUNK_OK && w.gap_samples == 0);
  AF_CHECK(s.chunks == 8 && af_stream_bad_chunks(&s) == 0);
  af_stream_destroy(&s);
  af_stream_destroy(&s); /* twice: safe */
  af_stream z;
  memset(&z, 0, sizeof z);
  af_stream_destroy(&z); /* zeroed: safe */
}

static void test_refused(void)
{
  af_stream_config cfg = config(1000, 1.0);
  af_stream s;
  AF_CHECK_STATUS(af_stream_create(&s, "force", &cfg), AF_OK);
  af_chunk c = chunk(0, CHUNK, 0);
  AF_CHECK(af_stream_push(&s, &c, 0, NULL) == AF_CHUNK_OK);

  c = chunk(100, CHUNK, 0);
  c.sample_rate_hz = 48000.0;
  AF_CHECK(af_stream_push(&s, &c, 1, NULL) == AF_CHUNK_BAD_RATE);
  AF_CHECK(strcmp(s.last_problem, "force chunk at sample 100: sample_rate 48000 Hz, expected "
                                  "50000 Hz") == 0);
  c.sample_rate_hz = RATE_HZ * (1.0 + 2e-6); /* beyond the float tolerance */
  AF_CHECK(af_stream_push(&s, &c, 1, NULL) == AF_CHUNK_BAD_RATE);
  c.sample_rate_hz = NAN;
  AF_CHECK(af_stream_push(&s, &c, 1, NULL) == AF_CHUNK_BAD_RATE);
  c.sample_rate_hz = (double)(float)(RATE_HZ / 3.0) * 3.0; /* a rate through a float: fine */
  c.unit = "mV";
  AF_CHECK(af_stream_push(&s, &c, 1, NULL) == AF_CHUNK_BAD_UNIT);
  AF_CHECK(strcmp(s.last_problem, "force chunk at sample 100: unit 'mV', expected 'N'") == 0);
  c.unit = NULL;
  AF_CHECK(af_stream_push(&s, &c, 1, NULL) == AF_CHUNK_BAD_UNIT);
  AF_CHECK(strcmp(s.last_problem, "force chunk at sample 100: unit '', expected 'N'") == 0);
  c.unit = "n"; /* units are case-sensitive */
  AF_CHECK(af_stream_push(&s, &c, 1, NULL) == AF_CHUNK_BAD_UNIT);
  /* Refused chunks: counted by kind, nothing else changes. */
  AF_CHECK(s.bad_rate == 3 && s.bad_unit == 3 && s.chunks == 1 && s.anchor_count == 1);
  /* Non-finite samples: the chunk is kept, the samples refused
   * as counted spans (42; 98..99) and held as NaN; the rest as sent. */
  c.unit = "V"; /* the second accepted unit */
  samples[42] = NAN;
  samples[98] = INFINITY;
  samples[99] = -INFINITY;
  AF_CHECK(af_stream_push(&s, &c, 1, NULL) == AF_CHUNK_OK);
  AF_CHECK(strcmp(s.last_problem, "force chunk at sample 100: 3 non-finite samples refused (held "
                                  "as lost); 3 so far") == 0);
  AF_CHECK(s.refused_samples == 3 && s.refused_spans == 2 && s.refused_chunks == 1);
  AF_CHECK(s.chunks == 2 && af_ring_end(s.ring) == 200);
  float got[100];
  AF_CHECK_STATUS(af_ring_read(s.ring, 100, 100, got), AF_OK);
  AF_CHECK(isnan(got[42]) && isnan(got[98]) && isnan(got[99]));
  AF_CHECK(got[41] == 141.25f && got[43] == 143.25f && got[97] == 197.25f);
  AF_CHECK(af_stream_refused_in(&s, 100, 100) == 3 && af_stream_refused_in(&s, 142, 1) == 1);
  AF_CHECK(af_stream_refused_in(&s, 143, 55) == 0 && af_stream_refused_in(&s, 99, 100) == 2);
  AF_CHECK(af_stream_refused_in(&s, 199, 1000) == 1 && af_stream_refused_in(&s, 0, 142) == 0);
  AF_CHECK(af_stream_bad_chunks(&s) == 6);
  /* Index overflow: first_sample + n past 2^64, its own reason. */
  c = chunk(0, 10, 0);
  c.first_sample = UINT64_MAX - 5;
  AF_CHECK(af_stream_push(&s, &c, 1, NULL) == AF_CHUNK_BAD_INDEX);
  AF_CHECK(strcmp(s.last_problem, "force chunk: first_sample 18446744073709551610 + 10 samples "
                                  "overflows the 64-bit index") == 0);
  AF_CHECK(s.bad_index == 1 && s.refused_samples == 3);
  /* A chunk refused on the wire (cut or empty, oversized): counted. */
  af_stream_refuse(&s, false, "force: a cut SignalChunk of 7 bytes");
  af_stream_refuse(&s, true, "force: a SignalChunk of 9 samples, cap 8");
  AF_CHECK(s.malformed == 1 && s.oversized == 1 && af_stream_bad_chunks(&s) == 9);
  AF_CHECK(strcmp(s.last_problem, "force: a SignalChunk of 9 samples, cap 8") == 0);
  AF_CHECK(s.chunks == 2 && s.last_rx_ns == 1 && s.gaps == 0);
  /* The good chunk after them: no gap, it follows sample 199. */
  c = chunk(200, CHUNK, 0);
  c.unit = "V";
  AF_CHECK(af_stream_push(&s, &c, 2, NULL) == AF_CHUNK_OK && s.gaps == 0 && s.chunks == 3);
  AF_CHECK(s.last_refused == 0 && s.refused_chunks == 1);
  af_stream_destroy(&s);
}

/* A force in volts: 0.5 V/N, so to_si = 2 N/V; chunks longer than the
 * conversion block (4096) are converted block by block. */
static void test_conversion(void)
{
  float x[5] = {1.0f, -0.5f, 0.0f, 3.0f, 1e-3f}, y[5];
  af_stream_to_si(2.0, x, 5, y);
  AF_CHECK(y[0] == 2.0f && y[1] == -1.0f && y[2] == 0.0f && y[3] == 6.0f && y[4] == 2e-3f);
  af_stream_to_si(0.1, x, 5, x); /* in place */
  AF_CHECK(x[0] == (float)0.1 && x[3] == (float)(3.0 * 0.1));

  const size_t n = 2 * AF_STREAM_BLOCK + 7, cap = 3 * AF_STREAM_BLOCK;
  af_stream_config cfg = config(cap, 2.0);
  af_stream s;
  AF_CHECK_STATUS(af_stream_create(&s, "force", &cfg), AF_OK);
  AF_CHECK(s.si != NULL);
  af_chunk c = chunk(1000, n, 0);
  c.unit = "V";
  AF_CHECK(af_stream_push(&s, &c, 0, NULL) == AF_CHUNK_OK);
  /* After a gap of 50 the long chunk reports the gap once (its first block). */
  af_ring_write_info w;
  c = chunk(1000 + n + 50, n, 0);
  c.unit = "V";
  AF_CHECK(af_stream_push(&s, &c, 1, &w) == AF_CHUNK_OK && w.gap_samples == 50 && !w.restarted);
  AF_CHECK(s.gaps == 1 && s.lost_samples == 50);
  static float back[3 * 4096];
  AF_CHECK_STATUS(af_ring_read(s.ring, 1000 + n + 50, n, back), AF_OK);
  int exact = 1;
  for (size_t k = 0; k < n; k++)
    if (back[k] != (float)(2.0 * ((double)(1000 + n + 50 + k) + 0.25)))
      exact = 0;
  AF_CHECK(exact);
  AF_CHECK(af_ring_end(s.ring) == 1000 + 2 * n + 50);
  af_stream_destroy(&s);
  AF_CHECK(s.si == NULL && s.ring == NULL);

  /* to_si 1 (or 0, a config without a unit): samples as sent (the scratch
   * is there for the non-finite check). */
  cfg = config(cap, 0.0);
  AF_CHECK_STATUS(af_stream_create(&s, "audio", &cfg), AF_OK);
  AF_CHECK(s.si != NULL);
  c = chunk(0, 10, 0);
  AF_CHECK(af_stream_push(&s, &c, 0, NULL) == AF_CHUNK_OK);
  AF_CHECK_STATUS(af_ring_read(s.ring, 3, 1, back), AF_OK);
  AF_CHECK(back[0] == 3.25f);
  af_stream_destroy(&s);
}

/* Stamps that drift against the counter: chunk k (100 samples = 2 ms)
 * stamped at t0 + k 2 ms + k 1 us. Sample i of chunk k is at
 * stamp_k + (i - 100 k) 20 us. */
#define T0_NS 1700000000000000000LL
static int64_t stamp_of_chunk(uint64_t k)
{
  return T0_NS + (int64_t)k * 2000000 + (int64_t)k * 1000;
}

static void test_time_mapping(void)
{
  af_stream_config cfg = config(100000, 1.0);
  af_stream s;
  AF_CHECK_STATUS(af_stream_create(&s, "audio", &cfg), AF_OK);
  for (uint64_t k = 0; k < 5; k++) {
    af_chunk c = chunk(k * CHUNK, CHUNK, stamp_of_chunk(k));
    AF_CHECK(af_stream_push(&s, &c, 0, NULL) == AF_CHUNK_OK);
  }
  /* Sample 250 is 50 samples (1 ms) into chunk 2. */
  AF_CHECK(af_stream_time_ns(&s, 250.0) == T0_NS + 4002000 + 1000000);
  AF_CHECK(af_stream_time_ns(&s, 200.0) == T0_NS + 4002000);
  AF_CHECK(af_stream_time_ns(&s, 199.0) == T0_NS + 2001000 + 99 * 20000);
  AF_CHECK(af_stream_time_ns(&s, 0.5) == T0_NS + 10000); /* half a sample: 10 us */
  /* Past the newest chunk: through the newest (chunk 4). */
  AF_CHECK(af_stream_time_ns(&s, 1000.0) == T0_NS + 8004000 + 600 * 20000);
  /* Before the oldest: through the oldest (chunk 0), a negative offset. */
  AF_CHECK(af_stream_time_ns(&s, -50.0) == T0_NS - 1000000);
  /* The inverse, through the chunk stamped at or before t. */
  AF_CHECK_ABS(af_stream_index_at(&s, T0_NS + 4002000 + 1000000), 250.0, 1e-9);
  AF_CHECK_ABS(af_stream_index_at(&s, T0_NS + 4002000), 200.0, 1e-9);
  /* 1 us before chunk 2's stamp: through chunk 1, 2.001 ms - 1 us after it:
   * 100 + 2000 us / 20 us = 199.95... (1 us is 0.05 sample) */
  AF_CHECK_ABS(af_stream_index_at(&s, T0_NS + 4002000 - 1000), 100.0 + 2000.0 / 20.0, 1e-9);
  AF_CHECK_ABS(af_stream_index_at(&s, T0_NS - 20000), -1.0, 1e-9);
  /* Round trip through the holding chunk. */
  for (double i = 0.0; i < 500.0; i += 37.5)
    AF_CHECK_ABS(af_stream_index_at(&s, af_stream_time_ns(&s, i)), i, 0.5e-9 * RATE_HZ);
  /* A restart forgets the old anchors: sample 0 is at the new stamp. */
  af_chunk c = chunk(0, CHUNK, T0_NS + 7000000000LL);
  AF_CHECK(af_stream_push(&s, &c, 0, NULL) == AF_CHUNK_OK && s.restarts == 1);
  AF_CHECK(af_stream_time_ns(&s, 10.0) == T0_NS + 7000000000LL + 200000);
  af_stream_destroy(&s);
}

/* 600 chunks: the oldest 88 anchors are dropped, earlier samples map
 * through chunk 88 (drift 1 us per chunk makes the difference visible). */
static void test_anchor_limit(void)
{
  af_stream_config cfg = config(1000, 1.0);
  af_stream s;
  AF_CHECK_STATUS(af_stream_create(&s, "audio", &cfg), AF_OK);
  const uint64_t n_chunks = 600, dropped = n_chunks - AF_STREAM_ANCHORS;
  for (uint64_t k = 0; k < n_chunks; k++) {
    af_chunk c = chunk(k * CHUNK, CHUNK, stamp_of_chunk(k));
    af_stream_push(&s, &c, 0, NULL);
  }
  AF_CHECK(s.chunks == n_chunks && s.anchor_count == AF_STREAM_ANCHORS);
  AF_CHECK(af_stream_time_ns(&s, (double)(dropped * CHUNK + 10)) ==
           stamp_of_chunk(dropped) + 10 * 20000);
  /* Sample 0 through chunk 88: stamp_88 - 8800 samples * 20 us. */
  AF_CHECK(af_stream_time_ns(&s, 0.0) == stamp_of_chunk(dropped) - (int64_t)dropped * 2000000);
  AF_CHECK(af_stream_time_ns(&s, 0.0) != stamp_of_chunk(0)); /* 88 us of drift lost */
  AF_CHECK(af_stream_time_ns(&s, 599.0 * CHUNK + 99.0) == stamp_of_chunk(599) + 99 * 20000);
  af_stream_destroy(&s);
}

static void test_stale(void)
{
  af_stream_config cfg = config(1000, 1.0);
  af_stream s;
  AF_CHECK_STATUS(af_stream_create(&s, "audio", &cfg), AF_OK);
  AF_CHECK(!af_stream_stale(&s, 1000000000000LL, 0.1)); /* never seen: not stale */
  af_chunk c = chunk(0, CHUNK, 0);
  af_stream_push(&s, &c, 2000000000LL, NULL);
  AF_CHECK(!af_stream_stale(&s, 2000000000LL, 0.5));
  AF_CHECK(!af_stream_stale(&s, 2490000000LL, 0.5));
  AF_CHECK(af_stream_stale(&s, 2510000000LL, 0.5));
  /* A refused chunk does not refresh the stream. */
  c.sample_rate_hz = 1.0;
  af_stream_push(&s, &c, 3000000000LL, NULL);
  AF_CHECK(s.last_rx_ns == 2000000000LL && af_stream_stale(&s, 3000000000LL, 0.5));
  af_stream_destroy(&s);
}

/* A chunk whose head repeats the ring's last samples (a partial
 * overlap was a restart): the new tail kept, the head counted as duplicate
 * samples. Stamps by hand: sample k at 1000 ns + k / 50 kHz = 1000 + 20000 k
 * ns. The ring's contents are checked against x[k] = k + 0.25. */
static void test_overlap(void)
{
  af_stream_config cfg = config(1000, 1.0);
  af_stream s;
  AF_CHECK_STATUS(af_stream_create(&s, "force", &cfg), AF_OK);
  af_ring_write_info w;
  af_chunk c = chunk(0, CHUNK, 1000);
  AF_CHECK(af_stream_push(&s, &c, 1, &w) == AF_CHUNK_OK);
  /* Samples 60..159: 40 held (60..99), 60 new. */
  c = chunk(60, CHUNK, 1000 + 60 * 20000);
  AF_CHECK(af_stream_push(&s, &c, 2, &w) == AF_CHUNK_OK);
  AF_CHECK(!w.restarted && w.gap_samples == 0);
  AF_CHECK(s.restarts == 0 && s.gaps == 0 && s.overlaps == 1 && s.duplicate_samples == 40);
  AF_CHECK(s.chunks == 2 && s.duplicates == 0 && af_ring_end(s.ring) == 160 && s.last_held == 40);
  AF_CHECK(strcmp(s.last_problem, "force chunk at sample 60: its first 40 of 100 samples already "
                                  "held (an overlap: the 60 new ones kept)") == 0);
  float got[160];
  AF_CHECK_STATUS(af_ring_read(s.ring, 0, 160, got), AF_OK);
  bool as_sent = true;
  for (size_t k = 0; k < 160; k++)
    as_sent &= got[k] == (float)((double)k + 0.25);
  AF_CHECK(as_sent);
  /* The time of the new tail, through the overlapping chunk's stamp. */
  AF_CHECK(af_stream_time_ns(&s, 150.0) == 1000 + 150 * 20000);
  /* Off by 0.4 of a sample: still the same samples (one held, 99 new). */
  c = chunk(159, CHUNK, 1000 + 159 * 20000 + 8000);
  AF_CHECK(af_stream_push(&s, &c, 3, &w) == AF_CHUNK_OK && !w.restarted);
  AF_CHECK(s.overlaps == 2 && s.duplicate_samples == 41 && af_ring_end(s.ring) == 259);
  /* One held value different: a restart, as before. */
  c = chunk(250, CHUNK, 1000 + 250 * 20000);
  samples[3] += 1.0f;
  AF_CHECK(af_stream_push(&s, &c, 4, &w) == AF_CHUNK_OK && w.restarted);
  AF_CHECK(s.restarts == 1 && s.overlaps == 2 && s.duplicate_samples == 41 && s.last_held == 0);
  /* The same samples 2 samples later in time: another stream, a restart. */
  c = chunk(340, CHUNK, 1000 + 342 * 20000);
  AF_CHECK(af_stream_push(&s, &c, 5, &w) == AF_CHUNK_OK && w.restarted && s.restarts == 2);
  /* Over a hole: a hole never matches a sample (a restart). After 340..439,
   * 450..549 leaves 440..449 lost; 445..564 overlaps 445..549, 5 of them
   * lost. */
  c = chunk(450, CHUNK, 1000 + 452 * 20000);
  AF_CHECK(af_stream_push(&s, &c, 6, &w) == AF_CHUNK_OK && w.gap_samples == 10);
  c = chunk(445, CHUNK + 20, 1000 + 447 * 20000);
  AF_CHECK(af_stream_push(&s, &c, 7, &w) == AF_CHUNK_OK && w.restarted && s.restarts == 3);
  AF_CHECK(s.overlaps == 2 && s.duplicate_samples == 41);
  /* A whole duplicate counts its samples too. */
  c = chunk(445, 20, 1000 + 447 * 20000);
  AF_CHECK(af_stream_push(&s, &c, 8, &w) == AF_CHUNK_DUPLICATE);
  AF_CHECK(s.duplicates == 1 && s.duplicate_samples == 61 && s.overlaps == 2);
  af_stream_destroy(&s);
}

/* An empty chunk, with no buffer at all (x NULL, as a decoder may hand
 * over a SignalChunk of no data): accepted, nothing held, nothing lost, the
 * ring unchanged (found by fuzz_msgs: the write took an offset of NULL). */
static void test_empty_chunk(void)
{
  af_stream_config cfg = config(1000, 1.0);
  af_stream s;
  AF_CHECK_STATUS(af_stream_create(&s, "force", &cfg), AF_OK);
  af_chunk c = chunk(0, CHUNK, 1000);
  AF_CHECK(af_stream_push(&s, &c, 1, NULL) == AF_CHUNK_OK);
  af_chunk empty = {1000 + CHUNK * 20000, CHUNK, RATE_HZ, "N", "hammer", NULL, 0};
  af_ring_write_info w;
  af_chunk_verdict v = af_stream_push(&s, &empty, 2, &w);
  AF_CHECK(v == AF_CHUNK_OK || v == AF_CHUNK_DUPLICATE);
  AF_CHECK(!w.restarted && w.gap_samples == 0 && s.gaps == 0 && s.restarts == 0);
  AF_CHECK(af_ring_end(s.ring) == CHUNK && s.refused_samples == 0);
  /* n > 0 with no buffer: malformed, named. */
  empty.n = 5;
  AF_CHECK(af_stream_push(&s, &empty, 3, NULL) == AF_CHUNK_MALFORMED && s.malformed == 1);
  AF_CHECK(strstr(s.last_problem, "5 samples, no data") != NULL);
  af_stream_destroy(&s);
}

/* A sender whose index jumps by 2^63 (a corrupt first_sample) and then
 * goes back into the jump's hole: the hole's times, extrapolated from the
 * chunk before the jump, lie 1.8e14 s away. They saturate at
 * AF_STREAM_TIME_MAX_NS, and the duplicate check's difference with the
 * chunk's stamp (a late ROS time) is no longer a signed overflow (UBSan in
 * the sanitizer build; found by fuzz_lane, test/fuzz/lane/regress_index_jump_back). */
static void test_far_index(void)
{
  af_stream_config cfg = config(100000, 1.0); /* the hole in the ring is longer than the 2048
                                                 samples a double resolves at 2^63 */
  af_stream s;
  AF_CHECK_STATUS(af_stream_create(&s, "force", &cfg), AF_OK);
  const uint64_t far = ((uint64_t)1 << 63) + 5000;
  const int64_t late_ns = (int64_t)4294967264 * 1000000000; /* 2106 */
  af_chunk c = chunk(0, CHUNK, 0);
  AF_CHECK(af_stream_push(&s, &c, 1, NULL) == AF_CHUNK_OK);
  c = chunk(far, CHUNK, late_ns);
  AF_CHECK(af_stream_push(&s, &c, 2, NULL) == AF_CHUNK_OK && s.gaps == 1);
  c = chunk(far - 50000, CHUNK, late_ns); /* in the ring, before the newest chunk: the hole */
  af_ring_write_info w;
  AF_CHECK(af_stream_push(&s, &c, 3, &w) == AF_CHUNK_OK && w.restarted);
  AF_CHECK(af_stream_time_ns(&s, 1e30) == AF_STREAM_TIME_MAX_NS);
  AF_CHECK(af_stream_time_ns(&s, -1e30) < 0 &&
           af_stream_time_ns(&s, -1e30) >= -AF_STREAM_TIME_MAX_NS);
  AF_CHECK(af_stream_time_of_ns(&s, far - 50000, 0.0) == late_ns);
  af_stream_destroy(&s);
}

int main(void)
{
  test_gaps_and_restarts();
  test_empty_chunk();
  test_overlap();
  test_refused();
  test_conversion();
  test_time_mapping();
  test_anchor_limit();
  test_stale();
  test_far_index();
  return af_test_summary("test_stream");
}
