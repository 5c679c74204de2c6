/* live_settings.h — dynamic_reconfigure of the running node: the criterion
 * settings, the measurement's thresholds and the firmness grades (the rows of
 * src/core/config/reconfigure.h; the description is generated from the parameter
 * table at build time, so its names, defaults and ranges are the table's).
 *
 * A request is checked as start-up checks the node's parameters: each value
 * goes through its table row (af_settings_set_*, on a copy of the node's
 * settings), then af_lane_config_derive runs every cross-check (e.g.
 * modulus_nominal_pa within [modulus_min_pa, modulus_max_pa], the grade
 * classes, the model's own check over the corners). Accepted: the node's
 * configuration is replaced in place and the lane's parts that copied it
 * are made anew (af_lane_io_reconfigured); the next apple, strike and
 * ~evaluate call use it. Refused: nothing changes, the server answers with
 * the values in force, the reason goes to a WARN log and /diagnostics.
 *
 * Two lane configurations are kept (allocated at create), so a request
 * allocates only inside the lane's remake. Not thread-safe: the node's one
 * spinning thread. */
#ifndef AF_NODE_LIVE_SETTINGS_H
#define AF_NODE_LIVE_SETTINGS_H

#include "af_ros.h"
#include "lane_io.h"
#include "params.h"
#include "snapshot.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct af_live_settings af_live_settings;

/* Starts the dynamic_reconfigure server on ~ (cfg is changed in place and
 * must outlive it). *out NULL on error, *what naming the part. */
af_status af_live_settings_create(af_ros *ros, af_node_config *cfg, af_lane_io *measured,
                                  af_live_settings **out, const char **what);
void af_live_settings_destroy(af_live_settings *l); /* NULL-safe */

/* The snapshot published again after each accepted reconfigure (borrowed). */
void af_live_settings_set_snapshot(af_live_settings *l, af_snapshot *snapshot);

/* The `reconfigure` keys of /diagnostics (nothing for NULL). */
void af_live_settings_diag(const af_live_settings *l, af_diag_status *d);

#ifdef __cplusplus
}
#endif
#endif
