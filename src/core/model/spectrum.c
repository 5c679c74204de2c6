/* spectrum.c — excitation spectrum of a force pulse, split into lobes.
 *
 * Work is done in the normalised angular frequency theta = 2 pi f dt [rad per
 * sample]; the FFT grid is theta_j = j h, h = 2 pi / fft_size. The sums are
 * kept unscaled: A(theta) = sum_k x_k exp(-i m_k theta), m_k = k - c, with
 * c = (n - 1)/2 the centre of the pulse (the shift changes only the phase,
 * never |A|, and keeps the derivative sums small), so |X(f)| = dt |A| [N s]
 * and g = |A|^2 is the function every search works on.
 *
 * Refinement. The grid (zero-padded FFT) gives a bracket for each feature;
 * the feature is then refined by direct O(n) evaluations at single
 * frequencies (a phasor recurrence, no sin/cos per sample; the pulse is
 * folded about its centre so each evaluation runs over n/2 pairs) of A and
 * of the moment sums B = sum m x e, C = sum m^2 x e, D = sum m^3 x e, which
 * give the derivatives of g exactly. A safeguarded Halley iteration (the
 * bracket shrinks on the sign of the target function; a step that leaves it,
 * or points the wrong way, is replaced by bisection) then solves
 *  - g'(theta) = 0 for minima and peaks,
 *  - g(theta) = ratio^2 g_peak for band edges.
 * Halley converges cubically from the grid's starting point (parabolic vertex
 * or linear interpolation of |X|), so a feature costs one or two evaluations
 * and lands within ~1e-9 of the lobe width whatever the bin width.
 *
 * Minima. A minimum is a grid point strictly lower than both neighbours. A
 * continuous |X| then certainly has a local minimum between those neighbours,
 * so nothing is invented; it is refined inside that two-bin bracket. Exact
 * ties (plateaus) are not minima. A minimum whose neighbouring maximum is
 * closer than about a bin can be missed: with damping the nulls fill in
 * (PHYSICS.md 4) and a minimum may shrink to a ripple of a fraction of a dB
 * before it vanishes; no threshold hides the shallow ones, but the grid must
 * be fine enough to hold a point inside the ripple. When a minimum vanishes
 * the lobes above it are renumbered — callers must read lobe frequencies, not
 * only lobe numbers.
 *
 * Lobe 1 runs from DC; its peak and band follow the same rule as the others,
 * which for a one-signed pulse gives peak_hz = 0 and band_low_hz = 0 (|X| is
 * largest at DC); a bipolar pulse gets its true main-lobe peak and low edge.
 *
 * State. execute writes; the getters only read (they may run concurrently
 * with each other, not with execute). A failed execute leaves the object as
 * if never executed: no stale lobes.
 */
#include "spectrum.h"

#include <fftw3.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "fft_plan.h"

/* Strict C11 <math.h> defines neither. */
#define AF_PI 3.14159265358979323846
#define AF_SQRT1_2 0.70710678118654752440

/* A Halley step below this fraction of pi/n (the scale of the spectral
 * features: a lobe is ~2 pi/n wide) is accepted without another evaluation:
 * cubic convergence leaves an error of order (step)^3, ~1e-9 pi/n. */
#define AF_ACCEPT_STEP 1e-3
/* Bisection from a two-bin bracket reaches AF_ACCEPT_STEP in < 30 halvings
 * even on the coarsest allowed grid; this only caps a pathological search. */
#define AF_REFINE_MAX_ITER 60
/* Entries per pair of samples in the folded moments (see fold_pulse). */
#define AF_FOLD 8

