/* station.c — per-apple prediction, strike advice, streams and diagnostics. */
#include "station.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "absent.h"
#include "advice.h"
#include "af_tf.h"
#include "af_wire_guard.h"
#include "audio_in.h"
#include "evaluate.h"
#include "live_settings.h"
#include "snapshot.h"
#include "markers.h"
#include "lane_io.h"
#include "model.h"
#include "lamb.h"
#include "status_marker.h"
#include "strike_plot.h"
#include "text.h"

#ifndef M_PI /* strict C11 <math.h> does not define it */
#define M_PI 3.14159265358979323846
#endif

/* Subscriber queues: apples come a few per second; chunks at 50 kHz in
 * blocks of ~20 ms. A chunk must never be dropped (it would be a gap under
 * a strike): 1000 chunks ride out 20 s of a real-time stream, or a bag
 * replayed several times faster than real time while a strike is measured.
 * An estimate must not be dropped either (its strike would go without its
 * apple), and roscpp drops the oldest of a full queue without a word: as
 * many as chunks, 100 s of a 10-apples/s line. The queue holds messages
 * only while the node is behind. */
#define AF_APPLE_QUEUE 1000
#define AF_CHUNK_QUEUE 1000
/* Outgoing messages a slow subscriber may leave queued: a node catching up
 * on a backlog publishes a burst of reports, and roscpp drops what exceeds
 * the queue without a word (5 StrikeReports lost at 80x with 10). */
#define AF_OUTPUT_QUEUE 1000
/* The smallest cap on roscpp's message buffers (af_wire_guard.h) [bytes]:
 * every message of the node's topics but the chunks (apple estimates, TF,
 * /clock, services, reconfigure) is far below it, and so is the largest
 * strike plot it publishes (2048 x 2048 x 3 bytes: 12 MiB). A chunk is
 * allowed its stream's ring and AF_WIRE_GUARD_SLACK_BYTES of header. */
#define AF_WIRE_GUARD_FLOOR_BYTES ((size_t)16 << 20)
#define AF_WIRE_GUARD_SLACK_BYTES ((size_t)64 << 10)
/* How long the start-up waits for the rig's frames in TF [s]. */
#define AF_TF_WAIT_S 3.0
/* Diagnostics period [s] follows the updater (~diagnostic_period). */

/* The diagnostic tasks, each its own status on /diagnostics, named
 * "<node>: <name>" (config/analyzers.yaml groups them per lane). */
typedef enum {
  AF_COMP_STATION = 0, /* the node: configuration, predictions, restarts, services */
  AF_COMP_FORCE,       /* the force stream: chunks, gaps, rate, stamps */
  AF_COMP_AUDIO,       /* the audio stream, and the microphone */
  AF_COMP_APPLE,       /* the vision's AppleEstimates: rate, stamps */
  AF_COMP_DETECTOR,    /* the strike detector and the strikes it makes */
  AF_COMP_ATTRIBUTION, /* each strike's apple and audio, by stamps; the streams' clocks */
  AF_COMP_HEALTH,      /* the hammer health */
  AF_COMP_FACTOR,      /* the modulus factor learned on the line */
  AF_COMPONENTS
} af_component_id;

static const char *const component_names[AF_COMPONENTS] = {
    "firmness station", "force stream",           "audio stream",  "apple input",
    "detector",         "attribution and clocks", "hammer health", "modulus factor"};

/* The inputs with a rate and a stamp check. */
enum { AF_INPUT_FORCE = 0, AF_INPUT_AUDIO, AF_INPUT_APPLE, AF_INPUTS };

typedef struct {
  af_diag_level level;
  char message[2 * AF_TEXT_MAX];
} af_component;

struct af_station {
  af_ros *ros;
  const af_node_config *cfg;
  af_ros_pub *band_pub, *advice_pub, *reliability_pub, *markers_pub;
  af_ros_diag *diag;
  af_lane_io *measured;  /* the lane (src/core/lane/lane.h) and its strike outputs */
  af_evaluate *evaluate; /* the ~evaluate service */
  /* dynamic_reconfigure of the criteria, thresholds and grades */
  af_live_settings *live;
  af_snapshot *snapshot; /* the settings and URDF, latched, for recordings */
  af_audio_in *audio_in; /* audio_common input (~audio_input); NULL with SignalChunk */
  af_strike_plot *plot;  /* the last strike's picture on strike_plot */
  af_tf *tf;             /* the rig's frames (robot_state_publisher, static transforms) */
  /* Output scratch, kept here so that no callback allocates. */
  af_excitation_band band;
  af_strike_advice advice;
  af_reliability reliability;
  af_marker markers[AF_MARKERS_COUNT];
  af_marker status; /* the diagnostic summary in rviz */
  /* Counters and last values for the diagnostics. */
  unsigned long long apples, apples_invalid, apples_unreliable, apples_rotate, model_failures;
  bool last_apple_invalid;
  int64_t last_apple_ns; /* ROS time the latest AppleEstimate came [ns]; 0 = none yet */
  unsigned long long force_problems_seen, audio_problems_seen; /* gaps + bad chunks + restarts
                                                                 at the last diagnostic */
  unsigned long long clock_faults_seen; /* clock steps + frozen chunks at the last one */
  unsigned long long force_clock_seen, audio_clock_seen; /* each stream's, at its last chunk */
  unsigned long long too_long_seen; /* messages too long to read, at the last one */
  int64_t clock_start_ns;   /* the first non-zero ROS time seen (sim time: the first /clock) [ns] */
  bool absent_logged;       /* the stream-absent warning went to the log */
  char absent[AF_TEXT_MAX]; /* the stream-absent warning; "" = none (absent.h) */
  /* The rig's frames, checked once the simulated clock has run AF_TF_WAIT_S
   * (replay: robot_state_publisher's fixed frames wait for the first /clock). */
  bool tf_check_deferred;
  int64_t tf_clock_start_ns; /* the first /clock seen by that check [ns]; 0 = none yet */
  /* The inputs' rate and stamp checks (rate_status.h): ticked by each
   * message, run once per diagnostic report. */
  af_rate_status force_rate, audio_rate, apple_rate;
  af_stamp_status force_stamps, audio_stamps, apple_stamps;
  bool rates_started; /* started on a running clock (sim time: after the first /clock) */
  /* One report's components, judged together by the first task (diag_collect)
   * and written by each component's task. */
  af_component comp[AF_COMPONENTS];
  af_rate_report rate_rep[AF_INPUTS];
  af_stamp_report stamp_rep[AF_INPUTS];
  af_wire_guard_stats guard;                 /* the messages too long to read, at this report */
  bool force_stale, audio_stale, absent_now; /* at this report; absent_now: absent_check's */
  char last_reason[AF_TEXT_MAX];
  char last_geometry_note[AF_TEXT_MAX];
  bool have_band;
  int starts;       /* this process's start under the master (~node_starts), 1 = first */
  char started[32]; /* when, UTC */
};

