/* audio_lag.c — the audio clock's lag behind the force's (see audio_lag.h). */
#include "audio_lag.h"

#include <math.h>
#include <string.h>

#include "median.h"

static double mean_square(const float *x, size_t n)
{
  double e = 0.0;
  for (size_t k = 0; k < n; k++)
    e += (double)x[k] * (double)x[k];
  return e / (double)n;
}

/* The quietest of the AF_AUDIO_LAG_REF_BLOCKS block energies before e[b]. */
static double reference(const double *e, size_t b)
{
  double q = INFINITY;
  for (size_t j = b - AF_AUDIO_LAG_REF_BLOCKS; j < b; j++)
    q = e[j] < q ? e[j] : q;
  return q;
}

/* The first sample of blocks b - 1 and b above level; the block's first
 * when none is (the rise is the block's as a whole). */
static size_t refine(const float *x, size_t b, size_t block, double level)
{
  for (size_t k = (b - 1) * block; k < (b + 1) * block; k++)
    if (fabs((double)x[k]) > level)
      return k;
  return b * block;
}

bool af_audio_onset_find(const float *x, size_t n, size_t block, size_t *at)
{
  if (x == NULL || block == 0 || n / block <= AF_AUDIO_LAG_REF_BLOCKS)
    return false;
  /* Each block's energy once (at most AF_AUDIO_LAG_MAX_BLOCKS: the search's
   * +-1 s at 1 ms blocks); the loudest sets the floor. */
  double e[AF_AUDIO_LAG_MAX_BLOCKS];
  size_t blocks = n / block;
  if (blocks > AF_AUDIO_LAG_MAX_BLOCKS)
    blocks = AF_AUDIO_LAG_MAX_BLOCKS;
  double loudest = 0.0;
  for (size_t b = 0; b < blocks; b++) {
    e[b] = mean_square(x + b * block, block);
    loudest = e[b] > loudest ? e[b] : loudest;
  }
  for (size_t b = AF_AUDIO_LAG_REF_BLOCKS; b < blocks; b++) {
    if (e[b] <= 0.0 || e[b] < AF_AUDIO_LAG_FLOOR * loudest)
      continue;
    const double ref = reference(e, b);
    if (e[b] > AF_AUDIO_LAG_RISE * ref) {
      *at = refine(x, b, block, 0.5 * sqrt(AF_AUDIO_LAG_RISE * ref));
      return true;
    }
  }
  return false;
}

void af_audio_lag_reset(af_audio_lag *g)
{
  memset(g, 0, sizeof *g);
  g->median_s = g->mad_s = NAN;
}

bool af_audio_lag_push(af_audio_lag *g, double lag_s, bool apply)
{
  const bool moved = g->stable && fabs(lag_s - g->median_s) >= AF_AUDIO_LAG_MOVE_S;
  g->moves += moved;
  g->measured++;
  g->lag_s[g->next] = lag_s;
  g->next = (g->next + 1) % AF_AUDIO_LAG_HISTORY;
  g->n += g->n < AF_AUDIO_LAG_HISTORY;
  if (g->n < AF_AUDIO_LAG_MIN)
    return moved;
  double dev[AF_AUDIO_LAG_HISTORY] = {0};
  g->median_s = af_median_small(g->lag_s, g->n);
  for (size_t k = 0; k < g->n; k++)
    dev[k] = fabs(g->lag_s[k] - g->median_s);
  g->mad_s = af_median_small(dev, g->n);
  g->stable = g->mad_s <= AF_AUDIO_LAG_STABLE_S;
  if (g->stable)
    g->applied_s = apply && fabs(g->median_s) > AF_AUDIO_LAG_DEADBAND_S ? g->median_s : 0.0;
  return moved;
}
