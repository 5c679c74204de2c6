/* test_lane.c — the lane (src/core/lane.h) without ROS: the apple a strike is
 * judged with (the bounded wait for its own estimate, a doubtful match and a
 * late estimate said), why a strike goes without audio, the full queue, and
 * the same figures whatever the chunking and the arrival order.
 *
 * Signals made here, not by the measurement's code: a half-sine force pulse
 * (40 N, 0.5 ms) on a 0.3 N offset with seeded Gaussian noise (0.02 N RMS)
 * at 50 kHz, and the microphone as one decaying sinusoid (682 Hz, Q 30, the
 * 0S2 of a 175 g, 8 MPa apple by PHYSICS.md 5) with noise 40 dB down at
 * 48 kHz. The lane is configured from the shipped YAML files. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "af_test.h"
#include "lane.h"
#include "settings.h"

#define FS_FORCE 50000.0
#define FS_AUDIO 48000.0
#define SPAN_S 3.0
#define MAX_STRIKES 8
#define PI 3.14159265358979323846

typedef struct {
  float *force, *audio;
  size_t n_force, n_audio;
} session;

typedef struct {
  size_t n;
  int64_t start_ns[MAX_STRIKES];
  uint32_t apple_id[MAX_STRIKES];
  bool with_audio[MAX_STRIKES];
  af_measure_report r[MAX_STRIKES];
  af_grade g[MAX_STRIKES]; /* the lane's grade of each */
} reports;

static void on_strike(const af_lane_strike *s, void *user)
{
  reports *out = user;
  if (out->n == MAX_STRIKES)
    return;
  out->start_ns[out->n] = s->start_ns;
  out->apple_id[out->n] = s->apple_id;
  out->with_audio[out->n] = s->with_audio;
  out->g[out->n] = s->grade;
  out->r[out->n++] = s->report;
}

static af_test_rng rng = {0}; /* test noise (af_test.h) */

/* Strikes at strikes_s[k] (contact start, seconds from the session start). */
static session make_session(const double *strikes_s, size_t n_strikes)
{
  session s;
  s.n_force = (size_t)(SPAN_S * FS_FORCE);
  s.n_audio = (size_t)(SPAN_S * FS_AUDIO);
  s.force = malloc(s.n_force * sizeof *s.force);
  s.audio = malloc(s.n_audio * sizeof *s.audio);
  rng.state = 20261122;
  for (size_t k = 0; k < s.n_force; k++) {
    double t = (double)k / FS_FORCE, x = 0.3 + 0.02 * af_test_gauss(&rng);
    for (size_t j = 0; j < n_strikes; j++) {
      double u = t - strikes_s[j];
      if (u > 0.0 && u < 0.5e-3)
        x += 40.0 * sin(PI * u / 0.5e-3);
    }
    s.force[k] = (float)x;
  }
  for (size_t k = 0; k < s.n_audio; k++) {
    double t = (double)k / FS_AUDIO, x = 0.01 * af_test_gauss(&rng);
    for (size_t j = 0; j < n_strikes; j++) {
      double u = t - strikes_s[j];
      if (u >= 0.0)
        x += exp(-PI * 682.0 / 30.0 * u) * sin(2.0 * PI * 682.0 * u);
    }
    s.audio[k] = (float)x;
  }
  return s;
}

static void free_session(session *s)
{
  free(s->force);
  free(s->audio);
}

static af_lane_config config(const char *const *sets, size_t n_sets)
{
  af_settings st;
  af_lane_config cfg;
  char err[512] = "";
  af_settings_reset(&st);
  int ok = af_settings_load_yaml(&st, "config/station.yaml", err, sizeof err) == AF_OK &&
           af_settings_load_yaml(&st, "config/jonagold.yaml", err, sizeof err) == AF_OK &&
           af_settings_set_arg(&st, "hammer_mass_kg=0.010", err, sizeof err) == AF_OK &&
           af_settings_set_arg(&st, "hammer_tip_radius_m=0", err, sizeof err) == AF_OK;
  for (size_t k = 0; ok && k < n_sets; k++)
    ok = af_settings_set_arg(&st, sets[k], err, sizeof err) == AF_OK;
  ok = ok && af_lane_config_derive(&st, &cfg, err, sizeof err) == AF_OK;
  if (!ok) {
    fprintf(stderr, "config: %s\n", err);
    exit(1);
  }
  return cfg;
}