/* What the node adds to one apple's prediction: the rig's geometry. */
typedef struct {
  bool frame_known;      /* TF transforms the hammer's mount frame into the apple's */
  af_transform to_frame; /* mount frame -> the apple's frame */
  double centre_m[3];    /* apple centre in its frame, for the markers */
} af_apple_work;

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

static void on_apple(const void *msg, void *user)
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

/* --- streams --------------------------------------------------------------- */

static bool power_of_two(unsigned long long n)
{
  return n != 0 && (n & (n - 1)) == 0;
}

/* A chunk into the lane; problems are warned about at the 1st, 2nd, 4th,
 * 8th ... occurrence so that a broken stream cannot flood the log. */
static void on_chunk(af_station *st, const af_stream *s, af_chunk_verdict v,
                     const af_ring_write_info *info)
{
  unsigned long long count = v == AF_CHUNK_DUPLICATE ? s->duplicates
                             : v != AF_CHUNK_OK      ? af_stream_bad_chunks(s)
                             : info->gap_samples > 0 ? s->gaps
                             : info->restarted       ? s->restarts
                             : s->last_refused > 0   ? s->refused_chunks
                                                     : 0;
  if (power_of_two(count))
    af_ros_log(st->ros, AF_LOG_WARN, "%s (%llu so far)", s->last_problem, count);
  const unsigned long long faults = s->clock_steps + s->clock_frozen + s->clock_rate_wrong;
  unsigned long long *seen = s == af_lane_force_stream(af_lane_io_lane(st->measured))
                                 ? &st->force_clock_seen
                                 : &st->audio_clock_seen;
  if (faults != *seen && power_of_two(faults))
    af_ros_log(st->ros, AF_LOG_WARN, "%s (%llu clock faults so far)", s->clock_problem, faults);
  *seen = faults;
}

/* A chunk received: its rate and stamp checks (rate_status.h). */
static void tick_input(af_station *st, const af_signal_chunk *c, af_rate_status *rate,
                       af_stamp_status *stamps)
{
  af_rate_tick(rate);
  af_stamp_tick(stamps, af_time_to_ns(c->header.stamp), af_time_to_ns(af_ros_now(st->ros)));
}

static void on_force(const void *msg, void *user)
{
  af_station *st = user;
  af_ring_write_info info;
  tick_input(st, msg, &st->force_rate, &st->force_stamps);
  af_chunk_verdict v = af_lane_io_force(st->measured, msg, &info);
  on_chunk(st, af_lane_force_stream(af_lane_io_lane(st->measured)), v, &info);
}

static void on_audio(const void *msg, void *user)
{
  af_station *st = user;
  af_ring_write_info info;
  tick_input(st, msg, &st->audio_rate, &st->audio_stamps);
  af_chunk_verdict v = af_lane_io_audio(st->measured, msg, &info);
  on_chunk(st, af_lane_audio_stream(af_lane_io_lane(st->measured)), v, &info);
}

/* The diagnostic summary in rviz (status_marker.h): warning NULL = OK. Over
 * the rig, in the hammer's mount frame (the URDF root's axes on the shipped
 * rig). */
static void publish_status(af_station *st, const char *warning)
{
  const af_node_config *c = st->cfg;
  if (!st->markers_pub || !c->hammer_axis_known)
    return;
  char text[AF_TEXT_MAX];
  const af_lane_stats *ls = af_lane_get_stats(af_lane_io_lane(st->measured));
  af_text(text, sizeof text, "%s: %s\napples %llu, strikes %llu (unreliable %llu)",
          af_ros_node_name(st->ros), warning ? warning : "OK", st->apples,
          (unsigned long long)ls->strikes, (unsigned long long)ls->unreliable);
  const af_vec3 *h = &c->hammer.mount_origin_m;
  const double at[3] = {h->x - 0.12, h->y, h->z + 0.08}; /* beside the hammer, above it */
  af_status_marker(c->hammer.mount_frame, at, warning ? AF_DIAG_WARN : AF_DIAG_OK, text,
                   &st->status);
  af_marker_array arr = {&st->status, 1};
  if (af_ros_publish(st->markers_pub, &arr) != AF_OK)
    af_ros_log(st->ros, AF_LOG_WARN, "status marker not published: %s", af_ros_last_error(st->ros));
}

/* The never-started input's warning (absent.h); tap-only: the audio alone,
 * no force being expected. */
