/* strike_prime.c — af_strike_prime: the detector's trackers set from robust
 * statistics of a whole recording (median and quiet-part RMS), so that an
 * offline recording is measured from its first sample with no warm-up
 * (strike.h says when to use it). */
#include "strike.h"

#include <math.h>

#include "strike_private.h"

/* At least this many quiet samples (of the AF_STRIKE_PRIME_SAMPLES at most
 * taken), else all finite ones are used. */
#define AF_STRIKE_PRIME_MIN 16
/* Normal consistency of the median absolute deviation. */
#define AF_STRIKE_MAD_TO_SIGMA 1.482602218505602

static void swap(double *a, double *b)
{
  double t = *a;
  *a = *b;
  *b = t;
}

/* The k-th smallest of v[0..n) (k < n), v reordered in place (Wirth's
 * selection). No allocation (qsort may allocate). */
static double select_kth(double *v, size_t n, size_t k)
{
  long lo = 0, hi = (long)n - 1, kk = (long)k;
  while (lo < hi) {
    double pivot = v[kk];
    long i = lo, j = hi;
    do {
      while (v[i] < pivot)
        i++;
      while (pivot < v[j])
        j--;
      if (i <= j) {
        swap(&v[i], &v[j]);
        i++;
        j--;
      }
    } while (i <= j);
    if (j < kk)
      lo = i;
    if (kk < i)
      hi = j;
  }
  return v[kk];
}

/* Median of v[0..n), n > 0 (the lower one for an even n); v reordered. */
static double median(double *v, size_t n)
{
  return select_kth(v, n, (n - 1) / 2);
}

/* Every stride-th finite sample of x[0..n) into ws, leaving out those within
 * `guard` samples of a loud one (|x - centre| > loud; none when loud is
 * +inf). Returns the count. */
static size_t prime_gather(const float *x, size_t n, size_t stride, double centre, double loud,
                           size_t guard, double *ws)
{
  size_t m = 0, scanned = 0;
  bool any_loud = false;
  size_t last_loud = 0; /* the latest loud sample before `scanned` */
  for (size_t k = 0; k < n && m < AF_STRIKE_PRIME_SAMPLES; k += stride) {
    size_t ahead = n - k > guard ? k + guard + 1 : n;
    for (; scanned < ahead; scanned++) {
      if (fabs((double)x[scanned] - centre) > loud) {
        any_loud = true;
        last_loud = scanned;
      }
    }
    if (any_loud && last_loud + guard >= k)
      continue; /* a loud sample within guard of k, before or after */
    if (isfinite(x[k]))
      ws[m++] = x[k];
  }
  return m;
}

af_status af_strike_prime(af_strike *d, const float *x, size_t n)
{
  if (d == NULL || (x == NULL && n > 0))
    return AF_EINVAL;
  size_t stride = n / AF_STRIKE_PRIME_SAMPLES + (n % AF_STRIKE_PRIME_SAMPLES != 0);
  size_t m = n > 0 ? prime_gather(x, n, stride, 0.0, INFINITY, 0, d->prime_ws) : 0;
  if (m < AF_STRIKE_PRIME_MIN)
    return AF_ENODATA; /* the detector is left as it was */
  /* First pass, all finite samples: median and MAD. */
  double centre = median(d->prime_ws, m);
  for (size_t i = 0; i < m; i++)
    d->prime_ws[i] = fabs(d->prime_ws[i] - centre);
  double sigma = AF_STRIKE_MAD_TO_SIGMA * median(d->prime_ws, m);
  /* Second pass, the quiet parts: away from every sample beyond the release
   * level the first pass gives (strikes, bounces, their ringing). */
  double thr = fmax(d->cfg.threshold_noise_factor * sigma, d->cfg.threshold_min_n);
  size_t guard = d->window + d->quiet_needed;
  size_t q = prime_gather(x, n, stride, centre, AF_STRIKE_RELEASE * thr, guard, d->prime_ws);
  double baseline = centre, mean_square = sigma * sigma;
  if (q >= AF_STRIKE_PRIME_MIN && 4 * q >= m) { /* else too little quiet signal: the MAD's */
    baseline = median(d->prime_ws, q);
    double sum2 = 0.0;
    for (size_t i = 0; i < q; i++)
      sum2 += (d->prime_ws[i] - baseline) * (d->prime_ws[i] - baseline);
    mean_square = sum2 / (double)q;
  }
  af_strike_reset(d);
  d->baseline_n = baseline;
  d->mean_square = mean_square;
  d->learned = d->warmup;
  d->primed = true;
  arm(d, 0);
  d->rec.armed_at = 0; /* until the first write says where the stream starts */
  return AF_OK;
}
