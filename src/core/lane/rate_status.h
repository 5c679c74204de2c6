/* rate_status.h — diagnostic_updater's FrequencyStatus and TimeStampStatus
 * (update_functions.h, as velodyne_driver uses them on its packets), in pure
 * C, for the node's input streams: force and audio chunks, apple estimates.
 *
 * Kept in the core instead of wrapping diagnostic_updater's classes behind
 * the shim: the judgement is then unit-tested without ROS on injected
 * times, the node's component tasks put its figures beside their own values
 * in one status (diagnostic_updater's tasks each write a status or need a
 * CompositeDiagnosticTask, not reachable through a C API), and the clock is
 * the caller's (the node: ROS time, the bag's under replay).
 *
 * Frequency: events are counted by af_rate_tick; each diagnostic update
 * (af_rate_run) takes the rate over the last `window` updates (since the
 * start while fewer have run): events in that window / its duration. The
 * level, as diagnostic_updater's:
 *   rate < min_hz (1 - tolerance)    WARN  "rate too low"
 *   rate > max_hz (1 + tolerance)    WARN  "rate too high"
 *   otherwise                        OK
 * except for a window of no duration (an update at the start's own time:
 * OK "no window yet"), and a window without an event, which is WARN "no events" here
 * (diagnostic_updater: ERROR): a silent input loses nothing while no apple
 * comes, and the node raises it to ERROR when apples do; with min_hz 0 (an
 * input that may pause, as the apple estimates of a stopped line) it is OK.
 * max_hz = INFINITY: no upper bound.
 *
 * Timestamps: each message's delay = receive time - header stamp [s] is
 * ticked; each update judges the earliest and latest delay since the last
 * one against [min_delay_s, max_delay_s] (real rigs: cameras stamp late,
 * DAQ clocks are offset). Outside, WARN (diagnostic_updater: ERROR; a late
 * stamp still lets the lane attribute within its tolerances, it tells that
 * the margin is being eaten); a zero stamp, ERROR (as diagnostic_updater:
 * nothing can be attributed by it); no message since the last update, OK
 * with "no data" (diagnostic_updater: WARN; the frequency check says it).
 *
 * Fixed-size values, no allocation; not thread-safe (the node's one spinning
 * thread). Times in integer nanoseconds of the caller's clock. */
#ifndef AF_RATE_STATUS_H
#define AF_RATE_STATUS_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#define AF_RATE_WINDOW_MAX 100 /* diagnostic updates in a window, at most (the table's range) */

/* diagnostic_msgs/DiagnosticStatus levels (the shim's af_diag_level alike). */
typedef enum { AF_HEALTH_OK = 0, AF_HEALTH_WARN = 1, AF_HEALTH_ERROR = 2 } af_health_level;

typedef struct {
  double min_hz;    /* lowest expected rate [1/s]; 0 = the input may pause */
  double max_hz;    /* highest expected rate [1/s]; INFINITY = no bound */
  double tolerance; /* fraction beyond [min_hz, max_hz] still accepted, e.g. 0.1 */
  size_t window;    /* diagnostic updates the rate is taken over, 1..AF_RATE_WINDOW_MAX */
} af_rate_config;

typedef struct {
  af_rate_config cfg;
  unsigned long long count;                      /* events since the start */
  int64_t times_ns[AF_RATE_WINDOW_MAX];          /* update times, a ring of cfg.window */
  unsigned long long counts[AF_RATE_WINDOW_MAX]; /* count at each of them */
  size_t next;                                   /* the oldest slot */
} af_rate_status;

typedef struct {
  af_health_level level;
  const char *message;             /* "rate ok", "rate too low", "rate too high", "no events",
                                      "no window yet" */
  unsigned long long events;       /* in the window */
  unsigned long long events_total; /* since the start */
  double window_s;                 /* the window's duration [s] */
  double rate_hz;                  /* events / window_s [1/s]; 0 when window_s <= 0 */
  double min_ok_hz, max_ok_hz;     /* the accepted band, tolerance included [1/s] */
} af_rate_report;

/* Every slot at now_ns with no event. cfg->window is clamped into
 * 1..AF_RATE_WINDOW_MAX. */
void af_rate_init(af_rate_status *r, const af_rate_config *cfg, int64_t now_ns);
/* One event (a message received). */
void af_rate_tick(af_rate_status *r);
/* One diagnostic update at now_ns: the rate over the window and its level;
 * the window moves on. */
void af_rate_run(af_rate_status *r, int64_t now_ns, af_rate_report *out);

typedef struct {
  double min_delay_s; /* earliest accepted receive - stamp [s] (negative: stamped ahead) */
  double max_delay_s; /* latest accepted receive - stamp [s] */
} af_stamp_config;

typedef struct {
  af_stamp_config cfg;
  bool valid;          /* a delay ticked since the last update */
  bool zero_seen;      /* a zero stamp since the last update */
  double min_s, max_s; /* earliest and latest delay since the last update [s] */
  unsigned long long early_updates, late_updates, zero_updates; /* updates that saw them */
} af_stamp_status;

typedef struct {
  af_health_level level;
  const char *message; /* "stamps ok", "stamps too late", "stamps too early", "zero stamp",
                          "no data" */
  bool valid;          /* min_delay_s and max_delay_s hold this update's delays */
  double min_delay_s, max_delay_s; /* [s] */
  unsigned long long early_updates, late_updates, zero_updates;
} af_stamp_report;

void af_stamp_init(af_stamp_status *t, const af_stamp_config *cfg);
/* One message with header stamp stamp_ns received at now_ns; stamp_ns 0 =
 * a zero stamp (no delay taken). */
void af_stamp_tick(af_stamp_status *t, int64_t stamp_ns, int64_t now_ns);
/* One diagnostic update: the delays since the last one judged, then cleared. */
void af_stamp_run(af_stamp_status *t, af_stamp_report *out);

#ifdef __cplusplus
}
#endif
#endif
