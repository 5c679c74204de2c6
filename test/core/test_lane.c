/* test_lane.c — the lane (src/core/lane/lane.h) without ROS: the apple a strike is
 * judged with (the bounded wait for its own estimate, the match by the
 * conveyor's transit with apples in flight, a camera stamping late, a late
 * or implausible estimate said), why a strike goes without audio, the full queue, and
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
#define SPAN_S 4.0
#define MAX_STRIKES 16
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

/* An estimate later than apple_wait_s: the strike goes without an apple,
 * never with the previous apple's (the newest estimate before it), and the
 * late estimate is counted with the strike it missed. */
static void test_late_estimate(void)
{
  const double strikes[] = {0.5, 1.2};
  session s = make_session(strikes, 2);
  const char *sets[] = {"apple_wait_s=0.1"};
  af_lane_config cfg = config(sets, 1);
  reports out;
  af_lane *l = make_lane(&cfg, &out);
  scheduled_apple ap[] = {{apple(1, 0.3), 0.3, false}, {apple(2, 1.0), 1.6, false}};
  feed(l, &s, 1024, 1024, false, ap, 2, SPAN_S);
  af_lane_finish(l);
  AF_CHECK(out.n == 2);
  AF_CHECK(out.apple_id[0] == 1 && out.apple_id[1] == 0);
  AF_CHECK(out.r[1].verdict.flags & AF_VERDICT_NO_APPLE);
  AF_CHECK(!out.r[1].reliable);
  /* Apple 1 is stamped 1.2 - 0.3 = 0.9 s before the strike. */
  AF_CHECK(strstr(out.r[1].reason, "no apple estimate stamped 0.2 +- 0.04 s before the strike "
                                   "(the nearest, apple 1, is stamped 0.900 s before it)") != NULL);
  AF_CHECK(af_lane_get_stats(l)->late_apples == 1);
  AF_CHECK(strstr(af_lane_get_stats(l)->last_late_apple,
                  "apple 2's estimate arrived after its strike at 1.200 s was reported without an "
                  "apple") != NULL);
  AF_CHECK(af_lane_get_stats(l)->doubtful == 0);
  AF_CHECK(out.g[1].index == 0 && strcmp(out.g[1].name, "ungraded") == 0);
  printf("late: %s\n      %s\n", out.r[1].reason, af_lane_get_stats(l)->last_late_apple);
  af_lane_destroy(l);
  free_session(&s);
}

/* A strike lost with dropped force chunks leaves its apple without a strike;
 * the next strike, whose own estimate is late, never takes that apple. */
static void test_lost_strike_and_late_estimate(void)
{
  const double strikes[] = {0.5, 1.2};
  session s = make_session(strikes, 2);
  const char *sets[] = {"apple_wait_s=0.1"};
  af_lane_config cfg = config(sets, 1);
  reports out;
  af_lane *l = make_lane(&cfg, &out);
  scheduled_apple ap[] = {{apple(1, 0.3), 0.3, false}, {apple(2, 1.0), 1.6, false}};
  drop_from_s = 0.45;
  drop_to_s = 0.6;
  feed(l, &s, 1024, 1024, false, ap, 2, SPAN_S);
  drop_from_s = drop_to_s = -1.0;
  af_lane_finish(l);
  AF_CHECK(out.n == 1);
  AF_CHECK(out.apple_id[0] == 0 && (out.r[0].verdict.flags & AF_VERDICT_NO_APPLE));
  AF_CHECK(!out.r[0].reliable && out.g[0].index == 0);
  printf("lost strike, late estimate: %s\n", out.r[0].reason);
  af_lane_destroy(l);
  free_session(&s);
}

/* A line at 10 strikes/s with the camera 0.2 s upstream: two apples between
 * the camera and the hammer at every strike, so the newest estimate before a
 * strike is the apple two places later. Each strike must go to its own
 * apple, and the observed transit be the one configured. */
