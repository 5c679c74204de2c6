/* fit.c — inverse fit of the impact model to one measured strike.
 *
 * Scaled parameters x, each of order 1 per natural unit so that one step
 * tolerance serves all of them:
 *     x[0] = ln(E2 / E2_start)
 *     x[1] = logit((e - e_min) / (1 - e_min))    keeps e inside (0.05, 1)
 *     x[v] = ln(v0 / v0_start)                   when v0 is free
 *     x[t] = (t0 - t0_start) / dt                when t0 is free
 * Residuals are scaled by 1 / (peak sqrt(n)), so |r| is the relative RMS
 * residual whatever the pulse's size in newtons.
 *
 * The search is GSL's Levenberg-Marquardt with More scaling. Its first step
 * is close to a Gauss-Newton step (GSL's lm ignores the trust radius; mu
 * starts at 1e-3 of the largest scaled curvature), which from the nominal
 * apple can overshoot into a long, heavily damped model (e at its bound)
 * that explains only part of the window — a false minimum. The start is
 * therefore first matched to the pulse by the model's scaling laws
 * (fit_match): one model run, and no false minimum in 300 random apples
 * with v0 free (noise-free, 40 dB, 30 dB; 9-11 without it), where geodesic
 * acceleration also avoided it but cost about 20 % more model runs. At
 * 20 dB about 1 % still end at e's bound, as AF_ENOCONV.
 *
 * The GSL workspace is sized for max_samples rows once; a shorter pulse
 * leaves the extra rows of r and J at 0, which changes neither the solution
 * nor J^T J.
 *
 * The model runs at h = dt / oversample and is read at k dt - t0 by a cubic
 * (Catmull-Rom) interpolant, which is C1 in t0, so the t0 column of J is its
 * analytic slope. The E2, e and v0 columns are forward differences of whole
 * model runs, step AF_FIT_FD_STEP in x.
 *
 * The table path (cfg.use_table, the default) searches the same scaled
 * parameters, from the same matched start, on the normalised pulse of
 * pulse_table.h: F(t) = F0 f((t - t0) / T; chi, gamma), with F0, T and gamma
 * from E2 and v0 by impact.c's scaling and chi from e by the damping law.
 * The table gives f and its slopes in tau, chi and gamma, so every column of
 * J is analytic (table_sample), and with J in hand at every evaluation the
 * Levenberg-Marquardt step is solved on the p x p normal equations
 * (table_search) instead of GSL's QR of the max_samples x p Jacobian, which
 * cost more than the model. At the optimum one ODE run (at dt / 4) checks
 * the table: the Gauss-Newton step that the ODE model's residual would add
 * from there, (J^T J)^-1 J^T (F_ODE - F_table), must stay within
 * table_check_se of every parameter's standard error (floored at 1e-3 in x).
 * The result then reports the ODE run's contact time, peak and residual, the
 * table's parameters and standard errors. A point of the search off the
 * table's grid, or a failed check, reruns the whole fit on the ODE path
 * (af_fit_path, af_fit_counts): the fallback's result is the ODE fit's, bit
 * for bit.
 */
#include "fit.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_blas.h>
#include <gsl/gsl_errno.h>
#include <gsl/gsl_linalg.h>
#include <gsl/gsl_matrix.h>
#include <gsl/gsl_multifit_nlinear.h>
#include <gsl/gsl_vector.h>

#include "pulse_table.h"

#define AF_FIT_MAX_PARAMS 4
#define AF_IX_MODULUS 0
#define AF_IX_RESTITUTION 1
#define AF_IX_NONE SIZE_MAX
/* Forward-difference step in the scaled parameters. The sampled model is
 * smooth in E2 at the 1e-10 N level (no adaptive-step decision jumps over a
 * 2 % sweep in steps of 1e-6; impact.c's tolerance is 1e-9 relative), so the
 * truncation error, ~0.5 step relative, dominates: 1e-5 leaves columns
 * accurate to ~1e-5 and a factor 1e4 of margin against a 1e-9 jump. */
#define AF_FIT_FD_STEP 1e-5
/* Relative residual norm reported for a trial whose model run failed (pulse
 * longer than the buffer, integration failure): far above any real fit, so
 * the trust region rejects the step and shrinks. Finite, because GSL's norm
 * of several infinities is NaN, which it would accept. */
#define AF_FIT_PENALTY 1e6
/* Limits of the configuration. */
#define AF_FIT_MAX_OVERSAMPLE 16
/* The model buffer holds this many times the longest pulse: a trial model
 * longer than that is a failed step (AF_FIT_PENALTY). */
#define AF_FIT_MODEL_SPAN 4
/* Largest moves of the matched start: factors e^2.5 = 12 on E*, e on v0. */
#define AF_FIT_MATCH_MAX_LN_MODULUS 2.5
#define AF_FIT_MATCH_MAX_LN_VELOCITY 1.0
/* The table path's check: the ODE model at the table's optimum, as a first
 * order (Gauss-Newton) step from there, must move every scaled parameter by
 * at most this many of its standard errors [-] (the default of
 * table_check_se) ... */
#define AF_FIT_CHECK_SHIFT_SE 0.1
/* ... each standard error taken as at least this much in the scaled
 * parameters [-] (1e-3 relative on E2 and v0, 1e-3 dt on t0): the floor for
 * noise-free pulses, whose standard errors are ~0, so that they may move by
 * 1e-4. */
#define AF_FIT_CHECK_SE_FLOOR 1e-3
/* Step of the central difference of chi(e) [-]: the laws are smooth (the
 * exact one a spline), so the error is ~1e-12 relative. */
#define AF_FIT_CHI_STEP 1e-6
/* The table search's Levenberg-Marquardt: the first damping relative to the
 * More-scaled curvature [-] (GSL's), and the rejected trials in a row that
 * end it (GSL's 16 before GSL_ENOPROG). */
#define AF_LM_MU_START 1e-3
/* The check's model runs at dt / this (when the pulse fits the model
 * buffer, else at the ODE path's dt / oversample), so that the cubic
 * interpolant's own error (~(h / t_c)^3) stays far below the table's: it
 * checks the table against the ODE, not against a coarse sampling of it. */
#define AF_FIT_CHECK_OVERSAMPLE 4
#define AF_LM_MAX_REJECTS 16

struct af_fit {
  af_fit_config cfg;
  size_t n_params;    /* p */
  size_t ix_velocity; /* index of ln v0 in x, or AF_IX_NONE */
  size_t ix_time;     /* index of t0 / dt in x, or AF_IX_NONE */
  size_t model_cap;   /* samples per model buffer */
  af_impact *impact;
  gsl_multifit_nlinear_workspace *nls;
  gsl_multifit_nlinear_fdf fdf;
  gsl_vector *x_start;                            /* start point */
  gsl_vector *x_prev;                             /* position before the last iteration */
  gsl_matrix *normal;                             /* p x p: scaled J^T J, then its inverse */
  double *model_n;                                /* model at the base point, every h [N] */
  double *probe_n;                                /* model at a perturbed point, every h [N] */
  double *base_at_n;                              /* base model at k dt - t0 [N] */
  double *base_slope_n_s;                         /* its time derivative [N/s] */
  double probe_contact_time_s[AF_FIT_MAX_PARAMS]; /* at x + step e_j, last Jacobian */

