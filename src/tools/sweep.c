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
  const af_cli_flag *param;
  double from, to;
  long steps;
  const char *csv_path; /* NULL = stdout */
  bool ode;             /* --ode: the reference ODE path instead of the fast path */
} af_sweep_args;

/* The defaults the parser starts from (none: every value but --csv and
 * --ode is required). */
static const af_sweep_args sweep_defaults = {NULL, 0.0, 0.0, 0, NULL, false};

#define AF_ARG(field) offsetof(af_sweep_args, field)
/* The sweep's own flags; the model flags are cli_flags.c's. */
static const af_option sweep_options[] = {
    {"--param", "NAME", AF_OPTION_NONE, 0, -1,
     "the model flag stepped, without its -- (a number flag below, or lobe)", NULL},
    {"--from", "X", AF_OPTION_NUMBER, AF_ARG(from), -1, "first value [the flag's unit]", NULL},
    {"--to", "X", AF_OPTION_NUMBER, AF_ARG(to), -1, "last value [the flag's unit]", NULL},
    {"--steps", "N", AF_OPTION_LONG, AF_ARG(steps), -1,
     "rows, linearly spaced, 1 .. " AF_OPTION_STR(
         AF_SWEEP_STEPS_MAX) " (with --ode 1 .. " AF_OPTION_STR(AF_SWEEP_ODE_STEPS_MAX) ") [-]",
     NULL},
    {"--csv", "FILE", AF_OPTION_TEXT, AF_ARG(csv_path), -1, "the rows into FILE", "stdout"},
    {"--ode", NULL, AF_OPTION_SWITCH, AF_ARG(ode), -1,
     "the reference ODE path instead of the fast path (fastpath.h)", NULL},
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

static bool parse_double_arg(const char *flag, const char *text, double *out)
{
  char *end;
  errno = 0;
  *out = strtod(text, &end);
  if (end == text || *end != '\0' || !isfinite(*out)) {
    fprintf(stderr, "firmness_model sweep: %s '%s' is not a finite number\n", flag, text);
    return false;
  }
  return true;
}

/* Reads the sweep's own flags from the arguments the model parser left. */
static bool parse_sweep_args(char **argv, int first, const int *rest, int n_rest, af_sweep_args *a)
{
  double steps = NAN;
  bool have_from = false, have_to = false;
  *a = sweep_defaults;
  for (int k = 0; k < n_rest; k++) {
    const char *flag = argv[rest[k]];
    const af_option *o = af_option_find(sweep_options, N_OPTIONS, flag);
    if (o != NULL && !af_options_once("firmness_model sweep", o, argv, first, rest[k]))
      return false;
    if (o == NULL) {
      char names[1024];
      af_cli_flag_names(names, sizeof names);
      af_options_unknown("firmness_model sweep", sweep_options, N_OPTIONS, flag, names);
      return false;
    }
    if (o->value == NULL) {
      (void)af_option_store(o, NULL, a);
      continue;
    }
    const char *value = k + 1 < n_rest && rest[k + 1] == rest[k] + 1 ? argv[rest[k + 1]] : NULL;
    if (value == NULL) {
      af_options_missing("firmness_model sweep", o);
      return false;
    }
    k++;
    if (strcmp(flag, "--param") == 0) {
      a->param = af_cli_flag_find(value);
      if (a->param == NULL) {
        fprintf(stderr, "firmness_model sweep: --param '%s' is not a model flag (see --help)\n",
                value);
        return false;
      }
    } else if (strcmp(flag, "--from") == 0) {
      have_from = parse_double_arg(flag, value, &a->from);
      if (!have_from)
        return false;
    } else if (strcmp(flag, "--to") == 0) {
      have_to = parse_double_arg(flag, value, &a->to);
      if (!have_to)
        return false;
    } else if (strcmp(flag, "--steps") == 0) {
      if (!parse_double_arg(flag, value, &steps))
        return false;
    } else if (strcmp(flag, "--csv") == 0) {
      a->csv_path = value;
    } else {
      fprintf(stderr, "firmness_model sweep: unknown argument '%s' (see --help)\n", flag);
      return false;
    }
  }
  if (a->param == NULL || !have_from || !have_to || isnan(steps)) {
    fprintf(stderr, "firmness_model sweep: needs --param NAME --from X --to Y --steps N\n");
    return false;
  }
  long max = a->ode ? AF_SWEEP_ODE_STEPS_MAX : AF_SWEEP_STEPS_MAX;
  if (steps != floor(steps) || steps < 1 || steps > (double)max) {
    char text[32];
    af_cli_number_text(steps, text, sizeof text);
    fprintf(stderr, "firmness_model sweep: --steps %s is outside the accepted range 1 .. %ld%s\n",
            text, max, a->ode ? " with --ode (about 1 ms a row)" : "");
    return false;
  }
  if (a->param->kind != AF_FLAG_DOUBLE && a->param->kind != AF_FLAG_LOBE) {
    fprintf(stderr, "firmness_model sweep: --param %s is a choice, not a number: run each value\n",
            a->param->name);
    return false;
  }
  a->steps = (long)steps;
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

/* The point k of the sweep: base with the swept flag at its value *v. */
static bool point(const af_sweep_args *a, const af_model_params *base, long k, af_model_params *p,
                  double *v)
{
  char text[64];
  *v = a->steps == 1 ? a->from : a->from + (a->to - a->from) * (double)k / (double)(a->steps - 1);
  *p = *base;
  snprintf(text, sizeof text, "%.17g", *v);
  return af_cli_flag_set(a->param, text, p);
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
    if (!point(a, base, k, &p, &v) || !af_cli_validate(&p, tool))
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
  af_report_csv_header(out, a->param->name);
  for (long k = 0; k < a->steps; k++) {
    af_model_params p;
    double v;
    af_status st = point(a, base, k, &p, &v) ? AF_OK : AF_EINVAL;
    if (st == AF_OK)
      st = fast ? af_report_compute_fast(fast, &p, &rep) : af_report_compute(m, &p, &rep);
    if (st != AF_OK) {
      char text[32];
      af_cli_number_text(v, text, sizeof text);
      fprintf(stderr, "firmness_model sweep: --%s %s (row %ld of %ld): the model failed: %s\n",
              a->param->name, text, k + 1, a->steps, af_strerror(st));
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
  if (af_options_want_help(argc, argv, first)) {
    sweep_help();
    return 0;
  }
  int *rest = malloc((size_t)argc * sizeof *rest);
  int n_rest = 0, code;
  if (rest == NULL)
    return 1;
  if (!af_cli_parse_model(argc, argv, first, &base, rest, &n_rest) ||
      !parse_sweep_args(argv, first, rest, n_rest, &a)) {
    free(rest);
    return AF_CLI_EXIT_USAGE;
  }
  free(rest);
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
