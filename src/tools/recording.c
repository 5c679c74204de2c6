/* recording.c — WAV and raw float32 recordings (see recording.h). */
#define _POSIX_C_SOURCE 200809L
#include "recording.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>
#include <sys/types.h>

#include "wav.h"

/* WAV samples are decoded through a buffer of this many bytes (at least
 * one frame). */
#define AF_RECORDING_BLOCK_BYTES ((size_t)1 << 16)

static int host_is_little_endian(void)
{
  const uint32_t one = 1;
  unsigned char b;
  memcpy(&b, &one, 1);
  return b == 1;
}

static void swap_bytes(float *x, size_t n)
{
  for (size_t k = 0; k < n; k++) {
    unsigned char b[4], t;
    memcpy(b, &x[k], 4);
    t = b[0], b[0] = b[3], b[3] = t;
    t = b[1], b[1] = b[2], b[2] = t;
    memcpy(&x[k], b, 4);
  }
}

af_recording_spec af_recording_spec_default(const char *rate_flag, const char *channel_flag)
{
  af_recording_spec s = {rate_flag,
                         channel_flag,
                         0.0,
                         -1,
                         AF_RECORDING_SCALE_DEFAULT,
                         AF_RECORDING_DEFAULT_MAX_SAMPLES};
  return s;
}

_Static_assert(AF_RECORDING_MAX_SAMPLES_N == (1L << 27), "2^27 samples, as documented");

static bool ends_with(const char *path, const char *ext)
{
  size_t n = strlen(path), e = strlen(ext);
  return n >= e && strcasecmp(path + n - e, ext) == 0;
}

/* Raw float32 from f (size_bytes long, already at its start). */
/* The cap of spec (0: the default), at most AF_RECORDING_MAX_SAMPLES. */
static size_t cap_of(const af_recording_spec *spec)
{
  size_t m = spec->max_samples ? spec->max_samples : AF_RECORDING_DEFAULT_MAX_SAMPLES;
  return m < AF_RECORDING_MAX_SAMPLES ? m : AF_RECORDING_MAX_SAMPLES;
}

static af_status too_long(const char *path, const char *what, uint64_t n,
                          const af_recording_spec *spec, char *err, size_t len)
{
  snprintf(err, len,
           "%s: %llu %s, above --max-samples %zu (at most %zu; split the recording or raise it)",
           path, (unsigned long long)n, what, cap_of(spec), AF_RECORDING_MAX_SAMPLES);
  return AF_ESIZE;
}

static af_status read_raw(FILE *f, const char *path, uint64_t size_bytes,
                          const af_recording_spec *spec, af_recording *out, char *err, size_t len)
{
  if (size_bytes % 4 != 0) {
    snprintf(err, len, "%s: %llu bytes is not a whole number of float32 samples", path,
             (unsigned long long)size_bytes);
    return AF_EINVAL;
  }
  if (size_bytes / 4 > cap_of(spec))
    return too_long(path, "samples", size_bytes / 4, spec, err, len);
  out->n = (size_t)size_bytes / 4;
  out->x = malloc(out->n > 0 ? out->n * sizeof *out->x : 1);
  if (out->x == NULL || fread(out->x, 4, out->n, f) != out->n) {
    snprintf(err, len, "%s: cannot read %zu samples", path, out->n);
    return AF_EIO;
  }
  if (!host_is_little_endian())
    swap_bytes(out->x, out->n);
  return AF_OK;
}

/* Opens path as a regular file; its size into *size_bytes. NULL with a message. */
static FILE *open_regular(const char *path, uint64_t *size_bytes, af_status *st, char *err,
                          size_t len)
{
  struct stat sb;
  FILE *f = fopen(path, "rb");
  if (f == NULL || fstat(fileno(f), &sb) != 0) {
    snprintf(err, len, "%s: cannot read: %s", path, strerror(errno));
    if (f)
      fclose(f);
    *st = AF_EIO;
    return NULL;
  }
  if (!S_ISREG(sb.st_mode)) {
    snprintf(err, len, "%s: not a regular file", path);
    fclose(f);
    *st = AF_EINVAL;
    return NULL;
  }
  *size_bytes = (uint64_t)sb.st_size;
  return f;
}

