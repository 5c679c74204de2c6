/* recording.h — a raw recording on disk: little-endian float32 samples, as a
 * DAQ or `sox -t f32` writes them. Read whole, with a stated maximum size, so
 * that a wrong file cannot make the tool allocate what the machine cannot
 * hold. */
#ifndef AF_RECORDING_H
#define AF_RECORDING_H

#include <stddef.h>

#include "status.h"

#ifdef __cplusplus
extern "C" {
#endif

/* 2^27 samples (512 MiB; 45 min at 50 kHz): a longer recording is split. */
#define AF_RECORDING_MAX_SAMPLES ((size_t)1 << 27)

typedef struct {
  float *x;
  size_t n;
} af_recording;

/* Reads path into *out (an empty file gives n = 0). AF_EIO (cannot open or
 * read), AF_EINVAL (not whole float32 samples, or not a regular file) or
 * AF_ESIZE (over AF_RECORDING_MAX_SAMPLES), with one line naming the file in
 * err; *out is then empty. */
af_status af_recording_read(const char *path, af_recording *out, char *err, size_t len);
void af_recording_free(af_recording *r); /* safe on an empty recording */

#ifdef __cplusplus
}
#endif
#endif
