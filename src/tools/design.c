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
#include "design.h"

#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli_flags.h"
#include "fastpath.h"
#include "options.h"
#include "plot.h"
#include "settings.h"

#define N_E2 6
#define N_MASS 4
#define N_R2 3
#define N_GRID 24
#define N_TIPS 4

typedef struct {
  double m_lo, m_hi, v_lo, v_hi, tip_lo, tip_hi, hammer_modulus, r2_min;
  const char *cultivar, *plot;
  bool ode;
} af_design_args;

/* The defaults the parser starts from: the search box of the strike and
 * the shipped cultivar. */
static const af_design_args design_defaults = {
    0.002, 0.05, 0.3, 3.0, 0.0, 0.02, 0.0, 0.025, AF_CONFIG_DIR "/jonagold.yaml", NULL, false};

#define AF_ARG(field) offsetof(af_design_args, field)
static const af_option design_options[] = {
    {"--cultivar", "FILE", AF_OPTION_TEXT, AF_ARG(cultivar), -1,
     "the cultivar's YAML: E2, mass, e, nu2, density, yield law", NULL},
    {"--hammer-mass-range", "A:B", AF_OPTION_RANGE, AF_ARG(m_lo), -1,
     "hammer masses searched, 0 < A <= B [kg]", NULL},
    {"--v0-range", "A:B", AF_OPTION_RANGE, AF_ARG(v_lo), -1,
     "contact velocities searched, 0 < A <= B [m/s]", NULL},
    {"--tip-radius-range", "A:B", AF_OPTION_RANGE, AF_ARG(tip_lo), -1,
     "tip radii searched, 0 <= A <= B, A = 0 adds the flat face [m]", NULL},
    {"--hammer-modulus", "PA", AF_OPTION_NUMBER, AF_ARG(hammer_modulus), -1,
     "hammer tip modulus, 0 = rigid [Pa]", "rigid"},
    {"--r2-min", "M", AF_OPTION_NUMBER, AF_ARG(r2_min), -1,
     "smallest radius of curvature under the hammer of the domain [m]", NULL},
    {"--plot", "FILE", AF_OPTION_TEXT, AF_ARG(plot), -1,
     "the feasibility map, FILE.png or FILE.svg", "no map"},
    {"--ode", NULL, AF_OPTION_SWITCH, AF_ARG(ode), -1,
     "the reference ODE path instead of the fast path (fastpath.h)", NULL},
};
#define N_OPTIONS (sizeof design_options / sizeof design_options[0])

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

typedef struct {
  double margin_db, band_db, damage_db;
  double e2, mass, r2;
  int failed; /* apples not reliable */
} af_design_eval;

static bool parse_range(const char *flag, const char *text, double *lo, double *hi)
{
  char *end;
  *lo = strtod(text, &end);
  if (*end == ':') {
    *hi = strtod(end + 1, &end);
    if (*end == '\0' && isfinite(*lo) && isfinite(*hi) && *lo >= 0.0 && *hi >= *lo)
      return true;
  }
  fprintf(stderr, "firmness_model design: %s '%s' is not A:B with 0 <= A <= B\n", flag, text);
  return false;
}

static bool parse_args(int argc, char **argv, int first, af_design_args *a)
{
  *a = design_defaults;
  for (int k = first; k < argc; k++) {
    const char *f = argv[k];
    const af_option *o = af_option_find(design_options, N_OPTIONS, f);
    if (o != NULL && o->value == NULL) {
      (void)af_option_store(o, NULL, a);
      continue;
    }
    if (o == NULL) {
      af_options_unknown("firmness_model design", design_options, N_OPTIONS, f, NULL);
      return false;
    }
    if (k + 1 >= argc) {
      af_options_missing("firmness_model design", o);
      return false;
    }
    const char *v = argv[++k];
    char *end = NULL;
    bool ok = true;
    if (strcmp(f, "--cultivar") == 0)
      a->cultivar = v;
    else if (strcmp(f, "--plot") == 0)
      a->plot = v;
    else if (strcmp(f, "--hammer-mass-range") == 0)
      ok = parse_range(f, v, &a->m_lo, &a->m_hi) && a->m_lo > 0.0;
    else if (strcmp(f, "--v0-range") == 0)
      ok = parse_range(f, v, &a->v_lo, &a->v_hi) && a->v_lo > 0.0;
    else if (strcmp(f, "--tip-radius-range") == 0)
      ok = parse_range(f, v, &a->tip_lo, &a->tip_hi);
    else if (strcmp(f, "--hammer-modulus") == 0)
      a->hammer_modulus = strtod(v, &end), ok = *end == '\0' && a->hammer_modulus >= 0.0;
    else if (strcmp(f, "--r2-min") == 0)
      a->r2_min = strtod(v, &end), ok = *end == '\0' && a->r2_min > 0.0;
    else
      ok = false;
    if (!ok) {
      fprintf(stderr, "firmness_model design: %s '%s' is not accepted: %s\n", f, v, o->help);
      return false;
    }
  }
  return true;
}

