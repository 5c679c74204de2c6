/* measure.c — one measured strike end to end: the detector's figures, the
 * measured band, the inverse fit, the 0S2 from the microphone, the criteria
 * and the reason (see measure.h). */
#include "measure.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "af_defaults.h"
#include "criteria.h"
#include "lamb.h"
#include "stress.h"
#include "text.h"

/* The measured pulse goes through a spectrum sized as the model's
 * (model.c), or as the fit's longest pulse when that is longer (a faster
 * force stream): 1024 samples is 20 ms at 50 kHz, twice the detector's
 * default max_contact_s; the 4x zero-padding only has to put a grid point
 * inside every minimum, the refinement does the rest. */
#define AF_MEASURE_SPECTRUM_SAMPLES 1024
#define AF_MEASURE_SPECTRUM_PADDING 4
/* The response refuses shorter windows and noise segments (response.c). */
#define AF_MEASURE_MIN_AUDIO 8
/* The 0S2 search stops this far below the audio's Nyquist frequency: the
 * response needs f_hi < Nyquist, and a microphone's anti-alias filter has
 * eaten the last few per cent anyway. */
#define AF_MEASURE_NYQUIST_FRACTION 0.98
/* A hammer bounce inside the contact: a second touch 0.2-0.3 ms after the
 * first, at 15-20 % of it, leaves the fit a residual that is smooth over the
 * contact, where a clean strike leaves white noise. The residual is averaged
 * over AF_MEASURE_BOUNCE_WINDOW_S (9 samples at 50 kHz, at least 3); the mean
 * square of that average against white noise's (the detector's noise RMS
 * squared over the window) and its RMS against the peak are the figures.
 * Two stages, both needed:
 *  - the fit with the rig's v0 (every strike, O(n)): a bounce leaves 45 x
 *    and 2 % of the peak and more; but so does a clean strike whose hammer
 *    ran 5 % off the set v0 (11 x, 1.1 % at 40 dB; 1200 x at 60 dB);
 *  - then, only past both limits, a fit with v0 free (one more fit): a
 *    clean strike at any v0 leaves noise (1.6 x at most, 0.4 % of the peak
 *    at 40 dB; 4.6 x but 0.02 % at 80 dB), a second touch of its own shape
 *    (sin^1.5 over 0.4 ms) 6.9 x and 1.0 % of the peak and more.
 * A bounce that is a scaled copy of the first pulse is a Hertz pulse of
 * another v0, E2 and e to the fit with v0 free (its residual is noise): it
 * is not seen here (its impulse reads a v0 10-20 % high). Measured in
 * test_bounce.c and with E2 4-12 MPa, e 0.4-0.8, 40-80 dB. */
#define AF_MEASURE_BOUNCE_WINDOW_S 0.18e-3
#define AF_MEASURE_BOUNCE_MIN_WINDOW 3
#define AF_MEASURE_BOUNCE_RIG_RATIO 8.0    /* stage 1: x white noise's mean square */
#define AF_MEASURE_BOUNCE_FREE_RATIO 4.0   /* stage 2 */
#define AF_MEASURE_BOUNCE_PEAK_RATIO 0.005 /* both: the smoothed residual's RMS / peak */
/* Fewer than this many windows in the pulse: too short to tell a bounce
 * from the pulse's own shape (the 9-sample pulses of a steel tip). */
#define AF_MEASURE_BOUNCE_MIN_WINDOWS 4

struct af_measure {
  af_measure_config cfg;
  af_spectrum *spectrum;
  af_fit *fit;
  af_fit *shape_fit; /* the same fit with v0 free: the bounce test's second stage */
  af_response *response;
  size_t window_samples; /* audio analysed at most [samples] */
  size_t noise_samples;  /* noise reference used at most [samples] */
  /* xi and tau_max/p0 depend on the Poisson ratio (and the shear mode)
   * only; their GSL solvers allocate, so they are solved on the first strike
   * of a new ratio and cached. */
  af_lamb_cache xi;
  af_shear_cache shear;
  af_sphere_modes_cache sphere; /* the Lamb ratios of the 0S2's neighbours, per nu */
  af_response_result peaks[AF_RESPONSE_MAX_PEAKS]; /* af_response_execute_peaks' list */
  af_stage_hook response_stages; /* the response's transform, passed on to cfg.stages */
  int64_t response_fft_ns;       /* its time in this strike's audio step [ns] */
};

/* What the steps of one strike found, for the criteria and the reason. */
typedef struct {
  af_status band_status; /* af_strike_measure_band */
  af_lobe band;
  af_status fit_status; /* af_fit_execute */
  double fit_residual;  /* relative residual, NaN when the fit did not run */
  bool bounce;          /* the fit's residual is structured: a second impact inside the
                           contact */
  double bounce_noise_ratio, bounce_peak_ratio; /* its figures (af_verdict's), NaN untested */
  af_status audio_status; /* af_response_execute; AF_ENODATA also for no audio */
  size_t n_audio;
  double f_lo_hz, f_hi_hz; /* searched 0S2 range */
  af_status judge_status;  /* Lamb root or shear ratio failed (a bad Poisson ratio) */
  bool tap_only;           /* no pulse: the 0S2's prior from the mass and the modulus range */
  /* No candidate in the range, but a peak just outside it (verdict.h):
   * its frequency [Hz], SNR [dB] and E2 by Lamb [Pa]. */
  bool outside;
  double outside_hz, outside_snr_db, outside_modulus_pa;
  size_t n_peaks; /* the peaks listed around the range (m->peaks) */
  /* A stray partial (stray_partial): its frequency [Hz] and SNR [dB]; NaN: none. */
  double stray_hz, stray_snr_db;
} af_measure_steps;

