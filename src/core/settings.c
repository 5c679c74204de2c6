/* settings.c — the one parameter table, the values object, the flat YAML
 * reader and af_lane_config_derive. */
#include "settings.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "lane_config.h"
#include "resonance.h"

#ifndef M_PI /* strict C11 <math.h> does not define it */
#define M_PI 3.14159265358979323846
#endif

/* ---- the table ------------------------------------------------------------ */

#define S AF_SETTINGS_STATION
#define C AF_SETTINGS_CULTIVAR
#define NUM(name, def, range, file, help)                                                          \
  {                                                                                                \
    name, AF_SETTING_NUMBER, def, range, NULL, file, false, false, NULL, 0, help, NULL             \
  }
#define WHOLE(name, def, range, file, help)                                                        \
  {                                                                                                \
    name, AF_SETTING_WHOLE, def, range, NULL, file, false, false, NULL, 0, help, NULL              \
  }
#define OPTIONAL_NUM(name, range, zero_is_absent, absent, rig, help)                               \
  {                                                                                                \
    name, AF_SETTING_NUMBER, NULL, range, NULL, S, true, zero_is_absent, absent, 0, help, rig      \
  }
#define BOOLEAN(name, def, file, help)                                                             \
  {                                                                                                \
    name, AF_SETTING_BOOL, def, NULL, NULL, file, false, false, NULL, 0, help, NULL                \
  }
#define STRING(name, def, max_chars, file, help)                                                   \
  {                                                                                                \
    name, AF_SETTING_STRING, def, NULL, NULL, file, false, false, NULL, max_chars, help, NULL      \
  }
#define CHOICE(name, def, choices, file, help)                                                     \
  {                                                                                                \
    name, AF_SETTING_CHOICE, def, NULL, choices, file, false, false, NULL, 0, help, NULL           \
  }

/* Every range and default of the lane. The ranges are sanity bounds of a
 * real rig and fruit (a value outside is a typo); af_model_params_check
 * applies the same rows to the model's fields. */
static const af_setting_def rows[AF_SETTING_COUNT] = {
    [AF_SETTING_HAMMER_LINK] = STRING("hammer_link", "hammer", AF_LANE_NAME_MAX - 1, S,
                                      "URDF link of the hammer head (mass, tip geometry; its "
                                      "parent joint's axis = strike direction)"),
    [AF_SETTING_URDF_FILE] = STRING("urdf_file", "\"\"", AF_SETTINGS_TEXT_MAX - 1, S,
                                    "path of the rig's URDF; empty = the robot_description "
                                    "parameter of the node's namespace"),
    [AF_SETTING_HAMMER_MASS_KG] = OPTIONAL_NUM("hammer_mass_kg", "[0.0005, 1] kg", true,
                                               "from the URDF", "0.010", /* the rig's 10 g head */
                                               "overrides the URDF's hammer mass"),
    [AF_SETTING_HAMMER_TIP_RADIUS_M] =
        OPTIONAL_NUM("hammer_tip_radius_m", "0 or [0.0005, 0.1] m", false, "from the URDF",
                     "0.0", /* the rig's flat face */
                     "overrides the URDF's tip radius; 0 = flat face"),
    [AF_SETTING_HAMMER_MODULUS_PA] =
        NUM("hammer_modulus_pa", "0.0", "0 or [1e5, 1e12] Pa", S, "hammer tip modulus; 0 = rigid"),
    [AF_SETTING_HAMMER_POISSON] = NUM("hammer_poisson", "0.3", "[0, 0.5)", S,
                                      "hammer tip Poisson ratio (unused while rigid)"),
    [AF_SETTING_STRIKE_VELOCITY_M_S] = NUM("strike_velocity_m_s", "1.4", "[0.05, 10] m/s", S,
                                           "contact velocity (the paper's optimum)"),
    [AF_SETTING_GRAVITY_M_S2] =
        NUM("gravity_m_s2", "9.80665", "[0, 20] m/s2", S, "gravity along the strike; 0 = off"),
    [AF_SETTING_DAMPING_LAW] = CHOICE("damping_law", "exact", "paper, exact, hu-guo", S,
                                      "damping law chi(e) (PHYSICS.md 2)"),
    [AF_SETTING_LOBE] =
        WHOLE("lobe", "1", "[1, 8]", S, "spectral lobe of the criterion (1 = main lobe)"),
    [AF_SETTING_BAND_LEVEL] = CHOICE("band_level", "amplitude-half", "power-half, amplitude-half",
                                     S, "half-power reading of the bands (PHYSICS.md 4)"),
    [AF_SETTING_SHEAR_RATIO] = CHOICE("shear_ratio", "exact", "paper, exact", S,
                                      "tau_max / p0: paper (0.31) or exact (Hertz, for the "
                                      "fruit's Poisson ratio)"),
    [AF_SETTING_LATITUDE_TOLERANCE_DEG] = NUM("latitude_tolerance_deg", "15.0", "[0, 90] deg", S,
                                              "strike latitudes beyond this are advised to "
                                              "rotate"),
    [AF_SETTING_R2_SEARCH_LOW_M] = NUM("r2_search_low_m", "0.002", "[0.0005, 1] m", S,
                                       "low end of the minimum reliable strike radius search"),
    [AF_SETTING_R2_SEARCH_HIGH_M] = NUM("r2_search_high_m", "0.5", "[0.0005, 1] m", S,
                                        "high end of that search, above r2_search_low_m"),
    [AF_SETTING_STRIKE_RADIUS_MIN_M] = NUM("strike_radius_min_m", "0.002", "[0.0005, 1] m", S,
                                           "smallest accepted AppleEstimate.strike_radius "
                                           "(when not 0)"),
    [AF_SETTING_STRIKE_RADIUS_MAX_M] = NUM("strike_radius_max_m", "0.5", "[0.0005, 1] m", S,
                                           "largest accepted AppleEstimate.strike_radius, "
                                           "above strike_radius_min_m"),
    [AF_SETTING_FORCE_SAMPLE_RATE_HZ] = NUM("force_sample_rate_hz", "50000.0", "[1000, 1e6] Hz", S,
                                            "force rate; chunks at another rate are refused "
                                            "and counted"),
    [AF_SETTING_FORCE_BUFFER_S] = NUM("force_buffer_s", "2.0", "(0, 3600] s", S,
                                      "force kept in the ring (at most 1e8 samples)"),
    [AF_SETTING_AUDIO_SAMPLE_RATE_HZ] = NUM("audio_sample_rate_hz", "48000.0", "[1000, 1e6] Hz", S,
                                            "audio rate; chunks at another rate are refused "
                                            "and counted"),
    [AF_SETTING_AUDIO_BUFFER_S] = NUM("audio_buffer_s", "2.0", "(0, 3600] s", S,
                                      "audio kept in the ring (at most 1e8 samples)"),
    [AF_SETTING_AUDIO_UNIT] = CHOICE("audio_unit", "Pa", "Pa, V", S,
                                     "the microphone's unit (the force transducer's is N)"),
    [AF_SETTING_AUDIO_INPUT] =
        CHOICE("audio_input", "signal_chunk", "signal_chunk, audio_common", S,
               "what the audio topic carries: acoustic_firmness/SignalChunk, "
               "or audio_common_msgs/AudioData(Stamped) with audio_info"),
    [AF_SETTING_AUDIO_CHANNEL] =
        WHOLE("audio_channel", "0", "[0, 255]", S,
              "the channel taken from audio_common frames (0 = the first)"),
    [AF_SETTING_AUDIO_FULL_SCALE] =
        NUM("audio_full_scale", "1.0", "[1e-6, 1e6]", S,
            "audio_common: the microphone's value at digital full scale, in audio_unit"),
    [AF_SETTING_STREAM_STALE_AFTER_S] = NUM("stream_stale_after_s", "1.0", "(0, 3600] s", S,
                                            "a stream silent this long is reported stale"),
    [AF_SETTING_STREAM_ABSENT_WARN_S] =
        NUM("stream_absent_warn_s", "5.0", "0 or [0.1, 3600] s", S,
            "/diagnostics warns when a stream has sent no chunk this long after the start "
            "(0 = never)"),
    [AF_SETTING_FORCE_UNIT] = CHOICE("force_unit", "N", "N, V", S,
                                     "the force transducer's unit: N, or V from a DAQ (divided by "
                                     "force_sensitivity_v_per_n at the lane's input)"),
    [AF_SETTING_FORCE_SENSITIVITY_V_PER_N] =
        NUM("force_sensitivity_v_per_n", "0.0", "0 or [1e-4, 10] V/N", S,
            "the transducer's sensitivity with its conditioning; required with force_unit V, "
            "0 = none (force_unit N)"),
    [AF_SETTING_MARKERS_ENABLED] =
        BOOLEAN("markers_enabled", "true", S, "publish the rviz markers"),
    [AF_SETTING_MARKER_LIFETIME_S] =
        NUM("marker_lifetime_s", "0.0", "[0, 3600] s", S, "marker lifetime; 0 = until replaced"),
    [AF_SETTING_MARKER_STRIKE_DISTANCE_M] =
        NUM("marker_strike_distance_m", "0.06", "[0, 10] m", S,
            "hammer link origin to the strike point along the axis (display only)"),
    [AF_SETTING_MARKER_ARROW_LENGTH_M] =
        NUM("marker_arrow_length_m", "0.05", "(0, 10] m", S, "hammer and rotation arrows"),
    [AF_SETTING_STRIKE_PLOT_WIDTH_PX] =
        WHOLE("strike_plot_width_px", "800", "[320, 2048] px", S,
              "width of the last strike's picture on ~strike_plot (sensor_msgs/Image, rgb8)"),
    [AF_SETTING_STRIKE_PLOT_HEIGHT_PX] = WHOLE("strike_plot_height_px", "450", "[240, 2048] px", S,
                                               "height of the last strike's picture"),
    [AF_SETTING_STRIKE_FULL_SCALE_N] = NUM("strike_full_scale_n", "500.0", "(0, 1e6] N", S,
                                           "a raw force sample at or beyond +-this is clipped"),
    [AF_SETTING_STRIKE_THRESHOLD_NOISE_FACTOR] =
        NUM("strike_threshold_noise_factor", "6.0", "(0, 1000]", S,
            "trigger when the force exceeds the baseline by this many noise RMS and by "
            "strike_threshold_min_n"),
    [AF_SETTING_STRIKE_THRESHOLD_MIN_N] = NUM("strike_threshold_min_n", "0.5", "[0, 1e6] N", S,
                                              "least excess over the baseline that triggers"),
    [AF_SETTING_STRIKE_PRE_TRIGGER_S] = NUM("strike_pre_trigger_s", "0.002", "(0, 1] s", S,
                                            "history kept before the trigger, above "
                                            "strike_baseline_window_s"),
    [AF_SETTING_STRIKE_BASELINE_TIME_CONSTANT_S] =
        NUM("strike_baseline_time_constant_s", "0.02", "(0, 10] s", S,
            "idle baseline and noise trackers (also the warm-up)"),
    [AF_SETTING_STRIKE_BASELINE_WINDOW_S] =
        NUM("strike_baseline_window_s", "0.001", "(0, 1] s", S,
            "quiet signal averaged before and after the contact"),
    [AF_SETTING_STRIKE_DOUBLE_HIT_GAP_S] =
        NUM("strike_double_hit_gap_s", "0.005", "[0, 1] s", S,
            "a contact starting this soon after the end is a bounce"),
    [AF_SETTING_STRIKE_MAX_CONTACT_S] = NUM("strike_max_contact_s", "0.01", "(0, 1] s", S,
                                            "a longer contact is not a strike (truncated)"),
    [AF_SETTING_STRIKE_POST_S] = NUM("strike_post_s", "0.005", "(0, 1] s", S,
                                     "wait after the contact, at least strike_double_hit_gap_s "
                                     "and above strike_baseline_window_s"),
    [AF_SETTING_STRIKE_RISE_FIT_LEVEL] = NUM("strike_rise_fit_level", "0.7", "(0, 1)", S,
                                             "rising-edge fit up to this fraction of the peak"),
    [AF_SETTING_STRIKE_FALL_FIT_LEVEL] = NUM("strike_fall_fit_level", "0.5", "(0, 1)", S,
                                             "falling-edge fit from this fraction of the peak"),
    [AF_SETTING_STRIKE_PENDING_SIZE] =
        WHOLE("strike_pending_size", "8", "[1, 1000] strikes", S,
              "strikes waiting for their audio; a full queue measures its oldest without audio"),
    [AF_SETTING_APPLE_STALE_AFTER_S] =
        NUM("apple_stale_after_s", "1.0", "(0, 3600] s", S,
            "a strike is matched to the newest AppleEstimate stamped at most this long before it"),
    [AF_SETTING_APPLE_WAIT_S] = NUM("apple_wait_s", "0.5", "[0, 10] s", S,
                                    "how long a strike waits for the AppleEstimate that "
                                    "belongs to it"),
    [AF_SETTING_MEASURE_FIT_VELOCITY] = BOOLEAN("measure_fit_velocity", "false", S,
                                                "fit the contact velocity too (false: the rig "
                                                "sets it, strike_velocity_m_s)"),
    [AF_SETTING_MEASURE_AUDIO_DELAY_S] =
        NUM("measure_audio_delay_s", "0.0005", "[0, 1] s", S,
            "the analysed audio starts this long after the contact start"),
    [AF_SETTING_MEASURE_AUDIO_WINDOW_S] =
        NUM("measure_audio_window_s", "0.04", "(0, 1] s", S, "analysed audio (at least 8 samples)"),
    [AF_SETTING_MEASURE_NOISE_WINDOW_S] =
        NUM("measure_noise_window_s", "0.02", "[0, 1] s", S,
            "audio before the strike, the noise reference (0 = none, else at least 8 samples)"),
    [AF_SETTING_MEASURE_NOISE_GUARD_S] =
        NUM("measure_noise_guard_s", "0.005", "[0, 1] s", S,
            "the noise reference ends this long before the contact start (stamp jitter)"),
    [AF_SETTING_MEASURE_RANGE_MARGIN] =
        NUM("measure_range_margin", "0.15", "[0, 1)", S,
            "relative widening of the model's 0S2 range for the apple's mass"),
    [AF_SETTING_MEASURE_SNR_THRESHOLD_DB] =
        NUM("measure_snr_threshold_db", "15.0", "[-100, 100] dB", S,
            "a peak below this is not a resonance (response.h: 12 dB lets ~0.1 % of noise-only "
            "windows through, 15 dB none of 2e4)"),
    [AF_SETTING_CULTIVAR] = STRING("cultivar", "Jonagold", AF_LANE_NAME_MAX - 1, C,
                                   "cultivar name, for the diagnostics"),
    [AF_SETTING_MODULUS_NOMINAL_PA] = NUM("modulus_nominal_pa", "8.0e+6", "[1e5, 1e9] Pa", C,
                                          "E2 of the prediction, within [modulus_min_pa, "
                                          "modulus_max_pa]"),
    [AF_SETTING_MODULUS_MIN_PA] =
        NUM("modulus_min_pa", "2.0e+6", "[1e5, 1e9] Pa", C, "softest fruit expected"),
    [AF_SETTING_MODULUS_MAX_PA] =
        NUM("modulus_max_pa", "12.0e+6", "[1e5, 1e9] Pa", C, "firmest fruit expected"),
    [AF_SETTING_MASS_MIN_KG] =
        NUM("mass_min_kg", "0.100", "[0.001, 10] kg", C, "lighter AppleEstimates are refused"),
    [AF_SETTING_MASS_MAX_KG] =
        NUM("mass_max_kg", "0.250", "[0.001, 10] kg", C, "heavier AppleEstimates are refused"),
    [AF_SETTING_EQUATORIAL_RADIUS_MIN_M] =
        NUM("equatorial_radius_min_m", "0.025", "[0.002, 1] m", C,
            "smallest accepted "
            "AppleEstimate.equatorial_radius"),
    [AF_SETTING_EQUATORIAL_RADIUS_MAX_M] =
        NUM("equatorial_radius_max_m", "0.060", "[0.002, 1] m", C,
            "largest accepted "
            "AppleEstimate.equatorial_radius"),
    [AF_SETTING_ASPECT_RATIO_MIN] = NUM("aspect_ratio_min", "0.5", "[0.1, 10]", C,
                                        "smallest polar / equatorial semi-axis implied by mass, "
                                        "density and radius"),
    [AF_SETTING_ASPECT_RATIO_MAX] =
        NUM("aspect_ratio_max", "1.5", "[0.1, 10]", C, "largest polar / equatorial semi-axis"),
    [AF_SETTING_RESTITUTION] = NUM("restitution", "0.6", "[0.01, 1]", C,
                                   "coefficient of restitution e (the exact damping law needs "
                                   "e >= 0.05)"),
    [AF_SETTING_FRUIT_POISSON] =
        NUM("fruit_poisson", "0.35", "[0, 0.5)", C, "Poisson ratio of the flesh"),
    [AF_SETTING_DENSITY_KG_M3] =
        NUM("density_kg_m3", "840.0", "[100, 3000] kg/m3", C, "density of the fruit"),
    [AF_SETTING_YIELD_RATIO] = NUM("yield_ratio", "0.0414", "[0.001, 1]", C,
                                   "yield law tau_y = yield_ratio E_ref (E2/E_ref)^p: "
                                   "tau_y / E2 at E_ref, a calibration (doc/paper.md)"),
    [AF_SETTING_YIELD_EXPONENT] = NUM("yield_exponent", "0.70", "[0, 3]", C,
                                      "p of the yield law; 1 = the ratio law tau_y = "
                                      "yield_ratio E2"),
    [AF_SETTING_YIELD_REFERENCE_MODULUS_PA] =
        NUM("yield_reference_modulus_pa", "8.0e+6", "[1e5, 1e9] Pa", C, "E_ref of the yield law"),
    [AF_SETTING_YIELD_MEASURED] =
        STRING("yield_measured", "\"\"", AF_SETTINGS_TEXT_MAX - 1, C,
               "measured yield shear stress \"E2:tau_y, ...\" [Pa], overriding the law; "
               "\"\" = the law"),
    [AF_SETTING_MODULUS_FACTOR] = NUM("modulus_factor", "1.0", "[0.1, 10]", C,
                                      "dynamic / quasi-static modulus for the 0S2 resonance "
                                      "(a calibration)"),
    [AF_SETTING_GRADE_QUANTITY] =
        CHOICE("grade_quantity", "stiffness_factor",
               "stiffness_factor, modulus_from_resonance, fitted_modulus", C,
               "what the firmness classes are read on (StrikeReport's figure of that name)"),
    [AF_SETTING_GRADE_CLASSES] = STRING(
        "grade_classes", "\"soft | 7.0e+4 | medium | 1.1e+5 | firm | 1.6e+5 | very firm\"", 400, C,
        "firmness classes, softest first, with the boundary between neighbours in "
        "grade_quantity's unit (grade.h); \"\" = no grading"),
};

