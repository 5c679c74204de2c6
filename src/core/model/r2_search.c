/* r2_search.c — the R2_min search over an evaluate callback. */
#include "r2_search.h"

#include <math.h>

/* Scan points over the bracket, then bisection to this relative width. */
#define AF_R2_SEARCH_SCAN 24
#define AF_R2_SEARCH_RTOL 1e-4
/* Evaluations the whole search may take: the scan's 24 and the bisection
 * between two scan points (about 12 halvings for 0.002 .. 1 m, under 20 for
 * any bracket of doubles), with room to spare: it guards the loop. */
#define AF_R2_SEARCH_BUDGET 80

af_status af_r2_search_radius(af_r2_reliable_fn reliable, void *ctx, double r_lo_m, double r_hi_m,
                              double *r_min_m)
{
  bool ok;
  int budget = AF_R2_SEARCH_BUDGET - 1;
  if (!(r_lo_m > 0.0 && r_hi_m > r_lo_m && isfinite(r_hi_m)))
    return AF_EINVAL;
  af_status st = reliable(ctx, r_hi_m, &ok);
  if (st != AF_OK)
    return st;
  if (!ok)
    return AF_ENOROOT;
  /* Walk down a geometric scan from r_hi to the first unreliable radius, then
   * bisect between it and the last reliable one: the criteria need not be
   * monotonic far below R2_min, only near it. */
  double step = pow(r_lo_m / r_hi_m, 1.0 / (AF_R2_SEARCH_SCAN - 1));
  double good = r_hi_m, bad = 0.0;
  for (int k = 1; k < AF_R2_SEARCH_SCAN; k++) {
    double r = k == AF_R2_SEARCH_SCAN - 1 ? r_lo_m : r_hi_m * pow(step, k);
    budget--;
    st = reliable(ctx, r, &ok);
    if (st != AF_OK)
      return st;
    if (!ok) {
      bad = r;
      break;
    }
    good = r;
  }
  if (bad == 0.0) {
    *r_min_m = r_lo_m;
    return AF_OK;
  }
  while (good - bad > AF_R2_SEARCH_RTOL * good) {
    if (budget-- <= 0)
      return AF_EBUDGET_SEARCH;
    double mid = sqrt(good * bad);
    st = reliable(ctx, mid, &ok);
    if (st != AF_OK)
      return st;
    if (ok)
      good = mid;
    else
      bad = mid;
  }
  *r_min_m = good;
  return AF_OK;
}

/* af_r2_search's verdict: its evaluate on a copy of the strike whose radius
 * is set per call (the copy made once per search). */
typedef struct {
  af_r2_evaluate_fn evaluate;
  void *ctx;
  af_model_params q;
} af_r2_evaluation;

static af_status reliable_at(void *ctx, double radius_m, bool *ok)
{
  af_r2_evaluation *e = ctx;
  af_model_result r;
  e->q.impact.strike_radius_m = radius_m;
  af_status st = e->evaluate(e->ctx, &e->q, &r);
  *ok = st == AF_OK && r.reliable;
  return st;
}

af_status af_r2_search(af_r2_evaluate_fn evaluate, void *ctx, const af_model_params *p,
                       double r_lo_m, double r_hi_m, double *r_min_m)
{
  af_r2_evaluation e = {evaluate, ctx, *p};
  return af_r2_search_radius(reliable_at, &e, r_lo_m, r_hi_m, r_min_m);
}