  /* The table path. */
  const af_pulse_table *table;         /* the process's, shared read-only */
  af_pulse_shape shape;                /* the base point's interpolated pulse */
  double *jac_n;                       /* max_samples x n_params, row-major: the base's
                                          Jacobian [scaled residual per unit x] */
  double *res_n;                       /* the base's scaled residual [-] */
  gsl_matrix_view jac_view;            /* n x p over jac_n, for this fit */
  gsl_vector_view res_view;            /* n over res_n */
  double lm_x[AF_FIT_MAX_PARAMS];      /* the table search's position */
  size_t lm_iterations;                /* its accepted steps */
  double *check_n;                     /* the ODE model at k dt - t0, the check [N] */
  double tc_grad_s[AF_FIT_MAX_PARAMS]; /* d t_c / d x_j at the base [s] */
  size_t from_table, fallbacks;        /* af_fit_counts */

  /* The problem of the current af_fit_execute call. */
  af_impact_params start; /* damping overridden by cfg */
  const double *pulse_n;
  size_t n;
  double dt_s, h_s, t0_start_s;
  double peak_n; /* max_k pulse_k */
  double scale;  /* 1 / (peak sqrt(n)) [1/N] */
  size_t model_runs;
  bool on_table;     /* this search's model: the table (else the ODE) */
  bool left_table;   /* a point of this search left the table's grid */
  bool check_failed; /* the ODE check at the table's optimum failed */

  /* The base point: last parameters the model was evaluated at. */
  bool base_valid;  /* base_x, base_* describe the current problem */
  bool base_failed; /* the model run failed there */
  double base_x[AF_FIT_MAX_PARAMS];
  af_impact_result base_res;
};

/* ---- configuration ---------------------------------------------------- */

af_fit_config af_fit_config_default(void)
{
  af_fit_config c = {
      .max_samples = 256,
      .oversample = 2,
      .fit_velocity = true,
      .fit_time_offset = true,
      .match_start = true,
      .accelerate = false,
      .damping = AF_DAMPING_EXACT,
      .max_iterations = 50,
      .step_tol = 1e-6,
      .gradient_tol = 1e-6,
      .max_relative_residual = 0.2,
      .window_margin = 0.5,
      .use_table = true,
      .table_check_se = AF_FIT_CHECK_SHIFT_SE,
  };
  return c;
}

static bool is_positive(double v)
{
  return isfinite(v) && v > 0.0;
}

static bool fit_config_valid(const af_fit_config *c)
{
  /* the model buffer's size in bytes must not overflow */
  const size_t limit = SIZE_MAX / 16 / AF_FIT_MODEL_SPAN / AF_FIT_MAX_OVERSAMPLE;
  return c->max_samples >= AF_FIT_MIN_SAMPLES && c->max_samples <= limit && c->oversample >= 1 &&
         c->oversample <= AF_FIT_MAX_OVERSAMPLE && c->max_iterations >= 1 &&
         is_positive(c->step_tol) && is_positive(c->gradient_tol) &&
         is_positive(c->max_relative_residual) && isfinite(c->window_margin) &&
         c->window_margin >= 0.0 && isfinite(c->table_check_se) && c->table_check_se >= 0.0 &&
         (c->damping == AF_DAMPING_PAPER || c->damping == AF_DAMPING_EXACT ||
          c->damping == AF_DAMPING_HU_GUO);
}

/* ---- parameters --------------------------------------------------------- */

static double logistic(double x)
{
  return 1.0 / (1.0 + exp(-x));
}

static double restitution_of(double x)
{
  return AF_FIT_RESTITUTION_MIN + (1.0 - AF_FIT_RESTITUTION_MIN) * logistic(x);
}

/* de/dx, for the standard error. */
static double restitution_slope(double x)
{
  double s = logistic(x);
  return (1.0 - AF_FIT_RESTITUTION_MIN) * s * (1.0 - s);
}

static double restitution_to_x(double e)
{
  double s = (e - AF_FIT_RESTITUTION_MIN) / (1.0 - AF_FIT_RESTITUTION_MIN);
  return log(s / (1.0 - s));
}

/* The model parameters and contact start at the scaled point x. */
static void fit_unpack(const af_fit *w, const double *x, af_impact_params *p, double *t0_s)
{
  *p = w->start;
  p->fruit_modulus_pa = w->start.fruit_modulus_pa * exp(x[AF_IX_MODULUS]);
  p->restitution = restitution_of(x[AF_IX_RESTITUTION]);
  if (w->ix_velocity != AF_IX_NONE)
    p->velocity_m_s = w->start.velocity_m_s * exp(x[w->ix_velocity]);
  *t0_s = w->t0_start_s;
  if (w->ix_time != AF_IX_NONE)
    *t0_s += x[w->ix_time] * w->dt_s;
}

/* ---- the model ---------------------------------------------------------- */

/* Catmull-Rom cubic through g[j] (j h), with g = 0 outside [0, n_g): the
 * value at tau [s] and its slope [per s]. C1 in tau, exact for cubics, and a
 * fixed linear combination of at most four samples. The interval after the
 * last sample is interpolated too (towards 0, with a small lobe from the
 * centred slope there): cutting it off made the model jump by ~1e-3 N
 * whenever the contact end crossed a grid point and the last sample (then
 * ~0) dropped out, which corrupted forward-difference columns; this way the
 * model is continuous in the parameters. */
static void fit_interp(const double *g, size_t n_g, double h_s, double tau_s, double *value,
                       double *slope)
{
  *value = 0.0;
  *slope = 0.0;
  double pos = tau_s / h_s;
  if (!(pos > -1.0) || pos >= (double)n_g + 1.0)
    return; /* all four samples are 0 (or tau is NaN) */
  if (pos < 0.0)
    return; /* before contact: exactly 0 */
  size_t j = (size_t)pos;
  double u = pos - (double)j;
  double p1 = j < n_g ? g[j] : 0.0;
  double p2 = j + 1 < n_g ? g[j + 1] : 0.0, p3 = j + 2 < n_g ? g[j + 2] : 0.0;
  /* F ~ tau^1.5 starts flat: mirroring g[1] gives the slope 0 at contact,
   * so the interpolant stays C1 across the contact start (the t0 column). */
  double p0 = j == 0 ? p2 : (j - 1 < n_g ? g[j - 1] : 0.0);
  double m1 = 0.5 * (p2 - p0), m2 = 0.5 * (p3 - p1);
  double u2 = u * u, u3 = u2 * u;
  *value =
      (2 * u3 - 3 * u2 + 1) * p1 + (u3 - 2 * u2 + u) * m1 + (3 * u2 - 2 * u3) * p2 + (u3 - u2) * m2;
  *slope = ((6 * u2 - 6 * u) * p1 + (3 * u2 - 4 * u + 1) * m1 + (6 * u - 6 * u2) * p2 +
            (3 * u2 - 2 * u) * m2) /
           h_s;
}

/* One impact run at x into buf (every h). */
static af_status fit_model(af_fit *w, const double *x, double *buf, af_impact_result *res,
                           double *t0_s)
{
  af_impact_params p;
  fit_unpack(w, x, &p, t0_s);
  w->model_runs++;
  return af_impact_execute(w->impact, &p, w->h_s, buf, NULL, w->model_cap, res);
}