#undef S
#undef C

/* ---- small helpers ------------------------------------------------------ */

/* vsnprintf into err[len], cut at len - 1 (err may be NULL). */
#if defined(__GNUC__)
__attribute__((format(printf, 3, 4)))
#endif
static void
say(char *err, size_t len, const char *fmt, ...)
{
  if (err == NULL || len == 0)
    return;
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(err, len, fmt, ap);
  va_end(ap);
  /* One line, whatever the values quoted in it hold: a control character
   * (a newline in a flag's value, a CR of a DOS file) shows as '?'. */
  for (char *p = err; *p; p++)
    if ((unsigned char)*p < 0x20 || *p == 0x7f)
      *p = '?';
}

static bool valid_id(af_setting_id id)
{
  return (int)id >= 0 && id < AF_SETTING_COUNT;
}

/* The name as messages write it: prefix + name. */
typedef struct {
  char text[AF_SETTINGS_PREFIX_MAX + 64];
} af_name;

static af_name name_of(const af_settings *s, af_setting_id id)
{
  af_name n;
  snprintf(n.text, sizeof n.text, "%.*s%.63s", AF_SETTINGS_PREFIX_MAX - 1, s->name_prefix,
           rows[id].name);
  return n;
}

/* Slot of a string row in s->text: the string rows before it. */
static int string_slot(af_setting_id id)
{
  int slot = 0;
  for (int k = 0; k < (int)id; k++)
    if (rows[k].kind == AF_SETTING_STRING)
      slot++;
  return slot < AF_SETTINGS_STRINGS ? slot : -1;
}

/* A whole C number: strtod consumed all of text (not empty, no range error). */
static bool c_number(const char *text, double *out)
{
  char *end;
  errno = 0;
  double v = strtod(text, &end);
  if (end == text || *end != '\0' || errno == ERANGE)
    return false;
  *out = v;
  return true;
}

/* ---- rows and ranges ------------------------------------------------------- */

const af_setting_def *af_setting_def_of(af_setting_id id)
{
  return valid_id(id) ? &rows[id] : NULL;
}

