/* response_lm.c — the Levenberg-Marquardt solver of the response's complex
 * fits (stage 2, the peak list's truncated one- and two-pole fits), in place
 * of GSL's multifit_nlinear driver. It moves only the poles' f0 and sigma'
 * (2 or 4 parameters): the linear ones are solved at every point by the
 * residual pass (variable projection, response_vp.c).
 *
 * Why not GSL: the fits are small (2 or 4 parameters, 18-130 rows) and
 * many (a dozen per strike). GSL's trust-region driver spent most of their
 * time outside the model: the residuals and the Jacobian in two passes, the
 * Jacobian stored and zeroed, cblas_dsyrk and cblas_dgemv for J^T J and
 * J^T f, and cblas_dnrm2 (one division per element) for the column norms of
 * its scaling at every iteration. Here the model's pass over the bins forms
 * the normal equations itself, J never stored (af_response_fit_eval), the
 * scaling comes from their diagonal, and the p x p system is solved by
 * Cholesky on the stack.
 *
 * The method is GSL's default one (Levenberg-Marquardt with More's scaling,
 * Nielsen's damping update): step dx from (J^T J + mu D^2) dx = -J^T f,
 * D_j^2 = the largest [J^T J]_jj seen (More), mu starting at 1e-3; a step is
 * taken when the cost falls (rho = actual / predicted reduction > 0), then
 * mu *= max(1/3, 1 - (2 rho - 1)^3), nu = 2; else mu *= nu, nu *= 2 and the
 * step is solved again. Stopping, with its named status (response.h):
 *  CONVERGED  every step component |dx_j| <= xtol (|x_j| + xtol) (a step
 *             taken, or one refused because rounding made the cost rise at
 *             the minimum), or the scaled gradient
 *             max_j |g_j| max(|x_j|, 1) <= gtol max(cost, 1), or the cost
 *             fell by at most ftol of itself, or (the peak list's truncated
 *             fits, response_fit.c) the Gauss-Newton step from the point
 *             would lower the cost by at most the fit's cost_floor, or the
 *             cost is at most the fit's cost_stop (a caller that asks only
 *             whether the minimum lies below it);
 *  CAPPED     max_iter steps taken (the callers' caps: 50 and 25);
 *  STALLED    AF_RESPONSE_LM_MAX_REJECT steps in a row raised the cost;
 *  FAILED     the start's residuals or Jacobian are not finite.
 * No allocation: everything lives on the stack (p <= 4). */
#include "response_chol.h"
#include "response_private.h"

#include <math.h>
#include <string.h>

/* Steps in a row that may raise the cost before the fit is stalled (GSL's
 * trust-region driver: 15). */
#define AF_RESPONSE_LM_MAX_REJECT 15
/* Starting damping, relative to the scaled diagonal (GSL: 1e-3). */
#define AF_RESPONSE_LM_MU0 1e-3

/* Solves m x = b for symmetric positive definite m (p x p, overwritten by
 * its Cholesky factor); 0 if m is not positive definite. */
AF_NUMERIC_KERNEL static int cholesky_solve(double *m, size_t p, const double *b, double *x)
{
  if (!af_response_chol_factor(m, p))
    return 0;
  memcpy(x, b, p * sizeof *x);
  af_response_chol_solve(m, p, x);
  return 1;
}

/* Every |dx_j| <= xtol (|x_j| + xtol). */
AF_NUMERIC_KERNEL static int step_small(const double *x, const double *dx, size_t p, double xtol)
{
  for (size_t j = 0; j < p; ++j)
    if (!(fabs(dx[j]) <= xtol * (fabs(x[j]) + xtol)))
      return 0;
  return 1;
}

/* The normal equations at a point, with the cost they were formed with. */
typedef struct {
  double a[AF_RESPONSE_SPLIT_PARAMS * AF_RESPONSE_SPLIT_PARAMS]; /* J^T J, p x p */
  double g[AF_RESPONSE_SPLIT_PARAMS];                            /* J^T f */
  double cost;                                                   /* |f|^2 */
  double beta[AF_RESPONSE_SPLIT_PARAMS]; /* the linear parameters solved there */
  int ok;                                /* J finite there */
} normal_eq;

/* One step from x (its normal equations *at, scaling d2): 1 taken (x, the
 * step into dx, the trial's normal equations into *next; the damping mu, nu
 * updated); 2 converged: a step that raised the cost (rounding, at the
 * minimum) was already below xtol, so no step the tolerance cares about
 * lowers it (MINPACK's test on the trust region); 0 stalled:
 * AF_RESPONSE_LM_MAX_REJECT steps raised it. A trial point's normal
 * equations are formed with its cost, in the same pass over the bins: a
 * taken step (the most) then needs no second pass (one model
 * evaluation per iteration, not two). */
