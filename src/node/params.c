/* params.c — loads and validates firmness_node's parameters and the URDF. */
#include "params.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "measure.h"
#include "resonance.h"
#include "strike.h"
#include "text.h"

#ifndef M_PI /* strict C11 <math.h> does not define it */
#define M_PI 3.14159265358979323846
#endif

/* A ring longer than this is a typo, not a buffer (400 MB of float). */
#define AF_RING_MAX_SAMPLES 100000000.0

/* One double parameter with its accepted range. */
typedef struct {
  const char *name; /* under ~ */
  double *dst;
  double lo, hi;
  bool lo_open, hi_open;
  const char *unit; /* for the messages; "" when dimensionless */
} af_double_param;

static void range_text(const af_double_param *d, char *buf, size_t len)
{
  char hi[32];
  if (isinf(d->hi))
    snprintf(hi, sizeof hi, "inf");
  else
    snprintf(hi, sizeof hi, "%g", d->hi);
  snprintf(buf, len, "%c%g, %s%c%s%s", d->lo_open ? '(' : '[', d->lo, hi, d->hi_open ? ')' : ']',
           d->unit[0] ? " " : "", d->unit);
}

static bool in_range(const af_double_param *d, double v)
{
  if (!isfinite(v))
    return false;
  if (d->lo_open ? !(v > d->lo) : !(v >= d->lo))
    return false;
  return d->hi_open ? v < d->hi : v <= d->hi;
}

/* Explains a status of af_ros_param_* for a required parameter. */
static af_status missing_or_wrong(af_status st, const char *name, const char *expected, char *err,
                                  size_t len)
{
  if (st == AF_ENODATA)
    af_text(err, len,
            "parameter ~%s is missing (expected %s; defaults are in config/station.yaml "
            "and the cultivar YAML)",
            name, expected);
  else
    af_text(err, len, "parameter ~%s has the wrong type or could not be read (expected %s)", name,
            expected);
  return AF_EINVAL;
}

static af_status get_double(af_ros *r, const af_double_param *d, char *err, size_t len)
{
  char range[96];
  range_text(d, range, sizeof range);
  af_status st = af_ros_param_double(r, d->name, d->dst);
  if (st == AF_EINVAL) {
    af_text(err, len,
            "parameter ~%s is not a number (expected %s; YAML 1.1 reads 8.0e6 as a "
            "string: write 8.0e+6)",
            d->name, range);
    return AF_EINVAL;
  }
  if (st != AF_OK)
    return missing_or_wrong(st, d->name, range, err, len);
  if (!in_range(d, *d->dst)) {
    af_text(err, len, "parameter ~%s = %g is outside the accepted range %s", d->name, *d->dst,
            range);
    return AF_EINVAL;
  }
  return AF_OK;
}

static af_status get_doubles(af_ros *r, const af_double_param *table, size_t n, char *err,
                             size_t len)
{
  for (size_t k = 0; k < n; k++) {
    af_status st = get_double(r, &table[k], err, len);
    if (st != AF_OK)
      return st;
  }
  return AF_OK;
}

static af_status get_string(af_ros *r, const char *name, char *buf, size_t size, char *err,
                            size_t len)
{
  af_status st = af_ros_param_string(r, name, buf, size);
  if (st == AF_ESIZE) {
    af_text(err, len, "parameter ~%s is longer than %zu characters", name, size - 1);
    return AF_EINVAL;
  }
  return st == AF_OK ? AF_OK : missing_or_wrong(st, name, "a string", err, len);
}

/* A string parameter naming one of a few choices, parsed by the core. */
static af_status get_choice(af_ros *r, const char *name, const char *choices,
                            af_status (*parse)(const char *, void *), void *out, char *err,
                            size_t len)
{
  char text[AF_NAME_MAX];
  af_status st = get_string(r, name, text, sizeof text, err, len);
  if (st != AF_OK)
    return st;
  if (parse(text, out) != AF_OK) {
    af_text(err, len, "parameter ~%s = '%s' is not one of: %s", name, text, choices);
    return AF_EINVAL;
  }
  return AF_OK;
}

