/* median.c — the median of a few values (see median.h). */
#include "median.h"

#include <math.h>
#include <string.h>

double af_median_small(const double *x, size_t n)
{
  double y[AF_MEDIAN_SMALL_MAX];
  if (x == NULL || n == 0 || n > AF_MEDIAN_SMALL_MAX)
    return NAN;
  memcpy(y, x, n * sizeof *y);
  for (size_t i = 1; i < n; i++) /* insertion sort: n is small */
    for (size_t j = i; j > 0 && y[j - 1] > y[j]; j--) {
      const double t = y[j];
      y[j] = y[j - 1];
      y[j - 1] = t;
    }
  return n % 2 ? y[n / 2] : 0.5 * (y[n / 2 - 1] + y[n / 2]);
}