struct af_spectrum {
  af_spectrum_config cfg;
  double *in;        /* FFT input: the pulse, then zeros [fft_size] */
  fftw_complex *out; /* r2c output, unscaled [fft_size/2 + 1] */
  double *mag2;      /* g on the grid, |out_j|^2, valid below grid_top [fft_size/2 + 1] */
  double *fold;      /* folded moments [AF_FOLD per pair, max_samples/2 + 1 pairs] */
  size_t n_pairs;    /* pairs (+-m) of the last pulse */
  double *min_theta; /* refined minima ending lobes 1.. [rad/sample, max_lobes] */
  double *min_g;     /* g at those minima [max_lobes] */
  size_t *min_bin;   /* grid bin of each minimum [max_lobes] */
  af_fft_r2c plan;   /* shared by the process (fft_plan.h) */
  size_t n;          /* samples of the last pulse; 0 = no valid result */
  size_t n_dirty;    /* leading entries of in that may be nonzero */
  size_t grid_top;   /* bins of mag2 computed so far */
  double dt_s;       /* sampling step of the last pulse [s] */
  size_t lobe_count; /* complete lobes located */
  double max_g;      /* global maximum of g */
};

/* ---- levels ------------------------------------------------------------ */

const char *af_band_level_name(af_band_level level)
{
  switch (level) {
  case AF_BAND_POWER_HALF: return "power-half";
  case AF_BAND_AMPLITUDE_HALF: return "amplitude-half";
  }
  return "unknown";
}

af_status af_band_level_parse(const char *name, af_band_level *level)
{
  if (name == NULL || level == NULL)
    return AF_EINVAL;
  if (strcmp(name, "power-half") == 0)
    *level = AF_BAND_POWER_HALF;
  else if (strcmp(name, "amplitude-half") == 0)
    *level = AF_BAND_AMPLITUDE_HALF;
  else
    return AF_EINVAL;
  return AF_OK;
}

double af_band_level_ratio(af_band_level level)
{
  switch (level) {
  case AF_BAND_POWER_HALF: return AF_SQRT1_2; /* |X|^2 halves: -3 dB */
  case AF_BAND_AMPLITUDE_HALF: return 0.5;    /* |X| halves: -6 dB */
  }
  return NAN;
}

/* ---- life cycle -------------------------------------------------------- */

af_spectrum_config af_spectrum_config_default(void)
{
  af_spectrum_config cfg;
  cfg.max_samples = 1024;
  /* 4x padding at the longest pulse, 30x at the model's ~130 samples: the
   * refinement makes the bin width irrelevant to accuracy, the grid only has
   * to hold a point inside every minimum; 8192 would double the FFT time. */
  cfg.fft_size = 4096;
  cfg.max_lobes = 8;
  return cfg;
}

static int is_power_of_two(size_t v)
{
  return v != 0 && (v & (v - 1)) == 0;
}

static af_status check_config(const af_spectrum_config *cfg)
{
  if (cfg == NULL || cfg->max_samples < 2 || cfg->max_lobes < 1)
    return AF_EINVAL;
  if (!is_power_of_two(cfg->fft_size) || cfg->fft_size / 2 < cfg->max_samples)
    return AF_EINVAL;
  if (cfg->fft_size > (size_t)1 << 30) /* FFTW takes the length as an int */
    return AF_EINVAL;
  return AF_OK;
}

/* Every buffer, or AF_ENOMEM; the caller frees a partial set. */
static af_status allocate(af_spectrum *s)
{
  size_t bins = s->cfg.fft_size / 2 + 1, lobes = s->cfg.max_lobes;
  s->in = fftw_alloc_real(s->cfg.fft_size);
  s->out = fftw_alloc_complex(bins);
  s->mag2 = malloc(bins * sizeof *s->mag2);
  s->fold = malloc(AF_FOLD * (s->cfg.max_samples / 2 + 1) * sizeof *s->fold);
  s->min_theta = malloc(lobes * sizeof *s->min_theta);
  s->min_g = malloc(lobes * sizeof *s->min_g);
  s->min_bin = malloc(lobes * sizeof *s->min_bin);
  int ok = s->in && s->out && s->mag2 && s->fold && s->min_theta && s->min_g && s->min_bin;
  return ok ? AF_OK : AF_ENOMEM;
}