/* Adapters with the common signature of get_choice. */
static af_status parse_damping(const char *s, void *out)
{
  return af_damping_law_parse(s, out);
}
static af_status parse_band(const char *s, void *out)
{
  return af_band_level_parse(s, out);
}
static af_status parse_shear(const char *s, void *out)
{
  return af_shear_ratio_parse(s, out);
}

static af_status check_order(const char *lo_name, double lo, const char *hi_name, double hi,
                             char *err, size_t len)
{
  if (lo < hi)
    return AF_OK;
  af_text(err, len, "parameter ~%s = %g must be below ~%s = %g", lo_name, lo, hi_name, hi);
  return AF_EINVAL;
}

static af_status load_strike(af_ros *r, af_node_config *c, char *err, size_t len)
{
  af_model_params *m = &c->lane.model;
  af_impact_params *i = &m->impact;
  double latitude_tolerance_deg, lobe;
  const af_double_param table[] = {
      {"strike_velocity_m_s", &i->velocity_m_s, 0.0, 10.0, true, false, "m/s"},
      {"gravity_m_s2", &i->gravity_m_s2, 0.0, 20.0, false, false, "m/s2"},
      {"hammer_modulus_pa", &i->hammer_modulus_pa, 0.0, INFINITY, false, true, "Pa (0 = rigid)"},
      {"hammer_poisson", &i->hammer_poisson, 0.0, 0.5, false, true, ""},
      {"lobe", &lobe, 1.0, AF_MODEL_MAX_LOBES, false, false, "(1 = main lobe)"},
      {"latitude_tolerance_deg", &latitude_tolerance_deg, 0.0, 90.0, false, false, "deg"},
      {"r2_search_low_m", &c->lane.r2_search_low_m, 0.0, 1.0, true, false, "m"},
      {"r2_search_high_m", &c->lane.r2_search_high_m, 0.0, 1.0, true, false, "m"},
      {"strike_radius_min_m", &c->lane.strike_radius_min_m, 0.0, 1.0, true, false, "m"},
      {"strike_radius_max_m", &c->lane.strike_radius_max_m, 0.0, 1.0, true, false, "m"},
  };
  af_status st = get_doubles(r, table, sizeof table / sizeof table[0], err, len);
  if (st == AF_OK && lobe != floor(lobe)) {
    af_text(err, len, "parameter ~lobe = %g must be a whole number in [1, %d]", lobe,
            AF_MODEL_MAX_LOBES);
    st = AF_EINVAL;
  }
  if (st == AF_OK)
    st = get_choice(r, "damping_law", "paper, exact, hu-guo", parse_damping, &i->damping, err, len);
  if (st == AF_OK)
    st = get_choice(r, "band_level", "power-half, amplitude-half", parse_band, &m->band_level, err,
                    len);
  if (st == AF_OK)
    st = get_choice(r, "shear_ratio", "paper, exact", parse_shear, &m->shear_ratio, err, len);
  if (st == AF_OK)
    st = check_order("r2_search_low_m", c->lane.r2_search_low_m, "r2_search_high_m",
                     c->lane.r2_search_high_m, err, len);
  if (st == AF_OK)
    st = check_order("strike_radius_min_m", c->lane.strike_radius_min_m, "strike_radius_max_m",
                     c->lane.strike_radius_max_m, err, len);
  m->lobe = (unsigned)lobe;
  c->lane.latitude_tolerance_rad = latitude_tolerance_deg * M_PI / 180.0;
  return st;
}

