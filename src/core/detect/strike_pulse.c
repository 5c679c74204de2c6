/* strike_pulse.c — the measurement of one strike's pulse on a span of raw
 * force samples (strike_pulse.h): baseline line, contact start and end,
 * peak, impulse, clipping. Pure: everything comes in through the arguments. */
#include "strike_pulse.h"

#include <math.h>

#include "numeric.h"

/* The peak is the maximum of a least-squares quartic through the samples
 * above this fraction of the largest (about 30 samples of a 1.4 ms pulse at
 * 50 kHz): a parabola would need a higher level (fewer samples, more noise)
 * to keep the bias of the damped pulse's skewed top small; the quartic's
 * bias here is below 0.1 %. */
#define AF_STRIKE_PEAK_LEVEL 0.7
#define AF_STRIKE_PEAK_TERMS 5
/* Scan step of the peak search [samples] before Newton's polish. */
#define AF_STRIKE_PEAK_STEP 0.1
/* Guard between the contact and the baseline windows [samples]: first
 * pass, around the coarse contact (whose ends sit inside the true ones by a
 * few samples, more at low SNR), a fixed part plus a fraction of its length;
 * second pass, around the fitted contact. The coarse guard is also how far
 * the edge fits reach into the quiet signal. */
#define AF_STRIKE_GUARD_COARSE 2
#define AF_STRIKE_GUARD_FRACTION 0.1
#define AF_STRIKE_GUARD_FITTED 3
/* Scan step of the edge-zero search [samples], then golden section to
 * AF_STRIKE_EDGE_TOL [samples]. The profile residual is smooth (C1) in the
 * zero, so the scan only has to land in the right basin. */
#define AF_STRIKE_EDGE_STEP 0.5
#define AF_STRIKE_EDGE_TOL 1e-3
/* First pass: only places the baseline windows. */
#define AF_STRIKE_EDGE_TOL_COARSE 5e-2
/* Terms of the edge law a1 s^1.5 + a2 s^4. A third, s^6.5, follows the
 * heavily damped tail better noise-free but lets the zero wander by several
 * samples at 40 dB. */
#define AF_STRIKE_EDGE_TERMS 2
/* Largest least-squares system solved (the peak quartic). */
#define AF_STRIKE_MAX_TERMS 5
/* Short pulses (strike.h): fewer than this many samples above the level
 * max(AF_STRIKE_LEVEL_NOISE x noise RMS, AF_STRIKE_LEVEL_FRACTION x peak)
 * take their edges from that level's interpolated crossings. */
#define AF_STRIKE_SHORT_SAMPLES 16
#define AF_STRIKE_LEVEL_NOISE 3.0
#define AF_STRIKE_LEVEL_FRACTION 0.02
/* A fitted zero is implausible (the fit failed: too few samples on a steep
 * edge, a foot that is no power law) when it lies more than
 * AF_STRIKE_FIT_SLACK [samples] inside its level crossing, or further out
 * than AF_STRIKE_FIT_GAP of the width between the crossings plus 1 sample
 * (the default strike's damped fall: 4.5 samples or 6 % beyond its 2 %
 * crossing). */
#define AF_STRIKE_FIT_SLACK 0.5
#define AF_STRIKE_FIT_GAP 0.15
/* Peak of a pulse too short for the quartic: the maximum of the band-limited
 * reconstruction, a Hann-windowed sinc of this many taps each side, scanned
 * over +-1 sample of the largest sample at this step [samples], then golden
 * section to AF_STRIKE_EDGE_TOL. */
#define AF_STRIKE_SINC_HALF 16
#define AF_STRIKE_SINC_STEP 0.05
/* A baseline window with fewer samples than this is not used. */
#define AF_STRIKE_MIN_WINDOW 4
#define AF_STRIKE_PI 3.14159265358979323846

/* Mean and centre of the finite samples of x in [lo, hi) (clipped to
 * [0, n)); returns their count (fewer than AF_STRIKE_MIN_WINDOW: 0, the
 * window is not used). */
static long window_mean(const double *x, long n, long lo, long hi, double *mean, double *centre)
{
  long first = lo < 0 ? 0 : lo, end = hi < n ? hi : n;
  double sum = 0.0, at = 0.0;
  long count = 0;
  /* Every sample finite (their sum is then finite; a sum that overflows
   * only takes the loop below): the same sum, and the sum of the indices,
   * exact integers below 2^53 either way, in closed form. */
  for (long k = first; k < end; k++)
    sum += x[k];
  if (isfinite(sum)) {
    count = end > first ? end - first : 0;
    at = (double)((first + end - 1) * count / 2);
  } else {
    sum = 0.0;
    for (long k = first; k < end; k++) {
      if (isfinite(x[k])) {
        sum += x[k];
        at += (double)k;
        count++;
      }
    }
  }
  if (count < AF_STRIKE_MIN_WINDOW)
    return 0;
  *mean = sum / (double)count;
  *centre = at / (double)count;
  return count;
}

/* Replaces the non-finite samples of r by the straight line between their
 * finite neighbours (the nearest one at the ends; 0 when none is finite). */
static void fill_holes(double *r, long n)
{
  long k = 0;
  while (k < n) {
    if (isfinite(r[k])) {
      k++;
      continue;
    }
    long a = k - 1, b = k;
    while (b < n && !isfinite(r[b]))
      b++;
    double ra = a >= 0 ? r[a] : (b < n ? r[b] : 0.0);
    double rb = b < n ? r[b] : ra;
    for (long j = k; j < b; j++)
      r[j] = a >= 0 && b < n ? ra + (rb - ra) * (double)(j - a) / (double)(b - a) : ra;
    k = b;
  }
}

/* The measurement's view of one event span. */
typedef struct {
  const double *x;    /* raw */
  double *r;          /* baseline removed */
  long n;             /* span length */
  long lim;           /* clean signal after the first contact ends before this */
  long window;        /* baseline window [samples] */
  double fallback;    /* baseline when no window is usable (the tracker's) */
  double b0, slope;   /* baseline line b0 + slope k */
  long before, after; /* samples averaged in the windows before and after */
} af_span;

/* Baseline line through the windows just before `a` and just after `e`
 * (the contact's first sample and first sample after it), `guard` samples
 * away from them; subtracted into s->r. */
