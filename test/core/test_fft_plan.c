/* test_fft_plan.c — the process's shared FFTW r2c plans (fft_plan.h): a
 * tone in its bin (closed form), the same bits as FFTW with a plan of the
 * caller's own, one plan per size, holders' own plans past the table, the
 * argument errors, and acquire / execute / release on two threads at once. */
#include <complex.h>
#include <fftw3.h>
#include <stdlib.h>
#include <string.h>
#include <threads.h>

#include "af_test.h"
#include "fft_plan.h"

#define PI 3.14159265358979323846

/* x_j = cos(2 pi k0 j / n): X_k0 = n / 2, every other bin 0. Largest error
 * against that [unscaled FFT units]. */
static double tone_error(const af_fft_r2c *p, size_t n, size_t k0)
{
  double *in = fftw_alloc_real(n);
  fftw_complex *out = fftw_alloc_complex(n / 2 + 1);
  for (size_t j = 0; j < n; j++)
    in[j] = cos(2.0 * PI * (double)(k0 * j % n) / (double)n);
  af_fft_r2c_execute(p, in, out);
  double worst = 0.0;
  for (size_t k = 0; k <= n / 2; k++) {
    double expect = k == k0 ? 0.5 * (double)n : 0.0;
    worst = fmax(worst, cabs(out[k] - expect));
  }
  fftw_free(in);
  fftw_free(out);
  return worst;
}

static void test_tone(void)
{
  af_fft_r2c p;
  AF_CHECK_STATUS(af_fft_r2c_acquire(1024, &p), AF_OK);
  AF_CHECK_ABS(tone_error(&p, 1024, 37), 0.0, 1e-9);
  af_fft_r2c_release(&p);
  AF_CHECK(p.plan == NULL);
}

/* The shared plan against FFTW planned by hand on the caller's arrays, on
 * seeded random data: equal bit for bit (memcmp). */
static void test_same_bits(void)
{
  const size_t n = 8192, bins = n / 2 + 1;
  double *in = fftw_alloc_real(n), *in2 = fftw_alloc_real(n);
  fftw_complex *out = fftw_alloc_complex(bins), *ref = fftw_alloc_complex(bins);
  fftw_plan own = fftw_plan_dft_r2c_1d((int)n, in2, ref, FFTW_ESTIMATE);
  srand(17);
  for (size_t j = 0; j < n; j++)
    in[j] = in2[j] = (double)rand() / RAND_MAX - 0.5;
  fftw_execute(own);
  af_fft_r2c p;
  AF_CHECK_STATUS(af_fft_r2c_acquire(n, &p), AF_OK);
  af_fft_r2c_execute(&p, in, out);
  AF_CHECK(memcmp(out, ref, bins * sizeof *out) == 0);
  af_fft_r2c_release(&p);
  fftw_destroy_plan(own);
  fftw_free(in);
  fftw_free(in2);
  fftw_free(out);
  fftw_free(ref);
}

/* One plan per size; past AF_FFT_PLAN_SHARED sizes, plans of the holder's
 * own that still transform right. */
static void test_sharing(void)
{
  af_fft_r2c a, b;
  AF_CHECK_STATUS(af_fft_r2c_acquire(512, &a), AF_OK);
  AF_CHECK_STATUS(af_fft_r2c_acquire(512, &b), AF_OK);
  AF_CHECK(a.plan == b.plan && !a.own && !b.own);
  af_fft_r2c_release(&a);
  af_fft_r2c_release(&b);
  /* sizes 2 .. AF_FFT_PLAN_SHARED + 9 (even): the table fills on the way */
  af_fft_r2c held[AF_FFT_PLAN_SHARED + 8];
  size_t owned = 0;
  for (size_t k = 0; k < AF_FFT_PLAN_SHARED + 8; k++) {
    AF_CHECK_STATUS(af_fft_r2c_acquire(2 * (k + 1) + 2, &held[k]), AF_OK);
    owned += held[k].own;
  }
  AF_CHECK(owned >= 8);
  AF_CHECK_ABS(tone_error(&held[AF_FFT_PLAN_SHARED + 7], 2 * (AF_FFT_PLAN_SHARED + 8) + 2, 3), 0.0,
               1e-9);
  for (size_t k = 0; k < AF_FFT_PLAN_SHARED + 8; k++)
    af_fft_r2c_release(&held[k]); /* the own ones destroyed: LeakSanitizer would say */
}

static void test_errors(void)
{
  af_fft_r2c p = {0};
  AF_CHECK_STATUS(af_fft_r2c_acquire(0, &p), AF_EINVAL);
  AF_CHECK(p.plan == NULL);
  AF_CHECK_STATUS(af_fft_r2c_acquire((size_t)1 << 40, &p), AF_EINVAL);
  AF_CHECK_STATUS(af_fft_r2c_acquire(16, NULL), AF_EINVAL);
  af_fft_r2c_release(NULL);
  af_fft_r2c_release(&p); /* zeroed: nothing */
  af_fft_r2c_release(&p); /* twice */
  AF_CHECK(p.plan == NULL);
}

/* Two threads acquire, execute and release plans of many sizes at once
 * (FFTW's planner is not thread-safe: the lock must hold it). */
static int worker(void *arg)
{
  size_t base = *(const size_t *)arg, bad = 0;
  for (int round = 0; round < 20; round++) {
    for (size_t k = 0; k < 6; k++) {
      size_t n = 64 * (base + k) + 2 * (size_t)round;
      af_fft_r2c p;
      if (af_fft_r2c_acquire(n, &p) != AF_OK || tone_error(&p, n, 5) > 1e-9)
        bad++;
      af_fft_r2c_release(&p);
    }
  }
  return (int)bad;
}

static void test_threads(void)
{
  thrd_t t[2];
  size_t base[2] = {1, 4};
  int bad[2] = {-1, -1};
  for (int i = 0; i < 2; i++)
    AF_CHECK(thrd_create(&t[i], worker, &base[i]) == thrd_success);
  for (int i = 0; i < 2; i++)
    AF_CHECK(thrd_join(t[i], &bad[i]) == thrd_success);
  AF_CHECK(bad[0] == 0 && bad[1] == 0);
}

int main(void)
{
  test_tone();
  test_same_bits();
  test_sharing();
  test_errors();
  test_threads();
  return af_test_summary("test_fft_plan");
}