/* ---- the table's model -------------------------------------------------- */

/* The scales of one point and their logarithmic derivatives per unit of
 * each scaled parameter (impact.c's scaling: D ~ (m1 v0^2 / E*)^0.4, so
 * d ln T = -0.4 d ln E* - 0.2 d ln v0, d ln F0 = 0.4 d ln E* + 1.2 d ln v0,
 * d ln gamma = -0.4 d ln E* - 1.2 d ln v0). */
typedef struct {
  double t_s, f0_n, chi, gamma;
  double dln_t[AF_FIT_MAX_PARAMS], dln_f0[AF_FIT_MAX_PARAMS];
  double dln_gamma[AF_FIT_MAX_PARAMS], dchi[AF_FIT_MAX_PARAMS];
} af_fit_scales;

/* dchi/de of the fit's damping law by a central difference (one-sided at
 * e = 1). */
static af_status chi_slope(const af_fit *w, double e, double *slope)
{
  double lo = fmax(e - AF_FIT_CHI_STEP, AF_FIT_RESTITUTION_MIN);
  double hi = fmin(e + AF_FIT_CHI_STEP, 1.0), chi_lo = NAN, chi_hi = NAN;
  af_status st = af_impact_chi(w->impact, w->cfg.damping, lo, &chi_lo);
  if (st == AF_OK)
    st = af_impact_chi(w->impact, w->cfg.damping, hi, &chi_hi);
  *slope = (chi_hi - chi_lo) / (hi - lo);
  return st;
}

/* AF_EINVAL when p's scales are not finite or (chi, gamma) is off the grid:
 * the table cannot answer (the ODE path names bad parameters). */
static af_status table_scales(const af_fit *w, const af_impact_params *p, const double *x,
                              af_fit_scales *sc)
{
  memset(sc, 0, sizeof *sc);
  double m1 = p->hammer_mass_kg, v0 = p->velocity_m_s, chi_de = 0.0;
  double d_m = pow(1.25 * m1 * v0 * v0 / af_impact_stiffness(p), 0.4); /* D [m] */
  sc->t_s = d_m / v0;
  sc->f0_n = m1 * v0 * v0 / d_m;
  sc->gamma = p->gravity_m_s2 * d_m / (v0 * v0);
  if (af_impact_chi(w->impact, w->cfg.damping, p->restitution, &sc->chi) != AF_OK ||
      chi_slope(w, p->restitution, &chi_de) != AF_OK)
    return AF_EINVAL;
  if (!is_positive(sc->t_s) || !is_positive(sc->f0_n) || !isfinite(chi_de) || !isfinite(sc->gamma))
    return AF_EINVAL; /* the grid is af_pulse_table_shape's to judge */
  /* d ln E* / d ln E2: the fruit's share of the contact compliance */
  double share = af_impact_effective_modulus_pa(p) * (1.0 - p->fruit_poisson * p->fruit_poisson) /
                 p->fruit_modulus_pa;
  sc->dln_t[AF_IX_MODULUS] = -0.4 * share;
  sc->dln_f0[AF_IX_MODULUS] = 0.4 * share;
  sc->dln_gamma[AF_IX_MODULUS] = -0.4 * share;
  sc->dchi[AF_IX_RESTITUTION] = chi_de * restitution_slope(x[AF_IX_RESTITUTION]);
  if (w->ix_velocity != AF_IX_NONE) {
    sc->dln_t[w->ix_velocity] = -0.2;
    sc->dln_f0[w->ix_velocity] = 1.2;
    sc->dln_gamma[w->ix_velocity] = -1.2;
  }
  return AF_OK;
}

/* Sample k of the table's model: its value and slope into base_*, its
 * Jacobian row into jac_n. */
static void table_sample(af_fit *w, const af_fit_scales *sc, size_t k, double t0_s)
{
  double tau = ((double)k * w->dt_s - t0_s) / sc->t_s, f, f_tau, f_chi, f_gamma;
  af_pulse_shape_eval(&w->shape, tau, &f, &f_tau, &f_chi, &f_gamma);
  w->base_at_n[k] = sc->f0_n * f;
  w->base_slope_n_s[k] = sc->f0_n * f_tau / sc->t_s;
  for (size_t j = 0; j < w->n_params; j++) {
    double d = j == w->ix_time ? -w->dt_s * w->base_slope_n_s[k]
                               : w->base_at_n[k] * sc->dln_f0[j] +
                                     sc->f0_n * (-f_tau * tau * sc->dln_t[j] + f_chi * sc->dchi[j] +
                                                 f_gamma * sc->gamma * sc->dln_gamma[j]);
    w->jac_n[k * w->n_params + j] = w->scale * d;
  }
  w->res_n[k] = w->scale * (w->base_at_n[k] - w->pulse_n[k]);
}

/* The table's figures at x: the shape, base_res's contact time, peak and
 * sample count (as the ODE would write them) and the contact time's
 * gradient. AF_EINVAL (and left_table) off the grid; AF_ESIZE when the
 * ODE's pulse would overflow its buffer, as on the ODE path. */
static af_status table_figures(af_fit *w, const double *x, af_fit_scales *sc, double *t0_s)
{
  af_impact_params p;
  fit_unpack(w, x, &p, t0_s);
  if (table_scales(w, &p, x, sc) != AF_OK ||
      af_pulse_table_shape(w->table, sc->chi, sc->gamma, &w->shape) != AF_OK) {
    w->left_table = true;
    return AF_EINVAL;
  }
  double tc_s = w->shape.tau_c * sc->t_s, samples = floor(tc_s / w->h_s) + 1.0;
  if (!(samples <= (double)w->model_cap))
    return AF_ESIZE;
  w->base_res = (af_impact_result){.contact_time_s = tc_s,
                                   .peak_force_n = w->shape.peak * sc->f0_n,
                                   .dt_s = w->h_s,
                                   .n_samples = (size_t)samples};
  for (size_t j = 0; j < w->n_params; j++)
    w->tc_grad_s[j] = j == w->ix_time
                          ? 0.0
                          : tc_s * (sc->dln_t[j] + w->shape.dln_tau_c[0] * sc->dchi[j] +
                                    w->shape.dln_tau_c[1] * sc->gamma * sc->dln_gamma[j]);
  return AF_OK;
}

/* ... and the model at the data times: values, slopes, Jacobian rows and
 * the scaled residual. */
static af_status table_model(af_fit *w, const double *x)
{
  af_fit_scales sc;
  double t0_s;
  af_status st = table_figures(w, x, &sc, &t0_s);
  if (st != AF_OK)
    return st;
  for (size_t k = 0; k < w->n; k++)
    table_sample(w, &sc, k, t0_s);
  return AF_OK;
}

/* Makes x the base point: the model and its values and slopes at the data
 * times. Reuses the last run when x has not moved (GSL asks for J right
 * after f at the same point). */
