/* capture_to_bag — a lab's recording as a station bag.
 *
 *   capture_to_bag --force FILE --audio FILE --apples FILE.csv --out FILE.bag [flags]
 *
 * Reads the force [N] and audio recordings (each a WAV, its rate from its
 * header, or raw little-endian float32 with an explicit rate: the loader of
 * `firmness_model analyze`, src/tools/recording.h) and the apple list
 * (apple_csv.h), and writes the bag strike_bag writes (src/demo/strike_bag.c):
 * /NS/force and /NS/audio as acoustic_firmness/SignalChunk of --chunk
 * samples (the last one shorter when the recording ends), header stamp the
 * time of the first sample, bag time that of the sample after the last;
 * frames force_transducer and microphone; /NS/apple as AppleEstimate in
 * camera_optical_frame, bag time = stamp; the three merged in bag-time
 * order. The node (replay.launch) and firmness_report read it as they read
 * strike_bag's; the recording's rates must then be the station's
 * force_sample_rate_hz and audio_sample_rate_hz (the tool says so when they
 * are not the defaults).
 *
 * Exit 0 ("wrote FILE" on stderr); 2 with one line on stderr for bad input
 * (a flag, a file, a CSV field); 1 when the bag cannot be written. */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "closeout.h"
#include "af_bag.h"
#include "apple_csv.h"
#include "options.h"
#include "recording.h"
#include "settings.h"
#include "tool_config.h"

#define AF_C2B_EXIT_USAGE 2
#define AF_C2B_ERR_MAX 1024
#define AF_C2B_START_S 1700000000 /* strike_bag's bag start [s since 1970] */
#define AF_C2B_START_MAX_S 4e9
#define AF_C2B_CHUNK 1024 /* samples per SignalChunk, as strike_bag */
#define AF_C2B_CHUNK_MIN 16
#define AF_C2B_CHUNK_MAX 65536
#define AF_C2B_OFFSET_MAX_S 3600

typedef struct {
  const char *force, *audio, *apples, *out, *ns, *audio_unit;
  double rate_force_hz, rate_audio_hz; /* 0 = the WAV header's */
  long force_channel, audio_channel;   /* 0-based */
  double force_scale, audio_scale;     /* value of full scale (integer PCM) or of 1.0 */
  double audio_offset_s;               /* audio's first sample after the force's [s] */
  uint64_t start_s;                    /* the force's first sample [s since 1970] */
  long chunk;                          /* samples per SignalChunk */
} af_c2b_args;

static af_c2b_args c2b_args_default(void)
{
  af_c2b_args a;
  memset(&a, 0, sizeof a);
  a.ns = "lane1";
  a.audio_unit = "Pa";
  a.force_scale = a.audio_scale = AF_RECORDING_SCALE_DEFAULT;
  a.start_s = AF_C2B_START_S;
  a.chunk = AF_C2B_CHUNK;
  return a;
}

