/* test_settings.c — the one parameter table (settings.h): its own
 * consistency, the shipped YAML files against it (every key a row, every
 * required row present, every value in range, station.yaml = the table's
 * defaults), af_lane_config_derive on them against figures computed here
 * from first principles, every error path as exactly one line naming the
 * parameter, its value and what is accepted, YAML edge cases, the model's
 * check against the table, and the printed table. Run from the repository
 * root (the shipped files are read as config/station.yaml and
 * config/jonagold.yaml). */
#define _POSIX_C_SOURCE 200809L /* mkfifo */
#include <malloc.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "af_test.h"
#include "lane.h"
#include "lane_config.h"
#include "lamb.h"
#include "settings.h"

#define STATION "config/station.yaml"
#define CULTIVAR "config/jonagold.yaml"
#define ERR_MAX 512

/* err is one complete line: not empty, not cut, no newline. */
static int one_line(const char *err)
{
  return err[0] != '\0' && strchr(err, '\n') == NULL && strlen(err) < ERR_MAX - 1;
}

/* The call failed with status st and exactly the line want. */
#define CHECK_ERROR(call, st, err, want)                                                           \
  do {                                                                                             \
    (err)[0] = '\0';                                                                               \
    AF_CHECK_STATUS(call, st);                                                                     \
    AF_CHECK(one_line(err));                                                                       \
    if (strcmp((err), (want)) != 0) {                                                              \
      af_test_failed++;                                                                            \
      fprintf(stderr, "%s:%d: FAIL message\n  got:  %s\n  want: %s\n", __FILE__, __LINE__, (err),  \
              (want));                                                                             \
    } else {                                                                                       \
      af_test_passed++;                                                                            \
    }                                                                                              \
  } while (0)

/* The call failed with status st and one line containing each of the words. */
static void check_words(af_status got, af_status st, const char *err, const char *const *words,
                        int line)
{
  AF_CHECK_STATUS(got, st);
  AF_CHECK(one_line(err));
  for (; *words; words++)
    if (strstr(err, *words) == NULL) {
      af_test_failed++;
      fprintf(stderr, "test_settings.c:%d: FAIL '%s' not in: %s\n", line, *words, err);
    } else {
      af_test_passed++;
    }
}
#define CHECK_WORDS(call, st, err, ...)                                                            \
  do {                                                                                             \
    const char *const words_[] = {__VA_ARGS__, NULL};                                              \
    (err)[0] = '\0';                                                                               \
    check_words(call, st, err, words_, __LINE__);                                                  \
  } while (0)

/* A temporary YAML file with the given text; its path in path[64]. */
static void write_file(char *path, const char *text)
{
  static int n;
  snprintf(path, 64, "/tmp/test_settings_%ld_%d.yaml", (long)getpid(), n++);
  FILE *f = fopen(path, "w");
  AF_CHECK(f != NULL);
  if (f) {
    fputs(text, f);
    fclose(f);
  }
}

/* Loads text as a YAML file into s; the status, err filled. */
static af_status load_text(af_settings *s, const char *text, char *err)
{
  char path[64];
  write_file(path, text);
  af_status st = af_settings_load_yaml(s, path, err, ERR_MAX);
  remove(path);
  return st;
}

/* Both shipped files and the hammer the node takes from config/rig.urdf. */
static af_status shipped(af_settings *s, char *err)
{
  af_settings_reset(s);
  af_status st = af_settings_load_yaml(s, STATION, err, ERR_MAX);
  if (st == AF_OK)
    st = af_settings_load_yaml(s, CULTIVAR, err, ERR_MAX);
  if (st == AF_OK)
    st = af_settings_set_arg(s, "hammer_mass_kg=0.010", err, ERR_MAX);
  if (st == AF_OK)
    st = af_settings_set_arg(s, "hammer_tip_radius_m=0", err, ERR_MAX);
  return st;
}

/* ---- the table itself ------------------------------------------------------- */

static void test_table(void)
{
  int strings = 0;
  af_settings d;
  af_settings_reset(&d);
  for (int k = 0; k < AF_SETTING_COUNT; k++) {
    af_setting_id id = (af_setting_id)k, found;
    const af_setting_def *r = af_setting_def_of(id);
    AF_CHECK(r != NULL && r->name != NULL && r->help != NULL && r->help[0] != '\0');
    if (r == NULL || r->name == NULL)
      continue;
    /* Names are unique (find gives this very row back). */
    AF_CHECK(af_setting_find(r->name, &found) == AF_OK && found == id);
    AF_CHECK(r->file == AF_SETTINGS_STATION || r->file == AF_SETTINGS_CULTIVAR);
    bool numeric = r->kind == AF_SETTING_NUMBER || r->kind == AF_SETTING_WHOLE;
    af_setting_range range;
    AF_CHECK((af_setting_range_of(id, &range) == AF_OK) == numeric);
    AF_CHECK((r->range != NULL) == numeric);
    AF_CHECK((r->choices != NULL) == (r->kind == AF_SETTING_CHOICE));
    AF_CHECK(r->optional == (r->def == NULL));
    AF_CHECK(!r->optional || (r->absent != NULL && numeric));
    if (r->kind == AF_SETTING_STRING) {
      strings++;
      AF_CHECK(r->max_chars > 0 && r->max_chars < AF_SETTINGS_TEXT_MAX);
    }
    /* Every default is accepted by its own row; optional rows start absent. */
    AF_CHECK(af_settings_present(&d, id) == !r->optional);
    AF_CHECK(!af_settings_given(&d, id));
    if (r->def != NULL) {
      af_settings t;
      char err[ERR_MAX], text[AF_SETTINGS_TEXT_MAX];
      af_settings_reset(&t);
      AF_CHECK_STATUS(af_settings_set_text(&t, r->name, r->def, err, sizeof err), AF_OK);
      /* value_text writes YAML that reads back to the same value. */
      af_settings_value_text(&d, id, text, sizeof text);
      AF_CHECK_STATUS(af_settings_set_text(&t, r->name, text, err, sizeof err), AF_OK);
      AF_CHECK(memcmp(&t.value[id], &d.value[id], sizeof(double)) == 0);
    }
  }
  AF_CHECK(strings == AF_SETTINGS_STRINGS);
  AF_CHECK(af_setting_def_of(AF_SETTING_COUNT) == NULL);
  af_setting_id id;
  AF_CHECK_STATUS(af_setting_find("no_such_parameter", &id), AF_EINVAL);
  AF_CHECK(strcmp(af_setting_unit(AF_SETTING_STRIKE_VELOCITY_M_S), "m/s") == 0);
  AF_CHECK(strcmp(af_setting_unit(AF_SETTING_HAMMER_POISSON), "") == 0);
  AF_CHECK(strcmp(af_setting_unit(AF_SETTING_CULTIVAR), "") == 0);

  /* The choices are exactly the core's names, both ways. */
  char w[64];
  for (size_t k = 0; af_setting_choice_word(AF_SETTING_DAMPING_LAW, k, w, sizeof w) == AF_OK; k++) {
    af_damping_law law;
    AF_CHECK(af_damping_law_parse(w, &law) == AF_OK && strcmp(af_damping_law_name(law), w) == 0);
  }
  for (size_t k = 0; af_setting_choice_word(AF_SETTING_BAND_LEVEL, k, w, sizeof w) == AF_OK; k++) {
    af_band_level level;
    AF_CHECK(af_band_level_parse(w, &level) == AF_OK);
  }
  for (size_t k = 0; af_setting_choice_word(AF_SETTING_SHEAR_RATIO, k, w, sizeof w) == AF_OK; k++) {
    af_shear_ratio ratio;
    AF_CHECK(af_shear_ratio_parse(w, &ratio) == AF_OK);
  }
  AF_CHECK_STATUS(af_setting_choice_word(AF_SETTING_DAMPING_LAW, 3, w, sizeof w), AF_EINVAL);
  AF_CHECK_STATUS(af_setting_choice_word(AF_SETTING_LOBE, 0, w, sizeof w), AF_EINVAL);
  const af_damping_law laws[] = {AF_DAMPING_PAPER, AF_DAMPING_EXACT, AF_DAMPING_HU_GUO};
  for (size_t k = 0; k < 3; k++) {
    char text[64];
    snprintf(text, sizeof text, "%s", af_damping_law_name(laws[k]));
    af_settings t;
    char err[ERR_MAX];
    af_settings_reset(&t);
    AF_CHECK_STATUS(af_settings_set_text(&t, "damping_law", text, err, sizeof err), AF_OK);
  }

  /* The lobe's range is the model's. */
  af_setting_range lobe;
  AF_CHECK(af_setting_range_of(AF_SETTING_LOBE, &lobe) == AF_OK && lobe.lo == 1.0 &&
           lobe.hi == AF_MODEL_MAX_LOBES && !lobe.lo_open && !lobe.hi_open);

  /* The rows of one quantity share one range. */
  static const af_setting_id same[][3] = {
      {AF_SETTING_R2_SEARCH_LOW_M, AF_SETTING_R2_SEARCH_HIGH_M, AF_SETTING_STRIKE_RADIUS_MIN_M},
      {AF_SETTING_STRIKE_RADIUS_MIN_M, AF_SETTING_STRIKE_RADIUS_MAX_M,
       AF_SETTING_STRIKE_RADIUS_MAX_M},
      {AF_SETTING_MODULUS_NOMINAL_PA, AF_SETTING_MODULUS_MIN_PA, AF_SETTING_MODULUS_MAX_PA},
      {AF_SETTING_MASS_MIN_KG, AF_SETTING_MASS_MAX_KG, AF_SETTING_MASS_MAX_KG},
      {AF_SETTING_EQUATORIAL_RADIUS_MIN_M, AF_SETTING_EQUATORIAL_RADIUS_MAX_M,
       AF_SETTING_EQUATORIAL_RADIUS_MAX_M},
      {AF_SETTING_ASPECT_RATIO_MIN, AF_SETTING_ASPECT_RATIO_MAX, AF_SETTING_ASPECT_RATIO_MAX},
      {AF_SETTING_FORCE_SAMPLE_RATE_HZ, AF_SETTING_AUDIO_SAMPLE_RATE_HZ,
       AF_SETTING_AUDIO_SAMPLE_RATE_HZ},
      {AF_SETTING_FORCE_BUFFER_S, AF_SETTING_AUDIO_BUFFER_S, AF_SETTING_AUDIO_BUFFER_S},
  };
  for (size_t k = 0; k < sizeof same / sizeof same[0]; k++)
    for (int j = 1; j < 3; j++)
      AF_CHECK(strcmp(af_setting_def_of(same[k][0])->range, af_setting_def_of(same[k][j])->range) ==
               0);

  /* Range texts: both bracket kinds, "0 or", a unit. */
  af_setting_range r;
  AF_CHECK(af_setting_range_of(AF_SETTING_HAMMER_MODULUS_PA, &r) == AF_OK && r.zero &&
           r.lo == 1e5 && !r.lo_open && r.hi == 1e12 && !r.hi_open);
  AF_CHECK(af_setting_range_contains(&r, 0.0) && af_setting_range_contains(&r, 1e5) &&
           af_setting_range_contains(&r, 1e12) && !af_setting_range_contains(&r, 1e-300) &&
           !af_setting_range_contains(&r, 1.1e12) && !af_setting_range_contains(&r, INFINITY) &&
           !af_setting_range_contains(&r, NAN) && !af_setting_range_contains(&r, -1e-300));
  AF_CHECK(af_setting_range_of(AF_SETTING_STRIKE_VELOCITY_M_S, &r) == AF_OK && !r.zero &&
           !r.lo_open && r.lo == 0.05 && !r.hi_open && r.hi == 10.0);
  AF_CHECK(!af_setting_range_contains(&r, 0.0) && !af_setting_range_contains(&r, 1e-9) &&
           af_setting_range_contains(&r, 10.0));
  AF_CHECK(af_setting_range_of(AF_SETTING_STREAM_STALE_AFTER_S, &r) == AF_OK && r.lo_open &&
           r.lo == 0.0 && !r.hi_open && r.hi == 3600.0);
  /* Every number row is physical: bounded on both sides. */
  for (int k = 0; k < AF_SETTING_COUNT; k++)
    if (af_setting_range_of((af_setting_id)k, &r) == AF_OK)
      AF_CHECK(isfinite(r.lo) && isfinite(r.hi));
  AF_CHECK(af_setting_range_of(AF_SETTING_MEASURE_SNR_THRESHOLD_DB, &r) == AF_OK &&
           r.lo == -100.0 && r.hi == 100.0);
}

