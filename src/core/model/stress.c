/* stress.c — Hertz contact radius and pressure, the subsurface shear ratio on
 * the axis and the yield shear stress. */
#include "stress.h"

#include <math.h>
#include <string.h>

#include <gsl/gsl_errno.h>
#include <gsl/gsl_math.h>
#include <gsl/gsl_min.h>

/* The paper's tau_max / p0 and its depth z / a, whatever nu. */
#define AF_SHEAR_PAPER_RATIO 0.31
#define AF_SHEAR_PAPER_DEPTH 0.48
/* Search for the maximum over zeta = z / a: the bracket holds it for every nu
 * in [0, 0.5) (0.43..0.55 a), the guess beats both ends (tau(0) = (1/2 - nu)/2
 * <= 0.25 < tau(0.5), tau(5) < 0.03). Tolerance: width of the final bracket
 * on zeta; Brent cannot shrink it below 2 sqrt(DBL_EPSILON) zeta ~ 1.7e-8 here,
 * so the depth is known to 2e-8 and the ratio (flat at its maximum) to
 * rounding. Iteration cap. */
#define AF_SHEAR_ZETA_LO 0.0
#define AF_SHEAR_ZETA_GUESS 0.5
#define AF_SHEAR_ZETA_HI 5.0
#define AF_SHEAR_ZETA_TOL 2e-8
#define AF_SHEAR_MAX_ITER 200

const char *af_shear_ratio_name(af_shear_ratio mode)
{
  switch (mode) {
  case AF_SHEAR_PAPER: return "paper";
  case AF_SHEAR_EXACT: return "exact";
  }
  return "unknown";
}

af_status af_shear_ratio_parse(const char *name, af_shear_ratio *mode)
{
  if (name == NULL || mode == NULL)
    return AF_EINVAL;
  if (strcmp(name, "paper") == 0) {
    *mode = AF_SHEAR_PAPER;
  } else if (strcmp(name, "exact") == 0) {
    *mode = AF_SHEAR_EXACT;
  } else {
    return AF_EINVAL;
  }
  return AF_OK;
}

double af_stress_contact_radius_m(double radius_m, double deformation_m)
{
  if (!(radius_m > 0.0 && deformation_m >= 0.0) || !isfinite(radius_m) || !isfinite(deformation_m))
    return NAN;
  return sqrt(radius_m * deformation_m);
}

double af_stress_hertz_contact_radius_m(double force_n, double radius_m,
                                        double effective_modulus_pa)
{
  if (!(force_n >= 0.0 && radius_m > 0.0 && effective_modulus_pa > 0.0) || !isfinite(force_n) ||
      !isfinite(radius_m) || !isfinite(effective_modulus_pa))
    return NAN;
  return cbrt(3.0 * force_n * radius_m / (4.0 * effective_modulus_pa));
}

double af_stress_center_pressure_pa(double force_n, double contact_radius_m)
{
  if (!(contact_radius_m > 0.0) || !isfinite(contact_radius_m) || !isfinite(force_n))
    return NAN;
  return 3.0 * force_n / (2.0 * M_PI * contact_radius_m * contact_radius_m);
}

af_status af_stress_max_center_pressure_pa(const double *force_n, const double *deformation_m,
                                           size_t n, double radius_m, double *p0_pa, size_t *at)
{
  if ((n > 0 && (force_n == NULL || deformation_m == NULL)) || p0_pa == NULL || !(radius_m > 0.0) ||
      !isfinite(radius_m))
    return AF_EINVAL;
  double best = -INFINITY;
  size_t best_k = 0;
  int found = 0;
  for (size_t k = 0; k < n; ++k) {
    if (!isfinite(force_n[k]) || !isfinite(deformation_m[k]))
      return AF_ENUMERIC;
    if (!(deformation_m[k] > 0.0))
      continue;
    /* a_k^2 = R d_k, so p0_k = 3 F_k / (2 pi a_k^2) */
    double p0 = 3.0 * force_n[k] / (2.0 * M_PI * radius_m * deformation_m[k]);
    if (!found || p0 > best) {
      best = p0;
      best_k = k;
      found = 1;
    }
  }
  if (!found)
    return AF_ENODATA;
  *p0_pa = best;
  if (at != NULL)
    *at = best_k;
  return AF_OK;
}

