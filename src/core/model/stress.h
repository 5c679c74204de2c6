/* stress.h — contact pressure, subsurface shear and the yield criterion.
 *
 * a = sqrt(R d), p0 = 3 F / (2 pi a^2) (Johnson, Contact Mechanics, eq. 4.23;
 * equals 2 a E* / (pi R) when elastic; the paper's eq. 3 carries an extra
 * sqrt(R2) and is dimensionally wrong). The maximum shear stress lies on the
 * axis below the surface: tau_max = ratio(nu) p0 at z = depth(nu) a. The paper
 * uses 0.31 at 0.48 a; the exact Hertz values are 0.3100 at 0.481 a (nu 0.30),
 * 0.2987 at 0.497 a (0.35), 0.268 at 0.544 a (0.49).
 */
#ifndef AF_STRESS_H
#define AF_STRESS_H

#include <stddef.h>

#include "status.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum { AF_SHEAR_PAPER = 0, AF_SHEAR_EXACT } af_shear_ratio;

/* "paper", "exact". */
const char *af_shear_ratio_name(af_shear_ratio mode);
af_status af_shear_ratio_parse(const char *name, af_shear_ratio *mode);

/* a = sqrt(R d) [m]. */
double af_stress_contact_radius_m(double radius_m, double deformation_m);
/* Elastic Hertz contact radius from the force: a = (3 F R / (4 E*))^(1/3) [m]. */
double af_stress_hertz_contact_radius_m(double force_n, double radius_m,
                                        double effective_modulus_pa);
/* p0 = 3 F / (2 pi a^2) [Pa]. */
double af_stress_center_pressure_pa(double force_n, double contact_radius_m);

/* Largest p0 over a sampled impact: max_k 3 F_k / (2 pi R d_k) over d_k > 0.
 * *at (may be NULL) receives the sample index. AF_ENODATA when no d_k > 0. */
af_status af_stress_max_center_pressure_pa(const double *force_n, const double *deformation_m,
                                           size_t n, double radius_m, double *p0_pa, size_t *at);

/* tau_max / p0 and its depth z / a on the axis. AF_SHEAR_PAPER: 0.31 and 0.48
 * for any nu. AF_SHEAR_EXACT: maximised over depth from the Hertz axial
 * stresses for nu in [0, 0.5). */
af_status af_stress_shear_ratio(af_shear_ratio mode, double poisson, double *ratio,
                                double *depth_over_a);

/* tau_max / p0 of the last mode and Poisson ratio asked (its GSL minimiser
 * allocates; a station asks for the same pair at every strike). Initialise
 * with af_shear_cache_reset. */
typedef struct {
  af_shear_ratio mode;
  double poisson; /* NaN: empty */
  double ratio;
} af_shear_cache;

void af_shear_cache_reset(af_shear_cache *c);
/* af_stress_shear_ratio's ratio, solved only when mode or poisson changed. */
af_status af_stress_shear_ratio_cached(af_shear_cache *c, af_shear_ratio mode, double poisson,
                                       double *ratio);

/* Yield shear stress [Pa] = yield_ratio * E2: a calibration, not a literature
 * value (PHYSICS.md 6). */
double af_stress_yield_shear_pa(double yield_ratio, double modulus_pa);

#ifdef __cplusplus
}
#endif
#endif
