/* audio_lag.c — the audio clock's lag behind the force's (see audio_lag.h). */
#include "audio_lag.h"

#include <math.h>
#include <stdint.h>
#include <string.h>

#include "median.h"

/* The sum in sample order (the same double whatever the unrolling: four
 * squares a step, added one by one, for fewer loop instructions). */
static double mean_square(const float *x, size_t n)
{
  double e = 0.0;
  size_t k = 0;
  for (; k + 4 <= n; k += 4) {
    const double a = x[k], b = x[k + 1], c = x[k + 2], d = x[k + 3];
    e += a * a;
    e += b * b;
    e += c * c;
    e += d * d;
  }
  for (; k < n; k++)
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

/* The largest |x[k]| of x[0..n), n >= 1: of finite floats the magnitude
 * bits order as integers, which the compiler vectorises (NaN or inf gives
 * a bound no energy passes). */
static double largest_magnitude(const float *x, size_t n)
{
  int32_t top = 0;
  for (size_t k = 0; k < n; k++) {
    int32_t b;
    memcpy(&b, &x[k], sizeof b);
    b &= 0x7fffffff;
    top = b > top ? b : top;
  }
  float m;
  memcpy(&m, &top, sizeof m);
  return m;
}

/* The block energies (each once): e[0..*done) computed, *loudest their
 * largest; onset_find computes them only as far as its search goes. */
typedef struct {
  const float *x;
  size_t blocks, block, done;
  double loudest;
  double e[AF_AUDIO_LAG_MAX_BLOCKS];
} af_energies;

static void energies_to(af_energies *s, size_t end)
{
  for (; s->done < end; s->done++) {
    const double e = mean_square(s->x + s->done * s->block, s->block);
    s->e[s->done] = e;
    s->loudest = e > s->loudest ? e : s->loudest;
  }
}

/* Whether e[b] is within AF_AUDIO_LAG_FLOOR of the loudest block of all
 * (e[b] < AF_AUDIO_LAG_FLOOR x loudest not true). The blocks not computed
 * yet are first bounded by their largest sample: a mean of squares is at
 * most its largest square, and its rounding over `block` terms at most
 * ~block ulps above (the factor's slack is far more). When e[b] passes the
 * bound it passes the loudest; else they are computed. */
static bool loud_enough(af_energies *s, size_t b)
{
  if (s->done < s->blocks) {
    const double m = largest_magnitude(s->x + s->done * s->block, (s->blocks - s->done) * s->block);
    const double bound = m * m * (1.0 + 1e-15 * (double)(s->block + 2));
    const double u = bound > s->loudest ? bound : s->loudest;
    if (!(s->e[b] < AF_AUDIO_LAG_FLOOR * u))
      return true;
    energies_to(s, s->blocks);
  }
  return !(s->e[b] < AF_AUDIO_LAG_FLOOR * s->loudest);
}

bool af_audio_onset_find(const float *x, size_t n, size_t block, size_t *at)
{
  if (x == NULL || block == 0 || n / block <= AF_AUDIO_LAG_REF_BLOCKS)
    return false;
  /* Each block's energy once (at most AF_AUDIO_LAG_MAX_BLOCKS: the search's
   * +-1 s at 1 ms blocks), in order as far as the search goes; the loudest
   * of all sets the floor. A block below the floor of those computed is
   * below it of all. */
  af_energies s; /* not zeroed: e[] is written before it is read */
  s.x = x;
  s.blocks = n / block < AF_AUDIO_LAG_MAX_BLOCKS ? n / block : AF_AUDIO_LAG_MAX_BLOCKS;
  s.block = block;
  s.done = 0;
  s.loudest = 0.0;
  energies_to(&s, AF_AUDIO_LAG_REF_BLOCKS);
  for (size_t b = AF_AUDIO_LAG_REF_BLOCKS; b < s.blocks; b++) {
    energies_to(&s, b + 1);
    if (s.e[b] <= 0.0 || s.e[b] < AF_AUDIO_LAG_FLOOR * s.loudest)
      continue;
    const double ref = reference(s.e, b);
    if (s.e[b] > AF_AUDIO_LAG_RISE * ref && loud_enough(&s, b)) {
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
