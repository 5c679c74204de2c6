/* absent.h — a lane input that never started: no force chunk, or no audio
 * chunk, accepted within stream_absent_warn_s of the lane's start. A stream
 * that stops after it has delivered is af_stream_stale's (stream.h); this
 * one covers the stream that was never wired, whose state would otherwise
 * read "no chunk yet" forever under an OK /diagnostics.
 *
 * Both streams are required by the lane (the strike detector runs on the
 * force, the resonance on the audio): there is no force-less or
 * microphone-less mode to spare from the warning; stream_absent_warn_s = 0
 * turns it off. Times are the lane's clock [ns], passed in by the caller
 * (the node: ROS time, which under replay is the bag's). */
#ifndef AF_ABSENT_H
#define AF_ABSENT_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "stream.h"

#ifdef __cplusplus
extern "C" {
#endif

/* s has accepted no chunk and now_ns is at least warn_after_s after start_ns.
 * Never with warn_after_s <= 0 (the check is off), nor with start_ns <= 0
 * (the clock has not started: a simulated clock before its first /clock). */
bool af_absent(const af_stream *s, int64_t start_ns, int64_t now_ns, double warn_after_s);

/* The warning for the two streams, e.g. "no force chunk within 5.0 s of
 * start", "no force and no audio chunk within 5.0 s of start", with the
 * refused chunks when some came ("(2 refused: force chunk at sample 0: unit
 * 'V', expected 'N')"). true and text written when one is absent; false and
 * text "" otherwise. */
bool af_absent_warning(const af_stream *force, const af_stream *audio, int64_t start_ns,
                       int64_t now_ns, double warn_after_s, char *text, size_t len);

#ifdef __cplusplus
}
#endif
#endif