/* ---- configuration and life cycle ------------------------------------------ */

af_measure_config af_measure_config_default(void)
{
  af_measure_config c;
  c.fit = af_fit_config_default();
  c.fit.fit_velocity = false; /* the rig sets v0 (measure_fit_velocity's default) */
  c.response = af_response_config_default();
  c.audio_delay_s = AF_DEFAULT_MEASURE_AUDIO_DELAY_S;
  c.audio_window_s = AF_DEFAULT_MEASURE_AUDIO_WINDOW_S;
  c.noise_window_s = AF_DEFAULT_MEASURE_NOISE_WINDOW_S;
  c.noise_guard_s = AF_DEFAULT_MEASURE_NOISE_GUARD_S;
  c.range_margin = AF_DEFAULT_MEASURE_RANGE_MARGIN;
  c.fruit_q_min = AF_DEFAULT_FRUIT_Q_MIN;
  c.fruit_q_max = AF_DEFAULT_FRUIT_Q_MAX;
  c.fruit_confidence_min = AF_DEFAULT_FRUIT_CONFIDENCE_MIN;
  c.fruit_neighbour_margin_db = AF_DEFAULT_FRUIT_NEIGHBOUR_MARGIN_DB;
  c.modes = af_modes_config_default();
  c.modulus_prior_rel_sd = 0.10;
  c.stages = NULL;
  return c;
}

static bool finite_nonneg(double v)
{
  return isfinite(v) && v >= 0.0;
}

/* Checks the fields measure.c owns; the fit and response configurations are
 * checked by their own create. Sets the window lengths in samples. */
static af_status measure_check(const af_measure_config *c, size_t *window_n, size_t *noise_n)
{
  double rate = c->response.sample_rate_hz;
  if (!(isfinite(rate) && rate > 0.0) || !finite_nonneg(c->audio_delay_s) ||
      !(isfinite(c->audio_window_s) && c->audio_window_s > 0.0) ||
      !finite_nonneg(c->noise_window_s) || !finite_nonneg(c->noise_guard_s) ||
      !(c->range_margin >= 0.0 && c->range_margin < 1.0) ||
      !(isfinite(c->modulus_prior_rel_sd) && c->modulus_prior_rel_sd > 0.0) ||
      !(c->fruit_q_min > 0.0 && c->fruit_q_min < c->fruit_q_max && isfinite(c->fruit_q_max)) ||
      !(c->fruit_confidence_min >= 0.0 && c->fruit_confidence_min <= 1.0) ||
      !finite_nonneg(c->fruit_neighbour_margin_db))
    return AF_EINVAL;
  double w = round(c->audio_window_s * rate), z = round(c->noise_window_s * rate);
  double cap = (double)c->response.window_samples;
  if (w < AF_MEASURE_MIN_AUDIO || w > cap || z > cap)
    return AF_EINVAL;
  *window_n = (size_t)w;
  *noise_n = (size_t)z;
  return AF_OK;
}

/* The spectrum for pulses up to the fit's longest (at least the model's
 * 1024 samples); an absurd length is left to af_spectrum_create to refuse. */
static af_status measure_spectrum_create(size_t fit_max_samples, af_spectrum **out)
{
  af_spectrum_config sc = af_spectrum_config_default();
  sc.max_samples =
      fit_max_samples > AF_MEASURE_SPECTRUM_SAMPLES ? fit_max_samples : AF_MEASURE_SPECTRUM_SAMPLES;
  sc.max_lobes = AF_MODEL_MAX_LOBES;
  sc.fft_size = 1;
  while (sc.fft_size / AF_MEASURE_SPECTRUM_PADDING < sc.max_samples && sc.fft_size < SIZE_MAX / 4)
    sc.fft_size *= 2;
  return af_spectrum_create(&sc, out);
}

/* The response's transform (fft), inside the audio step (modes): passed on,
 * and kept so that modes is reported without it. */
static void response_stage(af_stage stage, int64_t elapsed_ns, void *user)
{
  af_measure *m = user;
  m->response_fft_ns += elapsed_ns;
  m->cfg.stages->fn(stage, elapsed_ns, m->cfg.stages->user);
}

af_status af_measure_create(const af_measure_config *cfg, af_measure **out)
{
  size_t window_n = 0, noise_n = 0;
  if (out == NULL)
    return AF_EINVAL;
  *out = NULL;
  if (cfg == NULL || measure_check(cfg, &window_n, &noise_n) != AF_OK)
    return AF_EINVAL;
  af_status_init();
  af_measure *m = calloc(1, sizeof *m);
  if (m == NULL)
    return AF_ENOMEM;
  m->cfg = *cfg;
  if (cfg->stages != NULL && cfg->stages->fn != NULL) { /* the transform timed as fft */
    m->response_stages.fn = response_stage;
    m->response_stages.user = m;
    m->cfg.response.stages = &m->response_stages;
  }
  m->window_samples = window_n;
  m->noise_samples = noise_n;
  af_lamb_cache_reset(&m->xi);
  af_shear_cache_reset(&m->shear);
  af_sphere_modes_cache_reset(&m->sphere);
  af_status st = af_fit_create(&cfg->fit, &m->fit);
  af_fit_config shape = cfg->fit;
  shape.fit_velocity = true;
  if (st == AF_OK)
    st = af_fit_create(&shape, &m->shape_fit);
  if (st == AF_OK)
    st = measure_spectrum_create(cfg->fit.max_samples, &m->spectrum);
  if (st == AF_OK)
    st = af_response_create(&m->cfg.response, &m->response);
  if (st != AF_OK) {
    af_measure_destroy(m);
    return st;
  }
  *out = m;
  return AF_OK;
}