static af_apple apple(uint32_t id, double stamp_s)
{
  af_apple a;
  memset(&a, 0, sizeof a);
  a.apple_id = id;
  a.stamp_ns = (int64_t)llround(stamp_s * 1e9);
  a.mass_kg = 0.175;
  a.equatorial_radius_m = 0.0370; /* a sphere of 175 g at 840 kg/m3 */
  a.strike_radius_m = 0.040;
  a.confidence = 1.0;
  return a;
}

/* Force chunks starting in [drop_from_s, drop_to_s) are lost on the way
 * (never given to the lane): a dropped chunk's strike. */
static double drop_from_s = -1.0, drop_to_s = -1.0;

/* An apple to push once the session time reaches at_s. */
typedef struct {
  af_apple a;
  double at_s;
  bool done;
} scheduled_apple;

/* Feeds s up to until_s in chunks of n_force / n_audio samples, audio first
 * when audio_first; apples when their time comes; the lane's clock is the end
 * of the latest chunk. */
static void feed(af_lane *l, const session *s, size_t n_force, size_t n_audio, bool audio_first,
                 scheduled_apple *apples, size_t n_apples, double until_s)
{
  size_t kf = 0, ka = 0;
  const size_t end_f = (size_t)(until_s * FS_FORCE), end_a = (size_t)(until_s * FS_AUDIO);
  while (kf < end_f || ka < end_a) {
    double tf = (double)kf / FS_FORCE, ta = (double)ka / FS_AUDIO;
    const bool force_left = kf < end_f, audio_left = ka < end_a;
    const bool take_force = force_left && (!audio_left || (audio_first ? tf < ta : tf <= ta));
    double t = take_force ? tf : ta;
    for (size_t j = 0; j < n_apples; j++)
      if (!apples[j].done && apples[j].at_s <= t) {
        (void)af_lane_apple(l, &apples[j].a, (int64_t)llround(t * 1e9), NULL);
        apples[j].done = true;
      }
    size_t *k = take_force ? &kf : &ka;
    size_t step = take_force ? n_force : n_audio, end = take_force ? end_f : end_a;
    size_t n = end - *k < step ? end - *k : step;
    if (take_force && t >= drop_from_s && t < drop_to_s) {
      *k += n;
      continue;
    }
    double rate = take_force ? FS_FORCE : FS_AUDIO;
    af_chunk c = {(int64_t)llround((double)*k / rate * 1e9),
                  *k,
                  rate,
                  take_force ? "N" : "Pa",
                  take_force ? "force_transducer" : "microphone",
                  (take_force ? s->force : s->audio) + *k,
                  n};
    int64_t now = (int64_t)llround((double)(*k + n) / rate * 1e9);
    af_chunk_verdict v =
        take_force ? af_lane_force(l, &c, now, NULL) : af_lane_audio(l, &c, now, NULL);
    AF_CHECK(v == AF_CHUNK_OK);
    *k += n;
  }
}

static af_lane *make_lane(const af_lane_config *cfg, reports *out)
{
  af_lane *l = NULL;
  const char *what = "";
  memset(out, 0, sizeof *out);
  if (af_lane_create(cfg, on_strike, out, &l, &what) != AF_OK) {
    fprintf(stderr, "af_lane_create: %s\n", what);
    exit(1);
  }
  return l;
}

/* A strike whose estimate arrives late (but within apple_wait_s) is judged
 * with that estimate, not the previous apple's. */