static af_status load_stream(af_ros *r, const char *prefix, af_stream_config *s, char *err,
                             size_t len)
{
  char rate_name[64], buffer_name[64];
  snprintf(rate_name, sizeof rate_name, "%s_sample_rate_hz", prefix);
  snprintf(buffer_name, sizeof buffer_name, "%s_buffer_s", prefix);
  const af_double_param table[] = {
      {rate_name, &s->sample_rate_hz, 0.0, 10e6, true, false, "Hz"},
      {buffer_name, &s->buffer_s, 0.0, 3600.0, true, false, "s"},
  };
  af_status st = get_doubles(r, table, 2, err, len);
  if (st != AF_OK)
    return st;
  double samples = ceil(s->buffer_s * s->sample_rate_hz);
  if (samples > AF_RING_MAX_SAMPLES) {
    af_text(err, len,
            "parameters ~%s = %g and ~%s = %g make a ring of %.0f samples, above the %.0f "
            "accepted",
            buffer_name, s->buffer_s, rate_name, s->sample_rate_hz, samples, AF_RING_MAX_SAMPLES);
    return AF_EINVAL;
  }
  s->capacity_samples = (size_t)samples;
  return AF_OK;
}

static af_status load_streams(af_ros *r, af_node_config *c, char *err, size_t len)
{
  af_status st = load_stream(r, "force", &c->lane.force, err, len);
  if (st == AF_OK)
    st = load_stream(r, "audio", &c->lane.audio, err, len);
  if (st != AF_OK)
    return st;
  /* The force transducer speaks newtons; the microphone pascals or volts. */
  snprintf(c->lane.force.units[0], AF_UNIT_MAX, "N");
  st = get_string(r, "audio_unit", c->lane.audio.units[0], AF_UNIT_MAX, err, len);
  if (st == AF_OK && strcmp(c->lane.audio.units[0], "Pa") != 0 &&
      strcmp(c->lane.audio.units[0], "V") != 0) {
    af_text(err, len, "parameter ~audio_unit = '%s' is not one of: Pa, V", c->lane.audio.units[0]);
    st = AF_EINVAL;
  }
  const af_double_param stale = {
      "stream_stale_after_s", &c->lane.stream_stale_after_s, 0.0, INFINITY, true, true, "s"};
  return st == AF_OK ? get_double(r, &stale, err, len) : st;
}

/* Smallest power of two >= n (n >= 1). */
static size_t power_of_two_at_least(size_t n)
{
  size_t p = 1;
  while (p < n)
    p <<= 1;
  return p;
}

