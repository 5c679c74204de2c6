/* strike.c — strike detection and measurement in the force stream.
 *
 * Two layers: a per-sample state machine (trackers, trigger, contact end,
 * bounce, emission countdown) that touches a handful of doubles per sample,
 * and the measurement, run once per event on the span copied out of the
 * history ring. Definitions and their reasons are in strike.h. */
#include "strike.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "ring.h"

/* Longest event span accepted [samples] (2^24: 5.6 min at 50 kHz). */
#define AF_STRIKE_MAX_SPAN ((size_t)1 << 24)
/* Samples handled per ring write: the ring holds the longest span plus one
 * block, so an event that completes anywhere inside a block is still whole. */
#define AF_STRIKE_BLOCK ((size_t)1024)
/* A contact is over once the signal stays below the release level this long
 * [s]: one noisy sample under it in the damped tail is not the end. */
#define AF_STRIKE_QUIET_S 1e-4
/* Release level as a fraction of the trigger threshold (hysteresis). */
#define AF_STRIKE_RELEASE 0.5
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
/* af_strike_prime: at most this many samples of the recording (evenly
 * strided) enter the median; the workspace is allocated at create. */
#define AF_STRIKE_PRIME_SAMPLES ((size_t)8192)
/* ... and at least this many quiet ones, else all finite ones are used. */
#define AF_STRIKE_PRIME_MIN 16
/* Normal consistency of the median absolute deviation. */
#define AF_STRIKE_MAD_TO_SIGMA 1.482602218505602
#define AF_STRIKE_PI 3.14159265358979323846

typedef enum {
  AF_PHASE_WARMUP, /* learning the trackers, not armed */
  AF_PHASE_IDLE,   /* armed, trackers following the signal */
  AF_PHASE_CONTACT,
  AF_PHASE_AFTER, /* contact over: watching for a bounce, counting down */
  AF_PHASE_SETTLE /* after a cut event: waiting for quiet before arming */
} af_phase;

/* The event being collected, in running sample indices. */
typedef struct {
  uint64_t begin;           /* first sample of the span: trigger - pre-trigger */
  uint64_t trigger;         /* first sample above threshold */
  uint64_t contact_trigger; /* trigger of the current contact (first or bounce) */
  bool ended;               /* the first contact ended (end is valid) */
  uint64_t end;             /* first quiet sample after the first contact */
  uint64_t last_end;        /* same, for the last contact */
  bool double_hit;
  uint64_t bounce; /* trigger of the first bounce (when double_hit) */
  bool truncated;
  uint64_t lost; /* samples lost in a gap that cut the event */
  size_t quiet;  /* consecutive samples below release */
  double baseline_n, noise_rms_n, threshold_n, release_n; /* frozen at the trigger */
} af_pending;

/* What the detector saw, for af_strike_get_diagnosis: counts since the
 * stream started, largest excursions since then or the last strike. */
typedef struct {
  uint64_t strikes, samples;
  bool armed_ever;
  uint64_t armed_at;    /* first sample armed after the last warm-up */
  double arm_threshold; /* threshold when it armed [N] */
  double warm_max;      /* largest excursion in the warm-up [N] (-inf: none) */
  uint64_t warm_at;
  double idle_max, idle_ms; /* largest armed excursion, mean square then */
  uint64_t idle_at;
  double settle_max, settle_threshold; /* largest while waiting for quiet */
  uint64_t settle_at;
} af_record;

struct af_strike {
  af_strike_config cfg;
  /* derived sample counts */
  size_t pre, post, window, gap, max_contact, quiet_needed, warmup, span_cap;
  double alpha;   /* tracker weight per sample, 1 - exp(-1 / (tau fs)) */
  double factor2; /* threshold_noise_factor^2 */
  af_ring *ring;  /* raw history */
  float *span_f;  /* span read from the ring */
  double *x;      /* span, raw [N] */
  double *r;      /* span, baseline removed [N] */
  /* stream */
  bool started;
  uint64_t next; /* index expected next */
  af_phase phase;
  double baseline_n;  /* tracker: offset and drift */
  double mean_square; /* tracker: mean square of the residual [N^2] */
  size_t learned;     /* samples learned since the trackers restarted */
  size_t quiet;       /* SETTLE: consecutive quiet samples */
  uint64_t settle_since;
  uint64_t stream_first; /* first sample of the stream: no span reaches before it */
  bool primed;           /* trackers set by af_strike_prime for this stream */
  double *prime_ws;      /* af_strike_prime's sample of the recording */
  af_record rec;
  af_pending ev;
  af_strike_event out;
};

#include "af_defaults.h" /* the parameter table's defaults (issue 16) */
af_strike_config af_strike_config_default(void)
{
  return (af_strike_config){.sample_rate_hz = AF_DEFAULT_FORCE_SAMPLE_RATE_HZ,
                            .full_scale_n = AF_DEFAULT_STRIKE_FULL_SCALE_N,
                            .threshold_noise_factor = AF_DEFAULT_STRIKE_THRESHOLD_NOISE_FACTOR,
                            .threshold_min_n = AF_DEFAULT_STRIKE_THRESHOLD_MIN_N,
                            .pre_trigger_s = AF_DEFAULT_STRIKE_PRE_TRIGGER_S,
                            .baseline_time_constant_s = AF_DEFAULT_STRIKE_BASELINE_TIME_CONSTANT_S,
                            .baseline_window_s = AF_DEFAULT_STRIKE_BASELINE_WINDOW_S,
                            .double_hit_gap_s = AF_DEFAULT_STRIKE_DOUBLE_HIT_GAP_S,
                            .max_contact_s = AF_DEFAULT_STRIKE_MAX_CONTACT_S,
                            .post_s = AF_DEFAULT_STRIKE_POST_S,
                            .rise_fit_level = AF_DEFAULT_STRIKE_RISE_FIT_LEVEL,
                            .fall_fit_level = AF_DEFAULT_STRIKE_FALL_FIT_LEVEL};
}

