/* fit_table.c — the fit's table path (fit.h, fit.c).
 *
 * The table path (cfg.use_table, the default) searches the same scaled
 * parameters, from the same matched start, on the normalised pulse of
 * pulse_table.h: F(t) = F0 f((t - t0) / T; chi, gamma), with F0, T and gamma
 * from E2 and v0 by impact.c's scaling and chi from e by the damping law.
 * The table gives f and its slopes in tau, chi and gamma, so every column of
 * J is analytic (table_sample), and with J in hand at every evaluation the
 * Levenberg-Marquardt step is solved on the p x p normal equations
 * (af_fit_table_search) instead of GSL's QR of the max_samples x p Jacobian,
 * which cost more than the model. The search ends once Gauss-Newton's quadratic
 * regime puts it within AF_FIT_STOP_SE standard errors of the minimum, that
 * last step taken on the linear model (lm_near_minimum): an evaluation or two
 * fewer than step_tol's end, the result within ~1e-3 standard error of it. At
 * the optimum one ODE run, sampled at the data times, checks the table: the
 * Gauss-Newton step that the ODE model's residual would add from there,
 * (J^T J)^-1 J^T (F_ODE - F_table), must stay within table_check_se of every
 * parameter's standard error (floored at 1e-3 in x). The result then reports
 * the ODE run's contact time, peak and residual, the table's parameters and
 * standard errors. A point of the search off the table's grid, or a failed
 * check, reruns the whole fit on the ODE path (af_fit_path, af_fit_counts): the
 * fallback's result is the ODE fit's, bit for bit.
 */
#include "fit_private.h"

#include <math.h>
#include <string.h>

#include <gsl/gsl_blas.h>

/* The check's floor: each standard error taken as at least this much in the scaled
 * parameters [-] (1e-3 relative on E2 and v0, 1e-3 dt on t0): the floor for
 * noise-free pulses, whose standard errors are ~0, so that they may move by
 * 1e-4. */
#define AF_FIT_CHECK_SE_FLOOR 1e-3
/* Step of the central difference of chi(e) [-]: the laws are smooth (the
 * exact one a spline), so the error is ~1e-12 relative. */
#define AF_FIT_CHI_STEP 1e-6
/* The check's ODE runs at impact.c's tolerances times this [-]: its samples
 * then lie within ~1e-7 of the peak of the reference run's (1e-9), a
 * hundredth of the table's own error (pulse_table.h: ~1e-5), so that the
 * check still measures the table; its contact time within ~1e-8, its peak
 * within ~1e-7 (relative). A third of the reference run's steps. */
#define AF_FIT_CHECK_TOL_FACTOR 1e3
/* The table search's Levenberg-Marquardt: the first damping relative to the
 * More-scaled curvature [-] (GSL's), and the rejected trials in a row that
 * end it (GSL's 16 before GSL_ENOPROG). */
#define AF_LM_MU_START 1e-3
#define AF_LM_MAX_REJECTS 16
/* The table search ends at a point within this many standard errors [-] of
 * the linearised minimum (lm_gauss_newton), the Gauss-Newton step from there
 * taken on the linear model (lm_final_step): as the response fits, a small
 * fraction of the result's scatter under the pulse's noise, and the step's
 * own error is second order in it. */
#define AF_FIT_STOP_SE 0.1
/* ... when that distance fell by at least this factor [-] over the last
 * step: the quadratic regime of Gauss-Newton, where the linear model
 * holds (a search crawling along a curved valley of correlated E2, e and
 * v0 shortens its steps by a few tens of percent a step, its linearised
 * distance far below the true one) ... */
#define AF_FIT_STOP_RATIO 10.0
/* ... and when no scaled parameter moves by more than this [-] in the step:
 * its error, ~ its square (the model's curvature in x is of order 1), stays
 * a tenth of the check's floor (a pulse of a few samples has standard
 * errors of order 1 in x, where 0.1 of them is no small step). */
