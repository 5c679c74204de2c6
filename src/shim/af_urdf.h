/* af_urdf.h — the rig's URDF read through urdfdom, behind a C API.
 *
 * The hammer link gives the hammer's mass (inertial/mass [kg]) and tip
 * geometry (collision: sphere -> tip radius [m]; box or cylinder -> flat
 * face, radius 0). The strike direction is the axis of the hammer's parent
 * joint (a prismatic joint along which the hammer moves, positive towards the
 * fruit), given in the frame the joint is mounted on (its parent link); the
 * node turns it into the vision frame through TF (af_tf.h). Frames are also
 * composed along the tree with every movable joint at zero (root_frame,
 * af_urdf_rotation_to_root), for tools and tests without TF. */
#ifndef AF_URDF_H
#define AF_URDF_H

#include <stddef.h>

#include "af_msgs.h"
#include "status.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct af_urdf af_urdf;

/* Parses a URDF XML string. On failure *out is NULL and err (may be NULL)
 * receives a one-line reason. */
af_status af_urdf_parse(const char *xml, af_urdf **out, char *err, size_t err_len);
/* Reads and parses a URDF file. */
af_status af_urdf_load(const char *path, af_urdf **out, char *err, size_t err_len);
void af_urdf_destroy(af_urdf *u); /* NULL-safe */

typedef struct {
  double mass_kg;      /* inertial mass of the hammer link */
  double tip_radius_m; /* collision sphere radius; 0 = flat face (box/cylinder) */
  af_vec3 strike_axis; /* unit strike direction in root_frame */
  char root_frame[AF_FRAME_ID_MAX];
  /* The hammer's mount, for TF (af_tf.h): the parent link of its joint, a
   * frame that does not move with the hammer, and in it the unit strike
   * direction and the hammer link's origin with the joint at zero [m]. */
  char mount_frame[AF_FRAME_ID_MAX];
  af_vec3 mount_axis;
  af_vec3 mount_origin_m;
} af_hammer_geometry;

/* Reads the hammer from link hammer_link. AF_ENODATA with err naming what is
 * missing (the link, its inertial, its collision geometry, its parent joint
 * axis); AF_EINVAL for an unusable value (mass <= 0, unsupported geometry). */
af_status af_urdf_hammer(const af_urdf *u, const char *hammer_link, af_hammer_geometry *out,
                         char *err, size_t err_len);

/* Rotation matrix (row-major 3x3) taking vectors in link's frame to the root
 * frame, movable joints at zero. AF_ENODATA when link is absent. */
af_status af_urdf_rotation_to_root(const af_urdf *u, const char *link, double r[9]);

/* Origin of link in the root frame [m], movable joints at zero. */
af_status af_urdf_position_in_root(const af_urdf *u, const char *link, af_vec3 *p);

#ifdef __cplusplus
}
#endif
#endif
