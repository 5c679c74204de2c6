/* stream.c — checks and buffers the chunks of one input (see stream.h). */
#include "stream.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "samples.h"

/* Rates are configured and sent as the same nominal number; this only
 * absorbs a rate that went through a float. */
#define AF_RATE_RTOL 1e-6

/* Samples already in SI (a factor of exactly 1, or 0: a config made without
 * a unit): copied, non-finite ones to NaN; the same floats as the product
 * below, in single precision (four samples a vector instead of two). */
static size_t copy_si(const float *x, size_t n, float *out)
{
  size_t refused = 0;
  for (size_t k = 0; k < n; k++) {
    const float v = x[k];
    refused += !isfinite(v);
    out[k] = isfinite(v) ? v : NAN;
  }
  return refused;
}

size_t af_stream_to_si(double to_si, const float *x, size_t n, float *out)
{
  if (to_si == 0.0 || to_si == 1.0)
    return copy_si(x, n, out);
  const double k_si = to_si;
  size_t refused = 0;
  for (size_t k = 0; k < n; k++) {
    float v = (float)((double)x[k] * k_si);
    refused += !isfinite(v);
    out[k] = isfinite(v) ? v : NAN;
  }
  return refused;
}

af_status af_stream_create(af_stream *s, const char *name, const af_stream_config *cfg)
{
  memset(s, 0, sizeof *s);
  s->name = name;
  s->cfg = cfg;
  s->clock_rate_hz = s->clock_last_step_s = NAN;
  if ((s->si = malloc(2 * AF_STREAM_BLOCK * sizeof *s->si)) == NULL) /* + the ring's, to compare */
    return AF_ENOMEM;
  return af_ring_create(cfg->capacity_samples, &s->ring);
}

void af_stream_reset(af_stream *s)
{
  /* Everything but what create made (name, cfg, ring, scratch) is a count
   * or a memory of the stream: zeroed as create leaves it. */
  const af_stream keep = {.name = s->name, .cfg = s->cfg, .ring = s->ring, .si = s->si};
  *s = keep;
  s->clock_rate_hz = s->clock_last_step_s = NAN;
  af_ring_reset(s->ring);
}

void af_stream_destroy(af_stream *s)
{
  af_ring_destroy(s->ring);
  s->ring = NULL;
  free(s->si);
  s->si = NULL;
}

/* The runs of NaN in the converted block y[0..m) (sample 0 has index at)
 * as refused spans; a run that goes on from the previous block of the same
 * chunk (*open) extends that span. */
static void note_spans(af_stream *s, const float *y, size_t m, uint64_t at, bool *open)
{
  for (size_t k = 0; k < m; k++) {
    if (!isnan(y[k])) {
      *open = false;
      continue;
    }
    s->refused_samples++;
    if (*open) {
      s->spans[(s->span_next + AF_STREAM_SPANS - 1) % AF_STREAM_SPANS].end = at + k + 1;
      continue;
    }
    *open = true;
    s->refused_spans++;
    s->spans[s->span_next] = (af_stream_span){at + k, at + k + 1};
    s->span_next = (s->span_next + 1) % AF_STREAM_SPANS;
    s->span_count += s->span_count < AF_STREAM_SPANS;
  }
}

/* The chunk into the ring, converted (and non-finite samples made NaN)
 * block by block in the scratch; *w: what the first block's write found
 * (gaps and restarts can only come before it, the blocks follow each other).
 * Samples already in the lane's unit and all finite go in as sent, without
 * the scratch (the same floats: the conversion would copy them unchanged).
 * Returns the samples refused. */
static uint64_t write_ring(af_stream *s, const af_chunk *c, af_ring_write_info *w)
{
  const double to_si = s->cfg->to_si;
  s->last_as_sent = false;
  if (c->n == 0) { /* nothing to convert (x may be NULL), but its index still tells of a
                      gap or a restart */
    (void)af_ring_write(s->ring, s->si, 0, c->first_sample, w);
    return 0;
  }
  if ((to_si == 0.0 || to_si == 1.0) && af_samples_nonfinite(c->x, c->n) == 0) {
    (void)af_ring_write(s->ring, c->x, c->n, c->first_sample, w);
    s->last_as_sent = true;
    return 0;
  }
  uint64_t refused = 0;
  bool open = false;
  for (size_t at = 0; at < c->n; at += AF_STREAM_BLOCK) {
    size_t m = c->n - at < AF_STREAM_BLOCK ? c->n - at : AF_STREAM_BLOCK;
    af_ring_write_info block;
    size_t r = af_stream_to_si(to_si, c->x + at, m, s->si);
    if (r > 0) {
      refused += r;
      note_spans(s, s->si, m, c->first_sample + at, &open);
    } else {
      open = false;
    }
    (void)af_ring_write(s->ring, s->si, m, c->first_sample + at, at ? &block : w);
  }
  return refused;
}