#define AF_FIT_STOP_STEP 1e-2
/* ---- the table's model -------------------------------------------------- */

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
  if (!af_fit_is_positive(sc->t_s) || !af_fit_is_positive(sc->f0_n) || !isfinite(chi_de) ||
      !isfinite(sc->gamma))
    return AF_EINVAL; /* the grid is af_pulse_table_shape's to judge */
  /* d ln E* / d ln E2: the fruit's share of the contact compliance */
  double share = af_impact_effective_modulus_pa(p) * (1.0 - p->fruit_poisson * p->fruit_poisson) /
                 p->fruit_modulus_pa;
  sc->dln_t[AF_IX_MODULUS] = -0.4 * share;
  sc->dln_f0[AF_IX_MODULUS] = 0.4 * share;
  sc->dln_gamma[AF_IX_MODULUS] = -0.4 * share;
  sc->dchi[AF_IX_RESTITUTION] = chi_de * af_fit_restitution_slope(x[AF_IX_RESTITUTION]);
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
  double base = sc->f0_n * f, slope = sc->f0_n * f_tau / sc->t_s;
  /* the products common to every column, in the order of the sum below */
  double stretch = -f_tau * tau, bend = f_gamma * sc->gamma;
  double *row = w->jac_n + k * AF_FIT_MAX_PARAMS;
  w->base_at_n[k] = base;
  w->base_slope_n_s[k] = slope;
  for (size_t j = 0; j < w->n_params; j++) {
    double d = j == w->ix_time ? -w->dt_s * slope
                               : base * sc->dln_f0[j] +
                                     sc->f0_n * (stretch * sc->dln_t[j] + f_chi * sc->dchi[j] +
                                                 bend * sc->dln_gamma[j]);
    row[j] = w->scale * d;
  }
  w->res_n[k] = w->scale * (w->base_at_n[k] - w->pulse_n[k]);
}

/* base_res's contact time, peak and sample count (as the ODE would write
 * them) and the contact time's gradient from the figures f at scales sc.
 * AF_ESIZE when the ODE's pulse would overflow its buffer, as on the ODE
 * path. */
static af_status table_figures_from(af_fit *w, const af_fit_scales *sc, const af_fit_figures *f)
{
  double tc_s = f->tau_c * sc->t_s, samples = floor(tc_s / w->h_s) + 1.0;
  if (!(samples <= (double)w->model_cap))
    return AF_ESIZE;
  w->base_res = (af_impact_result){.contact_time_s = tc_s,
                                   .peak_force_n = f->peak * sc->f0_n,
                                   .dt_s = w->h_s,
                                   .n_samples = (size_t)samples};
  for (size_t j = 0; j < w->n_params; j++)
    w->tc_grad_s[j] = j == w->ix_time ? 0.0
                                      : tc_s * (sc->dln_t[j] + f->dln_tau_c[0] * sc->dchi[j] +
                                                f->dln_tau_c[1] * sc->gamma * sc->dln_gamma[j]);
  return AF_OK;
}

static af_fit_figures figures_of(const af_pulse_shape *s)
{
  return (af_fit_figures){.chi = s->chi,
                          .gamma = s->gamma,
                          .tau_c = s->tau_c,
                          .dln_tau_c = {s->dln_tau_c[0], s->dln_tau_c[1]},
                          .impulse = s->impulse,
                          .peak = s->peak,
                          .valid = true};
}

/* The scales at x, AF_EINVAL (and left_table) off the grid. */
static af_status table_point(af_fit *w, const double *x, af_fit_scales *sc, double *t0_s)
{
  af_impact_params p;
  af_fit_unpack(w, x, &p, t0_s);
  if (table_scales(w, &p, x, sc) != AF_OK || !af_pulse_table_covers(sc->chi, sc->gamma)) {
    w->left_table = true;
    return AF_EINVAL;
  }
  return AF_OK;
}

/* The table's figures at x: the shape, base_res's contact time, peak and
 * sample count and the contact time's gradient (table_figures_from).
 * AF_EINVAL (and left_table) off the grid; AF_ESIZE when the ODE's pulse
 * would overflow its buffer. */
