/* hammer_health.h — watches the hammer and its force transducer over a
 * shift: running statistics over the last `window` measured strikes and a
 * verdict, OK or WARN with the figure and its limit.
 *
 * Per strike (af_hammer_health_push), from the detector's event and the fit:
 *  - the contact velocity from the impulse. The momentum balance of the
 *    hammer over the contact (synth.c, PHYSICS.md) is
 *        J = m1 v0 (1 + e) + m1 g t_c,
 *    so   v0 = (J / m1 - g t_c) / (1 + e),
 *    with m1 the hammer's mass, g the gravity along the strike, t_c the
 *    detector's contact time and e the cultivar's restitution (the rig's
 *    figure: the fitted e is not used here, since with v0 fixed in the fit
 *    a faster hammer reads as a larger fitted e and would hide the drift).
 *    A fruit whose delivered e differs from the cultivar's by de reads as a
 *    relative change of v0 of -de / (1 + e). Only clean strikes count (no
 *    double hit, no clipping, no truncation, no lost samples): the impulse
 *    of the others is not the hammer's;
 *  - the contact velocity fitted to the pulse, when measure_fit_velocity
 *    frees it (NaN otherwise);
 *  - the delivered restitution fitted to the pulse, against the cultivar's;
 *  - the transducer's baseline (at the contact start) and noise RMS, as the
 *    detector measured them for the strike;
 *  - the peak force, and whether a raw sample clipped.
 *
 * The verdict, once the window holds at least min_strikes strikes (each
 * check its own count): WARN when
 *  - |mean v0 / strike_velocity_m_s - 1| > velocity_band (mean of the clean
 *    strikes of the window);
 *  - |mean baseline - reference| > baseline_drift_limit_n, the reference
 *    being the mean baseline of the first min_strikes strikes after a reset;
 *  - clipped strikes / strikes of the window > clip_rate_limit.
 * The text names each figure with its limit and the row that sets it.
 *
 * Fixed size: the ring holds AF_HAMMER_HEALTH_WINDOW_MAX strikes, allocated
 * in af_hammer_health_create; nothing is allocated per strike. A push costs
 * O(window). Not thread-safe. */
#ifndef AF_HAMMER_HEALTH_H
#define AF_HAMMER_HEALTH_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "settings.h" /* AF_SETTINGS_HEALTH_WINDOW_MAX */
#include "status.h"

