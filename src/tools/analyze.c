/* analyze.c — `firmness_model analyze`: the station's measurement offline.
 *
 * Reads the force [N] and the audio (any unit) as raw little-endian float32
 * files, writes the force to the strike detector in 1024-sample chunks with
 * their running index (as the node receives SignalChunks), and for every
 * strike cuts the audio by sample index and calls af_measure_strike, as the
 * node does. Prints the StrikeReport figures as a JSON array on stdout. */
#define _POSIX_C_SOURCE 200809L
#include "analyze.h"

#include <errno.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "cli_flags.h"
#include "measure.h"
#include "strike.h"

#define AF_ANALYZE_CHUNK 1024 /* samples per write, as the node's SignalChunks */
/* The fit takes pulses up to this long at any force rate (its default 256
 * samples at 50 kHz) [s]. */
#define AF_ANALYZE_FIT_SPAN_S 5.12e-3

typedef struct {
  const char *force_path, *audio_path;
  double rate_force_hz, rate_audio_hz;
  double audio_offset_s; /* audio start time minus force start time */
  double modulus_min_pa, modulus_max_pa;
  bool bench;
} af_analyze_args;

typedef struct {
  float *x;
  size_t n;
} af_samples;

typedef struct {
  double contact_start_s;
  af_measure_report r;
} af_analyze_row;

/* The callback's context: the measurement, the apple, the audio and the rows. */
typedef struct {
  af_measure *m;
  af_measure_apple apple;
  const af_analyze_args *args;
  af_samples audio;
  af_analyze_row *rows;
  size_t n_rows, cap_rows;
  bool failed;          /* a row could not be stored or measured */
  double measure_cpu_s; /* CPU spent in af_measure_strike (--bench) */
  double worst_measure_s;
} af_analyze_ctx;

