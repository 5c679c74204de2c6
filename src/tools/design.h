/* design.h — `firmness_model design`: the strike designer. The search is
 * af_design_execute, which fills an af_design_result; `firmness_model design`
 * prints it (af_design_print) and `firmness_model paper` quotes and judges
 * the same struct. */
#ifndef AF_TOOLS_DESIGN_H
#define AF_TOOLS_DESIGN_H

#include <stdbool.h>
#include <stddef.h>
#include <stdio.h>

#include "options.h"
#include "status.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

#define AF_DESIGN_APPLES 72 /* apples of the domain: 6 E2 x 4 masses x 3 R2 */
#define AF_DESIGN_GRID 24   /* hammer masses x contact velocities searched, each */
#define AF_DESIGN_CELLS (AF_DESIGN_GRID * AF_DESIGN_GRID)

/* The designer's flags (af_design_options): the search box and the cultivar. */
typedef struct {
  double m_lo, m_hi;     /* hammer masses searched [kg] */
  double v_lo, v_hi;     /* contact velocities searched [m/s] */
  double tip_lo, tip_hi; /* tip radii searched [m]; tip_lo 0 adds the flat face */
  double hammer_modulus; /* hammer tip modulus [Pa]; 0 = rigid */
  double r2_min;         /* smallest radius of curvature of the domain [m] */
  const char *cultivar;  /* the cultivar's YAML (path) */
  const char *plot;      /* the feasibility map, FILE.png or .svg; NULL = none */
  bool ode;              /* the reference ODE path instead of the fast path */
} af_design_args;

/* The shipped search box and cultivar (what the flags start from). */
af_design_args af_design_args_default(void);

/* One strike over the domain: its worst apple and how many it gives up. */
typedef struct {
  double hammer_mass_kg, velocity_m_s, tip_radius_m; /* the strike; tip 0 = flat */
  double margin_db;                                  /* the worst apple's min(band, damage) */
  double band_db, damage_db;                         /* that apple's two margins [dB] */
  double e2_pa, mass_kg, r2_m;                       /* that apple */
  int failed; /* apples not reliable (counted up to the worst apple: see design.c) */
  /* The energy and the two damage readings over the whole domain: the shear
   * criterion (the verdict) and the absorbed energy against the cultivar's
   * bruise_energy_j (shown beside it, never judged by). */
  double delivered_energy_j;   /* m1 v0^2 / 2 [J] */
  double absorbed_energy_j;    /* the largest (1 - e^2) share over the domain's apples [J] */
  double absorbed_e;           /* that apple's delivered restitution */
  double min_yield_over_shear; /* the smallest yield / shear over the domain */
  int damaged;                 /* apples whose shear reaches the yield */
  int bruised;                 /* apples whose absorbed energy reaches bruise_energy_j */
} af_design_strike;

/* One apple a strike gives up and why. */
typedef struct {
  double e2_pa, mass_kg, r2_m;
  bool outside_band, damaged;
} af_design_lost;

typedef struct {
  double modulus_min_pa, modulus_max_pa, mass_min_kg, mass_max_kg; /* the cultivar's domain */
  double restitution;                                              /* the cultivar's e */
  double bruise_energy_j;                /* the cultivar's bruise threshold (absorbed energy) [J] */
  int n_tips;                            /* tip radii tried per cell */
  af_design_strike recommended;          /* failed 0: every apple kept; else the best compromise */
  af_design_lost lost[AF_DESIGN_APPLES]; /* the apples the best compromise gives up */
  int n_lost;                            /* 0 when recommended.failed is 0 */
  int feasible_cells;                    /* cells whose best tip keeps every apple */
  int failed_strikes;      /* strikes (cell x tip) the model could not answer: infeasible */
  int failed_cells;        /* cells whose every tip failed (map margin -inf) */
  af_status failed_status; /* the first failed strike's status (AF_OK: none) */
  double feasible_m_lo_kg, feasible_m_hi_kg, feasible_v_lo_m_s, feasible_v_hi_m_s;
  af_design_strike paper; /* the paper's optimum on the same domain */
  af_status paper_status; /* AF_OK, or why the paper's optimum could not be evaluated */
  double map_mass_g[AF_DESIGN_CELLS], map_v_m_s[AF_DESIGN_CELLS]; /* the grid */
  double map_margin_db[AF_DESIGN_CELLS]; /* best tip's worst margin; >= 0 feasible */
} af_design_result;

/* Loads a->cultivar and searches the strike. AF_OK and *out (check
 * out->paper_status too); else one line into err (without the tool's name)
 * and *bad_input true for a cultivar file or value that cannot be used,
 * false for a model failure. Creates and destroys the model within the
 * call. */
af_status af_design_execute(const af_design_args *a, af_design_result *out, bool *bad_input,
                            char *err, size_t len);

/* The designer's report of r, as `firmness_model design` prints it;
 * cultivar is the path shown (e.g. relative to the package). */
void af_design_print(FILE *out, const char *cultivar, const af_design_args *a,
                     const af_design_result *r);

/* argv[first..] are the designer's flags. Exit status: 0, 1 model failure,
 * 2 bad input. */
int af_design_main(int argc, char **argv, int first);

/* Its flag table (the usage of firmness_model lists it); *n entries. */
const af_option *af_design_options(size_t *n);

#endif