af_status af_fit_table_figures(af_fit *w, const double *x, af_fit_scales *sc, double *t0_s)
{
  af_status st = table_point(w, x, sc, t0_s);
  if (st != AF_OK)
    return st;
  if (af_pulse_table_shape(w->table, sc->chi, sc->gamma, &w->shape) != AF_OK) {
    w->left_table = true;
    return AF_EINVAL;
  }
  af_fit_figures f = figures_of(&w->shape);
  return table_figures_from(w, sc, &f);
}

/* The same figures at the unmatched start x, for fit_match, which reads
 * only the shape's scalars, into start_figures: the shape is interpolated
 * only when (chi, gamma) differ from the last start's (the apple's nominal
 * parameters, the same from strike to strike on a line). The table is a
 * pure function of (chi, gamma): the same doubles as a new interpolation,
 * without its 3 x 65-node sums over 16 grid nodes. */
af_status af_fit_table_start_figures(af_fit *w, const double *x, af_fit_scales *sc, double *t0_s)
{
  af_status st = table_point(w, x, sc, t0_s);
  if (st != AF_OK)
    return st;
  af_fit_figures *f = &w->start_figures;
  if (!(f->valid && f->chi == sc->chi && f->gamma == sc->gamma)) {
    f->valid = false;
    if (af_pulse_table_shape(w->table, sc->chi, sc->gamma, &w->shape) != AF_OK) {
      w->left_table = true;
      return AF_EINVAL;
    }
    *f = figures_of(&w->shape);
  }
  return table_figures_from(w, sc, f);
}

/* ... and the model at the data times: values, slopes, Jacobian rows and
 * the scaled residual. */