static void remove_baseline(af_span *s, long a, long e, long guard)
{
  double m1, c1, m2, c2;
  long post_hi = e + guard + s->window;
  if (post_hi > s->lim - guard)
    post_hi = s->lim - guard;
  long pre = window_mean(s->x, s->n, a - guard - s->window, a - guard, &m1, &c1);
  long post = window_mean(s->x, s->n, e + guard, post_hi, &m2, &c2);
  s->before = pre;
  s->after = post;
  if (pre && post && c2 > c1) {
    s->slope = (m2 - m1) / (c2 - c1);
    s->b0 = m1 - s->slope * c1;
  } else {
    s->slope = 0.0;
    s->b0 = pre ? m1 : post ? m2 : s->fallback;
  }
  /* A non-finite sample makes its lane's sum non-finite: one add a sample
   * instead of fill_holes' test (a sum that overflows only runs fill_holes
   * on a finite r, which leaves it as it is). Two samples a step
   * (af_v2d): each r[k] the same double. */
  af_v2d b0 = {s->b0, s->b0}, slope = {s->slope, s->slope}, at = {0.0, 1.0}, sum2 = {0.0, 0.0};
  const af_v2d two = {2.0, 2.0};
  long k = 0;
  for (; k + 1 < s->n; k += 2, at += two) { /* at = k, k + 1: exact below 2^53 */
    af_v2d x, r;
    __builtin_memcpy(&x, s->x + k, sizeof x);
    r = x - (b0 + slope * at);
    __builtin_memcpy(s->r + k, &r, sizeof r);
    sum2 += r;
  }
  double sum = sum2[0] + sum2[1];
  for (; k < s->n; k++) {
    s->r[k] = s->x[k] - (s->b0 + s->slope * (double)k);
    sum += s->r[k];
  }
  if (!isfinite(sum))
    fill_holes(s->r, s->n);
}

static long argmax(const double *r, long lo, long hi)
{
  long best = lo;
  for (long k = lo + 1; k <= hi; k++)
    if (r[k] > r[best])
      best = k;
  return best;
}

/* Solves the nb x nb symmetric positive system a c = b (Cholesky, in place
 * on a copy); false when it is not positive definite. */
static bool solve_spd(double a[AF_STRIKE_MAX_TERMS][AF_STRIKE_MAX_TERMS], const double *b,
                      size_t nb, double *c)
{
  double l[AF_STRIKE_MAX_TERMS][AF_STRIKE_MAX_TERMS] = {{0}};
  for (size_t i = 0; i < nb; i++) {
    for (size_t j = 0; j <= i; j++) {
      double v = a[i][j];
      for (size_t k = 0; k < j; k++)
        v -= l[i][k] * l[j][k];
      if (i == j) {
        if (!(v > 1e-12 * a[i][i]))
          return false;
        l[i][i] = sqrt(v);
      } else {
        l[i][j] = v / l[j][j];
      }
    }
  }
  double y[AF_STRIKE_MAX_TERMS] = {0};
  for (size_t i = 0; i < nb; i++) {
    double v = b[i];
    for (size_t k = 0; k < i; k++)
      v -= l[i][k] * y[k];
    y[i] = v / l[i][i];
  }
  for (size_t i = nb; i-- > 0;) {
    double v = y[i];
    for (size_t k = i + 1; k < nb; k++)
      v -= l[k][i] * c[k];
    c[i] = v / l[i][i];
  }
  return true;
}

/* One edge: samples r[lo..hi], contact on the side `side` of the zero z
 * (+1: k > z, rising edge; -1: k < z, falling edge). */
typedef struct {
  const double *r;
  long lo, hi;
  int side;
  double scale; /* s is measured in units of the window length */
  double tol;   /* of the zero [samples] */
  double yy;    /* sum of r[k]^2 over the window (the same at every z) */
} af_edge;

/* The edge law's basis at s > 0: s^1.5, s^4. */
static void edge_basis(double s, double *p0, double *p1)
{
  double s2 = s * s;
  *p0 = s * sqrt(s);
  *p1 = s2 * s2;
}

/* Residual sum of squares from the normal equations (a00 a10; a10 a11) c =
 * (b0, b1), by the Cholesky factor of solve_spd written out for two terms
 * (the same operations in the same order); +inf when singular. */
static double edge_rss_of(double yy, double a00, double a10, double a11, double b0, double b1)
{
  if (!(a00 > 1e-12 * a00))
    return INFINITY;
  double l00 = sqrt(a00), l10 = a10 / l00, v = a11 - l10 * l10;
  if (!(v > 1e-12 * a11))
    return INFINITY;
  double l11 = sqrt(v);
  double y0 = b0 / l00, y1 = (b1 - l10 * y0) / l11;
  double c1 = y1 / l11, c0 = (y0 - l10 * c1) / l00;
  return yy - (c0 * b0 + c1 * b1);
}

/* Residual sum of squares of the best edge law with its zero at z (the
 * coefficients eliminated by linear least squares); +inf when singular. */
static double edge_rss(const af_edge *e, double z)
{
  double a00 = 0.0, a10 = 0.0, a11 = 0.0, b0 = 0.0, b1 = 0.0;
  /* only the samples on the contact's side of z: k > z rising, k < z falling */
  long lo = e->lo, hi = e->hi;
  if (e->side > 0 && (double)lo <= z)
    lo = (long)floor(z) + 1;
  if (e->side < 0 && (double)hi >= z)
    hi = (long)ceil(z) - 1;
  for (long k = lo; k <= hi; k++) {
    double s = (double)e->side * ((double)k - z) * e->scale;
    if (s <= 0.0)
      continue;
    double y = e->r[k], p0, p1;
    edge_basis(s, &p0, &p1);
    b0 += p0 * y;
    a00 += p0 * p0;
    b1 += p1 * y;
    a10 += p1 * p0;
    a11 += p1 * p1;
  }
  return edge_rss_of(e->yy, a00, a10, a11, b0, b1);
}

/* Brent's minimiser (parabolic steps, golden-section ones when a parabola
 * is not trusted; Brent 1973, netlib fmin) of edge_rss on [a, b]: the
 * profile residual is smooth near its minimum, where the parabolas
 * converge superlinearly, so it takes about half the evaluations of the
 * plain golden section to the same accuracy. It stops when the minimum is
 * bracketed within AF_STRIKE_BRENT_REACH of the tolerance e->tol on either
 * side of the point returned, as close as the golden section's midpoint of
 * a final bracket e->tol wide (within e->tol / 2). */
#define AF_STRIKE_BRENT_REACH 0.5
/* Evaluations at most: the golden-section fallback shrinks the bracket by
 * 0.618 at least every other step, so a bracket of a whole window (< 2^20
 * samples) reaches the tolerance in well under 200; the cap only guards a
 * bracket that a non-finite end would keep from shrinking. */
#define AF_STRIKE_BRENT_MAX_EVALS 200
#define AF_STRIKE_SQRT_EPS 1.4901161193847656e-08
typedef struct {
  double a, b;    /* the bracket */
  double x, w, v; /* best, second best, previous second best */
  double fx, fw, fv;
  double d, step; /* the last move and the one before */
} af_brent;

/* The next point to evaluate: a parabolic step through x, w, v when it
 * falls inside the bracket and moves less than half the step before last,
 * else a golden-section step into the larger part. */