/* The strike detector on the force stream (~strike_*). */
static af_status load_detector(af_ros *r, af_node_config *c, char *err, size_t len)
{
  af_strike_config *d = &c->lane.measured.strike;
  *d = af_strike_config_default(); /* every field is overwritten below */
  d->sample_rate_hz = c->lane.force.sample_rate_hz;
  const af_double_param table[] = {
      {"strike_full_scale_n", &d->full_scale_n, 0.0, 1e6, true, false, "N"},
      {"strike_threshold_noise_factor", &d->threshold_noise_factor, 0.0, 1e3, true, false,
       "(x noise RMS)"},
      {"strike_threshold_min_n", &d->threshold_min_n, 0.0, 1e6, false, false, "N"},
      {"strike_pre_trigger_s", &d->pre_trigger_s, 0.0, 1.0, true, false, "s"},
      {"strike_baseline_time_constant_s", &d->baseline_time_constant_s, 0.0, 10.0, true, false,
       "s"},
      {"strike_baseline_window_s", &d->baseline_window_s, 0.0, 1.0, true, false, "s"},
      {"strike_double_hit_gap_s", &d->double_hit_gap_s, 0.0, 1.0, false, false, "s"},
      {"strike_max_contact_s", &d->max_contact_s, 0.0, 1.0, true, false, "s"},
      {"strike_post_s", &d->post_s, 0.0, 1.0, true, false, "s"},
      {"strike_rise_fit_level", &d->rise_fit_level, 0.0, 1.0, true, true, "(of the peak)"},
      {"strike_fall_fit_level", &d->fall_fit_level, 0.0, 1.0, true, true, "(of the peak)"},
  };
  af_status st = get_doubles(r, table, sizeof table / sizeof table[0], err, len);
  if (st == AF_OK)
    st = check_order("strike_baseline_window_s", d->baseline_window_s, "strike_pre_trigger_s",
                     d->pre_trigger_s, err, len);
  if (st == AF_OK)
    st = check_order("strike_baseline_window_s", d->baseline_window_s, "strike_post_s", d->post_s,
                     err, len);
  if (st == AF_OK && d->post_s < d->double_hit_gap_s) {
    af_text(err, len,
            "parameter ~strike_post_s = %g must be at least ~strike_double_hit_gap_s = %g (a "
            "bounce must be ruled out before the strike is emitted)",
            d->post_s, d->double_hit_gap_s);
    st = AF_EINVAL;
  }
  if (st != AF_OK)
    return st;
  /* The longest span an event covers: pre-trigger, a contact and a bounce of
   * the longest kind, the gap between them, the wait after (strike.c). */
  double fs = d->sample_rate_hz;
  double span = ceil(d->pre_trigger_s * fs) + 2.0 * ceil(d->max_contact_s * fs) +
                ceil(d->double_hit_gap_s * fs) + ceil(d->post_s * fs) + 4.0;
  if (span > 16777216.0) {
    af_text(err, len,
            "parameters ~strike_pre_trigger_s, ~strike_max_contact_s, ~strike_double_hit_gap_s "
            "and ~strike_post_s give an event span of %.0f samples at %g Hz, above the 2^24 "
            "accepted",
            span, fs);
    return AF_EINVAL;
  }
  c->lane.measured.pulse_capacity_samples = (size_t)span;
  /* The core's own check (it also allocates: start-up only). */
  af_strike *trial = NULL;
  st = af_strike_create(d, &trial);
  af_strike_destroy(trial);
  if (st != AF_OK)
    af_text(err, len,
            "the strike detector refuses the ~strike_* parameters at ~force_sample_rate_hz = %g "
            "Hz: %s (a window shorter than 2 samples?)",
            fs, af_strerror(st));
  return st;
}