af_status af_fit_table_model(af_fit *w, const double *x)
{
  af_fit_scales sc;
  double t0_s;
  af_status st = af_fit_table_figures(w, x, &sc, &t0_s);
  if (st != AF_OK)
    return st;
  for (size_t k = 0; k < w->n; k++)
    table_sample(w, &sc, k, t0_s);
  w->lm_jtj_kept = false; /* a new J */
  return AF_OK;
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

/* J^T J into a (p x p), J^T r into g and |r|^2, at the base. The sums run
 * over all four columns of jac_n whatever p (those past p are 0), written
 * out so that they stay in registers (the loops over a run-time p cost
 * three times their multiply-adds); adding 0 x 0 leaves the other sums the
 * same doubles. J^T J is kept for the covariance (lm_jtj). */
_Static_assert(AF_FIT_MAX_PARAMS == 4, "lm_normal's sums are written out for 4 columns");
static double lm_normal(af_fit *w, double *a, double *g)
{
  double g0 = 0.0, g1 = 0.0, g2 = 0.0, g3 = 0.0, cost = 0.0;
  double a00 = 0.0, a10 = 0.0, a11 = 0.0, a20 = 0.0, a21 = 0.0, a22 = 0.0;
  double a30 = 0.0, a31 = 0.0, a32 = 0.0, a33 = 0.0;
  for (size_t k = 0; k < w->n; k++) {
    const double *row = w->jac_n + k * AF_FIT_MAX_PARAMS, res = w->res_n[k];
    double r0 = row[0], r1 = row[1], r2 = row[2], r3 = row[3];
    g0 += r0 * res;
    g1 += r1 * res;
    g2 += r2 * res;
    g3 += r3 * res;
    a00 += r0 * r0;
    a10 += r1 * r0;
    a11 += r1 * r1;
    a20 += r2 * r0;
    a21 += r2 * r1;
    a22 += r2 * r2;
    a30 += r3 * r0;
    a31 += r3 * r1;
    a32 += r3 * r2;
    a33 += r3 * r3;
    cost += res * res;
  }
  const double gg[AF_FIT_MAX_PARAMS] = {g0, g1, g2, g3};
  const double aa[AF_FIT_MAX_PARAMS][AF_FIT_MAX_PARAMS] = {
      {a00, a10, a20, a30}, {a10, a11, a21, a31}, {a20, a21, a22, a32}, {a30, a31, a32, a33}};
  const size_t p = w->n_params;
  for (size_t i = 0; i < p; i++) {
    g[i] = gg[i];
    for (size_t j = 0; j < p; j++)
      a[i * p + j] = w->lm_jtj[i * p + j] = aa[i][j];
  }
  w->lm_jtj_kept = true;
  return cost;
}

/* The cost |r|^2 at x, the base moved there; infinite when the model
 * cannot run there (a rejected step). */
static double lm_cost_at(af_fit *w, const double *x)
{
  gsl_vector_const_view xv = gsl_vector_const_view_array(x, w->n_params);
  if (af_fit_base(w, &xv.vector) != AF_OK)
    return INFINITY;
  double cost = 0.0;
  for (size_t k = 0; k < w->n; k++)
    cost += w->res_n[k] * w->res_n[k];
  return cost;
}

/* The Gauss-Newton step dx = -(J^T J)^-1 g from the point whose normal
 * equations are a, g (lm_normal) and cost, and its length in standard
 * errors (the Mahalanobis distance to the linearised minimum): the
 * covariance being s2 (J^T J)^-1, s2 = cost / (n - p) (fit_covariance), the
 * step lowers the linear model's cost by g^T (J^T J)^-1 g = s2 d^2.
 * Infinite when J^T J is not positive definite or s2 is 0. */
static double lm_gauss_newton(const af_fit *w, const double *a, const double *g, double cost,
                              double *dx)
{
  const size_t p = w->n_params;
  const double no_damping[AF_FIT_MAX_PARAMS] = {0};
  if (!lm_solve(p, a, no_damping, 0.0, g, dx))
    return INFINITY;
  double decrement = 0.0;
  for (size_t i = 0; i < p; i++)
    decrement -= g[i] * dx[i];
  double d = sqrt(decrement / (cost / (double)(w->n - p)));
  return isnan(d) ? INFINITY : d;
}

/* Whether the search stops at a point whose Gauss-Newton step is dx, d
 * standard errors long, after a point d_prev from the minimum. */
static bool lm_near_minimum(const af_fit *w, const double *dx, double d, double d_prev)
{
  bool small = d <= AF_FIT_STOP_SE && d * AF_FIT_STOP_RATIO <= d_prev;
  for (size_t i = 0; i < w->n_params; i++)
    small = small && fabs(dx[i]) <= AF_FIT_STOP_STEP;
  return small;
}

/* Takes the Gauss-Newton step dx of lm_gauss_newton on the linear model:
 * the position moves by dx and the base's values and residual by J dx,
 * J stays; their error against the table there is second order in dx, a
 * model evaluation saved. The result then reads the base as the model at
 * the reported point (fit_report: the covariance, the check's shift). */
static void lm_final_step(af_fit *w, const double *dx)
{
  for (size_t k = 0; k < w->n; k++) {
    const double *row = w->jac_n + k * AF_FIT_MAX_PARAMS;
    double move = 0.0; /* scaled */
    for (size_t j = 0; j < w->n_params; j++)
      move += row[j] * dx[j];
    w->res_n[k] += move;
    w->base_at_n[k] += move / w->scale;
  }
  for (size_t j = 0; j < w->n_params; j++) {
    w->lm_x[j] += dx[j];
    w->base_x[j] = w->lm_x[j];
  }
  w->lm_iterations++;
}

/* The table path's search: Levenberg-Marquardt as GSL's (More scaling, the
 * damping mu updated by Nielsen's rule, a step accepted when it lowers the
 * cost), on the p x p normal equations, which are cheap here because the
 * table gives J analytically with every evaluation. It ends at a point
 * near the minimum (lm_near_minimum, then lm_final_step), else with the
 * ends of fit_iterate: af_fit_converged, or AF_LM_MAX_REJECTS rejected
 * trials in a row (a minimum to the model's precision: AF_OK), or
 * max_iterations accepted steps (AF_EBUDGET_FIT_ITER). Leaving the table
 * stops it (left_table). From x_start, which fit_start has made the base. */
af_status af_fit_table_search(af_fit *w)
{
  const size_t p = w->n_params;
  double a[AF_FIT_MAX_PARAMS * AF_FIT_MAX_PARAMS], g[AF_FIT_MAX_PARAMS];
  double d2[AF_FIT_MAX_PARAMS] = {0}, dx[AF_FIT_MAX_PARAMS], trial[AF_FIT_MAX_PARAMS];
  double mu = AF_LM_MU_START, nu = 2.0;
  for (size_t i = 0; i < p; i++)
    w->lm_x[i] = gsl_vector_get(w->x_start, i);
  w->lm_iterations = 0;
  w->jac_view = gsl_matrix_view_array_with_tda(w->jac_n, w->n, p, AF_FIT_MAX_PARAMS);
  w->res_view = gsl_vector_view_array(w->res_n, w->n);
  if (!isfinite(lm_cost_at(w, w->lm_x)))
    return AF_ENUMERIC;
  double cost = lm_normal(w, a, g);
  double d_prev = lm_gauss_newton(w, a, g, cost, dx); /* the start's distance */
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
    double gn[AF_FIT_MAX_PARAMS], d = lm_gauss_newton(w, a, g, cost, gn);
    if (lm_near_minimum(w, gn, d, d_prev)) {
      lm_final_step(w, gn);
      return AF_OK;
    }
    d_prev = d;
    gsl_vector_view dxv = gsl_vector_view_array(dx, p);
    if (af_fit_converged(&dxv.vector, &w->jac_view.matrix, &w->res_view.vector, w->cfg.step_tol,
                         w->cfg.gradient_tol))
      return AF_OK;
  }
  return AF_EBUDGET_FIT_ITER;
}

