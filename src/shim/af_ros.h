/* af_ros.h — the C API over roscpp and diagnostic_updater (the shim).
 *
 * Conventions, after LevelDB's c.h and rclc:
 *  - opaque handles: af_ros (the node), af_ros_pub, af_ros_sub, af_ros_diag;
 *    each made by a function returning af_status with the handle through an
 *    OUT pointer, and freed by a NULL-safe function. Publishers, subscribers
 *    and diagnostics belong to their af_ros and are freed with it.
 *  - nothing throws across this API: every C++ exception is caught and turned
 *    into AF_EROS (or AF_EINVAL, AF_ENOMEM); af_ros_last_error() then holds
 *    the message.
 *  - callbacks are plain C: void (*)(const void *msg, void *user), msg points
 *    to the C struct of the subscribed type (af_msgs.h); they run only inside
 *    af_ros_spin_once, on the caller's thread.
 *  - topic and parameter names follow ROS: relative topics resolve in the
 *    node's namespace (so lane namespaces and remaps work), parameters are
 *    read from the private namespace (~name).
 *  - time is ROS time (sim time honoured when /use_sim_time is set).
 */
#ifndef AF_ROS_H
#define AF_ROS_H

#include <stdbool.h>
#include <stddef.h>

#include "af_msgs.h"
#include "status.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct af_ros af_ros;
typedef struct af_ros_pub af_ros_pub;
typedef struct af_ros_sub af_ros_sub;
typedef struct af_ros_diag af_ros_diag;

typedef enum {
  AF_MSG_SIGNAL_CHUNK = 0, /* af_signal_chunk      <-> acoustic_firmness/SignalChunk */
  AF_MSG_APPLE_ESTIMATE,   /* af_apple_estimate    <-> acoustic_firmness/AppleEstimate */
  AF_MSG_EXCITATION_BAND,  /* af_excitation_band   <-> acoustic_firmness/ExcitationBand */
  AF_MSG_STRIKE_ADVICE,    /* af_strike_advice     <-> acoustic_firmness/StrikeAdvice */
  AF_MSG_RELIABILITY,      /* af_reliability       <-> acoustic_firmness/Reliability */
  AF_MSG_MARKER_ARRAY,  /* af_marker_array       -> visualization_msgs/MarkerArray (publish only) */
  AF_MSG_STRIKE_REPORT, /* af_strike_report     <-> acoustic_firmness/StrikeReport */
  AF_MSG_IMAGE,         /* af_image              -> sensor_msgs/Image (publish only; image.cpp) */
  AF_MSG_TEXT           /* af_text_msg           -> std_msgs/String (publish only) */
} af_msg_type;

typedef enum {
  AF_LOG_DEBUG = 0,
  AF_LOG_INFO,
  AF_LOG_WARN,
  AF_LOG_ERROR,
  AF_LOG_FATAL
} af_log_level;

typedef void (*af_ros_callback)(const void *msg, void *user);

/* ros::init + NodeHandle. argv remappings (name:=value, __ns:=...) are
 * honoured and removed from argc/argv. */
af_status af_ros_create(int *argc, char **argv, const char *node_name, af_ros **out);
void af_ros_destroy(af_ros *r); /* NULL-safe; shuts the node down */

/* Last error message of this handle ("" when none). Never NULL. */
const char *af_ros_last_error(const af_ros *r);

/* ros::ok() and not shut down. */
bool af_ros_ok(const af_ros *r);
/* Requests shutdown (as Ctrl-C does). */
void af_ros_request_shutdown(af_ros *r);

/* Runs the callbacks that are ready, waiting up to timeout_s [s] for the
 * first one. A timeout is AF_OK, not an error. */
af_status af_ros_spin_once(af_ros *r, double timeout_s);

/* Current ROS time (sim time when /use_sim_time). */
af_time af_ros_now(const af_ros *r);
double af_time_to_s(af_time t);
af_time af_time_from_s(double s); /* s >= 0 */

/* Fully resolved name of this node, e.g. "/lane1/firmness_node". */
const char *af_ros_node_name(const af_ros *r);

