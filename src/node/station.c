/* station.c — the station node's life cycle and its input streams (station_private.h). */
#include "station_private.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

/* --- streams --------------------------------------------------------------- */

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
  if (af_station_power_of_two(count))
    af_ros_log(st->ros, AF_LOG_WARN, "%s (%llu so far)", s->last_problem, count);
  const unsigned long long faults = s->clock_steps + s->clock_frozen + s->clock_rate_wrong;
  unsigned long long *seen = s == af_lane_force_stream(af_lane_io_lane(st->measured))
                                 ? &st->force_clock_seen
                                 : &st->audio_clock_seen;
  if (faults != *seen && af_station_power_of_two(faults))
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
  if (!st->cfg->lane.strikes.tap_only) { /* tap-only: a microphone, no force transducer */
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
    s = af_ros_subscribe(st->ros, "apple", AF_MSG_APPLE_ESTIMATE, AF_APPLE_QUEUE,
                         af_station_on_apple, st, &sub);
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
  if ((s = af_station_diag_create(st)) != AF_OK)
    return s;
  af_station_start_rates(st, st->clock_start_ns);
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
