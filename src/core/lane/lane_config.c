/* lane_config.c — af_lane_config_derive: the lane's configuration from the
 * parameter table's values, with every check across parameters, and the
 * bound on what the lane allocates (lane_config.h). */
#include "lane_config.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "lamb.h"
#include "settings_private.h"

#ifndef M_PI /* strict C11 <math.h> does not define it */
#define M_PI 3.14159265358979323846
#endif

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
    const af_setting_def *d = &af_setting_rows[k];
    if (!s->present[k] && d->kind != AF_SETTING_STRING) {
      if (d->optional)
        af_text_line(err, len, "%s is not set (%s unless given)", af_settings_name_of(s, id).text,
                     d->absent);
      else
        af_text_line(err, len, "%s has no value", af_settings_name_of(s, id).text);
      return AF_EINVAL;
    }
    af_setting_range r;
    if (d->range &&
        (af_setting_range_of(id, &r) != AF_OK || !af_setting_range_contains(&r, s->value[k]) ||
         (d->kind == AF_SETTING_WHOLE && s->value[k] != floor(s->value[k])))) {
      af_text_line(err, len, "%s = %g is outside the accepted range %s",
                   af_settings_name_of(s, id).text, s->value[k], d->range);
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
  af_text_line(err, len, "%s = %g must be below %s = %g", af_settings_name_of(s, lo).text,
               num(s, lo), af_settings_name_of(s, hi).text, num(s, hi));
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
  af_text_line(err, len, "%s = '%s' is not one of: %s", af_settings_name_of(s, id).text, word,
               af_setting_rows[id].choices);
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
    af_text_line(err, len, "%s: %s", af_settings_name_of(s, AF_SETTING_YIELD_MEASURED).text, why);
    return AF_EINVAL;
  }
  m->modulus_factor = num(s, AF_SETTING_MODULUS_FACTOR);
  m->bruise_energy_j = num(s, AF_SETTING_BRUISE_ENERGY_J);
  if (!(c->modulus_min_pa <= i->fruit_modulus_pa && i->fruit_modulus_pa <= c->modulus_max_pa)) {
    af_text_line(err, len, "%s = %g must lie in [%s, %s] = [%g, %g] Pa",
                 af_settings_name_of(s, AF_SETTING_MODULUS_NOMINAL_PA).text, i->fruit_modulus_pa,
                 af_settings_name_of(s, AF_SETTING_MODULUS_MIN_PA).text,
                 af_settings_name_of(s, AF_SETTING_MODULUS_MAX_PA).text, c->modulus_min_pa,
                 c->modulus_max_pa);
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
  if (af_lamb_root(i->fruit_poisson, &c->resonance_xi) != AF_OK) {
    af_text_line(err, len, "%s = %g: no 0S2 root of Lamb's equation found",
                 af_settings_name_of(s, AF_SETTING_FRUIT_POISSON).text, i->fruit_poisson);
    return AF_EINVAL;
  }
  return AF_OK;
}

static af_status derive_stream(const af_settings *s, af_setting_id rate, af_setting_id buffer,
                               af_stream_config *sc, char *err, size_t len)
{
  sc->sample_rate_hz = num(s, rate);
  sc->buffer_s = num(s, buffer);
  sc->clock_step_s = num(s, AF_SETTING_STREAM_CLOCK_STEP_S);
  double samples = ceil(sc->buffer_s * sc->sample_rate_hz);
  if (samples > AF_RING_MAX_SAMPLES) {
    af_text_line(
        err, len, "%s = %g and %s = %g make a ring of %.0f samples, above the %.0f accepted",
        af_settings_name_of(s, buffer).text, sc->buffer_s, af_settings_name_of(s, rate).text,
        sc->sample_rate_hz, samples, AF_RING_MAX_SAMPLES);
    return AF_EINVAL;
  }
  sc->capacity_samples = (size_t)samples;
  sc->max_chunk_samples = sc->capacity_samples;
  return AF_OK;
}

/* The force transducer: newtons as sent, or volts from a DAQ turned into
 * newtons at the lane's input (x [V] / sensitivity [V/N] = x [N]). The
 * sensitivity goes with volts only: given with N it would be ignored. */
static af_status derive_force_unit(const af_settings *s, af_lane_config *c, char *err, size_t len)
{
  const af_setting_id unit = AF_SETTING_FORCE_UNIT, sens = AF_SETTING_FORCE_SENSITIVITY_V_PER_N;
  if (af_settings_choice(s, unit, c->force.units[0], AF_LANE_UNIT_MAX) != AF_OK) {
    af_text_line(err, len, "%s has no value", af_settings_name_of(s, unit).text);
    return AF_EINVAL;
  }
  const bool volts = strcmp(c->force.units[0], "V") == 0;
  if (volts && num(s, sens) == 0.0) {
    af_text_line(err, len, "%s = 0 (none), but %s = V needs it: a number in %s other than 0",
                 af_settings_name_of(s, sens).text, af_settings_name_of(s, unit).text,
                 af_setting_rows[sens].range);
    return AF_EINVAL;
  }
  if (!volts && num(s, sens) != 0.0) {
    af_text_line(err, len, "%s = %g is given but %s = %s (the sensitivity converts volts only)",
                 af_settings_name_of(s, sens).text, num(s, sens), af_settings_name_of(s, unit).text,
                 c->force.units[0]);
    return AF_EINVAL;
  }
  c->force.to_si = volts ? 1.0 / num(s, sens) : 1.0;
  return AF_OK;
}