static af_status fit_base(af_fit *w, const gsl_vector *xv)
{
  double x[AF_FIT_MAX_PARAMS] = {0};
  for (size_t i = 0; i < w->n_params; i++)
    x[i] = gsl_vector_get(xv, i);
  if (w->base_valid && memcmp(x, w->base_x, w->n_params * sizeof x[0]) == 0)
    return w->base_failed ? AF_ENUMERIC : AF_OK;
  memcpy(w->base_x, x, w->n_params * sizeof x[0]);
  w->base_valid = true;
  if (w->on_table) {
    af_status st = table_model(w, x);
    w->base_failed = st != AF_OK;
    return st;
  }
  double t0_s;
  af_status st = fit_model(w, x, w->model_n, &w->base_res, &t0_s);
  w->base_failed = st != AF_OK;
  if (st != AF_OK)
    return st;
  for (size_t k = 0; k < w->n; k++)
    fit_interp(w->model_n, w->base_res.n_samples, w->h_s, (double)k * w->dt_s - t0_s,
               &w->base_at_n[k], &w->base_slope_n_s[k]);
  return AF_OK;
}

/* ---- GSL callbacks ------------------------------------------------------ */

static int fit_f(const gsl_vector *x, void *params, gsl_vector *f)
{
  af_fit *w = params;
  gsl_vector_set_zero(f);
  if (fit_base(w, x) != AF_OK) {
    double r = AF_FIT_PENALTY / sqrt((double)w->n);
    for (size_t k = 0; k < w->n; k++)
      gsl_vector_set(f, k, r);
    return GSL_SUCCESS;
  }
  for (size_t k = 0; k < w->n; k++)
    gsl_vector_set(f, k, w->scale * (w->base_at_n[k] - w->pulse_n[k]));
  return GSL_SUCCESS;
}

/* Column j of J by a forward difference of whole model runs. */
static int fit_column_fd(af_fit *w, const gsl_vector *x, size_t j, gsl_matrix *J)
{
  double xp[AF_FIT_MAX_PARAMS] = {0}, t0_s;
  for (size_t i = 0; i < w->n_params; i++)
    xp[i] = gsl_vector_get(x, i);
  xp[j] += AF_FIT_FD_STEP;
  af_impact_result res;
  if (fit_model(w, xp, w->probe_n, &res, &t0_s) != AF_OK)
    return GSL_EFAILED;
  w->probe_contact_time_s[j] = res.contact_time_s;
  for (size_t k = 0; k < w->n; k++) {
    double v, s;
    fit_interp(w->probe_n, res.n_samples, w->h_s, (double)k * w->dt_s - t0_s, &v, &s);
    gsl_matrix_set(J, k, j, w->scale * (v - w->base_at_n[k]) / AF_FIT_FD_STEP);
  }
  return GSL_SUCCESS;
}

static int fit_df(const gsl_vector *x, void *params, gsl_matrix *J)
{
  af_fit *w = params;
  gsl_matrix_set_zero(J);
  if (fit_base(w, x) != AF_OK)
    return GSL_EFAILED;
  for (size_t j = 0; j < w->n_params; j++) {
    w->probe_contact_time_s[j] = w->base_res.contact_time_s; /* t0 leaves t_c alone */
    if (j == w->ix_time)
      continue;
    int rc = fit_column_fd(w, x, j, J);
    if (rc != GSL_SUCCESS)
      return rc;
  }
  if (w->ix_time != AF_IX_NONE) /* d/dx of F(k dt - t0_start - x dt) */
    for (size_t k = 0; k < w->n; k++)
      gsl_matrix_set(J, k, w->ix_time, -w->scale * w->dt_s * w->base_slope_n_s[k]);
  return GSL_SUCCESS;
}

/* ---- workspace ---------------------------------------------------------- */

static af_status fit_alloc_gsl(af_fit *w)
{
  gsl_multifit_nlinear_parameters par = gsl_multifit_nlinear_default_parameters();
  par.trs = w->cfg.accelerate ? gsl_multifit_nlinear_trs_lmaccel : gsl_multifit_nlinear_trs_lm;
  w->nls =
      gsl_multifit_nlinear_alloc(gsl_multifit_nlinear_trust, &par, w->cfg.max_samples, w->n_params);
  w->x_start = gsl_vector_calloc(w->n_params);
  w->x_prev = gsl_vector_alloc(w->n_params);
  w->normal = gsl_matrix_alloc(w->n_params, w->n_params);
  return w->nls && w->x_start && w->x_prev && w->normal ? AF_OK : AF_ENOMEM;
}

static af_status fit_alloc_buffers(af_fit *w)
{
  w->model_cap = AF_FIT_MODEL_SPAN * w->cfg.max_samples * w->cfg.oversample + 1;
  w->model_n = malloc(w->model_cap * sizeof *w->model_n);
  w->probe_n = malloc(w->model_cap * sizeof *w->probe_n);
  w->base_at_n = malloc(w->cfg.max_samples * sizeof *w->base_at_n);
  w->base_slope_n_s = malloc(w->cfg.max_samples * sizeof *w->base_slope_n_s);
  w->jac_n = malloc(AF_FIT_MAX_PARAMS * w->cfg.max_samples * sizeof *w->jac_n);
  w->check_n = malloc(w->cfg.max_samples * sizeof *w->check_n);
  w->res_n = malloc(w->cfg.max_samples * sizeof *w->res_n);
  return w->model_n && w->probe_n && w->base_at_n && w->base_slope_n_s && w->jac_n && w->check_n &&
                 w->res_n
             ? AF_OK
             : AF_ENOMEM;
}

af_status af_fit_create(const af_fit_config *cfg, af_fit **out)
{
  if (out == NULL)
    return AF_EINVAL;
  *out = NULL;
  if (cfg == NULL || !fit_config_valid(cfg))
    return AF_EINVAL;
  af_status_init();
  af_fit *w = calloc(1, sizeof *w);
  if (w == NULL)
    return AF_ENOMEM;
  w->cfg = *cfg;
  w->n_params = 2;
  w->ix_velocity = cfg->fit_velocity ? w->n_params++ : AF_IX_NONE;
  w->ix_time = cfg->fit_time_offset ? w->n_params++ : AF_IX_NONE;
  af_status st = fit_alloc_gsl(w);
  if (st == AF_OK)
    st = fit_alloc_buffers(w);
  if (st == AF_OK)
    st = af_impact_create(&w->impact);
  if (st == AF_OK && cfg->use_table)
    st = af_pulse_table_get(&w->table);
  if (st != AF_OK) {
    af_fit_destroy(w);
    return st;
  }
  w->fdf = (gsl_multifit_nlinear_fdf){
      .f = fit_f, .df = fit_df, .fvv = NULL, .n = cfg->max_samples, .p = w->n_params, .params = w};
  *out = w;
  return AF_OK;
}

void af_fit_destroy(af_fit *w)
{
  if (w == NULL)
    return;
  af_impact_destroy(w->impact);
  free(w->res_n);
  free(w->check_n);
  free(w->jac_n);
  free(w->base_slope_n_s);
  free(w->base_at_n);
  free(w->probe_n);
  free(w->model_n);
  gsl_matrix_free(w->normal);
  gsl_vector_free(w->x_prev);
  gsl_vector_free(w->x_start);
  gsl_multifit_nlinear_free(w->nls);
  free(w);
}

