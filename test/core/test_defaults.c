/* test_defaults.c — the generated C defaults (af_defaults.h) and the
 * measurement's analysis rows:
 *  - every AF_DEFAULT_<ROW> macro equals strtod of its row's default text,
 *    is named after its row, and is there for every number and whole row
 *    (counted from the table); whole rows give integer constants, number
 *    rows double constants; AF_RIG_<ROW> equals the row's rig value;
 *  - the core's *_default() functions hold the table's defaults wherever a
 *    row exists;
 *  - measure_hum_hz, measure_hum_harmonics, measure_noise_band_low_hz /
 *    _high_hz and measure_fft_padding are read from a YAML file, refused out
 *    of range in one line naming key, value and range, and reach the
 *    response configuration through af_lane_config_derive; the FFT size is
 *    checked against the smallest power of two computed here.
 * Run from the repository root (config/station.yaml, config/jonagold.yaml). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "af_defaults.h"
#include "af_test.h"
#include "impact.h"
#include "lane_config.h"
#include "measure.h"
#include "model.h"
#include "response.h"
#include "settings.h"
#include "strike.h"

#define STATION "config/station.yaml"
#define CULTIVAR "config/jonagold.yaml"
#define ERR_MAX 512

/* The row's default text read as a C number. */
static double table_default(af_setting_id id)
{
  const af_setting_def *d = af_setting_def_of(id);
  char *end;
  double v = strtod(d->def, &end);
  AF_CHECK(end != d->def && *end == '\0');
  return v;
}

/* ---- af_defaults.h against the table --------------------------------------- */

/* 1 for an integer constant, 0 for a double one, -1 otherwise. */
#define KIND_OF(x) _Generic((x), int : 1, long : 1, double : 0, default : -1)

static int listed; /* the macros of AF_DEFAULTS_LIST */

static void check_macro(af_setting_id id, const char *macro, double value, int kind)
{
  const af_setting_def *d = af_setting_def_of(id);
  listed++;
  /* named after its row: AF_DEFAULT_ + the name in capitals */
  char want[96] = "AF_DEFAULT_";
  for (size_t k = 0, n = strlen(want); d->name[k] && n + 1 < sizeof want; k++, n++) {
    want[n] = (char)(d->name[k] >= 'a' && d->name[k] <= 'z' ? d->name[k] - 'a' + 'A' : d->name[k]);
    want[n + 1] = '\0';
  }
  if (strcmp(macro, want) != 0) {
    af_test_failed++;
    fprintf(stderr, "FAIL %s is the macro of row %s (want %s)\n", macro, d->name, want);
  }
  if (value != table_default(id)) {
    af_test_failed++;
    fprintf(stderr, "FAIL %s = %.17g, the table's default of %s is '%s'\n", macro, value, d->name,
            d->def);
  } else {
    af_test_passed++;
  }
  AF_CHECK(kind == (d->kind == AF_SETTING_WHOLE ? 1 : 0));
}

static void test_macros(void)
{
#define CHECK_ONE(id, macro) check_macro(id, #macro, (double)(macro), KIND_OF(macro));
  AF_DEFAULTS_LIST(CHECK_ONE)
#undef CHECK_ONE
  /* one macro for each number and whole row with a default, counted here */
  int rows = 0;
  for (int k = 0; k < AF_SETTING_COUNT; k++) {
    const af_setting_def *d = af_setting_def_of((af_setting_id)k);
    rows += (d->kind == AF_SETTING_NUMBER || d->kind == AF_SETTING_WHOLE) && d->def != NULL;
  }
  AF_CHECK(listed == rows);
  AF_CHECK(rows > 60);
  /* a few by name, against the text of the issue */
  AF_CHECK(AF_DEFAULT_MEASURE_HUM_HZ == table_default(AF_SETTING_MEASURE_HUM_HZ));
  AF_CHECK(AF_DEFAULT_MEASURE_FFT_PADDING == 4);
  AF_CHECK(AF_DEFAULT_MEASURE_HUM_HARMONICS == 3);
  AF_CHECK(AF_DEFAULT_MEASURE_NOISE_BAND_LOW_HZ == 4000.0);
  AF_CHECK(AF_DEFAULT_MEASURE_NOISE_BAND_HIGH_HZ == 16000.0);
  /* the shipped rig's hammer */
  AF_CHECK(AF_RIG_HAMMER_MASS_KG == af_setting_rig_value(AF_SETTING_HAMMER_MASS_KG));
  AF_CHECK(AF_RIG_HAMMER_TIP_RADIUS_M == af_setting_rig_value(AF_SETTING_HAMMER_TIP_RADIUS_M));
  AF_CHECK(KIND_OF(AF_RIG_HAMMER_MASS_KG) == 0 && KIND_OF(AF_RIG_HAMMER_TIP_RADIUS_M) == 0);
}