static af_status eval(af_fastpath *f, af_model *m, bool ode, const af_model_params *p,
                      af_model_result *r)
{
  return ode ? af_model_evaluate(m, p, r) : af_fastpath_evaluate(f, p, r);
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

static af_status evaluate_strike(af_fastpath *f, af_model *m, const af_design_args *a,
                                 const af_model_params *base, const double dom[4],
                                 af_design_eval *out, FILE *list)
{
  out->margin_db = INFINITY;
  out->failed = 0;
  for (int i = 0; i < N_E2; i++)
    for (int j = 0; j < N_MASS; j++) {
      af_model_params p = *base;
      p.impact.fruit_modulus_pa = dom[0] + (dom[1] - dom[0]) * i / (N_E2 - 1);
      p.fruit_mass_kg = dom[2] + (dom[3] - dom[2]) * j / (N_MASS - 1);
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
        if (!r.reliable) {
          out->failed++;
          if (list)
            fprintf(list, "    gives up E2 %5.2f MPa, %3.0f g, R2 %4.1f mm: %s\n",
                    p.impact.fruit_modulus_pa / 1e6, p.fruit_mass_kg * 1e3,
                    p.impact.strike_radius_m * 1e3,
                    band < 0 ? (dmg < 0 ? "outside the band and damaged" : "outside the band")
                             : "damaged");
        }
        if (mg < out->margin_db) {
          *out = (af_design_eval){mg,
                                  band,
                                  dmg,
                                  p.impact.fruit_modulus_pa,
                                  p.fruit_mass_kg,
                                  p.impact.strike_radius_m,
                                  out->failed};
        }
      }
    }
  return AF_OK;
}

static double grid_at(double lo, double hi, int k, int n)
{
  return n == 1 || hi == lo ? lo : lo * pow(hi / lo, (double)k / (n - 1));
}