/* A stream's chunk rate [1/s]: its sample rate / the samples of a chunk;
 * 0 samples = any size, only a silence judged. */
static void chunk_rate(const af_settings *s, af_setting_id rate, af_setting_id samples,
                       double tolerance, size_t window, af_rate_config *out)
{
  const double n = num(s, samples);
  out->min_hz = n > 0.0 ? num(s, rate) / n : 0.0;
  out->max_hz = n > 0.0 ? num(s, rate) / n : INFINITY;
  out->tolerance = tolerance;
  out->window = window;
}

/* The rate and stamp checks of the inputs (rate_status.h); the min < max pairs. */
static af_status derive_input_health(const af_settings *s, af_lane_config *c, char *err, size_t len)
{
  static const af_setting_id pairs[][2] = {
      {AF_SETTING_STREAM_STAMP_DELAY_MIN_S, AF_SETTING_STREAM_STAMP_DELAY_MAX_S},
      {AF_SETTING_APPLE_STAMP_DELAY_MIN_S, AF_SETTING_APPLE_STAMP_DELAY_MAX_S},
      {AF_SETTING_APPLE_RATE_MIN_HZ, AF_SETTING_APPLE_RATE_MAX_HZ},
  };
  for (size_t k = 0; k < sizeof pairs / sizeof pairs[0]; k++)
    if (check_order(s, pairs[k][0], pairs[k][1], err, len) != AF_OK)
      return AF_EINVAL;
  const double tolerance = num(s, AF_SETTING_STREAM_RATE_TOLERANCE);
  const size_t window = (size_t)num(s, AF_SETTING_DIAGNOSTIC_RATE_WINDOW);
  chunk_rate(s, AF_SETTING_FORCE_SAMPLE_RATE_HZ, AF_SETTING_FORCE_CHUNK_SAMPLES, tolerance, window,
             &c->force_rate);
  chunk_rate(s, AF_SETTING_AUDIO_SAMPLE_RATE_HZ, AF_SETTING_AUDIO_CHUNK_SAMPLES, tolerance, window,
             &c->audio_rate);
  c->apple_rate.min_hz = num(s, AF_SETTING_APPLE_RATE_MIN_HZ);
  c->apple_rate.max_hz = num(s, AF_SETTING_APPLE_RATE_MAX_HZ);
  c->apple_rate.tolerance = tolerance;
  c->apple_rate.window = window;
  c->stream_stamps.min_delay_s = num(s, AF_SETTING_STREAM_STAMP_DELAY_MIN_S);
  c->stream_stamps.max_delay_s = num(s, AF_SETTING_STREAM_STAMP_DELAY_MAX_S);
  c->apple_stamps.min_delay_s = num(s, AF_SETTING_APPLE_STAMP_DELAY_MIN_S);
  c->apple_stamps.max_delay_s = num(s, AF_SETTING_APPLE_STAMP_DELAY_MAX_S);
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
    af_text_line(err, len, "%s has no value", af_settings_name_of(s, AF_SETTING_AUDIO_UNIT).text);
    return st;
  }
  c->audio.to_si = 1.0;
  c->stream_stale_after_s = num(s, AF_SETTING_STREAM_STALE_AFTER_S);
  c->stream_absent_warn_s = num(s, AF_SETTING_STREAM_ABSENT_WARN_S);
  st = derive_input_health(s, c, err, len);
  if (st != AF_OK)
    return st;
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
  af_strike_config *d = &c->strikes.strike;
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
  /* The floor of the threshold must be a force the sensor can report: at or
   * above its full scale no strike could ever cross it (a detector silent for
   * good, e.g. after a reconfigure to 1e6 N). */
  if (st == AF_OK && !(isfinite(d->threshold_min_n) && d->threshold_min_n < d->full_scale_n)) {
    af_text_line(err, len, "%s = %g N is outside the accepted range (0, %s = %g N)",
                 af_settings_name_of(s, AF_SETTING_STRIKE_THRESHOLD_MIN_N).text, d->threshold_min_n,
                 af_settings_name_of(s, AF_SETTING_STRIKE_FULL_SCALE_N).text, d->full_scale_n);
    st = AF_EINVAL;
  }
  if (st == AF_OK && d->post_s < d->double_hit_gap_s) {
    af_text_line(
        err, len,
        "%s = %g must be at least %s = %g (a bounce must be ruled out before the strike is "
        "emitted)",
        af_settings_name_of(s, AF_SETTING_STRIKE_POST_S).text, d->post_s,
        af_settings_name_of(s, AF_SETTING_STRIKE_DOUBLE_HIT_GAP_S).text, d->double_hit_gap_s);
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
    af_text_line(err, len,
                 "%s, %s, %s and %s give an event span of %.0f samples at %g Hz, above the 2^24 "
                 "accepted",
                 af_settings_name_of(s, AF_SETTING_STRIKE_PRE_TRIGGER_S).text,
                 af_settings_name_of(s, AF_SETTING_STRIKE_MAX_CONTACT_S).text,
                 af_settings_name_of(s, AF_SETTING_STRIKE_DOUBLE_HIT_GAP_S).text,
                 af_settings_name_of(s, AF_SETTING_STRIKE_POST_S).text, span, fs);
    return AF_EINVAL;
  }
  c->strikes.pulse_capacity_samples = (size_t)span;
  return AF_OK;
}

/* The core's own check of the detector (it allocates: start-up only, after
 * check_memory). */
