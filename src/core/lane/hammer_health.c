/* hammer_health.c — the hammer's running statistics and verdict (see
 * hammer_health.h). */
#include "hammer_health.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "text.h"

#define STR_(x) #x
#define STR(x) STR_(x) /* a macro's value as text */

/* One strike as held in the ring: its figures and its v0 from the impulse. */
typedef struct {
  af_hammer_strike s;
  double velocity_m_s; /* NaN: not clean */
} held_strike;

struct af_hammer_health {
  af_hammer_health_config cfg;
  held_strike *ring; /* AF_HAMMER_HEALTH_WINDOW_MAX */
  size_t next;       /* where the next strike goes */
  size_t held;       /* strikes held, at most WINDOW_MAX */
  double reference_sum_n;
  size_t reference_count; /* baselines summed into the reference, up to min_strikes */
  af_hammer_health_stats stats;
};

af_status af_hammer_health_check(const af_hammer_health_config *c, char *err, size_t len)
{
  if (c == NULL) {
    af_text(err, len, "hammer health: no configuration");
    return AF_EINVAL;
  }
  const char *what = NULL;
  double value = 0.0;
  const char *range = "";
  if (!(c->hammer_mass_kg > 0.0 && isfinite(c->hammer_mass_kg)))
    what = "hammer_mass_kg", value = c->hammer_mass_kg, range = "> 0 kg";
  else if (!(c->gravity_m_s2 >= 0.0 && isfinite(c->gravity_m_s2)))
    what = "gravity_m_s2", value = c->gravity_m_s2, range = ">= 0 m/s2";
  else if (!(c->velocity_m_s > 0.0 && isfinite(c->velocity_m_s)))
    what = "strike_velocity_m_s", value = c->velocity_m_s, range = "> 0 m/s";
  else if (!(c->restitution > 0.0 && c->restitution <= 1.0))
    what = "restitution", value = c->restitution, range = "(0, 1]";
  else if (c->window < 2 || c->window > AF_HAMMER_HEALTH_WINDOW_MAX)
    what = "hammer_health_window", value = (double)c->window,
    range = "[2, " STR(AF_HAMMER_HEALTH_WINDOW_MAX) "] strikes";
  else if (c->min_strikes < 1 || c->min_strikes > c->window)
    what = "hammer_health_min_strikes", value = (double)c->min_strikes,
    range = "[1, hammer_health_window] strikes";
  else if (!(c->velocity_band > 0.0 && c->velocity_band <= 1.0))
    what = "hammer_health_velocity_band", value = c->velocity_band, range = "(0, 1]";
  else if (!(c->baseline_drift_limit_n > 0.0 && isfinite(c->baseline_drift_limit_n)))
    what = "hammer_health_baseline_drift_n", value = c->baseline_drift_limit_n, range = "> 0 N";
  else if (!(c->clip_rate_limit >= 0.0 && c->clip_rate_limit <= 1.0))
    what = "hammer_health_clip_rate", value = c->clip_rate_limit, range = "[0, 1]";
  if (what == NULL)
    return AF_OK;
  af_text(err, len, "hammer health: %s = %g is outside the accepted range %s", what, value, range);
  return AF_EINVAL;
}

af_status af_hammer_health_create(const af_hammer_health_config *cfg, af_hammer_health **out)
{
  char err[AF_HAMMER_HEALTH_TEXT_MAX];
  if (out == NULL)
    return AF_EINVAL;
  *out = NULL;
  if (af_hammer_health_check(cfg, err, sizeof err) != AF_OK)
    return AF_EINVAL;
  af_hammer_health *h = calloc(1, sizeof *h);
  if (h == NULL)
    return AF_ENOMEM;
  h->ring = calloc(AF_HAMMER_HEALTH_WINDOW_MAX, sizeof *h->ring);
  if (h->ring == NULL) {
    free(h);
    return AF_ENOMEM;
  }
  h->cfg = *cfg;
  af_hammer_health_reset(h);
  *out = h;
  return AF_OK;
}

size_t af_hammer_health_bytes(void)
{
  return sizeof(af_hammer_health) + AF_HAMMER_HEALTH_WINDOW_MAX * sizeof(held_strike);
}