/* a[k] == b[k] for k < m, NaN matching NaN. */
static bool same_samples(const float *a, const float *b, size_t m)
{
  for (size_t k = 0; k < m; k++)
    if (!(a[k] == b[k] || (isnan(a[k]) && isnan(b[k]))))
      return false;
  return true;
}

/* Whether the first m samples of c repeat samples the ring holds, at the
 * time they were held (within half a sample) and value for value. NaN
 * matches NaN; a hole (NaN) never matches a sample. */
static bool repeats(af_stream *s, const af_chunk *c, size_t m)
{
  const double half_sample_ns = 0.5e9 / s->cfg->sample_rate_hz;
  const int64_t held_ns = af_stream_time_ns(s, (double)c->first_sample);
  /* Of one sign the difference cannot overflow; of both it is large anyway
   * (the chunk's stamp is the sender's: any 64-bit value). */
  const double off_ns = (held_ns >= 0) == (c->stamp_ns >= 0)
                            ? (double)(held_ns - c->stamp_ns)
                            : (double)held_ns - (double)c->stamp_ns;
  if (fabs(off_ns) > half_sample_ns)
    return false;
  float *held = s->si + AF_STREAM_BLOCK;
  for (size_t at = 0; at < m; at += AF_STREAM_BLOCK) {
    size_t k = m - at < AF_STREAM_BLOCK ? m - at : AF_STREAM_BLOCK;
    (void)af_stream_to_si(s->cfg->to_si, c->x + at, k, s->si);
    if (af_ring_read(s->ring, c->first_sample + at, k, held) != AF_OK ||
        !same_samples(s->si, held, k))
      return false;
  }
  return true;
}

/* Whether c repeats samples the ring holds, every one (a chunk sent or
 * recorded twice): not a restart, nothing new. A stream restarted at the
 * same indices comes at another time: a restart. */
static bool duplicate(af_stream *s, const af_chunk *c)
{
  if (!s->seen || c->n == 0 || c->first_sample < af_ring_begin(s->ring) ||
      c->first_sample + c->n > af_ring_end(s->ring))
    return false;
  return repeats(s, c, c->n);
}

/* The samples at the head of c that the ring holds already, when c starts
 * inside the held samples, runs past their end and repeats them (a sender
 * that resends the last samples with each new chunk, or a recording cut
 * into chunks that overlap); 0 otherwise (a gap, a restart, or in order). */
static size_t overlap_held(af_stream *s, const af_chunk *c)
{
  const uint64_t end = af_ring_end(s->ring);
  if (!s->seen || c->n == 0 || c->first_sample < af_ring_begin(s->ring) || c->first_sample >= end ||
      c->first_sample + c->n <= end)
    return 0;
  const size_t m = (size_t)(end - c->first_sample);
  return repeats(s, c, m) ? m : 0;
}

/* src into dst[0..len), cut to fit, '\0'-terminated: snprintf's "%s" without
 * its format parsing (a frame id with every chunk). */
static void copy_text(char *dst, size_t len, const char *src)
{
  size_t k = 0;
  for (; k + 1 < len && src[k] != '\0'; k++)
    dst[k] = src[k];
  dst[k] = '\0';
}

static bool unit_accepted(const af_stream_config *cfg, const char *unit)
{
  for (int k = 0; k < 2; k++)
    if (cfg->units[k][0] && strcmp(cfg->units[k], unit) == 0)
      return true;
  return false;
}

