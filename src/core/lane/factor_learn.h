/* factor_learn.h — the cultivar's modulus factor learned on the line: a
 * robust online estimate of the factor between the dynamic modulus of the
 * 0S2 and the quasi-static E2 fitted to the force pulse.
 *
 * Each measured strike reports E(0S2) = E_dyn / factor_used (measure.h:
 * Lamb's modulus divided by the factor the strike was measured with) and the
 * fitted E2. The true factor of that strike is therefore
 *
 *   factor_true = E_dyn / E2 = factor_used x E(0S2) / E2   [-]
 *
 * whatever factor was in use; firmness_report's modulus_factor_suggested is
 * the median of the same quantity over a session (src/report/summary.c).
 *
 * The estimate is the median of factor_true over the newest window_strikes
 * reliable strikes (a ring of that many values and a sorted copy kept by
 * insertion, both allocated in create: nothing per strike), with the
 * distribution-free 95 % confidence interval of the median: the order
 * statistics of ranks
 *
 *   lo = round(n/2 - z sqrt(n)/2),  hi = round(1 + n/2 + z sqrt(n)/2),  z = 1.96
 *
 * (1-based, clamped to [1, n]; Campbell & Gardner, BMJ 1988, the normal
 * approximation of the binomial's: ranks 2 and 8 for n = 9, 6 and 15 for
 * n = 20). A strike that is not reliable, has no 0S2 (no audio) or no fitted
 * E2 is refused: counted, never stored.
 *
 * Applied value: starts at the cultivar's modulus_factor. With apply on and
 * at least min_strikes in the window, the estimate replaces the applied value
 * when it differs from it by more than min_change (relative: the hysteresis
 * that keeps the value still while the median wanders within its noise), and
 * lies within [factor_min, factor_max] (the modulus_factor row's range).
 * Each change is counted and reported to the caller, who logs it.
 *
 * Not thread-safe; no allocation after create. */
#ifndef AF_FACTOR_LEARN_H
#define AF_FACTOR_LEARN_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "status.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Two-sided 95 % quantile of the standard normal distribution. */
#define AF_FACTOR_LEARN_Z95 1.959963984540054

typedef struct {
  size_t window_strikes; /* the newest reliable strikes the median is taken over, >= 1 */
  size_t min_strikes;    /* no estimate (NaN) below this many, in [1, window_strikes] */
  bool apply;            /* the estimate becomes the applied value (else only published) */
  double min_change;     /* relative change |estimate - applied| / applied needed to apply, >= 0 */
  double initial_factor; /* the cultivar's modulus_factor: the applied value at the start, > 0 */
  double factor_min, factor_max; /* an estimate outside is never applied [-] */
} af_factor_learn_config;

typedef struct {
  size_t n;          /* reliable strikes in the window */
  uint64_t taken;    /* reliable strikes stored since the start */
  uint64_t refused;  /* strikes refused: unreliable, without 0S2 or fitted E2, non-finite */
  double estimate;   /* median of factor_true over the window [-]; NaN while n < min_strikes */
  double ci_low_95;  /* 95 % confidence interval of the median [-]; NaN likewise */
  double ci_high_95; /* */
  double applied;    /* the factor in use for the following strikes [-] */
  double previous;   /* applied before the latest change [-]; NaN before any */
  uint64_t changes;  /* times the applied value changed */
} af_factor_learn_state;

typedef struct af_factor_learn af_factor_learn;

/* AF_EINVAL for a NULL pointer or a field outside its range (nothing
 * allocated, *out NULL); AF_ENOMEM. */
/* One strike's own factor, factor_used x E(0S2) / E2 [-] (the top comment);
 * NaN or infinite when a modulus is missing. What af_factor_learn_push
 * stores, for a caller that shows it per strike. */
double af_factor_learn_true(double factor_used, double modulus_from_resonance_pa,
                            double fitted_modulus_pa);

af_status af_factor_learn_create(const af_factor_learn_config *cfg, af_factor_learn **out);
void af_factor_learn_destroy(af_factor_learn *f); /* NULL-safe */

/* Empties the window and restores the initial applied value. */
void af_factor_learn_reset(af_factor_learn *f);

/* An operator's value (a reconfigured modulus_factor) becomes the applied
 * one; the window is kept. Not counted as a change. */
void af_factor_learn_set_applied(af_factor_learn *f, double factor);

/* One measured strike: reliable, its modulus from the 0S2 and fitted E2 [Pa]
 * (NaN when not measured) and the factor it was measured with [-]. *changed
 * (may be NULL) true when the applied value changed with it. AF_OK, also
 * for a refused strike (counted in state.refused); AF_EINVAL for NULL f. */
af_status af_factor_learn_push(af_factor_learn *f, bool reliable, double modulus_from_resonance_pa,
                               double fitted_modulus_pa, double factor_used, bool *changed);

/* The estimate, its interval, the applied value and the counts (borrowed). */
const af_factor_learn_state *af_factor_learn_get(const af_factor_learn *f);

/* The 1-based ranks of the 95 % interval of the median of n values. */
void af_factor_learn_ci_ranks(size_t n, size_t *lo, size_t *hi);

#ifdef __cplusplus
}
#endif
#endif