void af_hammer_health_destroy(af_hammer_health *h)
{
  if (h == NULL)
    return;
  free(h->ring);
  free(h);
}

/* The figures of a window that holds nothing yet. */
static void clear_figures(af_hammer_health_stats *t)
{
  t->window_strikes = t->velocity_strikes = t->fit_velocity_strikes = 0;
  t->restitution_strikes = t->clipped_strikes = 0;
  t->last_velocity_m_s = t->velocity_m_s = t->velocity_sd_m_s = t->velocity_deviation = NAN;
  t->fit_velocity_m_s = t->restitution = NAN;
  t->baseline_n = t->baseline_drift_n = t->noise_rms_n = NAN;
  t->peak_force_n = t->peak_force_sd_n = t->peak_force_min_n = t->peak_force_max_n = NAN;
  t->clip_rate = NAN;
  t->warnings = 0;
  t->text[0] = '\0';
}

void af_hammer_health_reset(af_hammer_health *h)
{
  if (h == NULL)
    return;
  h->next = h->held = 0;
  h->reference_sum_n = 0.0;
  h->reference_count = 0;
  memset(&h->stats, 0, sizeof h->stats);
  clear_figures(&h->stats);
  h->stats.baseline_reference_n = NAN;
}

af_status af_hammer_health_configure(af_hammer_health *h, const af_hammer_health_config *cfg)
{
  char err[AF_HAMMER_HEALTH_TEXT_MAX];
  if (h == NULL || af_hammer_health_check(cfg, err, sizeof err) != AF_OK)
    return AF_EINVAL;
  h->cfg = *cfg;
  return AF_OK;
}

double af_hammer_health_velocity_m_s(const af_hammer_health_config *cfg, double impulse_n_s,
                                     double contact_time_s)
{
  return (impulse_n_s / cfg->hammer_mass_kg - cfg->gravity_m_s2 * contact_time_s) /
         (1.0 + cfg->restitution);
}

/* Running mean and spread of the finite values offered (Welford's update). */
typedef struct {
  size_t n;
  double mean, m2, min, max;
} running;

static void offer(running *r, double x)
{
  if (!isfinite(x))
    return;
  r->n++;
  const double d = x - r->mean;
  r->mean += d / (double)r->n;
  r->m2 += d * (x - r->mean);
  r->min = r->n == 1 ? x : fmin(r->min, x);
  r->max = r->n == 1 ? x : fmax(r->max, x);
}

static double mean_of(const running *r)
{
  return r->n > 0 ? r->mean : NAN;
}

static double sd_of(const running *r)
{
  return r->n > 1 ? sqrt(r->m2 / (double)(r->n - 1)) : NAN;
}

/* The window's figures from the newest min(window, held) strikes. */
static void take_figures(af_hammer_health *h)
{
  af_hammer_health_stats *t = &h->stats;
  const size_t n = h->held < h->cfg.window ? h->held : h->cfg.window;
  running v = {0}, fv = {0}, e = {0}, b = {0}, noise = {0}, peak = {0};
  size_t clipped = 0;
  for (size_t k = 0; k < n; k++) {
    const held_strike *x =
        &h->ring[(h->next + AF_HAMMER_HEALTH_WINDOW_MAX - 1 - k) % AF_HAMMER_HEALTH_WINDOW_MAX];
    offer(&v, x->velocity_m_s);
    offer(&fv, x->s.fitted_velocity_m_s);
    offer(&e, x->s.fitted_restitution);
    offer(&b, x->s.baseline_n);
    offer(&noise, x->s.noise_rms_n);
    if (x->s.clean)
      offer(&peak, x->s.peak_force_n);
    clipped += x->s.clipped;
  }
  clear_figures(t);
  t->window_strikes = n;
  t->velocity_m_s = mean_of(&v);
  t->velocity_sd_m_s = sd_of(&v);
  t->velocity_strikes = v.n;
  t->velocity_deviation = t->velocity_m_s / h->cfg.velocity_m_s - 1.0;
  t->fit_velocity_m_s = mean_of(&fv);
  t->fit_velocity_strikes = fv.n;
  t->restitution = mean_of(&e);
  t->restitution_strikes = e.n;
  t->baseline_n = mean_of(&b);
  t->baseline_drift_n = t->baseline_n - t->baseline_reference_n;
  t->noise_rms_n = mean_of(&noise);
  t->peak_force_n = mean_of(&peak);
  t->peak_force_sd_n = sd_of(&peak);
  t->peak_force_min_n = peak.n > 0 ? peak.min : NAN;
  t->peak_force_max_n = peak.n > 0 ? peak.max : NAN;
  t->clipped_strikes = clipped;
  t->clip_rate = n > 0 ? (double)clipped / (double)n : NAN;
}

