/* bench_lane.c — what making a lane costs, stage by stage (a lane
 * made in under 1 ms after the first one in a process).
 *
 *   af_bench_lane [--runs N]
 *
 * The lane's configuration is the parameter table's defaults as a desk tool
 * reads them (af_lane_config_for_tool: the shipped rig's hammer). Prints, in
 * ms: the process's first configuration (its trial creates build the tables
 * shared by every later lane) and first lane, then the median and the max over N runs (default 200,
 * 1 to 100000) of each stage's create + destroy, the whole lane's last. The stages are the parts
 * af_lane_create makes: the force and audio streams (their rings), the strike detector, the impact
 * workspace (the exact damping law's table), the fit (its impact workspace and GSL workspace), the
 * microphone analysis (its FFTW plan), the measurement (fit + spectrum + response, and
 * af_measure_prepare's Lamb root and caches) and the prediction's fast-path handle (its table
 * is shared by the process and built as strikes need it). Also af_lane_config_derive, which makes a
 * trial detector and measurement. Exit 0; 2 for a bad flag; 1 when a create fails (the stage
 * named). */
#define _POSIX_C_SOURCE 200809L /* clock_gettime */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "closeout.h"
#include "fastpath.h"
#include "fit.h"
#include "impact.h"
#include "lane.h"
#include "lane_config.h"
#include "measure.h"
#include "model.h"
#include "response.h"
#include "settings.h"
#include "stream.h"
#include "strike.h"
#include "tool_config.h"

#define RUNS_DEFAULT 200
#define RUNS_MAX 100000

static af_lane_config cfg;
static af_settings settings;

static double now_ms(void)
{
  struct timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return (double)t.tv_sec * 1e3 + (double)t.tv_nsec * 1e-6;
}

/* One create + destroy of each stage; AF_OK or the create's status. */
static af_status run_streams(void)
{
  af_stream f, a;
  af_status s = af_stream_create(&f, "force", &cfg.force);
  if (s == AF_OK)
    s = af_stream_create(&a, "audio", &cfg.audio);
  af_stream_destroy(&f);
  if (s == AF_OK)
    af_stream_destroy(&a);
  return s;
}

static af_status run_detector(void)
{
  af_strike *d = NULL;
  af_status s = af_strike_create(&cfg.strikes.strike, &d);
  af_strike_destroy(d);
  return s;
}

static af_status run_impact(void)
{
  af_impact *w = NULL;
  af_status s = af_impact_create(&w);
  af_impact_destroy(w);
  return s;
}

static af_status run_fit(void)
{
  af_fit *w = NULL;
  af_status s = af_fit_create(&cfg.strikes.measure.fit, &w);
  af_fit_destroy(w);
  return s;
}

static af_status run_response(void)
{
  af_response *r = NULL;
  af_status s = af_response_create(&cfg.strikes.measure.response, &r);
  af_response_destroy(r);
  return s;
}

static af_status run_measure(void)
{
  af_measure *m = NULL;
  af_status s = af_measure_create(&cfg.strikes.measure, &m);
  if (s == AF_OK)
    s = af_measure_prepare(m, &cfg.model);
  af_measure_destroy(m);
  return s;
}

/* The lane's prediction handle (fastpath.h): the shared table is not made
 * here (its rows are built as strikes need them). */
static af_status run_fastpath(void)
{
  af_fastpath *f = NULL;
  af_status s = af_fastpath_create(&f);
  af_fastpath_destroy(f);
  return s;
}

static af_status run_derive(void)
{
  af_lane_config c;
  char err[512];
  return af_lane_config_for_tool(&settings, &c, err, sizeof err);
}

static af_status run_lane(void)
{
  af_lane *l = NULL;
  const char *what = "";
  af_status s = af_lane_create(&cfg, NULL, NULL, &l, &what);
  af_lane_destroy(l);
  return s;
}

typedef struct {
  const char *name;
  af_status (*run)(void);
} stage;

static const stage stages[] = {
    {"streams (force + audio rings)", run_streams},  {"strike detector", run_detector},
    {"impact (exact damping table)", run_impact},    {"fit", run_fit},
    {"response (FFTW plan)", run_response},          {"measure + prepare", run_measure},
    {"prediction handle (fast path)", run_fastpath}, {"af_lane_config_for_tool", run_derive},
    {"af_lane_create + destroy", run_lane},
};

static int cmp_double(const void *a, const void *b)
{
  double x = *(const double *)a, y = *(const double *)b;
  return (x > y) - (x < y);
}

/* Times n runs of st into t_ms; 0, or 1 after naming the failing stage. */
static int time_stage(const stage *st, size_t n, double *t_ms)
{
  for (size_t k = 0; k < n; k++) {
    double t0 = now_ms();
    af_status s = st->run();
    t_ms[k] = now_ms() - t0;
    if (s != AF_OK) {
      fprintf(stderr, "af_bench_lane: %s failed: %s\n", st->name, af_strerror(s));
      return 1;
    }
  }
  qsort(t_ms, n, sizeof *t_ms, cmp_double);
  return 0;
}

static int parse_runs(int argc, char **argv, size_t *runs)
{
  *runs = RUNS_DEFAULT;
  for (int i = 1; i < argc; i++) {
    char *end = NULL;
    long v = 0;
    if (strcmp(argv[i], "--runs") == 0 && i + 1 < argc) {
      v = strtol(argv[++i], &end, 10);
      if (*end == '\0' && v >= 1 && v <= RUNS_MAX) {
        *runs = (size_t)v;
        continue;
      }
      fprintf(stderr, "af_bench_lane: --runs '%s': a whole number from 1 to %d\n", argv[i],
              RUNS_MAX);
      return 2;
    }
    fprintf(stderr, "af_bench_lane: unknown argument '%s' (usage: af_bench_lane [--runs N])\n",
            argv[i]);
    return 2;
  }
  return 0;
}

int main(int argc, char **argv)
{
  af_closeout_install("af_bench_lane");
  size_t runs;
  int code = parse_runs(argc, argv, &runs);
  if (code != 0)
    return code;
  char err[512];
  /* The first configuration of the process: its trial creates build the
   * shared tables (impact.c, fft_plan.h, memo.h, the settings' defaults). */
  double t0 = now_ms();
  af_settings_reset(&settings);
  if (af_lane_config_for_tool(&settings, &cfg, err, sizeof err) != AF_OK) {
    fprintf(stderr, "af_bench_lane: %s\n", err);
    return 1;
  }
  const double config_ms = now_ms() - t0;
  double first_ms;
  if (time_stage(&stages[sizeof stages / sizeof stages[0] - 1], 1, &first_ms) != 0)
    return 1;
  printf("first configuration in the process (builds the shared tables): %.3f ms\n", config_ms);
  printf("first lane in the process, after it: %.3f ms\n", first_ms);
  printf("%-32s %10s %10s   (%zu runs, ms)\n", "stage (create + destroy)", "median", "max", runs);
  double *t_ms = malloc(runs * sizeof *t_ms);
  if (t_ms == NULL)
    return 1;
  for (size_t i = 0; i < sizeof stages / sizeof stages[0]; i++) {
    if (time_stage(&stages[i], runs, t_ms) != 0) {
      free(t_ms);
      return 1;
    }
    printf("%-32s %10.4f %10.4f\n", stages[i].name, t_ms[runs / 2], t_ms[runs - 1]);
  }
  free(t_ms);
  return 0;
}
