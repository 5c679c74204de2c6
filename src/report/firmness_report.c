/* firmness_report — the lab's report of recorded sessions.
 *
 *   firmness_report BAG... | DIR... [--config FILE] [--cultivar FILE] [--ns NAME]
 *                   [--set NAME=VALUE] [--csv FILE] [--plots DIR] [--json] [--bench]
 *                   [--jobs N]                                 (flags: af_report_options)
 *   firmness_report --fields [--json]
 *
 * Reads each BAG (a folder: its *.bag files, sorted by name) through the
 * shim's rosbag reader (no ROS master), runs the recorded force, audio and
 * apple topics of lane NS through the core lane exactly as the node does
 * under replay (session.h), and prints one line per strike with its apple's
 * prediction and the measurement, then the summary (summary.h); --json
 * prints the same as one JSON document, --csv writes one row per strike,
 * --plots draws the figures (report_plots.h), --bench tells the recorded
 * time processed per wall-clock second and the cost of each stage of a
 * strike (report_bench.h); --fields prints the table of a strike's fields
 * instead (serialize.h: name, type, unit, the message field it is or
 * report-only, meaning) as markdown, or with --json as a JSON array.
 * Configured from the node's YAML files (default:
 * the package's config/station.yaml and config/jonagold.yaml) through the
 * one parameter table; the hammer is the shipped rig's (the table's rig
 * values) unless a file or --set gives it.
 *
 * Several bags: --jobs worker threads (default: one per core), each running
 * one bag at a time through a lane of its own (lanes are never shared; the
 * bag's opening and the lane's making and freeing, which touch process-wide
 * state — the reader's error text, FFTW's planner — hold one lock); the
 * bags are written in the order given as they complete, a section each,
 * then the summary over all of them (combined.h). One bag: the output is
 * the same as it always was.
 *
 * Exit 0; 2 with one line on stderr for bad input (a flag, a file, the bag
 * or its topics); 1 when the report cannot be made. Several bags: every bag
 * that can be read is reported, one line on stderr for each that cannot,
 * and the exit status is the worst of them. */
#define _POSIX_C_SOURCE 200809L
#include <ctype.h>
#include <dirent.h>
#include <errno.h>
#include <limits.h>
#include <pthread.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "bag_settings.h"
#include "closeout.h"
#include "combined.h"
#include "json.h"
#include "merge_run.h"
#include "options.h"
#include "output.h"
#include "report_bench.h"
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
#define AF_JOBS_MAX 256 /* worker threads at most */

typedef struct {
  char **bags; /* as given, folders expanded to their *.bag files (owned) */
  size_t n_bags, cap_bags;
  const char *config, *cultivar, *ns, *csv, *plots;
  const char *sets[AF_SETS_MAX];
  int n_sets;
  long jobs; /* worker threads [workers], 1..AF_JOBS_MAX; 0: one per core online */
  bool json, bench, fields, merge;
} af_report_args;

/* The defaults the parser starts from (and --help shows). */
static af_report_args report_args_default(void)
{
  af_report_args a;
  memset(&a, 0, sizeof a);
  a.config = AF_CONFIG_DIR "/station.yaml";
  a.cultivar = AF_CONFIG_DIR "/jonagold.yaml";
  a.ns = "lane1";
  a.jobs = 0; /* one per core online (jobs_or_cores) */
  return a;
}