/* ---- the shipped files ---------------------------------------------------------- */

static void test_shipped_files(void)
{
  char err[ERR_MAX] = "";
  af_settings d, s;
  af_settings_reset(&d);

  /* station.yaml: station rows only, all required ones, each = the default. */
  af_settings_reset(&s);
  AF_CHECK_STATUS(af_settings_load_yaml(&s, STATION, err, sizeof err), AF_OK);
  if (err[0])
    fprintf(stderr, "%s\n", err);
  AF_CHECK_STATUS(af_settings_check_required(&s, AF_SETTINGS_STATION, err, sizeof err), AF_OK);
  int given = 0;
  for (int k = 0; k < AF_SETTING_COUNT; k++) {
    af_setting_id id = (af_setting_id)k;
    if (!af_settings_given(&s, id))
      continue;
    given++;
    char a[AF_SETTINGS_TEXT_MAX], b[AF_SETTINGS_TEXT_MAX];
    af_settings_value_text(&s, id, a, sizeof a);
    af_settings_value_text(&d, id, b, sizeof b);
    AF_CHECK(af_setting_def_of(id)->file == AF_SETTINGS_STATION);
    if (strcmp(a, b) != 0 ||
        !(af_settings_number(&s, id) == af_settings_number(&d, id) ||
          (isnan(af_settings_number(&s, id)) && isnan(af_settings_number(&d, id))))) {
      af_test_failed++;
      fprintf(stderr, "FAIL " STATION ": %s = %s, the table's default is %s\n",
              af_setting_def_of(id)->name, a, b);
    } else {
      af_test_passed++;
    }
  }
  /* Every station row but the two optional hammer overrides. */
  int station_rows = 0;
  for (int k = 0; k < AF_SETTING_COUNT; k++)
    station_rows += af_setting_def_of((af_setting_id)k)->file == AF_SETTINGS_STATION &&
                    !af_setting_def_of((af_setting_id)k)->optional;
  AF_CHECK(given == station_rows);
  AF_CHECK_STATUS(af_settings_check_required(&s, AF_SETTINGS_ALL, err, sizeof err), AF_EINVAL);
  AF_CHECK(strstr(err, "cultivar is missing") == err);

  /* The cultivar's file: cultivar rows only, all of them, in range. */
  af_settings_reset(&s);
  AF_CHECK_STATUS(af_settings_load_yaml(&s, CULTIVAR, err, sizeof err), AF_OK);
  AF_CHECK_STATUS(af_settings_check_required(&s, AF_SETTINGS_CULTIVAR, err, sizeof err), AF_OK);
  for (int k = 0; k < AF_SETTING_COUNT; k++)
    if (af_settings_given(&s, (af_setting_id)k))
      AF_CHECK(af_setting_def_of((af_setting_id)k)->file == AF_SETTINGS_CULTIVAR);
  AF_CHECK(strcmp(af_settings_string(&s, AF_SETTING_CULTIVAR), "Jonagold") == 0);
  AF_CHECK(af_settings_number(&s, AF_SETTING_MODULUS_NOMINAL_PA) == 8.0e6);
  AF_CHECK(af_settings_number(&s, AF_SETTING_MODULUS_MAX_PA) == 12.0e6);

  /* The SNR threshold: one value (the issue: 12 dB in the YAML, 15 in the core). */
  AF_CHECK(af_settings_number(&d, AF_SETTING_MEASURE_SNR_THRESHOLD_DB) == 15.0);
  AF_CHECK(af_settings_number(&d, AF_SETTING_APPLE_WAIT_S) == 0.5);
}

/* ---- af_lane_config_derive on the shipped files ------------------------------ */

