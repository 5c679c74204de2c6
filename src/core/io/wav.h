/* wav.h — RIFF/WAVE recordings: what the first bytes of a file are, the
 * header of a WAVE file checked against the file's real size, and its
 * samples through pcm.h (no second decoder).
 *
 * Accepted: RIFF/WAVE with a 'fmt ' chunk before its 'data' chunk, format
 * tag 1 (PCM: 8-bit unsigned, 16-, 24-, 32-bit signed), 3 (IEEE float: 32
 * or 64 bit), or 0xFFFE (WAVE_FORMAT_EXTENSIBLE) whose subformat GUID is
 * PCM or IEEE float with those container sizes (valid bits at most the
 * container's: the samples are left-justified, so they decode as the
 * container). Any channel count >= 1, any rate >= 1 Hz. Little-endian.
 *
 * Refused, with one line saying what is wrong: another container (RIFX,
 * RF64, a RIFF that is not WAVE), another format tag or bit depth, a 'fmt '
 * chunk whose block align or byte rate disagree with its channels, bits and
 * rate, and a header whose sizes lie: the RIFF size or a chunk's size
 * beyond the end of the file, a 'data' chunk that is not a whole number of
 * frames, no 'fmt ' or 'data' chunk within the part of the file given.
 * Bytes after the RIFF's end are ignored (some recorders pad the file).
 *
 * Pure functions, no allocation, no I/O: the caller reads the head of the
 * file (AF_WAV_HEAD_MAX bytes at most) and its data. */
#ifndef AF_WAV_H
#define AF_WAV_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "pcm.h"
#include "status.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The chunks before 'data' ('fmt ', LIST, fact, ...) must lie in the first
 * MiB of the file: the head a reader passes to af_wav_parse. */
#define AF_WAV_HEAD_MAX ((size_t)1 << 20)

/* What the first bytes of a file say it is. */
typedef enum {
  AF_WAV_KIND_NONE = 0, /* no known signature: raw samples, for the caller */
  AF_WAV_KIND_WAVE,     /* "RIFF" .... "WAVE" */
  AF_WAV_KIND_OTHER     /* a container or compressed format that is not WAVE */
} af_wav_kind;

/* The kind of a file from its first n bytes (all of them when the file is
 * shorter than AF_WAV_HEAD_MAX); for AF_WAV_KIND_OTHER *what names it
 * ("MP3 (ID3 tag)", "FLAC", "RIFF AVI  (not WAVE)", ...), else "". An MPEG
 * audio frame sync counts only when a second frame header follows where the
 * first frame's length says (raw float32 samples can begin with 0xFFFx). */
af_wav_kind af_wav_identify(const uint8_t *head, size_t n, const char **what);

typedef struct {
  af_pcm_format format;    /* the samples' pcm.h format */
  unsigned format_tag;     /* 1 or 3 (the extensible subformat's) */
  unsigned bits;           /* container bits per sample: 8, 16, 24, 32, 64 */
  unsigned channels;       /* >= 1 */
  uint32_t sample_rate_hz; /* frames per second, >= 1 */
  uint64_t data_offset;    /* first byte of the first frame, from the file start */
  uint64_t frames;         /* whole frames in the 'data' chunk */
  size_t frame_bytes;      /* channels * bits / 8 */
  unsigned valid_bits;     /* significant bits of an integer sample (extensible), else bits */
  /* The RIFF size was 0 or 0xFFFFFFFF, as recorders leave a stream they
   * never finalized: the chunks were read to the end of the file, and a
   * 'data' chunk of size 0, 0xFFFFFFFF or past the end holds the whole
   * frames up to it. */
  bool streamed;
} af_wav_info;

/* Parses the header in head[0..n) of a file of file_bytes bytes (n <=
 * file_bytes; the 'data' chunk's samples need not be in head). AF_OK and
 * *out; AF_EINVAL with one line in err (without the file's name: the caller
 * adds it) when the file is not an accepted WAVE or its sizes lie. */
af_status af_wav_parse(const uint8_t *head, size_t n, uint64_t file_bytes, af_wav_info *out,
                       char *err, size_t len);

/* Fewer valid bits than the container's (extensible integer PCM): the spec
 * puts them at the top (left-justified, the low bits zero). Some writers put
 * them at the bottom (right-justified), the top bits only the sign's
 * extension: read as the spec says, those samples come out 2^(bits - valid)
 * times too small. af_wav_justify_scan looks at every sample of n frames
 * (call it on each block read, from a zeroed af_wav_justify); then
 * af_wav_right_justified gives the factor that corrects them (256 for 24
 * valid bits in 32), or 1 when the samples are as the spec says, cannot be
 * told (all zero) or fit neither. */
typedef struct {
  bool low_used;    /* a sample with a low (unused by the spec) bit set */
  bool top_not_ext; /* a sample whose top bits are not the sign's extension */
} af_wav_justify;

void af_wav_justify_scan(const af_wav_info *w, const uint8_t *frames, size_t n, af_wav_justify *j);
double af_wav_right_justified(const af_wav_info *w, const af_wav_justify *j);

/* Channel `channel` (< w->channels) of n frames at frames, the bytes of
 * whole frames read from the data chunk, into out[0..n): integers at full
 * scale 1 (pcm.h), floats as they are, times gain. */
void af_wav_decode(const af_wav_info *w, const uint8_t *frames, size_t n, unsigned channel,
                   double gain, float *out);

#ifdef __cplusplus
}
#endif
#endif
