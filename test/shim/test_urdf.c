/* test_urdf.c — af_urdf.h over the fixtures in test/shim/, config/rig.urdf
 * and test/node/rig_heavy_hammer.urdf. Run from the package root (ctest sets
 * the working directory). Tolerances: 1e-12 m and 1e-12 (rotation entries)
 * for exact fixtures, the values being sums of products of cos/sin of pi/2. */
#include <stdbool.h>
#include <string.h>

#include "af_test.h"
#include "af_urdf.h"
#include "settings.h"

#define TOL 1e-12

static char err[256];

static af_urdf *load(const char *path)
{
  af_urdf *u = NULL;
  af_status s = af_urdf_load(path, &u, err, sizeof err);
  if (s != AF_OK)
    fprintf(stderr, "cannot load %s: %s\n", path, err);
  AF_CHECK(s == AF_OK && u != NULL);
  return u;
}

static bool has(const char *text, const char *part)
{
  bool ok = strstr(text, part) != NULL;
  if (!ok)
    fprintf(stderr, "  \"%s\" does not contain \"%s\"\n", text, part);
  return ok;
}

static void check_vec(af_vec3 v, double x, double y, double z)
{
  AF_CHECK_ABS(v.x, x, TOL);
  AF_CHECK_ABS(v.y, y, TOL);
  AF_CHECK_ABS(v.z, z, TOL);
}

static void check_rot(const double r[9], const double e[9])
{
  for (int i = 0; i < 9; i++)
    AF_CHECK_ABS(r[i], e[i], TOL);
}