af_status af_setting_find(const char *name, af_setting_id *id)
{
  if (name == NULL || id == NULL)
    return AF_EINVAL;
  for (int k = 0; k < AF_SETTING_COUNT; k++)
    if (rows[k].name != NULL && strcmp(rows[k].name, name) == 0) {
      *id = (af_setting_id)k;
      return AF_OK;
    }
  return AF_EINVAL;
}

/* "(lo, hi] unit" or "0 or [lo, hi] unit": the interval and where the unit
 * starts. */
static bool parse_range(const char *text, af_setting_range *r, const char **unit)
{
  static const char zero_or[] = "0 or ";
  r->zero = text != NULL && strncmp(text, zero_or, sizeof zero_or - 1) == 0;
  if (r->zero)
    text += sizeof zero_or - 1;
  if (text == NULL || (text[0] != '(' && text[0] != '['))
    return false;
  r->lo_open = text[0] == '(';
  char *end;
  r->lo = strtod(text + 1, &end);
  if (end == text + 1 || *end != ',')
    return false;
  const char *p = end + 1;
  while (*p == ' ')
    p++;
  r->hi = strtod(p, &end);
  if (end == p || (*end != ')' && *end != ']') || isnan(r->lo) || isnan(r->hi) || !(r->lo <= r->hi))
    return false;
  r->hi_open = *end == ')';
  p = end + 1;
  if (*p == ' ' && p[1] != '\0' && p[1] != ' ')
    p++;
  else if (*p != '\0')
    return false;
  if (unit)
    *unit = p;
  return true;
}

af_status af_setting_range_of(af_setting_id id, af_setting_range *out)
{
  if (!valid_id(id) || out == NULL || rows[id].range == NULL)
    return AF_EINVAL;
  return parse_range(rows[id].range, out, NULL) ? AF_OK : AF_EINVAL;
}

bool af_setting_range_contains(const af_setting_range *r, double v)
{
  if (r == NULL || !isfinite(v))
    return false;
  if (r->zero && v == 0.0)
    return true;
  if (r->lo_open ? !(v > r->lo) : !(v >= r->lo))
    return false;
  return r->hi_open ? v < r->hi : v <= r->hi;
}

double af_setting_rig_value(af_setting_id id)
{
  return valid_id(id) && rows[id].rig != NULL ? strtod(rows[id].rig, NULL) : NAN;
}

const char *af_setting_unit(af_setting_id id)
{
  af_setting_range r;
  const char *unit = "";
  if (valid_id(id) && rows[id].range != NULL && parse_range(rows[id].range, &r, &unit))
    return unit;
  return "";
}

af_status af_setting_choice_word(af_setting_id id, size_t k, char *buf, size_t len)
{
  if (!valid_id(id) || rows[id].kind != AF_SETTING_CHOICE || buf == NULL || len == 0)
    return AF_EINVAL;
  const char *p = rows[id].choices;
  for (size_t i = 0; i < k; i++) {
    p = strchr(p, ',');
    if (p == NULL)
      return AF_EINVAL;
    p += 2; /* ", " */
  }
  size_t n = strcspn(p, ",");
  if (n >= len)
    return AF_EINVAL;
  memcpy(buf, p, n);
  buf[n] = '\0';
  return AF_OK;
}

/* Index of word among a choice row's words, or -1. */
static int choice_index(af_setting_id id, const char *word)
{
  char w[64];
  for (size_t k = 0; af_setting_choice_word(id, k, w, sizeof w) == AF_OK; k++)
    if (strcmp(w, word) == 0)
      return (int)k;
  return -1;
}

/* ---- the values object ---------------------------------------------------- */

/* A typed value: what YAML, a flag or a ROS parameter gave. */
typedef enum { AF_V_NULL, AF_V_BOOL, AF_V_NUMBER, AF_V_STRING } af_vtype;

typedef struct {
  af_vtype type;
  double number;
  bool boolean;
  const char *text; /* AF_V_STRING */
  bool quoted;      /* AF_V_STRING from a quoted scalar */
  bool lenient;     /* a bare string that is a whole C number counts as one (CLI) */
} af_value;

/* The value as messages show it: 1.4, true, 'text'. */
static void value_shown(const af_value *v, char *buf, size_t len)
{
  switch (v->type) {
  case AF_V_NULL: snprintf(buf, len, "(nothing)"); break;
  case AF_V_BOOL: snprintf(buf, len, "%s", v->boolean ? "true" : "false"); break;
  case AF_V_NUMBER: snprintf(buf, len, "%g", v->number); break;
  case AF_V_STRING: snprintf(buf, len, "'%.60s%s'", v->text, strlen(v->text) > 60 ? "..." : "");
  }
}

/* What a row expects, for the messages: "a number in (0, 10] m/s". */
static void expected_text(af_setting_id id, char *buf, size_t len)
{
  const af_setting_def *d = &rows[id];
  switch (d->kind) {
  case AF_SETTING_NUMBER: snprintf(buf, len, "a number in %s", d->range); break;
  case AF_SETTING_WHOLE: snprintf(buf, len, "a whole number in %s", d->range); break;
  case AF_SETTING_BOOL: snprintf(buf, len, "true or false"); break;
  case AF_SETTING_STRING: snprintf(buf, len, "a string"); break;
  case AF_SETTING_CHOICE: snprintf(buf, len, "one of: %s", d->choices); break;
  }
}

/* A number for a number or whole row: range, then wholeness. */
static af_status store_number(af_settings *s, af_setting_id id, double v, char *err, size_t len)
{
  const af_setting_def *d = &rows[id];
  af_name n = name_of(s, id);
  if (d->zero_is_absent && v == 0.0) {
    s->value[id] = NAN;
    s->present[id] = false;
    s->given[id] = true;
    return AF_OK;
  }
  af_setting_range r;
  if (af_setting_range_of(id, &r) != AF_OK) {
    say(err, len, "%s has no valid range in the table", n.text);
    return AF_EINVAL;
  }
  if (!af_setting_range_contains(&r, v)) {
    if (d->optional)
      say(err, len, "%s = %g is outside the accepted range %s (%sabsent = %s)", n.text, v, d->range,
          d->zero_is_absent ? "0 or " : "", d->absent);
    else
      say(err, len, "%s = %g is outside the accepted range %s", n.text, v, d->range);
    return AF_EINVAL;
  }
  if (d->kind == AF_SETTING_WHOLE && v != floor(v)) {
    say(err, len, "%s = %g is not a whole number in %s", n.text, v, d->range);
    return AF_EINVAL;
  }
  s->value[id] = v;
  s->present[id] = true;
  s->given[id] = true;
  return AF_OK;
}

static af_status store_string(af_settings *s, af_setting_id id, const char *v, char *err,
                              size_t len)
{
  const af_setting_def *d = &rows[id];
  int slot = string_slot(id);
  if (slot < 0) {
    say(err, len, "%s: no room for its text", name_of(s, id).text);
    return AF_EINVAL;
  }
  if (strlen(v) > d->max_chars) {
    say(err, len, "%s = '%.40s...' is longer than %zu characters", name_of(s, id).text, v,
        d->max_chars);
    return AF_EINVAL;
  }
  snprintf(s->text[slot], sizeof s->text[slot], "%s", v);
  s->present[id] = true;
  s->given[id] = true;
  return AF_OK;
}

/* Checks v against row id and stores it, or says why not. */
static af_status apply(af_settings *s, af_setting_id id, const af_value *v, char *err, size_t len)
{
  const af_setting_def *d = &rows[id];
  af_name n = name_of(s, id);
  char shown[96];
  value_shown(v, shown, sizeof shown);
  if (v->type == AF_V_NULL) {
    char expected[160];
    expected_text(id, expected, sizeof expected);
    say(err, len, "%s has no value (expected %s)", n.text, expected);
    return AF_EINVAL;
  }
  switch (d->kind) {
  case AF_SETTING_NUMBER:
  case AF_SETTING_WHOLE: {
    double x;
    if (v->type == AF_V_NUMBER)
      return store_number(s, id, v->number, err, len);
    if (v->type == AF_V_STRING && v->lenient && !v->quoted && c_number(v->text, &x))
      return store_number(s, id, x, err, len);
    if (v->type == AF_V_STRING && !v->quoted && c_number(v->text, &x))
      say(err, len,
          "%s = %s is not a number (YAML 1.1 reads it as a string: write a dot and a signed "
          "exponent, e.g. 8.0e+6)",
          n.text, shown);
    else
      say(err, len, "%s = %s is not a number (expected %s)", n.text, shown, d->range);
    return AF_EINVAL;
  }
  case AF_SETTING_BOOL:
    if (v->type == AF_V_BOOL) {
      s->value[id] = v->boolean ? 1.0 : 0.0;
      s->present[id] = true;
      s->given[id] = true;
      return AF_OK;
    }
    say(err, len, "%s = %s is not true or false", n.text, shown);
    return AF_EINVAL;
  case AF_SETTING_STRING:
    if (v->type == AF_V_STRING)
      return store_string(s, id, v->text, err, len);
    say(err, len, "%s = %s is not a string (quote it)", n.text, shown);
    return AF_EINVAL;
  case AF_SETTING_CHOICE: {
    int k = v->type == AF_V_STRING ? choice_index(id, v->text) : -1;
    if (k < 0) {
      say(err, len, "%s = %s is not one of: %s", n.text, shown, d->choices);
      return AF_EINVAL;
    }
    s->value[id] = k;
    s->present[id] = true;
    s->given[id] = true;
    return AF_OK;
  }
  }
  return AF_EINVAL;
}

static af_status check_args(const af_settings *s, af_setting_id id, char *err, size_t len)
{
  if (s == NULL) {
    say(err, len, "settings: s is NULL");
    return AF_EINVAL;
  }
  if (!valid_id(id)) {
    say(err, len, "unknown parameter #%d", (int)id);
    return AF_EINVAL;
  }
  return AF_OK;
}

af_status af_settings_set_number(af_settings *s, af_setting_id id, double v, char *err, size_t len)
{
  af_value x = {.type = AF_V_NUMBER, .number = v};
  return check_args(s, id, err, len) == AF_OK ? apply(s, id, &x, err, len) : AF_EINVAL;
}

af_status af_settings_set_bool(af_settings *s, af_setting_id id, bool v, char *err, size_t len)
{
  af_value x = {.type = AF_V_BOOL, .boolean = v};
  return check_args(s, id, err, len) == AF_OK ? apply(s, id, &x, err, len) : AF_EINVAL;
}

af_status af_settings_set_string(af_settings *s, af_setting_id id, const char *v, char *err,
                                 size_t len)
{
  af_value x = {.type = v ? AF_V_STRING : AF_V_NULL, .text = v};
  return check_args(s, id, err, len) == AF_OK ? apply(s, id, &x, err, len) : AF_EINVAL;
}