static bool absent_check(af_station *st, const af_stream *force, const af_stream *audio,
                         int64_t now_ns)
{
  const af_node_config *c = st->cfg;
  if (!c->lane.measured.tap_only)
    return af_absent_warning(force, audio, st->clock_start_ns, now_ns, c->lane.stream_absent_warn_s,
                             st->absent, sizeof st->absent);
  st->absent[0] = '\0';
  if (!af_absent(audio, st->clock_start_ns, now_ns, c->lane.stream_absent_warn_s))
    return false;
  snprintf(st->absent, sizeof st->absent,
           "no audio chunk within %.1f s of start (tap_only: the only input)",
           c->lane.stream_absent_warn_s);
  return true;
}

/* --- diagnostics ------------------------------------------------------------ */

/* A stream's bookkeeping (its clock is the attribution task's). */
static void diag_stream(af_diag_status *d, const af_stream *s, bool stale)
{
  char key[64];
  af_text(key, sizeof key, "%s state", s->name);
  af_diag_add(d, key, "%s", !s->seen ? "no chunk yet" : stale ? "stale" : "live");
  af_text(key, sizeof key, "%s chunks", s->name);
  af_diag_add(d, key, "%llu", (unsigned long long)s->chunks);
  af_text(key, sizeof key, "%s gaps", s->name);
  af_diag_add(d, key, "%llu (%llu samples lost)", (unsigned long long)s->gaps,
              (unsigned long long)s->lost_samples);
  af_text(key, sizeof key, "%s restarts", s->name);
  af_diag_add(d, key,
              "%llu (duplicate chunks ignored %llu; overlapping chunks %llu, their new tails kept; "
              "samples sent twice %llu)",
              (unsigned long long)s->restarts, (unsigned long long)s->duplicates,
              (unsigned long long)s->overlaps, (unsigned long long)s->duplicate_samples);
  af_text(key, sizeof key, "%s bad chunks", s->name);
  af_diag_add(d, key,
              "%llu (rate %llu, unit %llu, index overflow %llu, malformed %llu, oversized %llu)",
              (unsigned long long)af_stream_bad_chunks(s), (unsigned long long)s->bad_rate,
              (unsigned long long)s->bad_unit, (unsigned long long)s->bad_index,
              (unsigned long long)s->malformed, (unsigned long long)s->oversized);
  af_text(key, sizeof key, "%s refused samples", s->name);
  af_diag_add(d, key, "%llu non-finite in %llu spans of %llu chunks",
              (unsigned long long)s->refused_samples, (unsigned long long)s->refused_spans,
              (unsigned long long)s->refused_chunks);
  af_text(key, sizeof key, "%s last problem", s->name);
  af_diag_add(d, key, "%s", s->last_problem);
  af_text(key, sizeof key, "%s ring [samples]", s->name);
  af_diag_add(d, key, "%zu at %g Hz, expected unit %s", s->cfg->capacity_samples,
              s->cfg->sample_rate_hz, s->cfg->units[0]);
}

/* A stream's clock (stream.h): steps, frozen chunks, the rate its stamps advance at. */
static void diag_clock(af_diag_status *d, const af_stream *s)
{
  char key[64];
  af_text(key, sizeof key, "%s clock", s->name);
  if (isnan(s->clock_rate_hz))
    af_diag_add(d, key, "%s; %llu steps, %llu frozen chunks; rate not yet judged",
                s->clock_problem[0] ? s->clock_problem : "OK", (unsigned long long)s->clock_steps,
                (unsigned long long)s->clock_frozen);
  else
    af_diag_add(d, key, "%s; %llu steps, %llu frozen chunks; stamps advance at %.1f Hz of samples",
                s->clock_problem[0] ? s->clock_problem : "OK", (unsigned long long)s->clock_steps,
                (unsigned long long)s->clock_frozen, s->clock_rate_hz);
}

/* An input's rate and stamp figures, diagnostic_updater's FrequencyStatus
 * and TimeStampStatus values under the input's name ("force rate [1/s]"). */
static void diag_input(af_diag_status *d, const char *name, const af_rate_report *r,
                       const af_stamp_report *t)
{
  char key[64];
  af_text(key, sizeof key, "%s rate [1/s]", name);
  af_diag_add(d, key, "%.2f (%s: %llu in the last %.1f s; %llu since the start)", r->rate_hz,
              r->message, r->events, r->window_s, r->events_total);
  af_text(key, sizeof key, "%s rate accepted [1/s]", name);
  if (isinf(r->max_ok_hz))
    af_diag_add(d, key, "%.2f .. unbounded", r->min_ok_hz);
  else
    af_diag_add(d, key, "%.2f .. %.2f", r->min_ok_hz, r->max_ok_hz);
  af_text(key, sizeof key, "%s stamp delay [s]", name);
  if (t->valid)
    af_diag_add(d, key, "%.4f .. %.4f since the last report (%s)", t->min_delay_s, t->max_delay_s,
                t->message);
  else
    af_diag_add(d, key, "%s", t->message);
  af_text(key, sizeof key, "%s stamp reports out of range", name);
  af_diag_add(d, key, "%llu late, %llu early, %llu with a zero stamp", t->late_updates,
              t->early_updates, t->zero_updates);
}

static void set_comp(af_station *st, af_component_id k, af_diag_level level, const char *message)
{
  st->comp[k].level = level;
  af_text(st->comp[k].message, sizeof st->comp[k].message, "%s", message);
}

static af_diag_level level_of(af_health_level h)
{
  return h == AF_HEALTH_ERROR ? AF_DIAG_ERROR : h == AF_HEALTH_WARN ? AF_DIAG_WARN : AF_DIAG_OK;
}

