/* sweep.c — `firmness_model sweep`: CSV rows over a linear range of one flag,
 * with a progress bar on stderr when stderr is a terminal. */
#define _POSIX_C_SOURCE 200809L /* clock_gettime */
#include "sweep.h"

#include <errno.h>
#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "cli_flags.h"
#include "closeout.h"
#include "options.h"
#include "report.h"

#define AF_SWEEP_STEPS_MAX 1000000   /* rows, fast path (~1 us a row) */
#define AF_SWEEP_ODE_STEPS_MAX 10000 /* rows with --ode (~1 ms a row: ~10 s at most) */
#define AF_SWEEP_PROGRESS_S 1.0      /* a progress line on stderr every [s] of a long run */

typedef struct {
  const af_option *param; /* the model flag stepped: a number entry of cli_flags.h */
  double from, to;        /* NaN: not given */
  long steps;
  const char *csv_path; /* NULL = stdout */
  bool ode;             /* --ode: the reference ODE path instead of the fast path */
} af_sweep_args;

/* The defaults the parser starts from (none: every value but --csv and
 * --ode is required). */
static const af_sweep_args sweep_defaults = {NULL, NAN, NAN, 0, NULL, false};

#define AF_ARG(field) offsetof(af_sweep_args, field)
/* The sweep's own flags; the model flags are cli_flags.c's. */
static const af_option sweep_options[] = {
    {"--param", "NAME", AF_OPTION_NONE, 0, -1, NULL,
     "the model flag stepped, without its -- (a number flag below, or lobe)", NULL, false},
    {"--from", "X", AF_OPTION_NUMBER, AF_ARG(from), -1, NULL, "first value [the flag's unit]", NULL,
     false},
    {"--to", "X", AF_OPTION_NUMBER, AF_ARG(to), -1, NULL, "last value [the flag's unit]", NULL,
     false},
    {"--steps", "N", AF_OPTION_LONG, AF_ARG(steps), -1,
     "[1, " AF_OPTION_STR(AF_SWEEP_STEPS_MAX) "]",
     "rows, linearly spaced (with --ode at most " AF_OPTION_STR(AF_SWEEP_ODE_STEPS_MAX) ")", NULL,
     false},
    {"--csv", "FILE", AF_OPTION_TEXT, AF_ARG(csv_path), -1, NULL, "the rows into FILE", "stdout",
     false},
    {"--ode", NULL, AF_OPTION_SWITCH, AF_ARG(ode), -1, NULL,
     "the reference ODE path instead of the fast path (fastpath.h)", NULL, false},
};
#define N_OPTIONS (sizeof sweep_options / sizeof sweep_options[0])

const af_option *af_sweep_options(size_t *n)
{
  *n = N_OPTIONS;
  return sweep_options;
}

static void sweep_help(void)
{
  printf("usage: firmness_model sweep --param NAME --from X --to Y --steps N [--csv FILE] [--ode]\n"
         "                            [model flags]\n\n"
         "One CSV row per value of one model flag (the other flags held), with a progress bar\n"
         "on stderr when it is a terminal.\n\nflags:\n");
  af_options_help(stdout, sweep_options, N_OPTIONS, &sweep_defaults, NULL);
  printf("\nmodel flags (SI units):\n");
  af_cli_print_flags();
  printf("\nexit status: 0 done, 1 model failure, 2 bad input\n");
}

/* --param NAME: a number flag of the model. */
static bool sweep_hand(void *user, const af_option *o, const char *value)
{
  af_sweep_args *a = user;
  (void)o; /* the one entry handed back */
  a->param = af_cli_model_number(value);
  if (a->param == NULL)
    fprintf(stderr,
            "firmness_model sweep: --param '%.40s' is not a number flag of the model (see "
            "--help)\n",
            value);
  return a->param != NULL;
}

/* What the table cannot say: the required flags, and --ode's cap. */
static bool sweep_check(const af_sweep_args *a)
{
  if (a->param == NULL || isnan(a->from) || isnan(a->to) || a->steps == 0) {
    fprintf(stderr, "firmness_model sweep: needs --param NAME --from X --to Y --steps N\n");
    return false;
  }
  if (a->ode && a->steps > AF_SWEEP_ODE_STEPS_MAX) {
    af_options_outside("firmness_model sweep", "--steps", (double)a->steps,
                       "[1, " AF_OPTION_STR(AF_SWEEP_ODE_STEPS_MAX) "]",
                       " with --ode (about 1 ms a row)");
    return false;
  }
  return true;
}