static af_status set_default(af_settings *s, af_setting_id id)
{
  const af_setting_def *d = &rows[id];
  s->value[id] = NAN;
  s->present[id] = false;
  if (d->def == NULL)
    return AF_OK;
  char err[8];
  return af_settings_set_text(s, d->name, d->def, err, sizeof err);
}

void af_settings_init(af_settings *s)
{
  if (s == NULL)
    return;
  memset(s, 0, sizeof *s);
  for (int k = 0; k < AF_SETTING_COUNT; k++)
    set_default(s, (af_setting_id)k); /* the test checks every default is accepted */
  memset(s->given, 0, sizeof s->given);
}

void af_settings_set_name_prefix(af_settings *s, const char *prefix)
{
  if (s != NULL)
    snprintf(s->name_prefix, sizeof s->name_prefix, "%s", prefix ? prefix : "");
}

/* ---- YAML 1.1 scalars ------------------------------------------------------ */

static bool one_of(const char *t, const char *const *words)
{
  for (; *words; words++)
    if (strcmp(t, *words) == 0)
      return true;
  return false;
}

/* Digits of set (plus '_') from t, at least one; returns the end. */
static const char *span_of(const char *t, const char *set)
{
  const char *p = t;
  while (*p && (strchr(set, *p) != NULL || *p == '_'))
    p++;
  return p;
}

/* t without its underscores into buf. */
static void without_underscores(const char *t, char *buf, size_t len)
{
  size_t n = 0;
  for (; *t && n + 1 < len; t++)
    if (*t != '_')
      buf[n++] = *t;
  buf[n] = '\0';
}

/* YAML 1.1 int (PyYAML's resolver, sexagesimal left out). */
static bool yaml_int(const char *t, double *out)
{
  const char *p = t + (*t == '-' || *t == '+');
  int base = 10;
  const char *digits = p;
  if (p[0] == '0' && p[1] == 'b') {
    base = 2, digits = p + 2;
    if (*digits == '\0' || *span_of(digits, "01") != '\0')
      return false;
  } else if (p[0] == '0' && p[1] == 'x') {
    base = 16, digits = p + 2;
    if (*digits == '\0' || *span_of(digits, "0123456789abcdefABCDEF") != '\0')
      return false;
  } else if (p[0] == '0' && p[1] != '\0') {
    base = 8, digits = p + 1;
    if (*span_of(digits, "01234567") != '\0')
      return false;
  } else if (!(p[0] == '0' && p[1] == '\0') &&
             !(p[0] >= '1' && p[0] <= '9' && *span_of(p + 1, "0123456789") == '\0')) {
    return false;
  }
  char clean[80];
  if (strlen(digits) >= sizeof clean)
    return false;
  without_underscores(digits, clean, sizeof clean);
  errno = 0;
  char *end;
  unsigned long long u = strtoull(clean, &end, base);
  if (errno == ERANGE || *end != '\0')
    return false;
  *out = (*t == '-' ? -1.0 : 1.0) * (double)u;
  return true;
}

/* YAML 1.1 float (PyYAML's resolver, sexagesimal left out): a dot is
 * required, an exponent needs its sign. */
static bool yaml_float(const char *t, double *out)
{
  static const char *const inf[] = {".inf", ".Inf", ".INF", NULL};
  static const char *const nan[] = {".nan", ".NaN", ".NAN", NULL};
  const char *p = t + (*t == '-' || *t == '+');
  if (one_of(p, inf)) {
    *out = *t == '-' ? -INFINITY : INFINITY;
    return true;
  }
  if (one_of(t, nan)) {
    *out = NAN;
    return true;
  }
  const char *q;
  if (*p >= '0' && *p <= '9') {
    q = span_of(p, "0123456789");
    if (*q != '.')
      return false;
    q = span_of(q + 1, "0123456789");
  } else if (*p == '.' && p == t) { /* ".5": no sign in this form */
    q = span_of(p + 1, "0123456789");
    if (q == p + 1)
      return false;
  } else {
    return false;
  }
  if (*q == 'e' || *q == 'E') {
    if (q[1] != '+' && q[1] != '-')
      return false;
    const char *e = q + 2;
    q = e;
    while (*q >= '0' && *q <= '9')
      q++;
    if (q == e)
      return false;
  }
  if (*q != '\0')
    return false;
  char clean[80];
  if (strlen(t) >= sizeof clean)
    return false;
  without_underscores(t, clean, sizeof clean);
  char *end;
  *out = strtod(clean, &end);
  return *end == '\0';
}

/* A bare (plain) YAML scalar, typed as PyYAML types it. */
static void resolve_plain(const char *t, af_value *v)
{
  static const char *const nulls[] = {"", "~", "null", "Null", "NULL", NULL};
  static const char *const trues[] = {"true", "True", "TRUE", "yes", "Yes",
                                      "YES",  "on",   "On",   "ON",  NULL};
  static const char *const falses[] = {"false", "False", "FALSE", "no",  "No",
                                       "NO",    "off",   "Off",   "OFF", NULL};
  v->text = t;
  v->quoted = false;
  if (one_of(t, nulls))
    v->type = AF_V_NULL;
  else if (one_of(t, trues))
    v->type = AF_V_BOOL, v->boolean = true;
  else if (one_of(t, falses))
    v->type = AF_V_BOOL, v->boolean = false;
  else if (yaml_int(t, &v->number) || yaml_float(t, &v->number))
    v->type = AF_V_NUMBER;
  else
    v->type = AF_V_STRING;
}

/* Parses the scalar at p into buf (unquoted text) and *v; *rest is where it
 * ended (after a closing quote, or at a comment / the end for a plain one).
 * false with why on a malformed scalar. */
static bool parse_scalar(const char *p, char *buf, size_t size, af_value *v, const char **rest,
                         const char **why)
{
  size_t n = 0;
  *v = (af_value){.type = AF_V_NULL};
  if (*p == '"' || *p == '\'') {
    char q = *p++;
    for (;; p++) {
      if (*p == '\0') {
        *why = "an unterminated quoted string";
        return false;
      }
      char c = *p;
      if (c == q) {
        if (q == '\'' && p[1] == '\'') { /* '' is a quote inside '...' */
          p++;
        } else {
          p++;
          break;
        }
      } else if (q == '"' && c == '\\') {
        static const char from[] = "\\\"/ntr0", to[] = "\\\"/\n\t\r";
        const char *k = p[1] ? strchr(from, p[1]) : NULL;
        if (k == NULL || *k == '0') {
          *why = "an escape other than \\\\ \\\" \\/ \\n \\t \\r in a quoted string";
          return false;
        }
        c = to[k - from];
        p++;
      }
      if (n + 1 >= size) {
        *why = "a value longer than the line buffer";
        return false;
      }
      buf[n++] = c;
    }
    buf[n] = '\0';
    v->type = AF_V_STRING;
    v->text = buf;
    v->quoted = true;
    *rest = p;
    return true;
  }
  if (*p != '\0' && strchr("[]{}&*!|>%@`,", *p) != NULL) {
    *why = "not a flat value (a list, a map, a tag, an anchor or a block scalar)";
    return false;
  }
  if ((*p == '-' || *p == '?') && (p[1] == ' ' || p[1] == '\0')) {
    *why = "not a flat value (a list)";
    return false;
  }
  /* A plain scalar runs to " #" or the end; its trailing blanks are not part of it. */
  const char *end = p;
  while (*end && !((*end == '#') && end > p && (end[-1] == ' ' || end[-1] == '\t')))
    end++;
  const char *stop = end;
  while (stop > p && (stop[-1] == ' ' || stop[-1] == '\t'))
    stop--;
  if ((size_t)(stop - p) >= size) {
    *why = "a value longer than the line buffer";
    return false;
  }
  memcpy(buf, p, (size_t)(stop - p));
  buf[stop - p] = '\0';
  n = strlen(buf);
  if (strstr(buf, ": ") != NULL || strstr(buf, ":\t") != NULL || (n > 0 && buf[n - 1] == ':')) {
    *why = "not a flat value (a map inside a value)";
    return false;
  }
  resolve_plain(buf, v);
  *rest = end;
  return true;
}

/* Nothing but blanks and a comment. */
static bool blank_or_comment(const char *p)
{
  while (*p == ' ' || *p == '\t')
    p++;
  return *p == '\0' || *p == '#';
}

/* set_text and set_arg: one scalar for the row called name. */
static af_status set_scalar(af_settings *s, const char *name, const char *text, bool lenient,
                            char *err, size_t len)
{
  if (s == NULL || name == NULL || text == NULL) {
    say(err, len, "settings: a NULL argument");
    return AF_EINVAL;
  }
  af_setting_id id;
  if (af_setting_find(name, &id) != AF_OK) {
    say(err, len, "unknown parameter '%s%.64s'", s->name_prefix, name);
    return AF_EINVAL;
  }
  char buf[AF_SETTINGS_TEXT_MAX * 2];
  af_value v;
  const char *rest = text, *why = NULL;
  while (*text == ' ' || *text == '\t')
    text++;
  if (!parse_scalar(text, buf, sizeof buf, &v, &rest, &why)) {
    say(err, len, "%s: %s", name_of(s, id).text, why);
    return AF_EINVAL;
  }
  if (!blank_or_comment(rest)) {
    say(err, len, "%s: text after the value: '%.40s'", name_of(s, id).text, rest);
    return AF_EINVAL;
  }
  v.lenient = lenient;
  if (lenient && v.type == AF_V_NULL && rows[id].kind == AF_SETTING_STRING && buf[0] == '\0' &&
      text[0] == '\0')
    v = (af_value){.type = AF_V_STRING, .text = "", .quoted = true}; /* "name=" */
  af_settings copy = *s;
  af_status st = apply(&copy, id, &v, err, len);
  if (st == AF_OK)
    *s = copy;
  return st;
}

af_status af_settings_set_text(af_settings *s, const char *name, const char *text, char *err,
                               size_t len)
{
  return set_scalar(s, name, text, false, err, len);
}

af_status af_settings_set_arg(af_settings *s, const char *arg, char *err, size_t len)
{
  const char *eq = arg ? strchr(arg, '=') : NULL;
  if (eq == NULL) {
    say(err, len, "'%.80s' is not name=value", arg ? arg : "(null)");
    return AF_EINVAL;
  }
  char name[80];
  if ((size_t)(eq - arg) >= sizeof name) {
    say(err, len, "unknown parameter '%.*s...'", 60, arg);
    return AF_EINVAL;
  }
  memcpy(name, arg, (size_t)(eq - arg));
  name[eq - arg] = '\0';
  return set_scalar(s, name, eq + 1, true, err, len);
}

