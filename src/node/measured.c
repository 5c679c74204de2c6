/* measured.c — strike detection, the pending queue, the apple match and the
 * measured outputs (see measured.h). */
#include "measured.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "markers.h"
#include "measure.h"
#include "strike.h"
#include "text.h"

/* AppleEstimates remembered for the match: a few seconds of a line. */
#define AF_APPLE_HISTORY 16
#define AF_OUTPUT_QUEUE 10

typedef struct {
  af_strike_event ev; /* ev.pulse_n points at pulse */
  double *pulse;      /* pulse_capacity_samples, preallocated */
  int64_t start_ns;   /* contact start */
  char frame_id[AF_FRAME_ID_MAX];
  double queued_ros_s; /* ROS time when queued, for the audio time-out */
} af_pending;

typedef struct {
  bool used;
  bool predicted; /* the apple got a prediction (apple is valid) */
  af_header header;
  uint32_t apple_id;
  int64_t stamp_ns;
  af_measure_apple apple;
  char why[AF_TEXT_MAX]; /* why no prediction */
  double centre_m[3], top_m;
} af_apple_slot;

/* Why a strike goes without audio, or that it waits. */
typedef enum { AF_AUDIO_WAIT = 0, AF_AUDIO_READY, AF_AUDIO_NONE } af_audio_state;

typedef struct {
  double last, max, sum;
  uint64_t n;
} af_timing;

struct af_measured {
  af_ros *ros;
  const af_node_config *cfg;
  const af_measured_config *mc;
  const af_stream *force, *audio;
  af_strike *detector;
  af_measure *measure;
  af_ros_pub *report_pub, *reliability_pub, *markers_pub;
  /* The pending queue: a ring of pending_size slots. */
  af_pending *pending;
  double *pulses;
  size_t head, count;
  /* Audio scratch. */
  float *audio_buf, *noise_buf;
  af_apple_slot apples[AF_APPLE_HISTORY];
  size_t apple_next;
  /* Output scratch. */
  af_measure_report mrep;
  af_strike_report report;
  af_reliability rel;
  af_marker label;
  /* Counters for the diagnostics. */
  unsigned long long strikes, double_hits, clipped, truncated, lost_samples, no_resonance, no_apple,
      no_audio, unreliable, overflows, measure_errors, pulse_cut;
  unsigned long long seen_overflows, seen_no_audio, seen_no_apple; /* at the last diagnostic */
  bool have_last;
  uint32_t last_apple_id;
  double last_resonance_hz, last_q, last_snr_db, last_modulus_res_pa, last_fitted_pa, last_fitted_e;
  char last_reason[AF_TEXT_MAX];
  char last_no_audio[AF_TEXT_MAX];
  af_timing latency, measure_time; /* [ms] */
};

double af_measured_wall_s(void)
{
  struct timespec ts;
  if (timespec_get(&ts, TIME_UTC) != TIME_UTC)
    return 0.0;
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static void timing_add(af_timing *t, double ms)
{
  t->last = ms;
  t->max = ms > t->max ? ms : t->max;
  t->sum += ms;
  t->n++;
}

static double now_s(const af_measured *m)
{
  return af_time_to_s(af_ros_now(m->ros));
}

/* --- the apple match ---------------------------------------------------------- */

/* The newest apple stamped at or before t_ns and at most apple_stale_after_s
 * before it; NULL when none. */
static const af_apple_slot *match_apple(const af_measured *m, int64_t t_ns)
{
  const int64_t stale_ns = (int64_t)llround(m->mc->apple_stale_after_s * 1e9);
  const af_apple_slot *best = NULL;
  for (size_t k = 0; k < AF_APPLE_HISTORY; k++) {
    const af_apple_slot *a = &m->apples[k];
    if (!a->used || a->stamp_ns > t_ns || t_ns - a->stamp_ns > stale_ns)
      continue;
    if (best == NULL || a->stamp_ns >= best->stamp_ns)
      best = a;
  }
  return best;
}

void af_measured_apple(af_measured *m, const af_apple_estimate *a, const af_model_params *params,
                       const char *why, const double centre_m[3], double top_m)
{
  af_apple_slot *s = &m->apples[m->apple_next];
  m->apple_next = (m->apple_next + 1) % AF_APPLE_HISTORY;
  memset(s, 0, sizeof *s);
  s->used = true;
  s->predicted = params != NULL;
  s->header = a->header;
  s->apple_id = a->apple_id;
  s->stamp_ns = af_time_to_ns(a->header.stamp);
  if (params) {
    s->apple.model = *params;
    s->apple.modulus_min_pa = m->cfg->lane.modulus_min_pa;
    s->apple.modulus_max_pa = m->cfg->lane.modulus_max_pa;
  }
  af_text(s->why, sizeof s->why, "%s", why ? why : "");
  if (centre_m)
    memcpy(s->centre_m, centre_m, sizeof s->centre_m);
  s->top_m = top_m;
}

/* --- outputs ------------------------------------------------------------------ */

static void publish(af_measured *m, af_ros_pub *pub, const void *msg, const char *topic)
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
  r->double_hit = q->double_hit;
  r->clipped = q->clipped;
  r->lost_samples = q->lost_samples;
}