#define AF_ARG(field) offsetof(af_report_args, field)
/* Every flag: the parser knows no other, --help prints each. */
static const af_option af_report_options[] = {
    {"--config", "FILE", AF_OPTION_TEXT, AF_ARG(config), -1, NULL, "station parameters (YAML)",
     NULL, false},
    {"--cultivar", "FILE", AF_OPTION_TEXT, AF_ARG(cultivar), -1, NULL, "cultivar parameters (YAML)",
     NULL, false},
    {"--ns", "NAME", AF_OPTION_TEXT, AF_ARG(ns), -1, NULL,
     "lane namespace of the topics /NS/force, /NS/audio, /NS/apple", NULL, false},
    {"--set", "NAME=VALUE", AF_OPTION_NONE, 0, -1, NULL,
     "any parameter of the two files, after them (repeatable, at most " AF_OPTION_STR(
         AF_SETS_MAX) ")",
     "the files' values", true},
    {"--csv", "FILE", AF_OPTION_TEXT, AF_ARG(csv), -1, NULL,
     "one row per strike (several bags: a first column \"bag\")", "no CSV", false},
    {"--plots", "DIR", AF_OPTION_TEXT, AF_ARG(plots), -1, NULL,
     "per-strike and session figures (PNG), the folder made if missing; one bag only", "no figures",
     false},
    {"--json", NULL, AF_OPTION_SWITCH, AF_ARG(json), -1, NULL,
     "the report as JSON on stdout instead of text", NULL, false},
    {"--bench", NULL, AF_OPTION_SWITCH, AF_ARG(bench), -1, NULL,
     "recorded time processed per wall-clock second and the cost of each stage of a strike "
     "(setup, detect, window, predict, fft, modes, fit, verdict, serialize: median, mean, p99 "
     "and max per strike), on stderr",
     NULL, false},
    {"--jobs", "N", AF_OPTION_LONG, AF_ARG(jobs), -1, "[1, " AF_OPTION_STR(AF_JOBS_MAX) "] workers",
     "bags read at once, each by a worker thread of its own", "one per core online", false},
    {"--merge", NULL, AF_OPTION_SWITCH, AF_ARG(merge), -1, NULL,
     "the arguments are JSON reports (--json, of one bag or several; a folder: its *.json) to "
     "merge into the summary one run over all their bags prints; no bag is read; only --json "
     "goes with it",
     NULL, false},
    {"--fields", NULL, AF_OPTION_SWITCH, AF_ARG(fields), -1, NULL,
     "print the strike fields (name, type, unit, message field, meaning) as a markdown table, "
     "with --json as JSON, and exit; no BAG",
     NULL, false},
};
#define AF_N_OPTIONS (sizeof af_report_options / sizeof af_report_options[0])

