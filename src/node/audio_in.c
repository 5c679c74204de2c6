/* audio_in.c — audio_common input (see audio_in.h). */
#include "audio_in.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "af_wire_guard.h"
#include "lane_io.h"
#include "pcm.h"
#include "text.h"

struct af_audio_in {
  af_ros *ros;
  const af_node_config *cfg;
  af_ros_callback feed;
  void *user;
  /* the format from audio_info */
  bool have_info, usable;
  af_audio_info info;
  af_pcm_format format;
  char format_problem[AF_TEXT_MAX]; /* why the format is refused; "" when usable */
  /* the stream */
  uint64_t next_sample; /* running index of the next decoded sample */
  bool have_last;       /* last_t0_ns and last_frames hold the previous chunk */
  int64_t last_t0_ns;   /* stamp of the previous chunk's first sample [ns] */
  size_t last_frames;
  double last_rate_hz;
  /* counters */
  unsigned long long messages, stamped, unstamped, definitions_sent, infos, fed;
  unsigned long long wrong_type, bad_format, before_info, partial, restarts, gaps, lost;
  unsigned long long format_changes;          /* audio_info changes at the same rate */
  unsigned long long oversized;               /* longer than max_bytes, never copied */
  unsigned long long problems, problems_seen; /* for the warning */
  /* jitter of the AudioData stamps against the sample clock [s] */
  unsigned long long jitter_n;
  double jitter_sum2, jitter_max;
  char last_problem[AF_TEXT_MAX];
  size_t max_bytes; /* the shim's cap on a message: the ring's samples in this format */
  float block[AF_AUDIO_IN_BLOCK];
};

/* Bytes of the largest usable message: a chunk of more frames than the
 * audio ring holds can never be used. Before a usable audio_info
 * (chunks dropped anyway), one channel of the widest PCM sample. */
#define AF_AUDIO_IN_WIDEST_SAMPLE_BYTES 8
static size_t cap_bytes(const af_audio_in *a)
{
  const size_t frame = a->usable ? af_pcm_sample_bytes(a->format) * a->info.channels
                                 : AF_AUDIO_IN_WIDEST_SAMPLE_BYTES;
  return a->cfg->lane.audio.max_chunk_samples * frame + 4096; /* + the header, frame_id and all */
}

/* a and b equal but for the case of ASCII letters. */
static bool same_word(const char *a, const char *b)
{
  for (; *a && *b; a++, b++) {
    char x = *a >= 'A' && *a <= 'Z' ? (char)(*a - 'A' + 'a') : *a;
    char y = *b >= 'A' && *b <= 'Z' ? (char)(*b - 'A' + 'a') : *b;
    if (x != y)
      return false;
  }
  return *a == *b;
}

static bool power_of_two(unsigned long long n)
{
  return n != 0 && (n & (n - 1)) == 0;
}

/* Records a problem; logged at the 1st, 2nd, 4th ... of its counter. */
static void problem(af_audio_in *a, unsigned long long count, const char *text)
{
  af_text(a->last_problem, sizeof a->last_problem, "%s", text);
  a->problems++;
  if (power_of_two(count))
    af_ros_log(a->ros, AF_LOG_WARN, "%s (%llu so far)", text, count);
}

/* --- the format ------------------------------------------------------------------ */

static void format_text(const af_audio_info *i, char *buf, size_t len)
{
  af_text(buf, len, "%u Hz, %s, %u channel%s, %s", i->sample_rate_hz, i->sample_format, i->channels,
          i->channels == 1 ? "" : "s", i->coding_format);
}