static af_status trial_detector(const af_settings *s, af_lane_config *c, char *err, size_t len)
{
  af_strike *trial = NULL;
  af_status st = af_strike_create(&c->strikes.strike, &trial);
  af_strike_destroy(trial);
  if (st != AF_OK)
    af_text_line(err, len,
                 "%s = %g Hz: the strike detector refuses the %sstrike_* parameters: %s (a window "
                 "shorter than 2 samples?)",
                 af_settings_name_of(s, AF_SETTING_FORCE_SAMPLE_RATE_HZ).text,
                 c->strikes.strike.sample_rate_hz, s->name_prefix, af_strerror(st));
  return st;
}

/* A frequency row [Hz] that must lie below the audio Nyquist frequency. */
static af_status check_below_nyquist(const af_settings *s, af_setting_id id, const char *what,
                                     char *err, size_t len)
{
  const double nyquist_hz = 0.5 * num(s, AF_SETTING_AUDIO_SAMPLE_RATE_HZ);
  if (num(s, id) < nyquist_hz)
    return AF_OK;
  af_text_line(err, len, "%s = %g must be below the audio Nyquist frequency %g Hz (%s = %g)%s",
               af_settings_name_of(s, id).text, num(s, id), nyquist_hz,
               af_settings_name_of(s, AF_SETTING_AUDIO_SAMPLE_RATE_HZ).text,
               num(s, AF_SETTING_AUDIO_SAMPLE_RATE_HZ), what);
  return AF_EINVAL;
}

/* The noise band holds at least AF_RESPONSE_MIN_NOISE_BINS bins of the
 * audio FFT once clipped to the Nyquist frequency (a band just below
 * Nyquist at a low audio rate holds too few). */
static af_status check_noise_band(const af_settings *s, const af_response_config *rc, char *err,
                                  size_t len)
{
  size_t bins = af_response_noise_band_bins(rc);
  if (bins >= AF_RESPONSE_MIN_NOISE_BINS)
    return AF_OK;
  af_text_line(err, len,
               "%s = %g .. %s = %g Hz, clipped to the Nyquist frequency %g Hz (%s = %g), holds "
               "%zu FFT bins of %.3g Hz, fewer than the %d the noise floor needs: lower %s",
               af_settings_name_of(s, AF_SETTING_MEASURE_NOISE_BAND_LOW_HZ).text,
               rc->noise_band_lo_hz,
               af_settings_name_of(s, AF_SETTING_MEASURE_NOISE_BAND_HIGH_HZ).text,
               rc->noise_band_hi_hz, 0.5 * rc->sample_rate_hz,
               af_settings_name_of(s, AF_SETTING_AUDIO_SAMPLE_RATE_HZ).text, rc->sample_rate_hz,
               bins, rc->sample_rate_hz / (double)rc->fft_size, AF_RESPONSE_MIN_NOISE_BINS,
               af_settings_name_of(s, AF_SETTING_MEASURE_NOISE_BAND_LOW_HZ).text);
  return AF_EINVAL;
}

/* The microphone analysis (measure_snr_threshold_db, measure_hum_*,
 * measure_noise_band_*, measure_fft_padding), after derive_measure has set
 * the windows: it holds the longer of the two, zero-padded to the power of
 * two at least measure_fft_padding times its length. The rest of the
 * response configuration stays af_response_config_default's. */
static af_status derive_response(const af_settings *s, af_lane_config *c, char *err, size_t len)
{
  const af_strikes_config *mc = &c->strikes;
  af_response_config *rc = &c->strikes.measure.response;
  rc->sample_rate_hz = c->audio.sample_rate_hz;
  rc->window_samples = mc->audio_window_samples > mc->noise_window_samples
                           ? mc->audio_window_samples
                           : mc->noise_window_samples;
  const size_t padding = (size_t)num(s, AF_SETTING_MEASURE_FFT_PADDING);
  rc->fft_size = power_of_two_at_least(padding * rc->window_samples);
  rc->snr_threshold_db = num(s, AF_SETTING_MEASURE_SNR_THRESHOLD_DB);
  rc->hum_hz = num(s, AF_SETTING_MEASURE_HUM_HZ);
  rc->hum_harmonics = (size_t)num(s, AF_SETTING_MEASURE_HUM_HARMONICS);
  rc->noise_band_lo_hz = num(s, AF_SETTING_MEASURE_NOISE_BAND_LOW_HZ);
  rc->noise_band_hi_hz = num(s, AF_SETTING_MEASURE_NOISE_BAND_HIGH_HZ);
  af_status st = check_below_nyquist(s, AF_SETTING_MEASURE_HUM_HZ, " (0 = off)", err, len);
  if (st == AF_OK)
    st = check_below_nyquist(s, AF_SETTING_MEASURE_NOISE_BAND_LOW_HZ, "", err, len);
  if (st == AF_OK)
    st = check_order(s, AF_SETTING_MEASURE_NOISE_BAND_LOW_HZ, AF_SETTING_MEASURE_NOISE_BAND_HIGH_HZ,
                     err, len);
  if (st == AF_OK)
    st = check_noise_band(s, rc, err, len);
  if (st == AF_OK)
    st = check_order(s, AF_SETTING_FRUIT_Q_MIN, AF_SETTING_FRUIT_Q_MAX, err, len);
  return st;
}