/* The rate and stamp checks are started on a running clock: under
 * simulated time that has not started (0) their window would reach back
 * to 1970. */
static void start_rates(af_station *st, int64_t now_ns)
{
  const af_lane_config *c = &st->cfg->lane;
  af_rate_init(&st->force_rate, &c->force_rate, now_ns);
  af_rate_init(&st->audio_rate, &c->audio_rate, now_ns);
  af_rate_init(&st->apple_rate, &c->apple_rate, now_ns);
  af_stamp_init(&st->force_stamps, &c->stream_stamps);
  af_stamp_init(&st->audio_stamps, &c->stream_stamps);
  af_stamp_init(&st->apple_stamps, &c->apple_stamps);
  st->rates_started = now_ns > 0;
}

/* One stream's level and message, the first that applies:
 *   ERROR  missing (never started or silent) while apples arrive: every
 *          strike on them is lost ("apples arriving, no strike can be
 *          measured: ...")
 *   WARN   never started (the absent warning), silent, new gaps, bad chunks
 *          or restarts since the last report, an input-specific warning
 *          (audio: the microphone clipped, audio_common refusals)
 *   WARN/ERROR  its stamps (too late or early / a zero stamp), its rate
 *   OK     "ok" */
static void judge_stream(af_station *st, af_component_id k, const af_stream *s, bool absent,
                         bool stale, unsigned long long *problems_seen, const char *extra,
                         bool apples_coming, int input)
{
  const af_node_config *c = st->cfg;
  char text[AF_TEXT_MAX];
  const unsigned long long problems = s->gaps + af_stream_bad_chunks(s) + s->restarts;
  const bool new_problems = problems != *problems_seen;
  *problems_seen = problems;
  const char *why = NULL;
  if (absent)
    why = st->absent;
  else if (stale) {
    af_text(text, sizeof text, "%s stream silent for more than %.1f s (stream_stale_after_s)",
            s->name, c->lane.stream_stale_after_s);
    why = text;
  }
  if (why && apples_coming) {
    char error[sizeof st->comp[0].message];
    af_text(error, sizeof error, "apples arriving, no strike can be measured: %s", why);
    set_comp(st, k, AF_DIAG_ERROR, error);
    return;
  }
  if (why) {
    set_comp(st, k, AF_DIAG_WARN, why);
    return;
  }
  if (new_problems) {
    af_text(text, sizeof text, "%s gaps, bad chunks or restarts since the last report: %s", s->name,
            s->last_problem);
    set_comp(st, k, AF_DIAG_WARN, text);
    return;
  }
  if (extra) {
    set_comp(st, k, AF_DIAG_WARN, extra);
    return;
  }
  const af_stamp_report *t = &st->stamp_rep[input];
  const af_rate_report *r = &st->rate_rep[input];
  if (t->level != AF_HEALTH_OK) {
    af_text(text, sizeof text, "%s: %s (delay %.3f .. %.3f s, accepted %.3f .. %.3f s)", s->name,
            t->message, t->min_delay_s, t->max_delay_s, c->lane.stream_stamps.min_delay_s,
            c->lane.stream_stamps.max_delay_s);
    set_comp(st, k, level_of(t->level), text);
  } else if (r->level != AF_HEALTH_OK) {
    af_text(text, sizeof text, "%s: %s (%.2f chunks/s, accepted %.2f .. %.2f)", s->name, r->message,
            r->rate_hz, r->min_ok_hz, r->max_ok_hz);
    set_comp(st, k, level_of(r->level), text);
  } else
    set_comp(st, k, AF_DIAG_OK, "ok");
}

/* Every component's level and message of this report, judged together
 * (the counters "since the last report" move on once), and the summary in
 * rviz. Run by the first task of each report (diagnostic_updater runs its
 * tasks in the order they were added). */
