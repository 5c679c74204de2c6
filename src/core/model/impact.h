/* impact.h — hammer-on-fruit impact: Hertz contact with hysteresis damping.
 *
 * The hammer (mass m1) strikes the fruit at v0 under gravity. With the
 * deformation d (m, positive into the fruit):
 *     m1 d'' = m1 g - F,   d(0) = 0, d'(0) = v0,
 *     F = K d^1.5 (1 + chi d'/v0),  K = (4/3) E* sqrt(R),
 *     1/E* = (1 - nu2^2)/E2 + (1 - nu1^2)/E1  (E1 = 0: rigid hammer),
 *     1/R  = 1/R2 + 1/R1                      (R1 = 0: flat face).
 * Integrated with GSL odeiv2 (adaptive step); the contact ends at the event
 * d = 0, located by root finding, not by a fixed step. The printed paper has
 * the exponent 2/3: see the project's physics notes (PHYSICS.md) section 1 and
 * doc/deviations.md.
 *
 * Damping laws for chi(e):
 *   AF_DAMPING_PAPER  Lankarani-Nikravesh 3(1-e^2)/4, as printed. It saturates:
 *                     the restitution it delivers is not e (PHYSICS.md 2).
 *   AF_DAMPING_EXACT  chi root-found so that the delivered restitution equals
 *                     e (elastic-dimensionless, no gravity); tabulated once at
 *                     create time and interpolated.
 *   AF_DAMPING_HU_GUO 3(1-e)/(2e).
 */
#ifndef AF_IMPACT_H
#define AF_IMPACT_H

#include <stddef.h>

#include "status.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum { AF_DAMPING_PAPER = 0, AF_DAMPING_EXACT, AF_DAMPING_HU_GUO } af_damping_law;

/* "paper", "exact", "hu-guo". */
const char *af_damping_law_name(af_damping_law law);
/* AF_OK and *law set when name is one of the names above, else AF_EINVAL. */
af_status af_damping_law_parse(const char *name, af_damping_law *law);

typedef struct {
  double hammer_mass_kg;    /* m1 > 0 */
  double velocity_m_s;      /* v0 > 0, contact velocity */
  double hammer_modulus_pa; /* E1 >= 0; 0 = rigid hammer */
  double hammer_poisson;    /* nu1 in [0, 0.5) */
  double hammer_radius_m;   /* R1 >= 0; 0 = flat face */
  double fruit_modulus_pa;  /* E2 > 0 */
  double fruit_poisson;     /* nu2 in [0, 0.5) */
  double strike_radius_m;   /* R2 > 0, local radius of curvature of the fruit */
  double restitution;       /* e in (0, 1]; 1 = elastic */
  double gravity_m_s2;      /* >= 0; 9.80665 by default, 0 to switch it off */
  af_damping_law damping;
} af_impact_params;

/* The paper's optimal strike on the average apple, every value a row of the
 * parameter table (af_defaults.h): the shipped rig's hammer (the rows' rig
 * values), strike_velocity_m_s, a rigid tip, modulus_nominal_pa,
 * fruit_poisson, restitution, gravity_m_s2, damping_law; R2 40 mm (no row:
 * per apple, from its estimate). */
af_impact_params af_impact_params_default(void);

double af_impact_effective_modulus_pa(const af_impact_params *p); /* E* */
double af_impact_effective_radius_m(const af_impact_params *p);   /* R */
double af_impact_stiffness(const af_impact_params *p);            /* K [N/m^1.5] */
/* The impact's energy (PHYSICS.md 1): the hammer's kinetic energy at contact,
 * m1 v0^2 / 2 [J], is what the strike delivers; the fruit keeps the share
 * 1 - e^2 of it, e the restitution the hammer leaves with (gravity does no
 * net work over a contact that ends where it began). NaN when an input is
 * not finite (a figure not known). */
double af_impact_delivered_energy_j(double hammer_mass_kg, double velocity_m_s);
double af_impact_absorbed_energy_j(double delivered_energy_j, double restitution);
/* Closed-form elastic contact time without gravity, 2.86827 (m1^2/(R E*^2 v0))^(1/5) [s]:
 * the scale callers use to choose a sampling step before running. */
double af_impact_hertz_contact_time_s(const af_impact_params *p);

typedef struct af_impact af_impact;

/* Allocates the ODE driver and the exact damping law's interpolant. The
 * law's table is built once per process, by the first create (about 10 ms
 * of ODE runs), and shared read-only by every workspace; later creates take
 * microseconds. Creates may run on several threads at once; a workspace is
 * used by one thread at a time. Allocates. */
af_status af_impact_create(af_impact **out);
void af_impact_destroy(af_impact *w); /* NULL-safe */

/* chi for law and e in (0, 1] (chi = 0 at e = 1). AF_EINVAL outside. The
 * exact law is defined for e in [0.05, 1]. */
af_status af_impact_chi(const af_impact *w, af_damping_law law, double e, double *chi);

typedef struct {
  double contact_time_s; /* d returns to 0 (event-located) */
  double peak_force_n;   /* max F, refined between samples */
  double time_of_peak_s;
  double max_deformation_m;     /* max d (where d' = 0) */
  double delivered_restitution; /* -d'(t_c)/v0 */
  double chi;                   /* damping coefficient used */
  double dt_s;                  /* sampling step of the arrays */
  size_t n_samples;             /* samples written: t_k = k dt_s, t_k <= t_c */
} af_impact_result;

/* Work budget of one pulse: integration steps, the event searches' included.
 * The default strike takes about 150; a contact that does not end (a hammer
 * resting on the fruit, or parameters far outside the physical ranges of
 * settings_table.c) stops here within a few milliseconds. */
#define AF_IMPACT_STEP_BUDGET 20000

/* Runs one impact. When force_n (and/or deformation_m) is not NULL, F(t_k)
 * [N] (and d(t_k) [m]) are written for t_k = k dt_s, k = 0 .. n-1, t_{n-1} <= t_c;
 * F = 0 after t_c. AF_ESIZE when the pulse needs more than cap samples,
 * AF_EINVAL for invalid params or dt_s <= 0, AF_ENUMERIC / AF_ENOCONV when the
 * integration fails, AF_EBUDGET_ODE_STEPS after AF_IMPACT_STEP_BUDGET steps
 * or 1000 elastic time scales D/v0 of contact,
 * AF_EBUDGET_ROOT_ITER when an event search runs out of iterations. No
 * allocation. */
af_status af_impact_execute(af_impact *w, const af_impact_params *p, double dt_s, double *force_n,
                            double *deformation_m, size_t cap, af_impact_result *res);

/* The largest tolerance factor of af_impact_execute_from. */
#define AF_IMPACT_MAX_TOL_FACTOR 1e4

/* As af_impact_execute, the force alone, sampled at t_k = t_first_s + k dt_s
 * (t_first_s >= 0; t_{n-1} <= t_c), the integration's tolerances (about
 * 1e-9 on the dimensionless deformation and rate) times tol_factor (1 ..
 * AF_IMPACT_MAX_TOL_FACTOR): a model read at a measurement's own sample
 * times, as accurate as its use needs (the fit's check), with no
 * interpolation between samples. AF_EINVAL as af_impact_execute's, or for
 * t_first_s or tol_factor out of range. With t_first_s 0 and tol_factor 1
 * the samples are af_impact_execute's, bit for bit. No allocation. */
af_status af_impact_execute_from(af_impact *w, const af_impact_params *p, double t_first_s,
                                 double dt_s, double tol_factor, double *force_n, size_t cap,
                                 af_impact_result *res);

#ifdef __cplusplus
}
#endif
#endif
