/* af_audio.h — audio_common's messages behind the C API (audio_common.cpp).
 *
 * A lab microphone on ROS runs audio_capture (audio_common), which publishes
 * audio_common_msgs/AudioData or AudioDataStamped with the format on a latched
 * audio_common_msgs/AudioInfo. Debian does not package audio_common, so the
 * shim subscribes generically (topic_tools::ShapeShifter) and checks each
 * message's type, md5sum and definition against the audio_common_msgs ones
 * written below (taken from its .msg files; md5 computed as genmsg does,
 * test/shim/test_audio_common.cpp recomputes them), then reads the bytes
 * itself, every length prefix checked against the bytes that remain.
 *
 * Callbacks are plain C and run inside af_ros_spin_once; data is borrowed
 * for the call. A message of another type, md5 or definition, or a
 * malformed one, goes to the refused callback with the reason. The
 * subscriptions belong to the af_ros. */
#ifndef AF_AUDIO_H
#define AF_AUDIO_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "af_msgs.h"
#include "af_ros.h"

#ifdef __cplusplus
extern "C" {
#endif

/* audio_common_msgs, as genmsg hashes them (md5 of "uint8[] data"; of
 * "<Header md5> header\n<AudioData md5> audio"; of the AudioInfo fields). */
#define AF_AUDIO_DATA_TYPE "audio_common_msgs/AudioData"
#define AF_AUDIO_DATA_MD5 "f43a8e1b362b75baa741461b46adc7e0"
#define AF_AUDIO_DATA_DEFINITION "uint8[] data\n"
#define AF_AUDIO_DATA_STAMPED_TYPE "audio_common_msgs/AudioDataStamped"
#define AF_AUDIO_DATA_STAMPED_MD5 "3cdd84a06846af0dca4d0434908f9d96"
#define AF_AUDIO_DATA_STAMPED_DEFINITION                                                           \
  "std_msgs/Header header\naudio_common_msgs/AudioData audio\n"
#define AF_AUDIO_INFO_TYPE "audio_common_msgs/AudioInfo"
#define AF_AUDIO_INFO_MD5 "9413d9b7029680d3b1db6ed0ae535f88"
#define AF_AUDIO_INFO_DEFINITION                                                                   \
  "uint8 channels       # Number of channels\n"                                                    \
  "uint32 sample_rate   # Sampling rate [Hz]\n"                                                    \
  "string sample_format # Audio format (e.g. S16LE)\n"                                             \
  "uint32 bitrate       # Amount of audio data per second [bits/s]\n"                              \
  "string coding_format # Audio coding format (e.g. WAVE, MP3)\n"

#define AF_AUDIO_FORMAT_MAX 32 /* sample_format and coding_format, with their NUL */
#define AF_AUDIO_TYPE_MAX 128

/* audio_common_msgs/AudioData or AudioDataStamped. */
typedef struct {
  bool stamped;         /* AudioDataStamped: header is the message's */
  af_header header;     /* zero for AudioData */
  af_time receipt;      /* ROS time when the message was received (sim time honoured) */
  const uint8_t *data;  /* the audio bytes, borrowed */
  size_t n_bytes;       /* */
  bool definition_sent; /* the publisher sent its definition (and it matched); false: the
                           type and md5 alone were checked */
} af_audio_data;

/* audio_common_msgs/AudioInfo. Longer strings are cut. */
typedef struct {
  uint8_t channels;
  uint32_t sample_rate_hz;
  char sample_format[AF_AUDIO_FORMAT_MAX]; /* e.g. "S16LE" */
  uint32_t bitrate_bit_s;
  char coding_format[AF_AUDIO_FORMAT_MAX]; /* e.g. "wave", "mp3" */
} af_audio_info;

/* A message the subscription does not take: what it was and why not. */
typedef struct {
  char datatype[AF_AUDIO_TYPE_MAX];
  char md5[40];
  char why[AF_TEXT_MAX];
  bool oversized; /* longer than the cap (max_bytes), never deserialized */
} af_audio_refusal;

typedef void (*af_audio_data_fn)(const af_audio_data *m, void *user);
typedef void (*af_audio_info_fn)(const af_audio_info *m, void *user);
typedef void (*af_audio_refused_fn)(const af_audio_refusal *r, void *user);

/* AudioData and AudioDataStamped on topic (either type; the publisher's
 * decides), queue >= 1. *max_bytes (max_bytes may be NULL: no cap; read at
 * each message, so the caller may change it): a message of more serialized
 * bytes is refused (refused, "oversized") before it is deserialized or
 * copied. AF_OK; AF_EINVAL for a NULL or empty argument; AF_EROS. */
af_status af_ros_subscribe_audio(af_ros *r, const char *topic, unsigned queue, af_audio_data_fn fn,
                                 af_audio_refused_fn refused, const size_t *max_bytes, void *user);
/* AudioInfo on topic (audio_capture latches it). */
af_status af_ros_subscribe_audio_info(af_ros *r, const char *topic, af_audio_info_fn fn,
                                      af_audio_refused_fn refused, void *user);

/* The parts of the shim's checks, for its tests: the fields of a definition
 * without comments, blank lines and the dependencies after the first
 * "=====" line, one "type name" per line. */
bool af_audio_definition_matches(const char *sent, const char *expected);

#ifdef __cplusplus
}
#endif
#endif