void af_measure_destroy(af_measure *m)
{
  if (m == NULL)
    return;
  af_spectrum_destroy(m->spectrum);
  af_fit_destroy(m->fit);
  af_fit_destroy(m->shape_fit);
  af_response_destroy(m->response);
  free(m);
}

const af_measure_config *af_measure_get_config(const af_measure *m)
{
  return m == NULL ? NULL : &m->cfg;
}

af_status af_measure_prepare(af_measure *m, const af_model_params *p)
{
  double xi, ratio;
  if (m == NULL || p == NULL)
    return AF_EINVAL;
  af_sphere_modes modes;
  af_status st = af_lamb_root_cached(&m->xi, p->impact.fruit_poisson, &xi);
  if (st == AF_OK)
    st = af_stress_shear_ratio_cached(&m->shear, p->shear_ratio, p->impact.fruit_poisson, &ratio);
  if (st == AF_OK)
    st = af_lamb_sphere_modes_cached(&m->sphere, p->impact.fruit_poisson, &modes);
  return st;
}

/* ---- the steps of one strike ---------------------------------------------- */

static bool apple_valid(const af_measure_apple *a)
{
  return af_model_params_check(&a->model, NULL) == AF_OK && isfinite(a->modulus_max_pa) &&
         a->modulus_min_pa > 0.0 && a->modulus_max_pa > a->modulus_min_pa;
}

/* Every figure NaN, the detector's copied: a part that fails leaves NaN. */
static void report_start(const af_strike_event *ev, unsigned lobe, af_measure_report *out)
{
  memset(out, 0, sizeof *out);
  out->contact_time_s = ev->contact_time_s;
  out->peak_force_n = ev->peak_force_n;
  out->impulse_n_s = ev->impulse_n_s;
  out->lobe = lobe;
  out->band_low_hz = out->band_high_hz = NAN;
  out->resonance_hz = out->resonance_q = out->snr_db = NAN;
  out->stiffness_factor = out->modulus_from_resonance_pa = NAN;
  out->fitted_modulus_pa = out->fitted_restitution = out->fit_residual = NAN;
  out->fitted_modulus_se_pa = out->fitted_restitution_se = NAN;
  out->fitted_velocity_m_s = NAN;
  out->delivered_energy_j = out->absorbed_energy_j = NAN;
  out->max_shear_stress_pa = out->yield_shear_stress_pa = NAN;
  out->double_hit = ev->double_hit;
  out->clipped = ev->clipped;
  out->lost_samples = ev->lost_samples > UINT32_MAX ? UINT32_MAX : (uint32_t)ev->lost_samples;
  af_verdict_clear(&out->verdict);
  out->modes.peak = AF_MODES_NO_PEAK;
  out->modes.frequency_hz = out->modes.f_pred_hz = out->modes.prior_z = NAN;
}

/* The band of the configured lobe, by the code path of the model's spectrum. */
static void step_band(af_measure *m, const af_strike_event *ev, af_band_level level, unsigned lobe,
                      af_measure_report *out, af_measure_steps *s)
{
  s->band_status = af_strike_measure_band(m->spectrum, ev, level, lobe, &s->band, NULL);
  if (s->band_status != AF_OK)
    return;
  out->band_low_hz = s->band.band_low_hz;
  out->band_high_hz = s->band.band_high_hz;
}

/* The smoothed residual of fit f (AF_MEASURE_BOUNCE_WINDOW_S), as mean
 * square against white noise's (*noise_ratio) and RMS against the peak
 * (*peak_ratio): a running sum, O(n), no buffer. False when f left no
 * residual or the pulse is too short for the test. */
static bool residual_structure(const af_fit *f, const af_strike_event *ev, double *noise_ratio,
                               double *peak_ratio)
{
  const double *r = NULL;
  size_t n = 0;
  if (af_fit_get_residual(f, &r, &n) != AF_OK || !(ev->peak_force_n > 0.0))
    return false;
  size_t w = (size_t)lround(AF_MEASURE_BOUNCE_WINDOW_S / ev->dt_s);
  w = w < AF_MEASURE_BOUNCE_MIN_WINDOW ? AF_MEASURE_BOUNCE_MIN_WINDOW : w;
  if (n < AF_MEASURE_BOUNCE_MIN_WINDOWS * w)
    return false;
  double sum = 0.0, ms = 0.0; /* the window's sum; the mean square of its mean [N^2] */
  for (size_t k = 0; k < n; k++) {
    sum += r[k] - (k >= w ? r[k - w] : 0.0);
    if (k + 1 >= w)
      ms += (sum / (double)w) * (sum / (double)w);
  }
  ms /= (double)(n + 1 - w);
  const double noise_ms = ev->noise_rms_n * ev->noise_rms_n / (double)w;
  *noise_ratio = noise_ms > 0.0 ? ms / noise_ms : INFINITY;
  *peak_ratio = sqrt(ms) / ev->peak_force_n;
  return true;
}

/* The bounce test's two stages (AF_MEASURE_BOUNCE_WINDOW_S): the figures
 * are the last stage run's, NaN when the pulse is too short. */