/* Appends one warning to the text, "; "-separated. */
static void say(af_hammer_health_stats *t, const char *piece)
{
  const size_t used = strlen(t->text);
  af_text(t->text + used, sizeof t->text - used, "%s%s", used ? "; " : "", piece);
}

/* The checks on the figures just taken. */
static void judge(af_hammer_health *h)
{
  af_hammer_health_stats *t = &h->stats;
  const af_hammer_health_config *c = &h->cfg;
  char piece[AF_HAMMER_HEALTH_TEXT_MAX];
  if (t->velocity_strikes >= c->min_strikes && fabs(t->velocity_deviation) > c->velocity_band) {
    t->warnings |= AF_HAMMER_WARN_VELOCITY;
    af_text(piece, sizeof piece,
            "hammer contact velocity %.4f m/s (%+.1f %%, mean of %zu strikes, from the impulse) "
            "outside strike_velocity_m_s %.4g m/s +- %.1f %% (hammer_health_velocity_band)",
            t->velocity_m_s, 100.0 * t->velocity_deviation, t->velocity_strikes, c->velocity_m_s,
            100.0 * c->velocity_band);
    say(t, piece);
  }
  if (isfinite(t->baseline_drift_n) && t->window_strikes >= c->min_strikes &&
      fabs(t->baseline_drift_n) > c->baseline_drift_limit_n) {
    t->warnings |= AF_HAMMER_WARN_BASELINE;
    af_text(piece, sizeof piece,
            "force baseline drifted %+.3f N (mean %.3f N of %zu strikes, reference %.3f N) beyond "
            "hammer_health_baseline_drift_n %.3g N",
            t->baseline_drift_n, t->baseline_n, t->window_strikes, t->baseline_reference_n,
            c->baseline_drift_limit_n);
    say(t, piece);
  }
  if (t->window_strikes >= c->min_strikes && t->clip_rate > c->clip_rate_limit) {
    t->warnings |= AF_HAMMER_WARN_CLIPPING;
    af_text(piece, sizeof piece,
            "clipping in %zu of %zu strikes (%.1f %%) beyond hammer_health_clip_rate %.1f %%",
            t->clipped_strikes, t->window_strikes, 100.0 * t->clip_rate,
            100.0 * c->clip_rate_limit);
    say(t, piece);
  }
  for (unsigned k = 0; k < AF_HAMMER_WARN_KINDS; k++)
    if ((t->warnings & (1u << k)) && t->first_warning_strike[k] == 0)
      t->first_warning_strike[k] = t->strikes;
  t->warned_strikes += t->warnings != 0;
}

af_status af_hammer_health_push(af_hammer_health *h, const af_hammer_strike *s)
{
  if (h == NULL || s == NULL)
    return AF_EINVAL;
  held_strike *x = &h->ring[h->next];
  x->s = *s;
  x->velocity_m_s =
      s->clean ? af_hammer_health_velocity_m_s(&h->cfg, s->impulse_n_s, s->contact_time_s) : NAN;
  h->next = (h->next + 1) % AF_HAMMER_HEALTH_WINDOW_MAX;
  h->held += h->held < AF_HAMMER_HEALTH_WINDOW_MAX;
  h->stats.strikes++;
  if (h->reference_count < h->cfg.min_strikes && isfinite(s->baseline_n)) {
    h->reference_sum_n += s->baseline_n;
    if (++h->reference_count == h->cfg.min_strikes)
      h->stats.baseline_reference_n = h->reference_sum_n / (double)h->reference_count;
  }
  take_figures(h);
  h->stats.last_velocity_m_s = x->velocity_m_s;
  judge(h);
  return AF_OK;
}

const af_hammer_health_stats *af_hammer_health_get_stats(const af_hammer_health *h)
{
  return &h->stats;
}
