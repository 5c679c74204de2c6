/* response_vp.c — the response fits' cost and normal equations by variable
 * projection (Golub-Pereyra, with Kaufman's Jacobian): the one residual pass
 * of every model (the bare pole pair of stage 2, the truncated one- or
 * two-pole model of the peak list).
 *
 * Why: each model is linear in all but two parameters per pole. Of a fit's
 * 10 or 14 parameters only f0 [bins] and sigma' [1/s] of each pole are
 * nonlinear; the poles' complex amplitudes and the complex quadratic
 * background (8 or 10 real numbers) enter linearly. The full
 * Levenberg-Marquardt fit moved all of them together and took ~12 model
 * passes a fit (the amplitudes lag the pole, so the steps converge slowly).
 * Here, at every point theta of the nonlinear parameters, the linear ones
 * are solved exactly (least squares, beta(theta)), and the solver
 * (response_lm.c, unchanged) sees only theta and the projected cost
 *   |Phi(theta) beta(theta) - y|^2,
 * the same minimum as the full fit's, reached in a few passes.
 *
 * Kaufman's Jacobian of the projected residual: column k is P v_k, with
 * v_k = (dPhi / dtheta_k) beta the model's derivative at the solved beta and
 * P the projection off Phi's columns. Hence, as Phi^T f = 0 at beta(theta),
 *   J^T f = v^T f,   J^T J = v^T v - W^T G^-1 W,
 * G = Phi^T Phi, W = Phi^T v: all formed in two passes over the bins, nothing
 * of size rows x columns kept beyond the poles' per-bin terms.
 *
 * Linear columns (complex, per bin): per pole (ARE, AIM) norm (t + tc) and
 * i norm (t - tc), t the pole's term and tc its conjugate's (c t + conj(c)
 * tc with c = norm (ARE + i AIM)); then the background x^q and i x^q,
 * q = 0..2, x the background's abscissa. Pole terms:
 *   pole pair (stage 2):  t = 1 / (1 - z u),          e = z u t^2
 *   truncated (list):     t = (1 - (z u)^m) / (1 - z u), e = (z u) dT/da
 * with e such that d(c t)/dz z = c e; then dModel/df0 = (c e - conj(c) ec)
 * i 2 pi / N and dModel/dsigma' = -(c e + conj(c) ec) / fs. */
#include "response_chol.h"
#include "response_private.h"

#include <math.h>
#include <string.h>

/* Linear parameters: two per pole and the background's six. */
#define VP_MAX_LINEAR (2 * 2 + 6)
/* Nonlinear parameters: two per pole. */
#define VP_MAX_THETA 4
/* Bins of a fit at most (the fits' rows / 2). */
#define VP_MAX_BINS (2 * AF_RESPONSE_FIT_MAX_HALF + 1)

/* What the first pass keeps of a bin for the second. */
typedef struct {
  double complex y;           /* data, scaled by the fit's gain */
  double complex col[4];      /* the poles' linear columns (2 a pole) */
  double complex e[2], ec[2]; /* the poles' derivative terms, pole and conjugate */
  double xb;                  /* the background's abscissa */
} vp_bin;

/* The constants of one pole at theta (per bin they need u and u^m). */
typedef struct {
  double complex z, zm, zm1; /* z, z^m, z^(m - 1) (the last two: truncated model) */
} vp_pole;

/* The poles' constants from theta (per pole f0 [bins], sigma' [1/s]). */
AF_NUMERIC_KERNEL static inline __attribute__((always_inline)) void
vp_poles(const af_response *r, const double *theta, size_t poles, vp_pole *pc)
{
  double n_fft = (double)r->cfg.fft_size, fs = r->cfg.sample_rate_hz, m = r->split_len;
  for (size_t j = 0; j < poles; ++j) {
    double complex lz = -theta[2 * j + 1] / fs + I * 2.0 * AF_PI * theta[2 * j] / n_fft;
    pc[j].z = cexp(lz);
    pc[j].zm = r->split_poles > 0 ? cexp(m * lz) : 0.0;
    pc[j].zm1 = r->split_poles > 0 ? pc[j].zm / pc[j].z : 0.0;
  }
}

/* A pole's term t at a = z u and its derivative term e (a dt/da); am, am1:
 * a^m, a^(m - 1) for the truncated model. */
AF_NUMERIC_KERNEL static inline __attribute__((always_inline)) double complex
vp_term(int truncated, double complex a, double complex am, double complex am1, double m,
        double complex *e)
{
  double complex inv = complex_recip(1.0 - a);
  if (!truncated) {
    *e = a * inv * inv;
    return inv;
  }
  double complex t = (1.0 - am) * inv;
  *e = a * (t - m * am1) * inv;
  return t;
}