static void test_waits_for_its_own_apple(void)
{
  const double strikes[] = {0.5, 1.5};
  session s = make_session(strikes, 2);
  const char *sets[] = {"grade_quantity=stiffness_factor", "grade_classes=lo | 1e5 | hi"};
  af_lane_config cfg = config(sets, 2);
  reports out;
  af_lane *l = make_lane(&cfg, &out);
  /* Apple 2 is stamped 1.3 s (before its strike at 1.5 s) but arrives at
   * 1.8 s of the session, 0.3 s after the strike: within the 0.5 s wait. */
  scheduled_apple ap[] = {{apple(1, 0.3), 0.3, false}, {apple(2, 1.3), 1.8, false}};
  feed(l, &s, 1024, 1024, false, ap, 2, SPAN_S);
  af_lane_finish(l);
  AF_CHECK(out.n == 2);
  AF_CHECK(out.apple_id[0] == 1 && out.apple_id[1] == 2);
  AF_CHECK(!(out.r[1].verdict.flags & AF_VERDICT_APPLE_DOUBTFUL));
  AF_CHECK(af_lane_get_stats(l)->late_apples == 0);
  /* The lane grades each strike: a reliable one by its stiffness factor against the
   * boundary 1e5 given here (the class above on the boundary). */
  for (size_t k = 0; k < out.n; k++) {
    const unsigned want = !out.r[k].reliable ? 0 : out.r[k].stiffness_factor < 1e5 ? 1 : 2;
    AF_CHECK(out.g[k].index == want);
    AF_CHECK(strcmp(out.g[k].name, want == 0 ? "ungraded" : want == 1 ? "lo" : "hi") == 0);
    AF_CHECK(out.r[k].reliable == (out.g[k].reason[0] == '\0'));
  }
  printf("own apple after a 0.3 s late estimate: strikes on apples %u, %u, grades %s, %s\n",
         out.apple_id[0], out.apple_id[1], out.g[0].name, out.g[1].name);
  af_lane_destroy(l);
  free_session(&s);
}

/* An estimate later than apple_wait_s: the strike goes with the previous
 * apple, flagged doubtful in its reason, and the late estimate is counted. */
static void test_doubtful_and_late(void)
{
  const double strikes[] = {0.5, 1.2};
  session s = make_session(strikes, 2);
  const char *sets[] = {"apple_wait_s=0.1"};
  af_lane_config cfg = config(sets, 1);
  reports out;
  af_lane *l = make_lane(&cfg, &out);
  scheduled_apple ap[] = {{apple(1, 0.3), 0.3, false}, {apple(2, 1.0), 2.2, false}};
  feed(l, &s, 1024, 1024, false, ap, 2, SPAN_S);
  af_lane_finish(l);
  AF_CHECK(out.n == 2);
  AF_CHECK(out.apple_id[1] == 1);
  AF_CHECK(out.r[1].verdict.flags & AF_VERDICT_APPLE_DOUBTFUL);
  AF_CHECK(!out.r[1].reliable);
  AF_CHECK(strstr(out.r[1].reason, "doubtful apple match (apple 1: already struck") != NULL);
  AF_CHECK(af_lane_get_stats(l)->late_apples == 1);
  AF_CHECK(af_lane_get_stats(l)->doubtful == 1);
  /* Graded after the lane's own flags: the doubtful match alone leaves it ungraded. */
  AF_CHECK(out.g[1].index == 0 && strcmp(out.g[1].name, "ungraded") == 0);
  AF_CHECK(strncmp(out.g[1].reason, "not reliable: ", 14) == 0 &&
           strstr(out.g[1].reason, "doubtful apple match") != NULL);
  printf("doubtful: %s\nlate: %s\n", out.r[1].reason, af_lane_get_stats(l)->last_late_apple);
  af_lane_destroy(l);
  free_session(&s);
}

/* A strike lost with dropped force chunks leaves its apple without a strike;
 * when the next apple's estimate is late, the next strike is matched to that
 * apple: flagged doubtful, never silent (issue 11: 80x replays). */
