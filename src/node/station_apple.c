/* station_apple.c — each AppleEstimate: the rig's geometry through TF, the
 * prediction's band, advice and reliability, the markers (station_private.h). */
#include "station_private.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static double deg(double rad)
{
  return rad * 180.0 / M_PI;
}

static void vec_of(const af_vec3 *v, double out[3])
{
  out[0] = v->x, out[1] = v->y, out[2] = v->z;
}

/* --- geometry -------------------------------------------------------------- */

/* r v (r row-major 3 x 3). */
static void rotate_vec(const double r[9], const double v[3], double out[3])
{
  for (int i = 0; i < 3; i++)
    out[i] = r[3 * i] * v[0] + r[3 * i + 1] * v[1] + r[3 * i + 2] * v[2];
}

/* The strike direction in the apple's frame: the URDF's hammer axis (in the
 * frame the hammer's slide is mounted on) turned into that frame through TF;
 * zero, with the reason in the note, when it cannot be. */
static void strike_direction(af_station *st, const char *frame, af_apple_work *w, af_apple *a)
{
  const af_node_config *c = st->cfg;
  double *d = a->strike_direction;
  char why[AF_TEXT_MAX];
  d[0] = d[1] = d[2] = 0.0;
  if (!c->hammer_axis_known) {
    af_text(a->direction_note, sizeof a->direction_note, "hammer axis unknown (no URDF)");
    return;
  }
  if (frame[0] == '\0') {
    af_text(a->direction_note, sizeof a->direction_note, "the AppleEstimate has no frame_id");
    return;
  }
  w->frame_known =
      af_tf_lookup(st->tf, frame, c->hammer.mount_frame, &w->to_frame, why, sizeof why) == AF_OK;
  if (!w->frame_known) {
    af_text(a->direction_note, sizeof a->direction_note, "no TF from the rig's '%s' to '%s': %s",
            c->hammer.mount_frame, frame, why);
    return;
  }
  double axis[3];
  vec_of(&c->hammer.mount_axis, axis);
  rotate_vec(w->to_frame.rotation, axis, d);
}

/* Where the apple's centre is drawn: the strike point lies
 * marker_strike_distance_m along the hammer axis from the hammer link's
 * origin (joint at zero), and the centre behind it. Display only; the
 * frame's origin when the frame is unknown. */
static void marker_centre(const af_node_config *c, const af_apple_estimate *a,
                          const af_prediction *pr, af_apple_work *w)
{
  double stem[3], p[3], q[3];
  memset(w->centre_m, 0, sizeof w->centre_m);
  if (!w->frame_known)
    return;
  const af_vec3 *h = &c->hammer.mount_origin_m, *s = &c->hammer.mount_axis;
  const double D = c->marker_strike_distance_m;
  const double strike[3] = {h->x + D * s->x, h->y + D * s->y, h->z + D * s->z}; /* mount frame */
  rotate_vec(w->to_frame.rotation, strike, q);
  vec_of(&a->stem_axis, stem);
  af_advice_surface_point_m(a->equatorial_radius_m, pr->polar_semi_axis_m, stem, pr->geo.normal, p);
  for (int i = 0; i < 3; i++)
    w->centre_m[i] = q[i] + w->to_frame.translation_m[i] - p[i];
}

/* The lane's view of the estimate, with the strike direction in its frame. */
static void apple_of(af_station *st, const af_apple_estimate *m, af_apple_work *w, af_apple *a)
{
  memset(a, 0, sizeof *a);
  a->apple_id = m->apple_id;
  a->stamp_ns = af_time_to_ns(m->header.stamp);
  a->mass_kg = m->mass_kg;
  a->equatorial_radius_m = m->equatorial_radius_m;
  a->strike_radius_m = m->strike_radius_m;
  vec_of(&m->stem_axis, a->stem_axis);
  a->confidence = m->confidence;
  strike_direction(st, m->header.frame_id, w, a);
}

/* --- outputs --------------------------------------------------------------- */

static void fill_band(const af_apple_estimate *a, const af_prediction *pr, af_excitation_band *b)
{
  const af_model_result *r = &pr->result;
  memset(b, 0, sizeof *b);
  b->header = a->header;
  b->apple_id = a->apple_id;
  b->contact_time_s = r->impact.contact_time_s;
  b->peak_force_n = r->impact.peak_force_n;
  b->lobe = (uint8_t)pr->params.lobe;
  b->band_low_hz = r->band.band_low_hz; /* zeros when the lobe does not exist */
  b->band_high_hz = r->band.band_high_hz;
  b->resonance_hz = r->resonance_hz;
  b->resonance_low_hz = pr->resonance_low_hz;
  b->resonance_high_hz = pr->resonance_high_hz;
  b->excitation_at_resonance_db = r->excitation_at_resonance_db;
}