static double brent_next(af_brent *s, double tol1)
{
  const double c = 0.3819660112501051; /* (3 - sqrt 5) / 2 */
  double xm = 0.5 * (s->a + s->b);
  bool parabolic = false;
  if (fabs(s->step) > tol1) {
    double r = (s->x - s->w) * (s->fx - s->fv), q = (s->x - s->v) * (s->fx - s->fw);
    double p = (s->x - s->v) * q - (s->x - s->w) * r, before_last = s->step;
    q = 2.0 * (q - r);
    if (q > 0.0)
      p = -p;
    q = fabs(q);
    s->step = s->d;
    if (fabs(p) < fabs(0.5 * q * before_last) && p > q * (s->a - s->x) && p < q * (s->b - s->x)) {
      s->d = p / q;
      double u = s->x + s->d;
      if (u - s->a < 2.0 * tol1 || s->b - u < 2.0 * tol1)
        s->d = xm >= s->x ? tol1 : -tol1;
      parabolic = true;
    }
  }
  if (!parabolic) {
    s->step = (s->x >= xm ? s->a : s->b) - s->x;
    s->d = c * s->step;
  }
  return s->x + (fabs(s->d) >= tol1 ? s->d : (s->d > 0.0 ? tol1 : -tol1));
}

/* Takes the value fu at u into the bracket and the three best points. */
static void brent_take(af_brent *s, double u, double fu)
{
  if (fu <= s->fx) {
    if (u >= s->x)
      s->a = s->x;
    else
      s->b = s->x;
    s->v = s->w;
    s->fv = s->fw;
    s->w = s->x;
    s->fw = s->fx;
    s->x = u;
    s->fx = fu;
    return;
  }
  if (u < s->x)
    s->a = u;
  else
    s->b = u;
  if (fu <= s->fw || s->w == s->x) {
    s->v = s->w;
    s->fv = s->fw;
    s->w = u;
    s->fw = fu;
  } else if (fu <= s->fv || s->v == s->x || s->v == s->w) {
    s->v = u;
    s->fv = fu;
  }
}

static double edge_brent(const af_edge *e, double a, double b)
{
  double x = a + 0.3819660112501051 * (b - a), fx = edge_rss(e, x);
  af_brent s = {.a = a, .b = b, .x = x, .w = x, .v = x, .fx = fx, .fw = fx, .fv = fx};
  for (int evals = 1; evals < AF_STRIKE_BRENT_MAX_EVALS; evals++) {
    double tol1 = AF_STRIKE_SQRT_EPS * fabs(s.x) + 0.5 * AF_STRIKE_BRENT_REACH * e->tol;
    if (fabs(s.x - 0.5 * (s.a + s.b)) <= 2.0 * tol1 - 0.5 * (s.b - s.a))
      return s.x;
    double u = brent_next(&s, tol1);
    brent_take(&s, u, edge_rss(e, u));
  }
  return s.x; /* the best point found */
}

/* The scan's zeros z = zlo + i / 2 with zlo a whole number of samples put
 * every k - z on the half-sample lattice: s = (m / 2) scale for a whole m,
 * so the basis is tabulated once per edge over m (the same doubles as
 * edge_rss computes) and each scan point costs multiply-adds only. The
 * samples on the contact's side of z take every other m of one parity,
 * m0, m0 + 2, ..., from the first one past z (m0 = 1 or 2) outwards, so the
 * normal matrix's sums, which depend on m only, are running sums over the
 * table per parity; only the two sums with the data remain per scan point.
 * Windows longer than the table are scanned by edge_rss. */
#define AF_STRIKE_EDGE_LATTICE 1024

/* The edge's lattice: p0[m], p1[m] the basis at s = (m / 2) scale, stored
 * at [AF_STRIKE_LATTICE_PAD + m] with 0 below m = 1 (edge_lattice_group
 * reads down to m = 1 - AF_STRIKE_LATTICE_PAD), and q00[m], q10[m], q11[m]
 * the sums of p0 p0, p1 p0, p1 p1 over m, m - 2, ... down to 1 or 2 (index
 * 0 and -1, i.e. [m + 1] stored, hold 0). */
#define AF_STRIKE_LATTICE_PAD 4
typedef struct {
  double p0[AF_STRIKE_LATTICE_PAD + AF_STRIKE_EDGE_LATTICE];
  double p1[AF_STRIKE_LATTICE_PAD + AF_STRIKE_EDGE_LATTICE];
  double q00[AF_STRIKE_EDGE_LATTICE + 1], q10[AF_STRIKE_EDGE_LATTICE + 1],
      q11[AF_STRIKE_EDGE_LATTICE + 1];
} af_edge_lattice;

/* The lattice for m = 1 .. m_max; q's are stored one place up (q[m + 1]),
 * so that q[m - 1] is the empty sum below m = 1 or 2. */
static void edge_lattice(double scale, long m_max, af_edge_lattice *t)
{
  t->q00[0] = t->q10[0] = t->q11[0] = 0.0;
  t->q00[1] = t->q10[1] = t->q11[1] = 0.0;
  for (long m = 1 - AF_STRIKE_LATTICE_PAD; m <= 0; m++)
    t->p0[AF_STRIKE_LATTICE_PAD + m] = t->p1[AF_STRIKE_LATTICE_PAD + m] = 0.0;
  /* m and m + 1 a step (af_v2d): each sum runs over one parity, so
   * q[m + 1], q[m + 2] are q[m - 1], q[m] plus the pair's terms, the same
   * additions as one m at a time; edge_basis' operations per lane. */
  long m = 1;
  for (; m + 1 <= m_max; m += 2) {
    af_v2d s = {(double)m * 0.5 * scale, (double)(m + 1) * 0.5 * scale}, s2 = s * s;
    af_v2d root = {sqrt(s[0]), sqrt(s[1])}, p0 = s * root, p1 = s2 * s2, q00, q10, q11;
    __builtin_memcpy(&q00, &t->q00[m - 1], sizeof q00);
    __builtin_memcpy(&q10, &t->q10[m - 1], sizeof q10);
    __builtin_memcpy(&q11, &t->q11[m - 1], sizeof q11);
    q00 += p0 * p0;
    q10 += p1 * p0;
    q11 += p1 * p1;
    __builtin_memcpy(&t->p0[AF_STRIKE_LATTICE_PAD + m], &p0, sizeof p0);
    __builtin_memcpy(&t->p1[AF_STRIKE_LATTICE_PAD + m], &p1, sizeof p1);
    __builtin_memcpy(&t->q00[m + 1], &q00, sizeof q00);
    __builtin_memcpy(&t->q10[m + 1], &q10, sizeof q10);
    __builtin_memcpy(&t->q11[m + 1], &q11, sizeof q11);
  }
  for (; m <= m_max; m++) {
    double *p0 = &t->p0[AF_STRIKE_LATTICE_PAD + m], *p1 = &t->p1[AF_STRIKE_LATTICE_PAD + m];
    edge_basis((double)m * 0.5 * scale, p0, p1);
    t->q00[m + 1] = t->q00[m - 1] + *p0 * *p0;
    t->q10[m + 1] = t->q10[m - 1] + *p1 * *p0;
    t->q11[m + 1] = t->q11[m - 1] + *p1 * *p1;
  }
}

/* The samples k0 .. k1 on the contact's side of the lattice's zero
 * z = zl + i / 2 (m >= 1): k >= zl + (i + 2) / 2 rising, k <= zl + (i + 1)
 * / 2 - 1 falling. */
static void edge_lattice_side(const af_edge *e, long zl, long i, long *k0, long *k1)
{
  long lo = e->side > 0 ? zl + (i + 2) / 2 : e->lo, hi = e->side > 0 ? e->hi : zl + (i + 1) / 2 - 1;
  *k0 = lo < e->lo ? e->lo : lo;
  *k1 = hi > e->hi ? e->hi : hi;
}

