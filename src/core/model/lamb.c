/* lamb.c — Lamb's frequency equation of the free sphere (spheroidal
 * and torsional modes) and the sphere frequency/modulus conversions.
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
 * Near y = 0 D vanishes like a power of y (a spurious root, not a mode), so
 * the scan for sign changes starts well above it. The torsional modes of
 * order n need (n - 1) j_n(y) - y j_{n+1}(y) = 0 (the shear traction of
 * the toroidal field), independent of nu.
 */
#include "lamb.h"

#include <math.h>
#include <stddef.h>

#include <gsl/gsl_errno.h>
#include <gsl/gsl_math.h>
#include <gsl/gsl_roots.h>
#include <gsl/gsl_sf_bessel.h>

#include "memo.h"

/* Spheroidal order of the 0S2 ("football") mode. */
#define AF_LAMB_ORDER 2
/* Scan for sign changes of D: start above the spurious root at 0, step small
 * against the spacing of the roots (~1 in y); the 0S2 root (2.4..2.7 for nu
 * in [0, 0.5)) is searched up to AF_LAMB_SCAN_TO, higher roots up to
 * AF_LAMB_SCAN_TO_HIGH (the 3rd overtone of order 8 lies near y = 20). */
#define AF_LAMB_SCAN_FROM 0.5
#define AF_LAMB_SCAN_STEP 0.05
#define AF_LAMB_SCAN_TO 10.0
#define AF_LAMB_SCAN_TO_HIGH 40.0
/* Brent on the bracket: absolute tolerance on y, iteration cap. */
#define AF_LAMB_XTOL 1e-12
#define AF_LAMB_MAX_ITER 100

typedef struct {
  double cs_over_cp; /* c_s / c_p = x / y */
  int n;             /* order */
} af_lamb_params;

/* j_n(x) and j_{n+1}(x); NaN when GSL reports an error. */
static void bessel_pair(int n, double x, double *jn, double *jn1)
{
  gsl_sf_result r0, r1;
  int s0 = gsl_sf_bessel_jl_e(n, x, &r0);
  int s1 = gsl_sf_bessel_jl_e(n + 1, x, &r1);
  *jn = s0 == GSL_SUCCESS ? r0.val : NAN;
  *jn1 = s1 == GSL_SUCCESS ? r1.val : NAN;
}

/* Lamb's spheroidal determinant D(y) of order p->n (dimensionless). */
static double lamb_determinant(double y, void *params)
{
  const af_lamb_params *p = params;
  const double n = p->n;
  double x = y * p->cs_over_cp;
  double jx, jx1, jy, jy1;
  bessel_pair(p->n, x, &jx, &jx1);
  bessel_pair(p->n, y, &jy, &jy1);
  double s_p = (2.0 * n * (n - 1.0) - y * y) * jx + 4.0 * x * jx1;
  double s_s = 2.0 * n * (n + 1.0) * ((n - 1.0) * jy - y * jy1);
  double t_p = 2.0 * ((n - 1.0) * jx - x * jx1);
  double t_s = (2.0 * (n * n - 1.0) - y * y) * jy + 2.0 * y * jy1;
  return s_p * t_s - s_s * t_p;
}

/* The torsional frequency function (n - 1) j_n(y) - y j_{n+1}(y), order p->n. */
static double torsional_function(double y, void *params)
{
  const af_lamb_params *p = params;
  double jy, jy1;
  bessel_pair(p->n, y, &jy, &jy1);
  return (p->n - 1.0) * jy - y * jy1;
}

/* The (skip + 1)-th sign change of f above AF_LAMB_SCAN_FROM, below scan_to:
 * [*lo, *hi]. */
static af_status lamb_bracket(gsl_function *f, unsigned skip, double scan_to, double *lo,
                              double *hi)
{
  double y0 = AF_LAMB_SCAN_FROM;
  double d0 = GSL_FN_EVAL(f, y0);
  for (double y1 = y0 + AF_LAMB_SCAN_STEP; y1 <= scan_to; y1 += AF_LAMB_SCAN_STEP) {
    double d1 = GSL_FN_EVAL(f, y1);
    if (!isfinite(d0) || !isfinite(d1))
      return AF_ENUMERIC;
    if ((d0 < 0.0) != (d1 < 0.0) || d1 == 0.0) {
      if (skip == 0) {
        *lo = y0;
        *hi = y1;
        return AF_OK;
      }
      --skip;
    }
    y0 = y1;
    d0 = d1;
  }
  return AF_ENOROOT;
}

