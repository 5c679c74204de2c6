/* test_wav.c — RIFF/WAVE headers and samples (wav.h) against byte arrays
 * built here after Microsoft's RIFF/WAVE layout: two files written out byte
 * by byte, then variations assembled field by field (every accepted format,
 * the extensible subformats, chunks before the data, odd padding) and every
 * lying or unsupported header; what a file's first bytes say it is. */
#include <math.h>
#include <stdint.h>
#include <string.h>

#include "af_test.h"
#include "wav.h"

#define ERR 256

/* A 16-bit mono PCM file at 8000 Hz with four samples: 0, 0.5, -1, max. */
static const uint8_t pcm16[] = {
    'R',  'I',  'F',  'F', 44, 0, 0,  0, 'W',  'A',  'V',  'E', /* 8 + 36 + 8 bytes */
    'f',  'm',  't',  ' ', 16, 0, 0,  0, 1,    0,    1,    0,
    0x40, 0x1F, 0,    0,                 /* PCM, 1 ch, 8000 Hz */
    0x80, 0x3E, 0,    0,   2,  0, 16, 0, /* 16000 B/s, align 2, 16 bit */
    'd',  'a',  't',  'a', 8,  0, 0,  0, 0x00, 0x00, 0x00, 0x40,
    0x00, 0x80, 0xFF, 0x7F};

/* 8-bit unsigned stereo at 11025 Hz, a LIST chunk of odd size (padded)
 * before the data: frames (128, 255), (0, 64). */
static const uint8_t u8_list[] = {
    'R', 'I', 'F', 'F', 52,  0,   0,   0,   'W',  'A',  'V', 'E', 'f',  'm',  't', ' ',
    16,  0,   0,   0,   1,   0,   2,   0,   0x11, 0x2B, 0,   0,   0x22, 0x56, 0,   0,
    2,   0,   8,   0,   'L', 'I', 'S', 'T', 3,    0,    0,   0,   'a',  'b',  'c', 0, /* pad */
    'd', 'a', 't', 'a', 4,   0,   0,   0,   128,  255,  0,   64};

/* ---- a builder for the variations ---------------------------------------- */

typedef struct {
  uint8_t b[512];
  size_t n;
} buf;

static void put(buf *w, const void *p, size_t n)
{
  memcpy(w->b + w->n, p, n);
  w->n += n;
}
static void u16(buf *w, uint32_t v)
{
  uint8_t b[2] = {(uint8_t)v, (uint8_t)(v >> 8)};
  put(w, b, 2);
}
static void u32(buf *w, uint32_t v)
{
  uint8_t b[4] = {(uint8_t)v, (uint8_t)(v >> 8), (uint8_t)(v >> 16), (uint8_t)(v >> 24)};
  put(w, b, 4);
}

typedef struct {
  uint32_t tag, channels, rate, bits, sub, valid; /* sub: extensible subformat, 0 = none */
  int32_t align_delta, byte_rate_delta;           /* lies in the fmt chunk */
} fmt_spec;

static void fmt(buf *w, const fmt_spec *f)
{
  uint32_t align = f->channels * f->bits / 8 + (uint32_t)f->align_delta;
  put(w, "fmt ", 4);
  u32(w, f->sub ? 40 : 16);
  u16(w, f->sub ? 0xFFFE : f->tag);
  u16(w, f->channels);
  u32(w, f->rate);
  u32(w, f->rate * align + (uint32_t)f->byte_rate_delta);
  u16(w, align);
  u16(w, f->bits);
  if (f->sub) {
    static const uint8_t tail[14] = {0, 0, 0, 0, 0x10, 0, 0x80, 0, 0, 0xAA, 0, 0x38, 0x9B, 0x71};
    u16(w, 22);
    u16(w, f->valid ? f->valid : f->bits);
    u32(w, 0); /* channel mask */
    u16(w, f->sub);
    put(w, tail, sizeof tail);
  }
}

/* RIFF + fmt + data of n_data bytes (payload p); riff_delta lies in the RIFF size. */
static void wav(buf *w, const fmt_spec *f, const uint8_t *p, uint32_t n_data, int32_t riff_delta)
{
  buf body = {{0}, 0};
  put(&body, "WAVE", 4);
  fmt(&body, f);
  put(&body, "data", 4);
  u32(&body, n_data);
  put(&body, p, n_data);
  w->n = 0;
  put(w, "RIFF", 4);
  u32(w, (uint32_t)body.n + (uint32_t)riff_delta);
  put(w, body.b, body.n);
}

