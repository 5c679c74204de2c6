/* firmness_report — the lab's report of a recorded session.
 *
 *   firmness_report BAG [--config FILE] [--cultivar FILE] [--ns NAME] [--set NAME=VALUE]
 *                   [--csv FILE] [--plots DIR] [--json] [--bench]   (flags: af_report_options)
 *   firmness_report --fields [--json]
 *
 * Reads BAG through the shim's rosbag reader (no ROS master), runs the
 * recorded force, audio and apple topics of lane NS through the core lane
 * exactly as the node does under replay (session.h), and prints one line per
 * strike with its apple's prediction and the measurement, then the summary
 * (summary.h); --json prints the same as one JSON document, --csv writes one
 * row per strike, --plots draws the figures (report_plots.h), --bench tells
 * the recorded time processed per wall-clock second; --fields prints the
 * table of a strike's fields instead (serialize.h: name, type, unit, the
 * message field it is or report-only, meaning) as markdown, or with --json
 * as a JSON array. Configured from the
 * node's YAML files (default: the package's config/station.yaml and
 * config/jonagold.yaml) through the one parameter table; the hammer is the
 * shipped rig's (the table's rig values) unless a file or --set gives it.
 *
 * Exit 0; 2 with one line on stderr for bad input (a flag, a file, the bag
 * or its topics); 1 when the report cannot be made. */
#define _POSIX_C_SOURCE 200809L
#include <ctype.h>
#include <errno.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "options.h"
#include "output.h"
#include "report_plots.h"
#include "serialize.h"
#include "session.h"
#include "settings.h"
#include "summary.h"

#ifndef AF_CONFIG_DIR /* set by CMakeLists.txt: the package's config/ */
#define AF_CONFIG_DIR "config"
#endif

#define AF_EXIT_USAGE 2
#define AF_ERR_MAX 512
#define AF_SETS_MAX 64

typedef struct {
  const char *bag, *config, *cultivar, *ns, *csv, *plots;
  const char *sets[AF_SETS_MAX];
  int n_sets;
  bool json, bench, fields;
} af_report_args;

/* The defaults the parser starts from (and --help shows). */
static af_report_args report_args_default(void)
{
  af_report_args a;
  memset(&a, 0, sizeof a);
  a.config = AF_CONFIG_DIR "/station.yaml";
  a.cultivar = AF_CONFIG_DIR "/jonagold.yaml";
  a.ns = "lane1";
  return a;
}

#define AF_ARG(field) offsetof(af_report_args, field)
/* Every flag: the parser knows no other, --help prints each. */
static const af_option af_report_options[] = {
    {"--config", "FILE", AF_OPTION_TEXT, AF_ARG(config), -1, "station parameters (YAML)", NULL},
    {"--cultivar", "FILE", AF_OPTION_TEXT, AF_ARG(cultivar), -1, "cultivar parameters (YAML)",
     NULL},
    {"--ns", "NAME", AF_OPTION_TEXT, AF_ARG(ns), -1,
     "lane namespace of the topics /NS/force, /NS/audio, /NS/apple", NULL},
    {"--set", "NAME=VALUE", AF_OPTION_NONE, 0, -1,
     "any parameter of the two files, after them (repeatable, at most " AF_OPTION_STR(
         AF_SETS_MAX) ")",
     "the files' values"},
    {"--csv", "FILE", AF_OPTION_TEXT, AF_ARG(csv), -1, "one row per strike", "no CSV"},
    {"--plots", "DIR", AF_OPTION_TEXT, AF_ARG(plots), -1,
     "per-strike and session figures (PNG), the folder made if missing", "no figures"},
    {"--json", NULL, AF_OPTION_SWITCH, AF_ARG(json), -1,
     "the report as JSON on stdout instead of text", NULL},
    {"--bench", NULL, AF_OPTION_SWITCH, AF_ARG(bench), -1,
     "recorded time processed per wall-clock second, on stderr", NULL},
    {"--fields", NULL, AF_OPTION_SWITCH, AF_ARG(fields), -1,
     "print the strike fields (name, type, unit, message field, meaning) as a markdown table, "
     "with --json as JSON, and exit; no BAG",
     NULL},
};
#define AF_N_OPTIONS (sizeof af_report_options / sizeof af_report_options[0])

