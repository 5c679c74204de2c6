/* recording.c — raw float32 recordings (see recording.h). */
#define _POSIX_C_SOURCE 200809L
#include "recording.h"

#include <errno.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

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

af_status af_recording_read(const char *path, af_recording *out, char *err, size_t len)
{
  struct stat st;
  memset(out, 0, sizeof *out);
  FILE *f = fopen(path, "rb");
  if (f == NULL || fstat(fileno(f), &st) != 0) {
    snprintf(err, len, "%s: cannot read: %s", path, strerror(errno));
    if (f)
      fclose(f);
    return AF_EIO;
  }
  af_status s = AF_OK;
  if (!S_ISREG(st.st_mode)) {
    snprintf(err, len, "%s: not a regular file", path);
    s = AF_EINVAL;
  } else if (st.st_size % 4 != 0) {
    snprintf(err, len, "%s: %lld bytes is not a whole number of float32 samples", path,
             (long long)st.st_size);
    s = AF_EINVAL;
  } else if ((unsigned long long)st.st_size / 4 > AF_RECORDING_MAX_SAMPLES) {
    snprintf(err, len, "%s: %lld samples, above the %zu accepted (split the recording)", path,
             (long long)st.st_size / 4, AF_RECORDING_MAX_SAMPLES);
    s = AF_ESIZE;
  }
  if (s == AF_OK) {
    out->n = (size_t)st.st_size / 4;
    out->x = malloc(out->n > 0 ? out->n * sizeof *out->x : 1);
    if (out->x == NULL || fread(out->x, 4, out->n, f) != out->n) {
      snprintf(err, len, "%s: cannot read %zu samples", path, out->n);
      s = AF_EIO;
    }
  }
  fclose(f);
  if (s != AF_OK) {
    af_recording_free(out);
    return s;
  }
  if (!host_is_little_endian())
    swap_bytes(out->x, out->n);
  return AF_OK;
}

void af_recording_free(af_recording *r)
{
  free(r->x);
  r->x = NULL;
  r->n = 0;
}