/* Brent's method on a bracket known to hold a sign change. */
static af_status lamb_polish(gsl_function *f, double lo, double hi, double *root)
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

/* The (overtone + 1)-th root of f above the spurious one, scanned to scan_to. */
static af_status lamb_solve(gsl_function *f, unsigned overtone, double scan_to, double *xi)
{
  double lo, hi;
  af_status st = lamb_bracket(f, overtone, scan_to, &lo, &hi);
  if (st == AF_OK)
    st = lamb_polish(f, lo, hi, xi);
  return st;
}

/* (c_s / c_p), from (c_p / c_s)^2 = 2 (1 - nu) / (1 - 2 nu). */
static double cs_over_cp_ratio(double poisson)
{
  return sqrt((1.0 - 2.0 * poisson) / (2.0 * (1.0 - poisson)));
}

af_status af_lamb_root(double poisson, double *xi)
{
  if (xi == NULL || !(poisson >= 0.0 && poisson < 0.5))
    return AF_EINVAL;
  af_status_init();
  af_lamb_params p = {cs_over_cp_ratio(poisson), AF_LAMB_ORDER};
  gsl_function f = {lamb_determinant, &p};
  return lamb_solve(&f, 0, AF_LAMB_SCAN_TO, xi);
}

af_status af_lamb_spheroidal_root(double poisson, unsigned order, unsigned overtone, double *xi)
{
  if (xi == NULL || !(poisson >= 0.0 && poisson < 0.5) || order < 2 ||
      order > AF_RESONANCE_MAX_ORDER || overtone > AF_RESONANCE_MAX_OVERTONE)
    return AF_EINVAL;
  af_status_init();
  af_lamb_params p = {cs_over_cp_ratio(poisson), (int)order};
  gsl_function f = {lamb_determinant, &p};
  return lamb_solve(&f, overtone, AF_LAMB_SCAN_TO_HIGH, xi);
}

af_status af_lamb_torsional_root(unsigned order, unsigned overtone, double *xi)
{
  if (xi == NULL || order < 2 || order > AF_RESONANCE_MAX_ORDER ||
      overtone > AF_RESONANCE_MAX_OVERTONE)
    return AF_EINVAL;
  af_status_init();
  af_lamb_params p = {1.0, (int)order};
  gsl_function f = {torsional_function, &p};
  return lamb_solve(&f, overtone, AF_LAMB_SCAN_TO_HIGH, xi);
}

const char *af_sphere_mode_name(af_sphere_mode mode)
{
  switch (mode) {
  case AF_MODE_0S2: return "0S2";
  case AF_MODE_0S3: return "0S3";
  case AF_MODE_0S4: return "0S4";
  case AF_MODE_1S2: return "1S2";
  case AF_MODE_0T2: return "0T2";
  case AF_MODE_COUNT: break;
  }
  return "?";
}

af_status af_lamb_sphere_modes(double poisson, af_sphere_modes *out)
{
  /* order and overtone of each af_sphere_mode; the 0T2 is torsional */
  static const unsigned order[AF_MODE_COUNT] = {2, 3, 4, 2, 2};
  static const unsigned overtone[AF_MODE_COUNT] = {0, 0, 0, 1, 0};
  if (out == NULL || !(poisson >= 0.0 && poisson < 0.5))
    return AF_EINVAL;
  af_sphere_modes m;
  m.poisson = poisson;
  for (int i = 0; i < AF_MODE_COUNT; ++i) {
    af_status st = i == AF_MODE_0T2
                       ? af_lamb_torsional_root(order[i], overtone[i], &m.xi[i])
                       : af_lamb_spheroidal_root(poisson, order[i], overtone[i], &m.xi[i]);
    if (st != AF_OK)
      return st;
  }
  for (int i = 0; i < AF_MODE_COUNT; ++i)
    m.ratio[i] = m.xi[i] / m.xi[AF_MODE_0S2];
  *out = m;
  return AF_OK;
}