static void print_usage(FILE *out)
{
  af_report_args d = report_args_default();
  fprintf(out,
          "usage: firmness_report BAG [flags]\n"
          "       firmness_report --fields [--json]\n\n"
          "Runs a recorded session (the /NS/force, /NS/audio and /NS/apple topics of a rosbag)\n"
          "through the station's lane, as the node judges it live, and reports every strike\n"
          "(its measurement, verdict flags and firmness grade) and a summary. No ROS master\n"
          "needed. Every file written is told by a line \"wrote FILE\" on stderr.\n\n"
          "flags:\n");
  af_options_help(out, af_report_options, AF_N_OPTIONS, &d, NULL);
  fprintf(out, "\nexit status: 0 done, 1 failure, 2 bad input\n");
}

static int bad_flag(const char *fmt, const char *a, const char *b)
{
  fprintf(stderr, "firmness_report: ");
  fprintf(stderr, fmt, a, b);
  fputc('\n', stderr);
  return AF_EXIT_USAGE;
}

/* A lane namespace: a ROS graph name of letters, digits and _ (segments
 * separated by /), starting with a letter; surrounding slashes are dropped. */
static bool ns_valid(const char *ns, char *out, size_t len)
{
  while (*ns == '/')
    ns++;
  size_t n = strlen(ns);
  while (n > 0 && ns[n - 1] == '/')
    n--;
  if (n == 0 || n >= len || !isalpha((unsigned char)ns[0]))
    return false;
  for (size_t k = 0; k < n; k++) {
    unsigned char c = (unsigned char)ns[k];
    if (!(isalnum(c) || c == '_' || (c == '/' && ns[k + 1] != '/')))
      return false;
    out[k] = (char)c;
  }
  out[n] = '\0';
  return true;
}

static int parse(int argc, char **argv, af_report_args *a)
{
  *a = report_args_default();
  for (int k = 1; k < argc; k++) {
    const char *f = argv[k];
    if (strncmp(f, "--", 2) != 0) {
      if (a->bag)
        return bad_flag("one bag only: '%s' after '%s'", f, a->bag);
      a->bag = f;
      continue;
    }
    const af_option *o = af_option_find(af_report_options, AF_N_OPTIONS, f);
    if (!o) {
      af_options_unknown("firmness_report", af_report_options, AF_N_OPTIONS, f, "one BAG");
      return AF_EXIT_USAGE;
    }
    if (o->value == NULL) {
      (void)af_option_store(o, NULL, a);
      continue;
    }
    if (k + 1 >= argc || argv[k + 1][0] == '\0') {
      af_options_missing("firmness_report", o);
      return AF_EXIT_USAGE;
    }
    const char *v = argv[++k];
    if (strcmp(f, "--set") == 0) {
      if (a->n_sets == AF_SETS_MAX)
        return bad_flag("--set %s: more than " AF_OPTION_STR(AF_SETS_MAX) " --set flags%s", v, "");
      a->sets[a->n_sets++] = v;
    } else
      (void)af_option_store(o, v, a);
  }
  if (a->fields && a->bag)
    return bad_flag("--fields takes no bag: '%s'%s", a->bag, "");
  if (a->fields && (a->csv || a->plots || a->bench || a->n_sets))
    return bad_flag("--fields takes only --json (not --csv, --plots, --bench or --set)%s%s", "",
                    "");
  if (!a->bag && !a->fields)
    return bad_flag("a bag is required: firmness_report BAG (see --help)%s%s", "", "");
  return 0;
}

/* The node's settings: the table's defaults, the two files, the shipped
 * rig's hammer unless given, then --set. */
