/* params.h — every parameter of firmness_node, loaded from the private
 * namespace and validated at start-up.
 *
 * Defaults live in one place only: config/station.yaml and the cultivar's
 * YAML (config/jonagold.yaml), which the launch files load into ~. The code
 * requires each parameter present; only the hammer overrides
 * (~hammer_mass_kg, ~hammer_tip_radius_m) are optional, since the URDF is
 * their normal source. Any bad value stops the node with a message naming
 * the parameter, its value and the accepted range.
 */
#ifndef AF_NODE_PARAMS_H
#define AF_NODE_PARAMS_H

#include <stdbool.h>
#include <stddef.h>

#include "af_msgs.h"
#include "af_ros.h"
#include "af_urdf.h"
#include "measure.h"
#include "model.h"
#include "strike.h"

#ifdef __cplusplus
extern "C" {
#endif

#define AF_PATH_MAX 512
#define AF_NAME_MAX 64
#define AF_SOURCE_TEXT_MAX 160

/* One sampled input stream (force or audio). */
typedef struct {
  double sample_rate_hz;      /* expected rate; other rates are refused and counted */
  double buffer_s;            /* ring length [s] */
  size_t capacity_samples;    /* ceil(buffer_s * sample_rate_hz) */
  char units[2][AF_UNIT_MAX]; /* accepted SignalChunk.unit values ("" = unused slot) */
} af_stream_config;

/* The measured strikes: the detector on the force stream, the measurement of
 * each strike, the queue of strikes waiting for their audio, and the match
 * to an AppleEstimate. */
typedef struct {
  af_strike_config strike;       /* ~strike_*; sample rate = ~force_sample_rate_hz */
  af_measure_config measure;     /* ~measure_*; response and fit sized from them */
  size_t pending_size;           /* ~strike_pending_size: strikes waiting for audio */
  size_t pulse_capacity_samples; /* longest event span the detector can emit */
  size_t audio_window_samples;   /* round(measure_audio_window_s * audio rate) */
  size_t noise_window_samples;   /* round(measure_noise_window_s * audio rate); 0 = none */
  double apple_stale_after_s;    /* ~apple_stale_after_s */
} af_measured_config;

typedef struct {
  /* --- rig (station.yaml, URDF) --- */
  char hammer_link[AF_NAME_MAX];
  char urdf_file[AF_PATH_MAX]; /* "" = the robot_description parameter */
  af_urdf *urdf;               /* NULL when running on parameters alone */
  bool hammer_axis_known;      /* the URDF gave the strike axis */
  af_hammer_geometry hammer;   /* mass and tip radius after overrides; axis in hammer.root_frame */
  af_vec3 hammer_origin_m;     /* of the hammer link in the root frame (for the markers) */
  char urdf_source[AF_SOURCE_TEXT_MAX]; /* where the URDF came from, or why there is none */
  char hammer_mass_source[AF_SOURCE_TEXT_MAX];
  char hammer_tip_source[AF_SOURCE_TEXT_MAX];
  /* --- the strike and the criteria --- */
  af_model_params model;         /* template: per-apple mass and R2 filled in later */
  double latitude_tolerance_rad; /* from ~latitude_tolerance_deg */
  double r2_search_low_m;        /* bracket of af_model_min_strike_radius */
  double r2_search_high_m;
  double strike_radius_min_m; /* accepted AppleEstimate.strike_radius (when not 0) */
  double strike_radius_max_m;
  /* --- streams --- */
  af_stream_config force, audio;
  double stream_stale_after_s;
  /* --- measured strikes --- */
  af_measured_config measured;
  /* --- rviz markers --- */
  bool markers_enabled;
  double marker_lifetime_s;
  double marker_strike_distance_m; /* hammer link origin to strike point, for display */
  double marker_arrow_length_m;
  /* --- cultivar --- */
  char cultivar[AF_NAME_MAX];
  double modulus_min_pa, modulus_max_pa; /* firmness range of the resonance band */
  double mass_min_kg, mass_max_kg;
  double equatorial_radius_min_m, equatorial_radius_max_m;
  double aspect_ratio_min, aspect_ratio_max; /* polar / equatorial semi-axis */
  double resonance_xi;                       /* Lamb root of the cultivar's Poisson ratio */
} af_node_config;

/* Loads and validates everything, loads the URDF. On failure returns
 * AF_EINVAL (bad or missing parameter), AF_ENODATA / AF_EIO (URDF) or
 * AF_ENOMEM, with a one-line reason in err; cfg then holds nothing to free. */
af_status af_params_load(af_ros *ros, af_node_config *cfg, char *err, size_t err_len);
/* Frees the URDF; safe on a zeroed or freed config. */
void af_params_free(af_node_config *cfg);

#ifdef __cplusplus
}
#endif
#endif