#define AF_ARG(field) offsetof(af_c2b_args, field)
#define AF_C2B_RATE_RANGE "[1000, 1e6] Hz" /* the rates the station's rows accept */
static const af_option af_c2b_options[] = {
    {"--force", "FILE", AF_OPTION_TEXT, AF_ARG(force), -1, NULL,
     "force recording [N]: WAV, or raw float32 with --rate-force", NULL, false},
    {"--audio", "FILE", AF_OPTION_TEXT, AF_ARG(audio), -1, NULL,
     "audio recording [--audio-unit]: WAV, or raw float32 with --rate-audio", NULL, false},
    {"--apples", "FILE", AF_OPTION_TEXT, AF_ARG(apples), -1, NULL,
     "apple list CSV (doc/recordings.md: one row per apple)", NULL, false},
    {"--out", "FILE", AF_OPTION_TEXT, AF_ARG(out), -1, NULL, "the bag written", NULL, false},
    {"--rate-force", "HZ", AF_OPTION_NUMBER, AF_ARG(rate_force_hz), -1, AF_C2B_RATE_RANGE,
     "force sample rate; for a WAV it must equal the header's",
     "the WAV header's; required for raw float32", false},
    {"--rate-audio", "HZ", AF_OPTION_NUMBER, AF_ARG(rate_audio_hz), -1, AF_C2B_RATE_RANGE,
     "audio sample rate; for a WAV it must equal the header's",
     "the WAV header's; required for raw float32", false},
    {"--force-channel", "N", AF_OPTION_LONG, AF_ARG(force_channel), -1,
     "[0, " AF_OPTION_STR(AF_RECORDING_CHANNEL_MAX) "]", "channel of the force WAV, 0-based",
     "0, the first", false},
    {"--audio-channel", "N", AF_OPTION_LONG, AF_ARG(audio_channel), -1,
     "[0, " AF_OPTION_STR(AF_RECORDING_CHANNEL_MAX) "]", "channel of the audio WAV, 0-based",
     "0, the first", false},
    {"--force-scale", "N", AF_OPTION_NUMBER, AF_ARG(force_scale), -1,
     "(0, " AF_OPTION_STR(AF_RECORDING_SCALE_MAX) "] N",
     "force at integer full scale, or of a float sample 1.0", NULL, false},
    {"--audio-scale", "X", AF_OPTION_NUMBER, AF_ARG(audio_scale), -1,
     "(0, " AF_OPTION_STR(AF_RECORDING_SCALE_MAX) "] audio_unit",
     "audio at integer full scale, or of a float sample 1.0", NULL, false},
    {"--audio-unit", "UNIT", AF_OPTION_SETTING, 0, AF_SETTING_AUDIO_UNIT, NULL,
     "unit of the audio chunks (the station's audio_unit must match)", NULL, false},
    {"--audio-offset", "S", AF_OPTION_NUMBER, AF_ARG(audio_offset_s), -1,
     "[-" AF_OPTION_STR(AF_C2B_OFFSET_MAX_S) ", " AF_OPTION_STR(AF_C2B_OFFSET_MAX_S) "] s",
     "audio's first sample after the force's first", "0, the two start together", false},
    {"--start", "S", AF_OPTION_U64, AF_ARG(start_s), -1,
     "[1, " AF_OPTION_STR(AF_C2B_START_MAX_S) ") s", "time of the force's first sample, since 1970",
     NULL, false},
    {"--chunk", "N", AF_OPTION_LONG, AF_ARG(chunk), -1,
     "[" AF_OPTION_STR(AF_C2B_CHUNK_MIN) ", " AF_OPTION_STR(AF_C2B_CHUNK_MAX) "] samples",
     "samples per SignalChunk", NULL, false},
    {"--ns", "NAME", AF_OPTION_TEXT, AF_ARG(ns), -1, NULL,
     "lane namespace of the topics /NS/force, /NS/audio, /NS/apple", NULL, false},
};
#define AF_C2B_N_OPTIONS (sizeof af_c2b_options / sizeof af_c2b_options[0])

static void c2b_usage(FILE *out)
{
  af_c2b_args d = c2b_args_default();
  fprintf(out, "usage: capture_to_bag --force FILE --audio FILE --apples FILE.csv --out FILE.bag "
               "[flags]\n\n"
               "Writes a lab's force and audio recordings and its apple list as the bag\n"
               "strike_bag writes (/NS/force, /NS/audio: SignalChunk; /NS/apple: AppleEstimate),\n"
               "for firmness_report and for the node (replay.launch). The bag is told by a line\n"
               "\"wrote FILE\" on stderr.\n\n"
               "flags:\n");
  af_options_help(out, af_c2b_options, AF_C2B_N_OPTIONS, &d, NULL);
  fprintf(out, "\n"
               "apple list: a header row naming the columns apple_id, stamp_s, mass_kg,\n"
               "equatorial_radius_m, strike_radius_m, stem_axis_x, stem_axis_y, stem_axis_z,\n"
               "confidence (any order), then one row per apple; stamp_s is the estimate's time\n"
               "from the force's first sample [s] (the node matches a strike to the newest\n"
               "estimate stamped apple_transit_s +- apple_transit_tolerance_s before it).\n\n"
               "exit status: 0 done, 1 failure, 2 bad input\n");
}

