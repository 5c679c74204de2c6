/* measured.h — the measured strikes of one lane: the strike detector on the
 * force stream, the queue of strikes waiting for their audio, the match to
 * an AppleEstimate, the measurement (src/core/measure.h) and its outputs.
 *
 *   force chunk (accepted) ──> af_strike_write ──> event: contact start time
 *       = chunk stamp + (start_sample - chunk first_sample) / force rate
 *       (streams.h: the mapping of the latest force chunk), the event and
 *       its pulse copied into a preallocated pending slot
 *   each audio chunk and each spin ──> every pending strike, oldest first,
 *       whose audio window [start + delay, start + delay + window] (sample
 *       indices by the audio stream's mapping) is in the audio ring is
 *       measured with it; without audio (and the reason says why) when the
 *       window left the ring, holds lost samples, lies before the audio
 *       stream began, the audio stream is stale, or the window has not come
 *       ~stream_stale_after_s after it was due; a full queue measures its
 *       oldest strike at once, without audio, and counts the overflow
 *   apple ──> the newest AppleEstimate stamped at or before the contact
 *       start and at most ~apple_stale_after_s before it (from a short
 *       history, so a late strike still finds its own apple); its model
 *       parameters (the prediction's) are what the strike is judged with.
 *       None: the report carries apple_id 0 and NaN for every
 *       model-dependent figure, and the Reliability says why.
 *
 * Outputs, one of each per strike, header stamp = contact start, frame = the
 * force chunk's: strike_report (StrikeReport) and reliability (Reliability,
 * source "measured"); with markers, a line of text above the matched apple.
 *
 * Everything is allocated in af_measured_create; nothing per chunk or strike.
 * Not thread-safe: the node's one spinning thread. */
#ifndef AF_NODE_MEASURED_H
#define AF_NODE_MEASURED_H

#include <stdbool.h>

#include "af_msgs.h"
#include "af_ros.h"
#include "model.h"
#include "params.h"
#include "streams.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct af_measured af_measured;

/* Makes the detector, the measurement, the spectrum (for strikes without an
 * apple), the queue and the strike_report publisher. force and audio are
 * the station's streams (read only; they must outlive m); reliability_pub
 * is the station's reliability publisher, markers_pub its markers publisher
 * (NULL when markers are off). *out is NULL on error; *what names the part
 * that failed. */
af_status af_measured_create(af_ros *ros, const af_node_config *cfg, const af_stream *force,
                             const af_stream *audio, af_ros_pub *reliability_pub,
                             af_ros_pub *markers_pub, af_measured **out, const char **what);
void af_measured_destroy(af_measured *m); /* NULL-safe */

/* A force chunk the force stream has just accepted (af_stream_push gave
 * AF_CHUNK_OK): runs the detector over it and queues its strikes.
 * entry_wall_s: wall-clock time the callback began (for the latency). */
void af_measured_force(af_measured *m, const af_signal_chunk *c, double entry_wall_s);

/* An audio chunk was accepted: measures what it completes. */
void af_measured_audio(af_measured *m, double entry_wall_s);

/* An AppleEstimate and its prediction: params are the model parameters the
 * prediction used (mass and R2 filled in), NULL when the apple got none
 * (why says why). centre_m and top_m place the text marker (apple centre
 * and its larger semi-axis, in the apple's frame). */
void af_measured_apple(af_measured *m, const af_apple_estimate *a, const af_model_params *params,
                       const char *why, const double centre_m[3], double top_m);

/* Each spin: measures what is due (time-outs, stale audio). */
void af_measured_poll(af_measured *m);

/* A short reason to WARN when something new went wrong since the last call
 * (queue overflow, strikes measured without audio or without an apple);
 * NULL when nothing did. Call once per diagnostic report. */
const char *af_measured_warning(af_measured *m);
/* Adds the measured-strike keys to d. */
void af_measured_diag(const af_measured *m, af_diag_status *d);

/* The wall clock [s] (C11 timespec_get), for entry_wall_s. */
double af_measured_wall_s(void);

#ifdef __cplusplus
}
#endif
#endif
