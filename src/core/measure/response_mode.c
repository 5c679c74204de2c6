/* response_mode.c — one damped mode's spectrum through the window, in
 * closed form: the bare pole pair the complex fit models, the mode as the
 * window holds it (its cut after m samples and its fade-in: what the peak
 * list subtracts), and the mode's own peak power.
 *
 * A real damped cosine c z^n + conj(c z^n), z = exp((-sigma' + i w0) dt),
 * n >= 0, has the DFT (u = exp(-i w dt))
 *   X(u) = c / (1 - z u) + conj(c) / (1 - conj(z) u):
 * the peak and its negative-frequency image, exact under the exponential
 * window. */
#include "response_private.h"

#include <math.h>

/* The pole z = exp(-sigma' / fs + i 2 pi bin / N) of a mode. */
double complex af_response_pole(const af_response *r, double bin, double sigma_windowed)
{
  double n_fft = (double)r->cfg.fft_size;
  return cexp(-sigma_windowed / r->cfg.sample_rate_hz + I * 2.0 * AF_PI * bin / n_fft);
}

/* c / (1 - z u) + conj(c) / (1 - conj(z) u) at bin k, u from the phase
 * table: its entry (af_response_phase) is the cexp of the same angle,
 * -2 pi k / N, so the same double as a cexp a bin (two with the pole's,
 * which af_response_pole gives once a mode). */
double complex af_response_pole_pair(const af_response *r, double complex z, double complex c,
                                     size_t k)
{
  double complex u = r->phase_u[k];
  return c / (1.0 - z * u) + conj(c) / (1.0 - conj(z) * u);
}

/* |X(f0)|^2 of the mode alone through the window, fade-in included (the
 * fit puts the fade-in into the background): the ringing f_k c z^k sums at
 * its own frequency to c (1 / (1 - r) - sum_{k < L} (1 - f_k) r^k). */
double af_response_mode_peak_power(const af_response *r, double complex c, double sigma_windowed)
{
  double rr = exp(-sigma_windowed / r->cfg.sample_rate_hz);
  double sum = 1.0 / (1.0 - rr), rk = 1.0;
  for (size_t k = 0; k < r->fade_samples; ++k, rk *= rr)
    sum -= r->fade_rest[k] * rk; /* 1 - f_k, tabled at create */
  return creal(c * conj(c)) * sum * sum;
}

/* The part of sum_k a^k the fade-in removes, F(a) = sum_{k < L} (1 - f_k) a^k
 * with 1 - f_k = (1 + cos(theta (k + 1/2))) / 2, theta = pi / L, in closed
 * form (three geometric sums; (a e^{+-i theta})^L = -a^L). With al = a^L,
 * e = e^{i theta}, h = e^{i theta / 2}, inv_1a = 1 / (1 - a):
 *   F = (1 - al) / (2 (1 - a)) + (1 + al) / 4 (h / (1 - a e) + conj(h) / (1 - a conj(e))). */
double complex af_response_fade_part(size_t fade_samples, double complex e, double complex eh,
                                     double complex a, double complex al, double complex inv_1a)
{
  if (fade_samples == 0)
    return 0.0;
  return 0.5 * (1.0 - al) * inv_1a +
         0.25 * (1.0 + al) *
             (eh * complex_recip(1.0 - a * e) + conj(eh) * complex_recip(1.0 - a * conj(e)));
}

static double complex fade_sum(const af_response *r, double complex a, double complex al,
                               double complex inv_1a)
{
  return af_response_fade_part(r->fade_samples, r->fade_e, r->fade_eh, a, al, inv_1a);
}

af_mode_k af_response_mode_consts(const af_response *r, const af_peak *pk)
{
  double complex lz = -pk->sigma_windowed / r->cfg.sample_rate_hz +
                      I * 2.0 * AF_PI * pk->bin / (double)r->cfg.fft_size;
  af_mode_k q = {pk->c, cexp(lz), cexp(r->split_len * lz), cexp((double)r->fade_samples * lz)};
  return q;
}

