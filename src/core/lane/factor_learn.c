/* factor_learn.c — the modulus factor learned on the line (see factor_learn.h). */
#include "factor_learn.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

struct af_factor_learn {
  af_factor_learn_config cfg;
  double *ring;   /* factor_true in arrival order, window_strikes slots */
  double *sorted; /* the same n values in ascending order */
  size_t head;    /* slot of the oldest value */
  af_factor_learn_state state;
};

/* First index of sorted[0..n) whose value is >= x. */
static size_t lower_bound(const double *sorted, size_t n, double x)
{
  size_t lo = 0, hi = n;
  while (lo < hi) {
    size_t mid = lo + (hi - lo) / 2;
    if (sorted[mid] < x)
      lo = mid + 1;
    else
      hi = mid;
  }
  return lo;
}

static void sorted_remove(double *sorted, size_t n, double x)
{
  size_t k = lower_bound(sorted, n, x); /* x is present: it was inserted */
  memmove(sorted + k, sorted + k + 1, (n - k - 1) * sizeof *sorted);
}

static void sorted_insert(double *sorted, size_t n, double x)
{
  size_t k = lower_bound(sorted, n, x);
  memmove(sorted + k + 1, sorted + k, (n - k) * sizeof *sorted);
  sorted[k] = x;
}

void af_factor_learn_ci_ranks(size_t n, size_t *lo, size_t *hi)
{
  const double half = 0.5 * AF_FACTOR_LEARN_Z95 * sqrt((double)n);
  double l = round(0.5 * (double)n - half), h = round(1.0 + 0.5 * (double)n + half);
  *lo = l < 1.0 ? 1 : (size_t)l;
  *hi = h > (double)n ? n : (size_t)h;
}

/* The median and its interval from the sorted window. */
static void estimate(af_factor_learn *f)
{
  af_factor_learn_state *s = &f->state;
  const size_t n = s->n;
  if (n == 0 || n < f->cfg.min_strikes) {
    s->estimate = s->ci_low_95 = s->ci_high_95 = NAN;
    return;
  }
  const double *x = f->sorted;
  s->estimate = n % 2 ? x[n / 2] : 0.5 * (x[n / 2 - 1] + x[n / 2]);
  size_t lo, hi;
  af_factor_learn_ci_ranks(n, &lo, &hi);
  s->ci_low_95 = x[lo - 1];
  s->ci_high_95 = x[hi - 1];
}

/* The hysteresis: true when the estimate became the applied value. */
static bool maybe_apply(af_factor_learn *f)
{
  af_factor_learn_state *s = &f->state;
  const af_factor_learn_config *c = &f->cfg;
  if (!c->apply || !isfinite(s->estimate) || s->estimate < c->factor_min ||
      s->estimate > c->factor_max)
    return false;
  if (!(fabs(s->estimate - s->applied) > c->min_change * s->applied))
    return false;
  s->previous = s->applied;
  s->applied = s->estimate;
  s->changes++;
  return true;
}

double af_factor_learn_true(double factor_used, double modulus_from_resonance_pa,
                            double fitted_modulus_pa)
{
  return factor_used * modulus_from_resonance_pa / fitted_modulus_pa;
}

af_status af_factor_learn_push(af_factor_learn *f, bool reliable, double modulus_from_resonance_pa,
                               double fitted_modulus_pa, double factor_used, bool *changed)
{
  if (changed)
    *changed = false;
  if (f == NULL)
    return AF_EINVAL;
  af_factor_learn_state *s = &f->state;
  const double x = af_factor_learn_true(factor_used, modulus_from_resonance_pa, fitted_modulus_pa);
  if (!reliable || !isfinite(x) || !(x > 0.0)) {
    s->refused++;
    return AF_OK;
  }
  const size_t w = f->cfg.window_strikes;
  if (s->n == w) { /* full: the oldest leaves */
    sorted_remove(f->sorted, s->n, f->ring[f->head]);
    f->ring[f->head] = x;
    f->head = (f->head + 1) % w;
    sorted_insert(f->sorted, s->n - 1, x);
  } else {
    f->ring[(f->head + s->n) % w] = x;
    sorted_insert(f->sorted, s->n, x);
    s->n++;
  }
  s->taken++;
  estimate(f);
  bool c = maybe_apply(f);
  if (changed)
    *changed = c;
  return AF_OK;
}

void af_factor_learn_reset(af_factor_learn *f)
{
  if (f == NULL)
    return;
  memset(&f->state, 0, sizeof f->state);
  f->head = 0;
  f->state.applied = f->cfg.initial_factor;
  f->state.previous = NAN;
  estimate(f);
}

void af_factor_learn_set_applied(af_factor_learn *f, double factor)
{
  if (f != NULL && isfinite(factor) && factor > 0.0)
    f->state.applied = factor;
}

static bool config_ok(const af_factor_learn_config *c)
{
  return c->window_strikes >= 1 && c->min_strikes >= 1 && c->min_strikes <= c->window_strikes &&
         isfinite(c->min_change) && c->min_change >= 0.0 && isfinite(c->initial_factor) &&
         c->initial_factor > 0.0 && isfinite(c->factor_min) && isfinite(c->factor_max) &&
         c->factor_min > 0.0 && c->factor_min <= c->factor_max;
}

af_status af_factor_learn_create(const af_factor_learn_config *cfg, af_factor_learn **out)
{
  if (out == NULL)
    return AF_EINVAL;
  *out = NULL;
  if (cfg == NULL || !config_ok(cfg))
    return AF_EINVAL;
  af_factor_learn *f = calloc(1, sizeof *f);
  if (f == NULL)
    return AF_ENOMEM;
  f->cfg = *cfg;
  f->ring = calloc(cfg->window_strikes, sizeof *f->ring);
  f->sorted = calloc(cfg->window_strikes, sizeof *f->sorted);
  if (f->ring == NULL || f->sorted == NULL) {
    af_factor_learn_destroy(f);
    return AF_ENOMEM;
  }
  af_factor_learn_reset(f);
  *out = f;
  return AF_OK;
}

void af_factor_learn_destroy(af_factor_learn *f)
{
  if (f == NULL)
    return;
  free(f->ring);
  free(f->sorted);
  free(f);
}

const af_factor_learn_state *af_factor_learn_get(const af_factor_learn *f)
{
  return f ? &f->state : NULL;
}
