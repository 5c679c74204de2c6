/* strike_view.c — one measured strike as a figure (see strike_view.h). */
#include "strike_view.h"

#include <fftw3.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "fft_plan.h"
#include "impact.h"
#include "spectrum.h"
#include "text.h"

#ifndef M_PI /* strict C11 <math.h> does not define it */
#define M_PI 3.14159265358979323846
#endif

#define AF_VIEW_OVERSAMPLE 4 /* model samples per measured sample */
#define AF_VIEW_FLOOR_DB (-60.0)
#define AF_VIEW_TEXT 160

struct af_strike_view {
  const af_lane_config *cfg;
  /* --- captured --- */
  bool captured, prepared;
  int64_t start_ns;
  uint32_t apple_id;
  bool has_prediction, with_audio;
  af_model_params params; /* the apple's (for the fitted model) */
  double mass_kg, resonance_low_hz, resonance_high_hz;
  af_measure_report report;
  double dt_s, t0_s; /* pulse sample step; contact start relative to pulse[0] [s] */
  size_t n_pulse, cap_pulse;
  double *pulse_n;
  size_t n_audio, cap_audio;
  float *audio;
  /* --- prepared --- */
  double *pulse_t_ms;           /* the samples' times from the contact start */
  size_t n_model, cap_model;    /* the fitted model */
  double *model_t_ms, *model_n; /* its times and force */
  double freq_hz[AF_STRIKE_VIEW_FREQS];
  double force_db[AF_STRIKE_VIEW_FREQS], audio_db[AF_STRIKE_VIEW_FREQS];
  bool have_model, have_force_spectrum, have_audio_spectrum;
  double level_db; /* the half-power level of the configured lobe, dB re max */
  /* --- workspaces --- */
  af_impact *impact;
  af_spectrum *spectrum;
  size_t fft_size;
  double *fft_in;
  fftw_complex *fft_out;
  af_fft_r2c plan; /* shared by the process (fft_plan.h) */
};

static size_t pow2_at_least(size_t n)
{
  size_t p = 1;
  while (p < n)
    p <<= 1;
  return p;
}

af_status af_strike_view_create(const af_lane_config *cfg, af_strike_view **out)
{
  if (!cfg || !out)
    return AF_EINVAL;
  *out = NULL;
  af_strike_view *v = calloc(1, sizeof *v);
  if (!v)
    return AF_ENOMEM;
  v->cfg = cfg;
  v->cap_pulse = cfg->strikes.pulse_capacity_samples + 1;
  v->cap_audio = cfg->strikes.audio_window_samples + 1;
  v->cap_model = AF_VIEW_OVERSAMPLE * 4 * v->cap_pulse;
  v->fft_size = pow2_at_least(4 * v->cap_audio);
  v->pulse_n = calloc(v->cap_pulse, sizeof *v->pulse_n);
  v->pulse_t_ms = calloc(v->cap_pulse, sizeof *v->pulse_t_ms);
  v->audio = calloc(v->cap_audio, sizeof *v->audio);
  v->model_t_ms = calloc(v->cap_model, sizeof *v->model_t_ms);
  v->model_n = calloc(v->cap_model, sizeof *v->model_n);
  v->fft_in = fftw_alloc_real(v->fft_size);
  v->fft_out = fftw_alloc_complex(v->fft_size / 2 + 1);
  af_spectrum_config sc = af_spectrum_config_default();
  sc.max_samples = v->cap_pulse;
  sc.fft_size = pow2_at_least(4 * v->cap_pulse);
  af_status st = AF_ENOMEM;
  if (v->pulse_n && v->pulse_t_ms && v->audio && v->model_t_ms && v->model_n && v->fft_in &&
      v->fft_out) {
    st = af_fft_r2c_acquire(v->fft_size, &v->plan);
    if (st == AF_OK)
      st = af_impact_create(&v->impact);
    if (st == AF_OK)
      st = af_spectrum_create(&sc, &v->spectrum);
  }
  if (st != AF_OK) {
    af_strike_view_destroy(v);
    return st;
  }
  *out = v;
  return AF_OK;
}

void af_strike_view_destroy(af_strike_view *v)
{
  if (!v)
    return;
  af_fft_r2c_release(&v->plan);
  fftw_free(v->fft_in);
  fftw_free(v->fft_out);
  af_spectrum_destroy(v->spectrum);
  af_impact_destroy(v->impact);
  free(v->pulse_n);
  free(v->pulse_t_ms);
  free(v->audio);
  free(v->model_t_ms);
  free(v->model_n);
  free(v);
}

