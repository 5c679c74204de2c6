/* test_reconfigure.c — the rows that may change while the node runs
 * (reconfigure.h): the hand-written list of names and groups, each a row of
 * the parameter table of a kind dynamic_reconfigure can carry, its range as
 * written here from the design (every number row's default inside it, its
 * ends accepted or refused by the table as the brackets say, with the
 * refusal naming the row, the value and the range), and no row that sizes
 * an allocation or comes from the rig allowed. */
#include <math.h>
#include <stdbool.h>
#include <string.h>

#include "af_test.h"
#include "lane_config.h"
#include "reconfigure.h"
#include "settings.h"

typedef struct {
  const char *name, *group;
  af_setting_kind kind;
  double lo, hi; /* number and whole rows */
  bool lo_open, hi_open;
} expected_row;

static const expected_row expected[] = {
    {"damping_law", "criterion", AF_SETTING_CHOICE, 0, 0, false, false},
    {"lobe", "criterion", AF_SETTING_WHOLE, 1, 8, false, false},
    {"band_level", "criterion", AF_SETTING_CHOICE, 0, 0, false, false},
    {"shear_ratio", "criterion", AF_SETTING_CHOICE, 0, 0, false, false},
    {"strike_velocity_m_s", "criterion", AF_SETTING_NUMBER, 0.05, 10, false, false},
    {"latitude_tolerance_deg", "criterion", AF_SETTING_NUMBER, 0, 90, false, false},
    {"modulus_nominal_pa", "criterion", AF_SETTING_NUMBER, 1e5, 1e9, false, false},
    {"restitution", "criterion", AF_SETTING_NUMBER, 0.01, 1, false, false},
    {"yield_ratio", "criterion", AF_SETTING_NUMBER, 0.001, 1, false, false},
    {"modulus_factor", "criterion", AF_SETTING_NUMBER, 0.1, 10, false, false},
    {"strike_threshold_noise_factor", "thresholds", AF_SETTING_NUMBER, 0, 1000, true, false},
    {"strike_threshold_min_n", "thresholds", AF_SETTING_NUMBER, 0, 1e6, true, false},
    {"measure_snr_threshold_db", "thresholds", AF_SETTING_NUMBER, -100, 100, false, false},
    {"measure_range_margin", "thresholds", AF_SETTING_NUMBER, 0, 1, false, true},
    {"grade_quantity", "grades", AF_SETTING_CHOICE, 0, 0, false, false},
    {"grade_classes", "grades", AF_SETTING_STRING, 0, 0, false, false},
};
#define N_EXPECTED (sizeof expected / sizeof expected[0])

static void test_rows(void)
{
  size_t n = 0;
  const af_reconfigure_row *rows = af_reconfigure_rows(&n);
  AF_CHECK(rows != NULL && n == N_EXPECTED);
  for (size_t k = 0; k < n && k < N_EXPECTED; k++) {
    const af_setting_def *d = af_setting_def_of(rows[k].id);
    AF_CHECK(d != NULL);
    if (d == NULL)
      continue;
    AF_CHECK(strcmp(d->name, expected[k].name) == 0);
    AF_CHECK(strcmp(rows[k].group, expected[k].group) == 0);
    AF_CHECK(d->kind == expected[k].kind);
    if (strcmp(d->name, expected[k].name) != 0 || strcmp(rows[k].group, expected[k].group) != 0)
      fprintf(stderr, "  row %zu: %s (%s), expected %s (%s)\n", k, d->name, rows[k].group,
              expected[k].name, expected[k].group);
    AF_CHECK(af_reconfigure_allowed(rows[k].id));
    AF_CHECK(!d->optional); /* dynamic_reconfigure has no "absent" */
    af_setting_id found;
    AF_CHECK_STATUS(af_setting_find(expected[k].name, &found), AF_OK);
    AF_CHECK(found == rows[k].id);
    for (size_t j = 0; j < k; j++) /* once each */
      AF_CHECK(rows[j].id != rows[k].id);
  }
}

/* Each number row's range as the table holds it, its default inside, its
 * ends as the brackets say. */
static void test_ranges(void)
{
  size_t n = 0;
  const af_reconfigure_row *rows = af_reconfigure_rows(&n);
  for (size_t k = 0; k < n && k < N_EXPECTED; k++) {
    const expected_row *e = &expected[k];
    if (e->kind != AF_SETTING_NUMBER && e->kind != AF_SETTING_WHOLE)
      continue;
    af_setting_range r;
    AF_CHECK_STATUS(af_setting_range_of(rows[k].id, &r), AF_OK);
    AF_CHECK(r.lo == e->lo && r.hi == e->hi && r.lo_open == e->lo_open && r.hi_open == e->hi_open &&
             !r.zero);
    if (r.lo != e->lo || r.hi != e->hi)
      fprintf(stderr, "  %s: range [%g, %g], expected [%g, %g]\n", e->name, r.lo, r.hi, e->lo,
              e->hi);
    af_settings s;
    af_settings_reset(&s);
    double def = af_settings_number(&s, rows[k].id);
    AF_CHECK(af_setting_range_contains(&r, def));
    char err[256] = "";
    /* The ends: accepted when closed, refused when open. */
    af_status lo_st = af_settings_set_number(&s, rows[k].id, e->lo, err, sizeof err);
    AF_CHECK(lo_st == (e->lo_open ? AF_EINVAL : AF_OK));
    af_status hi_st = af_settings_set_number(&s, rows[k].id, e->hi, err, sizeof err);
    AF_CHECK(hi_st == (e->hi_open ? AF_EINVAL : AF_OK));
    /* Just outside: refused with one line naming row, value and range. */
    double below = e->lo - (e->hi - e->lo) * 1e-3;
    err[0] = '\0';
    AF_CHECK_STATUS(af_settings_set_number(&s, rows[k].id, below, err, sizeof err), AF_EINVAL);
    AF_CHECK(strncmp(err, e->name, strlen(e->name)) == 0 &&
             strstr(err, "is outside the accepted range") != NULL && strchr(err, '\n') == NULL);
    AF_CHECK_STATUS(af_settings_set_number(&s, rows[k].id, e->hi * 1.01 + 1.0, err, sizeof err),
                    AF_EINVAL);
    AF_CHECK_STATUS(af_settings_set_number(&s, rows[k].id, NAN, err, sizeof err), AF_EINVAL);
  }
  /* One refusal in full. */
  af_settings s;
  af_settings_reset(&s);
  char err[256] = "";
  AF_CHECK_STATUS(af_settings_set_number(&s, AF_SETTING_RESTITUTION, 1.5, err, sizeof err),
                  AF_EINVAL);
  AF_CHECK(strcmp(err, "restitution = 1.5 is outside the accepted range [0.01, 1]") == 0);
}

