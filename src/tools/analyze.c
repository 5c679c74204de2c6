/* analyze.c — `firmness_model analyze`: a recording judged as the node judges
 * it live.
 *
 * Reads the force [N] and the audio (any unit), each a WAV (its rate from
 * its header; --force-channel/--audio-channel, --force-scale/--audio-scale)
 * or raw little-endian float32 (--rate-force/--rate-audio), through
 * recording.h; configures the lane from the same YAML files the node loads
 * (--config, --cultivar, defaulting to the shipped config/station.yaml and
 * config/jonagold.yaml; --set name=value for any row of the parameter table),
 * gives it one apple (--mass, --R2) stamped at the recording's start, and
 * feeds both recordings to the core lane (src/core/lane/lane.h) in 1024-sample
 * chunks in time order, as the node receives SignalChunks. Prints one JSON
 * object: the strikes, each the lane's whole result written by the core
 * serializer (serialize.h: the StrikeReport's names, stamp_ns from the
 * recording's start, %.17g), and why there are none when there are none.
 *
 * Tap-only (--tap-only, or tap_only true in a file or --set): the audio
 * alone, no --force; the strikes are the audio's onsets (onset.h), the
 * detector's floor primed from the whole recording. */
#define _POSIX_C_SOURCE 200809L
#include "analyze.h"

#include <errno.h>
#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "cli_flags.h"
#include "json.h"
#include "serialize.h"
#include "lane.h"
#include "options.h"
#include "recording.h"
#include "lamb.h"
#include "settings.h"

#define AF_ANALYZE_CHUNK 1024 /* samples per chunk, as the node's SignalChunks */
/* An integer force WAV's strike_threshold_min_n is at least this many steps
 * of its format: a flicker of one step is the converter's, not a strike. */
#define AF_ANALYZE_FORCE_STEPS 2.0
/* --audio-offset: the audio's start within an hour of the force's (the
 * stamps are integer nanoseconds: beyond ~9e9 s they would overflow). */
#define AF_ANALYZE_OFFSET_MAX_S 3600
/* Strike rows held at most: a 45-minute recording (AF_RECORDING_MAX_SAMPLES
 * at 50 kHz) struck twice a second has 5400. */
#define AF_ANALYZE_MAX_STRIKES ((size_t)100000)
#define AF_ERR_MAX 512

#ifndef AF_CONFIG_DIR /* set by CMakeLists.txt: the package's config/ */
#define AF_CONFIG_DIR "config"
#endif

typedef struct {
  const char *force_path, *audio_path;
  const char *config_path, *cultivar_path;
  double rate_force_hz, rate_audio_hz;      /* the flags', then the files' [Hz] */
  af_recording_spec force_spec, audio_spec; /* channel and scale flags */
  double audio_offset_s;                    /* audio start time minus force start time [s] */
  double mass_kg, r2_m, equatorial_radius_m;
  long max_samples; /* per recording, checked before reading it [samples] */
  bool bench;
  bool tap_only; /* --tap-only: the audio alone (the tap_only row) */
} af_analyze_args;

/* The callback's context: the lane's strike results (their borrowed pointers
 * cleared), stored in a buffer sized at start-up. */
typedef struct {
  af_lane_strike *rows;
  size_t n_rows, cap_rows, dropped;
  size_t room; /* rows allocated: the largest cap_rows of the session's runs */
} af_analyze_ctx;

/* What a session keeps from run to run (analyze.h): the flags, the YAML
 * files as read, the lane and the configuration it points into. */
struct af_analyze_session {
  int argc;
  char **argv;
  int first;
  af_analyze_args flags; /* as parsed; each run's copy takes the files' rates */
  af_settings files;     /* the YAML files and the rig's hammer, read at the first run */
  bool files_read;
  af_settings derived_from; /* the last run's settings, when have_derived */
  af_lane_config derived;   /* what af_lane_config_derive made of them */
  bool have_derived;
  af_lane_config cfg; /* the lane's: it reads it, so it lives here */
  af_lane *lane;      /* NULL until a run makes it */
  af_analyze_ctx ctx;
};

