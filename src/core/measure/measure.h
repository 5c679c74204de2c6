/* measure.h — one measured strike, end to end: from a detected force pulse
 * (strike.h) and the microphone window cut at its time, the StrikeReport
 * figures and the measured reliability.
 *
 *   force pulse ──> contact time, peak, impulse (the detector's)
 *               ──> spectrum, lobes, half-power band (spectrum.h: the same
 *                   code path as the model's spectrum)
 *               ──> inverse fit of E2, e (v0, t0) (fit.h), started from the
 *                   model's prediction for the matched apple
 *   audio window ─> the damped peaks over a band around the model's 0S2
 *                   range for this apple's mass (lamb.h over
 *                   [modulus_min, modulus_max], widened by a margin;
 *                   af_response_execute_peaks), and which of them is the 0S2
 *                   (modes.h: the 0S2 predicted from the fitted E2, the Lamb
 *                   ratios of its neighbours, the peaks present); Q, SNR;
 *                   stiffness factor and the modulus through Lamb's relation
 *   criteria    ──> excites_mode: the measured resonance in the measured band
 *                   of the configured lobe (same settings as the prediction);
 *                   no_damage: tau_max from the measured peak force and the
 *                   fitted E2 (elastic Hertz contact radius), below the yield
 *                   stress of the fitted E2; reliable = both and a clean
 *                   strike (no double hit: a bounce after the contact, or a
 *                   second impact inside it, seen as a structured residual of
 *                   the fit; no clipping, lost samples, failed fit,
 *                   or resonance below the SNR threshold), with the reason.
 *
 * Create once (all workspaces), then af_measure_execute per strike: no
 * allocation per strike. Used by the node and by `firmness_model analyze`. */
#ifndef AF_MEASURE_H
#define AF_MEASURE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "fit.h"
#include "model.h"
#include "modes.h"
#include "response.h"
#include "stage.h"
#include "status.h"
#include "strike.h"
#include "verdict.h"

