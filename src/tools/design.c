/* design.c — `firmness_model design`: the strike (hammer mass, contact
 * velocity, tip radius) that makes the whole cultivar domain reliable with
 * the largest margin, on the fast path (fastpath.h; --ode for the reference).
 *
 * Domain: E2 over [modulus_min_pa, modulus_max_pa] (6 values), fruit mass
 * over [mass_min_kg, mass_max_kg] (4), R2 from the equatorial radius of that
 * mass (a sphere at the cultivar's density) down to --r2-min (3, geometric).
 * Margin of one apple: min(band margin, damage margin) [dB], where the band
 * margin is the 0S2's level re the selected lobe's peak minus the band's
 * level (-6 or -3 dB; forced negative when outside the band) and the damage
 * margin 20 log10(yield / shear). A strike's margin is its worst apple's. */
#define _POSIX_C_SOURCE 200809L /* clock_gettime */
#include "design.h"

#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "cli_flags.h"
#include "fastpath.h"
#include "model_table.h"
#include "options.h"
#include "plot.h"
#include "settings.h"

#define N_E2 6
#define N_MASS 4
#define N_R2 3
#define N_GRID AF_DESIGN_GRID
#define N_TIPS 4
#define NO_STRIKE (1 << 30) /* best->failed before any strike was answered */
#define PROGRESS_S 1.0      /* a progress line on stderr every [s] of a long search */

