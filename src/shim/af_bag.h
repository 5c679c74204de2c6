/* af_bag.h — writing and reading rosbags from C (the shim's rosbag::Bag).
 *
 * For tools that make recordings (src/demo/strike_bag.c): the messages are
 * the C structs of af_msgs.h, converted as the publishers convert them
 * (convert.hpp), so a bag written here replays exactly as a live node would
 * have published. No ROS master and no ros::init are needed.
 *
 * Conventions of af_ros.h: an opaque handle made by a function returning
 * af_status with the handle through an OUT pointer; nothing throws across
 * this API (rosbag::BagException -> AF_EIO, a C struct that cannot be
 * represented -> AF_EINVAL, std::bad_alloc -> AF_ENOMEM, anything else ->
 * AF_EROS); af_bag_last_error() holds the message. Not thread-safe: one
 * writer per bag. Each write allocates (the message and rosbag's buffers):
 * this is for tools, not for the node's loop. */
#ifndef AF_BAG_H
#define AF_BAG_H

#include "af_msgs.h"
#include "af_ros.h"
#include "status.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct af_bag af_bag;

/* Creates (or truncates) the bag file at path, uncompressed. AF_EINVAL for a
 * NULL or empty path or NULL out, AF_EIO when the file cannot be opened;
 * *out is NULL on error and af_bag_last_error(NULL) says why. */
af_status af_bag_open_write(const char *path, af_bag **out);

/* Writes msg, the C struct of type (af_msgs.h), on topic (an absolute name
 * such as "/lane1/force": a bag has no namespace to resolve in) at the
 * bag time stamp (what `rosbag play` publishes it at; > 0). Types as
 * af_ros_advertise, AF_MSG_MARKER_ARRAY included. AF_EINVAL for a NULL
 * argument, an empty topic, an unknown type, a zero stamp or a struct that
 * cannot be represented; AF_EIO when rosbag fails (a full disk, a file-size
 * limit: af_bag_last_error(bag) gives rosbag's message and the cause). After
 * AF_EIO the bag takes no more writes (AF_EIO again): close it, which
 * removes the partial file. */
af_status af_bag_write(af_bag *bag, const char *topic, af_msg_type type, const void *msg,
                       af_time stamp);

/* Closes the file (writes the index) and frees bag. NULL-safe (AF_OK).
 * Returns AF_EIO when the close failed or an earlier write had failed: the
 * file, a bag cut short, is then removed, and af_bag_last_error(NULL) is one
 * line "PATH: CAUSE; the partial bag is removed" (or "... is left behind,
 * not a readable bag" when it cannot be removed). Never aborts: rosbag's
 * exceptions, its destructor's included, stay inside. bag is freed either
 * way. */
af_status af_bag_close(af_bag *bag);

/* The last error of bag, or of the last handle-less call of the calling
 * thread when bag is NULL ("" when none). Never NULL. */
const char *af_bag_last_error(const af_bag *bag);

/* --- reading ------------------------------------------------------------------ */

/* A bag opened for reading, its messages in bag-time order (the order
 * `rosbag play` publishes them in). For the desk tools: no master needed. */
typedef struct af_bag_reader af_bag_reader;

/* One message: its topic, bag time and type, and the C struct in the member
 * of its type. Arrays (SignalChunk.data) are borrowed until the next call. */
typedef struct {
  const char *topic; /* borrowed until the next call */
  af_time bag_time;
  af_msg_type type; /* one of the types below */
  union {
    af_signal_chunk chunk;      /* AF_MSG_SIGNAL_CHUNK */
    af_apple_estimate apple;    /* AF_MSG_APPLE_ESTIMATE */
    af_strike_report report;    /* AF_MSG_STRIKE_REPORT */
    af_reliability reliability; /* AF_MSG_RELIABILITY */
  } msg;
} af_bag_message;

/* Opens path for reading the messages on the given topics (absolute names;
 * n_topics 0 = every topic whose type is one of the above). AF_EIO when
 * the file is not a readable bag (not a bag, truncated, unindexed),
 * AF_EINVAL for bad arguments or a listed topic whose type in the bag is not
 * one of the above (the message names the topic and both types). The error
 * (af_bag_reader_error(NULL)) is one line that names path once:
 * "PATH: not a readable bag: WHY", ending with the `rosbag reindex PATH`
 * hint when the file is a bag cut short or never closed. */
af_status af_bag_open_read(const char *path, const char *const *topics, size_t n_topics,
                           af_bag_reader **out);

/* The next message into *m: AF_OK, AF_ENODATA at the end of the bag, AF_EIO
 * when the bag cannot be read further (truncated chunk). One message
 * refused, the next call going on after it (m->topic and m->bag_time set,
 * af_bag_reader_error(r) one line naming the topic and the lengths):
 * AF_ESIZE, a SignalChunk of more than the cap (af_bag_reader_limit),
 * refused before it is copied or deserialized; AF_EINVAL, a message on a
 * listed topic that is not one of the types above, or whose bytes are not
 * the type its connection states (a wrong message type on that topic, or
 * a cut message). */
af_status af_bag_read_next(af_bag_reader *r, af_bag_message *m);

/* SignalChunks of more than max_samples (0: no cap, the default) are
 * refused by af_bag_read_next (AF_ESIZE). */
void af_bag_reader_limit(af_bag_reader *r, size_t max_samples);

/* Messages on topic in the bag (0 when absent or NULL). */
size_t af_bag_topic_count(const af_bag_reader *r, const char *topic);

/* The text of the first message on topic (a std_msgs/String: the node's
 * settings snapshot, NS/settings) into buf: AF_OK with *found true; AF_OK
 * with *found false when the bag has no message on topic; AF_ESIZE when the
 * text does not fit len bytes with its NUL; AF_EINVAL when the topic has
 * another type; AF_EIO when the file is not a readable bag. A failure's
 * line, naming path, in af_bag_reader_error(NULL). Opens the bag on its
 * own (a View of that topic only: the chunks of the other topics are not
 * read). */
af_status af_bag_read_text(const char *path, const char *topic, char *buf, size_t len, bool *found);

/* Closes and frees r; NULL-safe. */
void af_bag_close_read(af_bag_reader *r);

/* The last error of r, or, when r is NULL, of the last reader-less call
 * (af_bag_open_read) made by the calling thread: readers on several threads
 * each see their own. */
const char *af_bag_reader_error(const af_bag_reader *r);

#ifdef __cplusplus
}
#endif
#endif