/* Why the station cannot decode i ("" when it can); *f its sample format. */
static void check_info(const af_audio_in *a, const af_audio_info *i, af_pcm_format *f, char *why,
                       size_t len)
{
  why[0] = '\0';
  if (!same_word(i->coding_format, "wave"))
    af_text(why, len,
            "audio_info coding_format '%s' is not decoded: the station takes uncompressed PCM "
            "only (coding_format 'wave'; audio_capture's format:=wave)",
            i->coding_format);
  else if (af_pcm_format_parse(i->sample_format, f) != AF_OK)
    af_text(why, len, "audio_info sample_format '%s' is not one of: %s", i->sample_format,
            af_pcm_format_list());
  else if (i->channels == 0)
    af_text(why, len, "audio_info says 0 channels");
  else if (a->cfg->audio_channel >= i->channels)
    af_text(why, len, "~audio_channel is %u but audio_info has %u channel%s (0..%u)",
            a->cfg->audio_channel, i->channels, i->channels == 1 ? "" : "s", i->channels - 1u);
  else if (i->sample_rate_hz == 0)
    af_text(why, len, "audio_info says a sample rate of 0 Hz");
}

static void on_info(const af_audio_info *m, void *user)
{
  af_audio_in *a = user;
  char why[AF_TEXT_MAX], was[128], now[128], text[AF_TEXT_MAX];
  af_pcm_format f = AF_PCM_S16LE;
  a->infos++;
  check_info(a, m, &f, why, sizeof why);
  const bool rate_changed = a->have_info && m->sample_rate_hz != a->info.sample_rate_hz;
  bool changed = a->have_info && (rate_changed || m->channels != a->info.channels ||
                                  strcmp(m->sample_format, a->info.sample_format) != 0 ||
                                  !same_word(m->coding_format, a->info.coding_format));
  format_text(&a->info, was, sizeof was);
  format_text(m, now, sizeof now);
  a->info = *m;
  a->have_info = true;
  a->usable = why[0] == '\0';
  a->format = f;
  af_text(a->format_problem, sizeof a->format_problem, "%s", why);
  a->max_bytes = cap_bytes(a);
  af_wire_guard_allow(a->max_bytes); /* a wider format: roscpp may now read longer messages */
  if (!a->usable) {
    a->bad_format++;
    problem(a, a->bad_format, why);
  }
  if (changed && rate_changed) {
    /* A new sample clock: the lane sees first_sample go back and restarts its
     * ring (a strike still waiting for its audio is measured without it). */
    a->restarts++;
    a->have_last = false;
    a->next_sample = 0;
    af_text(text, sizeof text,
            "audio_info changed from %s to %s: a new sample rate, the audio stream restarts%s", was,
            now, a->usable ? "" : " (and is refused)");
    problem(a, a->restarts, text);
  } else if (changed) {
    /* The same sample clock: the stream goes on, decoded the new way. */
    a->format_changes++;
    af_text(text, sizeof text,
            "audio_info changed from %s to %s: the same rate, the stream goes on%s", was, now,
            a->usable ? "" : " (but is refused)");
    problem(a, a->format_changes, text);
  }
  const double expected = a->cfg->lane.audio.sample_rate_hz;
  if (a->usable && (double)m->sample_rate_hz != expected && (changed || a->infos == 1)) {
    af_text(text, sizeof text,
            "audio_info says %u Hz, the station expects %g Hz (~audio_sample_rate_hz): its chunks "
            "are refused until the rates agree",
            m->sample_rate_hz, expected);
    problem(a, a->restarts + 1, text);
  }
}

/* --- the data -------------------------------------------------------------------- */

static int64_t ns_of(af_time t)
{
  return af_time_to_ns(t);
}

/* Where this chunk lies on the stream: a gap or a restart on stamped
 * audio, the jitter of the derived stamps otherwise. */
