/* median.h — the median of a few values (a lane's latest strikes), without
 * touching them and without allocation. */
#ifndef AF_MEDIAN_H
#define AF_MEDIAN_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

#define AF_MEDIAN_SMALL_MAX 64 /* values af_median_small takes at most */

/* The median of x[0..n) (the mean of the two middle ones for an even n);
 * NaN for n 0 or above AF_MEDIAN_SMALL_MAX. x is left as it is. */
double af_median_small(const double *x, size_t n);

#ifdef __cplusplus
}
#endif
#endif
