/* bench.c — `firmness_model bench`: full model evaluations (ODE + spectrum +
 * lobes + resonance + shear + criteria; the R2_min search excluded) per
 * second on one core, by the ODE path and by the fast path (fastpath.h)
 * side by side, on the given strike and on random strikes over the
 * designer's domain, and the heap the evaluations took (must be none). */
#define _POSIX_C_SOURCE 200809L
#include "bench.h"

#include <malloc.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "cli_flags.h"
#include "fastpath.h"
#include "options.h"
#include "report.h"
#include "settings.h"

static double now_s(void)
{
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static double cpu_s(void)
{
  struct timespec ts;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

#define AF_BENCH_SECONDS_MAX 600 /* [s] */

typedef struct {
  double seconds; /* CPU time of the four runs together [s] */
} af_bench_args;

static const af_bench_args bench_defaults = {2.0};

/* The bench's own flag; the model flags are cli_flags.c's. */
static const af_option bench_options[] = {
    {"--seconds", "S", AF_OPTION_NUMBER, offsetof(af_bench_args, seconds), -1,
     "(0, " AF_OPTION_STR(AF_BENCH_SECONDS_MAX) "] s", "time of the four runs together", NULL,
     false},
};
#define N_OPTIONS (sizeof bench_options / sizeof bench_options[0])

const af_option *af_bench_options(size_t *n)
{
  *n = N_OPTIONS;
  return bench_options;
}

static void bench_help(void)
{
  printf("usage: firmness_model bench [--seconds S] [model flags]\n\n"
         "Full model evaluations per second on one core, ODE path and fast path, on this\n"
         "strike and on 1000 random strikes, and the heap they took.\n\nflags:\n");
  af_options_help(stdout, bench_options, N_OPTIONS, &bench_defaults, NULL);
  printf("\nmodel flags (SI units):\n");
  af_cli_print_flags();
  printf("\nexit status: 0 done, 1 model failure, 2 bad input\n");
}

typedef af_status (*af_eval_fn)(void *ctx, const af_model_params *p, af_model_result *r);

static af_status eval_ode(void *ctx, const af_model_params *p, af_model_result *r)
{
  return af_model_execute(ctx, p, r);
}

static af_status eval_fast(void *ctx, const af_model_params *p, af_model_result *r)
{
  return af_fastpath_execute(ctx, p, r);
}

typedef struct {
  long n;
  double wall_s, cpu_s;
  long heap_bytes;
} af_bench_run;

/* Evaluates strikes[k % n_strikes] for `seconds` after one warm pass. */
static af_bench_run run(af_eval_fn fn, void *ctx, const af_model_params *strikes, int n_strikes,
                        double seconds)
{
  af_model_result r;
  af_bench_run b = {0, 0, 0, 0};
  for (int k = 0; k < n_strikes; k++)
    fn(ctx, &strikes[k], &r);
  struct mallinfo2 before = mallinfo2();
  double t0 = now_s(), c0 = cpu_s(), t1;
  int k = 0;
  do {
    for (int j = 0; j < 100; j++, k = k + 1 == n_strikes ? 0 : k + 1)
      fn(ctx, &strikes[k], &r);
    b.n += 100;
    t1 = now_s();
  } while (t1 - t0 < seconds);
  b.cpu_s = cpu_s() - c0;
  b.wall_s = t1 - t0;
  b.heap_bytes = (long)mallinfo2().uordblks - (long)before.uordblks;
  return b;
}

static void print_run(const char *name, const af_bench_run *b)
{
  printf("%-34s %10.0f   %8.2f us   %ld in %.2f s CPU, heap growth %ld B\n", name, b->n / b->cpu_s,
         1e6 * b->cpu_s / b->n, b->n, b->cpu_s, b->heap_bytes);
}

/* Random strikes over the designer's domain, from this strike's profile:
 * the apples of the parameter table's cultivar (modulus and mass ranges). */
#define AF_BENCH_DOMAIN 1000
static void domain_strikes(const af_model_params *p, af_model_params *out)
{
  af_settings s;
  af_settings_reset(&s);
  const double e_lo = af_settings_number(&s, AF_SETTING_MODULUS_MIN_PA);
  const double e_hi = af_settings_number(&s, AF_SETTING_MODULUS_MAX_PA);
  const double m_lo = af_settings_number(&s, AF_SETTING_MASS_MIN_KG);
  const double m_hi = af_settings_number(&s, AF_SETTING_MASS_MAX_KG);
  unsigned state = 7u;
  for (int k = 0; k < AF_BENCH_DOMAIN; k++) {
    double u[6];
    for (int j = 0; j < 6; j++) {
      state = state * 1103515245u + 12345u;
      u[j] = ((state >> 8) & 0xffffff) / 16777215.0;
    }
    out[k] = *p;
    out[k].impact.hammer_mass_kg = 0.002 + 0.048 * u[0];
    out[k].impact.velocity_m_s = 0.5 + 2.5 * u[1];
    out[k].impact.fruit_modulus_pa = e_lo + (e_hi - e_lo) * u[2];
    out[k].impact.strike_radius_m = 0.02 + 0.022 * u[3];
    out[k].fruit_mass_kg = m_lo + (m_hi - m_lo) * u[4];
    out[k].impact.hammer_radius_m = u[5] < 0.5 ? 0.0 : 0.005 + 0.03 * u[5];
  }
}

int af_bench_main(int argc, char **argv, int first)
{
  af_model_params p;
  af_model_result r;
  af_model *m = NULL;
  af_fastpath *f = NULL;
  if (af_options_want_help(argc, argv, first)) {
    bench_help();
    return 0;
  }
  af_bench_args a = bench_defaults;
  const af_option_set own = {bench_options, N_OPTIONS, &a, NULL, NULL};
  if (!af_cli_parse_model("firmness_model bench", &own, NULL, argc, argv, first, &p))
    return AF_CLI_EXIT_USAGE;
  const double seconds = a.seconds;
  if (af_model_create(&m) != AF_OK || af_model_execute(m, &p, &r) != AF_OK) {
    fprintf(stderr, "firmness_model bench: the model refuses this strike\n");
    af_model_destroy(m);
    return 1;
  }
  double build_s = 0.0; /* the table is the process's, built once (fastpath.h) */
  if (af_fastpath_table_build(&build_s) != AF_OK || af_fastpath_create(&f) != AF_OK) {
    fprintf(stderr, "firmness_model bench: cannot build the fast path's table\n");
    af_model_destroy(m);
    return 1;
  }
  static af_model_params domain[AF_BENCH_DOMAIN];
  domain_strikes(&p, domain);
  printf("full evaluations (pulse, spectrum, lobes, 0S2, shear, criteria), one core, CPU time\n");
  printf("%-34s %10s   %11s\n", "path", "evals/s", "per eval");
  af_bench_run ode = run(eval_ode, m, &p, 1, seconds / 4);
  print_run("ODE path, this strike", &ode);
  af_bench_run fast = run(eval_fast, f, &p, 1, seconds / 4);
  print_run("fast path, this strike", &fast);
  af_bench_run ode_d = run(eval_ode, m, domain, AF_BENCH_DOMAIN, seconds / 4);
  print_run("ODE path, 1000 random strikes", &ode_d);
  size_t t0n, f0n, t1n, f1n;
  af_fastpath_counts(f, &t0n, &f0n);
  af_bench_run fast_d = run(eval_fast, f, domain, AF_BENCH_DOMAIN, seconds / 4);
  af_fastpath_counts(f, &t1n, &f1n);
  print_run("fast path, 1000 random strikes", &fast_d);
  printf("speed-up             %.1fx on this strike, %.1fx on the random strikes\n",
         (fast.n / fast.cpu_s) / (ode.n / ode.cpu_s),
         (fast_d.n / fast_d.cpu_s) / (ode_d.n / ode_d.cpu_s));
  printf("fast path fallbacks  %.1f %% of the random strikes went to the ODE path\n",
         100.0 * (double)(f1n - f0n) / (double)((t1n - t0n) + (f1n - f0n)));
  printf("table build          %.3f s CPU (once, at start-up)\n", build_s);
  printf("pulse samples        %zu, lobes %zu\n", r.impact.n_samples, r.n_lobes);
  af_fastpath_destroy(f);
  af_model_destroy(m);
  return 0;
}