/* One side of the mode (a = z u, A = z^m u^m, al = z^L u^L) as the window
 * holds it, T(a) - F(a), over one denominator. F's two fade-in poles pair up:
 * with e = exp(i theta), h = exp(i theta / 2),
 *   h / (1 - a e) + conj(h) / (1 - a conj(e)) = 2 cos(theta / 2) (1 - a) / Q,
 *   Q = (1 - a e)(1 - a conj(e)) = (1 - a)^2 + kappa a,  kappa = 4 sin^2(theta / 2)
 * (Q in that form: near the peak a ~ 1 and 1 - 2 cos(theta) a + a^2 would
 * cancel), so that
 *   T - F = ((1/2 - A + al / 2) Q - cos(theta / 2) / 2 (1 + al) (1 - a)^2)
 *           / ((1 - a) Q):
 * one reciprocal a side where the three sums took three. */
static double complex windowed_side(double complex a, double complex am, double complex al,
                                    double kappa, double half_cos)
{
  double complex d = 1.0 - a, d2 = d * d, q = d2 + kappa * a;
  double complex num = (0.5 - am + 0.5 * al) * q - half_cos * (1.0 + al) * d2;
  return num * complex_recip(d * q);
}

/* The mode q as the window holds it over the m analysed samples, at bin i
 * (r->phase_um filled there):
 *   c (T(z u) - F(z u)) + conj,  T(a) = (1 - a^m) / (1 - a),
 * F the fade-in's part (fade_sum; windowed_side when there is a fade-in). The
 * fits see the pole alone (the fade-in and the cut are smooth or small across
 * a peak, taken by the background), but far from the peak both matter: the
 * cut leaves a ripple of period fs / m (~ -36 dB at 40 ms), the fade-in a
 * broad term ~ -25 dB of the peak; a bare pole subtracted would leave them as
 * false peaks beside the mode and as a raised floor under the weaker modes
 * sought next. */
double complex af_response_mode_at(const af_response *r, const af_mode_k *q, size_t i)
{
  double complex u = r->phase_u[i], um = r->phase_um[i], ul = r->phase_ul[i];
  double complex a = q->z * u, ac = conj(q->z) * u;
  if (r->fade_samples == 0) {
    double complex t = (1.0 - q->zm * um) * complex_recip(1.0 - a);
    double complex tc = (1.0 - conj(q->zm) * um) * complex_recip(1.0 - ac);
    return q->c * t + conj(q->c) * tc;
  }
  double s = cimag(r->fade_eh), kappa = 4.0 * s * s, half_cos = 0.5 * creal(r->fade_eh);
  double complex t = windowed_side(a, q->zm * um, q->zl * ul, kappa, half_cos);
  double complex tc = windowed_side(ac, conj(q->zm) * um, conj(q->zl) * ul, kappa, half_cos);
  return q->c * t + conj(q->c) * tc;
}

/* ---- two bins at a time (af_cv2) ------------------------------------------------
 * windowed_side and af_response_mode_at on a pair of bins, each complex
 * operation written as GCC expands it in the scalar code (response_private.h
 * on af_v2d): the same doubles, about 2.5 times fewer instructions (the
 * subtraction was 14 % of the peak list's on the 600-strike line bag). */

/* windowed_side, operation for operation: 1 - a is (1 - re, -im), a real
 * times a complex scales each part, complex_recip divides conj(b) by |b|^2. */
static inline af_cv2 windowed_side2(af_cv2 a, af_cv2 am, af_cv2 al, double kappa, double half_cos)
{
  af_cv2 d = {1.0 - a.re, -a.im}, d2 = cv2_mul(d, d);
  af_cv2 q = {d2.re + kappa * a.re, d2.im + kappa * a.im};
  af_cv2 s = {(0.5 - am.re) + 0.5 * al.re, -am.im + 0.5 * al.im};
  af_cv2 h = {half_cos * (1.0 + al.re), half_cos * al.im};
  af_cv2 sq = cv2_mul(s, q), hd = cv2_mul(h, d2), den = cv2_mul(d, q);
  af_cv2 num = {sq.re - hd.re, sq.im - hd.im};
  af_v2d n2 = den.re * den.re + den.im * den.im;
  af_cv2 rec = {den.re / n2, -den.im / n2};
  return cv2_mul(num, rec);
}