/* m of the zero z = zl + i / 2 at sample k: 2 side (k - z). */
static long edge_lattice_m(const af_edge *e, long zl, long i, long k)
{
  return e->side * (2 * (k - zl) - i);
}

/* The rss of the lattice's zero z = zl + i / 2, its contact side k0 .. k1,
 * from the data's sums b0, b1 over it (0 when it is empty). */
static double edge_lattice_rss(const af_edge *e, const af_edge_lattice *t, long zl, long i, long k0,
                               long k1, double b0, double b1)
{
  double a00 = 0.0, a10 = 0.0, a11 = 0.0;
  if (k1 >= k0) {
    /* the smallest and largest m */
    long m_in = edge_lattice_m(e, zl, i, e->side > 0 ? k0 : k1), m_out = m_in + 2 * (k1 - k0);
    a00 = t->q00[m_out + 1] - t->q00[m_in - 1];
    a10 = t->q10[m_out + 1] - t->q10[m_in - 1];
    a11 = t->q11[m_out + 1] - t->q11[m_in - 1];
  }
  return edge_rss_of(e->yy, a00, a10, a11, b0, b1);
}

/* The data's sums b0 = sum p0[m] r[k], b1 = sum p1[m] r[k] of the zero
 * zl + i / 2 over k0 .. k1, in k's order. */
static void edge_lattice_sums(const af_edge *e, const af_edge_lattice *t, long zl, long i, long k0,
                              long k1, double *b0, double *b1)
{
  double s0 = 0.0, s1 = 0.0;
  long m = edge_lattice_m(e, zl, i, k0), dm = 2 * e->side;
  for (long k = k0; k <= k1; k++, m += dm) {
    double y = e->r[k];
    s0 += t->p0[AF_STRIKE_LATTICE_PAD + m] * y;
    s1 += t->p1[AF_STRIKE_LATTICE_PAD + m] * y;
  }
  *b0 = s0;
  *b1 = s1;
}

/* Four zeros of the scan at once: lane j the zero i_j = i + j side, the
 * next ones in the scan's order. Its m at k is m_0(k) - j, so the four
 * lanes' basis values at k are the four table entries m_0 - 3 .. m_0 in a
 * row, two af_v2d registers. The lanes run over the
 * union of their sides; at a k outside its own side a lane's m is 0 or
 * below, where the table holds 0: the sum adds 0 x r[k] = +-0, which leaves
 * every partial sum the same double (0 + -0 = 0), r being finite (e->yy
 * is). False, nothing computed, when some lane's extra samples would reach
 * past the table's zeros (a side clipped to the window). */
#define AF_STRIKE_LANES 4

static bool edge_lattice_group(const af_edge *e, const af_edge_lattice *t, long zl, long i,
                               const long *k0, const long *k1, double *b0, double *b1)
{
  long lo = k0[0], hi = k1[0];
  for (int j = 1; j < AF_STRIKE_LANES; j++) {
    lo = k0[j] < lo ? k0[j] : lo;
    hi = k1[j] > hi ? k1[j] : hi;
  }
  for (int j = 0; j < AF_STRIKE_LANES; j++) {
    long ij = i + j * e->side, m_lo = edge_lattice_m(e, zl, ij, lo);
    long m_hi = edge_lattice_m(e, zl, ij, hi);
    bool lo_in = lo >= k0[j] && lo <= k1[j], hi_in = hi >= k0[j] && hi <= k1[j];
    if ((!lo_in && (m_lo > 0 || m_lo <= -AF_STRIKE_LATTICE_PAD)) ||
        (!hi_in && (m_hi > 0 || m_hi <= -AF_STRIKE_LATTICE_PAD)))
      return false;
  }
  af_v2d s0_hi = {0.0, 0.0}, s0_lo = {0.0, 0.0}, s1_hi = {0.0, 0.0}, s1_lo = {0.0, 0.0};
  const double *p0 = t->p0 + AF_STRIKE_LATTICE_PAD - 3, *p1 = t->p1 + AF_STRIKE_LATTICE_PAD - 3;
  long m = edge_lattice_m(e, zl, i, lo), dm = 2 * e->side;
  for (long k = lo; k <= hi; k++, m += dm) {
    af_v2d y = {e->r[k], e->r[k]}, a, b, c, d; /* a, b: m - 3, m - 2, m - 1, m */
    __builtin_memcpy(&a, p0 + m, sizeof a);
    __builtin_memcpy(&b, p0 + m + 2, sizeof b);
    __builtin_memcpy(&c, p1 + m, sizeof c);
    __builtin_memcpy(&d, p1 + m + 2, sizeof d);
    s0_lo += a * y;
    s0_hi += b * y;
    s1_lo += c * y;
    s1_hi += d * y;
  }
  /* lane j sits at m - j: element 1 - j of hi, 3 - j of lo */
  b0[0] = s0_hi[1], b0[1] = s0_hi[0], b0[2] = s0_lo[1], b0[3] = s0_lo[0];
  b1[0] = s1_hi[1], b1[1] = s1_hi[0], b1[2] = s1_lo[1], b1[3] = s1_lo[0];
  return true;
}

/* Far enough past the edge the quiet side holds signal: the rss of every
 * zero further on is at least the sum of r^2 over the samples it leaves
 * on the quiet side (modelled as 0), which only grows, so the scan stops
 * once that sum passes the best rss (by a margin far above the rounding of
 * either, ~1e-14 yy: no zero it skips could have been taken). The scan runs
 * from the window's quiet end towards the contact (falling edges
 * backwards, ties still to the smaller zero), where the sum grows. */
#define AF_STRIKE_EDGE_PRUNE_MARGIN 1e-9

/* The data's sums of the scan's zeros done .. done + AF_STRIKE_LANES - 1
 * (i = done rising, steps - done falling) into b0, b1: four at once when
 * they all lie on the scan (edge_lattice_group), else the first alone.
 * Returns how many it computed. */
static int edge_lattice_next(const af_edge *e, const af_edge_lattice *t, long zl, long done,
                             long steps, double *b0, double *b1)
{
  long i = e->side > 0 ? done : steps - done, k0[AF_STRIKE_LANES], k1[AF_STRIKE_LANES];
  if (done + AF_STRIKE_LANES - 1 <= steps && isfinite(e->yy)) {
    for (int j = 0; j < AF_STRIKE_LANES; j++)
      edge_lattice_side(e, zl, i + j * e->side, &k0[j], &k1[j]);
    if (edge_lattice_group(e, t, zl, i, k0, k1, b0, b1))
      return AF_STRIKE_LANES;
  }
  edge_lattice_side(e, zl, i, &k0[0], &k1[0]);
  b0[0] = b1[0] = 0.0;
  if (k1[0] >= k0[0])
    edge_lattice_sums(e, t, zl, i, k0[0], k1[0], &b0[0], &b1[0]);
  return 1;
}

