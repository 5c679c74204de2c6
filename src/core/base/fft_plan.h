/* fft_plan.h — FFTW real-to-complex plans shared by the whole process, one
 * per transform size.
 *
 * Why: FFTW's planner is not thread-safe (only the fftw_execute family is),
 * and even an FFTW_ESTIMATE plan costs its twiddle factors (about 0.1 ms at
 * 8192 points), paid by every lane made. So each size is planned once, under
 * one process-wide lock, kept for the life of the process (at most
 * AF_FFT_PLAN_SHARED sizes; a further size gets a plan of its own, made and
 * destroyed under the lock), and executed on each caller's own buffers by
 * FFTW's new-array interface. The buffers must come from fftw_alloc_real /
 * fftw_alloc_complex (the planned alignment) and must not overlap (the plan
 * is out-of-place). The transform is the one a plan made by the caller with
 * FFTW_ESTIMATE would compute: the same size, flags and alignment give the
 * same algorithm, bit for bit.
 */
#ifndef AF_FFT_PLAN_H
#define AF_FFT_PLAN_H

#include <stdbool.h>
#include <stddef.h>

/* fftw_complex as the includer has it: double[2], or the C99 double
 * complex when complex.h came first (the same layout, FFTW's guarantee). */
#include <fftw3.h>

#include "status.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Sizes planned once and kept; any further size is planned per caller. */
#define AF_FFT_PLAN_SHARED 32

typedef struct {
  fftw_plan plan; /* NULL: none */
  bool own;       /* made for this holder alone: destroyed by af_fft_r2c_release */
} af_fft_r2c;

/* The r2c plan of n real samples (n / 2 + 1 bins out), FFTW_ESTIMATE, into
 * *out. Thread-safe. AF_EINVAL for n < 1 or n > INT_MAX, AF_ENOMEM when
 * FFTW fails (*out then holds no plan). */
af_status af_fft_r2c_acquire(size_t n, af_fft_r2c *out);

/* Gives the plan back (destroys it when it was the holder's own); safe on a
 * zeroed or released holder. Thread-safe. */
void af_fft_r2c_release(af_fft_r2c *p);

/* The transform of in into out, with p's plan (fftw_execute_dft_r2c: safe on
 * several threads at once). */
void af_fft_r2c_execute(const af_fft_r2c *p, double *in, fftw_complex *out);

#ifdef __cplusplus
}
#endif
#endif
