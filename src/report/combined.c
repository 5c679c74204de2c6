/* combined.c — the summary over several bags (see combined.h). */
#include "combined.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void af_combined_init(af_combined *c)
{
  memset(c, 0, sizeof *c);
  c->counts.modulus_factor_now = NAN;
}

void af_combined_free(af_combined *c)
{
  for (int k = 0; k < AF_SUMMARY_COLUMNS; k++) {
    free(c->col[k]);
    c->col[k] = NULL;
  }
  c->n = c->cap = 0;
}

static bool reserve(af_combined *c, size_t more)
{
  if (c->n + more <= c->cap)
    return true;
  size_t want = c->cap ? c->cap : 1024;
  while (want < c->n + more)
    want *= 2;
  for (int k = 0; k < AF_SUMMARY_COLUMNS; k++) {
    double *q = realloc(c->col[k], want * sizeof *q);
    if (q == NULL)
      return false;
    c->col[k] = q;
  }
  c->cap = want;
  return true;
}

static void add_stream(af_session_stream *into, const af_session_stream *s)
{
  into->chunks += s->chunks;
  into->gaps += s->gaps;
  into->lost_samples += s->lost_samples;
  into->restarts += s->restarts;
  into->bad_rate += s->bad_rate;
  into->bad_unit += s->bad_unit;
  into->bad_index += s->bad_index;
  into->malformed += s->malformed;
  into->oversized += s->oversized;
  into->refused_samples += s->refused_samples;
  into->refused_spans += s->refused_spans;
  into->duplicates += s->duplicates;
  into->overlaps += s->overlaps;
  into->duplicate_samples += s->duplicate_samples;
  into->clock_steps += s->clock_steps;
  into->clock_frozen += s->clock_frozen;
  into->clock_rate_wrong |= s->clock_rate_wrong;
  if (s->clock_problem[0] != '\0')
    memcpy(into->clock_problem, s->clock_problem, sizeof into->clock_problem);
}

static void add_counts(af_summary *into, const af_summary *m)
{
  into->strikes += m->strikes;
  into->reliable += m->reliable;
  into->with_apple += m->with_apple;
  into->without_apple += m->without_apple;
  into->without_audio += m->without_audio;
  into->doubtful += m->doubtful;
  into->apples += m->apples;
  into->apples_refused += m->apples_refused;
  into->apples_without_strike += m->apples_without_strike;
  into->apples_predicted_reliable += m->apples_predicted_reliable;
  for (int b = 0; b < AF_SUMMARY_FLAGS; b++)
    into->by_flag[b] += m->by_flag[b];
  for (int k = 0; k < AF_SUMMARY_AUDIO_CAUSES; k++)
    into->by_audio_cause[k] += m->by_audio_cause[k];
  if (m->strikes > 0) { /* the latest bag's, as a bag's is its latest strike's */
    into->modulus_factor_now = m->modulus_factor_now;
    into->factor_learned = m->factor_learned; /* each bag's lane learns from its start */
  }
}

/* The bag's counts, streams and lane counters into c (its columns are added by the caller). */
static void add_bag(af_combined *c, const af_session *s, const af_summary *m)
{
  c->bags++;
  add_counts(&c->counts, m);
  af_session *t = &c->totals;
  add_stream(&t->force, &s->force);
  add_stream(&t->audio, &s->audio);
  t->stats.overflows += s->stats.overflows;
  t->stats.late_apples += s->stats.late_apples;
  t->stats.pulse_cut += s->stats.pulse_cut;
  t->stats.apples_implausible += s->stats.apples_implausible;
  t->stats.apples_skipped += s->stats.apples_skipped;
  if (s->stats.apples_skipped > 0)
    memcpy(t->stats.last_apples_skipped, s->stats.last_apples_skipped,
           sizeof t->stats.last_apples_skipped);
  t->stats.audio_clipped += s->stats.audio_clipped;
  t->stats.clock_faulted += s->stats.clock_faulted;
  t->stats.lag_no_onset += s->stats.lag_no_onset;
  t->stats.lag_moves += s->stats.lag_moves;
  if (s->stats.lag_strikes > 0) { /* the medians are a bag's own: the latest */
    t->stats.lag_median_s = s->stats.lag_median_s;
    t->stats.lag_mad_s = s->stats.lag_mad_s;
    t->stats.lag_applied_s = s->stats.lag_applied_s;
    t->stats.lag_strikes = s->stats.lag_strikes;
  }
  if (s->stats.lag_moves > 0)
    memcpy(t->stats.lag_warning, s->stats.lag_warning, sizeof t->stats.lag_warning);
  if (s->stats.apples_implausible > 0)
    memcpy(t->stats.last_implausible_apple, s->stats.last_implausible_apple,
           sizeof t->stats.last_implausible_apple);
  if (s->stats.transit_warning[0] != '\0' || t->stats.transit_strikes == 0) {
    /* The medians are a bag's own: the latest bag that says something. */
    t->stats.transit_observed_s = s->stats.transit_observed_s;
    t->stats.transit_strikes = s->stats.transit_strikes;
    memcpy(t->stats.transit_warning, s->stats.transit_warning, sizeof t->stats.transit_warning);
  }
  t->messages += s->messages;
  t->refused_messages += s->refused_messages;
  t->refused_apples += s->refused_apples;
  t->recorded_s += s->recorded_s;
  t->tap_only = s->tap_only; /* one configuration for every bag */
  t->wall_s += s->wall_s;
  t->cpu_s += s->cpu_s;
}

af_status af_combined_add(af_combined *c, const af_session *s, const af_summary *m)
{
  if (!reserve(c, s->n_strikes))
    return AF_ENOMEM;
  for (size_t k = 0; k < s->n_strikes; k++) {
    double row[AF_SUMMARY_COLUMNS];
    af_summary_columns_of(&s->strikes[k], row);
    for (int j = 0; j < AF_SUMMARY_COLUMNS; j++)
      c->col[j][c->n] = row[j];
    c->n++;
  }
  add_bag(c, s, m);
  return AF_OK;
}

af_status af_combined_add_rows(af_combined *c, const af_session *s, const af_summary *m,
                               const double *rows, size_t n)
{
  if (!reserve(c, n))
    return AF_ENOMEM;
  for (size_t k = 0; k < n; k++, c->n++)
    for (int j = 0; j < AF_SUMMARY_COLUMNS; j++)
      c->col[j][c->n] = rows[k * AF_SUMMARY_COLUMNS + (size_t)j];
  add_bag(c, s, m);
  return AF_OK;
}

void af_combined_summary(af_combined *c, af_summary *out)
{
  *out = c->counts;
  double *col[AF_SUMMARY_COLUMNS];
  for (int k = 0; k < AF_SUMMARY_COLUMNS; k++)
    col[k] = c->col[k];
  if (c->n == 0) { /* no column allocated: the figures of no strike */
    double none = NAN;
    for (int k = 0; k < AF_SUMMARY_COLUMNS; k++)
      col[k] = &none;
  }
  af_summary_figures(out, col, c->n);
}