/* The analysed audio window, found as the lane finds it (lane.c): the first
 * sample at or after the contact start + the delay, audio_window_samples
 * long, read from the audio ring. */
static size_t capture_audio(af_strike_view *v, const af_lane_strike *s, const af_lane *lane)
{
  const af_stream *a = af_lane_audio_stream(lane);
  const size_t n = v->cfg->strikes.audio_window_samples;
  if (!s->with_audio || !a->seen || n == 0 || n > v->cap_audio)
    return 0;
  const int64_t delay_ns = (int64_t)llround(v->cfg->strikes.measure.audio_delay_s * 1e9);
  const double first = af_stream_index_at(a, s->start_ns + delay_ns);
  if (first < -0.5)
    return 0;
  const uint64_t i0 = first <= 0.0 ? 0 : (uint64_t)ceil(first - 1e-6);
  return af_ring_read(a->ring, i0, n, v->audio) == AF_OK ? n : 0;
}

void af_strike_view_capture(af_strike_view *v, const af_lane_strike *s, const af_lane *lane)
{
  if (!v || !s)
    return;
  const af_strike_event *ev = s->event;
  v->captured = true;
  v->prepared = false;
  v->start_ns = s->start_ns;
  v->apple_id = s->apple_id;
  v->report = s->report;
  v->has_prediction = s->prediction && s->prediction->valid;
  if (v->has_prediction) {
    v->params = s->prediction->params;
    v->resonance_low_hz = s->prediction->resonance_low_hz;
    v->resonance_high_hz = s->prediction->resonance_high_hz;
  }
  v->mass_kg = s->apple ? s->apple->mass_kg : NAN;
  v->n_pulse = 0;
  if (ev && ev->pulse_n) {
    v->n_pulse = ev->n_samples < v->cap_pulse ? ev->n_samples : v->cap_pulse;
    memcpy(v->pulse_n, ev->pulse_n, v->n_pulse * sizeof *v->pulse_n);
    v->dt_s = ev->dt_s;
    v->t0_s = ev->pulse_t0_s;
  }
  v->n_audio = lane ? capture_audio(v, s, lane) : 0;
  v->with_audio = v->n_audio > 0;
}

bool af_strike_view_pending(const af_strike_view *v)
{
  return v && v->captured && !v->prepared;
}

/* ---- prepare ------------------------------------------------------------------- */

static void prepare_model(af_strike_view *v)
{
  const af_measure_report *r = &v->report;
  v->have_model = false;
  if (!v->has_prediction || !isfinite(r->fitted_modulus_pa) || !isfinite(r->fitted_restitution))
    return;
  af_impact_params p = v->params.impact;
  p.fruit_modulus_pa = r->fitted_modulus_pa;
  p.restitution = r->fitted_restitution;
  p.damping = v->cfg->strikes.measure.fit.damping;
  af_impact_result res;
  double dt = v->dt_s / AF_VIEW_OVERSAMPLE;
  if (af_impact_execute(v->impact, &p, dt, v->model_n, NULL, v->cap_model - 1, &res) != AF_OK)
    return;
  for (size_t k = 0; k < res.n_samples; k++)
    v->model_t_ms[k] = (double)k * dt * 1e3;
  /* The contact ends at t_c with F = 0. */
  v->model_t_ms[res.n_samples] = res.contact_time_s * 1e3;
  v->model_n[res.n_samples] = 0.0;
  v->n_model = res.n_samples + 1;
  v->have_model = true;
}

static void prepare_force_spectrum(af_strike_view *v, double f_max_hz)
{
  v->have_force_spectrum = false;
  v->level_db = NAN;
  if (v->n_pulse < 2 || af_spectrum_execute(v->spectrum, v->pulse_n, v->n_pulse, v->dt_s) != AF_OK)
    return;
  for (size_t k = 0; k < AF_STRIKE_VIEW_FREQS; k++)
    v->force_db[k] = fmax(af_spectrum_level_db(v->spectrum, v->freq_hz[k]), AF_VIEW_FLOOR_DB);
  (void)f_max_hz;
  af_lobe lobe;
  const af_model_params *mp = v->has_prediction ? &v->params : &v->cfg->model;
  if (af_spectrum_lobe(v->spectrum, mp->lobe, mp->band_level, &lobe) == AF_OK)
    v->level_db = 20.0 * log10(lobe.peak_magnitude_n_s * af_band_level_ratio(mp->band_level) /
                               af_spectrum_max_magnitude(v->spectrum));
  v->have_force_spectrum = true;
}

