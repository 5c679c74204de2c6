/* fuzz_wav.c — libFuzzer harness: the WAV reader (src/core/io/wav.c through
 * src/tools/recording.c, as `firmness_model analyze` and capture_to_bag read
 * a recording) on arbitrary file contents. The input's first byte chooses
 * the channel asked for (0..3) and whether a rate flag is given; the rest is
 * the file. Checked on every input:
 * - af_wav_parse on the head: a refusal is one line; an accepted header
 *   describes a 'data' chunk inside the file (data_offset + frames *
 *   frame_bytes <= file size), with frame_bytes = channels * bits / 8;
 * - af_recording_load: a refusal is one line naming the file, and leaves
 *   the recording empty; a WAVE read has the header's frames and rate;
 *   nothing above --max-samples is read (a small cap here, so that a header
 *   that claims more is refused, never allocated);
 * - no crash, hang, unbounded allocation or sanitizer report. */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fuzz_scratch.h"
#include "recording.h"
#include "wav.h"

/* The cap on samples read per input [samples]: above it the reader must
 * refuse before allocating. */
#define FUZZ_WAV_MAX_SAMPLES 65536

static void one_line(const char *err)
{
  if (err[0] == '\0' || strchr(err, '\n') != NULL)
    abort();
}

/* What the header parser alone says of the bytes. */
static void check_parse(const uint8_t *p, size_t n)
{
  af_wav_info w;
  char err[256] = "";
  const char *what = NULL;
  af_wav_kind kind = af_wav_identify(p, n, &what);
  if (what == NULL || (kind == AF_WAV_KIND_OTHER && what[0] == '\0'))
    abort();
  if (af_wav_parse(p, n < AF_WAV_HEAD_MAX ? n : AF_WAV_HEAD_MAX, n, &w, err, sizeof err) != AF_OK) {
    one_line(err);
    return;
  }
  if (w.channels < 1 || w.sample_rate_hz < 1 || w.frame_bytes != (size_t)w.channels * w.bits / 8)
    abort();
  if (w.data_offset > n || w.frames > (n - w.data_offset) / w.frame_bytes)
    abort();
  /* The first frames decode without reading past the data. */
  float out[64];
  size_t k = w.frames < 64 ? (size_t)w.frames : 64;
  af_wav_decode(&w, p + w.data_offset, k, w.channels - 1, 1.0, out);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
  const char *path = af_fuzz_scratch(0, "wav", "wav"); /* fuzz_scratch.h */
  if (size < 1)
    return 0;
  uint8_t head = data[0];
  data++;
  size--;
  check_parse(data, size);

  FILE *f = fopen(path, "wb");
  if (f == NULL)
    return 0;
  fwrite(data, 1, size, f);
  fclose(f);
  af_recording_spec spec = af_recording_spec_default("--rate-audio", "--audio-channel");
  spec.channel = (head & 3) == 0 ? -1 : (long)(head & 3);
  spec.rate_hz = (head & 4) ? 48000.0 : 0.0;
  spec.max_samples = FUZZ_WAV_MAX_SAMPLES;
  af_recording r = {0};
  double rate_hz = 0.0;
  char err[512] = "";
  af_status st = af_recording_load(path, &spec, &r, &rate_hz, err, sizeof err);
  if (st != AF_OK) {
    one_line(err);
    if (strstr(err, path) == NULL || r.x != NULL || r.n != 0)
      abort();
    return 0;
  }
  if (r.n > FUZZ_WAV_MAX_SAMPLES || !(rate_hz > 0.0))
    abort();
  af_wav_info w;
  char why[256];
  if (af_wav_identify(data, size, &(const char *){NULL}) == AF_WAV_KIND_WAVE &&
      af_wav_parse(data, size < AF_WAV_HEAD_MAX ? size : AF_WAV_HEAD_MAX, size, &w, why,
                   sizeof why) == AF_OK &&
      (r.n != w.frames || rate_hz != (double)w.sample_rate_hz))
    abort();
  af_recording_destroy(&r);
  return 0;
}