static void test_derive_shipped(void)
{
  char err[ERR_MAX] = "";
  af_settings s;
  af_lane_config c;
  AF_CHECK_STATUS(shipped(&s, err), AF_OK);
  AF_CHECK_STATUS(af_lane_config_derive(&s, &c, err, sizeof err), AF_OK);
  if (err[0])
    fprintf(stderr, "derive: %s\n", err);
  /* Streams: 2 s at 50 kHz and at 48 kHz. */
  AF_CHECK(c.force.capacity_samples == 100000 && c.audio.capacity_samples == 96000);
  AF_CHECK(strcmp(c.force.units[0], "N") == 0 && strcmp(c.audio.units[0], "Pa") == 0);
  AF_CHECK(c.force.units[1][0] == '\0' && c.audio.units[1][0] == '\0');
  /* 40 ms and 20 ms at 48 kHz: 1920 and 960 samples; the longer zero-padded
   * 4 times to a power of two: 4 x 1920 = 7680 -> 8192. */
  AF_CHECK(c.strikes.audio_window_samples == 1920 && c.strikes.noise_window_samples == 960);
  AF_CHECK(c.strikes.measure.response.window_samples == 1920);
  AF_CHECK(c.strikes.measure.response.fft_size == 8192);
  AF_CHECK(c.strikes.measure.response.sample_rate_hz == 48000.0);
  AF_CHECK(c.strikes.measure.response.snr_threshold_db == 15.0);
  AF_CHECK(c.strikes.pending_size == 8);
  AF_CHECK(c.strikes.apple_stale_after_s == 1.0 && c.strikes.apple_wait_s == 0.5);
  /* Event span at 50 kHz: pre-trigger 2 ms (100) + 2 contacts of 10 ms (2 x
   * 500) + gap 5 ms (250) + post 5 ms (250) + 4 = 1604 samples. */
  AF_CHECK(c.strikes.pulse_capacity_samples == 1604);
  AF_CHECK(c.strikes.strike.sample_rate_hz == 50000.0);
  AF_CHECK(c.strikes.strike.pre_trigger_s == 0.002 && c.strikes.strike.post_s == 0.005);
  AF_CHECK(c.strikes.strike.rise_fit_level == 0.7 && c.strikes.strike.fall_fit_level == 0.5);
  /* The fit holds the longest contact: 10 ms at 50 kHz + 2 = 502 samples. */
  AF_CHECK(c.strikes.measure.fit.max_samples == 502);
  AF_CHECK(!c.strikes.measure.fit.fit_velocity);
  AF_CHECK(c.strikes.measure.fit.damping == AF_DAMPING_EXACT);
  AF_CHECK(c.strikes.measure.audio_window_s == 0.04 && c.strikes.measure.range_margin == 0.15);
  /* The model template. */
  const af_impact_params *i = &c.model.impact;
  AF_CHECK(i->hammer_mass_kg == 0.010 && i->hammer_radius_m == 0.0 && i->velocity_m_s == 1.4);
  AF_CHECK(i->hammer_modulus_pa == 0.0 && i->hammer_poisson == 0.3 && i->gravity_m_s2 == 9.80665);
  AF_CHECK(i->fruit_modulus_pa == 8e6 && i->fruit_poisson == 0.35 && i->restitution == 0.6);
  AF_CHECK(i->strike_radius_m == 0.0 && c.model.fruit_mass_kg == 0.0); /* per apple */
  AF_CHECK(c.model.lobe == 1 && c.model.band_level == AF_BAND_AMPLITUDE_HALF &&
           c.model.shear_ratio == AF_SHEAR_EXACT);
  AF_CHECK(c.model.fruit_density_kg_m3 == 840.0 && c.model.yield_ratio == 0.0414 &&
           c.model.yield_exponent == 0.70 && c.model.yield_reference_modulus_pa == 8e6 &&
           c.model.modulus_factor == 1.0);
  AF_CHECK_ABS(c.latitude_tolerance_rad, 3.14159265358979323846 / 12.0, 1e-15); /* 15 deg */
  AF_CHECK(c.r2_search_low_m == 0.002 && c.r2_search_high_m == 0.5);
  AF_CHECK(c.strike_radius_min_m == 0.002 && c.strike_radius_max_m == 0.5);
  AF_CHECK(c.stream_stale_after_s == 1.0);
  AF_CHECK(strcmp(c.cultivar, "Jonagold") == 0);
  AF_CHECK(c.modulus_min_pa == 2e6 && c.modulus_max_pa == 12e6);
  AF_CHECK(c.mass_min_kg == 0.1 && c.mass_max_kg == 0.25);
  AF_CHECK(c.equatorial_radius_min_m == 0.025 && c.equatorial_radius_max_m == 0.06);
  AF_CHECK(c.aspect_ratio_min == 0.5 && c.aspect_ratio_max == 1.5);
  double xi;
  AF_CHECK(af_lamb_root(0.35, &xi) == AF_OK && c.resonance_xi == xi);

  /* Another rate: 44.1 kHz x 40 ms = 1764 samples -> 4 x 1764 = 7056 -> 8192;
   * a 50 ms noise reference is the longer: 2205 -> 8820 -> 16384. */
  AF_CHECK_STATUS(af_settings_set_arg(&s, "audio_sample_rate_hz=44100", err, sizeof err), AF_OK);
  AF_CHECK_STATUS(af_lane_config_derive(&s, &c, err, sizeof err), AF_OK);
  AF_CHECK(c.strikes.audio_window_samples == 1764 && c.strikes.measure.response.fft_size == 8192);
  AF_CHECK_STATUS(af_settings_set_arg(&s, "measure_noise_window_s=0.05", err, sizeof err), AF_OK);
  AF_CHECK_STATUS(af_lane_config_derive(&s, &c, err, sizeof err), AF_OK);
  AF_CHECK(c.strikes.noise_window_samples == 2205);
  AF_CHECK(c.strikes.measure.response.window_samples == 2205);
  AF_CHECK(c.strikes.measure.response.fft_size == 16384);
  /* round(), not floor: 0.0333 s x 44.1 kHz = 1468.53 -> 1469. */
  AF_CHECK_STATUS(af_settings_set_arg(&s, "measure_audio_window_s=0.0333", err, sizeof err), AF_OK);
  AF_CHECK_STATUS(af_lane_config_derive(&s, &c, err, sizeof err), AF_OK);
  AF_CHECK(c.strikes.audio_window_samples == 1469);
  /* The fit's own 256 stays when the longest contact needs fewer: 1 ms at
   * 50 kHz + 2 = 52 (the detector then needs a shorter gap and post). */
  AF_CHECK_STATUS(af_settings_set_arg(&s, "strike_max_contact_s=0.001", err, sizeof err), AF_OK);
  AF_CHECK_STATUS(af_lane_config_derive(&s, &c, err, sizeof err), AF_OK);
  AF_CHECK(c.strikes.measure.fit.max_samples == 256);
  /* Choices and whole numbers reach the model. */
  AF_CHECK_STATUS(af_settings_set_arg(&s, "damping_law=hu-guo", err, sizeof err), AF_OK);
  AF_CHECK_STATUS(af_settings_set_arg(&s, "lobe=2", err, sizeof err), AF_OK);
  AF_CHECK_STATUS(af_settings_set_arg(&s, "audio_unit=V", err, sizeof err), AF_OK);
  AF_CHECK_STATUS(af_settings_set_arg(&s, "measure_fit_velocity=true", err, sizeof err), AF_OK);
  AF_CHECK_STATUS(af_lane_config_derive(&s, &c, err, sizeof err), AF_OK);
  AF_CHECK(c.model.impact.damping == AF_DAMPING_HU_GUO && c.model.lobe == 2);
  AF_CHECK(c.strikes.measure.fit.damping == AF_DAMPING_HU_GUO);
  AF_CHECK(strcmp(c.audio.units[0], "V") == 0 && c.strikes.measure.fit.fit_velocity);
}

/* ---- one value at a time: every message ---------------------------------------- */