static void step_bounce(af_measure *m, const af_strike_event *ev, const af_impact_params *start,
                        af_measure_steps *s)
{
  double rig = NAN, peak = NAN;
  /* A clipped, cut or holed pulse is not a Hertz pulse either, and has its
   * own flag: a bounce would only hide the clearer reason. */
  if (ev->clipped || ev->truncated || ev->lost_samples > 0 ||
      !residual_structure(m->fit, ev, &rig, &peak))
    return;
  s->bounce_noise_ratio = rig;
  s->bounce_peak_ratio = peak;
  if (rig < AF_MEASURE_BOUNCE_RIG_RATIO || peak < AF_MEASURE_BOUNCE_PEAK_RATIO)
    return;
  const af_fit *f = m->fit;
  if (!m->cfg.fit.fit_velocity) { /* else the rig's fit had v0 free already */
    af_fit_result r;
    if (af_fit_execute(m->shape_fit, start, ev->pulse_n, ev->n_samples, ev->dt_s, ev->pulse_t0_s,
                       &r) != AF_OK)
      return;
    f = m->shape_fit;
  }
  if (!residual_structure(f, ev, &s->bounce_noise_ratio, &s->bounce_peak_ratio))
    return;
  s->bounce = s->bounce_noise_ratio >= AF_MEASURE_BOUNCE_FREE_RATIO &&
              s->bounce_peak_ratio >= AF_MEASURE_BOUNCE_PEAK_RATIO;
}

/* E2 and e (v0 when configured free, t0) from the prediction's nominal
 * apple. The start's e must lie inside the fit's open range: an elastic
 * (e = 1) prediction starts just below it. */
static void step_fit(af_measure *m, const af_strike_event *ev, const af_measure_apple *apple,
                     af_measure_report *out, af_measure_steps *s)
{
  af_impact_params start = apple->model.impact;
  af_fit_result r;
  start.restitution = fmin(fmax(start.restitution, 2.0 * AF_FIT_RESTITUTION_MIN), 0.95);
  s->fit_status = ev->pulse_n == NULL ? AF_EINVAL
                                      : af_fit_execute(m->fit, &start, ev->pulse_n, ev->n_samples,
                                                       ev->dt_s, ev->pulse_t0_s, &r);
  s->fit_residual =
      s->fit_status == AF_EINVAL || s->fit_status == AF_ESIZE ? NAN : r.relative_residual;
  out->fit_residual = s->fit_residual;
  if (s->fit_status != AF_OK)
    return;
  step_bounce(m, ev, &start, s);
  out->double_hit |= s->bounce;
  out->fitted_modulus_pa = r.modulus_pa;
  out->fitted_modulus_se_pa = r.modulus_se_pa;
  out->fitted_restitution = r.restitution;
  out->fitted_restitution_se = r.restitution_se;
  if (m->cfg.fit.fit_velocity) /* else r.velocity_m_s is the start's, the set value */
    out->fitted_velocity_m_s = r.velocity_m_s;
  /* The fitted model's contact time uses every sample of the pulse: 0.3 %
   * RMS at 40 dB against the detector's 1 % from its two edges alone
   * (strike.h), whose figure stays the fallback when the fit fails. */
  out->contact_time_s = r.contact_time_s;
}

/* The strike's energy (model.h): the rig's hammer at the v0 the fit freed or
 * the rig's, the absorbed share from the fitted e; NaN where not known. */
static void step_energy(const af_measure *m, const af_measure_apple *apple, af_measure_report *out)
{
  const af_impact_params *rig = &apple->model.impact;
  double v0_m_s =
      m->cfg.fit.fit_velocity && !out->tap_only ? out->fitted_velocity_m_s : rig->velocity_m_s;
  out->delivered_energy_j = af_impact_delivered_energy_j(rig->hammer_mass_kg, v0_m_s);
  out->absorbed_energy_j =
      af_impact_absorbed_energy_j(out->delivered_energy_j, out->fitted_restitution);
}

/* The model's 0S2 over the cultivar's firmness range for this apple's mass,
 * widened by the margin, kept below the audio's Nyquist frequency. */
static void lamb_range(const af_measure *m, const af_measure_apple *apple, double xi,
                       double *f_lo_hz, double *f_hi_hz)
{
  const af_model_params *p = &apple->model;
  double nu = p->impact.fruit_poisson, margin = m->cfg.range_margin;
  double lo = af_lamb_frequency_hz(xi, p->modulus_factor * apple->modulus_min_pa, nu,
                                   p->fruit_density_kg_m3, p->fruit_mass_kg);
  double hi = af_lamb_frequency_hz(xi, p->modulus_factor * apple->modulus_max_pa, nu,
                                   p->fruit_density_kg_m3, p->fruit_mass_kg);
  *f_lo_hz = lo * (1.0 - margin);
  *f_hi_hz =
      fmin(hi * (1.0 + margin), 0.5 * AF_MEASURE_NYQUIST_FRACTION * m->cfg.response.sample_rate_hz);
}

/* The noise reference is this strike's own (cleared, then added): the report
 * then depends on this strike's audio alone, not on the history of the
 * station, and a changed noise environment shows at once. Its last
 * noise_samples samples, those nearest the strike; too short or non-finite:
 * the window's own noise band instead. */
static void set_noise(af_measure *m, const float *noise, size_t n_noise, const af_measure_steps *s)
{
  af_response_clear_noise(m->response);
  if (noise == NULL || n_noise < AF_MEASURE_MIN_AUDIO || m->noise_samples < AF_MEASURE_MIN_AUDIO)
    return;
  size_t n = n_noise < m->noise_samples ? n_noise : m->noise_samples;
  /* the reference only as high as the peak list's band (identify) reads it */
  double band_lo, band_hi = INFINITY;
  if (af_modes_list_band(s->f_lo_hz, s->f_hi_hz, m->cfg.response.sample_rate_hz, &band_lo,
                         &band_hi) != AF_OK)
    band_hi = INFINITY;
  (void)af_response_add_noise_below(m->response, noise + (n_noise - n), n, band_hi);
}

