/* r2_search.h — the R2_min search: the smallest strike radius R2 [m] in a
 * bracket above which a strike is reliable, over any evaluation of the model.
 *
 * One search for both paths: af_model_min_strike_radius passes the ODE
 * evaluation (model.c), af_fastpath_min_strike_radius the table's
 * (fastpath.c). The search allocates nothing; the evaluation must not either.
 */
#ifndef AF_R2_SEARCH_H
#define AF_R2_SEARCH_H

#include <stdbool.h>

#include "model.h"
#include "status.h"

#ifdef __cplusplus
extern "C" {
#endif

/* One evaluation of p into r (as af_model_execute); ctx is the caller's
 * workspace (an af_model, an af_fastpath). */
typedef af_status (*af_r2_evaluate_fn)(void *ctx, const af_model_params *p, af_model_result *r);

/* Smallest strike radius R2 [m] in [r_lo_m, r_hi_m] above which the strike is
 * reliable under evaluate (all else as in p): a geometric scan of 24 points
 * down from r_hi_m to the first unreliable radius, then bisection to a
 * relative width of 1e-4. AF_EINVAL for a bad bracket; AF_ENOROOT when not
 * reliable even at r_hi_m; *r_min_m = r_lo_m when reliable down to r_lo_m;
 * AF_EBUDGET_SEARCH after 80 evaluations (a guard: about 36 suffice for any
 * bracket); any status of evaluate. */
af_status af_r2_search(af_r2_evaluate_fn evaluate, void *ctx, const af_model_params *p,
                       double r_lo_m, double r_hi_m, double *r_min_m);

/* The verdict at strike radius radius_m [m], all else fixed by ctx: *ok the
 * strike is reliable (false when the status is not AF_OK). */
typedef af_status (*af_r2_reliable_fn)(void *ctx, double radius_m, bool *ok);

/* The same search over a verdict alone, for a caller that works out what
 * does not depend on the radius once per search (fastpath.c);
 * af_r2_search is this over its evaluate. */
af_status af_r2_search_radius(af_r2_reliable_fn reliable, void *ctx, double r_lo_m, double r_hi_m,
                              double *r_min_m);

#ifdef __cplusplus
}
#endif

#endif