/* ------------------------------------------------------------------------ */
/* configuration */

static bool positive(double v)
{
  return isfinite(v) && v > 0.0;
}

static bool fraction(double v)
{
  return isfinite(v) && v > 0.0 && v < 1.0;
}

/* Duration [s] -> samples, rounded up; 0 when beyond the span limit. */
static size_t samples_of(double seconds, double rate_hz)
{
  double n = ceil(seconds * rate_hz - 1e-9);
  return n >= 0.0 && n <= (double)AF_STRIKE_MAX_SPAN ? (size_t)n : 0;
}

static bool config_valid(const af_strike_config *c)
{
  return positive(c->sample_rate_hz) && positive(c->full_scale_n) &&
         positive(c->threshold_noise_factor) && isfinite(c->threshold_min_n) &&
         c->threshold_min_n >= 0.0 && positive(c->pre_trigger_s) &&
         positive(c->baseline_time_constant_s) && positive(c->baseline_window_s) &&
         isfinite(c->double_hit_gap_s) && c->double_hit_gap_s >= 0.0 &&
         positive(c->max_contact_s) && positive(c->post_s) &&
         c->pre_trigger_s > c->baseline_window_s && c->post_s > c->baseline_window_s &&
         c->post_s >= c->double_hit_gap_s && fraction(c->rise_fit_level) &&
         fraction(c->fall_fit_level);
}

/* Sample counts of a valid config; false when one is 0 or the span too long. */
static bool derive_counts(af_strike *d)
{
  const af_strike_config *c = &d->cfg;
  double fs = c->sample_rate_hz;
  d->pre = samples_of(c->pre_trigger_s, fs);
  d->post = samples_of(c->post_s, fs);
  d->window = samples_of(c->baseline_window_s, fs);
  d->gap = samples_of(c->double_hit_gap_s, fs);
  d->max_contact = samples_of(c->max_contact_s, fs);
  d->warmup = samples_of(c->baseline_time_constant_s, fs);
  d->quiet_needed = samples_of(AF_STRIKE_QUIET_S, fs);
  if (d->quiet_needed < 2)
    d->quiet_needed = 2;
  if (d->pre < 2 || d->post < 2 || d->window < 1 || d->max_contact < 2 || d->warmup < 1 ||
      d->pre <= d->window || d->post <= d->window)
    return false;
  /* One contact and one bounce of the longest kind, the gap between them. */
  double span = (double)d->pre + 2.0 * (double)d->max_contact + (double)d->gap + (double)d->post;
  if (span > (double)AF_STRIKE_MAX_SPAN)
    return false;
  d->span_cap = (size_t)span;
  d->alpha = -expm1(-1.0 / (c->baseline_time_constant_s * fs));
  d->factor2 = c->threshold_noise_factor * c->threshold_noise_factor;
  return true;
}

af_status af_strike_create(const af_strike_config *cfg, af_strike **out)
{
  if (out == NULL)
    return AF_EINVAL;
  *out = NULL;
  if (cfg == NULL || !config_valid(cfg))
    return AF_EINVAL;
  af_strike *d = calloc(1, sizeof *d);
  if (d == NULL)
    return AF_ENOMEM;
  d->cfg = *cfg;
  if (!derive_counts(d)) {
    free(d);
    return AF_EINVAL;
  }
  af_status st = af_ring_create(d->span_cap + AF_STRIKE_BLOCK, &d->ring);
  d->span_f = malloc(d->span_cap * sizeof *d->span_f);
  d->x = malloc(d->span_cap * sizeof *d->x);
  d->r = malloc(d->span_cap * sizeof *d->r);
  d->prime_ws = malloc(AF_STRIKE_PRIME_SAMPLES * sizeof *d->prime_ws);
  if (st != AF_OK || d->span_f == NULL || d->x == NULL || d->r == NULL || d->prime_ws == NULL) {
    af_strike_destroy(d);
    return AF_ENOMEM;
  }
  af_strike_reset(d);
  *out = d;
  return AF_OK;
}

void af_strike_destroy(af_strike *d)
{
  if (d == NULL)
    return;
  af_ring_destroy(d->ring);
  free(d->span_f);
  free(d->x);
  free(d->r);
  free(d->prime_ws);
  free(d);
}

/* Forgets the largest excursions (at a strike, or when the stream starts). */
static void clear_maxima(af_record *rec)
{
  rec->warm_max = rec->idle_max = rec->settle_max = -INFINITY;
  rec->warm_at = rec->idle_at = rec->settle_at = 0;
  rec->idle_ms = rec->settle_threshold = 0.0;
}

/* Trackers forget everything and learn again (running means first). */
static void restart_trackers(af_strike *d)
{
  d->phase = AF_PHASE_WARMUP;
  d->learned = 0;
  d->baseline_n = 0.0;
  d->mean_square = 0.0;
  d->primed = false;
  d->rec.armed_ever = false;
}

