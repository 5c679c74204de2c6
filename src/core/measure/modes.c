/* modes.c — the 0S2 among the listed peaks: prior from the fitted modulus,
 * the comb of Lamb ratios, the decision and its one-line text (see modes.h
 * for the rules and their reasoning). */
#include "modes.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>

#define AF_MODES_PI 3.14159265358979323846
/* Partner groups: the 0S3, and the 0S4 with the 1S2 (one peak at the apple's
 * Q). */
#define AF_MODES_GROUPS 2
/* Scores equal within this are a tie (broken by SNR). */
#define AF_MODES_TIE 1e-9

af_modes_config af_modes_config_default(void)
{
  af_modes_config c;
  c.ratio_tolerance = 0.03;
  c.p_heard = 0.5;
  c.random_density = 1.5;
  c.ambiguity_margin = log(4.0);
  c.conflict_sigmas = 3.0;
  c.loudest_margin_db = 6.0;
  return c;
}

const char *af_modes_method_name(af_modes_method method)
{
  switch (method) {
  case AF_MODES_METHOD_NONE: return "none";
  case AF_MODES_METHOD_PRIOR_RATIOS: return "prior+ratios";
  case AF_MODES_METHOD_PRIOR: return "prior";
  case AF_MODES_METHOD_RATIOS: return "ratios";
  case AF_MODES_METHOD_LOUDEST: return "loudest in range";
  }
  return "?";
}

af_status af_modes_list_band(double f_lo_hz, double f_hi_hz, double sample_rate_hz,
                             double *band_lo_hz, double *band_hi_hz)
{
  if (band_lo_hz == NULL || band_hi_hz == NULL || !(f_lo_hz > 0.0) || !(f_hi_hz > f_lo_hz) ||
      !(f_hi_hz < 0.5 * sample_rate_hz) || !isfinite(sample_rate_hz))
    return AF_EINVAL;
  *band_lo_hz = 0.8 * f_lo_hz;
  *band_hi_hz = fmax(f_hi_hz, fmin(2.0 * f_hi_hz, 0.9 * 0.5 * sample_rate_hz));
  return AF_OK;
}

/* ---- arguments ---------------------------------------------------------------- */

static bool config_ok(const af_modes_config *c)
{
  return c->ratio_tolerance > 0.0 && c->ratio_tolerance < 0.2 && c->p_heard > 0.0 &&
         c->p_heard < 1.0 && c->random_density > 0.0 && isfinite(c->random_density) &&
         c->ambiguity_margin > 0.0 && isfinite(c->ambiguity_margin) && c->conflict_sigmas > 0.0 &&
         isfinite(c->conflict_sigmas) && c->loudest_margin_db >= 0.0 &&
         isfinite(c->loudest_margin_db);
}

static bool input_ok(const af_modes_input *in)
{
  if ((in->peaks == NULL && in->n_peaks > 0) || in->modes == NULL)
    return false;
  if (!(in->band_lo_hz > 0.0) || !(in->f_lo_hz >= in->band_lo_hz) || !(in->f_hi_hz > in->f_lo_hz) ||
      !(in->band_hi_hz >= in->f_hi_hz) || !isfinite(in->band_hi_hz))
    return false;
  for (int i = 0; i < AF_MODE_COUNT; ++i)
    if (!(in->modes->ratio[i] > 0.0) || !isfinite(in->modes->ratio[i]))
      return false;
  if (isnan(in->f_pred_hz))
    return true;
  return in->f_pred_hz > 0.0 && isfinite(in->f_pred_hz) && in->f_pred_rel_sd > 0.0 &&
         isfinite(in->f_pred_rel_sd);
}

/* ---- the comb ----------------------------------------------------------------- */

/* What the identification works with, derived once per call. */
typedef struct {
  const af_modes_config *cfg;
  const af_modes_input *in;
  bool prior;                    /* f_pred given */
  double prior_norm;             /* ln(W / (s sqrt(2 pi))) */
  double r_lo[AF_MODES_GROUPS];  /* group ratios, lowest */
  double r_hi[AF_MODES_GROUPS];  /*   and highest */
  double match[AF_MODES_GROUPS]; /* score of a partner found */
  double miss[AF_MODES_GROUPS];  /* score of a checkable partner missing */
} af_comb;

/* One candidate's evidence. */
typedef struct {
  double prior;              /* prior score; 0 without prior */
  double ratio;              /* partner and below scores */
  double z;                  /* ln(f / f_pred) / s; NaN without prior */
  bool evidence;             /* a partner found or a relation below */
  bool partner;              /* a partner found */
  af_sphere_mode looks_like; /* relation below: this peak as that mode... */
  double base_hz;            /*   ...of the peak at base_hz */
} af_evidence;

