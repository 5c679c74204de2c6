/* snapshot.h — what a recording needs to be judged again as it was judged
 * live: the node publishes, latched, in its namespace,
 *   settings           (std_msgs/String) every row it runs with, flat YAML
 *                      (src/core/config/snapshot.h), again after each
 *                      accepted reconfigure;
 *   robot_description  (std_msgs/String) the URDF it read (~urdf_file or
 *                      the robot_description parameter), once.
 * launch/record.launch records both; firmness_report reads the settings
 * from a bag that holds them. The text buffer is allocated at create. */
#ifndef AF_NODE_SNAPSHOT_H
#define AF_NODE_SNAPSHOT_H

#include "af_ros.h"
#include "params.h"

typedef struct af_snapshot af_snapshot;

/* Advertises both topics and publishes them from cfg. AF_OK; an error with
 * af_ros_last_error(ros). *out NULL on failure. */
af_status af_snapshot_create(af_ros *ros, const af_node_config *cfg, af_snapshot **out);

/* Publishes the settings again (after a reconfigure). NULL-safe. */
void af_snapshot_publish(af_snapshot *p, const af_settings *s);

void af_snapshot_destroy(af_snapshot *p); /* NULL-safe */

#endif