/* The 0S2 predicted from the fitted E2 [Hz], the prior of the mode
 * identification; NaN when the fit failed. Tap-only (no pulse, no fit): the
 * middle (in ln f) of the range for this mass and the cultivar's modulus
 * range, [f_lo, f_hi] before the margin. */
static double predicted_0s2_hz(const af_measure_apple *apple, const af_measure_report *out,
                               double xi, const af_measure_steps *s)
{
  const af_model_params *p = &apple->model;
  if (s->tap_only)
    return af_lamb_frequency_hz(
        xi, p->modulus_factor * sqrt(apple->modulus_min_pa * apple->modulus_max_pa),
        p->impact.fruit_poisson, p->fruit_density_kg_m3, p->fruit_mass_kg);
  if (!isfinite(out->fitted_modulus_pa))
    return NAN;
  return af_lamb_frequency_hz(xi, p->modulus_factor * out->fitted_modulus_pa,
                              p->impact.fruit_poisson, p->fruit_density_kg_m3, p->fruit_mass_kg);
}

/* No candidate in the range: the strongest listed peak above the SNR
 * threshold within AF_VERDICT_OUTSIDE_FACTOR below or above it, for the
 * reason to name with the modulus it implies (the strike stays unreliable).
 * The list's band reaches 0.8 f_lo below the range (af_modes_list_band), so
 * a peak under that is not seen. */
static void outside_peak(const af_measure *m, const af_measure_apple *apple, double xi,
                         size_t n_peaks, af_measure_steps *s)
{
  const af_model_params *p = &apple->model;
  const double lo = s->f_lo_hz / AF_VERDICT_OUTSIDE_FACTOR,
               hi = s->f_hi_hz * AF_VERDICT_OUTSIDE_FACTOR;
  for (size_t k = 0; k < n_peaks; k++) {
    const af_response_result *r = &m->peaks[k];
    const double f = r->frequency_hz;
    const bool near = (f >= lo && f < s->f_lo_hz) || (f > s->f_hi_hz && f <= hi);
    if (!near || !(r->snr_db >= m->cfg.response.snr_threshold_db) ||
        (s->outside && !(r->snr_db > s->outside_snr_db)))
      continue;
    s->outside = true;
    s->outside_hz = f;
    s->outside_snr_db = r->snr_db;
    s->outside_modulus_pa = af_lamb_modulus_pa(xi, f, p->impact.fruit_poisson,
                                               p->fruit_density_kg_m3, p->fruit_mass_kg) /
                            p->modulus_factor;
  }
}

/* Lists the damped peaks around the 0S2 range and identifies the 0S2 among
 * them (modes.h); the status of step_audio's old single-peak reading:
 * AF_OK (an identification, ambiguous or not), AF_ENODATA (no candidate
 * cleared the SNR threshold: out->snr_db the best rejected one's), or the
 * response's error. */
static af_status identify(af_measure *m, const af_measure_apple *apple, const float *audio,
                          size_t n, double xi, af_measure_report *out, af_measure_steps *s)
{
  af_sphere_modes modes;
  double band_lo, band_hi;
  size_t n_peaks = 0;
  af_status st = af_lamb_sphere_modes_cached(&m->sphere, apple->model.impact.fruit_poisson, &modes);
  if (st == AF_OK)
    st = af_modes_list_band(s->f_lo_hz, s->f_hi_hz, m->cfg.response.sample_rate_hz, &band_lo,
                            &band_hi);
  if (st == AF_OK)
    st = af_response_execute_peaks(m->response, audio, n, band_lo, band_hi, m->peaks,
                                   AF_RESPONSE_MAX_PEAKS, &n_peaks);
  if (st == AF_ENODATA)
    out->snr_db = m->peaks[0].snr_db; /* the best rejected candidate's */
  if (st != AF_OK)
    return st;
  s->n_peaks = n_peaks;
  /* The fit's own standard error and the calibration's, in quadrature;
   * f goes as sqrt(E): half the relative uncertainty in ln f. Tap-only: the
   * modulus range [min, max] taken as +-2 sigma of ln E, i.e. ln(max / min) / 4. */
  const double se = out->fitted_modulus_se_pa / out->fitted_modulus_pa;
  const double cal = s->tap_only ? 0.25 * log(apple->modulus_max_pa / apple->modulus_min_pa)
                                 : m->cfg.modulus_prior_rel_sd;
  const af_modes_input in = {
      .peaks = m->peaks,
      .n_peaks = n_peaks,
      .band_lo_hz = band_lo,
      .band_hi_hz = band_hi,
      .f_lo_hz = s->f_lo_hz,
      .f_hi_hz = s->f_hi_hz,
      .modes = &modes,
      .f_pred_hz = predicted_0s2_hz(apple, out, xi, s),
      .f_pred_rel_sd = 0.5 * sqrt((isfinite(se) && !s->tap_only ? se * se : 0.0) + cal * cal)};
  st = af_modes_execute(&m->cfg.modes, &in, &out->modes);
  af_modes_format(&out->modes, out->modes_text, sizeof out->modes_text);
  if (st == AF_ENODATA) { /* peaks, none in the 0S2 range: the best in range is none */
    out->snr_db = -INFINITY;
    for (size_t k = 0; k < n_peaks; k++)
      if (m->peaks[k].frequency_hz >= s->f_lo_hz && m->peaks[k].frequency_hz <= s->f_hi_hz)
        out->snr_db = fmax(out->snr_db, m->peaks[k].snr_db);
    outside_peak(m, apple, xi, n_peaks, s);
  }
  return st;
}

/* The span of the sphere's comb above the 0S2 (lamb.h: 0S3 1.49x, 0S4 1.92x,
 * 1S2 1.94x at nu 0.35, a few per cent either way over nu 0.25..0.45): 1.2
 * keeps the 0S2's own split and the 0T2 (0.94x) out, 2.1 the modes above. */