/* ---- the YAML file --------------------------------------------------------- */

#define AF_YAML_LINE_MAX 1024 /* with its NUL */

af_status af_settings_load_yaml(af_settings *s, const char *path, char *err, size_t len)
{
  if (s == NULL || path == NULL) {
    say(err, len, "settings: a NULL argument");
    return AF_EINVAL;
  }
  FILE *f = fopen(path, "r");
  if (f == NULL) {
    say(err, len, "%s: cannot be opened: %s", path, strerror(errno));
    return AF_EIO;
  }
  af_settings copy = *s;
  int first_line[AF_SETTING_COUNT] = {0};
  char line[AF_YAML_LINE_MAX + 1], value[AF_YAML_LINE_MAX], why_buf[AF_SETTINGS_TEXT_MAX];
  af_status st = AF_OK;
  int number = 0;
  bool any = false;
  while (st == AF_OK && fgets(line, sizeof line, f) != NULL) {
    number++;
    size_t n = strlen(line);
    if (n == sizeof line - 1 && line[n - 1] != '\n' && !feof(f)) {
      say(err, len, "%s:%d: a line longer than %d characters", path, number, AF_YAML_LINE_MAX - 1);
      st = AF_EINVAL;
      break;
    }
    while (n > 0 && (line[n - 1] == '\n' || line[n - 1] == '\r'))
      line[--n] = '\0';
    if (blank_or_comment(line))
      continue;
    if (!any && strcmp(line, "---") == 0) { /* a document start before any key */
      any = true;
      continue;
    }
    any = true;
    const char *p = line;
    while ((*p >= 'a' && *p <= 'z') || (*p >= 'A' && *p <= 'Z') || (*p >= '0' && *p <= '9') ||
           *p == '_')
      p++;
    if (p == line || *p != ':' || (p[1] != '\0' && p[1] != ' ' && p[1] != '\t')) {
      say(err, len, "%s:%d: not a flat `key: value` line: '%.60s'", path, number, line);
      st = AF_EINVAL;
      break;
    }
    char key[80];
    snprintf(key, sizeof key, "%.*s", (int)(p - line) < 79 ? (int)(p - line) : 79, line);
    af_setting_id id;
    if (af_setting_find(key, &id) != AF_OK) {
      say(err, len, "%s:%d: unknown parameter '%s'", path, number, key);
      st = AF_EINVAL;
      break;
    }
    if (first_line[id] != 0) {
      say(err, len, "%s:%d: duplicate key '%s' (first on line %d)", path, number, key,
          first_line[id]);
      st = AF_EINVAL;
      break;
    }
    first_line[id] = number;
    p++;
    while (*p == ' ' || *p == '\t')
      p++;
    af_value v;
    const char *rest = p, *why = NULL;
    if (!parse_scalar(p, value, sizeof value, &v, &rest, &why) || !blank_or_comment(rest)) {
      say(err, len, "%s:%d: %s: %s", path, number, key, why ? why : "text after the quoted value");
      st = AF_EINVAL;
      break;
    }
    st = apply(&copy, id, &v, why_buf, sizeof why_buf);
    if (st != AF_OK)
      say(err, len, "%s:%d: %s", path, number, why_buf);
  }
  if (st == AF_OK && ferror(f)) {
    say(err, len, "%s: read error after line %d", path, number);
    st = AF_EIO;
  }
  fclose(f);
  if (st == AF_OK)
    *s = copy;
  return st;
}

af_status af_settings_check_required(const af_settings *s, unsigned files, char *err, size_t len)
{
  if (s == NULL) {
    say(err, len, "settings: s is NULL");
    return AF_EINVAL;
  }
  for (int k = 0; k < AF_SETTING_COUNT; k++) {
    const af_setting_def *d = &rows[k];
    if (!(d->file & files) || d->optional || s->given[k])
      continue;
    char expected[160];
    expected_text((af_setting_id)k, expected, sizeof expected);
    say(err, len, "%s is missing (expected %s; %s)", name_of(s, (af_setting_id)k).text, expected,
        d->file == AF_SETTINGS_STATION
            ? "its default is in config/station.yaml"
            : "a cultivar value: see the cultivar's YAML, e.g. config/jonagold.yaml");
    return AF_EINVAL;
  }
  return AF_OK;
}

/* ---- reading values -------------------------------------------------------- */

bool af_settings_given(const af_settings *s, af_setting_id id)
{
  return s != NULL && valid_id(id) && s->given[id];
}

af_status af_settings_use_rig_hammer(af_settings *s, char *err, size_t len)
{
  for (int k = 0; k < AF_SETTING_COUNT; k++) {
    af_setting_id id = (af_setting_id)k;
    if (rows[k].rig == NULL || s->present[k])
      continue;
    af_status st = af_settings_set_number(s, id, af_setting_rig_value(id), err, len);
    if (st != AF_OK)
      return st;
  }
  return AF_OK;
}

bool af_settings_present(const af_settings *s, af_setting_id id)
{
  return s != NULL && valid_id(id) && s->present[id];
}

double af_settings_number(const af_settings *s, af_setting_id id)
{
  if (!af_settings_present(s, id) || rows[id].kind == AF_SETTING_STRING)
    return NAN;
  return s->value[id];
}

bool af_settings_bool(const af_settings *s, af_setting_id id)
{
  return af_settings_present(s, id) && rows[id].kind == AF_SETTING_BOOL && s->value[id] != 0.0;
}

const char *af_settings_string(const af_settings *s, af_setting_id id)
{
  if (s == NULL || !valid_id(id) || rows[id].kind != AF_SETTING_STRING)
    return NULL;
  int slot = string_slot(id);
  return slot < 0 ? NULL : s->text[slot];
}

af_status af_settings_choice(const af_settings *s, af_setting_id id, char *buf, size_t len)
{
  if (!af_settings_present(s, id) || rows[id].kind != AF_SETTING_CHOICE)
    return AF_EINVAL;
  return af_setting_choice_word(id, (size_t)s->value[id], buf, len);
}

/* Shortest %g that reads back as v. */
static void shortest(double v, char *buf, size_t len)
{
  for (int digits = 6; digits <= 17; digits++) {
    snprintf(buf, len, "%.*g", digits, v);
    if (strtod(buf, NULL) == v)
      return;
  }
}

/* v as a YAML 1.1 number: a dot before any exponent ("9.0e+06"), .inf, .nan. */
static void yaml_number(double v, char *buf, size_t len)
{
  if (isnan(v) || isinf(v)) {
    snprintf(buf, len, "%s", isnan(v) ? ".nan" : v > 0 ? ".inf" : "-.inf");
    return;
  }
  char t[40];
  shortest(v, t, sizeof t);
  char *e = strchr(t, 'e');
  if (e != NULL && strchr(t, '.') == NULL)
    snprintf(buf, len, "%.*s.0%s", (int)(e - t), t, e);
  else
    snprintf(buf, len, "%s", t);
}

/* t as a YAML scalar that reads back as the string t: bare when it would,
 * else double-quoted with \\ and \" escaped. */
static void yaml_string(const char *t, char *buf, size_t len)
{
  char copy[AF_SETTINGS_TEXT_MAX * 2];
  af_value v;
  const char *rest = NULL, *why = NULL;
  if (t[0] != ' ' && parse_scalar(t, copy, sizeof copy, &v, &rest, &why) && *rest == '\0' &&
      v.type == AF_V_STRING && strcmp(copy, t) == 0) {
    snprintf(buf, len, "%s", t);
    return;
  }
  size_t n = 0;
  if (len < 3) {
    if (len)
      buf[0] = '\0';
    return;
  }
  buf[n++] = '"';
  for (; *t && n + 3 < len; t++) {
    if (*t == '"' || *t == '\\')
      buf[n++] = '\\';
    buf[n++] = *t;
  }
  buf[n++] = '"';
  buf[n] = '\0';
}

void af_settings_value_text(const af_settings *s, af_setting_id id, char *buf, size_t len)
{
  if (buf == NULL || len == 0)
    return;
  if (s == NULL || !valid_id(id)) {
    snprintf(buf, len, "?");
    return;
  }
  if (rows[id].kind == AF_SETTING_STRING) {
    yaml_string(af_settings_string(s, id), buf, len);
    return;
  }
  if (!s->present[id]) {
    snprintf(buf, len, "absent");
    return;
  }
  switch (rows[id].kind) {
  case AF_SETTING_BOOL: snprintf(buf, len, "%s", s->value[id] != 0.0 ? "true" : "false"); break;
  case AF_SETTING_CHOICE:
    if (af_settings_choice(s, id, buf, len) != AF_OK)
      snprintf(buf, len, "?");
    break;
  default: yaml_number(s->value[id], buf, len); break;
  }
}

/* ---- printing --------------------------------------------------------------- */

static const char *kind_word(af_setting_kind k)
{
  switch (k) {
  case AF_SETTING_NUMBER: return "double";
  case AF_SETTING_WHOLE: return "int";
  case AF_SETTING_BOOL: return "bool";
  case AF_SETTING_STRING:
  case AF_SETTING_CHOICE: return "string";
  }
  return "?";
}

void af_settings_print(FILE *out, unsigned files, af_settings_print_format format)
{
  if (out == NULL)
    return;
  if (format == AF_SETTINGS_PRINT_TEXT)
    fprintf(out, "%-32s %-6s %-15s %-26s %-8s %s\n", "name", "kind", "default", "range / choices",
            "file", "help");
  for (int k = 0; k < AF_SETTING_COUNT; k++) {
    const af_setting_def *d = &rows[k];
    if (d->name == NULL || !(d->file & files))
      continue;
    char def[80], choices[96];
    snprintf(def, sizeof def, "%s", d->def ? d->def : "absent");
    /* "paper, exact, hu-guo" -> "paper | exact | hu-guo" */
    choices[0] = '\0';
    if (d->choices) {
      char w[64];
      for (size_t i = 0; af_setting_choice_word((af_setting_id)k, i, w, sizeof w) == AF_OK; i++)
        snprintf(choices + strlen(choices), sizeof choices - strlen(choices), "%s%s",
                 i ? " | " : "", w);
    }
    const char *unit = af_setting_unit((af_setting_id)k);
    if (format == AF_SETTINGS_PRINT_TEXT) {
      char range[96];
      if (d->range)
        snprintf(range, sizeof range, "%s", d->range);
      else
        snprintf(range, sizeof range, "%s", d->choices ? choices : "");
      fprintf(out, "%-32s %-6s %-15s %-26s %-8s %s%s%s%s\n", d->name, kind_word(d->kind), def,
              range, d->file == AF_SETTINGS_STATION ? "station" : "cultivar", d->help,
              d->optional ? (d->zero_is_absent ? " (0 or absent = " : " (absent = ") : "",
              d->optional ? d->absent : "", d->optional ? ")" : "");
      continue;
    }
    /* doc/parameters.md: "- **name** (double, 1.4, (0, 10], m/s): help." */
    bool backticks = d->kind == AF_SETTING_STRING || d->kind == AF_SETTING_CHOICE;
    fprintf(out, "- **%s** (%s, %s%s%s", d->name, kind_word(d->kind), backticks ? "`" : "", def,
            backticks ? "`" : "");
    if (d->range) {
      af_setting_range r;
      const char *u = "";
      parse_range(d->range, &r, &u);
      fprintf(out, ", %.*s, %s", (int)(strlen(d->range) - strlen(u) - (u[0] ? 1 : 0)), d->range,
              unit[0] ? unit : "–");
    } else if (d->choices) {
      fprintf(out, ", %s", choices);
    }
    if (d->optional)
      fprintf(out, "): %s; %sabsent = %s.\n", d->help, d->zero_is_absent ? "0 or " : "", d->absent);
    else
      fprintf(out, "): %s.\n", d->help);
  }
}