/* Everything else stays as started: what sizes an allocation (rates, ring
 * lengths, windows, the queue), the rig, the cultivar's bounds. */
static void test_not_allowed(void)
{
  const af_setting_id fixed[] = {AF_SETTING_FORCE_SAMPLE_RATE_HZ,
                                 AF_SETTING_FORCE_BUFFER_S,
                                 AF_SETTING_AUDIO_SAMPLE_RATE_HZ,
                                 AF_SETTING_AUDIO_BUFFER_S,
                                 AF_SETTING_MEASURE_AUDIO_WINDOW_S,
                                 AF_SETTING_MEASURE_NOISE_WINDOW_S,
                                 AF_SETTING_STRIKE_PENDING_SIZE,
                                 AF_SETTING_STRIKE_MAX_CONTACT_S,
                                 AF_SETTING_STRIKE_PLOT_WIDTH_PX,
                                 AF_SETTING_HAMMER_MASS_KG,
                                 AF_SETTING_HAMMER_LINK,
                                 AF_SETTING_URDF_FILE,
                                 AF_SETTING_FORCE_UNIT,
                                 AF_SETTING_CULTIVAR,
                                 AF_SETTING_MODULUS_MIN_PA,
                                 AF_SETTING_MASS_MAX_KG};
  for (size_t k = 0; k < sizeof fixed / sizeof fixed[0]; k++)
    AF_CHECK(!af_reconfigure_allowed(fixed[k]));
  /* Exactly the listed rows, of all the table's. */
  int allowed = 0;
  for (int id = 0; id < AF_SETTING_COUNT; id++)
    allowed += af_reconfigure_allowed((af_setting_id)id);
  AF_CHECK(allowed == (int)N_EXPECTED);
  AF_CHECK(!af_reconfigure_allowed(AF_SETTING_COUNT));
  AF_CHECK(!af_reconfigure_allowed((af_setting_id)-1));
}

/* strike_threshold_min_n through a reconfigure: inf is refused
 * by the row, and a value inside the row's (0, 1e6] N but at or above
 * strike_full_scale_n (500 N shipped) by af_lane_config_derive, the check
 * the node runs on every request, naming both rows; 499 N is taken. */
static void test_threshold_below_full_scale(void)
{
  af_settings s;
  af_lane_config c;
  char err[512];
  af_settings_reset(&s);
  AF_CHECK_STATUS(af_settings_set_arg(&s, "hammer_mass_kg=0.01", err, sizeof err), AF_OK);
  AF_CHECK_STATUS(af_settings_set_arg(&s, "hammer_tip_radius_m=0", err, sizeof err), AF_OK);
  AF_CHECK_STATUS(af_lane_config_derive(&s, &c, err, sizeof err), AF_OK);
  AF_CHECK(af_settings_number(&s, AF_SETTING_STRIKE_FULL_SCALE_N) == 500.0);
  af_status st =
      af_settings_set_number(&s, AF_SETTING_STRIKE_THRESHOLD_MIN_N, INFINITY, err, sizeof err);
  AF_CHECK_STATUS(st, AF_EINVAL);
  AF_CHECK(strcmp(err, "strike_threshold_min_n = inf is outside the accepted range (0, 1e6] N") ==
           0);
  AF_CHECK_STATUS(
      af_settings_set_number(&s, AF_SETTING_STRIKE_THRESHOLD_MIN_N, 1e6, err, sizeof err), AF_OK);
  AF_CHECK_STATUS(af_lane_config_derive(&s, &c, err, sizeof err), AF_EINVAL);
  AF_CHECK(strcmp(err, "strike_threshold_min_n = 1e+06 N is outside the accepted range (0, "
                       "strike_full_scale_n = 500 N)") == 0);
  AF_CHECK_STATUS(
      af_settings_set_number(&s, AF_SETTING_STRIKE_THRESHOLD_MIN_N, 500.0, err, sizeof err), AF_OK);
  AF_CHECK_STATUS(af_lane_config_derive(&s, &c, err, sizeof err), AF_EINVAL);
  AF_CHECK_STATUS(
      af_settings_set_number(&s, AF_SETTING_STRIKE_THRESHOLD_MIN_N, 499.0, err, sizeof err), AF_OK);
  AF_CHECK_STATUS(af_lane_config_derive(&s, &c, err, sizeof err), AF_OK);
}

int main(void)
{
  test_threshold_below_full_scale();
  test_rows();
  test_ranges();
  test_not_allowed();
  return af_test_summary("test_reconfigure");
}
