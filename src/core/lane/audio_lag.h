/* audio_lag.h — how late the audio's stamps run behind the force's, from the
 * strikes themselves.
 *
 * A strike is heard when it is struck: the acoustic path at rig distances is
 * under 1 ms (0.3 m at 343 m/s). So the sound's onset in the audio, by the
 * audio's stamps, minus the contact start, by the force's, is the offset of
 * the two clocks: a capture stack's device delay and buffering (ALSA's
 * 12-21 ms, more through a pipe, a driver stamping at publish time). Offsets
 * of 15-200 ms are normal; each strike measures one (af_audio_onset_find)
 * and the lane aligns its audio window by their median once it is stable
 * (af_audio_lag_push), so that the 0S2 is read from the ring, not from the
 * silence before it.
 *
 * The onset: audio in blocks of ~1 ms; the first block whose mean square
 * exceeds AF_AUDIO_LAG_RISE times the quietest of the AF_AUDIO_LAG_REF_BLOCKS
 * blocks before it, and at least AF_AUDIO_LAG_FLOOR of the loudest block's
 * (exact-zero silence has a reference of 0); then the first sample of that
 * block, or of the one before, above the reference RMS times
 * sqrt(AF_AUDIO_LAG_RISE) / 2. */
#ifndef AF_AUDIO_LAG_H
#define AF_AUDIO_LAG_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#define AF_AUDIO_LAG_BLOCK_S 0.001  /* block length [s] */
#define AF_AUDIO_LAG_REF_BLOCKS 10  /* the quiet reference before a block */
#define AF_AUDIO_LAG_RISE 100.0     /* 20 dB over that reference [-] */
#define AF_AUDIO_LAG_FLOOR 1e-3     /* and within 30 dB of the loudest block [-] */
#define AF_AUDIO_LAG_HISTORY 16     /* strikes the median is taken over */
#define AF_AUDIO_LAG_MIN 5          /* strikes before the median is judged */
#define AF_AUDIO_LAG_STABLE_S 0.001 /* stable: their median absolute deviation within this [s] */
#define AF_AUDIO_LAG_DEADBAND_S                                                                    \
  0.002                           /* a smaller median is not applied (the window's own             \
                                      tolerance: measure_audio_delay_s, the onset's) [s] */
#define AF_AUDIO_LAG_MOVE_S 0.005 /* a strike this far from a stable median: the lag moved [s] */
#define AF_AUDIO_LAG_MAX_BLOCKS                                                                    \
  2048 /* blocks searched at most: +-audio_lag_max_s (1 s at the                                   \
          most) and the reference, at 1 ms */

/* The first onset in x[0..n) (finite samples), block samples a block: its
 * sample index in *at. False when there is none (no block rises so, or n
 * holds fewer than the reference and one block). No allocation. */
bool af_audio_onset_find(const float *x, size_t n, size_t block, size_t *at);

typedef struct {
  double lag_s[AF_AUDIO_LAG_HISTORY]; /* the latest measured lags [s] */
  size_t n, next;
  uint64_t measured, moves; /* lags pushed; strikes off a stable median by AF_AUDIO_LAG_MOVE_S */
  double median_s, mad_s;   /* over the history; NaN until AF_AUDIO_LAG_MIN */
  bool stable;
  double applied_s; /* the lag the audio window is moved by: the stable median beyond the
                       dead band, held while the lags are not stable [s] */
} af_audio_lag;

/* No lag measured, none applied. */
void af_audio_lag_reset(af_audio_lag *g);

/* One strike's lag [s]: the median, its stability and the applied lag (only
 * when apply; else 0) updated. Returns whether the lag moved: the strike
 * lies AF_AUDIO_LAG_MOVE_S or more from a median that was stable. */
bool af_audio_lag_push(af_audio_lag *g, double lag_s, bool apply);

#ifdef __cplusplus
}
#endif
#endif
