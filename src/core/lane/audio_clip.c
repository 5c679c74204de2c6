/* audio_clip.c — a saturated microphone, from the samples alone (see audio_clip.h). */
#include "audio_clip.h"

#include <math.h>
#include <stdint.h>
#include <string.h>

/* A negative float's magnitude bits flipped (the bits' own inverse). */
static uint32_t flip_negative(uint32_t b)
{
  return b ^ ((0u - (b >> 31)) >> 1);
}

/* An order-preserving key of a finite float: its bits as a signed integer,
 * a negative one's magnitude bits flipped (so -0 sorts just below +0). */
static int32_t key_of(float v)
{
  uint32_t b;
  memcpy(&b, &v, sizeof b);
  b = flip_negative(b);
  int32_t key;
  memcpy(&key, &b, sizeof key);
  return key;
}

static float value_of(int32_t key)
{
  uint32_t b;
  memcpy(&b, &key, sizeof b);
  b = flip_negative(b);
  float v;
  memcpy(&v, &b, sizeof v);
  return v;
}

/* The first zero of x[0..n) (there is one): -0 or +0. */
static float first_zero(const float *x, size_t n)
{
  size_t k = 0;
  while (x[k] != 0.0f && k + 1 < n)
    k++;
  return x[k];
}

/* The extremes of the finite x[0..n): the largest and smallest keys, in
 * integer compares that the compiler vectorises (float ones it may not:
 * -0 and +0 compare equal). A zero extreme is then the first zero, as a
 * scan keeping the first of equal values gives. */
static void extremes(const float *x, size_t n, double *hi, double *lo)
{
  int32_t top = key_of(x[0]), bottom = top;
  for (size_t k = 1; k < n; k++) {
    const int32_t c = key_of(x[k]);
    top = c > top ? c : top;
    bottom = c < bottom ? c : bottom;
  }
  const float h = value_of(top), l = value_of(bottom);
  *hi = h == 0.0f ? first_zero(x, n) : h;
  *lo = l == 0.0f ? first_zero(x, n) : l;
}

/* Whether some step between neighbours is non-zero and at most top /
 * AF_AUDIO_CLIP_MIN_LEVELS: the extremes lie that many converter quanta
 * (the smallest non-zero step; float audio: some tiny step) or more from
 * zero. A signal of any level finds one within a few samples. */
static bool fine_steps(const float *x, size_t n, double top)
{
  for (size_t k = 1; k < n; k++) {
    const double d = fabs((double)x[k] - (double)x[k - 1]);
    if (d > 0.0 && AF_AUDIO_CLIP_MIN_LEVELS * d <= top)
      return true;
  }
  return false;
}

/* Samples of x[0..n) equal to hi or lo (vectorised). */
static size_t count_at(const float *x, size_t n, float hi, float lo)
{
  size_t at = 0;
  for (size_t k = 0; k < n; k++)
    at += (x[k] == hi) | (x[k] == lo);
  return at;
}

/* Whether x[0..n) holds at least AF_AUDIO_CLIP_MIN_VALUES distinct values
 * (a small open-addressed set of their bit patterns, on the stack): a
 * signal pinned at full scale has its other samples anywhere, a quiet one
 * of a few converter codes has only those. */
static bool many_values(const float *x, size_t n)
{
  uint32_t seen[4 * AF_AUDIO_CLIP_MIN_VALUES] = {0};
  bool used[4 * AF_AUDIO_CLIP_MIN_VALUES] = {false};
  const size_t slots = sizeof seen / sizeof seen[0];
  size_t distinct = 0;
  for (size_t k = 0; k < n && distinct < AF_AUDIO_CLIP_MIN_VALUES; k++) {
    uint32_t b;
    memcpy(&b, &x[k], sizeof b);
    size_t h = (size_t)(b * 2654435761u) % slots;
    while (used[h] && seen[h] != b)
      h = (h + 1) % slots;
    if (!used[h]) {
      used[h] = true;
      seen[h] = b;
      distinct++;
    }
  }
  return distinct >= AF_AUDIO_CLIP_MIN_VALUES;
}

/* Runs of >= 2 samples at hi or lo in x[0..n). */
static size_t flat_tops(const float *x, size_t n, double hi, double lo)
{
  size_t run = 0, tops = 0;
  for (size_t k = 0; k < n; k++) {
    /* Runs of the maximum and of the minimum alike (a run cannot hold both). */
    const bool at = x[k] == (float)hi || x[k] == (float)lo;
    const bool same = at && run > 0 && x[k] == x[k - 1];
    run = at ? (same ? run + 1 : 1) : 0;
    tops += run == 2; /* counted once, when the run becomes a top */
  }
  return tops;
}

void af_audio_clip_check(const float *x, size_t n, af_audio_clip *out)
{
  *out = (af_audio_clip){.clipped = false, .max = NAN, .min = NAN};
  if (x == NULL || n < 2)
    return;
  double hi, lo;
  extremes(x, n, &hi, &lo);
  out->max = hi;
  out->min = lo;
  if (!fine_steps(x, n, fmax(fabs(hi), fabs(lo))) && !many_values(x, n))
    return; /* a few codes (or a constant): the extremes repeat by themselves */
  out->at_extremes = count_at(x, n, (float)hi, (float)lo);
  /* A flat top needs two samples at one extreme: none when the maximum
   * and the minimum are held once each. */
  out->flat_tops = out->at_extremes == 2 && hi != lo ? 0 : flat_tops(x, n, hi, lo);
  out->clipped = out->flat_tops >= AF_AUDIO_CLIP_MIN_TOPS ||
                 (double)out->at_extremes > AF_AUDIO_CLIP_MIN_SHARE * (double)n;
}
