/* status_marker.h — the station's diagnostic status in rviz: one text marker
 * (namespace "firmness_status", id 0) over the rig, in the frame the hammer
 * is mounted on, coloured by level (green OK, orange WARN, red ERROR), with
 * the summary /diagnostics gives and a few counts. Published on the markers
 * topic each time the diagnostics are, so that an operator watching rviz
 * sees what rqt_runtime_monitor would say. Display only. */
#ifndef AF_NODE_STATUS_MARKER_H
#define AF_NODE_STATUS_MARKER_H

#include "af_msgs.h"
#include "af_ros.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Fills *out: text at position_m in frame (stamp 0: the latest transform).
 * No allocation. */
void af_status_marker(const char *frame, const double position_m[3], af_diag_level level,
                      const char *text, af_marker *out);

#ifdef __cplusplus
}
#endif
#endif
