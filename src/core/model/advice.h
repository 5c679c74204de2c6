/* advice.h — where the hammer meets the apple, and how to turn the apple.
 *
 * The apple is a spheroid of revolution about its stem-calyx axis s:
 * equatorial radius a (from vision), polar semi-axis c from the mass and
 * density (V = m / rho = 4/3 pi a^2 c); c < a is oblate, c > a prolate.
 *
 * A flat hammer face moving along the unit strike direction d first touches
 * the fruit where the outward normal is n = -d: that is the strike point.
 * Its latitude is the geodetic one, phi = asin(s . n) with s the unit stem
 * axis (+ towards the stem). At latitude phi the principal radii of
 * curvature of the spheroid are (the Earth-ellipsoid formulas, valid for
 * both oblate and prolate shapes)
 *     meridional M = a^2 c^2 / (a^2 cos^2 phi + c^2 sin^2 phi)^(3/2),
 *     transverse N = a^2     / (a^2 cos^2 phi + c^2 sin^2 phi)^(1/2),
 * and the Hertz contact sees the equivalent radius R2 = sqrt(M N)
 * (Johnson, Contact Mechanics, 4.2: R_e = sqrt(R' R'') for a point contact).
 *
 * Turning the apple by -phi about unit(s x n) brings the equator under the
 * hammer (s ends perpendicular to n). Pure geometry, no allocation, no ROS;
 * vectors are double[3] in any one frame.
 */
#ifndef AF_ADVICE_H
#define AF_ADVICE_H

#include <stdbool.h>

#include "status.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Polar semi-axis c [m] of the spheroid with this mass [kg], density [kg/m3]
 * and equatorial radius a [m]: c = 3 m / (4 pi rho a^2). NaN for
 * non-positive inputs. */
double af_advice_polar_semi_axis_m(double mass_kg, double density_kg_m3,
                                   double equatorial_radius_m);

/* Principal radii of curvature [m] at geodetic latitude phi [rad] of the
 * spheroid (a, c); either OUT pointer may be NULL. */
void af_advice_spheroid_radii_m(double equatorial_radius_m, double polar_semi_axis_m,
                                double latitude_rad, double *meridional_m, double *transverse_m);

/* Equivalent Hertz radius sqrt(M N) [m] at latitude phi. A sphere gives its
 * radius at every latitude; the equator of a spheroid gives c, its poles a^2/c. */
double af_advice_equivalent_radius_m(double equatorial_radius_m, double polar_semi_axis_m,
                                     double latitude_rad);

/* Latitude [rad] of the surface point with outward normal n, for the stem
 * axis s; both of any non-zero length. AF_ENODATA when s or n is zero (or
 * not finite). */
af_status af_advice_latitude_rad(const double stem[3], const double normal[3],
                                 double *latitude_rad);

/* Position [m] of the surface point with outward normal n, relative to the
 * centre of the spheroid (a, c) whose unit stem axis is s (s zero: a sphere
 * of radius a is assumed, the orientation being unknown). */
void af_advice_surface_point_m(double equatorial_radius_m, double polar_semi_axis_m,
                               const double stem[3], const double normal[3], double point_m[3]);

/* A unit vector perpendicular to v (v non-zero). */
void af_advice_perpendicular(const double v[3], double out[3]);

/* Rodrigues: v turned by angle [rad], right-handed about the unit axis. */
void af_advice_rotate_vector(const double axis[3], double angle_rad, const double v[3],
                             double out[3]);

/* Where R2 came from. */
typedef enum {
  AF_R2_GIVEN = 0, /* the vision system measured the local radius */
  AF_R2_SPHEROID,  /* sqrt(M N) of the spheroid at the strike latitude */
  AF_R2_EQUATORIAL /* strike direction unknown: the equatorial radius */
} af_r2_source;

typedef struct {
  double equatorial_radius_m; /* a > 0 */
  double polar_semi_axis_m;   /* c > 0 */
  double stem_axis[3];        /* any length; zero = unknown */
  double strike_direction[3]; /* direction the hammer moves, any length; zero = unknown */
  double strike_radius_m;     /* > 0: measured local radius, used as is; 0: from the shape */
} af_advice_input;

typedef struct {
  bool direction_known;   /* the strike direction was given */
  bool latitude_known;    /* and the stem axis too */
  double latitude_rad;    /* 0 (the equator) when unknown */
  double normal[3];       /* unit outward normal at the strike point; zero when unknown */
  double strike_radius_m; /* R2 for the model */
  af_r2_source r2_source;
} af_advice_geometry;

/* The strike geometry of one apple. AF_EINVAL when a or c is not finite and
 * positive, or strike_radius_m is negative or not finite. */
af_status af_advice_geometry_eval(const af_advice_input *in, af_advice_geometry *out);

typedef struct {
  bool rotate;       /* turn the apple before striking */
  bool latitude_off; /* |phi| > tolerance */
  bool radius_small; /* R2 < R2_min */
  double axis[3];    /* unit rotation axis; zero when rotate is false */
  double angle_rad;  /* right-handed about axis; brings the equator under the hammer */
} af_advice_rotation;

/* Rotate when |phi| > latitude_tolerance_rad or R2 < min_strike_radius_m
 * (min_strike_radius_m <= 0: no minimum known, that test is skipped). The
 * axis is unit(s x n), or a unit vector perpendicular to n (to s when n is
 * unknown) when s is zero or parallel to n; the angle is -phi. */
void af_advice_decide(const af_advice_geometry *g, const double stem[3],
                      double latitude_tolerance_rad, double min_strike_radius_m,
                      af_advice_rotation *out);

#ifdef __cplusplus
}
#endif
#endif