/* A mode's constants in both lanes: c, z, z^m, z^L and their conjugates. */
typedef struct {
  af_cv2 c, z, zm, zl, cc, zc, zmc, zlc;
  double kappa, half_cos; /* windowed_side's, as af_response_mode_at computes them */
} mode_pair;

static mode_pair mode_pair_consts(const af_response *r, const af_mode_k *q)
{
  double s = cimag(r->fade_eh);
  mode_pair k = {cv2_splat(q->c),        cv2_splat(q->z),        cv2_splat(q->zm),
                 cv2_splat(q->zl),       cv2_splat(conj(q->c)),  cv2_splat(conj(q->z)),
                 cv2_splat(conj(q->zm)), cv2_splat(conj(q->zl)), 4.0 * s * s,
                 0.5 * creal(r->fade_eh)};
  return k;
}

/* The mode at bins i and i + 1 (af_response_mode_at with a fade-in). */
static inline af_cv2 mode_at2(const af_response *r, const mode_pair *k, size_t i)
{
  af_cv2 u = cv2_load(r->phase_u + i), um = cv2_load(r->phase_um + i);
  af_cv2 ul = cv2_load(r->phase_ul + i);
  af_cv2 t = windowed_side2(cv2_mul(k->z, u), cv2_mul(k->zm, um), cv2_mul(k->zl, ul), k->kappa,
                            k->half_cos);
  af_cv2 tc = windowed_side2(cv2_mul(k->zc, u), cv2_mul(k->zmc, um), cv2_mul(k->zlc, ul), k->kappa,
                             k->half_cos);
  af_cv2 ct = cv2_mul(k->c, t), cct = cv2_mul(k->cc, tc);
  af_cv2 x = {ct.re + cct.re, ct.im + cct.im};
  return x;
}

void af_response_mode_subtract(af_response *r, const af_mode_k *q, size_t lo, size_t hi)
{
  size_t i = lo;
  if (r->fade_samples > 0) {
    const mode_pair k = mode_pair_consts(r, q);
    for (; i + 1 <= hi; i += 2) {
      af_cv2 x = mode_at2(r, &k, i), sp = cv2_load(r->spec + i);
      af_v2d re = sp.re - x.re, im = sp.im - x.im, pw = re * re + im * im;
      r->spec[i] = complex_of(re[0], im[0]);
      r->spec[i + 1] = complex_of(re[1], im[1]);
      r->power[i] = pw[0];
      r->power[i + 1] = pw[1];
    }
  }
  for (; i <= hi; ++i) { /* an odd last bin; every bin without a fade-in */
    r->spec[i] -= af_response_mode_at(r, q, i);
    r->power[i] = creal(r->spec[i] * conj(r->spec[i]));
  }
}

/* The same, by the three geometric sums (fade_sum): what windowed_side
 * rearranges, for the tests. */
double complex af_response_mode_at_sums(const af_response *r, const af_mode_k *q, size_t i)
{
  double complex u = r->phase_u[i], um = r->phase_um[i], ul = r->phase_ul[i];
  double complex a = q->z * u, ac = conj(q->z) * u;
  double complex inv = complex_recip(1.0 - a), invc = complex_recip(1.0 - ac);
  double complex t = (1.0 - q->zm * um) * inv - fade_sum(r, a, q->zl * ul, inv);
  double complex tc = (1.0 - conj(q->zm) * um) * invc - fade_sum(r, ac, conj(q->zl) * ul, invc);
  return q->c * t + conj(q->c) * tc;
}