/* The measurement of each strike (measure_*) and the pending queue. */
static af_status derive_measure(const af_settings *s, af_lane_config *c, char *err, size_t len)
{
  af_strikes_config *mc = &c->strikes;
  af_measure_config *m = &mc->measure;
  *m = af_measure_config_default(); /* the fit and response settings not exposed stay the core's */
  m->fit.fit_velocity = af_settings_bool(s, AF_SETTING_MEASURE_FIT_VELOCITY);
  m->audio_delay_s = num(s, AF_SETTING_MEASURE_AUDIO_DELAY_S);
  m->audio_window_s = num(s, AF_SETTING_MEASURE_AUDIO_WINDOW_S);
  m->noise_window_s = num(s, AF_SETTING_MEASURE_NOISE_WINDOW_S);
  m->noise_guard_s = num(s, AF_SETTING_MEASURE_NOISE_GUARD_S);
  m->range_margin = num(s, AF_SETTING_MEASURE_RANGE_MARGIN);
  m->fruit_q_min = num(s, AF_SETTING_FRUIT_Q_MIN);
  m->fruit_q_max = num(s, AF_SETTING_FRUIT_Q_MAX);
  m->fruit_confidence_min = num(s, AF_SETTING_FRUIT_CONFIDENCE_MIN);
  m->fruit_neighbour_margin_db = num(s, AF_SETTING_FRUIT_NEIGHBOUR_MARGIN_DB);
  mc->pending_size = (size_t)num(s, AF_SETTING_STRIKE_PENDING_SIZE);
  mc->apple_stale_after_s = num(s, AF_SETTING_APPLE_STALE_AFTER_S);
  mc->apple_wait_s = num(s, AF_SETTING_APPLE_WAIT_S);
  mc->apple_transit_s = num(s, AF_SETTING_APPLE_TRANSIT_S);
  mc->apple_transit_tolerance_s = num(s, AF_SETTING_APPLE_TRANSIT_TOLERANCE_S);
  mc->audio_lag_learn = num(s, AF_SETTING_AUDIO_LAG_LEARN) != 0.0;
  mc->audio_lag_max_s = num(s, AF_SETTING_AUDIO_LAG_MAX_S);
  double fs = c->audio.sample_rate_hz;
  /* Rounded as the measurement rounds them (measure.c). */
  double window = round(m->audio_window_s * fs), noise = round(m->noise_window_s * fs);
  if (window < 8.0) {
    af_text_line(err, len,
                 "%s = %g gives %.0f audio samples at %g Hz, fewer than the 8 the analysis needs",
                 af_settings_name_of(s, AF_SETTING_MEASURE_AUDIO_WINDOW_S).text, m->audio_window_s,
                 window, fs);
    return AF_EINVAL;
  }
  if (noise > 0.0 && noise < 8.0) {
    af_text_line(err, len, "%s = %g gives %.0f audio samples at %g Hz: 0 (none) or at least 8",
                 af_settings_name_of(s, AF_SETTING_MEASURE_NOISE_WINDOW_S).text, m->noise_window_s,
                 noise, fs);
    return AF_EINVAL;
  }
  /* The ring must hold the noise before the strike, the delay and the window. */
  double needed_s = m->noise_window_s + m->noise_guard_s + m->audio_delay_s + m->audio_window_s;
  if (!(needed_s < c->audio.buffer_s)) {
    af_text_line(err, len, "%s + %s + %s + %s = %g s must be below %s = %g s",
                 af_settings_name_of(s, AF_SETTING_MEASURE_NOISE_WINDOW_S).text,
                 af_settings_name_of(s, AF_SETTING_MEASURE_NOISE_GUARD_S).text,
                 af_settings_name_of(s, AF_SETTING_MEASURE_AUDIO_DELAY_S).text,
                 af_settings_name_of(s, AF_SETTING_MEASURE_AUDIO_WINDOW_S).text, needed_s,
                 af_settings_name_of(s, AF_SETTING_AUDIO_BUFFER_S).text, c->audio.buffer_s);
    return AF_EINVAL;
  }
  mc->audio_window_samples = (size_t)window;
  mc->noise_window_samples = (size_t)noise;
  /* The fit: the strike's own damping law; sized for the longest contact. */
  m->fit.damping = c->model.impact.damping;
  size_t longest = (size_t)ceil(mc->strike.max_contact_s * c->force.sample_rate_hz) + 2;
  if (longest > m->fit.max_samples)
    m->fit.max_samples = longest;
  return derive_response(s, c, err, len);
}

/* The core's own check of the measurement (it allocates: start-up only,
 * after check_memory). */
