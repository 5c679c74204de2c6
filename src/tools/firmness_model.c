/* firmness_model — the impact-excitation model from the command line.
 *
 *   firmness_model [model flags] [--json]          one strike
 *   firmness_model SUBCOMMAND [flags]              analyze, design, plot, sweep, bench, paper
 *   firmness_model [SUBCOMMAND] --help             the flags, units and defaults
 *
 * Bad input exits with code 2 and a one-line message naming the flag. */
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "closeout.h"
#include "analyze.h"
#include "bench.h"
#include "cli_flags.h"
#include "design.h"
#include "options.h"
#include "paper.h"
#include "plot_cmd.h"
#include "report.h"
#include "sweep.h"

typedef int af_subcommand_fn(int argc, char **argv, int first);

/* Every subcommand: main dispatches through this table and the usage lists
 * it, so a subcommand cannot exist without being listed. Each answers
 * `firmness_model SUB --help` with its flags. */
typedef const af_option *af_options_fn(size_t *n);

static const struct {
  const char *name;
  af_subcommand_fn *main;
  af_options_fn *options; /* its flag table */
  bool model_flags;       /* also takes the model flags below */
  const char *summary;
} subcommands[] = {
    {"analyze", af_analyze_main, af_analyze_options, false,
     "recorded force and audio judged as the node judges them live"},
    {"design", af_design_main, af_design_options, false,
     "the strike that makes the cultivar's domain reliable"},
    {"plot", af_plot_main, af_plot_options, true, "one predicted strike as a figure (PNG or SVG)"},
    {"sweep", af_sweep_main, af_sweep_options, true, "CSV rows over a range of one model flag"},
    {"bench", af_bench_main, af_bench_options, true,
     "model evaluations per second, ODE and fast path"},
    {"paper", af_paper_main, af_paper_options, false,
     "the paper's Figs. 2-8 and a verdict on each of its claims"},
};
#define N_SUBCOMMANDS (sizeof subcommands / sizeof subcommands[0])

/* A subcommand's flags as "--name VALUE" words, wrapped under its summary. */
static void print_flag_words(const af_option *table, size_t n, bool model_flags)
{
  const int indent = 12, width = 96;
  int col = printf("%*s", indent, "");
  for (size_t k = 0; k < n + (model_flags ? 1 : 0); k++) {
    char word[64];
    if (k == n)
      snprintf(word, sizeof word, "[model flags]");
    else
      snprintf(word, sizeof word, "%s%s%s", table[k].name, table[k].value ? " " : "",
               table[k].value ? table[k].value : "");
    if (col > indent && col + 1 + (int)strlen(word) > width)
      col = printf("\n%*s", indent, "") - 1;
    col += printf("%s%s", col > indent ? " " : "", word);
  }
  printf("\n");
}

/* The one flag of the single strike besides the model flags. */
static const af_option single_options[] = {
    {"--json", NULL, AF_OPTION_SWITCH, 0, -1, NULL, "the report as JSON instead of text", NULL,
     false},
};

static void usage(void)
{
  printf("usage: firmness_model [flags]              one strike (below)\n"
         "       firmness_model SUBCOMMAND [flags]   (firmness_model SUBCOMMAND --help: its "
         "flags)\n\n"
         "subcommands:\n");
  for (size_t k = 0; k < N_SUBCOMMANDS; k++) {
    size_t n;
    const af_option *table = subcommands[k].options(&n);
    printf("  %-9s %s\n", subcommands[k].name, subcommands[k].summary);
    print_flag_words(table, n, subcommands[k].model_flags);
  }
  printf("\n"
         "One strike: predicts the hammer impact on an apple (Hertz contact with hysteresis\n"
         "damping), its excitation spectrum, the 0S2 resonance and the subsurface shear, and\n"
         "tells whether the strike is reliable. Defaults: the paper's optimal strike on the\n"
         "average apple under the shipped profile (exact damping, lobe 1, amplitude-half,\n"
         "exact shear); --profile paper: LN damping as printed, lobe 2, power-half, 0.31.\n"
         "Files written by any subcommand are told by a line \"wrote FILE\" on stderr.\n"
         "The other tools: firmness_report BAG (a recorded session as the node judges it),\n"
         "strike_bag (a bag of synthetic strikes); each answers --help.\n\n"
         "flags (SI units):\n");
  af_cli_print_flags();
  af_options_help(stdout, single_options, 1, &(bool){false}, NULL);
  printf("\nexit status: 0 done, 1 model failure, 2 bad input\n");
}

static int single(int argc, char **argv)
{
  af_model_params p;
  af_report rep;
  af_model *m;
  bool json = false;
  const af_option_set own = {single_options, 1, &json, NULL, NULL};
  if (!af_cli_parse_model("firmness_model", &own, "a subcommand first", argc, argv, 1, &p))
    return AF_CLI_EXIT_USAGE;
  if (af_model_create(&m) != AF_OK) {
    fprintf(stderr, "firmness_model: cannot create the model workspace\n");
    return 1;
  }
  af_status st = af_report_compute(m, &p, &rep);
  af_model_destroy(m);
  if (st != AF_OK) {
    fprintf(stderr, "firmness_model: the model failed on this strike: %s\n", af_strerror(st));
    return 1;
  }
  if (json)
    af_report_json(stdout, &rep);
  else
    af_report_text(stdout, &rep);
  return 0;
}

int main(int argc, char **argv)
{
  af_closeout_install("firmness_model");
  if (!af_options_args_plain("firmness_model", argc, argv))
    return AF_CLI_EXIT_USAGE;
  for (size_t k = 0; argc > 1 && k < N_SUBCOMMANDS; k++)
    if (strcmp(argv[1], subcommands[k].name) == 0)
      return subcommands[k].main(argc, argv, 2);
  if (af_options_want_help(argc, argv, 1)) {
    usage();
    return 0;
  }
  /* No argument: the documented default strike (README, doc/cli.md), and where the
   * subcommands and flags are told. */
  if (argc == 1)
    fprintf(stderr, "firmness_model: the paper's optimal strike on the average apple "
                    "(firmness_model --help: every subcommand and flag)\n");
  return single(argc, argv);
}
