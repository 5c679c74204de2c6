/* pcm.c — raw audio samples (see pcm.h). */
#include "pcm.h"

#include <string.h>

static const struct {
  const char *name;
  size_t bytes;
} formats[AF_PCM_FORMAT_COUNT] = {
    [AF_PCM_U8] = {"U8", 1},
    [AF_PCM_S8] = {"S8", 1},
    [AF_PCM_S16LE] = {"S16LE", 2},
    [AF_PCM_S16BE] = {"S16BE", 2},
    [AF_PCM_S24LE] = {"S24LE", 3},
    [AF_PCM_S24BE] = {"S24BE", 3},
    [AF_PCM_S24_32LE] = {"S24_32LE", 4},
    [AF_PCM_S32LE] = {"S32LE", 4},
    [AF_PCM_S32BE] = {"S32BE", 4},
    [AF_PCM_F32LE] = {"F32LE", 4},
    [AF_PCM_F32BE] = {"F32BE", 4},
    [AF_PCM_F64LE] = {"F64LE", 8},
    [AF_PCM_F64BE] = {"F64BE", 8},
};

static int valid(af_pcm_format f)
{
  return (int)f >= 0 && f < AF_PCM_FORMAT_COUNT;
}

af_status af_pcm_format_parse(const char *name, af_pcm_format *out)
{
  if (name == NULL || out == NULL)
    return AF_EINVAL;
  for (int k = 0; k < AF_PCM_FORMAT_COUNT; k++)
    if (strcmp(name, formats[k].name) == 0) {
      *out = (af_pcm_format)k;
      return AF_OK;
    }
  return AF_EINVAL;
}

const char *af_pcm_format_name(af_pcm_format f)
{
  return valid(f) ? formats[f].name : "?";
}

const char *af_pcm_format_list(void)
{
  return "U8, S8, S16LE, S16BE, S24LE, S24BE, S24_32LE, S32LE, S32BE, F32LE, F32BE, F64LE, F64BE";
}

size_t af_pcm_sample_bytes(af_pcm_format f)
{
  return valid(f) ? formats[f].bytes : 0;
}

af_status af_pcm_frames(af_pcm_format f, unsigned channels, size_t n_bytes, size_t *frames)
{
  size_t frame = af_pcm_sample_bytes(f) * channels;
  *frames = frame ? n_bytes / frame : 0;
  return frame != 0 && n_bytes % frame == 0 ? AF_OK : AF_EINVAL;
}

/* Unsigned integer of n bytes, little- or big-endian. */
static uint64_t unsigned_of(const uint8_t *p, size_t n, int big)
{
  uint64_t v = 0;
  for (size_t k = 0; k < n; k++)
    v |= (uint64_t)p[big ? n - 1 - k : k] << (8 * k);
  return v;
}

/* Two's complement of bits bits (the low bits of u) as a signed value. */
static int64_t signed_of(uint64_t u, unsigned bits)
{
  const uint64_t sign = (uint64_t)1 << (bits - 1);
  u &= (sign << 1) - 1;
  return (int64_t)(u ^ sign) - (int64_t)sign;
}

static double sample_at(af_pcm_format f, const uint8_t *p)
{
  switch (f) {
  case AF_PCM_U8: return ((double)p[0] - 128.0) / 128.0;
  case AF_PCM_S8: return (double)signed_of(p[0], 8) / 128.0;
  case AF_PCM_S16LE:
  case AF_PCM_S16BE: return (double)signed_of(unsigned_of(p, 2, f == AF_PCM_S16BE), 16) / 32768.0;
  case AF_PCM_S24LE:
  case AF_PCM_S24BE: return (double)signed_of(unsigned_of(p, 3, f == AF_PCM_S24BE), 24) / 8388608.0;
  case AF_PCM_S24_32LE: return (double)signed_of(unsigned_of(p, 4, 0), 24) / 8388608.0;
  case AF_PCM_S32LE:
  case AF_PCM_S32BE:
    return (double)signed_of(unsigned_of(p, 4, f == AF_PCM_S32BE), 32) / 2147483648.0;
  case AF_PCM_F32LE:
  case AF_PCM_F32BE: {
    uint32_t u = (uint32_t)unsigned_of(p, 4, f == AF_PCM_F32BE);
    float x;
    memcpy(&x, &u, sizeof x);
    return x;
  }
  case AF_PCM_F64LE:
  case AF_PCM_F64BE: {
    uint64_t u = unsigned_of(p, 8, f == AF_PCM_F64BE);
    double x;
    memcpy(&x, &u, sizeof x);
    return x;
  }
  case AF_PCM_FORMAT_COUNT: break;
  }
  return 0.0;
}

void af_pcm_decode(af_pcm_format f, unsigned channels, unsigned channel, const uint8_t *bytes,
                   size_t first_frame, size_t n, double gain, float *out)
{
  const size_t sb = af_pcm_sample_bytes(f), frame = sb * channels;
  const uint8_t *p = bytes + first_frame * frame + (size_t)channel * sb;
  for (size_t k = 0; k < n; k++, p += frame)
    out[k] = (float)(gain * sample_at(f, p));
}