static int c2b_bad(const char *msg)
{
  fprintf(stderr, "capture_to_bag: %s\n", msg);
  return AF_C2B_EXIT_USAGE;
}

/* --audio-unit: a value the audio_unit row accepts (checked now, kept as
 * given); false after one line. */
static bool c2b_hand(void *user, const af_option *o, const char *v)
{
  af_c2b_args *a = user;
  af_settings s;
  char arg[AF_C2B_ERR_MAX], err[AF_C2B_ERR_MAX / 2];
  (void)o; /* the one entry handed back */
  af_settings_reset(&s);
  snprintf(arg, sizeof arg, "audio_unit=%s", v);
  if (af_settings_set_arg(&s, arg, err, sizeof err) != AF_OK) {
    snprintf(arg, sizeof arg, "--audio-unit: %s", err);
    return c2b_bad(arg) == 0;
  }
  a->audio_unit = v;
  return true;
}

/* The required flags, and a namespace the topics can be made of. */
static int c2b_required(const af_c2b_args *a)
{
  const char *names[] = {"--force", "--audio", "--apples", "--out"};
  const char *values[] = {a->force, a->audio, a->apples, a->out};
  char msg[256];
  for (size_t k = 0; k < 4; k++)
    if (values[k] == NULL || values[k][0] == '\0') {
      snprintf(msg, sizeof msg, "%s is required (capture_to_bag --help)", names[k]);
      return c2b_bad(msg);
    }
  size_t n = strlen(a->ns);
  if (n == 0 || n > 64 ||
      strspn(a->ns, "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ"
                    "0123456789_/") != n ||
      a->ns[0] == '/' || a->ns[n - 1] == '/' || strstr(a->ns, "//") != NULL) {
    snprintf(msg, sizeof msg,
             "--ns '%.80s' must be a namespace of letters, digits, _ and inner / "
             "(1 to 64 characters)",
             a->ns);
    return c2b_bad(msg);
  }
  return 0;
}

static int c2b_parse(int argc, char **argv, af_c2b_args *a)
{
  *a = c2b_args_default();
  const af_options_parser p = {
      "capture_to_bag", {{af_c2b_options, AF_C2B_N_OPTIONS, a, c2b_hand, a}}, 1, NULL, false};
  if (!af_options_parse(&p, argc, argv, 1))
    return AF_C2B_EXIT_USAGE;
  return c2b_required(a);
}

/* ---- the recordings ------------------------------------------------------------ */

/* One input: its samples, rate and place in the bag. */
typedef struct {
  af_recording rec;
  double rate_hz;
  int64_t offset_ns; /* first sample after the force's first [ns] */
  size_t next;       /* first sample of the next chunk */
  char topic[128];
  const char *frame, *unit;
} af_c2b_stream;

/* Loads one recording; 0, or the exit status after one line. */
static int c2b_load(const char *path, const char *what, double rate_flag_hz, long channel,
                    double scale, af_c2b_stream *st)
{
  char err[AF_C2B_ERR_MAX], msg[AF_C2B_ERR_MAX + 64];
  af_recording_spec spec =
      af_recording_spec_default(what[0] == 'f' ? "--rate-force" : "--rate-audio",
                                what[0] == 'f' ? "--force-channel" : "--audio-channel");
  spec.rate_hz = rate_flag_hz;
  spec.channel = channel;
  spec.scale = scale;
  af_status s = af_recording_load(path, &spec, &st->rec, &st->rate_hz, err, sizeof err);
  if (s != AF_OK) {
    snprintf(msg, sizeof msg, "--%s %s", what, err);
    return c2b_bad(msg);
  }
  if (st->rec.n == 0 || !(st->rate_hz >= 1000.0 && st->rate_hz <= 1e6)) {
    snprintf(msg, sizeof msg, "--%s %s: %s", what, path,
             st->rec.n == 0 ? "holds no samples" : "its rate is outside [1000, 1e6] Hz");
    return c2b_bad(msg);
  }
  return 0;
}