/* |FFT| of the Hann-windowed audio, zero-padded, read at the curve's
 * frequencies (linear interpolation between bins), dB re its maximum. */
static void prepare_audio_spectrum(af_strike_view *v)
{
  v->have_audio_spectrum = false;
  if (!v->with_audio)
    return;
  const size_t n = v->n_audio;
  memset(v->fft_in, 0, v->fft_size * sizeof *v->fft_in);
  for (size_t k = 0; k < n; k++)
    v->fft_in[k] = v->audio[k] * 0.5 * (1.0 - cos(2.0 * M_PI * (double)k / (double)(n - 1)));
  af_fft_r2c_execute(&v->plan, v->fft_in, v->fft_out);
  const double rate = v->cfg->audio.sample_rate_hz, bin_hz = rate / (double)v->fft_size;
  const size_t bins = v->fft_size / 2 + 1;
  double peak = 0.0;
  for (size_t k = 1; k < bins; k++)
    peak = fmax(peak, hypot(v->fft_out[k][0], v->fft_out[k][1]));
  if (!(peak > 0.0))
    return;
  for (size_t k = 0; k < AF_STRIKE_VIEW_FREQS; k++) {
    double b = v->freq_hz[k] / bin_hz;
    size_t i = (size_t)b;
    if (i + 1 >= bins) {
      v->audio_db[k] = NAN;
      continue;
    }
    double w = b - (double)i;
    double m = (1.0 - w) * hypot(v->fft_out[i][0], v->fft_out[i][1]) +
               w * hypot(v->fft_out[i + 1][0], v->fft_out[i + 1][1]);
    v->audio_db[k] = fmax(20.0 * log10(m / peak), AF_VIEW_FLOOR_DB);
  }
  v->have_audio_spectrum = true;
}

af_status af_strike_view_prepare(af_strike_view *v)
{
  if (!v || !v->captured)
    return AF_ENODATA;
  for (size_t k = 0; k < v->n_pulse; k++)
    v->pulse_t_ms[k] = ((double)k * v->dt_s - v->t0_s) * 1e3;
  /* Up to 3 kHz or 1.25 x the 0S2 range, below the audio's Nyquist frequency. */
  double f_max = 3000.0;
  if (v->has_prediction)
    f_max = fmax(f_max, 1.25 * v->resonance_high_hz);
  if (isfinite(v->report.resonance_hz))
    f_max = fmax(f_max, 1.25 * v->report.resonance_hz);
  f_max = fmin(f_max, 0.5 * v->cfg->audio.sample_rate_hz);
  for (size_t k = 0; k < AF_STRIKE_VIEW_FREQS; k++)
    v->freq_hz[k] = f_max * (double)k / (double)(AF_STRIKE_VIEW_FREQS - 1);
  prepare_model(v);
  prepare_force_spectrum(v, f_max);
  prepare_audio_spectrum(v);
  v->prepared = true;
  return AF_OK;
}

/* ---- draw ------------------------------------------------------------------------ */

