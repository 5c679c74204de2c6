/* audio_clip.h — a saturated microphone, from the samples alone.
 *
 * A microphone's preamplifier or converter that saturates writes the same
 * extreme value for as long as the sound exceeds it: flat tops at the
 * window's maximum and minimum, in cycle after cycle. A ringing fruit that
 * is only loud reaches its extreme once (its envelope decays: the next
 * cycle is exp(-pi / Q) lower). So a window is clipped when its extremes are
 * held by flat tops in at least AF_AUDIO_CLIP_MIN_TOPS places, or by more
 * than AF_AUDIO_CLIP_MIN_SHARE of its samples (a sound card pinned at full
 * scale). A window whose extremes lie within AF_AUDIO_CLIP_MIN_LEVELS steps
 * of its quantum and that holds fewer than AF_AUDIO_CLIP_MIN_VALUES distinct
 * values (a quiet signal of a few converter codes, whose slowly decaying
 * peaks may repeat a code) is not judged: its extremes repeat without any
 * saturation. The full scale need not be known; SignalChunk audio in Pa does
 * not carry it. */
#ifndef AF_AUDIO_CLIP_H
#define AF_AUDIO_CLIP_H

#include <stdbool.h>
#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

#define AF_AUDIO_CLIP_MIN_TOPS 3       /* flat tops (runs of >= 2 samples) at the extremes */
#define AF_AUDIO_CLIP_MIN_SHARE 0.01   /* or this share of the window at its extremes */
#define AF_AUDIO_CLIP_MIN_LEVELS 256.0 /* extremes below this many quanta ... */
#define AF_AUDIO_CLIP_MIN_VALUES 16    /* ... and fewer distinct values than this: not judged */

typedef struct {
  bool clipped;
  size_t at_extremes; /* samples equal to the window's maximum or minimum */
  size_t flat_tops;   /* runs of >= 2 such samples */
  double max, min;    /* the window's extremes, in the audio's unit */
} af_audio_clip;

/* Judges x[0..n) (finite samples; the lane reads windows without lost
 * samples). Allocation-free: a pass for the extremes, one for a step finer
 * than the quantum test needs (it stops at the first), one counting the
 * samples at the extremes, and one for the runs only when an extreme is
 * held more than once. n 0: not clipped. */
void af_audio_clip_check(const float *x, size_t n, af_audio_clip *out);

#ifdef __cplusplus
}
#endif
#endif
