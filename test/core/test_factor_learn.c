/* test_factor_learn.c — the modulus factor learned on the line, with hand
 * sequences: the median (odd and even counts, the factor in use undone), the
 * sliding window against a brute-force median (qsort of the window), the 95 %
 * interval's ranks against Campbell & Gardner's table (BMJ 1988: n = 9 ->
 * 2nd and 8th, n = 20 -> 6th and 15th) and their binomial coverage, the
 * minimum count, the hysteresis of the applied value, unreliable strikes and
 * strikes without 0S2 or fit ignored, and the error cases. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "af_test.h"
#include "factor_learn.h"

#define E2_PA 8.0e6 /* any fitted E2: the strikes below give E(0S2) = x E2 */

static af_factor_learn_config config(size_t window, size_t min_strikes)
{
  af_factor_learn_config c = {window, min_strikes, false, 0.01, 1.0, 0.1, 10.0};
  return c;
}

/* A reliable strike whose true factor is x, measured with factor 1. */
static void push(af_factor_learn *f, double x, bool *changed)
{
  AF_CHECK_STATUS(af_factor_learn_push(f, true, x * E2_PA, E2_PA, 1.0, changed), AF_OK);
}

static void test_median(void)
{
  af_factor_learn_config c = config(10, 1);
  af_factor_learn *f;
  AF_CHECK_STATUS(af_factor_learn_create(&c, &f), AF_OK);
  const double x[] = {1.10, 0.90, 1.00, 1.30, 0.95};
  for (size_t k = 0; k < 5; k++)
    push(f, x[k], NULL);
  const af_factor_learn_state *s = af_factor_learn_get(f);
  AF_CHECK(s->n == 5 && s->taken == 5 && s->refused == 0);
  AF_CHECK_ABS(s->estimate, 1.00, 1e-12); /* 0.90 0.95 [1.00] 1.10 1.30 */
  push(f, 1.05, NULL);
  AF_CHECK_ABS(s->estimate, 1.025, 1e-12); /* (1.00 + 1.05) / 2 */
  /* The factor in use is undone: E(0S2) = E_dyn / 4 measured with 4. */
  AF_CHECK_STATUS(af_factor_learn_push(f, true, 0.25 * 0.97 * E2_PA, E2_PA, 4.0, NULL), AF_OK);
  AF_CHECK_ABS(s->estimate, 1.00, 1e-12);         /* 0.90 0.95 0.97 [1.00] 1.05 1.10 1.30 */
  AF_CHECK(s->applied == 1.0 && s->changes == 0); /* apply off: never changes */
  af_factor_learn_reset(f);
  AF_CHECK(s->n == 0 && isnan(s->estimate) && s->applied == 1.0);
  af_factor_learn_destroy(f);
}

static int cmp(const void *a, const void *b)
{
  double x = *(const double *)a, y = *(const double *)b;
  return (x > y) - (x < y);
}

/* The window: the newest w values; compared with qsort of them. */
static void test_window(void)
{
  af_factor_learn_config c = config(3, 1);
  af_factor_learn *f;
  AF_CHECK_STATUS(af_factor_learn_create(&c, &f), AF_OK);
  const af_factor_learn_state *s = af_factor_learn_get(f);
  for (int k = 1; k <= 5; k++)
    push(f, k, NULL);
  AF_CHECK(s->n == 3);
  AF_CHECK_ABS(s->estimate, 4.0, 1e-12); /* 3 4 5 */
  push(f, 9.0, NULL);
  push(f, 9.0, NULL);
  AF_CHECK_ABS(s->estimate, 9.0, 1e-12); /* 5 9 9 */
  af_factor_learn_destroy(f);

  enum { W = 37, N = 2000 };
  c = config(W, 1);
  AF_CHECK_STATUS(af_factor_learn_create(&c, &f), AF_OK);
  s = af_factor_learn_get(f);
  static double seq[N];
  unsigned bad = 0;
  srand(19);
  for (int k = 0; k < N; k++) {
    /* ties on purpose: values on a coarse grid */
    seq[k] = 0.5 + (double)(rand() % 64) / 64.0;
    push(f, seq[k], NULL);
    int first = k + 1 >= W ? k + 1 - W : 0, n = k + 1 - first;
    double win[W];
    memcpy(win, seq + first, (size_t)n * sizeof *win);
    qsort(win, (size_t)n, sizeof *win, cmp);
    double med = n % 2 ? win[n / 2] : 0.5 * (win[n / 2 - 1] + win[n / 2]);
    size_t lo, hi;
    af_factor_learn_ci_ranks((size_t)n, &lo, &hi);
    bad += s->estimate != med || s->ci_low_95 != win[lo - 1] || s->ci_high_95 != win[hi - 1];
  }
  AF_CHECK(bad == 0);
  af_factor_learn_destroy(f);
}

