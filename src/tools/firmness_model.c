/* firmness_model — the impact-excitation model from the command line.
 *
 *   firmness_model [model flags] [--json]          one strike
 *   firmness_model sweep --param NAME --from X --to Y --steps N [--csv FILE]
 *   firmness_model bench [--seconds S]
 *   firmness_model plot [model flags] --out FILE.png|FILE.svg [--modulus-min PA] [--modulus-max PA]
 *   firmness_model analyze --force FILE --audio FILE [--rate-force HZ] [--rate-audio HZ]
 *                          --mass KG --R2 M [--force-channel N] [--audio-channel N]
 *                          [--force-scale N] [--audio-scale X] [--audio-offset S]
 *
 * Bad input exits with code 2 and a one-line message naming the flag. */
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "analyze.h"
#include "bench.h"
#include "cli_flags.h"
#include "design.h"
#include "paper.h"
#include "plot_cmd.h"
#include "report.h"
#include "sweep.h"

static void usage(void)
{
  printf("usage: firmness_model [--profile default|paper] [model flags] [--json]\n"
         "       firmness_model sweep --param NAME --from X --to Y --steps N [--csv FILE] "
         "[--ode] [model flags]\n"
         "       firmness_model bench [--seconds S] [model flags]\n"
         "       firmness_model design [--cultivar FILE] [--hammer-mass-range A:B] "
         "[--v0-range A:B]\n"
         "                      [--tip-radius-range A:B] [--hammer-modulus X] [--r2-min M] "
         "[--plot FILE] [--ode]\n"
         "       firmness_model paper [--out DIR] [--quick]   (the paper's Figs. 2-8 and "
         "claims)\n"
         "       firmness_model plot [model flags] --out FILE.png|FILE.svg [--modulus-min PA] "
         "[--modulus-max PA]\n"
         "       firmness_model analyze --force FILE --audio FILE [--rate-force HZ] "
         "[--rate-audio HZ] --mass KG --R2 M\n"
         "                      [--force-channel N] [--audio-channel N] [--force-scale N] "
         "[--audio-scale X]\n"
         "                      [--audio-offset S] [--modulus-min PA] [--modulus-max PA] [--bench] "
         "[model flags]\n"
         "                      (FILE: a WAV, its rate from its header, channel 0-based, default "
         "0;\n"
         "                      or raw float32, --rate-* required; scale: the value of integer "
         "full\n"
         "                      scale or of a float 1.0, default 1; doc/notes/wav.md)\n\n"
         "Predicts the hammer impact on an apple (Hertz contact with hysteresis damping), its\n"
         "excitation spectrum, the 0S2 resonance and the subsurface shear, and tells whether\n"
         "the strike is reliable. Defaults: the paper's optimal strike on the average apple\n"
         "under the shipped profile (exact damping, lobe 1, amplitude-half, exact shear);\n"
         "--profile paper: LN damping as printed, lobe 2, power-half, 0.31.\n\n"
         "model flags (SI units):\n");
  af_cli_print_flags();
  printf("\nexit status: 0 done, 1 model failure, 2 bad input\n");
}

static int single(int argc, char **argv)
{
  af_model_params p;
  af_report rep;
  af_model *m;
  bool json = false;
  /* --json is the one argument that is not a model flag: taken out wherever
   * it stands before the model flags are parsed. */
  int n = 0;
  for (int k = 0; k < argc; k++) {
    if (strcmp(argv[k], "--json") == 0)
      json = true;
    else
      argv[n++] = argv[k];
  }
  if (!af_cli_parse_model(n, argv, 1, &p, NULL, NULL))
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

/* No argument holds a control character: every message that quotes one
 * stays one line (a newline in a value would split it). Exit 2 naming the
 * argument, the character shown as '?'. */
static bool printable_args(int argc, char **argv)
{
  for (int k = 1; k < argc; k++) {
    const char *c = argv[k];
    while (*c && !((unsigned char)*c < 0x20 || *c == 0x7f))
      c++;
    if (*c == '\0')
      continue;
    char shown[64];
    size_t n = 0;
    for (const char *p = argv[k]; *p && n + 1 < sizeof shown; p++, n++)
      shown[n] = ((unsigned char)*p < 0x20 || *p == 0x7f) ? '?' : *p;
    shown[n] = '\0';
    fprintf(stderr, "firmness_model: argument %d '%s%s' holds a control character (shown as ?)\n",
            k, shown, strlen(argv[k]) > n ? "..." : "");
    return false;
  }
  return true;
}

int main(int argc, char **argv)
{
  if (!printable_args(argc, argv))
    return AF_CLI_EXIT_USAGE;
  if (argc > 1 && (strcmp(argv[1], "--help") == 0 || strcmp(argv[1], "-h") == 0)) {
    usage();
    return 0;
  }
  if (argc > 1 && strcmp(argv[1], "sweep") == 0)
    return af_sweep_main(argc, argv, 2);
  if (argc > 1 && strcmp(argv[1], "bench") == 0)
    return af_bench_main(argc, argv, 2);
  if (argc > 1 && strcmp(argv[1], "plot") == 0)
    return af_plot_main(argc, argv, 2);
  if (argc > 1 && strcmp(argv[1], "design") == 0)
    return af_design_main(argc, argv, 2);
  if (argc > 1 && strcmp(argv[1], "paper") == 0)
    return af_paper_main(argc, argv, 2);
  if (argc > 1 && strcmp(argv[1], "analyze") == 0)
    return af_analyze_main(argc, argv, 2);
  return single(argc, argv);
}