af_status af_spectrum_create(const af_spectrum_config *cfg, af_spectrum **out)
{
  af_status_init();
  if (out == NULL)
    return AF_EINVAL;
  *out = NULL;
  af_status st = check_config(cfg);
  if (st != AF_OK)
    return st;
  af_spectrum *s = calloc(1, sizeof *s);
  if (s == NULL)
    return AF_ENOMEM;
  s->cfg = *cfg;
  st = allocate(s);
  if (st == AF_OK) /* one plan per size for the whole process (fft_plan.h) */
    st = af_fft_r2c_acquire(cfg->fft_size, &s->plan);
  if (st != AF_OK) {
    af_spectrum_destroy(s);
    return st;
  }
  memset(s->in, 0, cfg->fft_size * sizeof *s->in);
  *out = s;
  return AF_OK;
}

void af_spectrum_destroy(af_spectrum *s)
{
  if (s == NULL)
    return;
  af_fft_r2c_release(&s->plan);
  fftw_free(s->in);
  fftw_free(s->out);
  free(s->mag2);
  free(s->fold);
  free(s->min_theta);
  free(s->min_g);
  free(s->min_bin);
  free(s);
}

/* ---- direct evaluation ------------------------------------------------- */

/* Grid spacing h [rad/sample]. */
static double bin_theta(const af_spectrum *s)
{
  return 2.0 * AF_PI / (double)s->cfg.fft_size;
}

/* Folded moments. With m the offset from the centre, samples pair up at +m
 * and -m (m = 0 or 1/2 upwards); e = x(+m) + x(-m), o = x(+m) - x(-m) (the
 * centre sample of an odd pulse: e = x, o = 0). Writing p = exp(-i m theta)
 * = cos - i sin, the sums become real dot products over the pairs only:
 *   Re A = sum e p_re,     Im A = sum o p_im,
 *   Re B = sum m o p_re,   Im B = sum m e p_im,
 *   Re C = sum m^2 e p_re, Im C = sum m^2 o p_im,
 *   Re D = sum m^3 o p_re, Im D = sum m^3 e p_im,
 * i.e. entry 2r of a pair multiplies p_re and entry 2r+1 multiplies p_im:
 * half the work of the plain sums. */
static void fold_pulse(af_spectrum *s, size_t n)
{
  const double *x = s->in;
  size_t half = n / 2;
  double m0 = n % 2 ? 0.0 : 0.5; /* offset of the first pair */
  s->n_pairs = (n + 1) / 2;
  for (size_t j = 0; j < s->n_pairs; j++) {
    size_t up = half + j, down = n - 1 - up; /* x(c + m), x(c - m) */
    double m = m0 + (double)j, m2 = m * m, m3 = m2 * m;
    double e = up == down ? x[up] : x[up] + x[down];
    double o = up == down ? 0.0 : x[up] - x[down];
    double *f = s->fold + AF_FOLD * j;
    f[0] = e;
    f[1] = o;
    f[2] = m * o;
    f[3] = m * e;
    f[4] = m2 * e;
    f[5] = m2 * o;
    f[6] = m3 * o;
    f[7] = m3 * e;
  }
}

typedef struct {
  double re, im;
} af_cpx;

static af_cpx cpx_mul(af_cpx a, af_cpx b)
{
  af_cpx r = {a.re * b.re - a.im * b.im, a.re * b.im + a.im * b.re};
  return r;
}

/* The phasor of the first pair, exp(-i m0 theta). The recurrence p *= z
 * drifts by ~n eps over the pulse (n <= max_samples): negligible. */
static af_cpx phasor_first(const af_spectrum *s, double theta)
{
  double m0 = s->n % 2 ? 0.0 : 0.5;
  af_cpx p = {cos(m0 * theta), -sin(m0 * theta)};
  return p;
}

