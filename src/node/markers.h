/* markers.h — the rviz picture of one apple: the spheroid, the strike point,
 * the hammer axis, the rotation advice and a text, as one MarkerArray in the
 * AppleEstimate's frame. Markers keep fixed ids so each apple replaces the
 * last; those that do not apply (no rotation, unknown axis) are deleted. */
#ifndef AF_NODE_MARKERS_H
#define AF_NODE_MARKERS_H

#include <stdbool.h>
#include <stddef.h>

#include "af_msgs.h"

#ifdef __cplusplus
extern "C" {
#endif

enum {
  AF_MARKER_APPLE = 0,
  AF_MARKER_STRIKE,
  AF_MARKER_HAMMER,
  AF_MARKER_ROTATION,
  AF_MARKER_LABEL,
  AF_MARKERS_COUNT
};

typedef struct {
  af_header header;   /* the AppleEstimate's */
  double centre_m[3]; /* apple centre in header.frame_id */
  double equatorial_radius_m;
  double polar_semi_axis_m;
  double stem_axis[3];  /* any length; zero = unknown (drawn as a sphere) */
  bool direction_known; /* the strike direction is known in this frame */
  double normal[3];     /* unit outward normal at the strike point */
  bool rotate;
  double rotation_axis[3]; /* unit */
  bool reliable;
  const char *text; /* label above the apple */
  double lifetime_s;
  double arrow_length_m;
} af_markers_scene;

/* Fills out[AF_MARKERS_COUNT]; returns AF_MARKERS_COUNT. No allocation. */
size_t af_markers_build(const af_markers_scene *s, af_marker out[AF_MARKERS_COUNT]);

/* The measured strike's line of text (namespace "firmness_measured", id 0,
 * replaced by each strike), one line above the apple's label: header, centre
 * and the larger semi-axis top_m of the apple it was matched to. No
 * allocation. */
void af_markers_measured_label(const af_header *header, const double centre_m[3], double top_m,
                               const char *text, double lifetime_s, af_marker *out);

#ifdef __cplusplus
}
#endif
#endif