/* The scan of fit_edge over the lattice; the best zero and its rss. The
 * data's sums are computed a group of zeros ahead (edge_lattice_next),
 * after the prune test of the group's first: a group the pruning cuts
 * short only costs its unused lanes. */
static void edge_scan_lattice(const af_edge *e, double zlo, long steps, long m_max, double *best,
                              double *best_rss)
{
  af_edge_lattice t;
  edge_lattice(e->scale, m_max, &t);
  const long zl = (long)zlo;
  const double margin = AF_STRIKE_EDGE_PRUNE_MARGIN * e->yy;
  double quiet = 0.0;                      /* sum of r^2 on the quiet side of the zero */
  long next = e->side > 0 ? e->lo : e->hi; /* the next sample to join it */
  double b0[AF_STRIKE_LANES], b1[AF_STRIKE_LANES];
  int have = 0, at = 0; /* zeros whose sums are computed, the next one's lane */
  for (long done = 0; done <= steps; done++, at++) {
    long i = e->side > 0 ? done : steps - done, k0, k1;
    edge_lattice_side(e, zl, i, &k0, &k1);
    for (; e->side > 0 ? next < k0 && next <= e->hi : next > k1 && next >= e->lo; next += e->side)
      quiet += e->r[next] * e->r[next];
    if (quiet > *best_rss + margin)
      break;
    if (at == have) {
      have = edge_lattice_next(e, &t, zl, done, steps, b0, b1);
      at = 0;
    }
    double rss = edge_lattice_rss(e, &t, zl, i, k0, k1, b0[at], b1[at]);
    if (e->side > 0 ? rss < *best_rss : rss <= *best_rss) {
      *best_rss = rss;
      *best = zlo + (double)i * AF_STRIKE_EDGE_STEP;
    }
  }
}

/* Zero of the edge law fitted to r[lo..hi], searched in [zlo, zhi]; the
 * fallback when the window is too short or no fit exists. */
static double fit_edge(af_edge *e, double zlo, double zhi, double fallback)
{
  if (e->hi - e->lo + 1 < AF_STRIKE_EDGE_TERMS + 2 || !(zhi > zlo))
    return fallback;
  e->yy = 0.0;
  for (long k = e->lo; k <= e->hi; k++)
    e->yy += e->r[k] * e->r[k];
  double best = NAN, best_rss = INFINITY;
  long steps = (long)floor((zhi - zlo) / AF_STRIKE_EDGE_STEP);
  /* m = 2 side (k - z) of the scan: at most m_max (its first zero and the
   * window's far end). */
  long m_max = e->side > 0 ? 2 * (e->hi - (long)zlo) : 2 * ((long)zlo - e->lo) + steps;
  if (zlo == floor(zlo) && m_max < AF_STRIKE_EDGE_LATTICE) {
    edge_scan_lattice(e, zlo, steps, m_max, &best, &best_rss);
  } else {
    for (long i = 0; i <= steps; i++) {
      double z = zlo + (double)i * AF_STRIKE_EDGE_STEP, rss = edge_rss(e, z);
      if (rss < best_rss) {
        best_rss = rss;
        best = z;
      }
    }
  }
  if (!isfinite(best_rss))
    return fallback;
  double a = fmax(zlo, best - AF_STRIKE_EDGE_STEP), b = fmin(zhi, best + AF_STRIKE_EDGE_STEP);
  return edge_brent(e, a, b);
}

/* Contact start: fit from the quiet signal at `outer` up to the last sample
 * below the rise level before the peak. */
static double fit_start(const af_span *s, long outer, long ipk, double level, double fallback,
                        double tol)
{
  long lo = outer < 0 ? 0 : outer, hi = ipk;
  while (hi > lo && s->r[hi] > level)
    hi--;
  af_edge e = {.r = s->r, .lo = lo, .hi = hi, .side = 1, .tol = tol};
  e.scale = 1.0 / (double)(hi - lo + 1);
  return fit_edge(&e, (double)lo - 1.0, (double)(hi - AF_STRIKE_EDGE_TERMS - 1), fallback);
}

/* Contact end: fit from the first sample below the fall level after the
 * peak down to the quiet signal at `outer` (before s->lim). */
static double fit_end(const af_span *s, long outer, long ipk, double level, double fallback,
                      double tol)
{
  long before_bounce = s->lim - 1 - AF_STRIKE_GUARD_FITTED;
  long hi = outer < before_bounce ? outer : before_bounce, lo = ipk;
  if (hi > s->n - 1)
    hi = s->n - 1;
  while (lo < hi && s->r[lo] > level)
    lo++;
  af_edge e = {.r = s->r, .lo = lo, .hi = hi, .side = -1, .tol = tol};
  e.scale = 1.0 / (double)(hi - lo + 1);
  return fit_edge(&e, (double)(lo + AF_STRIKE_EDGE_TERMS + 1), (double)hi + 1.0, fallback);
}

/* Value of the polynomial c[0..AF_STRIKE_PEAK_TERMS) at u: poly_eval's *v
 * alone (the same double: its first step, 0 u + c[4], is c[4]), written
 * out for the scan. */
_Static_assert(AF_STRIKE_PEAK_TERMS == 5, "poly_value is written out for a quartic");
static double poly_value(const double *c, double u)
{
  return (((c[4] * u + c[3]) * u + c[2]) * u + c[1]) * u + c[0];
}

/* The largest of poly_value at u = ulo + i du, i = 0 .. steps, and its u
 * (the first on a tie) into *best, *ub: two u's a step (af_v2d),
 * each value the same double, compared in i's order. */
static void peak_scan(const double *c, double ulo, double du, long steps, double *best, double *ub)
{
  const af_v2d lo = {ulo, ulo}, step = {du, du}, two = {2.0, 2.0};
  af_v2d at = {0.0, 1.0}; /* i, i + 1: exact below 2^53 */
  long i = 0;
  for (; i + 1 <= steps; i += 2, at += two) {
    af_v2d u = lo + at * step;
    af_v2d v = (((c[4] * u + c[3]) * u + c[2]) * u + c[1]) * u + c[0];
    for (int j = 0; j < 2; j++)
      if (v[j] > *best) {
        *best = v[j];
        *ub = u[j];
      }
  }
  for (; i <= steps; i++) {
    double u = ulo + (double)i * du, v = poly_value(c, u);
    if (v > *best) {
      *best = v;
      *ub = u;
    }
  }
}

/* Value and derivatives of the polynomial c[0..AF_STRIKE_PEAK_TERMS) at u. */
static void poly_eval(const double *c, double u, double *v, double *d1, double *d2)
{
  *v = *d1 = *d2 = 0.0;
  for (int i = AF_STRIKE_PEAK_TERMS - 1; i >= 0; i--) {
    *d2 = *d2 * u + 2.0 * *d1;
    *d1 = *d1 * u + *v;
    *v = *v * u + c[i];
  }
}

/* cos and sin of pi / AF_STRIKE_SINC_HALF: the Hann window's step per tap. */
#define AF_STRIKE_SINC_COS_STEP 0.98078528040323044913
#define AF_STRIKE_SINC_SIN_STEP 0.19509032201612826785
_Static_assert(AF_STRIKE_SINC_HALF == 16, "the window's step constants are for 16 taps");

