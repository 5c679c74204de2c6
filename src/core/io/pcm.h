/* pcm.h — uncompressed audio samples as audio_common (GStreamer) carries
 * them: interleaved frames of one sample per channel, in one of the raw
 * formats below, named as GStreamer names them (audio_common_msgs/AudioInfo
 * sample_format). One channel is taken out and scaled to full scale 1:
 * integers divided by 2^(bits - 1) (U8 offset by 128 first), floats as they
 * are; then multiplied by a gain (the microphone's value at full scale).
 *
 * Pure functions, no allocation; any alignment of the bytes. */
#ifndef AF_PCM_H
#define AF_PCM_H

#include <stddef.h>
#include <stdint.h>

#include "status.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum {
  AF_PCM_U8 = 0,
  AF_PCM_S8,
  AF_PCM_S16LE,
  AF_PCM_S16BE,
  AF_PCM_S24LE, /* 3 bytes per sample, packed */
  AF_PCM_S24BE,
  AF_PCM_S24_32LE, /* 24 bits in the low 3 bytes of 4 */
  AF_PCM_S32LE,
  AF_PCM_S32BE,
  AF_PCM_F32LE,
  AF_PCM_F32BE,
  AF_PCM_F64LE,
  AF_PCM_F64BE,
  AF_PCM_FORMAT_COUNT
} af_pcm_format;

/* AF_OK and *out for a GStreamer format name ("S16LE", ...); AF_EINVAL. */
af_status af_pcm_format_parse(const char *name, af_pcm_format *out);
/* The name of f; "?" when f is not a format. */
const char *af_pcm_format_name(af_pcm_format f);
/* "U8, S8, S16LE, ..." (every format, for messages). */
const char *af_pcm_format_list(void);
/* Bytes per sample of f (1-8); 0 when f is not a format. */
size_t af_pcm_sample_bytes(af_pcm_format f);

/* Channel `channel` of the frames [first_frame, first_frame + n) of the
 * interleaved bytes, channels per frame, into out[0..n), at full scale 1
 * times gain. The caller checks that the bytes hold those frames and that
 * channel < channels (af_pcm_frames). */
void af_pcm_decode(af_pcm_format f, unsigned channels, unsigned channel, const uint8_t *bytes,
                   size_t first_frame, size_t n, double gain, float *out);

/* Whole frames in n_bytes; AF_EINVAL (and *frames the whole ones) when
 * n_bytes is not a multiple of the frame size, or for channels 0 or a bad f. */
af_status af_pcm_frames(af_pcm_format f, unsigned channels, size_t n_bytes, size_t *frames);

#ifdef __cplusplus
}
#endif
#endif