static double now_s(void)
{
  struct timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* A bar on a terminal; otherwise one line every AF_SWEEP_PROGRESS_S of a
 * run that lasts longer, so that a long --ode sweep is never silent. */
static void progress(long done, long total, bool bar, double start_s, double *last_s)
{
  if (bar) {
    int width = 40, filled = (int)(width * done / total);
    fprintf(stderr, "\r[%.*s%*s] %ld/%ld", filled, "########################################",
            width - filled, "", done, total);
    if (done == total)
      fputc('\n', stderr);
    fflush(stderr);
    return;
  }
  double t = now_s();
  if (t - *last_s < AF_SWEEP_PROGRESS_S && done != total)
    return;
  if (done == total && t - start_s < AF_SWEEP_PROGRESS_S)
    return;
  fprintf(stderr, "firmness_model sweep: %ld/%ld rows, %.1f s\n", done, total, t - start_s);
  *last_s = t;
}

/* The point k of the sweep: base with the swept flag at its value *v,
 * refused (one line naming tool) outside the flag's range or kind. */
static bool point(const char *tool, const af_sweep_args *a, const af_model_params *base, long k,
                  af_model_params *p, double *v)
{
  char text[64];
  *v = a->steps == 1 ? a->from : a->from + (a->to - a->from) * (double)k / (double)(a->steps - 1);
  *p = *base;
  snprintf(text, sizeof text, "%.17g", *v);
  if (!af_option_number(tool, a->param, text, v))
    return false;
  af_cli_model_set(a->param, *v, p);
  return true;
}

/* Every point checked before any row is written: a sweep that would stop
 * half-way on a refused value writes nothing and exits 2. */
static bool check_points(const af_sweep_args *a, const af_model_params *base)
{
  char tool[96];
  for (long k = 0; k < a->steps; k++) {
    af_model_params p;
    double v;
    snprintf(tool, sizeof tool, "firmness_model sweep: row %ld of %ld", k + 1, a->steps);
    if (!point(tool, a, base, k, &p, &v) || !af_cli_validate(&p, tool))
      return false;
  }
  return true;
}

/* Runs every point (each already checked); a point the model fails stops
 * the sweep with the flag and value named (exit 1). */
static int run_sweep(const af_sweep_args *a, const af_model_params *base, FILE *out)
{
  af_model *m = NULL;
  af_fastpath *fast = NULL;
  af_report rep;
  bool bar = isatty(STDERR_FILENO);
  double start_s = now_s(), last_s = start_s;
  if (a->ode ? af_model_create(&m) != AF_OK : af_fastpath_create(&fast) != AF_OK) {
    fprintf(stderr, "firmness_model sweep: cannot create the model workspace\n");
    return 1;
  }
  af_report_csv_header(out, a->param->name + 2); /* without its "--" */
  for (long k = 0; k < a->steps; k++) {
    af_model_params p;
    double v;
    af_status st = point("firmness_model sweep", a, base, k, &p, &v) ? AF_OK : AF_EINVAL;
    if (st == AF_OK)
      st = fast ? af_report_compute_fast(fast, &p, &rep) : af_report_compute(m, &p, &rep);
    if (st != AF_OK) {
      char text[32];
      af_options_number_text(v, text, sizeof text);
      fprintf(stderr, "firmness_model sweep: --%s %s (row %ld of %ld): the model failed: %s\n",
              a->param->name + 2, text, k + 1, a->steps, af_strerror(st));
      af_model_destroy(m);
      af_fastpath_destroy(fast);
      return 1;
    }
    af_report_csv_row(out, v, &rep);
    progress(k + 1, a->steps, bar, start_s, &last_s);
  }
  af_model_destroy(m);
  af_fastpath_destroy(fast);
  return 0;
}

int af_sweep_main(int argc, char **argv, int first)
{
  af_model_params base;
  af_sweep_args a;
  int code;
  if (af_options_want_help(argc, argv, first)) {
    sweep_help();
    return 0;
  }
  a = sweep_defaults;
  const af_option_set own = {sweep_options, N_OPTIONS, &a, sweep_hand, &a};
  if (!af_cli_parse_model("firmness_model sweep", &own, NULL, argc, argv, first, &base) ||
      !sweep_check(&a))
    return AF_CLI_EXIT_USAGE;
  if (!check_points(&a, &base))
    return AF_CLI_EXIT_USAGE;
  FILE *out = a.csv_path ? fopen(a.csv_path, "w") : stdout;
  if (out == NULL) {
    fprintf(stderr, "firmness_model sweep: cannot write --csv %s: %s\n", a.csv_path,
            strerror(errno));
    return 1;
  }
  code = run_sweep(&a, &base, out);
  if (a.csv_path && af_closeout_file(out, a.csv_path) != 0 && code == 0)
    code = 1;
  else if (a.csv_path && code == 0)
    af_options_wrote(a.csv_path);
  return code;
}