#ifdef __cplusplus
extern "C" {
#endif

#define AF_MEASURE_REASON_MAX 256

typedef struct {
  af_fit_config fit;           /* inverse fit (fit_velocity false when the rig sets v0) */
  af_response_config response; /* microphone analysis (sample rate, window, SNR threshold) */
  double audio_delay_s;        /* audio window starts this long after the contact start [s], >= 0 */
  double audio_window_s; /* analysed audio length [s], > 0, <= response.window_samples / rate */
  double noise_guard_s;  /* the noise reference ends this long before the contact start [s],
                            >= 0: stamp jitter must not put the strike's ringing into it */
  double noise_window_s; /* audio just before the strike used as the noise reference [s], >= 0 (0 =
                            none) */
  double range_margin;   /* relative widening of the model's 0S2 range, [0, 1) */
  double fruit_q_min, fruit_q_max;  /* the 0S2's Q fruit flesh rings with: outside, not fruit */
  double fruit_confidence_min;      /* the identification's least confidence to grade, [0, 1] */
  double fruit_neighbour_margin_db; /* a stray partial this close to the 0S2's SNR: not fruit,
                                       >= 0 [dB] */
  af_modes_config modes;            /* which listed peak is the 0S2 (modes.h) */
  double modulus_prior_rel_sd;      /* how well the fitted E2 predicts the dynamic modulus (the
                                       contact's model error and the modulus_factor calibration),
                                       relative, 1 sigma, > 0; the 0S2 predicted from it carries
                                       0.5 sqrt(se^2 + this^2) in ln f (f goes as sqrt(E)) */
  const af_stage_hook *stages;      /* times the stages (stage.h), the response's transform too;
                                       NULL (the default) = not timed; must outlive the measure */
} af_measure_config;

/* fit defaults with fit_velocity false; response defaults; delay 0.5 ms,
 * window 40 ms, noise 20 ms ending 5 ms before the contact, margin 0.15;
 * modes defaults; modulus prior 0.10 (1 sigma: a fitted E2 20 % off is 2
 * sigma, while the 0S3, 1.49 x the 0S2, sits 8 sigma away in ln f). */
af_measure_config af_measure_config_default(void);

/* The apple the strike is judged for: the model parameters of its prediction
 * (mass, strike radius, nominal E2, e, nu, density, hammer, criteria settings)
 * and the cultivar's firmness range for the 0S2 search. */
typedef struct {
  af_model_params model;
  double modulus_min_pa;
  double modulus_max_pa;
} af_measure_apple;

/* The figures of msg/StrikeReport.msg plus the measured Reliability. NaN
 * where a figure could not be measured. */
typedef struct {
  double contact_time_s; /* of the fitted impact model; the detector's when the fit fails */
  double peak_force_n, impulse_n_s; /* the detector's */
  unsigned lobe;
  double band_low_hz, band_high_hz;         /* measured band of the configured lobe */
  double resonance_hz, resonance_q, snr_db; /* 0S2 from the microphone */
  af_modes_id modes;                        /* how the 0S2 was identified (method NONE:
                                               no audio analysed, or no candidate) */
  char modes_text[AF_MEASURE_REASON_MAX];   /* af_modes_format of modes; "" when none ran */
  double stiffness_factor;                  /* f^2 m^(2/3) [Hz^2 kg^(2/3)] */
  double modulus_from_resonance_pa;         /* Lamb, divided by the modulus factor */
  double fitted_modulus_pa, fitted_restitution, fit_residual; /* residual: RMS / peak */
  double fitted_modulus_se_pa, fitted_restitution_se;
  double fitted_velocity_m_s; /* v0 of the fit when measure_fit_velocity frees it; NaN when
                                 the rig sets it or the fit failed [m/s] */
  double delivered_energy_j;  /* m1 v0^2 / 2 of the rig's hammer, v0 the fitted one when
                                 measure_fit_velocity frees it, else the rig's; NaN when the v0
                                 is not known [J] */
  double absorbed_energy_j;   /* its share 1 - e^2 kept by the fruit, e the fitted restitution;
                                 NaN without a fit (tap-only too) [J] */
  bool double_hit; /* the detector's bounce after the contact, or one inside it: the fit's
                      residual structured (verdict.bounce_noise_ratio, measure.c) */
  bool clipped;
  uint32_t lost_samples;
  bool audio_clipped; /* the microphone saturated in the audio window (the lane's audio_clip.h) */
  double audio_lag_s; /* the sound's onset by the audio's stamps minus the contact start (the
                         lane's audio_lag.h); NaN: not measured [s] */
  double audio_lag_applied_s; /* the audio window was taken this much later [s] */
  bool excites_mode, no_damage, reliable;
  double max_shear_stress_pa, yield_shear_stress_pa;
  bool tap_only;      /* measured from the microphone alone (af_measure_execute_tap): no pulse, no
                         fit; band and shear the prediction's (verdict.model_only says so) */
  af_verdict verdict; /* why not reliable, as flags and values */
  char model_only_text[AF_MEASURE_REASON_MAX]; /* af_verdict_format_model_only: "" when
                                                   everything was measured */
  char reason[AF_MEASURE_REASON_MAX];          /* af_verdict_format of verdict: "" when reliable */
} af_measure_report;

typedef struct af_measure af_measure;

af_status af_measure_create(const af_measure_config *cfg, af_measure **out);
void af_measure_destroy(af_measure *m); /* NULL-safe */
const af_measure_config *af_measure_get_config(const af_measure *m);

/* What the pulse alone gives, for a strike no apple matches: the detector's
 * figures and flags and the measured band of lobe at level; every
 * apple-dependent figure NaN, reliable false, reason "" (the caller knows
 * why there is no apple). AF_EINVAL for a NULL argument or a bad dt. */
af_status af_measure_execute_pulse(af_measure *m, const af_strike_event *ev, af_band_level level,
                                   unsigned lobe, af_measure_report *out);

/* Solves the Poisson-ratio caches (Lamb's xi, tau_max/p0) for these settings
 * ahead of the first strike: their GSL solvers allocate, and no strike may.
 * Call at start-up with the cultivar's model parameters; a strike on an apple
 * with another Poisson ratio or shear mode solves (and allocates) once more. */
af_status af_measure_prepare(af_measure *m, const af_model_params *p);

/* Measures one strike. ev: the detector's event (its pulse is read during the
 * call only). audio: the window cut from the audio stream starting
 * audio_delay_s after ev's contact start (by sample index), n_audio samples
 * (may be shorter than the configured window, or 0 when no audio: then the
 * resonance figures are NaN and the reason says so); noise: the audio just
 * before the strike (may be NULL). Always fills *out (reason set) unless an
 * argument is invalid (AF_EINVAL). Returns AF_OK when every figure was
 * measured; a failed part (fit, resonance) is reported in out->reason with
 * reliable false, and the call still returns AF_OK. */
af_status af_measure_execute(af_measure *m, const af_strike_event *ev,
                             const af_measure_apple *apple, const float *audio, size_t n_audio,
                             const float *noise, size_t n_noise, af_measure_report *out);

/* Tap-only (no force transducer): one strike from its audio alone. audio:
 * the window cut audio_delay_s after the onset (onset.h), noise: the audio
 * before it (may be NULL). The 0S2 by the same identification (modes.h) with
 * the prior from the apple's mass and the cultivar's modulus range (the
 * middle of the 0S2 range in ln f, the range +-2 sigma), the stiffness factor
 * f^2 m^(2/3) and the modulus through Lamb; no fit (the fitted figures NaN).
 * The band and the shear are predicted's (the model's result for the
 * configured hammer), noted in out->verdict.model_only; reliable as in
 * af_measure_execute. Every pulse figure NaN, tap_only true. AF_EINVAL for a
 * NULL argument or an invalid apple; else AF_OK (*out always filled). */
af_status af_measure_execute_tap(af_measure *m, const af_measure_apple *apple,
                                 const af_model_result *predicted, const float *audio,
                                 size_t n_audio, const float *noise, size_t n_noise,
                                 af_measure_report *out);

#ifdef __cplusplus
}
#endif
#endif
