/* af_tf.h — the rig's frames through tf2 (tf2_ros::Buffer and
 * TransformListener on /tf and /tf_static), behind a C API.
 *
 * The node reads the strike geometry through TF: the hammer's axis is given
 * in the frame its slide is mounted on (af_hammer_geometry.mount_frame, from
 * the URDF), and TF turns it into the frame of each AppleEstimate, be that
 * frame a link of the rig's URDF (published by robot_state_publisher) or a
 * frame that exists only in TF (a camera calibrated with a static
 * transform).
 *
 * The listener's callbacks go to the af_ros's callback queue: the buffer
 * fills in af_ros_spin_once, in arrival order with the other messages, and
 * no thread polls a queue of its own (tf2_ros's dedicated thread woke every
 * 10 ms, ~0.25 % of a core); lookups never wait.
 * Allocation: the buffer and the listener in af_tf_create; tf2 allocates
 * inside a lookup (frame names, its cache), which the node does once per
 * AppleEstimate, never per chunk. Every C++ exception is caught: a failed
 * lookup is a status with a one-line reason. */
#ifndef AF_TF_H
#define AF_TF_H

#include <stdbool.h>
#include <stddef.h>

#include "af_ros.h"
#include "status.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct af_tf af_tf;

/* A rigid transform taking coordinates in a source frame to a target frame:
 * p_target = rotation p_source + translation_m. */
typedef struct {
  double rotation[9];      /* row-major 3 x 3 */
  double translation_m[3]; /* the source frame's origin in the target frame [m] */
} af_transform;

/* Starts the buffer (cache 10 s) and its listener. r must outlive the
 * af_tf (destroy the af_tf first). AF_EROS, AF_ENOMEM. */
af_status af_tf_create(af_ros *r, af_tf **out);
void af_tf_destroy(af_tf *t); /* NULL-safe */

/* The latest transform from source to target (the rig's frames are fixed:
 * the newest data of each is used, not the apple's stamp). Does not wait.
 * AF_ENODATA when tf2 cannot transform, with why (may be NULL) saying it in
 * a few words: "frame 'x' does not exist in TF", "'x' and 'y' are not
 * connected in TF", ...; AF_EINVAL for a NULL or empty name. */
af_status af_tf_lookup(af_tf *t, const char *target, const char *source, af_transform *out,
                       char *why, size_t len);

/* Whether frame is in the buffer now. */
bool af_tf_frame_known(af_tf *t, const char *frame);

#ifdef __cplusplus
}
#endif
#endif