static void diag_collect(af_station *st)
{
  const af_node_config *c = st->cfg;
  const af_lane *lane = af_lane_io_lane(st->measured);
  const af_stream *force = af_lane_force_stream(lane), *audio = af_lane_audio_stream(lane);
  const int64_t now_ns = af_time_to_ns(af_ros_now(st->ros));
  char text[AF_TEXT_MAX];
  if (!st->rates_started)
    start_rates(st, now_ns);
  af_rate_run(&st->force_rate, now_ns, &st->rate_rep[AF_INPUT_FORCE]);
  af_rate_run(&st->audio_rate, now_ns, &st->rate_rep[AF_INPUT_AUDIO]);
  af_rate_run(&st->apple_rate, now_ns, &st->rate_rep[AF_INPUT_APPLE]);
  af_stamp_run(&st->force_stamps, &st->stamp_rep[AF_INPUT_FORCE]);
  af_stamp_run(&st->audio_stamps, &st->stamp_rep[AF_INPUT_AUDIO]);
  af_stamp_run(&st->apple_stamps, &st->stamp_rep[AF_INPUT_APPLE]);
  st->force_stale = af_stream_stale(force, now_ns, c->lane.stream_stale_after_s);
  st->audio_stale = af_stream_stale(audio, now_ns, c->lane.stream_stale_after_s);
  if (st->clock_start_ns == 0)
    st->clock_start_ns = now_ns; /* stays 0 while a simulated clock has not started */
  st->absent_now = absent_check(st, force, audio, now_ns);
  if (st->absent_now && !st->absent_logged)
    af_ros_log(st->ros, AF_LOG_WARN, "%s", st->absent);
  st->absent_logged |= st->absent_now;
  /* Apples keep coming while an input is missing: every strike on them is
   * lost, an ERROR on that input's task (a stream merely silent between
   * apples is a WARN). */
  const bool apples_coming =
      st->last_apple_ns > 0 &&
      now_ns - st->last_apple_ns <= (int64_t)(c->lane.stream_absent_warn_s * 1e9);
  af_lane_io_warnings w;
  af_lane_io_warnings_get(st->measured, &w);

  /* the streams */
  if (c->lane.measured.tap_only)
    set_comp(st, AF_COMP_FORCE, AF_DIAG_OK,
             "not used (tap_only: strikes from the audio onset, no force subscription)");
  else
    judge_stream(st, AF_COMP_FORCE, force,
                 st->absent_now &&
                     af_absent(force, st->clock_start_ns, now_ns, c->lane.stream_absent_warn_s),
                 st->force_stale, &st->force_problems_seen, NULL, apples_coming, AF_INPUT_FORCE);
  const char *audio_extra = w.audio ? w.audio : af_audio_in_warning(st->audio_in);
  judge_stream(
      st, AF_COMP_AUDIO, audio,
      st->absent_now && af_absent(audio, st->clock_start_ns, now_ns, c->lane.stream_absent_warn_s),
      st->audio_stale, &st->audio_problems_seen, audio_extra, apples_coming, AF_INPUT_AUDIO);

  /* the apple estimates */
  const af_rate_report *ar = &st->rate_rep[AF_INPUT_APPLE];
  const af_stamp_report *at = &st->stamp_rep[AF_INPUT_APPLE];
  if (at->level != AF_HEALTH_OK) {
    af_text(text, sizeof text,
            "apple estimates: %s (delay %.3f .. %.3f s, accepted %.3f .. %.3f s)", at->message,
            at->min_delay_s, at->max_delay_s, c->lane.apple_stamps.min_delay_s,
            c->lane.apple_stamps.max_delay_s);
    set_comp(st, AF_COMP_APPLE, level_of(at->level), text);
  } else if (ar->level != AF_HEALTH_OK) {
    af_text(text, sizeof text, "apple estimates: %s (%.2f /s, accepted %.2f .. %.2f)", ar->message,
            ar->rate_hz, ar->min_ok_hz, ar->max_ok_hz);
    set_comp(st, AF_COMP_APPLE, level_of(ar->level), text);
  } else
    set_comp(st, AF_COMP_APPLE, AF_DIAG_OK, st->apples == 0 ? "no apple estimate yet" : "ok");

  /* the detector */
  af_strike_tracker tr;
  af_strike_get_tracker(af_lane_detector(lane), &tr);
  if (w.detector)
    set_comp(st, AF_COMP_DETECTOR, AF_DIAG_WARN, w.detector);
  else
    set_comp(st, AF_COMP_DETECTOR, AF_DIAG_OK,
             c->lane.measured.tap_only ? "ok (tap_only: the audio onset)"
             : tr.armed                ? "ok (armed)"
                                       : "ok (learning the baseline or waiting for quiet)");

  /* attribution and clocks: a clock fault first (the stamps everything is matched by) */
  const unsigned long long clock_faults =
      force->clock_steps + force->clock_frozen + audio->clock_steps + audio->clock_frozen;
  const bool clock_fault =
      clock_faults != st->clock_faults_seen || force->clock_rate_wrong || audio->clock_rate_wrong;
  st->clock_faults_seen = clock_faults;
  const char *clock_words = force->clock_problem[0] ? force->clock_problem : audio->clock_problem;
  if (clock_fault)
    set_comp(st, AF_COMP_ATTRIBUTION, AF_DIAG_WARN, clock_words);
  else if (w.attribution)
    set_comp(st, AF_COMP_ATTRIBUTION, AF_DIAG_WARN, w.attribution);
  else
    set_comp(st, AF_COMP_ATTRIBUTION, AF_DIAG_OK, "ok");

  /* the hammer, the modulus factor */
  if (w.health)
    set_comp(st, AF_COMP_HEALTH, AF_DIAG_WARN, w.health);
  else
    set_comp(st, AF_COMP_HEALTH, AF_DIAG_OK, "ok");
  set_comp(st, AF_COMP_FACTOR, AF_DIAG_OK,
           af_lane_io_factor_summary(st->measured, text, sizeof text));

  /* the node itself */
  af_wire_guard_get(&st->guard);
  const bool too_long = st->guard.refused != st->too_long_seen;
  if (too_long && power_of_two(st->guard.refused))
    af_ros_log(st->ros, AF_LOG_WARN,
               "a message of %zu bytes dropped unread: above the %zu bytes this node reads "
               "(%llu so far; the publisher's connection made again)",
               st->guard.largest_refused_bytes, st->guard.cap_bytes, st->guard.refused);
  st->too_long_seen = st->guard.refused;
  const char *warning = st->last_apple_invalid ? "last apple got no prediction"
                        : too_long ? "a message too long to read dropped since the last report"
                                   : NULL;
  /* A restart is said until the first strike, also beside another warning
   * (a restarted node often starts on a silent stream). */
  if (st->starts > 1 && af_lane_get_stats(lane)->strikes == 0) {
    af_text(text, sizeof text, "%s%srestarted: resuming with the next apple",
            warning ? warning : "", warning ? "; " : "");
    warning = text;
  }
  set_comp(st, AF_COMP_STATION, warning ? AF_DIAG_WARN : AF_DIAG_OK, warning ? warning : "ok");

  /* rviz: the worst component's message (the first of the worst level) */
  const af_component *worst = &st->comp[0];
  for (size_t k = 1; k < AF_COMPONENTS; k++)
    if (st->comp[k].level > worst->level)
      worst = &st->comp[k];
  publish_status(st, worst->level == AF_DIAG_OK ? NULL : worst->message);
}

static af_station *task_station(void *user, af_diag_status *d, af_component_id k)
{
  af_station *st = user;
  af_diag_summary(d, st->comp[k].level, st->comp[k].message);
  return st;
}