static void place(af_audio_in *a, const af_audio_data *m, int64_t t0_ns, double rate)
{
  if (!a->have_last || a->last_rate_hz != rate)
    return;
  const double expected_s = 1e-9 * (double)(t0_ns - a->last_t0_ns);
  const double d_s = expected_s - (double)a->last_frames / rate; /* [s] */
  char text[AF_TEXT_MAX];
  if (!m->stamped) {
    a->jitter_n++;
    a->jitter_sum2 += d_s * d_s;
    a->jitter_max = fmax(a->jitter_max, fabs(d_s));
    return;
  }
  const double tolerance_s = 0.5 * (double)a->last_frames / rate;
  if (d_s > tolerance_s) {
    unsigned long long skip = (unsigned long long)llround(d_s * rate);
    a->next_sample += skip;
    a->gaps++;
    a->lost += skip;
    af_text(text, sizeof text,
            "audio stamps jump %.3f ms past the previous chunk's end: %llu samples taken as lost",
            d_s * 1e3, skip);
    problem(a, a->gaps, text);
  } else if (d_s < -tolerance_s) {
    a->restarts++;
    a->next_sample = 0;
    af_text(text, sizeof text,
            "audio stamps go back %.3f ms before the previous chunk's end: the stream restarts",
            -d_s * 1e3);
    problem(a, a->restarts, text);
  }
}

static void on_data(const af_audio_data *m, void *user)
{
  af_audio_in *a = user;
  size_t frames;
  a->messages++;
  a->stamped += m->stamped;
  a->unstamped += !m->stamped;
  a->definitions_sent += m->definition_sent;
  if (!a->have_info) {
    a->before_info++;
    problem(a, a->before_info,
            "audio chunk before any audio_info: its format is unknown, the chunk is dropped");
    return;
  }
  if (!a->usable) {
    a->bad_format++;
    problem(a, a->bad_format, a->format_problem);
    return;
  }
  const unsigned channels = a->info.channels;
  if (af_pcm_frames(a->format, channels, m->n_bytes, &frames) != AF_OK) {
    char text[AF_TEXT_MAX];
    a->partial++;
    af_text(text, sizeof text,
            "an audio chunk of %zu bytes is not a whole number of %zu-byte frames (%s x %u): "
            "dropped",
            m->n_bytes, af_pcm_sample_bytes(a->format) * channels, a->info.sample_format, channels);
    problem(a, a->partial, text);
    return;
  }
  if (frames == 0)
    return;
  const double rate = (double)a->info.sample_rate_hz;
  const int64_t duration_ns = (int64_t)llround((double)frames / rate * 1e9);
  const int64_t t0_ns = m->stamped ? ns_of(m->header.stamp) : ns_of(m->receipt) - duration_ns;
  place(a, m, t0_ns, rate);
  for (size_t done = 0; done < frames;) {
    size_t n = frames - done < AF_AUDIO_IN_BLOCK ? frames - done : AF_AUDIO_IN_BLOCK;
    af_pcm_decode(a->format, channels, a->cfg->audio_channel, m->data, done, n,
                  a->cfg->audio_full_scale, a->block);
    af_signal_chunk c;
    memset(&c, 0, sizeof c);
    c.header.stamp = af_time_from_ns(t0_ns + (int64_t)llround((double)done / rate * 1e9));
    if (m->stamped)
      af_text(c.header.frame_id, sizeof c.header.frame_id, "%s", m->header.frame_id);
    c.first_sample = a->next_sample;
    c.sample_rate_hz = rate;
    af_text(c.unit, sizeof c.unit, "%s", a->cfg->lane.audio.units[0]);
    c.data = a->block;
    c.n = n;
    a->feed(&c, a->user);
    a->fed++;
    a->next_sample += n;
    done += n;
  }
  a->have_last = true;
  a->last_t0_ns = t0_ns;
  a->last_frames = frames;
  a->last_rate_hz = rate;
}

static void on_refused(const af_audio_refusal *r, void *user)
{
  af_audio_in *a = user;
  unsigned long long *n = r->oversized ? &a->oversized : &a->wrong_type;
  ++*n;
  problem(a, *n, r->why);
}

/* --- diagnostics ------------------------------------------------------------------ */