/* Band-limited reconstruction of r at t [samples]: Hann-windowed sinc over
 * AF_STRIKE_SINC_HALF samples each side, r taken as 0 outside [0, n) (it is
 * baseline-removed). Equals r[k] at an integer t = k. With t = k0 + f and
 * d = k0 - j, sin(pi (t - j)) = (-1)^d sin(pi f) and the window's angle
 * pi (f + d) / AF_STRIKE_SINC_HALF steps by a fixed rotation from tap to tap:
 * three sines and cosines per call instead of two per tap. */
AF_NUMERIC_KERNEL static double sinc_at(const double *r, long n, double t)
{
  long k0 = (long)floor(t);
  double f = t - (double)k0, sf = sin(AF_STRIKE_PI * f), sum = 0.0;
  double w = AF_STRIKE_PI * (f + (double)(AF_STRIKE_SINC_HALF - 1)) / AF_STRIKE_SINC_HALF;
  double wc = cos(w), ws = sin(w);
  double sign = (AF_STRIKE_SINC_HALF - 1) % 2 ? -1.0 : 1.0; /* (-1)^d at the first tap */
  for (long j = k0 - AF_STRIKE_SINC_HALF + 1; j <= k0 + AF_STRIKE_SINC_HALF; j++) {
    double u = t - (double)j;
    if (j >= 0 && j < n) {
      if (fabs(u) < 1e-12) {
        sum += r[j];
      } else {
        double x = AF_STRIKE_PI * u;
        sum += r[j] * (sign * sf) / x * (0.5 + 0.5 * wc);
      }
    }
    double c = wc * AF_STRIKE_SINC_COS_STEP + ws * AF_STRIKE_SINC_SIN_STEP;
    ws = ws * AF_STRIKE_SINC_COS_STEP - wc * AF_STRIKE_SINC_SIN_STEP;
    wc = c;
    sign = -sign;
  }
  return sum;
}

/* sinc_at with every tap's sine and cosine taken directly: the value the
 * peak reports (its position is searched with sinc_at, equal to ~1e-16
 * relative), so that the reported peak force is the same double as the
 * direct sum gives. */
static double sinc_at_direct(const double *r, long n, double t)
{
  long k0 = (long)floor(t);
  double sum = 0.0;
  for (long j = k0 - AF_STRIKE_SINC_HALF + 1; j <= k0 + AF_STRIKE_SINC_HALF; j++) {
    if (j < 0 || j >= n)
      continue;
    double u = t - (double)j;
    if (fabs(u) < 1e-12) {
      sum += r[j];
      continue;
    }
    double x = AF_STRIKE_PI * u;
    sum += r[j] * sin(x) / x * (0.5 + 0.5 * cos(x / AF_STRIKE_SINC_HALF));
  }
  return sum;
}

/* Maximum of sinc_at within +-1 sample of ipk (the largest sample); at
 * least r[ipk], the reconstruction passing through it. */
static double sinc_peak(const double *r, long n, long ipk, double *at)
{
  double best = r[ipk], tb = (double)ipk;
  long steps = (long)lround(2.0 / AF_STRIKE_SINC_STEP);
  for (long i = 0; i <= steps; i++) {
    double t = (double)ipk - 1.0 + (double)i * AF_STRIKE_SINC_STEP, v = sinc_at(r, n, t);
    if (v > best) {
      best = v;
      tb = t;
    }
  }
  /* golden section for the maximum around the best scanned point */
  const double g = 0.6180339887498949;
  double a = tb - AF_STRIKE_SINC_STEP, b = tb + AF_STRIKE_SINC_STEP;
  double u = b - g * (b - a), v = a + g * (b - a);
  double fu = sinc_at(r, n, u), fv = sinc_at(r, n, v);
  while (b - a > AF_STRIKE_EDGE_TOL) {
    if (fu > fv) {
      b = v;
      v = u;
      fv = fu;
      u = b - g * (b - a);
      fu = sinc_at(r, n, u);
    } else {
      a = u;
      u = v;
      fu = fv;
      v = a + g * (b - a);
      fv = sinc_at(r, n, v);
    }
  }
  double tm = 0.5 * (a + b), vm = sinc_at(r, n, tm);
  if (vm > best) {
    best = vm;
    tb = tm;
  }
  *at = tb;
  return best > r[ipk] ? fmax(sinc_at_direct(r, n, tb), r[ipk]) : best;
}

/* Maximum of the least-squares quartic through the samples around ipk above
 * AF_STRIKE_PEAK_LEVEL of r[ipk]; of the band-limited reconstruction when
 * there are too few for the quartic (a short pulse); the largest sample when
 * the quartic has no interior maximum. *at receives its position [samples]. */
static double refine_peak(const double *r, long n, long ipk, double *at)
{
  double top = r[ipk], level = AF_STRIKE_PEAK_LEVEL * top;
  long lo = ipk, hi = ipk;
  while (lo > 0 && r[lo - 1] > level)
    lo--;
  while (hi < n - 1 && r[hi + 1] > level)
    hi++;
  *at = (double)ipk;
  if (hi - lo + 1 < AF_STRIKE_PEAK_TERMS + 2)
    return sinc_peak(r, n, ipk, at);
  /* Abscissa u = (k - ipk) / width keeps the normal equations conditioned. */
  double w = (double)(hi - lo + 1);
  double m[AF_STRIKE_MAX_TERMS][AF_STRIKE_MAX_TERMS] = {{0}};
  double t[AF_STRIKE_MAX_TERMS] = {0}, c[AF_STRIKE_MAX_TERMS];
  for (long k = lo; k <= hi; k++) {
    double u = (double)(k - ipk) / w, p = 1.0, pw[AF_STRIKE_PEAK_TERMS];
    for (int i = 0; i < AF_STRIKE_PEAK_TERMS; i++, p *= u)
      pw[i] = p;
#pragma GCC unroll 5 /* a constant count: the sums stay in registers */
    for (int i = 0; i < AF_STRIKE_PEAK_TERMS; i++) {
      t[i] += r[k] * pw[i];
#pragma GCC unroll 5
      for (int j = 0; j <= i; j++)
        m[i][j] += pw[i] * pw[j];
    }
  }
  for (int i = 0; i < AF_STRIKE_PEAK_TERMS; i++) /* pw[j] pw[i] is the same double */
    for (int j = i + 1; j < AF_STRIKE_PEAK_TERMS; j++)
      m[i][j] = m[j][i];
  if (!solve_spd(m, t, AF_STRIKE_PEAK_TERMS, c))
    return top;
  double ulo = (double)(lo - ipk) / w, uhi = (double)(hi - ipk) / w, du = AF_STRIKE_PEAK_STEP / w;
  double best = -INFINITY, ub = 0.0, v, d1, d2;
  peak_scan(c, ulo, du, (long)floor((uhi - ulo) / du), &best, &ub);
  double un = ub; /* Newton on the derivative, from the best scanned point */
  for (int it = 0; it < 8; it++) {
    poly_eval(c, un, &v, &d1, &d2);
    double next = un - d1 / d2;
    if (!(d2 < 0.0) || !(fabs(next - ub) <= du)) /* stay in the scanned basin */
      break;
    un = next;
  }
  poly_eval(c, un, &v, &d1, &d2);
  if (v >= best)
    ub = un;
  else
    v = best;
  *at = (double)ipk + ub * w;
  return v;
}