/* "firmness station": the node, its configuration, the predictions, its
 * services. The first task: it judges every component of the report. */
static void task_node(af_diag_status *d, void *user)
{
  af_station *st = user;
  const af_node_config *c = st->cfg;
  diag_collect(st);
  task_station(user, d, AF_COMP_STATION);
  af_diag_add(d, "cultivar", "%s", c->lane.cultivar);
  af_diag_add(d, "input mode", "%s",
              c->lane.measured.tap_only
                  ? "tap_only: strikes from the audio onset, no force subscription"
                  : "force and audio");
  af_diag_add(d, "URDF source", "%s", c->urdf_source);
  af_diag_add(d, "hammer mass [kg]", "%g from %s", c->hammer.mass_kg, c->hammer_mass_source);
  af_diag_add(d, "hammer tip radius [m]", "%g from %s", c->hammer.tip_radius_m,
              c->hammer_tip_source);
  af_diag_add(d, "parameters", "%s (private; config/station.yaml + cultivar YAML)",
              af_ros_node_name(st->ros));
  af_diag_add(d, "node starts", "%d (%s; this one at %s UTC)", st->starts,
              st->starts > 1 ? "restarted: resumes with the next apple, nothing from before the "
                               "restart is reported"
                             : "first start",
              st->started);
  af_diag_add(d, "malformed messages dropped", "%llu", af_ros_malformed(st->ros));
  af_diag_add(d, "messages too long to read",
              "%llu (longest %zu bytes; cap %zu bytes: never read, the publisher's connection "
              "made again)",
              st->guard.refused, st->guard.largest_refused_bytes, st->guard.cap_bytes);
  af_diag_add(d, "apples processed", "%llu", st->apples);
  af_diag_add(d, "apples without prediction", "%llu (model failures %llu)", st->apples_invalid,
              st->model_failures);
  af_diag_add(d, "apples unreliable", "%llu", st->apples_unreliable);
  af_diag_add(d, "apples to rotate", "%llu", st->apples_rotate);
  af_diag_add(d, "last unreliable reason", "%s", st->last_reason);
  af_diag_add(d, "last geometry note", "%s", st->last_geometry_note);
  if (st->have_band) {
    af_diag_add(d, "last band [Hz]", "%.1f .. %.1f (lobe %u)", st->band.band_low_hz,
                st->band.band_high_hz, (unsigned)st->band.lobe);
    af_diag_add(d, "last resonance [Hz]", "%.1f (firmness range %.1f .. %.1f)",
                st->band.resonance_hz, st->band.resonance_low_hz, st->band.resonance_high_hz);
  }
  af_evaluate_diag(st->evaluate, d);
  af_live_settings_diag(st->live, d);
  af_strike_plot_diag(st->plot, d);
}

/* "force stream", "audio stream": each stream's bookkeeping, rate and stamps. */
static void task_stream(af_station *st, af_diag_status *d, af_component_id k)
{
  const af_node_config *c = st->cfg;
  const af_lane *lane = af_lane_io_lane(st->measured);
  const bool is_force = k == AF_COMP_FORCE;
  task_station(st, d, k);
  const af_stream *s = is_force ? af_lane_force_stream(lane) : af_lane_audio_stream(lane);
  const int input = is_force ? AF_INPUT_FORCE : AF_INPUT_AUDIO;
  diag_stream(d, s, is_force ? st->force_stale : st->audio_stale);
  diag_input(d, s->name, &st->rate_rep[input], &st->stamp_rep[input]);
  if (c->lane.stream_absent_warn_s > 0.0)
    af_diag_add(d, "stream absent check", "%s", st->absent_now ? st->absent : "ok");
  else
    af_diag_add(d, "stream absent check", "off (stream_absent_warn_s 0)");
  if (!is_force) {
    af_lane_io_diag_audio(st->measured, d);
    af_audio_in_diag(st->audio_in, d);
  }
}

static void task_force(af_diag_status *d, void *user)
{
  task_stream(user, d, AF_COMP_FORCE);
}

static void task_audio(af_diag_status *d, void *user)
{
  task_stream(user, d, AF_COMP_AUDIO);
}

/* "apple input": the vision's AppleEstimates, their rate and stamps. */
static void task_apple(af_diag_status *d, void *user)
{
  af_station *st = task_station(user, d, AF_COMP_APPLE);
  af_diag_add(d, "apple estimates", "%llu", st->apples);
  diag_input(d, "apple", &st->rate_rep[AF_INPUT_APPLE], &st->stamp_rep[AF_INPUT_APPLE]);
}

static void task_detector(af_diag_status *d, void *user)
{
  af_station *st = task_station(user, d, AF_COMP_DETECTOR);
  af_lane_io_diag_detector(st->measured, d);
}

static void task_attribution(af_diag_status *d, void *user)
{
  af_station *st = task_station(user, d, AF_COMP_ATTRIBUTION);
  const af_lane *lane = af_lane_io_lane(st->measured);
  if (!st->cfg->lane.measured.tap_only)
    diag_clock(d, af_lane_force_stream(lane));
  diag_clock(d, af_lane_audio_stream(lane));
  af_lane_io_diag_attribution(st->measured, d);
}

static void task_health(af_diag_status *d, void *user)
{
  af_station *st = task_station(user, d, AF_COMP_HEALTH);
  af_lane_io_diag_health(st->measured, d);
}

static void task_factor(af_diag_status *d, void *user)
{
  af_station *st = task_station(user, d, AF_COMP_FACTOR);
  af_lane_io_diag_factor(st->measured, d);
}

