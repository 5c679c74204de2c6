/* recording_sndfile.c — WAV, FLAC and raw float32 recordings (see
 * recording.h) read with libsndfile instead of src/core/io/wav.c (built with
 * -DAF_RECORDING_READER=sndfile; doc/recordings.md, "Libraries measured").
 * The file-level bounds stay ours and come first: a regular file, whose
 * frames (from libsndfile's header) are checked against --max-samples before
 * anything is allocated; libsndfile reads through the descriptor we opened. */
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

#include <sndfile.h>
#include <unistd.h>

#include "wav.h"

/* Samples are decoded through a buffer of this many bytes (at least one
 * frame). */
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

bool af_recording_parse_channel(const char *flag, const char *text, long *out, char *err,
                                size_t len)
{
  char *end;
  errno = 0;
  long v = strtol(text, &end, 10);
  if (end == text || *end != '\0' || errno == ERANGE || v < 0 || v > AF_RECORDING_CHANNEL_MAX) {
    snprintf(err, len, "%s '%s' must be a whole number in [0, %ld] (0 = the first channel)", flag,
             text, AF_RECORDING_CHANNEL_MAX);
    return false;
  }
  *out = v;
  return true;
}

bool af_recording_parse_scale(const char *flag, const char *text, double *out, char *err,
                              size_t len)
{
  char *end;
  errno = 0;
  double v = strtod(text, &end);
  if (end == text || *end != '\0' || errno == ERANGE || !(v > 0.0 && v <= AF_RECORDING_SCALE_MAX)) {
    snprintf(err, len, "%s '%s' must be a number in (0, %g] (the value at full scale)", flag, text,
             AF_RECORDING_SCALE_MAX);
    return false;
  }
  *out = v;
  return true;
}

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

/* After libsndfile found no header it knows: checks and reads raw float32. */
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

/* The container and sample type libsndfile found: NULL when accepted, else
 * what it is, for the refusal. *bits: integer bits (0 for floats). */
static const char *refused_format(int format, unsigned *bits, const char **container)
{
  const int major = format & SF_FORMAT_TYPEMASK, sub = format & SF_FORMAT_SUBMASK;
  switch (major) {
  case SF_FORMAT_WAV:
  case SF_FORMAT_WAVEX: *container = "WAV"; break;
  case SF_FORMAT_RF64: *container = "RF64"; break;
  case SF_FORMAT_W64: *container = "Wave64"; break;
  case SF_FORMAT_FLAC: *container = "FLAC"; break;
  case SF_FORMAT_MPEG: return "MPEG audio (lossy)";
  case SF_FORMAT_OGG: return "Ogg (lossy)";
  case SF_FORMAT_AIFF: return "AIFF";
  case SF_FORMAT_AU: return "Sun/NeXT AU";
  case SF_FORMAT_CAF: return "Core Audio (CAF)";
  default: return "an audio format other than WAV, RF64, Wave64 or FLAC";
  }
  switch (sub) {
  case SF_FORMAT_PCM_U8:
  case SF_FORMAT_PCM_S8: *bits = 8; return NULL;
  case SF_FORMAT_PCM_16: *bits = 16; return NULL;
  case SF_FORMAT_PCM_24: *bits = 24; return NULL;
  case SF_FORMAT_PCM_32: *bits = 32; return NULL;
  case SF_FORMAT_FLOAT:
  case SF_FORMAT_DOUBLE: *bits = 0; return NULL;
  default: return "compressed or non-linear samples (ADPCM, A-law, mu-law, ...)";
  }
}

/* The rate and channel count libsndfile read, against the flags. */
static af_status check_flags(const char *path, const char *container, const SF_INFO *info,
                             const af_recording_spec *spec, char *err, size_t len)
{
  if (spec->rate_hz > 0.0 && spec->rate_hz != (double)info->samplerate) {
    snprintf(err, len, "%s: %s %.17g disagrees with the %s header's %d Hz (leave it out for a %s)",
             path, spec->rate_flag, spec->rate_hz, container, info->samplerate, container);
    return AF_EINVAL;
  }
  if (spec->channel >= (long)info->channels) {
    snprintf(err, len, "%s: %s %ld is beyond the %s's %d channel%s (0 to %d)", path,
             spec->channel_flag, spec->channel, container, info->channels,
             info->channels == 1 ? "" : "s", info->channels - 1);
    return AF_EINVAL;
  }
  if (info->frames < 0 || (uint64_t)info->frames > cap_of(spec))
    return too_long(path, "frames", (uint64_t)info->frames, spec, err, len);
  return AF_OK;
}

