/* af_msgs.h — C mirrors of this package's ROS messages (the .msg files in msg/), plus the
 * few standard ones the node uses. Plain structs, SI units in the names.
 *
 * Strings are fixed-size, NUL-terminated arrays: the shim truncates longer
 * incoming strings (a frame_id longer than AF_FRAME_ID_MAX - 1 is cut) and
 * never overflows. Arrays in incoming messages are borrowed: the pointer is
 * valid only during the callback. */
#ifndef AF_MSGS_H
#define AF_MSGS_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#define AF_FRAME_ID_MAX 64
#define AF_TEXT_MAX 256
#define AF_UNIT_MAX 16
#define AF_SOURCE_MAX 16
#define AF_GRADE_NAME_TEXT 32 /* = AF_GRADE_NAME_MAX of src/core/lane/grade.h */

typedef struct {
  uint32_t sec;
  uint32_t nsec;
} af_time;

typedef struct {
  af_time stamp;
  char frame_id[AF_FRAME_ID_MAX];
} af_header;

typedef struct {
  double x, y, z;
} af_vec3;

/* std_msgs/String (publish only): a text the node states once, latched (its
 * settings snapshot, the URDF it read) */
typedef struct {
  const char *data; /* caller-owned, NUL-terminated */
} af_text_msg;

/* acoustic_firmness/SignalChunk */
typedef struct {
  af_header header;      /* stamp = time of data[0] */
  uint64_t first_sample; /* running index of data[0] */
  double sample_rate_hz;
  char unit[AF_UNIT_MAX];
  const float *data; /* borrowed (incoming) or caller-owned (outgoing) */
  size_t n;          /* samples in data */
} af_signal_chunk;

/* acoustic_firmness/AppleEstimate */
typedef struct {
  af_header header;
  uint32_t apple_id;
  double mass_kg;
  double equatorial_radius_m;
  double strike_radius_m; /* 0 = unknown */
  af_vec3 stem_axis;      /* in header.frame_id; zero = unknown */
  double confidence;      /* [0, 1] */
} af_apple_estimate;

/* acoustic_firmness/ExcitationBand */
typedef struct {
  af_header header;
  uint32_t apple_id;
  double contact_time_s;
  double peak_force_n;
  uint8_t lobe;
  double band_low_hz;
  double band_high_hz;
  double resonance_hz;
  double resonance_low_hz;
  double resonance_high_hz;
  double excitation_at_resonance_db;
} af_excitation_band;

/* acoustic_firmness/StrikeAdvice */
typedef struct {
  af_header header;
  uint32_t apple_id;
  double strike_radius_m;
  double min_strike_radius_m;
  double strike_latitude_rad;
  bool rotate;
  af_vec3 rotation_axis;
  double rotation_angle_rad;
  char text[AF_TEXT_MAX];
} af_strike_advice;

/* acoustic_firmness/Reliability */
typedef struct {
  af_header header;
  uint32_t apple_id;
  char source[AF_SOURCE_MAX]; /* "predicted" or "measured" */
  bool reliable;
  bool excites_mode;
  bool no_damage;
  double max_shear_stress_pa;
  double yield_shear_stress_pa;
  char reason[AF_TEXT_MAX];
} af_reliability;

/* acoustic_firmness/StrikeReport: one measured strike. NaN where a figure
 * could not be measured. */
typedef struct {
  af_header header;                 /* stamp = contact start; frame = the force chunk's */
  uint32_t apple_id;                /* 0 = no apple estimate matched */
  double contact_time_s;            /* [s] */
  double peak_force_n;              /* [N] */
  double impulse_n_s;               /* [N s] */
  double band_low_hz;               /* half-power band of the configured lobe [Hz] */
  double band_high_hz;              /* [Hz] */
  double resonance_hz;              /* 0S2 from the microphone [Hz] */
  double resonance_q;               /* quality factor [-] */
  double snr_db;                    /* [dB] */
  double stiffness_factor;          /* f^2 m^(2/3) [Hz^2 kg^(2/3)] */
  double modulus_from_resonance_pa; /* Lamb, divided by the modulus factor [Pa] */
  double fitted_modulus_pa;         /* impact model fitted to the pulse [Pa] */
  double fitted_restitution;        /* [-] */
  double fit_residual;              /* RMS / peak [-] */
  double delivered_energy_j;        /* m1 v0^2 / 2 [J]; NaN: v0 not known */
  double absorbed_energy_j;         /* (1 - e^2) of it, e fitted [J]; NaN: no fit */
  bool double_hit;
  bool clipped;
  uint32_t lost_samples; /* force samples missing around the strike */
  bool audio_clipped;    /* the microphone saturated in the strike's audio window */
  double audio_lag_s, audio_lag_applied_s; /* the sound's onset minus the contact start; the
                                              window's shift [s] */
  /* The firmness grade (src/core/lane/grade.h). */
  uint8_t grade_index;            /* class 1..N of grade_classes, softest first; 0 = ungraded */
  char grade[AF_GRADE_NAME_TEXT]; /* the class name, or "ungraded" */
  char grade_reason[AF_TEXT_MAX]; /* why ungraded; "" when graded */
  bool tap_only;                  /* measured from the microphone alone (tap-only) */
  char judged_from_model[AF_TEXT_MAX]; /* judged from the prediction only; "" when none */
} af_strike_report;

/* visualization_msgs/Marker (the subset the node draws); published as a
 * visualization_msgs/MarkerArray through af_marker_array. */
typedef enum {
  AF_MARKER_ARROW = 0,
  AF_MARKER_CUBE = 1,
  AF_MARKER_SPHERE = 2,
  AF_MARKER_CYLINDER = 3,
  AF_MARKER_LINE_STRIP = 4,
  AF_MARKER_TEXT = 9
} af_marker_type;

#define AF_MARKER_MAX_POINTS 64

typedef struct {
  af_header header;
  char ns[32];
  int32_t id;
  af_marker_type type;
  bool delete_marker;                   /* action DELETE instead of ADD */
  af_vec3 position;                     /* [m] */
  double orientation[4];                /* quaternion x, y, z, w */
  af_vec3 scale;                        /* [m] */
  float rgba[4];                        /* [0, 1] */
  double lifetime_s;                    /* 0 = forever */
  char text[AF_TEXT_MAX];               /* TEXT markers */
  af_vec3 points[AF_MARKER_MAX_POINTS]; /* ARROW (2 points) and LINE_STRIP */
  size_t n_points;
} af_marker;

typedef struct {
  const af_marker *markers;
  size_t n;
} af_marker_array;

/* sensor_msgs/Image (publish only): a picture for rviz's Image display, e.g.
 * the node's ~strike_plot. The pixels are borrowed: the shim copies them
 * into its kept message when publishing. */
#define AF_IMAGE_ENCODING_MAX 16

typedef struct {
  af_header header;
  uint32_t height_px, width_px;
  char encoding[AF_IMAGE_ENCODING_MAX]; /* sensor_msgs/image_encodings, e.g. "rgb8" */
  uint32_t step_bytes;                  /* bytes per row */
  const uint8_t *data;                  /* step_bytes x height_px bytes, rows top first */
} af_image;

#ifdef __cplusplus
}
#endif
#endif