static af_chunk_verdict check(af_stream *s, const af_chunk *c)
{
  double expected = s->cfg->sample_rate_hz;
  if (!(fabs(c->sample_rate_hz - expected) <= AF_RATE_RTOL * expected)) {
    s->bad_rate++;
    snprintf(s->last_problem, sizeof s->last_problem,
             "%s chunk at sample %llu: sample_rate %g Hz, expected %g Hz", s->name,
             (unsigned long long)c->first_sample, c->sample_rate_hz, expected);
    return AF_CHUNK_BAD_RATE;
  }
  if (!unit_accepted(s->cfg, c->unit ? c->unit : "")) {
    s->bad_unit++;
    snprintf(s->last_problem, sizeof s->last_problem,
             "%s chunk at sample %llu: unit '%s', expected '%s'", s->name,
             (unsigned long long)c->first_sample, c->unit ? c->unit : "", s->cfg->units[0]);
    return AF_CHUNK_BAD_UNIT;
  }
  if (c->n > UINT64_MAX - c->first_sample) {
    s->bad_index++;
    snprintf(s->last_problem, sizeof s->last_problem,
             "%s chunk: first_sample %llu + %zu samples overflows the 64-bit index", s->name,
             (unsigned long long)c->first_sample, c->n);
    return AF_CHUNK_BAD_INDEX;
  }
  if (c->n > 0 && c->x == NULL) {
    s->malformed++;
    snprintf(s->last_problem, sizeof s->last_problem,
             "%s chunk at sample %llu: %zu samples, no data", s->name,
             (unsigned long long)c->first_sample, c->n);
    return AF_CHUNK_MALFORMED;
  }
  return AF_CHUNK_OK;
}

/* --- the clock ---------------------------------------------------------------- */

static const af_stream_anchor *anchor(const af_stream *s, size_t k);

static void clock_fault(af_stream *s, const af_chunk *c)
{
  s->clock_fault_ns = c->stamp_ns;
  s->clock_base = (af_stream_anchor){c->stamp_ns, c->first_sample};
  s->clock_based = true;
}

/* The rate the stamps advance at since the base, once AF_STREAM_RATE_SPAN_S
 * of them: a fault while it contradicts the chunks' rate. */
static void clock_rate(af_stream *s, const af_chunk *c)
{
  const double span_s = (double)(c->stamp_ns - s->clock_base.stamp_ns) * 1e-9;
  if (span_s < AF_STREAM_RATE_SPAN_S)
    return;
  const double rate_hz = (double)(c->first_sample - s->clock_base.first_sample) / span_s;
  const double nominal_hz = s->cfg->sample_rate_hz;
  s->clock_rate_hz = rate_hz;
  s->clock_rate_wrong = fabs(rate_hz / nominal_hz - 1.0) > AF_STREAM_RATE_TOL;
  if (s->clock_rate_wrong) {
    s->clock_fault_ns = c->stamp_ns;
    snprintf(s->clock_problem, sizeof s->clock_problem,
             "%s stamps advance at %.0f Hz of samples while the chunks say %.0f Hz: a clock "
             "that contradicts the sample rate",
             s->name, rate_hz, nominal_hz);
  }
}

/* Chunk c against the newest anchor (before it is added): a step, frozen
 * stamps, or a rate that contradicts the samples. After a gap the samples
 * between still count (first_sample says how many were lost); after a
 * restart the old indices mean nothing. */
static void check_clock(af_stream *s, const af_chunk *c, bool restarted)
{
  if (restarted || s->anchor_count == 0 || !s->clock_based) {
    s->clock_base = (af_stream_anchor){c->stamp_ns, c->first_sample};
    s->clock_based = true;
    return;
  }
  const af_stream_anchor *prev = anchor(s, 0);
  if (c->first_sample <= prev->first_sample)
    return;
  const double after_s = (double)(c->first_sample - prev->first_sample) / s->cfg->sample_rate_hz;
  const double off_s = (double)(c->stamp_ns - prev->stamp_ns) * 1e-9 - after_s;
  if (c->stamp_ns <= prev->stamp_ns) {
    s->clock_frozen++;
    clock_fault(s, c);
    snprintf(s->clock_problem, sizeof s->clock_problem,
             "%s stamps frozen: the chunk at sample %llu is stamped %.6f s, no later than the "
             "one %.6f s of samples before it",
             s->name, (unsigned long long)c->first_sample, (double)c->stamp_ns * 1e-9, after_s);
  } else if (fabs(off_s) > s->cfg->clock_step_s) {
    s->clock_steps++;
    s->clock_last_step_s = off_s;
    clock_fault(s, c);
    snprintf(s->clock_problem, sizeof s->clock_problem,
             "%s clock stepped %+.6f s at sample %llu (stamp against the samples since the "
             "chunk before; stream_clock_step_s %g s)",
             s->name, off_s, (unsigned long long)c->first_sample, s->cfg->clock_step_s);
  } else {
    clock_rate(s, c);
  }
}