/* ---- tests ------------------------------------------------------------------ */

static void test_pcm16(void)
{
  af_wav_info w;
  char err[ERR] = "";
  AF_CHECK(af_wav_parse(pcm16, sizeof pcm16, sizeof pcm16, &w, err, sizeof err) == AF_OK);
  AF_CHECK(w.format == AF_PCM_S16LE && w.format_tag == 1 && w.bits == 16);
  AF_CHECK(w.channels == 1 && w.sample_rate_hz == 8000 && w.frame_bytes == 2);
  AF_CHECK(w.data_offset == 44 && w.frames == 4);
  float x[4];
  af_wav_decode(&w, pcm16 + w.data_offset, 4, 0, 2.0, x); /* gain 2 */
  AF_CHECK_ABS(x[0], 0.0, 0.0);
  AF_CHECK_ABS(x[1], 1.0, 0.0);
  AF_CHECK_ABS(x[2], -2.0, 0.0);
  AF_CHECK_ABS(x[3], 2.0 * 32767.0 / 32768.0, 1e-6);
}

static void test_u8_list(void)
{
  af_wav_info w;
  char err[ERR] = "";
  AF_CHECK(af_wav_parse(u8_list, sizeof u8_list, sizeof u8_list, &w, err, sizeof err) == AF_OK);
  AF_CHECK(w.format == AF_PCM_U8 && w.channels == 2 && w.sample_rate_hz == 11025);
  AF_CHECK(w.data_offset == 56 && w.frames == 2);
  float x[2];
  af_wav_decode(&w, u8_list + w.data_offset, 2, 1, 1.0, x); /* the second channel */
  AF_CHECK_ABS(x[0], 127.0 / 128.0, 1e-7);
  AF_CHECK_ABS(x[1], -0.5, 0.0);
  af_wav_decode(&w, u8_list + w.data_offset, 2, 0, 1.0, x);
  AF_CHECK_ABS(x[0], 0.0, 0.0);
  AF_CHECK_ABS(x[1], -1.0, 0.0);
}

/* Every accepted format: -0.25 in the second of two channels. */
static void test_formats(void)
{
  const struct {
    fmt_spec f;
    af_pcm_format want;
    uint8_t sample[8]; /* -0.25 in the format */
  } cases[] = {
      {{1, 2, 48000, 24, 0, 0, 0, 0}, AF_PCM_S24LE, {0x00, 0x00, 0xE0}},
      {{1, 2, 48000, 32, 0, 0, 0, 0}, AF_PCM_S32LE, {0x00, 0x00, 0x00, 0xE0}},
      {{3, 2, 48000, 32, 0, 0, 0, 0}, AF_PCM_F32LE, {0x00, 0x00, 0x80, 0xBE}},
      {{3, 2, 48000, 64, 0, 0, 0, 0}, AF_PCM_F64LE, {0, 0, 0, 0, 0, 0, 0xD0, 0xBF}},
      {{0, 2, 48000, 32, 3, 0, 0, 0}, AF_PCM_F32LE, {0x00, 0x00, 0x80, 0xBE}},
      {{0, 2, 48000, 16, 1, 0, 0, 0}, AF_PCM_S16LE, {0x00, 0xE0}},
      /* 24 valid bits left-justified in 32: decoded as the container */
      {{0, 2, 48000, 32, 1, 24, 0, 0}, AF_PCM_S32LE, {0x00, 0x00, 0x00, 0xE0}},
  };
  for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
    const size_t sb = cases[k].f.bits / 8;
    uint8_t frame[16] = {0};
    memcpy(frame + sb, cases[k].sample, sb);
    buf b;
    wav(&b, &cases[k].f, frame, (uint32_t)(2 * sb), 0);
    af_wav_info w;
    char err[ERR] = "";
    AF_CHECK(af_wav_parse(b.b, b.n, b.n, &w, err, sizeof err) == AF_OK);
    AF_CHECK(w.format == cases[k].want && w.frames == 1 && w.channels == 2);
    float x = 1.0f;
    af_wav_decode(&w, b.b + w.data_offset, 1, 1, 8.0, &x);
    AF_CHECK_ABS(x, -2.0, 0.0);
    if (err[0])
      fprintf(stderr, "case %zu: %s\n", k, err);
  }
}

