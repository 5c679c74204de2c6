/* resonance.h — the lowest spherical mode (0S2) of a homogeneous elastic sphere.
 *
 * Lamb's frequency equation for the free sphere, spheroidal order n = 2,
 * solved for xi = omega a / c_s with GSL spherical Bessel functions and a
 * bracketing root finder; c_s = sqrt(E / (2 (1 + nu) rho)), a = (3 m / (4 pi rho))^(1/3).
 * xi depends on nu only: callers compute it once per Poisson ratio.
 * Reference values (PHYSICS.md 5): 2.6399 (nu 0.25), 2.6462 (0.30),
 * 2.6519 (0.35), 2.6569 (0.40), 2.6648 (0.49).
 */
#ifndef AF_RESONANCE_H
#define AF_RESONANCE_H

#include "status.h"

#ifdef __cplusplus
extern "C" {
#endif

/* xi of the 0S2 mode for nu in [0, 0.5). AF_EINVAL outside, AF_ENOROOT/AF_ENOCONV
 * if the root finder fails. */
af_status af_resonance_lamb_root(double poisson, double *xi);

/* xi of the last Poisson ratio asked: the root costs ~17 us and its GSL
 * solver allocates, while a station asks for the same ratio at every strike.
 * Initialise with af_lamb_cache_init. */
typedef struct {
  double poisson; /* NaN: empty */
  double xi;
} af_lamb_cache;

void af_lamb_cache_init(af_lamb_cache *c);
/* af_resonance_lamb_root, solved only when poisson differs from the cached one. */
af_status af_resonance_lamb_root_cached(af_lamb_cache *c, double poisson, double *xi);

/* Radius [m] of the sphere of this mass [kg] and density [kg/m3]. */
double af_resonance_sphere_radius_m(double mass_kg, double density_kg_m3);

/* 0S2 frequency [Hz] of a sphere of the given (dynamic) modulus [Pa], nu,
 * density [kg/m3] and mass [kg], with xi from af_resonance_lamb_root(nu). */
double af_resonance_frequency_hz(double xi, double modulus_pa, double poisson, double density_kg_m3,
                                 double mass_kg);

/* The inverse: the modulus [Pa] whose 0S2 frequency is f_hz. */
double af_resonance_modulus_pa(double xi, double f_hz, double poisson, double density_kg_m3,
                               double mass_kg);

/* Stiffness factor f^2 m^(2/3) [Hz^2 kg^(2/3)]. */
double af_resonance_stiffness_factor(double f_hz, double mass_kg);

#ifdef __cplusplus
}
#endif
#endif