#ifdef __cplusplus
extern "C" {
#endif

#define AF_HAMMER_HEALTH_WINDOW_MAX                                                                \
  AF_SETTINGS_HEALTH_WINDOW_MAX /* strikes: the upper end of hammer_health_window */
#define AF_HAMMER_HEALTH_TEXT_MAX 512

typedef struct {
  double hammer_mass_kg;         /* m1 > 0 */
  double gravity_m_s2;           /* >= 0, along the strike */
  double velocity_m_s;           /* the set contact velocity v0 > 0 (strike_velocity_m_s) */
  double restitution;            /* the cultivar's e in (0, 1] */
  size_t window;                 /* strikes in the statistics, [2, WINDOW_MAX] */
  size_t min_strikes;            /* strikes before any check, [1, window] */
  double velocity_band;          /* relative half-width of the v0 band, (0, 1] [-] */
  double baseline_drift_limit_n; /* > 0 [N] */
  double clip_rate_limit;        /* [0, 1]: clipped strikes per strike [-] */
} af_hammer_health_config;

/* One measured strike's figures (NaN where not measured). */
typedef struct {
  double impulse_n_s;         /* the detector's */
  double contact_time_s;      /* the detector's */
  double peak_force_n;        /* the detector's */
  double baseline_n;          /* baseline at the contact start [N] */
  double noise_rms_n;         /* noise floor when it triggered [N] */
  double fitted_velocity_m_s; /* NaN unless the fit freed v0 */
  double fitted_restitution;  /* NaN when no fit */
  bool clipped;               /* a raw sample at or beyond full scale */
  bool clean;                 /* no double hit, clip, truncation or lost sample */
} af_hammer_strike;

/* The checks, as bits of af_hammer_health_stats.warnings. */
enum {
  AF_HAMMER_WARN_VELOCITY = 1u << 0,
  AF_HAMMER_WARN_BASELINE = 1u << 1,
  AF_HAMMER_WARN_CLIPPING = 1u << 2
};
#define AF_HAMMER_WARN_KINDS 3

/* The window's figures after the latest push (NaN where none). */
typedef struct {
  uint64_t strikes;            /* pushed since the reset */
  size_t window_strikes;       /* in the window now */
  double last_velocity_m_s;    /* v0 of the latest strike from its impulse (NaN: not clean) */
  double velocity_m_s;         /* mean v0 from the impulse, clean strikes of the window */
  double velocity_sd_m_s;      /* their standard deviation */
  size_t velocity_strikes;     /* clean strikes behind them */
  double velocity_deviation;   /* velocity_m_s / set - 1 [-] */
  double fit_velocity_m_s;     /* mean fitted v0 (NaN: v0 not fitted) */
  size_t fit_velocity_strikes; /* strikes behind it */
  double restitution;          /* mean fitted delivered e [-] */
  size_t restitution_strikes;  /* strikes behind it */
  double baseline_n;           /* mean baseline [N] */
  double baseline_reference_n; /* the first min_strikes strikes' (NaN: not yet) [N] */
  double baseline_drift_n;     /* baseline_n - baseline_reference_n [N] */
  double noise_rms_n;          /* mean noise RMS [N] */
  double peak_force_n;         /* mean peak force of the clean strikes [N] */
  double peak_force_sd_n;      /* its standard deviation [N] */
  double peak_force_min_n, peak_force_max_n;
  size_t clipped_strikes;                              /* in the window */
  double clip_rate;                                    /* clipped_strikes / window_strikes [-] */
  uint32_t warnings;                                   /* AF_HAMMER_WARN_* now; 0 = OK */
  uint64_t first_warning_strike[AF_HAMMER_WARN_KINDS]; /* strike number (1 = the first
                                  after the reset) at which each check first warned; 0 = never */
  uint64_t warned_strikes;                             /* strikes after which some check warned */
  char text[AF_HAMMER_HEALTH_TEXT_MAX]; /* "" when OK; else each warning with its figure and
                                           limit, "; "-separated */
} af_hammer_health_stats;

typedef struct af_hammer_health af_hammer_health;

/* Checks cfg: AF_EINVAL with one line in err[len] naming the field, its
 * value and the accepted range; AF_OK. No allocation. */
af_status af_hammer_health_check(const af_hammer_health_config *cfg, char *err, size_t len);

/* Validates cfg, then allocates the ring (AF_ENOMEM). *out NULL on error. */
af_status af_hammer_health_create(const af_hammer_health_config *cfg, af_hammer_health **out);
void af_hammer_health_destroy(af_hammer_health *h); /* NULL-safe */

/* What af_hammer_health_create allocates [bytes] (the lane's memory estimate). */
size_t af_hammer_health_bytes(void);

/* Forgets every strike (the reference baseline too). */
void af_hammer_health_reset(af_hammer_health *h);

/* A new configuration (the set velocity, the limits, the window: strikes
 * already held are kept, the verdict is taken again at the next push).
 * AF_EINVAL (the old one kept) or AF_OK. No allocation. */
af_status af_hammer_health_configure(af_hammer_health *h, const af_hammer_health_config *cfg);

/* The contact velocity of an impulse J [N s] over a contact t_c [s]:
 * (J / m1 - g t_c) / (1 + e) with cfg's m1, g and e [m/s]. */
double af_hammer_health_velocity_m_s(const af_hammer_health_config *cfg, double impulse_n_s,
                                     double contact_time_s);

/* One measured strike: the window moves on, the figures and the verdict are
 * taken again. AF_EINVAL for NULL pointers. No allocation. */
af_status af_hammer_health_push(af_hammer_health *h, const af_hammer_strike *s);

const af_hammer_health_stats *af_hammer_health_get_stats(const af_hammer_health *h);

#ifdef __cplusplus
}
#endif
#endif
