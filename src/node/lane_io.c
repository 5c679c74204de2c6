/* lane_io.c — messages into the lane, measured strikes out (see lane_io.h). */
#include "lane_io.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "fastpath.h"
#include "grade.h"
#include "markers.h"
#include "strike_plot.h"
#include "text.h"

/* Outgoing messages a slow subscriber may leave queued: a node catching up
 * on a backlog publishes a burst of reports, and roscpp drops what exceeds
 * the queue without a word (5 StrikeReports lost at 80x with 10). */
#define AF_OUTPUT_QUEUE 1000
#define AF_LABELS 16 /* label places remembered, as the lane's apple history */

typedef struct {
  double last, max, sum;
  uint64_t n;
} af_timing;

typedef struct {
  bool used;
  uint32_t apple_id;
  af_header header;
  double centre_m[3], top_m;
} af_label_place;

struct af_lane_io {
  af_ros *ros;
  const af_node_config *cfg;
  af_lane *lane;
  af_ros_pub *report_pub, *reliability_pub, *markers_pub;
  af_strike_plot *plot; /* the live picture; NULL = none (strike_plot.h) */
  af_label_place labels[AF_LABELS];
  size_t label_next;
  double entry_wall_s; /* wall clock [s] when the current callback began (chunk, apple
                        * estimate or poll: what can make a strike decidable); 0 = none */
  /* Output scratch. */
  af_strike_report report;
  af_reliability rel;
  af_marker label;
  /* For the diagnostics. */
  af_lane_stats seen; /* at the last diagnostic */
  bool have_last;
  af_strike_report last;
  af_timing latency; /* [ms] */
  /* Strikes per firmness class; [0] ungraded. */
  unsigned long long graded[AF_GRADE_CLASSES_MAX + 1];
};

