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
 * The table path (cfg.use_table, the default): fit_table.c.
 */
#include "fit_private.h"

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
 * table_check_se; fit_table.c floors the standard errors). */
#define AF_FIT_CHECK_SHIFT_SE 0.1

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

bool af_fit_is_positive(double v)
{
  return isfinite(v) && v > 0.0;
}

static bool fit_config_valid(const af_fit_config *c)
{
  /* the model buffer's size in bytes must not overflow */
  const size_t limit = SIZE_MAX / 16 / AF_FIT_MODEL_SPAN / AF_FIT_MAX_OVERSAMPLE;
  return c->max_samples >= AF_FIT_MIN_SAMPLES && c->max_samples <= limit && c->oversample >= 1 &&
         c->oversample <= AF_FIT_MAX_OVERSAMPLE && c->max_iterations >= 1 &&
         af_fit_is_positive(c->step_tol) && af_fit_is_positive(c->gradient_tol) &&
         af_fit_is_positive(c->max_relative_residual) && isfinite(c->window_margin) &&
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
double af_fit_restitution_slope(double x)
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
void af_fit_unpack(const af_fit *w, const double *x, af_impact_params *p, double *t0_s)
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
void af_fit_interp(const double *g, size_t n_g, double h_s, double tau_s, double *value,
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
  af_fit_unpack(w, x, &p, t0_s);
  w->model_runs++;
  return af_impact_execute(w->impact, &p, w->h_s, buf, NULL, w->model_cap, res);
}

/* Makes x the base point: the model and its values and slopes at the data
 * times. Reuses the last run when x has not moved (GSL asks for J right
 * after f at the same point). */
af_status af_fit_base(af_fit *w, const gsl_vector *xv)
{
  double x[AF_FIT_MAX_PARAMS] = {0};
  for (size_t i = 0; i < w->n_params; i++)
    x[i] = gsl_vector_get(xv, i);
  if (w->base_valid && memcmp(x, w->base_x, w->n_params * sizeof x[0]) == 0)
    return w->base_failed ? AF_ENUMERIC : AF_OK;
  memcpy(w->base_x, x, w->n_params * sizeof x[0]);
  w->base_valid = true;
  if (w->on_table) {
    af_status st = af_fit_table_model(w, x);
    w->base_failed = st != AF_OK;
    return st;
  }
  double t0_s;
  af_status st = fit_model(w, x, w->model_n, &w->base_res, &t0_s);
  w->base_failed = st != AF_OK;
  if (st != AF_OK)
    return st;
  for (size_t k = 0; k < w->n; k++)
    af_fit_interp(w->model_n, w->base_res.n_samples, w->h_s, (double)k * w->dt_s - t0_s,
                  &w->base_at_n[k], &w->base_slope_n_s[k]);
  return AF_OK;
}

/* ---- GSL callbacks ------------------------------------------------------ */

static int fit_f(const gsl_vector *x, void *params, gsl_vector *f)
{
  af_fit *w = params;
  gsl_vector_set_zero(f);
  if (af_fit_base(w, x) != AF_OK) {
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
    af_fit_interp(w->probe_n, res.n_samples, w->h_s, (double)k * w->dt_s - t0_s, &v, &s);
    gsl_matrix_set(J, k, j, w->scale * (v - w->base_at_n[k]) / AF_FIT_FD_STEP);
  }
  return GSL_SUCCESS;
}

static int fit_df(const gsl_vector *x, void *params, gsl_matrix *J)
{
  af_fit *w = params;
  gsl_matrix_set_zero(J);
  if (af_fit_base(w, x) != AF_OK)
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
  w->jac_n = calloc(AF_FIT_MAX_PARAMS * w->cfg.max_samples, sizeof *w->jac_n);
  w->check_n = malloc(w->cfg.max_samples * sizeof *w->check_n);
  w->res_n = malloc(w->cfg.max_samples * sizeof *w->res_n);
  w->final_res_n = malloc(w->cfg.max_samples * sizeof *w->final_res_n);
  return w->model_n && w->probe_n && w->base_at_n && w->base_slope_n_s && w->jac_n && w->check_n &&
                 w->res_n && w->final_res_n
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
  free(w->final_res_n);
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
      !af_fit_is_positive(dt_s) || !isfinite(t0_s))
    return AF_EINVAL;
  if (!(start->restitution > AF_FIT_RESTITUTION_MIN && start->restitution < 1.0) ||
      !af_fit_is_positive(start->fruit_modulus_pa) || !af_fit_is_positive(start->velocity_m_s))
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
        w->start_figures.impulse * w->start.hammer_mass_kg * w->start.velocity_m_s *
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
  if (!af_fit_is_positive(e2))
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
    st = af_fit_table_start_figures(w, x, &sc, &t0_s);
  } else {
    st = af_fit_base(w, w->x_start);
  }
  if (st != AF_OK && w->left_table)
    return st; /* the caller falls back */
  if (st != AF_OK)
    return st == AF_ESIZE || st == AF_EINVAL ? st : AF_ENUMERIC;
  if (w->cfg.match_start) {
    fit_match(w);
    st = af_fit_base(w, w->x_start);
    if (st != AF_OK && w->left_table)
      return st;
    if (st != AF_OK)
      return st == AF_ESIZE ? st : AF_ENUMERIC;
  }
  if (w->on_table)
    return AF_OK; /* af_fit_table_search takes over from x_start */
  return gsl_multifit_nlinear_init(w->x_start, &w->fdf, w->nls) == GSL_SUCCESS ? AF_OK
                                                                               : AF_ENUMERIC;
}