static void publish_label(af_measured *m, const af_apple_slot *a)
{
  const af_strike_report *r = &m->report;
  char text[AF_TEXT_MAX];
  af_text(text, sizeof text, "measured: 0S2 %.0f Hz (%.1f MPa), fit %.1f MPa e %.2f, %.2f ms, %s",
          r->resonance_hz, r->modulus_from_resonance_pa * 1e-6, r->fitted_modulus_pa * 1e-6,
          r->fitted_restitution, r->contact_time_s * 1e3,
          m->rel.reliable ? "reliable" : "NOT reliable");
  af_markers_measured_label(&a->header, a->centre_m, a->top_m, text, m->cfg->marker_lifetime_s,
                            &m->label);
  af_marker_array arr = {&m->label, 1};
  if (af_ros_publish(m->markers_pub, &arr) != AF_OK)
    af_ros_log(m->ros, AF_LOG_WARN, "markers not published: %s", af_ros_last_error(m->ros));
}

/* The measurement's reason with its "no audio" part saying why:
 * "...; no audio (audio stream stale ...); ..." (prepended when absent). */
static void reason_with_audio(const char *reason, const char *why, char *out, size_t len)
{
  static const char tag[] = "no audio";
  const char *at = reason;
  while ((at = strstr(at, tag)) != NULL) {
    bool starts = at == reason || (at >= reason + 2 && at[-2] == ';' && at[-1] == ' ');
    char next = at[sizeof tag - 1];
    if (starts && (next == '\0' || next == ';'))
      break;
    at += sizeof tag - 1;
  }
  if (at == NULL)
    af_text(out, len, "no audio (%s)%s%s", why, reason[0] ? "; " : "", reason);
  else
    af_text(out, len, "%.*sno audio (%s)%s", (int)(at - reason), reason, why, at + sizeof tag - 1);
}

/* Measures the pending strike p with the audio window (n_audio 0: none, and
 * no_audio says why) and publishes its report and Reliability. */