#define AF_MEASURE_COMB_LOW 1.2
#define AF_MEASURE_COMB_HIGH 2.1

static bool comb_partner(const af_modes_id *id)
{
  for (size_t k = 0; k < id->n_matched; k++)
    if (id->matched[k].mode == AF_MODE_0S3 || id->matched[k].mode == AF_MODE_0S4 ||
        id->matched[k].mode == AF_MODE_1S2)
      return true;
  return false;
}

/* A fruit heard above its 0S2 rings in the sphere's comb. When none of the
 * comb's modes is heard but another peak in its span is, within
 * fruit_neighbour_margin_db of the 0S2 or louder, the sound is another
 * object's: its partials stand at ratios the sphere does not have. The
 * loudest such peak is kept for the reason. Tap-only: with a force
 * transducer the pulse's fitted modulus already says the hammer met fruit
 * flesh, and a mode of the rig (the support, the hammer) may stand there. */
static void stray_partial(const af_measure *m, const af_measure_report *out, af_measure_steps *s)
{
  if (!s->tap_only || comb_partner(&out->modes))
    return;
  const af_response_result *r0 = &m->peaks[out->modes.peak];
  for (size_t k = 0; k < s->n_peaks; k++) {
    const af_response_result *r = &m->peaks[k];
    const double ratio = r->frequency_hz / r0->frequency_hz;
    if (!(ratio >= AF_MEASURE_COMB_LOW && ratio <= AF_MEASURE_COMB_HIGH) ||
        !(r->snr_db >= m->cfg.response.snr_threshold_db) ||
        !(r->snr_db >= r0->snr_db - m->cfg.fruit_neighbour_margin_db) ||
        (isfinite(s->stray_snr_db) && !(r->snr_db > s->stray_snr_db)))
      continue;
    s->stray_hz = r->frequency_hz;
    s->stray_snr_db = r->snr_db;
  }
}

/* The 0S2 among the microphone's peaks; stiffness factor and the modulus,
 * divided by the modulus factor so that it compares with the quasi-static E2
 * of the contact and of the fit. */
static void step_audio(af_measure *m, const af_measure_apple *apple, const float *audio,
                       size_t n_audio, const float *noise, size_t n_noise, af_measure_report *out,
                       af_measure_steps *s)
{
  const af_model_params *p = &apple->model;
  double xi;
  s->n_audio = audio == NULL ? 0 : n_audio;
  s->audio_status = AF_ENODATA;
  s->judge_status = af_lamb_root_cached(&m->xi, p->impact.fruit_poisson, &xi);
  if (s->judge_status != AF_OK || s->n_audio < AF_MEASURE_MIN_AUDIO)
    return;
  lamb_range(m, apple, xi, &s->f_lo_hz, &s->f_hi_hz);
  set_noise(m, noise, n_noise, s);
  size_t n = s->n_audio < m->window_samples ? s->n_audio : m->window_samples;
  s->audio_status = identify(m, apple, audio, n, xi, out, s);
  if (s->audio_status != AF_OK)
    return;
  stray_partial(m, out, s);
  const af_response_result *r = &m->peaks[out->modes.peak];
  out->resonance_hz = r->frequency_hz;
  out->resonance_q = r->q;
  out->snr_db = r->snr_db;
  out->stiffness_factor = af_lamb_stiffness_factor(r->frequency_hz, p->fruit_mass_kg);
  out->modulus_from_resonance_pa = af_lamb_modulus_pa(xi, r->frequency_hz, p->impact.fruit_poisson,
                                                      p->fruit_density_kg_m3, p->fruit_mass_kg) /
                                   p->modulus_factor;
}

/* tau_max from the measured peak force through the elastic Hertz contact
 * radius with the fitted E2 (the deformation is not measured), against the
 * yield stress of the fitted E2. */
static void step_stress(af_measure *m, const af_measure_apple *apple, af_measure_report *out,
                        af_measure_steps *s)
{
  const af_model_params *p = &apple->model;
  double ratio;
  if (!isfinite(out->fitted_modulus_pa) || !isfinite(out->peak_force_n))
    return;
  af_status st =
      af_stress_shear_ratio_cached(&m->shear, p->shear_ratio, p->impact.fruit_poisson, &ratio);
  if (st != AF_OK) {
    s->judge_status = st;
    return;
  }
  af_impact_params fitted = p->impact;
  fitted.fruit_modulus_pa = out->fitted_modulus_pa;
  double a_m = af_stress_hertz_contact_radius_m(fmax(out->peak_force_n, 0.0),
                                                af_impact_effective_radius_m(&fitted),
                                                af_impact_effective_modulus_pa(&fitted));
  out->max_shear_stress_pa = ratio * af_stress_center_pressure_pa(out->peak_force_n, a_m);
  af_yield_law law = af_model_yield_law(p);
  out->yield_shear_stress_pa = af_yield_shear_pa(&law, out->fitted_modulus_pa);
}

/* ---- verdict ------------------------------------------------------------------ */

