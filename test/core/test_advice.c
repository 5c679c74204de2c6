/* test_advice.c — strike geometry against closed forms: a sphere has R2 = its
 * radius at every latitude; a spheroid's radii at the equator and the pole
 * are the textbook c^2/a, a and a^2/c; the advised rotation brings s
 * perpendicular to n; volume 4/3 pi a^2 c gives back the mass. */
#include <math.h>
#include <string.h>

#include "advice.h"
#include "af_test.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

static double dot3(const double u[3], const double v[3])
{
  return u[0] * v[0] + u[1] * v[1] + u[2] * v[2];
}

static void test_polar_semi_axis(void)
{
  /* The paper's average apple: 175 g, 840 kg/m3, 80 mm equator. */
  double c = af_advice_polar_semi_axis_m(0.175, 840.0, 0.040);
  AF_CHECK_REL(4.0 / 3.0 * M_PI * 0.040 * 0.040 * c * 840.0, 0.175, 1e-12); /* [kg] */
  AF_CHECK_REL(c, 0.031084, 1e-4);                                          /* [m] */
  AF_CHECK(isnan(af_advice_polar_semi_axis_m(0.0, 840.0, 0.04)));
  AF_CHECK(isnan(af_advice_polar_semi_axis_m(0.175, 840.0, -0.04)));
}

static void test_sphere(void)
{
  for (double phi = -M_PI / 2; phi <= M_PI / 2 + 1e-12; phi += M_PI / 12) {
    double m, n;
    af_advice_spheroid_radii_m(0.04, 0.04, phi, &m, &n);
    AF_CHECK_REL(m, 0.04, 1e-12);
    AF_CHECK_REL(n, 0.04, 1e-12);
    AF_CHECK_REL(af_advice_equivalent_radius_m(0.04, 0.04, phi), 0.04, 1e-12);
  }
}

static void test_spheroid_radii(void)
{
  const double shapes[][2] = {{0.040, 0.031}, {0.035, 0.045}}; /* oblate, prolate [m] */
  for (int k = 0; k < 2; k++) {
    double a = shapes[k][0], c = shapes[k][1], m, n;
    /* Equator: meridional c^2/a, transverse (parallel circle) a. */
    af_advice_spheroid_radii_m(a, c, 0.0, &m, &n);
    AF_CHECK_REL(m, c * c / a, 1e-12);
    AF_CHECK_REL(n, a, 1e-12);
    AF_CHECK_REL(af_advice_equivalent_radius_m(a, c, 0.0), c, 1e-12);
    /* Poles: both a^2/c (umbilic points). */
    af_advice_spheroid_radii_m(a, c, M_PI / 2, &m, &n);
    AF_CHECK_REL(m, a * a / c, 1e-12);
    AF_CHECK_REL(n, a * a / c, 1e-12);
    af_advice_spheroid_radii_m(a, c, -M_PI / 2, &m, NULL);
    AF_CHECK_REL(m, a * a / c, 1e-12);
  }
}

/* The transverse radius is the distance from the surface point to the axis
 * along the normal: check it on the surface point itself. */
static void test_surface_point(void)
{
  const double a = 0.040, c = 0.031, s[3] = {0.0, 0.0, 1.0};
  for (double phi = -1.4; phi <= 1.4; phi += 0.35) {
    double n[3] = {cos(phi), 0.0, sin(phi)}, p[3];
    af_advice_surface_point_m(a, c, s, n, p);
    AF_CHECK_ABS(p[0] * p[0] / (a * a) + p[2] * p[2] / (c * c), 1.0, 1e-12); /* on the surface */
    double tn;
    af_advice_spheroid_radii_m(a, c, phi, NULL, &tn);
    AF_CHECK_REL(p[0] / cos(phi), tn, 1e-9); /* N = x / cos(phi) [m] */
  }
  /* Unknown stem axis: a sphere of radius a. */
  const double zero[3] = {0.0, 0.0, 0.0}, n[3] = {0.0, 0.6, 0.8};
  double p[3];
  af_advice_surface_point_m(a, c, zero, n, p);
  AF_CHECK_REL(sqrt(dot3(p, p)), a, 1e-12);
}

static void test_latitude(void)
{
  const double s[3] = {0.0, 0.0, 2.0}; /* any length */
  const double n_eq[3] = {1.0, 0.0, 0.0}, n_45[3] = {1.0, 0.0, 1.0}, n_pole[3] = {0.0, 0.0, -3.0};
  const double zero[3] = {0.0, 0.0, 0.0};
  double phi = 99.0;
  AF_CHECK_STATUS(af_advice_latitude_rad(s, n_eq, &phi), AF_OK);
  AF_CHECK_ABS(phi, 0.0, 1e-15);
  AF_CHECK_STATUS(af_advice_latitude_rad(s, n_45, &phi), AF_OK);
  AF_CHECK_ABS(phi, M_PI / 4, 1e-12);
  AF_CHECK_STATUS(af_advice_latitude_rad(s, n_pole, &phi), AF_OK);
  AF_CHECK_ABS(phi, -M_PI / 2, 1e-12);
  AF_CHECK_STATUS(af_advice_latitude_rad(zero, n_eq, &phi), AF_ENODATA);
  AF_CHECK_STATUS(af_advice_latitude_rad(s, zero, &phi), AF_ENODATA);
}