static void test_value_errors(void)
{
  char err[ERR_MAX];
  af_settings s;
  af_settings_reset(&s);
  CHECK_ERROR(af_settings_set_text(&s, "strike_velocity_m_s", "-1", err, sizeof err), AF_EINVAL,
              err, "strike_velocity_m_s = -1 is outside the accepted range [0.05, 10] m/s");
  AF_CHECK(af_settings_number(&s, AF_SETTING_STRIKE_VELOCITY_M_S) == 1.4); /* unchanged */
  CHECK_ERROR(af_settings_set_number(&s, AF_SETTING_MODULUS_MIN_PA, -2e6, err, sizeof err),
              AF_EINVAL, err,
              "modulus_min_pa = -2e+06 is outside the accepted range [1e5, 1e9] Pa");
  CHECK_ERROR(af_settings_set_number(&s, AF_SETTING_HAMMER_POISSON, 0.5, err, sizeof err),
              AF_EINVAL, err, "hammer_poisson = 0.5 is outside the accepted range [0, 0.5)");
  CHECK_ERROR(af_settings_set_number(&s, AF_SETTING_GRAVITY_M_S2, NAN, err, sizeof err), AF_EINVAL,
              err, "gravity_m_s2 = nan is outside the accepted range [0, 20] m/s2");
  CHECK_ERROR(af_settings_set_text(&s, "lobe", "9", err, sizeof err), AF_EINVAL, err,
              "lobe = 9 is outside the accepted range [1, 8]");
  CHECK_ERROR(af_settings_set_text(&s, "lobe", "1.5", err, sizeof err), AF_EINVAL, err,
              "lobe = 1.5 is not a whole number in [1, 8]");
  CHECK_ERROR(af_settings_set_number(&s, AF_SETTING_STRIKE_PENDING_SIZE, 2.5, err, sizeof err),
              AF_EINVAL, err,
              "strike_pending_size = 2.5 is not a whole number in [1, 1000] strikes");
  CHECK_WORDS(af_settings_set_text(&s, "modulus_min_pa", "2.0e6", err, sizeof err), AF_EINVAL, err,
              "modulus_min_pa = '2.0e6' is not a number", "8.0e+6");
  CHECK_ERROR(af_settings_set_text(&s, "modulus_min_pa", "soft", err, sizeof err), AF_EINVAL, err,
              "modulus_min_pa = 'soft' is not a number (expected [1e5, 1e9] Pa)");
  CHECK_ERROR(af_settings_set_text(&s, "lobe", "\"1\"", err, sizeof err), AF_EINVAL, err,
              "lobe = '1' is not a number (expected [1, 8])");
  CHECK_ERROR(af_settings_set_bool(&s, AF_SETTING_LOBE, true, err, sizeof err), AF_EINVAL, err,
              "lobe = true is not a number (expected [1, 8])");
  CHECK_ERROR(af_settings_set_text(&s, "damping_law", "fancy", err, sizeof err), AF_EINVAL, err,
              "damping_law = 'fancy' is not one of: paper, exact, hu-guo");
  CHECK_ERROR(af_settings_set_number(&s, AF_SETTING_AUDIO_UNIT, 3, err, sizeof err), AF_EINVAL, err,
              "audio_unit = 3 is not one of: Pa, V");
  CHECK_ERROR(af_settings_set_text(&s, "markers_enabled", "maybe", err, sizeof err), AF_EINVAL, err,
              "markers_enabled = 'maybe' is not true or false");
  CHECK_ERROR(af_settings_set_text(&s, "cultivar", "12", err, sizeof err), AF_EINVAL, err,
              "cultivar = 12 is not a string (quote it)");
  CHECK_ERROR(af_settings_set_text(&s, "lobes", "1", err, sizeof err), AF_EINVAL, err,
              "unknown parameter 'lobes'");
  CHECK_ERROR(af_settings_set_text(&s, "lobe", "", err, sizeof err), AF_EINVAL, err,
              "lobe has no value (expected a whole number in [1, 8])");
  CHECK_ERROR(af_settings_set_text(&s, "lobe", "1 2", err, sizeof err), AF_EINVAL, err,
              "lobe = '1 2' is not a number (expected [1, 8])");
  char longer[80];
  memset(longer, 'x', 70);
  longer[70] = '\0';
  CHECK_WORDS(af_settings_set_string(&s, AF_SETTING_HAMMER_LINK, longer, err, sizeof err),
              AF_EINVAL, err, "hammer_link = 'xxx", "is longer than 63 characters");
  char want[64];
  snprintf(want, sizeof want, "unknown parameter #%d", (int)AF_SETTING_COUNT);
  CHECK_ERROR(af_settings_set_number(&s, AF_SETTING_COUNT, 1, err, sizeof err), AF_EINVAL, err,
              want);

  /* Optional overrides: absent by default, 0 = absent for the mass. */
  AF_CHECK(!af_settings_present(&s, AF_SETTING_HAMMER_MASS_KG));
  AF_CHECK(isnan(af_settings_number(&s, AF_SETTING_HAMMER_MASS_KG)));
  CHECK_ERROR(af_settings_set_number(&s, AF_SETTING_HAMMER_MASS_KG, 2, err, sizeof err), AF_EINVAL,
              err,
              "hammer_mass_kg = 2 is outside the accepted range [0.0005, 1] kg (0 or absent = from "
              "the URDF)");
  CHECK_ERROR(
      af_settings_set_number(&s, AF_SETTING_HAMMER_TIP_RADIUS_M, -1, err, sizeof err), AF_EINVAL,
      err,
      "hammer_tip_radius_m = -1 is outside the accepted range 0 or [0.0005, 0.1] m (absent = from "
      "the URDF)");
  AF_CHECK_STATUS(af_settings_set_number(&s, AF_SETTING_HAMMER_MASS_KG, 0.02, err, sizeof err),
                  AF_OK);
  AF_CHECK(af_settings_present(&s, AF_SETTING_HAMMER_MASS_KG));
  AF_CHECK_STATUS(af_settings_set_number(&s, AF_SETTING_HAMMER_MASS_KG, 0.0, err, sizeof err),
                  AF_OK);
  AF_CHECK(!af_settings_present(&s, AF_SETTING_HAMMER_MASS_KG));
  AF_CHECK(af_settings_given(&s, AF_SETTING_HAMMER_MASS_KG));
  AF_CHECK_STATUS(af_settings_set_number(&s, AF_SETTING_HAMMER_TIP_RADIUS_M, 0.0, err, sizeof err),
                  AF_OK);
  AF_CHECK(af_settings_present(&s, AF_SETTING_HAMMER_TIP_RADIUS_M)); /* 0 = a flat face */

  /* The node's prefix. */
  af_settings_set_name_prefix(&s, "~");
  CHECK_ERROR(af_settings_set_text(&s, "lobe", "9", err, sizeof err), AF_EINVAL, err,
              "~lobe = 9 is outside the accepted range [1, 8]");
  CHECK_ERROR(af_settings_set_text(&s, "lobes", "9", err, sizeof err), AF_EINVAL, err,
              "unknown parameter '~lobes'");

  /* Missing required rows. */
  af_settings_reset(&s);
  CHECK_ERROR(af_settings_check_required(&s, AF_SETTINGS_STATION, err, sizeof err), AF_EINVAL, err,
              "hammer_link is missing (expected a string; its default is in "
              "config/station.yaml)");
  char path[64];
  AF_CHECK_STATUS(af_settings_load_yaml(&s, STATION, err, sizeof err), AF_OK);
  write_file(path, "cultivar: Gala\nmodulus_nominal_pa: 7.0e+6\n");
  AF_CHECK_STATUS(af_settings_load_yaml(&s, path, err, sizeof err), AF_OK);
  remove(path);
  CHECK_ERROR(
      af_settings_check_required(&s, AF_SETTINGS_ALL, err, sizeof err), AF_EINVAL, err,
      "modulus_min_pa is missing (expected a number in [1e5, 1e9] Pa; a cultivar value: see "
      "the cultivar's YAML, e.g. config/jonagold.yaml)");
}

/* ---- command-line name=value -------------------------------------------------- */

static void test_args(void)
{
  char err[ERR_MAX];
  af_settings s;
  af_settings_reset(&s);
  AF_CHECK_STATUS(af_settings_set_arg(&s, "modulus_nominal_pa=9e6", err, sizeof err), AF_OK);
  AF_CHECK(af_settings_number(&s, AF_SETTING_MODULUS_NOMINAL_PA) == 9e6); /* C numbers too */
  AF_CHECK_STATUS(af_settings_set_arg(&s, "cultivar=Gala", err, sizeof err), AF_OK);
  AF_CHECK(strcmp(af_settings_string(&s, AF_SETTING_CULTIVAR), "Gala") == 0);
  AF_CHECK_STATUS(af_settings_set_arg(&s, "urdf_file=", err, sizeof err), AF_OK);
  AF_CHECK_STATUS(af_settings_set_arg(&s, "urdf_file=/tmp/a b.urdf", err, sizeof err), AF_OK);
  AF_CHECK(strcmp(af_settings_string(&s, AF_SETTING_URDF_FILE), "/tmp/a b.urdf") == 0);
  AF_CHECK_STATUS(af_settings_set_arg(&s, "markers_enabled=false", err, sizeof err), AF_OK);
  AF_CHECK(!af_settings_bool(&s, AF_SETTING_MARKERS_ENABLED));
  AF_CHECK_STATUS(af_settings_set_arg(&s, "strike_pending_size=16", err, sizeof err), AF_OK);
  AF_CHECK(af_settings_number(&s, AF_SETTING_STRIKE_PENDING_SIZE) == 16.0);
  CHECK_ERROR(af_settings_set_arg(&s, "lobe", err, sizeof err), AF_EINVAL, err,
              "'lobe' is not name=value");
  CHECK_ERROR(af_settings_set_arg(&s, "colour=red", err, sizeof err), AF_EINVAL, err,
              "unknown parameter 'colour'");
  CHECK_ERROR(af_settings_set_arg(&s, "strike_velocity_m_s=20", err, sizeof err), AF_EINVAL, err,
              "strike_velocity_m_s = 20 is outside the accepted range [0.05, 10] m/s");
  CHECK_ERROR(af_settings_set_arg(&s, "strike_velocity_m_s=fast", err, sizeof err), AF_EINVAL, err,
              "strike_velocity_m_s = 'fast' is not a number (expected [0.05, 10] m/s)");
  char text[64];
  af_settings_value_text(&s, AF_SETTING_MODULUS_NOMINAL_PA, text, sizeof text);
  AF_CHECK(strcmp(text, "9.0e+06") == 0); /* YAML 1.1 reads it back as a number */
  static const char *const strings[] = {"yes", "12",      "a: b", "x #y", "",
                                        "'q'", "a\"b\\c", "Gala", " lead"};
  for (size_t k = 0; k < sizeof strings / sizeof strings[0]; k++) {
    af_settings t;
    af_settings_reset(&t);
    AF_CHECK_STATUS(af_settings_set_string(&s, AF_SETTING_CULTIVAR, strings[k], err, sizeof err),
                    AF_OK);
    af_settings_value_text(&s, AF_SETTING_CULTIVAR, text, sizeof text);
    AF_CHECK_STATUS(af_settings_set_text(&t, "cultivar", text, err, sizeof err), AF_OK);
    AF_CHECK(strcmp(af_settings_string(&t, AF_SETTING_CULTIVAR), strings[k]) == 0);
  }
  af_settings_value_text(&s, AF_SETTING_HAMMER_MASS_KG, text, sizeof text);
  AF_CHECK(strcmp(text, "absent") == 0);
  af_settings_value_text(&s, AF_SETTING_DAMPING_LAW, text, sizeof text);
  AF_CHECK(strcmp(text, "exact") == 0);
  af_settings_value_text(&s, AF_SETTING_GRAVITY_M_S2, text, sizeof text);
  AF_CHECK(strcmp(text, "9.80665") == 0);
}

/* ---- YAML edge cases ------------------------------------------------------------ */

