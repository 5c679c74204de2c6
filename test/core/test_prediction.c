/* test_prediction.c — one apple's prediction (prediction.h) with the
 * table's defaults: a spherical 175 g apple's shape, strike geometry and
 * 0S2 range against Lamb's closed form and PHYSICS.md 5's published
 * frequencies (341 / 682 / 835 Hz at 2 / 8 / 12 MPa), R2 by source (given,
 * the spheroid at the strike latitude, the equator when the direction is
 * unknown, which is never reliable), the rotation advice at a 45 deg
 * latitude, and every refused AppleEstimate field as one line naming the
 * field, the value and the accepted range. */
#include <math.h>
#include <string.h>

#include "af_test.h"
#include "prediction.h"
#include "settings.h"

static const double PI = 3.14159265358979323846;
#define RHO 840.0     /* density_kg_m3's default [kg/m3] */
#define XI_035 2.6519 /* Lamb's 0S2 root at nu 0.35 (PHYSICS.md 5) */

static af_lane_config cfg;
static af_model *model;

static int setup(void)
{
  char err[512] = "";
  af_settings s;
  af_settings_reset(&s);
  af_status st = af_settings_set_arg(&s, "hammer_mass_kg=0.010", err, sizeof err);
  if (st == AF_OK)
    st = af_settings_set_arg(&s, "hammer_tip_radius_m=0", err, sizeof err);
  if (st == AF_OK)
    st = af_lane_config_derive(&s, &cfg, err, sizeof err);
  if (st != AF_OK)
    fprintf(stderr, "  setup: %s\n", err);
  AF_CHECK_STATUS(st, AF_OK);
  AF_CHECK_STATUS(af_model_create(&model), AF_OK);
  return st == AF_OK && model != NULL;
}

/* The sphere of mass m [kg] at density RHO: its radius [m]. */
static double sphere_radius_m(double m)
{
  return cbrt(3.0 * m / (4.0 * PI * RHO));
}

/* Lamb's 0S2 of that sphere for modulus e_pa, nu 0.35: xi c_s / (2 pi a). */
static double lamb_hz(double m, double e_pa)
{
  return XI_035 / (2.0 * PI * sphere_radius_m(m)) * sqrt(e_pa / (2.0 * 1.35 * RHO));
}

/* A 175 g sphere, stem along z, struck on the equator (the hammer moving
 * along -x hits the point whose outward normal is +x). */
static af_apple sphere_apple(void)
{
  af_apple a;
  memset(&a, 0, sizeof a);
  a.apple_id = 7;
  a.mass_kg = 0.175;
  a.equatorial_radius_m = sphere_radius_m(0.175);
  a.stem_axis[2] = 1.0;
  a.confidence = 0.9;
  a.strike_direction[0] = -2.0; /* any length */
  return a;
}

