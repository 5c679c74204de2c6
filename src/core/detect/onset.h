/* onset.h — strikes found in the microphone alone (tap-only mode):
 * a tap is a sudden rise of the audio's energy above the running noise floor.
 *
 *   audio ──> frames of frame_s: mean square e [unit^2]
 *         ──> floor: an exponential average of the frames that are not
 *             above the threshold, time constant floor_time_constant_s
 *             (the first AF_ONSET_WARMUP_FRAMES frames: their plain mean, no
 *             onset; af_onset_prime sets it from a whole recording instead)
 *         ──> onset when e >= floor x 10^(snr_db / 10) and e >= the mean of
 *             the frames 2..4 before x 10^(snr_db / 10) (a rise, not the swell
 *             of a ring already sounding: beats, a long ring-down, a crest of
 *             a low tail after a zero crossing; a new tap over the tail of the
 *             last one is a rise), and holdoff_s past the last
 *             onset (the hammer's bounce is no second tap): a line striking
 *             faster than 1 / holdoff_s loses strikes.
 *         ──> floor and frame energies bounded below by
 *             max(floor_rms, quantum)^2: exact zeros (a noise gate closed,
 *             padding) give a floor of 0 that any flicker would exceed by
 *             any SNR; below one step of the converter nothing is measured.
 *             A frame whose own variance is below that bound (digital
 *             silence) teaches the floor nothing, so a gate that reopens
 *             onto the room's noise is no rise.
 *         ──> energies about the resting level dc (the mean of the quiet
 *             frames), and the onset held holdoff_s as a candidate: a rise
 *             of snr_db over everything since replaces it (a gate opened
 *             onto noise, the tap comes after), and it is reported only when
 *             two frames after its own hold alternating energy above the
 *             threshold (a ring); a step of the level is no tap, the resting
 *             level moves to it. Each onset is reported holdoff_s after its
 *             sample; one in the last holdoff_s of a stream is not.
 * The onset sample is the first sample of the firing frame whose square
 * reaches the threshold (the frame's first sample when none does): at most one
 * frame after the true start, and at most one frame before it.
 *
 * What it does not tell: any sound as sudden and as loud as a tap (a click,
 * a neighbour's strike, a dropped fruit) is an onset; the mode
 * identification then finds no 0S2 and says so.
 *
 * Figures (test/core/test_onset.c, signals of the test's own generators, at
 * the table's defaults and 48 kHz): no false onset in 10 min of white or of
 * pink noise (pink: 17 at 9 dB, 2272 at 6 dB); every tap whose first
 * millisecond is 18 dB above the noise (its mean square over the noise
 * variance) found, its onset within 1 ms of the true start; 3 dB weaker, 193
 * of 200 (a tap split over two frames may stay below the threshold in both).
 * test/core/test_onset_silence.c: no onset in 10 s of exact zeros nor at a
 * DC step; one, at the tap, after 10 s of zeros, after a gate opening 20 ms
 * before it, and for 16-bit taps with and without dither.
 * Buffers: one frame's samples, made in af_onset_create; no allocation after
 * it (af_onset_prime, offline only, excepted). Not thread-safe. */
#ifndef AF_ONSET_H
#define AF_ONSET_H

#include <stddef.h>
#include <stdint.h>

#include "status.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Frames averaged plainly into the first floor before any onset may fire. */
#define AF_ONSET_WARMUP_FRAMES 16
/* The shortest frame [samples]: a mean square of fewer scatters too much. */
#define AF_ONSET_MIN_FRAME_SAMPLES 4

typedef struct {
  double sample_rate_hz;        /* audio rate [Hz], > 0 */
  double frame_s;               /* energy frame [s]: at least AF_ONSET_MIN_FRAME_SAMPLES */
  double snr_db;                /* minimum frame energy over the floor [dB], > 0 */
  double holdoff_s;             /* no onset this long after one [s], >= frame_s */
  double floor_time_constant_s; /* the floor's averaging time [s], >= frame_s */
  double floor_rms;             /* the noise floor's lower bound, RMS [unit] > 0 (onset_floor) */
  double quantum;               /* the input's quantization step [unit]: the floor is at least
                                   its square; 0 = unknown (float input) */
} af_onset_config;

/* The table's defaults (onset_* rows, audio_sample_rate_hz), quantum 0. */
af_onset_config af_onset_config_default(void);

typedef struct {
  uint64_t sample; /* stream index of the onset */
  double snr_db;   /* the firing frame's energy over the floor [dB] */
  double floor_ms; /* the noise floor then: mean square [unit^2] */
} af_onset_event;

typedef void af_onset_fn(const af_onset_event *ev, void *user);

typedef struct af_onset af_onset;

/* AF_EINVAL for a config outside its ranges (one field at a time: see
 * af_onset_config_check); AF_ENOMEM. */
af_status af_onset_create(const af_onset_config *cfg, af_onset **out);
void af_onset_destroy(af_onset *o); /* NULL-safe */
/* Forgets the floor and the hold-off (a restarted stream). */
void af_onset_reset(af_onset *o);
/* AF_OK, or AF_EINVAL with the field's name in *field (may be NULL). */
af_status af_onset_config_check(const af_onset_config *c, const char **field);

/* Offline: the floor from a whole recording x[0..n): the mean of the frame
 * energies at or below their median (a recording holds mostly noise, its
 * taps are the loud minority), so that a tap a few milliseconds after the
 * start of a triggered capture is found. Allocates a scratch (desk tools
 * only). AF_ENODATA when x holds fewer than AF_ONSET_WARMUP_FRAMES finite
 * frames; AF_EINVAL for NULL. */
af_status af_onset_prime(af_onset *o, const float *x, size_t n);

/* Feeds x[0..n) (stream indices first_sample..): fn per onset, in order.
 * Samples must follow on from the previous call (a jump in first_sample
 * starts a new frame); a non-finite sample drops its frame. AF_EINVAL for
 * NULL arguments (x may be NULL when n is 0). */
af_status af_onset_write(af_onset *o, uint64_t first_sample, const float *x, size_t n,
                         af_onset_fn *fn, void *user);

/* Onsets so far, and the current floor [unit^2] (NaN before the warm-up). */
uint64_t af_onset_count(const af_onset *o);
double af_onset_floor(const af_onset *o);

#ifdef __cplusplus
}
#endif
#endif
