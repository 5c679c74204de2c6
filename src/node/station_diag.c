/* station_diag.c — the station's /diagnostics: one task per component,
 * judged together by the first (station_private.h). */
#include "station_private.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static const char *const component_names[AF_COMPONENTS] = {
    "firmness station", "force stream",           "audio stream",  "apple input",
    "detector",         "attribution and clocks", "hammer health", "modulus factor"};

/* The diagnostic summary in rviz (status_marker.h): warning NULL = OK. Over
 * the rig, in the hammer's mount frame (the URDF root's axes on the shipped
 * rig). */
void af_station_publish_status(af_station *st, const char *warning)
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
  if (!c->lane.strikes.tap_only)
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
void af_station_start_rates(af_station *st, int64_t now_ns)
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
    af_station_start_rates(st, now_ns);
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
  if (c->lane.strikes.tap_only)
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
             c->lane.strikes.tap_only ? "ok (tap_only: the audio onset)"
             : tr.armed               ? "ok (armed)"
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
  if (too_long && af_station_power_of_two(st->guard.refused))
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
  af_station_publish_status(st, worst->level == AF_DIAG_OK ? NULL : worst->message);
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
              c->lane.strikes.tap_only
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
  if (!st->cfg->lane.strikes.tap_only)
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

af_status af_station_diag_create(af_station *st)
{
  const char *hw =
      st->cfg->hardware_id[0] != '\0' ? st->cfg->hardware_id : af_ros_node_name(st->ros);
  af_status s = af_ros_diag_create(st->ros, hw, &st->diag);
  for (size_t k = 0; k < AF_COMPONENTS && s == AF_OK; k++)
    s = af_ros_diag_add_task(st->diag, component_names[k], component_tasks[k], st);
  return s;
}
