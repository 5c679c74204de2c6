/* strike_view.h — the figure of one measured strike, for the report's
 * per-strike plots and the node's live image (~strike_plot): the same data,
 * the same drawing.
 *
 *   left:  the measured force pulse (the detector's baseline-removed contact
 *          samples) and over it the impact model with the fitted E2 and e
 *          (af_impact_execute at a quarter of the sample step, from the
 *          detector's contact start), time from the contact start [ms];
 *   right: the spectra in dB re their own maxima: the force pulse's (the
 *          excitation, af_spectrum) and the audio window's (Hann window; the
 *          window the measurement analysed), the measured half-power band of
 *          the configured lobe and its level, the 0S2 range of this apple's
 *          mass over the cultivar's firmness range, the measured 0S2 and
 *          where its neighbours 0S3 and 1S2 would lie (Lamb's ratios for
 *          nu 0.35, PHYSICS.md 5).
 *
 * Three steps so that the node's chunk callbacks only copy:
 *   af_strike_view_capture  in the lane's strike callback: copies the pulse,
 *                           the figures and the audio window (ring read);
 *   af_strike_view_prepare  later (the node's spin loop): the fitted model and
 *                           both spectra;
 *   af_strike_view_draw     the figure, to a file or an RGB buffer.
 * Everything is allocated in af_strike_view_create; capture and prepare
 * allocate nothing. Not thread-safe. */
#ifndef AF_STRIKE_VIEW_H
#define AF_STRIKE_VIEW_H

#include <stdbool.h>
#include <stddef.h>

#include "lane.h"
#include "plot.h"

#ifdef __cplusplus
extern "C" {
#endif

#define AF_STRIKE_VIEW_FREQS 600 /* points of each spectrum curve */

typedef struct af_strike_view af_strike_view;

/* Sized from cfg (pulse capacity, audio window, rates; cfg must outlive the
 * view). AF_ENOMEM, AF_EINVAL. */
af_status af_strike_view_create(const af_lane_config *cfg, af_strike_view **out);
void af_strike_view_destroy(af_strike_view *v); /* NULL-safe */

/* Copies strike s (lane: its audio stream, for the analysed window). No
 * allocation, no computation beyond the copy. */
void af_strike_view_capture(af_strike_view *v, const af_lane_strike *s, const af_lane *lane);

/* Whether a strike was captured and not yet prepared. */
bool af_strike_view_pending(const af_strike_view *v);

/* Computes the fitted model's pulse and both spectra of the last capture.
 * AF_ENODATA when nothing was captured; a part that cannot be computed (no
 * fit, no audio) is left out of the figure. No allocation. */
af_status af_strike_view_prepare(af_strike_view *v);

/* Draws the prepared strike to t (plot.h). */
af_status af_strike_view_draw(const af_strike_view *v, const af_plot_target *t, char *err,
                              size_t len);

#ifdef __cplusplus
}
#endif
#endif