static void print_usage(FILE *out)
{
  af_report_args d = report_args_default();
  fprintf(out,
          "usage: firmness_report BAG... [flags]\n"
          "       firmness_report --merge REPORT.json... [--json]\n"
          "       firmness_report --fields [--json]\n\n"
          "Runs a recorded session (the /NS/force, /NS/audio and /NS/apple topics of a rosbag)\n"
          "through the station's lane, as the node judges it live, and reports every strike\n"
          "(its measurement, verdict flags and firmness grade) and a summary. No ROS master\n"
          "needed. Every file written is told by a line \"wrote FILE\" on stderr.\n\n"
          "A bag that holds the node's settings (/NS/settings, as record.launch records it) is\n"
          "judged with them unless --config or --cultivar is given (said on stderr).\n\n"
          "Several bags, or a folder (its *.bag files, sorted by name): one section per bag\n"
          "in the order given, then the summary over all of them; --jobs bags at once.\n"
          "Bags reported apart (each with --json, on several machines) merge with --merge into\n"
          "the summary one run over all of them prints.\n\n"
          "flags:\n");
  af_options_help(out, af_report_options, AF_N_OPTIONS, &d, NULL);
  fprintf(out, "\nexit status: 0 done, 1 failure, 2 bad input (several bags: the worst)\n");
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

/* ---- the bags ------------------------------------------------------------------ */

static bool add_bag(af_report_args *a, const char *path)
{
  if (a->n_bags == a->cap_bags) {
    size_t want = a->cap_bags ? 2 * a->cap_bags : 16;
    char **q = realloc(a->bags, want * sizeof *q);
    if (!q)
      return false;
    a->bags = q;
    a->cap_bags = want;
  }
  if (!(a->bags[a->n_bags] = strdup(path)))
    return false;
  a->n_bags++;
  return true;
}

static void free_bags(af_report_args *a)
{
  for (size_t k = 0; k < a->n_bags; k++)
    free(a->bags[k]);
  free(a->bags);
  a->bags = NULL;
  a->n_bags = a->cap_bags = 0;
}

static int cmp_text(const void *x, const void *y)
{
  return strcmp(*(char *const *)x, *(char *const *)y);
}

/* name ends in suffix (".bag", ".json") after at least one character. */
static bool has_suffix(const char *name, const char *suffix)
{
  size_t n = strlen(name), m = strlen(suffix);
  return n > m && strcmp(name + n - m, suffix) == 0;
}

/* A folder's *.bag files (--merge: *.json; regular files), sorted by name.
 * 0, or the exit code. */
static int add_folder(af_report_args *a, const char *dir)
{
  const char *suffix = a->merge ? ".json" : ".bag";
  DIR *d = opendir(dir);
  if (!d)
    return bad_flag("%s: cannot read the folder: %s", dir, strerror(errno));
  size_t first = a->n_bags, len = strlen(dir);
  const char *sep = len > 0 && dir[len - 1] == '/' ? "" : "/";
  struct dirent *e;
  int code = 0;
  while (code == 0 && (e = readdir(d)) != NULL) {
    char path[PATH_MAX];
    struct stat st;
    if (!has_suffix(e->d_name, suffix) ||
        snprintf(path, sizeof path, "%s%s%s", dir, sep, e->d_name) >= (int)sizeof path ||
        stat(path, &st) != 0 || !S_ISREG(st.st_mode))
      continue;
    if (!add_bag(a, path))
      code = bad_flag("%s: out of memory listing the folder%s", dir, "");
  }
  closedir(d);
  if (code == 0 && a->n_bags == first)
    return bad_flag("%s: the folder holds no *%s file", dir, suffix);
  qsort(a->bags + first, a->n_bags - first, sizeof *a->bags, cmp_text);
  return code;
}

/* A BAG argument: a folder's bags, or the file itself. 0, or the exit code. */
static int add_argument(af_report_args *a, const char *path)
{
  struct stat st;
  if (stat(path, &st) == 0 && S_ISDIR(st.st_mode))
    return add_folder(a, path);
  if (!add_bag(a, path))
    return bad_flag("%s: out of memory%s", path, "");
  return 0;
}

/* The workers: --jobs, or one per core online (at least 1, at most AF_JOBS_MAX). */
static long jobs_or_cores(long jobs)
{
  if (jobs > 0)
    return jobs;
  long cores = sysconf(_SC_NPROCESSORS_ONLN);
  return cores < 1 ? 1 : cores > AF_JOBS_MAX ? AF_JOBS_MAX : cores;
}

/* A bag or folder (o NULL) or a --set, in the order given. */
static bool report_hand(void *user, const af_option *o, const char *value)
{
  af_report_args *a = user;
  if (o == NULL)
    return add_argument(a, value) == 0;
  if (a->n_sets == AF_SETS_MAX) {
    (void)bad_flag("--set %s: more than " AF_OPTION_STR(AF_SETS_MAX) " --set flags%s", value, "");
    return false;
  }
  a->sets[a->n_sets++] = value;
  return true;
}

static int parse(int argc, char **argv, af_report_args *a)
{
  *a = report_args_default();
  for (int k = 1; k < argc; k++) /* before the arguments: a folder's files are *.json */
    a->merge |= strcmp(argv[k], "--merge") == 0;
  const af_options_parser p = {
      "firmness_report", {{af_report_options, AF_N_OPTIONS, a, report_hand, a}}, 1, "BAG...", true};
  if (!af_options_parse(&p, argc, argv, 1))
    return AF_EXIT_USAGE;
  if (a->fields && a->n_bags > 0)
    return bad_flag("--fields takes no bag: '%s'%s", a->bags[0], "");
  if (a->fields && (a->csv || a->plots || a->bench || a->n_sets || a->jobs || a->merge))
    return bad_flag("--fields takes only --json (not --csv, --plots, --bench, --jobs, --merge or "
                    "--set)%s%s",
                    "", "");
  if (a->fields)
    return 0;
  if (a->merge && (a->csv || a->plots || a->bench || a->n_sets || a->jobs))
    return bad_flag("--merge takes only --json (not --csv, --plots, --bench, --jobs or --set: "
                    "the reports were made with theirs)%s%s",
                    "", "");
  if (a->merge && a->n_bags == 0)
    return bad_flag("--merge needs the reports: firmness_report --merge REPORT.json... or a "
                    "folder of them%s%s",
                    "", "");
  if (a->n_bags == 0)
    return bad_flag("a bag is required: firmness_report BAG... or a folder of bags (see "
                    "--help)%s%s",
                    "", "");
  if (a->plots && a->n_bags > 1)
    return bad_flag("--plots %s draws one bag's figures: give one bag (%s given)", a->plots,
                    "several");
  return 0;
}

/* The table's defaults and the two files. */
static int load_files(const af_report_args *a, af_settings *s)
{
  char err[AF_ERR_MAX];
  af_settings_reset(s);
  if (af_settings_load_yaml(s, a->config, err, sizeof err) != AF_OK)
    return bad_flag("--config %s%s", err, "");
  if (af_settings_load_yaml(s, a->cultivar, err, sizeof err) != AF_OK)
    return bad_flag("--cultivar %s%s", err, "");
  return 0;
}

/* The settings before the hammer and --set: the bags' snapshot of the
 * node's (bag_settings.h) when they hold one and no file is given, else
 * the files; said on stderr when a snapshot is used or set aside. */
static int base_settings(const af_report_args *a, const char *ns, bool files_given, af_settings *s)
{
  char err[AF_ERR_MAX], topic[AF_SESSION_TOPIC_MAX];
  snprintf(topic, sizeof topic, "/%s/settings", ns);
  af_bag_settings_result r = af_bag_settings_read(a->bags, a->n_bags, topic, s, err, sizeof err);
  if (r == AF_BAG_SETTINGS_REFUSED && !files_given)
    return bad_flag("%s%s", err, "");
  if (r == AF_BAG_SETTINGS_READ && !files_given) {
    fprintf(stderr,
            "firmness_report: settings from %s of the bag%s (the node's, as recorded); "
            "--config and --cultivar judge with files instead\n",
            topic, a->n_bags > 1 ? "s" : "");
    return 0;
  }
  if (r == AF_BAG_SETTINGS_READ)
    fprintf(stderr,
            "firmness_report: the node's settings recorded on %s not used: --config or "
            "--cultivar given\n",
            topic);
  return load_files(a, s);
}

/* The node's settings: the bags' snapshot or the two files, the shipped
 * rig's hammer unless given, then --set. */
static int configure(const af_report_args *a, const char *ns, bool files_given, af_settings *s,
                     af_lane_config *cfg)
{
  char err[AF_ERR_MAX];
  int code = base_settings(a, ns, files_given, s);
  if (code)
    return code;
  /* The node reads the hammer from the rig's URDF; a bag does not hold it:
   * the shipped rig's (the table's rig values). */
  if (af_settings_use_rig_hammer(s, err, sizeof err) != AF_OK)
    return bad_flag("%s%s", err, "");
  for (int k = 0; k < a->n_sets; k++)
    if (af_settings_set_arg(s, a->sets[k], err, sizeof err) != AF_OK)
      return bad_flag("--set %s: %s", a->sets[k], err);
  if (af_lane_config_derive(s, cfg, err, sizeof err) != AF_OK)
    return bad_flag("%s%s", err, "");
  return 0;
}

/* --config or --cultivar given (the parser stores the argument, never the
 * default's text): the files, not a bag's snapshot. */
static bool files_given(const af_report_args *a)
{
  const af_report_args d = report_args_default();
  return a->config != d.config || a->cultivar != d.cultivar;
}

/* ---- the workers ----------------------------------------------------------------- */

/* One bag's run: filled by a worker, written and freed by the main thread. */
typedef struct {
  const char *path;
  af_session s;
  int code;
  char err[AF_ERR_MAX];
  bool done;
} af_bag_job;

typedef struct af_run af_run;

typedef struct {
  af_run *run;
  af_lane_config *cfg; /* the run's, with this worker's stage hook */
  af_report_bench bench;
  pthread_t thread;
  bool started;
} af_worker;

struct af_run {
  af_bag_job *jobs;
  size_t n_jobs, next;  /* next: the first bag no worker has taken */
  pthread_mutex_t lock; /* next, every job's done */
  pthread_cond_t done;
  pthread_mutex_t setup; /* session.h: opening a bag, making and freeing a lane */
  const af_lane_config *cfg;
  const char *ns;
  af_report_plots *plots;
  bool bench;
  bool progress; /* stderr is a terminal: one bag's bar, or a line per bag done */
};

/* The session's strike callback: the bench's strike, the plots. */
static void on_strike(const af_lane_strike *ls, const af_lane *lane, void *user)
{
  af_worker *w = user;
  if (w->run->bench)
    af_report_bench_strike(&w->bench);
  if (w->run->plots)
    af_report_plots_strike(ls, lane, w->run->plots);
}

static void run_job(af_worker *w, af_bag_job *j)
{
  af_run *r = w->run;
  af_session_options o = {j->path,  r->ns, w->cfg, on_strike, w, r->progress && r->n_jobs == 1,
                          &r->setup};
  j->code = af_session_execute(&o, &j->s, j->err, sizeof j->err);
}

/* Takes bags until none is left. */
static void *work(void *user)
{
  af_worker *w = user;
  af_run *r = w->run;
  for (;;) {
    pthread_mutex_lock(&r->lock);
    size_t k = r->next < r->n_jobs ? r->next++ : r->n_jobs;
    pthread_mutex_unlock(&r->lock);
    if (k == r->n_jobs)
      return NULL;
    run_job(w, &r->jobs[k]);
    pthread_mutex_lock(&r->lock);
    r->jobs[k].done = true;
    pthread_cond_broadcast(&r->done);
    pthread_mutex_unlock(&r->lock);
  }
}

static void wait_job(af_run *r, size_t k)
{
  pthread_mutex_lock(&r->lock);
  while (!r->jobs[k].done)
    pthread_cond_wait(&r->done, &r->lock);
  pthread_mutex_unlock(&r->lock);
}

/* Makes the workers (their configurations first); false: out of memory or no thread. */
static bool start_workers(af_run *r, af_worker *w, int n)
{
  for (int k = 0; k < n; k++) {
    w[k].run = r;
    af_report_bench_init(&w[k].bench);
    if (!(w[k].cfg = malloc(sizeof *w[k].cfg)))
      return false;
    *w[k].cfg = *r->cfg;
    w[k].cfg->strikes.measure.stages = r->bench ? &w[k].bench.hook : NULL;
  }
  for (int k = 0; k < n; k++) {
    if (pthread_create(&w[k].thread, NULL, work, &w[k]) != 0)
      return k > 0; /* those started do every bag */
    w[k].started = true;
  }
  return true;
}

static void stop_workers(af_worker *w, int n)
{
  for (int k = 0; k < n; k++) {
    if (w[k].started)
      pthread_join(w[k].thread, NULL);
    free(w[k].cfg);
  }
}

/* ---- the output ------------------------------------------------------------------ */

typedef struct {
  const af_report_args *a;
  const char *ns;
  const af_settings *settings; /* as run: each bag's JSON carries them (merge_state.h) */
  FILE *csv;
  af_report_plots *plots;
  af_report_bench bench; /* the rows written (serialize), then the workers' */
  af_combined all;
  bool many;       /* several bags: sections, the combined summary, the CSV's bag column */
  bool csv_header; /* written */
} af_writer;

static double now_s(clockid_t id)
{
  struct timespec ts;
  clock_gettime(id, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static void print_bench(const char *bag, const af_session *s)
{
  fprintf(stderr,
          "bench: %s%s%.1f s of recording (%zu strikes, %llu messages) in %.3f s wall, %.3f s "
          "CPU: %.0f x real time (CPU: %.0f x)\n",
          bag ? bag : "", bag ? ": " : "", s->recorded_s, s->n_strikes,
          (unsigned long long)s->messages, s->wall_s, s->cpu_s,
          s->wall_s > 0.0 ? s->recorded_s / s->wall_s : 0.0,
          s->cpu_s > 0.0 ? s->recorded_s / s->cpu_s : 0.0);
}

static void write_failed(af_writer *w, size_t k, size_t n, const af_bag_job *j)
{
  if (!w->many) {
    fprintf(stderr, "firmness_report: %s\n", j->err);
    return;
  }
  bool named = strncmp(j->err, j->path, strlen(j->path)) == 0;
  fprintf(stderr, "firmness_report: %s%s%s\n", named ? "" : j->path, named ? "" : ": ", j->err);
  w->all.failed++;
  if (w->a->json) {
    fputs(k ? ",\n" : "", stdout);
    af_output_json_failed(stdout, j->path, j->err);
  } else
    printf("%s== bag %zu of %zu: %s ==\nnot read: %s\n", k ? "\n" : "", k + 1, n, j->path, j->err);
}

/* One bag's section (the whole report for one bag), its CSV rows, its figures. */
static int write_bag(af_writer *w, size_t k, size_t n, af_bag_job *j)
{
  const af_report_args *a = w->a;
  const af_stage_hook *timer = a->bench ? &w->bench.serialize_hook : NULL;
  char err[AF_ERR_MAX];
  if (j->code != AF_SESSION_OK) {
    write_failed(w, k, n, j);
    return j->code;
  }
  af_summary m;
  if (af_summary_compute(&j->s, &m) != AF_OK) {
    fprintf(stderr, "firmness_report: out of memory for the summary\n");
    return 1;
  }
  int code = 0;
  if (af_combined_add(&w->all, &j->s, &m) != AF_OK) {
    fprintf(stderr, "firmness_report: out of memory for the combined summary\n");
    code = 1;
  }
  af_report_bench_pass(&w->bench);
  if (a->json) {
    fputs(w->many && k ? ",\n" : "", stdout);
    af_output_json(stdout, j->path, w->ns, &j->s, &m, w->settings, timer);
  } else {
    if (w->many)
      printf("%s== bag %zu of %zu: %s ==\n", k ? "\n" : "", k + 1, n, j->path);
    af_output_text(stdout, &j->s, &m, timer);
  }
  if (w->csv) {
    if (!w->csv_header) /* at the first bag read: no bag read, an empty file as before */
      af_output_csv_header(w->csv, w->many);
    w->csv_header = true;
    af_report_bench_pass(&w->bench);
    af_output_csv_rows(w->csv, &j->s, w->many ? j->path : NULL, timer);
  }
  af_report_bench_bag_written(&w->bench, j->s.n_strikes);
  if (w->plots && af_report_plots_session(w->plots, &j->s, &m, err, sizeof err) != AF_OK) {
    fprintf(stderr, "firmness_report: --plots %s: %s\n", a->plots, err);
    code = 1;
  }
  if (a->bench)
    print_bench(w->many ? j->path : NULL, &j->s);
  return code;
}

static void write_combined(af_writer *w)
{
  fputs(w->a->json ? "\n  ],\n  \"combined\": " : "\n", stdout);
  af_report_print_combined(&w->all, w->a->json);
  if (w->a->json)
    fputs("\n}\n", stdout);
}

/* ---- the run --------------------------------------------------------------------- */

static int worse(int a, int b)
{
  return a > b ? a : b;
}

/* Runs every bag on the workers and writes each as it completes, in order. */
static int run_bags(af_writer *w, af_run *r, int jobs)
{
  const size_t n = r->n_jobs;
  af_worker *workers = calloc((size_t)jobs, sizeof *workers);
  if (!workers) {
    fprintf(stderr, "firmness_report: out of memory for %d workers\n", jobs);
    return 1;
  }
  double wall0 = now_s(CLOCK_MONOTONIC);
  int code = 0;
  if (!start_workers(r, workers, jobs)) {
    fprintf(stderr, "firmness_report: could not start the workers (--jobs %d)\n", jobs);
    stop_workers(workers, jobs); /* none started: no bag is waited for */
    free(workers);
    return 1;
  }
  if (w->a->json && w->many)
    fputs("{\n  \"bags\": [\n", stdout);
  for (size_t k = 0; k < n; k++) {
    wait_job(r, k);
    code = worse(code, write_bag(w, k, n, &r->jobs[k]));
    if (w->many && r->progress)
      fprintf(stderr, "bag %zu of %zu done: %s\n", k + 1, n, r->jobs[k].path);
    af_session_destroy(&r->jobs[k].s);
  }
  stop_workers(workers, jobs);
  double run_wall_s = now_s(CLOCK_MONOTONIC) - wall0;
  if (w->many)
    write_combined(w);
  if (w->a->bench) {
    for (int k = 0; k < jobs; k++) {
      (void)af_report_bench_merge(&w->bench, &workers[k].bench);
      af_report_bench_free(&workers[k].bench);
    }
    af_report_bench_print(stderr, &w->bench, w->bench.serialize_base, w->all.totals.recorded_s,
                          run_wall_s, w->all.totals.cpu_s, jobs);
  }
  free(workers);
  return code;
}

static int run_report(const af_report_args *a, const char *ns, const af_settings *settings,
                      const af_lane_config *cfg, FILE *csv)
{
  char err[AF_ERR_MAX];
  af_writer w;
  memset(&w, 0, sizeof w);
  w.a = a;
  w.ns = ns;
  w.settings = settings;
  w.csv = csv;
  w.many = a->n_bags > 1;
  af_report_bench_init(&w.bench);
  af_combined_init(&w.all);
  if (a->plots && af_report_plots_create(a->plots, cfg, &w.plots, err, sizeof err) != AF_OK)
    return bad_flag("--plots %s: %s", a->plots, err);
  af_run r;
  memset(&r, 0, sizeof r);
  r.jobs = calloc(a->n_bags, sizeof *r.jobs);
  if (!r.jobs) {
    af_report_plots_destroy(w.plots);
    fprintf(stderr, "firmness_report: out of memory for %zu bags\n", a->n_bags);
    return 1;
  }
  for (size_t k = 0; k < a->n_bags; k++)
    r.jobs[k].path = a->bags[k];
  r.n_jobs = a->n_bags;
  r.cfg = cfg;
  r.ns = ns;
  r.plots = w.plots;
  r.bench = a->bench;
  r.progress = isatty(STDERR_FILENO) != 0;
  pthread_mutex_init(&r.lock, NULL);
  pthread_mutex_init(&r.setup, NULL);
  pthread_cond_init(&r.done, NULL);
  const long wanted = jobs_or_cores(a->jobs);
  const long jobs = wanted < (long)a->n_bags ? wanted : (long)a->n_bags;
  int code = run_bags(&w, &r, (int)jobs);
  pthread_cond_destroy(&r.done);
  pthread_mutex_destroy(&r.setup);
  pthread_mutex_destroy(&r.lock);
  free(r.jobs);
  af_combined_free(&w.all);
  af_report_bench_free(&w.bench);
  af_report_plots_destroy(w.plots);
  return code;
}

int main(int argc, char **argv)
{
  af_closeout_install("firmness_report");
  if (!af_options_args_plain("firmness_report", argc, argv))
    return 2;
  if (af_options_want_help(argc, argv, 1)) {
    print_usage(stdout);
    return 0;
  }
  af_report_args a;
  int code = parse(argc, argv, &a);
  if (code) {
    free_bags(&a);
    return code;
  }
  if (a.fields) {
    if (a.json)
      af_serialize_fields_json(stdout);
    else
      af_serialize_fields_markdown(stdout);
    free_bags(&a);
    return 0;
  }
  if (a.merge) {
    code = af_report_merge(a.bags, a.n_bags, a.json);
    free_bags(&a);
    return code;
  }
  char ns[AF_SESSION_NS_MAX];
  static af_lane_config cfg; /* large: not on the stack */
  static af_settings settings;
  FILE *csv = NULL;
  if (!ns_valid(a.ns, ns, sizeof ns))
    code = bad_flag("--ns '%s' is not a lane namespace (a ROS name: letters, digits, _ and /, "
                    "starting with a letter)%s",
                    a.ns, "");
  for (size_t k = 0; k < a.n_bags && code == 0; k++) {
    FILE *probe = fopen(a.bags[k], "rb");
    if (!probe)
      code = bad_flag("%s cannot be opened: %s", a.bags[k], strerror(errno));
    else
      fclose(probe);
  }
  if (code == 0)
    code = configure(&a, ns, files_given(&a), &settings, &cfg);
  if (code == 0 && a.csv && !(csv = fopen(a.csv, "w")))
    code = bad_flag("--csv %s: cannot write: %s", a.csv, strerror(errno));
  if (code == 0) {
    af_status_init(); /* GSL's handler, once, before any worker runs */
    code = run_report(&a, ns, &settings, &cfg, csv);
  }
  if (csv && af_closeout_file(csv, a.csv) != 0 && code == 0)
    code = 1;
  else if (csv && code == 0)
    af_options_wrote(a.csv);
  free_bags(&a);
  return code;
}