/* The flags that make a strike unclean, whatever the criteria say. */
static void verdict_clean(const af_strike_event *ev, const af_measure_steps *s, af_verdict *v)
{
  v->flags |= (ev->double_hit ? AF_VERDICT_DOUBLE_HIT : 0u) |
              (ev->clipped ? AF_VERDICT_CLIPPED : 0u) |
              (ev->lost_samples > 0 ? AF_VERDICT_LOST_SAMPLES : 0u) |
              (ev->truncated ? AF_VERDICT_TRUNCATED : 0u);
  v->flags |= s->bounce ? AF_VERDICT_DOUBLE_HIT : 0u;
  v->bounce_inside = s->bounce;
  v->bounce_noise_ratio = s->bounce_noise_ratio;
  v->bounce_peak_ratio = s->bounce_peak_ratio;
  v->lost_samples = ev->lost_samples;
  v->spectrum_status = s->band_status;
  if (s->band_status != AF_OK && s->band_status != AF_ENOLOBE)
    v->flags |= AF_VERDICT_SPECTRUM_FAILED;
  v->fit_status = s->fit_status;
  v->fit_residual = s->fit_residual;
  if (s->fit_status != AF_OK)
    v->flags |= AF_VERDICT_FIT_FAILED;
  v->judge_status = s->judge_status;
  if (s->judge_status != AF_OK)
    v->flags |= AF_VERDICT_POISSON;
}

static void verdict_audio(const af_measure *m, const af_measure_steps *s,
                          const af_measure_report *out, af_verdict *v)
{
  v->audio_status = s->audio_status;
  v->snr_db = out->snr_db;
  v->snr_threshold_db = m->cfg.response.snr_threshold_db;
  v->f_lo_hz = s->f_lo_hz;
  v->f_hi_hz = s->f_hi_hz;
  v->n_audio = s->n_audio;
  if (s->judge_status != AF_OK || s->audio_status == AF_OK)
    return;
  if (s->n_audio < AF_MEASURE_MIN_AUDIO) {
    v->flags |= AF_VERDICT_NO_AUDIO;
    v->audio_cause = s->n_audio == 0 ? AF_AUDIO_NOT_GIVEN : AF_AUDIO_TOO_SHORT;
  } else if (s->audio_status == AF_ENODATA) {
    v->flags |= AF_VERDICT_NO_RESONANCE;
    if (s->outside) {
      v->outside_hz = s->outside_hz;
      v->outside_snr_db = s->outside_snr_db;
      v->outside_modulus_pa = s->outside_modulus_pa;
    }
  } else if (s->audio_status == AF_EINVAL)
    v->flags |= AF_VERDICT_RANGE_NYQUIST;
  else
    v->flags |= AF_VERDICT_AUDIO_FAILED;
}

/* Two peaks could be the 0S2: the strike cannot say which (modes.h). */
static void verdict_modes(const af_measure_report *out, af_verdict *v)
{
  if (!out->modes.ambiguous)
    return;
  v->flags |= AF_VERDICT_MODE_AMBIGUOUS;
  af_text(v->mode_text, sizeof v->mode_text, "%s", out->modes_text);
}

/* Fruit or not (the heard mode must sound like fruit flesh): its Q within
 * fruit_q_min..fruit_q_max, no stray partial where the sphere's comb would
 * be, and an identification at fruit_confidence_min or above. */
static void verdict_fruit(const af_measure *m, const af_measure_report *out,
                          const af_measure_steps *s, af_verdict *v)
{
  if (!isfinite(out->resonance_hz) || out->modes.ambiguous)
    return;
  const double q = out->resonance_q;
  uint32_t cause = 0;
  if (isfinite(q) && (q < m->cfg.fruit_q_min || q > m->cfg.fruit_q_max))
    cause |= AF_NOT_FRUIT_Q;
  if (isfinite(s->stray_hz))
    cause |= AF_NOT_FRUIT_NEIGHBOURS;
  if (out->modes.confidence < m->cfg.fruit_confidence_min)
    cause |= AF_NOT_FRUIT_CONFIDENCE;
  if (cause == 0)
    return;
  v->flags |= AF_VERDICT_NOT_FRUIT;
  v->not_fruit = cause;
  v->resonance_hz = out->resonance_hz;
  v->resonance_q = q;
  v->fruit_q_min = m->cfg.fruit_q_min;
  v->fruit_q_max = m->cfg.fruit_q_max;
  v->stray_hz = s->stray_hz;
  v->stray_db = s->stray_snr_db - out->snr_db;
  v->mode_confidence = out->modes.confidence;
  v->fruit_confidence_min = m->cfg.fruit_confidence_min;
}

/* The criteria on what was measured. The heard mode is the evidence that
 * the strike excited it: the paper's band criterion predicts, before a
 * strike, whether it will (the prediction, excites_mode); on a measured
 * strike the 0S2 heard above its SNR threshold and identified answers
 * that, if it sounds like fruit flesh (verdict_fruit). A criterion that
 * could not be judged (no resonance, no fitted E2) is already flagged above. */
static void verdict_criteria(const af_measure *m, const af_measure_apple *apple,
                             const af_measure_report *out, const af_measure_steps *s, af_verdict *v)
{
  v->lobe = apple->model.lobe;
  verdict_fruit(m, out, s, v);
  if (isfinite(out->max_shear_stress_pa) && isfinite(out->yield_shear_stress_pa) &&
      !out->no_damage) {
    v->flags |= AF_VERDICT_DAMAGE;
    v->max_shear_pa = out->max_shear_stress_pa;
    v->yield_shear_pa = out->yield_shear_stress_pa;
  }
}

static void verdict_judge(const af_measure *m, const af_strike_event *ev,
                          const af_measure_apple *apple, const af_measure_steps *s,
                          af_measure_report *out)
{
  af_verdict *v = &out->verdict;
  out->excites_mode =
      af_criteria_excites_mode(s->band_status == AF_OK ? &s->band : NULL, out->resonance_hz);
  out->no_damage = isfinite(out->max_shear_stress_pa) && isfinite(out->yield_shear_stress_pa) &&
                   af_criteria_no_damage(out->max_shear_stress_pa, out->yield_shear_stress_pa);
  verdict_clean(ev, s, v);
  v->modulus_min_pa = apple->modulus_min_pa;
  v->modulus_max_pa = apple->modulus_max_pa;
  verdict_audio(m, s, out, v);
  verdict_modes(out, v);
  verdict_criteria(m, apple, out, s, v);
  out->reliable = v->flags == 0 && out->no_damage;
  af_verdict_format(v, out->reason, sizeof out->reason);
}