static void comb_setup(const af_modes_config *cfg, const af_modes_input *in, af_comb *c)
{
  const double *r = in->modes->ratio;
  double tol = cfg->ratio_tolerance;
  c->cfg = cfg;
  c->in = in;
  c->prior = !isnan(in->f_pred_hz);
  c->prior_norm =
      c->prior ? log(log(in->f_hi_hz / in->f_lo_hz) / (in->f_pred_rel_sd * sqrt(2.0 * AF_MODES_PI)))
               : 0.0;
  c->r_lo[0] = c->r_hi[0] = r[AF_MODE_0S3];
  c->r_lo[1] = fmin(r[AF_MODE_0S4], r[AF_MODE_1S2]);
  c->r_hi[1] = fmax(r[AF_MODE_0S4], r[AF_MODE_1S2]);
  for (int g = 0; g < AF_MODES_GROUPS; ++g) {
    double width = log(c->r_hi[g] * (1.0 + tol) / (c->r_lo[g] * (1.0 - tol)));
    double p_random = 1.0 - exp(-cfg->random_density * width);
    c->match[g] = log(cfg->p_heard / p_random);
    c->miss[g] = log((1.0 - cfg->p_heard) / (1.0 - p_random));
  }
}

static double peak_hz(const af_modes_input *in, size_t i)
{
  return in->peaks[i].frequency_hz;
}

static bool in_range(const af_modes_input *in, size_t i)
{
  double f = peak_hz(in, i);
  return f >= in->f_lo_hz && f <= in->f_hi_hz;
}

/* The peak other than 'skip' in [lo, hi] nearest (in ln f) to target;
 * AF_MODES_NO_PEAK if none. */
static size_t find_peak(const af_modes_input *in, double lo, double hi, double target, size_t skip)
{
  size_t best = AF_MODES_NO_PEAK;
  double best_d = INFINITY;
  for (size_t j = 0; j < in->n_peaks; ++j) {
    double f = peak_hz(in, j);
    if (j == skip || !(f >= lo && f <= hi))
      continue;
    double d = fabs(log(f / target));
    if (d < best_d) {
      best_d = d;
      best = j;
    }
  }
  return best;
}

/* Which of the 0S4 and the 1S2 a peak at ratio r to the 0S2 is nearer to. */
static af_sphere_mode group2_mode(const af_modes_input *in, double r)
{
  const double *m = in->modes->ratio;
  return fabs(log(r / m[AF_MODE_0S4])) <= fabs(log(r / m[AF_MODE_1S2])) ? AF_MODE_0S4 : AF_MODE_1S2;
}

/* Scores 1-3 of modes.h for the peak i taken as the 0S2. */
static af_evidence evidence_as_0s2(const af_comb *c, size_t i)
{
  const af_modes_input *in = c->in;
  double f = peak_hz(in, i), tol = c->cfg->ratio_tolerance;
  af_evidence e = {0.0, 0.0, NAN, false, false, AF_MODE_COUNT, NAN};
  if (c->prior) {
    e.z = log(f / in->f_pred_hz) / in->f_pred_rel_sd;
    e.prior = c->prior_norm - 0.5 * e.z * e.z;
  }
  for (int g = 0; g < AF_MODES_GROUPS; ++g) {
    double centre = 0.5 * (c->r_lo[g] + c->r_hi[g]);
    /* above: the partner */
    double lo = f * c->r_lo[g] * (1.0 - tol), hi = f * c->r_hi[g] * (1.0 + tol);
    if (lo >= in->band_lo_hz && hi <= in->band_hi_hz) {
      if (find_peak(in, lo, hi, f * centre, i) != AF_MODES_NO_PEAK) {
        e.ratio += c->match[g];
        e.evidence = e.partner = true;
      } else {
        e.ratio += c->miss[g];
      }
    }
    /* below: this peak as the partner of a lower one */
    size_t j = find_peak(in, f / (c->r_hi[g] * (1.0 + tol)), f / (c->r_lo[g] * (1.0 - tol)),
                         f / centre, i);
    if (j != AF_MODES_NO_PEAK) {
      e.ratio -= c->match[g];
      e.evidence = true;
      if (e.looks_like == AF_MODE_COUNT) {
        e.looks_like = g == 0 ? AF_MODE_0S3 : group2_mode(in, f / peak_hz(in, j));
        e.base_hz = peak_hz(in, j);
      }
    }
  }
  return e;
}