/* ---- af_lane_config_derive ------------------------------------------------- */

/* A ring longer than this is a typo, not a buffer (400 MB of float). */
#define AF_RING_MAX_SAMPLES 100000000.0
/* The strike detector's longest event span (strike.c refuses more). */
#define AF_SPAN_MAX_SAMPLES 16777216.0

static double num(const af_settings *s, af_setting_id id)
{
  return s->value[id];
}

/* Every row present and, for numbers, still within its range (a caller may
 * have written s->value by hand). */
static af_status check_values(const af_settings *s, char *err, size_t len)
{
  for (int k = 0; k < AF_SETTING_COUNT; k++) {
    af_setting_id id = (af_setting_id)k;
    const af_setting_def *d = &rows[k];
    if (!s->present[k] && d->kind != AF_SETTING_STRING) {
      if (d->optional)
        say(err, len, "%s is not set (%s unless given)", name_of(s, id).text, d->absent);
      else
        say(err, len, "%s has no value", name_of(s, id).text);
      return AF_EINVAL;
    }
    af_setting_range r;
    if (d->range &&
        (af_setting_range_of(id, &r) != AF_OK || !af_setting_range_contains(&r, s->value[k]) ||
         (d->kind == AF_SETTING_WHOLE && s->value[k] != floor(s->value[k])))) {
      say(err, len, "%s = %g is outside the accepted range %s", name_of(s, id).text, s->value[k],
          d->range);
      return AF_EINVAL;
    }
  }
  return AF_OK;
}

static af_status check_order(const af_settings *s, af_setting_id lo, af_setting_id hi, char *err,
                             size_t len)
{
  if (num(s, lo) < num(s, hi))
    return AF_OK;
  say(err, len, "%s = %g must be below %s = %g", name_of(s, lo).text, num(s, lo),
      name_of(s, hi).text, num(s, hi));
  return AF_EINVAL;
}

/* A choice row's word through the core's own parser. */
static af_status parse_choice(const af_settings *s, af_setting_id id,
                              af_status (*parse)(const char *, void *), void *out, char *err,
                              size_t len)
{
  char word[64] = "";
  if (af_settings_choice(s, id, word, sizeof word) == AF_OK && parse(word, out) == AF_OK)
    return AF_OK;
  say(err, len, "%s = '%s' is not one of: %s", name_of(s, id).text, word, rows[id].choices);
  return AF_EINVAL;
}

/* Adapters with the common signature of parse_choice. */
static af_status parse_damping(const char *t, void *out)
{
  return af_damping_law_parse(t, out);
}
static af_status parse_band(const char *t, void *out)
{
  return af_band_level_parse(t, out);
}
static af_status parse_shear(const char *t, void *out)
{
  return af_shear_ratio_parse(t, out);
}

/* The strike, the criteria and the advice. */
static af_status derive_strike(const af_settings *s, af_lane_config *c, char *err, size_t len)
{
  af_model_params *m = &c->model;
  af_impact_params *i = &m->impact;
  i->velocity_m_s = num(s, AF_SETTING_STRIKE_VELOCITY_M_S);
  i->gravity_m_s2 = num(s, AF_SETTING_GRAVITY_M_S2);
  i->hammer_modulus_pa = num(s, AF_SETTING_HAMMER_MODULUS_PA);
  i->hammer_poisson = num(s, AF_SETTING_HAMMER_POISSON);
  c->r2_search_low_m = num(s, AF_SETTING_R2_SEARCH_LOW_M);
  c->r2_search_high_m = num(s, AF_SETTING_R2_SEARCH_HIGH_M);
  c->strike_radius_min_m = num(s, AF_SETTING_STRIKE_RADIUS_MIN_M);
  c->strike_radius_max_m = num(s, AF_SETTING_STRIKE_RADIUS_MAX_M);
  m->lobe = (unsigned)num(s, AF_SETTING_LOBE);
  c->latitude_tolerance_rad = num(s, AF_SETTING_LATITUDE_TOLERANCE_DEG) * M_PI / 180.0;
  af_status st = parse_choice(s, AF_SETTING_DAMPING_LAW, parse_damping, &i->damping, err, len);
  if (st == AF_OK)
    st = parse_choice(s, AF_SETTING_BAND_LEVEL, parse_band, &m->band_level, err, len);
  if (st == AF_OK)
    st = parse_choice(s, AF_SETTING_SHEAR_RATIO, parse_shear, &m->shear_ratio, err, len);
  if (st == AF_OK)
    st = check_order(s, AF_SETTING_R2_SEARCH_LOW_M, AF_SETTING_R2_SEARCH_HIGH_M, err, len);
  if (st == AF_OK)
    st = check_order(s, AF_SETTING_STRIKE_RADIUS_MIN_M, AF_SETTING_STRIKE_RADIUS_MAX_M, err, len);
  return st;
}

static af_status derive_cultivar(const af_settings *s, af_lane_config *c, char *err, size_t len)
{
  af_model_params *m = &c->model;
  af_impact_params *i = &m->impact;
  snprintf(c->cultivar, sizeof c->cultivar, "%s", af_settings_string(s, AF_SETTING_CULTIVAR));
  i->fruit_modulus_pa = num(s, AF_SETTING_MODULUS_NOMINAL_PA);
  c->modulus_min_pa = num(s, AF_SETTING_MODULUS_MIN_PA);
  c->modulus_max_pa = num(s, AF_SETTING_MODULUS_MAX_PA);
  c->mass_min_kg = num(s, AF_SETTING_MASS_MIN_KG);
  c->mass_max_kg = num(s, AF_SETTING_MASS_MAX_KG);
  c->equatorial_radius_min_m = num(s, AF_SETTING_EQUATORIAL_RADIUS_MIN_M);
  c->equatorial_radius_max_m = num(s, AF_SETTING_EQUATORIAL_RADIUS_MAX_M);
  c->aspect_ratio_min = num(s, AF_SETTING_ASPECT_RATIO_MIN);
  c->aspect_ratio_max = num(s, AF_SETTING_ASPECT_RATIO_MAX);
  i->restitution = num(s, AF_SETTING_RESTITUTION);
  i->fruit_poisson = num(s, AF_SETTING_FRUIT_POISSON);
  m->fruit_density_kg_m3 = num(s, AF_SETTING_DENSITY_KG_M3);
  m->yield_ratio = num(s, AF_SETTING_YIELD_RATIO);
  m->yield_exponent = num(s, AF_SETTING_YIELD_EXPONENT);
  m->yield_reference_modulus_pa = num(s, AF_SETTING_YIELD_REFERENCE_MODULUS_PA);
  char why[160];
  if (af_yield_points_parse(af_settings_string(s, AF_SETTING_YIELD_MEASURED), &m->yield_measured,
                            why, sizeof why) != AF_OK) {
    say(err, len, "%s: %s", name_of(s, AF_SETTING_YIELD_MEASURED).text, why);
    return AF_EINVAL;
  }
  m->modulus_factor = num(s, AF_SETTING_MODULUS_FACTOR);
  if (!(c->modulus_min_pa <= i->fruit_modulus_pa && i->fruit_modulus_pa <= c->modulus_max_pa)) {
    say(err, len, "%s = %g must lie in [%s, %s] = [%g, %g] Pa",
        name_of(s, AF_SETTING_MODULUS_NOMINAL_PA).text, i->fruit_modulus_pa,
        name_of(s, AF_SETTING_MODULUS_MIN_PA).text, name_of(s, AF_SETTING_MODULUS_MAX_PA).text,
        c->modulus_min_pa, c->modulus_max_pa);
    return AF_EINVAL;
  }
  static const af_setting_id pairs[][2] = {
      {AF_SETTING_MODULUS_MIN_PA, AF_SETTING_MODULUS_MAX_PA},
      {AF_SETTING_MASS_MIN_KG, AF_SETTING_MASS_MAX_KG},
      {AF_SETTING_EQUATORIAL_RADIUS_MIN_M, AF_SETTING_EQUATORIAL_RADIUS_MAX_M},
      {AF_SETTING_ASPECT_RATIO_MIN, AF_SETTING_ASPECT_RATIO_MAX},
  };
  for (size_t k = 0; k < sizeof pairs / sizeof pairs[0]; k++)
    if (check_order(s, pairs[k][0], pairs[k][1], err, len) != AF_OK)
      return AF_EINVAL;
  if (af_resonance_lamb_root(i->fruit_poisson, &c->resonance_xi) != AF_OK) {
    say(err, len, "%s = %g: no 0S2 root of Lamb's equation found",
        name_of(s, AF_SETTING_FRUIT_POISSON).text, i->fruit_poisson);
    return AF_EINVAL;
  }
  return AF_OK;
}

static af_status derive_stream(const af_settings *s, af_setting_id rate, af_setting_id buffer,
                               af_stream_config *sc, char *err, size_t len)
{
  sc->sample_rate_hz = num(s, rate);
  sc->buffer_s = num(s, buffer);
  double samples = ceil(sc->buffer_s * sc->sample_rate_hz);
  if (samples > AF_RING_MAX_SAMPLES) {
    say(err, len, "%s = %g and %s = %g make a ring of %.0f samples, above the %.0f accepted",
        name_of(s, buffer).text, sc->buffer_s, name_of(s, rate).text, sc->sample_rate_hz, samples,
        AF_RING_MAX_SAMPLES);
    return AF_EINVAL;
  }
  sc->capacity_samples = (size_t)samples;
  return AF_OK;
}

