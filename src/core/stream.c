/* stream.c — checks and buffers the chunks of one input (see stream.h). */
#include "stream.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Rates are configured and sent as the same nominal number; this only
 * absorbs a rate that went through a float. */
#define AF_RATE_RTOL 1e-6

void af_stream_to_si(double to_si, const float *x, size_t n, float *out)
{
  for (size_t k = 0; k < n; k++)
    out[k] = (float)((double)x[k] * to_si);
}

static bool converts(const af_stream_config *cfg)
{
  return cfg->to_si != 1.0 && cfg->to_si != 0.0; /* 0: a config made without a unit */
}

af_status af_stream_create(af_stream *s, const char *name, const af_stream_config *cfg)
{
  memset(s, 0, sizeof *s);
  s->name = name;
  s->cfg = cfg;
  if (converts(cfg) && (s->si = malloc(AF_STREAM_BLOCK * sizeof *s->si)) == NULL)
    return AF_ENOMEM;
  return af_ring_create(cfg->capacity_samples, &s->ring);
}

void af_stream_destroy(af_stream *s)
{
  af_ring_destroy(s->ring);
  s->ring = NULL;
  free(s->si);
  s->si = NULL;
}

/* The chunk into the ring, converted block by block when the unit is not
 * the lane's; *w: what the first block's write found (gaps and restarts can
 * only come before it, the blocks follow each other). */
static af_status write_ring(af_stream *s, const af_chunk *c, af_ring_write_info *w)
{
  if (!converts(s->cfg))
    return af_ring_write(s->ring, c->x, c->n, c->first_sample, w);
  for (size_t at = 0; at < c->n || at == 0; at += AF_STREAM_BLOCK) {
    size_t m = c->n - at < AF_STREAM_BLOCK ? c->n - at : AF_STREAM_BLOCK;
    af_ring_write_info block;
    af_stream_to_si(s->cfg->to_si, c->x + at, m, s->si);
    af_status st = af_ring_write(s->ring, s->si, m, c->first_sample + at, at ? &block : w);
    if (st != AF_OK || c->n == 0)
      return st;
  }
  return AF_OK;
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
  for (size_t k = 0; k < c->n; k++) {
    if (!isfinite(c->x[k])) {
      s->bad_data++;
      snprintf(s->last_problem, sizeof s->last_problem, "%s chunk at sample %llu: sample %zu is %g",
               s->name, (unsigned long long)c->first_sample, k, (double)c->x[k]);
      return AF_CHUNK_BAD_DATA;
    }
  }
  return AF_CHUNK_OK;
}

af_chunk_verdict af_stream_push(af_stream *s, const af_chunk *c, int64_t now_ns,
                                af_ring_write_info *info)
{
  af_ring_write_info w;
  memset(&w, 0, sizeof w);
  af_chunk_verdict v = check(s, c);
  if (v == AF_CHUNK_OK && write_ring(s, c, &w) != AF_OK) {
    /* Only an index overflow gets here: first_sample + n past 2^64. */
    s->bad_data++;
    snprintf(s->last_problem, sizeof s->last_problem, "%s chunk: first_sample %llu + %zu overflows",
             s->name, (unsigned long long)c->first_sample, c->n);
    v = AF_CHUNK_BAD_DATA;
  }
  if (v == AF_CHUNK_OK) {
    s->chunks++;
    s->seen = true;
    s->last_rx_ns = now_ns;
    if (w.restarted)
      s->anchor_count = 0; /* the old indices mean nothing now */
    s->anchors[s->anchor_next] = (af_stream_anchor){c->stamp_ns, c->first_sample};
    s->anchor_next = (s->anchor_next + 1) % AF_STREAM_ANCHORS;
    s->anchor_count += s->anchor_count < AF_STREAM_ANCHORS;
    snprintf(s->frame_id, sizeof s->frame_id, "%s", c->frame_id ? c->frame_id : "");
    if (w.gap_samples > 0) {
      s->gaps++;
      s->lost_samples += w.gap_samples;
      snprintf(s->last_problem, sizeof s->last_problem, "%s: %llu samples lost before sample %llu",
               s->name, (unsigned long long)w.gap_samples, (unsigned long long)c->first_sample);
    }
    if (w.restarted) {
      s->restarts++;
      snprintf(s->last_problem, sizeof s->last_problem,
               "%s: stream restarted at sample %llu (went backwards)", s->name,
               (unsigned long long)c->first_sample);
    }
  }
  if (info)
    *info = w;
  return v;
}

uint64_t af_stream_bad_chunks(const af_stream *s)
{
  return s->bad_rate + s->bad_unit + s->bad_data;
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

int64_t af_stream_time_ns(const af_stream *s, double index)
{
  const af_stream_anchor *a = holding(s, index, 0, false);
  double offset_s = (index - (double)a->first_sample) / s->cfg->sample_rate_hz;
  return a->stamp_ns + (int64_t)llround(offset_s * 1e9);
}

double af_stream_index_at(const af_stream *s, int64_t t_ns)
{
  const af_stream_anchor *a = holding(s, 0.0, t_ns, true);
  return (double)a->first_sample + (double)(t_ns - a->stamp_ns) * 1e-9 * s->cfg->sample_rate_hz;
}