/* ---- one fit ------------------------------------------------------------ */

static af_status fit_check(const af_fit *w, const af_impact_params *start, const double *pulse_n,
                           size_t n, double dt_s, double t0_s)
{
  if (w == NULL || start == NULL || pulse_n == NULL || n < AF_FIT_MIN_SAMPLES ||
      !is_positive(dt_s) || !isfinite(t0_s))
    return AF_EINVAL;
  if (!(start->restitution > AF_FIT_RESTITUTION_MIN && start->restitution < 1.0) ||
      !is_positive(start->fruit_modulus_pa) || !is_positive(start->velocity_m_s))
    return AF_EINVAL;
  if (n > w->cfg.max_samples)
    return AF_ESIZE;
  for (size_t k = 0; k < n; k++)
    if (!isfinite(pulse_n[k]))
      return AF_EINVAL;
  return AF_OK;
}

/* Takes in the problem; AF_ENODATA when the pulse has no positive peak or
 * no positive impulse. */
static af_status fit_setup(af_fit *w, const af_impact_params *start, const double *pulse_n,
                           size_t n, double dt_s, double t0_s)
{
  w->start = *start;
  w->start.damping = w->cfg.damping;
  w->pulse_n = pulse_n;
  w->n = n;
  w->dt_s = dt_s;
  w->h_s = dt_s / (double)w->cfg.oversample;
  w->t0_start_s = t0_s;
  w->peak_n = pulse_n[0];
  for (size_t k = 1; k < n; k++)
    w->peak_n = fmax(w->peak_n, pulse_n[k]);
  w->scale = 1.0 / (w->peak_n * sqrt((double)n));
  w->model_runs = 0;
  w->base_valid = false;
  double impulse = 0.0;
  for (size_t k = 0; k < n; k++)
    impulse += pulse_n[k];
  /* A strike pushes: its impulse is m1 v0 (1 + e) > 0. */
  return w->peak_n > 0.0 && impulse > 0.0 ? AF_OK : AF_ENODATA;
}

/* E2 giving the effective modulus e_star_pa with the start's hammer and
 * Poisson ratios (1/E* = (1 - nu2^2)/E2 + (1 - nu1^2)/E1); NAN when the
 * hammer alone is softer than that. */
static double fit_modulus_for(const af_impact_params *p, double e_star_pa)
{
  double fruit_compliance = 1.0 / e_star_pa;
  if (p->hammer_modulus_pa > 0.0)
    fruit_compliance -= (1.0 - p->hammer_poisson * p->hammer_poisson) / p->hammer_modulus_pa;
  return fruit_compliance > 0.0 ? (1.0 - p->fruit_poisson * p->fruit_poisson) / fruit_compliance
                                : NAN;
}

/* Moves the start's E2 (and v0 when free) so that the start model's impulse
 * and peak match the pulse's (see the top comment for why). At fixed chi and
 * without gravity the impact is self-similar (impact.c): impulse =
 * m1 v0 (1 + e) ~ v0, peak ~ E*^0.4 v0^1.2, width = impulse / peak ~
 * E*^-0.4 v0^-0.2. e stays: its effect on the impulse is taken for v0's. The
 * changes are clamped: this is a start, not an estimate. */
static void fit_match(af_fit *w)
{
  double impulse_model = 0.0, impulse_data = 0.0;
  if (w->on_table) /* the table's integral, in units of m1 v0 */
    impulse_model =
        w->shape.impulse * w->start.hammer_mass_kg * w->start.velocity_m_s *
        exp(w->ix_velocity != AF_IX_NONE ? gsl_vector_get(w->x_start, w->ix_velocity) : 0.0);
  else
    for (size_t j = 0; j < w->base_res.n_samples; j++)
      impulse_model += w->model_n[j] * w->h_s;
  for (size_t k = 0; k < w->n; k++)
    impulse_data += w->pulse_n[k] * w->dt_s;
  if (!(impulse_data > 0.0 && impulse_model > 0.0 && w->base_res.peak_force_n > 0.0))
    return;
  double l_impulse = log(impulse_data / impulse_model);
  double l_peak = log(w->peak_n / w->base_res.peak_force_n);
  double l_velocity = 0.0, l_modulus;
  if (w->ix_velocity != AF_IX_NONE) {
    l_velocity = fmax(-AF_FIT_MATCH_MAX_LN_VELOCITY, fmin(AF_FIT_MATCH_MAX_LN_VELOCITY, l_impulse));
    l_modulus = (l_peak - 1.2 * l_velocity) / 0.4;
  } else { /* least squares of peak (+0.4) and width (-0.4) in ln E* */
    l_modulus = (2.0 * l_peak - l_impulse) / 0.8;
  }
  l_modulus = fmax(-AF_FIT_MATCH_MAX_LN_MODULUS, fmin(AF_FIT_MATCH_MAX_LN_MODULUS, l_modulus));
  double e2 =
      fit_modulus_for(&w->start, af_impact_effective_modulus_pa(&w->start) * exp(l_modulus));
  if (!is_positive(e2))
    return;
  gsl_vector_set(w->x_start, AF_IX_MODULUS, log(e2 / w->start.fruit_modulus_pa));
  if (w->ix_velocity != AF_IX_NONE)
    gsl_vector_set(w->x_start, w->ix_velocity, l_velocity);
}

/* The start point: e as logit, every other scaled parameter 0, then matched
 * to the pulse. The start model must run: its failure is the caller's
 * parameters' fault (or the buffer's size). */
static af_status fit_start(af_fit *w)
{
  gsl_vector_set_zero(w->x_start);
  gsl_vector_set(w->x_start, AF_IX_RESTITUTION, restitution_to_x(w->start.restitution));
  af_status st;
  if (w->on_table && w->cfg.match_start) { /* the match needs the figures only */
    af_fit_scales sc;
    double x[AF_FIT_MAX_PARAMS] = {0}, t0_s;
    for (size_t i = 0; i < w->n_params; i++)
      x[i] = gsl_vector_get(w->x_start, i);
    st = table_figures(w, x, &sc, &t0_s);
  } else {
    st = fit_base(w, w->x_start);
  }
  if (st != AF_OK && w->left_table)
    return st; /* the caller falls back */
  if (st != AF_OK)
    return st == AF_ESIZE || st == AF_EINVAL ? st : AF_ENUMERIC;
  if (w->cfg.match_start) {
    fit_match(w);
    st = fit_base(w, w->x_start);
    if (st != AF_OK && w->left_table)
      return st;
    if (st != AF_OK)
      return st == AF_ESIZE ? st : AF_ENUMERIC;
  }
  if (w->on_table)
    return AF_OK; /* table_search takes over from x_start */
  return gsl_multifit_nlinear_init(w->x_start, &w->fdf, w->nls) == GSL_SUCCESS ? AF_OK
                                                                               : AF_ENUMERIC;
}

/* The convergence test, a pure function of the last step dx, the Jacobian J
 * and the residual r at the new point: every |dx_i| <= step_tol, or every
 * column of J within gradient_tol (as a cosine) of orthogonal to r. */