void af_sphere_modes_cache_reset(af_sphere_modes_cache *c)
{
  c->modes.poisson = NAN;
  for (int i = 0; i < AF_MODE_COUNT; ++i)
    c->modes.xi[i] = c->modes.ratio[i] = NAN;
}

static af_status sphere_modes_of(const void *poisson, void *out)
{
  return af_lamb_sphere_modes(*(const double *)poisson, out);
}

af_status af_lamb_sphere_modes_cached(af_sphere_modes_cache *c, double poisson,
                                      af_sphere_modes *out)
{
  static const char kind[] = "af_lamb_sphere_modes";
  if (c == NULL || out == NULL)
    return AF_EINVAL;
  if (poisson != c->modes.poisson) {
    /* A miss here (a new measurement) is most often the process's same
     * Poisson ratio again: the process-wide copy (memo.h). */
    af_sphere_modes m;
    af_status st = af_memo_get(kind, &poisson, sizeof poisson, sphere_modes_of, &m, sizeof m);
    if (st != AF_OK)
      return st;
    c->modes = m;
  }
  *out = c->modes;
  return AF_OK;
}

double af_lamb_sphere_radius_m(double mass_kg, double density_kg_m3)
{
  if (!(mass_kg > 0.0 && density_kg_m3 > 0.0) || !isfinite(mass_kg) || !isfinite(density_kg_m3))
    return NAN;
  return cbrt(3.0 * mass_kg / (4.0 * M_PI * density_kg_m3));
}

/* True when the material and sphere arguments are usable (NaN otherwise). */
static int sphere_args_ok(double xi, double poisson, double density_kg_m3, double mass_kg)
{
  return xi > 0.0 && isfinite(xi) && poisson >= 0.0 && poisson < 0.5 && density_kg_m3 > 0.0 &&
         isfinite(density_kg_m3) && mass_kg > 0.0 && isfinite(mass_kg);
}

double af_lamb_frequency_hz(double xi, double modulus_pa, double poisson, double density_kg_m3,
                            double mass_kg)
{
  if (!sphere_args_ok(xi, poisson, density_kg_m3, mass_kg) || !(modulus_pa > 0.0) ||
      !isfinite(modulus_pa))
    return NAN;
  /* shear wave speed [m/s] */
  double c_s = sqrt(modulus_pa / (2.0 * (1.0 + poisson) * density_kg_m3));
  return xi * c_s / (2.0 * M_PI * af_lamb_sphere_radius_m(mass_kg, density_kg_m3));
}

double af_lamb_modulus_pa(double xi, double f_hz, double poisson, double density_kg_m3,
                          double mass_kg)
{
  if (!sphere_args_ok(xi, poisson, density_kg_m3, mass_kg) || !(f_hz > 0.0) || !isfinite(f_hz))
    return NAN;
  /* shear wave speed [m/s] that puts the 0S2 mode at f_hz */
  double c_s = 2.0 * M_PI * f_hz * af_lamb_sphere_radius_m(mass_kg, density_kg_m3) / xi;
  return 2.0 * (1.0 + poisson) * density_kg_m3 * c_s * c_s;
}

double af_lamb_stiffness_factor(double f_hz, double mass_kg)
{
  if (!(f_hz >= 0.0 && mass_kg > 0.0) || !isfinite(f_hz) || !isfinite(mass_kg))
    return NAN;
  return f_hz * f_hz * cbrt(mass_kg * mass_kg);
}

void af_lamb_cache_reset(af_lamb_cache *c)
{
  c->poisson = NAN;
  c->xi = NAN;
}

static af_status root_of(const void *poisson, void *xi)
{
  return af_lamb_root(*(const double *)poisson, xi);
}

af_status af_lamb_root_cached(af_lamb_cache *c, double poisson, double *xi)
{
  static const char kind[] = "af_lamb_root";
  if (poisson != c->poisson) {
    /* as af_lamb_sphere_modes_cached: the process-wide copy first */
    double root;
    af_status st = af_memo_get(kind, &poisson, sizeof poisson, root_of, &root, sizeof root);
    if (st != AF_OK)
      return st;
    c->xi = root;
    c->poisson = poisson;
  }
  *xi = c->xi;
  return AF_OK;
}