static double now_s(void)
{
  struct timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* One line on stderr every PROGRESS_S of a search that lasts longer (heavy
 * hammers take the ODE: a wide box can run for seconds), never on stdout. */
static void progress(int done, double start_s, double *last_s)
{
  double t = now_s();
  if (t - *last_s < PROGRESS_S)
    return;
  fprintf(stderr, "firmness_model design: %d/%d cells searched, %.1f s\n", done, AF_DESIGN_CELLS,
          t - start_s);
  *last_s = t;
}

/* The defaults the parser starts from: the search box of the strike and
 * the shipped cultivar. */
static const af_design_args design_defaults = {
    0.002, 0.05, 0.3, 3.0, 0.0, 0.02, 0.0, 0.025, AF_CONFIG_DIR "/jonagold.yaml", NULL, false};

#define AF_ARG(field) offsetof(af_design_args, field)
/* The ranges are the parameter table rows' that the strike's fields take. */
static const af_option design_options[] = {
    {"--cultivar", "FILE", AF_OPTION_TEXT, AF_ARG(cultivar), -1, NULL,
     "the cultivar's YAML: E2, mass, e, nu2, density, yield law", NULL, false},
    {"--hammer-mass-range", "A:B", AF_OPTION_RANGE, AF_ARG(m_lo), AF_SETTING_HAMMER_MASS_KG, NULL,
     "hammer masses searched, A <= B, each in the range", NULL, false},
    {"--v0-range", "A:B", AF_OPTION_RANGE, AF_ARG(v_lo), AF_SETTING_STRIKE_VELOCITY_M_S, NULL,
     "contact velocities searched, A <= B, each in the range", NULL, false},
    {"--tip-radius-range", "A:B", AF_OPTION_RANGE, AF_ARG(tip_lo), AF_SETTING_HAMMER_TIP_RADIUS_M,
     NULL, "tip radii searched, A <= B, each in the range, A = 0 adds the flat face", NULL, false},
    {"--hammer-modulus", "PA", AF_OPTION_NUMBER, AF_ARG(hammer_modulus),
     AF_SETTING_HAMMER_MODULUS_PA, NULL, "hammer tip modulus, 0 = rigid", "rigid", false},
    {"--r2-min", "M", AF_OPTION_NUMBER, AF_ARG(r2_min), AF_SETTING_STRIKE_RADIUS_MIN_M, NULL,
     "smallest radius of curvature under the hammer of the domain", NULL, false},
    {"--plot", "FILE", AF_OPTION_TEXT, AF_ARG(plot), -1, NULL,
     "the feasibility map, FILE.png or FILE.svg", "no map", false},
    {"--ode", NULL, AF_OPTION_SWITCH, AF_ARG(ode), -1, NULL,
     "the reference ODE path instead of the fast path (fastpath.h)", NULL, false},
};
#define N_OPTIONS (sizeof design_options / sizeof design_options[0])

af_design_args af_design_args_default(void)
{
  return design_defaults;
}

const af_option *af_design_options(size_t *n)
{
  *n = N_OPTIONS;
  return design_options;
}

static void design_help(void)
{
  printf("usage: firmness_model design [flags]\n\n"
         "The strike (hammer mass, contact velocity, tip radius) that makes every apple of\n"
         "the cultivar's domain reliable with the largest margin, and the paper's optimum on\n"
         "the same domain.\n\nflags:\n");
  af_options_help(stdout, design_options, N_OPTIONS, &design_defaults, NULL);
  printf("\nexit status: 0 done, 1 model failure, 2 bad input\n");
}

static bool parse_args(int argc, char **argv, int first, af_design_args *a)
{
  *a = design_defaults;
  const af_options_parser p = {
      "firmness_model design", {{design_options, N_OPTIONS, a, NULL, NULL}}, 1, NULL, false};
  return af_options_parse(&p, argc, argv, first);
}

static af_status eval(af_fastpath *f, af_model *m, bool ode, const af_model_params *p,
                      af_model_result *r)
{
  return ode ? af_model_execute(m, p, r) : af_fastpath_execute(f, p, r);
}

/* Band margin [dB] of one result. */
static double band_margin_db(const af_model_params *p, const af_model_result *r)
{
  if (!r->band_found)
    return -60.0;
  double thr = 20.0 * log10(af_band_level_ratio(p->band_level));
  double lobe_db = 20.0 * log10(r->band.peak_magnitude_n_s / r->lobes[0].peak_magnitude_n_s);
  double m = r->excitation_at_resonance_db - lobe_db - thr;
  return r->excites_mode ? fmax(m, 0.0) : fmin(m, -0.01);
}

/* The domain's apples under the strike of *base: the worst margin into
 * *out (its strike fields untouched); the apples given up into lost[*n_lost]
 * when lost is not NULL. */
static af_status evaluate_strike(af_fastpath *f, af_model *m, const af_design_args *a,
                                 const af_model_params *base, const af_design_result *dom,
                                 af_design_strike *out, af_design_lost *lost, int *n_lost)
{
  out->margin_db = INFINITY;
  out->failed = 0;
  out->delivered_energy_j = out->absorbed_energy_j = out->absorbed_e = NAN;
  out->min_yield_over_shear = INFINITY;
  out->damaged = out->bruised = 0;
  for (int i = 0; i < N_E2; i++)
    for (int j = 0; j < N_MASS; j++) {
      af_model_params p = *base;
      p.impact.fruit_modulus_pa =
          dom->modulus_min_pa + (dom->modulus_max_pa - dom->modulus_min_pa) * i / (N_E2 - 1);
      p.fruit_mass_kg = dom->mass_min_kg + (dom->mass_max_kg - dom->mass_min_kg) * j / (N_MASS - 1);
      double r_eq = cbrt(3.0 * p.fruit_mass_kg / (4.0 * M_PI * p.fruit_density_kg_m3));
      double r_lo = fmin(a->r2_min, r_eq);
      for (int k = 0; k < N_R2; k++) {
        af_model_result r;
        p.impact.strike_radius_m = r_eq * pow(r_lo / r_eq, (double)k / (N_R2 - 1));
        af_status st = eval(f, m, a->ode, &p, &r);
        if (st != AF_OK)
          return st;
        double band = band_margin_db(&p, &r);
        double dmg = 20.0 * log10(r.yield_shear_stress_pa / r.max_shear_stress_pa);
        double mg = fmin(band, dmg);
        out->delivered_energy_j = r.delivered_energy_j;
        if (!(r.absorbed_energy_j <= out->absorbed_energy_j)) /* the first, or more */
          out->absorbed_energy_j = r.absorbed_energy_j,
          out->absorbed_e = r.impact.delivered_restitution;
        out->min_yield_over_shear =
            fmin(out->min_yield_over_shear, r.yield_shear_stress_pa / r.max_shear_stress_pa);
        out->damaged += !r.no_damage;
        out->bruised += !r.below_bruise_energy;
        if (!r.reliable) {
          out->failed++;
          if (lost)
            lost[(*n_lost)++] = (af_design_lost){p.impact.fruit_modulus_pa, p.fruit_mass_kg,
                                                 p.impact.strike_radius_m, band < 0, dmg < 0};
        }
        if (mg < out->margin_db) {
          out->margin_db = mg, out->band_db = band, out->damage_db = dmg;
          out->e2_pa = p.impact.fruit_modulus_pa, out->mass_kg = p.fruit_mass_kg;
          out->r2_m = p.impact.strike_radius_m;
        }
      }
    }
  return AF_OK;
}

static double grid_at(double lo, double hi, int k, int n)
{
  return n == 1 || hi == lo ? lo : lo * pow(hi / lo, (double)k / (n - 1));
}

/* base with the strike (m1 [kg], v0 [m/s], tip [m]). */
static af_model_params with_strike(const af_model_params *base, double m1, double v0, double tip)
{
  af_model_params p = *base;
  p.impact.hammer_mass_kg = m1;
  p.impact.velocity_m_s = v0;
  p.impact.hammer_radius_m = tip;
  return p;
}

/* The cultivar's model parameters and domain into *base and *r; false with
 * err on a file or value that cannot be used. */
static bool load_cultivar(const af_design_args *a, af_model_params *base, af_design_result *r,
                          char *err, size_t len)
{
  af_settings s;
  char why[512];
  af_settings_reset(&s);
  if (af_settings_load_yaml(&s, a->cultivar, why, sizeof why) != AF_OK) {
    snprintf(err, len, "%s", why);
    return false;
  }
  /* The table's model with the cultivar's rows: what the node derives. */
  if (af_model_params_from_settings(&s, base, why, sizeof why) != AF_OK) {
    snprintf(err, len, "%s: %s", a->cultivar, why);
    return false;
  }
  base->impact.hammer_modulus_pa = a->hammer_modulus;
  r->modulus_min_pa = af_settings_number(&s, AF_SETTING_MODULUS_MIN_PA);
  r->modulus_max_pa = af_settings_number(&s, AF_SETTING_MODULUS_MAX_PA);
  r->mass_min_kg = af_settings_number(&s, AF_SETTING_MASS_MIN_KG);
  r->mass_max_kg = af_settings_number(&s, AF_SETTING_MASS_MAX_KG);
  r->restitution = base->impact.restitution;
  r->bruise_energy_j = base->bruise_energy_j;
  return true;
}

/* The grid search: the best strike, the feasibility map, the feasible box. */
static af_status search(af_fastpath *f, af_model *m, const af_design_args *a,
                        const af_model_params *base, af_design_result *r)
{
  double tips[N_TIPS + 1];
  int n_tips = 0;
  if (a->tip_lo == 0.0)
    tips[n_tips++] = 0.0;
  double t_lo = fmax(a->tip_lo, 0.002);
  if (a->tip_hi >= t_lo)
    for (int k = 0; k < N_TIPS; k++)
      tips[n_tips++] = grid_at(t_lo, a->tip_hi, k, N_TIPS);
  r->n_tips = n_tips;
  af_design_strike *best = &r->recommended;
  *best = (af_design_strike){0};
  best->margin_db = -INFINITY, best->failed = NO_STRIKE;
  r->feasible_cells = 0;
  r->failed_cells = 0, r->failed_strikes = 0, r->failed_status = AF_OK;
  r->feasible_m_lo_kg = INFINITY, r->feasible_m_hi_kg = 0;
  r->feasible_v_lo_m_s = INFINITY, r->feasible_v_hi_m_s = 0;
  double start_s = now_s(), last_s = start_s;
  for (int i = 0; i < N_GRID; i++)
    for (int j = 0; j < N_GRID; j++) {
      double m1 = grid_at(a->m_lo, a->m_hi, i, N_GRID), v0 = grid_at(a->v_lo, a->v_hi, j, N_GRID);
      double cell = -INFINITY;
      for (int t = 0; t < n_tips; t++) {
        af_model_params p = with_strike(base, m1, v0, tips[t]);
        af_design_strike e = {.hammer_mass_kg = m1, .velocity_m_s = v0, .tip_radius_m = tips[t]};
        af_status st = evaluate_strike(f, m, a, &p, r, &e, NULL, NULL);
        if (st == AF_EINVAL)
          return st;
        if (st != AF_OK) { /* the model cannot answer this strike: failed, counted */
          if (r->failed_strikes++ == 0)
            r->failed_status = st;
          continue;
        }
        cell = fmax(cell, e.margin_db);
        /* Best: all reliable first, then the largest worst margin; without
         * a feasible strike the fewest apples given up. */
        if (e.failed < best->failed || (e.failed == best->failed && e.margin_db > best->margin_db))
          *best = e;
      }
      r->map_mass_g[i * N_GRID + j] = m1 * 1e3;
      r->map_v_m_s[i * N_GRID + j] = v0;
      r->map_margin_db[i * N_GRID + j] = cell; /* -inf: every tip failed */
      r->failed_cells += cell == -INFINITY;
      if (cell >= 0.0) {
        r->feasible_cells++;
        r->feasible_m_lo_kg = fmin(r->feasible_m_lo_kg, m1);
        r->feasible_m_hi_kg = fmax(r->feasible_m_hi_kg, m1);
        r->feasible_v_lo_m_s = fmin(r->feasible_v_lo_m_s, v0);
        r->feasible_v_hi_m_s = fmax(r->feasible_v_hi_m_s, v0);
      }
      progress(i * N_GRID + j + 1, start_s, &last_s);
    }
  return AF_OK;
}

/* After the search: the apples the best compromise gives up (a failure
 * there leaves the list as far as it got, as the printed list did), and
 * the paper's optimum: the parameter table's strike (its velocity, the
 * shipped rig's hammer), which base holds. */
static void compare(af_fastpath *f, af_model *m, const af_design_args *a,
                    const af_model_params *base, af_design_result *r)
{
  r->n_lost = 0;
  if (r->recommended.failed > 0) {
    const af_design_strike *b = &r->recommended;
    af_model_params p = with_strike(base, b->hammer_mass_kg, b->velocity_m_s, b->tip_radius_m);
    af_design_strike e;
    (void)evaluate_strike(f, m, a, &p, r, &e, r->lost, &r->n_lost);
  }
  const af_impact_params opt = base->impact;
  af_model_params p = with_strike(base, opt.hammer_mass_kg, opt.velocity_m_s, opt.hammer_radius_m);
  r->paper = (af_design_strike){.hammer_mass_kg = opt.hammer_mass_kg,
                                .velocity_m_s = opt.velocity_m_s,
                                .tip_radius_m = opt.hammer_radius_m};
  r->paper_status = evaluate_strike(f, m, a, &p, r, &r->paper, NULL, NULL);
}

af_status af_design_execute(const af_design_args *a, af_design_result *out, bool *bad_input,
                            char *err, size_t len)
{
  af_model_params base;
  *bad_input = true;
  if (!load_cultivar(a, &base, out, err, len))
    return AF_EINVAL;
  *bad_input = false;
  af_fastpath *f = NULL;
  af_model *m = NULL;
  if (a->ode ? af_model_create(&m) != AF_OK : af_fastpath_create(&f) != AF_OK) {
    snprintf(err, len, "cannot create the model");
    return AF_ENOMEM;
  }
  af_status st = search(f, m, a, &base, out);
  if (st == AF_OK && out->recommended.failed == NO_STRIKE) {
    st = out->failed_status;
    snprintf(err, len, "the model failed on every strike of the box (%d): %s", out->failed_strikes,
             af_strerror(st));
  } else if (st != AF_OK) {
    *bad_input = st == AF_EINVAL;
    snprintf(err, len, "the model failed: %s", af_strerror(st));
  } else
    compare(f, m, a, &base, out);
  af_fastpath_destroy(f);
  af_model_destroy(m);
  return st;
}

static void print_strike(FILE *out, const char *what, const af_design_strike *e,
                         double bruise_energy_j)
{
  double tip = e->tip_radius_m;
  fprintf(out, "%s: hammer %.1f g at %.2f m/s, tip %s", what, e->hammer_mass_kg * 1e3,
          e->velocity_m_s, tip > 0.0 ? "" : "flat");
  if (tip > 0.0)
    fprintf(out, "radius %.1f mm", tip * 1e3);
  fprintf(out,
          "\n  worst apple: E2 %.2f MPa, %.0f g, R2 %.1f mm: band margin %+.2f dB, damage margin "
          "%+.2f dB (yield / shear %.3f); %d of %d apples not reliable\n",
          e->e2_pa / 1e6, e->mass_kg * 1e3, e->r2_m * 1e3, e->band_db, e->damage_db,
          pow(10.0, e->damage_db / 20.0), e->failed, AF_DESIGN_APPLES);
  fprintf(out,
          "  energy: %.2f mJ delivered (m1 v0^2 / 2), up to %.2f mJ absorbed (1 - e^2, e "
          "%.3f)\n",
          e->delivered_energy_j * 1e3, e->absorbed_energy_j * 1e3, e->absorbed_e);
  /* Both readings over the same apples; the shear's is the verdict. */
  fprintf(out,
          "  damage readings: shear (the criterion) %d of %d apples damaged, smallest yield / "
          "shear %.3f; bruise energy %d of %d apples bruised, absorbed / threshold %.3f of "
          "%.1f mJ\n",
          e->damaged, AF_DESIGN_APPLES, e->min_yield_over_shear, e->bruised, AF_DESIGN_APPLES,
          e->absorbed_energy_j / bruise_energy_j, bruise_energy_j * 1e3);
}

void af_design_print(FILE *out, const char *cultivar, const af_design_args *a,
                     const af_design_result *r)
{
  fprintf(out,
          "cultivar %s: E2 %.1f-%.1f MPa, %.0f-%.0f g, R2 from the equatorial radius down to "
          "%.1f mm; e %.2f; hammer modulus %s\n",
          cultivar, r->modulus_min_pa / 1e6, r->modulus_max_pa / 1e6, r->mass_min_kg * 1e3,
          r->mass_max_kg * 1e3, a->r2_min * 1e3, r->restitution,
          a->hammer_modulus > 0 ? "given" : "rigid");
  fprintf(out,
          "searched: hammer %.1f-%.1f g x v0 %.2f-%.2f m/s (%d x %d, geometric) x %d tips; %d "
          "apples per strike; %s path\n",
          a->m_lo * 1e3, a->m_hi * 1e3, a->v_lo, a->v_hi, N_GRID, N_GRID, r->n_tips,
          AF_DESIGN_APPLES, a->ode ? "ODE" : "fast");
  print_strike(out,
               r->recommended.failed == 0 ? "recommended strike"
                                          : "no feasible strike; best compromise",
               &r->recommended, r->bruise_energy_j);
  for (int k = 0; k < r->n_lost; k++) {
    const af_design_lost *l = &r->lost[k];
    fprintf(out, "    gives up E2 %5.2f MPa, %3.0f g, R2 %4.1f mm: %s\n", l->e2_pa / 1e6,
            l->mass_kg * 1e3, l->r2_m * 1e3,
            l->outside_band ? (l->damaged ? "outside the band and damaged" : "outside the band")
                            : "damaged");
  }
  if (r->feasible_cells > 0)
    fprintf(out,
            "feasible region (best tip per cell): %d of %d cells, hammer %.1f-%.1f g, v0 "
            "%.2f-%.2f m/s\n",
            r->feasible_cells, AF_DESIGN_CELLS, r->feasible_m_lo_kg * 1e3,
            r->feasible_m_hi_kg * 1e3, r->feasible_v_lo_m_s, r->feasible_v_hi_m_s);
  else
    fprintf(out, "feasible region: none in the searched ranges\n");
  if (r->failed_strikes > 0)
    fprintf(out,
            "failed: %d strikes (%d of %d cells wholly) the model could not answer, marked "
            "infeasible: %s\n",
            r->failed_strikes, r->failed_cells, AF_DESIGN_CELLS, af_strerror(r->failed_status));
  if (r->paper_status == AF_OK)
    print_strike(out, "the paper's optimum", &r->paper, r->bruise_energy_j);
}

/* The feasibility map into a->plot; false when it cannot be drawn. */
static bool draw_map(const af_design_args *a, const af_design_result *r)
{
  static double fx[AF_DESIGN_CELLS], fy[AF_DESIGN_CELLS], nx_[AF_DESIGN_CELLS],
      ny_[AF_DESIGN_CELLS];
  size_t nf = 0, nn = 0;
  for (int k = 0; k < AF_DESIGN_CELLS; k++) {
    if (r->map_margin_db[k] >= 0.0)
      fx[nf] = r->map_mass_g[k], fy[nf++] = r->map_v_m_s[k];
    else
      nx_[nn] = r->map_mass_g[k], ny_[nn++] = r->map_v_m_s[k];
  }
  double bx = r->recommended.hammer_mass_kg * 1e3, by = r->recommended.velocity_m_s;
  double px = r->paper.hammer_mass_kg * 1e3, py = r->paper.velocity_m_s;
  char rec_label[96], paper_label[64], err[512];
  snprintf(rec_label, sizeof rec_label, "%s: %.1f g at %.2f m/s",
           r->recommended.failed == 0 ? "recommended" : "best compromise", bx, by);
  snprintf(paper_label, sizeof paper_label, "paper's optimum (%.0f g, %.1f m/s)", px, py);
  af_plot_series ser[4] = {
      {"feasible: every apple reliable", fx, fy, nf, AF_PLOT_GREEN, AF_PLOT_POINTS},
      {"not feasible", nx_, ny_, nn, AF_PLOT_LIGHT_RED, AF_PLOT_POINTS},
      {rec_label, &bx, &by, 1, AF_PLOT_BLUE, AF_PLOT_MARKER},
      {paper_label, &px, &py, 1, AF_PLOT_ORANGE, AF_PLOT_MARKER},
  };
  af_plot_panel panel = af_plot_panel_empty();
  panel.title = "Feasibility map of the strike over the cultivar's domain";
  panel.subtitle = "best tip per cell; worst apple's margin >= 0 dB = feasible";
  panel.x_label = "hammer mass [g]";
  panel.y_label = "contact velocity v0 [m/s]";
  panel.series = ser;
  panel.n_series = 4;
  panel.legend = AF_PLOT_LEGEND_BELOW;
  af_plot_target t;
  return af_plot_target_file(a->plot, 900, 700, &t) == AF_OK &&
         af_plot_draw(&t, &panel, 1, 1, err, sizeof err) == AF_OK;
}

int af_design_main(int argc, char **argv, int first)
{
  af_design_args a;
  if (af_options_want_help(argc, argv, first)) {
    design_help();
    return 0;
  }
  if (!parse_args(argc, argv, first, &a))
    return AF_CLI_EXIT_USAGE;
  static af_design_result r;
  char err[1100];
  bool bad_input = false;
  if (af_design_execute(&a, &r, &bad_input, err, sizeof err) != AF_OK) {
    fprintf(stderr, "firmness_model design: %s\n", err);
    return bad_input ? AF_CLI_EXIT_USAGE : 1;
  }
  af_design_print(stdout, a.cultivar, &a, &r);
  int rc = 0;
  if (r.paper_status != AF_OK) { /* said, never left out in silence */
    fprintf(stderr, "firmness_model design: the paper's optimum could not be evaluated: %s\n",
            af_strerror(r.paper_status));
    rc = 1;
  }
  if (a.plot) {
    if (!draw_map(&a, &r)) {
      fprintf(stderr, "firmness_model design: cannot draw --plot %s\n", a.plot);
      rc = AF_CLI_EXIT_USAGE;
    } else
      af_options_wrote(a.plot);
  }
  return rc;
}