/* P(lo <= B <= hi - 1), B ~ Binomial(n, 1/2): the coverage of [x_lo, x_hi]. */
static double coverage(size_t n, size_t lo, size_t hi)
{
  double p = 0.0;
  for (size_t k = lo; k < hi; k++)
    p += exp(lgamma(n + 1.0) - lgamma(k + 1.0) - lgamma((double)(n - k) + 1.0) - n * log(2.0));
  return p;
}

static void test_interval(void)
{
  size_t lo, hi;
  af_factor_learn_ci_ranks(9, &lo, &hi);
  AF_CHECK(lo == 2 && hi == 8); /* Campbell & Gardner, n = 9 */
  af_factor_learn_ci_ranks(20, &lo, &hi);
  AF_CHECK(lo == 6 && hi == 15); /* n = 20 */
  af_factor_learn_ci_ranks(1, &lo, &hi);
  AF_CHECK(lo == 1 && hi == 1);
  double worst = 1.0, widest = 0.0;
  for (size_t n = 5; n <= 1000; n++) {
    af_factor_learn_ci_ranks(n, &lo, &hi);
    double p = coverage(n, lo, hi);
    worst = p < worst ? p : worst;
    widest = n >= 30 && p > widest ? p : widest;
  }
  AF_CHECK(worst >= 0.9375 - 1e-9); /* 95 % nominal: n = 5 gives the whole sample, 15/16 */
  AF_CHECK(widest <= 0.9850);       /* not trivially wide once n >= 30 (worst 0.980) */

  af_factor_learn_config c = config(20, 1);
  af_factor_learn *f;
  AF_CHECK_STATUS(af_factor_learn_create(&c, &f), AF_OK);
  const double x[] = {1.09, 0.91, 1.05, 0.93, 1.01, 0.99, 1.07, 0.95, 1.03};
  for (size_t k = 0; k < 9; k++)
    push(f, x[k], NULL);
  const af_factor_learn_state *s = af_factor_learn_get(f);
  /* sorted 0.91 [0.93] 0.95 0.99 (1.01) 1.03 1.05 [1.07] 1.09 */
  AF_CHECK_ABS(s->estimate, 1.01, 1e-12);
  AF_CHECK_ABS(s->ci_low_95, 0.93, 1e-12);
  AF_CHECK_ABS(s->ci_high_95, 1.07, 1e-12);
  af_factor_learn_destroy(f);
}

/* Unreliable strikes, no 0S2 (no audio), no fit, nonsense: counted, never stored. */
static void test_refused(void)
{
  af_factor_learn_config c = config(10, 3);
  af_factor_learn *f;
  AF_CHECK_STATUS(af_factor_learn_create(&c, &f), AF_OK);
  const af_factor_learn_state *s = af_factor_learn_get(f);
  push(f, 1.2, NULL);
  push(f, 1.2, NULL);
  AF_CHECK(s->n == 2 && isnan(s->estimate) && isnan(s->ci_low_95)); /* below min_strikes */
  AF_CHECK_STATUS(af_factor_learn_push(f, false, 5.0 * E2_PA, E2_PA, 1.0, NULL), AF_OK);
  AF_CHECK_STATUS(af_factor_learn_push(f, true, NAN, E2_PA, 1.0, NULL), AF_OK);
  AF_CHECK_STATUS(af_factor_learn_push(f, true, E2_PA, NAN, 1.0, NULL), AF_OK);
  AF_CHECK_STATUS(af_factor_learn_push(f, true, E2_PA, 0.0, 1.0, NULL), AF_OK);
  AF_CHECK_STATUS(af_factor_learn_push(f, true, -E2_PA, E2_PA, 1.0, NULL), AF_OK);
  AF_CHECK(s->n == 2 && s->refused == 5 && s->taken == 2 && isnan(s->estimate));
  push(f, 0.1, NULL);
  AF_CHECK(s->n == 3);
  AF_CHECK_ABS(s->estimate, 1.2, 1e-12); /* 0.1 [1.2] 1.2: the 5.0 never came in */
  AF_CHECK_STATUS(af_factor_learn_push(NULL, true, E2_PA, E2_PA, 1.0, NULL), AF_EINVAL);
  af_factor_learn_destroy(f);
}