/* Channel spec->channel of the open file, in blocks, times the scale. */
static af_status read_frames(SNDFILE *sf, const char *path, const SF_INFO *info,
                             const af_recording_spec *spec, af_recording *out, char *err,
                             size_t len)
{
  const size_t channels = (size_t)info->channels;
  size_t block = AF_RECORDING_BLOCK_BYTES / (channels * sizeof(float));
  block = block > 0 ? block : 1;
  float *buf = malloc(block * channels * sizeof *buf);
  out->n = (size_t)info->frames;
  out->x = malloc(out->n > 0 ? out->n * sizeof *out->x : 1);
  if (buf == NULL || out->x == NULL) {
    free(buf);
    snprintf(err, len, "%s: no memory for %zu frames", path, out->n);
    return AF_ENOMEM;
  }
  const size_t channel = spec->channel < 0 ? 0u : (size_t)spec->channel;
  af_status s = AF_OK;
  for (size_t done = 0; s == AF_OK && done < out->n;) {
    size_t n = out->n - done < block ? out->n - done : block;
    sf_count_t got = sf_readf_float(sf, buf, (sf_count_t)n);
    if (got != (sf_count_t)n) {
      snprintf(err, len, "%s: cannot read %zu frames: %zu read, %s", path, out->n,
               done + (got > 0 ? (size_t)got : 0), sf_strerror(sf));
      s = AF_EINVAL;
    }
    for (size_t k = 0; s == AF_OK && k < n; k++)
      out->x[done + k] = (float)(spec->scale * buf[k * channels + channel]);
    done += n;
  }
  free(buf);
  return s;
}

/* The containers handed to libsndfile, by their first bytes: RIFF/WAVE,
 * RF64 and FLAC. Every other file stays away from it (it would parse Ogg,
 * MP3, AIFF, CAF, ... before we could refuse them; a malformed Ogg/Vorbis
 * file leaks memory in libsndfile 1.2.0 with libvorbis). */
static bool for_sndfile(const uint8_t *head, size_t n)
{
  return n >= 12 && ((memcmp(head, "RIFF", 4) == 0 && memcmp(head + 8, "WAVE", 4) == 0) ||
                     memcmp(head, "RF64", 4) == 0 || memcmp(head, "fLaC", 4) == 0);
}

/* libsndfile's reading of the file at fd. */
static af_status load_sndfile(int fd, const char *path, const af_recording_spec *spec,
                              af_recording *out, double *rate_hz, char *err, size_t len)
{
  SF_INFO info;
  memset(&info, 0, sizeof info);
  if (lseek(fd, 0, SEEK_SET) != 0) {
    snprintf(err, len, "%s: cannot read: %s", path, strerror(errno));
    return AF_EIO;
  }
  /* libsndfile closes a descriptor it failed to open even when told not
   * to (1.2.0): it gets a copy of its own, closed by sf_close or there. */
  const int copy = dup(fd);
  SNDFILE *sf = copy >= 0 ? sf_open_fd(copy, SFM_READ, &info, 1) : NULL;
  if (copy < 0) {
    snprintf(err, len, "%s: cannot read: %s", path, strerror(errno));
    return AF_EIO;
  }
  if (sf == NULL) {
    snprintf(err, len, "%s: %s", path, sf_strerror(NULL));
    return AF_EINVAL;
  }
  unsigned bits = 0;
  const char *container = "";
  const char *what = refused_format(info.format, &bits, &container);
  af_status s = AF_OK;
  if (what != NULL) {
    snprintf(err, len, "%s: is %s, not WAV, FLAC or raw float32 (convert it to WAV)", path, what);
    s = AF_EINVAL;
  }
  if (s == AF_OK)
    s = check_flags(path, container, &info, spec, err, len);
  if (s == AF_OK)
    s = read_frames(sf, path, &info, spec, out, err, len);
  if (s == AF_OK) {
    *rate_hz = (double)info.samplerate;
    if (bits > 0) /* integer PCM: full scale is 2^(bits - 1) steps */
      out->quantum = spec->scale / ldexp(1.0, (int)bits - 1);
  }
  sf_close(sf);
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
  /* The head: what the file is (af_wav_identify names MP3, Ogg, AIFF, ...). */
  size_t n_head = size_bytes < AF_WAV_HEAD_MAX ? (size_t)size_bytes : AF_WAV_HEAD_MAX;
  uint8_t *head = malloc(n_head > 0 ? n_head : 1);
  if (head == NULL || fread(head, 1, n_head, f) != n_head) {
    snprintf(err, len, "%s: cannot read its first %zu bytes", path, n_head);
    s = AF_EIO;
  }
  const char *what = "";
  if (s == AF_OK && for_sndfile(head, n_head)) {
    s = load_sndfile(fileno(f), path, spec, out, rate_hz, err, len);
  } else if (s == AF_OK && af_wav_identify(head, n_head, &what) != AF_WAV_KIND_NONE) {
    snprintf(err, len, "%s: is %s, not WAV, FLAC or raw float32 (convert it to WAV)", path,
             what[0] ? what : "not a RIFF/WAVE file");
    s = AF_EINVAL;
  } else if (s == AF_OK) {
    s = load_raw(f, path, size_bytes, spec, out, rate_hz, err, len);
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