static af_advice_input input(double sx, double sy, double sz, double dx, double dy, double dz)
{
  af_advice_input in;
  memset(&in, 0, sizeof in);
  in.equatorial_radius_m = 0.040;
  in.polar_semi_axis_m = 0.031;
  in.stem_axis[0] = sx, in.stem_axis[1] = sy, in.stem_axis[2] = sz;
  in.strike_direction[0] = dx, in.strike_direction[1] = dy, in.strike_direction[2] = dz;
  return in;
}

static void test_geometry(void)
{
  af_advice_geometry g;
  /* Hammer moving along -x onto an apple whose stem points up: the equator. */
  af_advice_input in = input(0, 0, 1, -1, 0, 0);
  AF_CHECK_STATUS(af_advice_geometry_eval(&in, &g), AF_OK);
  AF_CHECK(g.direction_known && g.latitude_known);
  AF_CHECK_ABS(g.latitude_rad, 0.0, 1e-15);
  AF_CHECK_ABS(g.normal[0], 1.0, 1e-15);
  AF_CHECK(g.r2_source == AF_R2_SPHEROID);
  AF_CHECK_REL(g.strike_radius_m, 0.031, 1e-12); /* equator: sqrt(c^2/a * a) = c [m] */
  /* Struck from above: the stem pole, latitude +90 degrees. */
  in = input(0, 0, 1, 0, 0, -1);
  AF_CHECK_STATUS(af_advice_geometry_eval(&in, &g), AF_OK);
  AF_CHECK_ABS(g.latitude_rad, M_PI / 2, 1e-12);
  AF_CHECK_REL(g.strike_radius_m, 0.040 * 0.040 / 0.031, 1e-12);
  /* A measured local radius is used as is. */
  in.strike_radius_m = 0.008;
  AF_CHECK_STATUS(af_advice_geometry_eval(&in, &g), AF_OK);
  AF_CHECK(g.r2_source == AF_R2_GIVEN);
  AF_CHECK_REL(g.strike_radius_m, 0.008, 1e-15);
  /* Stem axis unknown: latitude unknown, treated as the equator. */
  in = input(0, 0, 0, -1, 0, 0);
  AF_CHECK_STATUS(af_advice_geometry_eval(&in, &g), AF_OK);
  AF_CHECK(g.direction_known && !g.latitude_known);
  AF_CHECK_REL(g.strike_radius_m, 0.031, 1e-12);
  /* Strike direction unknown (frame unknown to the URDF): equatorial radius. */
  in = input(0, 0, 1, 0, 0, 0);
  AF_CHECK_STATUS(af_advice_geometry_eval(&in, &g), AF_OK);
  AF_CHECK(!g.direction_known && !g.latitude_known);
  AF_CHECK(g.r2_source == AF_R2_EQUATORIAL);
  AF_CHECK_REL(g.strike_radius_m, 0.040, 1e-15);
  /* Errors. */
  in = input(0, 0, 1, -1, 0, 0);
  in.polar_semi_axis_m = NAN;
  AF_CHECK_STATUS(af_advice_geometry_eval(&in, &g), AF_EINVAL);
  in = input(0, 0, 1, -1, 0, 0);
  in.strike_radius_m = -0.01;
  AF_CHECK_STATUS(af_advice_geometry_eval(&in, &g), AF_EINVAL);
}

/* A stem axis is a direction whatever its finite length (finding
 * 8): (1e200, 0, -1e200) and (1e-170, 0, -1e-170), whose squares overflow or
 * underflow, give what (1, 0, -1) gives: 45 degrees, and the closed-form
 * spheroid radius there, R = a^2 c / (a^2 cos^2 + c^2 sin^2). */
static void test_extreme_stem_length(void)
{
  const double a = 0.040, c = 0.031, w2 = 0.5 * (a * a + c * c);
  const double scale[3] = {1.0, 1e200, 1e-170};
  for (int k = 0; k < 3; k++) {
    af_advice_geometry g;
    af_advice_input in = input(scale[k], 0, -scale[k], -1, 0, 0);
    AF_CHECK_STATUS(af_advice_geometry_eval(&in, &g), AF_OK);
    AF_CHECK(g.direction_known && g.latitude_known);
    AF_CHECK_ABS(g.latitude_rad, M_PI / 4, 1e-15);
    AF_CHECK_REL(g.strike_radius_m, a * a * c / w2, 1e-12);
  }
  /* Zero and non-finite stay unknown. */
  af_advice_geometry g;
  af_advice_input in = input(INFINITY, 0, -1, -1, 0, 0);
  AF_CHECK_STATUS(af_advice_geometry_eval(&in, &g), AF_OK);
  AF_CHECK(g.direction_known && !g.latitude_known);
}

