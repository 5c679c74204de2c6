/* resonance.c — Lamb's frequency equation for the 0S2 mode and the sphere
 * frequency/modulus conversions.
 *
 * Frequency equation (Lamb 1882; in matrix form Sato & Usami 1962, eq. 2.2):
 * with x = omega a / c_p, y = omega a / c_s and the spheroidal displacement
 * fields of order n (P: U = d/dr j_n(hr), V = j_n(hr)/r; S: U = n(n+1) j_n(kr)/r,
 * V = (r j_n(kr))'/r), the tractions on r = a, times a^2/mu, are
 *   sigma_rr:  P  (2n(n-1) - y^2) j_n(x) + 4 x j_{n+1}(x)
 *              S  2n(n+1) [(n-1) j_n(y) - y j_{n+1}(y)]
 *   sigma_rt:  P  2 [(n-1) j_n(x) - x j_{n+1}(x)]
 *              S  (2(n^2-1) - y^2) j_n(y) + 2 y j_{n+1}(y)
 * and a free surface needs the 2x2 determinant D = sP tS - sS tP to vanish.
 * Near y = 0 D vanishes like x^2 y^4 (a spurious root, not a mode), so the
 * scan for the first sign change starts well above it.
 */
#include "resonance.h"

#include <math.h>
#include <stddef.h>

#include <gsl/gsl_errno.h>
#include <gsl/gsl_math.h>
#include <gsl/gsl_roots.h>
#include <gsl/gsl_sf_bessel.h>

/* Spheroidal order of the 0S2 ("football") mode. */
#define AF_LAMB_ORDER 2
/* Scan for the first sign change of D: start above the spurious root at 0,
 * step small against the spacing of the roots (~1 in y), stop far above the
 * 0S2 root (2.4..2.7 for nu in [0, 0.5)). */
#define AF_LAMB_SCAN_FROM 0.5
#define AF_LAMB_SCAN_STEP 0.05
#define AF_LAMB_SCAN_TO 10.0
/* Brent on the bracket: absolute tolerance on y, iteration cap. */
#define AF_LAMB_XTOL 1e-12
#define AF_LAMB_MAX_ITER 100

typedef struct {
  double cs_over_cp; /* c_s / c_p = x / y */
} af_lamb_params;

/* j_n(x) and j_{n+1}(x); NaN when GSL reports an error. */
static void af_bessel_pair(int n, double x, double *jn, double *jn1)
{
  gsl_sf_result r0, r1;
  int s0 = gsl_sf_bessel_jl_e(n, x, &r0);
  int s1 = gsl_sf_bessel_jl_e(n + 1, x, &r1);
  *jn = s0 == GSL_SUCCESS ? r0.val : NAN;
  *jn1 = s1 == GSL_SUCCESS ? r1.val : NAN;
}

/* Lamb's determinant D(y) for the order AF_LAMB_ORDER (dimensionless). */
static double af_lamb_determinant(double y, void *params)
{
  const af_lamb_params *p = params;
  const double n = AF_LAMB_ORDER;
  double x = y * p->cs_over_cp;
  double jx, jx1, jy, jy1;
  af_bessel_pair(AF_LAMB_ORDER, x, &jx, &jx1);
  af_bessel_pair(AF_LAMB_ORDER, y, &jy, &jy1);
  double s_p = (2.0 * n * (n - 1.0) - y * y) * jx + 4.0 * x * jx1;
  double s_s = 2.0 * n * (n + 1.0) * ((n - 1.0) * jy - y * jy1);
  double t_p = 2.0 * ((n - 1.0) * jx - x * jx1);
  double t_s = (2.0 * (n * n - 1.0) - y * y) * jy + 2.0 * y * jy1;
  return s_p * t_s - s_s * t_p;
}

/* First sign change of D above AF_LAMB_SCAN_FROM: [*lo, *hi]. */
static af_status af_lamb_bracket(gsl_function *f, double *lo, double *hi)
{
  double y0 = AF_LAMB_SCAN_FROM;
  double d0 = GSL_FN_EVAL(f, y0);
  for (double y1 = y0 + AF_LAMB_SCAN_STEP; y1 <= AF_LAMB_SCAN_TO; y1 += AF_LAMB_SCAN_STEP) {
    double d1 = GSL_FN_EVAL(f, y1);
    if (!isfinite(d0) || !isfinite(d1))
      return AF_ENUMERIC;
    if ((d0 < 0.0) != (d1 < 0.0) || d1 == 0.0) {
      *lo = y0;
      *hi = y1;
      return AF_OK;
    }
    y0 = y1;
    d0 = d1;
  }
  return AF_ENOROOT;
}