/* Trapezoid integral [N samples] of r over [t0, t1], r taken as 0 at both. */
static double integral(const double *r, long n, double t0, double t1)
{
  long k0 = (long)ceil(t0), k1 = (long)floor(t1);
  if (k0 < 0)
    k0 = 0;
  if (k1 > n - 1)
    k1 = n - 1;
  if (k1 < k0)
    return 0.0; /* no sample inside: a contact shorter than one sample */
  double sum = 0.5 * r[k0] * ((double)k0 - t0) + 0.5 * r[k1] * (t1 - (double)k1);
  for (long k = k0; k < k1; k++)
    sum += 0.5 * (r[k] + r[k + 1]);
  return sum;
}

static bool clipped(const double *x, long lo, long hi, double full_scale_n)
{
  for (long k = lo; k <= hi; k++)
    if (fabs(x[k]) >= full_scale_n)
      return true;
  return false;
}

static long clamp_index(long k, long n)
{
  return k < 0 ? 0 : k > n - 1 ? n - 1 : k;
}

/* The crossing of `level` by the band-limited reconstruction of r between
 * samples k and k + 1, which straddle it, found by bisection to
 * AF_STRIKE_EDGE_TOL (the reconstruction passes through both samples, so a
 * crossing exists). The bisection is run lazily: a crossing is a bracket
 * [a, b] that always holds the final value (the midpoint of the last
 * bracket), refined only as far as a decision needs it (crossing_decide);
 * the value itself, once asked for, is the same double as the whole
 * bisection gives. Each step costs a 32-tap reconstruction, and for a long
 * pulse the crossings only bound its fitted edges, which lie samples away
 * from the bounds: most strikes need no step at all. */
typedef struct {
  const double *r;
  long n, k;
  double level, a, b;
  bool a_below; /* r[k] <= level */
} af_crossing;

static af_crossing crossing_at(const double *r, long n, long k, double level)
{
  return (af_crossing){.r = r,
                       .n = n,
                       .k = k,
                       .level = level,
                       .a = (double)k,
                       .b = (double)(k + 1),
                       .a_below = r[k] <= level};
}

/* An end of the span reached above the level: the outermost sample, exact. */
static af_crossing crossing_exact(double t)
{
  return (af_crossing){.r = NULL, .a = t, .b = t};
}

static bool crossing_done(const af_crossing *c)
{
  return c->r == NULL || !(c->b - c->a > AF_STRIKE_EDGE_TOL);
}

/* One bisection step; false when the bracket is already final. */
static bool crossing_step(af_crossing *c)
{
  if (crossing_done(c))
    return false;
  double m = 0.5 * (c->a + c->b);
  if ((sinc_at(c->r, c->n, m) <= c->level) == c->a_below)
    c->a = m;
  else
    c->b = m;
  return true;
}

static double crossing_value(af_crossing *c)
{
  while (crossing_step(c))
    ;
  return c->r == NULL ? c->a : 0.5 * (c->a + c->b);
}

/* Crossings of `level` around the largest sample ipk: *c0 between the last
 * sample at or below it before ipk and the next, *c1 likewise after ipk
 * (the outermost sample when the span ends above it), both unrefined.
 * Returns the number of samples above it (0 when r[ipk] is not). */
static long level_edges(const double *r, long n, long ipk, double level, af_crossing *c0,
                        af_crossing *c1)
{
  if (!(r[ipk] > level))
    return 0;
  long lo = ipk, hi = ipk;
  while (lo > 0 && r[lo - 1] > level)
    lo--;
  while (hi < n - 1 && r[hi + 1] > level)
    hi++;
  *c0 = lo > 0 ? crossing_at(r, n, lo - 1, level) : crossing_exact((double)lo);
  *c1 = hi < n - 1 ? crossing_at(r, n, hi, level) : crossing_exact((double)hi);
  return hi - lo + 1;
}

/* A condition on the crossings' final values l0 and l1, given in interval
 * form: +1 true and -1 false for every l0 in [a0, b0] and l1 in [a1, b1],
 * 0 undecided. The conditions below are built from operations monotone in
 * each argument (rounding to nearest is monotone), so evaluating them at the
 * bracket's ends bounds their value at the final crossings. */
typedef int af_crossing_test(double a0, double b0, double a1, double b1, double t);

/* l1 > l0 */
static int test_ordered(double a0, double b0, double a1, double b1, double t)
{
  (void)t;
  return a1 > b0 ? 1 : !(b1 > a0) ? -1 : 0;
}

/* The fitted start t is plausible: l0 - out <= t <= l0 + AF_STRIKE_FIT_SLACK
 * with out = AF_STRIKE_FIT_GAP (l1 - l0) + 1 (measure_span says why). */
static int test_start(double a0, double b0, double a1, double b1, double t)
{
  double out_lo = AF_STRIKE_FIT_GAP * (a1 - b0) + 1.0, out_hi = AF_STRIKE_FIT_GAP * (b1 - a0) + 1.0;
  if (t <= a0 + AF_STRIKE_FIT_SLACK && t >= b0 - out_lo)
    return 1;
  if (!(t <= b0 + AF_STRIKE_FIT_SLACK) || !(t >= a0 - out_hi))
    return -1; /* NaN too */
  return 0;
}

/* The fitted end t is plausible: l1 - AF_STRIKE_FIT_SLACK <= t <= l1 + out. */
static int test_end(double a0, double b0, double a1, double b1, double t)
{
  double out_lo = AF_STRIKE_FIT_GAP * (a1 - b0) + 1.0, out_hi = AF_STRIKE_FIT_GAP * (b1 - a0) + 1.0;
  if (t >= b1 - AF_STRIKE_FIT_SLACK && t <= a1 + out_lo)
    return 1;
  if (!(t >= a1 - AF_STRIKE_FIT_SLACK) || !(t <= b1 + out_hi))
    return -1;
  return 0;
}

/* The bounds of c's final value: the bracket, or the value once final. */
static void crossing_bounds(af_crossing *c, double *lo, double *hi)
{
  if (crossing_done(c)) {
    *lo = *hi = crossing_value(c);
  } else {
    *lo = c->a;
    *hi = c->b;
  }
}

/* The test's value at the final crossings, refining the wider bracket
 * until it is decided (once both are final the bounds are points and the
 * test is the exact comparison). */
static bool crossing_decide(af_crossing_test *test, af_crossing *c0, af_crossing *c1, double t)
{
  for (;;) {
    double a0, b0, a1, b1;
    crossing_bounds(c0, &a0, &b0);
    crossing_bounds(c1, &a1, &b1);
    int v = test(a0, b0, a1, b1, t);
    if (v != 0)
      return v > 0;
    af_crossing *wide = b0 - a0 >= b1 - a1 ? c0 : c1;
    if (!crossing_step(wide) && !crossing_step(wide == c0 ? c1 : c0))
      return false; /* unreachable: point bounds decide */
  }
}

