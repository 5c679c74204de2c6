/* status_marker.c — the diagnostic status as an rviz text marker (see status_marker.h). */
#include "status_marker.h"

#include <string.h>

#include "text.h"

#define AF_STATUS_HEIGHT_M 0.012 /* text height */

void af_status_marker(const char *frame, const double position_m[3], af_diag_level level,
                      const char *text, af_marker *out)
{
  static const float rgb[4][3] = {{0.45f, 0.9f, 0.45f}, /* OK */
                                  {1.0f, 0.65f, 0.2f},  /* WARN */
                                  {1.0f, 0.3f, 0.3f},   /* ERROR */
                                  {0.7f, 0.7f, 0.7f}};  /* STALE */
  const int k = level >= AF_DIAG_OK && level <= AF_DIAG_STALE ? (int)level : 3;
  memset(out, 0, sizeof *out);
  af_text(out->header.frame_id, sizeof out->header.frame_id, "%s", frame);
  af_text(out->ns, sizeof out->ns, "firmness_status");
  out->id = 0;
  out->type = AF_MARKER_TEXT;
  out->orientation[3] = 1.0;
  out->position.x = position_m[0];
  out->position.y = position_m[1];
  out->position.z = position_m[2];
  out->scale.z = AF_STATUS_HEIGHT_M;
  out->rgba[0] = rgb[k][0];
  out->rgba[1] = rgb[k][1];
  out->rgba[2] = rgb[k][2];
  out->rgba[3] = 1.0f;
  af_text(out->text, sizeof out->text, "%s", text ? text : "");
}