/* The header's rate and channel count against the flags. */
static af_status check_wav_flags(const char *path, const af_wav_info *w,
                                 const af_recording_spec *spec, char *err, size_t len)
{
  if (spec->rate_hz > 0.0 && spec->rate_hz != (double)w->sample_rate_hz) {
    snprintf(err, len,
             "%s: %s %.17g disagrees with the WAV header's %u Hz (leave it out for a WAV)", path,
             spec->rate_flag, spec->rate_hz, (unsigned)w->sample_rate_hz);
    return AF_EINVAL;
  }
  if (spec->channel >= (long)w->channels) {
    snprintf(err, len, "%s: %s %ld is beyond the WAV's %u channel%s (0 to %u)", path,
             spec->channel_flag, spec->channel, w->channels, w->channels == 1 ? "" : "s",
             w->channels - 1);
    return AF_EINVAL;
  }
  if (w->frames > cap_of(spec))
    return too_long(path, "frames", w->frames, spec, err, len);
  return AF_OK;
}

/* The samples of channel spec->channel of the WAV w in f, in blocks. */
static af_status read_wav(FILE *f, const char *path, const af_wav_info *w,
                          const af_recording_spec *spec, af_recording *out, char *err, size_t len)
{
  size_t block = AF_RECORDING_BLOCK_BYTES / w->frame_bytes;
  block = block > 0 ? block : 1;
  uint8_t *buf = malloc(block * w->frame_bytes);
  out->n = (size_t)w->frames;
  out->x = malloc(out->n > 0 ? out->n * sizeof *out->x : 1);
  af_status s = buf && out->x ? AF_OK : AF_ENOMEM;
  if (s == AF_OK && fseeko(f, (off_t)w->data_offset, SEEK_SET) != 0)
    s = AF_EIO;
  const unsigned channel = spec->channel < 0 ? 0u : (unsigned)spec->channel;
  af_wav_justify justify = {0};
  for (size_t done = 0; s == AF_OK && done < out->n;) {
    size_t n = out->n - done < block ? out->n - done : block;
    if (fread(buf, w->frame_bytes, n, f) != n)
      s = AF_EIO;
    else {
      af_wav_justify_scan(w, buf, n, &justify);
      af_wav_decode(w, buf, n, channel, spec->scale, out->x + done);
    }
    done += n;
  }
  if (s != AF_OK)
    snprintf(err, len, "%s: cannot read %zu WAV frames: %s", path, out->n, af_strerror(s));
  /* Right-justified samples: scaled by a power of two, exact in float. */
  const double factor = s == AF_OK ? af_wav_right_justified(w, &justify) : 1.0;
  if (factor != 1.0) {
    for (size_t k = 0; k < out->n; k++)
      out->x[k] = (float)(factor * out->x[k]);
    fprintf(stderr,
            "%s: note: its %u valid bits sit right-justified in %u-bit samples (the top bits only "
            "the sign's extension, against the WAV spec): read as %u-bit samples (x %g)\n",
            path, w->valid_bits, w->bits, w->valid_bits, factor);
  }
  free(buf);
  return s;
}