static void measure_one(af_measured *m, af_pending *p, const float *audio, size_t n_audio,
                        const float *noise, size_t n_noise, const char *no_audio,
                        double entry_wall_s)
{
  af_strike_report *r = &m->report;
  af_reliability *rel = &m->rel;
  memset(r, 0, sizeof *r);
  memset(rel, 0, sizeof *rel);
  r->header.stamp = af_time_from_ns(p->start_ns);
  memcpy(r->header.frame_id, p->frame_id, sizeof r->header.frame_id);
  rel->header = r->header;
  af_text(rel->source, sizeof rel->source, "measured");
  rel->max_shear_stress_pa = rel->yield_shear_stress_pa = NAN;

  const af_apple_slot *a = match_apple(m, p->start_ns);
  char reason[AF_TEXT_MAX] = "";
  bool measured = false;
  if (a == NULL) {
    m->no_apple++;
    af_text(reason, sizeof reason, "no apple estimate within %g s before the strike",
            m->mc->apple_stale_after_s);
  } else if (!a->predicted) {
    m->no_apple++;
    r->apple_id = a->apple_id;
    af_text(reason, sizeof reason, "apple %u got no prediction: %s", a->apple_id, a->why);
  } else {
    r->apple_id = a->apple_id;
    double t0 = af_measured_wall_s();
    af_status s = af_measure_strike(m->measure, &p->ev, &a->apple, n_audio ? audio : NULL, n_audio,
                                    n_noise ? noise : NULL, n_noise, &m->mrep);
    timing_add(&m->measure_time, (af_measured_wall_s() - t0) * 1e3);
    if (s == AF_OK) {
      measured = true;
      report_from_measure(&m->mrep, r);
      rel->excites_mode = m->mrep.excites_mode;
      rel->no_damage = m->mrep.no_damage;
      rel->reliable = m->mrep.reliable;
      rel->max_shear_stress_pa = m->mrep.max_shear_stress_pa;
      rel->yield_shear_stress_pa = m->mrep.yield_shear_stress_pa;
      if (n_audio == 0 && no_audio && no_audio[0])
        reason_with_audio(m->mrep.reason, no_audio, reason, sizeof reason);
      else
        af_text(reason, sizeof reason, "%s", m->mrep.reason);
    } else {
      m->measure_errors++;
      af_text(reason, sizeof reason, "measurement failed: %s", af_strerror(s));
    }
  }
  if (!measured) {
    if (af_measure_pulse(m->measure, &p->ev, m->cfg->lane.model.band_level, m->cfg->lane.model.lobe,
                         &m->mrep) == AF_OK)
      report_from_measure(&m->mrep, r);
    else
      m->measure_errors++;
  }
  if (rel->reliable && reason[0] == '\0')
    rel->reason[0] = '\0';
  else {
    rel->reliable = false;
    af_text(rel->reason, sizeof rel->reason, "%s", reason[0] ? reason : "not reliable");
  }
  rel->apple_id = r->apple_id;

  publish(m, m->report_pub, r, "strike_report");
  publish(m, m->reliability_pub, rel, "reliability");
  if (n_audio > 0 && entry_wall_s > 0.0)
    timing_add(&m->latency, (af_measured_wall_s() - entry_wall_s) * 1e3);
  if (m->markers_pub && a != NULL && a->predicted)
    publish_label(m, a);

  /* Bookkeeping. */
  m->strikes++;
  m->double_hits += p->ev.double_hit;
  m->clipped += p->ev.clipped;
  m->truncated += p->ev.truncated;
  m->lost_samples += p->ev.lost_samples;
  m->no_resonance += isnan(r->resonance_hz);
  m->unreliable += !rel->reliable;
  if (n_audio == 0 && no_audio && no_audio[0]) {
    m->no_audio++;
    af_text(m->last_no_audio, sizeof m->last_no_audio, "strike at %u.%09u: %s", r->header.stamp.sec,
            r->header.stamp.nsec, no_audio);
  }
  m->have_last = true;
  m->last_apple_id = r->apple_id;
  m->last_resonance_hz = r->resonance_hz;
  m->last_q = r->resonance_q;
  m->last_snr_db = r->snr_db;
  m->last_modulus_res_pa = r->modulus_from_resonance_pa;
  m->last_fitted_pa = r->fitted_modulus_pa;
  m->last_fitted_e = r->fitted_restitution;
  if (!rel->reliable)
    af_text(m->last_reason, sizeof m->last_reason, "apple %u: %s", r->apple_id, rel->reason);
  af_ros_log(m->ros, AF_LOG_DEBUG,
             "strike on apple %u: t_c %.4f ms, peak %.2f N, 0S2 %.1f Hz, E2 fit %.3g Pa: %s",
             r->apple_id, r->contact_time_s * 1e3, r->peak_force_n, r->resonance_hz,
             r->fitted_modulus_pa, rel->reliable ? "reliable" : rel->reason);
}

/* --- the pending queue ----------------------------------------------------------- */

static bool all_finite(const float *x, size_t n, size_t *bad)
{
  size_t b = 0;
  for (size_t k = 0; k < n; k++)
    b += !isfinite(x[k]);
  *bad = b;
  return b == 0;
}

/* Whether p's audio window can be read now (into m->audio_buf, and the
 * noise before the strike into m->noise_buf when held: *n_noise), must be
 * waited for, or will not come (why). */