static void test_yaml(void)
{
  char err[ERR_MAX] = "";
  af_settings s;
  af_settings_reset(&s);
  AF_CHECK_STATUS(load_text(&s,
                            "---\n"
                            "# a comment\n"
                            "\n"
                            "   \n"
                            "cultivar: 'Cox''s Orange'   # quoted, '' inside\n"
                            "hammer_link: \"head \\\"A\\\" # not a comment\"\n"
                            "urdf_file: /rigs/a#b.urdf  # '#' without a blank is text\n"
                            "modulus_nominal_pa: 8.0e+6\n"
                            "modulus_max_pa: 1.2E+7\r\n"
                            "modulus_min_pa:\t.5e+6\n"
                            "strike_pending_size: 1_000\n"
                            "lobe: 010\n"
                            "markers_enabled: off\n"
                            "measure_fit_velocity: Yes\n"
                            "gravity_m_s2: 0\n"
                            "measure_snr_threshold_db: -3.\n"
                            "audio_unit: V",
                            err),
                  AF_OK);
  AF_CHECK(strcmp(af_settings_string(&s, AF_SETTING_CULTIVAR), "Cox's Orange") == 0);
  AF_CHECK(strcmp(af_settings_string(&s, AF_SETTING_HAMMER_LINK), "head \"A\" # not a comment") ==
           0);
  AF_CHECK(strcmp(af_settings_string(&s, AF_SETTING_URDF_FILE), "/rigs/a#b.urdf") == 0);
  AF_CHECK(af_settings_number(&s, AF_SETTING_MODULUS_NOMINAL_PA) == 8e6);
  AF_CHECK(af_settings_number(&s, AF_SETTING_MODULUS_MAX_PA) == 12e6);
  AF_CHECK(af_settings_number(&s, AF_SETTING_MODULUS_MIN_PA) == 0.5e6);
  AF_CHECK(af_settings_number(&s, AF_SETTING_STRIKE_PENDING_SIZE) == 1000.0);
  AF_CHECK(af_settings_number(&s, AF_SETTING_LOBE) == 8.0); /* YAML 1.1: octal */
  AF_CHECK(!af_settings_bool(&s, AF_SETTING_MARKERS_ENABLED));
  AF_CHECK(af_settings_bool(&s, AF_SETTING_MEASURE_FIT_VELOCITY));
  AF_CHECK(af_settings_number(&s, AF_SETTING_GRAVITY_M_S2) == 0.0);
  AF_CHECK(af_settings_number(&s, AF_SETTING_MEASURE_SNR_THRESHOLD_DB) == -3.0);
  char word[16];
  AF_CHECK(af_settings_choice(&s, AF_SETTING_AUDIO_UNIT, word, sizeof word) == AF_OK &&
           strcmp(word, "V") == 0);
  AF_CHECK_STATUS(load_text(&s, "", err), AF_OK); /* an empty file sets nothing */
  AF_CHECK_STATUS(load_text(&s, "lobe: 0x2\n", err), AF_OK);
  AF_CHECK(af_settings_number(&s, AF_SETTING_LOBE) == 2.0);

  /* Every refusal: one line with the file and line, and s unchanged. */
  af_settings before = s;
  char path[64];
  write_file(path, "lobe: 1\nlobe: 2\n");
  char want[ERR_MAX];
  snprintf(want, sizeof want, "%s:2: duplicate key 'lobe': given on line 1 and again on line 2",
           path);
  CHECK_ERROR(af_settings_load_yaml(&s, path, err, sizeof err), AF_EINVAL, err, want);
  remove(path);
  AF_CHECK(memcmp(&before, &s, sizeof s) == 0);
  write_file(path, "# x\nlobe: 1\nlobes: 2\n");
  snprintf(want, sizeof want, "%s:3: unknown parameter 'lobes'", path);
  CHECK_ERROR(af_settings_load_yaml(&s, path, err, sizeof err), AF_EINVAL, err, want);
  remove(path);
  AF_CHECK(memcmp(&before, &s, sizeof s) == 0); /* line 2 was not kept */
  write_file(path, "lobe: 1\n\nstrike_velocity_m_s: 11.0 # too fast\n");
  snprintf(want, sizeof want,
           "%s:3: strike_velocity_m_s = 11 is outside the accepted range [0.05, 10] m/s", path);
  CHECK_ERROR(af_settings_load_yaml(&s, path, err, sizeof err), AF_EINVAL, err, want);
  remove(path);
  write_file(path, "modulus_min_pa: 2.0e6\n");
  snprintf(want, sizeof want, "%s:1: modulus_min_pa = '2.0e6' is not a number", path);
  CHECK_WORDS(af_settings_load_yaml(&s, path, err, sizeof err), AF_EINVAL, err, want, "8.0e+6");
  remove(path);
  CHECK_WORDS(load_text(&s, "modulus_min_pa: 1e+6\n", err), AF_EINVAL, err,
              "modulus_min_pa = '1e+6' is not a number");
  /* YAML as rosparam reads it (libyaml): an indented map, flow style, a
   * quoted key, an anchor and its alias, a value on the next line */
  af_settings y = s;
  AF_CHECK_STATUS(load_text(&y, "  lobe: 1\n", err), AF_OK);
  AF_CHECK(af_settings_number(&y, AF_SETTING_LOBE) == 1.0);
  AF_CHECK_STATUS(load_text(&y, "{lobe: 2, mass_max_kg: 0.3}\n", err), AF_OK);
  AF_CHECK(af_settings_number(&y, AF_SETTING_LOBE) == 2.0);
  AF_CHECK_STATUS(load_text(&y, "\"lobe\": 3\nmass_max_kg: &m 0.4\nmass_min_kg: *m\n", err), AF_OK);
  AF_CHECK(af_settings_number(&y, AF_SETTING_LOBE) == 3.0);
  AF_CHECK(af_settings_number(&y, AF_SETTING_MASS_MIN_KG) == 0.4);
  AF_CHECK_STATUS(load_text(&y, "lobe:\n  4\n", err), AF_OK);
  AF_CHECK(af_settings_number(&y, AF_SETTING_LOBE) == 4.0);
  /* `key: # comment` is null, as rosparam reads it, never the text '# comment' */
  CHECK_WORDS(load_text(&y, "cultivar: # Gala\n", err), AF_EINVAL, err,
              ":1: cultivar has no value");
  CHECK_WORDS(load_text(&s, "{lobe: 1,\n lobe: 2}\n", err), AF_EINVAL, err,
              ":2: duplicate key 'lobe': given on line 1 and again on line 2");
  CHECK_WORDS(load_text(&s, "lobe: 1\n---\nlobe: 2\n", err), AF_EINVAL, err,
              ":2: a second YAML document; a settings file holds one");
  CHECK_WORDS(load_text(&s, "lobe: *none\n", err), AF_EINVAL, err,
              ":1: lobe: an alias to 'none', which is not an anchored scalar");
  CHECK_WORDS(load_text(&s, "lobe\n", err), AF_EINVAL, err,
              ":1: not a flat `key: value` file: the document is a scalar");
  CHECK_WORDS(load_text(&s, "lobe:1\n", err), AF_EINVAL, err,
              ":1: not a flat `key: value` file: the document is a scalar");
  CHECK_WORDS(load_text(&s, "- lobe: 1\n", err), AF_EINVAL, err,
              ":1: not a flat `key: value` file: the document is a list");
  CHECK_WORDS(load_text(&s, "lobe:\n  a: 1\n", err), AF_EINVAL, err,
              ":2: lobe: not a flat value (a map)");
  CHECK_WORDS(load_text(&s, "lobe: |\n  1\n", err), AF_EINVAL, err,
              ":1: lobe: not a flat value (a block scalar)");
  CHECK_WORDS(load_text(&s, "lobe:\n", err), AF_EINVAL, err, ":1: lobe has no value");
  CHECK_WORDS(load_text(&s, "lobe: ~\n", err), AF_EINVAL, err, ":1: lobe has no value");
  CHECK_WORDS(load_text(&s, "lobe: [1, 2]\n", err), AF_EINVAL, err, ":1: lobe: not a flat value");
  CHECK_WORDS(load_text(&s, "lobe: !!int 1\n", err), AF_EINVAL, err, ":1: lobe: not a flat value");
  /* libyaml's own refusals: file:line:column and its words */
  CHECK_WORDS(load_text(&s, "cultivar: a: b\n", err), AF_EINVAL, err,
              ":1:12: mapping values are not allowed in this context");
  CHECK_WORDS(load_text(&s, "cultivar: 'Gala\n", err), AF_EINVAL, err,
              ":2:1: found unexpected end of stream while scanning a quoted scalar");
  CHECK_WORDS(load_text(&s, "cultivar: 'Gala' x\n", err), AF_EINVAL, err,
              ":1:18: did not find expected key while parsing a block mapping");
  CHECK_WORDS(load_text(&s, "cultivar: \"a\\qb\"\n", err), AF_EINVAL, err,
              ":1:13: found unknown escape character while parsing a quoted scalar");
  /* an escape libyaml reads into a NUL: refused, never a C string cut short */
  CHECK_WORDS(load_text(&s, "cultivar: \"a\\0b\"\n", err), AF_EINVAL, err,
              ":1: cultivar: a NUL character in a quoted value");
  CHECK_WORDS(load_text(&s, "lobe: .inf\n", err), AF_EINVAL, err,
              "lobe = inf is outside the accepted range [1, 8]");
  CHECK_WORDS(load_text(&s, "stream_stale_after_s: .inf\n", err), AF_EINVAL, err,
              "stream_stale_after_s = inf is outside the accepted range (0, 3600] s");
  CHECK_WORDS(load_text(&s, "markers_enabled: 1\n", err), AF_EINVAL, err,
              "markers_enabled = 1 is not true or false");
  char longline[1200];
  memset(longline, 'x', sizeof longline);
  memcpy(longline, "cultivar: ", 10);
  longline[1100] = '\n';
  longline[1101] = '\0';
  CHECK_WORDS(load_text(&s, longline, err), AF_EINVAL, err, ":1: a line longer than 1023");
  AF_CHECK(memcmp(&before, &s, sizeof s) == 0);
  CHECK_ERROR(af_settings_load_yaml(&s, "/no/such/dir/station.yaml", err, sizeof err), AF_EIO, err,
              "/no/such/dir/station.yaml: cannot be opened: No such file or directory");
  AF_CHECK(memcmp(&before, &s, sizeof s) == 0);
}