/* Bin k's columns and terms into *b. */
AF_NUMERIC_KERNEL static inline __attribute__((always_inline)) void
vp_fill_bin(const af_response *r, const vp_pole *pc, size_t poles, size_t k, vp_bin *b)
{
  const af_fit_ctx *f = &r->ctx;
  int truncated = r->split_poles > 0;
  double m = r->split_len;
  double complex u = r->phase_u[k], um = 0.0, um1 = 0.0;
  if (truncated) {
    um = r->phase_um[k];
    um1 = um * conj(u);
  }
  b->y = f->gain * f->data[k];
  b->xb = ((double)k - f->center) / f->half;
  for (size_t j = 0; j < poles; ++j) {
    double complex zc = conj(pc[j].z);
    double complex t = vp_term(truncated, pc[j].z * u, pc[j].zm * um, pc[j].zm1 * um1, m, &b->e[j]);
    double complex tc =
        vp_term(truncated, zc * u, conj(pc[j].zm) * um, conj(pc[j].zm1) * um1, m, &b->ec[j]);
    b->col[2 * j] = f->norm * (t + tc);
    b->col[2 * j + 1] = f->norm * I * (t - tc);
  }
}

/* vp_term on two bins (af_cv2), operation for operation: 1 - a is
 * (1 - re, -im), complex_recip divides conj(b) by |b|^2, a real times a
 * complex scales each part. */
AF_NUMERIC_KERNEL static inline __attribute__((always_inline)) af_cv2
vp_term2(int truncated, af_cv2 a, af_cv2 am, af_cv2 am1, double m, af_cv2 *e)
{
  af_cv2 d = {1.0 - a.re, -a.im};
  af_v2d n2 = d.re * d.re + d.im * d.im;
  af_cv2 inv = {d.re / n2, -d.im / n2};
  if (!truncated) {
    *e = cv2_mul(cv2_mul(a, inv), inv);
    return inv;
  }
  af_cv2 t = cv2_mul((af_cv2){1.0 - am.re, -am.im}, inv);
  *e = cv2_mul(cv2_mul(a, (af_cv2){t.re - m * am1.re, t.im - m * am1.im}), inv);
  return t;
}

/* Part i of lane pair x as a complex. */
static inline double complex cv2_at(af_cv2 x, size_t i)
{
  return complex_of(x.re[i], x.im[i]);
}

/* vp_fill_bin for bins k and k + 1 into b[0], b[1]: its operations two bins
 * a register (af_cv2; response_private.h: the same doubles; a NaN's sign
 * may differ, and a NaN ends the evaluation either way), 15 k fewer
 * instructions a strike on the 600-strike line bag. norm i (t - tc) is
 * (-(norm Im), norm Re) of t - tc, as the scalar product by the constant i
 * expands. */
AF_NUMERIC_KERNEL static inline __attribute__((always_inline)) void
vp_fill_pair(const af_response *r, const vp_pole *pc, size_t poles, size_t k, vp_bin *b)
{
  const af_fit_ctx *f = &r->ctx;
  int truncated = r->split_poles > 0;
  double m = r->split_len, norm = f->norm;
  af_cv2 u = cv2_load(r->phase_u + k), um = {{0.0, 0.0}, {0.0, 0.0}}, um1 = um;
  if (truncated) {
    um = cv2_load(r->phase_um + k);
    um1 = cv2_mul(um, (af_cv2){u.re, -u.im});
  }
  for (size_t i = 0; i < 2; ++i) {
    b[i].y = f->gain * f->data[k + i];
    b[i].xb = ((double)(k + i) - f->center) / f->half;
  }
  for (size_t j = 0; j < poles; ++j) {
    af_cv2 z = cv2_splat(pc[j].z), zm = cv2_splat(pc[j].zm), zm1 = cv2_splat(pc[j].zm1);
    af_cv2 zc = cv2_splat(conj(pc[j].z)), zmc = cv2_splat(conj(pc[j].zm));
    af_cv2 zm1c = cv2_splat(conj(pc[j].zm1)), e, ec;
    af_cv2 t = vp_term2(truncated, cv2_mul(z, u), cv2_mul(zm, um), cv2_mul(zm1, um1), m, &e);
    af_cv2 tc = vp_term2(truncated, cv2_mul(zc, u), cv2_mul(zmc, um), cv2_mul(zm1c, um1), m, &ec);
    af_cv2 sum = {norm * (t.re + tc.re), norm * (t.im + tc.im)};
    af_cv2 dif = {-(norm * (t.im - tc.im)), norm * (t.re - tc.re)};
    for (size_t i = 0; i < 2; ++i) {
      b[i].e[j] = cv2_at(e, i);
      b[i].ec[j] = cv2_at(ec, i);
      b[i].col[2 * j] = cv2_at(sum, i);
      b[i].col[2 * j + 1] = cv2_at(dif, i);
    }
  }
}

