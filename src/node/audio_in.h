/* audio_in.h — the microphone as ROS users publish it: audio_common's
 * AudioData / AudioDataStamped on the lane's audio topic, the format on
 * audio_info (~audio_input: audio_common), decoded into the lane's audio
 * chunks.
 *
 *  - format: audio_info's coding_format must be "wave" (uncompressed PCM);
 *    mp3 and any other coding is refused with a diagnostic naming it, as is a
 *    sample_format that is not a raw PCM format (src/core/io/pcm.h), a channel
 *    count of 0 or ~audio_channel beyond the channels. Before the first
 *    audio_info, chunks are dropped and counted;
 *  - decoding: channel ~audio_channel of each frame, at full scale 1 times
 *    ~audio_full_scale, in blocks of AF_AUDIO_IN_BLOCK samples;
 *  - time: AudioDataStamped's header stamp is the time of the first sample;
 *    AudioData carries none, so its first sample is taken at the receive
 *    time minus the chunk's duration, and the jitter of those stamps against
 *    the sample clock (each chunk's stamp minus the previous one's plus its
 *    duration) is measured and reported in /diagnostics;
 *  - the running sample index (SignalChunk's first_sample) is kept here per
 *    stream: it counts decoded frames; a stamped chunk later than the
 *    previous one's end by more than half its own duration is a gap (the
 *    missing samples skipped, so the lane counts them as lost), an earlier
 *    one a restart; a change of rate, format or channels in audio_info
 *    restarts the stream at sample 0 (the lane restarts its ring) with a
 *    diagnostic. The lane still refuses chunks at a rate other than
 *    ~audio_sample_rate_hz, as it refuses such SignalChunks.
 *
 * Everything is allocated in af_audio_in_create; a chunk allocates nothing
 * here (the shim keeps its byte buffer). Not thread-safe: the node's one
 * spinning thread. */
#ifndef AF_NODE_AUDIO_IN_H
#define AF_NODE_AUDIO_IN_H

#include "af_audio.h"
#include "af_ros.h"
#include "params.h"

#ifdef __cplusplus
extern "C" {
#endif

#define AF_AUDIO_IN_BLOCK 4096 /* samples per chunk handed to the lane */

typedef struct af_audio_in af_audio_in;

/* Subscribes to audio (AudioData or AudioDataStamped) and audio_info
 * (relative topics); each decoded block goes to feed as an af_signal_chunk
 * (the station's audio callback). *out NULL on error, *what naming the part. */
af_status af_audio_in_create(af_ros *ros, const af_node_config *cfg, af_ros_callback feed,
                             void *user, af_audio_in **out, const char **what);
void af_audio_in_destroy(af_audio_in *a); /* NULL-safe */

/* The audio_common keys of /diagnostics (NULL-safe: nothing for NULL). */
void af_audio_in_diag(const af_audio_in *a, af_diag_status *d);
/* A short reason to WARN when chunks were refused or the stream restarted
 * since the last call; NULL when not (and for NULL). */
const char *af_audio_in_warning(af_audio_in *a);

#ifdef __cplusplus
}
#endif
#endif