/* ---- the decision ------------------------------------------------------------- */

/* True when candidate a beats b: higher score, ties to the higher SNR. */
static bool beats(const af_modes_input *in, double score_a, size_t a, double score_b, size_t b)
{
  if (b == AF_MODES_NO_PEAK)
    return true;
  if (fabs(score_a - score_b) > AF_MODES_TIE)
    return score_a > score_b;
  return in->peaks[a].snr_db > in->peaks[b].snr_db;
}

/* Score of candidate i under the method: prior + ratios, ratios alone
 * (ratios_only), or 0 (LOUDEST: no evidence). */
static double candidate_score(const af_evidence *e, af_modes_method method, bool ratios_only)
{
  if (method == AF_MODES_METHOD_LOUDEST)
    return 0.0;
  return ratios_only ? e->ratio : e->prior + e->ratio;
}

/* The best candidate by score (ratios_only: the comb's scores alone);
 * LOUDEST: by SNR. */
static size_t best_candidate(const af_comb *c, af_modes_method method, bool ratios_only,
                             double *score)
{
  const af_modes_input *in = c->in;
  size_t best = AF_MODES_NO_PEAK;
  *score = -INFINITY;
  for (size_t i = 0; i < in->n_peaks; ++i) {
    if (!in_range(in, i))
      continue;
    af_evidence e = evidence_as_0s2(c, i);
    double s = candidate_score(&e, method, ratios_only);
    if (beats(in, s, i, *score, best)) {
      best = i;
      *score = s;
    }
  }
  return best;
}

static void add_competing(const af_comb *c, af_modes_id *out, size_t i, double score)
{
  if (out->n_competing >= AF_MODES_MAX_COMPETING)
    return;
  af_evidence e = evidence_as_0s2(c, i);
  af_modes_candidate *k = &out->competing[out->n_competing++];
  k->peak = i;
  k->frequency_hz = peak_hz(c->in, i);
  k->score = score;
  k->looks_like = e.looks_like;
  k->base_hz = e.base_hz;
}

/* The chosen first, then the other candidates 'close' to it (score within the
 * margin, or SNR within the loudest margin for LOUDEST), best first. */
static void name_competitors(const af_comb *c, af_modes_method method, af_modes_id *out,
                             double best_score)
{
  const af_modes_input *in = c->in;
  bool loudest = method == AF_MODES_METHOD_LOUDEST;
  double best_key = loudest ? in->peaks[out->peak].snr_db : best_score;
  size_t top[AF_MODES_MAX_COMPETING - 1], n_top = 0;
  double key[AF_MODES_MAX_COMPETING - 1];
  for (size_t i = 0; i < in->n_peaks; ++i) {
    if (!in_range(in, i) || i == out->peak)
      continue;
    af_evidence e = evidence_as_0s2(c, i);
    double k = loudest ? in->peaks[i].snr_db : candidate_score(&e, method, false);
    bool close = loudest ? best_key - k <= c->cfg->loudest_margin_db
                         : best_key - k < c->cfg->ambiguity_margin;
    if (!close)
      continue;
    /* insertion, best first; the weakest falls off a full list */
    size_t at = n_top;
    while (at > 0 && key[at - 1] < k)
      --at;
    if (at >= AF_MODES_MAX_COMPETING - 1)
      continue;
    size_t end = n_top < AF_MODES_MAX_COMPETING - 1 ? n_top : AF_MODES_MAX_COMPETING - 2;
    for (size_t j = end; j > at; --j) {
      top[j] = top[j - 1];
      key[j] = key[j - 1];
    }
    top[at] = i;
    key[at] = k;
    if (n_top < AF_MODES_MAX_COMPETING - 1)
      ++n_top;
  }
  add_competing(c, out, out->peak, best_score);
  for (size_t j = 0; j < n_top; ++j)
    add_competing(c, out, top[j], loudest ? 0.0 : key[j]);
}

/* posterior of the chosen: exp(L_best) / (1 + sum exp(L_i)) */
static double confidence_of(const af_comb *c, af_modes_method method, double best_score)
{
  const af_modes_input *in = c->in;
  double top = fmax(0.0, best_score), sum = exp(-top);
  for (size_t i = 0; i < in->n_peaks; ++i) {
    if (!in_range(in, i))
      continue;
    af_evidence e = evidence_as_0s2(c, i);
    sum += exp(candidate_score(&e, method, false) - top);
  }
  return exp(best_score - top) / sum;
}