/* Brent's method on a bracket known to hold a sign change. */
static af_status af_lamb_polish(gsl_function *f, double lo, double hi, double *root)
{
  gsl_root_fsolver *s = gsl_root_fsolver_alloc(gsl_root_fsolver_brent);
  if (s == NULL)
    return AF_ENOMEM;
  af_status st = AF_ENOCONV;
  if (gsl_root_fsolver_set(s, f, lo, hi) != GSL_SUCCESS) {
    st = AF_ENOROOT;
  } else {
    for (int i = 0; i < AF_LAMB_MAX_ITER; ++i) {
      int gs = gsl_root_fsolver_iterate(s);
      if (gs != GSL_SUCCESS) {
        st = gs == GSL_EBADFUNC ? AF_ENUMERIC : AF_ENOCONV;
        break;
      }
      double a = gsl_root_fsolver_x_lower(s), b = gsl_root_fsolver_x_upper(s);
      if (gsl_root_test_interval(a, b, AF_LAMB_XTOL, 0.0) == GSL_SUCCESS) {
        *root = gsl_root_fsolver_root(s);
        st = AF_OK;
        break;
      }
    }
  }
  gsl_root_fsolver_free(s);
  return st;
}

af_status af_resonance_lamb_root(double poisson, double *xi)
{
  if (xi == NULL || !(poisson >= 0.0 && poisson < 0.5))
    return AF_EINVAL;
  af_status_init();
  /* (c_p / c_s)^2 = 2 (1 - nu) / (1 - 2 nu) */
  af_lamb_params p = {sqrt((1.0 - 2.0 * poisson) / (2.0 * (1.0 - poisson)))};
  gsl_function f = {af_lamb_determinant, &p};
  double lo, hi;
  af_status st = af_lamb_bracket(&f, &lo, &hi);
  if (st == AF_OK)
    st = af_lamb_polish(&f, lo, hi, xi);
  return st;
}

double af_resonance_sphere_radius_m(double mass_kg, double density_kg_m3)
{
  if (!(mass_kg > 0.0 && density_kg_m3 > 0.0) || !isfinite(mass_kg) || !isfinite(density_kg_m3))
    return NAN;
  return cbrt(3.0 * mass_kg / (4.0 * M_PI * density_kg_m3));
}

/* True when the material and sphere arguments are usable (NaN otherwise). */
static int af_sphere_args_ok(double xi, double poisson, double density_kg_m3, double mass_kg)
{
  return xi > 0.0 && isfinite(xi) && poisson >= 0.0 && poisson < 0.5 && density_kg_m3 > 0.0 &&
         isfinite(density_kg_m3) && mass_kg > 0.0 && isfinite(mass_kg);
}

double af_resonance_frequency_hz(double xi, double modulus_pa, double poisson, double density_kg_m3,
                                 double mass_kg)
{
  if (!af_sphere_args_ok(xi, poisson, density_kg_m3, mass_kg) || !(modulus_pa > 0.0) ||
      !isfinite(modulus_pa))
    return NAN;
  /* shear wave speed [m/s] */
  double c_s = sqrt(modulus_pa / (2.0 * (1.0 + poisson) * density_kg_m3));
  return xi * c_s / (2.0 * M_PI * af_resonance_sphere_radius_m(mass_kg, density_kg_m3));
}

double af_resonance_modulus_pa(double xi, double f_hz, double poisson, double density_kg_m3,
                               double mass_kg)
{
  if (!af_sphere_args_ok(xi, poisson, density_kg_m3, mass_kg) || !(f_hz > 0.0) || !isfinite(f_hz))
    return NAN;
  /* shear wave speed [m/s] that puts the 0S2 mode at f_hz */
  double c_s = 2.0 * M_PI * f_hz * af_resonance_sphere_radius_m(mass_kg, density_kg_m3) / xi;
  return 2.0 * (1.0 + poisson) * density_kg_m3 * c_s * c_s;
}

double af_resonance_stiffness_factor(double f_hz, double mass_kg)
{
  if (!(f_hz >= 0.0 && mass_kg > 0.0) || !isfinite(f_hz) || !isfinite(mass_kg))
    return NAN;
  return f_hz * f_hz * cbrt(mass_kg * mass_kg);
}

void af_lamb_cache_init(af_lamb_cache *c)
{
  c->poisson = NAN;
  c->xi = NAN;
}

af_status af_resonance_lamb_root_cached(af_lamb_cache *c, double poisson, double *xi)
{
  if (poisson != c->poisson) {
    af_status st = af_resonance_lamb_root(poisson, &c->xi);
    if (st != AF_OK)
      return st;
    c->poisson = poisson;
  }
  *xi = c->xi;
  return AF_OK;
}