/* Whatever the stem direction, turning s by the advised rotation leaves it
 * perpendicular to n (the equator under the hammer). */
static void test_rotation_brings_equator(void)
{
  const double tol = 10.0 * M_PI / 180.0;
  const double stems[][3] = {{0.3, -0.2, 0.9}, {1, 1, 0.2}, {-0.5, 0.1, -0.7},
                             {0.9, 0.0, 0.1},  {1, 0, 0},   {-2, 0, 0}};
  for (size_t k = 0; k < sizeof stems / sizeof stems[0]; k++) {
    af_advice_input in = input(stems[k][0], stems[k][1], stems[k][2], -1, 0, 0);
    af_advice_geometry g;
    af_advice_rotation rot;
    AF_CHECK_STATUS(af_advice_geometry_eval(&in, &g), AF_OK);
    af_advice_decide(&g, in.stem_axis, tol, 0.0, &rot);
    AF_CHECK(rot.rotate == (fabs(g.latitude_rad) > tol));
    AF_CHECK(rot.latitude_off == rot.rotate && !rot.radius_small);
    if (!rot.rotate)
      continue;
    AF_CHECK_ABS(dot3(rot.axis, rot.axis), 1.0, 1e-12);
    AF_CHECK_ABS(rot.angle_rad, -g.latitude_rad, 1e-15);
    double s[3], s2[3], len = sqrt(dot3(in.stem_axis, in.stem_axis));
    for (int i = 0; i < 3; i++)
      s[i] = in.stem_axis[i] / len;
    af_advice_rotate_vector(rot.axis, rot.angle_rad, s, s2);
    AF_CHECK_ABS(dot3(s2, g.normal), 0.0, 1e-12); /* s' . n = sin(latitude') = 0 */
    AF_CHECK_ABS(dot3(s2, s2), 1.0, 1e-12);
  }
}

static void test_decide(void)
{
  const double tol = 10.0 * M_PI / 180.0;
  af_advice_geometry g;
  af_advice_rotation rot;
  /* On the equator with a large enough radius: strike as is. */
  af_advice_input in = input(0, 0, 1, -1, 0, 0);
  af_advice_geometry_eval(&in, &g);
  af_advice_decide(&g, in.stem_axis, tol, 0.025, &rot);
  AF_CHECK(!rot.rotate);
  AF_CHECK(rot.axis[0] == 0.0 && rot.axis[1] == 0.0 && rot.axis[2] == 0.0);
  /* On the equator but the radius below the minimum: rotate. */
  af_advice_decide(&g, in.stem_axis, tol, 0.035, &rot);
  AF_CHECK(rot.rotate && rot.radius_small && !rot.latitude_off);
  AF_CHECK_ABS(dot3(rot.axis, rot.axis), 1.0, 1e-12);
  /* No minimum found (0): only the latitude counts. */
  af_advice_decide(&g, in.stem_axis, tol, 0.0, &rot);
  AF_CHECK(!rot.rotate);
  /* Latitude unknown (no stem axis): never rotated for latitude. */
  in = input(0, 0, 0, -1, 0, 0);
  af_advice_geometry_eval(&in, &g);
  af_advice_decide(&g, in.stem_axis, 0.0, 0.0, &rot);
  AF_CHECK(!rot.rotate);
  af_advice_decide(&g, in.stem_axis, tol, 0.05, &rot);
  AF_CHECK(rot.rotate && rot.radius_small);
  AF_CHECK_ABS(dot3(rot.axis, g.normal), 0.0, 1e-12);
  /* A right-handed check: stem +z, hammer moving along -x (n = +x), stem
   * tilted 30 degrees towards n: phi = +30 deg, axis s x n = +y direction
   * turned, angle -30 deg. */
  in = input(sin(M_PI / 6), 0, cos(M_PI / 6), -1, 0, 0);
  af_advice_geometry_eval(&in, &g);
  af_advice_decide(&g, in.stem_axis, tol, 0.0, &rot);
  AF_CHECK_ABS(g.latitude_rad, M_PI / 6, 1e-12);
  AF_CHECK(rot.rotate);
  AF_CHECK_ABS(rot.axis[1], 1.0, 1e-12);
  AF_CHECK_ABS(rot.angle_rad, -M_PI / 6, 1e-12);
}

static void test_perpendicular(void)
{
  const double vs[][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 1}, {-3, 0.01, 2}};
  for (size_t k = 0; k < sizeof vs / sizeof vs[0]; k++) {
    double p[3];
    af_advice_perpendicular(vs[k], p);
    AF_CHECK_ABS(dot3(p, vs[k]), 0.0, 1e-12);
    AF_CHECK_ABS(dot3(p, p), 1.0, 1e-12);
  }
}

int main(void)
{
  test_polar_semi_axis();
  test_sphere();
  test_spheroid_radii();
  test_surface_point();
  test_latitude();
  test_extreme_stem_length();
  test_geometry();
  test_rotation_brings_equator();
  test_decide();
  test_perpendicular();
  return af_test_summary("test_advice");
}