static af_audio_state audio_for(af_measured *m, const af_pending *p, size_t *n_noise, char *why,
                                size_t len)
{
  const af_stream *s = m->audio;
  const af_measure_config *mc = &m->mc->measure;
  const double stale_s = m->cfg->lane.stream_stale_after_s;
  const double t = now_s(m);
  /* The window is due delay + window after the strike; after that it gets
   * the stale time-out (a stream far behind, or stamps that disagree). */
  const bool timed_out = t - p->queued_ros_s > stale_s + mc->audio_delay_s + mc->audio_window_s;
  *n_noise = 0;
  if (!s->seen) {
    if (!timed_out)
      return AF_AUDIO_WAIT;
    af_text(why, len, "no audio chunk received (within %g s of the strike)",
            stale_s + mc->audio_delay_s + mc->audio_window_s);
    return AF_AUDIO_NONE;
  }
  if (af_stream_stale(s, t, stale_s)) {
    af_text(why, len, "audio stream stale (silent for more than %g s)", stale_s);
    return AF_AUDIO_NONE;
  }
  const int64_t delay_ns = (int64_t)llround(mc->audio_delay_s * 1e9);
  const double first = af_stream_index_at(s, p->start_ns + delay_ns);
  const size_t n = m->mc->audio_window_samples;
  if (first < -0.5) {
    af_text(why, len, "audio window starts %.4f s before the audio stream's first sample",
            -first / s->cfg->sample_rate_hz);
    return AF_AUDIO_NONE;
  }
  /* The first sample at or after the window's start. */
  const uint64_t i0 = first <= 0.0 ? 0 : (uint64_t)ceil(first - 1e-6);
  const uint64_t begin = af_ring_begin(s->ring), end = af_ring_end(s->ring);
  if (i0 + n > end) {
    if (!timed_out)
      return AF_AUDIO_WAIT;
    af_text(why, len,
            "audio window (samples %llu..%llu) not received within %g s of the strike (audio "
            "at sample %llu)",
            (unsigned long long)i0, (unsigned long long)(i0 + n), t - p->queued_ros_s,
            (unsigned long long)end);
    return AF_AUDIO_NONE;
  }
  if (i0 < begin) {
    af_text(why, len, "audio window (sample %llu) no longer in the %g s audio ring",
            (unsigned long long)i0, s->cfg->buffer_s);
    return AF_AUDIO_NONE;
  }
  size_t bad;
  if (af_ring_read(s->ring, i0, n, m->audio_buf) != AF_OK) {
    af_text(why, len, "audio window (samples %llu..%llu) could not be read from the ring",
            (unsigned long long)i0, (unsigned long long)(i0 + n));
    return AF_AUDIO_NONE;
  }
  if (!all_finite(m->audio_buf, n, &bad)) {
    af_text(why, len, "audio window holds %zu lost samples", bad);
    return AF_AUDIO_NONE;
  }
  /* The noise reference: the audio ending a guard before the contact, when held. */
  const size_t nn = m->mc->noise_window_samples;
  const double at = af_stream_index_at(s, p->start_ns) -
                    m->mc->measure.noise_guard_s * m->mc->measure.response.sample_rate_hz;
  if (nn > 0 && at >= (double)nn) {
    const uint64_t j1 = (uint64_t)floor(at), j0 = j1 - nn;
    if (j0 >= begin && j1 <= end && af_ring_read(s->ring, j0, nn, m->noise_buf) == AF_OK &&
        all_finite(m->noise_buf, nn, &bad))
      *n_noise = nn;
  }
  return AF_AUDIO_READY;
}

/* Measures the oldest pending strikes whose audio is decided, in order. */
static void process(af_measured *m, double entry_wall_s)
{
  char why[AF_TEXT_MAX];
  while (m->count > 0) {
    af_pending *p = &m->pending[m->head];
    size_t n_noise = 0;
    why[0] = '\0';
    af_audio_state a = audio_for(m, p, &n_noise, why, sizeof why);
    if (a == AF_AUDIO_WAIT)
      return;
    if (a == AF_AUDIO_READY)
      measure_one(m, p, m->audio_buf, m->mc->audio_window_samples, m->noise_buf, n_noise, NULL,
                  entry_wall_s);
    else
      measure_one(m, p, NULL, 0, NULL, 0, why, 0.0);
    m->head = (m->head + 1) % m->mc->pending_size;
    m->count--;
  }
}