bool af_stream_clock_fault_near(const af_stream *s, int64_t t_ns, int64_t margin_ns)
{
  if (s->clock_rate_wrong)
    return true;
  return s->clock_fault_ns != 0 && llabs(t_ns - s->clock_fault_ns) <= margin_ns;
}

af_chunk_verdict af_stream_push(af_stream *s, const af_chunk *c, int64_t now_ns,
                                af_ring_write_info *info)
{
  af_ring_write_info w;
  memset(&w, 0, sizeof w);
  af_chunk_verdict v = check(s, c);
  if (v == AF_CHUNK_OK && duplicate(s, c)) {
    s->duplicates++;
    snprintf(s->last_problem, sizeof s->last_problem,
             "%s chunk at sample %llu: %zu samples already held (a duplicate, ignored)", s->name,
             (unsigned long long)c->first_sample, c->n);
    v = AF_CHUNK_DUPLICATE;
  }
  if (v == AF_CHUNK_DUPLICATE)
    s->duplicate_samples += c->n;
  /* An overlap: only the new tail goes into the ring (its first sample is
   * the ring's end, so no gap and no restart). */
  const size_t held = v == AF_CHUNK_OK ? overlap_held(s, c) : 0;
  af_chunk tail = *c;
  tail.first_sample += held;
  tail.n -= held;
  tail.x = held > 0 ? c->x + held : c->x;
  uint64_t refused = v == AF_CHUNK_OK ? write_ring(s, &tail, &w) : 0;
  if (v == AF_CHUNK_OK) {
    s->chunks++;
    s->seen = true;
    s->last_rx_ns = now_ns;
    check_clock(s, c, w.restarted);
    if (w.restarted)
      s->anchor_count = 0; /* the old indices mean nothing now (the spans' are kept: a
                              window of the new stream that meets one is flagged, at worst
                              needlessly) */
    s->anchors[s->anchor_next] = (af_stream_anchor){c->stamp_ns, c->first_sample};
    s->anchor_next = (s->anchor_next + 1) % AF_STREAM_ANCHORS;
    s->anchor_count += s->anchor_count < AF_STREAM_ANCHORS;
    copy_text(s->frame_id, sizeof s->frame_id, c->frame_id ? c->frame_id : "");
    if (w.gap_samples > 0) {
      s->gaps++;
      s->lost_samples += w.gap_samples;
      snprintf(s->last_problem, sizeof s->last_problem, "%s: %llu samples lost before sample %llu",
               s->name, (unsigned long long)w.gap_samples, (unsigned long long)c->first_sample);
    }
    if (held > 0) {
      s->overlaps++;
      s->duplicate_samples += held;
      snprintf(s->last_problem, sizeof s->last_problem,
               "%s chunk at sample %llu: its first %zu of %zu samples already held (an "
               "overlap: the %zu new ones kept)",
               s->name, (unsigned long long)c->first_sample, held, c->n, c->n - held);
    }
    if (w.restarted) {
      s->restarts++;
      snprintf(s->last_problem, sizeof s->last_problem,
               "%s: stream restarted at sample %llu (went backwards)", s->name,
               (unsigned long long)c->first_sample);
    }
    s->last_refused = refused;
    s->last_held = held;
    s->refused_chunks += refused > 0;
    if (refused > 0)
      snprintf(s->last_problem, sizeof s->last_problem,
               "%s chunk at sample %llu: %llu non-finite samples refused (held as lost); "
               "%llu so far",
               s->name, (unsigned long long)c->first_sample, (unsigned long long)refused,
               (unsigned long long)s->refused_samples);
  }
  if (info)
    *info = w;
  return v;
}

uint64_t af_stream_bad_chunks(const af_stream *s)
{
  return s->bad_rate + s->bad_unit + s->bad_index + s->malformed + s->oversized;
}

void af_stream_refuse(af_stream *s, bool oversized, const char *why)
{
  if (oversized)
    s->oversized++;
  else
    s->malformed++;
  snprintf(s->last_problem, sizeof s->last_problem, "%s", why ? why : "");
}

uint64_t af_stream_refused_in(const af_stream *s, uint64_t first, uint64_t n)
{
  uint64_t total = 0, end = first + n < first ? UINT64_MAX : first + n;
  for (size_t k = 0; k < s->span_count; k++) {
    const af_stream_span *p = &s->spans[(s->span_next + AF_STREAM_SPANS - 1 - k) % AF_STREAM_SPANS];
    uint64_t a = p->first > first ? p->first : first, b = p->end < end ? p->end : end;
    total += b > a ? b - a : 0;
  }
  return total;
}

