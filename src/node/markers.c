/* markers.c — rviz markers of one apple. */
#include "markers.h"

#include <math.h>
#include <string.h>

#include "advice.h"
#include "text.h"

/* Display sizes [m]: a strike point visible next to an 80 mm apple. */
#define AF_STRIKE_POINT_DIAMETER_M 0.006
#define AF_ARROW_SHAFT_M 0.004
#define AF_ARROW_HEAD_M 0.008
#define AF_LABEL_HEIGHT_M 0.012

static void set_rgba(af_marker *m, float r, float g, float b, float a)
{
  m->rgba[0] = r, m->rgba[1] = g, m->rgba[2] = b, m->rgba[3] = a;
}

static void to_vec(const double v[3], af_vec3 *out)
{
  out->x = v[0], out->y = v[1], out->z = v[2];
}

static void base(const af_markers_scene *s, int id, af_marker_type type, af_marker *m)
{
  memset(m, 0, sizeof *m);
  m->header = s->header;
  af_text(m->ns, sizeof m->ns, "firmness");
  m->id = id;
  m->type = type;
  m->orientation[3] = 1.0;
  m->lifetime_s = s->lifetime_s;
}

/* Quaternion (x, y, z, w) turning +z onto the unit vector u: the marker's
 * z scale then lies along the stem axis. */
static void quat_z_to(const double u[3], double q[4])
{
  double c = u[2];        /* cos of the angle between z and u */
  if (c < -1.0 + 1e-12) { /* opposite: half a turn about x */
    q[0] = 1.0, q[1] = q[2] = q[3] = 0.0;
    return;
  }
  /* q = (z x u, 1 + z.u) normalised: the half-angle form. */
  const double v[4] = {-u[1], u[0], 0.0, 1.0 + c};
  double n = sqrt(v[0] * v[0] + v[1] * v[1] + v[3] * v[3]);
  for (int k = 0; k < 4; k++)
    q[k] = v[k] / n;
}

static void apple(const af_markers_scene *s, af_marker *m)
{
  /* A direction whatever its finite length: scaled by its largest
   * component first, so that 1e200 or 1e-170 neither overflows nor vanishes. */
  const double *v = s->stem_axis;
  double big = fmax(fabs(v[0]), fmax(fabs(v[1]), fabs(v[2])));
  bool finite = isfinite(v[0]) && isfinite(v[1]) && isfinite(v[2]);
  double w[3] = {0.0, 0.0, 0.0};
  for (int k = 0; k < 3 && finite && big > 0.0; k++)
    w[k] = v[k] / big;
  double len = sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
  double a = s->equatorial_radius_m;
  double c = len > 0.0 ? s->polar_semi_axis_m : a; /* orientation unknown: a sphere */
  base(s, AF_MARKER_APPLE, AF_MARKER_SPHERE, m);
  to_vec(s->centre_m, &m->position);
  if (len > 0.0) {
    double u[3] = {w[0] / len, w[1] / len, w[2] / len};
    quat_z_to(u, m->orientation);
  }
  m->scale.x = m->scale.y = 2.0 * a;
  m->scale.z = 2.0 * c;
  if (s->reliable)
    set_rgba(m, 0.2f, 0.8f, 0.2f, 0.6f);
  else
    set_rgba(m, 0.9f, 0.2f, 0.1f, 0.6f);
}

static void arrow(const af_markers_scene *s, int id, const double from[3], const double to[3],
                  af_marker *m)
{
  base(s, id, AF_MARKER_ARROW, m);
  to_vec(from, &m->points[0]);
  to_vec(to, &m->points[1]);
  m->n_points = 2;
  m->scale.x = AF_ARROW_SHAFT_M;
  m->scale.y = AF_ARROW_HEAD_M;
  m->scale.z = AF_ARROW_HEAD_M;
}

static void deleted(const af_markers_scene *s, int id, af_marker *m)
{
  base(s, id, AF_MARKER_SPHERE, m);
  m->delete_marker = true;
}

