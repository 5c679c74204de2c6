/* session.h — a recorded session (a rosbag) through the core lane, offline:
 * what firmness_report prints and plots.
 *
 * Reads /NS/force, /NS/audio (acoustic_firmness/SignalChunk) and /NS/apple
 * (acoustic_firmness/AppleEstimate) in bag-time order through the shim's
 * reader (af_bag.h, no ROS master), and drives one af_lane (src/core/lane/lane.h)
 * exactly as the node does under `rosbag play --clock`: every message at the
 * lane clock of its bag time (what /clock says when it is published), force
 * and audio chunks converted field by field, each apple's strike direction
 * unknown (the node takes it from the rig's URDF; the measurement does not
 * depend on it when the estimate gives its strike radius, and the
 * prediction's R2 is then that radius too). At the end of the bag the lane
 * is finished (af_lane_finish): a strike still waiting is measured with what
 * there is. Each measured strike is kept as a row; each estimate as an
 * apple with its prediction.
 *
 * Bad input is refused before the lane sees a message, with one line in err
 * and AF_SESSION_BAD_INPUT: not a bag or a truncated one (rosbag cannot open
 * or index it), a topic missing (no message on it), a topic of another type
 * (the reader's check, or the first message of a type this tool reads but
 * not the one the topic must carry); a bag that breaks while being read is
 * bad input too. Allocates (rows grow by doubling): a desk tool, not the
 * node's path. */
#ifndef AF_REPORT_SESSION_H
#define AF_REPORT_SESSION_H

#include <pthread.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "grade.h"
#include "lane.h"
#include "serialize.h"

#define AF_SESSION_OK 0
#define AF_SESSION_FAILED 1    /* the lane could not be made, out of memory */
#define AF_SESSION_BAD_INPUT 2 /* the bag or its topics (err says which) */

#define AF_SESSION_NS_MAX 96
#define AF_SESSION_TOPIC_MAX 128

/* One measured strike and what the station knew of its apple. */
typedef struct {
  int64_t start_ns;                   /* contact start [ns] (the StrikeReport's stamp) */
  char frame_id[AF_STREAM_FRAME_MAX]; /* the force chunk's (the StrikeReport's) */
  uint32_t apple_id;                  /* 0 = no apple matched */
  bool has_apple;                     /* an estimate matched (apple_* are its) */
  int64_t apple_stamp_ns;
  double mass_kg;
  bool predicted; /* the apple's prediction ran (predicted_* are its) */
  double predicted_band_low_hz, predicted_band_high_hz, predicted_resonance_hz;
  bool predicted_reliable;
  char predicted_reason[AF_PREDICTION_TEXT_MAX];
  bool with_audio;                 /* an audio window was analysed */
  double modulus_factor;           /* the apple's (dynamic / quasi-static), to suggest a new one */
  af_measure_report report;        /* the StrikeReport figures and the measured verdict */
  af_grade grade;                  /* its firmness class, as the lane graded it (lane.h): the node's
                                      StrikeReport grade_index, grade, grade_reason */
  double hammer_velocity_m_s;      /* its contact velocity from the impulse (hammer_health.h; NaN:
                                      not a clean strike) */
  double hammer_velocity_mean_m_s; /* the window's mean v0 the health judged after it [m/s] */
  uint32_t hammer_warnings;        /* the hammer health's AF_HAMMER_WARN_* after it */
  double factor_true; /* its own dynamic / quasi-static factor, modulus_factor x E(0S2) / E2
                         [-] (factor_learn.h); NaN without both moduli */
  double factor_estimate, factor_ci_low_95, factor_ci_high_95; /* the learned factor after it
                                                                  [-] (NaN while too few) */
  double factor_applied; /* the factor applied from the next strike on [-] */
} af_session_strike;

/* The view of r that serialize.h writes (borrowed: valid while r is). */
af_serial_strike af_session_serial(const af_session_strike *r);

/* One AppleEstimate and its prediction. */
typedef struct {
  uint32_t apple_id;
  int64_t stamp_ns;
  double mass_kg;
  bool valid; /* the estimate was accepted and the model ran */
  double band_low_hz, band_high_hz, resonance_hz;
  bool reliable;
  char reason[AF_PREDICTION_TEXT_MAX]; /* why not reliable, or why refused */
  size_t strikes;                      /* strikes matched to it */
} af_session_apple;

/* A stream's counters at the end of the bag. */
typedef struct {
  uint64_t chunks, gaps, lost_samples, restarts, bad_rate, bad_unit, bad_index, malformed,
      oversized;
  uint64_t refused_samples, refused_spans; /* non-finite samples of accepted chunks */
  uint64_t duplicates;                     /* chunks that repeat samples already held */
  uint64_t overlaps, duplicate_samples;    /* chunks whose head repeated held samples (tail kept);
                                              samples sent again (stream.h) */
  int64_t first_ns, end_ns;           /* time of the first sample, end of the last chunk [ns] */
  uint64_t clock_steps, clock_frozen; /* the stream's clock faults (stream.h) */
  double clock_rate_hz;               /* the rate its stamps advance at; NaN: not judged */
  bool clock_rate_wrong;
  char clock_problem[AF_STREAM_TEXT_MAX]; /* the latest in words; "" when none */
} af_session_stream;

typedef struct {
  af_session_strike *strikes;
  size_t n_strikes, cap_strikes;
  af_session_apple *apples;
  size_t n_apples, cap_apples;
  af_lane_stats stats;                /* the lane's at the end (the hammer health's last window) */
  af_hammer_health_config health_cfg; /* what the hammer health was judged with */
  af_factor_learn_state factor;       /* the lane's learned modulus factor at the end (lane.h) */
  af_session_stream force, audio;
  uint64_t messages;         /* read from the bag */
  uint64_t refused_messages; /* refused by the reader (oversized, not their type), all topics */
  uint64_t refused_apples;   /* of those, on the apple topic */
  double recorded_s;         /* recorded time: the force stream's span [s] */
  bool tap_only;             /* measured from the audio alone: recorded_s is the audio's */
  double wall_s, cpu_s;      /* spent reading and processing [s]; CPU: this thread's */
} af_session;

/* Extra work per strike (plots); lane: for its streams. Called after the
 * row is stored. */
typedef void af_session_strike_fn(const af_lane_strike *s, const af_lane *lane, void *user);

typedef struct {
  const char *bag_path;
  const char *ns; /* lane namespace without slashes, e.g. "lane1" */
  const af_lane_config *cfg;
  af_session_strike_fn *on_strike; /* may be NULL */
  void *user;
  bool progress;               /* a progress bar on stderr */
  pthread_mutex_t *setup_lock; /* held while the bag is opened and the lane made or freed (the
                                  rosbag reader's error text and FFTW's planner are
                                  process-wide); NULL: one session at a time */
} af_session_options;

/* Runs the bag through a lane made from o->cfg into *out (zeroed first).
 * AF_SESSION_OK, AF_SESSION_BAD_INPUT or AF_SESSION_FAILED with one line in
 * err. *out holds what was read even on error; free it with
 * af_session_destroy. */
int af_session_execute(const af_session_options *o, af_session *out, char *err, size_t len);
void af_session_destroy(af_session *s); /* safe on a zeroed or freed session */

#endif
