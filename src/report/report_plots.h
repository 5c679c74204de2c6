/* report_plots.h — the figures of firmness_report --plots DIR (PNG, drawn by
 * the plotting module src/plot/plot.h):
 *   strike_<n>_apple_<id>.png  per strike: the measured pulse with the fitted
 *                              model over it; the spectra (force pulse and
 *                              audio window, dB re their maxima) with the
 *                              half-power band, the 0S2 search range and the
 *                              measured 0S2;
 *   firmness_histogram.png     the modulus from the 0S2 and the fitted E2;
 *   stiffness_vs_mass.png      the stiffness factor against the mass, by verdict;
 *   resonance_vs_band.png      the 0S2 against the band edges, strike by strike;
 *   hammer_velocity.png        the contact velocity of each strike from its
 *                              impulse and the window's mean (hammer_health.h)
 *                              against strike_velocity_m_s and its band, the
 *                              first velocity warning marked;
 *   modulus_factor.png         each strike's own factor E(0S2) / fitted E2
 *                              (reliable ones, learned from; the others,
 *                              never used), the learned estimate with its
 *                              95 % interval, the applied value and the
 *                              cultivar's modulus_factor (factor_learn.h). */
#ifndef AF_REPORT_PLOTS_H
#define AF_REPORT_PLOTS_H

#include <stddef.h>

#include "lane.h"
#include "session.h"
#include "summary.h"

typedef struct af_report_plots af_report_plots;

/* Makes dir when missing (one level) and the per-strike workspace for cfg.
 * AF_EIO (dir cannot be made or written), AF_ENOMEM; err says which. */
af_status af_report_plots_create(const char *dir, const af_lane_config *cfg, af_report_plots **out,
                                 char *err, size_t len);
void af_report_plots_destroy(af_report_plots *p); /* NULL-safe */

/* An af_session_strike_fn: draws the strike's figure. Failures are counted
 * and reported by af_report_plots_session. */
void af_report_plots_strike(const af_lane_strike *s, const af_lane *lane, void *user);

/* Draws the session's figures. AF_EIO when a figure (this one or a strike's)
 * could not be written. */
af_status af_report_plots_session(af_report_plots *p, const af_session *s, const af_summary *m,
                                  char *err, size_t len);

#endif
