/* tool_config.c — the lane's configuration as a desk tool reads it. */
#include "tool_config.h"

#include <stdio.h>

af_status af_lane_config_for_tool(const af_settings *s, af_lane_config *out, char *err, size_t len)
{
  if (s == NULL || out == NULL) {
    if (err && len)
      snprintf(err, len, "af_lane_config_for_tool: s or out is NULL");
    return AF_EINVAL;
  }
  af_settings t = *s; /* the caller's values keep their absent hammer rows */
  af_status st = af_settings_use_rig_hammer(&t, err, len);
  return st == AF_OK ? af_lane_config_derive(&t, out, err, len) : st;
}