/* rosconsole logging under the node's name; printf format. */
void af_ros_log(const af_ros *r, af_log_level level, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;

/* Private parameters (~name). AF_ENODATA when absent; AF_EINVAL when present
 * with another type (an int is accepted for a double). */
af_status af_ros_param_double(const af_ros *r, const char *name, double *out);
af_status af_ros_param_int(const af_ros *r, const char *name, int *out);
/* Sets the private parameter ~name (e.g. the node's start count, which
 * outlives a respawned process: the master keeps it). */
af_status af_ros_param_set_int(af_ros *r, const char *name, int value);
af_status af_ros_param_bool(const af_ros *r, const char *name, bool *out);
/* Copies at most len - 1 bytes; AF_ESIZE when the value is longer. */
af_status af_ros_param_string(const af_ros *r, const char *name, char *buf, size_t len);
/* A global or relative parameter (not private), e.g. "robot_description". */
af_status af_ros_param_string_global(const af_ros *r, const char *name, char *buf, size_t len);
/* The length + 1 a string parameter needs (0 when absent), to size buffers at start-up. */
size_t af_ros_param_string_bytes(const af_ros *r, const char *name, bool private_ns);

/* Publishers and subscribers on relative or absolute topics. queue >= 1. */
af_status af_ros_advertise(af_ros *r, const char *topic, af_msg_type type, unsigned queue,
                           bool latch, af_ros_pub **out);
/* msg points to the C struct of the publisher's type. */
af_status af_ros_publish(af_ros_pub *p, const void *msg);
/* Subscribers connected to p now. */
unsigned af_ros_pub_subscribers(const af_ros_pub *p);

af_status af_ros_subscribe(af_ros *r, const char *topic, af_msg_type type, unsigned queue,
                           af_ros_callback cb, void *user, af_ros_sub **out);
/* Messages s dropped before deserializing them: malformed, a length prefix
 * claiming more bytes than the message holds (which would make roscpp
 * allocate it). Each is also logged (WARN at the 1st, 2nd, 4th, ...). */
unsigned long long af_ros_sub_malformed(const af_ros_sub *s);
/* The same over every subscriber of r. */
unsigned long long af_ros_malformed(const af_ros *r);

/* Told of a message refused before deserializing: oversized (longer than
 * the cap) or malformed (cut, empty, a length beyond the message); why is
 * one line naming the lengths (and the cap). user: the subscriber's. */
typedef void (*af_ros_refused_fn)(bool oversized, const char *why, void *user);
/* A SignalChunk subscriber s refuses, before deserializing, a chunk of more
 * than max_samples samples (0: no cap): a chunk longer than the ring it
 * feeds can never be used, and deserializing it would allocate it. Each
 * refusal (oversized, cut or empty) is counted and passed to fn (may be
 * NULL). AF_EINVAL for another message type. */
af_status af_ros_sub_limit(af_ros_sub *s, size_t max_samples, af_ros_refused_fn fn);
/* Chunks s refused as longer than its cap. */
unsigned long long af_ros_sub_oversized(const af_ros_sub *s);

/* diagnostic_updater: one updater per node, on /diagnostics.
 * hardware_id names the station (e.g. the lane). */
typedef struct af_diag_status af_diag_status;
typedef enum {
  AF_DIAG_OK = 0,
  AF_DIAG_WARN = 1,
  AF_DIAG_ERROR = 2,
  AF_DIAG_STALE = 3
} af_diag_level;
/* Fills a status; called from af_ros_diag_update when the updater's period is due. */
typedef void (*af_diag_fn)(af_diag_status *st, void *user);
void af_diag_summary(af_diag_status *st, af_diag_level level, const char *message);
void af_diag_add(af_diag_status *st, const char *key, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;

af_status af_ros_diag_create(af_ros *r, const char *hardware_id, af_ros_diag **out);
af_status af_ros_diag_add_task(af_ros_diag *d, const char *name, af_diag_fn fn, void *user);
/* Publishes when the updater's period (~diagnostic_period, 1 s) is due. */
void af_ros_diag_update(af_ros_diag *d);
/* Publishes now (e.g. after an error). */
void af_ros_diag_force_update(af_ros_diag *d);

#ifdef __cplusplus
}
#endif
#endif
