/* wav.c — RIFF/WAVE headers and samples (see wav.h). */
#include "wav.h"

#include <stdio.h>
#include <string.h>

static uint32_t le16(const uint8_t *p)
{
  return (uint32_t)p[0] | (uint32_t)p[1] << 8;
}

static uint32_t le32(const uint8_t *p)
{
  return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

/* ---- what a file is ---------------------------------------------------------- */

/* The length [bytes] of the MPEG audio frame whose header is h; 0 when h is
 * not a valid header (no sync, a reserved field, a free or bad bitrate). */
static uint32_t mpeg_frame_bytes(uint32_t h)
{
  static const uint16_t kbps[5][15] = {
      {0, 32, 64, 96, 128, 160, 192, 224, 256, 288, 320, 352, 384, 416, 448}, /* V1 L1 */
      {0, 32, 48, 56, 64, 80, 96, 112, 128, 160, 192, 224, 256, 320, 384},    /* V1 L2 */
      {0, 32, 40, 48, 56, 64, 80, 96, 112, 128, 160, 192, 224, 256, 320},     /* V1 L3 */
      {0, 32, 48, 56, 64, 80, 96, 112, 128, 144, 160, 176, 192, 224, 256},    /* V2 L1 */
      {0, 8, 16, 24, 32, 40, 48, 56, 64, 80, 96, 112, 128, 144, 160}};        /* V2 L2, L3 */
  static const uint32_t rate_v1_hz[3] = {44100, 48000, 32000};
  const unsigned version = (h >> 19) & 3, layer = (h >> 17) & 3; /* 3 = V1 / layer I */
  const unsigned rate_idx = (h >> 10) & 3, br_idx = (h >> 12) & 15, pad = (h >> 9) & 1;
  if ((h >> 21) != 0x7FF || version == 1 || layer == 0 || rate_idx == 3 || br_idx == 0 ||
      br_idx == 15)
    return 0;
  const unsigned lay = 4 - layer; /* 1, 2, 3 */
  const unsigned row = version == 3 ? lay - 1 : (lay == 1 ? 3 : 4);
  const uint32_t rate_hz = rate_v1_hz[rate_idx] >> (version == 3 ? 0 : version == 2 ? 1 : 2);
  const uint32_t bps = 1000u * kbps[row][br_idx];
  if (lay == 1)
    return (12 * bps / rate_hz + pad) * 4;
  return (lay == 3 && version != 3 ? 72 : 144) * bps / rate_hz + pad;
}

/* Two consecutive MPEG audio frame headers at the start of head. */
static int is_mpeg_audio(const uint8_t *head, size_t n)
{
  if (n < 4)
    return 0;
  const uint32_t first =
      (uint32_t)head[0] << 24 | (uint32_t)head[1] << 16 | (uint32_t)head[2] << 8 | head[3];
  const uint32_t len = mpeg_frame_bytes(first);
  if (len < 4 || (size_t)len + 4 > n)
    return 0;
  const uint8_t *p = head + len;
  const uint32_t second = (uint32_t)p[0] << 24 | (uint32_t)p[1] << 16 | (uint32_t)p[2] << 8 | p[3];
  /* same version, layer and rate */
  return mpeg_frame_bytes(second) != 0 && (first & 0xFFFE0C00u) == (second & 0xFFFE0C00u);
}

af_wav_kind af_wav_identify(const uint8_t *head, size_t n, const char **what)
{
  static const struct {
    const char *magic, *what;
  } other[] = {
      {"RIFX", "RIFX (big-endian RIFF, not supported)"},
      {"RF64", "RF64 (64-bit WAVE, not supported)"},
      {"BW64", "BW64 (64-bit WAVE, not supported)"},
      {"fLaC", "FLAC (compressed)"},
      {"OggS", "Ogg (compressed)"},
      {"FORM", "AIFF or another IFF file"},
      {".snd", "Sun/NeXT AU"},
      {"caff", "Core Audio (CAF)"},
  };
  *what = "";
  if (n >= 4 && memcmp(head, "RIFF", 4) == 0) {
    if (n >= 12 && memcmp(head + 8, "WAVE", 4) != 0) {
      *what = "a RIFF file that is not WAVE";
      return AF_WAV_KIND_OTHER;
    }
    return AF_WAV_KIND_WAVE; /* a short one is refused by af_wav_parse */
  }
  for (size_t k = 0; k < sizeof other / sizeof other[0]; k++)
    if (n >= 4 && memcmp(head, other[k].magic, 4) == 0) {
      *what = other[k].what;
      return AF_WAV_KIND_OTHER;
    }
  if (n >= 10 && memcmp(head, "ID3", 3) == 0 && head[3] < 0xFF && head[4] < 0xFF) {
    *what = "MP3 (ID3 tag)";
    return AF_WAV_KIND_OTHER;
  }
  if (is_mpeg_audio(head, n)) {
    *what = "MP3/MPEG audio (frame sync)";
    return AF_WAV_KIND_OTHER;
  }
  return AF_WAV_KIND_NONE;
}

/* ---- the header ---------------------------------------------------------------- */

static const uint8_t guid_tail[14] = {0x00, 0x00, 0x00, 0x00, 0x10, 0x00, 0x80,
                                      0x00, 0x00, 0xAA, 0x00, 0x38, 0x9B, 0x71};

static const char *tag_name(uint32_t tag)
{
  switch (tag) {
  case 0x0002: return " (MS ADPCM)";
  case 0x0006: return " (A-law)";
  case 0x0007: return " (mu-law)";
  case 0x0011: return " (IMA ADPCM)";
  case 0x0050: return " (MPEG)";
  case 0x0055: return " (MPEG layer 3)";
  default: return "";
  }
}

/* The pcm.h format of tag and container bits; false with a message. */
static int format_of(uint32_t tag, uint32_t bits, af_pcm_format *f, char *err, size_t len)
{
  if (tag == 1 && (bits == 8 || bits == 16 || bits == 24 || bits == 32)) {
    *f = bits == 8    ? AF_PCM_U8
         : bits == 16 ? AF_PCM_S16LE
         : bits == 24 ? AF_PCM_S24LE
                      : AF_PCM_S32LE;
    return 1;
  }
  if (tag == 3 && (bits == 32 || bits == 64)) {
    *f = bits == 32 ? AF_PCM_F32LE : AF_PCM_F64LE;
    return 1;
  }
  if (tag == 1)
    snprintf(err, len, "WAV PCM of %u bits per sample: accepted are 8, 16, 24 and 32", bits);
  else if (tag == 3)
    snprintf(err, len, "WAV IEEE float of %u bits per sample: accepted are 32 and 64", bits);
  else
    snprintf(err, len,
             "WAV format tag 0x%04X%s: accepted are PCM (1), IEEE float (3) and extensible "
             "(0xFFFE) of those",
             tag, tag_name(tag));
  return 0;
}

/* The 'fmt ' chunk's size bytes at p into w; false with a message. */
static int parse_fmt(const uint8_t *p, uint32_t size, af_wav_info *w, char *err, size_t len)
{
  if (size < 16) {
    snprintf(err, len, "WAV 'fmt ' chunk of %u bytes, shorter than the 16 of its fields", size);
    return 0;
  }
  uint32_t tag = le16(p), channels = le16(p + 2), rate = le32(p + 4), byte_rate = le32(p + 8);
  uint32_t align = le16(p + 12), bits = le16(p + 14);
  if (tag == 0xFFFE) {
    if (size < 40 || le16(p + 16) < 22) {
      snprintf(err, len, "WAV extensible 'fmt ' chunk of %u bytes, shorter than its 40", size);
      return 0;
    }
    uint32_t valid = le16(p + 18), sub = le16(p + 24);
    if (memcmp(p + 26, guid_tail, sizeof guid_tail) != 0 || (sub != 1 && sub != 3)) {
      snprintf(err, len, "WAV extensible subformat is not PCM or IEEE float");
      return 0;
    }
    if (valid == 0 || valid > bits) {
      snprintf(err, len, "WAV extensible: %u valid bits in a %u-bit sample", valid, bits);
      return 0;
    }
    w->valid_bits = sub == 1 ? valid : bits;
    tag = sub;
  }
  if (!format_of(tag, bits, &w->format, err, len))
    return 0;
  if (channels == 0 || rate == 0) {
    snprintf(err, len, "WAV header says %u channels at %u Hz", channels, rate);
    return 0;
  }
  if (align != channels * bits / 8) {
    snprintf(err, len, "WAV block align %u bytes, but %u channels of %u bits make %u", align,
             channels, bits, channels * bits / 8);
    return 0;
  }
  if ((uint64_t)byte_rate != (uint64_t)rate * align) {
    snprintf(err, len, "WAV byte rate %u, but %u Hz of %u-byte frames make %llu", byte_rate, rate,
             align, (unsigned long long)rate * align);
    return 0;
  }
  w->format_tag = tag;
  if (w->valid_bits == 0)
    w->valid_bits = bits;
  w->bits = bits;
  w->channels = channels;
  w->sample_rate_hz = rate;
  w->frame_bytes = align;
  return 1;
}

/* A chunk id for messages: its four bytes, '?' where not printable. */
static void chunk_name(const uint8_t *p, char name[5])
{
  for (int k = 0; k < 4; k++)
    name[k] = p[k] >= 0x20 && p[k] < 0x7F ? (char)p[k] : '?';
  name[4] = '\0';
}

af_status af_wav_parse(const uint8_t *head, size_t n, uint64_t file_bytes, af_wav_info *out,
                       char *err, size_t len)
{
  memset(out, 0, sizeof *out);
  if (n > file_bytes)
    n = (size_t)file_bytes;
  if (n < 12 || memcmp(head, "RIFF", 4) != 0 || memcmp(head + 8, "WAVE", 4) != 0) {
    snprintf(err, len, "not a RIFF/WAVE file (%llu bytes)", (unsigned long long)file_bytes);
    return AF_EINVAL;
  }
  const uint32_t riff_size = le32(head + 4);
  out->streamed = riff_size == 0 || riff_size == UINT32_MAX;
  const uint64_t riff_end = out->streamed ? file_bytes : 8 + (uint64_t)riff_size;
  if (riff_end > file_bytes) {
    snprintf(err, len, "WAV RIFF size says %llu bytes, the file has %llu",
             (unsigned long long)riff_end, (unsigned long long)file_bytes);
    return AF_EINVAL;
  }
  int have_fmt = 0;
  for (uint64_t pos = 12;;) {
    if (pos + 8 > riff_end || pos + 8 > n) {
      const char *what = have_fmt ? "data" : "fmt ";
      if (pos + 8 <= riff_end)
        snprintf(err, len, "WAV has no '%s' chunk in its first MiB", what);
      else if (riff_end < file_bytes) /* the size may be what is wrong, not the file */
        snprintf(err, len,
                 "WAV has no '%s' chunk within the %llu bytes its RIFF size (%u) says; the file "
                 "has %llu",
                 what, (unsigned long long)riff_end, riff_size, (unsigned long long)file_bytes);
      else
        snprintf(err, len, "WAV has no '%s' chunk", what);
      return AF_EINVAL;
    }
    char name[5];
    chunk_name(head + pos, name);
    uint32_t size = le32(head + pos + 4);
    const uint64_t body = pos + 8;
    if (out->streamed && have_fmt && memcmp(name, "data", 4) == 0 &&
        (size == 0 || size == UINT32_MAX || body + size > riff_end)) /* never finalized */
      size = (uint32_t)((riff_end - body) / out->frame_bytes * out->frame_bytes);
    const uint64_t end = body + size;
    if (end > riff_end) {
      snprintf(err, len, "WAV chunk '%s' at byte %llu claims %u bytes, past the RIFF's end at %llu",
               name, (unsigned long long)pos, size, (unsigned long long)riff_end);
      return AF_EINVAL;
    }
    if (memcmp(name, "fmt ", 4) == 0) {
      if (have_fmt || end > n) {
        snprintf(err, len, "WAV 'fmt ' chunk %s",
                 have_fmt ? "given twice" : "beyond the first MiB");
        return AF_EINVAL;
      }
      if (!parse_fmt(head + body, size, out, err, len))
        return AF_EINVAL;
      have_fmt = 1;
    } else if (memcmp(name, "data", 4) == 0) {
      if (!have_fmt) {
        snprintf(err, len, "WAV 'data' chunk before its 'fmt ' chunk");
        return AF_EINVAL;
      }
      if (size % out->frame_bytes != 0) {
        snprintf(err, len, "WAV 'data' chunk of %u bytes is not a whole number of %zu-byte frames",
                 size, out->frame_bytes);
        return AF_EINVAL;
      }
      out->data_offset = body;
      out->frames = size / out->frame_bytes;
      return AF_OK;
    }
    pos = end + (size & 1u); /* chunks are padded to an even size */
  }
}

/* The sample of `bytes` bytes at p as a sign-extended integer. */
static int64_t sample_int(const uint8_t *p, unsigned bytes)
{
  uint64_t u = 0;
  for (unsigned k = 0; k < bytes; k++)
    u |= (uint64_t)p[k] << (8 * k);
  const uint64_t sign = (uint64_t)1 << (8 * bytes - 1);
  return (int64_t)(u ^ sign) - (int64_t)sign;
}

void af_wav_justify_scan(const af_wav_info *w, const uint8_t *frames, size_t n, af_wav_justify *j)
{
  if (w->format_tag != 1 || w->valid_bits >= w->bits || w->bits < 16 || w->bits > 32)
    return;
  const unsigned bytes = w->bits / 8, shift = w->bits - w->valid_bits;
  const int64_t low_mask = ((int64_t)1 << shift) - 1, top = (int64_t)1 << (w->valid_bits - 1);
  for (size_t k = 0; k < n * w->channels; k++) {
    const int64_t v = sample_int(frames + k * bytes, bytes);
    j->low_used |= (v & low_mask) != 0;
    j->top_not_ext |= v < -top || v >= top;
  }
}

double af_wav_right_justified(const af_wav_info *w, const af_wav_justify *j)
{
  if (w->format_tag != 1 || w->valid_bits >= w->bits || !j->low_used || j->top_not_ext)
    return 1.0;
  return (double)((uint64_t)1 << (w->bits - w->valid_bits));
}

void af_wav_decode(const af_wav_info *w, const uint8_t *frames, size_t n, unsigned channel,
                   double gain, float *out)
{
  af_pcm_decode(w->format, w->channels, channel, frames, 0, n, gain, out);
}