/* The modes of the chosen 0S2 heard: the 0S2, then for each other mode the
 * peak nearest its ratio within the tolerance (a peak claimed by both the
 * 0S4 and the 1S2 goes to the nearer), sorted by frequency. */
static void fill_matched(const af_comb *c, af_modes_id *out)
{
  const af_modes_input *in = c->in;
  double f = out->frequency_hz, tol = c->cfg->ratio_tolerance;
  size_t at[AF_MODE_COUNT];
  for (int m = 0; m < AF_MODE_COUNT; ++m) {
    double target = f * in->modes->ratio[m];
    at[m] = m == AF_MODE_0S2
                ? out->peak
                : find_peak(in, target * (1.0 - tol), target * (1.0 + tol), target, out->peak);
  }
  if (at[AF_MODE_0S4] != AF_MODES_NO_PEAK && at[AF_MODE_0S4] == at[AF_MODE_1S2]) {
    af_sphere_mode keep = group2_mode(in, peak_hz(in, at[AF_MODE_0S4]) / f);
    at[keep == AF_MODE_0S4 ? AF_MODE_1S2 : AF_MODE_0S4] = AF_MODES_NO_PEAK;
  }
  out->n_matched = 0;
  for (int m = 0; m < AF_MODE_COUNT; ++m) {
    if (at[m] == AF_MODES_NO_PEAK)
      continue;
    af_modes_match x = {(af_sphere_mode)m, at[m], peak_hz(in, at[m]),
                        peak_hz(in, at[m]) / (f * in->modes->ratio[m]) - 1.0};
    size_t k = out->n_matched++;
    for (; k > 0 && out->matched[k - 1].frequency_hz > x.frequency_hz; --k)
      out->matched[k] = out->matched[k - 1];
    out->matched[k] = x;
  }
}

static void id_clear(const af_modes_input *in, af_modes_id *out)
{
  out->method = AF_MODES_METHOD_NONE;
  out->peak = AF_MODES_NO_PEAK;
  out->frequency_hz = NAN;
  out->confidence = 0.0;
  out->ambiguous = false;
  out->ambiguity = AF_MODES_CLEAR;
  out->prior_conflict = false;
  out->prior_z = NAN;
  out->f_pred_hz = in->f_pred_hz;
  out->f_lo_hz = in->f_lo_hz;
  out->f_hi_hz = in->f_hi_hz;
  out->n_candidates = 0;
  out->n_matched = 0;
  out->n_competing = 0;
}

/* Candidates in range; whether any of them has ratio evidence. */
static size_t count_candidates(const af_comb *c, bool *evidence)
{
  size_t n = 0;
  *evidence = false;
  for (size_t i = 0; i < c->in->n_peaks; ++i) {
    if (!in_range(c->in, i))
      continue;
    ++n;
    af_evidence e = evidence_as_0s2(c, i);
    *evidence = *evidence || e.evidence;
  }
  return n;
}

static af_modes_method choose_method(bool prior, bool evidence)
{
  if (prior)
    return evidence ? AF_MODES_METHOD_PRIOR_RATIOS : AF_MODES_METHOD_PRIOR;
  return evidence ? AF_MODES_METHOD_RATIOS : AF_MODES_METHOD_LOUDEST;
}

/* The ambiguity rules of modes.h, in order; names the competitors. */
static void judge(const af_comb *c, af_modes_id *out, double best_score)
{
  af_evidence chosen = evidence_as_0s2(c, out->peak);
  out->prior_z = chosen.z;
  out->prior_conflict = c->prior && fabs(chosen.z) > c->cfg->conflict_sigmas;
  name_competitors(c, out->method, out, best_score);
  if (out->n_competing > 1) {
    out->ambiguity =
        out->method == AF_MODES_METHOD_LOUDEST ? AF_MODES_LOUDNESS_TIE : AF_MODES_CLOSE_CALL;
  } else if (out->method == AF_MODES_METHOD_PRIOR_RATIOS) {
    double r_best;
    size_t j = best_candidate(c, out->method, true, &r_best);
    if (j != out->peak && r_best - chosen.ratio >= c->cfg->ambiguity_margin) {
      out->ambiguity = AF_MODES_PRIOR_VS_RATIOS;
      add_competing(c, out, j, evidence_as_0s2(c, j).prior + r_best);
    }
  }
  if (out->ambiguity == AF_MODES_CLEAR && out->prior_conflict && !chosen.partner)
    out->ambiguity = AF_MODES_PRIOR_CONFLICT;
  out->ambiguous = out->ambiguity != AF_MODES_CLEAR;
  if (!out->ambiguous)
    out->n_competing = 0;
}

