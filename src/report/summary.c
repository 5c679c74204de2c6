/* summary.c — the figures of a session (see summary.h). */
#include "summary.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

const double af_summary_levels[AF_SUMMARY_QUANTILES] = {0.0, 0.1, 0.25, 0.5, 0.75, 0.9, 1.0};

static int cmp_double(const void *a, const void *b)
{
  double x = *(const double *)a, y = *(const double *)b;
  return (x > y) - (x < y);
}

af_quantiles af_summary_quantiles(double *x, size_t n)
{
  af_quantiles q;
  size_t m = 0;
  for (size_t k = 0; k < n; k++) /* the finite ones first */
    if (isfinite(x[k])) {
      double t = x[m];
      x[m++] = x[k];
      x[k] = t;
    }
  qsort(x, m, sizeof *x, cmp_double);
  q.n = m;
  for (int k = 0; k < AF_SUMMARY_QUANTILES; k++) {
    if (m == 0) {
      q.q[k] = NAN;
      continue;
    }
    double h = af_summary_levels[k] * (double)(m - 1);
    size_t lo = (size_t)floor(h);
    size_t hi = lo + 1 < m ? lo + 1 : lo;
    q.q[k] = x[lo] + (h - (double)lo) * (x[hi] - x[lo]);
  }
  return q;
}

/* One column of the strikes into scratch, then its quantiles. */
typedef double af_column_fn(const af_session_strike *r);

static double col_e0s2(const af_session_strike *r)
{
  return r->report.modulus_from_resonance_pa;
}
static double col_efit(const af_session_strike *r)
{
  return r->report.fitted_modulus_pa;
}
static double col_stiffness(const af_session_strike *r)
{
  return r->report.stiffness_factor;
}
static double col_resonance(const af_session_strike *r)
{
  return r->report.resonance_hz;
}
static double col_ratio(const af_session_strike *r)
{
  return r->report.modulus_from_resonance_pa / r->report.fitted_modulus_pa;
}
static double col_factor(const af_session_strike *r)
{
  return r->modulus_factor * col_ratio(r);
}

/* The per-strike columns of the figures, in af_summary_figures' order. */
static af_column_fn *const columns[AF_SUMMARY_COLUMNS] = {col_e0s2,      col_efit,  col_stiffness,
                                                          col_resonance, col_ratio, col_factor};

void af_summary_columns_of(const af_session_strike *r, double out[AF_SUMMARY_COLUMNS])
{
  for (int c = 0; c < AF_SUMMARY_COLUMNS; c++)
    out[c] = columns[c](r);
}

void af_summary_figures(af_summary *out, double *const col[AF_SUMMARY_COLUMNS], size_t n)
{
  out->modulus_from_resonance_pa = af_summary_quantiles(col[0], n);
  out->fitted_modulus_pa = af_summary_quantiles(col[1], n);
  out->stiffness_factor = af_summary_quantiles(col[2], n);
  out->resonance_hz = af_summary_quantiles(col[3], n);
  out->modulus_ratio = af_summary_quantiles(col[4], n);
  /* Spread: the median absolute deviation of the ratio (its column holds
   * the finite ratios sorted first), scaled to a standard deviation. */
  double *ratio = col[4];
  const size_t m = out->modulus_ratio.n;
  const double median = out->modulus_ratio.q[3];
  for (size_t k = 0; k < m; k++)
    ratio[k] = fabs(ratio[k] - median);
  af_quantiles mad = af_summary_quantiles(ratio, m);
  out->modulus_ratio_spread = m > 0 ? 1.4826 * mad.q[3] / median : NAN;
  out->modulus_factor_suggested = af_summary_quantiles(col[5], n).q[3];
}

af_status af_summary_compute(const af_session *s, af_summary *out)
{
  memset(out, 0, sizeof *out);
  const size_t n = s->n_strikes;
  double *scratch = malloc((AF_SUMMARY_COLUMNS * n + 1) * sizeof *scratch);
  if (!scratch)
    return AF_ENOMEM;
  double *col[AF_SUMMARY_COLUMNS];
  for (int c = 0; c < AF_SUMMARY_COLUMNS; c++)
    col[c] = scratch + (size_t)c * n;
  out->strikes = n;
  out->modulus_factor_now = NAN;
  for (size_t k = 0; k < n; k++) {
    const af_session_strike *r = &s->strikes[k];
    const af_verdict *v = &r->report.verdict;
    double row[AF_SUMMARY_COLUMNS];
    af_summary_columns_of(r, row);
    for (int c = 0; c < AF_SUMMARY_COLUMNS; c++)
      col[c][k] = row[c];
    out->reliable += r->report.reliable;
    out->with_apple += r->has_apple;
    out->without_apple += (v->flags & AF_VERDICT_NO_APPLE) != 0;
    out->doubtful += (v->flags & AF_VERDICT_APPLE_DOUBTFUL) != 0;
    if (v->flags & AF_VERDICT_NO_AUDIO) {
      out->without_audio++;
      if ((unsigned)v->audio_cause < AF_SUMMARY_AUDIO_CAUSES)
        out->by_audio_cause[v->audio_cause]++;
    }
    for (unsigned b = 0; b < AF_SUMMARY_FLAGS; b++)
      out->by_flag[b] += (v->flags >> b) & 1u;
    out->modulus_factor_now = r->modulus_factor;
  }
  out->apples = s->n_apples;
  for (size_t k = 0; k < s->n_apples; k++) {
    out->apples_refused += !s->apples[k].valid;
    out->apples_without_strike += s->apples[k].strikes == 0;
    out->apples_predicted_reliable += s->apples[k].reliable;
  }
  af_summary_figures(out, col, n);
  out->factor_learned = s->factor;
  free(scratch);
  return AF_OK;
}
