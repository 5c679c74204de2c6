/* test_grade.c — firmness classes (grade.h): the shipped cultivar's classes,
 * classification at and around every boundary, ungraded strikes with their
 * reasons, every refused spec as one line naming the row and the token, and
 * the quantity's stiffness factor against Lamb's 0S2 of a sphere (the
 * figure behind the shipped boundaries). */
#include <math.h>
#include <string.h>

#include "af_test.h"
#include "grade.h"
#include "lamb.h"
#include "settings.h"

#define ERR_MAX 512

static void test_shipped(void)
{
  char err[ERR_MAX] = "";
  af_settings s;
  af_grade_config g;
  af_settings_reset(&s);
  AF_CHECK_STATUS(af_settings_load_yaml(&s, "config/jonagold.yaml", err, sizeof err), AF_OK);
  AF_CHECK_STATUS(af_grade_config_from_settings(&s, &g, err, sizeof err), AF_OK);
  AF_CHECK(g.quantity == AF_GRADE_BY_STIFFNESS_FACTOR);
  AF_CHECK(g.n_classes == 4);
  AF_CHECK(strcmp(g.names[0], "soft") == 0 && strcmp(g.names[3], "very firm") == 0);
  AF_CHECK(g.lower[1] == 7.0e4 && g.lower[2] == 1.1e5 && g.lower[3] == 1.6e5);
  char text[256];
  af_grade_config_format(&g, text, sizeof text);
  AF_CHECK(strcmp(text, "soft < 70000 <= medium < 110000 <= firm < 160000 <= very firm "
                        "(stiffness_factor, Hz2 kg^(2/3))") == 0);

  /* The boundaries in MPa, as the YAML says (3.9, 6.1, 8.8 MPa): S = f^2 m^(2/3)
   * of Lamb's 0S2 does not depend on the mass. */
  double xi;
  AF_CHECK_STATUS(af_lamb_root(0.35, &xi), AF_OK);
  const double mpa[] = {3.9, 6.1, 8.8};
  for (int k = 0; k < 3; k++) {
    for (double m = 0.1; m <= 0.25; m += 0.05) {
      double f = af_lamb_frequency_hz(xi, mpa[k] * 1e6, 0.35, 840.0, m);
      AF_CHECK_REL(f * f * pow(m, 2.0 / 3.0), g.lower[k + 1], 0.02); /* [2 %] */
    }
  }
}

static void test_classify(void)
{
  char err[ERR_MAX] = "";
  af_grade_config g;
  AF_CHECK_STATUS(af_grade_config_parse(AF_GRADE_BY_STIFFNESS_FACTOR,
                                        " soft|7e4 | medium | 1.1e+5|firm ", NULL, &g, err,
                                        sizeof err),
                  AF_OK);
  AF_CHECK(g.n_classes == 3 && strcmp(g.names[1], "medium") == 0);
  AF_CHECK(af_grade_classify(&g, 1.0) == 1);
  AF_CHECK(af_grade_classify(&g, nextafter(7e4, 0.0)) == 1);
  AF_CHECK(af_grade_classify(&g, 7e4) == 2); /* on a boundary: the class above */
  AF_CHECK(af_grade_classify(&g, 1.0999e5) == 2);
  AF_CHECK(af_grade_classify(&g, 1.1e5) == 3);
  AF_CHECK(af_grade_classify(&g, 1e9) == 3);
  AF_CHECK(af_grade_classify(&g, NAN) == 0);
  AF_CHECK(af_grade_classify(&g, INFINITY) == 0);

  /* One class: everything measured is in it. Empty: grading off. */
  AF_CHECK_STATUS(
      af_grade_config_parse(AF_GRADE_BY_FITTED_MODULUS, "all", NULL, &g, err, sizeof err), AF_OK);
  AF_CHECK(g.n_classes == 1 && af_grade_classify(&g, 8e6) == 1);
  AF_CHECK_STATUS(
      af_grade_config_parse(AF_GRADE_BY_FITTED_MODULUS, "  ", NULL, &g, err, sizeof err), AF_OK);
  AF_CHECK(g.n_classes == 0 && af_grade_classify(&g, 8e6) == 0);
}

static af_measure_report report(bool reliable, double s, double e_res, double e_fit)
{
  af_measure_report r;
  memset(&r, 0, sizeof r);
  r.reliable = reliable;
  r.stiffness_factor = s;
  r.modulus_from_resonance_pa = e_res;
  r.fitted_modulus_pa = e_fit;
  if (!reliable)
    strcpy(r.reason, "resonance 900 Hz outside the half-power band [0, 700] Hz of lobe 1");
  return r;
}