void af_strike_reset(af_strike *d)
{
  if (d == NULL)
    return;
  af_ring_reset(d->ring);
  d->started = false;
  d->next = 0;
  d->stream_first = 0;
  memset(&d->rec, 0, sizeof d->rec);
  clear_maxima(&d->rec);
  restart_trackers(d);
  memset(&d->ev, 0, sizeof d->ev);
}

static double threshold_now(const af_strike *d)
{
  double t = d->cfg.threshold_noise_factor * sqrt(d->mean_square);
  return t > d->cfg.threshold_min_n ? t : d->cfg.threshold_min_n;
}

void af_strike_get_tracker(const af_strike *d, af_strike_tracker *out)
{
  if (d == NULL || out == NULL)
    return;
  *out = (af_strike_tracker){.armed = d->phase != AF_PHASE_WARMUP && d->phase != AF_PHASE_SETTLE,
                             .baseline_n = d->baseline_n,
                             .noise_rms_n = sqrt(d->mean_square),
                             .threshold_n = threshold_now(d),
                             .next_sample = d->next};
}

/* ------------------------------------------------------------------------ */
/* measurement: spans indexed from 0, long for windows that run off the ends */

/* Mean and centre of the finite samples of x in [lo, hi) (clipped to
 * [0, n)); returns their count (fewer than AF_STRIKE_MIN_WINDOW: 0, the
 * window is not used). */