void af_audio_in_diag(const af_audio_in *a, af_diag_status *d)
{
  if (!a)
    return;
  af_diag_add(d, "audio input",
              "audio_common: AudioData or AudioDataStamped on audio, format on audio_info; "
              "channel %u, full scale %g %s",
              a->cfg->audio_channel, a->cfg->audio_full_scale, a->cfg->lane.audio.units[0]);
  if (!a->have_info)
    af_diag_add(d, "audio format", "no audio_info yet");
  else {
    char text[AF_TEXT_MAX];
    format_text(&a->info, text, sizeof text);
    af_diag_add(d, "audio format", "%s%s%s", text,
                a->usable ? "" : ": REFUSED: ", a->format_problem);
  }
  af_diag_add(d, "audio messages",
              "%llu (AudioDataStamped %llu, AudioData %llu; with their definition %llu), "
              "%llu chunks to the lane",
              a->messages, a->stamped, a->unstamped, a->definitions_sent, a->fed);
  af_diag_add(d, "audio refused",
              "wrong type/md5/definition %llu, undecodable format %llu, before audio_info %llu, "
              "partial frames %llu, oversized %llu (cap %zu bytes)",
              a->wrong_type, a->bad_format, a->before_info, a->partial, a->oversized, a->max_bytes);
  af_diag_add(
      d, "audio stream",
      "next sample %llu, restarts %llu (rate changes, stamps back), gaps %llu (%llu samples "
      "lost), format changes at the same rate %llu",
      (unsigned long long)a->next_sample, a->restarts, a->gaps, a->lost, a->format_changes);
  if (a->stamped > 0)
    af_diag_add(d, "audio stamps (AudioDataStamped)", "header stamp = the first sample");
  if (a->unstamped > 0) {
    if (a->jitter_n == 0)
      af_diag_add(d, "audio stamps (AudioData)",
                  "receive time minus the chunk's duration (no stamp in AudioData); jitter: "
                  "not measured yet");
    else
      af_diag_add(d, "audio stamps (AudioData)",
                  "receive time minus the chunk's duration (no stamp in AudioData); jitter "
                  "against the sample clock: RMS %.3f ms, max %.3f ms over %llu chunks",
                  1e3 * sqrt(a->jitter_sum2 / (double)a->jitter_n), 1e3 * a->jitter_max,
                  a->jitter_n);
  }
  af_diag_add(d, "audio last problem", "%s", a->last_problem);
}

const char *af_audio_in_warning(af_audio_in *a)
{
  if (!a || a->problems == a->problems_seen)
    return NULL;
  a->problems_seen = a->problems;
  return "audio_common chunks refused or the audio stream restarted since the last report";
}

/* --- life cycle ------------------------------------------------------------------- */

af_status af_audio_in_create(af_ros *ros, const af_node_config *cfg, af_ros_callback feed,
                             void *user, af_audio_in **out, const char **what)
{
  *out = NULL;
  *what = "the audio_common input";
  af_audio_in *a = calloc(1, sizeof *a);
  if (!a)
    return AF_ENOMEM;
  a->ros = ros;
  a->cfg = cfg;
  a->feed = feed;
  a->user = user;
  a->max_bytes = cap_bytes(a);
  af_wire_guard_allow(a->max_bytes);
  /* As many chunks as the SignalChunk subscription queues (station.c). */
  af_status s = af_ros_subscribe_audio_info(ros, "audio_info", on_info, on_refused, a);
  if (s == AF_OK)
    s = af_ros_subscribe_audio(ros, "audio", 1000, on_data, on_refused, &a->max_bytes, a);
  if (s != AF_OK) {
    af_audio_in_destroy(a);
    return s;
  }
  *out = a;
  return AF_OK;
}

void af_audio_in_destroy(af_audio_in *a)
{
  free(a); /* the subscriptions belong to the af_ros (NULL-safe) */
}