/* The force transducer: newtons as sent, or volts from a DAQ turned into
 * newtons at the lane's input (x [V] / sensitivity [V/N] = x [N]). The
 * sensitivity goes with volts only: given with N it would be ignored. */
static af_status derive_force_unit(const af_settings *s, af_lane_config *c, char *err, size_t len)
{
  const af_setting_id unit = AF_SETTING_FORCE_UNIT, sens = AF_SETTING_FORCE_SENSITIVITY_V_PER_N;
  if (af_settings_choice(s, unit, c->force.units[0], AF_LANE_UNIT_MAX) != AF_OK) {
    say(err, len, "%s has no value", name_of(s, unit).text);
    return AF_EINVAL;
  }
  const bool volts = strcmp(c->force.units[0], "V") == 0;
  if (volts && num(s, sens) == 0.0) {
    say(err, len, "%s = 0 (none), but %s = V needs it: a number in %s other than 0",
        name_of(s, sens).text, name_of(s, unit).text, rows[sens].range);
    return AF_EINVAL;
  }
  if (!volts && num(s, sens) != 0.0) {
    say(err, len, "%s = %g is given but %s = %s (the sensitivity converts volts only)",
        name_of(s, sens).text, num(s, sens), name_of(s, unit).text, c->force.units[0]);
    return AF_EINVAL;
  }
  c->force.to_si = volts ? 1.0 / num(s, sens) : 1.0;
  return AF_OK;
}

static af_status derive_streams(const af_settings *s, af_lane_config *c, char *err, size_t len)
{
  af_status st = derive_stream(s, AF_SETTING_FORCE_SAMPLE_RATE_HZ, AF_SETTING_FORCE_BUFFER_S,
                               &c->force, err, len);
  if (st == AF_OK)
    st = derive_stream(s, AF_SETTING_AUDIO_SAMPLE_RATE_HZ, AF_SETTING_AUDIO_BUFFER_S, &c->audio,
                       err, len);
  if (st != AF_OK)
    return st;
  /* The microphone speaks pascals or volts, as sent. */
  st = af_settings_choice(s, AF_SETTING_AUDIO_UNIT, c->audio.units[0], AF_LANE_UNIT_MAX);
  if (st != AF_OK) {
    say(err, len, "%s has no value", name_of(s, AF_SETTING_AUDIO_UNIT).text);
    return st;
  }
  c->audio.to_si = 1.0;
  c->stream_stale_after_s = num(s, AF_SETTING_STREAM_STALE_AFTER_S);
  c->stream_absent_warn_s = num(s, AF_SETTING_STREAM_ABSENT_WARN_S);
  return derive_force_unit(s, c, err, len);
}

/* Smallest power of two >= n (n >= 1); SIZE_MAX / 2 + 1 at most, never a
 * wrap to 0 (a caller's size check then refuses it). */
static size_t power_of_two_at_least(size_t n)
{
  size_t p = 1;
  while (p < n && p <= SIZE_MAX / 4)
    p <<= 1;
  return p < n ? SIZE_MAX / 2 + 1 : p;
}

/* The strike detector on the force stream (strike_*). */
static af_status derive_detector(const af_settings *s, af_lane_config *c, char *err, size_t len)
{
  af_strike_config *d = &c->measured.strike;
  *d = af_strike_config_default(); /* every field is overwritten below */
  d->sample_rate_hz = c->force.sample_rate_hz;
  d->full_scale_n = num(s, AF_SETTING_STRIKE_FULL_SCALE_N);
  d->threshold_noise_factor = num(s, AF_SETTING_STRIKE_THRESHOLD_NOISE_FACTOR);
  d->threshold_min_n = num(s, AF_SETTING_STRIKE_THRESHOLD_MIN_N);
  d->pre_trigger_s = num(s, AF_SETTING_STRIKE_PRE_TRIGGER_S);
  d->baseline_time_constant_s = num(s, AF_SETTING_STRIKE_BASELINE_TIME_CONSTANT_S);
  d->baseline_window_s = num(s, AF_SETTING_STRIKE_BASELINE_WINDOW_S);
  d->double_hit_gap_s = num(s, AF_SETTING_STRIKE_DOUBLE_HIT_GAP_S);
  d->max_contact_s = num(s, AF_SETTING_STRIKE_MAX_CONTACT_S);
  d->post_s = num(s, AF_SETTING_STRIKE_POST_S);
  d->rise_fit_level = num(s, AF_SETTING_STRIKE_RISE_FIT_LEVEL);
  d->fall_fit_level = num(s, AF_SETTING_STRIKE_FALL_FIT_LEVEL);
  af_status st = check_order(s, AF_SETTING_STRIKE_BASELINE_WINDOW_S,
                             AF_SETTING_STRIKE_PRE_TRIGGER_S, err, len);
  if (st == AF_OK)
    st = check_order(s, AF_SETTING_STRIKE_BASELINE_WINDOW_S, AF_SETTING_STRIKE_POST_S, err, len);
  if (st == AF_OK && d->post_s < d->double_hit_gap_s) {
    say(err, len,
        "%s = %g must be at least %s = %g (a bounce must be ruled out before the strike is "
        "emitted)",
        name_of(s, AF_SETTING_STRIKE_POST_S).text, d->post_s,
        name_of(s, AF_SETTING_STRIKE_DOUBLE_HIT_GAP_S).text, d->double_hit_gap_s);
    st = AF_EINVAL;
  }
  if (st != AF_OK)
    return st;
  /* The longest span an event covers: pre-trigger, a contact and a bounce of
   * the longest kind, the gap between them, the wait after (strike.c). */
  double fs = d->sample_rate_hz;
  double span = ceil(d->pre_trigger_s * fs) + 2.0 * ceil(d->max_contact_s * fs) +
                ceil(d->double_hit_gap_s * fs) + ceil(d->post_s * fs) + 4.0;
  if (span > AF_SPAN_MAX_SAMPLES) {
    say(err, len,
        "%s, %s, %s and %s give an event span of %.0f samples at %g Hz, above the 2^24 "
        "accepted",
        name_of(s, AF_SETTING_STRIKE_PRE_TRIGGER_S).text,
        name_of(s, AF_SETTING_STRIKE_MAX_CONTACT_S).text,
        name_of(s, AF_SETTING_STRIKE_DOUBLE_HIT_GAP_S).text,
        name_of(s, AF_SETTING_STRIKE_POST_S).text, span, fs);
    return AF_EINVAL;
  }
  c->measured.pulse_capacity_samples = (size_t)span;
  return AF_OK;
}

/* The core's own check of the detector (it allocates: start-up only, after
 * check_memory). */
static af_status trial_detector(const af_settings *s, af_lane_config *c, char *err, size_t len)
{
  af_strike *trial = NULL;
  af_status st = af_strike_create(&c->measured.strike, &trial);
  af_strike_destroy(trial);
  if (st != AF_OK)
    say(err, len,
        "%s = %g Hz: the strike detector refuses the %sstrike_* parameters: %s (a window "
        "shorter than 2 samples?)",
        name_of(s, AF_SETTING_FORCE_SAMPLE_RATE_HZ).text, c->measured.strike.sample_rate_hz,
        s->name_prefix, af_strerror(st));
  return st;
}

/* The measurement of each strike (measure_*) and the pending queue. */
static af_status derive_measure(const af_settings *s, af_lane_config *c, char *err, size_t len)
{
  af_measured_config *mc = &c->measured;
  af_measure_config *m = &mc->measure;
  *m = af_measure_config_default(); /* the fit and response settings not exposed stay the core's */
  m->fit.fit_velocity = af_settings_bool(s, AF_SETTING_MEASURE_FIT_VELOCITY);
  m->audio_delay_s = num(s, AF_SETTING_MEASURE_AUDIO_DELAY_S);
  m->audio_window_s = num(s, AF_SETTING_MEASURE_AUDIO_WINDOW_S);
  m->noise_window_s = num(s, AF_SETTING_MEASURE_NOISE_WINDOW_S);
  m->noise_guard_s = num(s, AF_SETTING_MEASURE_NOISE_GUARD_S);
  m->range_margin = num(s, AF_SETTING_MEASURE_RANGE_MARGIN);
  mc->pending_size = (size_t)num(s, AF_SETTING_STRIKE_PENDING_SIZE);
  mc->apple_stale_after_s = num(s, AF_SETTING_APPLE_STALE_AFTER_S);
  mc->apple_wait_s = num(s, AF_SETTING_APPLE_WAIT_S);
  double fs = c->audio.sample_rate_hz;
  /* Rounded as the measurement rounds them (measure.c). */
  double window = round(m->audio_window_s * fs), noise = round(m->noise_window_s * fs);
  if (window < 8.0) {
    say(err, len, "%s = %g gives %.0f audio samples at %g Hz, fewer than the 8 the analysis needs",
        name_of(s, AF_SETTING_MEASURE_AUDIO_WINDOW_S).text, m->audio_window_s, window, fs);
    return AF_EINVAL;
  }
  if (noise > 0.0 && noise < 8.0) {
    say(err, len, "%s = %g gives %.0f audio samples at %g Hz: 0 (none) or at least 8",
        name_of(s, AF_SETTING_MEASURE_NOISE_WINDOW_S).text, m->noise_window_s, noise, fs);
    return AF_EINVAL;
  }
  /* The ring must hold the noise before the strike, the delay and the window. */
  double needed_s = m->noise_window_s + m->noise_guard_s + m->audio_delay_s + m->audio_window_s;
  if (!(needed_s < c->audio.buffer_s)) {
    say(err, len, "%s + %s + %s + %s = %g s must be below %s = %g s",
        name_of(s, AF_SETTING_MEASURE_NOISE_WINDOW_S).text,
        name_of(s, AF_SETTING_MEASURE_NOISE_GUARD_S).text,
        name_of(s, AF_SETTING_MEASURE_AUDIO_DELAY_S).text,
        name_of(s, AF_SETTING_MEASURE_AUDIO_WINDOW_S).text, needed_s,
        name_of(s, AF_SETTING_AUDIO_BUFFER_S).text, c->audio.buffer_s);
    return AF_EINVAL;
  }
  mc->audio_window_samples = (size_t)window;
  mc->noise_window_samples = (size_t)noise;
  /* The analysis holds the longer of the two windows, zero-padded 4 times. */
  af_response_config *rc = &m->response;
  rc->sample_rate_hz = fs;
  rc->window_samples = mc->audio_window_samples > mc->noise_window_samples
                           ? mc->audio_window_samples
                           : mc->noise_window_samples;
  rc->fft_size = power_of_two_at_least(4 * rc->window_samples);
  rc->snr_threshold_db = num(s, AF_SETTING_MEASURE_SNR_THRESHOLD_DB);
  /* The fit: the strike's own damping law; sized for the longest contact. */
  m->fit.damping = c->model.impact.damping;
  size_t longest = (size_t)ceil(mc->strike.max_contact_s * c->force.sample_rate_hz) + 2;
  if (longest > m->fit.max_samples)
    m->fit.max_samples = longest;
  return AF_OK;
}

