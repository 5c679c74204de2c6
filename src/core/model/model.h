/* model.h — one full evaluation of a strike on one apple: impact, excitation
 * spectrum and lobes, 0S2 resonance, subsurface shear, and the criteria.
 *
 * af_model owns the impact and spectrum workspaces and the pulse buffers:
 * create once, evaluate many times without allocation.
 */
#ifndef AF_MODEL_H
#define AF_MODEL_H

#include <stdbool.h>
#include <stddef.h>

#include "impact.h"
#include "spectrum.h"
#include "status.h"
#include "stress.h"
#include "yield.h"

#ifdef __cplusplus
extern "C" {
#endif

#define AF_MODEL_MAX_LOBES 8

typedef struct {
  af_impact_params impact;    /* hammer and local contact */
  double fruit_mass_kg;       /* m > 0 */
  double fruit_density_kg_m3; /* rho > 0 */
  double modulus_factor;      /* dynamic / quasi-static modulus, > 0 (cultivar calibration) */
  unsigned lobe;              /* lobe of the criterion, 1-based (1 = main lobe) */
  af_band_level band_level;   /* half-power reading */
  af_shear_ratio shear_ratio; /* tau_max / p0: paper 0.31 or exact for nu2 */
  double yield_ratio;         /* tau_ref / E_ref of the yield law, > 0: a calibration */
  double yield_exponent;      /* p of tau_y = yield_ratio E_ref (E2/E_ref)^p; 1 = ratio law */
  double yield_reference_modulus_pa; /* E_ref [Pa] */
  af_yield_points yield_measured;    /* measured tau_y(E2); overrides the law when n > 0 */
  double bruise_energy_j;            /* absorbed energy [J] at which the second damage reading says
                                        "bruised": a calibration (doc/model.md); the verdict stays the
                                        shear criterion's */
} af_model_params;

/* The yield law of p (yield.h). */
af_yield_law af_model_yield_law(const af_model_params *p);

/* Shipped default profile: the paper's optimal strike on the average apple
 * (175 g, 840 kg/m3) with exact damping, lobe 1, amplitude-half, exact shear,
 * yield law tau_y = yield_ratio x E_ref x (E2 / E_ref)^yield_exponent, the
 * parameter table's rows (calibrated: the
 * average apple's damage boundary at the paper's 31 mm under this profile,
 * and an exponent below the shear's 0.8 so that soft apples are safe when
 * firm ones are, Fig. 3b's ordering; doc/paper.md), modulus factor 1. */
af_model_params af_model_params_default(void);
/* Paper-literal profile: LN damping as printed, lobe 2, power-half, 0.31. */
af_model_params af_model_params_paper(void);

/* Why a parameter set was refused: the field, its value and the accepted range. */
typedef struct {
  const char *field; /* C name of the field, e.g. "impact.fruit_modulus_pa" */
  double value;
  const char *range; /* e.g. "(0, inf)" */
} af_param_error;

/* AF_OK, or AF_EINVAL with *err (may be NULL) naming the first bad field. */
af_status af_model_params_check(const af_model_params *p, af_param_error *err);

typedef struct {
  af_impact_result impact;
  af_lobe lobes[AF_MODEL_MAX_LOBES]; /* at the configured band level */
  size_t n_lobes;
  bool band_found;                   /* the configured lobe exists */
  af_lobe band;                      /* the configured lobe (zeros when absent) */
  double resonance_hz;               /* 0S2 with the modulus factor applied */
  double excitation_at_resonance_db; /* spectrum level at the resonance [dB re max] */
  double max_contact_pressure_pa;    /* max over the contact of p0 */
  double max_shear_stress_pa;
  double yield_shear_stress_pa;
  bool excites_mode;
  bool no_damage;
  bool reliable;
  /* The second damage reading, beside the shear criterion (no_damage), which
   * alone sets reliable: the energy the strike delivers, m1 v0^2 / 2, the
   * share 1 - e^2 the fruit absorbs (e the delivered restitution) and
   * whether that stays below bruise_energy_j. */
  double delivered_energy_j; /* [J] */
  double absorbed_energy_j;  /* [J] */
  bool below_bruise_energy;
} af_model_result;

typedef struct af_model af_model;

af_status af_model_create(af_model **out); /* allocates everything */
void af_model_destroy(af_model *m);        /* NULL-safe */

/* Evaluates p. No allocation. AF_EINVAL for invalid p (see check). */
af_status af_model_execute(af_model *m, const af_model_params *p, af_model_result *r);

/* Smallest strike radius R2 [m] in [r_lo_m, r_hi_m] above which the strike is
 * reliable (root-found on the criteria over R2, all else as in p): the paper's
 * "31 mm". AF_ENOROOT when not reliable even at r_hi_m; *r_min_m = r_lo_m when
 * reliable down to r_lo_m; AF_EBUDGET_SEARCH after 80 evaluations
 * (a guard: about 36 suffice for any bracket); any status of af_model_execute. */
af_status af_model_min_strike_radius(af_model *m, const af_model_params *p, double r_lo_m,
                                     double r_hi_m, double *r_min_m);

/* Fills r's energy figures and bruise reading from p and
 * r->impact.delivered_restitution (af_model_execute calls it; the fast path
 * too, for the same figures). */
void af_model_energy_figures(const af_model_params *p, af_model_result *r);

/* One-line reason why r is not reliable ("" when reliable), into buf;
 * lobe is the configured lobe (p->lobe). */
void af_model_reason(const af_model_result *r, unsigned lobe, char *buf, size_t len);

#ifdef __cplusplus
}
#endif
#endif