static void test_doubtful_after_lost_samples(void)
{
  const double strikes[] = {0.5, 1.2};
  session s = make_session(strikes, 2);
  const char *sets[] = {"apple_wait_s=0.1"};
  af_lane_config cfg = config(sets, 1);
  reports out;
  af_lane *l = make_lane(&cfg, &out);
  scheduled_apple ap[] = {{apple(1, 0.3), 0.3, false}, {apple(2, 1.0), 2.2, false}};
  drop_from_s = 0.45;
  drop_to_s = 0.6;
  feed(l, &s, 1024, 1024, false, ap, 2, SPAN_S);
  drop_from_s = drop_to_s = -1.0;
  af_lane_finish(l);
  AF_CHECK(out.n == 1);
  AF_CHECK(out.apple_id[0] == 1);
  AF_CHECK(out.r[0].verdict.flags & AF_VERDICT_APPLE_DOUBTFUL);
  AF_CHECK(!out.r[0].reliable);
  AF_CHECK(strstr(out.r[0].reason, "force samples were lost") != NULL);
  AF_CHECK(af_lane_get_stats(l)->doubtful == 1);
  /* Graded after the lane's own flags: the doubtful match alone leaves it ungraded. */
  AF_CHECK(out.g[0].index == 0 && strcmp(out.g[0].name, "ungraded") == 0);
  AF_CHECK(strncmp(out.g[0].reason, "not reliable: ", 14) == 0 &&
           strstr(out.g[0].reason, "doubtful apple match") != NULL);
  printf("doubtful after lost samples: %s\n", out.r[0].reason);
  af_lane_destroy(l);
  free_session(&s);
}

/* Two late estimates in a row: strike 2 goes to apple 1 (already struck:
 * doubtful), then strike 3 to apple 2, which has no strike of its own yet
 * but whose estimate came after its strike had gone to apple 1: doubtful
 * too, never a silent match one apple behind (issue 11). */
static void test_doubtful_chain(void)
{
  const double strikes[] = {0.5, 1.2, 1.9};
  session s = make_session(strikes, 3);
  const char *sets[] = {"apple_wait_s=0.1"};
  af_lane_config cfg = config(sets, 1);
  reports out;
  af_lane *l = make_lane(&cfg, &out);
  scheduled_apple ap[] = {
      {apple(1, 0.3), 0.3, false}, {apple(2, 1.0), 1.5, false}, {apple(3, 1.7), 2.5, false}};
  feed(l, &s, 1024, 1024, false, ap, 3, SPAN_S);
  af_lane_finish(l);
  AF_CHECK(out.n == 3);
  AF_CHECK(out.apple_id[1] == 1 && out.apple_id[2] == 2);
  AF_CHECK(out.r[1].verdict.flags & AF_VERDICT_APPLE_DOUBTFUL);
  AF_CHECK(out.r[2].verdict.flags & AF_VERDICT_APPLE_DOUBTFUL);
  AF_CHECK(strstr(out.r[2].reason, "its estimate came after its own strike was judged against "
                                   "apple 1") != NULL);
  AF_CHECK(af_lane_get_stats(l)->late_apples == 2 && af_lane_get_stats(l)->doubtful == 2);
  printf("doubtful chain: %s\n", out.r[2].reason);
  af_lane_destroy(l);
  free_session(&s);
}

/* No estimate at all: the flag, its words, and no model-dependent figure. */
static void test_no_apple(void)
{
  const double strikes[] = {0.5};
  session s = make_session(strikes, 1);
  af_lane_config cfg = config(NULL, 0);
  reports out;
  af_lane *l = make_lane(&cfg, &out);
  feed(l, &s, 1024, 1024, false, NULL, 0, SPAN_S);
  af_lane_finish(l);
  AF_CHECK(out.n == 1 && out.apple_id[0] == 0);
  AF_CHECK(out.r[0].verdict.flags & AF_VERDICT_NO_APPLE);
  AF_CHECK(strstr(out.r[0].reason, "no apple estimate within 1 s before the strike") != NULL);
  AF_CHECK(isnan(out.r[0].resonance_hz) && isfinite(out.r[0].peak_force_n));
  AF_CHECK(fabs(out.r[0].peak_force_n - 40.0) < 0.4); /* 1 % */
  af_lane_destroy(l);
  free_session(&s);
}

/* The same session fed in other chunk sizes and with the audio leading: the
 * same figures, bit for bit (the windows are cut by sample index). */