/* The core's own check of the measurement (it allocates: start-up only,
 * after check_memory). */
static af_status trial_measure(const af_settings *s, af_lane_config *c, char *err, size_t len)
{
  af_measure *trial = NULL;
  af_status st = af_measure_create(&c->measured.measure, &trial);
  af_measure_destroy(trial);
  if (st != AF_OK)
    say(err, len, "%s = %g Hz: the strike measurement refuses the %smeasure_* parameters: %s",
        name_of(s, AF_SETTING_AUDIO_SAMPLE_RATE_HZ).text, c->audio.sample_rate_hz, s->name_prefix,
        af_strerror(st));
  return st;
}

/* ---- the lane's memory, bounded before anything is allocated ---------------- */

/* Smallest power of two >= n, as a double (no wrap for any n). */
static double pow2_at_least(double n)
{
  double p = 1.0;
  while (p < n && p < 0x1p62)
    p *= 2.0;
  return p;
}

void af_lane_config_memory(const af_lane_config *c, af_lane_memory *m)
{
  memset(m, 0, sizeof *m);
  const af_measured_config *mc = &c->measured;
  /* float rings */
  m->rings = 4.0 * ((double)c->force.capacity_samples + (double)c->audio.capacity_samples);
  /* detector: its float ring (span + a block), the span as float and twice
   * as double, the priming sample; the queue's pulses (double) and the
   * audio and noise windows (float) */
  const double span = (double)mc->pulse_capacity_samples;
  m->detector_queue = 4.0 * (span + 1024.0) + 20.0 * span + 8.0 * 8192.0 +
                      (double)mc->pending_size * (8.0 * span + 256.0) +
                      4.0 * ((double)mc->audio_window_samples + (double)mc->noise_window_samples);
  /* microphone analysis: the FFT input, its complex and real spectra, the
   * mode analysis's work arrays, FFTW's plan (its twiddles about one complex
   * per point): 86 bytes per FFT point measured (test_settings), counted as
   * 128 so that a buffer added there does not outgrow the estimate */
  const double fft = (double)mc->measure.response.fft_size;
  m->microphone = 128.0 * fft + 8.0 * (double)mc->measure.response.window_samples;
  /* pulse fit (GSL's n x p workspace and the oversampled model buffers)
   * and the pulse's spectrum (4 x zero-padded) */
  const double n = (double)mc->measure.fit.max_samples;
  const double over = (double)mc->measure.fit.oversample;
  const double ms = n > 1024.0 ? n : 1024.0, sfft = pow2_at_least(4.0 * ms);
  m->fit_spectrum = 16.0 * (4.0 * n * over + 1.0) + 16.0 * n + 8.0 * n * 20.0 + 8.0 * sfft +
                    (sfft / 2.0 + 1.0) * 24.0 + 16.0 * sfft + 64.0 * (ms / 2.0 + 1.0);
  /* the model workspace (fixed: 4096-point FFT, 1024 samples) and the
   * objects themselves */
  m->fixed = 1048576.0;
  m->total = m->rings + m->detector_queue + m->microphone + m->fit_spectrum + m->fixed;
}

static af_status check_memory(const af_settings *s, const af_lane_config *c, char *err, size_t len)
{
  af_lane_memory m;
  af_lane_config_memory(c, &m);
  if (m.total <= (double)AF_LANE_MEMORY_MAX_BYTES)
    return AF_OK;
  const double mib = 1048576.0;
  say(err, len,
      "the lane would allocate about %.0f MiB (rings %.0f: %sforce_buffer_s x "
      "%sforce_sample_rate_hz + %saudio_buffer_s x %saudio_sample_rate_hz; detector and queue "
      "%.0f: %sstrike_* x %sstrike_pending_size; microphone analysis %.0f: "
      "%smeasure_audio_window_s; pulse fit %.0f: %sstrike_max_contact_s), above the %.0f MiB "
      "accepted",
      m.total / mib, m.rings / mib, s->name_prefix, s->name_prefix, s->name_prefix, s->name_prefix,
      m.detector_queue / mib, s->name_prefix, s->name_prefix, m.microphone / mib, s->name_prefix,
      m.fit_spectrum / mib, s->name_prefix, AF_LANE_MEMORY_MAX_BYTES / mib);
  return AF_EINVAL;
}

/* The parameters behind a field of af_model_params, for the messages. */
typedef struct {
  const char *field;
  af_setting_id ids[3];
  int n;
  const char *note;
} af_field_source;

static const af_field_source field_sources[] = {
    {"impact.hammer_mass_kg", {AF_SETTING_HAMMER_MASS_KG}, 1, " (or the URDF hammer mass)"},
    {"impact.velocity_m_s", {AF_SETTING_STRIKE_VELOCITY_M_S}, 1, ""},
    {"impact.hammer_modulus_pa", {AF_SETTING_HAMMER_MODULUS_PA}, 1, ""},
    {"impact.hammer_poisson", {AF_SETTING_HAMMER_POISSON}, 1, ""},
    {"impact.hammer_radius_m", {AF_SETTING_HAMMER_TIP_RADIUS_M}, 1, " (or the URDF tip radius)"},
    {"impact.fruit_modulus_pa",
     {AF_SETTING_MODULUS_NOMINAL_PA, AF_SETTING_MODULUS_MIN_PA, AF_SETTING_MODULUS_MAX_PA},
     3,
     ""},
    {"impact.fruit_poisson", {AF_SETTING_FRUIT_POISSON}, 1, ""},
    {"impact.strike_radius_m", {AF_SETTING_R2_SEARCH_LOW_M, AF_SETTING_R2_SEARCH_HIGH_M}, 2, ""},
    {"impact.restitution", {AF_SETTING_RESTITUTION}, 1, ""},
    {"impact.gravity_m_s2", {AF_SETTING_GRAVITY_M_S2}, 1, ""},
    {"impact.damping", {AF_SETTING_DAMPING_LAW}, 1, ""},
    {"fruit_mass_kg", {AF_SETTING_MASS_MIN_KG, AF_SETTING_MASS_MAX_KG}, 2, ""},
    {"fruit_density_kg_m3", {AF_SETTING_DENSITY_KG_M3}, 1, ""},
    {"modulus_factor", {AF_SETTING_MODULUS_FACTOR}, 1, ""},
    {"lobe", {AF_SETTING_LOBE}, 1, ""},
    {"band_level", {AF_SETTING_BAND_LEVEL}, 1, ""},
    {"shear_ratio", {AF_SETTING_SHEAR_RATIO}, 1, ""},
    {"yield_ratio", {AF_SETTING_YIELD_RATIO}, 1, ""},
    {"yield_exponent", {AF_SETTING_YIELD_EXPONENT}, 1, ""},
    {"yield_reference_modulus_pa", {AF_SETTING_YIELD_REFERENCE_MODULUS_PA}, 1, ""},
    {"yield_measured", {AF_SETTING_YIELD_MEASURED}, 1, ""},
};

/* "~a / ~b (note)" for field, or the field itself. */
static void field_parameters(const af_settings *s, const char *field, char *buf, size_t len)
{
  snprintf(buf, len, "%s", field);
  for (size_t k = 0; k < sizeof field_sources / sizeof field_sources[0]; k++) {
    const af_field_source *f = &field_sources[k];
    if (strcmp(f->field, field) != 0)
      continue;
    buf[0] = '\0';
    for (int j = 0; j < f->n; j++)
      snprintf(buf + strlen(buf), len - strlen(buf), "%s%s", j ? " / " : "",
               name_of(s, f->ids[j]).text);
    snprintf(buf + strlen(buf), len - strlen(buf), "%s", f->note);
    return;
  }
}

/* The core's own check over the corners the lane will evaluate: the
 * extreme masses and moduli, and both ends of the R2 search. */
static af_status check_model(const af_settings *s, const af_lane_config *c, char *err, size_t len)
{
  const double masses[] = {c->mass_min_kg, c->mass_max_kg};
  const double moduli[] = {c->model.impact.fruit_modulus_pa, c->modulus_min_pa, c->modulus_max_pa};
  const double radii[] = {c->r2_search_low_m, c->r2_search_high_m};
  for (size_t i = 0; i < 2; i++)
    for (size_t j = 0; j < 3; j++)
      for (size_t k = 0; k < 2; k++) {
        af_model_params p = c->model;
        af_param_error e;
        p.fruit_mass_kg = masses[i];
        p.impact.fruit_modulus_pa = moduli[j];
        p.impact.strike_radius_m = radii[k];
        if (af_model_params_check(&p, &e) == AF_OK)
          continue;
        char names[256];
        field_parameters(s, e.field, names, sizeof names);
        say(err, len, "%s: %s = %g is outside the accepted range %s", names, e.field, e.value,
            e.range);
        return AF_EINVAL;
      }
  return AF_OK;
}

af_status af_lane_config_derive(const af_settings *s, af_lane_config *out, char *err, size_t len)
{
  if (s == NULL || out == NULL) {
    say(err, len, "af_lane_config_derive: s or out is NULL");
    return AF_EINVAL;
  }
  memset(out, 0, sizeof *out);
  af_status st = check_values(s, err, len);
  if (st == AF_OK)
    st = derive_strike(s, out, err, len);
  if (st == AF_OK)
    st = derive_cultivar(s, out, err, len);
  if (st == AF_OK)
    st = derive_streams(s, out, err, len);
  if (st == AF_OK)
    st = derive_detector(s, out, err, len);
  if (st == AF_OK)
    st = derive_measure(s, out, err, len);
  if (st == AF_OK)
    st = af_grade_config_from_settings(s, &out->grade, err, len);
  if (st == AF_OK)
    st = check_memory(s, out, err, len);
  if (st == AF_OK)
    st = trial_detector(s, out, err, len);
  if (st == AF_OK)
    st = trial_measure(s, out, err, len);
  if (st != AF_OK)
    return st;
  out->model.impact.hammer_mass_kg = num(s, AF_SETTING_HAMMER_MASS_KG);
  out->model.impact.hammer_radius_m = num(s, AF_SETTING_HAMMER_TIP_RADIUS_M);
  return check_model(s, out, err, len);
}
