/* fit.h — inverse fit of the impact model to one measured strike.
 *
 * The force transducer on the hammer records a strike; the detector cuts the
 * baseline-removed pulse and estimates where the contact starts. This module
 * fits the fruit modulus E2 and the coefficient of restitution e (and, when
 * the rig does not measure them, the contact velocity v0 and the contact
 * start t0) by nonlinear least squares on the samples:
 *     r_k = F_model(k dt - t0; E2, e, v0) - pulse_k,   k = 0 .. n-1,
 * with F_model the force of af_impact_execute (0 before contact and after t_c).
 * Every other parameter (hammer mass, radii, Poisson ratios, gravity) is
 * taken as known from the start parameters.
 *
 * Damping law: the config's, AF_DAMPING_EXACT by default, so that the fitted
 * e is the restitution the model delivers (separation over contact velocity;
 * PHYSICS.md 2), not the saturating Lankarani-Nikravesh parameter. The law
 * is exact without gravity; the model keeps gravity, which lowers the
 * delivered value by about 0.003 for the nominal apple.
 *
 * Method: GSL multifit_nlinear, trust region (Levenberg-Marquardt), from a
 * start matched to the pulse's impulse and peak by the model's scaling laws.
 * By default (use_table) the model is the normalised pulse of pulse_table.h
 * scaled back to newtons and seconds, its Jacobian analytic, its search
 * ending within a small fraction of a standard error of the minimum
 * (fit_table.c); one impact run at the optimum checks it, and the whole
 * fit reruns on the ODE (the reference path, below) when a point of the
 * search leaves the table or the check fails (af_fit_path, af_fit_counts).
 * The reference path runs
 * the impact model at every evaluation, its Jacobian by forward differences
 * (one impact run per free physical parameter) and analytically for t0:
 * about 30 impact runs per fit with v0 free, 17 with v0 measured (see
 * af_fit_result.model_runs).
 * Conventions of status.h: all memory in af_fit_create, none in
 * af_fit_execute; one af_fit per thread.
 *
 * Identifiability: E2, e and v0 are strongly correlated through the pulse's
 * amplitude, width and asymmetry. At 40 dB SNR (50 kHz, R2 40 mm) the
 * standard error of E2 is about 1 % with v0 measured but up to 5 % with v0
 * free at e = 0.4; trust the reported standard errors, they match the
 * scatter.
 */
#ifndef AF_FIT_H
#define AF_FIT_H

#include <stdbool.h>
#include <stddef.h>

#include "impact.h"
#include "status.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Fewest samples a pulse may have (more than the 4 free parameters). */
#define AF_FIT_MIN_SAMPLES 5
/* The fitted restitution stays inside (AF_FIT_RESTITUTION_MIN, 1): the
 * exact damping law is defined from 0.05. */
#define AF_FIT_RESTITUTION_MIN 0.05

typedef struct {
  size_t max_samples;           /* longest pulse accepted [samples] (>= AF_FIT_MIN_SAMPLES);
                                   sizes the workspace */
  size_t oversample;            /* model samples per data sample (1 .. 16): the model runs at
                                   dt / oversample and is interpolated (cubic) at k dt - t0 */
  bool fit_velocity;            /* v0 free; false when the rig measures it (start's v0 used) */
  bool fit_time_offset;         /* t0 free; false to trust the detector's t0_s */
  bool match_start;             /* move the start's E2 (and v0 when free) so that the start
                                   model's impulse and peak match the pulse's (one model run) */
  bool accelerate;              /* geodesic acceleration (one more model run per trial step;
                                   the ODE path only) */
  af_damping_law damping;       /* maps e to chi; overrides start->damping */
  size_t max_iterations;        /* accepted trust-region steps before AF_EBUDGET_FIT_ITER (>= 1) */
  double step_tol;              /* converged when every step of the scaled parameters (ln E2,
                                   logit e, ln v0, t0 / dt) is below this (> 0) */
  double gradient_tol;          /* or when the residual is orthogonal to every Jacobian
                                   column within this cosine (> 0) */
  double max_relative_residual; /* a fit leaving more RMS / peak than this is not a
                                   strike: AF_ENODATA (> 0) */
  double window_margin;         /* the fitted contact [t0, t0 + t_c] must lie within
                                   [-dt, n dt] widened by this fraction of n dt on
                                   each side, else AF_ENODATA (>= 0) */
  bool use_table;               /* search on the normalised pulse table (pulse_table.h)
                                   with one ODE check at the optimum; false: the ODE at
                                   every iteration (the reference the table is checked
                                   against) */
  double table_check_se;        /* the table's result stands when the ODE model at its
                                   optimum moves no scaled parameter (to first order) by
                                   more than this many of its standard errors, each at
                                   least 1e-3 (>= 0; 0 fails every check: the fallback's
                                   test) */
} af_fit_config;