static long window_mean(const double *x, long n, long lo, long hi, double *mean, double *centre)
{
  double sum = 0.0, at = 0.0;
  long count = 0;
  for (long k = lo < 0 ? 0 : lo; k < hi && k < n; k++) {
    if (isfinite(x[k])) {
      sum += x[k];
      at += (double)k;
      count++;
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
  for (long k = 0; k < s->n; k++)
    s->r[k] = s->x[k] - (s->b0 + s->slope * (double)k);
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
} af_edge;

/* Residual sum of squares of the best edge law with its zero at z (the
 * coefficients eliminated by linear least squares); +inf when singular. */
static double edge_rss(const af_edge *e, double z)
{
  double a[AF_STRIKE_MAX_TERMS][AF_STRIKE_MAX_TERMS] = {{0}};
  double b[AF_STRIKE_MAX_TERMS] = {0}, c[AF_STRIKE_MAX_TERMS];
  double yy = 0.0;
  for (long k = e->lo; k <= e->hi; k++) {
    double y = e->r[k];
    yy += y * y;
    double s = (double)e->side * ((double)k - z) * e->scale;
    if (s <= 0.0)
      continue;
    double s2 = s * s;
    const double phi[AF_STRIKE_EDGE_TERMS] = {s * sqrt(s), s2 * s2};
    for (size_t i = 0; i < AF_STRIKE_EDGE_TERMS; i++) {
      b[i] += phi[i] * y;
      for (size_t j = 0; j <= i; j++)
        a[i][j] += phi[i] * phi[j];
    }
  }
  a[0][1] = a[1][0];
  if (!solve_spd(a, b, AF_STRIKE_EDGE_TERMS, c))
    return INFINITY;
  return yy - (c[0] * b[0] + c[1] * b[1]);
}

/* Golden-section minimum of edge_rss on [a, b]. */
static double edge_golden(const af_edge *e, double a, double b)
{
  const double g = 0.6180339887498949;
  double u = b - g * (b - a), v = a + g * (b - a);
  double fu = edge_rss(e, u), fv = edge_rss(e, v);
  while (b - a > e->tol) {
    if (fu < fv) {
      b = v;
      v = u;
      fv = fu;
      u = b - g * (b - a);
      fu = edge_rss(e, u);
    } else {
      a = u;
      u = v;
      fu = fv;
      v = a + g * (b - a);
      fv = edge_rss(e, v);
    }
  }
  return 0.5 * (a + b);
}

/* Zero of the edge law fitted to r[lo..hi], searched in [zlo, zhi]; the
 * fallback when the window is too short or no fit exists. */
static double fit_edge(const af_edge *e, double zlo, double zhi, double fallback)
{
  if (e->hi - e->lo + 1 < AF_STRIKE_EDGE_TERMS + 2 || !(zhi > zlo))
    return fallback;
  double best = NAN, best_rss = INFINITY;
  long steps = (long)floor((zhi - zlo) / AF_STRIKE_EDGE_STEP);
  for (long i = 0; i <= steps; i++) {
    double z = zlo + (double)i * AF_STRIKE_EDGE_STEP, rss = edge_rss(e, z);
    if (rss < best_rss) {
      best_rss = rss;
      best = z;
    }
  }
  if (!isfinite(best_rss))
    return fallback;
  double a = fmax(zlo, best - AF_STRIKE_EDGE_STEP), b = fmin(zhi, best + AF_STRIKE_EDGE_STEP);
  return edge_golden(e, a, b);
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

/* Band-limited reconstruction of r at t [samples]: Hann-windowed sinc over
 * AF_STRIKE_SINC_HALF samples each side, r taken as 0 outside [0, n) (it is
 * baseline-removed). Equals r[k] at an integer t = k. */
static double sinc_at(const double *r, long n, double t)
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
  return best;
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
    for (int i = 0; i < AF_STRIKE_PEAK_TERMS; i++) {
      t[i] += r[k] * pw[i];
      for (int j = 0; j < AF_STRIKE_PEAK_TERMS; j++)
        m[i][j] += pw[i] * pw[j];
    }
  }
  if (!solve_spd(m, t, AF_STRIKE_PEAK_TERMS, c))
    return top;
  double ulo = (double)(lo - ipk) / w, uhi = (double)(hi - ipk) / w, du = AF_STRIKE_PEAK_STEP / w;
  double best = -INFINITY, ub = 0.0, v, d1, d2;
  long steps = (long)floor((uhi - ulo) / du);
  for (long i = 0; i <= steps; i++) {
    double u = ulo + (double)i * du;
    poly_eval(c, u, &v, &d1, &d2);
    if (v > best) {
      best = v;
      ub = u;
    }
  }
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
 * samples k and k + 1, which straddle it (bisection to AF_STRIKE_EDGE_TOL:
 * the reconstruction passes through both samples, so a crossing exists). */
static double level_crossing(const double *r, long n, long k, double level)
{
  double a = (double)k, b = (double)(k + 1);
  bool a_below = r[k] <= level;
  while (b - a > AF_STRIKE_EDGE_TOL) {
    double m = 0.5 * (a + b);
    if ((sinc_at(r, n, m) <= level) == a_below)
      a = m;
    else
      b = m;
  }
  return 0.5 * (a + b);
}

/* Crossings of `level` around the largest sample ipk: *t0 between the last
 * sample at or below it before ipk and the next, *t1 likewise after ipk
 * (the outermost sample when the span ends above it). Returns the number
 * of samples above it (0 when r[ipk] is not). */
static long level_edges(const double *r, long n, long ipk, double level, double *t0, double *t1)
{
  if (!(r[ipk] > level))
    return 0;
  long lo = ipk, hi = ipk;
  while (lo > 0 && r[lo - 1] > level)
    lo--;
  while (hi < n - 1 && r[hi + 1] > level)
    hi++;
  *t0 = lo > 0 ? level_crossing(r, n, lo - 1, level) : (double)lo;
  *t1 = hi < n - 1 ? level_crossing(r, n, hi, level) : (double)hi;
  return hi - lo + 1;
}

/* Result of the two baseline/fit passes, span-relative. */
typedef struct {
  double t0, t1, peak_n, peak_at;
  long cs, ce; /* coarse contact: first sample, first sample after */
  af_strike_edges start_edge, end_edge;
  double level_n; /* the level of the crossings */
} af_fit_out;

/* Coarse contact, then two passes of baseline removal and edge fits. */
static void measure_span(const af_strike *d, af_span *s, long trigger, long ce, af_fit_out *o)
{
  const af_pending *ev = &d->ev;
  long cs = trigger;
  while (cs > 0 && s->x[cs - 1] - ev->baseline_n > ev->release_n)
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
    level = fmax(AF_STRIKE_LEVEL_NOISE * ev->noise_rms_n, AF_STRIKE_LEVEL_FRACTION * peak_n);
    double l0 = 0.0, l1 = 0.0;
    long above = level_edges(s->r, s->n, ipk, level, &l0, &l1);
    bool crossed = above > 0 && l1 > l0;
    start_edge = end_edge = AF_STRIKE_EDGES_LEVEL;
    if (crossed && above < AF_STRIKE_SHORT_SAMPLES) {
      t0 = l0;
      t1 = l1;
    } else {
      double tol = pass == 0 ? AF_STRIKE_EDGE_TOL_COARSE : AF_STRIKE_EDGE_TOL;
      t0 = fit_start(s, a - reach, ipk, d->cfg.rise_fit_level * peak_n, NAN, tol);
      t1 = fit_end(s, e - 1 + reach, ipk, d->cfg.fall_fit_level * peak_n, NAN, tol);
      /* No fit (too few samples), a fitted zero on the wrong side of its
       * level crossing or further out than any plausible foot: the fit
       * failed, the crossing stands (the coarse contact without one). */
      double out = AF_STRIKE_FIT_GAP * (l1 - l0) + 1.0;
      if (crossed && !(t0 <= l0 + AF_STRIKE_FIT_SLACK && t0 >= l0 - out)) {
        t0 = l0;
      } else {
        start_edge = AF_STRIKE_EDGES_FIT;
        t0 = isnan(t0) ? (double)a : t0;
      }
      if (crossed && !(t1 >= l1 - AF_STRIKE_FIT_SLACK && t1 <= l1 + out)) {
        t1 = l1;
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

/* Fills d->out from the span [d->ev.begin, end) of the ring; false when the
 * ring does not hold it (cannot happen while the sizes hold). */
static bool measure(af_strike *d, uint64_t end)
{
  af_pending *ev = &d->ev;
  uint64_t begin = ev->begin < af_ring_begin(d->ring) ? af_ring_begin(d->ring) : ev->begin;
  if (end <= begin || end - begin > d->span_cap ||
      af_ring_read(d->ring, begin, (size_t)(end - begin), d->span_f) != AF_OK)
    return false;
  long n = (long)(end - begin);
  uint64_t lost = ev->lost + (begin - ev->begin);
  for (long k = 0; k < n; k++) {
    d->x[k] = d->span_f[k];
    lost += !isfinite(d->x[k]);
  }
  long ce = ev->ended ? (long)(ev->end - begin) : n;
  af_span s = {.x = d->x,
               .r = d->r,
               .n = n,
               .lim = ev->double_hit ? (long)(ev->bounce - begin) : n,
               .window = (long)d->window,
               .fallback = ev->baseline_n};
  af_fit_out o;
  measure_span(d, &s, (long)(ev->trigger - begin), ce, &o);
  double dt = 1.0 / d->cfg.sample_rate_hz;
  long k0 = clamp_index((long)ceil(o.t0), n), k1 = clamp_index((long)floor(o.t1), n);
  long c0 = clamp_index(o.cs < k0 ? o.cs : k0, n), c1 = clamp_index(o.ce > k1 ? o.ce : k1, n);
  double b = (double)begin;
  d->out = (af_strike_event){.start_sample = b + o.t0,
                             .end_sample = b + o.t1,
                             .peak_sample = b + o.peak_at,
                             .contact_time_s = (o.t1 - o.t0) * dt,
                             .peak_force_n = o.peak_n,
                             .impulse_n_s = integral(d->r, n, o.t0, o.t1) * dt,
                             .baseline_n = s.b0 + s.slope * o.t0,
                             .noise_rms_n = ev->noise_rms_n,
                             .threshold_n = ev->threshold_n,
                             .trigger_sample = ev->trigger,
                             .double_hit = ev->double_hit,
                             .clipped = clipped(d->x, c0, c1, d->cfg.full_scale_n),
                             .truncated = ev->truncated,
                             .lost_samples = lost,
                             .pulse_n = d->r + k0,
                             .n_samples = k1 >= k0 ? (size_t)(k1 - k0 + 1) : 0,
                             .dt_s = dt,
                             .pulse_first_sample = begin + (uint64_t)k0,
                             .pulse_t0_s = (o.t0 - (double)k0) * dt,
                             .start_edge = o.start_edge,
                             .end_edge = o.end_edge,
                             .edge_level_n = o.level_n,
                             .baseline_before_samples = (size_t)s.before,
                             .baseline_after_samples = (size_t)s.after,
                             .primed = d->primed};
  return true;
}

/* ------------------------------------------------------------------------ */
/* per-sample state machine */

/* Measures the pending event over [begin, end) and hands it to fn. */
static void emit(af_strike *d, uint64_t end, af_strike_fn *fn, void *user)
{
  if (!measure(d, end))
    return;
  d->rec.strikes++;
  clear_maxima(&d->rec);
  if (fn != NULL)
    fn(&d->out, user);
}

/* The warm-up is over at sample `at`: armed from the next one. */
static void arm(af_strike *d, uint64_t at)
{
  d->phase = AF_PHASE_IDLE;
  d->rec.armed_ever = true;
  d->rec.armed_at = at + 1;
  d->rec.arm_threshold = threshold_now(d);
}

/* One sample into the trackers: running means until the warm-up is done
 * (fast, unbiased start), then the exponential average. */
static void learn(af_strike *d, double x)
{
  double a = d->alpha;
  if (d->learned < d->warmup) {
    d->learned++;
    double mean_weight = 1.0 / (double)d->learned;
    a = mean_weight > a ? mean_weight : a;
  }
  d->baseline_n += a * (x - d->baseline_n);
  double e = x - d->baseline_n;
  d->mean_square += a * (e * e - d->mean_square);
}

static void trigger(af_strike *d, uint64_t at)
{
  af_pending *ev = &d->ev;
  double thr = threshold_now(d);
  uint64_t first = d->stream_first; /* the span never reaches before the stream */
  *ev = (af_pending){.begin = at > first + d->pre ? at - d->pre : first,
                     .trigger = at,
                     .contact_trigger = at,
                     .baseline_n = d->baseline_n,
                     .noise_rms_n = sqrt(d->mean_square),
                     .threshold_n = thr,
                     .release_n = AF_STRIKE_RELEASE * thr};
  d->phase = AF_PHASE_CONTACT;
}

static void settle(af_strike *d, uint64_t from)
{
  d->phase = AF_PHASE_SETTLE;
  d->quiet = 0;
  d->settle_since = from;
}

/* The armed idle state over x[0..n) (x[0] has index at): the trackers in
 * registers, one multiply-add per tracker and sample (this loop is nearly
 * all of the streaming cost). Returns the samples consumed: n, or up to and
 * including the one that triggered. */
static size_t idle_run(af_strike *d, uint64_t at, const float *x, size_t n)
{
  const double a = d->alpha, keep = 1.0 - d->alpha, min_n = d->cfg.threshold_min_n;
  const double factor2 = d->factor2;
  double b = d->baseline_n, ms = d->mean_square;
  double top = d->rec.idle_max, top_ms = d->rec.idle_ms; /* diagnosis */
  size_t k = 0, top_k = n;
  for (; k < n; k++) {
    double v = x[k], r = v - b;
    if (r > top) {
      top = r;
      top_ms = ms;
      top_k = k;
    }
    if (r > min_n && r * r > factor2 * ms)
      break;
    if (!isfinite(v))
      continue; /* a lost sample teaches nothing */
    b = keep * b + a * v;
    double e = v - b;
    ms = keep * ms + a * e * e;
  }
  d->baseline_n = b;
  d->mean_square = ms;
  if (top_k < n) {
    d->rec.idle_max = top;
    d->rec.idle_ms = top_ms;
    d->rec.idle_at = at + top_k;
  }
  if (k == n)
    return n;
  trigger(d, at + k);
  return k + 1;
}

/* Cut the event: emitted now with what the span holds. */
static void cut(af_strike *d, uint64_t end, af_strike_fn *fn, void *user)
{
  d->ev.truncated = true;
  emit(d, end, fn, user);
}

static void step_contact(af_strike *d, uint64_t at, double x, af_strike_fn *fn, void *user)
{
  af_pending *ev = &d->ev;
  double r = x - ev->baseline_n;
  if (r < ev->release_n) {
    if (++ev->quiet >= d->quiet_needed) {
      uint64_t end = at + 1 - ev->quiet;
      if (!ev->ended) {
        ev->ended = true;
        ev->end = end;
      }
      ev->last_end = end;
      d->phase = AF_PHASE_AFTER;
    }
  } else {
    ev->quiet = 0;
  }
  if (d->phase == AF_PHASE_CONTACT && at - ev->contact_trigger >= d->max_contact) {
    /* Too long for a strike (a step in the offset, the hammer resting):
     * reported, then the trackers learn the new level. */
    cut(d, at + 1, fn, user);
    restart_trackers(d);
  } else if (d->phase == AF_PHASE_CONTACT && at + 1 - ev->begin >= d->span_cap) {
    cut(d, at + 1, fn, user);
    settle(d, at + 1);
  }
}

static void step_after(af_strike *d, uint64_t at, double x, af_strike_fn *fn, void *user)
{
  af_pending *ev = &d->ev;
  double r = x - ev->baseline_n;
  if (r > ev->threshold_n) {
    if (at - ev->last_end <= d->gap && at + 1 - ev->begin < d->span_cap) {
      if (!ev->double_hit)
        ev->bounce = at;
      ev->double_hit = true;
      ev->contact_trigger = at;
      ev->quiet = 0;
      d->phase = AF_PHASE_CONTACT;
    } else { /* a new strike: this one ends where it starts */
      emit(d, at, fn, user);
      trigger(d, at);
    }
  } else if (at + 1 - ev->last_end >= d->post || at + 1 - ev->begin >= d->span_cap) {
    emit(d, at + 1, fn, user);
    d->phase = AF_PHASE_IDLE;
  }
}

static void step_settle(af_strike *d, uint64_t at, double x)
{
  double r = x - d->baseline_n, thr = threshold_now(d);
  if (r > d->rec.settle_max) {
    d->rec.settle_max = r;
    d->rec.settle_at = at;
    d->rec.settle_threshold = thr;
  }
  if (r < AF_STRIKE_RELEASE * thr) {
    if (++d->quiet >= d->quiet_needed)
      d->phase = AF_PHASE_IDLE;
  } else {
    d->quiet = 0;
  }
  if (d->phase == AF_PHASE_SETTLE && at - d->settle_since >= d->max_contact)
    restart_trackers(d); /* never quiet again: the level moved */
}

/* One sample in any state but IDLE. */
static void step(af_strike *d, uint64_t at, double x, af_strike_fn *fn, void *user)
{
  switch (d->phase) {
  case AF_PHASE_WARMUP:
    if (isfinite(x)) {
      double r = d->learned > 0 ? x - d->baseline_n : 0.0; /* against what came before */
      learn(d, x);
      if (r > d->rec.warm_max) {
        d->rec.warm_max = r;
        d->rec.warm_at = at;
      }
      if (d->learned >= d->warmup)
        arm(d, at);
    }
    break;
  case AF_PHASE_IDLE: break; /* idle_run's */
  case AF_PHASE_CONTACT: step_contact(d, at, x, fn, user); break;
  case AF_PHASE_AFTER: step_after(d, at, x, fn, user); break;
  case AF_PHASE_SETTLE: step_settle(d, at, x); break;
  }
}

/* x[0..n) through the state machine, idle stretches in idle_run. */
static void process(af_strike *d, uint64_t at, const float *x, size_t n, af_strike_fn *fn,
                    void *user)
{
  size_t k = 0;
  while (k < n) {
    if (d->phase == AF_PHASE_IDLE) {
      k += idle_run(d, at + k, x + k, n - k);
    } else {
      step(d, at + k, x[k], fn, user);
      k++;
    }
  }
}

static bool in_event(const af_strike *d)
{
  return d->phase == AF_PHASE_CONTACT || d->phase == AF_PHASE_AFTER;
}

/* first_sample is not d->next: a gap (lost samples) or a restarted stream.
 * An event in progress is emitted from what the ring holds, before the
 * chunk is written. */
static void discontinuity(af_strike *d, uint64_t first_sample, af_strike_fn *fn, void *user)
{
  if (first_sample < d->next) { /* restarted stream */
    if (in_event(d))
      cut(d, d->next, fn, user);
    af_strike_reset(d);
    return;
  }
  uint64_t gap = first_sample - d->next;
  bool was_in_event = in_event(d);
  if (was_in_event) {
    d->ev.lost += gap;
    if (d->phase == AF_PHASE_CONTACT)
      d->ev.truncated = true;
    emit(d, d->next, fn, user);
  }
  if (gap > (uint64_t)d->warmup)
    restart_trackers(d); /* longer than the trackers remember */
  else if (was_in_event || d->phase == AF_PHASE_SETTLE)
    settle(d, first_sample);
}

af_status af_strike_write(af_strike *d, uint64_t first_sample, const float *x, size_t n,
                          af_strike_fn *fn, void *user)
{
  if (d == NULL || (x == NULL && n > 0) || first_sample > ((uint64_t)1 << 63) ||
      (uint64_t)n > ((uint64_t)1 << 63) - first_sample)
    return AF_EINVAL;
  if (n == 0)
    return AF_OK;
  if (d->started && first_sample != d->next)
    discontinuity(d, first_sample, fn, user);
  if (!d->started) {
    d->started = true;
    d->next = first_sample;
    d->stream_first = first_sample;
    if (d->primed)
      d->rec.armed_at = first_sample; /* armed from the first sample written */
  }
  d->rec.samples += n;
  for (size_t done = 0; done < n;) {
    size_t block = n - done < AF_STRIKE_BLOCK ? n - done : AF_STRIKE_BLOCK;
    uint64_t at = first_sample + done;
    (void)af_ring_write(d->ring, x + done, block, at, NULL); /* fails on bad arguments only */
    process(d, at, x + done, block, fn, user);
    done += block;
  }
  d->next = first_sample + n;
  return AF_OK;
}

af_status af_strike_flush(af_strike *d, af_strike_fn *fn, void *user)
{
  if (d == NULL)
    return AF_EINVAL;
  if (d->phase == AF_PHASE_CONTACT) {
    cut(d, d->next, fn, user);
    settle(d, d->next);
  } else if (d->phase == AF_PHASE_AFTER) {
    emit(d, d->next, fn, user);
    d->phase = AF_PHASE_IDLE;
  }
  return AF_OK;
}

/* ------------------------------------------------------------------------ */
/* priming from a whole recording */

static void swap(double *a, double *b)
{
  double t = *a;
  *a = *b;
  *b = t;
}

/* The k-th smallest of v[0..n) (k < n), v reordered in place (Wirth's
 * selection). No allocation (qsort may allocate). */
static double select_kth(double *v, size_t n, size_t k)
{
  long lo = 0, hi = (long)n - 1, kk = (long)k;
  while (lo < hi) {
    double pivot = v[kk];
    long i = lo, j = hi;
    do {
      while (v[i] < pivot)
        i++;
      while (pivot < v[j])
        j--;
      if (i <= j) {
        swap(&v[i], &v[j]);
        i++;
        j--;
      }
    } while (i <= j);
    if (j < kk)
      lo = i;
    if (kk < i)
      hi = j;
  }
  return v[kk];
}

/* Median of v[0..n), n > 0 (the lower one for an even n); v reordered. */
static double median(double *v, size_t n)
{
  return select_kth(v, n, (n - 1) / 2);
}

/* Every stride-th finite sample of x[0..n) into ws, leaving out those within
 * `guard` samples of a loud one (|x - centre| > loud; none when loud is
 * +inf). Returns the count. */
static size_t prime_gather(const float *x, size_t n, size_t stride, double centre, double loud,
                           size_t guard, double *ws)
{
  size_t m = 0, scanned = 0;
  bool any_loud = false;
  size_t last_loud = 0; /* the latest loud sample before `scanned` */
  for (size_t k = 0; k < n && m < AF_STRIKE_PRIME_SAMPLES; k += stride) {
    size_t ahead = n - k > guard ? k + guard + 1 : n;
    for (; scanned < ahead; scanned++) {
      if (fabs((double)x[scanned] - centre) > loud) {
        any_loud = true;
        last_loud = scanned;
      }
    }
    if (any_loud && last_loud + guard >= k)
      continue; /* a loud sample within guard of k, before or after */
    if (isfinite(x[k]))
      ws[m++] = x[k];
  }
  return m;
}

af_status af_strike_prime(af_strike *d, const float *x, size_t n)
{
  if (d == NULL || (x == NULL && n > 0))
    return AF_EINVAL;
  size_t stride = n / AF_STRIKE_PRIME_SAMPLES + (n % AF_STRIKE_PRIME_SAMPLES != 0);
  size_t m = n > 0 ? prime_gather(x, n, stride, 0.0, INFINITY, 0, d->prime_ws) : 0;
  if (m < AF_STRIKE_PRIME_MIN)
    return AF_ENODATA; /* the detector is left as it was */
  /* First pass, all finite samples: median and MAD. */
  double centre = median(d->prime_ws, m);
  for (size_t i = 0; i < m; i++)
    d->prime_ws[i] = fabs(d->prime_ws[i] - centre);
  double sigma = AF_STRIKE_MAD_TO_SIGMA * median(d->prime_ws, m);
  /* Second pass, the quiet parts: away from every sample beyond the release
   * level the first pass gives (strikes, bounces, their ringing). */
  double thr = fmax(d->cfg.threshold_noise_factor * sigma, d->cfg.threshold_min_n);
  size_t guard = d->window + d->quiet_needed;
  size_t q = prime_gather(x, n, stride, centre, AF_STRIKE_RELEASE * thr, guard, d->prime_ws);
  double baseline = centre, mean_square = sigma * sigma;
  if (q >= AF_STRIKE_PRIME_MIN && 4 * q >= m) { /* else too little quiet signal: the MAD's */
    baseline = median(d->prime_ws, q);
    double sum2 = 0.0;
    for (size_t i = 0; i < q; i++)
      sum2 += (d->prime_ws[i] - baseline) * (d->prime_ws[i] - baseline);
    mean_square = sum2 / (double)q;
  }
  af_strike_reset(d);
  d->baseline_n = baseline;
  d->mean_square = mean_square;
  d->learned = d->warmup;
  d->primed = true;
  arm(d, 0);
  d->rec.armed_at = 0; /* until the first write says where the stream starts */
  return AF_OK;
}

/* ------------------------------------------------------------------------ */
/* diagnosis */

static bool in_event(const af_strike *d);

void af_strike_get_diagnosis(const af_strike *d, af_strike_diagnosis *out)
{
  if (d == NULL || out == NULL)
    return;
  const af_record *rec = &d->rec;
  double factor = d->cfg.threshold_noise_factor, min_n = d->cfg.threshold_min_n;
  double idle_thr = fmax(factor * sqrt(rec->idle_ms), min_n);
  *out = (af_strike_diagnosis){
      .strikes = rec->strikes,
      .samples = rec->samples,
      .primed = d->primed,
      .armed = d->phase != AF_PHASE_WARMUP && d->phase != AF_PHASE_SETTLE,
      .armed_sample = rec->armed_ever ? rec->armed_at : UINT64_MAX,
      .warmup_samples = (uint64_t)d->warmup,
      .warmup_learned = (uint64_t)(d->learned < d->warmup ? d->learned : d->warmup),
      .arm_threshold_n = rec->armed_ever ? rec->arm_threshold : NAN,
      .warmup_max_n = isfinite(rec->warm_max) ? rec->warm_max : NAN,
      .warmup_max_sample = rec->warm_at,
      .armed_max_n = isfinite(rec->idle_max) ? rec->idle_max : NAN,
      .armed_max_sample = rec->idle_at,
      .armed_max_threshold_n = isfinite(rec->idle_max) ? idle_thr : NAN,
      .settle_max_n = isfinite(rec->settle_max) ? rec->settle_max : NAN,
      .settle_max_sample = rec->settle_at,
      .settle_max_threshold_n = isfinite(rec->settle_max) ? rec->settle_threshold : NAN,
      .pending_trigger_sample = in_event(d) ? d->ev.trigger : 0,
      .threshold_n = threshold_now(d),
      .noise_rms_n = sqrt(d->mean_square)};
  /* The verdict: the state in which the largest excursion came. */
  double w = rec->warm_max, a = rec->idle_max, st = rec->settle_max;
  if (in_event(d))
    out->why = AF_STRIKE_PENDING;
  else if (rec->strikes > 0)
    out->why = AF_STRIKE_FOUND;
  else if (rec->samples == 0)
    out->why = AF_STRIKE_NO_SIGNAL;
  else if (!rec->armed_ever ||
           (w > rec->arm_threshold && w >= a && w >= st)) /* -inf when never seen */
    out->why = AF_STRIKE_IN_WARMUP;
  else if (!isfinite(a) || (st > rec->settle_threshold && st >= a))
    out->why = AF_STRIKE_WAITING_QUIET;
  else
    out->why = AF_STRIKE_BELOW_THRESHOLD;
}

const char *af_strike_why_text(af_strike_why why)
{
  switch (why) {
  case AF_STRIKE_FOUND: return "strike found";
  case AF_STRIKE_NO_SIGNAL: return "no signal";
  case AF_STRIKE_IN_WARMUP: return "still in warm-up";
  case AF_STRIKE_BELOW_THRESHOLD: return "never above threshold";
  case AF_STRIKE_WAITING_QUIET: return "waiting for quiet";
  case AF_STRIKE_PENDING: return "strike still in progress";
  }
  return "unknown";
}

af_status af_strike_explain(const af_strike *d, char *buf, size_t size)
{
  if (d == NULL || buf == NULL || size == 0)
    return AF_EINVAL;
  af_strike_diagnosis g;
  af_strike_get_diagnosis(d, &g);
  const char *why = af_strike_why_text(g.why);
  double fs = d->cfg.sample_rate_hz;
  unsigned long long warm_at = g.warmup_max_sample, armed_at = g.armed_sample;
  int len = 0;
  switch (g.why) {
  case AF_STRIKE_FOUND:
    len = snprintf(buf, size, "%llu strike%s found", (unsigned long long)g.strikes,
                   g.strikes == 1 ? "" : "s");
    break;
  case AF_STRIKE_NO_SIGNAL: len = snprintf(buf, size, "%s: nothing written", why); break;
  case AF_STRIKE_PENDING:
    len = snprintf(buf, size,
                   "%s: triggered at sample %llu, emitted %g s after its contact ends "
                   "(af_strike_flush emits it now)",
                   why, (unsigned long long)g.pending_trigger_sample, d->cfg.post_s);
    break;
  case AF_STRIKE_IN_WARMUP:
    if (g.armed_sample == UINT64_MAX)
      len = snprintf(buf, size,
                     "%s: %llu of the %llu samples (%g s) learned before arming, largest "
                     "excursion %.4g N at sample %llu; prime the detector or start earlier",
                     why, (unsigned long long)g.warmup_learned,
                     (unsigned long long)g.warmup_samples, (double)g.warmup_samples / fs,
                     isfinite(g.warmup_max_n) ? g.warmup_max_n : 0.0, warm_at);
    else
      len = snprintf(buf, size,
                     "%s when the largest excursion came (%.4g N at sample %llu; armed from "
                     "sample %llu, threshold %.4g N then); prime the detector or start "
                     "earlier",
                     why, g.warmup_max_n, warm_at, armed_at, g.arm_threshold_n);
    break;
  case AF_STRIKE_WAITING_QUIET:
    len = snprintf(buf, size,
                   "%s after a cut event when the largest excursion came (%.4g N at sample "
                   "%llu, threshold %.4g N)",
                   why, isfinite(g.settle_max_n) ? g.settle_max_n : 0.0,
                   (unsigned long long)g.settle_max_sample,
                   isfinite(g.settle_max_threshold_n) ? g.settle_max_threshold_n : g.threshold_n);
    break;
  case AF_STRIKE_BELOW_THRESHOLD:
    len = snprintf(buf, size,
                   "%s: largest excursion %.4g N at sample %llu, threshold %.4g N there "
                   "(max(%g x noise RMS, %g N); noise RMS now %.4g N)",
                   why, g.armed_max_n, (unsigned long long)g.armed_max_sample,
                   g.armed_max_threshold_n, d->cfg.threshold_noise_factor, d->cfg.threshold_min_n,
                   g.noise_rms_n);
    break;
  }
  return len >= 0 && (size_t)len < size ? AF_OK : AF_ESIZE;
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