/* The tasks in their order on /diagnostics; the first judges them all. */
static const af_diag_fn component_tasks[AF_COMPONENTS] = {
    task_node,     task_force,       task_audio,  task_apple,
    task_detector, task_attribution, task_health, task_factor};

/* --- life cycle -------------------------------------------------------------- */

static af_status advertise(af_station *st)
{
  af_status s = af_ros_advertise(st->ros, "excitation_band", AF_MSG_EXCITATION_BAND,
                                 AF_OUTPUT_QUEUE, false, &st->band_pub);
  if (s == AF_OK)
    s = af_ros_advertise(st->ros, "strike_advice", AF_MSG_STRIKE_ADVICE, AF_OUTPUT_QUEUE, false,
                         &st->advice_pub);
  if (s == AF_OK)
    s = af_ros_advertise(st->ros, "reliability", AF_MSG_RELIABILITY, AF_OUTPUT_QUEUE, false,
                         &st->reliability_pub);
  if (s == AF_OK && st->cfg->markers_enabled)
    s = af_ros_advertise(st->ros, "markers", AF_MSG_MARKER_ARRAY, AF_OUTPUT_QUEUE, false,
                         &st->markers_pub);
  return s;
}

/* A chunk refused by the shim before deserializing (the shim logs it). */
static void on_force_refused(bool oversized, const char *why, void *user)
{
  af_station *st = user;
  af_lane_io_refuse(st->measured, true, oversized, why);
}

static void on_audio_refused(bool oversized, const char *why, void *user)
{
  af_station *st = user;
  af_lane_io_refuse(st->measured, false, oversized, why);
}

/* A chunk longer than its stream's ring can never be used: the cap on the
 * wire, so that it is never deserialized; firmness_report caps each stream
 * alike (lane_config.h, max_chunk_samples). */
static size_t ring_samples(const af_station *st, bool force)
{
  const af_lane *l = af_lane_io_lane(st->measured);
  return (force ? af_lane_force_stream(l) : af_lane_audio_stream(l))->cfg->max_chunk_samples;
}

/* The cap on roscpp's message buffers: the largest message the node can
 * use or publishes (af_wire_guard.h; audio_in.c raises it for its format). */
static void guard_wire(const af_station *st)
{
  /* the chunks' float32 samples, the plot's RGB8 pixels; each + its header */
  const size_t body[] = {4 * ring_samples(st, true), 4 * ring_samples(st, false),
                         3 * (size_t)st->cfg->strike_plot_width_px *
                             (size_t)st->cfg->strike_plot_height_px};
  size_t cap = AF_WIRE_GUARD_FLOOR_BYTES;
  for (size_t k = 0; k < sizeof body / sizeof body[0]; k++)
    if (body[k] + AF_WIRE_GUARD_SLACK_BYTES > cap)
      cap = body[k] + AF_WIRE_GUARD_SLACK_BYTES;
  af_wire_guard_allow(cap);
}

static af_status subscribe(af_station *st)
{
  af_ros_sub *sub; /* owned by the af_ros */
  af_status s = AF_OK;
  guard_wire(st);
  if (!st->cfg->lane.measured.tap_only) { /* tap-only: a microphone, no force transducer */
    s = af_ros_subscribe(st->ros, "force", AF_MSG_SIGNAL_CHUNK, AF_CHUNK_QUEUE, on_force, st, &sub);
    if (s == AF_OK)
      s = af_ros_sub_limit(sub, ring_samples(st, true), on_force_refused);
  }
  const char *what;
  if (s == AF_OK && st->cfg->audio_common) /* audio_common_msgs, decoded (audio_in.h) */
    s = af_audio_in_create(st->ros, st->cfg, on_audio, st, &st->audio_in, &what);
  else if (s == AF_OK) {
    s = af_ros_subscribe(st->ros, "audio", AF_MSG_SIGNAL_CHUNK, AF_CHUNK_QUEUE, on_audio, st, &sub);
    if (s == AF_OK)
      s = af_ros_sub_limit(sub, ring_samples(st, false), on_audio_refused);
  }
  if (s == AF_OK)
    s = af_ros_subscribe(st->ros, "apple", AF_MSG_APPLE_ESTIMATE, AF_APPLE_QUEUE, on_apple, st,
                         &sub);
  return s;
}

/* Waits up to AF_TF_WAIT_S for the hammer's mount frame in TF (latched
 * /tf_static from robot_state_publisher), so that the first apples find it;
 * without it each apple's prediction says why its strike point is unknown. */
static void warn_no_rig_frames(af_station *st)
{
  af_ros_log(st->ros, AF_LOG_WARN,
             "the rig's frame '%s' is not in TF after %.0f s (is robot_state_publisher "
             "running on the rig's URDF?): strike points stay unknown until it is",
             st->cfg->hammer.mount_frame, AF_TF_WAIT_S);
}

/* Under simulated time that has not started (replay before rosbag play's
 * first /clock) the rig's fixed frames cannot be there yet:
 * robot_state_publisher sends them from a timer on that clock. The check
 * then waits for the clock (af_station_update) instead of warning falsely. */
static void wait_for_rig_frames(af_station *st)
{
  const char *mount = st->cfg->hammer.mount_frame;
  if (!st->cfg->hammer_axis_known)
    return;
  if (af_time_to_ns(af_ros_now(st->ros)) == 0) {
    st->tf_check_deferred = true;
    af_ros_log(st->ros, AF_LOG_DEBUG,
               "simulated clock not started: the rig's frames are checked %.0f s after it does",
               AF_TF_WAIT_S);
    return;
  }
  for (int k = 0; k < (int)(AF_TF_WAIT_S / 0.1) && !af_tf_frame_known(st->tf, mount); k++)
    if (af_ros_spin_once(st->ros, 0.1) != AF_OK || !af_ros_ok(st->ros))
      return;
  if (!af_tf_frame_known(st->tf, mount))
    warn_no_rig_frames(st);
}

