/* af_test.h — the core tests' minimal harness: checks with tolerances in
 * stated units, one line per failure, a summary line "N passed, M failed". */
#ifndef AF_TEST_H
#define AF_TEST_H

#include <math.h>
#include <stdint.h>
#include <stdio.h>

static int af_test_passed;
static int af_test_failed;

#define AF_CHECK(cond)                                                                             \
  do {                                                                                             \
    if (cond) {                                                                                    \
      af_test_passed++;                                                                            \
    } else {                                                                                       \
      af_test_failed++;                                                                            \
      fprintf(stderr, "%s:%d: FAIL %s\n", __FILE__, __LINE__, #cond);                              \
    }                                                                                              \
  } while (0)

/* |actual - expected| <= rel_tol |expected| */
#define AF_CHECK_REL(actual, expected, rel_tol)                                                    \
  do {                                                                                             \
    double a_ = (actual), e_ = (expected), t_ = (rel_tol);                                         \
    if (isfinite(a_) && fabs(a_ - e_) <= t_ * fabs(e_)) {                                          \
      af_test_passed++;                                                                            \
    } else {                                                                                       \
      af_test_failed++;                                                                            \
      fprintf(stderr, "%s:%d: FAIL %s = %.9g, expected %.9g within %.3g %% (off by %.3g %%)\n",    \
              __FILE__, __LINE__, #actual, a_, e_, 100.0 * t_, 100.0 * fabs(a_ - e_) / fabs(e_));  \
    }                                                                                              \
  } while (0)

/* |actual - expected| <= abs_tol */
#define AF_CHECK_ABS(actual, expected, abs_tol)                                                    \
  do {                                                                                             \
    double a_ = (actual), e_ = (expected), t_ = (abs_tol);                                         \
    if (isfinite(a_) && fabs(a_ - e_) <= t_) {                                                     \
      af_test_passed++;                                                                            \
    } else {                                                                                       \
      af_test_failed++;                                                                            \
      fprintf(stderr, "%s:%d: FAIL %s = %.9g, expected %.9g within %.3g\n", __FILE__, __LINE__,    \
              #actual, a_, e_, t_);                                                                \
    }                                                                                              \
  } while (0)

#define AF_CHECK_STATUS(call, expected)                                                            \
  do {                                                                                             \
    int s_ = (int)(call);                                                                          \
    if (s_ == (int)(expected)) {                                                                   \
      af_test_passed++;                                                                            \
    } else {                                                                                       \
      af_test_failed++;                                                                            \
      fprintf(stderr, "%s:%d: FAIL %s returned %d, expected %d\n", __FILE__, __LINE__, #call, s_,  \
              (int)(expected));                                                                    \
    }                                                                                              \
  } while (0)

/* Prints the summary and gives main's exit status. */
static inline int af_test_summary(const char *name)
{
  printf("%s: %d passed, %d failed\n", name, af_test_passed, af_test_failed);
  return af_test_failed == 0 && af_test_passed > 0 ? 0 : 1;
}

/* Seeded test noise independent of the package's synth (synth.c):
 * splitmix64 for uniforms in (0, 1), Box-Muller for normals. One
 * generator per test file: static af_test_rng rng = {SEED}. */
typedef struct {
  uint64_t state;
} af_test_rng;

static inline double af_test_uniform(af_test_rng *g)
{
  uint64_t z = (g->state += 0x9e3779b97f4a7c15ULL);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return ((double)((z ^ (z >> 31)) >> 11) + 0.5) / 9007199254740992.0;
}

static inline double af_test_gauss(af_test_rng *g)
{
  return sqrt(-2.0 * log(af_test_uniform(g))) *
         cos(2.0 * 3.14159265358979323846 * af_test_uniform(g));
}

#endif
