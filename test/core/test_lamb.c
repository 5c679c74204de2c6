/* test_lamb.c — the 0S2 root of Lamb's equation, its neighbouring
 * modes (0S3, 0S4, 1S2, 0T2) and the sphere frequency/modulus conversions
 * against PHYSICS.md 5. */
#include "lamb.h"

#include <math.h>
#include <stddef.h>
#include <string.h>

#include "af_test.h"

#define MPA 1e6 /* [Pa] */
#define G 1e-3  /* [kg] */

/* xi of Lamb's equation: PHYSICS.md 5, to 1e-4 absolute. */
static void test_lamb_root(void)
{
  const double nu[] = {0.25, 0.30, 0.35, 0.40, 0.49};
  const double xi_ref[] = {2.6399, 2.6462, 2.6519, 2.6569, 2.6648};
  for (size_t i = 0; i < sizeof nu / sizeof nu[0]; ++i) {
    double xi = NAN;
    AF_CHECK_STATUS(af_lamb_root(nu[i], &xi), AF_OK);
    AF_CHECK_ABS(xi, xi_ref[i], 1e-4);
  }
  /* the ends of the accepted range still give a root in the expected band */
  double xi0 = NAN, xi_half = NAN;
  AF_CHECK_STATUS(af_lamb_root(0.0, &xi0), AF_OK);
  AF_CHECK(xi0 > 2.5 && xi0 < 2.6399);
  AF_CHECK_STATUS(af_lamb_root(0.4999, &xi_half), AF_OK);
  AF_CHECK(xi_half > 2.6648 && xi_half < 2.7);
}

/* E = C f^2 m^(2/3) rho^(1/3): C = 5.641 (nu 0.30), 5.833 (nu 0.35), to 0.1 %. */
static void test_modulus_constant(void)
{
  const double nu[] = {0.30, 0.35};
  const double c_ref[] = {5.641, 5.833};
  const double f_hz = 700.0, m_kg = 175 * G, rho = 840.0;
  for (size_t i = 0; i < 2; ++i) {
    double xi = NAN;
    AF_CHECK_STATUS(af_lamb_root(nu[i], &xi), AF_OK);
    double e_pa = af_lamb_modulus_pa(xi, f_hz, nu[i], rho, m_kg);
    AF_CHECK_REL(e_pa / (af_lamb_stiffness_factor(f_hz, m_kg) * cbrt(rho)), c_ref[i], 1e-3);
  }
}

/* Frequency table for rho 840, nu 0.35 (PHYSICS.md 5), to 0.3 %. */
static void test_frequency_table(void)
{
  const double e_pa[] = {2 * MPA, 8 * MPA, 12 * MPA};
  const double m_kg[] = {100 * G, 175 * G, 250 * G};
  const double f_ref[3][3] = {{411, 341, 303}, {821, 682, 605}, {1006, 835, 741}};
  double xi = NAN;
  AF_CHECK_STATUS(af_lamb_root(0.35, &xi), AF_OK);
  for (size_t i = 0; i < 3; ++i)
    for (size_t j = 0; j < 3; ++j)
      AF_CHECK_REL(af_lamb_frequency_hz(xi, e_pa[i], 0.35, 840.0, m_kg[j]), f_ref[i][j], 3e-3);
}

/* The inverse, the scaling laws and the helpers. */
static void test_inverse_and_scaling(void)
{
  double xi = NAN;
  AF_CHECK_STATUS(af_lamb_root(0.35, &xi), AF_OK);
  const double e_pa = 8 * MPA, m_kg = 175 * G, rho = 840.0;
  double f = af_lamb_frequency_hz(xi, e_pa, 0.35, rho, m_kg);
  AF_CHECK_REL(af_lamb_modulus_pa(xi, f, 0.35, rho, m_kg), e_pa, 1e-12);
  AF_CHECK_REL(
      af_lamb_frequency_hz(xi, af_lamb_modulus_pa(xi, 1000.0, 0.35, rho, m_kg), 0.35, rho, m_kg),
      1000.0, 1e-12);
  /* f ~ sqrt(E), f ~ m^(-1/3) */
  AF_CHECK_REL(af_lamb_frequency_hz(xi, 4.0 * e_pa, 0.35, rho, m_kg), 2.0 * f, 1e-12);
  AF_CHECK_REL(af_lamb_frequency_hz(xi, e_pa, 0.35, rho, 8.0 * m_kg), 0.5 * f, 1e-12);
  /* a = (3 m / (4 pi rho))^(1/3): a 1000 kg/m3, 4.18879 g sphere has a 1 cm radius */
  AF_CHECK_REL(af_lamb_sphere_radius_m(4.0 / 3.0 * 3.14159265358979 * 1e-3, 1000.0), 0.01, 1e-12);
  AF_CHECK_REL(af_lamb_stiffness_factor(500.0, 0.125), 500.0 * 500.0 * 0.25, 1e-12);
}