/* g = |A|^2 at theta. */
static double eval_g(const af_spectrum *s, double theta)
{
  af_cpx z = {cos(theta), -sin(theta)};
  af_cpx p = phasor_first(s, theta);
  double ar = 0.0, ai = 0.0;
  const double *f = s->fold;
  for (size_t j = 0; j < s->n_pairs; j++, f += AF_FOLD) {
    ar += f[0] * p.re;
    ai += f[1] * p.im;
    p = cpx_mul(p, z);
  }
  return ar * ar + ai * ai;
}

/* g and its first three theta-derivatives. */
typedef struct {
  double g, d1, d2, d3;
} af_gval;

/* From the eight sums (Re A, Im A, Re B, Im B, ...), with dA = -i B,
 * dB = -i C, dC = -i D: g' = 2 Im(A* B), g'' = 2 (|B|^2 - Re(A* C)),
 * g''' = 2 (3 Im(B* C) - Im(A* D)). */
static af_gval gval_from_sums(const double u[AF_FOLD])
{
  double ar = u[0], ai = u[1], br = u[2], bi = u[3];
  double cr = u[4], ci = u[5], dr = u[6], di = u[7];
  af_gval v;
  v.g = ar * ar + ai * ai;
  v.d1 = 2.0 * (ar * bi - ai * br);
  v.d2 = 2.0 * (br * br + bi * bi - (ar * cr + ai * ci));
  v.d3 = 2.0 * (3.0 * (br * ci - bi * cr) - (ar * di - ai * dr));
  return v;
}

/* g, g', g'', g''' at theta. Two phasors (even and odd pairs) step by
 * exp(-2 i theta) so that the recurrence's dependency chain is not the
 * limit; the eight sums are plain locals so that they stay in registers (an
 * array here costs a third more time at -O2). */
static af_gval eval_gval(const af_spectrum *s, double theta)
{
  af_cpx z = {cos(theta), -sin(theta)}, z2 = cpx_mul(z, z);
  af_cpx p = phasor_first(s, theta), q = cpx_mul(p, z);
  double u0 = 0, u1 = 0, u2 = 0, u3 = 0, u4 = 0, u5 = 0, u6 = 0, u7 = 0;
  const double *f = s->fold, *f1 = s->fold + AF_FOLD; /* even, odd pair */
  size_t j = 0;
  for (; j + 1 < s->n_pairs; j += 2, f += 2 * AF_FOLD, f1 += 2 * AF_FOLD) {
    u0 += f[0] * p.re + f1[0] * q.re;
    u1 += f[1] * p.im + f1[1] * q.im;
    u2 += f[2] * p.re + f1[2] * q.re;
    u3 += f[3] * p.im + f1[3] * q.im;
    u4 += f[4] * p.re + f1[4] * q.re;
    u5 += f[5] * p.im + f1[5] * q.im;
    u6 += f[6] * p.re + f1[6] * q.re;
    u7 += f[7] * p.im + f1[7] * q.im;
    p = cpx_mul(p, z2);
    q = cpx_mul(q, z2);
  }
  if (j < s->n_pairs) { /* odd count: the last pair on its own */
    u0 += f[0] * p.re;
    u1 += f[1] * p.im;
    u2 += f[2] * p.re;
    u3 += f[3] * p.im;
    u4 += f[4] * p.re;
    u5 += f[5] * p.im;
    u6 += f[6] * p.re;
    u7 += f[7] * p.im;
  }
  const double u[AF_FOLD] = {u0, u1, u2, u3, u4, u5, u6, u7};
  return gval_from_sums(u);
}

/* ---- refinement -------------------------------------------------------- */

/* What a search solves: g' = 0 (extremum) or g = level (band edge). */
typedef struct {
  int extremum;
  double level;  /* g at the band edge (edge searches only) */
  double sign_a; /* sign of the target function at the bracket's low end */
} af_target;

/* Target function and its first two derivatives at one evaluation. */
static void target_values(const af_target *t, const af_gval *v, double f[3])
{
  f[0] = t->extremum ? v->d1 : v->g - t->level;
  f[1] = t->extremum ? v->d2 : v->d1;
  f[2] = t->extremum ? v->d3 : v->d2;
}