static double af_cpu_s(void)
{
  struct timespec ts;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* ---- arguments ------------------------------------------------------------- */

static bool af_parse_value(const char *flag, const char *text, bool positive, double *out)
{
  char *end;
  errno = 0;
  *out = strtod(text, &end);
  if (end == text || *end != '\0' || errno == ERANGE || !isfinite(*out) ||
      (positive && !(*out > 0.0))) {
    fprintf(stderr, "firmness_model analyze: %s '%s' must be a finite number%s\n", flag, text,
            positive ? " > 0" : "");
    return false;
  }
  return true;
}

/* One of analyze's own flags with its value; false after a message. */
static bool af_analyze_flag(const char *flag, const char *value, af_analyze_args *a)
{
  if (strcmp(flag, "--force") == 0)
    a->force_path = value;
  else if (strcmp(flag, "--audio") == 0)
    a->audio_path = value;
  else if (strcmp(flag, "--rate-force") == 0)
    return af_parse_value(flag, value, true, &a->rate_force_hz);
  else if (strcmp(flag, "--rate-audio") == 0)
    return af_parse_value(flag, value, true, &a->rate_audio_hz);
  else if (strcmp(flag, "--audio-offset") == 0)
    return af_parse_value(flag, value, false, &a->audio_offset_s);
  else if (strcmp(flag, "--modulus-min") == 0)
    return af_parse_value(flag, value, true, &a->modulus_min_pa);
  else if (strcmp(flag, "--modulus-max") == 0)
    return af_parse_value(flag, value, true, &a->modulus_max_pa);
  else {
    fprintf(stderr, "firmness_model analyze: unknown argument '%s' (see --help)\n", flag);
    return false;
  }
  return true;
}

/* Reads analyze's own flags from the arguments the model parser left. */
static bool af_parse_analyze_args(char **argv, const int *rest, int n_rest, af_analyze_args *a)
{
  memset(a, 0, sizeof *a);
  a->modulus_min_pa = 2e6; /* the shipped cultivar's (config/jonagold.yaml) */
  a->modulus_max_pa = 12e6;
  for (int k = 0; k < n_rest; k++) {
    const char *flag = argv[rest[k]];
    if (strcmp(flag, "--bench") == 0) {
      a->bench = true;
      continue;
    }
    bool has_value = k + 1 < n_rest && rest[k + 1] == rest[k] + 1;
    if (!has_value && strncmp(flag, "--", 2) == 0) {
      fprintf(stderr, "firmness_model analyze: %s needs a value\n", flag);
      return false;
    }
    if (!af_analyze_flag(flag, has_value ? argv[rest[++k]] : "", a))
      return false;
  }
  const char *missing = !a->force_path      ? "--force FILE"
                        : !a->audio_path    ? "--audio FILE"
                        : !a->rate_force_hz ? "--rate-force HZ"
                        : !a->rate_audio_hz ? "--rate-audio HZ"
                                            : NULL;
  if (missing != NULL) {
    fprintf(stderr, "firmness_model analyze: %s is required\n", missing);
    return false;
  }
  if (!(a->modulus_max_pa > a->modulus_min_pa)) {
    fprintf(stderr, "firmness_model analyze: --modulus-max %g must be above --modulus-min %g\n",
            a->modulus_max_pa, a->modulus_min_pa);
    return false;
  }
  return true;
}

/* --mass and --R2 are model flags, but the apple's own: no default applies. */
static bool af_require_model_flags(int argc, char **argv, int first)
{
  static const char *const required[] = {"--mass", "--R2"};
  for (size_t i = 0; i < sizeof required / sizeof required[0]; i++) {
    bool found = false;
    for (int k = first; k < argc && !found; k++)
      found = strcmp(argv[k], required[i]) == 0;
    if (!found) {
      fprintf(stderr, "firmness_model analyze: %s is required (the apple's)\n", required[i]);
      return false;
    }
  }
  return true;
}

/* ---- files ----------------------------------------------------------------- */

static bool af_host_is_little_endian(void)
{
  const uint32_t one = 1;
  unsigned char b;
  memcpy(&b, &one, 1);
  return b == 1;
}

static void af_swap_bytes(float *x, size_t n)
{
  for (size_t k = 0; k < n; k++) {
    unsigned char b[4], t;
    memcpy(b, &x[k], 4);
    t = b[0], b[0] = b[3], b[3] = t;
    t = b[1], b[1] = b[2], b[2] = t;
    memcpy(&x[k], b, 4);
  }
}

/* The whole file as float32 samples; false after a message naming the flag
 * and the file. */
static bool af_read_samples(const char *flag, const char *path, af_samples *out)
{
  FILE *f = fopen(path, "rb");
  long size = -1;
  if (f != NULL && fseek(f, 0, SEEK_END) == 0)
    size = ftell(f);
  if (f == NULL || size < 0 || fseek(f, 0, SEEK_SET) != 0) {
    fprintf(stderr, "firmness_model analyze: cannot read %s %s: %s\n", flag, path, strerror(errno));
    if (f != NULL)
      fclose(f);
    return false;
  }
  if (size % 4 != 0) {
    fprintf(stderr,
            "firmness_model analyze: %s %s: %ld bytes is not a whole number of float32 "
            "samples\n",
            flag, path, size);
    fclose(f);
    return false;
  }
  out->n = (size_t)size / 4;
  out->x = malloc(out->n > 0 ? out->n * sizeof *out->x : 1);
  bool ok = out->x != NULL && fread(out->x, 4, out->n, f) == out->n;
  fclose(f);
  if (!ok) {
    fprintf(stderr, "firmness_model analyze: cannot read %s %s: short read\n", flag, path);
    free(out->x);
    out->x = NULL;
    return false;
  }
  if (!af_host_is_little_endian())
    af_swap_bytes(out->x, out->n);
  return true;
}

/* ---- configuration --------------------------------------------------------- */

static size_t af_pow2_at_least(size_t n)
{
  size_t p = 1;
  while (p < n)
    p *= 2;
  return p;
}

/* The defaults, scaled to the files' rates: the audio window (and its FFT)
 * and the fit's longest pulse hold the same durations at any rate; the
 * response's noise band is moved below a low rate's Nyquist frequency. */
static af_measure_config af_analyze_measure_config(const af_analyze_args *a)
{
  af_measure_config c = af_measure_config_default();
  af_response_config *r = &c.response;
  double nyquist_hz = 0.5 * a->rate_audio_hz;
  size_t window = (size_t)ceil(fmax(c.audio_window_s, c.noise_window_s) * a->rate_audio_hz);
  r->sample_rate_hz = a->rate_audio_hz;
  if (window > r->window_samples) {
    r->window_samples = window;
    r->fft_size = af_pow2_at_least(2 * window);
  }
  if (r->noise_band_lo_hz >= 0.9 * nyquist_hz) {
    r->noise_band_lo_hz = 0.5 * nyquist_hz;
    r->noise_band_hi_hz = 0.9 * nyquist_hz;
  }
  size_t fit_samples = (size_t)ceil(AF_ANALYZE_FIT_SPAN_S * a->rate_force_hz);
  if (fit_samples > c.fit.max_samples)
    c.fit.max_samples = fit_samples;
  return c;
}

/* ---- per strike -------------------------------------------------------------- */

/* Audio index of force time t_s: audio sample j is at audio_offset_s + j / rate. */
static long af_audio_index(const af_analyze_ctx *c, double t_s)
{
  return lround((t_s - c->args->audio_offset_s) * c->args->rate_audio_hz);
}

/* The window [first, first + n) of the audio, clipped to the recording. */
static const float *af_audio_cut(const af_analyze_ctx *c, long first, long n, size_t *n_out)
{
  long total = (long)c->audio.n;
  long lo = first < 0 ? 0 : first, hi = first + n > total ? total : first + n;
  *n_out = hi > lo ? (size_t)(hi - lo) : 0;
  return *n_out > 0 ? c->audio.x + lo : NULL;
}

static bool af_store_row(af_analyze_ctx *c, double start_s, const af_measure_report *r)
{
  if (c->n_rows == c->cap_rows) {
    size_t cap = c->cap_rows ? 2 * c->cap_rows : 16;
    af_analyze_row *rows = realloc(c->rows, cap * sizeof *rows);
    if (rows == NULL)
      return false;
    c->rows = rows;
    c->cap_rows = cap;
  }
  c->rows[c->n_rows].contact_start_s = start_s;
  c->rows[c->n_rows].r = *r;
  c->n_rows++;
  return true;
}

static void af_on_strike(const af_strike_event *ev, void *user)
{
  af_analyze_ctx *c = user;
  const af_measure_config *mc = af_measure_get_config(c->m);
  double start_s = ev->start_sample / c->args->rate_force_hz, rate = c->args->rate_audio_hz;
  size_t n_audio, n_noise;
  const float *audio = af_audio_cut(c, af_audio_index(c, start_s + mc->audio_delay_s),
                                    lround(mc->audio_window_s * rate), &n_audio);
  long noise_end = af_audio_index(c, start_s - mc->noise_guard_s);
  long noise_n = lround(mc->noise_window_s * rate);
  const float *noise = af_audio_cut(c, noise_end - noise_n, noise_n, &n_noise);
  af_measure_report r;
  double t0 = af_cpu_s();
  af_status st = af_measure_strike(c->m, ev, &c->apple, audio, n_audio, noise, n_noise, &r);
  double spent = af_cpu_s() - t0;
  c->measure_cpu_s += spent;
  c->worst_measure_s = fmax(c->worst_measure_s, spent);
  if (st != AF_OK || !af_store_row(c, start_s, &r))
    c->failed = true;
}

/* ---- output ------------------------------------------------------------------ */

static void af_json_number(FILE *out, const char *key, double v)
{
  if (isfinite(v))
    fprintf(out, "    \"%s\": %.10g,\n", key, v);
  else
    fprintf(out, "    \"%s\": null,\n", key);
}

static void af_json_bool(FILE *out, const char *key, bool v)
{
  fprintf(out, "    \"%s\": %s,\n", key, v ? "true" : "false");
}

static void af_json_string(FILE *out, const char *key, const char *s)
{
  fprintf(out, "    \"%s\": \"", key);
  for (; *s; s++) {
    unsigned char ch = (unsigned char)*s;
    if (ch == '"' || ch == '\\')
      fprintf(out, "\\%c", ch);
    else if (ch < 0x20)
      fprintf(out, "\\u%04x", ch);
    else
      fputc(ch, out);
  }
  fputs("\"\n", out);
}

static void af_json_row(FILE *out, const af_analyze_row *row, bool last)
{
  const af_measure_report *r = &row->r;
  fputs("  {\n", out);
  af_json_number(out, "contact_start_s", row->contact_start_s);
  af_json_number(out, "contact_time_s", r->contact_time_s);
  af_json_number(out, "peak_force_N", r->peak_force_n);
  af_json_number(out, "impulse_Ns", r->impulse_n_s);
  af_json_number(out, "band_low_Hz", r->band_low_hz);
  af_json_number(out, "band_high_Hz", r->band_high_hz);
  af_json_number(out, "resonance_Hz", r->resonance_hz);
  af_json_number(out, "resonance_q", r->resonance_q);
  af_json_number(out, "snr_dB", r->snr_db);
  af_json_number(out, "stiffness_factor", r->stiffness_factor);
  af_json_number(out, "modulus_from_resonance_Pa", r->modulus_from_resonance_pa);
  af_json_number(out, "fitted_modulus_Pa", r->fitted_modulus_pa);
  af_json_number(out, "fitted_restitution", r->fitted_restitution);
  af_json_number(out, "fit_residual", r->fit_residual);
  af_json_bool(out, "double_hit", r->double_hit);
  af_json_bool(out, "clipped", r->clipped);
  fprintf(out, "    \"lost_samples\": %lu,\n", (unsigned long)r->lost_samples);
  af_json_bool(out, "excites_mode", r->excites_mode);
  af_json_bool(out, "no_damage", r->no_damage);
  af_json_bool(out, "reliable", r->reliable);
  af_json_string(out, "reason", r->reason);
  fprintf(out, "  }%s\n", last ? "" : ",");
}

static void af_json_rows(FILE *out, const af_analyze_ctx *c)
{
  fputs(c->n_rows ? "[\n" : "[", out);
  for (size_t k = 0; k < c->n_rows; k++)
    af_json_row(out, &c->rows[k], k + 1 == c->n_rows);
  fputs("]\n", out);
}

static void af_print_bench(const af_analyze_ctx *c, double write_cpu_s, size_t n_force)
{
  double seconds = (double)n_force / c->args->rate_force_hz;
  double detector_s = write_cpu_s - c->measure_cpu_s; /* the callbacks run inside the writes */
  fprintf(stderr, "bench: %zu strikes, af_measure_strike %.1f us mean, %.1f us worst (CPU)\n",
          c->n_rows, c->n_rows ? 1e6 * c->measure_cpu_s / (double)c->n_rows : NAN,
          1e6 * c->worst_measure_s);
  fprintf(stderr,
          "bench: af_strike_write %.1f us CPU per second of force at %g Hz (%.3f %% of a "
          "core)\n",
          seconds > 0 ? 1e6 * detector_s / seconds : NAN, c->args->rate_force_hz,
          seconds > 0 ? 100.0 * detector_s / seconds : NAN);
}

/* ---- the run ----------------------------------------------------------------- */

/* Streams the force through the detector; the strikes land in c->rows. */
static int af_analyze_run(af_analyze_ctx *c, const af_samples *force)
{
  af_strike_config sc = af_strike_config_default();
  af_strike *d = NULL;
  sc.sample_rate_hz = c->args->rate_force_hz;
  af_status st = af_strike_create(&sc, &d);
  if (st != AF_OK) {
    fprintf(stderr, "firmness_model analyze: --rate-force %g: the strike detector refuses it: %s\n",
            c->args->rate_force_hz, af_strerror(st));
    return st == AF_EINVAL ? AF_CLI_EXIT_USAGE : 1;
  }
  double t0 = af_cpu_s();
  for (size_t k = 0; k < force->n && st == AF_OK; k += AF_ANALYZE_CHUNK) {
    size_t n = force->n - k < AF_ANALYZE_CHUNK ? force->n - k : AF_ANALYZE_CHUNK;
    st = af_strike_write(d, k, force->x + k, n, af_on_strike, c);
  }
  double write_cpu_s = af_cpu_s() - t0;
  af_strike_destroy(d);
  if (st != AF_OK || c->failed) {
    fprintf(stderr, "firmness_model analyze: measurement failed: %s\n",
            st != AF_OK ? af_strerror(st) : "a strike could not be measured or stored");
    return 1;
  }
  af_json_rows(stdout, c);
  if (c->args->bench)
    af_print_bench(c, write_cpu_s, force->n);
  return 0;
}

static int af_analyze_files(const af_analyze_args *a, const af_model_params *p)
{
  af_samples force = {0}, audio = {0};
  af_analyze_ctx c = {.args = a};
  c.apple.model = *p;
  c.apple.modulus_min_pa = a->modulus_min_pa;
  c.apple.modulus_max_pa = a->modulus_max_pa;
  if (!af_read_samples("--force", a->force_path, &force) ||
      !af_read_samples("--audio", a->audio_path, &audio)) {
    free(force.x);
    return AF_CLI_EXIT_USAGE;
  }
  c.audio = audio;
  af_measure_config mc = af_analyze_measure_config(a);
  af_status st = af_measure_create(&mc, &c.m);
  if (st == AF_OK)
    st = af_measure_prepare(c.m, &c.apple.model);
  int code;
  if (st != AF_OK) {
    fprintf(stderr, "firmness_model analyze: --rate-audio %g: the measurement refuses it: %s\n",
            a->rate_audio_hz, af_strerror(st));
    code = st == AF_EINVAL ? AF_CLI_EXIT_USAGE : 1;
  } else {
    code = af_analyze_run(&c, &force);
  }
  af_measure_destroy(c.m);
  free(c.rows);
  free(force.x);
  free(audio.x);
  return code;
}

int af_analyze_main(int argc, char **argv, int first)
{
  af_model_params p;
  af_analyze_args a;
  int *rest = malloc((size_t)argc * sizeof *rest);
  int n_rest = 0;
  bool ok = rest != NULL && af_cli_parse_model(argc, argv, first, &p, rest, &n_rest) &&
            af_parse_analyze_args(argv, rest, n_rest, &a) &&
            af_require_model_flags(argc, argv, first);
  free(rest);
  if (!ok)
    return AF_CLI_EXIT_USAGE;
  return af_analyze_files(&a, &p);
}
