/* test_criteria.c — the two criteria of a reliable strike (criteria.h):
 * excites_mode at and around the half-power band's edges (closed interval),
 * no_damage at and around the yield (strict), and the reason's wording for
 * each combination, its "; " join and its cut into a short buffer. */
#include <math.h>
#include <string.h>

#include "af_test.h"
#include "criteria.h"

static af_lobe band_of(double lo_hz, double hi_hz)
{
  af_lobe b;
  memset(&b, 0, sizeof b);
  b.band_low_hz = lo_hz;
  b.band_high_hz = hi_hz;
  return b;
}

static void test_excites_mode(void)
{
  af_lobe b = band_of(600.0, 1200.0);
  AF_CHECK(af_criteria_excites_mode(&b, 600.0)); /* both edges belong to the band */
  AF_CHECK(af_criteria_excites_mode(&b, 1200.0));
  AF_CHECK(af_criteria_excites_mode(&b, 900.0));
  AF_CHECK(!af_criteria_excites_mode(&b, nextafter(600.0, 0.0)));
  AF_CHECK(!af_criteria_excites_mode(&b, nextafter(1200.0, 2000.0)));
  AF_CHECK(!af_criteria_excites_mode(&b, 0.0));
  AF_CHECK(!af_criteria_excites_mode(&b, NAN));
  AF_CHECK(!af_criteria_excites_mode(&b, INFINITY));
  AF_CHECK(!af_criteria_excites_mode(NULL, 900.0));
  af_lobe point = band_of(900.0, 900.0); /* a degenerate band holds its one point */
  AF_CHECK(af_criteria_excites_mode(&point, 900.0));
}

static void test_no_damage(void)
{
  const double yield = 0.3312e6; /* [Pa] */
  AF_CHECK(af_criteria_no_damage(0.0, yield));
  AF_CHECK(af_criteria_no_damage(nextafter(yield, 0.0), yield));
  AF_CHECK(!af_criteria_no_damage(yield, yield)); /* reaching the yield is damage */
  AF_CHECK(!af_criteria_no_damage(nextafter(yield, 1e9), yield));
  AF_CHECK(!af_criteria_no_damage(NAN, yield)); /* an unknown shear is not safe */
  AF_CHECK(!af_criteria_no_damage(0.1e6, NAN));
}

static int reason_is(const af_lobe *b, unsigned lobe, double f_hz, double shear_pa, double yield_pa,
                     const char *expected)
{
  char buf[512];
  memset(buf, '#', sizeof buf);
  af_criteria_reason(b, lobe, f_hz, shear_pa, yield_pa, buf, sizeof buf);
  if (strcmp(buf, expected) != 0) {
    fprintf(stderr, "  reason: got '%s', expected '%s'\n", buf, expected);
    return 0;
  }
  return 1;
}

static void test_reason(void)
{
  af_lobe b = band_of(612.4, 1187.6);
  /* Both hold: "". */
  AF_CHECK(reason_is(&b, 1, 899.796, 0.25e6, 0.3312e6, ""));
  AF_CHECK(reason_is(&b, 1, 612.4, 0.0, 0.3312e6, ""));
  /* Outside the band (figures rounded to whole Hz). */
  AF_CHECK(reason_is(&b, 1, 1300.0, 0.25e6, 0.3312e6,
                     "resonance 1300 Hz outside the half-power band [612, 1188] Hz of lobe 1"));
  /* No lobe: the band's test is not made. */
  AF_CHECK(reason_is(NULL, 3, 900.0, 0.25e6, 0.3312e6, "spectrum has no lobe 3"));
  /* Shear at the yield, in MPa with 3 decimals. */
  AF_CHECK(reason_is(&b, 1, 900.0, 0.3312e6, 0.3312e6,
                     "max shear 0.331 MPa not below yield 0.331 MPa (bruise risk)"));
  AF_CHECK(reason_is(&b, 2, 500.0, 0.41e6, 0.3312e6,
                     "resonance 500 Hz outside the half-power band [612, 1188] Hz of lobe 2; "
                     "max shear 0.410 MPa not below yield 0.331 MPa (bruise risk)"));
  AF_CHECK(reason_is(NULL, 0, 900.0, 1.0e6, 0.5e6,
                     "spectrum has no lobe 0; max shear 1.000 MPa not below yield 0.500 MPa "
                     "(bruise risk)"));

  /* Cut: never past len, always NUL-terminated. */
  char small[24];
  memset(small, '#', sizeof small);
  af_criteria_reason(&b, 2, 500.0, 0.41e6, 0.3312e6, small, 16);
  AF_CHECK(strcmp(small, "resonance 500 H") == 0);
  AF_CHECK(small[16] == '#');
  small[0] = '#';
  af_criteria_reason(&b, 2, 500.0, 0.41e6, 0.3312e6, small, 0); /* len 0: untouched */
  AF_CHECK(small[0] == '#');
  /* A first part that fills the buffer leaves no room for the second. */
  char mid[70];
  af_criteria_reason(&b, 2, 500.0, 0.41e6, 0.3312e6, mid, sizeof mid);
  AF_CHECK(strlen(mid) == sizeof mid - 1);
  AF_CHECK(strncmp(mid, "resonance 500 Hz outside the half-power band [612, 1188] Hz of lobe 2",
                   sizeof mid - 1) == 0);
}

int main(void)
{
  test_excites_mode();
  test_no_damage();
  test_reason();
  return af_test_summary("test_criteria");
}