static bool fit_converged(const gsl_vector *dx, const gsl_matrix *J, const gsl_vector *r,
                          double step_tol, double gradient_tol)
{
  bool small_step = true;
  for (size_t i = 0; i < dx->size; i++)
    small_step = small_step && fabs(gsl_vector_get(dx, i)) <= step_tol;
  if (small_step)
    return true;
  double r_norm = gsl_blas_dnrm2(r);
  if (r_norm == 0.0)
    return true;
  for (size_t j = 0; j < J->size2; j++) {
    gsl_vector_const_view col = gsl_matrix_const_column(J, j);
    double g, c_norm = gsl_blas_dnrm2(&col.vector);
    gsl_blas_ddot(&col.vector, r, &g);
    if (fabs(g) > gradient_tol * c_norm * r_norm)
      return false;
  }
  return true;
}

/* The caller-owned iteration loop. */
static af_status fit_iterate(af_fit *w)
{
  for (size_t i = 0; i < w->cfg.max_iterations; i++) {
    gsl_vector_memcpy(w->x_prev, gsl_multifit_nlinear_position(w->nls));
    int rc = gsl_multifit_nlinear_iterate(w->nls);
    if (w->left_table)
      return AF_ENOCONV; /* off the table: the caller falls back */
    /* GSL_ENOPROG: 16 trial steps in a row, each on a trust region half the
     * last, failed to lower the cost. That is a minimum to the precision of
     * the model (the integrator's noise), and how a noise-free pulse ends. */
    if (rc == GSL_ENOPROG)
      return AF_OK;
    if (rc != GSL_SUCCESS)
      return AF_ENOCONV;
    gsl_vector *dx = w->x_prev; /* reused: the step, up to its sign */
    gsl_vector_sub(dx, gsl_multifit_nlinear_position(w->nls));
    if (fit_converged(dx, gsl_multifit_nlinear_jac(w->nls), gsl_multifit_nlinear_residual(w->nls),
                      w->cfg.step_tol, w->cfg.gradient_tol))
      return AF_OK;
  }
  return AF_EBUDGET_FIT_ITER;
}

/* The Jacobian and residual at the final point: GSL's on the ODE path
 * (max_samples rows, 0 beyond n), the table search's (n rows). */
static const gsl_matrix *fit_jacobian(const af_fit *w)
{
  return w->on_table ? &w->jac_view.matrix : gsl_multifit_nlinear_jac(w->nls);
}

static const gsl_vector *fit_residual(const af_fit *w)
{
  return w->on_table ? &w->res_view.vector : gsl_multifit_nlinear_residual(w->nls);
}

/* ---- the table path's search --------------------------------------------- */

/* Solves (A + mu D^2) dx = -g for the p x p symmetric A by Cholesky; false
 * when the matrix is not positive definite. */
static bool lm_solve(size_t p, const double *a, const double *d2, double mu, const double *g,
                     double *dx)
{
  double l[AF_FIT_MAX_PARAMS * AF_FIT_MAX_PARAMS] = {0}, y[AF_FIT_MAX_PARAMS] = {0};
  for (size_t i = 0; i < p; i++) {
    for (size_t j = 0; j <= i; j++) {
      double v = a[i * p + j] + (i == j ? mu * d2[i] : 0.0);
      for (size_t k = 0; k < j; k++)
        v -= l[i * p + k] * l[j * p + k];
      if (i == j) {
        if (!(v > 0.0))
          return false;
        l[i * p + i] = sqrt(v);
      } else {
        l[i * p + j] = v / l[j * p + j];
      }
    }
  }
  for (size_t i = 0; i < p; i++) { /* L y = -g */
    double v = -g[i];
    for (size_t k = 0; k < i; k++)
      v -= l[i * p + k] * y[k];
    y[i] = v / l[i * p + i];
  }
  for (size_t i = p; i-- > 0;) { /* L^T dx = y */
    double v = y[i];
    for (size_t k = i + 1; k < p; k++)
      v -= l[k * p + i] * dx[k];
    dx[i] = v / l[i * p + i];
  }
  return true;
}

/* J^T J into a (p x p), J^T r into g and |r|^2, at the base. */
static double lm_normal(const af_fit *w, double *a, double *g)
{
  const size_t p = w->n_params;
  double cost = 0.0;
  memset(a, 0, p * p * sizeof *a);
  memset(g, 0, p * sizeof *g);
  for (size_t k = 0; k < w->n; k++) {
    const double *row = w->jac_n + k * p;
    for (size_t i = 0; i < p; i++) {
      g[i] += row[i] * w->res_n[k];
      for (size_t j = 0; j <= i; j++)
        a[i * p + j] += row[i] * row[j];
    }
    cost += w->res_n[k] * w->res_n[k];
  }
  for (size_t i = 0; i < p; i++)
    for (size_t j = 0; j < i; j++)
      a[j * p + i] = a[i * p + j];
  return cost;
}

/* The cost |r|^2 at x, the base moved there; infinite when the model
 * cannot run there (a rejected step). */
static double lm_cost_at(af_fit *w, const double *x)
{
  gsl_vector_const_view xv = gsl_vector_const_view_array(x, w->n_params);
  if (fit_base(w, &xv.vector) != AF_OK)
    return INFINITY;
  double cost = 0.0;
  for (size_t k = 0; k < w->n; k++)
    cost += w->res_n[k] * w->res_n[k];
  return cost;
}

/* The table path's search: Levenberg-Marquardt as GSL's (More scaling, the
 * damping mu updated by Nielsen's rule, a step accepted when it lowers the
 * cost), on the p x p normal equations, which are cheap here because the
 * table gives J analytically with every evaluation. The same ends as
 * fit_iterate: fit_converged, or AF_LM_MAX_REJECTS rejected trials in a
 * row (a minimum to the model's precision: AF_OK), or max_iterations
 * accepted steps (AF_EBUDGET_FIT_ITER). Leaving the table stops it
 * (left_table). From x_start, which fit_start has made the base. */
static af_status table_search(af_fit *w)
{
  const size_t p = w->n_params;
  double a[AF_FIT_MAX_PARAMS * AF_FIT_MAX_PARAMS], g[AF_FIT_MAX_PARAMS];
  double d2[AF_FIT_MAX_PARAMS] = {0}, dx[AF_FIT_MAX_PARAMS], trial[AF_FIT_MAX_PARAMS];
  double mu = AF_LM_MU_START, nu = 2.0;
  for (size_t i = 0; i < p; i++)
    w->lm_x[i] = gsl_vector_get(w->x_start, i);
  w->lm_iterations = 0;
  w->jac_view = gsl_matrix_view_array(w->jac_n, w->n, p);
  w->res_view = gsl_vector_view_array(w->res_n, w->n);
  if (!isfinite(lm_cost_at(w, w->lm_x)))
    return AF_ENUMERIC;
  double cost = lm_normal(w, a, g);
  for (size_t it = 0; it < w->cfg.max_iterations; it++) {
    for (size_t i = 0; i < p; i++)
      d2[i] = fmax(d2[i], a[i * p + i]);
    size_t rejects = 0;
    for (;;) {
      if (!lm_solve(p, a, d2, mu, g, dx))
        return AF_ENUMERIC;
      double pred = 0.0; /* cost - |r + J dx|^2 */
      for (size_t i = 0; i < p; i++) {
        trial[i] = w->lm_x[i] + dx[i];
        double adx = 0.0;
        for (size_t j = 0; j < p; j++)
          adx += a[i * p + j] * dx[j];
        pred -= 2.0 * g[i] * dx[i] + dx[i] * adx;
      }
      double trial_cost = lm_cost_at(w, trial);
      if (w->left_table)
        return AF_ENOCONV; /* the caller falls back */
      double rho = (cost - trial_cost) / pred;
      if (pred > 0.0 && rho > 0.0) {
        double c = 2.0 * rho - 1.0;
        mu *= fmax(1.0 / 3.0, 1.0 - c * c * c);
        nu = 2.0;
        break;
      }
      mu *= nu;
      nu *= 2.0;
      if (++rejects >= AF_LM_MAX_REJECTS)
        return AF_OK; /* no step lowers the cost: a minimum (as GSL_ENOPROG) */
    }
    memcpy(w->lm_x, trial, p * sizeof trial[0]);
    w->lm_iterations++;
    cost = lm_normal(w, a, g); /* the base is the accepted trial */
    gsl_vector_view dxv = gsl_vector_view_array(dx, p);
    if (fit_converged(&dxv.vector, &w->jac_view.matrix, &w->res_view.vector, w->cfg.step_tol,
                      w->cfg.gradient_tol))
      return AF_OK;
  }
  return AF_EBUDGET_FIT_ITER;
}