/* Halley step, or NaN when the slope does not point across the bracket
 * (from sign_a at a to -sign_a at b), e.g. near a stationary point. */
static double halley_step(const double f[3], double sign_a)
{
  if (!(f[1] * sign_a < 0.0))
    return NAN;
  double newton = -f[0] / f[1];
  double shrink = 1.0 + 0.5 * newton * f[2] / f[1]; /* x - 2 f f' / (2 f'^2 - f f'') */
  return shrink > 0.5 ? newton / shrink : newton;
}

/* g at x + dx from the cubic Taylor polynomial of an evaluation at x. */
static double taylor_g(const af_gval *v, double dx)
{
  return v->g + dx * (v->d1 + dx * (0.5 * v->d2 + dx * v->d3 / 6.0));
}

/* Root of the target in [a, b] from x (a < x < b); *g_root gets g there. */
static double refine(const af_spectrum *s, const af_target *t, double a, double b, double x,
                     double *g_root)
{
  double accept = AF_ACCEPT_STEP * AF_PI / (double)s->n;
  af_gval v = {0.0, 0.0, 0.0, 0.0};
  double x_eval = x;
  for (int it = 0; it < AF_REFINE_MAX_ITER; it++) {
    double f[3];
    v = eval_gval(s, x);
    x_eval = x;
    target_values(t, &v, f);
    if (f[0] == 0.0)
      break;
    if ((f[0] > 0.0) == (t->sign_a > 0.0))
      a = x;
    else
      b = x;
    double dx = halley_step(f, t->sign_a);
    if (!(x + dx > a && x + dx < b))
      dx = 0.5 * (a + b) - x;
    x += dx;
    if (fabs(dx) < accept)
      break;
  }
  *g_root = taylor_g(&v, x - x_eval);
  return x;
}

/* Vertex of the parabola through g at bins j-1, j, j+1 [bins from j],
 * kept inside the bracket. */
static double parabola_offset(const double *g, size_t j)
{
  double lo = g[j - 1], mid = g[j], hi = g[j + 1];
  double den = lo - 2.0 * mid + hi;
  double off = den != 0.0 ? 0.5 * (lo - hi) / den : 0.0;
  return fmax(-0.9, fmin(0.9, off));
}

/* Extremum around interior grid bin j (0 < j < grid_top - 1): sign_a -1
 * for a minimum (g' < 0 below it), +1 for a maximum. */
static double refine_bin(const af_spectrum *s, size_t j, double sign_a, double *g_at)
{
  double h = bin_theta(s);
  af_target t = {1, 0.0, sign_a};
  double x0 = ((double)j + parabola_offset(s->mag2, j)) * h;
  return refine(s, &t, (double)(j - 1) * h, (double)(j + 1) * h, x0, g_at);
}

/* ---- execute ----------------------------------------------------------- */

/* Validates and copies the pulse, zeroes what a previous pulse left in the
 * FFT input. Nothing is written unless every sample is finite, so the
 * zero padding stays clean after a refused pulse. *one_signed: no two
 * samples of opposite sign. */
static af_status load_pulse(af_spectrum *s, const double *x, size_t n, int *one_signed)
{
  int pos = 0, neg = 0;
  for (size_t k = 0; k < n; k++) {
    if (!isfinite(x[k]))
      return AF_ENUMERIC;
    pos |= x[k] > 0.0;
    neg |= x[k] < 0.0;
  }
  memcpy(s->in, x, n * sizeof *s->in);
  if (s->n_dirty > n)
    memset(s->in + n, 0, (s->n_dirty - n) * sizeof *s->in);
  s->n_dirty = n;
  *one_signed = !(pos && neg);
  return AF_OK;
}

/* g on the grid up to bin top (inclusive), computed once per execute. */
static void grid_fill(af_spectrum *s, size_t top)
{
  const double *o = (const double *)s->out;
  for (size_t j = s->grid_top; j <= top; j++)
    s->mag2[j] = o[2 * j] * o[2 * j] + o[2 * j + 1] * o[2 * j + 1];
  if (top + 1 > s->grid_top)
    s->grid_top = top + 1;
}

