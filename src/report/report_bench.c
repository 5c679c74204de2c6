/* report_bench.c — the per-stage cost table of firmness_report --bench (see report_bench.h). */
#include "report_bench.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define AF_US_PER_NS 1e-3

static bool push(af_report_bench *b, af_stage s, int64_t v)
{
  if (b->n[s] == b->cap[s]) {
    size_t want = b->cap[s] ? 2 * b->cap[s] : 1024;
    int64_t *q = realloc(b->samples[s], want * sizeof *q);
    if (q == NULL) {
      b->out_of_memory = true;
      return false;
    }
    b->samples[s] = q;
    b->cap[s] = want;
  }
  b->samples[s][b->n[s]++] = v;
  return true;
}

/* The lane's hook: a timed call of a stage. */
static void on_stage(af_stage stage, int64_t elapsed_ns, void *user)
{
  af_report_bench *b = user;
  if ((unsigned)stage >= AF_STAGES)
    return;
  b->total_ns[stage] += elapsed_ns;
  b->calls[stage]++;
  if (stage == AF_STAGE_SETUP) /* once per lane: a sample of its own */
    (void)push(b, stage, elapsed_ns);
  else
    b->strike_ns[stage] += elapsed_ns;
}

/* The output's hook: one row of one strike written (serialize). */
static void on_row(af_stage stage, int64_t elapsed_ns, void *user)
{
  af_report_bench *b = user;
  size_t k = b->serialize_base + b->serialize_at++;
  b->total_ns[stage] += elapsed_ns;
  b->calls[stage]++;
  while (b->n[stage] <= k)
    if (!push(b, stage, 0))
      return;
  b->samples[stage][k] += elapsed_ns;
}

void af_report_bench_init(af_report_bench *b)
{
  memset(b, 0, sizeof *b);
  b->hook.fn = on_stage;
  b->hook.user = b;
  b->serialize_hook.fn = on_row;
  b->serialize_hook.user = b;
}

void af_report_bench_free(af_report_bench *b)
{
  for (int s = 0; s < AF_STAGES; s++) {
    free(b->samples[s]);
    b->samples[s] = NULL;
    b->n[s] = b->cap[s] = 0;
  }
}

void af_report_bench_strike(af_report_bench *b)
{
  for (int s = 0; s < AF_STAGES; s++) {
    if (s == AF_STAGE_SERIALIZE || s == AF_STAGE_SETUP) /* not the lane's per strike */
      continue;
    (void)push(b, (af_stage)s, b->strike_ns[s]);
    b->strike_ns[s] = 0;
  }
}

void af_report_bench_pass(af_report_bench *b)
{
  b->serialize_at = 0;
}

void af_report_bench_bag_written(af_report_bench *b, size_t n_strikes)
{
  b->serialize_base += n_strikes;
  b->serialize_at = 0;
}

bool af_report_bench_merge(af_report_bench *into, const af_report_bench *from)
{
  into->out_of_memory |= from->out_of_memory;
  for (int s = 0; s < AF_STAGES; s++) {
    into->total_ns[s] += from->total_ns[s];
    into->calls[s] += from->calls[s];
    for (size_t k = 0; k < from->n[s]; k++)
      if (!push(into, (af_stage)s, from->samples[s][k]))
        return false;
  }
  return true;
}

static int cmp_i64(const void *a, const void *b)
{
  int64_t x = *(const int64_t *)a, y = *(const int64_t *)b;
  return (x > y) - (x < y);
}

/* The median, 99th percentile (nearest rank: the smallest sample with at
 * least 99 % of them at or below it) and maximum of a stage's per-strike
 * samples [ns]; NaN when there are none. The tail is where a strike's
 * latency goes over its budget (the mode list's two-pole fits), which the
 * median hides. */
typedef struct {
  double median, p99, max;
} spread_ns;

