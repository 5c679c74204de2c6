/* yield.h — the flesh's yield shear stress as a function of its modulus.
 *
 * The law (a calibration, PHYSICS.md 6 and doc/paper.md "The yield law"):
 *     tau_y(E2) = tau_ref (E2 / E_ref)^p,   tau_ref = ratio x E_ref,
 * so p = 1 is the ratio law tau_y = ratio x E2 whatever E_ref. The paper's
 * Fig. 3b (yield and shear both fall with ripening, the shear a little more)
 * needs p below the exponent of the computed shear in E2 (about 0.8).
 *
 * A measured yield (tau_y at given E2 values, the cultivar's YAML key
 * yield_measured: "E2:tau, E2:tau, ...", Pa) overrides the law: log-log
 * linear between the points; outside them the law's exponent p carries the
 * nearest point on (one point therefore sets tau_ref at its modulus).
 * No allocation; reentrant.
 */
#ifndef AF_YIELD_H
#define AF_YIELD_H

#include <stddef.h>

#include "status.h"

#ifdef __cplusplus
extern "C" {
#endif

#define AF_YIELD_MAX_POINTS 8

typedef struct {
  size_t n;                                   /* 0 = no measurement: the law holds */
  double modulus_pa[AF_YIELD_MAX_POINTS];     /* E2 of each point, strictly increasing [Pa] */
  double yield_shear_pa[AF_YIELD_MAX_POINTS]; /* measured tau_y there [Pa] */
} af_yield_points;

typedef struct {
  double ratio;                /* tau_ref / E_ref [-], > 0 */
  double reference_modulus_pa; /* E_ref [Pa], > 0 */
  double exponent;             /* p [-], >= 0; 1 = the ratio law */
  af_yield_points measured;    /* overrides the law when measured.n > 0 */
} af_yield_law;

/* tau_y [Pa] at modulus_pa; NAN for a non-positive or non-finite modulus or
 * law figure. */
double af_yield_shear_pa(const af_yield_law *law, double modulus_pa);

/* Parses "E2:tau, E2:tau, ..." (Pa, C numbers, commas or blanks between
 * pairs; "" = none) into *out. AF_EINVAL with one line in err for a
 * malformed pair, a non-positive value, moduli not strictly increasing or
 * more than AF_YIELD_MAX_POINTS pairs; *out is unchanged then. */
af_status af_yield_points_parse(const char *text, af_yield_points *out, char *err, size_t len);

#ifdef __cplusplus
}
#endif
#endif