static void test_chunking_and_order(void)
{
  const double strikes[] = {0.5, 1.5};
  session s = make_session(strikes, 2);
  af_lane_config cfg = config(NULL, 0);
  reports a, b;
  af_lane *la = make_lane(&cfg, &a), *lb = make_lane(&cfg, &b);
  scheduled_apple pa[] = {{apple(1, 0.3), 0.3, false}, {apple(2, 1.3), 1.3, false}};
  scheduled_apple pb[] = {{apple(1, 0.3), 0.3, false}, {apple(2, 1.3), 1.3, false}};
  feed(la, &s, 1024, 1024, false, pa, 2, SPAN_S);
  feed(lb, &s, 333, 4000, true, pb, 2, SPAN_S);
  af_lane_finish(la);
  af_lane_finish(lb);
  AF_CHECK(a.n == 2 && b.n == 2);
  for (size_t k = 0; k < 2 && k < a.n && k < b.n; k++) {
    const af_measure_report *x = &a.r[k], *y = &b.r[k];
    AF_CHECK(a.start_ns[k] == b.start_ns[k] && a.apple_id[k] == b.apple_id[k]);
    AF_CHECK(a.with_audio[k] && b.with_audio[k]);
    AF_CHECK(memcmp(&x->contact_time_s, &y->contact_time_s, sizeof(double)) == 0);
    AF_CHECK(memcmp(&x->resonance_hz, &y->resonance_hz, sizeof(double)) == 0);
    AF_CHECK(memcmp(&x->snr_db, &y->snr_db, sizeof(double)) == 0);
    AF_CHECK(x->verdict.flags == y->verdict.flags && strcmp(x->reason, y->reason) == 0);
    AF_CHECK(fabs(x->resonance_hz - 682.0) < 0.005 * 682.0);
  }
  printf("chunking: 0S2 %.3f Hz and %.3f Hz either way\n", a.r[0].resonance_hz,
         a.r[1].resonance_hz);
  af_lane_destroy(la);
  af_lane_destroy(lb);
  free_session(&s);
}

/* No audio: live, after the time-out (no audio chunk received), and a full
 * queue (the oldest strike goes at once). */
static void test_without_audio(void)
{
  const double strikes[] = {0.5, 0.6};
  session s = make_session(strikes, 2);
  af_lane_config cfg = config(NULL, 0);
  reports out;
  scheduled_apple ap[] = {{apple(1, 0.3), 0.3, false}};
  /* Force only: after stream_stale_after_s + delay + window the strikes go. */
  af_lane *l = make_lane(&cfg, &out);
  size_t kf = 0;
  while (kf < s.n_force) {
    size_t n = s.n_force - kf < 1024 ? s.n_force - kf : 1024;
    af_chunk c = {
        (int64_t)llround((double)kf / FS_FORCE * 1e9), kf, FS_FORCE, "N", "f", s.force + kf, n};
    if (!ap[0].done && (double)kf / FS_FORCE >= 0.3) {
      (void)af_lane_apple(l, &ap[0].a, c.stamp_ns, NULL);
      ap[0].done = true;
    }
    af_lane_force(l, &c, (int64_t)llround((double)(kf + n) / FS_FORCE * 1e9), NULL);
    kf += n;
  }
  AF_CHECK(out.n == 2);
  AF_CHECK(out.r[0].verdict.flags & AF_VERDICT_NO_AUDIO);
  AF_CHECK(out.r[0].verdict.audio_cause == AF_AUDIO_NONE_RECEIVED);
  AF_CHECK(strstr(out.r[0].reason, "no audio (no audio chunk received within") != NULL);
  printf("live, no audio: %s\n", out.r[0].reason);
  af_lane_destroy(l);

  /* A queue of one: the first strike is measured when the second comes. */
  const char *sets[] = {"strike_pending_size=1"};
  cfg = config(sets, 1);
  l = make_lane(&cfg, &out);
  ap[0].done = false;
  feed(l, &s, 1024, 1024, false, ap, 1, 0.7);
  AF_CHECK(out.n >= 1);
  AF_CHECK(out.r[0].verdict.audio_cause == AF_AUDIO_QUEUE_FULL);
  AF_CHECK(af_lane_get_stats(l)->overflows == 1);
  printf("queue full: %s\n", out.r[0].reason);
  af_lane_finish(l);
  AF_CHECK(out.n == 2 && out.with_audio[1]);
  af_lane_destroy(l);
  free_session(&s);
}

int main(void)
{
  test_waits_for_its_own_apple();
  test_doubtful_and_late();
  test_doubtful_after_lost_samples();
  test_doubtful_chain();
  test_no_apple();
  test_chunking_and_order();
  test_without_audio();
  return af_test_summary("test_lane");
}
