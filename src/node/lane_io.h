/* lane_io.h — the node's side of one lane (src/core/lane/lane.h): SignalChunk and
 * AppleEstimate messages into the lane, and each strike the lane measures
 * out as a StrikeReport, a Reliability (source "measured") and, with
 * markers, a line of text above the matched apple.
 *
 * Outputs, one of each per strike, header stamp = contact start, frame = the
 * force chunk's. Everything is allocated in af_lane_io_create (the lane
 * included); nothing per chunk or strike. Not thread-safe: the node's one
 * spinning thread. */
#ifndef AF_NODE_MEASURED_H
#define AF_NODE_MEASURED_H

#include <stdbool.h>

#include "af_msgs.h"
#include "af_ros.h"
#include "lane.h"
#include "params.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct af_lane_io af_lane_io;

/* Makes the lane and the strike_report publisher. reliability_pub is the
 * station's reliability publisher, markers_pub its markers publisher (NULL
 * when markers are off). *out is NULL on error; *what names the part that
 * failed. */
af_status af_lane_io_create(af_ros *ros, const af_node_config *cfg, af_ros_pub *reliability_pub,
                            af_ros_pub *markers_pub, af_lane_io **out, const char **what);
void af_lane_io_destroy(af_lane_io *m); /* NULL-safe */

/* The lane, for its streams and counters. */
const af_lane *af_lane_io_lane(const af_lane_io *m);

/* A force or audio chunk into the lane; the stream's verdict, *info its gaps
 * and restarts. Strikes it completes are published before it returns. */
af_chunk_verdict af_lane_io_force(af_lane_io *m, const af_signal_chunk *c,
                                  af_ring_write_info *info);
af_chunk_verdict af_lane_io_audio(af_lane_io *m, const af_signal_chunk *c,
                                  af_ring_write_info *info);

/* A chunk refused on the wire (af_ros_refused_fn), counted in the lane's
 * force or audio stream. */
void af_lane_io_refuse(af_lane_io *m, bool force, bool oversized, const char *why);

/* An apple into the lane: its prediction in *pred (see af_lane_apple). */
af_status af_lane_io_apple(af_lane_io *m, const af_apple *a, const af_prediction **pred);

/* Where the text of a strike on this apple is drawn: the AppleEstimate's
 * header, the apple centre and its larger semi-axis in its frame. */
void af_lane_io_label_place(af_lane_io *m, uint32_t apple_id, const af_header *h,
                            const double centre_m[3], double top_m);

/* The live picture each strike is copied into (strike_plot.h); NULL = none. */
struct af_strike_plot;
void af_lane_io_set_strike_plot(af_lane_io *m, struct af_strike_plot *plot);

/* The node's configuration was changed in place (src/node/live_settings.c):
 * the lane's parts that copied it are made anew (af_lane_reconfigured);
 * grades_changed restarts the counts per class. */
af_status af_lane_io_reconfigured(af_lane_io *m, bool grades_changed, const char **what);

/* Each spin: measures what is due (time-outs, stale audio). */
void af_lane_io_poll(af_lane_io *m);

/* Each component's short reason to WARN: something new went wrong since
 * the last call, or a held condition lasts; NULL = none.
 *   detector     the strike queue overflowed, strikes lost to a reconfigure
 *   audio        the microphone clipped
 *   attribution  doubtful matches, late, skipped or refused apple estimates,
 *                strikes without audio or apple, audio lag moves, strikes
 *                across a clock fault, the apple transit (held)
 *   health       the hammer health (held while it warns: its text, with each
 *                figure and its limit: hammer_health.h)
 * Call once per diagnostic report. */
typedef struct {
  const char *detector, *audio, *attribution, *health;
} af_lane_io_warnings;
void af_lane_io_warnings_get(af_lane_io *m, af_lane_io_warnings *w);

/* The measured-strike keys into each component's status (/diagnostics):
 * the detector's ("strikes", "strike detector", queue, last strike, latency,
 * grades), the attribution's ("audio lag [s]", apple matches, transit,
 * strikes without audio or apple), the audio's ("strikes with the microphone
 * clipped"), the hammer health's ("hammer health", "hammer contact velocity
 * [m/s]", "hammer contact velocity fitted [m/s]", "hammer delivered
 * restitution [-]", "force baseline [N]", "force noise RMS [N]", "hammer
 * peak force [N]", "hammer clipping"), the modulus factor's. */
void af_lane_io_diag_detector(const af_lane_io *m, af_diag_status *d);
void af_lane_io_diag_attribution(const af_lane_io *m, af_diag_status *d);
void af_lane_io_diag_audio(const af_lane_io *m, af_diag_status *d);
void af_lane_io_diag_health(const af_lane_io *m, af_diag_status *d);
void af_lane_io_diag_factor(const af_lane_io *m, af_diag_status *d);
/* The modulus factor's one line ("learning: 3 of 20 reliable strikes; 1.0000
 * applied", "learned 1.0312, 1.0000 applied (the cultivar's)") into buf. */
const char *af_lane_io_factor_summary(const af_lane_io *m, char *buf, size_t len);

/* ROS time in integer nanoseconds. */
int64_t af_time_to_ns(af_time t);
af_time af_time_from_ns(int64_t ns); /* ns >= 0 */

#ifdef __cplusplus
}
#endif
#endif
