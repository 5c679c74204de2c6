/* lamb.h — the free modes of a homogeneous elastic sphere: the 0S2
 * (the lowest, the apple's firmness mode) and its audible neighbours.
 *
 * Lamb's frequency equation for the free sphere, spheroidal order n, solved
 * for xi = omega a / c_s with GSL spherical Bessel functions and a
 * bracketing root finder; c_s = sqrt(E / (2 (1 + nu) rho)), a = (3 m / (4 pi rho))^(1/3).
 * xi depends on nu only: callers compute it once per Poisson ratio.
 * Reference values of the 0S2 (PHYSICS.md 5): 2.6399 (nu 0.25), 2.6462
 * (0.30), 2.6519 (0.35), 2.6569 (0.40), 2.6648 (0.49).
 *
 * Neighbouring modes, as ratios to the 0S2 (PHYSICS.md 5; independent of
 * size and modulus, so a comb with fixed spacing whatever the firmness):
 *
 *   nu    0S3/0S2  0S4/0S2  1S2/0S2  0T2/0S2
 *   0.25  1.4835   1.8976   1.8430   0.9474
 *   0.30  1.4879   1.9068   1.8921   0.9452
 *   0.35  1.4919   1.9153   1.9381   0.9432
 *   0.40  1.4954   1.9229   1.9804   0.9414
 *
 * nSl: order l (angular), overtone n (0 = the fundamental of that order);
 * 1S2 is the second root of the n = 2 equation. The 0S3/0S2 ratio hardly
 * moves with nu (+-0.4 %), the 1S2/0S2 one does (+-3.6 %). The 0T2 is
 * torsional: no radial surface motion, a microphone barely hears it.
 */
#ifndef AF_RESONANCE_H
#define AF_RESONANCE_H

#include "status.h"

#ifdef __cplusplus
extern "C" {
#endif

/* xi of the 0S2 mode for nu in [0, 0.5). AF_EINVAL outside, AF_ENOROOT/AF_ENOCONV
 * if the root finder fails. */
af_status af_lamb_root(double poisson, double *xi);

/* xi of the last Poisson ratio asked: the root costs ~17 us and its GSL
 * solver allocates, while a station asks for the same ratio at every strike.
 * Initialise with af_lamb_cache_reset. */
typedef struct {
  double poisson; /* NaN: empty */
  double xi;
} af_lamb_cache;

void af_lamb_cache_reset(af_lamb_cache *c);
/* af_lamb_root, solved only when poisson differs from the cached one. */
af_status af_lamb_root_cached(af_lamb_cache *c, double poisson, double *xi);

/* Orders and overtones af_lamb_spheroidal_root and
 * af_lamb_torsional_root accept: order 2..AF_RESONANCE_MAX_ORDER,
 * overtone 0..AF_RESONANCE_MAX_OVERTONE (the roots are scanned up to y = 40
 * with a 0.05 step, fine against their spacing in this range). */
#define AF_RESONANCE_MAX_ORDER 8
#define AF_RESONANCE_MAX_OVERTONE 3

/* xi of the spheroidal mode (overtone)S(order) for nu in [0, 0.5): the
 * (overtone + 1)-th root of Lamb's equation of that order. Order 2 overtone
 * 0 gives af_lamb_root's 0S2 (bit for bit), order 3 overtone 0 the
 * 0S3, order 2 overtone 1 the 1S2. AF_EINVAL
 * outside the ranges above (n = 0 and 1 hold the breathing and translation
 * modes and a different equation), AF_ENOROOT/AF_ENOCONV/AF_ENUMERIC if the
 * root finder fails. Allocates (a GSL root solver): not for the per-strike path. */
af_status af_lamb_spheroidal_root(double poisson, unsigned order, unsigned overtone, double *xi);
/* xi of the torsional mode (overtone)T(order): root of
 * (n - 1) j_n(y) - y j_{n+1}(y), independent of nu (0T2: 2.5011). */
af_status af_lamb_torsional_root(unsigned order, unsigned overtone, double *xi);

/* The modes a mode identification works with (modes.h). */
typedef enum {
  AF_MODE_0S2 = 0, /* fundamental spheroidal mode, n = 2: the firmness mode */
  AF_MODE_0S3,     /* n = 3 */
  AF_MODE_0S4,     /* n = 4 */
  AF_MODE_1S2,     /* first overtone of n = 2 */
  AF_MODE_0T2,     /* torsional n = 2 (barely audible) */
  AF_MODE_COUNT
} af_sphere_mode;

/* "0S2", "0S3", "0S4", "1S2", "0T2"; "?" otherwise. */
const char *af_sphere_mode_name(af_sphere_mode mode);

typedef struct {
  double poisson;              /* the ratio they were solved for; NaN: none */
  double xi[AF_MODE_COUNT];    /* omega a / c_s of each mode */
  double ratio[AF_MODE_COUNT]; /* f / f_0S2 (ratio[AF_MODE_0S2] = 1) */
} af_sphere_modes;

/* Solves every af_sphere_mode for nu in [0, 0.5) (~0.3 ms, allocates);
 * *out untouched on failure (statuses as af_lamb_spheroidal_root). */
af_status af_lamb_sphere_modes(double poisson, af_sphere_modes *out);

/* The modes of the last Poisson ratio asked, as af_lamb_cache: solved at
 * start-up (or on the first strike of a new ratio), never per strike.
 * Initialise with af_sphere_modes_cache_reset. */
typedef struct {
  af_sphere_modes modes; /* modes.poisson NaN: empty */
} af_sphere_modes_cache;

void af_sphere_modes_cache_reset(af_sphere_modes_cache *c);
/* af_lamb_sphere_modes, solved only when poisson differs from the
 * cached one; no allocation otherwise. AF_EINVAL for NULL; a failure leaves
 * the cache as it was. */
af_status af_lamb_sphere_modes_cached(af_sphere_modes_cache *c, double poisson,
                                      af_sphere_modes *out);

/* Radius [m] of the sphere of this mass [kg] and density [kg/m3]. */
double af_lamb_sphere_radius_m(double mass_kg, double density_kg_m3);

/* 0S2 frequency [Hz] of a sphere of the given (dynamic) modulus [Pa], nu,
 * density [kg/m3] and mass [kg], with xi from af_lamb_root(nu). */
double af_lamb_frequency_hz(double xi, double modulus_pa, double poisson, double density_kg_m3,
                            double mass_kg);

/* The inverse: the modulus [Pa] whose 0S2 frequency is f_hz. */
double af_lamb_modulus_pa(double xi, double f_hz, double poisson, double density_kg_m3,
                          double mass_kg);

/* Stiffness factor f^2 m^(2/3) [Hz^2 kg^(2/3)]. */
double af_lamb_stiffness_factor(double f_hz, double mass_kg);

#ifdef __cplusplus
}
#endif
#endif