/* max_samples 256 (5.1 ms at 50 kHz), oversample 2, v0 and t0 free, matched
 * start, no acceleration, AF_DAMPING_EXACT, the table path checked at 0.1
 * standard error, 50 iterations, step_tol 1e-6,
 * gradient_tol 1e-6, max_relative_residual 0.2 (a strike at 20 dB SNR fits
 * at 0.10 at most, white noise alone at 0.24 and above), window_margin 0.5
 * (a noise fit lasts 3 to 100 windows; a v0-free fit at e 0.4 may overrun
 * the window by 10 %). */
af_fit_config af_fit_config_default(void);

typedef struct af_fit af_fit;

/* Validates cfg (AF_EINVAL), then allocates the GSL workspace, the impact
 * workspace (which tabulates the exact damping law, ~10 ms) and the model
 * buffers; with use_table it takes the process's pulse table, which the
 * first such create builds (~20 ms CPU, once per process; its status if the
 * build fails). AF_ENOMEM when an allocation fails; *out is NULL on error. */
af_status af_fit_create(const af_fit_config *cfg, af_fit **out);
void af_fit_destroy(af_fit *f); /* NULL-safe */

/* Which model the result comes from (cfg.use_table). The fallbacks rerun
 * the whole fit on the ODE from the same start, so their result is the ODE
 * fit's, bit for bit. */
typedef enum {
  AF_FIT_PATH_ODE = 0,        /* use_table false: the ODE at every iteration (also said
                                 of a fit refused before any search) */
  AF_FIT_PATH_TABLE,          /* the search on the table, confirmed by the ODE check */
  AF_FIT_PATH_FALLBACK_RANGE, /* a point of the search (or the start) left the table's
                                 grid (chi > 6, gamma > 0.3, scales not finite): ODE fit */
  AF_FIT_PATH_FALLBACK_CHECK  /* the check failed: the ODE model at the table's optimum
                                 would move a parameter by more than table_check_se (0.1)
                                 standard errors (and 1e-4 relative), or the ODE run
                                 there failed: ODE fit */
} af_fit_path;

/* "ode", "table", "fallback-range", "fallback-check". */
const char *af_fit_path_name(af_fit_path path);

typedef struct {
  double modulus_pa;        /* fitted E2 */
  double modulus_se_pa;     /* its standard error */
  double restitution;       /* fitted e (delivered restitution with the exact law) */
  double restitution_se;    /* its standard error */
  double velocity_m_s;      /* fitted v0, or start's when fixed */
  double velocity_se_m_s;   /* 0 when fixed */
  double time_offset_s;     /* contact start relative to pulse[0]'s time; t0_s when fixed */
  double time_offset_se_s;  /* 0 when fixed */
  double contact_time_s;    /* of the fitted model */
  double contact_time_se_s; /* its standard error (first order, full covariance) */
  double peak_force_n;      /* of the fitted model */
  double residual_rms_n;    /* RMS of r_k over the n samples */
  double relative_residual; /* residual_rms_n / max_k pulse_k */
  size_t iterations;        /* accepted trust-region steps */
  size_t model_runs;        /* impact-model integrations spent (the cost): 1 on the table
                               path (the check), the check's + the ODE fit's on a
                               fallback */
  af_fit_path path;         /* the model the result comes from */
  double check_shift;       /* table path: the check's largest first-order move of a
                               scaled parameter, in its standard errors (each floored at
                               1e-3 in the scaled parameters); the table's result stands
                               at <= table_check_se. NaN when no check ran */
  af_status status;         /* as returned */
} af_fit_result;