static double cpu_time_s(void)
{
  struct timespec ts;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static int print_usage(const char *fmt, const char *a, const char *b)
{
  fprintf(stderr, "firmness_model analyze: ");
  fprintf(stderr, fmt, a, b);
  fputc('\n', stderr);
  return AF_CLI_EXIT_USAGE;
}

/* ---- arguments ------------------------------------------------------------- */

/* The defaults the parser starts from: the shipped YAML files, the
 * recordings' channels and scales as recording.h leaves them; the
 * recordings and the apple are required (0 / NULL), the rates when a
 * recording is raw float32. */
static af_analyze_args analyze_args_default(void)
{
  af_analyze_args a;
  memset(&a, 0, sizeof a);
  a.force_spec = af_recording_spec_default("--rate-force", "--force-channel");
  a.audio_spec = af_recording_spec_default("--rate-audio", "--audio-channel");
  a.force_spec.channel = a.audio_spec.channel = 0; /* as -1 (not given): the first */
  a.max_samples = (long)AF_RECORDING_DEFAULT_MAX_SAMPLES;
  a.config_path = AF_CONFIG_DIR "/station.yaml";
  a.cultivar_path = AF_CONFIG_DIR "/jonagold.yaml";
  return a;
}

#define AF_ARG(field) offsetof(af_analyze_args, field)
#define AF_ROW(flag, value, id)                                                                    \
  {                                                                                                \
    flag, value, AF_OPTION_SETTING, 0, id, NULL, NULL, NULL, false                                 \
  }
/* The rates and the apple need only be positive here: their physical ranges
 * are the parameter table's, checked with the files' values (later). */
#define AF_POSITIVE(unit) "(0, inf) " unit
/* Every flag of analyze: its own (files, rates, the apple), then those that
 * set a row of the parameter table (applied after the files: later =
 * stronger). The parser knows no other; --help prints each. */
static const af_option analyze_options[] = {
    {"--force", "FILE", AF_OPTION_TEXT, AF_ARG(force_path), -1, NULL,
     "force recording, WAV or raw little-endian float32 [N]", NULL, false},
    {"--audio", "FILE", AF_OPTION_TEXT, AF_ARG(audio_path), -1, NULL,
     "audio recording, WAV or raw little-endian float32 [the station's audio_unit]", NULL, false},
    {"--rate-force", "HZ", AF_OPTION_NUMBER, AF_ARG(rate_force_hz), -1, AF_POSITIVE("Hz"),
     "force sample rate, must agree with a WAV header",
     "the WAV header's; required for raw float32", false},
    {"--rate-audio", "HZ", AF_OPTION_NUMBER, AF_ARG(rate_audio_hz), -1, AF_POSITIVE("Hz"),
     "audio sample rate, must agree with a WAV header",
     "the WAV header's; required for raw float32", false},
    {"--force-channel", "N", AF_OPTION_LONG, AF_ARG(force_spec.channel), -1,
     "[0, " AF_OPTION_STR(AF_RECORDING_CHANNEL_MAX) "]",
     "channel of a multichannel force WAV, 0-based, below the file's channels", "0, the first",
     false},
    {"--audio-channel", "N", AF_OPTION_LONG, AF_ARG(audio_spec.channel), -1,
     "[0, " AF_OPTION_STR(AF_RECORDING_CHANNEL_MAX) "]",
     "channel of a multichannel audio WAV, 0-based, below the file's channels", "0, the first",
     false},
    {"--force-scale", "X", AF_OPTION_NUMBER, AF_ARG(force_spec.scale), -1,
     "(0, " AF_OPTION_STR(AF_RECORDING_SCALE_MAX) "] N",
     "force of a full-scale PCM sample or a float sample 1.0", NULL, false},
    {"--audio-scale", "X", AF_OPTION_NUMBER, AF_ARG(audio_spec.scale), -1,
     "(0, " AF_OPTION_STR(AF_RECORDING_SCALE_MAX) "] audio_unit",
     "audio of a full-scale PCM sample or a float sample 1.0", NULL, false},
    {"--audio-offset", "S", AF_OPTION_NUMBER, AF_ARG(audio_offset_s), -1,
     "[-" AF_OPTION_STR(AF_ANALYZE_OFFSET_MAX_S) ", " AF_OPTION_STR(AF_ANALYZE_OFFSET_MAX_S) "] s",
     "audio start minus force start", "none, the two start together", false},
    {"--mass", "KG", AF_OPTION_NUMBER, AF_ARG(mass_kg), -1, AF_POSITIVE("kg"), "the apple's mass",
     NULL, false},
    {"--R2", "M", AF_OPTION_NUMBER, AF_ARG(r2_m), -1, AF_POSITIVE("m"),
     "the apple's radius of curvature under the hammer", NULL, false},
    {"--equatorial-radius", "M", AF_OPTION_NUMBER, AF_ARG(equatorial_radius_m), -1,
     AF_POSITIVE("m"), "the apple's equatorial radius",
     "the sphere of --mass at the cultivar's density", false},
    {"--config", "FILE", AF_OPTION_TEXT, AF_ARG(config_path), -1, NULL,
     "station parameters (YAML), as the node loads them", NULL, false},
    {"--cultivar", "FILE", AF_OPTION_TEXT, AF_ARG(cultivar_path), -1, NULL,
     "cultivar parameters (YAML), as the node loads them", NULL, false},
    {"--max-samples", "N", AF_OPTION_LONG, AF_ARG(max_samples), -1,
     "[1, " AF_OPTION_STR(AF_RECORDING_MAX_SAMPLES_N) "] samples",
     "longest recording read, each; a longer one is refused before it is read (2^24 samples "
     "are 64 MiB of float32)",
     NULL, false},
    {"--bench", NULL, AF_OPTION_SWITCH, AF_ARG(bench), -1, NULL,
     "CPU time and speed against real time, on stderr", NULL, false},
    {"--tap-only", NULL, AF_OPTION_SWITCH, AF_ARG(tap_only), -1, NULL,
     "a microphone-only rig: sets tap_only; strikes from the audio onset, no --force", NULL, false},
    {"--set", "NAME=VALUE", AF_OPTION_NONE, 0, -1, NULL,
     "any row of the parameter table, after the files (repeatable)", "the files' values", true},
    {"--profile", "default|paper", AF_OPTION_NONE, 0, -1, NULL,
     "paper: the paper-literal criterion (damping paper, lobe 2, power-half, shear paper)",
     "the files' values", false},
    AF_ROW("--hammer-mass", "KG", AF_SETTING_HAMMER_MASS_KG),
    AF_ROW("--hammer-radius", "M", AF_SETTING_HAMMER_TIP_RADIUS_M),
    AF_ROW("--modulus-min", "PA", AF_SETTING_MODULUS_MIN_PA),
    AF_ROW("--modulus-max", "PA", AF_SETTING_MODULUS_MAX_PA),
    AF_ROW("--E2", "PA", AF_SETTING_MODULUS_NOMINAL_PA),
    AF_ROW("--e", "X", AF_SETTING_RESTITUTION),
    AF_ROW("--v0", "M/S", AF_SETTING_STRIKE_VELOCITY_M_S),
    AF_ROW("--snr-threshold", "DB", AF_SETTING_MEASURE_SNR_THRESHOLD_DB),
    AF_ROW("--nu2", "X", AF_SETTING_FRUIT_POISSON),
    AF_ROW("--density", "KG/M3", AF_SETTING_DENSITY_KG_M3),
    AF_ROW("--yield-ratio", "X", AF_SETTING_YIELD_RATIO),
    AF_ROW("--modulus-factor", "X", AF_SETTING_MODULUS_FACTOR),
};
#define AF_N_OPTIONS (sizeof analyze_options / sizeof analyze_options[0])

const af_option *af_analyze_options(size_t *n)
{
  *n = AF_N_OPTIONS;
  return analyze_options;
}

/* "--flag value" as "row=value" into s; false after a message naming both. */
static bool set_row(af_settings *s, const char *flag, const char *row, const char *value)
{
  char arg[AF_SETTINGS_TEXT_MAX + 64], err[AF_ERR_MAX];
  snprintf(arg, sizeof arg, "%s=%s", row, value);
  if (af_settings_set_arg(s, arg, err, sizeof err) == AF_OK)
    return true;
  fprintf(stderr, "firmness_model analyze: %s: %s\n", flag, err);
  return false;
}

/* --profile paper: the paper-literal criterion settings, af_model_params_paper's
 * choices (model.h) written as the table's rows. */
static bool set_profile(af_settings *s, const char *name)
{
  if (strcmp(name, "default") == 0)
    return true;
  if (strcmp(name, "paper") != 0) {
    fprintf(stderr, "firmness_model analyze: --profile '%s' is not one of: default, paper\n", name);
    return false;
  }
  const af_model_params paper = af_model_params_paper();
  char lobe[16];
  snprintf(lobe, sizeof lobe, "%u", paper.lobe);
  const char *const rows[][2] = {{"damping_law", af_damping_law_name(paper.impact.damping)},
                                 {"lobe", lobe},
                                 {"band_level", af_band_level_name(paper.band_level)},
                                 {"shear_ratio", af_shear_ratio_name(paper.shear_ratio)}};
  for (size_t k = 0; k < sizeof rows / sizeof rows[0]; k++)
    if (!set_row(s, "--profile", rows[k][0], rows[k][1]))
      return false;
  return true;
}

/* A flag the parser hands back (--set, --profile, a parameter row), applied
 * to the settings after the files; false after a message. */
static bool apply_settings_flag(void *user, const af_option *o, const char *value)
{
  af_settings *s = user;
  if (strcmp(o->name, "--set") == 0) {
    char err[AF_ERR_MAX];
    if (af_settings_set_arg(s, value, err, sizeof err) == AF_OK)
      return true;
    fprintf(stderr, "firmness_model analyze: --set %s: %s\n", value, err);
    return false;
  }
  if (strcmp(o->name, "--profile") == 0)
    return set_profile(s, value);
  return set_row(s, o->name, af_setting_def_of((af_setting_id)o->setting)->name, value);
}

/* The flags into a (s NULL: the settings flags are only checked to have a
 * value), or, a second pass after the files (a NULL), the settings flags into s. */
static bool analyze_parse(int argc, char **argv, int first, af_analyze_args *a, af_settings *s)
{
  const af_options_parser p = {
      "firmness_model analyze",
      {{analyze_options, AF_N_OPTIONS, a, s ? apply_settings_flag : NULL, s}},
      1,
      NULL,
      false};
  return af_options_parse(&p, argc, argv, first);
}

/* First pass: files, rates, the apple; every flag must be known and have a
 * value. */
static bool parse_args(int argc, char **argv, int first, af_analyze_args *a)
{
  *a = analyze_args_default();
  if (!analyze_parse(argc, argv, first, a, NULL))
    return false;
  /* The rates: a WAV's header gives them (analyze_load). */
  /* --force may be missing when tap_only comes from a file: checked after
   * the settings (analyze_inputs). */
  const char *missing = !a->audio_path ? "--audio FILE"
                        : !a->mass_kg  ? "--mass KG (the apple's)"
                        : !a->r2_m     ? "--R2 M (the apple's)"
                                       : NULL;
  if (missing != NULL) {
    fprintf(stderr, "firmness_model analyze: %s is required\n", missing);
    return false;
  }
  return true;
}

/* ---- configuration --------------------------------------------------------- */

/* Table defaults, the two files, the hammer when no file gives it: what
 * the flags then change (and what --help shows as their defaults). */
static bool analyze_files(const af_analyze_args *a, af_settings *s)
{
  char err[AF_ERR_MAX];
  af_settings_reset(s);
  if (af_settings_load_yaml(s, a->config_path, err, sizeof err) != AF_OK ||
      af_settings_load_yaml(s, a->cultivar_path, err, sizeof err) != AF_OK) {
    fprintf(stderr, "firmness_model analyze: %s\n", err);
    return false;
  }
  /* The node reads the hammer from the rig's URDF; this tool cannot, and
   * takes the shipped rig's hammer (the table's rig values) unless a file
   * or a flag gives it. */
  if (af_settings_use_rig_hammer(s, err, sizeof err) != AF_OK) {
    fprintf(stderr, "firmness_model analyze: %s\n", err);
    return false;
  }
  return true;
}

/* The settings the node would run with: the files (read once a session),
 * the recordings' rates, then the flags. */
static bool analyze_settings(af_analyze_session *ss, const af_analyze_args *a, af_settings *s)
{
  char rate[64];
  if (!ss->files_read && !analyze_files(a, &ss->files))
    return false;
  ss->files_read = true;
  *s = ss->files;
  snprintf(rate, sizeof rate, "%.17g", a->rate_force_hz);
  if (a->force_path != NULL && !set_row(s, "--rate-force", "force_sample_rate_hz", rate))
    return false;
  if (a->tap_only && !set_row(s, "--tap-only", "tap_only", "true"))
    return false;
  snprintf(rate, sizeof rate, "%.17g", a->rate_audio_hz);
  if (!set_row(s, "--rate-audio", "audio_sample_rate_hz", rate))
    return false;
  /* The settings flags, in order (parse_args checked the rest). */
  return analyze_parse(ss->argc, ss->argv, ss->first, NULL, s);
}

/* ---- the lane's strikes --------------------------------------------------------- */

static void on_strike(const af_lane_strike *s, void *user)
{
  af_analyze_ctx *c = user;
  if (c->n_rows == c->cap_rows) {
    c->dropped++;
    return;
  }
  af_lane_strike *row = &c->rows[c->n_rows++];
  *row = *s;
  row->apple = NULL, row->prediction = NULL, row->event = NULL; /* the lane's, for the call */
}

/* ---- output ------------------------------------------------------------------ */

/* One strike: every field of the serializer (serialize.h), one per line. */
static void json_row(FILE *out, const af_lane_strike *row, bool last)
{
  const af_serial_strike v = af_serial_of_lane(row);
  fputs("    {\n      ", out);
  af_serialize_json_members(out, &v, ",\n      ");
  fprintf(out, "\n    }%s\n", last ? "" : ",");
}

/* A stream's counts: what was refused is never silent. */
static void json_stream(FILE *out, const char *key, const af_stream *s, bool last)
{
  fprintf(out,
          "    \"%s\": {\"chunks\": %llu, \"refused_samples\": %llu, \"refused_spans\": %llu, "
          "\"bad_chunks\": %llu, \"gaps\": %llu, \"lost_samples\": %llu}%s\n",
          key, (unsigned long long)s->chunks, (unsigned long long)s->refused_samples,
          (unsigned long long)s->refused_spans, (unsigned long long)af_stream_bad_chunks(s),
          (unsigned long long)s->gaps, (unsigned long long)s->lost_samples, last ? "" : ",");
}

/* One line on stderr per stream with refused samples. */
static void warn_refused(const af_stream *s, const char *path)
{
  if (s->refused_samples > 0)
    fprintf(stderr,
            "firmness_model analyze: %s: %llu non-finite samples refused in %llu spans (held as "
            "lost; a strike that meets them is flagged)\n",
            path, (unsigned long long)s->refused_samples, (unsigned long long)s->refused_spans);
}

static void json_print(FILE *out, const af_analyze_ctx *c, const af_lane *lane,
                       const char *no_strike)
{
  fputs("{\n  \"strikes\": [", out);
  if (c->n_rows > 0)
    fputc('\n', out);
  for (size_t k = 0; k < c->n_rows; k++)
    json_row(out, &c->rows[k], k + 1 == c->n_rows);
  fputs(c->n_rows > 0 ? "  ],\n" : "],\n", out);
  fputs("  \"streams\": {\n", out);
  json_stream(out, "force", af_lane_force_stream(lane), false);
  json_stream(out, "audio", af_lane_audio_stream(lane), true);
  fputs("  },\n  \"no_strike_reason\": ", out);
  if (no_strike)
    af_json_string(out, no_strike);
  else
    fputs("null", out);
  fputs("\n}\n", out);
}

/* ---- the run ----------------------------------------------------------------- */

/* The apple of the whole recording, stamped at its start. */
static af_apple analyze_apple(const af_analyze_args *a, const af_lane_config *cfg)
{
  af_apple ap;
  memset(&ap, 0, sizeof ap);
  ap.apple_id = 1;
  ap.stamp_ns = (int64_t)llround(fmin(0.0, a->audio_offset_s) * 1e9);
  ap.mass_kg = a->mass_kg;
  /* Unknown: the sphere of this mass at the cultivar's density (aspect 1). */
  ap.equatorial_radius_m =
      a->equatorial_radius_m > 0.0
          ? a->equatorial_radius_m
          : af_lamb_sphere_radius_m(a->mass_kg, cfg->model.fruit_density_kg_m3);
  ap.strike_radius_m = a->r2_m;
  ap.confidence = 1.0;
  snprintf(ap.direction_note, sizeof ap.direction_note, "strike direction not recorded");
  return ap;
}

/* Both recordings into the lane in time order, chunk by chunk; the lane's
 * clock is the end of the latest chunk. */
static void feed(af_lane *lane, const af_analyze_args *a, const af_lane_config *cfg,
                 const af_recording *force, const af_recording *audio)
{
  size_t kf = 0, ka = 0;
  const int64_t offset_ns = (int64_t)llround(a->audio_offset_s * 1e9);
  while (kf < force->n || ka < audio->n) {
    int64_t tf = (int64_t)llround((double)kf / a->rate_force_hz * 1e9);
    int64_t ta = offset_ns + (int64_t)llround((double)ka / a->rate_audio_hz * 1e9);
    const bool force_left = kf < force->n, audio_left = ka < audio->n;
    const bool take_force = force_left && (!audio_left || tf <= ta);
    const af_recording *r = take_force ? force : audio;
    size_t *k = take_force ? &kf : &ka;
    double rate = take_force ? a->rate_force_hz : a->rate_audio_hz;
    size_t n = r->n - *k < AF_ANALYZE_CHUNK ? r->n - *k : AF_ANALYZE_CHUNK;
    const char *unit = take_force ? cfg->force.units[0] : cfg->audio.units[0];
    af_chunk c = {take_force ? tf : ta, *k, rate, unit, NULL, r->x + *k, n};
    int64_t now = c.stamp_ns + (int64_t)llround((double)n / rate * 1e9);
    if (take_force)
      af_lane_force(lane, &c, now, NULL);
    else
      af_lane_audio(lane, &c, now, NULL);
    *k += n;
  }
  af_lane_finish(lane);
}

static void print_bench(double rate_hz, const af_analyze_ctx *c, double cpu_s, size_t n)
{
  double seconds = (double)n / rate_hz;
  fprintf(stderr,
          "bench: %zu strikes in %.3f s of recording: %.1f ms CPU, %.0f x real time on one "
          "core\n",
          c->n_rows, seconds, 1e3 * cpu_s, cpu_s > 0.0 ? seconds / cpu_s : INFINITY);
}

/* What the force holds, read independently of the detector so that the
 * reason can name a force with no finite sample or one of the wrong sign:
 * the count of finite samples, and the largest excursions either side of
 * their median [N] with the samples they are at. */
typedef struct {
  size_t finite;
  double up_n, down_n; /* >= 0 and <= 0 [N] */
  size_t up_at, down_at;
} af_force_survey;

static int cmp_float(const void *a, const void *b)
{
  const float x = *(const float *)a, y = *(const float *)b;
  return (x > y) - (x < y);
}

/* false: out of memory for the median's copy (nothing said then). */
static bool survey_force(const af_recording *force, af_force_survey *out)
{
  *out = (af_force_survey){0};
  float *sorted = malloc((force->n > 0 ? force->n : 1) * sizeof *sorted);
  if (sorted == NULL)
    return false;
  for (size_t k = 0; k < force->n; k++)
    if (isfinite(force->x[k]))
      sorted[out->finite++] = force->x[k];
  if (out->finite > 0) {
    qsort(sorted, out->finite, sizeof *sorted, cmp_float);
    const double median = sorted[out->finite / 2];
    for (size_t k = 0; k < force->n; k++) {
      const double e = (double)force->x[k] - median;
      if (!isfinite(e))
        continue;
      if (e > out->up_n) {
        out->up_n = e;
        out->up_at = k;
      } else if (e < out->down_n) {
        out->down_n = e;
        out->down_at = k;
      }
    }
  }
  free(sorted);
  return true;
}

/* A pulse of the wrong sign: its largest excursion is downwards, more than
 * twice any excursion upwards (noise is about symmetric, a rebound smaller
 * than its pulse) and larger than limit_n [N]. */
static bool looks_inverted(const af_force_survey *g, double limit_n)
{
  return g->finite > 0 && -g->down_n > fmax(limit_n, 2.0 * g->up_n);
}

/* Why no strike came, from the force itself when it says more than the
 * detector's state: no finite sample, or a pulse of the wrong sign. */
static void why_no_strike(const af_analyze_args *a, const af_lane *lane, const af_recording *force,
                          char *why, size_t len)
{
  af_force_survey g;
  const bool surveyed = survey_force(force, &g);
  if (surveyed && g.finite == 0) {
    snprintf(why, len,
             "the force recording %s holds no finite sample (%zu samples, all NaN or infinite)",
             a->force_path, force->n);
    return;
  }
  if (surveyed && looks_inverted(&g, 0.0)) {
    snprintf(why, len,
             "the largest excursion is %.3g N at sample %zu, against %.3g N at most upwards: is "
             "the force inverted (transducer polarity)?",
             g.down_n, g.down_at, g.up_n);
    return;
  }
  (void)af_strike_explain(af_lane_detector(lane), why, len);
}

/* Strikes found, but the force's largest excursion is downwards and larger
 * than every strike's peak: the strikes are likely its rebounds. */
static void warn_inverted(const af_analyze_args *a, const af_analyze_ctx *c,
                          const af_recording *force)
{
  af_force_survey g;
  double peak_n = 0.0;
  for (size_t i = 0; i < c->n_rows; i++)
    if (isfinite(c->rows[i].report.peak_force_n))
      peak_n = fmax(peak_n, c->rows[i].report.peak_force_n);
  if (survey_force(force, &g) && looks_inverted(&g, 2.0 * peak_n))
    fprintf(stderr,
            "firmness_model analyze: warning: the largest excursion in %s is %.3g N at sample "
            "%zu, against %.3g N for the largest strike found: is the force inverted "
            "(transducer polarity)?\n",
            a->force_path, g.down_n, g.down_at, peak_n);
}

/* This run's rows: at most one strike per post_s of force (the detector
 * waits that long after each), or one onset per hold-off (tap-only); the
 * buffer grows to the largest run's. false: out of memory. */
static bool rows_ready(af_analyze_ctx *c, const af_analyze_args *a, const af_lane_config *cfg,
                       const af_recording *force, const af_recording *audio)
{
  c->cap_rows = cfg->strikes.tap_only
                    ? audio->n / (size_t)ceil(cfg->strikes.onset.holdoff_s * a->rate_audio_hz) + 1
                    : force->n / (size_t)ceil(cfg->strikes.strike.post_s * a->rate_force_hz) + 1;
  if (c->cap_rows > AF_ANALYZE_MAX_STRIKES)
    c->cap_rows = AF_ANALYZE_MAX_STRIKES;
  c->n_rows = c->dropped = 0;
  if (c->cap_rows <= c->room)
    return true;
  af_lane_strike *rows = realloc(c->rows, c->cap_rows * sizeof *rows);
  if (rows == NULL)
    return false;
  c->rows = rows;
  c->room = c->cap_rows;
  return true;
}

/* The session's lane for cfg: the last run's, reset (af_lane_reset: as
 * af_lane_create leaves it), when it was made with the same configuration
 * to the byte; else a new one. 0 or the exit status. */
static int lane_ready(af_analyze_session *ss, const af_lane_config *cfg)
{
  if (ss->lane != NULL && memcmp(&ss->cfg, cfg, sizeof *cfg) == 0) {
    af_lane_reset(ss->lane);
    return 0;
  }
  af_lane_destroy(ss->lane);
  ss->lane = NULL;
  memcpy(&ss->cfg, cfg, sizeof *cfg);
  const char *what = "";
  af_status st = af_lane_create(&ss->cfg, on_strike, &ss->ctx, &ss->lane, &what);
  if (st == AF_OK)
    return 0;
  fprintf(stderr, "firmness_model analyze: could not create %s: %s\n", what, af_strerror(st));
  return 1;
}

/* Runs the session's lane over the recordings; prints the JSON (and why no
 * strike). */
static int analyze_run(af_analyze_session *ss, const af_analyze_args *a,
                       const af_lane_config *run_cfg, const af_recording *force,
                       const af_recording *audio)
{
  af_analyze_ctx *c = &ss->ctx;
  if (!rows_ready(c, a, run_cfg, force, audio)) {
    fprintf(stderr, "firmness_model analyze: could not create the strike rows: %s\n",
            af_strerror(AF_ENOMEM));
    return 1;
  }
  const int made = lane_ready(ss, run_cfg);
  if (made != 0)
    return made;
  af_lane *lane = ss->lane;
  const af_lane_config *cfg = &ss->cfg;
  af_apple apple = analyze_apple(a, cfg);
  const af_prediction *pr = NULL;
  int code = 0;
  af_status ast = af_lane_apple(lane, &apple, apple.stamp_ns, &pr);
  if (ast == AF_EINVAL) {
    fprintf(stderr, "firmness_model analyze: --mass/--R2: %s\n", pr->why);
    code = AF_CLI_EXIT_USAGE;
  } else if (ast != AF_OK) { /* the model itself: a budget, a numerical failure */
    fprintf(stderr, "firmness_model analyze: the model failed on this apple: %s\n", pr->why);
    code = 1;
  } else {
    /* A triggered capture has its strike within a millisecond of its start:
     * the baseline and noise come from the whole capture's quiet parts. */
    if (cfg->strikes.tap_only)
      (void)af_lane_prime_audio(lane, audio->x, audio->n);
    else
      (void)af_lane_prime_force(lane, force->x, force->n);
    double t0 = cpu_time_s();
    feed(lane, a, cfg, force, audio);
    double cpu_s = cpu_time_s() - t0;
    char why[AF_ERR_MAX] = "";
    if (c->n_rows == 0) {
      if (cfg->strikes.tap_only)
        snprintf(why, sizeof why,
                 "tap-only: no audio onset %g dB above the noise floor (onset_snr_db) in %s",
                 cfg->strikes.onset.snr_db, a->audio_path);
      else if (force->n == 0)
        snprintf(why, sizeof why, "the force recording %s is empty", a->force_path);
      else
        why_no_strike(a, lane, force, why, sizeof why);
      fprintf(stderr, "firmness_model analyze: no strike found: %s\n", why);
    } else if (!cfg->strikes.tap_only)
      warn_inverted(a, c, force);
    warn_refused(af_lane_force_stream(lane), a->force_path);
    warn_refused(af_lane_audio_stream(lane), a->audio_path);
    json_print(stdout, c, lane, c->n_rows == 0 ? why : NULL);
    if (c->dropped > 0) {
      fprintf(stderr, "firmness_model analyze: %zu strikes beyond the %zu expected at most\n",
              c->dropped, c->cap_rows);
      code = 1;
    }
    if (a->bench && cfg->strikes.tap_only)
      print_bench(a->rate_audio_hz, c, cpu_s, audio->n);
    else if (a->bench)
      print_bench(a->rate_force_hz, c, cpu_s, force->n);
  }
  return code;
}

/* Both recordings, WAV or raw (recording.h), and their rates into a. */
static bool analyze_load(af_analyze_args *a, af_recording *force, af_recording *audio)
{
  char rerr[AF_ERR_MAX];
  a->force_spec.rate_hz = a->rate_force_hz;
  a->audio_spec.rate_hz = a->rate_audio_hz;
  a->force_spec.max_samples = a->audio_spec.max_samples = (size_t)a->max_samples;
  if (a->force_path != NULL && af_recording_load(a->force_path, &a->force_spec, force,
                                                 &a->rate_force_hz, rerr, sizeof rerr) != AF_OK) {
    print_usage("--force %s", rerr, "");
    return false;
  }
  if (af_recording_load(a->audio_path, &a->audio_spec, audio, &a->rate_audio_hz, rerr,
                        sizeof rerr) != AF_OK) {
    af_recording_destroy(force);
    print_usage("--audio %s", rerr, "");
    return false;
  }
  return true;
}

/* --help: every flag, the rows' defaults as the shipped files set them. */
static void analyze_help(void)
{
  af_analyze_args d = analyze_args_default();
  af_settings s;
  bool files = analyze_files(&d, &s);
  if (!files)
    af_settings_reset(&s);
  printf("usage: firmness_model analyze --force FILE --audio FILE --mass KG --R2 M\n"
         "                              [--rate-force HZ --rate-audio HZ] [flags]\n"
         "       firmness_model analyze --tap-only --audio FILE --mass KG --R2 M\n"
         "                              [--rate-audio HZ] [flags]\n\n"
         "A recording judged as the node judges it live: the force and audio files (WAV, or\n"
         "raw float32 with their rates) through the station's lane, configured from the\n"
         "node's YAML files, one apple for the whole recording. Prints one JSON object: the\n"
         "strikes with their StrikeReport figures and verdict flags, and why there are none\n"
         "when there are none.\n\n"
         "flags (the parameter rows' defaults: %s):\n",
         files ? "the parameter table under the default --config and --cultivar"
               : "the parameter table's, the default files being unreadable");
  af_options_help(stdout, analyze_options, AF_N_OPTIONS, &d, &s);
  printf("\nexit status: 0 done, 1 failure, 2 bad input\n");
}

/* The inputs the mode needs: the force (and the audio) with a force
 * transducer; the audio alone, no --force, tap-only. 0 or the exit status. */
static int analyze_inputs(const af_analyze_args *a, const af_lane_config *cfg,
                          const af_recording *force, const af_recording *audio)
{
  if (cfg->strikes.tap_only) {
    if (a->force_path != NULL)
      return print_usage("--force %s: tap_only is set (a microphone-only rig): the force is not "
                         "read; drop --force or set tap_only false",
                         a->force_path, "");
    if (audio->n == 0)
      return print_usage("--audio %s is empty: no samples to analyze", a->audio_path, "");
    return 0;
  }
  if (a->force_path == NULL) {
    fprintf(stderr, "firmness_model analyze: --force FILE is required (or --tap-only for a "
                    "microphone-only rig)\n");
    return AF_CLI_EXIT_USAGE;
  }
  /* Nothing to analyze is bad input, not an empty answer. (An empty audio
   * file is allowed: the strikes are then measured without audio, each
   * saying so.) */
  if (force->n == 0)
    return print_usage("--force %s is empty: no samples to analyze", a->force_path, "");
  return 0;
}

/* The lane's apple stays fresh for longer than any recording the flags
 * admit (--max-samples at the slower rate read, and the offset) [s]: the
 * configuration then does not depend on this recording's length, and a
 * session's next run can reuse the lane. */
static double stale_bound_s(const af_analyze_args *a, const af_lane_config *cfg)
{
  const double rate_hz =
      cfg->strikes.tap_only ? a->rate_audio_hz : fmin(a->rate_force_hz, a->rate_audio_hz);
  return (double)a->max_samples / rate_hz + fabs(a->audio_offset_s) + 1.0;
}

/* The lane's configuration for these recordings into cfg; 0 or the exit
 * status. */
static int run_config(af_analyze_session *ss, const af_analyze_args *a, const af_recording *force,
                      const af_recording *audio, af_lane_config *cfg)
{
  af_settings s;
  if (!analyze_settings(ss, a, &s))
    return AF_CLI_EXIT_USAGE;
  /* The same settings derive the same configuration (the last run's rates
   * and flags: every run of a session over raw files). */
  if (!ss->have_derived || memcmp(&s, &ss->derived_from, sizeof s) != 0) {
    char err[AF_ERR_MAX];
    ss->have_derived = false;
    if (af_lane_config_derive(&s, &ss->derived, err, sizeof err) != AF_OK)
      return print_usage("%s%s", err, "");
    memcpy(&ss->derived_from, &s, sizeof s);
    ss->have_derived = true;
  }
  memcpy(cfg, &ss->derived, sizeof *cfg);
  int code = analyze_inputs(a, cfg, force, audio);
  if (code != 0)
    return code;
  /* One apple for the whole recording: it must match every strike in it. */
  cfg->strikes.apple_stale_after_s = stale_bound_s(a, cfg);
  cfg->strikes.single_apple = true;
  /* An integer WAV's step bounds the onset detector's floor (onset.h), and
   * the strike detector's: one step after exact zeros is no strike. */
  cfg->strikes.onset.quantum = audio->quantum;
  if (force->quantum > 0.0 &&
      cfg->strikes.strike.threshold_min_n < AF_ANALYZE_FORCE_STEPS * force->quantum)
    cfg->strikes.strike.threshold_min_n = AF_ANALYZE_FORCE_STEPS * force->quantum;
  return 0;
}

int af_analyze_session_create(int argc, char **argv, int first, af_analyze_session **out)
{
  *out = NULL;
  af_analyze_session *ss = calloc(1, sizeof *ss);
  if (ss == NULL) {
    fprintf(stderr, "firmness_model analyze: %s\n", af_strerror(AF_ENOMEM));
    return 1;
  }
  ss->argc = argc;
  ss->argv = argv;
  ss->first = first;
  if (!parse_args(argc, argv, first, &ss->flags)) {
    free(ss);
    return AF_CLI_EXIT_USAGE;
  }
  *out = ss;
  return 0;
}

int af_analyze_session_run(af_analyze_session *ss)
{
  af_analyze_args a = ss->flags;
  af_recording force = {0}, audio = {0};
  if (!analyze_load(&a, &force, &audio))
    return AF_CLI_EXIT_USAGE;
  af_lane_config cfg;
  int code = run_config(ss, &a, &force, &audio, &cfg);
  if (code == 0)
    code = analyze_run(ss, &a, &cfg, &force, &audio);
  af_recording_destroy(&force);
  af_recording_destroy(&audio);
  return code;
}

void af_analyze_session_destroy(af_analyze_session *ss)
{
  if (ss == NULL)
    return;
  af_lane_destroy(ss->lane);
  free(ss->ctx.rows);
  free(ss);
}

int af_analyze_main(int argc, char **argv, int first)
{
  if (af_options_want_help(argc, argv, first)) {
    analyze_help();
    return 0;
  }
  af_analyze_session *ss;
  int code = af_analyze_session_create(argc, argv, first, &ss);
  if (code != 0)
    return code;
  code = af_analyze_session_run(ss);
  af_analyze_session_destroy(ss);
  return code;
}