static void test_bad_input(void)
{
  double xi = 1.0;
  AF_CHECK_STATUS(af_lamb_root(-0.01, &xi), AF_EINVAL);
  AF_CHECK_STATUS(af_lamb_root(0.5, &xi), AF_EINVAL);
  AF_CHECK_STATUS(af_lamb_root(NAN, &xi), AF_EINVAL);
  AF_CHECK_STATUS(af_lamb_root(0.3, NULL), AF_EINVAL);
  AF_CHECK(xi == 1.0); /* untouched on failure */
  AF_CHECK(isnan(af_lamb_sphere_radius_m(0.0, 840.0)));
  AF_CHECK(isnan(af_lamb_sphere_radius_m(0.1, -1.0)));
  AF_CHECK(isnan(af_lamb_frequency_hz(2.65, -1.0, 0.35, 840.0, 0.175)));
  AF_CHECK(isnan(af_lamb_frequency_hz(2.65, 8e6, 0.5, 840.0, 0.175)));
  AF_CHECK(isnan(af_lamb_frequency_hz(0.0, 8e6, 0.35, 840.0, 0.175)));
  AF_CHECK(isnan(af_lamb_frequency_hz(2.65, 8e6, 0.35, 840.0, INFINITY)));
  AF_CHECK(isnan(af_lamb_modulus_pa(2.65, 0.0, 0.35, 840.0, 0.175)));
  AF_CHECK(isnan(af_lamb_modulus_pa(2.65, 700.0, 0.35, 0.0, 0.175)));
  AF_CHECK(isnan(af_lamb_stiffness_factor(700.0, 0.0)));
  AF_CHECK(isnan(af_lamb_stiffness_factor(NAN, 0.175)));
}

/* The cache answers as the solver does, for the ratio asked now. */
static void test_cache(void)
{
  af_lamb_cache c;
  double xi = 0.0;
  af_lamb_cache_reset(&c);
  AF_CHECK(isnan(c.poisson));
  AF_CHECK_STATUS(af_lamb_root_cached(&c, 0.25, &xi), AF_OK);
  AF_CHECK_ABS(xi, 2.6399, 1e-4);
  AF_CHECK_STATUS(af_lamb_root_cached(&c, 0.49, &xi), AF_OK);
  AF_CHECK_ABS(xi, 2.6648, 1e-4);
  AF_CHECK_STATUS(af_lamb_root_cached(&c, 0.49, &xi), AF_OK);
  AF_CHECK_ABS(xi, 2.6648, 1e-4);
  AF_CHECK_STATUS(af_lamb_root_cached(&c, 0.5, &xi), AF_EINVAL);
  AF_CHECK_ABS(c.poisson, 0.49, 0.0);
}

/* Ratios of the neighbouring modes to the 0S2: PHYSICS.md 5's table (4
 * decimals, so 1e-4 absolute); the 0S2 of the general solver is the one of
 * af_lamb_root, bit for bit. */
static void test_mode_ratios(void)
{
  const double nu[] = {0.25, 0.30, 0.35, 0.40};
  const double ref[4][4] = {{1.4835, 1.8976, 1.8430, 0.9474},
                            {1.4879, 1.9068, 1.8921, 0.9452},
                            {1.4919, 1.9153, 1.9381, 0.9432},
                            {1.4954, 1.9229, 1.9804, 0.9414}};
  const af_sphere_mode mode[] = {AF_MODE_0S3, AF_MODE_0S4, AF_MODE_1S2, AF_MODE_0T2};
  for (size_t i = 0; i < 4; ++i) {
    af_sphere_modes m;
    double xi = NAN, xi2 = NAN;
    AF_CHECK_STATUS(af_lamb_sphere_modes(nu[i], &m), AF_OK);
    AF_CHECK_STATUS(af_lamb_root(nu[i], &xi), AF_OK);
    AF_CHECK_STATUS(af_lamb_spheroidal_root(nu[i], 2, 0, &xi2), AF_OK);
    AF_CHECK(xi2 == xi && m.xi[AF_MODE_0S2] == xi);
    AF_CHECK(m.ratio[AF_MODE_0S2] == 1.0 && m.poisson == nu[i]);
    for (size_t j = 0; j < 4; ++j)
      AF_CHECK_ABS(m.ratio[mode[j]], ref[i][j], 1e-4);
  }
  /* 0T2 alone: 2.5011, independent of nu; the 0S3 and the 1S2 by order and
   * overtone, as the table gives them (nu 0.35) */
  double xi = NAN;
  AF_CHECK_STATUS(af_lamb_torsional_root(2, 0, &xi), AF_OK);
  AF_CHECK_ABS(xi, 2.5011, 1e-4);
  AF_CHECK_STATUS(af_lamb_spheroidal_root(0.35, 3, 0, &xi), AF_OK);
  AF_CHECK_ABS(xi / 2.6519, 1.4919, 2e-4);
  AF_CHECK_STATUS(af_lamb_spheroidal_root(0.35, 2, 1, &xi), AF_OK);
  AF_CHECK_ABS(xi / 2.6519, 1.9381, 2e-4);
  /* the roots of one order rise with the overtone */
  double prev = 0.0;
  for (unsigned k = 0; k <= AF_RESONANCE_MAX_OVERTONE; ++k) {
    AF_CHECK_STATUS(af_lamb_spheroidal_root(0.3, AF_RESONANCE_MAX_ORDER, k, &xi), AF_OK);
    AF_CHECK(xi > prev + 0.5);
    prev = xi;
  }
  AF_CHECK(strcmp(af_sphere_mode_name(AF_MODE_0S3), "0S3") == 0);
  AF_CHECK(strcmp(af_sphere_mode_name(AF_MODE_1S2), "1S2") == 0);
  AF_CHECK(strcmp(af_sphere_mode_name(AF_MODE_COUNT), "?") == 0);
}

