/* response_chol.h — the Cholesky factor and solve of the response's small
 * normal equations (at most 14 x 14: the variable projection's linear
 * parameters, the Levenberg-Marquardt steps), inlined into their callers so
 * that the loops take the callers' constant sizes, and unrolled there (GCC
 * leaves these triangular loops rolled without the pragma: 8 k instructions
 * a strike on the 600-strike line bag; the same operations in the same
 * order). Private to the module. */
#ifndef AF_RESPONSE_CHOL_H
#define AF_RESPONSE_CHOL_H

#include <math.h>
#include <stddef.h>

#include "response_private.h" /* AF_NUMERIC_KERNEL */

/* Solves l l^T x = b in place in x (l: Cholesky factor, lower, n x n). */
AF_NUMERIC_KERNEL static inline __attribute__((always_inline)) void
af_response_chol_solve(const double *l, size_t n, double *x)
{
#pragma GCC unroll 16
  for (size_t i = 0; i < n; ++i) {
    double s = x[i];
#pragma GCC unroll 16
    for (size_t k = 0; k < i; ++k)
      s -= l[i * n + k] * x[k];
    x[i] = s / l[i * n + i];
  }
#pragma GCC unroll 16
  for (size_t i = n; i-- > 0;) {
    double s = x[i];
#pragma GCC unroll 16
    for (size_t k = i + 1; k < n; ++k)
      s -= l[k * n + i] * x[k];
    x[i] = s / l[i * n + i];
  }
}

/* m (n x n, symmetric, upper triangle read) into its Cholesky factor, lower;
 * 0 if not positive definite. */
AF_NUMERIC_KERNEL static inline __attribute__((always_inline)) int
af_response_chol_factor(double *m, size_t n)
{
#pragma GCC unroll 16
  for (size_t j = 0; j < n; ++j) {
    double d = m[j * n + j];
#pragma GCC unroll 16
    for (size_t k = 0; k < j; ++k)
      d -= m[j * n + k] * m[j * n + k];
    if (!(d > 0.0))
      return 0;
    d = sqrt(d);
    m[j * n + j] = d;
#pragma GCC unroll 16
    for (size_t i = j + 1; i < n; ++i) {
      double s = m[j * n + i];
#pragma GCC unroll 16
      for (size_t k = 0; k < j; ++k)
        s -= m[i * n + k] * m[j * n + k];
      m[i * n + j] = s / d;
    }
  }
  return 1;
}

#endif