static double wall_s(void)
{
  struct timespec ts;
  if (timespec_get(&ts, TIME_UTC) != TIME_UTC)
    return 0.0;
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static int64_t now_ns(const af_lane_io *m)
{
  return af_time_to_ns(af_ros_now(m->ros));
}

int64_t af_time_to_ns(af_time t)
{
  return (int64_t)t.sec * 1000000000LL + (int64_t)t.nsec;
}

af_time af_time_from_ns(int64_t ns)
{
  af_time t = {0, 0};
  if (ns > 0) {
    t.sec = (uint32_t)(ns / 1000000000LL);
    t.nsec = (uint32_t)(ns % 1000000000LL);
  }
  return t;
}

/* --- outputs ------------------------------------------------------------------ */

static void publish(af_lane_io *m, af_ros_pub *pub, const void *msg, const char *topic)
{
  if (af_ros_publish(pub, msg) != AF_OK)
    af_ros_log(m->ros, AF_LOG_ERROR, "%s not published: %s", topic, af_ros_last_error(m->ros));
}

static void report_from_measure(const af_measure_report *q, af_strike_report *r)
{
  r->contact_time_s = q->contact_time_s;
  r->peak_force_n = q->peak_force_n;
  r->impulse_n_s = q->impulse_n_s;
  r->band_low_hz = q->band_low_hz;
  r->band_high_hz = q->band_high_hz;
  r->resonance_hz = q->resonance_hz;
  r->resonance_q = q->resonance_q;
  r->snr_db = q->snr_db;
  r->stiffness_factor = q->stiffness_factor;
  r->modulus_from_resonance_pa = q->modulus_from_resonance_pa;
  r->fitted_modulus_pa = q->fitted_modulus_pa;
  r->fitted_restitution = q->fitted_restitution;
  r->fit_residual = q->fit_residual;
  r->delivered_energy_j = q->delivered_energy_j;
  r->absorbed_energy_j = q->absorbed_energy_j;
  r->double_hit = q->double_hit;
  r->clipped = q->clipped;
  r->lost_samples = q->lost_samples;
  r->audio_clipped = q->audio_clipped;
  r->audio_lag_s = q->audio_lag_s;
  r->audio_lag_applied_s = q->audio_lag_applied_s;
  r->tap_only = q->tap_only;
  af_text(r->judged_from_model, sizeof r->judged_from_model, "%s", q->model_only_text);
}

/* The strike's firmness class, graded by the lane (lane.h), counted for the diagnostics. */
static void grade_report(af_lane_io *m, const af_grade *g, af_strike_report *r)
{
  r->grade_index = (uint8_t)g->index;
  af_text(r->grade, sizeof r->grade, "%s", g->name);
  af_text(r->grade_reason, sizeof r->grade_reason, "%s", g->reason);
  m->graded[g->index <= AF_GRADE_CLASSES_MAX ? g->index : 0]++;
}

static void grade_diag(const af_lane_io *m, af_diag_status *d)
{
  const af_grade_config *g = &m->cfg->lane.grade;
  char text[AF_TEXT_MAX];
  af_grade_config_format(g, text, sizeof text);
  af_diag_add(d, "grade classes", "%s", text);
  size_t used = 0;
  text[0] = '\0';
  for (size_t k = 1; k <= g->n_classes && used < sizeof text; k++) {
    int w = snprintf(text + used, sizeof text - used, "%s %llu, ", g->names[k - 1], m->graded[k]);
    used += w > 0 ? (size_t)w : 0;
  }
  if (used < sizeof text)
    snprintf(text + used, sizeof text - used, "ungraded %llu", m->graded[0]);
  af_diag_add(d, "strikes per grade", "%s", text);
}

static const af_label_place *label_place(const af_lane_io *m, uint32_t apple_id)
{
  for (size_t k = 0; k < AF_LABELS; k++)
    if (m->labels[k].used && m->labels[k].apple_id == apple_id)
      return &m->labels[k];
  return NULL;
}

static void publish_label(af_lane_io *m, const af_label_place *a)
{
  const af_strike_report *r = &m->report;
  char text[AF_TEXT_MAX];
  af_text(text, sizeof text,
          "measured: 0S2 %.0f Hz (%.1f MPa), fit %.1f MPa e %.2f, %.2f ms, %s, grade %s",
          r->resonance_hz, r->modulus_from_resonance_pa * 1e-6, r->fitted_modulus_pa * 1e-6,
          r->fitted_restitution, r->contact_time_s * 1e3,
          m->rel.reliable ? "reliable" : "NOT reliable", r->grade);
  af_markers_measured_label(&a->header, a->centre_m, a->top_m, text, m->cfg->marker_lifetime_s,
                            &m->label);
  af_marker_array arr = {&m->label, 1};
  if (af_ros_publish(m->markers_pub, &arr) != AF_OK)
    af_ros_log(m->ros, AF_LOG_WARN, "markers not published: %s", af_ros_last_error(m->ros));
}

static void timing_add(af_timing *t, double ms)
{
  t->last = ms;
  t->max = ms > t->max ? ms : t->max;
  t->sum += ms;
  t->n++;
}

/* The lane's callback: one measured strike out as messages. */
static void on_lane_strike(const af_lane_strike *s, void *user)
{
  af_lane_io *m = user;
  af_strike_report *r = &m->report;
  af_reliability *rel = &m->rel;
  const af_measure_report *q = &s->report;
  memset(r, 0, sizeof *r);
  memset(rel, 0, sizeof *rel);
  r->header.stamp = af_time_from_ns(s->start_ns);
  af_text(r->header.frame_id, sizeof r->header.frame_id, "%s", s->frame_id);
  r->apple_id = s->apple_id;
  report_from_measure(q, r);
  grade_report(m, &s->grade, r);
  rel->header = r->header;
  rel->apple_id = s->apple_id;
  af_text(rel->source, sizeof rel->source, "measured");
  rel->excites_mode = q->excites_mode;
  rel->no_damage = q->no_damage;
  rel->reliable = q->reliable;
  rel->max_shear_stress_pa = q->max_shear_stress_pa;
  rel->yield_shear_stress_pa = q->yield_shear_stress_pa;
  af_text(rel->reason, sizeof rel->reason, "%s", q->reason);
  publish(m, m->report_pub, r, "strike_report");
  publish(m, m->reliability_pub, rel, "reliability");
  if (s->with_audio && m->entry_wall_s > 0.0)
    timing_add(&m->latency, (wall_s() - m->entry_wall_s) * 1e3);
  const af_label_place *place = label_place(m, s->apple_id);
  if (m->markers_pub && s->prediction && s->prediction->valid && place)
    publish_label(m, place);
  if (s->factor_changed) {
    const af_factor_learn_state *f = af_lane_factor(m->lane);
    af_ros_log(m->ros, AF_LOG_INFO,
               "modulus_factor applied: %.4f (was %.4f), the median of %zu reliable strikes "
               "(95 %% interval [%.4f, %.4f]); change %llu",
               f->applied, f->previous, f->n, f->ci_low_95, f->ci_high_95,
               (unsigned long long)f->changes);
  }
  af_strike_plot_capture(m->plot, s, m->lane); /* a copy; drawn in the node's loop */
  m->have_last = true;
  m->last = *r;
  af_ros_log(m->ros, AF_LOG_DEBUG,
             "strike on apple %u: t_c %.4f ms, peak %.2f N, 0S2 %.1f Hz, E2 fit %.3g Pa: %s",
             r->apple_id, r->contact_time_s * 1e3, r->peak_force_n, r->resonance_hz,
             r->fitted_modulus_pa, rel->reliable ? "reliable" : rel->reason);
}

/* --- inputs ------------------------------------------------------------------- */

static af_chunk chunk_of(const af_signal_chunk *c)
{
  af_chunk k = {af_time_to_ns(c->header.stamp),
                c->first_sample,
                c->sample_rate_hz,
                c->unit,
                c->header.frame_id,
                c->data,
                c->n};
  return k;
}

/* One chunk into the lane through push (af_lane_force or af_lane_audio),
 * the wall clock noted for the latency of the strikes it completes. */
static af_chunk_verdict push_chunk(af_lane_io *m,
                                   af_chunk_verdict (*push)(af_lane *, const af_chunk *, int64_t,
                                                            af_ring_write_info *),
                                   const af_signal_chunk *c, af_ring_write_info *info)
{
  af_chunk k = chunk_of(c);
  m->entry_wall_s = wall_s();
  af_chunk_verdict v = push(m->lane, &k, now_ns(m), info);
  m->entry_wall_s = 0.0;
  return v;
}

af_chunk_verdict af_lane_io_force(af_lane_io *m, const af_signal_chunk *c, af_ring_write_info *info)
{
  return push_chunk(m, af_lane_force, c, info);
}

af_chunk_verdict af_lane_io_audio(af_lane_io *m, const af_signal_chunk *c, af_ring_write_info *info)
{
  return push_chunk(m, af_lane_audio, c, info);
}

af_status af_lane_io_apple(af_lane_io *m, const af_apple *a, const af_prediction **pred)
{
  m->entry_wall_s = wall_s(); /* the next apple's estimate settles a waiting strike */
  af_status st = af_lane_apple(m->lane, a, now_ns(m), pred);
  m->entry_wall_s = 0.0;
  return st;
}

void af_lane_io_label_place(af_lane_io *m, uint32_t apple_id, const af_header *h,
                            const double centre_m[3], double top_m)
{
  af_label_place *p = &m->labels[m->label_next];
  m->label_next = (m->label_next + 1) % AF_LABELS;
  p->used = true;
  p->apple_id = apple_id;
  p->header = *h;
  memcpy(p->centre_m, centre_m, sizeof p->centre_m);
  p->top_m = top_m;
}

void af_lane_io_set_strike_plot(af_lane_io *m, af_strike_plot *plot)
{
  m->plot = plot;
}

void af_lane_io_poll(af_lane_io *m)
{
  m->entry_wall_s = wall_s(); /* the apple wait may have run out */
  af_lane_poll(m->lane, now_ns(m));
  m->entry_wall_s = 0.0;
}

af_status af_lane_io_reconfigured(af_lane_io *m, bool grades_changed, const char **what)
{
  if (grades_changed) /* the classes' counts start again */
    memset(m->graded, 0, sizeof m->graded);
  return af_lane_reconfigured(m->lane, what);
}

const af_lane *af_lane_io_lane(const af_lane_io *m)
{
  return m->lane;
}

void af_lane_io_refuse(af_lane_io *m, bool force, bool oversized, const char *why)
{
  af_lane_refuse(m->lane, force, oversized, why);
}

/* --- diagnostics ---------------------------------------------------------------- */

/* The first new problem of each component since the last report, in the
 * order of importance; the held ones (transit, hammer health) while they last. */
void af_lane_io_warnings_get(af_lane_io *m, af_lane_io_warnings *w)
{
  const af_lane_stats *s = af_lane_get_stats(m->lane);
  memset(w, 0, sizeof *w);
  if (s->overflows != m->seen.overflows)
    w->detector = "strike queue overflowed since the last report";
  else if (s->reconfigure_lost != m->seen.reconfigure_lost)
    w->detector = s->last_reconfigure_lost;
  if (s->audio_clipped != m->seen.audio_clipped)
    w->audio = "the microphone clipped since the last report: lower the microphone gain";
  if (s->doubtful != m->seen.doubtful)
    w->attribution = "doubtful apple matches since the last report";
  else if (s->late_apples != m->seen.late_apples)
    w->attribution = "apple estimates arrived after their strikes since the last report";
  else if (s->no_audio != m->seen.no_audio)
    w->attribution = "strikes measured without audio since the last report";
  else if (s->no_apple != m->seen.no_apple)
    w->attribution = "strikes without an apple estimate since the last report";
  else if (s->apples_skipped != m->seen.apples_skipped)
    w->attribution = s->last_apples_skipped;
  else if (s->lag_moves != m->seen.lag_moves)
    w->attribution = s->lag_warning;
  else if (s->clock_faulted != m->seen.clock_faulted)
    w->attribution = "strikes judged across a clock fault since the last report (their audio or "
                     "apple found by stamps that cannot be trusted)";
  else if (s->transit_warning[0] != '\0')
    w->attribution = s->transit_warning; /* held while it lasts, as the hammer's */
  else if (s->apples_implausible != m->seen.apples_implausible)
    w->attribution = "apple estimates refused (apple_id 0, or stamped far from the data) since "
                     "the last report";
  if (s->health.warnings != 0)
    w->health = s->health.text; /* held while it lasts: the lane's stats outlive the report */
  m->seen = *s;
}

/* The hammer health's figures (hammer_health.h): each with its limit. */
static void health_diag(const af_lane_io *m, af_diag_status *d)
{
  const af_hammer_health_stats *h = &af_lane_get_stats(m->lane)->health;
  const af_hammer_health_config *c = &m->cfg->lane.health;
  if (h->warnings != 0)
    af_diag_add(d, "hammer health", "WARN: %s", h->text);
  else
    af_diag_add(d, "hammer health", "OK (%zu strikes in the window of %zu; checks from %zu)",
                h->window_strikes, c->window, c->min_strikes);
  af_diag_add(d, "hammer contact velocity [m/s]",
              "%.4f from the impulse (mean of %zu clean strikes, SD %.4f, %+.2f %% of "
              "strike_velocity_m_s %.4g, band +- %.1f %%)",
              h->velocity_m_s, h->velocity_strikes, h->velocity_sd_m_s,
              100.0 * h->velocity_deviation, c->velocity_m_s, 100.0 * c->velocity_band);
  if (h->fit_velocity_strikes > 0)
    af_diag_add(d, "hammer contact velocity fitted [m/s]", "%.4f (mean of %zu strikes)",
                h->fit_velocity_m_s, h->fit_velocity_strikes);
  else
    af_diag_add(d, "hammer contact velocity fitted [m/s]",
                "none (measure_fit_velocity false, or no fit)");
  af_diag_add(d, "hammer delivered restitution [-]", "%.3f fitted (mean of %zu), cultivar's %.3f",
              h->restitution, h->restitution_strikes, c->restitution);
  af_diag_add(d, "force baseline [N]", "%.4f (reference %.4f, drift %+.4f, limit %.4g)",
              h->baseline_n, h->baseline_reference_n, h->baseline_drift_n,
              c->baseline_drift_limit_n);
  af_diag_add(d, "force noise RMS [N]", "%.4f (mean of %zu strikes)", h->noise_rms_n,
              h->window_strikes);
  af_diag_add(d, "hammer peak force [N]", "mean %.3f, SD %.3f, %.3f .. %.3f", h->peak_force_n,
              h->peak_force_sd_n, h->peak_force_min_n, h->peak_force_max_n);
  af_diag_add(d, "hammer clipping", "%zu of %zu strikes (%.1f %%, limit %.1f %%)",
              h->clipped_strikes, h->window_strikes, 100.0 * h->clip_rate,
              100.0 * c->clip_rate_limit);
}

/* The modulus factor learned on the line (factor_learn.h); NaN = none yet. */
static void factor_diag(const af_lane_io *m, af_diag_status *d)
{
  const af_factor_learn_state *f = af_lane_factor(m->lane);
  const af_factor_learn_config *c = &m->cfg->lane.factor_learn;
  af_diag_add(d, "modulus factor learned", "%.4f", f->estimate);
  af_diag_add(d, "modulus factor learned 95% interval", "[%.4f, %.4f]", f->ci_low_95,
              f->ci_high_95);
  af_diag_add(d, "modulus factor learned strikes",
              "%zu (estimate from %zu, window %zu; %llu "
              "refused: unreliable or without 0S2 or fit)",
              f->n, c->min_strikes, c->window_strikes, (unsigned long long)f->refused);
  af_diag_add(d, "modulus factor applied", "%.4f (%s)", f->applied,
              c->apply ? "learned values applied: modulus_factor_learn_apply true"
                       : "the cultivar's: modulus_factor_learn_apply false");
  af_diag_add(d, "modulus factor changes", "%llu", (unsigned long long)f->changes);
}

/* The detector and the strikes it makes (the "detector" task). */
void af_lane_io_diag_detector(const af_lane_io *m, af_diag_status *d)
{
  const af_lane_stats *s = af_lane_get_stats(m->lane);
  af_strike_tracker tr;
  af_strike_get_tracker(af_lane_detector(m->lane), &tr);
  af_diag_add(d, "strikes", "%llu", (unsigned long long)s->strikes);
  af_diag_add(d, "strike detector", "%s, baseline %.4f N, noise %.4f N RMS, threshold %.4f N",
              tr.armed ? "armed" : "learning or waiting for quiet", tr.baseline_n, tr.noise_rms_n,
              tr.threshold_n);
  af_diag_add(d, "strike double hits", "%llu", (unsigned long long)s->double_hits);
  af_diag_add(d, "strikes clipped", "%llu (truncated %llu)", (unsigned long long)s->clipped,
              (unsigned long long)s->truncated);
  af_diag_add(d, "strikes cut by a stalled force stream", "%llu",
              (unsigned long long)s->force_stalls);
  af_diag_add(d, "strikes lost to a reconfigure",
              "%llu (the detector made anew is primed from "
              "the latest force, no warm-up)",
              (unsigned long long)s->reconfigure_lost);
  af_diag_add(d, "strike force samples lost", "%llu", (unsigned long long)s->lost_force_samples);
  af_diag_add(d, "strikes without resonance", "%llu", (unsigned long long)s->no_resonance);
  af_diag_add(d, "strikes unreliable", "%llu (measurement errors %llu)",
              (unsigned long long)s->unreliable, (unsigned long long)s->measure_errors);
  af_diag_add(d, "strike queue", "%zu pending of %zu", af_lane_pending(m->lane),
              m->cfg->lane.strikes.pending_size);
  af_diag_add(d, "strike queue overflows", "%llu", (unsigned long long)s->overflows);
  if (s->pulse_cut > 0)
    af_diag_add(d, "strike pulses cut", "%llu (longer than the pending slot)",
                (unsigned long long)s->pulse_cut);
  if (m->have_last) {
    const af_strike_report *r = &m->last;
    af_diag_add(d, "last measured apple", "%u", r->apple_id);
    af_diag_add(d, "last measured resonance [Hz]", "%.2f (Q %.1f, SNR %.1f dB)", r->resonance_hz,
                r->resonance_q, r->snr_db);
    af_diag_add(d, "last measured modulus [Pa]", "%.4g from the resonance, %.4g fitted (e %.3f)",
                r->modulus_from_resonance_pa, r->fitted_modulus_pa, r->fitted_restitution);
  }
  af_diag_add(d, "last measured unreliable reason", "%s", s->last_unreliable);
  if (m->latency.n == 0)
    af_diag_add(d, "strike report latency [ms]", "none yet");
  else
    af_diag_add(d, "strike report latency [ms]",
                "last %.3f, mean %.3f, max %.3f over %llu (from the callback that made the "
                "strike decidable: its last audio chunk, the next apple's estimate or the "
                "apple wait's end, to the published report)",
                m->latency.last, m->latency.sum / (double)m->latency.n, m->latency.max,
                (unsigned long long)m->latency.n);
  grade_diag(m, d);
}

/* Which apple and which audio each strike was given, by stamps (the
 * "attribution and clocks" task; the streams' clocks are the station's). */
void af_lane_io_diag_attribution(const af_lane_io *m, af_diag_status *d)
{
  const af_lane_stats *s = af_lane_get_stats(m->lane);
  af_diag_add(d, "audio lag [s]",
              "median %.4f (MAD %.4f over %zu strikes), applied %.4f (audio_lag_learn %s); sound "
              "onset not found in %llu strikes; %llu moves%s%s",
              s->lag_median_s, s->lag_mad_s, s->lag_strikes, s->lag_applied_s,
              m->cfg->lane.strikes.audio_lag_learn ? "true" : "false",
              (unsigned long long)s->lag_no_onset, (unsigned long long)s->lag_moves,
              s->lag_warning[0] ? ": " : "", s->lag_warning);
  af_diag_add(d, "strikes judged across a clock fault", "%llu",
              (unsigned long long)s->clock_faulted);
  af_diag_add(d, "strikes without apple", "%llu", (unsigned long long)s->no_apple);
  af_diag_add(d, "strikes with a doubtful apple match", "%llu", (unsigned long long)s->doubtful);
  af_diag_add(d, "apple estimates after their strike", "%llu (last: %s)",
              (unsigned long long)s->late_apples, s->last_late_apple);
  if (s->transit_strikes > 0)
    af_diag_add(d, "apple transit [s]",
                "%.4f observed (median of the latest %zu matched strikes; "
                "apple_transit_s %g +- %g)",
                s->transit_observed_s, s->transit_strikes, m->cfg->lane.strikes.apple_transit_s,
                m->cfg->lane.strikes.apple_transit_tolerance_s);
  else
    af_diag_add(d, "apple transit [s]", "none observed yet (apple_transit_s %g +- %g)",
                m->cfg->lane.strikes.apple_transit_s,
                m->cfg->lane.strikes.apple_transit_tolerance_s);
  af_diag_add(d, "apple transit check", "%s",
              s->transit_warning[0] != '\0' ? s->transit_warning : "OK");
  af_diag_add(d, "apple estimates that never came",
              "%llu (ids counting up by one skipped; "
              "last: %s)",
              (unsigned long long)s->apples_skipped, s->last_apples_skipped);
  af_diag_add(d, "apple estimates refused as implausible", "%llu (last: %s)",
              (unsigned long long)s->apples_implausible, s->last_implausible_apple);
  af_diag_add(d, "strikes without audio", "%llu", (unsigned long long)s->no_audio);
  af_diag_add(d, "last strike without audio", "%s", s->last_no_audio);
}

/* The microphone's clipping, for the "audio stream" task. */
void af_lane_io_diag_audio(const af_lane_io *m, af_diag_status *d)
{
  const af_lane_stats *s = af_lane_get_stats(m->lane);
  af_diag_add(d, "strikes with the microphone clipped", "%llu%s",
              (unsigned long long)s->audio_clipped,
              s->audio_clipped ? " (lower the microphone gain)" : "");
}

void af_lane_io_diag_health(const af_lane_io *m, af_diag_status *d)
{
  health_diag(m, d);
}

void af_lane_io_diag_factor(const af_lane_io *m, af_diag_status *d)
{
  factor_diag(m, d);
}

const char *af_lane_io_factor_summary(const af_lane_io *m, char *buf, size_t len)
{
  const af_factor_learn_state *f = af_lane_factor(m->lane);
  const af_factor_learn_config *c = &m->cfg->lane.factor_learn;
  if (isnan(f->estimate))
    af_text(buf, len, "learning: %zu of %zu reliable strikes; %.4f applied", f->n, c->min_strikes,
            f->applied);
  else
    af_text(buf, len, "learned %.4f, %.4f applied (%s)", f->estimate, f->applied,
            c->apply ? "learned values applied" : "the cultivar's");
  return buf;
}

/* --- life cycle ------------------------------------------------------------------ */

af_status af_lane_io_create(af_ros *ros, const af_node_config *cfg, af_ros_pub *reliability_pub,
                            af_ros_pub *markers_pub, af_lane_io **out, const char **what)
{
  *out = NULL;
  *what = "the measured strikes";
  af_lane_io *m = calloc(1, sizeof *m);
  if (!m)
    return AF_ENOMEM;
  m->ros = ros;
  m->cfg = cfg;
  m->reliability_pub = reliability_pub;
  m->markers_pub = markers_pub;
  af_status s = af_lane_create(&cfg->lane, on_lane_strike, m, &m->lane, what);
  if (s == AF_OK) {
    /* The prediction's fast-path table, whole, at start-up (~0.08 s once):
     * otherwise the first apples of a shift pay its rows (~1 ms each) inside
     * their answer's latency. */
    *what = "the prediction's fast-path table";
    s = af_fastpath_table_build(NULL);
  }
  if (s == AF_OK) {
    *what = "the strike_report publisher";
    s = af_ros_advertise(ros, "strike_report", AF_MSG_STRIKE_REPORT, AF_OUTPUT_QUEUE, false,
                         &m->report_pub);
  }
  if (s != AF_OK) {
    af_lane_io_destroy(m);
    return s;
  }
  *out = m;
  return AF_OK;
}

void af_lane_io_destroy(af_lane_io *m)
{
  if (!m)
    return;
  af_lane_destroy(m->lane);
  free(m); /* the publisher belongs to the af_ros */
}