/* The audio step timed as modes, less the response's transform (timed as fft). */
static void timed_audio(af_measure *m, const af_measure_apple *apple, const float *audio,
                        size_t n_audio, const float *noise, size_t n_noise, af_measure_report *out,
                        af_measure_steps *s)
{
  const af_stage_hook *h = m->cfg.stages;
  m->response_fft_ns = 0;
  const int64_t t0_ns = af_stage_begin(h);
  step_audio(m, apple, audio, n_audio, noise, n_noise, out, s);
  if (h != NULL && h->fn != NULL)
    h->fn(AF_STAGE_MODES, af_stage_now_ns() - t0_ns - m->response_fft_ns, h->user);
}

af_status af_measure_execute(af_measure *m, const af_strike_event *ev,
                             const af_measure_apple *apple, const float *audio, size_t n_audio,
                             const float *noise, size_t n_noise, af_measure_report *out)
{
  if (m == NULL || ev == NULL || apple == NULL || out == NULL || (audio == NULL && n_audio > 0) ||
      !(isfinite(ev->dt_s) && ev->dt_s > 0.0) || !apple_valid(apple))
    return AF_EINVAL;
  af_measure_steps s = {.band_status = AF_OK,
                        .fit_residual = NAN,
                        .bounce_noise_ratio = NAN,
                        .bounce_peak_ratio = NAN,
                        .f_lo_hz = NAN,
                        .f_hi_hz = NAN,
                        .stray_hz = NAN,
                        .stray_snr_db = NAN};
  const af_stage_hook *h = m->cfg.stages;
  report_start(ev, apple->model.lobe, out);
  int64_t t0_ns = af_stage_begin(h);
  step_band(m, ev, apple->model.band_level, apple->model.lobe, out, &s);
  af_stage_end(h, AF_STAGE_FFT, t0_ns);
  t0_ns = af_stage_begin(h);
  step_fit(m, ev, apple, out, &s);
  step_energy(m, apple, out);
  af_stage_end(h, AF_STAGE_FIT, t0_ns);
  timed_audio(m, apple, audio, n_audio, noise, n_noise, out, &s);
  t0_ns = af_stage_begin(h);
  step_stress(m, apple, out, &s);
  verdict_judge(m, ev, apple, &s, out);
  af_stage_end(h, AF_STAGE_VERDICT, t0_ns);
  return AF_OK;
}

af_status af_measure_execute_pulse(af_measure *m, const af_strike_event *ev, af_band_level level,
                                   unsigned lobe, af_measure_report *out)
{
  if (m == NULL || ev == NULL || out == NULL || !(isfinite(ev->dt_s) && ev->dt_s > 0.0))
    return AF_EINVAL;
  af_measure_steps s = {.band_status = AF_OK};
  report_start(ev, lobe, out);
  step_band(m, ev, level, lobe, out, &s);
  return AF_OK;
}

/* ---- tap-only: the microphone alone ------------------------------------------ */

/* No pulse: the prediction for the configured hammer stands in for it, its
 * lobe for the pulse's band and its shear for the fitted one, so that the
 * verdict is judged as for a measured strike (verdict_judge), then noted as
 * judged from the model only. */
static void tap_from_prediction(const af_model_result *pred, af_measure_steps *s,
                                af_measure_report *out)
{
  s->band_status = pred->band_found ? AF_OK : AF_ENOLOBE;
  if (pred->band_found) {
    s->band = pred->band;
    out->band_low_hz = pred->band.band_low_hz;
    out->band_high_hz = pred->band.band_high_hz;
  }
  out->max_shear_stress_pa = pred->max_shear_stress_pa;
  out->yield_shear_stress_pa = pred->yield_shear_stress_pa;
}

af_status af_measure_execute_tap(af_measure *m, const af_measure_apple *apple,
                                 const af_model_result *predicted, const float *audio,
                                 size_t n_audio, const float *noise, size_t n_noise,
                                 af_measure_report *out)
{
  if (m == NULL || apple == NULL || predicted == NULL || out == NULL ||
      (audio == NULL && n_audio > 0) || !apple_valid(apple))
    return AF_EINVAL;
  af_measure_steps s = {.band_status = AF_OK,
                        .fit_status = AF_OK,
                        .fit_residual = NAN,
                        .f_lo_hz = NAN,
                        .f_hi_hz = NAN,
                        .stray_hz = NAN,
                        .stray_snr_db = NAN,
                        .tap_only = true};
  af_strike_event none;
  memset(&none, 0, sizeof none);
  none.contact_time_s = none.peak_force_n = none.impulse_n_s = NAN;
  report_start(&none, apple->model.lobe, out);
  out->tap_only = true;
  step_energy(m, apple, out);
  timed_audio(m, apple, audio, n_audio, noise, n_noise, out, &s);
  const af_stage_hook *h = m->cfg.stages;
  const int64_t t0_ns = af_stage_begin(h);
  tap_from_prediction(predicted, &s, out);
  verdict_judge(m, &none, apple, &s, out);
  out->verdict.model_only = AF_VERDICT_MODEL_SHEAR; /* excitation: the heard mode */
  af_verdict_format_model_only(&out->verdict, out->model_only_text, sizeof out->model_only_text);
  af_stage_end(h, AF_STAGE_VERDICT, t0_ns);
  return AF_OK;
}