/* ---- writing ---------------------------------------------------------------------- */

static af_time c2b_time(uint64_t start_s, int64_t rel_ns)
{
  int64_t abs_ns = (int64_t)start_s * 1000000000LL + rel_ns;
  af_time t = {(uint32_t)(abs_ns / 1000000000LL), (uint32_t)(abs_ns % 1000000000LL)};
  return t;
}

/* Time of sample k of st from the force's first sample [ns]. */
static int64_t c2b_sample_ns(const af_c2b_stream *st, size_t k)
{
  return st->offset_ns + (int64_t)llround((double)k / st->rate_hz * 1e9);
}

static size_t c2b_chunk_len(const af_c2b_stream *st, size_t chunk)
{
  size_t left = st->rec.n - st->next;
  return left < chunk ? left : chunk;
}

/* Bag time of st's next chunk (the sample after its last) [ns]; INT64_MAX at the end. */
static int64_t c2b_due_ns(const af_c2b_stream *st, size_t chunk)
{
  if (st->next >= st->rec.n)
    return INT64_MAX;
  return c2b_sample_ns(st, st->next + c2b_chunk_len(st, chunk));
}

static af_status c2b_write_chunk(af_bag *bag, af_c2b_stream *st, const af_c2b_args *a)
{
  af_signal_chunk c;
  memset(&c, 0, sizeof c);
  size_t n = c2b_chunk_len(st, (size_t)a->chunk);
  c.header.stamp = c2b_time(a->start_s, c2b_sample_ns(st, st->next));
  snprintf(c.header.frame_id, sizeof c.header.frame_id, "%s", st->frame);
  c.first_sample = st->next;
  c.sample_rate_hz = st->rate_hz;
  snprintf(c.unit, sizeof c.unit, "%s", st->unit);
  c.data = st->rec.x + st->next;
  c.n = n;
  af_time at = c2b_time(a->start_s, c2b_due_ns(st, (size_t)a->chunk));
  st->next += n;
  return af_bag_write(bag, st->topic, AF_MSG_SIGNAL_CHUNK, &c, at);
}

static af_status c2b_write_apple(af_bag *bag, const char *topic, const af_csv_apple *p,
                                 const af_c2b_args *a)
{
  af_apple_estimate e;
  memset(&e, 0, sizeof e);
  e.header.stamp = c2b_time(a->start_s, (int64_t)llround(p->stamp_s * 1e9));
  snprintf(e.header.frame_id, sizeof e.header.frame_id, "camera_optical_frame");
  e.apple_id = p->apple_id;
  e.mass_kg = p->mass_kg;
  e.equatorial_radius_m = p->equatorial_radius_m;
  e.strike_radius_m = p->strike_radius_m;
  e.stem_axis.x = p->stem_axis[0];
  e.stem_axis.y = p->stem_axis[1];
  e.stem_axis.z = p->stem_axis[2];
  e.confidence = p->confidence;
  return af_bag_write(bag, topic, AF_MSG_APPLE_ESTIMATE, &e, e.header.stamp);
}

/* The three streams merged in bag-time order (apple, then force, then
 * audio at equal times, as strike_bag). */
static af_status c2b_merge(af_bag *bag, af_c2b_stream *s, const af_csv_apple *apples,
                           size_t n_apples, const char *apple_topic, const af_c2b_args *a)
{
  size_t next_apple = 0;
  af_status st = AF_OK;
  while (st == AF_OK) {
    int64_t tf = c2b_due_ns(&s[0], (size_t)a->chunk);
    int64_t ta = c2b_due_ns(&s[1], (size_t)a->chunk);
    int64_t tp = next_apple < n_apples ? llround(apples[next_apple].stamp_s * 1e9) : INT64_MAX;
    if (tf == INT64_MAX && ta == INT64_MAX && tp == INT64_MAX)
      break;
    if (tp <= tf && tp <= ta)
      st = c2b_write_apple(bag, apple_topic, &apples[next_apple++], a);
    else
      st = c2b_write_chunk(bag, &s[tf <= ta ? 0 : 1], a);
  }
  return st;
}