/* The samples need not be in the head: only the headers before them. */
static void test_head_only(void)
{
  af_wav_info w;
  char err[ERR] = "";
  AF_CHECK(af_wav_parse(pcm16, 44, sizeof pcm16, &w, err, sizeof err) == AF_OK && w.frames == 4);
  /* a head that ends before the data chunk's header */
  AF_CHECK(af_wav_parse(pcm16, 40, sizeof pcm16, &w, err, sizeof err) == AF_EINVAL);
  AF_CHECK(strstr(err, "no 'data' chunk in its first MiB") != NULL);
}

/* expect(bytes, n, file_bytes, words): refused with a line holding words. */
static void expect(const uint8_t *b, size_t n, uint64_t file_bytes, const char *words)
{
  af_wav_info w;
  char err[ERR] = "";
  af_status s = af_wav_parse(b, n, file_bytes, &w, err, sizeof err);
  AF_CHECK(s == AF_EINVAL);
  AF_CHECK(strstr(err, words) != NULL && strchr(err, '\n') == NULL);
  if (!strstr(err, words))
    fprintf(stderr, "  wanted '%s', got '%s'\n", words, err);
}

static void test_refused(void)
{
  const uint8_t z[16] = {0};
  const fmt_spec mono16 = {1, 1, 8000, 16, 0, 0, 0, 0};
  buf b;
  /* sizes that lie */
  expect(pcm16, sizeof pcm16 - 1, sizeof pcm16 - 1, "RIFF size says 52 bytes, the file has 51");
  wav(&b, &mono16, z, 4, 0);
  b.b[40] = 200; /* the data chunk claims 200 bytes */
  expect(b.b, b.n, b.n, "chunk 'data' at byte 36 claims 200 bytes, past the RIFF's end at 48");
  wav(&b, &mono16, z, 4, 0);
  b.b[16] = 255; /* the fmt chunk claims 255 bytes */
  expect(b.b, b.n, b.n, "chunk 'fmt ' at byte 12 claims 255 bytes");
  const fmt_spec stereo16 = {1, 2, 8000, 16, 0, 0, 0, 0};
  wav(&b, &stereo16, z, 6, 0);
  expect(b.b, b.n, b.n, "'data' chunk of 6 bytes is not a whole number of 4-byte frames");
  const fmt_spec lie_align = {1, 1, 8000, 16, 0, 0, 2, 0};
  wav(&b, &lie_align, z, 4, 0);
  expect(b.b, b.n, b.n, "block align 4 bytes, but 1 channels of 16 bits make 2");
  const fmt_spec lie_rate = {1, 1, 8000, 16, 0, 0, 0, 1};
  wav(&b, &lie_rate, z, 4, 0);
  expect(b.b, b.n, b.n, "byte rate 16001, but 8000 Hz of 2-byte frames make 16000");
  /* formats */
  const fmt_spec tag55 = {0x55, 1, 8000, 16, 0, 0, 0, 0};
  wav(&b, &tag55, z, 4, 0);
  expect(b.b, b.n, b.n, "format tag 0x0055 (MPEG layer 3)");
  const fmt_spec pcm12 = {1, 1, 8000, 12, 0, 0, 0, 0};
  wav(&b, &pcm12, z, 4, 0);
  expect(b.b, b.n, b.n, "PCM of 12 bits per sample");
  const fmt_spec float16 = {3, 1, 8000, 16, 0, 0, 0, 0};
  wav(&b, &float16, z, 4, 0);
  expect(b.b, b.n, b.n, "IEEE float of 16 bits per sample");
  const fmt_spec ext_alaw = {0, 1, 8000, 16, 6, 0, 0, 0};
  wav(&b, &ext_alaw, z, 4, 0);
  expect(b.b, b.n, b.n, "extensible subformat is not PCM or IEEE float");
  const fmt_spec ext_valid = {0, 1, 8000, 16, 1, 20, 0, 0};
  wav(&b, &ext_valid, z, 4, 0);
  expect(b.b, b.n, b.n, "20 valid bits in a 16-bit sample");
  const fmt_spec none = {1, 0, 8000, 16, 0, 0, 0, 0};
  wav(&b, &none, z, 4, 0);
  expect(b.b, b.n, b.n, "0 channels at 8000 Hz");
  const fmt_spec still = {1, 1, 0, 16, 0, 0, 0, 0};
  wav(&b, &still, z, 4, 0);
  expect(b.b, b.n, b.n, "1 channels at 0 Hz");
  /* structure */
  expect(pcm16, 11, 11, "not a RIFF/WAVE file");
  uint8_t order[sizeof pcm16]; /* data chunk before the fmt chunk */
  memcpy(order, pcm16, 12);
  memcpy(order + 12, pcm16 + 36, 16);
  memcpy(order + 28, pcm16 + 12, 24);
  expect(order, sizeof order, sizeof order, "'data' chunk before its 'fmt ' chunk");
  expect(pcm16, 36, 36, "RIFF size says 52 bytes"); /* cut after fmt: RIFF lies */
  uint8_t nodata[36];
  memcpy(nodata, pcm16, 36);
  nodata[4] = 28;
  expect(nodata, 36, 36, "has no 'data' chunk");
  uint8_t twice[60];
  memcpy(twice, pcm16, 36);
  memcpy(twice + 36, pcm16 + 12, 24);
  twice[4] = 52;
  expect(twice, 60, 60, "'fmt ' chunk given twice");
  uint8_t short_fmt[] = {'R', 'I', 'F', 'F', 16, 0, 0, 0, 'W', 'A', 'V', 'E',
                         'f', 'm', 't', ' ', 4,  0, 0, 0, 1,   0,   1,   0};
  expect(short_fmt, sizeof short_fmt, sizeof short_fmt, "'fmt ' chunk of 4 bytes");
}