static af_status trial_measure(const af_settings *s, af_lane_config *c, char *err, size_t len)
{
  af_measure *trial = NULL;
  af_status st = af_measure_create(&c->strikes.measure, &trial);
  af_measure_destroy(trial);
  if (st != AF_OK)
    af_text_line(err, len,
                 "%s = %g Hz: the strike measurement refuses the %smeasure_* parameters: %s",
                 af_settings_name_of(s, AF_SETTING_AUDIO_SAMPLE_RATE_HZ).text,
                 c->audio.sample_rate_hz, s->name_prefix, af_strerror(st));
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
  const af_strikes_config *mc = &c->strikes;
  /* float rings */
  m->rings = 4.0 * ((double)c->force.capacity_samples + (double)c->audio.capacity_samples);
  /* detector: its float ring (span + a block), the span as float and twice
   * as double, the priming sample; the queue's pulses (double) and the
   * audio and noise windows (float) */
  const double span = (double)mc->pulse_capacity_samples;
  m->detector_queue = 4.0 * (span + 1024.0) + 20.0 * span + 8.0 * 8192.0 +
                      (double)mc->pending_size * (8.0 * span + 256.0) +
                      4.0 * ((double)mc->audio_window_samples + (double)mc->noise_window_samples);
  /* the audio lag's onset search (lane.c): +-audio_lag_max_s and its
   * reference blocks, float */
  m->detector_queue += 4.0 * ((2.0 * mc->audio_lag_max_s + 0.012) * c->audio.sample_rate_hz + 16.0);
  /* microphone analysis: the FFT input, its complex and real spectra, the
   * mode analysis's work arrays, FFTW's plan (its twiddles about one complex
   * per point): 86 bytes per FFT point measured (test_settings), counted as
   * 128 so that a buffer added there does not outgrow the estimate */
  const double fft = (double)mc->measure.response.fft_size;
  m->microphone = 128.0 * fft + 8.0 * (double)mc->measure.response.window_samples +
                  (double)af_response_share_table_bytes(&mc->measure.response);
  /* pulse fit (GSL's n x p workspace and the oversampled model buffers)
   * and the pulse's spectrum (4 x zero-padded) */
  const double n = (double)mc->measure.fit.max_samples;
  const double over = (double)mc->measure.fit.oversample;
  const double ms = n > 1024.0 ? n : 1024.0, sfft = pow2_at_least(4.0 * ms);
  m->fit_spectrum = 16.0 * (4.0 * n * over + 1.0) + 16.0 * n + 8.0 * n * 20.0 + 8.0 * sfft +
                    (sfft / 2.0 + 1.0) * 24.0 + 16.0 * sfft + 64.0 * (ms / 2.0 + 1.0);
  /* the second fit, v0 free, of the bounce test (measure.c): as the first */
  m->fit_spectrum += 16.0 * (4.0 * n * over + 1.0) + 16.0 * n + 8.0 * n * 20.0;
  /* the model workspace (fixed: 4096-point FFT, 1024 samples), the
   * objects themselves and the hammer health's ring */
  m->fixed = 1048576.0 + (double)af_hammer_health_bytes();
  /* the learned modulus factor: its ring and sorted copy (factor_learn.c) */
  m->fixed += 16.0 * (double)c->factor_learn.window_strikes;
  m->total = m->rings + m->detector_queue + m->microphone + m->fit_spectrum + m->fixed;
}

static af_status check_memory(const af_settings *s, const af_lane_config *c, char *err, size_t len)
{
  af_lane_memory m;
  af_lane_config_memory(c, &m);
  if (m.total <= (double)AF_LANE_MEMORY_MAX_BYTES)
    return AF_OK;
  const double mib = 1048576.0;
  af_text_line(
      err, len,
      "the lane would allocate about %.0f MiB (rings %.0f: %sforce_buffer_s x "
      "%sforce_sample_rate_hz + %saudio_buffer_s x %saudio_sample_rate_hz; detector and queue "
      "%.0f: %sstrike_* x %sstrike_pending_size; microphone analysis %.0f: "
      "%smeasure_audio_window_s x %smeasure_fft_padding; pulse fit %.0f: %sstrike_max_contact_s), "
      "above the %.0f MiB accepted",
      m.total / mib, m.rings / mib, s->name_prefix, s->name_prefix, s->name_prefix, s->name_prefix,
      m.detector_queue / mib, s->name_prefix, s->name_prefix, m.microphone / mib, s->name_prefix,
      s->name_prefix, m.fit_spectrum / mib, s->name_prefix, AF_LANE_MEMORY_MAX_BYTES / mib);
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
    {"bruise_energy_j", {AF_SETTING_BRUISE_ENERGY_J}, 1, ""},
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
               af_settings_name_of(s, f->ids[j]).text);
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
        af_text_line(err, len, "%s: %s = %g is outside the accepted range %s", names, e.field,
                     e.value, e.range);
        return AF_EINVAL;
      }
  return AF_OK;
}

/* The hammer health's limits (hammer_health_*) and the strike they watch:
 * the hammer's mass, the gravity, the set velocity and the cultivar's
 * restitution, from the model template (its hammer mass already set). */
static af_status derive_health(const af_settings *s, af_lane_config *c, char *err, size_t len)
{
  af_hammer_health_config *h = &c->health;
  const af_impact_params *i = &c->model.impact;
  h->hammer_mass_kg = i->hammer_mass_kg;
  h->gravity_m_s2 = i->gravity_m_s2;
  h->velocity_m_s = i->velocity_m_s;
  h->restitution = i->restitution;
  h->window = (size_t)num(s, AF_SETTING_HAMMER_HEALTH_WINDOW);
  h->min_strikes = (size_t)num(s, AF_SETTING_HAMMER_HEALTH_MIN_STRIKES);
  h->velocity_band = num(s, AF_SETTING_HAMMER_HEALTH_VELOCITY_BAND);
  h->baseline_drift_limit_n = num(s, AF_SETTING_HAMMER_HEALTH_BASELINE_DRIFT_N);
  h->clip_rate_limit = num(s, AF_SETTING_HAMMER_HEALTH_CLIP_RATE);
  if (h->min_strikes > h->window) {
    af_text_line(err, len, "%s = %zu must be at most %s = %zu",
                 af_settings_name_of(s, AF_SETTING_HAMMER_HEALTH_MIN_STRIKES).text, h->min_strikes,
                 af_settings_name_of(s, AF_SETTING_HAMMER_HEALTH_WINDOW).text, h->window);
    return AF_EINVAL;
  }
  return af_hammer_health_check(h, err, len);
}