static int c2b_write(const af_c2b_args *a, af_c2b_stream *s, const af_csv_apple *apples,
                     size_t n_apples)
{
  char apple_topic[128];
  snprintf(s[0].topic, sizeof s[0].topic, "/%s/force", a->ns);
  snprintf(s[1].topic, sizeof s[1].topic, "/%s/audio", a->ns);
  snprintf(apple_topic, sizeof apple_topic, "/%s/apple", a->ns);
  af_bag *bag = NULL;
  af_status st = af_bag_open_write(a->out, &bag);
  if (st != AF_OK) {
    fprintf(stderr, "capture_to_bag: --out %s: %s (%s)\n", a->out, af_strerror(st),
            af_bag_last_error(NULL));
    return st == AF_EIO ? AF_C2B_EXIT_USAGE : 1;
  }
  st = c2b_merge(bag, s, apples, n_apples, apple_topic, a);
  if (st == AF_EIO) { /* the file failed (a full disk): the close removes the partial bag */
    (void)af_bag_close(bag);
    fprintf(stderr, "capture_to_bag: cannot write %s\n", af_bag_last_error(NULL));
    return 1;
  }
  if (st != AF_OK) {
    fprintf(stderr, "capture_to_bag: writing %s: %s (%s)\n", a->out, af_strerror(st),
            af_bag_last_error(bag));
    af_bag_close(bag);
    return 1;
  }
  if (af_bag_close(bag) != AF_OK) {
    fprintf(stderr, "capture_to_bag: cannot write %s\n", af_bag_last_error(NULL));
    return 1;
  }
  return 0;
}

/* What the station must be told to read the bag, when not its defaults. */
static void c2b_station_note(const af_c2b_args *a, const af_c2b_stream *s)
{
  af_settings d;
  af_settings_reset(&d);
  double f_hz = af_settings_number(&d, AF_SETTING_FORCE_SAMPLE_RATE_HZ);
  double a_hz = af_settings_number(&d, AF_SETTING_AUDIO_SAMPLE_RATE_HZ);
  char unit[16] = "";
  (void)af_settings_choice(&d, AF_SETTING_AUDIO_UNIT, unit, sizeof unit);
  if (s[0].rate_hz == f_hz && s[1].rate_hz == a_hz && strcmp(unit, a->audio_unit) == 0)
    return;
  printf("capture_to_bag: the station reads this bag with force_sample_rate_hz=%.17g "
         "audio_sample_rate_hz=%.17g audio_unit=%s (defaults %g, %g, %s): e.g. "
         "firmness_report BAG --set force_sample_rate_hz=%.17g --set audio_sample_rate_hz=%.17g "
         "--set audio_unit=%s\n",
         s[0].rate_hz, s[1].rate_hz, a->audio_unit, f_hz, a_hz, unit, s[0].rate_hz, s[1].rate_hz,
         a->audio_unit);
}

/* The station (its defaults at the recording's rates and audio unit, as
 * c2b_station_note tells it to read the bag) takes chunks up to each
 * stream's ring (lane_config.h, max_chunk_samples): with a longer --chunk it
 * would refuse every chunk of that stream. 2 with one line, else 0; when
 * the station refuses its defaults at these rates, a note and 0 (the lab
 * will give it other settings). */