/* Minus the principal shear tau / p0 on the axis at zeta = z / a under a Hertz
 * (spherical) contact (Johnson, Contact Mechanics, eq. 3.45):
 *   sigma_r / p0 = -(1 + nu)(1 - zeta atan(1/zeta)) + 1 / (2 (1 + zeta^2)),
 *   sigma_z / p0 = -1 / (1 + zeta^2),  tau = |sigma_z - sigma_r| / 2.
 * Negated so that the minimiser finds the maximum. */
static double neg_axial_shear(double zeta, void *params)
{
  double nu = *(const double *)params;
  double q = 1.0 / (1.0 + zeta * zeta);
  double sigma_r = -(1.0 + nu) * (1.0 - zeta * atan2(1.0, zeta)) + 0.5 * q;
  double sigma_z = -q;
  return -0.5 * fabs(sigma_z - sigma_r);
}

/* Maximum of tau / p0 over zeta by Brent's minimiser. */
static af_status exact_shear(double poisson, double *ratio, double *depth_over_a)
{
  gsl_min_fminimizer *s = gsl_min_fminimizer_alloc(gsl_min_fminimizer_brent);
  if (s == NULL)
    return AF_ENOMEM;
  gsl_function f = {neg_axial_shear, &poisson};
  af_status st = AF_ENOCONV;
  if (gsl_min_fminimizer_set(s, &f, AF_SHEAR_ZETA_GUESS, AF_SHEAR_ZETA_LO, AF_SHEAR_ZETA_HI) ==
      GSL_SUCCESS) {
    for (int i = 0; i < AF_SHEAR_MAX_ITER; ++i) {
      if (gsl_min_fminimizer_iterate(s) != GSL_SUCCESS)
        break;
      double a = gsl_min_fminimizer_x_lower(s), b = gsl_min_fminimizer_x_upper(s);
      if (gsl_min_test_interval(a, b, AF_SHEAR_ZETA_TOL, 0.0) == GSL_SUCCESS) {
        *ratio = -gsl_min_fminimizer_f_minimum(s);
        if (depth_over_a != NULL)
          *depth_over_a = gsl_min_fminimizer_x_minimum(s);
        st = AF_OK;
        break;
      }
    }
  }
  gsl_min_fminimizer_free(s);
  return st;
}

af_status af_stress_shear_ratio(af_shear_ratio mode, double poisson, double *ratio,
                                double *depth_over_a)
{
  if (ratio == NULL || !(poisson >= 0.0 && poisson < 0.5))
    return AF_EINVAL;
  switch (mode) {
  case AF_SHEAR_PAPER:
    *ratio = AF_SHEAR_PAPER_RATIO;
    if (depth_over_a != NULL)
      *depth_over_a = AF_SHEAR_PAPER_DEPTH;
    return AF_OK;
  case AF_SHEAR_EXACT:
    af_status_init(); /* the minimiser must report, not abort */
    return exact_shear(poisson, ratio, depth_over_a);
  }
  return AF_EINVAL;
}

double af_stress_yield_shear_pa(double yield_ratio, double modulus_pa)
{
  if (!(yield_ratio > 0.0 && modulus_pa > 0.0) || !isfinite(yield_ratio) || !isfinite(modulus_pa))
    return NAN;
  return yield_ratio * modulus_pa;
}

void af_shear_cache_reset(af_shear_cache *c)
{
  c->mode = AF_SHEAR_EXACT;
  c->poisson = NAN;
  c->ratio = NAN;
}

af_status af_stress_shear_ratio_cached(af_shear_cache *c, af_shear_ratio mode, double poisson,
                                       double *ratio)
{
  if (poisson != c->poisson || mode != c->mode) {
    af_status st = af_stress_shear_ratio(mode, poisson, &c->ratio, NULL);
    if (st != AF_OK)
      return st;
    c->poisson = poisson;
    c->mode = mode;
  }
  *ratio = c->ratio;
  return AF_OK;
}
