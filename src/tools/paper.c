/* paper.c — `firmness_model paper [--out DIR] [--quick]`: the paper
 * (Chen & De Baerdemaeker) reproduced by one command.
 *
 * For each profile (paper-literal: af_model_params_paper; shipped default:
 * af_model_params_default) on the ODE path (the reference):
 *   Figs. 2, 4, 6, 8: pulse and spectrum for E2, R2, e and nu2 varied;
 *   Figs. 3, 5, 7: the selected lobe's half-power band against the 0S2 of
 *   100 g and 250 g fruit, and the shear against the yield, over E2, R2, e;
 * as DIR/paper/fig<N>_<profile>.png and .svg; then DIR/paper.md: each of the
 * paper's claims with the figure computed here and a verdict per profile,
 * and the designer (af_design_execute, design.h) on the shipped cultivar against
 * the paper's optimum, its report quoted as `firmness_model design` prints it.
 * Every number in the report is computed by this command. */
#define _POSIX_C_SOURCE 200809L
#include "paper.h"

#include <errno.h>
#include <math.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "cli_flags.h"
#include "closeout.h"
#include "design.h"
#include "impact.h"
#include "model.h"
#include "model_table.h"
#include "options.h"
#include "plot.h"
#include "lamb.h"
#include "spectrum.h"
#include "text.h"
#include "paper_work.h"

const char *const af_paper_verdict_name[4] = {"reproduces", "reproduces with a different number",
                                              "does not reproduce", "calibrated to 31 mm"};
const char *const af_paper_profile_key[2] = {"paper", "default"};
const char *const af_paper_profile_title[2] = {"paper-literal", "shipped default"};

#define AF_ARG(field) offsetof(af_paper, field)
static const af_option paper_options[] = {
    {"--out", "DIR", AF_OPTION_TEXT, AF_ARG(out_dir), -1, NULL,
     "folder of paper.md; the figures go to DIR/paper/ (both made if missing)", NULL, false},
    {"--quick", NULL, AF_OPTION_SWITCH, AF_ARG(quick), -1, NULL,
     "coarser sweeps, for tests (every figure and claim still made)", NULL, false},
};
#define N_OPTIONS (sizeof paper_options / sizeof paper_options[0])

const af_option *af_paper_options(size_t *n)
{
  *n = N_OPTIONS;
  return paper_options;
}

/* The defaults the parser starts from. */
static void paper_defaults(af_paper *w)
{
  w->out_dir = "doc";
  w->quick = false;
}

static void paper_help(void)
{
  static af_paper d;
  paper_defaults(&d);
  printf("usage: firmness_model paper [--out DIR] [--quick]\n\n"
         "The paper's Figs. 2-8 under the paper-literal and the shipped profile (PNG and SVG)\n"
         "and DIR/paper.md: a verdict on each of its claims, and the designer against its\n"
         "optimum.\n\nflags:\n");
  af_options_help(stdout, paper_options, N_OPTIONS, &d, NULL);
  printf("\nexit status: 0 done, 1 model or output failure, 2 bad input\n");
}

/* Profile k: 0 the paper-literal choices, else the shipped one; both on the
 * parameter table's defaults, derived once (af_model_params_table runs the
 * lane's checks). The table's defaults always derive (test_settings); were
 * they not to, there is no figure to draw: exit 1. */
af_model_params af_paper_profile(int k)
{
  static af_model_params table;
  static bool derived;
  if (!derived) {
    char err[512];
    if (af_model_params_table(&table, err, sizeof err) != AF_OK) {
      fprintf(stderr, "firmness_model paper: the parameter table's defaults: %s\n", err);
      exit(1);
    }
    derived = true;
  }
  return k == 0 ? af_model_params_paper_of(&table) : table;
}

/* "<m1> g, <v0> m/s; else E2 <E2> MPa, R2 <R2> mm, e <e>, nu2 <nu2>" (PLplot escapes;
 * sep between the strike's mass and velocity) from p: the table's figures,
 * not typed. */
void af_paper_subtitle(char *buf, size_t len, const af_model_params *p, const char *sep)
{
  af_text(buf, len, "%g g%s%g m/s; else E#d2#u %g MPa, R#d2#u %g mm, e %g, #gn#d2#u %g",
          p->impact.hammer_mass_kg * 1e3, sep, p->impact.velocity_m_s,
          p->impact.fruit_modulus_pa * 1e-6, p->impact.strike_radius_m * 1e3, p->impact.restitution,
          p->impact.fruit_poisson);
}

