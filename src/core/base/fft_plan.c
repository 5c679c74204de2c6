/* fft_plan.c — FFTW r2c plans shared by the process, one per size (see
 * fft_plan.h). */
#include "fft_plan.h"

#include <limits.h>
#include <threads.h>

/* The planned sizes, filled in order and kept for the process's life. */
static struct {
  size_t n;
  fftw_plan plan;
} shared[AF_FFT_PLAN_SHARED];
static size_t n_shared;
/* Guards shared[], n_shared and every call of FFTW's planner. */
static mtx_t planner;
static bool planner_ok;
static once_flag planner_once = ONCE_FLAG_INIT;

static void planner_init(void)
{
  planner_ok = mtx_init(&planner, mtx_plain) == thrd_success;
}

/* A new FFTW_ESTIMATE plan of n points on buffers of FFTW's alignment (the
 * planning buffers are not kept: the plan runs on its callers' buffers);
 * NULL when FFTW fails. Under the lock. */
static fftw_plan plan_new(size_t n)
{
  double *in = fftw_alloc_real(n);
  fftw_complex *out = fftw_alloc_complex(n / 2 + 1);
  fftw_plan p = in && out ? fftw_plan_dft_r2c_1d((int)n, in, out, FFTW_ESTIMATE) : NULL;
  fftw_free(in);
  fftw_free(out);
  return p;
}

/* The plan of n points under the lock: a shared one, or (the table full) a
 * holder's own. */
static void acquire_locked(size_t n, af_fft_r2c *out)
{
  for (size_t k = 0; k < n_shared; k++) {
    if (shared[k].n == n) {
      out->plan = shared[k].plan;
      return;
    }
  }
  out->plan = plan_new(n);
  if (out->plan == NULL)
    return;
  if (n_shared < AF_FFT_PLAN_SHARED) {
    shared[n_shared].n = n;
    shared[n_shared].plan = out->plan;
    n_shared++;
  } else {
    out->own = true;
  }
}

af_status af_fft_r2c_acquire(size_t n, af_fft_r2c *out)
{
  if (out == NULL)
    return AF_EINVAL;
  out->plan = NULL;
  out->own = false;
  if (n < 1 || n > (size_t)INT_MAX)
    return AF_EINVAL;
  call_once(&planner_once, planner_init);
  if (!planner_ok || mtx_lock(&planner) != thrd_success)
    return AF_ENOMEM;
  acquire_locked(n, out);
  mtx_unlock(&planner);
  return out->plan != NULL ? AF_OK : AF_ENOMEM;
}

void af_fft_r2c_release(af_fft_r2c *p)
{
  if (p == NULL || p->plan == NULL)
    return;
  /* A holder's own plan exists only when the lock worked for its acquire. */
  if (p->own && mtx_lock(&planner) == thrd_success) {
    fftw_destroy_plan(p->plan);
    mtx_unlock(&planner);
  }
  p->plan = NULL;
  p->own = false;
}

void af_fft_r2c_execute(const af_fft_r2c *p, double *in, fftw_complex *out)
{
  fftw_execute_dft_r2c(p->plan, in, out);
}
