/* test_snapshot_text.c — the settings snapshot (snapshot_text.h): written
 * from settings changed by hand, read back into the very same values (every
 * row's text, and the numbers bit for bit); a hand-written snapshot read; an
 * absent optional row left out; refusals naming the line. */
#include <math.h>
#include <string.h>

#include "af_test.h"
#include "settings.h"
#include "snapshot_text.h"

static char text[AF_SNAPSHOT_MAX_BYTES];

static bool same_settings(const af_settings *a, const af_settings *b)
{
  for (int id = 0; id < AF_SETTING_COUNT; id++) {
    char x[2 * AF_SETTINGS_TEXT_MAX], y[2 * AF_SETTINGS_TEXT_MAX];
    af_settings_value_text(a, (af_setting_id)id, x, sizeof x);
    af_settings_value_text(b, (af_setting_id)id, y, sizeof y);
    double u = af_settings_number(a, (af_setting_id)id),
           v = af_settings_number(b, (af_setting_id)id);
    if (strcmp(x, y) != 0 || (!(isnan(u) && isnan(v)) && memcmp(&u, &v, sizeof u) != 0)) {
      fprintf(stderr, "row %s: %s against %s\n", af_setting_def_of((af_setting_id)id)->name, x, y);
      return false;
    }
  }
  return true;
}

static void test_round_trip(void)
{
  static af_settings s, back;
  char err[256];
  af_settings_reset(&s);
  /* Values no YAML file ships: a double that needs 17 digits, a bool, a
   * choice, strings with a quote, a colon and a hash. */
  AF_CHECK(af_settings_set_number(&s, AF_SETTING_MODULUS_FACTOR, 0.1 + 0.2, err, sizeof err) ==
           AF_OK);
  AF_CHECK(af_settings_set_text(&s, "tap_only", "true", err, sizeof err) == AF_OK);
  AF_CHECK(af_settings_set_text(&s, "damping_law", "paper", err, sizeof err) == AF_OK);
  AF_CHECK(af_settings_set_string(&s, AF_SETTING_HARDWARE_ID, "DAQ \"7\": s/n #42", err,
                                  sizeof err) == AF_OK);
  AF_CHECK(af_settings_snapshot(&s, text, sizeof text) == AF_OK);
  AF_CHECK(strstr(text, "modulus_factor: 0.30000000000000004\n") != NULL);
  AF_CHECK(strstr(text, "tap_only: true\n") != NULL);
  AF_CHECK(af_settings_from_snapshot(&back, text, err, sizeof err) == AF_OK);
  AF_CHECK(same_settings(&s, &back));
  AF_CHECK(af_settings_number(&back, AF_SETTING_MODULUS_FACTOR) == 0.1 + 0.2);
  AF_CHECK(strcmp(af_settings_string(&back, AF_SETTING_HARDWARE_ID), "DAQ \"7\": s/n #42") == 0);
  /* Too small a buffer: AF_ESIZE, whole lines only. */
  char small[64];
  AF_CHECK(af_settings_snapshot(&s, small, sizeof small) == AF_ESIZE);
  AF_CHECK(strlen(small) < sizeof small && (small[0] == '\0' || small[strlen(small) - 1] == '\n'));
}

/* A snapshot written by hand: the rows given, the rest at their defaults. */
static void test_by_hand(void)
{
  static af_settings s;
  char err[256];
  AF_CHECK(af_settings_from_snapshot(&s,
                                     "lobe: 2\nmodulus_factor: 1.25\n\nstrike_velocity_m_s: 1.1",
                                     err, sizeof err) == AF_OK);
  AF_CHECK(af_settings_number(&s, AF_SETTING_LOBE) == 2.0);
  AF_CHECK(af_settings_number(&s, AF_SETTING_MODULUS_FACTOR) == 1.25);
  AF_CHECK(af_settings_number(&s, AF_SETTING_STRIKE_VELOCITY_M_S) == 1.1);
  /* An absent optional row (the hammer's mass before a URDF) is not written. */
  static af_settings d;
  af_settings_reset(&d);
  AF_CHECK(af_settings_snapshot(&d, text, sizeof text) == AF_OK);
  AF_CHECK(!af_settings_present(&d, AF_SETTING_HAMMER_MASS_KG));
  AF_CHECK(strstr(text, "hammer_mass_kg:") == NULL);
}

static void expect_refused(const char *snapshot, const char *want)
{
  static af_settings s;
  char err[256] = "";
  af_settings_reset(&s);
  AF_CHECK(af_settings_set_text(&s, "lobe", "3", err, sizeof err) == AF_OK);
  AF_CHECK(af_settings_from_snapshot(&s, snapshot, err, sizeof err) == AF_EINVAL);
  if (strstr(err, want) == NULL)
    fprintf(stderr, "'%s': '%s' lacks '%s'\n", snapshot, err, want);
  AF_CHECK(strstr(err, want) != NULL);
  AF_CHECK(af_settings_number(&s, AF_SETTING_LOBE) == 3.0); /* unchanged */
}

static void test_refused(void)
{
  expect_refused("lobe: 2\nno_such_row: 1\n", "line 2: 'no_such_row' is not a parameter");
  expect_refused("lobe: 2\nlobe: 1\n", "line 2: lobe is given twice");
  expect_refused("lobe 2\n", "line 1: not `name: value`");
  expect_refused("lobe: 2\nmodulus_factor: -1\n", "line 2:");
  expect_refused("lobe: two\n", "line 1:");
}

int main(void)
{
  test_round_trip();
  test_by_hand();
  test_refused();
  printf("test_snapshot_text: %d passed, %d failed\n", af_test_passed, af_test_failed);
  return af_test_failed ? 1 : 0;
}