static int configure(const af_report_args *a, af_lane_config *cfg)
{
  char err[AF_ERR_MAX];
  af_settings s;
  af_settings_reset(&s);
  if (af_settings_load_yaml(&s, a->config, err, sizeof err) != AF_OK)
    return bad_flag("--config %s%s", err, "");
  if (af_settings_load_yaml(&s, a->cultivar, err, sizeof err) != AF_OK)
    return bad_flag("--cultivar %s%s", err, "");
  /* The node reads the hammer from the rig's URDF; a bag does not hold it:
   * the shipped rig's (the table's rig values). */
  if (af_settings_use_rig_hammer(&s, err, sizeof err) != AF_OK)
    return bad_flag("%s%s", err, "");
  for (int k = 0; k < a->n_sets; k++)
    if (af_settings_set_arg(&s, a->sets[k], err, sizeof err) != AF_OK)
      return bad_flag("--set %s: %s", a->sets[k], err);
  if (af_lane_config_derive(&s, cfg, err, sizeof err) != AF_OK)
    return bad_flag("%s%s", err, "");
  return 0;
}

static void print_bench(const af_session *s)
{
  fprintf(stderr,
          "bench: %.1f s of recording (%zu strikes, %llu messages) in %.3f s wall, %.3f s CPU: "
          "%.0f x real time (CPU: %.0f x)\n",
          s->recorded_s, s->n_strikes, (unsigned long long)s->messages, s->wall_s, s->cpu_s,
          s->wall_s > 0.0 ? s->recorded_s / s->wall_s : 0.0,
          s->cpu_s > 0.0 ? s->recorded_s / s->cpu_s : 0.0);
}

static int run_report(const af_report_args *a, const char *ns, const af_lane_config *cfg, FILE *csv)
{
  char err[AF_ERR_MAX];
  af_report_plots *plots = NULL;
  if (a->plots && af_report_plots_create(a->plots, cfg, &plots, err, sizeof err) != AF_OK)
    return bad_flag("--plots %s: %s", a->plots, err);
  af_session_options o = {
      a->bag, ns, cfg, plots ? af_report_plots_strike : NULL, plots, isatty(STDERR_FILENO) != 0};
  af_session s;
  int code = af_session_execute(&o, &s, err, sizeof err);
  if (code != AF_SESSION_OK) {
    fprintf(stderr, "firmness_report: %s\n", err);
    af_session_destroy(&s);
    af_report_plots_destroy(plots);
    return code;
  }
  af_summary m;
  if (af_summary_compute(&s, &m) != AF_OK) {
    fprintf(stderr, "firmness_report: out of memory for the summary\n");
    code = 1;
  } else {
    if (a->json)
      af_output_json(stdout, a->bag, ns, &s, &m);
    else
      af_output_text(stdout, &s, &m);
    if (csv)
      af_output_csv(csv, &s);
    if (plots && af_report_plots_session(plots, &s, &m, err, sizeof err) != AF_OK) {
      fprintf(stderr, "firmness_report: --plots %s: %s\n", a->plots, err);
      code = 1;
    }
    if (a->bench)
      print_bench(&s);
  }
  af_session_destroy(&s);
  af_report_plots_destroy(plots);
  return code;
}

int main(int argc, char **argv)
{
  if (af_options_want_help(argc, argv, 1)) {
    print_usage(stdout);
    return 0;
  }
  af_report_args a;
  int code = parse(argc, argv, &a);
  if (code)
    return code;
  if (a.fields) {
    if (a.json)
      af_serialize_fields_json(stdout);
    else
      af_serialize_fields_markdown(stdout);
    return 0;
  }
  char ns[AF_SESSION_NS_MAX];
  if (!ns_valid(a.ns, ns, sizeof ns))
    return bad_flag("--ns '%s' is not a lane namespace (a ROS name: letters, digits, _ and /, "
                    "starting with a letter)%s",
                    a.ns, "");
  FILE *probe = fopen(a.bag, "rb");
  if (!probe)
    return bad_flag("%s cannot be opened: %s", a.bag, strerror(errno));
  fclose(probe);
  static af_lane_config cfg; /* large: not on the stack */
  if ((code = configure(&a, &cfg)) != 0)
    return code;
  FILE *csv = NULL;
  if (a.csv && !(csv = fopen(a.csv, "w")))
    return bad_flag("--csv %s: cannot write: %s", a.csv, strerror(errno));
  code = run_report(&a, ns, &cfg, csv);
  if (csv && fclose(csv) != 0 && code == 0) {
    fprintf(stderr, "firmness_report: --csv %s: write failed\n", a.csv);
    code = 1;
  } else if (csv && code == 0)
    af_options_wrote(a.csv);
  return code;
}