AF_NUMERIC_KERNEL static int lm_step(af_response *r, size_t p, double *x, const normal_eq *at,
                                     const double *a, normal_eq *next, const double *d2, double *mu,
                                     double *nu, double *dx, double xtol)
{
  double m[AF_RESPONSE_SPLIT_PARAMS * AF_RESPONSE_SPLIT_PARAMS], minus_g[AF_RESPONSE_SPLIT_PARAMS];
  double xt[AF_RESPONSE_SPLIT_PARAMS];
  const double *g = at->g;
  for (size_t j = 0; j < p; ++j)
    minus_g[j] = -g[j];
  for (size_t tries = 0; tries < AF_RESPONSE_LM_MAX_REJECT; ++tries) {
    memcpy(m, a, p * p * sizeof *m);
    for (size_t j = 0; j < p; ++j)
      m[j * p + j] += *mu * d2[j];
    if (cholesky_solve(m, p, minus_g, dx)) {
      /* predicted reduction by the quadratic model of the cost (a: its
       * Hessian / 2, J^T J in the Gauss-Newton model): -2 g.dx - dx^T a dx */
      double pred = 0.0;
      for (size_t j = 0; j < p; ++j) {
        double adx = 0.0;
        for (size_t l = 0; l < p; ++l)
          adx += a[j * p + l] * dx[l];
        pred -= dx[j] * (2.0 * g[j] + adx);
        xt[j] = x[j] + dx[j];
      }
      /* 0 from the pass: the cost or a derivative not finite there */
      next->ok = af_response_fit_eval(r, xt, &next->cost, next->a, next->g, next->beta);
      double trial = isfinite(next->cost) ? next->cost : INFINITY;
      double rho = pred > 0.0 ? (at->cost - trial) / pred : -1.0;
      if (isfinite(trial) && rho > 0.0) {
        memcpy(x, xt, p * sizeof *x);
        double t = 2.0 * rho - 1.0;
        *mu *= fmax(1.0 / 3.0, 1.0 - t * t * t);
        *nu = 2.0;
        return 1;
      }
      if (step_small(x, dx, p, xtol))
        return 2;
    }
    *mu *= *nu;
    *nu *= 2.0;
  }
  return 0;
}

/* The structured secant update of s (p x p), the part of the cost's
 * Hessian / 2 that J^T J lacks (sum f_i d2f_i: large when the fit leaves a
 * residual well above the noise, where the Gauss-Newton steps converge only
 * linearly), after the step dx changed the gradient J^T f by y, a_new the
 * new J^T J: s dx = y - a_new dx (the secant condition; Dennis, Gay and
 * Welsch's update with NL2SOL's sizing). Skipped when y . dx <= 0. */
AF_NUMERIC_KERNEL static void secant_update(size_t p, double *s, const double *dx, const double *y,
                                            const double *a_new)
{
  double ysharp[AF_RESPONSE_SPLIT_PARAMS], sdx[AF_RESPONSE_SPLIT_PARAMS];
  double ys = 0.0, sys = 0.0, dsd = 0.0, ws = 0.0;
  for (size_t j = 0; j < p; ++j) {
    double adx = 0.0, s_dx = 0.0;
    for (size_t l = 0; l < p; ++l) {
      adx += a_new[j * p + l] * dx[l];
      s_dx += s[j * p + l] * dx[l];
    }
    ysharp[j] = y[j] - adx;
    sdx[j] = s_dx;
    ys += y[j] * dx[j];
    sys += ysharp[j] * dx[j];
    dsd += s_dx * dx[j];
  }
  if (!(ys > 0.0) || !isfinite(ys))
    return;
  double tau = fabs(dsd) > 0.0 ? fmin(1.0, fabs(sys) / fabs(dsd)) : 1.0;
  for (size_t j = 0; j < p; ++j) {
    ysharp[j] -= tau * sdx[j]; /* now w = y# - tau s dx */
    ws += ysharp[j] * dx[j];
  }
  for (size_t j = 0; j < p; ++j)
    for (size_t l = 0; l < p; ++l)
      s[j * p + l] = tau * s[j * p + l] + (ysharp[j] * y[l] + y[j] * ysharp[l]) / ys -
                     ws * y[j] * y[l] / (ys * ys);
}

/* 1 if the Gauss-Newton step from *at would lower the cost by at most floor
 * (> 0): g^T (J^T J)^-1 g, the cost the linearised model has still to lose,
 * is the squared distance to its minimum in the metric J^T J. 0 when floor is
 * 0 or J^T J is not positive definite. */