/* The table path's check, part 1: one ODE run at the table's optimum x,
 * sampled at the data times k dt - t0 themselves (impact.c's quintic
 * interpolant across its steps, ~1e-9: no interpolation of ours, whose own
 * error would add to the table's) into check_n, 0 before the contact and
 * after it; its contact time and peak into out (the ODE's, as on the ODE
 * path). */
af_status af_fit_check_run(af_fit *w, const double *x, af_fit_result *out)
{
  af_impact_params p;
  af_impact_result res;
  double t0_s;
  af_fit_unpack(w, x, &p, &t0_s);
  if (!isfinite(t0_s))
    return AF_ENUMERIC;
  /* the first sample in contact, k_first dt - t0 >= 0 (rounding may make it
   * -0: F = 0 there either way); none when the contact starts after the
   * window */
  double k_first = t0_s > 0.0 ? fmin(ceil(t0_s / w->dt_s), (double)w->n) : 0.0;
  double t_first_s = fmax(k_first * w->dt_s - t0_s, 0.0);
  w->model_runs++;
  af_status st = af_impact_execute_from(w->impact, &p, t_first_s, w->dt_s, AF_FIT_CHECK_TOL_FACTOR,
                                        w->model_n, w->model_cap, &res);
  if (st != AF_OK)
    return st;
  size_t first = (size_t)k_first;
  for (size_t k = 0; k < w->n; k++)
    w->check_n[k] = k >= first && k - first < res.n_samples ? w->model_n[k - first] : 0.0;
  out->contact_time_s = res.contact_time_s;
  out->peak_force_n = res.peak_force_n;
  return AF_OK;
}

/* Part 2, after the covariance: the first-order move of the scaled
 * parameters, (J^T J)^-1 J^T (ODE - table), when the ODE model replaces the
 * table's at its optimum: the largest component in standard errors, each
 * floored at AF_FIT_CHECK_SE_FLOOR. Infinite when it cannot be computed. */
double af_fit_check_shift(const af_fit *w)
{
  const gsl_matrix *J = af_fit_jacobian(w);
  const size_t p = w->n_params;
  double g[AF_FIT_MAX_PARAMS] = {0};
  for (size_t k = 0; k < w->n; k++) {
    const double *row = J->data + k * J->tda; /* gsl_matrix_get's element, unchecked */
    for (size_t j = 0; j < p; j++)
      g[j] += row[j] * w->scale * (w->check_n[k] - w->base_at_n[k]);
  }
  double s2 = w->res_norm * w->res_norm / (double)(w->n - p); /* normal: s2 (J^T J)^-1 */
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