/* p[0], p[1] += v[0], v[1]: a real and imaginary pair of sums in one
 * register (af_v2d: each sum's own addition). */
static inline __attribute__((always_inline)) void v2d_add_to(double *p, af_v2d v)
{
  af_v2d s;
  memcpy(&s, p, sizeof s);
  s += v;
  memcpy(p, &s, sizeof s);
}

/* Adds bin b to g = Phi^T Phi (upper triangle, nl x nl) and h = Phi^T y;
 * npc pole columns, then the background's six. */
AF_NUMERIC_KERNEL static inline __attribute__((always_inline)) void
vp_gram_add(const vp_bin *b, size_t npc, size_t nl, double *g, double *h)
{
  const double xp[3] = {1.0, b->xb, b->xb * b->xb};
#pragma GCC unroll 4
  for (size_t l = 0; l < npc; ++l) {
    double cr = creal(b->col[l]), ci = cimag(b->col[l]);
    double *row = g + l * nl;
#pragma GCC unroll 4
    for (size_t j = l; j < npc; ++j)
      row[j] += cr * creal(b->col[j]) + ci * cimag(b->col[j]);
    const af_v2d c = {cr, ci};
#pragma GCC unroll 3
    for (size_t q = 0; q < 3; ++q) /* the background's x^q and i x^q: (cr, ci) x^q */
      v2d_add_to(row + npc + 2 * q, c * xp[q]);
    h[l] += cr * creal(b->y) + ci * cimag(b->y);
  }
  const af_v2d y = {creal(b->y), cimag(b->y)};
#pragma GCC unroll 3
  for (size_t q = 0; q < 3; ++q)
    v2d_add_to(h + npc + 2 * q, xp[q] * y);
}

/* The background block of g: sum x^(q + t) on both real and imaginary. */
static inline __attribute__((always_inline)) void
vp_gram_background(double *g, size_t npc, size_t nl, const double *moment)
{
  for (size_t q = 0; q < 3; ++q)
    for (size_t t = q; t < 3; ++t) {
      g[(npc + 2 * q) * nl + npc + 2 * t] = moment[q + t];
      g[(npc + 2 * q + 1) * nl + npc + 2 * t + 1] = moment[q + t];
      g[(npc + 2 * q) * nl + npc + 2 * t + 1] = 0.0;
      g[(npc + 2 * q + 1) * nl + npc + 2 * t] = 0.0;
    }
}

/* The model's derivatives at bin b wrt each pole's f0 and sigma' at the
 * linear solution beta, into v[2 poles]. */
AF_NUMERIC_KERNEL static inline __attribute__((always_inline)) void
vp_derivs(const af_response *r, const vp_bin *b, const double *beta, size_t poles,
          double complex *v)
{
  double n_fft = (double)r->cfg.fft_size, fs = r->cfg.sample_rate_hz;
  for (size_t j = 0; j < poles; ++j) {
    double complex c = r->ctx.norm * (beta[2 * j] + I * beta[2 * j + 1]);
    double complex ga = c * b->e[j], gac = conj(c) * b->ec[j];
    v[2 * j] = (ga - gac) * (I * 2.0 * AF_PI / n_fft);
    v[2 * j + 1] = -(ga + gac) / fs;
  }
}

/* The second pass: the residual at beta, the cost, and (when a is not NULL)
 * g_theta = v^T f, a = v^T v and w = Phi^T v (nl x nt, stored by column:
 * w[k nl + i] is row i of column k). */
AF_NUMERIC_KERNEL static inline __attribute__((always_inline)) double
vp_second_pass(const af_response *r, const vp_bin *bins, size_t count, size_t poles,
               const double *beta, double *a, double *g, double *w)
{
  size_t npc = 2 * poles, nt = npc, nl = npc + 6; /* nt: one per pole column */
  double sum = 0.0;
  for (size_t i = 0; i < count; ++i) {
    const vp_bin *b = &bins[i];
    const double xp[3] = {1.0, b->xb, b->xb * b->xb};
    double complex model = 0.0, v[VP_MAX_THETA];
#pragma GCC unroll 4
    for (size_t l = 0; l < npc; ++l)
      model += beta[l] * b->col[l];
    af_v2d mv = {creal(model), cimag(model)};
#pragma GCC unroll 3
    for (size_t q = 0; q < 3; ++q) /* x^q (beta_re + i beta_im), part by part */
      mv += xp[q] * (af_v2d){beta[npc + 2 * q], beta[npc + 2 * q + 1]};
    model = complex_of(mv[0], mv[1]);
    double complex res = model - b->y;
    double fr = creal(res), fi = cimag(res);
    sum += fr * fr + fi * fi;
    if (a == NULL)
      continue;
    vp_derivs(r, b, beta, poles, v);
#pragma GCC unroll 4
    for (size_t k = 0; k < nt; ++k) {
      double vr = creal(v[k]), vi = cimag(v[k]);
      g[k] += vr * fr + vi * fi;
#pragma GCC unroll 4
      for (size_t j = k; j < nt; ++j)
        a[k * nt + j] += vr * creal(v[j]) + vi * cimag(v[j]);
      double *wk = w + k * nl; /* column k of w, its rows side by side */
#pragma GCC unroll 4
      for (size_t l = 0; l < npc; ++l)
        wk[l] += creal(b->col[l]) * vr + cimag(b->col[l]) * vi;
      const af_v2d vk = {vr, vi};
#pragma GCC unroll 3
      for (size_t q = 0; q < 3; ++q)
        v2d_add_to(wk + npc + 2 * q, xp[q] * vk);
    }
  }
  return sum;
}