/* Fits the model to pulse_n[0 .. n-1] [N], sampled every dt_s, starting from
 * start (E2, e, v0 as first guesses; the rest held fixed) and t0_s, the
 * detector's estimate of the contact start relative to pulse_n[0]'s time
 * (fractional in dt; af_strike_event gives pulse_n, n_samples, dt_s and
 * pulse_t0_s in exactly this form). The window may be the contact alone, as
 * the detector cuts it, or include quiet samples around it. Standard errors
 * come from the covariance (J^T J)^-1 at the solution scaled by the residual
 * variance |r|^2 / (n - p), mapped to the physical parameters to first
 * order; they match the scatter (rms z 1.0 over 1000 random apples).
 *
 * Returns (and stores in out->status):
 *   AF_OK       converged: a small step, a gradient orthogonal to the
 *               residual, or no step lowering the cost any more (a minimum
 *               to the model's numerical precision: how noise-free data end);
 *   AF_EINVAL   a NULL pointer, n < AF_FIT_MIN_SAMPLES, a non-finite sample,
 *               dt_s or t0_s not finite, dt_s <= 0, start restitution outside
 *               (AF_FIT_RESTITUTION_MIN, 1) or start parameters the impact
 *               model rejects;
 *   AF_ESIZE    n > max_samples, or the start model is longer than the model
 *               buffer (4 max_samples dt; a longer trial model during the
 *               search is a rejected step);
 *   AF_ENODATA  no positive peak or impulse, or the fitted model does not
 *               explain the pulse: a relative residual above
 *               max_relative_residual (noise alone fits at 0.24 and above) or
 *               a contact reaching outside the window by more than
 *               window_margin (noise in a short window; a truncated
 *               contact); takes precedence over the two below;
 *   AF_EBUDGET_FIT_ITER  not converged within max_iterations (the budget);
 *   AF_ENOCONV  a Jacobian run failed;
 *   AF_ENUMERIC the model failed at the start point or the covariance is
 *               singular (a parameter has no influence on the pulse).
 * Once the search has run (AF_OK, AF_EBUDGET_FIT_ITER, AF_ENOCONV, AF_ENUMERIC, AF_ENODATA from
 * the model checks), out holds the last estimate; otherwise its values are
 * NaN.
 * No allocation. */
af_status af_fit_execute(af_fit *f, const af_impact_params *start, const double *pulse_n, size_t n,
                         double dt_s, double t0_s, af_fit_result *out);

/* The residual of the last af_fit_execute at the parameters it reported,
 * pulse_k - model_k [N] for k = 0 .. n-1 (the samples residual_rms_n
 * summarises): a clean strike leaves white noise, a pulse the model does not
 * describe (a hammer bounce inside the contact) a structure. *residual_n is
 * borrowed: valid until the next af_fit_execute or af_fit_destroy.
 * AF_EINVAL for a NULL argument; AF_ENODATA (NULL, 0) when the last call
 * left no final model (refused before the search, or the model failed at
 * its end). No allocation. */
af_status af_fit_get_residual(const af_fit *f, const double **residual_n, size_t *n);

/* Fits of f since create that the table answered, and that fell back to the
 * ODE fit (AF_FIT_PATH_FALLBACK_*); fits refused before any search (AF_EINVAL,
 * AF_ESIZE from the checks, AF_ENODATA without a peak) count in neither. */
void af_fit_counts(const af_fit *f, size_t *from_table, size_t *fallbacks);

#ifdef __cplusplus
}
#endif
#endif