static void print_strike(const char *what, double m1, double v0, double tip,
                         const af_design_eval *e)
{
  printf("%s: hammer %.1f g at %.2f m/s, tip %s", what, m1 * 1e3, v0, tip > 0.0 ? "" : "flat");
  if (tip > 0.0)
    printf("radius %.1f mm", tip * 1e3);
  printf("\n  worst apple: E2 %.2f MPa, %.0f g, R2 %.1f mm: band margin %+.2f dB, damage margin "
         "%+.2f dB (yield / shear %.3f); %d of %d apples not reliable\n",
         e->e2 / 1e6, e->mass * 1e3, e->r2 * 1e3, e->band_db, e->damage_db,
         pow(10.0, e->damage_db / 20.0), e->failed, N_E2 * N_MASS * N_R2);
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
  af_settings s;
  char err[512];
  af_settings_init(&s);
  const char *cultivar = a.cultivar;
  if (af_settings_load_yaml(&s, cultivar, err, sizeof err) != AF_OK) {
    fprintf(stderr, "firmness_model design: %s\n", err);
    return AF_CLI_EXIT_USAGE;
  }
  af_model_params base = af_model_params_default();
  base.impact.restitution = af_settings_number(&s, AF_SETTING_RESTITUTION);
  base.impact.fruit_poisson = af_settings_number(&s, AF_SETTING_FRUIT_POISSON);
  base.impact.hammer_modulus_pa = a.hammer_modulus;
  base.fruit_density_kg_m3 = af_settings_number(&s, AF_SETTING_DENSITY_KG_M3);
  base.yield_ratio = af_settings_number(&s, AF_SETTING_YIELD_RATIO);
  base.yield_exponent = af_settings_number(&s, AF_SETTING_YIELD_EXPONENT);
  base.yield_reference_modulus_pa = af_settings_number(&s, AF_SETTING_YIELD_REFERENCE_MODULUS_PA);
  base.modulus_factor = af_settings_number(&s, AF_SETTING_MODULUS_FACTOR);
  if (af_yield_points_parse(af_settings_string(&s, AF_SETTING_YIELD_MEASURED), &base.yield_measured,
                            err, sizeof err) != AF_OK) {
    fprintf(stderr, "firmness_model design: %s: yield_measured: %s\n", cultivar, err);
    return AF_CLI_EXIT_USAGE;
  }
  double dom[4] = {af_settings_number(&s, AF_SETTING_MODULUS_MIN_PA),
                   af_settings_number(&s, AF_SETTING_MODULUS_MAX_PA),
                   af_settings_number(&s, AF_SETTING_MASS_MIN_KG),
                   af_settings_number(&s, AF_SETTING_MASS_MAX_KG)};
  af_fastpath *f = NULL;
  af_model *m = NULL;
  if (a.ode ? af_model_create(&m) != AF_OK : af_fastpath_create(&f) != AF_OK) {
    fprintf(stderr, "firmness_model design: cannot create the model\n");
    return 1;
  }
  double tips[N_TIPS + 1];
  int n_tips = 0;
  if (a.tip_lo == 0.0)
    tips[n_tips++] = 0.0;
  double t_lo = fmax(a.tip_lo, 0.002);
  if (a.tip_hi >= t_lo)
    for (int k = 0; k < N_TIPS; k++)
      tips[n_tips++] = grid_at(t_lo, a.tip_hi, k, N_TIPS);
  static double map_m[N_GRID * N_GRID], map_v[N_GRID * N_GRID], map_margin[N_GRID * N_GRID];
  af_design_eval best = {-INFINITY, 0, 0, 0, 0, 0, 1 << 30};
  double best_m = 0, best_v = 0, best_t = 0;
  int feasible = 0;
  double fm_lo = INFINITY, fm_hi = 0, fv_lo = INFINITY, fv_hi = 0;
  af_status st = AF_OK;
  for (int i = 0; i < N_GRID && st == AF_OK; i++)
    for (int j = 0; j < N_GRID && st == AF_OK; j++) {
      double m1 = grid_at(a.m_lo, a.m_hi, i, N_GRID), v0 = grid_at(a.v_lo, a.v_hi, j, N_GRID);
      double cell = -INFINITY;
      for (int t = 0; t < n_tips && st == AF_OK; t++) {
        af_model_params p = base;
        af_design_eval e;
        p.impact.hammer_mass_kg = m1;
        p.impact.velocity_m_s = v0;
        p.impact.hammer_radius_m = tips[t];
        st = evaluate_strike(f, m, &a, &p, dom, &e, NULL);
        if (st != AF_OK)
          break;
        cell = fmax(cell, e.margin_db);
        /* Best: all reliable first, then the largest worst margin; without
         * a feasible strike the fewest apples given up. */
        if (e.failed < best.failed || (e.failed == best.failed && e.margin_db > best.margin_db)) {
          best = e;
          best_m = m1, best_v = v0, best_t = tips[t];
        }
      }
      map_m[i * N_GRID + j] = m1 * 1e3;
      map_v[i * N_GRID + j] = v0;
      map_margin[i * N_GRID + j] = cell;
      if (cell >= 0.0) {
        feasible++;
        fm_lo = fmin(fm_lo, m1), fm_hi = fmax(fm_hi, m1), fv_lo = fmin(fv_lo, v0),
        fv_hi = fmax(fv_hi, v0);
      }
    }
  if (st != AF_OK) {
    fprintf(stderr, "firmness_model design: the model failed: %s\n", af_strerror(st));
    af_fastpath_destroy(f);
    af_model_destroy(m);
    return 1;
  }
  printf("cultivar %s: E2 %.1f-%.1f MPa, %.0f-%.0f g, R2 from the equatorial radius down to %.1f "
         "mm; e %.2f; hammer modulus %s\n",
         cultivar, dom[0] / 1e6, dom[1] / 1e6, dom[2] * 1e3, dom[3] * 1e3, a.r2_min * 1e3,
         base.impact.restitution, a.hammer_modulus > 0 ? "given" : "rigid");
  printf("searched: hammer %.1f-%.1f g x v0 %.2f-%.2f m/s (%d x %d, geometric) x %d tips; %d "
         "apples per strike; %s path\n",
         a.m_lo * 1e3, a.m_hi * 1e3, a.v_lo, a.v_hi, N_GRID, N_GRID, n_tips, N_E2 * N_MASS * N_R2,
         a.ode ? "ODE" : "fast");
  print_strike(best.failed == 0 ? "recommended strike" : "no feasible strike; best compromise",
               best_m, best_v, best_t, &best);
  if (best.failed > 0) {
    af_model_params p = base;
    af_design_eval e;
    p.impact.hammer_mass_kg = best_m, p.impact.velocity_m_s = best_v,
    p.impact.hammer_radius_m = best_t;
    evaluate_strike(f, m, &a, &p, dom, &e, stdout);
  }
  if (feasible > 0)
    printf("feasible region (best tip per cell): %d of %d cells, hammer %.1f-%.1f g, v0 %.2f-%.2f "
           "m/s\n",
           feasible, N_GRID * N_GRID, fm_lo * 1e3, fm_hi * 1e3, fv_lo, fv_hi);
  else
    printf("feasible region: none in the searched ranges\n");
  /* The paper's optimum: af_impact_params_default's strike (the shipped
   * rig's hammer, from the parameter table). */
  const af_impact_params opt = af_impact_params_default();
  af_model_params paper = base;
  af_design_eval pe;
  paper.impact.hammer_mass_kg = opt.hammer_mass_kg, paper.impact.velocity_m_s = opt.velocity_m_s;
  paper.impact.hammer_radius_m = opt.hammer_radius_m;
  int rc = 0;
  af_status ps = evaluate_strike(f, m, &a, &paper, dom, &pe, NULL);
  if (ps == AF_OK) {
    print_strike("the paper's optimum", opt.hammer_mass_kg, opt.velocity_m_s, opt.hammer_radius_m,
                 &pe);
  } else { /* said, never left out in silence */
    fprintf(stderr, "firmness_model design: the paper's optimum could not be evaluated: %s\n",
            af_strerror(ps));
    rc = 1;
  }
  if (a.plot) {
    static double fx[N_GRID * N_GRID], fy[N_GRID * N_GRID], nx_[N_GRID * N_GRID],
        ny_[N_GRID * N_GRID];
    size_t nf = 0, nn = 0;
    for (int k = 0; k < N_GRID * N_GRID; k++) {
      if (map_margin[k] >= 0.0)
        fx[nf] = map_m[k], fy[nf++] = map_v[k];
      else
        nx_[nn] = map_m[k], ny_[nn++] = map_v[k];
    }
    double bx = best_m * 1e3, by = best_v, px = opt.hammer_mass_kg * 1e3, py = opt.velocity_m_s;
    char rec_label[96], paper_label[64];
    snprintf(paper_label, sizeof paper_label, "paper's optimum (%.0f g, %.1f m/s)", px, py);
    snprintf(rec_label, sizeof rec_label, "%s: %.1f g at %.2f m/s",
             best.failed == 0 ? "recommended" : "best compromise", bx, by);
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
    if (af_plot_target_file(a.plot, 900, 700, &t) != AF_OK ||
        af_plot_draw(&t, &panel, 1, 1, err, sizeof err) != AF_OK) {
      fprintf(stderr, "firmness_model design: cannot draw --plot %s\n", a.plot);
      rc = AF_CLI_EXIT_USAGE;
    } else
      af_options_wrote(a.plot);
  }
  af_fastpath_destroy(f);
  af_model_destroy(m);
  return rc;
}
