/* station_private.h — the station's state and what its files share:
 * station.c (life cycle, streams), station_apple.c (each apple: geometry,
 * prediction outputs, markers), station_diag.c (/diagnostics, per component).
 * Not a public header: src/node only. */
#ifndef AF_NODE_STATION_PRIVATE_H
#define AF_NODE_STATION_PRIVATE_H

#include "station.h"

#include <stdbool.h>
#include <stdint.h>

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

/* Warnings at the 1st, 2nd, 4th, 8th ... occurrence: a broken input cannot
 * flood the log. */
static inline bool af_station_power_of_two(unsigned long long n)
{
  return n != 0 && (n & (n - 1)) == 0;
}

/* station_apple.c: an AppleEstimate (subscriber callback). */
void af_station_on_apple(const void *msg, void *user);

/* station_diag.c: the diagnostic tasks made on st->diag, and the inputs'
 * rate checks started at the ROS time now_ns. */
af_status af_station_diag_create(af_station *st);
void af_station_start_rates(af_station *st, int64_t now_ns);
/* The diagnostic summary in rviz (status_marker.h): warning NULL = OK. */
void af_station_publish_status(af_station *st, const char *warning);

#endif