/* a -= w^T G^-1 w (Kaufman's projection; l: G's Cholesky factor), then the
 * lower triangle from the upper. */
AF_NUMERIC_KERNEL static inline __attribute__((always_inline)) void
vp_project(const double *l, size_t nl, size_t nt, const double *w, double *a)
{
  for (size_t k = 0; k < nt; ++k) {
    double z[VP_MAX_LINEAR];
    for (size_t i = 0; i < nl; ++i)
      z[i] = w[k * nl + i];
    af_response_chol_solve(l, nl, z);
    for (size_t j = k; j < nt; ++j) {
      double s = 0.0;
      for (size_t i = 0; i < nl; ++i)
        s += w[j * nl + i] * z[i];
      a[k * nt + j] -= s;
    }
  }
  for (size_t j = 0; j < nt; ++j)
    for (size_t k = 0; k < j; ++k)
      a[j * nt + k] = a[k * nt + j];
}

/* af_response_fit_eval for 'poles' poles: inlined into it once per count
 * (1, 2), so that every loop over the columns has constant bounds (8 % of
 * the pass's instructions on the 600-strike line bag). */
AF_NUMERIC_KERNEL static inline __attribute__((always_inline)) int
vp_eval(const af_response *r, const double *theta, double *cost, double *a, double *g, double *beta,
        size_t poles)
{
  vp_bin bins[VP_MAX_BINS];
  vp_pole pc[2];
  size_t count = r->ctx.count;
  size_t npc = 2 * poles, nl = npc + 6, nt = npc;
  double gram[VP_MAX_LINEAR * VP_MAX_LINEAR] = {0.0}, moment[5] = {0.0};
  double w[VP_MAX_LINEAR * VP_MAX_THETA] = {0.0};
  *cost = INFINITY;
  if (count > VP_MAX_BINS || poles > 2)
    return 0;
  vp_poles(r, theta, poles, pc);
  memset(beta, 0, nl * sizeof *beta);
  for (size_t i = 0; i < count; ++i) {
    if (i % 2 == 0 && i + 1 < count) /* two bins' terms at once; an odd last alone */
      vp_fill_pair(r, pc, poles, r->ctx.first + i, &bins[i]);
    else if (i % 2 == 0)
      vp_fill_bin(r, pc, poles, r->ctx.first + i, &bins[i]);
    vp_gram_add(&bins[i], npc, nl, gram, beta);
    double xq = 1.0;
#pragma GCC unroll 5
    for (size_t q = 0; q < 5; ++q, xq *= bins[i].xb)
      moment[q] += xq;
  }
  vp_gram_background(gram, npc, nl, moment);
  if (!af_response_chol_factor(gram, nl))
    return 0;
  af_response_chol_solve(gram, nl, beta);
  if (a != NULL) {
    memset(a, 0, nt * nt * sizeof *a);
    memset(g, 0, nt * sizeof *g);
  }
  double sum = vp_second_pass(r, bins, count, poles, beta, a, g, w);
  *cost = sum;
  if (!isfinite(sum))
    return 0; /* a value not finite makes the sum so */
  if (a == NULL)
    return 1;
  for (size_t k = 0; k < nt; ++k)
    if (!isfinite(a[k * nt + k]) || !isfinite(g[k]))
      return 0;
  vp_project(gram, nl, nt, w, a);
  return 1;
}

AF_NUMERIC_KERNEL int af_response_fit_eval(const af_response *r, const double *theta, double *cost,
                                           double *a, double *g, double *beta)
{
  if (r->split_poles == 2)
    return vp_eval(r, theta, cost, a, g, beta, 2);
  return vp_eval(r, theta, cost, a, g, beta, 1);
}