af_status af_modes_execute(const af_modes_config *cfg, const af_modes_input *in, af_modes_id *out)
{
  if (cfg == NULL || in == NULL || out == NULL || !config_ok(cfg) || !input_ok(in))
    return AF_EINVAL;
  af_comb c;
  comb_setup(cfg, in, &c);
  id_clear(in, out);
  bool evidence = false;
  out->n_candidates = count_candidates(&c, &evidence);
  if (out->n_candidates == 0)
    return AF_ENODATA;
  out->method = choose_method(c.prior, evidence);
  double best_score;
  out->peak = best_candidate(&c, out->method, false, &best_score);
  if (out->method == AF_MODES_METHOD_LOUDEST) {
    /* by SNR: best_candidate's scores are all 0 and its ties go to the higher SNR */
    out->confidence = 1.0 / (1.0 + (double)out->n_candidates);
  } else {
    out->confidence = confidence_of(&c, out->method, best_score);
  }
  out->frequency_hz = peak_hz(in, out->peak);
  judge(&c, out, best_score);
  fill_matched(&c, out);
  return AF_OK;
}

/* ---- text --------------------------------------------------------------------- */

typedef struct {
  char *buf;
  size_t size, len; /* len: the length the whole text needs so far */
} af_text;

static void text_add(af_text *t, const char *fmt, ...)
{
  va_list ap;
  va_start(ap, fmt);
  size_t room = t->len < t->size ? t->size - t->len : 0;
  int n = vsnprintf(room > 0 ? t->buf + t->len : NULL, room, fmt, ap);
  va_end(ap);
  if (n > 0)
    t->len += (size_t)n;
}

static void text_candidate(af_text *t, const af_modes_candidate *k)
{
  text_add(t, "%.0f Hz", k->frequency_hz);
  if (k->looks_like != AF_MODE_COUNT)
    text_add(t, " (%s of %.0f Hz?)", af_sphere_mode_name(k->looks_like), k->base_hz);
}

static void text_ambiguous(af_text *t, const af_modes_id *id)
{
  text_add(t, "ambiguous 0S2: ");
  switch (id->ambiguity) {
  case AF_MODES_PRIOR_VS_RATIOS:
    text_add(t, "%.0f Hz (pulse fit) or %.0f Hz (mode ratios)", id->competing[0].frequency_hz,
             id->competing[1].frequency_hz);
    return;
  case AF_MODES_PRIOR_CONFLICT:
    text_add(t, "%.0f Hz, %.1f sigma from the %.0f Hz of the pulse fit, no partner mode",
             id->frequency_hz, id->prior_z, id->f_pred_hz);
    return;
  case AF_MODES_CLEAR:
  case AF_MODES_CLOSE_CALL:
  case AF_MODES_LOUDNESS_TIE: break;
  }
  for (size_t i = 0; i < id->n_competing; ++i) {
    if (i > 0)
      text_add(t, " or ");
    text_candidate(t, &id->competing[i]);
  }
  text_add(t, "; %s", af_modes_method_name(id->method));
}

size_t af_modes_format(const af_modes_id *id, char *buf, size_t size)
{
  af_text t = {buf, buf == NULL ? 0 : size, 0};
  if (t.size > 0)
    buf[0] = '\0';
  if (id == NULL) {
    text_add(&t, "no mode identification");
    return t.len;
  }
  if (id->method == AF_MODES_METHOD_NONE) {
    text_add(&t, "no 0S2 candidate in [%.0f, %.0f] Hz", id->f_lo_hz, id->f_hi_hz);
    return t.len;
  }
  if (id->ambiguous) {
    text_ambiguous(&t, id);
    return t.len;
  }
  text_add(&t, "0S2 %.0f Hz (%s", id->frequency_hz, af_modes_method_name(id->method));
  if (id->method == AF_MODES_METHOD_LOUDEST)
    text_add(&t, ", nothing better known");
  const char *sep = ": ";
  for (size_t i = 0; i < id->n_matched; ++i) {
    if (id->matched[i].mode == AF_MODE_0S2)
      continue;
    text_add(&t, "%s%s %.0f Hz", sep, af_sphere_mode_name(id->matched[i].mode),
             id->matched[i].frequency_hz);
    sep = ", ";
  }
  text_add(&t, "; confidence %.2f", id->confidence);
  if (id->prior_conflict)
    text_add(&t, "; %.1f sigma from the pulse fit's %.0f Hz", id->prior_z, id->f_pred_hz);
  text_add(&t, ")");
  return t.len;
}
