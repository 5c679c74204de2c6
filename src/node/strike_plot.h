/* strike_plot.h — the node's live picture of the last measured strike on
 * ~strike_plot (sensor_msgs/Image, rgb8): the plotting module's strike
 * figure (src/plot/strike_view.h: the pulse with the fitted model, the force
 * and audio spectra, band, level, 0S2 range, measured 0S2), for rviz's Image
 * display.
 *
 * Two halves, so that no chunk callback draws:
 *   af_strike_plot_capture  in the lane's strike callback (inside a chunk
 *                           callback): copies the strike into the view's
 *                           preallocated slot (pulse, figures, the audio
 *                           window from the ring) and marks it dirty; no
 *                           allocation, no drawing;
 *   af_strike_plot_update   in the node's loop (af_station_update, after the
 *                           spin): when dirty and someone subscribes,
 *                           prepares the figure (fitted model, spectra),
 *                           renders it into the preallocated RGB buffer
 *                           (PLplot memcairo) and publishes it. A strike
 *                           captured while no one subscribes stays dirty and
 *                           is drawn when a subscriber comes.
 * Allocation: the view, its workspaces and the RGB buffer in create. PLplot
 * itself allocates and frees its stream state inside every render (plot.h):
 * the one exception to "nothing allocated after start-up", kept in the loop,
 * out of every callback (doc/lane.md: the live strike picture).
 * Not thread-safe: the node's one spinning thread. */
#ifndef AF_NODE_STRIKE_PLOT_H
#define AF_NODE_STRIKE_PLOT_H

#include <stdbool.h>

#include "af_ros.h"
#include "lane.h"
#include "params.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct af_strike_plot af_strike_plot;

/* The view, the buffer (cfg->strike_plot_width_px x height_px x 3 bytes)
 * and the strike_plot publisher. *out NULL on error, *what naming the part
 * that failed. cfg must outlive the plot. */
af_status af_strike_plot_create(af_ros *ros, const af_node_config *cfg, af_strike_plot **out,
                                const char **what);
void af_strike_plot_destroy(af_strike_plot *p); /* NULL-safe */

/* In the lane's strike callback: copies strike s (lane: its audio ring). */
void af_strike_plot_capture(af_strike_plot *p, const af_lane_strike *s, const af_lane *lane);

/* In the node's loop: renders and publishes the captured strike when due. */
void af_strike_plot_update(af_strike_plot *p);

/* Adds the strike plot's keys (images, skipped, render time) to d. */
void af_strike_plot_diag(const af_strike_plot *p, af_diag_status *d);

#ifdef __cplusplus
}
#endif
#endif