static int c2b_check_chunk(const af_c2b_args *a, const af_c2b_stream *s)
{
  static af_lane_config cfg; /* large; main's one call */
  af_settings d;
  char err[AF_C2B_ERR_MAX / 2], arg[96];
  af_settings_reset(&d);
  snprintf(arg, sizeof arg, "force_sample_rate_hz=%.17g", s[0].rate_hz);
  af_status st = af_settings_set_arg(&d, arg, err, sizeof err);
  snprintf(arg, sizeof arg, "audio_sample_rate_hz=%.17g", s[1].rate_hz);
  if (st == AF_OK)
    st = af_settings_set_arg(&d, arg, err, sizeof err);
  snprintf(arg, sizeof arg, "audio_unit=%s", a->audio_unit);
  if (st == AF_OK)
    st = af_settings_set_arg(&d, arg, err, sizeof err);
  if (st == AF_OK)
    st = af_lane_config_for_tool(&d, &cfg, err, sizeof err);
  if (st != AF_OK) {
    fprintf(stderr,
            "capture_to_bag: note: the station's defaults at these rates are refused (%s)\n", err);
    return 0;
  }
  for (int k = 0; k < 2; k++) {
    const af_stream_config *sc = k == 0 ? &cfg.force : &cfg.audio;
    if ((size_t)a->chunk <= sc->max_chunk_samples)
      continue;
    char msg[AF_C2B_ERR_MAX];
    snprintf(msg, sizeof msg,
             "--chunk %ld: a %s chunk of %g s at %.17g Hz is longer than the station's %s ring "
             "(%s_buffer_s = %g s, %zu samples), and the station refuses every longer chunk: "
             "--chunk at most %zu",
             a->chunk, k == 0 ? "force" : "audio", (double)a->chunk / sc->sample_rate_hz,
             sc->sample_rate_hz, k == 0 ? "force" : "audio", k == 0 ? "force" : "audio",
             sc->buffer_s, sc->max_chunk_samples,
             cfg.force.max_chunk_samples < cfg.audio.max_chunk_samples
                 ? cfg.force.max_chunk_samples
                 : cfg.audio.max_chunk_samples);
    return c2b_bad(msg);
  }
  return 0;
}

static int c2b_run(const af_c2b_args *a, af_c2b_stream *s)
{
  int rc = c2b_load(a->force, "force", a->rate_force_hz, a->force_channel, a->force_scale, &s[0]);
  if (rc == 0)
    rc = c2b_load(a->audio, "audio", a->rate_audio_hz, a->audio_channel, a->audio_scale, &s[1]);
  if (rc != 0)
    return rc;
  s[0].frame = "force_transducer", s[0].unit = "N";
  s[1].frame = "microphone", s[1].unit = a->audio_unit;
  s[1].offset_ns = (int64_t)llround(a->audio_offset_s * 1e9);
  rc = c2b_check_chunk(a, s);
  if (rc != 0)
    return rc;
  if (s[1].offset_ns < -(int64_t)a->start_s * 1000000000LL + 1)
    return c2b_bad("--audio-offset: the audio would start before 1970 (raise --start)");
  const double force_s = (double)s[0].rec.n / s[0].rate_hz;
  af_csv_apple *apples = NULL;
  size_t n_apples = 0;
  char err[AF_C2B_ERR_MAX];
  if (af_apple_csv_read(a->apples, 0.0, force_s, &apples, &n_apples, err, sizeof err) != AF_OK) {
    char msg[AF_C2B_ERR_MAX + 16];
    snprintf(msg, sizeof msg, "--apples %s", err);
    return c2b_bad(msg);
  }
  rc = c2b_write(a, s, apples, n_apples);
  if (rc == 0) {
    printf("capture_to_bag: %zu apples; force %zu samples at %.17g Hz (%.3f s), audio %zu at "
           "%.17g Hz from %+.6f s; chunks of %ld on /%s/force, /%s/audio, /%s/apple\n",
           n_apples, s[0].rec.n, s[0].rate_hz, force_s, s[1].rec.n, s[1].rate_hz, a->audio_offset_s,
           a->chunk, a->ns, a->ns, a->ns);
    c2b_station_note(a, s);
    af_options_wrote(a->out);
  }
  free(apples);
  return rc;
}

int main(int argc, char **argv)
{
  af_closeout_install("capture_to_bag");
  if (!af_options_args_plain("capture_to_bag", argc, argv))
    return 2;
  if (af_options_want_help(argc, argv, 1)) {
    c2b_usage(stdout);
    return 0;
  }
  af_c2b_args a;
  int rc = c2b_parse(argc, argv, &a);
  if (rc != 0)
    return rc;
  af_c2b_stream s[2];
  memset(s, 0, sizeof s);
  rc = c2b_run(&a, s);
  af_recording_destroy(&s[0].rec);
  af_recording_destroy(&s[1].rec);
  return rc;
}