/* The covariance of the scaled parameters, s^2 (J^T J)^-1 with
 * s^2 = |r|^2 / (n - p), into the lower triangle of w->normal.
 * gsl_multifit_nlinear_covar would allocate an n x p copy on every call, so
 * the p x p normal matrix is inverted here instead, by Cholesky after
 * scaling its columns to unit norm (the condition number that squaring J
 * costs is then only that of the parameter correlations). */
static af_status fit_covariance(af_fit *w)
{
  const gsl_matrix *J = fit_jacobian(w);
  const gsl_vector *r = fit_residual(w);
  const size_t p = w->n_params;
  double norm[AF_FIT_MAX_PARAMS] = {0};
  for (size_t j = 0; j < p; j++) {
    gsl_vector_const_view col = gsl_matrix_const_column(J, j);
    norm[j] = gsl_blas_dnrm2(&col.vector);
    if (!(norm[j] > 0.0))
      return AF_ENUMERIC;
  }
  gsl_blas_dsyrk(CblasLower, CblasTrans, 1.0, J, 0.0, w->normal);
  for (size_t i = 0; i < p; i++)
    for (size_t j = 0; j <= i; j++)
      gsl_matrix_set(w->normal, i, j, gsl_matrix_get(w->normal, i, j) / (norm[i] * norm[j]));
  if (gsl_linalg_cholesky_decomp1(w->normal) != GSL_SUCCESS ||
      gsl_linalg_cholesky_invert(w->normal) != GSL_SUCCESS)
    return AF_ENUMERIC;
  double r_norm = gsl_blas_dnrm2(r);
  double s2 = r_norm * r_norm / (double)(w->n - p);
  for (size_t i = 0; i < p; i++)
    for (size_t j = 0; j <= i; j++)
      gsl_matrix_set(w->normal, i, j, s2 * gsl_matrix_get(w->normal, i, j) / (norm[i] * norm[j]));
  return AF_OK;
}

/* Standard error of the fitted model's contact time, to first order:
 * sqrt(g^T C g) with g_j = dt_c/dx_j from the last Jacobian's runs. */
static double fit_contact_time_se(const af_fit *w)
{
  double g[AF_FIT_MAX_PARAMS] = {0}, var = 0.0;
  for (size_t j = 0; j < w->n_params; j++)
    g[j] = w->on_table ? w->tc_grad_s[j]
                       : (w->probe_contact_time_s[j] - w->base_res.contact_time_s) / AF_FIT_FD_STEP;
  for (size_t i = 0; i < w->n_params; i++)
    for (size_t j = 0; j <= i; j++)
      var += (i == j ? 1.0 : 2.0) * g[i] * g[j] * gsl_matrix_get(w->normal, i, j);
  return sqrt(fmax(var, 0.0));
}

/* The table path's check, part 1: one ODE run at the table's optimum x,
 * read at the data times into check_n; its contact time and peak into out
 * (the ODE's, as on the ODE path). */
static af_status check_run(af_fit *w, const double *x, af_fit_result *out)
{
  af_impact_params p;
  af_impact_result res;
  double t0_s, slope, h_s = w->dt_s / AF_FIT_CHECK_OVERSAMPLE;
  fit_unpack(w, x, &p, &t0_s);
  w->model_runs++;
  af_status st = af_impact_execute(w->impact, &p, h_s, w->model_n, NULL, w->model_cap, &res);
  if (st == AF_ESIZE && h_s < w->h_s) { /* a long pulse: the search's step */
    h_s = w->h_s;
    w->model_runs++;
    st = af_impact_execute(w->impact, &p, h_s, w->model_n, NULL, w->model_cap, &res);
  }
  if (st != AF_OK)
    return st;
  for (size_t k = 0; k < w->n; k++)
    fit_interp(w->model_n, res.n_samples, h_s, (double)k * w->dt_s - t0_s, &w->check_n[k], &slope);
  out->contact_time_s = res.contact_time_s;
  out->peak_force_n = res.peak_force_n;
  return AF_OK;
}

/* Part 2, after the covariance: the first-order move of the scaled
 * parameters, (J^T J)^-1 J^T (ODE - table), when the ODE model replaces the
 * table's at its optimum: the largest component in standard errors, each
 * floored at AF_FIT_CHECK_SE_FLOOR. Infinite when it cannot be computed. */
static double check_shift(const af_fit *w)
{
  const gsl_matrix *J = fit_jacobian(w);
  const size_t p = w->n_params;
  double g[AF_FIT_MAX_PARAMS] = {0};
  for (size_t k = 0; k < w->n; k++)
    for (size_t j = 0; j < p; j++)
      g[j] += gsl_matrix_get(J, k, j) * w->scale * (w->check_n[k] - w->base_at_n[k]);
  double r_norm = gsl_blas_dnrm2(fit_residual(w));
  double s2 = r_norm * r_norm / (double)(w->n - p); /* normal holds s2 (J^T J)^-1 */
  if (!(s2 > 0.0))
    return INFINITY;
  double worst = 0.0;
  for (size_t i = 0; i < p; i++) {
    double shift = 0.0;
    for (size_t j = 0; j < p; j++)
      shift += gsl_matrix_get(w->normal, i > j ? i : j, i > j ? j : i) * g[j] / s2;
    double se = sqrt(gsl_matrix_get(w->normal, i, i));
    worst = fmax(worst, fabs(shift) / fmax(se, AF_FIT_CHECK_SE_FLOOR));
  }
  return isnan(worst) ? INFINITY : worst;
}

/* Fills out from the final point; the status says whether the standard
 * errors could be computed. On the table path it also runs the check
 * (check_failed). */