bool af_stream_stale(const af_stream *s, int64_t now_ns, double stale_after_s)
{
  return s->seen && (double)(now_ns - s->last_rx_ns) * 1e-9 > stale_after_s;
}

/* Anchor k, 0 = the newest. */
static const af_stream_anchor *anchor(const af_stream *s, size_t k)
{
  return &s->anchors[(s->anchor_next + AF_STREAM_ANCHORS - 1 - k) % AF_STREAM_ANCHORS];
}

/* The newest anchor at or before index (by_time false) or t_ns (true);
 * the oldest kept when all are later. Linear from the newest: a strike asks
 * for times a few chunks back. */
static const af_stream_anchor *holding(const af_stream *s, double index, int64_t t_ns, bool by_time)
{
  size_t k = 0;
  while (k + 1 < s->anchor_count) {
    const af_stream_anchor *a = anchor(s, k);
    if (by_time ? a->stamp_ns <= t_ns : (double)a->first_sample <= index)
      break;
    k++;
  }
  return anchor(s, k);
}

/* The newest anchor at or before a whole index; the oldest kept when all
 * are later. */
static const af_stream_anchor *holding_index(const af_stream *s, uint64_t index)
{
  size_t k = 0;
  while (k + 1 < s->anchor_count && anchor(s, k)->first_sample > index)
    k++;
  return anchor(s, k);
}

/* stamp_ns + offset_ns, saturated at +-AF_STREAM_TIME_MAX_NS: an index a
 * sender put 2^63 samples away from its anchor is a time no clock reaches,
 * and the difference of two such times must still be a number (the sum of
 * two values within the bound cannot overflow). The integer stamp is added
 * to the rounded offset, not in a double: 1.7e18 ns in a double is only
 * good to 256 ns. */
static int64_t time_plus(int64_t stamp_ns, double offset_ns)
{
  const double max = (double)AF_STREAM_TIME_MAX_NS;
  const int64_t stamp = stamp_ns > AF_STREAM_TIME_MAX_NS    ? AF_STREAM_TIME_MAX_NS
                        : stamp_ns < -AF_STREAM_TIME_MAX_NS ? -AF_STREAM_TIME_MAX_NS
                                                            : stamp_ns;
  const int64_t offset = offset_ns >= max    ? AF_STREAM_TIME_MAX_NS
                         : offset_ns <= -max ? -AF_STREAM_TIME_MAX_NS
                                             : (int64_t)llround(offset_ns); /* NaN: not here */
  const int64_t t = stamp + offset;
  return t > AF_STREAM_TIME_MAX_NS    ? AF_STREAM_TIME_MAX_NS
         : t < -AF_STREAM_TIME_MAX_NS ? -AF_STREAM_TIME_MAX_NS
                                      : t;
}

int64_t af_stream_time_of_ns(const af_stream *s, uint64_t index, double frac)
{
  const af_stream_anchor *a = holding_index(s, index);
  /* The difference in integers first: small, whatever the index. */
  const double offset = (double)(int64_t)(index - a->first_sample) + frac;
  return time_plus(a->stamp_ns, offset / s->cfg->sample_rate_hz * 1e9);
}

bool af_stream_pos_at(const af_stream *s, int64_t t_ns, uint64_t *index, double *frac)
{
  const af_stream_anchor *a = holding(s, 0.0, t_ns, true);
  const double offset = (double)(t_ns - a->stamp_ns) * 1e-9 * s->cfg->sample_rate_hz;
  const double whole = floor(offset);
  *frac = offset - whole;
  if (whole < 0.0 && -whole > (double)a->first_sample)
    return false;
  *index = whole < 0.0 ? a->first_sample - (uint64_t)(-whole) : a->first_sample + (uint64_t)whole;
  return true;
}

int64_t af_stream_time_ns(const af_stream *s, double index)
{
  const af_stream_anchor *a = holding(s, index, 0, false);
  double offset_s = (index - (double)a->first_sample) / s->cfg->sample_rate_hz;
  return time_plus(a->stamp_ns, offset_s * 1e9);
}

double af_stream_index_at(const af_stream *s, int64_t t_ns)
{
  const af_stream_anchor *a = holding(s, 0.0, t_ns, true);
  return (double)a->first_sample + (double)(t_ns - a->stamp_ns) * 1e-9 * s->cfg->sample_rate_hz;
}