/* The applied value moves only by more than min_change, within the range. */
static void test_hysteresis(void)
{
  af_factor_learn_config c = config(1, 1); /* window 1: the estimate is the last value */
  c.apply = true;
  c.min_change = 0.05;
  af_factor_learn *f;
  AF_CHECK_STATUS(af_factor_learn_create(&c, &f), AF_OK);
  const af_factor_learn_state *s = af_factor_learn_get(f);
  bool changed = true;
  AF_CHECK(s->applied == 1.0 && isnan(s->previous));
  push(f, 1.04, &changed); /* 4 % < 5 % */
  AF_CHECK(!changed && s->applied == 1.0 && s->changes == 0);
  push(f, 1.06, &changed); /* 6 % */
  AF_CHECK(changed && s->applied == 1.06 && s->previous == 1.0 && s->changes == 1);
  push(f, 1.10, &changed); /* 3.8 % from 1.06 */
  AF_CHECK(!changed && s->applied == 1.06);
  push(f, 1.12, &changed); /* 5.7 % */
  AF_CHECK(changed && s->applied == 1.12 && s->changes == 2);
  push(f, 0.98, &changed); /* down 12.5 % */
  AF_CHECK(changed && s->applied == 0.98 && s->previous == 1.12 && s->changes == 3);
  push(f, 20.0, &changed); /* outside [0.1, 10]: published, never applied */
  AF_CHECK(!changed && s->applied == 0.98 && s->estimate == 20.0);
  AF_CHECK_STATUS(af_factor_learn_push(f, false, 2.0 * E2_PA, E2_PA, 1.0, &changed), AF_OK);
  AF_CHECK(!changed && s->applied == 0.98); /* an unreliable strike moves nothing */
  af_factor_learn_reset(f);
  AF_CHECK(s->applied == 1.0 && s->changes == 0);
  af_factor_learn_destroy(f);
}

static void test_errors(void)
{
  af_factor_learn *f = (af_factor_learn *)&f;
  af_factor_learn_config c = config(10, 11); /* min above the window */
  AF_CHECK_STATUS(af_factor_learn_create(&c, &f), AF_EINVAL);
  AF_CHECK(f == NULL);
  c = config(0, 1);
  AF_CHECK_STATUS(af_factor_learn_create(&c, &f), AF_EINVAL);
  c = config(10, 1);
  c.initial_factor = 0.0;
  AF_CHECK_STATUS(af_factor_learn_create(&c, &f), AF_EINVAL);
  c = config(10, 1);
  c.min_change = NAN;
  AF_CHECK_STATUS(af_factor_learn_create(&c, &f), AF_EINVAL);
  AF_CHECK_STATUS(af_factor_learn_create(NULL, &f), AF_EINVAL);
  AF_CHECK_STATUS(af_factor_learn_create(&c, NULL), AF_EINVAL);
  AF_CHECK(af_factor_learn_get(NULL) == NULL);
  af_factor_learn_destroy(NULL);
  af_factor_learn_reset(NULL);
}

int main(void)
{
  test_median();
  test_window();
  test_interval();
  test_refused();
  test_hysteresis();
  test_errors();
  return af_test_summary("test_factor_learn");
}