/* n bytes (NULs included) as a YAML file; the status, err filled. */
static af_status load_bytes(af_settings *s, const char *bytes, size_t n, char *err, char *path)
{
  write_file(path, "");
  FILE *f = fopen(path, "wb");
  AF_CHECK(f != NULL);
  if (f) {
    AF_CHECK(fwrite(bytes, 1, n, f) == n);
    fclose(f);
  }
  return af_settings_load_yaml(s, path, err, ERR_MAX);
}
#define LOAD_BYTES(s, lit, err, path) load_bytes(s, lit, sizeof lit - 1, err, path)

/* The reader works on bytes: a NUL anywhere, a lone CR, a line
 * over 1023 bytes, a file that is not regular or is over 1 MiB are refused
 * with file:line:column; CR LF and a UTF-8 BOM at the start are accepted. */
static void test_yaml_bytes(void)
{
  af_settings s;
  char err[ERR_MAX], path[64], want[ERR_MAX];
  af_settings_reset(&s);
  af_settings before = s;
  AF_CHECK_STATUS(LOAD_BYTES(&s, "mass_max_kg: 0.3\0junk\n", err, path), AF_EINVAL);
  snprintf(want, sizeof want, "%s:1:17: a NUL byte; a settings file is text", path);
  AF_CHECK(strcmp(err, want) == 0);
  remove(path);
  AF_CHECK_STATUS(LOAD_BYTES(&s, "lobe: 2\n\0bogus_key: 5\n", err, path), AF_EINVAL);
  snprintf(want, sizeof want, "%s:2:1: a NUL byte; a settings file is text", path);
  AF_CHECK(strcmp(err, want) == 0);
  remove(path);
  AF_CHECK_STATUS(LOAD_BYTES(&s, "lobe: 2\n# a\rlobe: 3\n", err, path), AF_EINVAL);
  snprintf(want, sizeof want,
           "%s:2:4: a carriage return not followed by a line feed; lines end with LF or CR LF",
           path);
  AF_CHECK(strcmp(err, want) == 0);
  remove(path);
  AF_CHECK_STATUS(LOAD_BYTES(&s, "lobe: 2\r", err, path), AF_EINVAL); /* a CR at the end too */
  remove(path);
  AF_CHECK(memcmp(&before, &s, sizeof s) == 0);
  /* CR LF, a BOM, both, and a last line without its end are accepted. */
  AF_CHECK_STATUS(LOAD_BYTES(&s, "lobe: 2\r\nmass_max_kg: 0.3 # max\r\n", err, path), AF_OK);
  remove(path);
  AF_CHECK(af_settings_number(&s, AF_SETTING_LOBE) == 2.0);
  AF_CHECK(af_settings_number(&s, AF_SETTING_MASS_MAX_KG) == 0.3);
  AF_CHECK_STATUS(LOAD_BYTES(&s, "\xef\xbb\xbf---\r\nlobe: 3\r\ncultivar: 'Gala'", err, path),
                  AF_OK);
  remove(path);
  AF_CHECK(af_settings_number(&s, AF_SETTING_LOBE) == 3.0);
  AF_CHECK(strcmp(af_settings_string(&s, AF_SETTING_CULTIVAR), "Gala") == 0);
  /* a BOM elsewhere is text: not a key */
  CHECK_WORDS(LOAD_BYTES(&s, "lobe: 2\n\xef\xbb\xbflobe: 3\n", err, path), AF_EINVAL, err,
              ":2:2: did not find expected key while parsing a block mapping");
  remove(path);
  /* A text row is one line: a line break folded into a quoted value, or a
   * tab from an escape, is refused by name and place, in one line (the
   * grade list's messages quote its class names). */
  CHECK_WORDS(LOAD_BYTES(&s, "grade_classes: \"soft | 1e5\n\n  | firm\"\n", err, path), AF_EINVAL,
              err,
              "grade_classes = 'soft | 1e5?| firm' holds a control character (0x0a at "
              "character 11)");
  remove(path);
  CHECK_WORDS(LOAD_BYTES(&s, "cultivar: \"Gala\\tRed\"\n", err, path), AF_EINVAL, err,
              "cultivar = 'Gala?Red' holds a control character (0x09 at character 5)");
  remove(path);
  CHECK_ERROR(af_settings_set_string(&s, AF_SETTING_FRAME_PREFIX, "lane\x7f", err, sizeof err),
              AF_EINVAL, err,
              "frame_prefix = 'lane?' holds a control character (0x7f at character 5)");
  AF_CHECK(strcmp(af_settings_string(&s, AF_SETTING_CULTIVAR), "Gala") == 0);
  /* 1023 bytes of a line are accepted, 1024 refused (with its CR LF or not) */
  static char line[1100];
  memset(line, 'x', sizeof line);
  line[0] = '#';
  line[1023] = '\r', line[1024] = '\n';
  AF_CHECK_STATUS(load_bytes(&s, line, 1025, err, path), AF_OK);
  remove(path);
  line[1023] = 'x', line[1024] = '\n';
  AF_CHECK_STATUS(load_bytes(&s, line, 1025, err, path), AF_EINVAL);
  snprintf(want, sizeof want, "%s:1: a line longer than 1023 bytes", path);
  AF_CHECK(strcmp(err, want) == 0);
  remove(path);
  /* the size cap, 1 MiB: at it accepted (comment lines), one byte over refused */
  static char big[1048577];
  for (size_t k = 0; k < sizeof big; k++)
    big[k] = k % 64 == 63 ? '\n' : '#';
  AF_CHECK_STATUS(load_bytes(&s, big, 1048576, err, path), AF_OK);
  remove(path);
  AF_CHECK_STATUS(load_bytes(&s, big, 1048577, err, path), AF_EINVAL);
  snprintf(want, sizeof want,
           "%s: 1048577 bytes is outside the accepted size of a settings file, [0, 1048576] bytes",
           path);
  AF_CHECK(strcmp(err, want) == 0);
  remove(path);
  /* not a regular file: a device, a directory, a FIFO (never waited on) */
  CHECK_ERROR(af_settings_load_yaml(&s, "/dev/zero", err, sizeof err), AF_EINVAL, err,
              "/dev/zero: is a character device; a settings file must be a regular file of at "
              "most 1048576 bytes");
  CHECK_WORDS(af_settings_load_yaml(&s, "/tmp", err, sizeof err), AF_EINVAL, err,
              "/tmp: is a directory");
  write_file(path, "");
  remove(path);
  AF_CHECK(mkfifo(path, 0600) == 0);
  CHECK_WORDS(af_settings_load_yaml(&s, path, err, sizeof err), AF_EINVAL, err, ": is a FIFO");
  remove(path);
}

/* ---- af_lane_config_derive: every cross-check --------------------------------- */

/* The shipped settings with one change, then derive: the status and err. */
static af_status derive_with(const char *const *args, char *err)
{
  af_settings s;
  af_lane_config c;
  af_status st = shipped(&s, err);
  for (; st == AF_OK && *args; args++)
    st = af_settings_set_arg(&s, *args, err, ERR_MAX);
  return st == AF_OK ? af_lane_config_derive(&s, &c, err, ERR_MAX) : AF_EIO;
}
#define DERIVE(err, ...) derive_with((const char *const[]){__VA_ARGS__, NULL}, err)

/* yield_measured: "" = the law; "E2:tau, ..." parsed into the model and
 * overriding the law at its points; a malformed row names itself. */
static void test_yield_measured(void)
{
  char err[ERR_MAX];
  af_settings s;
  af_lane_config c;
  AF_CHECK(shipped(&s, err) == AF_OK);
  AF_CHECK(strcmp(af_settings_string(&s, AF_SETTING_YIELD_MEASURED), "") == 0);
  AF_CHECK(af_lane_config_derive(&s, &c, err, sizeof err) == AF_OK);
  AF_CHECK(c.model.yield_measured.n == 0);
  AF_CHECK(af_settings_set_arg(&s, "yield_measured=2e6:0.12e6, 8e6:0.33e6, 12e6:0.44e6", err,
                               sizeof err) == AF_OK);
  AF_CHECK(af_lane_config_derive(&s, &c, err, sizeof err) == AF_OK);
  AF_CHECK(c.model.yield_measured.n == 3);
  AF_CHECK(c.model.yield_measured.modulus_pa[0] == 2e6 &&
           c.model.yield_measured.yield_shear_pa[2] == 0.44e6);
  af_yield_law law = af_model_yield_law(&c.model);
  AF_CHECK_ABS(af_yield_shear_pa(&law, 8e6), 0.33e6, 1e-6);  /* the point, not the law's 0.331 */
  AF_CHECK_ABS(af_yield_shear_pa(&law, 12e6), 0.44e6, 1e-6); /* the point, not the law's 0.440 */
  AF_CHECK_ABS(af_yield_shear_pa(&law, 2e6), 0.12e6, 1e-6);
  CHECK_WORDS(DERIVE(err, "yield_measured=8e6:0.33e6, 2e6:0.12e6"), AF_EINVAL, err,
              "yield_measured");
  CHECK_WORDS(DERIVE(err, "yield_measured=8e6"), AF_EINVAL, err, "yield_measured");
}

