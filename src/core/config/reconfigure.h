/* reconfigure.h — the rows of the one parameter table (settings.h) that may
 * change while the node runs (dynamic_reconfigure): the criterion settings,
 * the measurement's thresholds and the firmness grades. Everything that sizes
 * an allocation (rates, ring lengths, windows, queue) or comes from the rig
 * stays as started. The node's dynamic_reconfigure description is generated
 * from this list and the table at build time (src/cfg/reconfigure_cfg.c), so
 * names, defaults and ranges cannot drift; a change is then checked by the
 * table and af_lane_config_derive exactly as at start-up. */
#ifndef AF_RECONFIGURE_H
#define AF_RECONFIGURE_H

#include <stdbool.h>
#include <stddef.h>

#include "settings.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct {
  af_setting_id id;
  const char *group; /* "criterion", "thresholds" or "grades" */
} af_reconfigure_row;

/* The reconfigurable rows, in the order of the description; *n their count. */
const af_reconfigure_row *af_reconfigure_rows(size_t *n);
/* id is one of them. */
bool af_reconfigure_allowed(af_setting_id id);

#ifdef __cplusplus
}
#endif
#endif