static af_status fit_report(af_fit *w, af_fit_result *out)
{
  gsl_vector_view lm_xv = gsl_vector_view_array(w->lm_x, w->n_params);
  const gsl_vector *xv = w->on_table ? &lm_xv.vector : gsl_multifit_nlinear_position(w->nls);
  double x[AF_FIT_MAX_PARAMS] = {0};
  for (size_t i = 0; i < w->n_params; i++)
    x[i] = gsl_vector_get(xv, i);
  af_impact_params p;
  fit_unpack(w, x, &p, &out->time_offset_s);
  out->modulus_pa = p.fruit_modulus_pa;
  out->restitution = p.restitution;
  out->velocity_m_s = p.velocity_m_s;
  out->iterations = w->on_table ? w->lm_iterations : gsl_multifit_nlinear_niter(w->nls);
  if (fit_base(w, xv) != AF_OK) /* reruns only if the last run was a rejected trial */
    return AF_ENUMERIC;
  const double *model_at_n = w->base_at_n;
  if (w->on_table) {
    af_status st = check_run(w, x, out);
    w->check_failed = st != AF_OK;
    if (st != AF_OK)
      return st;
    model_at_n = w->check_n;
  } else {
    out->contact_time_s = w->base_res.contact_time_s;
    out->peak_force_n = w->base_res.peak_force_n;
  }
  double ss = 0.0;
  for (size_t k = 0; k < w->n; k++)
    ss += (model_at_n[k] - w->pulse_n[k]) * (model_at_n[k] - w->pulse_n[k]);
  out->residual_rms_n = sqrt(ss / (double)w->n);
  out->relative_residual = out->residual_rms_n / w->peak_n;

  af_status st = fit_covariance(w);
  if (w->on_table) {
    out->check_shift = st == AF_OK ? check_shift(w) : INFINITY;
    w->check_failed = !(out->check_shift <= w->cfg.table_check_se);
  }
  if (st != AF_OK)
    return st;
  double se[AF_FIT_MAX_PARAMS] = {0};
  for (size_t j = 0; j < w->n_params; j++)
    se[j] = sqrt(gsl_matrix_get(w->normal, j, j));
  out->contact_time_se_s = fit_contact_time_se(w);
  out->modulus_se_pa = p.fruit_modulus_pa * se[AF_IX_MODULUS];
  out->restitution_se = restitution_slope(x[AF_IX_RESTITUTION]) * se[AF_IX_RESTITUTION];
  out->velocity_se_m_s = w->ix_velocity == AF_IX_NONE ? 0.0 : p.velocity_m_s * se[w->ix_velocity];
  out->time_offset_se_s = w->ix_time == AF_IX_NONE ? 0.0 : w->dt_s * se[w->ix_time];
  return AF_OK;
}

static af_status fit_finish(af_fit_result *out, af_status st, const af_fit *w)
{
  out->model_runs = w != NULL ? w->model_runs : 0;
  out->status = st;
  return st;
}

static void fit_result_clear(af_fit_result *out)
{
  *out = (af_fit_result){.modulus_pa = NAN,
                         .modulus_se_pa = NAN,
                         .restitution = NAN,
                         .restitution_se = NAN,
                         .velocity_m_s = NAN,
                         .velocity_se_m_s = NAN,
                         .time_offset_s = NAN,
                         .time_offset_se_s = NAN,
                         .contact_time_s = NAN,
                         .contact_time_se_s = NAN,
                         .peak_force_n = NAN,
                         .residual_rms_n = NAN,
                         .relative_residual = NAN,
                         .check_shift = NAN};
}

/* Whether the fitted model explains the pulse as a strike: a small enough
 * residual, and a contact [t0, t0 + t_c] inside the window [-dt, n dt]
 * (the detector's window runs from the first sample at or after the contact
 * start to the last at or before its end) widened by window_margin of its
 * length. With few samples, noise alone is fitted closely by a pulse that
 * starts long before the window and lasts 100 times longer: only the second
 * test sees it. */
static bool fit_explains(const af_fit *w, const af_fit_result *r)
{
  double length_s = (double)w->n * w->dt_s, margin_s = w->cfg.window_margin * length_s;
  return r->relative_residual <= w->cfg.max_relative_residual &&
         r->time_offset_s >= -w->dt_s - margin_s &&
         r->time_offset_s + r->contact_time_s <= length_s + margin_s;
}

/* One search on the table (on_table) or the ODE, from the start to out.
 * On the table, *path says whether its result stands: a point off the grid
 * or a failed check sets it to the fallback's reason. */
static af_status fit_search(af_fit *w, bool on_table, af_fit_result *out, af_fit_path *path)
{
  w->on_table = on_table;
  w->left_table = false;
  w->check_failed = false;
  w->base_valid = false;
  af_status st = fit_start(w);
  if (on_table && w->left_table) {
    *path = AF_FIT_PATH_FALLBACK_RANGE;
    return st;
  }
  if (st != AF_OK)
    return st;
  af_status fit_st = on_table ? table_search(w) : fit_iterate(w);
  if (on_table && w->left_table) {
    *path = AF_FIT_PATH_FALLBACK_RANGE;
    return fit_st;
  }
  af_status report_st = fit_report(w, out);
  if (on_table && w->check_failed) {
    *path = AF_FIT_PATH_FALLBACK_CHECK;
    return report_st;
  }
  /* Most telling first: a pulse the model cannot explain is no strike,
   * whether or not the search converged on it (NaN: no final model). */
  if (!isnan(out->relative_residual) && !fit_explains(w, out))
    return AF_ENODATA;
  return fit_st != AF_OK ? fit_st : report_st;
}

af_status af_fit_execute(af_fit *w, const af_impact_params *start, const double *pulse_n, size_t n,
                         double dt_s, double t0_s, af_fit_result *out)
{
  if (out == NULL)
    return AF_EINVAL;
  fit_result_clear(out);
  af_status st = fit_check(w, start, pulse_n, n, dt_s, t0_s);
  if (st != AF_OK)
    return fit_finish(out, st, NULL);
  st = fit_setup(w, start, pulse_n, n, dt_s, t0_s);
  if (st != AF_OK)
    return fit_finish(out, st, w);
  if (w->cfg.use_table) {
    af_fit_path path = AF_FIT_PATH_TABLE;
    st = fit_search(w, true, out, &path);
    out->path = path;
    if (path == AF_FIT_PATH_TABLE) {
      w->from_table++;
      return fit_finish(out, st, w);
    }
    w->fallbacks++;
    double shift = out->check_shift; /* kept: why the table's result fell */
    fit_result_clear(out);
    out->path = path;
    out->check_shift = shift;
  }
  st = fit_search(w, false, out, NULL);
  return fit_finish(out, st, w);
}

void af_fit_counts(const af_fit *w, size_t *from_table, size_t *fallbacks)
{
  if (from_table != NULL)
    *from_table = w != NULL ? w->from_table : 0;
  if (fallbacks != NULL)
    *fallbacks = w != NULL ? w->fallbacks : 0;
}

const char *af_fit_path_name(af_fit_path path)
{
  switch (path) {
  case AF_FIT_PATH_ODE: return "ode";
  case AF_FIT_PATH_TABLE: return "table";
  case AF_FIT_PATH_FALLBACK_RANGE: return "fallback-range";
  case AF_FIT_PATH_FALLBACK_CHECK: return "fallback-check";
  }
  return "unknown";
}
