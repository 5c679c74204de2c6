/* test_pcm.c — raw audio samples (pcm.h): every format encoded here from
 * known values (a tone and the extremes) and decoded back, the channel of a
 * stereo stream, the gain, odd byte alignment, frame counting. */
#include <math.h>
#include <stdint.h>
#include <string.h>

#include "af_test.h"
#include "pcm.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

#define N 64

/* x in [-1, 1) as format f at p (the encoder the decoder is checked against). */
static void encode(af_pcm_format f, double x, uint8_t *p)
{
  size_t n = af_pcm_sample_bytes(f);
  int big = f == AF_PCM_S16BE || f == AF_PCM_S24BE || f == AF_PCM_S32BE || f == AF_PCM_F32BE ||
            f == AF_PCM_F64BE;
  uint64_t u = 0;
  switch (f) {
  case AF_PCM_U8: u = (uint64_t)(int64_t)lround(x * 128.0 + 128.0); break;
  case AF_PCM_S8: u = (uint64_t)(int64_t)lround(x * 128.0); break;
  case AF_PCM_S16LE:
  case AF_PCM_S16BE: u = (uint64_t)(int64_t)lround(x * 32768.0); break;
  case AF_PCM_S24LE:
  case AF_PCM_S24BE:
  case AF_PCM_S24_32LE: u = (uint64_t)(int64_t)lround(x * 8388608.0); break;
  case AF_PCM_S32LE:
  case AF_PCM_S32BE: u = (uint64_t)(int64_t)llround(x * 2147483648.0); break;
  case AF_PCM_F32LE:
  case AF_PCM_F32BE: {
    float v = (float)x;
    uint32_t w;
    memcpy(&w, &v, 4);
    u = w;
    break;
  }
  default: memcpy(&u, &x, 8); break;
  }
  if (f == AF_PCM_S24_32LE)
    u &= 0xffffff; /* the top byte: padding */
  for (size_t k = 0; k < n; k++)
    p[big ? n - 1 - k : k] = (uint8_t)(u >> (8 * k));
}

static double step_of(af_pcm_format f)
{
  switch (af_pcm_sample_bytes(f)) {
  case 1: return 1.0 / 128.0;
  case 2: return 1.0 / 32768.0;
  case 3: return 1.0 / 8388608.0;
  default:
    return f == AF_PCM_S24_32LE                     ? 1.0 / 8388608.0
           : f == AF_PCM_S32LE || f == AF_PCM_S32BE ? 1.0 / 2147483648.0
                                                    : 1e-7;
  }
}

static void test_formats(void)
{
  uint8_t bytes[1 + 2 * N * 8];
  float out[N];
  for (int k = 0; k < AF_PCM_FORMAT_COUNT; k++) {
    af_pcm_format f = (af_pcm_format)k, back;
    AF_CHECK_STATUS(af_pcm_format_parse(af_pcm_format_name(f), &back), AF_OK);
    AF_CHECK(back == f);
    size_t sb = af_pcm_sample_bytes(f);
    /* Stereo, starting at an odd address: channel 0 a tone, channel 1 its negative. */
    uint8_t *p = bytes + 1;
    double x[N];
    for (int i = 0; i < N; i++) {
      x[i] = i == 0 ? -1.0 : 0.9 * sin(2.0 * M_PI * 1000.0 * i / 48000.0);
      encode(f, x[i], p + (2 * i) * sb);
      encode(f, -x[i] * 0.5, p + (2 * i + 1) * sb);
    }
    double tol = step_of(f) * 0.51; /* [full scale]: half an LSB, rounding */
    af_pcm_decode(f, 2, 0, p, 0, N, 1.0, out);
    for (int i = 0; i < N; i++)
      AF_CHECK_ABS(out[i], x[i], tol + 1e-7);
    af_pcm_decode(f, 2, 1, p, 10, N - 10, 2.0, out); /* from frame 10, gain 2 */
    for (int i = 10; i < N; i++)
      AF_CHECK_ABS(out[i - 10], -x[i], 2.0 * tol + 1e-6);
    size_t frames;
    AF_CHECK_STATUS(af_pcm_frames(f, 2, 2 * N * sb, &frames), AF_OK);
    AF_CHECK(frames == N);
    if (sb > 1) {
      AF_CHECK_STATUS(af_pcm_frames(f, 2, 2 * N * sb - 1, &frames), AF_EINVAL);
      AF_CHECK(frames == N - 1);
    }
  }
}

static void test_known_bytes(void)
{
  float v;
  const uint8_t s16[] = {0x00, 0x80}, s16be[] = {0x40, 0x00}, u8[] = {0x80, 0xff};
  af_pcm_decode(AF_PCM_S16LE, 1, 0, s16, 0, 1, 1.0, &v);
  AF_CHECK(v == -1.0f);
  af_pcm_decode(AF_PCM_S16BE, 1, 0, s16be, 0, 1, 1.0, &v);
  AF_CHECK(v == 0.5f);
  af_pcm_decode(AF_PCM_U8, 1, 0, u8, 0, 1, 1.0, &v);
  AF_CHECK(v == 0.0f);
  af_pcm_decode(AF_PCM_U8, 1, 0, u8, 1, 1, 1.0, &v);
  AF_CHECK(v == 127.0f / 128.0f);
  const uint8_t s24[] = {0xff, 0xff, 0x7f}, s24_32[] = {0x00, 0x00, 0x80, 0x55};
  af_pcm_decode(AF_PCM_S24LE, 1, 0, s24, 0, 1, 1.0, &v);
  AF_CHECK(v == (float)(8388607.0 / 8388608.0));
  af_pcm_decode(AF_PCM_S24_32LE, 1, 0, s24_32, 0, 1, 1.0, &v); /* the padding byte ignored */
  AF_CHECK(v == -1.0f);
  const uint8_t f32[] = {0x00, 0x00, 0x20, 0x41}; /* 10.0f: floats are not clipped */
  af_pcm_decode(AF_PCM_F32LE, 1, 0, f32, 0, 1, 1.0, &v);
  AF_CHECK(v == 10.0f);
}

static void test_errors(void)
{
  af_pcm_format f;
  size_t frames = 99;
  AF_CHECK_STATUS(af_pcm_format_parse("s16le", &f), AF_EINVAL); /* GStreamer's case */
  AF_CHECK_STATUS(af_pcm_format_parse("MP3", &f), AF_EINVAL);
  AF_CHECK_STATUS(af_pcm_format_parse(NULL, &f), AF_EINVAL);
  AF_CHECK_STATUS(af_pcm_frames(AF_PCM_S16LE, 0, 4, &frames), AF_EINVAL);
  AF_CHECK(frames == 0);
  AF_CHECK(af_pcm_sample_bytes(AF_PCM_FORMAT_COUNT) == 0);
  AF_CHECK(strcmp(af_pcm_format_name(AF_PCM_FORMAT_COUNT), "?") == 0);
  AF_CHECK(strstr(af_pcm_format_list(), "S24_32LE") != NULL);
}

int main(void)
{
  test_formats();
  test_known_bytes();
  test_errors();
  return af_test_summary("test_pcm");
}