/* Bins of the grid computed at a time ahead of the minima's search: a call
 * per bin cost more than the bin (~700 calls per pulse); at most this many
 * bins past the last lobe are computed for nothing. */
#define AF_SPECTRUM_GRID_BLOCK 32

/* Local minima from DC upwards, each ending a lobe, up to max_lobes; a
 * minimum needs its upper neighbour, so only bins below Nyquist count. The
 * grid is only computed as far as the search goes (and a block ahead). */
static void locate_minima(af_spectrum *s)
{
  size_t last = s->cfg.fft_size / 2, j = 1;
  const double *g = s->mag2;
  s->lobe_count = 0;
  grid_fill(s, 1);
  while (j < last && s->lobe_count < s->cfg.max_lobes) {
    if (j + 1 >= s->grid_top)
      grid_fill(s, j + AF_SPECTRUM_GRID_BLOCK < last ? j + AF_SPECTRUM_GRID_BLOCK : last);
    /* the bins below stop have their upper neighbour computed: a tight loop
     * over them to the next minimum */
    size_t stop = s->grid_top - 1 < last ? s->grid_top - 1 : last;
    while (j < stop && !(g[j] < g[j - 1] && g[j] < g[j + 1]))
      j++;
    if (j == stop)
      continue;
    size_t i = s->lobe_count++;
    s->min_bin[i] = j;
    s->min_theta[i] = refine_bin(s, j, -1.0, &s->min_g[i]);
    j++;
  }
}

/* Bounds of the pulse's transform away from DC: with d1, d2 its first
 * and second differences (x = 0 outside [0, n)), D1 (theta) = (1 - e^-i
 * theta) A and D2 = (1 - e^-i theta)^2 A, and |1 - e^-i theta| =
 * 2 sin(theta / 2), so |A(theta)| <= min(sum |x|, sum |d1| / (2 sin(theta / 2)),
 * sum |d2| / (4 sin^2(theta / 2))): a smooth pulse's transform falls off
 * as theta^-2 whatever its sign changes. */
typedef struct {
  double s0, s1, s2; /* sum |x|, sum |d1|, sum |d2| [N] */
} af_spectrum_bounds;

static af_spectrum_bounds pulse_bounds(const double *x, size_t n)
{
  af_spectrum_bounds b = {0.0, 0.0, 0.0};
  double x1 = 0.0, x2 = 0.0; /* x[k - 1], x[k - 2] */
  for (size_t k = 0; k < n + 2; k++) {
    double v = k < n ? x[k] : 0.0;
    b.s0 += fabs(v);
    b.s1 += fabs(v - x1);
    b.s2 += fabs(v - 2.0 * x1 + x2);
    x2 = x1;
    x1 = v;
  }
  return b;
}

/* Relative slack of the tail's bound, far above the rounding of the sums
 * (n eps), of the sine and of |out|^2, and the FFT's own error on a bin as a
 * share of sum |x| (a radix-2 transform of N points: ~eps log2 N sqrt N
 * ||x||_2, below 1e-11 sum |x| at 2^20 points). */
#define AF_SPECTRUM_BOUND_SLACK 1e-9
#define AF_SPECTRUM_FFT_ERROR 1e-9

/* Whether no computed g at bin j or above can exceed g_max: the bound at
 * theta_j, the smallest in [theta_j, pi], widened by the slacks. */
static int tail_below(const af_spectrum *s, const af_spectrum_bounds *b, size_t j, double g_max)
{
  double half = sin(0.5 * (double)j * (2.0 * AF_PI / (double)s->cfg.fft_size));
  double a = fmin(b->s0, fmin(b->s1 / (2.0 * half), b->s2 / (4.0 * half * half)));
  a = a * (1.0 + AF_SPECTRUM_BOUND_SLACK) + AF_SPECTRUM_FFT_ERROR * b->s0;
  return half > 0.0 && a * a * (1.0 + AF_SPECTRUM_BOUND_SLACK) < g_max;
}