static void test_derive_errors(void)
{
  char err[ERR_MAX];
  CHECK_ERROR(DERIVE(err, "r2_search_low_m=0.6"), AF_EINVAL, err,
              "r2_search_low_m = 0.6 must be below r2_search_high_m = 0.5");
  CHECK_ERROR(DERIVE(err, "strike_radius_min_m=0.5"), AF_EINVAL, err,
              "strike_radius_min_m = 0.5 must be below strike_radius_max_m = 0.5");
  CHECK_ERROR(DERIVE(err, "mass_min_kg=0.3"), AF_EINVAL, err,
              "mass_min_kg = 0.3 must be below mass_max_kg = 0.25");
  CHECK_ERROR(DERIVE(err, "aspect_ratio_min=2"), AF_EINVAL, err,
              "aspect_ratio_min = 2 must be below aspect_ratio_max = 1.5");
  CHECK_ERROR(DERIVE(err, "equatorial_radius_max_m=0.02"), AF_EINVAL, err,
              "equatorial_radius_min_m = 0.025 must be below equatorial_radius_max_m = 0.02");
  CHECK_ERROR(DERIVE(err, "modulus_nominal_pa=15.0e+6"), AF_EINVAL, err,
              "modulus_nominal_pa = 1.5e+07 must lie in [modulus_min_pa, modulus_max_pa] = "
              "[2e+06, 1.2e+07] Pa");
  CHECK_ERROR(
      DERIVE(err, "modulus_min_pa=8.0e+6", "modulus_nominal_pa=8.0e+6", "modulus_max_pa=8.0e+6"),
      AF_EINVAL, err, "modulus_min_pa = 8e+06 must be below modulus_max_pa = 8e+06");
  /* A ring too large: 3600 s at 1 MHz. */
  CHECK_ERROR(DERIVE(err, "force_buffer_s=3600", "force_sample_rate_hz=1e6"), AF_EINVAL, err,
              "force_buffer_s = 3600 and force_sample_rate_hz = 1e+06 make a ring of 3600000000 "
              "samples, above the 100000000 accepted");
  CHECK_ERROR(DERIVE(err, "audio_buffer_s=3000", "audio_sample_rate_hz=1e5"), AF_EINVAL, err,
              "audio_buffer_s = 3000 and audio_sample_rate_hz = 100000 make a ring of 300000000 "
              "samples, above the 100000000 accepted");
  CHECK_ERROR(DERIVE(err, "strike_baseline_window_s=0.002"), AF_EINVAL, err,
              "strike_baseline_window_s = 0.002 must be below strike_pre_trigger_s = 0.002");
  CHECK_ERROR(DERIVE(err, "strike_baseline_window_s=0.0015", "strike_post_s=0.001",
                     "strike_double_hit_gap_s=0"),
              AF_EINVAL, err,
              "strike_baseline_window_s = 0.0015 must be below strike_post_s = 0.001");
  CHECK_ERROR(DERIVE(err, "strike_post_s=0.003"), AF_EINVAL, err,
              "strike_post_s = 0.003 must be at least strike_double_hit_gap_s = 0.005 (a bounce "
              "must be ruled out before the strike is emitted)");
  /* (1 + 2 x 1 + 1 + 1) s x 1 MHz + 4 = 5000004 samples: under 2^24 (which
   * no rate of the table's reaches any more), but 8 queued pulses of it and
   * the detector's copies are about 500 MiB: refused before allocating. */
  CHECK_WORDS(DERIVE(err, "force_buffer_s=1", "force_sample_rate_hz=1e6", "strike_pre_trigger_s=1",
                     "strike_max_contact_s=1", "strike_double_hit_gap_s=1", "strike_post_s=1"),
              AF_EINVAL, err, "the lane would allocate about ");
  AF_CHECK(strstr(err, "above the 256 MiB accepted") != NULL);
  /* Both rings at their most that the memory cap leaves: 2 x 27 s at 1 MHz. */
  AF_CHECK_STATUS(DERIVE(err, "force_buffer_s=27", "force_sample_rate_hz=1e6", "audio_buffer_s=27",
                         "audio_sample_rate_hz=1e6"),
                  AF_OK);
  CHECK_WORDS(DERIVE(err, "force_buffer_s=60", "force_sample_rate_hz=1e6", "audio_buffer_s=30",
                     "audio_sample_rate_hz=1e6"),
              AF_EINVAL, err, "the lane would allocate about ");
  /* 0.1 ms at 48 kHz = 4.8 -> 5 samples. */
  CHECK_ERROR(DERIVE(err, "measure_audio_window_s=0.0001"), AF_EINVAL, err,
              "measure_audio_window_s = 0.0001 gives 5 audio samples at 48000 Hz, fewer than the "
              "8 the analysis needs");
  CHECK_ERROR(DERIVE(err, "measure_noise_window_s=0.0001"), AF_EINVAL, err,
              "measure_noise_window_s = 0.0001 gives 5 audio samples at 48000 Hz: 0 (none) or at "
              "least 8");
  AF_CHECK_STATUS(DERIVE(err, "measure_noise_window_s=0"), AF_OK);
  /* 0.02 + 0.005 + 0.0005 + 0.04 = 0.0655 s of audio needed. */
  CHECK_ERROR(DERIVE(err, "audio_buffer_s=0.05"), AF_EINVAL, err,
              "measure_noise_window_s + measure_noise_guard_s + measure_audio_delay_s + "
              "measure_audio_window_s = 0.0655 s must be below audio_buffer_s = 0.05 s");
  /* The exact damping law needs e >= 0.05; the closed forms take (0, 1]. */
  CHECK_ERROR(DERIVE(err, "restitution=0.01"), AF_EINVAL, err,
              "restitution: impact.restitution = 0.01 is outside the accepted range [0.05, 1] with "
              "the exact damping law");
  AF_CHECK_STATUS(DERIVE(err, "restitution=0.01", "damping_law=hu-guo"), AF_OK);
  /* The hammer must be given (the node sets it from the URDF). */
  af_settings s;
  af_lane_config c;
  af_settings_reset(&s);
  CHECK_ERROR(af_lane_config_derive(&s, &c, err, sizeof err), AF_EINVAL, err,
              "hammer_mass_kg is not set (from the URDF unless given)");
  af_settings_set_name_prefix(&s, "~");
  AF_CHECK_STATUS(af_settings_set_arg(&s, "hammer_mass_kg=0.01", err, sizeof err), AF_OK);
  CHECK_ERROR(af_lane_config_derive(&s, &c, err, sizeof err), AF_EINVAL, err,
              "~hammer_tip_radius_m is not set (from the URDF unless given)");
  /* The defaults alone, with the hammer, derive (the table's cultivar is Jonagold). */
  AF_CHECK_STATUS(af_settings_set_arg(&s, "hammer_tip_radius_m=0.0", err, sizeof err), AF_OK);
  AF_CHECK_STATUS(af_lane_config_derive(&s, &c, err, sizeof err), AF_OK);
  /* A value written by hand past the table is caught. */
  s.value[AF_SETTING_LOBE] = 12;
  CHECK_ERROR(af_lane_config_derive(&s, &c, err, sizeof err), AF_EINVAL, err,
              "~lobe = 12 is outside the accepted range [1, 8]");
}

/* ---- the model's check takes the table's ranges ---------------------------------- */

static void expect_model_range(af_model_params p, const char *field, af_setting_id row)
{
  af_param_error e = {0};
  AF_CHECK_STATUS(af_model_params_check(&p, &e), AF_EINVAL);
  AF_CHECK(e.field != NULL && strcmp(e.field, field) == 0);
  AF_CHECK(e.range != NULL && strcmp(e.range, af_setting_def_of(row)->range) == 0);
}