static void test_apples_in_flight(void)
{
  double strikes[12];
  scheduled_apple ap[12];
  for (size_t k = 0; k < 12; k++) {
    strikes[k] = 0.5 + 0.1 * (double)k + 1e-4 * (double)(k % 3); /* 0.1 s apart */
    ap[k] = (scheduled_apple){apple((uint32_t)(k + 1), strikes[k] - 0.2), strikes[k] - 0.2, false};
  }
  session s = make_session(strikes, 12);
  af_lane_config cfg = config(NULL, 0);
  reports out;
  af_lane *l = make_lane(&cfg, &out);
  feed(l, &s, 1024, 1024, false, ap, 12, SPAN_S);
  af_lane_finish(l);
  AF_CHECK(out.n == 12);
  size_t own = 0;
  for (size_t k = 0; k < out.n; k++) {
    own += out.apple_id[k] == k + 1;
    AF_CHECK(!(out.r[k].verdict.flags & (AF_VERDICT_NO_APPLE | AF_VERDICT_APPLE_DOUBTFUL)));
  }
  AF_CHECK(own == 12);
  const af_lane_stats *st = af_lane_get_stats(l);
  AF_CHECK(st->transit_strikes == 12 && fabs(st->transit_observed_s - 0.2) < 2e-4);
  AF_CHECK(st->transit_warning[0] == '\0');
  printf("in flight: %zu of 12 strikes on their own apple, transit %.4f s\n", own,
         st->transit_observed_s);
  af_lane_destroy(l);
  free_session(&s);
}

/* A camera that stamps at publish time: each estimate stamped 50 ms after
 * its own strike, strikes 0.4 s apart. The apple before is then stamped
 * 0.35 s before the strike, outside 0.2 +- 0.04 s: each strike goes without
 * an apple, never to another's, and the lag is named. */
static void test_camera_stamps_late(void)
{
  double strikes[8];
  scheduled_apple ap[8];
  for (size_t k = 0; k < 8; k++) {
    strikes[k] = 0.5 + 0.4 * (double)k;
    ap[k] =
        (scheduled_apple){apple((uint32_t)(k + 1), strikes[k] + 0.05), strikes[k] + 0.06, false};
  }
  session s = make_session(strikes, 8);
  af_lane_config cfg = config(NULL, 0);
  reports out;
  af_lane *l = make_lane(&cfg, &out);
  feed(l, &s, 1024, 1024, false, ap, 8, SPAN_S);
  af_lane_finish(l);
  AF_CHECK(out.n == 8);
  size_t wrong = 0;
  for (size_t k = 0; k < out.n; k++)
    wrong += out.apple_id[k] != 0 && out.apple_id[k] != k + 1 && out.r[k].reliable;
  AF_CHECK(wrong == 0);
  AF_CHECK(out.apple_id[7] == 0 && strstr(out.r[7].reason, "(the nearest, apple 8, is stamped "
                                                           "0.050 s after it)") != NULL);
  const af_lane_stats *st = af_lane_get_stats(l);
  AF_CHECK(fabs(st->unmatched_lag_s + 0.05) < 1e-4);
  AF_CHECK(strstr(st->transit_warning, "stamped 50 ms after their strikes: is the camera "
                                       "stamping at publish time?") != NULL);
  printf("camera late: %zu reliable under another id; %s\n", wrong, st->transit_warning);
  af_lane_destroy(l);
  free_session(&s);
}

/* Estimates lost on the way (a subscriber queue that overflowed): ids 1..12
 * without 10 and 11 are counted once the ids count up; ids that do not
 * count up by one (a tracker's) are never judged. */