/* Global maximum. For a one-signed pulse |A(theta)| <= sum |x| = |A(0)|: DC,
 * exactly. Otherwise the grid argmax, refined unless at DC or Nyquist, where
 * |A| of a real pulse is even about the bin and the bin is the extremum.
 * The grid's argmax is searched upwards only until the bound of the bins
 * left (tail_below, tested once a block of bins) falls below the largest g
 * so far: none of them could be taken (a bin is taken only when it exceeds
 * every one before it), so the argmax is the whole grid's, without
 * computing or reading g there. */
static void locate_maximum(af_spectrum *s, const double *x, int one_signed)
{
  size_t last = s->cfg.fft_size / 2, jmax = 0;
  s->max_g = s->mag2[0];
  if (one_signed)
    return;
  af_spectrum_bounds b = pulse_bounds(x, s->n);
  for (size_t j = 1; j <= last; j++) {
    if (j % AF_SPECTRUM_GRID_BLOCK == 0 || j >= s->grid_top) { /* a block's first bin */
      if (tail_below(s, &b, j, s->mag2[jmax]))
        break;
      if (j >= s->grid_top)
        grid_fill(s, j + AF_SPECTRUM_GRID_BLOCK < last ? j + AF_SPECTRUM_GRID_BLOCK : last);
    }
    if (s->mag2[j] > s->mag2[jmax])
      jmax = j;
  }
  s->max_g = s->mag2[jmax];
  if (jmax > 0 && jmax < last) {
    double g;
    refine_bin(s, jmax, 1.0, &g);
    s->max_g = fmax(s->max_g, g);
  }
}

af_status af_spectrum_execute(af_spectrum *s, const double *x, size_t n, double dt_s)
{
  if (s == NULL)
    return AF_EINVAL;
  s->n = 0; /* no valid result until this call succeeds */
  s->lobe_count = 0;
  if (x == NULL || n < 2 || !(dt_s > 0.0) || !isfinite(dt_s))
    return AF_EINVAL;
  if (n > s->cfg.max_samples)
    return AF_ESIZE;
  int one_signed;
  af_status st = load_pulse(s, x, n, &one_signed);
  if (st != AF_OK)
    return st;
  fold_pulse(s, n);
  af_fft_r2c_execute(&s->plan, s->in, s->out);
  s->n = n;
  s->dt_s = dt_s;
  s->grid_top = 0;
  locate_minima(s);
  locate_maximum(s, x, one_signed);
  return AF_OK;
}

/* ---- lobes ------------------------------------------------------------- */

size_t af_spectrum_lobe_count(const af_spectrum *s)
{
  return s != NULL && s->n > 0 ? s->lobe_count : 0;
}

/* A point of a lobe: frequency [rad/sample], g there, nearest grid bin. */
typedef struct {
  double theta, g;
  size_t bin;
} af_point;

static af_point lobe_start(const af_spectrum *s, unsigned index)
{
  af_point e = {0.0, s->mag2[0], 0};
  if (index > 1) {
    e.theta = s->min_theta[index - 2];
    e.g = s->min_g[index - 2];
    e.bin = s->min_bin[index - 2];
  }
  return e;
}

static af_point lobe_end(const af_spectrum *s, unsigned index)
{
  af_point e = {s->min_theta[index - 1], s->min_g[index - 1], s->min_bin[index - 1]};
  return e;
}

/* The lobe's maximum: grid argmax between its end bins, refined unless at DC
 * (a lobe's interior is never empty: two strict minima cannot be adjacent). */