/* The convergence test, a pure function of the last step dx, the Jacobian J
 * and the residual r at the new point: every |dx_i| <= step_tol, or every
 * column of J within gradient_tol (as a cosine) of orthogonal to r. */
bool af_fit_converged(const gsl_vector *dx, const gsl_matrix *J, const gsl_vector *r,
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
    if (af_fit_converged(dx, gsl_multifit_nlinear_jac(w->nls),
                         gsl_multifit_nlinear_residual(w->nls), w->cfg.step_tol,
                         w->cfg.gradient_tol))
      return AF_OK;
  }
  return AF_EBUDGET_FIT_ITER;
}

/* The Jacobian and residual at the final point: GSL's on the ODE path
 * (max_samples rows, 0 beyond n), the table search's (n rows). */
const gsl_matrix *af_fit_jacobian(const af_fit *w)
{
  return w->on_table ? &w->jac_view.matrix : gsl_multifit_nlinear_jac(w->nls);
}

const gsl_vector *af_fit_residual(const af_fit *w)
{
  return w->on_table ? &w->res_view.vector : gsl_multifit_nlinear_residual(w->nls);
}

/* J^T J into the lower triangle of w->normal: the table search's own
 * (lm_jtj) while jac_n is its J, else gsl_blas_dsyrk's. Both are the sums
 * of J_ki J_kj over k = 0 .. n - 1 in k's order from 0 (GSL's CBLAS syrk:
 * 0 + 1 x the sum), the same doubles. */
static void fit_normal(af_fit *w, const gsl_matrix *J)
{
  const size_t p = w->n_params;
  if (!(w->on_table && w->lm_jtj_kept)) {
    gsl_blas_dsyrk(CblasLower, CblasTrans, 1.0, J, 0.0, w->normal);
    return;
  }
  for (size_t i = 0; i < p; i++)
    for (size_t j = 0; j <= i; j++)
      gsl_matrix_set(w->normal, i, j, w->lm_jtj[i * p + j]);
}

/* The covariance of the scaled parameters, s^2 (J^T J)^-1 with
 * s^2 = |r|^2 / (n - p), into the lower triangle of w->normal, |r| into
 * res_norm. gsl_multifit_nlinear_covar would allocate an n x p copy on
 * every call, so the p x p normal matrix is inverted here instead, by
 * Cholesky after scaling its columns to unit norm (the condition number
 * that squaring J costs is then only that of the parameter correlations). */