/* After the file's first bytes said raw: checks and reads it. */
static af_status load_raw(FILE *f, const char *path, uint64_t size_bytes,
                          const af_recording_spec *spec, af_recording *out, double *rate_hz,
                          char *err, size_t len)
{
  if (ends_with(path, ".wav") || ends_with(path, ".wave") || ends_with(path, ".mp3")) {
    snprintf(err, len, "%s: named %s but not a RIFF/WAVE file%s", path, strrchr(path, '.'),
             ends_with(path, ".mp3") ? " (MP3 is not accepted: convert it to WAV)" : "");
    return AF_EINVAL;
  }
  if (!(spec->rate_hz > 0.0)) {
    snprintf(err, len, "%s: raw float32 needs %s HZ (only a WAV carries its rate)", path,
             spec->rate_flag);
    return AF_EINVAL;
  }
  if (spec->channel > 0) {
    snprintf(err, len, "%s: %s %ld is beyond raw float32's one channel (0)", path,
             spec->channel_flag, spec->channel);
    return AF_EINVAL;
  }
  if (fseeko(f, 0, SEEK_SET) != 0) {
    snprintf(err, len, "%s: cannot read: %s", path, strerror(errno));
    return AF_EIO;
  }
  af_status s = read_raw(f, path, size_bytes, spec, out, err, len);
  for (size_t k = 0; s == AF_OK && spec->scale != 1.0 && k < out->n; k++)
    out->x[k] = (float)(spec->scale * out->x[k]);
  *rate_hz = spec->rate_hz;
  return s;
}

/* After the file's first bytes said RIFF/WAVE: its header, then its samples. */
static af_status load_wav(FILE *f, const char *path, const uint8_t *head, size_t n_head,
                          uint64_t size_bytes, const af_recording_spec *spec, af_recording *out,
                          double *rate_hz, char *err, size_t len)
{
  af_wav_info w;
  char why[256];
  if (af_wav_parse(head, n_head, size_bytes, &w, why, sizeof why) != AF_OK) {
    snprintf(err, len, "%s: %s", path, why);
    return AF_EINVAL;
  }
  af_status s = check_wav_flags(path, &w, spec, err, len);
  if (s == AF_OK && w.streamed)
    fprintf(stderr,
            "%s: note: its RIFF size is %s, as a recorder leaves a stream it never finalized: "
            "read to the end of the file, %llu frames\n",
            path, head[4] == 0 ? "0" : "0xFFFFFFFF", (unsigned long long)w.frames);
  if (s == AF_OK)
    s = read_wav(f, path, &w, spec, out, err, len);
  if (s == AF_OK)
    *rate_hz = (double)w.sample_rate_hz;
  if (s == AF_OK && w.format_tag == 1) /* integer PCM: full scale is 2^(valid bits - 1) steps */
    out->quantum = spec->scale / ldexp(1.0, (int)w.valid_bits - 1);
  return s;
}

af_status af_recording_load(const char *path, const af_recording_spec *spec, af_recording *out,
                            double *rate_hz, char *err, size_t len)
{
  uint64_t size_bytes = 0;
  af_status s = AF_OK;
  memset(out, 0, sizeof *out);
  *rate_hz = 0.0;
  FILE *f = open_regular(path, &size_bytes, &s, err, len);
  if (f == NULL)
    return s;
  /* The head: enough for every chunk header before the samples. */
  size_t n_head = size_bytes < AF_WAV_HEAD_MAX ? (size_t)size_bytes : AF_WAV_HEAD_MAX;
  uint8_t *head = malloc(n_head > 0 ? n_head : 1);
  if (head == NULL || fread(head, 1, n_head, f) != n_head) {
    snprintf(err, len, "%s: cannot read its first %zu bytes", path, n_head);
    s = AF_EIO;
  }
  const char *what = "";
  af_wav_kind kind = s == AF_OK ? af_wav_identify(head, n_head, &what) : AF_WAV_KIND_NONE;
  if (s == AF_OK && kind == AF_WAV_KIND_OTHER) {
    snprintf(err, len, "%s: is %s, not WAV or raw float32 (convert it to WAV)", path, what);
    s = AF_EINVAL;
  } else if (s == AF_OK && kind == AF_WAV_KIND_NONE) {
    s = load_raw(f, path, size_bytes, spec, out, rate_hz, err, len);
  } else if (s == AF_OK) {
    s = load_wav(f, path, head, n_head, size_bytes, spec, out, rate_hz, err, len);
  }
  free(head);
  fclose(f);
  if (s != AF_OK)
    af_recording_destroy(out);
  return s;
}

void af_recording_destroy(af_recording *r)
{
  free(r->x);
  r->x = NULL;
  r->n = 0;
}