static af_point lobe_peak(const af_spectrum *s, af_point start, af_point end)
{
  af_point p = {0.0, 0.0, start.bin};
  for (size_t j = start.bin + 1; j < end.bin; j++)
    if (s->mag2[j] > s->mag2[p.bin])
      p.bin = j;
  p.g = s->mag2[p.bin];
  if (p.bin > 0) {
    double g;
    p.theta = refine_bin(s, p.bin, 1.0, &g);
    p.g = fmax(p.g, g);
  }
  return p;
}

/* Linear interpolation of |A| between (xa, ga) and (xb, gb) at g = level. */
static double interpolate_level(double xa, double ga, double xb, double gb, double level)
{
  double ra = sqrt(ga), rb = sqrt(gb), r = sqrt(level);
  return ra != rb ? xa + (xb - xa) * (ra - r) / (ra - rb) : 0.5 * (xa + xb);
}

/* The crossing of level between an inner point (g >= level) and an outer one
 * (g < level), on either side. */
static double edge_between(const af_spectrum *s, af_point in, af_point out, double level)
{
  double g;
  double x0 = interpolate_level(in.theta, in.g, out.theta, out.g, level);
  int rising = out.theta < in.theta; /* the low edge: below level at the low end */
  af_target t = {0, level, rising ? -1.0 : 1.0};
  return rising ? refine(s, &t, out.theta, in.theta, x0, &g)
                : refine(s, &t, in.theta, out.theta, x0, &g);
}

/* Band edge on one side (dir +1 up, -1 down) of the refined peak: walk the
 * grid bins strictly between the peak and the lobe end while g >= level,
 * then refine the crossing between the last point above and the first
 * below. When the lobe end itself is at or above the level, the band is
 * clipped there. */
static double band_edge(const af_spectrum *s, af_point peak, af_point end, double level, int dir)
{
  double h = bin_theta(s);
  af_point in = peak;
  long j = dir > 0 ? (long)floor(peak.theta / h) + 1 : (long)ceil(peak.theta / h) - 1;
  for (; dir > 0 ? (double)j * h < end.theta : (double)j * h > end.theta; j += dir) {
    af_point p = {(double)j * h, s->mag2[j], (size_t)j};
    if (p.g < level)
      return edge_between(s, in, p, level);
    in = p;
  }
  return end.g >= level ? end.theta : edge_between(s, in, end, level);
}

af_status af_spectrum_lobe(const af_spectrum *s, unsigned index, af_band_level level, af_lobe *out)
{
  double ratio = af_band_level_ratio(level);
  if (out == NULL || isnan(ratio))
    return AF_EINVAL;
  if (s == NULL || s->n == 0 || index == 0 || index > s->lobe_count)
    return AF_ENOLOBE;
  af_point start = lobe_start(s, index), end = lobe_end(s, index);
  af_point peak = lobe_peak(s, start, end);
  double g_level = ratio * ratio * peak.g;
  double to_hz = 1.0 / (2.0 * AF_PI * s->dt_s);
  out->index = index;
  out->start_hz = start.theta * to_hz;
  out->end_hz = end.theta * to_hz;
  out->peak_hz = peak.theta * to_hz;
  out->peak_magnitude_n_s = s->dt_s * sqrt(peak.g);
  out->band_low_hz = band_edge(s, peak, start, g_level, -1) * to_hz;
  out->band_high_hz = band_edge(s, peak, end, g_level, +1) * to_hz;
  return AF_OK;
}

/* ---- magnitudes -------------------------------------------------------- */

double af_spectrum_magnitude(const af_spectrum *s, double f_hz)
{
  if (s == NULL || s->n == 0 || !isfinite(f_hz))
    return NAN;
  return s->dt_s * sqrt(eval_g(s, 2.0 * AF_PI * f_hz * s->dt_s));
}

double af_spectrum_max_magnitude(const af_spectrum *s)
{
  if (s == NULL || s->n == 0)
    return NAN;
  return s->dt_s * sqrt(s->max_g);
}

double af_spectrum_level_db(const af_spectrum *s, double f_hz)
{
  return 20.0 * log10(af_spectrum_magnitude(s, f_hz) / af_spectrum_max_magnitude(s));
}