static void test_rig(void)
{
  af_urdf *u = load("config/rig.urdf");
  if (u == NULL)
    return;
  af_hammer_geometry h;
  AF_CHECK_STATUS(af_urdf_hammer(u, "hammer", &h, err, sizeof err), AF_OK);
  /* The shipped rig's URDF says the hammer the parameter table's rig values
   * say (what tools that read no URDF take): the rig's head, 10 g, flat. */
  AF_CHECK_ABS(h.mass_kg, 0.010, 1e-15);
  AF_CHECK_ABS(h.mass_kg, af_setting_rig_value(AF_SETTING_HAMMER_MASS_KG), 0.0);
  AF_CHECK_ABS(h.tip_radius_m, 0.0, 0.0); /* flat face (cylinder) */
  AF_CHECK_ABS(h.tip_radius_m, af_setting_rig_value(AF_SETTING_HAMMER_TIP_RADIUS_M), 0.0);
  check_vec(h.strike_axis, 0, 0, -1);
  AF_CHECK(strcmp(h.root_frame, "rig_base") == 0);
  AF_CHECK(err[0] == '\0');

  af_vec3 p;
  AF_CHECK_STATUS(af_urdf_position_in_root(u, "rig_base", &p), AF_OK);
  check_vec(p, 0, 0, 0);
  AF_CHECK_STATUS(af_urdf_position_in_root(u, "hammer", &p), AF_OK);
  check_vec(p, 0, 0, 0.15);
  AF_CHECK_STATUS(af_urdf_position_in_root(u, "force_transducer", &p), AF_OK);
  check_vec(p, 0, 0, 0.161);
  AF_CHECK_STATUS(af_urdf_position_in_root(u, "fruit_cup", &p), AF_OK);
  check_vec(p, 0, 0, 0.02);
  AF_CHECK_STATUS(af_urdf_position_in_root(u, "microphone", &p), AF_OK);
  check_vec(p, 0.05, 0, 0.06);
  AF_CHECK_STATUS(af_urdf_position_in_root(u, "camera_optical_frame", &p), AF_OK);
  check_vec(p, 0.10, 0, 0.30);

  double r[9];
  static const double identity[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  AF_CHECK_STATUS(af_urdf_rotation_to_root(u, "rig_base", r), AF_OK);
  check_rot(r, identity);
  /* The microphone's x (acoustic axis) points at the apple: -x of rig_base. */
  AF_CHECK_STATUS(af_urdf_rotation_to_root(u, "microphone", r), AF_OK);
  AF_CHECK_ABS(r[0], -1, TOL);
  AF_CHECK_ABS(r[3], 0, TOL);
  AF_CHECK_ABS(r[6], 0, TOL);
  /* Camera body: Ry(90), x looks down. */
  static const double ry90[9] = {0, 0, 1, 0, 1, 0, -1, 0, 0};
  AF_CHECK_STATUS(af_urdf_rotation_to_root(u, "camera_link", r), AF_OK);
  check_rot(r, ry90);
  /* Optical frame: z (viewing direction) down, x (image right) along -y,
   * y (image down) along -x of rig_base. So the strike axis is +z in the
   * vision frame: R^T (0, 0, -1). */
  static const double optical[9] = {0, -1, 0, -1, 0, 0, 0, 0, -1};
  AF_CHECK_STATUS(af_urdf_rotation_to_root(u, "camera_optical_frame", r), AF_OK);
  check_rot(r, optical);
  double a_vision[3];
  for (int i = 0; i < 3; i++)
    a_vision[i] = r[i] * h.strike_axis.x + r[3 + i] * h.strike_axis.y + r[6 + i] * h.strike_axis.z;
  AF_CHECK_ABS(a_vision[0], 0, TOL);
  AF_CHECK_ABS(a_vision[1], 0, TOL);
  AF_CHECK_ABS(a_vision[2], 1, TOL);

  /* Missing link. */
  AF_CHECK_STATUS(af_urdf_hammer(u, "mallet", &h, err, sizeof err), AF_ENODATA);
  AF_CHECK(has(err, "'mallet'"));
  AF_CHECK_STATUS(af_urdf_rotation_to_root(u, "mallet", r), AF_ENODATA);
  AF_CHECK_STATUS(af_urdf_position_in_root(u, "mallet", &p), AF_ENODATA);
  /* NULL arguments; err may be NULL. */
  AF_CHECK_STATUS(af_urdf_hammer(u, "hammer", NULL, NULL, 0), AF_EINVAL);
  AF_CHECK_STATUS(af_urdf_hammer(NULL, "hammer", &h, NULL, 0), AF_EINVAL);
  AF_CHECK_STATUS(af_urdf_rotation_to_root(u, NULL, r), AF_EINVAL);
  AF_CHECK_STATUS(af_urdf_position_in_root(u, "hammer", NULL), AF_EINVAL);
  /* A short err buffer is cut, not overrun. */
  char small[8];
  memset(small, 'x', sizeof small);
  AF_CHECK_STATUS(af_urdf_hammer(u, "mallet", &h, small, sizeof small), AF_ENODATA);
  AF_CHECK(small[7] == '\0' && strlen(small) == 7);
  af_urdf_destroy(u);
}

static void test_other_rigs(void)
{
  af_hammer_geometry h;
  af_urdf *u = load("test/shim/rig_spherical_tip.urdf");
  if (u != NULL) {
    AF_CHECK_STATUS(af_urdf_hammer(u, "hammer", &h, err, sizeof err), AF_OK);
    AF_CHECK_ABS(h.mass_kg, 0.012, 1e-15);
    AF_CHECK_ABS(h.tip_radius_m, 0.005, 1e-15);
    check_vec(h.strike_axis, 0, 0, -1);
    AF_CHECK(strcmp(h.root_frame, "rig_base") == 0);
    af_urdf_destroy(u);
  }
  u = load("test/node/rig_heavy_hammer.urdf");
  if (u != NULL) {
    AF_CHECK_STATUS(af_urdf_hammer(u, "hammer", &h, err, sizeof err), AF_OK);
    AF_CHECK_ABS(h.mass_kg, 0.020, 1e-15);
    AF_CHECK_ABS(h.tip_radius_m, 0.0, 0.0);
    check_vec(h.strike_axis, 0, 0, -1);
    af_urdf_destroy(u);
  }
}

static void test_hammer_cases(void)
{
  af_urdf *u = load("test/shim/hammer_cases.urdf");
  if (u == NULL)
    return;
  af_hammer_geometry h;
  AF_CHECK_STATUS(af_urdf_hammer(u, "hammer_box", &h, err, sizeof err), AF_OK);
  AF_CHECK_ABS(h.mass_kg, 0.015, 1e-15);
  AF_CHECK_ABS(h.tip_radius_m, 0.0, 0.0);
  check_vec(h.strike_axis, 1, 0, 0); /* normalised from (2, 0, 0) */
  AF_CHECK(strcmp(h.root_frame, "base") == 0);

  AF_CHECK_STATUS(af_urdf_hammer(u, "hammer_no_inertial", &h, err, sizeof err), AF_ENODATA);
  AF_CHECK(has(err, "'hammer_no_inertial'") && has(err, "<inertial>") && has(err, "mass"));
  AF_CHECK_STATUS(af_urdf_hammer(u, "hammer_no_collision", &h, err, sizeof err), AF_ENODATA);
  AF_CHECK(has(err, "<collision>"));
  AF_CHECK_STATUS(af_urdf_hammer(u, "hammer_mesh", &h, err, sizeof err), AF_EINVAL);
  AF_CHECK(has(err, "unsupported geometry"));
  AF_CHECK_STATUS(af_urdf_hammer(u, "hammer_zero_mass", &h, err, sizeof err), AF_EINVAL);
  AF_CHECK(has(err, "mass"));
  AF_CHECK_STATUS(af_urdf_hammer(u, "hammer_no_axis", &h, err, sizeof err), AF_ENODATA);
  AF_CHECK(has(err, "'no_axis_joint'") && has(err, "<axis>"));
  AF_CHECK_STATUS(af_urdf_hammer(u, "hammer_fixed", &h, err, sizeof err), AF_ENODATA);
  AF_CHECK(has(err, "'fixed_joint'") && has(err, "fixed"));
  AF_CHECK_STATUS(af_urdf_hammer(u, "hammer_revolute", &h, err, sizeof err), AF_EINVAL);
  AF_CHECK(has(err, "prismatic"));
  AF_CHECK_STATUS(af_urdf_hammer(u, "hammer_zero_axis", &h, err, sizeof err), AF_EINVAL);
  AF_CHECK(has(err, "zero <axis>"));
  /* The root has no parent joint at all. */
  AF_CHECK_STATUS(af_urdf_hammer(u, "base", &h, err, sizeof err), AF_ENODATA);
  af_urdf_destroy(u);
}

static void test_chain(void)
{
  af_urdf *u = load("test/shim/chain_rpy.urdf");
  if (u == NULL)
    return;
  static const double m[9] = {0, 0, 1, 1, 0, 0, 0, 1, 0};
  static const double mm[9] = {0, 1, 0, 0, 0, 1, 1, 0, 0};
  static const double rz90[9] = {0, -1, 0, 1, 0, 0, 0, 0, 1};
  double r[9];
  af_vec3 p;
  AF_CHECK_STATUS(af_urdf_rotation_to_root(u, "a", r), AF_OK);
  check_rot(r, rz90);
  AF_CHECK_STATUS(af_urdf_position_in_root(u, "a", &p), AF_OK);
  check_vec(p, 1, 0, 0);
  AF_CHECK_STATUS(af_urdf_rotation_to_root(u, "b", r), AF_OK);
  check_rot(r, m);
  AF_CHECK_STATUS(af_urdf_position_in_root(u, "b", &p), AF_OK);
  check_vec(p, 1, 1, 0);
  AF_CHECK_STATUS(af_urdf_rotation_to_root(u, "c", r), AF_OK);
  check_rot(r, mm);
  AF_CHECK_STATUS(af_urdf_position_in_root(u, "c", &p), AF_OK);
  check_vec(p, 1.5, 1, 0);
  AF_CHECK_STATUS(af_urdf_rotation_to_root(u, "hammer", r), AF_OK);
  check_rot(r, mm);
  AF_CHECK_STATUS(af_urdf_position_in_root(u, "hammer", &p), AF_OK);
  check_vec(p, 1.5, 1, 0.1);
  af_hammer_geometry h;
  AF_CHECK_STATUS(af_urdf_hammer(u, "hammer", &h, err, sizeof err), AF_OK);
  check_vec(h.strike_axis, 0, 1, 0);
  AF_CHECK(strcmp(h.root_frame, "base") == 0);
  af_urdf_destroy(u);
}

static void test_bad_input(void)
{
  af_urdf *u = (af_urdf *)&u; /* must be reset to NULL on failure */
  AF_CHECK_STATUS(af_urdf_load("test/shim/broken.urdf", &u, err, sizeof err), AF_EINVAL);
  AF_CHECK(u == NULL);
  AF_CHECK(has(err, "broken.urdf") && has(err, "not well-formed") && has(err, "line"));

  AF_CHECK_STATUS(af_urdf_load("test/shim/not_a_tree.urdf", &u, err, sizeof err), AF_EINVAL);
  AF_CHECK(u == NULL);
  AF_CHECK(has(err, "urdfdom") && has(err, "no_such_link"));

  AF_CHECK_STATUS(af_urdf_load("test/shim/no_such_file.urdf", &u, err, sizeof err), AF_EIO);
  AF_CHECK(has(err, "no_such_file.urdf"));

  AF_CHECK_STATUS(af_urdf_parse("<robot name=\"r\"><link name=\"base\"/></robot", &u, NULL, 0),
                  AF_EINVAL);
  AF_CHECK_STATUS(af_urdf_parse("<model/>", &u, err, sizeof err), AF_EINVAL);
  AF_CHECK(has(err, "<robot>"));
  AF_CHECK_STATUS(af_urdf_parse(NULL, &u, err, sizeof err), AF_EINVAL);
  AF_CHECK_STATUS(af_urdf_parse("<robot name=\"r\"/>", NULL, err, sizeof err), AF_EINVAL);
  af_urdf_destroy(NULL);

  /* A string (robot_description) parses as a file does. */
  AF_CHECK_STATUS(
      af_urdf_parse("<robot name=\"r\"><link name=\"base\"/></robot>", &u, err, sizeof err), AF_OK);
  af_vec3 p;
  AF_CHECK_STATUS(af_urdf_position_in_root(u, "base", &p), AF_OK);
  af_urdf_destroy(u);
}

int main(void)
{
  test_rig();
  test_other_rigs();
  test_hammer_cases();
  test_chain();
  test_bad_input();
  return af_test_summary("test_urdf");
}