static void test_sphere(void)
{
  af_apple a = sphere_apple();
  af_prediction p;
  const double r_m = sphere_radius_m(0.175); /* 36.78 mm */
  AF_CHECK_REL(r_m, 0.036775, 1e-4);
  AF_CHECK_STATUS(af_prediction_execute(model, &cfg, &a, &p), AF_OK);
  AF_CHECK(p.valid && p.why[0] == '\0');
  /* c = 3 m / (4 pi rho a^2) = a for the sphere. */
  AF_CHECK_REL(p.polar_semi_axis_m, r_m, 1e-12);
  AF_CHECK(p.geo.direction_known && p.geo.latitude_known);
  AF_CHECK_ABS(p.geo.latitude_rad, 0.0, 1e-12);
  AF_CHECK_ABS(p.geo.normal[0], 1.0, 1e-12);
  AF_CHECK(p.geo.r2_source == AF_R2_SPHEROID);
  AF_CHECK_REL(p.geo.strike_radius_m, r_m, 1e-9); /* a sphere's sqrt(M N) is its radius */
  /* The model ran on this apple. */
  AF_CHECK(p.params.fruit_mass_kg == 0.175);
  AF_CHECK_REL(p.params.impact.strike_radius_m, r_m, 1e-9);
  AF_CHECK(p.params.impact.fruit_modulus_pa == 8.0e6);
  /* 0S2 over the cultivar's 2..12 MPa: Lamb's closed form, and PHYSICS.md's
   * published 341 and 835 Hz (3 digits); at the nominal 8 MPa 682 Hz. */
  AF_CHECK_REL(p.resonance_low_hz, lamb_hz(0.175, 2.0e6), 1e-4);
  AF_CHECK_REL(p.resonance_high_hz, lamb_hz(0.175, 12.0e6), 1e-4);
  AF_CHECK_ABS(p.resonance_low_hz, 341.0, 0.5);
  AF_CHECK_ABS(p.resonance_high_hz, 835.0, 0.5);
  AF_CHECK_ABS(p.result.resonance_hz, 682.0, 0.5);
  /* f ~ sqrt(E): the ends' ratio is sqrt(6) whatever the mass. */
  AF_CHECK_REL(p.resonance_high_hz / p.resonance_low_hz, sqrt(6.0), 1e-9);
  /* The verdict: R2 known, so it is the model's. */
  AF_CHECK(p.reliable == p.result.reliable);
  AF_CHECK(p.reliable == (p.reason[0] == '\0'));
  /* The smallest reliable R2 lies in the search bracket, and the advice
   * follows it: at the equator only R2 < R2_min asks for a rotation. */
  AF_CHECK(p.min_strike_radius_m == 0.0 ||
           (p.min_strike_radius_m >= 0.002 && p.min_strike_radius_m <= 0.5));
  AF_CHECK(!p.rotation.latitude_off);
  AF_CHECK(p.rotation.radius_small == (p.geo.strike_radius_m < p.min_strike_radius_m));
  AF_CHECK(p.rotation.rotate == p.rotation.radius_small);

  /* PHYSICS.md 5's other masses: 411 / 1006 Hz at 100 g, 303 / 741 Hz at 250 g. */
  const double masses[2] = {0.100, 0.250}, lo[2] = {411.0, 303.0}, hi[2] = {1006.0, 741.0};
  for (int k = 0; k < 2; k++) {
    a.mass_kg = masses[k];
    a.equatorial_radius_m = sphere_radius_m(masses[k]);
    AF_CHECK_STATUS(af_prediction_execute(model, &cfg, &a, &p), AF_OK);
    AF_CHECK_ABS(p.resonance_low_hz, lo[k], 0.5);
    AF_CHECK_ABS(p.resonance_high_hz, hi[k], 0.5);
  }
}

static void test_r2_sources(void)
{
  af_apple a = sphere_apple();
  af_prediction p;
  /* A measured local radius is used as is. */
  a.strike_radius_m = 0.031;
  AF_CHECK_STATUS(af_prediction_execute(model, &cfg, &a, &p), AF_OK);
  AF_CHECK(p.geo.r2_source == AF_R2_GIVEN && p.geo.strike_radius_m == 0.031);
  AF_CHECK(p.params.impact.strike_radius_m == 0.031);

  /* Direction unknown: the equatorial radius, never reliable, and the
   * reason says so first, with the caller's note. */
  a = sphere_apple();
  memset(a.strike_direction, 0, sizeof a.strike_direction);
  strcpy(a.direction_note, "no hammer frame");
  AF_CHECK_STATUS(af_prediction_execute(model, &cfg, &a, &p), AF_OK);
  AF_CHECK(p.valid && !p.geo.direction_known && p.geo.r2_source == AF_R2_EQUATORIAL);
  AF_CHECK_REL(p.geo.strike_radius_m, a.equatorial_radius_m, 1e-12);
  AF_CHECK(!p.reliable);
  const char *head = "no hammer frame: R2 unknown, equatorial radius 36.8 mm assumed";
  AF_CHECK(strncmp(p.reason, head, strlen(head)) == 0);
  if (strncmp(p.reason, head, strlen(head)) != 0)
    fprintf(stderr, "  reason: '%s'\n", p.reason);

  /* Struck at 45 deg latitude (normal (1, 0, 1)/sqrt 2): beyond the 15 deg
   * tolerance, the advice turns the apple by -45 deg about s x n. */
  a = sphere_apple();
  a.strike_direction[0] = -1.0;
  a.strike_direction[2] = -1.0;
  AF_CHECK_STATUS(af_prediction_execute(model, &cfg, &a, &p), AF_OK);
  AF_CHECK_ABS(p.geo.latitude_rad, PI / 4.0, 1e-9);
  AF_CHECK_REL(p.geo.strike_radius_m, a.equatorial_radius_m, 1e-9); /* sphere: any latitude */
  AF_CHECK(p.rotation.latitude_off && p.rotation.rotate);
  AF_CHECK_ABS(p.rotation.angle_rad, -PI / 4.0, 1e-9);
  /* s x n = z x (x + z) / sqrt 2: along +y */
  AF_CHECK_ABS(p.rotation.axis[1], 1.0, 1e-9);
  AF_CHECK_ABS(cfg.latitude_tolerance_rad, 15.0 * PI / 180.0, 1e-12);
}