static void test_identify(void)
{
  const char *what = NULL;
  AF_CHECK(af_wav_identify(pcm16, sizeof pcm16, &what) == AF_WAV_KIND_WAVE && what[0] == '\0');
  const uint8_t avi[12] = {'R', 'I', 'F', 'F', 4, 0, 0, 0, 'A', 'V', 'I', ' '};
  AF_CHECK(af_wav_identify(avi, sizeof avi, &what) == AF_WAV_KIND_OTHER &&
           strstr(what, "not WAVE"));
  const uint8_t id3[12] = {'I', 'D', '3', 4, 0, 0, 0, 0, 0, 10, 0, 0};
  AF_CHECK(af_wav_identify(id3, sizeof id3, &what) == AF_WAV_KIND_OTHER && strstr(what, "ID3"));
  const uint8_t flac[8] = {'f', 'L', 'a', 'C', 0, 0, 0, 34};
  AF_CHECK(af_wav_identify(flac, sizeof flac, &what) == AF_WAV_KIND_OTHER && strstr(what, "FLAC"));
  /* MPEG-1 layer III, 128 kbit/s, 44.1 kHz, no padding: 417-byte frames */
  static uint8_t mp3[2 * 417];
  memset(mp3, 0, sizeof mp3);
  const uint8_t hdr[4] = {0xFF, 0xFB, 0x90, 0x64};
  memcpy(mp3, hdr, 4);
  memcpy(mp3 + 417, hdr, 4);
  AF_CHECK(af_wav_identify(mp3, sizeof mp3, &what) == AF_WAV_KIND_OTHER && strstr(what, "MPEG"));
  /* one sync without a second frame where the first says: raw samples */
  mp3[417] = 0x12;
  AF_CHECK(af_wav_identify(mp3, sizeof mp3, &what) == AF_WAV_KIND_NONE);
  /* MPEG-2 layer III, 64 kbit/s, 22.05 kHz, padded: 72 * 64000 / 22050 + 1 = 209 bytes */
  const uint8_t hdr2[4] = {0xFF, 0xF3, 0x82, 0x64};
  memset(mp3, 0, sizeof mp3);
  memcpy(mp3, hdr2, 4);
  memcpy(mp3 + 209, hdr2, 4);
  AF_CHECK(af_wav_identify(mp3, sizeof mp3, &what) == AF_WAV_KIND_OTHER);
  memcpy(mp3 + 208, hdr2, 4); /* one byte early: not where the length says */
  mp3[212] = 0;
  AF_CHECK(af_wav_identify(mp3, sizeof mp3, &what) == AF_WAV_KIND_NONE);
  const float raw[4] = {0.25f, -1.5f, 3.0f, 1e-3f};
  AF_CHECK(af_wav_identify((const uint8_t *)raw, sizeof raw, &what) == AF_WAV_KIND_NONE);
  AF_CHECK(af_wav_identify((const uint8_t *)raw, 0, &what) == AF_WAV_KIND_NONE);
}

int main(void)
{
  test_pcm16();
  test_u8_list();
  test_formats();
  test_head_only();
  test_refused();
  test_identify();
  return af_test_summary("test_wav");
}