/* The measurement of each strike (~measure_*) and the pending queue. */
static af_status load_measure(af_ros *r, af_node_config *c, char *err, size_t len)
{
  af_measured_config *mc = &c->lane.measured;
  af_measure_config *m = &mc->measure;
  *m = af_measure_config_default(); /* the fit and response settings not exposed stay the core's */
  double pending, snr_db;
  const af_double_param table[] = {
      {"measure_audio_delay_s", &m->audio_delay_s, 0.0, 1.0, false, false, "s"},
      {"measure_audio_window_s", &m->audio_window_s, 0.0, 1.0, true, false, "s"},
      {"measure_noise_window_s", &m->noise_window_s, 0.0, 1.0, false, false, "s (0 = none)"},
      {"measure_noise_guard_s", &m->noise_guard_s, 0.0, 1.0, false, false, "s"},
      {"measure_range_margin", &m->range_margin, 0.0, 1.0, false, true, "(relative)"},
      {"measure_snr_threshold_db", &snr_db, -100.0, 100.0, false, false, "dB"},
      {"strike_pending_size", &pending, 1.0, 1000.0, false, false, "strikes"},
      {"apple_stale_after_s", &mc->apple_stale_after_s, 0.0, 3600.0, true, false, "s"},
  };
  af_status st = af_ros_param_bool(r, "measure_fit_velocity", &m->fit.fit_velocity);
  if (st != AF_OK)
    return missing_or_wrong(st, "measure_fit_velocity", "true or false", err, len);
  st = get_doubles(r, table, sizeof table / sizeof table[0], err, len);
  if (st != AF_OK)
    return st;
  if (pending != floor(pending)) {
    af_text(err, len, "parameter ~strike_pending_size = %g must be a whole number in [1, 1000]",
            pending);
    return AF_EINVAL;
  }
  mc->pending_size = (size_t)pending;
  double fs = c->lane.audio.sample_rate_hz;
  /* Rounded as the measurement rounds them (measure.c). */
  double window = round(m->audio_window_s * fs), noise = round(m->noise_window_s * fs);
  if (window < 8.0) {
    af_text(err, len,
            "parameter ~measure_audio_window_s = %g gives %.0f audio samples at %g Hz, fewer "
            "than the 8 the analysis needs",
            m->audio_window_s, window, fs);
    return AF_EINVAL;
  }
  if (noise > 0.0 && noise < 8.0) {
    af_text(err, len,
            "parameter ~measure_noise_window_s = %g gives %.0f audio samples at %g Hz: 0 (none) "
            "or at least 8",
            m->noise_window_s, noise, fs);
    return AF_EINVAL;
  }
  /* The ring must hold the noise before the strike, the delay and the window. */
  double needed_s = m->noise_window_s + m->noise_guard_s + m->audio_delay_s + m->audio_window_s;
  if (!(needed_s < c->lane.audio.buffer_s)) {
    af_text(
        err, len,
        "parameters ~measure_noise_window_s + ~measure_noise_guard_s + ~measure_audio_delay_s + "
        "~measure_audio_window_s = %g s must be below ~audio_buffer_s = %g s",
        needed_s, c->lane.audio.buffer_s);
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
  rc->snr_threshold_db = snr_db;
  /* The fit: the strike's own damping law; sized for the longest contact. */
  m->fit.damping = c->lane.model.impact.damping;
  size_t longest = (size_t)ceil(mc->strike.max_contact_s * c->lane.force.sample_rate_hz) + 2;
  if (longest > m->fit.max_samples)
    m->fit.max_samples = longest;
  /* The core's own check (it also allocates: start-up only). */
  af_measure *trial = NULL;
  st = af_measure_create(m, &trial);
  af_measure_destroy(trial);
  if (st != AF_OK)
    af_text(err, len,
            "the strike measurement refuses the ~measure_* parameters at "
            "~audio_sample_rate_hz = %g Hz: %s",
            fs, af_strerror(st));
  return st;
}

static af_status load_markers(af_ros *r, af_node_config *c, char *err, size_t len)
{
  af_status st = af_ros_param_bool(r, "markers_enabled", &c->markers_enabled);
  if (st != AF_OK)
    return missing_or_wrong(st, "markers_enabled", "true or false", err, len);
  const af_double_param table[] = {
      {"marker_lifetime_s", &c->marker_lifetime_s, 0.0, INFINITY, false, true, "s (0 = forever)"},
      {"marker_strike_distance_m", &c->marker_strike_distance_m, 0.0, 10.0, false, false, "m"},
      {"marker_arrow_length_m", &c->marker_arrow_length_m, 0.0, 10.0, true, false, "m"},
  };
  return get_doubles(r, table, sizeof table / sizeof table[0], err, len);
}

static af_status load_cultivar(af_ros *r, af_node_config *c, char *err, size_t len)
{
  af_model_params *m = &c->lane.model;
  af_impact_params *i = &m->impact;
  const af_double_param table[] = {
      {"modulus_nominal_pa", &i->fruit_modulus_pa, 0.0, INFINITY, true, true, "Pa"},
      {"modulus_min_pa", &c->lane.modulus_min_pa, 0.0, INFINITY, true, true, "Pa"},
      {"modulus_max_pa", &c->lane.modulus_max_pa, 0.0, INFINITY, true, true, "Pa"},
      {"mass_min_kg", &c->lane.mass_min_kg, 0.0, 10.0, true, false, "kg"},
      {"mass_max_kg", &c->lane.mass_max_kg, 0.0, 10.0, true, false, "kg"},
      {"equatorial_radius_min_m", &c->lane.equatorial_radius_min_m, 0.0, 1.0, true, false, "m"},
      {"equatorial_radius_max_m", &c->lane.equatorial_radius_max_m, 0.0, 1.0, true, false, "m"},
      {"aspect_ratio_min", &c->lane.aspect_ratio_min, 0.0, INFINITY, true, true, ""},
      {"aspect_ratio_max", &c->lane.aspect_ratio_max, 0.0, INFINITY, true, true, ""},
      {"restitution", &i->restitution, 0.0, 1.0, true, false, ""},
      {"fruit_poisson", &i->fruit_poisson, 0.0, 0.5, false, true, ""},
      {"density_kg_m3", &m->fruit_density_kg_m3, 0.0, INFINITY, true, true, "kg/m3"},
      {"yield_ratio", &m->yield_ratio, 0.0, 1.0, true, false, "(calibration, tau_y / E2)"},
      {"modulus_factor", &m->modulus_factor, 0.0, INFINITY, true, true, "(dynamic / static)"},
  };
  af_status st = get_string(r, "cultivar", c->lane.cultivar, sizeof c->lane.cultivar, err, len);
  if (st == AF_OK)
    st = get_doubles(r, table, sizeof table / sizeof table[0], err, len);
  if (st == AF_OK && !(c->lane.modulus_min_pa <= i->fruit_modulus_pa &&
                       i->fruit_modulus_pa <= c->lane.modulus_max_pa)) {
    af_text(err, len,
            "parameter ~modulus_nominal_pa = %g must lie in [~modulus_min_pa, "
            "~modulus_max_pa] = [%g, %g] Pa",
            i->fruit_modulus_pa, c->lane.modulus_min_pa, c->lane.modulus_max_pa);
    st = AF_EINVAL;
  }
  if (st == AF_OK)
    st = check_order("modulus_min_pa", c->lane.modulus_min_pa, "modulus_max_pa",
                     c->lane.modulus_max_pa, err, len);
  if (st == AF_OK)
    st = check_order("mass_min_kg", c->lane.mass_min_kg, "mass_max_kg", c->lane.mass_max_kg, err,
                     len);
  if (st == AF_OK)
    st = check_order("equatorial_radius_min_m", c->lane.equatorial_radius_min_m,
                     "equatorial_radius_max_m", c->lane.equatorial_radius_max_m, err, len);
  if (st == AF_OK)
    st = check_order("aspect_ratio_min", c->lane.aspect_ratio_min, "aspect_ratio_max",
                     c->lane.aspect_ratio_max, err, len);
  if (st == AF_OK && af_resonance_lamb_root(i->fruit_poisson, &c->lane.resonance_xi) != AF_OK) {
    af_text(err, len, "parameter ~fruit_poisson = %g: no 0S2 root of Lamb's equation found",
            i->fruit_poisson);
    st = AF_EINVAL;
  }
  return st;
}

/* An optional override: *given false when absent. */
static af_status get_override(af_ros *r, const af_double_param *d, bool zero_means_absent,
                              bool *given, char *err, size_t len)
{
  char range[96];
  range_text(d, range, sizeof range);
  af_status st = af_ros_param_double(r, d->name, d->dst);
  *given = st == AF_OK && !(zero_means_absent && *d->dst == 0.0);
  if (st == AF_ENODATA || (st == AF_OK && !*given))
    return AF_OK;
  if (st != AF_OK)
    return missing_or_wrong(st, d->name, range, err, len);
  if (!in_range(d, *d->dst)) {
    af_text(err, len, "parameter ~%s = %g is outside the accepted range %s%s", d->name, *d->dst,
            range,
            zero_means_absent ? " (0 or absent = from the URDF)" : " (absent = from the URDF)");
    return AF_EINVAL;
  }
  return AF_OK;
}

/* The directory part of the node's resolved name, e.g. "/lane1/". */
static void node_namespace(const af_ros *r, char *buf, size_t len)
{
  snprintf(buf, len, "%s", af_ros_node_name(r));
  char *slash = strrchr(buf, '/');
  if (slash)
    slash[1] = '\0';
}

/* Reads the URDF from ~urdf_file or robot_description into cfg->urdf. */
static af_status read_urdf(af_ros *r, af_node_config *c, char *uerr, size_t ulen)
{
  if (c->urdf_file[0]) {
    af_text(c->urdf_source, sizeof c->urdf_source, "file %s (~urdf_file)", c->urdf_file);
    return af_urdf_load(c->urdf_file, &c->urdf, uerr, ulen);
  }
  char ns[AF_SOURCE_TEXT_MAX / 2];
  node_namespace(r, ns, sizeof ns);
  af_text(c->urdf_source, sizeof c->urdf_source, "parameter %srobot_description", ns);
  size_t size = af_ros_param_string_size(r, "robot_description", false);
  if (size == 0) {
    af_text(uerr, ulen, "not set (and ~urdf_file is empty)");
    return AF_ENODATA;
  }
  char *xml = malloc(size); /* start-up only */
  if (!xml)
    return AF_ENOMEM;
  af_status st = af_ros_param_string_global(r, "robot_description", xml, size);
  if (st == AF_OK)
    st = af_urdf_parse(xml, &c->urdf, uerr, ulen);
  else
    af_text(uerr, ulen, "parameter %srobot_description could not be read as a string: %s", ns,
            af_ros_last_error(r));
  free(xml);
  return st;
}

static af_status load_hammer(af_ros *r, af_node_config *c, char *err, size_t len)
{
  af_status st = get_string(r, "hammer_link", c->hammer_link, sizeof c->hammer_link, err, len);
  if (st == AF_OK)
    st = get_string(r, "urdf_file", c->urdf_file, sizeof c->urdf_file, err, len);
  double mass_kg = 0.0, tip_m = 0.0;
  bool mass_given = false, tip_given = false;
  const af_double_param mass = {"hammer_mass_kg", &mass_kg, 0.0, 1.0, true, false, "kg"};
  const af_double_param tip = {"hammer_tip_radius_m", &tip_m, 0.0, 0.1, false, false,
                               "m (0 = flat face)"};
  if (st == AF_OK)
    st = get_override(r, &mass, true, &mass_given, err, len);
  if (st == AF_OK)
    st = get_override(r, &tip, false, &tip_given, err, len);
  if (st != AF_OK)
    return st;

  char uerr[AF_TEXT_MAX] = "";
  st = read_urdf(r, c, uerr, sizeof uerr);
  if (st == AF_OK)
    st = af_urdf_hammer(c->urdf, c->hammer_link, &c->hammer, uerr, sizeof uerr);
  if (st == AF_ENOMEM)
    return st;
  if (st == AF_OK)
    st = af_urdf_position_in_root(c->urdf, c->hammer_link, &c->hammer_origin_m);
  c->hammer_axis_known = st == AF_OK;
  if (st != AF_OK) {
    af_urdf_destroy(c->urdf);
    c->urdf = NULL;
    memset(&c->hammer, 0, sizeof c->hammer);
    if (!(mass_given && tip_given)) {
      af_text(err, len,
              "URDF from %s: %s; the hammer%s%s must come from it unless ~hammer_mass_kg "
              "and ~hammer_tip_radius_m are both given",
              c->urdf_source, uerr, mass_given ? "" : "'s mass",
              tip_given ? "" : (mass_given ? "'s tip radius" : " and tip radius"));
      return st == AF_EINVAL ? AF_EINVAL : AF_ENODATA;
    }
    /* Runs on parameters alone; the strike axis stays unknown. */
    char why[AF_SOURCE_TEXT_MAX];
    af_text(why, sizeof why, "none (%s: %s)", c->urdf_source, uerr);
    af_text(c->urdf_source, sizeof c->urdf_source, "%s", why);
  }
  snprintf(c->hammer_mass_source, sizeof c->hammer_mass_source, "%s%s",
           mass_given ? "parameter ~hammer_mass_kg" : "URDF link ",
           mass_given ? "" : c->hammer_link);
  snprintf(c->hammer_tip_source, sizeof c->hammer_tip_source, "%s%s",
           tip_given ? "parameter ~hammer_tip_radius_m" : "URDF link ",
           tip_given ? "" : c->hammer_link);
  if (mass_given)
    c->hammer.mass_kg = mass_kg;
  if (tip_given)
    c->hammer.tip_radius_m = tip_m;
  c->lane.model.impact.hammer_mass_kg = c->hammer.mass_kg;
  c->lane.model.impact.hammer_radius_m = c->hammer.tip_radius_m;
  return AF_OK;
}

/* The parameter behind a field of af_model_params, for the messages. */
static const char *param_of_field(const char *field)
{
  static const char *const map[][2] = {
      {"impact.hammer_mass_kg", "hammer_mass_kg (or the URDF hammer mass)"},
      {"impact.velocity_m_s", "strike_velocity_m_s"},
      {"impact.hammer_modulus_pa", "hammer_modulus_pa"},
      {"impact.hammer_poisson", "hammer_poisson"},
      {"impact.hammer_radius_m", "hammer_tip_radius_m (or the URDF tip radius)"},
      {"impact.fruit_modulus_pa", "modulus_nominal_pa / modulus_min_pa / modulus_max_pa"},
      {"impact.fruit_poisson", "fruit_poisson"},
      {"impact.strike_radius_m", "r2_search_low_m / r2_search_high_m"},
      {"impact.restitution", "restitution"},
      {"impact.gravity_m_s2", "gravity_m_s2"},
      {"impact.damping", "damping_law"},
      {"fruit_mass_kg", "mass_min_kg / mass_max_kg"},
      {"fruit_density_kg_m3", "density_kg_m3"},
  };
  for (size_t k = 0; k < sizeof map / sizeof map[0]; k++)
    if (strcmp(map[k][0], field) == 0)
      return map[k][1];
  return field; /* modulus_factor, lobe, band_level, shear_ratio, yield_ratio: same names */
}

/* The core's own check over the corners the node will evaluate: the
 * extreme masses and moduli, and both ends of the R2 search. */
static af_status check_model(af_node_config *c, char *err, size_t len)
{
  const double masses[] = {c->lane.mass_min_kg, c->lane.mass_max_kg};
  const double moduli[] = {c->lane.model.impact.fruit_modulus_pa, c->lane.modulus_min_pa,
                           c->lane.modulus_max_pa};
  const double radii[] = {c->lane.r2_search_low_m, c->lane.r2_search_high_m};
  for (size_t i = 0; i < 2; i++)
    for (size_t j = 0; j < 3; j++)
      for (size_t k = 0; k < 2; k++) {
        af_model_params p = c->lane.model;
        af_param_error e;
        p.fruit_mass_kg = masses[i];
        p.impact.fruit_modulus_pa = moduli[j];
        p.impact.strike_radius_m = radii[k];
        if (af_model_params_check(&p, &e) == AF_OK)
          continue;
        af_text(err, len, "parameter ~%s: %s = %g is outside the accepted range %s",
                param_of_field(e.field), e.field, e.value, e.range);
        return AF_EINVAL;
      }
  return AF_OK;
}

af_status af_params_load(af_ros *ros, af_node_config *cfg, char *err, size_t err_len)
{
  memset(cfg, 0, sizeof *cfg);
  af_status st = load_strike(ros, cfg, err, err_len);
  if (st == AF_OK)
    st = load_cultivar(ros, cfg, err, err_len);
  if (st == AF_OK)
    st = load_streams(ros, cfg, err, err_len);
  if (st == AF_OK)
    st = load_detector(ros, cfg, err, err_len);
  if (st == AF_OK)
    st = load_measure(ros, cfg, err, err_len);
  if (st == AF_OK)
    st = load_markers(ros, cfg, err, err_len);
  if (st == AF_OK)
    st = load_hammer(ros, cfg, err, err_len);
  if (st == AF_OK)
    st = check_model(cfg, err, err_len);
  if (st != AF_OK)
    af_params_free(cfg);
  return st;
}

void af_params_free(af_node_config *cfg)
{
  af_urdf_destroy(cfg->urdf);
  cfg->urdf = NULL;
}