/* ---- the core's *_default() against the table ----------------------------- */

#define SAME(field, id)                                                                            \
  do {                                                                                             \
    if ((double)(field) == table_default(id)) {                                                    \
      af_test_passed++;                                                                            \
    } else {                                                                                       \
      af_test_failed++;                                                                            \
      fprintf(stderr, "%s:%d: FAIL %s = %.17g, the table's %s is '%s'\n", __FILE__, __LINE__,      \
              #field, (double)(field), af_setting_def_of(id)->name, af_setting_def_of(id)->def);   \
    }                                                                                              \
  } while (0)

static void test_core_defaults(void)
{
  af_impact_params i = af_impact_params_default();
  SAME(i.velocity_m_s, AF_SETTING_STRIKE_VELOCITY_M_S);
  SAME(i.gravity_m_s2, AF_SETTING_GRAVITY_M_S2);
  SAME(i.hammer_modulus_pa, AF_SETTING_HAMMER_MODULUS_PA);
  SAME(i.hammer_poisson, AF_SETTING_HAMMER_POISSON);
  SAME(i.fruit_modulus_pa, AF_SETTING_MODULUS_NOMINAL_PA);
  SAME(i.fruit_poisson, AF_SETTING_FRUIT_POISSON);
  SAME(i.restitution, AF_SETTING_RESTITUTION);
  AF_CHECK(i.hammer_mass_kg == af_setting_rig_value(AF_SETTING_HAMMER_MASS_KG));
  AF_CHECK(i.hammer_radius_m == af_setting_rig_value(AF_SETTING_HAMMER_TIP_RADIUS_M));

  af_model_params m = af_model_params_default();
  SAME(m.fruit_density_kg_m3, AF_SETTING_DENSITY_KG_M3);
  SAME(m.modulus_factor, AF_SETTING_MODULUS_FACTOR);
  SAME(m.lobe, AF_SETTING_LOBE);
  SAME(m.yield_ratio, AF_SETTING_YIELD_RATIO);
  SAME(m.yield_exponent, AF_SETTING_YIELD_EXPONENT);
  SAME(m.yield_reference_modulus_pa, AF_SETTING_YIELD_REFERENCE_MODULUS_PA);

  af_measure_config c = af_measure_config_default();
  SAME(c.audio_delay_s, AF_SETTING_MEASURE_AUDIO_DELAY_S);
  SAME(c.audio_window_s, AF_SETTING_MEASURE_AUDIO_WINDOW_S);
  SAME(c.noise_window_s, AF_SETTING_MEASURE_NOISE_WINDOW_S);
  SAME(c.noise_guard_s, AF_SETTING_MEASURE_NOISE_GUARD_S);
  SAME(c.range_margin, AF_SETTING_MEASURE_RANGE_MARGIN);
  AF_CHECK(!c.fit.fit_velocity); /* measure_fit_velocity: false */
  AF_CHECK(strcmp(af_setting_def_of(AF_SETTING_MEASURE_FIT_VELOCITY)->def, "false") == 0);

  af_response_config r = af_response_config_default();
  SAME(r.sample_rate_hz, AF_SETTING_AUDIO_SAMPLE_RATE_HZ);
  SAME(r.hum_hz, AF_SETTING_MEASURE_HUM_HZ);
  SAME(r.hum_harmonics, AF_SETTING_MEASURE_HUM_HARMONICS);
  SAME(r.snr_threshold_db, AF_SETTING_MEASURE_SNR_THRESHOLD_DB);
  SAME(r.noise_band_lo_hz, AF_SETTING_MEASURE_NOISE_BAND_LOW_HZ);
  SAME(r.noise_band_hi_hz, AF_SETTING_MEASURE_NOISE_BAND_HIGH_HZ);

  af_strike_config d = af_strike_config_default();
  SAME(d.sample_rate_hz, AF_SETTING_FORCE_SAMPLE_RATE_HZ);
  SAME(d.full_scale_n, AF_SETTING_STRIKE_FULL_SCALE_N);
  SAME(d.threshold_noise_factor, AF_SETTING_STRIKE_THRESHOLD_NOISE_FACTOR);
  SAME(d.threshold_min_n, AF_SETTING_STRIKE_THRESHOLD_MIN_N);
  SAME(d.pre_trigger_s, AF_SETTING_STRIKE_PRE_TRIGGER_S);
  SAME(d.baseline_time_constant_s, AF_SETTING_STRIKE_BASELINE_TIME_CONSTANT_S);
  SAME(d.baseline_window_s, AF_SETTING_STRIKE_BASELINE_WINDOW_S);
  SAME(d.double_hit_gap_s, AF_SETTING_STRIKE_DOUBLE_HIT_GAP_S);
  SAME(d.max_contact_s, AF_SETTING_STRIKE_MAX_CONTACT_S);
  SAME(d.post_s, AF_SETTING_STRIKE_POST_S);
  SAME(d.rise_fit_level, AF_SETTING_STRIKE_RISE_FIT_LEVEL);
  SAME(d.fall_fit_level, AF_SETTING_STRIKE_FALL_FIT_LEVEL);
}

/* ---- the new rows through YAML and af_lane_config_derive ------------------ */

/* The shipped files, then text as a third YAML file; derive into *c. The
 * status of the first step that failed, its line in err. */
static af_status derive_yaml(const char *text, af_lane_config *c, char *err)
{
  static int n;
  char path[64];
  snprintf(path, sizeof path, "/tmp/test_defaults_%ld_%d.yaml", (long)getpid(), n++);
  FILE *f = fopen(path, "w");
  if (f == NULL)
    return AF_EIO;
  fputs(text, f);
  fclose(f);
  af_settings s;
  af_settings_reset(&s);
  af_status st = af_settings_load_yaml(&s, STATION, err, ERR_MAX);
  if (st == AF_OK)
    st = af_settings_load_yaml(&s, CULTIVAR, err, ERR_MAX);
  /* a site's own file over the shipped ones (a key may be given again in
   * another file) */
  if (st == AF_OK)
    st = af_settings_load_yaml(&s, path, err, ERR_MAX);
  if (st == AF_OK)
    st = af_settings_use_rig_hammer(&s, err, ERR_MAX);
  if (st == AF_OK)
    st = af_lane_config_derive(&s, c, err, ERR_MAX);
  remove(path);
  return st;
}

/* The status is st and err holds want, on one line. */
static void check_line(af_status got, af_status st, const char *err, const char *want)
{
  AF_CHECK_STATUS(got, st);
  if (strstr(err, want) != NULL && strchr(err, '\n') == NULL) {
    af_test_passed++;
  } else {
    af_test_failed++;
    fprintf(stderr, "FAIL message\n  got:  %s\n  want: ...%s...\n", err, want);
  }
}

/* Smallest power of two at least n (n >= 1). */
static size_t pow2_at_least(size_t n)
{
  size_t p = 1;
  while (p < n)
    p *= 2;
  return p;
}

static void test_rows_through_derive(void)
{
  char err[ERR_MAX] = "";
  af_lane_config c;
  /* the shipped values */
  AF_CHECK_STATUS(derive_yaml("# nothing\n", &c, err), AF_OK);
  if (err[0])
    fprintf(stderr, "%s\n", err);
  const af_response_config *r = &c.strikes.measure.response;
  AF_CHECK(r->hum_hz == 50.0 && r->hum_harmonics == 3);
  AF_CHECK(r->noise_band_lo_hz == 4000.0 && r->noise_band_hi_hz == 16000.0);
  /* 0.04 s at 48 kHz = 1920 samples, the longer window; 4 x 1920 = 7680 -> 8192 */
  AF_CHECK(r->window_samples == 1920);
  AF_CHECK(r->fft_size == pow2_at_least(4 * 1920) && r->fft_size == 8192);
  const size_t fft4 = r->fft_size;

  /* a 60 Hz site, 5 harmonics, another band, padding 8 */
  AF_CHECK_STATUS(derive_yaml("measure_hum_hz: 60.0\n"
                              "measure_hum_harmonics: 5\n"
                              "measure_noise_band_low_hz: 5000.0\n"
                              "measure_noise_band_high_hz: 12000.0  # below Nyquist\n"
                              "measure_fft_padding: 8\n",
                              &c, err),
                  AF_OK);
  if (err[0])
    fprintf(stderr, "%s\n", err);
  AF_CHECK(r->hum_hz == 60.0 && r->hum_harmonics == 5);
  AF_CHECK(r->noise_band_lo_hz == 5000.0 && r->noise_band_hi_hz == 12000.0);
  AF_CHECK(r->fft_size == 2 * fft4 && r->fft_size == pow2_at_least(8 * 1920));
  /* the microphone's memory estimate follows the FFT size */
  af_lane_memory mem;
  af_lane_config_memory(&c, &mem);
  AF_CHECK(mem.microphone >= 128.0 * 16384.0);

  /* hum off; padding 1: the FFT just holds the window */
  AF_CHECK_STATUS(derive_yaml("measure_hum_hz: 0.0\nmeasure_fft_padding: 1\n", &c, err), AF_OK);
  AF_CHECK(r->hum_hz == 0.0 && r->fft_size == 2048);
  /* a band above the default's Nyquist at 96 kHz audio */
  AF_CHECK_STATUS(derive_yaml("audio_sample_rate_hz: 96000.0\n"
                              "measure_noise_band_low_hz: 30000.0\n"
                              "measure_noise_band_high_hz: 45000.0\n",
                              &c, err),
                  AF_OK);
  AF_CHECK(r->noise_band_lo_hz == 30000.0 && r->sample_rate_hz == 96000.0);

  /* out of range: one line naming key, value and range (with the file's line) */
  check_line(derive_yaml("measure_hum_hz: 5.0\n", &c, err), AF_EINVAL, err,
             ":1: measure_hum_hz = 5 is outside the accepted range 0 or [10, 1000] Hz");
  check_line(derive_yaml("# a 60 Hz site\nmeasure_hum_hz: 1200.0\n", &c, err), AF_EINVAL, err,
             ":2: measure_hum_hz = 1200 is outside the accepted range 0 or [10, 1000] Hz");
  check_line(derive_yaml("measure_hum_harmonics: 9\n", &c, err), AF_EINVAL, err,
             ":1: measure_hum_harmonics = 9 is outside the accepted range [0, 8]");
  check_line(derive_yaml("measure_hum_harmonics: 2.5\n", &c, err), AF_EINVAL, err,
             ":1: measure_hum_harmonics = 2.5 is not a whole number in [0, 8]");
  check_line(derive_yaml("measure_fft_padding: 0\n", &c, err), AF_EINVAL, err,
             ":1: measure_fft_padding = 0 is outside the accepted range [1, 16]");
  check_line(derive_yaml("measure_fft_padding: 17\n", &c, err), AF_EINVAL, err,
             ":1: measure_fft_padding = 17 is outside the accepted range [1, 16]");
  check_line(derive_yaml("measure_noise_band_low_hz: -1.0\n", &c, err), AF_EINVAL, err,
             ":1: measure_noise_band_low_hz = -1 is outside the accepted range [0, 5e5] Hz");
  check_line(derive_yaml("measure_noise_band_high_hz: 6.0e+5\n", &c, err), AF_EINVAL, err,
             ":1: measure_noise_band_high_hz = 600000 is outside the accepted range [0, 5e5] Hz");
  check_line(derive_yaml("measure_fft_padding: four\n", &c, err), AF_EINVAL, err,
             ":1: measure_fft_padding = 'four' is not a number");
  /* across rows, in af_lane_config_derive */
  check_line(derive_yaml("measure_noise_band_low_hz: 8000.0\n"
                         "measure_noise_band_high_hz: 6000.0\n",
                         &c, err),
             AF_EINVAL, err,
             "measure_noise_band_low_hz = 8000 must be below measure_noise_band_high_hz = 6000");
  check_line(derive_yaml("measure_noise_band_low_hz: 24000.0\n"
                         "measure_noise_band_high_hz: 30000.0\n",
                         &c, err),
             AF_EINVAL, err,
             "measure_noise_band_low_hz = 24000 must be below the audio Nyquist frequency 24000 Hz "
             "(audio_sample_rate_hz = 48000)");
  check_line(derive_yaml("audio_sample_rate_hz: 1000.0\n"
                         "measure_hum_hz: 600.0\n"
                         "measure_noise_band_low_hz: 100.0\n"
                         "measure_noise_band_high_hz: 400.0\n",
                         &c, err),
             AF_EINVAL, err,
             "measure_hum_hz = 600 must be below the audio Nyquist frequency 500 Hz "
             "(audio_sample_rate_hz = 1000) (0 = off)");
  /* 16 x a 0.9 s window at 1 MHz: 2^24 points, above the lane's memory bound (about 2 GiB at
   * 128 bytes a point), which names the padding */
  check_line(derive_yaml("audio_sample_rate_hz: 1.0e+6\n"
                         "audio_buffer_s: 3.0\n"
                         "measure_audio_window_s: 0.9\n"
                         "measure_fft_padding: 16\n",
                         &c, err),
             AF_EINVAL, err, "measure_audio_window_s x measure_fft_padding; pulse fit");
  AF_CHECK_STATUS(derive_yaml("audio_sample_rate_hz: 1.0e+6\n"
                              "audio_buffer_s: 3.0\n"
                              "measure_audio_window_s: 0.9\n"
                              "measure_fft_padding: 1\n",
                              &c, err),
                  AF_OK);
  AF_CHECK(r->fft_size == ((size_t)1 << 20)); /* 900000 samples -> 2^20 */
}

int main(void)
{
  test_macros();
  test_core_defaults();
  test_rows_through_derive();
  return af_test_summary("test_defaults");
}
