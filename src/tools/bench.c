/* bench.c — `firmness_model bench`: full model evaluations (ODE + spectrum +
 * lobes + resonance + shear + criteria; the R2_min search excluded) per
 * second on one core, and the heap the evaluations took (must be none). */
#define _POSIX_C_SOURCE 200809L
#include "bench.h"

#include <malloc.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "cli_flags.h"
#include "report.h"

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

static bool parse_seconds(char **argv, const int *rest, int n_rest, double *seconds)
{
  for (int k = 0; k < n_rest; k++) {
    char *end;
    if (strcmp(argv[rest[k]], "--seconds") != 0 || k + 1 >= n_rest || rest[k + 1] != rest[k] + 1) {
      fprintf(stderr, "firmness_model bench: unknown argument '%s'\n", argv[rest[k]]);
      return false;
    }
    *seconds = strtod(argv[rest[++k]], &end);
    if (*end != '\0' || !(*seconds > 0.0 && *seconds <= 600.0)) {
      fprintf(stderr, "firmness_model bench: --seconds '%s' must be in (0, 600]\n", argv[rest[k]]);
      return false;
    }
  }
  return true;
}

int af_bench_main(int argc, char **argv, int first)
{
  af_model_params p;
  af_model_result r;
  af_model *m;
  double seconds = 2.0;
  int *rest = malloc((size_t)argc * sizeof *rest);
  int n_rest = 0;
  bool ok = rest && af_cli_parse_model(argc, argv, first, &p, rest, &n_rest) &&
            parse_seconds(argv, rest, n_rest, &seconds);
  free(rest);
  if (!ok)
    return AF_CLI_EXIT_USAGE;
  if (af_model_create(&m) != AF_OK || af_model_evaluate(m, &p, &r) != AF_OK) {
    fprintf(stderr, "firmness_model bench: the model refuses this strike\n");
    af_model_destroy(m);
    return 1;
  }
  /* Warm, then count: the first call fills the Poisson-ratio caches. */
  struct mallinfo2 before = mallinfo2();
  long n = 0;
  double t0 = now_s(), c0 = cpu_s(), t1;
  do {
    for (int k = 0; k < 100; k++)
      af_model_evaluate(m, &p, &r);
    n += 100;
    t1 = now_s();
  } while (t1 - t0 < seconds);
  double cpu = cpu_s() - c0;
  struct mallinfo2 after = mallinfo2();
  printf("evaluations          %ld in %.3f s wall, %.3f s CPU\n", n, t1 - t0, cpu);
  printf("evaluations/second   %.0f (CPU time, one core)\n", n / cpu);
  printf("time per evaluation  %.2f us\n", 1e6 * cpu / n);
  printf("pulse samples        %zu, lobes %zu\n", r.impact.n_samples, r.n_lobes);
  printf("heap growth          %ld bytes over all evaluations\n",
         (long)after.uordblks - (long)before.uordblks);
  af_model_destroy(m);
  return 0;
}
