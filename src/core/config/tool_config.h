/* tool_config.h — the lane's configuration as a desk tool (firmness_model,
 * firmness_report, strike_bag) reads it from the parameter table: a tool
 * reads no URDF, so the hammer is the shipped rig's unless given. */
#ifndef AF_TOOL_CONFIG_H
#define AF_TOOL_CONFIG_H

#include <stddef.h>

#include "lane_config.h"
#include "settings.h"
#include "status.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The lane's configuration from s: each hammer row still absent takes the
 * shipped rig's value (af_settings_use_rig_hammer, on a copy of s), then
 * af_lane_config_derive. AF_OK; AF_EINVAL with its one line in err. */
af_status af_lane_config_for_tool(const af_settings *s, af_lane_config *out, char *err, size_t len);

#ifdef __cplusplus
}
#endif
#endif