/* The detector's callback: a strike, copied into the next pending slot. */
static void on_strike(const af_strike_event *ev, void *user)
{
  af_measured *m = user;
  const size_t size = m->mc->pending_size;
  if (m->count == size) {
    /* Full: the oldest goes now, with whatever audio there is. */
    af_pending *old = &m->pending[m->head];
    char why[AF_TEXT_MAX];
    m->overflows++;
    af_text(why, sizeof why, "strike queue full (%zu strikes waiting for audio)", size);
    if ((m->overflows & (m->overflows - 1)) == 0)
      af_ros_log(m->ros, AF_LOG_WARN, "%s: oldest measured without audio (%llu overflows so far)",
                 why, m->overflows);
    measure_one(m, old, NULL, 0, NULL, 0, why, 0.0);
    m->head = (m->head + 1) % size;
    m->count--;
  }
  af_pending *p = &m->pending[(m->head + m->count) % size];
  double *pulse = p->pulse;
  p->ev = *ev;
  size_t n = ev->n_samples;
  if (n > m->mc->pulse_capacity_samples) {
    n = m->mc->pulse_capacity_samples; /* cannot happen with the detector's span; counted */
    m->pulse_cut++;
  }
  if (n > 0)
    memcpy(pulse, ev->pulse_n, n * sizeof *pulse);
  p->ev.pulse_n = pulse;
  p->ev.n_samples = n;
  p->pulse = pulse;
  p->start_ns = af_stream_time_ns(m->force, ev->start_sample);
  memcpy(p->frame_id, m->force->frame_id, sizeof p->frame_id);
  p->queued_ros_s = now_s(m);
  m->count++;
}

void af_measured_force(af_measured *m, const af_signal_chunk *c, double entry_wall_s)
{
  af_status s = af_strike_write(m->detector, c->first_sample, c->data, c->n, on_strike, m);
  if (s != AF_OK)
    af_ros_log(m->ros, AF_LOG_WARN, "strike detector refused the force chunk at sample %llu: %s",
               (unsigned long long)c->first_sample, af_strerror(s));
  /* The audio may lead the force: what is complete goes now. */
  process(m, entry_wall_s);
}

void af_measured_audio(af_measured *m, double entry_wall_s)
{
  process(m, entry_wall_s);
}

void af_measured_poll(af_measured *m)
{
  process(m, 0.0);
}

/* --- diagnostics ---------------------------------------------------------------- */

static void diag_timing(af_diag_status *d, const char *key, const af_timing *t, const char *what)
{
  if (t->n == 0)
    af_diag_add(d, key, "none yet (%s)", what);
  else
    af_diag_add(d, key, "last %.3f, mean %.3f, max %.3f over %llu (%s)", t->last,
                t->sum / (double)t->n, t->max, (unsigned long long)t->n, what);
}

const char *af_measured_warning(af_measured *m)
{
  const char *w = NULL;
  if (!m)
    return NULL;
  if (m->overflows != m->seen_overflows)
    w = "strike queue overflowed since the last report";
  else if (m->no_audio != m->seen_no_audio)
    w = "strikes measured without audio since the last report";
  else if (m->no_apple != m->seen_no_apple)
    w = "strikes without an apple estimate since the last report";
  m->seen_overflows = m->overflows;
  m->seen_no_audio = m->no_audio;
  m->seen_no_apple = m->no_apple;
  return w;
}