/* The learned modulus factor (factor_learn.h): window, minimum count,
 * apply, hysteresis; it starts from the cultivar's modulus_factor and is
 * applied only within that row's range. After derive_cultivar. */
static af_status derive_factor_learn(const af_settings *s, af_lane_config *c, char *err, size_t len)
{
  af_factor_learn_config *f = &c->factor_learn;
  const af_setting_id window = AF_SETTING_MODULUS_FACTOR_LEARN_WINDOW,
                      min = AF_SETTING_MODULUS_FACTOR_LEARN_MIN_STRIKES;
  f->window_strikes = (size_t)num(s, window);
  f->min_strikes = (size_t)num(s, min);
  f->apply = af_settings_bool(s, AF_SETTING_MODULUS_FACTOR_LEARN_APPLY);
  f->min_change = num(s, AF_SETTING_MODULUS_FACTOR_LEARN_MIN_CHANGE);
  f->initial_factor = c->model.modulus_factor;
  af_setting_range r;
  if (af_setting_range_of(AF_SETTING_MODULUS_FACTOR, &r) != AF_OK) {
    af_text_line(err, len, "the modulus_factor row has no range");
    return AF_EINVAL;
  }
  f->factor_min = r.lo;
  f->factor_max = r.hi;
  if (f->min_strikes <= f->window_strikes)
    return AF_OK;
  af_text_line(err, len, "%s = %zu must be at most %s = %zu", af_settings_name_of(s, min).text,
               f->min_strikes, af_settings_name_of(s, window).text, f->window_strikes);
  return AF_EINVAL;
}

/* Tap-only mode and its onset detector (onset.h), at the audio rate. After
 * derive_streams. */
static af_status derive_tap(const af_settings *s, af_lane_config *c, char *err, size_t len)
{
  af_strikes_config *mc = &c->strikes;
  af_onset_config *o = &mc->onset;
  const char *field = NULL;
  mc->tap_only = af_settings_bool(s, AF_SETTING_TAP_ONLY);
  o->sample_rate_hz = c->audio.sample_rate_hz;
  o->frame_s = num(s, AF_SETTING_ONSET_FRAME_S);
  o->snr_db = num(s, AF_SETTING_ONSET_SNR_DB);
  o->holdoff_s = num(s, AF_SETTING_ONSET_HOLDOFF_S);
  o->floor_time_constant_s = num(s, AF_SETTING_ONSET_FLOOR_TIME_CONSTANT_S);
  o->floor_rms = num(s, AF_SETTING_ONSET_FLOOR);
  o->quantum = 0.0; /* unknown here: a tool that reads integer PCM sets it */
  /* Checked only when used: a slow audio rate need not suit a detector that
   * does not run. */
  if (!mc->tap_only || af_onset_config_check(o, &field) == AF_OK)
    return AF_OK;
  if (strcmp(field, "onset_frame_s") == 0)
    af_text_line(err, len, "%s = %g gives %.1f audio samples at %g Hz: at least %d",
                 af_settings_name_of(s, AF_SETTING_ONSET_FRAME_S).text, o->frame_s,
                 o->frame_s * o->sample_rate_hz, o->sample_rate_hz, AF_ONSET_MIN_FRAME_SAMPLES);
  else
    af_text_line(err, len, "%s must be at least %s = %g s", field,
                 af_settings_name_of(s, AF_SETTING_ONSET_FRAME_S).text, o->frame_s);
  return AF_EINVAL;
}

/* ---- settings that cannot work together --------------------------------------- */

/* x rounded to 4 significant digits, up or down: a bound suggested in a
 * message must itself pass (1e-9: a product of decimals a hair off an exact
 * digit is not rounded a whole digit further). */
static double round_4(double x, bool up)
{
  if (!(x > 0.0) || !isfinite(x))
    return x;
  const double scale = pow(10.0, 3.0 - floor(log10(x)));
  return (up ? ceil(x * scale - 1e-9) : floor(x * scale + 1e-9)) / scale;
}

/* How long after its contact start the detector emits a strike, at the
 * latest [s]: its longest event, a contact and a bounce of
 * strike_max_contact_s each, the gap between them, the wait after
 * (strike.c; derive_detector's span without the pre-trigger). */
static double emission_s(const af_strike_config *d)
{
  return 2.0 * d->max_contact_s + d->double_hit_gap_s + d->post_s;
}

/* The audio ring must still hold a strike's audio when the lane reads it
 * (lane.c, audio_for): from the noise reference (measure_noise_window_s
 * ending measure_noise_guard_s before the contact start) to the newest audio
 * received by then. The strike is read once its apple is decided
 * (apple_decided: apple_wait_s of force after the contact start, not before
 * the detector emits it) and its window (measure_audio_delay_s +
 * measure_audio_window_s) is complete; by then the audio may have run ahead
 * of the force by up to stream_stale_after_s (a chunk, or a force stream
 * late by less than the lane calls stale). */
