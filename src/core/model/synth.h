/* synth.h — seeded signal synthesis for tests, demos and benchmarks — not
 * used by the station's measurement.
 *
 * Synthetic force signals: a model pulse at any sampling rate and sub-sample
 * delay, seeded white noise, mains hum, transducer offset and drift,
 * clipping. Used by the core tests (strike detector, inverse fit, measure,
 * response) and the strike_bag demo tool.
 *
 * No allocation: the caller owns every buffer. The generator is
 * self-contained (splitmix64 + Marsaglia's polar method) so that a seed gives
 * the same signal on every platform and library version.
 *
 * Typical use:
 *     af_synth_pulse p;
 *     double fine[8192];
 *     af_synth_pulse_model(w, &params, 20e-6 / 64, fine, 8192, &p);
 *     af_synth_add_pulse(x, n, 20e-6, 0.0, &p, 0.0123456, 1.0);   F(t - t0)
 *     af_synth_add_noise(x, n, af_synth_noise_rms(p.res.peak_force_n, 40.0), &g);
 * Sample k of x is at time t_first_s + k dt_s throughout. */
#ifndef AF_SYNTH_H
#define AF_SYNTH_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "impact.h"

/* ---- seeded generator ---------------------------------------------------- */

typedef struct {
  uint64_t state;
  bool has_spare; /* the polar method makes normals in pairs */
  double spare;
} af_synth_rng;

/* Starts the stream of seed (no spare normal). */
void af_synth_rng_seed(af_synth_rng *g, uint64_t seed);

/* splitmix64 (Steele, Lea, Flood 2014): full period, passes BigCrush. */
uint64_t af_synth_rng_next(af_synth_rng *g);

/* Uniform in [0, 1), 53 bits. */
double af_synth_uniform(af_synth_rng *g);

/* Standard normal (Marsaglia's polar method). */
double af_synth_gauss(af_synth_rng *g);

/* ---- model pulse ---------------------------------------------------------- */

/* The model's force on a fine grid, to be sampled at any rate and delay by
 * linear interpolation (at dt/64 of a 50 kHz stream the interpolation error
 * is ~1e-7 of the peak). */
typedef struct {
  const double *force_n; /* F(j fine_dt_s) [N], j = 0 .. n-1: the caller's buffer */
  size_t n;
  double fine_dt_s;
  af_impact_result res; /* the model's contact time, peak, restitution ... */
  double impulse_n_s;   /* momentum balance m1 v0 (1 + e_delivered) + m1 g t_c: the
                           exact integral of F, independent of the sampling */
} af_synth_pulse;

/* Runs the impact model at fine_dt_s into buf[0..cap) and describes it in
 * *out (out->force_n = buf). Statuses of af_impact_execute (AF_ESIZE when cap is
 * too small). */
af_status af_synth_pulse_model(af_impact *w, const af_impact_params *p, double fine_dt_s,
                               double *buf, size_t cap, af_synth_pulse *out);

/* The same pulse from an integrator of its own, so that a test or the demo
 * does not check the model against itself: classical fixed-step RK4 of
 * m1 d'' = m1 g - K d^1.5 (1 + chi d'/v0), d(0) = 0, d'(0) = v0 (PHYSICS.md
 * 1), at fine_dt_s, contact end where d returns to 0 (linear crossing).
 * Shares only K (af_impact_stiffness) and chi (af_impact_chi, the damping
 * law's definition) with af_impact_execute, not its GSL odeiv2 stepper, events
 * or peak refinement. out->res: contact_time_s, peak_force_n (largest fine
 * sample), time_of_peak_s, max_deformation_m, delivered_restitution, chi,
 * dt_s, n_samples. AF_EINVAL for invalid params or fine_dt_s, AF_ESIZE when
 * the contact needs more than cap fine samples. */
af_status af_synth_pulse_rk4(const af_impact *w, const af_impact_params *p, double fine_dt_s,
                             double *buf, size_t cap, af_synth_pulse *out);

/* F(t) [N]: 0 before contact (t <= 0) and after it (t >= t_c); between the
 * last fine sample and t_c the force falls linearly to 0. */
double af_synth_pulse_at(const af_synth_pulse *p, double t_s);

/* x[k] += scale F(t_first_s + k dt_s - t0_s): the pulse starting at t0_s
 * (any real time, so any sub-sample delay). */
void af_synth_add_pulse(double *x, size_t n, double dt_s, double t_first_s, const af_synth_pulse *p,
                        double t0_s, double scale);

/* ---- imperfections --------------------------------------------------------- */

/* Noise RMS [N] that gives snr_db = 20 log10(peak / noise RMS). */
double af_synth_noise_rms(double peak_n, double snr_db);

/* White Gaussian noise of the given RMS. */
void af_synth_add_noise(double *x, size_t n, double rms, af_synth_rng *g);

/* Mains hum amplitude sin(2 pi f t + phase). */
void af_synth_add_hum(double *x, size_t n, double dt_s, double t_first_s, double amplitude,
                      double freq_hz, double phase_rad);

/* Transducer offset and drift: offset + slope t + exp_amplitude exp(-t/exp_tau)
 * (the charge of an AC-coupled piezo settling after power-up). exp_tau_s <= 0
 * leaves the exponential out. */
void af_synth_add_drift(double *x, size_t n, double dt_s, double t_first_s, double offset,
                        double slope_per_s, double exp_amplitude, double exp_tau_s);

/* Saturates at +-full_scale, as the amplifier or the converter does. */
void af_synth_clip(double *x, size_t n, double full_scale);

/* The float32 samples a SignalChunk carries. */
void af_synth_to_float(const double *x, size_t n, float *out);

#endif
