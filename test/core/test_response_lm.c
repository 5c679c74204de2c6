/* test_response_lm.c — the response fits' stop at a cost (af_fit_ctx's
 * cost_stop, response_lm.c): the peak list's split asks of a one-pole fit
 * beside a neighbour only whether its minimum lies under a misfit, and ends
 * the fit once a point's cost is under it. Checked against the same fit run
 * to its own end: one damped mode as the window holds it
 * (af_response_mode_at) plus gaussian noise 30 dB under its peak, fitted by
 * the truncated one-pole model from a start 0.4 bin and 30 % off:
 *  - a stop between the start's cost and the full fit's: the stopped fit ends
 *    at a cost at most the stop and at least the full fit's minimum, in
 *    fewer iterations;
 *  - a stop under the full fit's minimum: the same fit, bit for bit (its
 *    cost and its poles);
 *  - a stop above the start's cost: no step, the start's cost. */
#include <complex.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "af_test.h"
#include "response_private.h"

static af_test_rng rng = {20261129u};

/* The fit's iterations so far (every status). */
static size_t iterations(const af_response *r)
{
  return r->fit_stats.iterations;
}

/* One one-pole fit of r->ctx from x0 with the stop cost_stop; its cost into
 * *rss, its iterations into *iter, its parameters into x. */
static int fit(af_response *r, const double *x0, double cost_stop, double *x, double *rss,
               size_t *iter)
{
  size_t before = iterations(r);
  r->ctx.cost_stop = cost_stop;
  memcpy(x, x0, AF_RESPONSE_SPLIT_PARAMS * sizeof *x);
  int ok = af_response_split_run(r, 1, x, rss);
  memcpy(x, r->split_x, AF_RESPONSE_SPLIT_PARAMS * sizeof *x);
  r->ctx.cost_stop = 0.0;
  *iter = iterations(r) - before;
  return ok;
}

/* One mode at a random bin on r's grid, m analysed samples; the checks. */
static void check_mode(af_response *r, size_t m)
{
  size_t n_fft = r->cfg.fft_size;
  af_peak pk = {0};
  pk.bin = 100.0 + 800.0 * af_test_uniform(&rng);
  pk.sigma_windowed = 80.0 + 300.0 * af_test_uniform(&rng);
  pk.c = (0.5 + af_test_uniform(&rng)) * cexp(I * 2.0 * AF_PI * af_test_uniform(&rng));
  r->split_len = (double)m;
  for (size_t i = 0; i < r->bins; ++i)
    r->phase_um[i] = af_response_phase(i, n_fft, (double)m);
  af_mode_k q = af_response_mode_consts(r, &pk);
  double noise_rms = 0.03 * cabs(pk.c) / (1.0 - cabs(q.z)); /* 30 dB under the peak */
  size_t k = (size_t)lround(pk.bin), half = 20;
  for (size_t i = k - 3 * half; i <= k + 3 * half; ++i)
    r->spec[i] = af_response_mode_at(r, &q, i) +
                 noise_rms * (af_test_gauss(&rng) + I * af_test_gauss(&rng)) / sqrt(2.0);
  AF_CHECK(af_response_fit_bins(r, r->spec, k - half, k + half, (double)k, (double)half, k,
                                pk.sigma_windowed));
  double x0[AF_RESPONSE_SPLIT_PARAMS] = {0.0}, x_full[AF_RESPONSE_SPLIT_PARAMS];
  double x_stop[AF_RESPONSE_SPLIT_PARAMS];
  af_response_fit_seed(r, x0, 0, pk.bin + 0.4, 1.3 * pk.sigma_windowed, pk.c);
  double theta[2] = {x0[0], x0[1]}, beta[AF_RESPONSE_SPLIT_PARAMS], start = NAN;
  r->split_poles = 1;
  AF_CHECK(af_response_fit_eval(r, theta, &start, NULL, NULL, beta));
  double full = NAN, stopped = NAN;
  size_t it_full = 0, it_stop = 0;
  AF_CHECK(fit(r, x0, 0.0, x_full, &full, &it_full));
  AF_CHECK(full < start && it_full >= 2);
  /* between the start and the minimum */
  double stop = sqrt(start * full);
  AF_CHECK(fit(r, x0, stop, x_stop, &stopped, &it_stop));
  AF_CHECK(stopped <= stop && stopped >= full);
  AF_CHECK(it_stop < it_full);
  /* under the minimum: the full fit */
  AF_CHECK(fit(r, x0, 0.5 * full, x_stop, &stopped, &it_stop));
  AF_CHECK(stopped == full && it_stop == it_full);
  AF_CHECK(memcmp(x_stop, x_full, 2 * sizeof *x_full) == 0);
  /* above the start: no step */
  AF_CHECK(fit(r, x0, 2.0 * start, x_stop, &stopped, &it_stop));
  AF_CHECK(stopped == start && it_stop == 0);
}

int main(void)
{
  af_response_config cfg = af_response_config_default();
  af_response *r = NULL;
  AF_CHECK_STATUS(af_response_create(&cfg, &r), AF_OK);
  if (r == NULL)
    return af_test_summary("test_response_lm");
  const size_t lengths[] = {1000, 2500, 4096};
  for (size_t j = 0; j < sizeof lengths / sizeof lengths[0]; ++j)
    for (int t = 0; t < 4; ++t)
      check_mode(r, lengths[j]);
  printf("12 fits: the stop between start and minimum ends fewer iterations in, at or under "
         "it and over the minimum; under the minimum the full fit; over the start no step\n");
  af_response_destroy(r);
  return af_test_summary("test_response_lm");
}