static af_status check_audio_ring(const af_settings *s, const af_lane_config *c, char *err,
                                  size_t len)
{
  const af_measure_config *m = &c->strikes.measure;
  const double before_s = m->noise_window_s > 0.0 ? m->noise_window_s + m->noise_guard_s : 0.0;
  const double window_s = m->audio_delay_s + m->audio_window_s;
  const double decided_s = fmax(c->strikes.apple_wait_s, emission_s(&c->strikes.strike));
  const double needed_s = before_s + fmax(window_s, decided_s) + c->stream_stale_after_s;
  if (c->audio.buffer_s >= needed_s)
    return AF_OK;
  char after[200];
  if (window_s >= decided_s)
    snprintf(after, sizeof after, "%s + %s = %g s",
             af_settings_name_of(s, AF_SETTING_MEASURE_AUDIO_DELAY_S).text,
             af_settings_name_of(s, AF_SETTING_MEASURE_AUDIO_WINDOW_S).text, window_s);
  else if (c->strikes.apple_wait_s >= decided_s)
    snprintf(after, sizeof after, "%s %g s", af_settings_name_of(s, AF_SETTING_APPLE_WAIT_S).text,
             c->strikes.apple_wait_s);
  else
    snprintf(after, sizeof after, "the strike detector's emission %g s after the contact start",
             decided_s);
  af_text_line(err, len,
               "%s = %g s is shorter than the audio a strike must find still held when it is "
               "read: %g s of noise reference before the contact (%s + %s), %s after it, and "
               "%s %g s the audio may run ahead of the force: raise %s to at least %g s",
               af_settings_name_of(s, AF_SETTING_AUDIO_BUFFER_S).text, c->audio.buffer_s, before_s,
               af_settings_name_of(s, AF_SETTING_MEASURE_NOISE_WINDOW_S).text,
               af_settings_name_of(s, AF_SETTING_MEASURE_NOISE_GUARD_S).text, after,
               af_settings_name_of(s, AF_SETTING_STREAM_STALE_AFTER_S).text,
               c->stream_stale_after_s, af_settings_name_of(s, AF_SETTING_AUDIO_BUFFER_S).text,
               round_4(needed_s, true));
  return AF_EINVAL;
}

/* The largest chunk either station (the node on the wire, firmness_report
 * in the bag) takes is its stream's ring: a longer one could not be held
 * whole. The force ring must then take a chunk that holds one strike's
 * whole event (pre-trigger, contact, bounce, gap, wait after), or a sender
 * that chunks strike by strike has every chunk refused. */
static af_status check_force_ring(const af_settings *s, const af_lane_config *c, char *err,
                                  size_t len)
{
  const af_strike_config *d = &c->strikes.strike;
  const double event = (double)c->strikes.pulse_capacity_samples;
  if ((double)c->force.max_chunk_samples >= event)
    return AF_OK;
  af_text_line(
      err, len,
      "%s = %g s holds %zu samples at %s = %g Hz, fewer than one strike's event of "
      "%.0f samples (%s + 2 x %s + %s + %s = %g s): the station refuses every force "
      "chunk longer than its ring: raise %s to at least %g s",
      af_settings_name_of(s, AF_SETTING_FORCE_BUFFER_S).text, c->force.buffer_s,
      c->force.max_chunk_samples, af_settings_name_of(s, AF_SETTING_FORCE_SAMPLE_RATE_HZ).text,
      c->force.sample_rate_hz, event, af_settings_name_of(s, AF_SETTING_STRIKE_PRE_TRIGGER_S).text,
      af_settings_name_of(s, AF_SETTING_STRIKE_MAX_CONTACT_S).text,
      af_settings_name_of(s, AF_SETTING_STRIKE_DOUBLE_HIT_GAP_S).text,
      af_settings_name_of(s, AF_SETTING_STRIKE_POST_S).text, d->pre_trigger_s + emission_s(d),
      af_settings_name_of(s, AF_SETTING_FORCE_BUFFER_S).text,
      round_4(event / c->force.sample_rate_hz, true));
  return AF_EINVAL;
}

/* The noise band's floor (used without a noise reference: response_noise.c,
 * the median of the band) must be measured where the 0S2 cannot be: outside
 * the range the measurement searches for it (measure.c, lamb_range), over
 * the cultivar's masses and moduli: from the softest, heaviest apple to the
 * firmest, lightest, widened by measure_range_margin, kept below the audio
 * Nyquist frequency. */
static af_status check_noise_band_vs_0s2(const af_settings *s, const af_lane_config *c, char *err,
                                         size_t len)
{
  const af_model_params *m = &c->model;
  const af_response_config *rc = &c->strikes.measure.response;
  const double nu = m->impact.fruit_poisson, rho = m->fruit_density_kg_m3;
  const double margin = c->strikes.measure.range_margin, fs = c->audio.sample_rate_hz;
  const double f_lo =
      (1.0 - margin) * af_lamb_frequency_hz(c->resonance_xi, m->modulus_factor * c->modulus_min_pa,
                                            nu, rho, c->mass_max_kg);
  const double f_hi = fmin(
      (1.0 + margin) * af_lamb_frequency_hz(c->resonance_xi, m->modulus_factor * c->modulus_max_pa,
                                            nu, rho, c->mass_min_kg),
      0.5 * 0.98 * fs); /* measure.c's AF_MEASURE_NYQUIST_FRACTION */
  const double band_hi = fmin(rc->noise_band_hi_hz, 0.5 * fs);
  if (!(rc->noise_band_lo_hz < f_hi && band_hi > f_lo))
    return AF_OK;
  af_text_line(
      err, len,
      "%s = %g .. %s = %g Hz overlaps the 0S2's search range %.0f .. %.0f Hz (%s = %g .. %s = "
      "%g Pa x %s = %g, %s = %g .. %s = %g kg at %s = %g kg/m3, widened by %s = %g): the noise "
      "floor would be measured on the 0S2 itself: put the band above %.0f Hz or below %.0f Hz",
      af_settings_name_of(s, AF_SETTING_MEASURE_NOISE_BAND_LOW_HZ).text, rc->noise_band_lo_hz,
      af_settings_name_of(s, AF_SETTING_MEASURE_NOISE_BAND_HIGH_HZ).text, rc->noise_band_hi_hz,
      f_lo, f_hi, af_settings_name_of(s, AF_SETTING_MODULUS_MIN_PA).text, c->modulus_min_pa,
      af_settings_name_of(s, AF_SETTING_MODULUS_MAX_PA).text, c->modulus_max_pa,
      af_settings_name_of(s, AF_SETTING_MODULUS_FACTOR).text, m->modulus_factor,
      af_settings_name_of(s, AF_SETTING_MASS_MIN_KG).text, c->mass_min_kg,
      af_settings_name_of(s, AF_SETTING_MASS_MAX_KG).text, c->mass_max_kg,
      af_settings_name_of(s, AF_SETTING_DENSITY_KG_M3).text, rho,
      af_settings_name_of(s, AF_SETTING_MEASURE_RANGE_MARGIN).text, margin, ceil(f_hi),
      floor(f_lo));
  return AF_EINVAL;
}

