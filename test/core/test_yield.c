/* test_yield.c — the yield law, the measured override, and the shipped
 * calibration's three statements (doc/model.md, "The yield law"). */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "af_test.h"
#include "model.h"
#include "yield.h"

static void test_law(void)
{
  af_yield_law law = {0.04, 8e6, 1.0, {0}};
  /* p = 1 is the ratio law whatever E_ref. */
  AF_CHECK_REL(af_yield_shear_pa(&law, 2e6), 0.04 * 2e6, 1e-12);
  law.reference_modulus_pa = 3e6;
  AF_CHECK_REL(af_yield_shear_pa(&law, 12e6), 0.04 * 12e6, 1e-12);
  law.exponent = 0.7;
  AF_CHECK_REL(af_yield_shear_pa(&law, 3e6), 0.04 * 3e6, 1e-12);
  AF_CHECK_REL(af_yield_shear_pa(&law, 6e6), 0.04 * 3e6 * pow(2.0, 0.7), 1e-12);
  law.exponent = 0.0; /* constant yield */
  AF_CHECK_REL(af_yield_shear_pa(&law, 11e6), 0.12e6, 1e-12);
  AF_CHECK(isnan(af_yield_shear_pa(&law, 0.0)));
  AF_CHECK(isnan(af_yield_shear_pa(&law, NAN)));
  law.ratio = -1.0;
  AF_CHECK(isnan(af_yield_shear_pa(&law, 8e6)));
  AF_CHECK(isnan(af_yield_shear_pa(NULL, 8e6)));
}

static void test_measured(void)
{
  af_yield_law law = {0.04, 8e6, 0.5, {0}};
  char err[160];
  AF_CHECK_STATUS(
      af_yield_points_parse("2e6:0.1e6, 8e6:0.4e6 12e6:0.45e6", &law.measured, err, sizeof err),
      AF_OK);
  AF_CHECK(law.measured.n == 3);
  /* At the points, between them log-log, beyond them the law's exponent. */
  AF_CHECK_REL(af_yield_shear_pa(&law, 8e6), 0.4e6, 1e-12);
  AF_CHECK_REL(af_yield_shear_pa(&law, 4e6), 0.2e6, 1e-12); /* tau ~ E2 between 2 and 8 */
  AF_CHECK_REL(af_yield_shear_pa(&law, 1e6), 0.1e6 * sqrt(0.5), 1e-12);
  AF_CHECK_REL(af_yield_shear_pa(&law, 48e6), 0.45e6 * 2.0, 1e-12);
  af_yield_points one;
  AF_CHECK_STATUS(af_yield_points_parse("8e6:0.3e6", &one, err, sizeof err), AF_OK);
  law.measured = one;
  AF_CHECK_REL(af_yield_shear_pa(&law, 2e6), 0.3e6 * 0.5, 1e-12);
  af_yield_points none = one;
  AF_CHECK_STATUS(af_yield_points_parse("", &none, err, sizeof err), AF_OK);
  AF_CHECK(none.n == 0);
  /* Refused: *out unchanged, one line. */
  const char *bad[] = {"8e6",
                       "8e6:",
                       "8e6:-1",
                       "abc:1",
                       "8e6:1e5x",
                       "8e6:1e5, 4e6:1e5",
                       "1:1 2:1 3:1 4:1 5:1 6:1 7:1 8:1 9:1"};
  for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) {
    af_yield_points p = one;
    err[0] = '\0';
    AF_CHECK_STATUS(af_yield_points_parse(bad[k], &p, err, sizeof err), AF_EINVAL);
    AF_CHECK(p.n == 1 && strlen(err) > 0 && strchr(err, '\n') == NULL);
  }
}

/* The shipped calibration: the average apple (8 MPa, 175 g) is reliable
 * down to 31 mm; at R2 40 mm the shear / yield ratio grows with E2 (soft
 * apples safe whenever firm ones are) and both fall with ripening, the shear
 * more (Fig. 3b). */
static void test_calibration(void)
{
  af_model *m;
  af_model_params p = af_model_params_default();
  af_model_result r;
  double r_min = 0.0;
  AF_CHECK_STATUS(af_model_create(&m), AF_OK);
  AF_CHECK_STATUS(af_model_min_strike_radius(m, &p, 0.002, 0.5, &r_min), AF_OK);
  AF_CHECK_ABS(r_min, 0.031, 0.0005);
  double prev_ratio = 0.0, tau2 = 0, tau12 = 0, y2 = 0, y12 = 0;
  for (double e2 = 2e6; e2 <= 12e6 + 1; e2 += 1e6) {
    p.impact.fruit_modulus_pa = e2;
    AF_CHECK_STATUS(af_model_execute(m, &p, &r), AF_OK);
    double ratio = r.max_shear_stress_pa / r.yield_shear_stress_pa;
    AF_CHECK(ratio > prev_ratio && r.no_damage);
    prev_ratio = ratio;
    if (e2 == 2e6)
      tau2 = r.max_shear_stress_pa, y2 = r.yield_shear_stress_pa;
    if (e2 == 12e6)
      tau12 = r.max_shear_stress_pa, y12 = r.yield_shear_stress_pa;
  }
  AF_CHECK(tau12 / tau2 > y12 / y2 && y12 / y2 > 1.0);
  af_model_destroy(m);
}

int main(void)
{
  test_law();
  test_measured();
  test_calibration();
  return af_test_summary("test_yield");
}