/* "the strike point is 35 deg towards the stem", or why it is not known. */
static void where_text(const af_apple *a, const af_prediction *pr, char *buf, size_t len)
{
  double lat_deg = deg(pr->geo.latitude_rad);
  if (!pr->geo.direction_known)
    af_text(buf, len, "strike point unknown (%s)%s", a->direction_note,
            pr->geo.r2_source == AF_R2_EQUATORIAL ? ", R2 = the equatorial radius" : "");
  else if (!pr->geo.latitude_known)
    af_text(buf, len, "stem axis unknown, latitude taken as the equator");
  else if (fabs(lat_deg) < 0.5)
    af_text(buf, len, "strike point on the equator");
  else
    af_text(buf, len, "strike point %.0f deg from the equator towards the %s", fabs(lat_deg),
            lat_deg > 0.0 ? "stem" : "calyx");
}

static void advice_text(const af_node_config *c, const af_apple_estimate *m, const af_apple *a,
                        const af_prediction *pr, char *buf, size_t len)
{
  char where[160], radius[96], todo[160];
  const af_advice_rotation *rot = &pr->rotation;
  where_text(a, pr, where, sizeof where);
  if (pr->min_strike_radius_m > 0.0)
    af_text(radius, sizeof radius, "R2 %.1f mm %s the %.1f mm minimum",
            pr->geo.strike_radius_m * 1e3, rot->radius_small ? "is below" : "meets",
            pr->min_strike_radius_m * 1e3);
  else
    af_text(radius, sizeof radius, "R2 %.1f mm; no R2 in [%g, %g] mm is reliable",
            pr->geo.strike_radius_m * 1e3, c->lane.r2_search_low_m * 1e3,
            c->lane.r2_search_high_m * 1e3);
  if (!rot->rotate)
    af_text(todo, sizeof todo, "strike as placed");
  else if (rot->latitude_off) {
    /* Said as a positive angle: -phi about k is +phi about -k. */
    double sign = rot->angle_rad < 0.0 ? -1.0 : 1.0;
    af_text(todo, sizeof todo,
            "turn the apple %.0f deg right-handed about (%.2f, %.2f, %.2f) in %s to bring the "
            "equator under the hammer",
            deg(fabs(rot->angle_rad)), sign * rot->axis[0], sign * rot->axis[1],
            sign * rot->axis[2], m->header.frame_id);
  } else
    af_text(todo, sizeof todo, "turn the apple to strike a flatter spot (R2 >= %.1f mm)",
            pr->min_strike_radius_m * 1e3);
  af_text(buf, len, "apple %u: %s; %s: %s.", m->apple_id, where, radius, todo);
}

static void fill_advice(const af_node_config *c, const af_apple_estimate *m, const af_apple *a,
                        const af_prediction *pr, af_strike_advice *adv)
{
  memset(adv, 0, sizeof *adv);
  adv->header = m->header;
  adv->apple_id = m->apple_id;
  adv->strike_radius_m = pr->geo.strike_radius_m;
  adv->min_strike_radius_m = pr->min_strike_radius_m;
  adv->strike_latitude_rad = pr->geo.latitude_rad;
  adv->rotate = pr->rotation.rotate;
  adv->rotation_axis.x = pr->rotation.axis[0];
  adv->rotation_axis.y = pr->rotation.axis[1];
  adv->rotation_axis.z = pr->rotation.axis[2];
  adv->rotation_angle_rad = pr->rotation.angle_rad;
  advice_text(c, m, a, pr, adv->text, sizeof adv->text);
}

static void fill_reliability(const af_apple_estimate *a, const af_prediction *pr,
                             af_reliability *rel)
{
  const af_model_result *r = &pr->result;
  memset(rel, 0, sizeof *rel);
  rel->header = a->header;
  rel->apple_id = a->apple_id;
  af_text(rel->source, sizeof rel->source, "predicted");
  rel->excites_mode = r->excites_mode;
  rel->no_damage = r->no_damage;
  rel->max_shear_stress_pa = r->max_shear_stress_pa;
  rel->yield_shear_stress_pa = r->yield_shear_stress_pa;
  rel->reliable = pr->reliable;
  af_text(rel->reason, sizeof rel->reason, "%s", pr->reason);
}