static void test_strikes(void)
{
  char err[ERR_MAX] = "";
  af_grade_config g;
  af_grade out;
  AF_CHECK_STATUS(af_grade_config_parse(AF_GRADE_BY_STIFFNESS_FACTOR,
                                        "soft | 7.0e+4 | medium | 1.1e+5 | firm", NULL, &g, err,
                                        sizeof err),
                  AF_OK);
  af_measure_report r = report(true, 1.2e5, 6.6e6, 6.5e6);
  af_grade_strike(&g, &r, &out);
  AF_CHECK(out.index == 3 && strcmp(out.name, "firm") == 0 && out.reason[0] == '\0');
  AF_CHECK(out.value == 1.2e5);

  r = report(false, 1.2e5, 6.6e6, 6.5e6);
  af_grade_strike(&g, &r, &out);
  AF_CHECK(out.index == 0 && strcmp(out.name, "ungraded") == 0);
  AF_CHECK(strcmp(out.reason, "not reliable: resonance 900 Hz outside the half-power band [0, "
                              "700] Hz of lobe 1") == 0);

  r = report(true, NAN, NAN, 6.5e6);
  af_grade_strike(&g, &r, &out);
  AF_CHECK(out.index == 0 && strcmp(out.reason, "no stiffness_factor measured") == 0);

  /* On the fitted modulus the same strike is graded. */
  AF_CHECK_STATUS(af_grade_config_parse(AF_GRADE_BY_FITTED_MODULUS, "soft | 4.0e+6 | firm", NULL,
                                        &g, err, sizeof err),
                  AF_OK);
  af_grade_strike(&g, &r, &out);
  AF_CHECK(out.index == 2 && strcmp(out.name, "firm") == 0 && out.value == 6.5e6);

  af_grade_config off;
  AF_CHECK_STATUS(
      af_grade_config_parse(AF_GRADE_BY_FITTED_MODULUS, "", NULL, &off, err, sizeof err), AF_OK);
  af_grade_strike(&off, &r, &out);
  AF_CHECK(out.index == 0 && strstr(out.reason, "no firmness classes configured") == out.reason);
}

#define REFUSED(q, spec, want)                                                                     \
  do {                                                                                             \
    af_grade_config g_;                                                                            \
    err[0] = '\0';                                                                                 \
    AF_CHECK_STATUS(af_grade_config_parse(q, spec, "~grade_classes", &g_, err, sizeof err),        \
                    AF_EINVAL);                                                                    \
    AF_CHECK(g_.n_classes == 0);                                                                   \
    if (strcmp(err, want) != 0) {                                                                  \
      af_test_failed++;                                                                            \
      fprintf(stderr, "%s:%d: FAIL\n  got:  %s\n  want: %s\n", __FILE__, __LINE__, err, want);     \
    } else {                                                                                       \
      af_test_passed++;                                                                            \
    }                                                                                              \
  } while (0)

static void test_refused(void)
{
  char err[ERR_MAX];
  const af_grade_quantity S = AF_GRADE_BY_STIFFNESS_FACTOR, E = AF_GRADE_BY_FITTED_MODULUS;
  REFUSED(S, "soft | 7e4", "~grade_classes: no class name after the last boundary 70000");
  REFUSED(S, "soft || firm",
          "~grade_classes: no boundary after class 'soft' (expected a number in Hz2 kg^(2/3))");
  REFUSED(S, "| 7e4 | firm",
          "~grade_classes: class 1 has no name (expected 'name | boundary | name ...')");
  REFUSED(S, "soft | 7e4x | firm",
          "~grade_classes: boundary '7e4x' after class 'soft' is not a "
          "number");
  REFUSED(S, "soft | nan | firm",
          "~grade_classes: boundary 'nan' after class 'soft' is not a "
          "number");
  REFUSED(S, "soft | 1e9 | firm",
          "~grade_classes: boundary 1e+09 after class 'soft' is outside "
          "the accepted range [1000, 1e+08] Hz2 kg^(2/3) of "
          "stiffness_factor");
  REFUSED(E, "soft | 1e3 | firm",
          "~grade_classes: boundary 1000 after class 'soft' is outside "
          "the accepted range [100000, 1e+09] Pa of fitted_modulus");
  REFUSED(S, "a | 2e4 | b | 2e4 | c",
          "~grade_classes: boundary 20000 after class 'b' must be above the one before (20000)");
  REFUSED(S, "a | 3e4 | b | 2e4 | c",
          "~grade_classes: boundary 20000 after class 'b' must be above the one before (30000)");
  REFUSED(S, "a | 2e4 | a", "~grade_classes: class name 'a' is given twice");
  REFUSED(S, "ungraded | 2e4 | a",
          "~grade_classes: 'ungraded' is reserved for strikes without a "
          "class");
  REFUSED(S, "a-very-long-class-name-that-goes-on | 2e4 | b",
          "~grade_classes: class 1's name 'a-very-long-class-name-that-goes-on | 2e...' is "
          "longer than 31 characters");
  /* 17 classes: one too many. */
  REFUSED(S,
          "c1|2e3|c2|3e3|c3|4e3|c4|5e3|c5|6e3|c6|7e3|c7|8e3|c8|9e3|c9|1e4|c10|2e4|c11|3e4|c12|4e4|"
          "c13|5e4|c14|6e4|c15|7e4|c16|8e4|c17",
          "~grade_classes: more than 16 classes");

  /* Through the table: the row's name with the values object's prefix. */
  af_settings s;
  af_grade_config g;
  af_settings_reset(&s);
  af_settings_set_name_prefix(&s, "~");
  AF_CHECK_STATUS(af_settings_set_text(&s, "grade_classes", "\"soft | 5 | firm\"", err, sizeof err),
                  AF_OK);
  AF_CHECK_STATUS(af_grade_config_from_settings(&s, &g, err, sizeof err), AF_EINVAL);
  AF_CHECK(strcmp(err, "~grade_classes: boundary 5 after class 'soft' is outside the accepted "
                       "range [1000, 1e+08] Hz2 kg^(2/3) of stiffness_factor") == 0);
  AF_CHECK_STATUS(af_settings_set_text(&s, "grade_quantity", "modulus", err, sizeof err),
                  AF_EINVAL);
  AF_CHECK(strcmp(err, "~grade_quantity = 'modulus' is not one of: stiffness_factor, "
                       "modulus_from_resonance, fitted_modulus") == 0);
}

int main(void)
{
  test_shipped();
  test_classify();
  test_strikes();
  test_refused();
  return af_test_summary("test_grade");
}
