/* recording.h — a recording on disk, read whole: a RIFF/WAVE file (its
 * rate, format and channels from its header, src/core/io/wav.h) or raw
 * little-endian float32 samples, as a DAQ or `sox -t f32` writes them (one
 * channel, the rate given by a flag). Read with a stated maximum size, so
 * that a wrong file cannot make a tool allocate what the machine cannot
 * hold; nothing is allocated from a size in a header before that size has
 * been checked against the file's real size. Used by `firmness_model
 * analyze` and capture_to_bag. */
#ifndef AF_RECORDING_H
#define AF_RECORDING_H

#include <stdbool.h>
#include <stddef.h>

#include "status.h"

#ifdef __cplusplus
extern "C" {
#endif

/* 2^27 samples (512 MiB; 45 min at 50 kHz): a longer recording is split;
 * the largest --max-samples. */
#define AF_RECORDING_MAX_SAMPLES_N 134217728 /* a plain literal, for the flag's range text */
#define AF_RECORDING_MAX_SAMPLES ((size_t)AF_RECORDING_MAX_SAMPLES_N)
/* The default --max-samples, per recording: 2^24 samples (64 MiB of float32;
 * 5.6 min at 50 kHz, 6.3 min at 44.1 kHz), so that two recordings and the
 * lane stay under the tools' 256 MiB peak RSS. Checked before allocating. */
#define AF_RECORDING_DEFAULT_MAX_SAMPLES ((size_t)1 << 24)
/* --force-channel / --audio-channel: 0-based, as the node's audio_channel;
 * a WAV header holds at most 65535 channels. */
#define AF_RECORDING_CHANNEL_MAX 65535
/* --force-scale / --audio-scale: the value [N, or the audio unit] of a
 * sample at digital full scale (integer PCM) or of a sample 1.0 (float WAV,
 * raw float32). The default leaves the samples as decoded: integer PCM at
 * +-1, floats as written. */
#define AF_RECORDING_SCALE_DEFAULT 1.0
#define AF_RECORDING_SCALE_MAX 1e6

typedef struct {
  float *x;
  size_t n;
  double quantum; /* integer PCM: the step between sample values, in the scaled unit
                     (scale / 2^(valid bits - 1)); 0 for float samples (none known) */
} af_recording;

/* How to read one input, with its flags' names for the messages. */
typedef struct {
  const char *rate_flag;    /* e.g. "--rate-force" */
  const char *channel_flag; /* e.g. "--force-channel" */
  double rate_hz;           /* the rate flag's value; 0 = not given */
  long channel;             /* the channel flag's value; -1 = not given (channel 0) */
  double scale;             /* AF_RECORDING_SCALE_DEFAULT unless a flag says */
  size_t max_samples; /* longer is refused before allocating; in [1, AF_RECORDING_MAX_SAMPLES] */
} af_recording_spec;

/* The spec of an input whose flags were not given (max_samples
 * AF_RECORDING_DEFAULT_MAX_SAMPLES). */
af_recording_spec af_recording_spec_default(const char *rate_flag, const char *channel_flag);

/* Reads path, a WAV or raw float32 (by its first bytes), into *out and its
 * rate into *rate_hz (the header's, or the flag's for raw). One line in err
 * naming the file: AF_EIO (cannot open or read), AF_EINVAL (another format
 * such as MP3, a WAV that is not accepted or whose sizes lie, raw float32
 * that is not whole samples or has no rate flag, a rate flag that disagrees
 * with the WAV header, a channel beyond the file's, not a regular file),
 * AF_ESIZE (over spec->max_samples: the line names --max-samples, the
 * length and the cap); *out is then empty. */
af_status af_recording_load(const char *path, const af_recording_spec *spec, af_recording *out,
                            double *rate_hz, char *err, size_t len);

void af_recording_destroy(af_recording *r); /* safe on an empty recording */

#ifdef __cplusplus
}
#endif
#endif