static int refused(af_apple a, const char *expected)
{
  af_prediction p;
  memset(&p, 0x5a, sizeof p);
  af_status st = af_prediction_execute(model, &cfg, &a, &p);
  int ok = st == AF_EINVAL && !p.valid && strcmp(p.why, expected) == 0;
  if (!ok)
    fprintf(stderr, "  refusal: status %d, why '%s'\n  expected '%s'\n", (int)st, p.why, expected);
  return ok;
}

static void test_refusals(void)
{
  af_apple a = sphere_apple();
  a.mass_kg = 0.05;
  AF_CHECK(refused(a, "invalid AppleEstimate: mass = 0.05 kg is outside the accepted range "
                      "[0.1, 0.25] kg"));
  a.mass_kg = NAN;
  AF_CHECK(refused(a, "invalid AppleEstimate: mass = nan kg is outside the accepted range "
                      "[0.1, 0.25] kg"));
  a = sphere_apple();
  a.equatorial_radius_m = 0.07;
  AF_CHECK(refused(a, "invalid AppleEstimate: equatorial_radius = 0.07 m is outside the accepted "
                      "range [0.025, 0.06] m"));
  a = sphere_apple();
  a.strike_radius_m = -0.01;
  AF_CHECK(refused(a, "invalid AppleEstimate: strike_radius = -0.01 m is outside the accepted "
                      "range 0 (unknown) or [0.002, 0.5] m"));
  a.strike_radius_m = 0.001;
  AF_CHECK(refused(a, "invalid AppleEstimate: strike_radius = 0.001 m is outside the accepted "
                      "range 0 (unknown) or [0.002, 0.5] m"));
  a = sphere_apple();
  a.stem_axis[1] = INFINITY;
  AF_CHECK(refused(a, "invalid AppleEstimate: stem_axis.y = inf is outside the accepted range "
                      "(any finite value)"));
  a = sphere_apple();
  a.confidence = 1.5;
  AF_CHECK(refused(a, "invalid AppleEstimate: confidence = 1.5 is outside the accepted range "
                      "[0, 1]"));
  /* The ends are accepted. */
  a = sphere_apple();
  a.confidence = 0.0;
  af_prediction p;
  AF_CHECK_STATUS(af_prediction_execute(model, &cfg, &a, &p), AF_OK);
  a.confidence = 1.0;
  AF_CHECK_STATUS(af_prediction_execute(model, &cfg, &a, &p), AF_OK);
  /* Mass and radius that disagree: 250 g in a 30 mm equator gives
   * c = 3 0.25 / (4 pi 840 0.03^2) = 78.9 mm, aspect 2.63 > 1.5. */
  a = sphere_apple();
  a.mass_kg = 0.25;
  a.equatorial_radius_m = 0.03;
  AF_CHECK(refused(a, "invalid AppleEstimate: mass = 0.25 kg and equatorial_radius = 0.03 m give "
                      "a polar semi-axis of 0.0789 m (density 840 kg/m3), aspect 2.63 outside "
                      "the accepted range [0.5, 1.5]"));
  /* And the flat end: 100 g in a 60 mm equator, c = 7.9 mm, aspect 0.13. */
  a.mass_kg = 0.1;
  a.equatorial_radius_m = 0.06;
  AF_CHECK(refused(a, "invalid AppleEstimate: mass = 0.1 kg and equatorial_radius = 0.06 m give a "
                      "polar semi-axis of 0.0079 m (density 840 kg/m3), aspect 0.13 outside the "
                      "accepted range [0.5, 1.5]"));
}

int main(void)
{
  if (setup()) {
    test_sphere();
    test_r2_sources();
    test_refusals();
  }
  af_model_destroy(model);
  return af_test_summary("test_prediction");
}
