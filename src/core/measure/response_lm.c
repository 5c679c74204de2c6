/* response_lm.c — the Levenberg-Marquardt solver of the response's complex
 * fits (stage 2, the peak list's truncated one- and two-pole fits), in place
 * of GSL's multifit_nlinear driver.
 *
 * Why not GSL: the fits are small (10 or 14 parameters, 18-130 rows) and
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
 *             fell by at most ftol of itself;
 *  CAPPED     max_iter steps taken (the callers' caps: 50 and 25);
 *  STALLED    AF_RESPONSE_LM_MAX_REJECT steps in a row raised the cost;
 *  FAILED     the start's residuals or Jacobian are not finite.
 * No allocation: everything lives on the stack (p <= 14). */
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
  for (size_t j = 0; j < p; ++j) {
    double d = m[j * p + j];
    for (size_t k = 0; k < j; ++k)
      d -= m[j * p + k] * m[j * p + k];
    if (!(d > 0.0))
      return 0;
    d = sqrt(d);
    m[j * p + j] = d;
    for (size_t i = j + 1; i < p; ++i) {
      double s = m[i * p + j];
      for (size_t k = 0; k < j; ++k)
        s -= m[i * p + k] * m[j * p + k];
      m[i * p + j] = s / d;
    }
  }
  for (size_t i = 0; i < p; ++i) { /* L y = b */
    double s = b[i];
    for (size_t k = 0; k < i; ++k)
      s -= m[i * p + k] * x[k];
    x[i] = s / m[i * p + i];
  }
  for (size_t i = p; i-- > 0;) { /* L^T x = y */
    double s = x[i];
    for (size_t k = i + 1; k < p; ++k)
      s -= m[k * p + i] * x[k];
    x[i] = s / m[i * p + i];
  }
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
  int ok;                                                        /* J finite there */
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
                                     normal_eq *next, const double *d2, double *mu, double *nu,
                                     double *dx, double xtol)
{
  double m[AF_RESPONSE_SPLIT_PARAMS * AF_RESPONSE_SPLIT_PARAMS], minus_g[AF_RESPONSE_SPLIT_PARAMS];
  double xt[AF_RESPONSE_SPLIT_PARAMS];
  const double *a = at->a, *g = at->g;
  for (size_t j = 0; j < p; ++j)
    minus_g[j] = -g[j];
  for (size_t tries = 0; tries < AF_RESPONSE_LM_MAX_REJECT; ++tries) {
    memcpy(m, a, p * p * sizeof *m);
    for (size_t j = 0; j < p; ++j)
      m[j * p + j] += *mu * d2[j];
    if (cholesky_solve(m, p, minus_g, dx)) {
      /* predicted reduction: cost - |f + J dx|^2 = -2 g.dx - dx^T J^T J dx */
      double pred = 0.0;
      for (size_t j = 0; j < p; ++j) {
        double adx = 0.0;
        for (size_t l = 0; l < p; ++l)
          adx += a[j * p + l] * dx[l];
        pred -= dx[j] * (2.0 * g[j] + adx);
        xt[j] = x[j] + dx[j];
      }
      /* 0 from the pass: the cost or a derivative not finite there */
      next->ok = af_response_fit_eval(r, xt, &next->cost, next->a, next->g);
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

AF_NUMERIC_KERNEL af_response_fit_status af_response_lm(af_response *r, size_t p, double *x,
                                                        size_t max_iter, double xtol, double gtol,
                                                        double ftol, double *cost_out,
                                                        size_t *iterations)
{
  normal_eq eq[2], *at = &eq[0], *next = &eq[1];
  double d2[AF_RESPONSE_SPLIT_PARAMS], dx[AF_RESPONSE_SPLIT_PARAMS];
  double mu = AF_RESPONSE_LM_MU0, nu = 2.0;
  *iterations = 0;
  if (!af_response_fit_eval(r, x, &at->cost, at->a, at->g))
    return AF_RESPONSE_FIT_FAILED;
  *cost_out = at->cost;
  for (size_t j = 0; j < p; ++j)
    d2[j] = 0.0;
  while (*iterations < max_iter) {
    double gmax = 0.0;
    for (size_t j = 0; j < p; ++j) {
      double diag = at->a[j * p + j];
      d2[j] = fmax(d2[j], diag > 0.0 ? diag : (d2[j] > 0.0 ? d2[j] : 1.0));
      gmax = fmax(gmax, fabs(at->g[j]) * fmax(fabs(x[j]), 1.0));
    }
    if (gmax <= gtol * fmax(at->cost, 1.0))
      return AF_RESPONSE_FIT_CONVERGED;
    double before = at->cost;
    int step = lm_step(r, p, x, at, next, d2, &mu, &nu, dx, xtol);
    if (step == 2)
      return AF_RESPONSE_FIT_CONVERGED;
    if (step == 0)
      return AF_RESPONSE_FIT_STALLED;
    normal_eq *taken = next;
    next = at;
    at = taken;
    ++*iterations;
    *cost_out = at->cost;
    if (!at->ok)
      return AF_RESPONSE_FIT_FAILED; /* a derivative not finite there */
    if (step_small(x, dx, p, xtol) || before - at->cost <= ftol * before)
      return AF_RESPONSE_FIT_CONVERGED;
  }
  return AF_RESPONSE_FIT_CAPPED;
}