static void test_skipped_ids(void)
{
  const double strikes[] = {3.5};
  session s = make_session(strikes, 1);
  af_lane_config cfg = config(NULL, 0);
  reports out;
  af_lane *l = make_lane(&cfg, &out);
  for (uint32_t id = 1; id <= 12; id++)
    if (id != 10 && id != 11) {
      af_apple a = apple(id, 0.1 * id);
      (void)af_lane_apple(l, &a, (int64_t)llround(0.1 * id * 1e9), NULL);
    }
  const af_lane_stats *st = af_lane_get_stats(l);
  AF_CHECK(st->apples_skipped == 2);
  AF_CHECK(strstr(st->last_apples_skipped, "apple estimates 10..11 never came (apple 12 followed "
                                           "apple 9)") != NULL);
  printf("skipped: %s\n", st->last_apples_skipped);
  af_lane_destroy(l);
  l = make_lane(&cfg, &out);
  const uint32_t tracker[] = {17, 45, 46, 90, 203, 204, 511, 600, 601, 950, 1200};
  for (size_t k = 0; k < sizeof tracker / sizeof tracker[0]; k++) {
    af_apple a = apple(tracker[k], 0.1 * (double)(k + 1));
    (void)af_lane_apple(l, &a, (int64_t)llround(0.1 * (double)(k + 1) * 1e9), NULL);
  }
  AF_CHECK(af_lane_get_stats(l)->apples_skipped == 0);
  af_lane_destroy(l);
  free_session(&s);
}

/* Estimates no match may use: stamped 4294967295 s (a clock far off), and
 * apple_id 0 (the report's "no apple"). Both refused and counted; the
 * strikes after them still wait for, and take, their own estimates. */