void af_measured_diag(const af_measured *m, af_diag_status *d)
{
  if (!m)
    return;
  af_strike_tracker tr;
  af_strike_get_tracker(m->detector, &tr);
  af_diag_add(d, "strikes", "%llu", m->strikes);
  af_diag_add(d, "strike double hits", "%llu", m->double_hits);
  af_diag_add(d, "strikes clipped", "%llu (truncated %llu)", m->clipped, m->truncated);
  af_diag_add(d, "strike force samples lost", "%llu", m->lost_samples);
  af_diag_add(d, "strikes without resonance", "%llu", m->no_resonance);
  af_diag_add(d, "strikes without apple", "%llu", m->no_apple);
  af_diag_add(d, "strikes without audio", "%llu", m->no_audio);
  af_diag_add(d, "strikes unreliable", "%llu (measurement errors %llu)", m->unreliable,
              m->measure_errors);
  af_diag_add(d, "strike queue", "%zu pending of %zu", m->count, m->mc->pending_size);
  af_diag_add(d, "strike queue overflows", "%llu", m->overflows);
  af_diag_add(d, "strike detector", "%s, baseline %.4f N, noise %.4f N RMS, threshold %.4f N",
              tr.armed ? "armed" : "learning or waiting for quiet", tr.baseline_n, tr.noise_rms_n,
              tr.threshold_n);
  if (m->have_last) {
    af_diag_add(d, "last measured apple", "%u", m->last_apple_id);
    af_diag_add(d, "last measured resonance [Hz]", "%.2f (Q %.1f, SNR %.1f dB)",
                m->last_resonance_hz, m->last_q, m->last_snr_db);
    af_diag_add(d, "last measured modulus [Pa]", "%.4g from the resonance, %.4g fitted (e %.3f)",
                m->last_modulus_res_pa, m->last_fitted_pa, m->last_fitted_e);
  }
  af_diag_add(d, "last measured unreliable reason", "%s", m->last_reason);
  af_diag_add(d, "last strike without audio", "%s", m->last_no_audio);
  diag_timing(d, "strike report latency [ms]", &m->latency,
              "arrival of the chunk completing the audio window to the published report");
  diag_timing(d, "strike measure time [ms]", &m->measure_time, "af_measure_strike");
  if (m->pulse_cut > 0)
    af_diag_add(d, "strike pulses cut", "%llu (longer than the pending slot)", m->pulse_cut);
}

/* --- life cycle ------------------------------------------------------------------ */

af_status af_measured_create(af_ros *ros, const af_node_config *cfg, const af_stream *force,
                             const af_stream *audio, af_ros_pub *reliability_pub,
                             af_ros_pub *markers_pub, af_measured **out, const char **what)
{
  *out = NULL;
  *what = "the measured strikes";
  af_measured *m = calloc(1, sizeof *m);
  if (!m)
    return AF_ENOMEM;
  m->ros = ros;
  m->cfg = cfg;
  m->mc = &cfg->lane.measured;
  m->force = force;
  m->audio = audio;
  m->reliability_pub = reliability_pub;
  m->markers_pub = markers_pub;
  af_status s;
  *what = "the strike detector";
  if ((s = af_strike_create(&m->mc->strike, &m->detector)) != AF_OK)
    goto fail;
  *what = "the strike measurement";
  if ((s = af_measure_create(&m->mc->measure, &m->measure)) != AF_OK ||
      (s = af_measure_prepare(m->measure, &cfg->lane.model)) != AF_OK)
    goto fail;
  *what = "the strike queue";
  s = AF_ENOMEM;
  const size_t n = m->mc->pending_size, cap = m->mc->pulse_capacity_samples;
  m->pending = calloc(n, sizeof *m->pending);
  m->pulses = calloc(n * cap, sizeof *m->pulses);
  m->audio_buf = calloc(m->mc->audio_window_samples, sizeof *m->audio_buf);
  m->noise_buf = calloc(m->mc->noise_window_samples + 1, sizeof *m->noise_buf);
  if (!m->pending || !m->pulses || !m->audio_buf || !m->noise_buf)
    goto fail;
  for (size_t k = 0; k < n; k++)
    m->pending[k].pulse = m->pulses + k * cap;
  *what = "the strike_report publisher";
  if ((s = af_ros_advertise(ros, "strike_report", AF_MSG_STRIKE_REPORT, AF_OUTPUT_QUEUE, false,
                            &m->report_pub)) != AF_OK)
    goto fail;
  *out = m;
  return AF_OK;
fail:
  af_measured_destroy(m);
  return s;
}

void af_measured_destroy(af_measured *m)
{
  if (!m)
    return;
  af_strike_destroy(m->detector);
  af_measure_destroy(m->measure);
  free(m->pending);
  free(m->pulses);
  free(m->audio_buf);
  free(m->noise_buf);
  free(m); /* the publisher belongs to the af_ros */
}