static af_status fit_covariance(af_fit *w)
{
  const gsl_matrix *J = af_fit_jacobian(w);
  const gsl_vector *r = af_fit_residual(w);
  const size_t p = w->n_params;
  double norm[AF_FIT_MAX_PARAMS] = {0};
  for (size_t j = 0; j < p; j++) {
    gsl_vector_const_view col = gsl_matrix_const_column(J, j);
    norm[j] = gsl_blas_dnrm2(&col.vector);
    if (!(norm[j] > 0.0))
      return AF_ENUMERIC;
  }
  fit_normal(w, J);
  for (size_t i = 0; i < p; i++)
    for (size_t j = 0; j <= i; j++)
      gsl_matrix_set(w->normal, i, j, gsl_matrix_get(w->normal, i, j) / (norm[i] * norm[j]));
  if (gsl_linalg_cholesky_decomp1(w->normal) != GSL_SUCCESS ||
      gsl_linalg_cholesky_invert(w->normal) != GSL_SUCCESS)
    return AF_ENUMERIC;
  double r_norm = w->res_norm = gsl_blas_dnrm2(r);
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
  af_fit_unpack(w, x, &p, &out->time_offset_s);
  out->modulus_pa = p.fruit_modulus_pa;
  out->restitution = p.restitution;
  out->velocity_m_s = p.velocity_m_s;
  out->iterations = w->on_table ? w->lm_iterations : gsl_multifit_nlinear_niter(w->nls);
  if (af_fit_base(w, xv) != AF_OK) /* reruns only if the last run was a rejected trial */
    return AF_ENUMERIC;
  const double *model_at_n = w->base_at_n;
  if (w->on_table) {
    af_status st = af_fit_check_run(w, x, out);
    w->check_failed = st != AF_OK;
    if (st != AF_OK)
      return st;
    model_at_n = w->check_n;
  } else {
    out->contact_time_s = w->base_res.contact_time_s;
    out->peak_force_n = w->base_res.peak_force_n;
  }
  double ss = 0.0;
  for (size_t k = 0; k < w->n; k++) {
    w->final_res_n[k] = w->pulse_n[k] - model_at_n[k];
    ss += w->final_res_n[k] * w->final_res_n[k];
  }
  w->final_n = w->n;
  out->residual_rms_n = sqrt(ss / (double)w->n);
  out->relative_residual = out->residual_rms_n / w->peak_n;

  af_status st = fit_covariance(w);
  if (w->on_table) {
    out->check_shift = st == AF_OK ? af_fit_check_shift(w) : INFINITY;
    w->check_failed = !(out->check_shift <= w->cfg.table_check_se);
  }
  if (st != AF_OK)
    return st;
  double se[AF_FIT_MAX_PARAMS] = {0};
  for (size_t j = 0; j < w->n_params; j++)
    se[j] = sqrt(gsl_matrix_get(w->normal, j, j));
  out->contact_time_se_s = fit_contact_time_se(w);
  out->modulus_se_pa = p.fruit_modulus_pa * se[AF_IX_MODULUS];
  out->restitution_se = af_fit_restitution_slope(x[AF_IX_RESTITUTION]) * se[AF_IX_RESTITUTION];
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
  af_status fit_st = on_table ? af_fit_table_search(w) : fit_iterate(w);
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
  if (w != NULL)
    w->final_n = 0;
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
    w->final_n = 0;
  }
  st = fit_search(w, false, out, NULL);
  return fit_finish(out, st, w);
}

af_status af_fit_get_residual(const af_fit *w, const double **residual_n, size_t *n)
{
  if (w == NULL || residual_n == NULL || n == NULL)
    return AF_EINVAL;
  *residual_n = w->final_n > 0 ? w->final_res_n : NULL;
  *n = w->final_n;
  return w->final_n > 0 ? AF_OK : AF_ENODATA;
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
