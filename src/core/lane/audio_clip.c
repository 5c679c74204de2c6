/* audio_clip.c — a saturated microphone, from the samples alone (see audio_clip.h). */
#include "audio_clip.h"

#include <math.h>
#include <stdint.h>
#include <string.h>

/* The extremes and the smallest non-zero step between neighbours: the
 * converter's quantum where there is one (float audio: some tiny step). */
static double extremes(const float *x, size_t n, double *hi, double *lo)
{
  double q = INFINITY;
  *hi = *lo = x[0];
  for (size_t k = 1; k < n; k++) {
    const double v = x[k], d = fabs(v - (double)x[k - 1]);
    *hi = v > *hi ? v : *hi;
    *lo = v < *lo ? v : *lo;
    if (d > 0.0 && d < q)
      q = d;
  }
  return q;
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

void af_audio_clip_check(const float *x, size_t n, af_audio_clip *out)
{
  *out = (af_audio_clip){.clipped = false, .max = NAN, .min = NAN};
  if (x == NULL || n < 2)
    return;
  double hi, lo;
  const double q = extremes(x, n, &hi, &lo);
  out->max = hi;
  out->min = lo;
  if (!(fmax(fabs(hi), fabs(lo)) >= AF_AUDIO_CLIP_MIN_LEVELS * q) && !many_values(x, n))
    return; /* a few codes (or a constant): the extremes repeat by themselves */
  size_t run = 0;
  for (size_t k = 0; k < n; k++) {
    /* Runs of the maximum and of the minimum alike (a run cannot hold both). */
    const bool at = x[k] == (float)hi || x[k] == (float)lo;
    const bool same = at && run > 0 && x[k] == x[k - 1];
    out->at_extremes += at;
    run = at ? (same ? run + 1 : 1) : 0;
    out->flat_tops += run == 2; /* counted once, when the run becomes a top */
  }
  out->clipped = out->flat_tops >= AF_AUDIO_CLIP_MIN_TOPS ||
                 (double)out->at_extremes > AF_AUDIO_CLIP_MIN_SHARE * (double)n;
}
