/* test_response_mode.c — one damped mode's spectrum as the window holds it
 * (af_response_mode_at, what the peak list subtracts) against the DFT of its
 * windowed samples summed here term by term: the ringing
 * c z^k + conj(c) conj(z)^k, k < m, weighted by the fade-in's raised cosine
 * (1 - cos(pi (k + 1/2) / L)) / 2 for k < L and 1 beyond, at bin i
 *   X_i = sum_k w_k (c (z u_i)^k + conj(c) (conj(z) u_i)^k),
 *   u_i = exp(-2 pi i i / N).
 * Modes from 40 to 1,500 bins, windowed decay rates 55-600 1/s, analysed
 * lengths 600-4,096 samples, with the default 1 ms fade-in and without one;
 * every bin of the peak's neighbourhood and a stride over the rest of the
 * spectrum (the skirt and the cut's ripple the subtraction must remove). The
 * closed form over one denominator must agree with the sum to 1e-12 of the
 * mode's peak |X| (rounding of the ~4,000-term sum), and with the fade-in's
 * three geometric sums it rearranges (af_response_mode_at_sums) to 1e-13.
 * The peak list's subtraction two bins at a time (af_response_mode_subtract)
 * must give the same doubles as af_response_mode_at bin by bin. */
#include <complex.h>
#include <math.h>
#include <stdio.h>

#include "af_test.h"
#include "response_private.h"

static af_test_rng rng = {20261129u};
/* check_subtract's own draws: the closed form's checks keep their modes */
static af_test_rng rng_sub = {20261130u};

/* The fade-in's weight at sample k of L (1 beyond), as response.h defines it. */
static double fade_weight(size_t k, size_t length)
{
  if (k >= length)
    return 1.0;
  return 0.5 * (1.0 - cos(AF_PI * ((double)k + 0.5) / (double)length));
}

/* The DFT at bin i of the mode's m windowed samples, term by term. */
static double complex mode_sum(double complex c, double complex z, size_t m, size_t fade,
                               size_t n_fft, size_t i)
{
  double complex u = cexp(-I * 2.0 * AF_PI * (double)i / (double)n_fft);
  double complex a = z * u, ac = conj(z) * u, ak = 1.0, ack = 1.0, sum = 0.0;
  for (size_t k = 0; k < m; ++k) {
    sum += fade_weight(k, fade) * (c * ak + conj(c) * ack);
    ak *= a;
    ack *= ac;
  }
  return sum;
}

/* One mode at a random bin, decay and amplitude over m analysed samples on
 * r's grid; the worst deviations (relative to the peak |X|) raised into
 * *worst_sum (against mode_sum) and *worst_sums (against the three sums). */
static void check_mode(af_response *r, size_t m, double *worst_sum, double *worst_sums)
{
  size_t n_fft = r->cfg.fft_size;
  af_peak pk = {0};
  pk.bin = 40.0 + 1460.0 * af_test_uniform(&rng);
  pk.sigma_windowed = 55.0 + 545.0 * af_test_uniform(&rng);
  pk.c = (0.2 + af_test_uniform(&rng)) * cexp(I * 2.0 * AF_PI * af_test_uniform(&rng));
  r->split_len = (double)m;
  for (size_t i = 0; i < r->bins; ++i)
    r->phase_um[i] = af_response_phase(i, n_fft, (double)m);
  af_mode_k q = af_response_mode_consts(r, &pk);
  double peak = cabs(pk.c) / (1.0 - cabs(q.z));
  size_t k0 = (size_t)pk.bin;
  for (size_t i = 1; i + 1 < r->bins; i += (i + 40 > k0 && i < k0 + 40) ? 1 : 97) {
    double complex got = af_response_mode_at(r, &q, i);
    double complex want = mode_sum(pk.c, q.z, m, r->fade_samples, n_fft, i);
    *worst_sum = fmax(*worst_sum, cabs(got - want) / peak);
    *worst_sums = fmax(*worst_sums, cabs(got - af_response_mode_at_sums(r, &q, i)) / peak);
  }
}

/* af_response_mode_subtract (two bins at a time) against r->spec less
 * af_response_mode_at bin by bin: the same doubles, spectrum and power, over
 * a range of odd length (the last bin alone); mismatching bins counted into
 * *mismatches. */
static void check_subtract(af_response *r, size_t m, size_t *mismatches)
{
  af_peak pk = {0};
  pk.bin = 40.0 + 1460.0 * af_test_uniform(&rng_sub);
  pk.sigma_windowed = 55.0 + 545.0 * af_test_uniform(&rng_sub);
  pk.c = (0.2 + af_test_uniform(&rng_sub)) * cexp(I * 2.0 * AF_PI * af_test_uniform(&rng_sub));
  r->split_len = (double)m;
  size_t lo = (size_t)pk.bin > 100 ? (size_t)pk.bin - 100 : 1, hi = lo + 200;
  for (size_t i = lo; i <= hi; ++i) {
    r->phase_um[i] = af_response_phase(i, r->cfg.fft_size, (double)m);
    r->spec[i] = af_test_uniform(&rng_sub) - 0.5 + I * (af_test_uniform(&rng_sub) - 0.5);
    r->work[i] = r->spec[i];
  }
  af_mode_k q = af_response_mode_consts(r, &pk);
  af_response_mode_subtract(r, &q, lo, hi);
  for (size_t i = lo; i <= hi; ++i) {
    double complex want = r->work[i] - af_response_mode_at(r, &q, i);
    double power = creal(want * conj(want));
    if (!(creal(r->spec[i]) == creal(want) && cimag(r->spec[i]) == cimag(want) &&
          r->power[i] == power))
      ++*mismatches;
  }
}

static void test_config(double fade_in_s, const char *label)
{
  af_response_config cfg = af_response_config_default();
  cfg.fade_in_s = fade_in_s;
  af_response *r = NULL;
  AF_CHECK_STATUS(af_response_create(&cfg, &r), AF_OK);
  if (r == NULL)
    return;
  const size_t lengths[] = {600, 1777, 3000, 4096};
  double worst_sum = 0.0, worst_sums = 0.0;
  for (size_t j = 0; j < sizeof lengths / sizeof lengths[0]; ++j)
    for (int t = 0; t < 6; ++t)
      check_mode(r, lengths[j], &worst_sum, &worst_sums);
  printf(
      "%s (fade-in %zu samples): worst |closed form - sum| %.2e, - three sums %.2e of the peak\n",
      label, r->fade_samples, worst_sum, worst_sums);
  AF_CHECK(worst_sum <= 1e-12);
  AF_CHECK(worst_sums <= 1e-13);
  size_t mismatches = 0;
  for (size_t j = 0; j < sizeof lengths / sizeof lengths[0]; ++j)
    for (int t = 0; t < 6; ++t)
      check_subtract(r, lengths[j], &mismatches);
  printf("%s: the subtraction two bins at a time, bins differing from one at a time: %zu\n", label,
         mismatches);
  AF_CHECK(mismatches == 0);
  af_response_destroy(r);
}

int main(void)
{
  test_config(0.001, "default window");
  test_config(0.0, "no fade-in");
  return af_test_summary("test_response_mode");
}