/* Result of the two baseline/fit passes, span-relative. */
typedef struct {
  double t0, t1, peak_n, peak_at;
  long cs, ce; /* coarse contact: first sample, first sample after */
  af_strike_edges start_edge, end_edge;
  double level_n; /* the level of the crossings */
} af_fit_out;

/* Coarse contact, then two passes of baseline removal and edge fits. */
static void measure_span(const af_strike_pulse_input *in, af_span *s, af_fit_out *o)
{
  long cs = in->trigger, ce = in->contact_end;
  while (cs > 0 && s->x[cs - 1] - in->tracker_baseline_n > in->release_n)
    cs--;
  if (ce > s->n)
    ce = s->n;
  long a = cs, e = ce > cs + 1 ? ce : cs + 1;
  /* The edge fits reach this far into the quiet signal in both passes: a
   * shorter reach after a first fit that came early would keep it early. */
  long reach = AF_STRIKE_GUARD_COARSE + (long)(AF_STRIKE_GUARD_FRACTION * (double)(e - a));
  long guard = reach;
  double t0 = (double)a, t1 = (double)e - 1.0, peak_n = 0.0, peak_at = 0.0, level = 0.0;
  af_strike_edges start_edge = AF_STRIKE_EDGES_FIT, end_edge = AF_STRIKE_EDGES_FIT;
  for (int pass = 0; pass < 2; pass++) {
    remove_baseline(s, a, e, guard);
    long ipk = argmax(s->r, clamp_index(a, s->n), clamp_index(e - 1, s->n));
    peak_n = refine_peak(s->r, s->n, ipk, &peak_at);
    level = fmax(AF_STRIKE_LEVEL_NOISE * in->noise_rms_n, AF_STRIKE_LEVEL_FRACTION * peak_n);
    af_crossing c0 = crossing_exact(0.0), c1 = crossing_exact(0.0);
    long above = level_edges(s->r, s->n, ipk, level, &c0, &c1);
    bool crossed = above > 0 && crossing_decide(test_ordered, &c0, &c1, 0.0);
    start_edge = end_edge = AF_STRIKE_EDGES_LEVEL;
    if (crossed && above < AF_STRIKE_SHORT_SAMPLES) {
      t0 = crossing_value(&c0);
      t1 = crossing_value(&c1);
    } else {
      double tol = pass == 0 ? AF_STRIKE_EDGE_TOL_COARSE : AF_STRIKE_EDGE_TOL;
      t0 = fit_start(s, a - reach, ipk, in->rise_fit_level * peak_n, NAN, tol);
      t1 = fit_end(s, e - 1 + reach, ipk, in->fall_fit_level * peak_n, NAN, tol);
      /* No fit (too few samples), a fitted zero on the wrong side of its
       * level crossing or further out than any plausible foot: the fit
       * failed, the crossing stands (the coarse contact without one). */
      if (crossed && !crossing_decide(test_start, &c0, &c1, t0)) {
        t0 = crossing_value(&c0);
      } else {
        start_edge = AF_STRIKE_EDGES_FIT;
        t0 = isnan(t0) ? (double)a : t0;
      }
      if (crossed && !crossing_decide(test_end, &c0, &c1, t1)) {
        t1 = crossing_value(&c1);
      } else {
        end_edge = AF_STRIKE_EDGES_FIT;
        t1 = isnan(t1) ? (double)e - 1.0 : t1;
      }
      if (!(t1 > t0))
        t1 = (double)e - 1.0;
    }
    a = (long)floor(t0);
    e = (long)ceil(t1) + 1;
    guard = AF_STRIKE_GUARD_FITTED;
  }
  *o = (af_fit_out){.t0 = t0,
                    .t1 = t1,
                    .peak_n = peak_n,
                    .peak_at = peak_at,
                    .cs = cs,
                    .ce = ce,
                    .start_edge = start_edge,
                    .end_edge = end_edge,
                    .level_n = level};
}

static bool input_valid(const af_strike_pulse_input *in)
{
  return in->x != NULL && in->n >= 1 && in->trigger >= 0 && in->trigger < in->n &&
         in->clean_end >= 1 && in->clean_end <= in->n && in->window >= 1 &&
         isfinite(in->tracker_baseline_n) && in->release_n >= 0.0 && in->noise_rms_n >= 0.0 &&
         in->rise_fit_level > 0.0 && in->rise_fit_level < 1.0 && in->fall_fit_level > 0.0 &&
         in->fall_fit_level < 1.0 && isfinite(in->sample_rate_hz) && in->sample_rate_hz > 0.0 &&
         in->full_scale_n > 0.0;
}

af_status af_strike_pulse_measure(const af_strike_pulse_input *in, double *r, af_strike_pulse *out)
{
  if (in == NULL || r == NULL || out == NULL || !input_valid(in))
    return AF_EINVAL;
  long n = in->n;
  af_span s = {.x = in->x,
               .r = r,
               .n = n,
               .lim = in->clean_end,
               .window = in->window,
               .fallback = in->tracker_baseline_n};
  af_fit_out o;
  measure_span(in, &s, &o);
  double dt = 1.0 / in->sample_rate_hz;
  long k0 = clamp_index((long)ceil(o.t0), n), k1 = clamp_index((long)floor(o.t1), n);
  long c0 = clamp_index(o.cs < k0 ? o.cs : k0, n), c1 = clamp_index(o.ce > k1 ? o.ce : k1, n);
  *out = (af_strike_pulse){.start = o.t0,
                           .end = o.t1,
                           .peak_at = o.peak_at,
                           .peak_n = o.peak_n,
                           .contact_time_s = (o.t1 - o.t0) * dt,
                           .impulse_n_s = integral(r, n, o.t0, o.t1) * dt,
                           .baseline_n = s.b0,
                           .baseline_slope_n = s.slope,
                           .start_edge = o.start_edge,
                           .end_edge = o.end_edge,
                           .edge_level_n = o.level_n,
                           .clipped = clipped(in->x, c0, c1, in->full_scale_n),
                           .coarse_start = o.cs,
                           .coarse_end = o.ce,
                           .first = k0,
                           .n_samples = k1 >= k0 ? (size_t)(k1 - k0 + 1) : 0,
                           .baseline_before_samples = (size_t)s.before,
                           .baseline_after_samples = (size_t)s.after};
  return AF_OK;
}

af_status af_strike_measure_band(af_spectrum *s, const af_strike_event *ev, af_band_level level,
                                 unsigned lobe, af_lobe *band, size_t *lobe_count)
{
  if (s == NULL || ev == NULL || band == NULL || ev->pulse_n == NULL)
    return AF_EINVAL;
  af_status st = af_spectrum_execute(s, ev->pulse_n, ev->n_samples, ev->dt_s);
  if (st != AF_OK)
    return st;
  if (lobe_count != NULL)
    *lobe_count = af_spectrum_lobe_count(s);
  return af_spectrum_lobe(s, lobe, level, band);
}