static spread_ns spread_of(const int64_t *samples, size_t n)
{
  spread_ns s = {NAN, NAN, NAN};
  int64_t *x = n > 0 ? malloc(n * sizeof *x) : NULL;
  if (x == NULL)
    return s;
  memcpy(x, samples, n * sizeof *x);
  qsort(x, n, sizeof *x, cmp_i64);
  s.median = n % 2 ? (double)x[n / 2] : 0.5 * ((double)x[n / 2 - 1] + (double)x[n / 2]);
  size_t rank = (99 * n + 99) / 100; /* ceil(0.99 n), 1-based */
  s.p99 = (double)x[rank - 1];
  s.max = (double)x[n - 1];
  free(x);
  return s;
}

static double ratio(double a, double b)
{
  return b > 0.0 ? a / b : NAN;
}

void af_report_bench_print(FILE *out, const af_report_bench *b, size_t strikes, double recorded_s,
                           double run_wall_s, double cpu_s, int jobs)
{
  int64_t stages_ns = 0;
  for (int s = 0; s < AF_STAGES; s++)
    stages_ns += b->total_ns[s];
  const double all_ns = cpu_s * 1e9 + (double)b->total_ns[AF_STAGE_SERIALIZE];
  fprintf(out,
          "bench: cost per stage over %zu strikes (the time of the thread that runs it, on the "
          "monotonic clock; all: the workers' CPU time; "
          "median: of each strike's time in the stage, detect and predict: the force chunks "
          "and apples since the previous strike, setup: per lane)\n",
          strikes);
  fprintf(out, "  %-10s %10s %14s %14s %16s %7s %12s %12s\n", "stage", "calls", "median",
          "mean/strike", "total", "share", "p99", "max");
  fprintf(out, "  %-10s %10s %14s %14s %16s %7s %12s %12s\n", "", "", "[us]", "[us]", "[us]", "[%]",
          "[us]", "[us]");
  for (int s = 0; s < AF_STAGES; s++) {
    spread_ns sp = spread_of(b->samples[s], b->n[s]);
    fprintf(out, "  %-10s %10llu %14.2f %14.2f %16.1f %7.2f %12.2f %12.2f\n",
            af_stage_name((af_stage)s), (unsigned long long)b->calls[s], sp.median * AF_US_PER_NS,
            ratio((double)b->total_ns[s], (double)strikes) * AF_US_PER_NS,
            (double)b->total_ns[s] * AF_US_PER_NS, 100.0 * ratio((double)b->total_ns[s], all_ns),
            sp.p99 * AF_US_PER_NS, sp.max * AF_US_PER_NS);
  }
  const double rest_ns = all_ns - (double)stages_ns;
  if (rest_ns >= 0.0)
    fprintf(
        out,
        "  %-10s %10s %14s %14.2f %16.1f %7.2f %12s %12s   (reading the bags, streams, match)\n",
        "other", "-", "-", ratio(rest_ns, (double)strikes) * AF_US_PER_NS, rest_ns * AF_US_PER_NS,
        100.0 * ratio(rest_ns, all_ns), "-", "-");
  else /* the stages' clock counted time the thread waited for a core (stage.h) */
    fprintf(out,
            "  %-10s %10s %14s %14s %16s %7s %12s %12s   (reading the bags, streams, match: not "
            "known, the stages' monotonic time exceeds the workers' CPU time by %.1f us: the "
            "machine was loaded, rerun it idle)\n",
            "other", "-", "-", "-", "-", "-", "-", "-", -rest_ns * AF_US_PER_NS);
  fprintf(out, "  %-10s %10s %14s %14.2f %16.1f %7.2f %12s %12s\n", "all", "-", "-",
          ratio(all_ns, (double)strikes) * AF_US_PER_NS, all_ns * AF_US_PER_NS, 100.0, "-", "-");
  fprintf(out,
          "bench: real-time factor %.1f x (%.3f s of recording in %.3f s wall, %d worker%s); "
          "CPU %.1f x (%.3f s of the workers' CPU, %.1f us per strike)\n",
          ratio(recorded_s, run_wall_s), recorded_s, run_wall_s, jobs, jobs == 1 ? "" : "s",
          ratio(recorded_s, cpu_s), cpu_s, ratio(cpu_s * 1e6, (double)strikes));
  if (b->out_of_memory)
    fprintf(out,
            "bench: out of memory for some samples: the medians, p99 and max leave them out\n");
}