/* 0S2 [Hz] of a fruit of mass_kg under p (its modulus, nu2, density, factor). */
double af_paper_resonance_hz(const af_model_params *p, double mass_kg)
{
  double xi;
  if (af_lamb_root(p->impact.fruit_poisson, &xi) != AF_OK)
    return NAN;
  return af_lamb_frequency_hz(xi, p->modulus_factor * p->impact.fruit_modulus_pa,
                              p->impact.fruit_poisson, p->fruit_density_kg_m3, mass_kg);
}

af_status af_paper_eval(af_paper *w, const af_model_params *p, af_model_result *r)
{
  return af_model_execute(w->model, p, r);
}

static int make_dir(const char *dir)
{
  struct stat st;
  if (stat(dir, &st) == 0 && S_ISDIR(st.st_mode))
    return 0;
  if (mkdir(dir, 0777) != 0) {
    fprintf(stderr, "firmness_model paper: cannot create %s: %s\n", dir, strerror(errno));
    return 1;
  }
  return 0;
}

int af_paper_main(int argc, char **argv, int first)
{
  static af_paper w;
  if (af_options_want_help(argc, argv, first)) {
    paper_help();
    return 0;
  }
  paper_defaults(&w);
  const af_options_parser p = {
      "firmness_model paper", {{paper_options, N_OPTIONS, &w, NULL, NULL}}, 1, NULL, false};
  if (!af_options_parse(&p, argc, argv, first))
    return AF_CLI_EXIT_USAGE;
  af_text(w.fig_dir, sizeof w.fig_dir, "%s/paper", w.out_dir);
  if (make_dir(w.out_dir) || make_dir(w.fig_dir))
    return AF_CLI_EXIT_USAGE;
  af_spectrum_config sc = af_spectrum_config_default();
  sc.max_samples = AF_PAPER_PULSE_CAP;
  sc.fft_size = 4 * AF_PAPER_PULSE_CAP;
  if (af_model_create(&w.model) != AF_OK || af_impact_create(&w.impact) != AF_OK ||
      af_spectrum_create(&sc, &w.spectrum) != AF_OK) {
    fprintf(stderr, "firmness_model paper: cannot create the model\n");
    af_model_destroy(w.model);
    af_impact_destroy(w.impact);
    return 1;
  }
  const af_family fams[4] = {
      {2, "E#d2#u", "E#d2#u %.0f MPa", 1e-6, af_paper_vary_e2, {2e6, 4e6, 8e6, 12e6}, 4},
      {4,
       "R#d2#u",
       "R#d2#u %.0f mm",
       1e3,
       af_paper_vary_r2,
       {0.010, 0.020, 0.031, 0.040, 0.060},
       5},
      {6, "e", "e %.1f", 1.0, af_paper_vary_e, {1.0, 0.9, 0.8, 0.6, 0.4}, 5},
      {8, "#gn#d2#u", "#gn#d2#u %.2f", 1.0, af_paper_vary_nu, {0.2, 0.3, 0.4, 0.49}, 4},
  };
  const af_sweep_fig sweeps[3] = {
      {3, "E#d2#u [MPa]", "E#d2#u", 2e6, 12e6, 1e-6, af_paper_vary_e2},
      {5, "R#d2#u [mm]", "R#d2#u", 0.005, 0.060, 1e3, af_paper_vary_r2},
      {7, "coefficient of restitution e", "e", 0.2, 1.0, 1.0, af_paper_vary_e},
  };
  int rc = 0;
  static af_claim_row rows[AF_PAPER_N_CLAIMS][2];
  for (int prof = 0; prof < 2 && rc == 0; prof++) {
    for (int f = 0; f < 4 && rc == 0; f++)
      rc = af_paper_family_figure(&w, prof, &fams[f]);
    for (int f = 0; f < 3 && rc == 0; f++)
      rc = af_paper_sweep_figure(&w, prof, &sweeps[f]);
    for (size_t c = 0; c < AF_PAPER_N_CLAIMS && rc == 0; c++) {
      af_status st = af_paper_claims[c].fn(&w, prof, &rows[c][prof]);
      if (st != AF_OK) {
        fprintf(stderr, "firmness_model paper: claim %zu: the model failed: %s\n", c + 1,
                af_strerror(st));
        rc = 1;
      }
    }
  }
  if (rc == 0)
    rc = af_paper_write_report(&w, rows);
  af_model_destroy(w.model);
  af_impact_destroy(w.impact);
  af_spectrum_destroy(w.spectrum);
  return rc;
}