static void publish_markers(af_station *st, const af_apple_estimate *a, const af_prediction *pr,
                            const af_apple_work *w)
{
  const af_node_config *c = st->cfg;
  char label[AF_TEXT_MAX];
  af_text(label, sizeof label, "apple %u: band %.0f-%.0f Hz, 0S2 %.0f Hz, %s", a->apple_id,
          st->band.band_low_hz, st->band.band_high_hz, st->band.resonance_hz,
          st->reliability.reliable ? "reliable" : "NOT reliable");
  af_markers_scene scene;
  memset(&scene, 0, sizeof scene);
  scene.header = a->header;
  memcpy(scene.centre_m, w->centre_m, sizeof scene.centre_m);
  scene.equatorial_radius_m = a->equatorial_radius_m;
  scene.polar_semi_axis_m = pr->polar_semi_axis_m;
  vec_of(&a->stem_axis, scene.stem_axis);
  scene.direction_known = pr->geo.direction_known;
  memcpy(scene.normal, pr->geo.normal, sizeof scene.normal);
  scene.rotate = pr->rotation.rotate;
  memcpy(scene.rotation_axis, pr->rotation.axis, sizeof scene.rotation_axis);
  scene.reliable = st->reliability.reliable;
  scene.text = label;
  scene.lifetime_s = c->marker_lifetime_s;
  scene.arrow_length_m = c->marker_arrow_length_m;
  af_marker_array arr = {st->markers, af_markers_build(&scene, st->markers)};
  if (af_ros_publish(st->markers_pub, &arr) != AF_OK)
    af_ros_log(st->ros, AF_LOG_WARN, "markers not published: %s", af_ros_last_error(st->ros));
}

static void publish(af_station *st, af_ros_pub *pub, const void *msg, const char *topic)
{
  if (af_ros_publish(pub, msg) != AF_OK)
    af_ros_log(st->ros, AF_LOG_ERROR, "%s not published: %s", topic, af_ros_last_error(st->ros));
}

/* A Reliability saying why this apple got no prediction. */
static void reject_apple(af_station *st, const af_apple_estimate *a, const char *why)
{
  af_reliability *rel = &st->reliability;
  memset(rel, 0, sizeof *rel);
  rel->header = a->header;
  rel->apple_id = a->apple_id;
  af_text(rel->source, sizeof rel->source, "predicted");
  af_text(rel->reason, sizeof rel->reason, "%s", why);
  st->apples_invalid++;
  st->apples_unreliable++;
  st->last_apple_invalid = true;
  af_text(st->last_reason, sizeof st->last_reason, "apple %u: %s", a->apple_id, why);
  af_ros_log(st->ros, AF_LOG_WARN, "apple %u: no prediction: %s", a->apple_id, why);
  publish(st, st->reliability_pub, rel, "reliability");
  af_ros_diag_force_update(st->diag);
}

void af_station_on_apple(const void *msg, void *user)
{
  af_station *st = user;
  const af_apple_estimate *m = msg;
  af_apple_work w;
  af_apple a;
  const af_prediction *pr = NULL;
  memset(&w, 0, sizeof w);
  st->apples++;
  st->last_apple_ns = af_time_to_ns(af_ros_now(st->ros));
  af_rate_tick(&st->apple_rate);
  af_stamp_tick(&st->apple_stamps, af_time_to_ns(m->header.stamp), st->last_apple_ns);
  apple_of(st, m, &w, &a);
  af_status s = af_lane_io_apple(st->measured, &a, &pr);
  if (s != AF_OK) {
    st->model_failures += s != AF_EINVAL;
    reject_apple(st, m, pr->why);
    return;
  }
  st->last_apple_invalid = false;
  if (st->cfg->markers_enabled) {
    marker_centre(st->cfg, m, pr, &w);
    /* The measured line goes 1.5 label heights above the apple's label, towards
     * the hammer when the direction is known (af_markers_measured_label adds
     * top + 3.5 h along +z of the frame: the anchor takes that back). */
    const double top = fmax(m->equatorial_radius_m, pr->polar_semi_axis_m), h = 0.012;
    double anchor[3];
    for (int i = 0; i < 3; i++)
      anchor[i] = w.centre_m[i] +
                  (pr->geo.direction_known ? (top + 3.5 * h) * pr->geo.normal[i] : 0.0) -
                  (pr->geo.direction_known && i == 2 ? top + 3.5 * h : 0.0);
    af_lane_io_label_place(st->measured, m->apple_id, &m->header, anchor, top);
  }
  fill_band(m, pr, &st->band);
  fill_advice(st->cfg, m, &a, pr, &st->advice);
  fill_reliability(m, pr, &st->reliability);
  publish(st, st->band_pub, &st->band, "excitation_band");
  publish(st, st->advice_pub, &st->advice, "strike_advice");
  publish(st, st->reliability_pub, &st->reliability, "reliability");
  if (st->cfg->markers_enabled)
    publish_markers(st, m, pr, &w);
  st->have_band = true;
  st->apples_rotate += st->advice.rotate;
  af_text(st->last_geometry_note, sizeof st->last_geometry_note, "%s", a.direction_note);
  if (!st->reliability.reliable) {
    st->apples_unreliable++;
    af_text(st->last_reason, sizeof st->last_reason, "apple %u: %s", m->apple_id,
            st->reliability.reason);
  }
  af_ros_log(st->ros, AF_LOG_DEBUG, "%s", st->advice.text);
}
