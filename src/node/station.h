/* station.h — one firmness station lane: its subscriptions, the per-apple
 * prediction and advice, the stream rings, the publishers and the
 * diagnostics.
 *
 * Inputs (relative topics, so lane namespaces and remaps work):
 *   force, audio  acoustic_firmness/SignalChunk -> checked, buffered in rings
 *   apple         acoustic_firmness/AppleEstimate -> one prediction each
 * Outputs, each header the AppleEstimate's (stamp and frame, never now()):
 *   excitation_band, strike_advice, reliability, markers; /diagnostics.
 * Measured strikes (lane_io.h), header = contact start and the force
 *   chunk's frame: strike_report, reliability (source "measured").
 *
 * Everything is allocated in af_station_create; the callbacks allocate
 * nothing (the shim copies messages as it must). */
#ifndef AF_NODE_STATION_H
#define AF_NODE_STATION_H

#include "af_ros.h"
#include "params.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct af_station af_station;

/* Makes the model, rings, publishers, subscribers and the diagnostic task.
 * cfg must outlive the station. On failure *out is NULL and the reason is
 * logged. */
af_status af_station_create(af_ros *ros, const af_node_config *cfg, af_station **out);
void af_station_destroy(af_station *st); /* NULL-safe */

/* Publishes the diagnostics when their period is due: call once per loop. */
void af_station_update(af_station *st);

#ifdef __cplusplus
}
#endif
#endif