/* The deferred check: AF_TF_WAIT_S of the clock after its first tick. */
static void deferred_rig_frames(af_station *st)
{
  int64_t now_ns = af_time_to_ns(af_ros_now(st->ros));
  if (!st->tf_check_deferred || now_ns == 0)
    return;
  if (af_tf_frame_known(st->tf, st->cfg->hammer.mount_frame)) {
    st->tf_check_deferred = false;
    return;
  }
  if (st->tf_clock_start_ns == 0)
    st->tf_clock_start_ns = now_ns;
  if ((double)(now_ns - st->tf_clock_start_ns) * 1e-9 >= AF_TF_WAIT_S) {
    warn_no_rig_frames(st);
    st->tf_check_deferred = false;
  }
}

/* Makes each part in turn; *what names the one that failed. */
/* This process's start under the master: ~node_starts + 1 (station.launch
 * sets it to 0 at each launch; the master keeps it across respawns). A
 * restarted process keeps nothing of the one before (no pending strike, no
 * apple, fresh streams and detector, which stays unarmed through its warm-up
 * so that the tail of a contact cut by the restart is not taken for a
 * strike): it resumes with the next apple's estimate and the strikes after
 * it, and says so in the log and /diagnostics. */
static void note_start(af_station *st)
{
  int n = 0;
  if (af_ros_param_int(st->ros, "node_starts", &n) != AF_OK || n < 0)
    n = 0; /* absent (rosrun): a first start */
  st->starts = n + 1;
  if (af_ros_param_set_int(st->ros, "node_starts", st->starts) != AF_OK)
    af_ros_log(st->ros, AF_LOG_WARN, "could not record the start count: %s",
               af_ros_last_error(st->ros));
  time_t now = time(NULL);
  const struct tm *utc = gmtime(&now);
  if (!utc || strftime(st->started, sizeof st->started, "%Y-%m-%d %H:%M:%S", utc) == 0)
    af_text(st->started, sizeof st->started, "unknown time");
  if (st->starts > 1)
    af_ros_log(st->ros, AF_LOG_WARN,
               "restarted (start %d under this master): resuming with the next apple; nothing "
               "from before the restart is reported",
               st->starts);
}

static af_status build(af_station *st, const char **what)
{
  af_status s;
  st->clock_start_ns = af_time_to_ns(af_ros_now(st->ros)); /* 0: a simulated clock not started */
  *what = "the diagnostics";
  const char *hw =
      st->cfg->hardware_id[0] != '\0' ? st->cfg->hardware_id : af_ros_node_name(st->ros);
  if ((s = af_ros_diag_create(st->ros, hw, &st->diag)) != AF_OK)
    return s;
  for (size_t k = 0; k < AF_COMPONENTS; k++)
    if ((s = af_ros_diag_add_task(st->diag, component_names[k], component_tasks[k], st)) != AF_OK)
      return s;
  start_rates(st, st->clock_start_ns);
  note_start(st);
  *what = "the publishers";
  if ((s = advertise(st)) != AF_OK)
    return s;
  if ((s = af_lane_io_create(st->ros, st->cfg, st->reliability_pub, st->markers_pub, &st->measured,
                             what)) != AF_OK)
    return s;
  if ((s = af_strike_plot_create(st->ros, st->cfg, &st->plot, what)) != AF_OK)
    return s;
  af_lane_io_set_strike_plot(st->measured, st->plot);
  if ((s = af_evaluate_create(st->ros, st->cfg, &st->evaluate, what)) != AF_OK)
    return s;
  /* main owns the configuration (not const there); a reconfigure changes it in place. */
  if ((s = af_live_settings_create(st->ros, (af_node_config *)st->cfg, st->measured, &st->live,
                                   what)) != AF_OK)
    return s;
  *what = "the settings snapshot";
  if ((s = af_snapshot_create(st->ros, st->cfg, &st->snapshot)) != AF_OK)
    return s;
  af_live_settings_set_snapshot(st->live, st->snapshot);
  *what = "the TF listener";
  if ((s = af_tf_create(st->ros, &st->tf)) != AF_OK)
    return s;
  wait_for_rig_frames(st);
  *what = "the subscribers";
  return subscribe(st);
}

af_status af_station_create(af_ros *ros, const af_node_config *cfg, af_station **out)
{
  *out = NULL;
  af_station *st = calloc(1, sizeof *st);
  if (!st)
    return AF_ENOMEM;
  st->ros = ros;
  st->cfg = cfg;
  const char *what;
  af_status s = build(st, &what);
  if (s != AF_OK) {
    af_ros_log(ros, AF_LOG_FATAL, "could not create %s: %s %s", what, af_strerror(s),
               af_ros_last_error(ros));
    af_station_destroy(st);
    return s;
  }
  *out = st;
  return AF_OK;
}

void af_station_destroy(af_station *st)
{
  if (!st)
    return;
  af_lane_io_destroy(st->measured);
  af_evaluate_destroy(st->evaluate);
  af_live_settings_destroy(st->live);
  af_snapshot_destroy(st->snapshot);
  af_audio_in_destroy(st->audio_in);
  af_strike_plot_destroy(st->plot);
  af_tf_destroy(st->tf);
  free(st); /* publishers, subscribers and diagnostics belong to the af_ros */
}

void af_station_update(af_station *st)
{
  deferred_rig_frames(st);
  af_lane_io_poll(st->measured);
  af_strike_plot_update(st->plot); /* renders outside every callback */
  af_ros_diag_update(st->diag);
}
