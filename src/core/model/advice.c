/* advice.c — strike geometry on a spheroidal apple and the rotation advice. */
#include "advice.h"

#include <math.h>
#include <string.h>

#ifndef M_PI /* strict C11 <math.h> does not define it */
#define M_PI 3.14159265358979323846
#endif

/* |s x n|^2 of two unit vectors below this counts as parallel. (A given
 * vector of any finite non-zero length is a direction: see unit3.) */
#define AF_ADVICE_TINY 1e-24

static double dot3(const double u[3], const double v[3])
{
  return u[0] * v[0] + u[1] * v[1] + u[2] * v[2];
}

static void cross3(const double u[3], const double v[3], double out[3])
{
  double w[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
  memcpy(out, w, sizeof w);
}

/* Scales v to unit length into out; false (out zeroed) when v is zero or
 * not finite. Any other length is a direction: v is first divided by its
 * largest |component|, so (1e200, 0, -1e200) and (1e-170, 0, -1e-170) are
 * (1, 0, -1) and not an overflowed or underflowed square. */
static bool unit3(const double v[3], double out[3])
{
  double m = fmax(fabs(v[0]), fmax(fabs(v[1]), fabs(v[2])));
  if (!(isfinite(v[0]) && isfinite(v[1]) && isfinite(v[2])) || m == 0.0) {
    out[0] = out[1] = out[2] = 0.0;
    return false;
  }
  double w[3] = {v[0] / m, v[1] / m, v[2] / m};
  double n = sqrt(dot3(w, w)); /* in [1, sqrt 3] */
  for (int k = 0; k < 3; k++)
    out[k] = w[k] / n;
  return true;
}

/* unit3 of u x v for unit u and v; false when they are parallel (|u x v|^2
 * below AF_ADVICE_TINY), where the cross product has no direction. */
static bool unit_cross3(const double u[3], const double v[3], double out[3])
{
  double w[3];
  cross3(u, v, w);
  if (dot3(w, w) < AF_ADVICE_TINY) {
    out[0] = out[1] = out[2] = 0.0;
    return false;
  }
  return unit3(w, out);
}

double af_advice_polar_semi_axis_m(double mass_kg, double density_kg_m3, double equatorial_radius_m)
{
  if (!(mass_kg > 0.0 && density_kg_m3 > 0.0 && equatorial_radius_m > 0.0))
    return NAN;
  return 3.0 * mass_kg / (4.0 * M_PI * density_kg_m3 * equatorial_radius_m * equatorial_radius_m);
}

void af_advice_spheroid_radii_m(double equatorial_radius_m, double polar_semi_axis_m,
                                double latitude_rad, double *meridional_m, double *transverse_m)
{
  double a = equatorial_radius_m, c = polar_semi_axis_m;
  double cp = cos(latitude_rad), sp = sin(latitude_rad);
  double w2 = a * a * cp * cp + c * c * sp * sp;
  double w = sqrt(w2);
  if (meridional_m)
    *meridional_m = a * a * c * c / (w2 * w);
  if (transverse_m)
    *transverse_m = a * a / w;
}

double af_advice_equivalent_radius_m(double equatorial_radius_m, double polar_semi_axis_m,
                                     double latitude_rad)
{
  double m, n;
  af_advice_spheroid_radii_m(equatorial_radius_m, polar_semi_axis_m, latitude_rad, &m, &n);
  return sqrt(m * n);
}

af_status af_advice_latitude_rad(const double stem[3], const double normal[3], double *latitude_rad)
{
  double s[3], n[3];
  if (!unit3(stem, s) || !unit3(normal, n))
    return AF_ENODATA;
  double sn = dot3(s, n);
  /* Rounding can push |s.n| a hair past 1 when s and n are parallel. */
  *latitude_rad = asin(sn > 1.0 ? 1.0 : sn < -1.0 ? -1.0 : sn);
  return AF_OK;
}

void af_advice_surface_point_m(double equatorial_radius_m, double polar_semi_axis_m,
                               const double stem[3], const double normal[3], double point_m[3])
{
  double a = equatorial_radius_m, c = polar_semi_axis_m;
  double s[3], n[3];
  unit3(normal, n);
  if (!unit3(stem, s))
    c = a; /* orientation unknown: draw the sphere of the equatorial radius */
  /* The gradient of x^2/a^2 + y^2/a^2 + z^2/c^2 is parallel to n where
   * p = (a^2 n_perp + c^2 n_z s) / sqrt(a^2 |n_perp|^2 + c^2 n_z^2). */
  double nz = dot3(n, s);
  double perp[3] = {n[0] - nz * s[0], n[1] - nz * s[1], n[2] - nz * s[2]};
  double lam = sqrt(a * a * dot3(perp, perp) + c * c * nz * nz);
  for (int k = 0; k < 3; k++)
    point_m[k] = lam > 0.0 ? (a * a * perp[k] + c * c * nz * s[k]) / lam : 0.0;
}

void af_advice_perpendicular(const double v[3], double out[3])
{
  /* Cross with the coordinate axis least aligned with v: never degenerate. */
  double ax = fabs(v[0]), ay = fabs(v[1]), az = fabs(v[2]);
  double e[3] = {0.0, 0.0, 0.0};
  e[ax <= ay && ax <= az ? 0 : ay <= az ? 1 : 2] = 1.0;
  double w[3];
  cross3(v, e, w);
  unit3(w, out);
}

void af_advice_rotate_vector(const double axis[3], double angle_rad, const double v[3],
                             double out[3])
{
  double k[3], kxv[3];
  cross3(axis, v, kxv);
  memcpy(k, axis, sizeof k);
  double c = cos(angle_rad), s = sin(angle_rad), kv = dot3(k, v);
  for (int i = 0; i < 3; i++)
    out[i] = v[i] * c + kxv[i] * s + k[i] * kv * (1.0 - c);
}

af_status af_advice_geometry_eval(const af_advice_input *in, af_advice_geometry *out)
{
  double a = in->equatorial_radius_m, c = in->polar_semi_axis_m;
  if (!(isfinite(a) && a > 0.0 && isfinite(c) && c > 0.0))
    return AF_EINVAL;
  if (!(isfinite(in->strike_radius_m) && in->strike_radius_m >= 0.0))
    return AF_EINVAL;
  memset(out, 0, sizeof *out);
  double d[3];
  out->direction_known = unit3(in->strike_direction, d);
  for (int k = 0; k < 3; k++)
    out->normal[k] = -d[k]; /* a flat face first touches where the normal opposes its motion */
  out->latitude_known = out->direction_known && af_advice_latitude_rad(in->stem_axis, out->normal,
                                                                       &out->latitude_rad) == AF_OK;
  if (!out->latitude_known)
    out->latitude_rad = 0.0; /* unknown: treated as the equator */
  if (in->strike_radius_m > 0.0) {
    out->strike_radius_m = in->strike_radius_m;
    out->r2_source = AF_R2_GIVEN;
  } else if (out->direction_known) {
    out->strike_radius_m = af_advice_equivalent_radius_m(a, c, out->latitude_rad);
    out->r2_source = AF_R2_SPHEROID;
  } else {
    out->strike_radius_m = a;
    out->r2_source = AF_R2_EQUATORIAL;
  }
  return AF_OK;
}

void af_advice_decide(const af_advice_geometry *g, const double stem[3],
                      double latitude_tolerance_rad, double min_strike_radius_m,
                      af_advice_rotation *out)
{
  memset(out, 0, sizeof *out);
  out->latitude_off = g->latitude_known && fabs(g->latitude_rad) > latitude_tolerance_rad;
  out->radius_small = min_strike_radius_m > 0.0 && g->strike_radius_m < min_strike_radius_m;
  out->rotate = out->latitude_off || out->radius_small;
  if (!out->rotate)
    return;
  out->angle_rad = -g->latitude_rad;
  double s[3];
  bool have_s = unit3(stem, s);
  if (have_s && g->direction_known) {
    if (unit_cross3(s, g->normal, out->axis))
      return;
  }
  /* s parallel to n, or one of them unknown: any axis perpendicular to n
   * tilts the pole down to the equator by the same angle. */
  if (g->direction_known)
    af_advice_perpendicular(g->normal, out->axis);
  else if (have_s)
    af_advice_perpendicular(s, out->axis);
  else
    out->axis[0] = 1.0;
}