static void test_model_ranges(void)
{
  af_model_params d = af_model_params_default(), p;
  AF_CHECK_STATUS(af_model_params_check(&d, NULL), AF_OK);
  p = d, p.impact.velocity_m_s = 10.0;
  AF_CHECK_STATUS(af_model_params_check(&p, NULL), AF_OK);
  p = d, p.impact.velocity_m_s = 10.5;
  expect_model_range(p, "impact.velocity_m_s", AF_SETTING_STRIKE_VELOCITY_M_S);
  p = d, p.impact.hammer_mass_kg = 1.5;
  expect_model_range(p, "impact.hammer_mass_kg", AF_SETTING_HAMMER_MASS_KG);
  p = d, p.impact.hammer_radius_m = 0.2;
  expect_model_range(p, "impact.hammer_radius_m", AF_SETTING_HAMMER_TIP_RADIUS_M);
  p = d, p.impact.gravity_m_s2 = 25.0;
  expect_model_range(p, "impact.gravity_m_s2", AF_SETTING_GRAVITY_M_S2);
  p = d, p.impact.strike_radius_m = 1.5;
  expect_model_range(p, "impact.strike_radius_m", AF_SETTING_STRIKE_RADIUS_MIN_M);
  p = d, p.fruit_mass_kg = 11.0;
  expect_model_range(p, "fruit_mass_kg", AF_SETTING_MASS_MIN_KG);
  p = d, p.yield_ratio = 1.5;
  expect_model_range(p, "yield_ratio", AF_SETTING_YIELD_RATIO);
  p = d, p.impact.restitution = 0.0, p.impact.damping = AF_DAMPING_PAPER;
  expect_model_range(p, "impact.restitution", AF_SETTING_RESTITUTION);
  p = d, p.impact.fruit_poisson = 0.5;
  expect_model_range(p, "impact.fruit_poisson", AF_SETTING_FRUIT_POISSON);
  p = d, p.lobe = 9;
  expect_model_range(p, "lobe", AF_SETTING_LOBE);
  p = d, p.modulus_factor = 0.0;
  expect_model_range(p, "modulus_factor", AF_SETTING_MODULUS_FACTOR);
  p = d, p.impact.hammer_modulus_pa = -1.0;
  expect_model_range(p, "impact.hammer_modulus_pa", AF_SETTING_HAMMER_MODULUS_PA);
  p = d, p.impact.hammer_poisson = 0.5;
  expect_model_range(p, "impact.hammer_poisson", AF_SETTING_HAMMER_POISSON);
  p = d, p.fruit_density_kg_m3 = 0.0;
  expect_model_range(p, "fruit_density_kg_m3", AF_SETTING_DENSITY_KG_M3);
  p = d, p.impact.fruit_modulus_pa = 0.0;
  expect_model_range(p, "impact.fruit_modulus_pa", AF_SETTING_MODULUS_NOMINAL_PA);
  af_param_error e = {0};
  p = d, p.impact.damping = (af_damping_law)7;
  AF_CHECK_STATUS(af_model_params_check(&p, &e), AF_EINVAL);
  AF_CHECK(strcmp(e.range, af_setting_def_of(AF_SETTING_DAMPING_LAW)->choices) == 0);
}

/* ---- the printed table ------------------------------------------------------------ */

static void test_print(void)
{
  char path[64];
  write_file(path, "");
  FILE *f = fopen(path, "w");
  AF_CHECK(f != NULL);
  if (f == NULL)
    return;
  af_settings_print(f, AF_SETTINGS_ALL, AF_SETTINGS_PRINT_MARKDOWN);
  af_settings_print(f, AF_SETTINGS_STATION, AF_SETTINGS_PRINT_TEXT);
  fclose(f);
  f = fopen(path, "r");
  char line[1024];
  int lines = 0, velocity = 0, mass = 0, choice = 0, header = 0;
  while (f && fgets(line, sizeof line, f)) {
    lines++;
    velocity += strcmp(line, "- **strike_velocity_m_s** (double, 1.4, [0.05, 10], m/s): contact "
                             "velocity (the paper's optimum).\n") == 0;
    mass +=
        strcmp(line, "- **hammer_mass_kg** (double, absent, [0.0005, 1], kg): overrides the URDF's "
                     "hammer mass; 0 or absent = from the URDF.\n") == 0;
    choice += strcmp(line, "- **damping_law** (string, `exact`, paper | exact | hu-guo): damping "
                           "law chi(e) (PHYSICS.md 2).\n") == 0;
    header += strncmp(line, "name ", 5) == 0;
  }
  if (f)
    fclose(f);
  remove(path);
  int station = 0;
  for (int k = 0; k < AF_SETTING_COUNT; k++)
    station += af_setting_def_of((af_setting_id)k)->file == AF_SETTINGS_STATION;
  AF_CHECK(lines == AF_SETTING_COUNT + 1 + station);
  AF_CHECK(velocity == 1 && mass == 1 && choice == 1 && header == 1);
}

/* Heap in use (small chunks and mmapped ones) [bytes]. */
static double heap_bytes(void)
{
  struct mallinfo2 mi = mallinfo2();
  return (double)mi.uordblks + (double)mi.hblkhd;
}

/* af_lane_config_memory bounds what af_lane_create takes, and not loosely:
 * the defaults and the largest parts the memory cap leaves. (Skipped under
 * ASan, whose allocator mallinfo2 does not see.) */
static void test_memory_estimate(void)
{
#if defined(__SANITIZE_ADDRESS__)
  return;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
  return;
#endif
#endif
  static const char *const cases[][7] = {
      {NULL},
      {"force_buffer_s=27", "force_sample_rate_hz=1e6", "audio_buffer_s=27",
       "audio_sample_rate_hz=1e6", NULL},
      {"audio_sample_rate_hz=1e6", "audio_buffer_s=2", "measure_audio_window_s=0.2",
       "measure_noise_window_s=0.2", NULL},
      {"force_sample_rate_hz=1e6", "strike_max_contact_s=0.1", "strike_pre_trigger_s=0.2",
       "strike_post_s=0.2", "strike_pending_size=4", NULL},
  };
  for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
    char err[ERR_MAX];
    af_settings s;
    af_lane_config c;
    af_status st = shipped(&s, err);
    for (const char *const *a = cases[k]; st == AF_OK && *a; a++)
      st = af_settings_set_arg(&s, *a, err, ERR_MAX);
    if (st == AF_OK)
      st = af_lane_config_derive(&s, &c, err, ERR_MAX);
    AF_CHECK_STATUS(st, AF_OK);
    if (st != AF_OK) {
      fprintf(stderr, "  case %zu: %s\n", k, err);
      continue;
    }
    af_lane_memory m;
    af_lane_config_memory(&c, &m);
    double before = heap_bytes();
    af_lane *lane = NULL;
    const char *what = "";
    AF_CHECK_STATUS(af_lane_create(&c, NULL, NULL, &lane, &what), AF_OK);
    double taken = heap_bytes() - before;
    af_lane_destroy(lane);
    AF_CHECK(taken > 0.0 && taken <= m.total);
    AF_CHECK(m.total <= 3.0 * taken + 2.0 * 1048576.0);
    AF_CHECK(m.total <= (double)AF_LANE_MEMORY_MAX_BYTES);
    printf("lane memory, case %zu: %.1f MiB taken, %.1f MiB estimated\n", k, taken / 1048576.0,
           m.total / 1048576.0);
  }
}

/* The shipped rig's hammer, said once in the table (the URDF test checks
 * config/rig.urdf against it): the two hammer rows carry it, no other row
 * does; tools that read no URDF fill only what is still absent; the impact
 * model's default strike uses it. */
static void test_rig_hammer(void)
{
  char err[ERR_MAX];
  for (int k = 0; k < AF_SETTING_COUNT; k++) {
    af_setting_id id = (af_setting_id)k;
    double v = af_setting_rig_value(id);
    bool hammer = id == AF_SETTING_HAMMER_MASS_KG || id == AF_SETTING_HAMMER_TIP_RADIUS_M;
    AF_CHECK(hammer ? !isnan(v) : isnan(v));
    af_setting_range r;
    if (hammer && af_setting_range_of(id, &r) == AF_OK)
      AF_CHECK(af_setting_range_contains(&r, v));
  }
  AF_CHECK_ABS(af_setting_rig_value(AF_SETTING_HAMMER_MASS_KG), 0.010, 0.0);    /* 10 g head */
  AF_CHECK_ABS(af_setting_rig_value(AF_SETTING_HAMMER_TIP_RADIUS_M), 0.0, 0.0); /* flat */
  AF_CHECK(isnan(af_setting_rig_value((af_setting_id)AF_SETTING_COUNT)));
  af_settings s;
  af_settings_reset(&s);
  AF_CHECK_STATUS(af_settings_set_arg(&s, "hammer_mass_kg=0.02", err, sizeof err), AF_OK);
  AF_CHECK_STATUS(af_settings_use_rig_hammer(&s, err, sizeof err), AF_OK);
  AF_CHECK_ABS(af_settings_number(&s, AF_SETTING_HAMMER_MASS_KG), 0.02, 0.0); /* kept */
  AF_CHECK(af_settings_present(&s, AF_SETTING_HAMMER_TIP_RADIUS_M));
  AF_CHECK_ABS(af_settings_number(&s, AF_SETTING_HAMMER_TIP_RADIUS_M), 0.0, 0.0);
  af_settings_reset(&s);
  AF_CHECK_STATUS(af_settings_use_rig_hammer(&s, err, sizeof err), AF_OK);
  AF_CHECK_ABS(af_settings_number(&s, AF_SETTING_HAMMER_MASS_KG), 0.010, 0.0);
  af_lane_config c;
  AF_CHECK_STATUS(af_lane_config_derive(&s, &c, err, sizeof err), AF_OK);
  af_impact_params d = af_impact_params_default();
  AF_CHECK_ABS(d.hammer_mass_kg, af_setting_rig_value(AF_SETTING_HAMMER_MASS_KG), 0.0);
  AF_CHECK_ABS(d.hammer_radius_m, af_setting_rig_value(AF_SETTING_HAMMER_TIP_RADIUS_M), 0.0);
}

int main(void)
{
  test_table();
  test_rig_hammer();
  test_shipped_files();
  test_derive_shipped();
  test_value_errors();
  test_args();
  test_yaml();
  test_yaml_bytes();
  test_derive_errors();
  test_yield_measured();
  test_model_ranges();
  test_print();
  test_memory_estimate();
  return af_test_summary("test_settings");
}