/* Equatorial semi-axis [m] of an apple of mass m_kg and density rho whose
 * polar / equatorial semi-axis ratio is aspect: m = 4/3 pi rho a^2 c with
 * c = aspect x a. */
static double equatorial_radius_m(double m_kg, double rho_kg_m3, double aspect)
{
  return cbrt(3.0 * m_kg / (4.0 * M_PI * rho_kg_m3 * aspect));
}

/* Some apple must pass the prediction's checks (prediction.c): a mass in
 * [mass_min_kg, mass_max_kg] and an equatorial radius in
 * [equatorial_radius_min_m, equatorial_radius_max_m] whose implied aspect
 * (the polar semi-axis from mass and density over the radius) lies in
 * [aspect_ratio_min, aspect_ratio_max]. The lightest, tallest apple has the
 * smallest radius, the heaviest, flattest the largest. */
static af_status check_radius_vs_mass(const af_settings *s, const af_lane_config *c, char *err,
                                      size_t len)
{
  const double rho = c->model.fruit_density_kg_m3;
  const double smallest = equatorial_radius_m(c->mass_min_kg, rho, c->aspect_ratio_max);
  const double largest = equatorial_radius_m(c->mass_max_kg, rho, c->aspect_ratio_min);
  const bool too_small = c->equatorial_radius_max_m < smallest;
  if (!too_small && c->equatorial_radius_min_m <= largest)
    return AF_OK;
  const double bound = round_4(too_small ? smallest : largest, too_small);
  const af_setting_id radius = too_small ? AF_SETTING_EQUATORIAL_RADIUS_MAX_M
                                         : AF_SETTING_EQUATORIAL_RADIUS_MIN_M,
                      mass = too_small ? AF_SETTING_MASS_MIN_KG : AF_SETTING_MASS_MAX_KG,
                      aspect =
                          too_small ? AF_SETTING_ASPECT_RATIO_MAX : AF_SETTING_ASPECT_RATIO_MIN;
  af_text_line(err, len,
               "%s = %g m is %s than any apple the cultivar accepts: %s = %g kg at %s = %g "
               "kg/m3 and %s = %g has an equatorial radius of %.5g m (cbrt(3 m / (4 pi rho "
               "aspect))): every apple would be refused: %s %s to %s %.4g m",
               af_settings_name_of(s, radius).text, num(s, radius),
               too_small ? "smaller" : "larger", af_settings_name_of(s, mass).text, num(s, mass),
               af_settings_name_of(s, AF_SETTING_DENSITY_KG_M3).text, rho,
               af_settings_name_of(s, aspect).text, num(s, aspect), too_small ? smallest : largest,
               too_small ? "raise" : "lower", af_settings_name_of(s, radius).text,
               too_small ? "at least" : "at most", bound);
  return AF_EINVAL;
}

/* Settings each valid alone that cannot work together: refused at start-up,
 * one line naming both sides, rather than every strike or apple refused on
 * the line. */
static af_status check_together(const af_settings *s, const af_lane_config *c, char *err,
                                size_t len)
{
  af_status st = c->strikes.tap_only ? AF_OK : check_force_ring(s, c, err, len);
  if (st == AF_OK)
    st = check_audio_ring(s, c, err, len);
  if (st == AF_OK)
    st = check_noise_band_vs_0s2(s, c, err, len);
  if (st == AF_OK)
    st = check_radius_vs_mass(s, c, err, len);
  return st;
}

af_status af_lane_config_derive(const af_settings *s, af_lane_config *out, char *err, size_t len)
{
  if (s == NULL || out == NULL) {
    af_text_line(err, len, "af_lane_config_derive: s or out is NULL");
    return AF_EINVAL;
  }
  memset(out, 0, sizeof *out);
  af_status st = check_values(s, err, len);
  if (st == AF_OK)
    st = derive_strike(s, out, err, len);
  if (st == AF_OK)
    st = derive_cultivar(s, out, err, len);
  if (st == AF_OK)
    st = derive_factor_learn(s, out, err, len);
  if (st == AF_OK)
    st = derive_streams(s, out, err, len);
  if (st == AF_OK)
    st = derive_detector(s, out, err, len);
  if (st == AF_OK)
    st = derive_measure(s, out, err, len);
  if (st == AF_OK)
    st = derive_tap(s, out, err, len);
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
  st = check_model(s, out, err, len);
  if (st == AF_OK)
    st = derive_health(s, out, err, len);
  return st == AF_OK ? check_together(s, out, err, len) : st;
}