static void test_mode_bad_input(void)
{
  double xi = 1.0;
  af_sphere_modes m;
  m.poisson = 7.0;
  AF_CHECK_STATUS(af_lamb_spheroidal_root(0.35, 1, 0, &xi), AF_EINVAL);
  AF_CHECK_STATUS(af_lamb_spheroidal_root(0.35, AF_RESONANCE_MAX_ORDER + 1, 0, &xi), AF_EINVAL);
  AF_CHECK_STATUS(af_lamb_spheroidal_root(0.35, 2, AF_RESONANCE_MAX_OVERTONE + 1, &xi), AF_EINVAL);
  AF_CHECK_STATUS(af_lamb_spheroidal_root(0.5, 2, 0, &xi), AF_EINVAL);
  AF_CHECK_STATUS(af_lamb_spheroidal_root(0.35, 2, 0, NULL), AF_EINVAL);
  AF_CHECK_STATUS(af_lamb_torsional_root(1, 0, &xi), AF_EINVAL);
  AF_CHECK_STATUS(af_lamb_torsional_root(2, 0, NULL), AF_EINVAL);
  AF_CHECK(xi == 1.0);
  AF_CHECK_STATUS(af_lamb_sphere_modes(-0.1, &m), AF_EINVAL);
  AF_CHECK_STATUS(af_lamb_sphere_modes(NAN, &m), AF_EINVAL);
  AF_CHECK_STATUS(af_lamb_sphere_modes(0.3, NULL), AF_EINVAL);
  AF_CHECK(m.poisson == 7.0); /* untouched on failure */
}

/* The mode cache answers as the solver does; a failure keeps it. */
static void test_mode_cache(void)
{
  af_sphere_modes_cache c;
  af_sphere_modes m;
  af_sphere_modes_cache_reset(&c);
  AF_CHECK(isnan(c.modes.poisson));
  AF_CHECK_STATUS(af_lamb_sphere_modes_cached(&c, 0.35, &m), AF_OK);
  AF_CHECK_ABS(m.ratio[AF_MODE_0S3], 1.4919, 1e-4);
  AF_CHECK_STATUS(af_lamb_sphere_modes_cached(&c, 0.25, &m), AF_OK);
  AF_CHECK_ABS(m.ratio[AF_MODE_1S2], 1.8430, 1e-4);
  AF_CHECK_STATUS(af_lamb_sphere_modes_cached(&c, 0.25, &m), AF_OK);
  AF_CHECK_ABS(m.ratio[AF_MODE_1S2], 1.8430, 1e-4);
  AF_CHECK_STATUS(af_lamb_sphere_modes_cached(&c, 0.5, &m), AF_EINVAL);
  AF_CHECK_ABS(c.modes.poisson, 0.25, 0.0);
  AF_CHECK_ABS(m.ratio[AF_MODE_1S2], 1.8430, 1e-4);
  AF_CHECK_STATUS(af_lamb_sphere_modes_cached(NULL, 0.25, &m), AF_EINVAL);
  AF_CHECK_STATUS(af_lamb_sphere_modes_cached(&c, 0.25, NULL), AF_EINVAL);
}

int main(void)
{
  test_cache();
  test_lamb_root();
  test_modulus_constant();
  test_frequency_table();
  test_inverse_and_scaling();
  test_bad_input();
  test_mode_ratios();
  test_mode_bad_input();
  test_mode_cache();
  return af_test_summary("test_lamb");
}
