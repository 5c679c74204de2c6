/* params.h — every parameter of firmness_node, loaded from the private
 * namespace and validated at start-up.
 *
 * Each private parameter is a row of the one parameter table
 * (src/core/params/settings.h: name, kind, default, range, unit, file); its values
 * ship in config/station.yaml and the cultivar's YAML (config/jonagold.yaml),
 * which the launch files load into ~. The node requires every row present;
 * only the hammer overrides (~hammer_mass_kg, ~hammer_tip_radius_m) are
 * optional, since the URDF is their normal source. The lane's configuration
 * is then made in the core by af_lane_config_derive, as `firmness_model
 * analyze` makes it from the same files. Any bad value stops the node with
 * one line naming the parameter, its value and the accepted range.
 */
#ifndef AF_NODE_PARAMS_H
#define AF_NODE_PARAMS_H

#include <stdbool.h>
#include <stddef.h>

#include "af_msgs.h"
#include "af_ros.h"
#include "af_urdf.h"
#include "lane_config.h"

#ifdef __cplusplus
extern "C" {
#endif

#define AF_PATH_MAX AF_SETTINGS_TEXT_MAX /* ~urdf_file, with its NUL */
#define AF_NAME_MAX AF_LANE_NAME_MAX     /* ~hammer_link, with its NUL */
#define AF_SOURCE_TEXT_MAX 160

typedef struct {
  /* --- rig (station.yaml, URDF) --- */
  char hammer_link[AF_NAME_MAX];
  char urdf_file[AF_PATH_MAX];   /* "" = the robot_description parameter */
  char hardware_id[AF_NAME_MAX]; /* /diagnostics' hardware_id; "" = the node's name */
  af_urdf *urdf;                 /* NULL when running on parameters alone */
  bool hammer_axis_known;        /* the URDF gave the strike axis */
  af_hammer_geometry hammer;     /* mass and tip radius after overrides; the axis and origin in
                                    hammer.mount_frame, turned into the apple's frame through TF */
  char urdf_source[AF_SOURCE_TEXT_MAX]; /* where the URDF came from, or why there is none */
  char hammer_mass_source[AF_SOURCE_TEXT_MAX];
  char hammer_tip_source[AF_SOURCE_TEXT_MAX];
  af_lane_config lane; /* everything outside ROS (src/core/lane/lane_config.h) */
  /* Every row as loaded (the URDF's hammer too): the base of a reconfigure. */
  af_settings settings;
  /* --- audio input (~audio_input, src/node/audio_in.h) --- */
  bool audio_common;       /* audio_common_msgs on audio + audio_info, not SignalChunk */
  unsigned audio_channel;  /* the channel taken from each audio_common frame */
  double audio_full_scale; /* the microphone's value at digital full scale [audio_unit] */
  /* --- rviz markers --- */
  bool markers_enabled;
  double marker_lifetime_s;
  double marker_strike_distance_m; /* hammer link origin to strike point, for display */
  double marker_arrow_length_m;
  /* --- the live strike picture (~strike_plot) --- */
  int strike_plot_width_px, strike_plot_height_px;
} af_node_config;

/* Loads every table row from ~ (checked by the table), the URDF (hammer
 * mass and tip radius unless overridden, then checked by the table too),
 * and derives cfg->lane with af_lane_config_derive. On failure returns
 * AF_EINVAL (bad or missing parameter), AF_ENODATA / AF_EIO (URDF) or
 * AF_ENOMEM, with a one-line reason in err; cfg then holds nothing to free. */
af_status af_params_load(af_ros *ros, af_node_config *cfg, char *err, size_t err_len);
/* Frees the URDF; safe on a zeroed or freed config. */
void af_params_destroy(af_node_config *cfg);

#ifdef __cplusplus
}
#endif
#endif