size_t af_markers_build(const af_markers_scene *s, af_marker out[AF_MARKERS_COUNT])
{
  apple(s, &out[AF_MARKER_APPLE]);
  const double L = s->arrow_length_m;
  if (s->direction_known) {
    double p[3];
    af_advice_surface_point_m(s->equatorial_radius_m, s->polar_semi_axis_m, s->stem_axis, s->normal,
                              p);
    for (int k = 0; k < 3; k++)
      p[k] += s->centre_m[k];
    af_marker *sp = &out[AF_MARKER_STRIKE];
    base(s, AF_MARKER_STRIKE, AF_MARKER_SPHERE, sp);
    to_vec(p, &sp->position);
    sp->scale.x = sp->scale.y = sp->scale.z = AF_STRIKE_POINT_DIAMETER_M;
    set_rgba(sp, 1.0f, 1.0f, 0.0f, 1.0f);
    /* The hammer comes in along -n and stops at the strike point. */
    double from[3] = {p[0] + L * s->normal[0], p[1] + L * s->normal[1], p[2] + L * s->normal[2]};
    arrow(s, AF_MARKER_HAMMER, from, p, &out[AF_MARKER_HAMMER]);
    set_rgba(&out[AF_MARKER_HAMMER], 0.6f, 0.6f, 0.6f, 1.0f);
  } else {
    deleted(s, AF_MARKER_STRIKE, &out[AF_MARKER_STRIKE]);
    deleted(s, AF_MARKER_HAMMER, &out[AF_MARKER_HAMMER]);
  }
  if (s->rotate) {
    const double *c = s->centre_m, *k = s->rotation_axis;
    double to[3] = {c[0] + L * k[0], c[1] + L * k[1], c[2] + L * k[2]};
    arrow(s, AF_MARKER_ROTATION, c, to, &out[AF_MARKER_ROTATION]);
    set_rgba(&out[AF_MARKER_ROTATION], 0.2f, 0.4f, 1.0f, 1.0f);
  } else {
    deleted(s, AF_MARKER_ROTATION, &out[AF_MARKER_ROTATION]);
  }
  af_marker *t = &out[AF_MARKER_LABEL];
  base(s, AF_MARKER_LABEL, AF_MARKER_TEXT, t);
  double top =
      s->equatorial_radius_m > s->polar_semi_axis_m ? s->equatorial_radius_m : s->polar_semi_axis_m;
  /* Above the apple: towards the hammer (the outward normal at the strike
   * point) when the strike direction is known, else +z of the frame (which
   * is down in a camera's optical frame). */
  const double up[3] = {s->direction_known ? s->normal[0] : 0.0,
                        s->direction_known ? s->normal[1] : 0.0,
                        s->direction_known ? s->normal[2] : 1.0};
  const double lift = top + 2.0 * AF_LABEL_HEIGHT_M;
  t->position.x = s->centre_m[0] + lift * up[0];
  t->position.y = s->centre_m[1] + lift * up[1];
  t->position.z = s->centre_m[2] + lift * up[2];
  t->scale.z = AF_LABEL_HEIGHT_M;
  set_rgba(t, 1.0f, 1.0f, 1.0f, 1.0f);
  af_text(t->text, sizeof t->text, "%s", s->text ? s->text : "");
  return AF_MARKERS_COUNT;
}

void af_markers_measured_label(const af_header *header, const double centre_m[3], double top_m,
                               const char *text, double lifetime_s, af_marker *out)
{
  memset(out, 0, sizeof *out);
  out->header = *header;
  af_text(out->ns, sizeof out->ns, "firmness_measured");
  out->id = 0;
  out->type = AF_MARKER_TEXT;
  out->orientation[3] = 1.0;
  out->lifetime_s = lifetime_s;
  /* The apple's label is at top + 2 h; this line 1.5 h above it. */
  out->position.x = centre_m[0];
  out->position.y = centre_m[1];
  out->position.z = centre_m[2] + top_m + 3.5 * AF_LABEL_HEIGHT_M;
  out->scale.z = AF_LABEL_HEIGHT_M;
  set_rgba(out, 0.6f, 0.9f, 1.0f, 1.0f);
  af_text(out->text, sizeof out->text, "%s", text ? text : "");
}
