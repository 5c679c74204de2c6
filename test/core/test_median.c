/* test_median.c — af_median_small against medians worked by hand. */
#include <math.h>

#include "af_test.h"
#include "median.h"

int main(void)
{
  const double odd[] = {5.0, -1.0, 3.0, 3.0, 10.0}; /* sorted: -1 3 3 5 10 */
  const double even[] = {0.4, 0.1, 0.3, 0.2};       /* sorted: 0.1 0.2 0.3 0.4 */
  AF_CHECK(af_median_small(odd, 5) == 3.0);
  AF_CHECK_ABS(af_median_small(even, 4), 0.25, 1e-15);
  AF_CHECK(af_median_small(odd, 1) == 5.0);
  AF_CHECK(odd[0] == 5.0 && odd[1] == -1.0 && even[0] == 0.4); /* left as they were */
  AF_CHECK(isnan(af_median_small(odd, 0)) && isnan(af_median_small(NULL, 3)));
  double many[AF_MEDIAN_SMALL_MAX + 1];
  for (int k = 0; k <= AF_MEDIAN_SMALL_MAX; k++)
    many[k] = (double)(AF_MEDIAN_SMALL_MAX - k);                /* 64 .. 0 */
  AF_CHECK(af_median_small(many, AF_MEDIAN_SMALL_MAX) == 32.5); /* 64 .. 1 */
  AF_CHECK(isnan(af_median_small(many, AF_MEDIAN_SMALL_MAX + 1)));
  return af_test_summary("test_median");
}