static void test_implausible_estimates(void)
{
  const double strikes[] = {0.5, 1.5};
  session s = make_session(strikes, 2);
  af_lane_config cfg = config(NULL, 0);
  reports out;
  af_lane *l = make_lane(&cfg, &out);
  af_apple far = apple(7, 4294967295.0), zero = apple(0, 0.3);
  scheduled_apple ap[] = {
      {apple(1, 0.3), 0.3, false},
      {far, 0.35, false},
      {zero, 0.36, false},
      {apple(2, 1.3), 1.75, false}}; /* 0.25 s after its strike: within apple_wait_s */
  feed(l, &s, 1024, 1024, false, ap, 4, SPAN_S);
  af_lane_finish(l);
  const af_lane_stats *st = af_lane_get_stats(l);
  AF_CHECK(st->apples_implausible == 2 && st->apples_refused == 2);
  AF_CHECK(strstr(st->last_implausible_apple, "apple 0 refused: apple_id 0 is reserved") != NULL);
  AF_CHECK(out.n == 2 && out.apple_id[0] == 1 && out.apple_id[1] == 2);
  AF_CHECK(!(out.r[1].verdict.flags & (AF_VERDICT_NO_APPLE | AF_VERDICT_APPLE_DOUBTFUL)));
  /* The far one before any data: nothing to judge its clock by, so taken
   * (its prediction stands), but it decides no strike's wait. */
  reports out3;
  af_lane *l3 = make_lane(&cfg, &out3);
  scheduled_apple ap3[] = {
      {far, 0.0, false}, {apple(1, 0.3), 0.3, false}, {apple(2, 1.3), 1.75, false}};
  feed(l3, &s, 1024, 1024, false, ap3, 3, SPAN_S);
  af_lane_finish(l3);
  AF_CHECK(out3.n == 2 && out3.apple_id[0] == 1 && out3.apple_id[1] == 2);
  AF_CHECK(!(out3.r[1].verdict.flags & (AF_VERDICT_NO_APPLE | AF_VERDICT_APPLE_DOUBTFUL)));
  af_lane_destroy(l3);
  /* Refused, with the words of the far one. */
  reports out2;
  af_lane *l2 = make_lane(&cfg, &out2);
  const af_prediction *pr = NULL;
  af_chunk c = {0, 0, FS_FORCE, "N", "f", s.force, 1024};
  AF_CHECK(af_lane_force(l2, &c, 20480000, NULL) == AF_CHUNK_OK);
  const af_status far_status = af_lane_apple(l2, &far, 20480000, &pr);
  AF_CHECK(far_status == AF_EINVAL && pr != NULL);
  if (pr != NULL) {
    AF_CHECK(!pr->valid);
    AF_CHECK(strstr(pr->why, "stamped 4294967294.98") != NULL &&
             strstr(pr->why, "after the newest force sample (apple_stale_after_s 1 s)") != NULL);
    printf("implausible: %s\n", pr->why);
  }
  af_lane_destroy(l2);
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
  AF_CHECK(strstr(out.r[0].reason, "no apple estimate stamped 0.2 +- 0.04 s before the strike") !=
           NULL);
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

/* af_lane_reset: a lane that has run one session (apples, strikes, one
 * still queued when it stops) and is reset judges the next exactly as a new
 * lane does, bit for bit; the next stream's first chunk, at index 0, is no
 * restart, and the strike left queued is dropped, not reported. */
static void test_reset_is_new(void)
{
  const double strikes[] = {0.5, 1.5};
  session s = make_session(strikes, 2);
  af_lane_config cfg = config(NULL, 0);
  reports a, b;
  af_lane *la = make_lane(&cfg, &a), *lb = make_lane(&cfg, &b);
  scheduled_apple before[] = {{apple(41, 0.3), 0.3, false}, {apple(47, 1.3), 1.3, false}};
  feed(lb, &s, 512, 2048, true, before, 2, 1.52); /* stops with the second strike queued */
  AF_CHECK(b.n == 1 && af_lane_pending(lb) == 1);
  af_lane_reset(lb);
  memset(&b, 0, sizeof b);
  AF_CHECK(af_lane_pending(lb) == 0 && af_lane_get_stats(lb)->strikes == 0);
  scheduled_apple pa[] = {{apple(1, 0.3), 0.3, false}, {apple(2, 1.3), 1.3, false}};
  scheduled_apple pb[] = {{apple(1, 0.3), 0.3, false}, {apple(2, 1.3), 1.3, false}};
  feed(la, &s, 1024, 1024, false, pa, 2, SPAN_S);
  feed(lb, &s, 1024, 1024, false, pb, 2, SPAN_S);
  af_lane_finish(la);
  af_lane_finish(lb);
  AF_CHECK(a.n == 2 && b.n == 2);
  for (size_t k = 0; k < 2 && k < a.n && k < b.n; k++) {
    const af_measure_report *x = &a.r[k], *y = &b.r[k];
    AF_CHECK(a.start_ns[k] == b.start_ns[k] && a.apple_id[k] == b.apple_id[k]);
    AF_CHECK(a.with_audio[k] == b.with_audio[k]);
    AF_CHECK(memcmp(&x->contact_time_s, &y->contact_time_s, sizeof(double)) == 0);
    AF_CHECK(memcmp(&x->resonance_hz, &y->resonance_hz, sizeof(double)) == 0);
    AF_CHECK(memcmp(&x->fitted_modulus_pa, &y->fitted_modulus_pa, sizeof(double)) == 0);
    AF_CHECK(x->verdict.flags == y->verdict.flags && strcmp(x->reason, y->reason) == 0);
  }
  const af_lane_stats *sa = af_lane_get_stats(la), *sb = af_lane_get_stats(lb);
  AF_CHECK(sa->strikes == sb->strikes && sa->apples == sb->apples);
  AF_CHECK(sa->late_apples == sb->late_apples && sa->doubtful == sb->doubtful);
  AF_CHECK(sa->health.strikes == sb->health.strikes);
  AF_CHECK(memcmp(&sa->transit_observed_s, &sb->transit_observed_s, sizeof(double)) == 0);
  AF_CHECK(af_lane_factor(la)->applied == af_lane_factor(lb)->applied);
  AF_CHECK(af_lane_force_stream(lb)->restarts == 0 && af_lane_audio_stream(lb)->restarts == 0);
  AF_CHECK(af_lane_force_stream(lb)->chunks == af_lane_force_stream(la)->chunks);
  af_lane_destroy(la);
  af_lane_destroy(lb);
  free_session(&s);
}

/* An empty chunk (no samples, no data: x NULL) is accepted by either
 * stream, the node's lane and a tap-only one alike, and changes nothing; the
 * tap-only lane once offset NULL by 0 (undefined: UBSan in the sanitizer
 * build, found by fuzz_lane, test/fuzz/lane/regress_empty_audio_chunk_tap_only). */
static void test_empty_chunks(void)
{
  const char *tap[] = {"tap_only=true"};
  for (int k = 0; k < 2; k++) {
    af_lane_config cfg = config(tap, (size_t)k);
    reports out;
    af_lane *l = make_lane(&cfg, &out);
    const af_chunk f = {0, 0, FS_FORCE, "N", "f", NULL, 0};
    const af_chunk a = {0, 0, FS_AUDIO, "Pa", "m", NULL, 0};
    AF_CHECK(af_lane_audio(l, &a, 0, NULL) == AF_CHUNK_OK);
    AF_CHECK(af_lane_force(l, &f, 0, NULL) == AF_CHUNK_OK);
    af_lane_finish(l);
    AF_CHECK(out.n == 0 && af_lane_audio_stream(l)->chunks == 1);
    af_lane_destroy(l);
  }
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

/* The force stream stalls 0.2 ms into a contact while the audio goes on: the
 * strike is reported, truncated, once the force has been silent
 * stream_stale_after_s (1 s), not held until force data comes back. */
static void test_force_stall(void)
{
  const double strikes[] = {0.5};
  session s = make_session(strikes, 1);
  af_lane_config cfg = config(NULL, 0);
  reports out;
  af_lane *l = make_lane(&cfg, &out);
  const size_t stop = (size_t)((0.5 + 0.2e-3) * FS_FORCE); /* force samples sent */
  size_t kf = 0, ka = 0;
  scheduled_apple ap[] = {{apple(1, 0.3), 0.3, false}};
  while (ka < s.n_audio) {
    const double t = (double)ka / FS_AUDIO;
    if (!ap[0].done && t >= 0.3) {
      (void)af_lane_apple(l, &ap[0].a, (int64_t)llround(t * 1e9), NULL);
      ap[0].done = true;
    }
    while (kf < stop && (double)kf / FS_FORCE <= t) {
      const size_t n = stop - kf < 64 ? stop - kf : 64;
      af_chunk c = {
          (int64_t)llround((double)kf / FS_FORCE * 1e9), kf, FS_FORCE, "N", "f", s.force + kf, n};
      AF_CHECK(af_lane_force(l, &c, (int64_t)llround((double)(kf + n) / FS_FORCE * 1e9), NULL) ==
               AF_CHUNK_OK);
      kf += n;
    }
    af_chunk c = {(int64_t)llround(t * 1e9), ka, FS_AUDIO, "Pa", "m", s.audio + ka, 1024};
    const int64_t now = (int64_t)llround((double)(ka + 1024) / FS_AUDIO * 1e9);
    AF_CHECK(af_lane_audio(l, &c, now, NULL) == AF_CHUNK_OK);
    ka += 1024;
    if (now < (int64_t)1400000000) /* not before the force is 1 s silent (at 1.5 s) */
      AF_CHECK(out.n == 0);
    if (now > (int64_t)2300000000) /* + apple_wait_s, the wait for its own estimate */
      break;
  }
  AF_CHECK(out.n == 1 && (out.r[0].verdict.flags & AF_VERDICT_TRUNCATED));
  AF_CHECK(out.n == 1 && out.apple_id[0] == 1); /* stamped 0.3 s: 0.2 s before it */
  AF_CHECK(af_lane_get_stats(l)->force_stalls == 1);
  printf("force stall: %zu strike, %s\n", out.n, out.n ? out.r[0].reason : "");
  af_lane_destroy(l);
  free_session(&s);
}

int main(void)
{
  test_waits_for_its_own_apple();
  test_late_estimate();
  test_lost_strike_and_late_estimate();
  test_apples_in_flight();
  test_camera_stamps_late();
  test_implausible_estimates();
  test_skipped_ids();
  test_no_apple();
  test_chunking_and_order();
  test_reset_is_new();
  test_empty_chunks();
  test_without_audio();
  test_force_stall();
  return af_test_summary("test_lane");
}