AF_NUMERIC_KERNEL static int near_minimum(const normal_eq *at, size_t p, double floor)
{
  double m[AF_RESPONSE_SPLIT_PARAMS * AF_RESPONSE_SPLIT_PARAMS], y[AF_RESPONSE_SPLIT_PARAMS];
  if (!(floor > 0.0))
    return 0;
  memcpy(m, at->a, p * p * sizeof *m);
  if (!cholesky_solve(m, p, at->g, y))
    return 0;
  double decrement = 0.0;
  for (size_t j = 0; j < p; ++j)
    decrement += at->g[j] * y[j];
  return decrement <= floor;
}

/* The iterations from *at (formed at x); the last point's equations in *at.
 * The secant term s joins J^T J only in the tail (the last step lowered the
 * cost by less than AF_RESPONSE_LM_TAIL of it): there the fit is in the
 * minimum's basin and s only speeds the approach; earlier, the Gauss-Newton
 * path decides which minimum is reached, as before s existed. */
#define AF_RESPONSE_LM_TAIL 1e-3
AF_NUMERIC_KERNEL static af_response_fit_status
lm_iterate(af_response *r, size_t p, double *x, normal_eq **at_io, normal_eq **next_io,
           size_t max_iter, double xtol, double gtol, double ftol, size_t *iterations)
{
  double d2[AF_RESPONSE_SPLIT_PARAMS], dx[AF_RESPONSE_SPLIT_PARAMS];
  double mu = AF_RESPONSE_LM_MU0, nu = 2.0;
  double s[AF_RESPONSE_SPLIT_PARAMS * AF_RESPONSE_SPLIT_PARAMS] = {0.0};
  double h[AF_RESPONSE_SPLIT_PARAMS * AF_RESPONSE_SPLIT_PARAMS], y[AF_RESPONSE_SPLIT_PARAMS];
  normal_eq *at = *at_io, *next = *next_io;
  af_response_fit_status st = AF_RESPONSE_FIT_CAPPED;
  int tail = 0;
  for (size_t j = 0; j < p; ++j)
    d2[j] = 0.0;
  while (*iterations < max_iter) {
    /* every step taken lowers the cost: the minimum lies below this point */
    if (r->ctx.cost_stop > 0.0 && at->cost <= r->ctx.cost_stop) {
      st = AF_RESPONSE_FIT_CONVERGED;
      break;
    }
    double gmax = 0.0;
    for (size_t j = 0; j < p; ++j) {
      double diag = at->a[j * p + j];
      d2[j] = fmax(d2[j], diag > 0.0 ? diag : (d2[j] > 0.0 ? d2[j] : 1.0));
      gmax = fmax(gmax, fabs(at->g[j]) * fmax(fabs(x[j]), 1.0));
    }
    if (gmax <= gtol * fmax(at->cost, 1.0) || near_minimum(at, p, r->ctx.cost_floor)) {
      st = AF_RESPONSE_FIT_CONVERGED;
      break;
    }
    double before = at->cost;
    for (size_t j = 0; j < p * p; ++j)
      h[j] = tail ? at->a[j] + s[j] : at->a[j];
    int step = lm_step(r, p, x, at, h, next, d2, &mu, &nu, dx, xtol);
    if (step != 1) {
      st = step == 2 ? AF_RESPONSE_FIT_CONVERGED : AF_RESPONSE_FIT_STALLED;
      break;
    }
    normal_eq *taken = next;
    next = at;
    at = taken;
    ++*iterations;
    for (size_t j = 0; j < p; ++j)
      y[j] = at->g[j] - next->g[j];
    secant_update(p, s, dx, y, at->a);
    tail = before - at->cost < AF_RESPONSE_LM_TAIL * before;
    if (!at->ok) {
      st = AF_RESPONSE_FIT_FAILED; /* a derivative not finite there */
      break;
    }
    if (step_small(x, dx, p, xtol) || before - at->cost <= ftol * before) {
      st = AF_RESPONSE_FIT_CONVERGED;
      break;
    }
  }
  *at_io = at;
  *next_io = next;
  return st;
}

AF_NUMERIC_KERNEL af_response_fit_status af_response_lm(af_response *r, size_t p, double *x,
                                                        double *beta, size_t max_iter, double xtol,
                                                        double gtol, double ftol, double *cost_out,
                                                        size_t *iterations)
{
  normal_eq eq[2], *at = &eq[0], *next = &eq[1];
  *iterations = 0;
  if (!af_response_fit_eval(r, x, &at->cost, at->a, at->g, at->beta)) {
    *cost_out = at->cost;
    return AF_RESPONSE_FIT_FAILED;
  }
  af_response_fit_status st =
      lm_iterate(r, p, x, &at, &next, max_iter, xtol, gtol, ftol, iterations);
  *cost_out = at->cost;
  memcpy(beta, at->beta, sizeof at->beta);
  return st;
}