af_status af_strike_view_draw(const af_strike_view *v, const af_plot_target *t, char *err,
                              size_t len)
{
  if (!v || !v->prepared) {
    af_text(err, len, "no prepared strike to draw");
    return AF_ENODATA;
  }
  const af_measure_report *r = &v->report;
  char title1[AF_VIEW_TEXT], title2[AF_VIEW_TEXT], fit_label[AF_VIEW_TEXT];
  /* The labels outlive the blocks that fill them: the panels point to them. */
  /* cppcheck-suppress variableScope */
  char band_label[AF_VIEW_TEXT], range_label[AF_VIEW_TEXT], res_label[AF_VIEW_TEXT];
  /* cppcheck-suppress variableScope */
  char level_label[AF_VIEW_TEXT];
  if (v->apple_id)
    af_text(title1, sizeof title1, "apple %u at %.3f s: t#dc#u %.3f ms, %.1f N", v->apple_id,
            (double)v->start_ns * 1e-9, r->contact_time_s * 1e3, r->peak_force_n);
  else
    af_text(title1, sizeof title1, "strike at %.3f s (no apple): t#dc#u %.3f ms, %.1f N",
            (double)v->start_ns * 1e-9, r->contact_time_s * 1e3, r->peak_force_n);
  char subtitle[AF_VIEW_TEXT];
  af_text(title2, sizeof title2, "spectra: %s", r->reliable ? "RELIABLE" : "NOT reliable");
  af_text(subtitle, sizeof subtitle, "%.100s%s", r->reliable ? "" : r->reason,
          strlen(r->reason) > 100 ? "..." : "");
  af_text(fit_label, sizeof fit_label, "model, fitted E#d2#u %.2f MPa, e %.2f",
          r->fitted_modulus_pa * 1e-6, r->fitted_restitution);
  af_plot_series s1[2] = {{"measured (baseline removed)", v->pulse_t_ms, v->pulse_n, v->n_pulse,
                           AF_PLOT_BLUE, AF_PLOT_POINTS},
                          {fit_label, v->model_t_ms, v->model_n, v->have_model ? v->n_model : 0,
                           AF_PLOT_ORANGE, AF_PLOT_LINE}};
  af_plot_panel p[2] = {af_plot_panel_empty(), af_plot_panel_empty()};
  p[0].title = title1;
  p[0].x_label = "time from the contact start [ms]";
  p[0].y_label = "force [N]";
  p[0].series = s1;
  p[0].n_series = v->have_model ? 2 : 1;
  p[0].y_min = 0.0;
  af_plot_series s2[2];
  size_t n2 = 0;
  if (v->have_force_spectrum)
    s2[n2++] = (af_plot_series){"force pulse",        v->freq_hz,   v->force_db,
                                AF_STRIKE_VIEW_FREQS, AF_PLOT_BLUE, AF_PLOT_LINE};
  if (v->have_audio_spectrum)
    s2[n2++] = (af_plot_series){"audio (Hann window)", v->freq_hz,    v->audio_db,
                                AF_STRIKE_VIEW_FREQS,  AF_PLOT_GREEN, AF_PLOT_LINE};
  af_plot_span spans[2];
  size_t ns = 0;
  if (v->has_prediction) {
    af_text(range_label, sizeof range_label, "0S2 range %.0f-%.0f MPa at %.0f g",
            v->cfg->modulus_min_pa * 1e-6, v->cfg->modulus_max_pa * 1e-6, v->mass_kg * 1e3);
    spans[ns++] = (af_plot_span){range_label, v->resonance_low_hz, v->resonance_high_hz,
                                 AF_PLOT_LIGHT_PURPLE};
  }
  if (isfinite(r->band_high_hz)) {
    af_text(band_label, sizeof band_label, "half-power band, lobe %u", r->lobe ? r->lobe : 1);
    spans[ns++] = (af_plot_span){band_label, r->band_low_hz, r->band_high_hz, AF_PLOT_LIGHT_ORANGE};
  }
  af_plot_rule xr[1], yr[1];
  size_t nx = 0, ny = 0;
  if (isfinite(r->resonance_hz)) {
    af_text(res_label, sizeof res_label, "0S2 measured %.0f Hz (Q %.0f, SNR %.0f dB)",
            r->resonance_hz, r->resonance_q, r->snr_db);
    xr[nx++] = (af_plot_rule){res_label, r->resonance_hz, AF_PLOT_RED, false};
  }
  if (isfinite(v->level_db)) {
    af_text(level_label, sizeof level_label, "half-power level (%.1f dB)", v->level_db);
    yr[ny++] = (af_plot_rule){level_label, v->level_db, AF_PLOT_ORANGE, true};
  }
  p[1].title = title2;
  p[1].x_label = "frequency [Hz]";
  p[1].y_label = "level [dB re max]";
  p[1].series = s2;
  p[1].n_series = n2;
  p[1].spans = spans;
  p[1].n_spans = ns;
  p[1].x_rules = xr;
  p[1].n_x_rules = nx;
  p[1].y_rules = yr;
  p[1].n_y_rules = ny;
  p[1].x_min = 0.0;
  p[1].x_max = v->freq_hz[AF_STRIKE_VIEW_FREQS - 1];
  p[1].y_min = AF_VIEW_FLOOR_DB;
  p[1].y_max = 5.0;
  p[1].subtitle = subtitle[0] ? subtitle : NULL;
  p[0].legend = p[1].legend = AF_PLOT_LEGEND_BELOW;
  return af_plot_draw(t, p, 2, 1, err, len);
}
