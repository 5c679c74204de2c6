/* strike_bag — a rosbag of synthetic strikes for the replay demo and the
 * strikes rostest, with the truth it was made from.
 *
 *   strike_bag --strikes N --out FILE [--seed S] [--truth FILE] [--ns NAME]
 *              [--spacing S] [--velocity-drift X] [--modulus-factor F]
 *              [--modulus-factor-spread S] [--unreliable-fraction P] [--tap-only]
 *              [--max-size GB]
 *                                     (flags: the table `options`; --help)
 *
 * Per strike k (apple_id k + 1), spacing S apart (default 0.5 s) after a
 * 1 s lead-in, with a random sub-millisecond offset:
 * The station, the cultivar and the strike are the parameter table's
 * defaults (src/core/params/settings_table.c; what config/station.yaml,
 * config/jonagold.yaml and config/rig.urdf ship), derived through
 * af_lane_config_derive as the node derives them:
 *  - an apple: E2 uniform in the cultivar's [modulus_min_pa,
 *    modulus_max_pa], mass uniform in [mass_min_kg, mass_max_kg], a sphere
 *    of the cultivar's density_kg_m3;
 *  - force (force_sample_rate_hz, N, frame force_transducer): the impact
 *    model's pulse integrated by an RK4 of its own (af_synth_pulse_rk4, at
 *    1/64 of the sample step, linearly interpolated at the samples; not the
 *    GSL integrator the station's fit inverts, so the demo is no round
 *    trip) for the table's strike (the rig's hammer, strike_velocity_m_s,
 *    restitution, fruit_poisson, gravity, damping_law; R2 = model.c's
 *    example apple's) on that apple, the contact velocity of strike k of n
 *    being strike_velocity_m_s (1 + X k / (n - 1)) with --velocity-drift X
 *    (default 0: constant; a hammer heating over a shift, for the hammer
 *    health); plus white noise at 40 dB below the
 *    smallest peak of the bag, mains hum at the station's measure_hum_hz,
 *    an offset and a slow drift;
 *  - audio (audio_sample_rate_hz, Pa, frame microphone): the apple's 0S2
 *    mode at Lamb's frequency of F x E2 (F = --modulus-factor, default 1:
 *    the true dynamic / quasi-static factor the station should learn;
 *    times exp(S g), g standard normal, per apple with
 *    --modulus-factor-spread S: apples unlike the model's homogeneous
 *    sphere) ringing from the contact start with Q 30, a mode twice as loud
 *    at 2.6 kHz (above every apple's 0S2 range: the support, say) with Q 60,
 *    and white noise 30 dB below the 0S2 amplitude;
 *  - an AppleEstimate 0.2 s before the strike (camera_optical_frame,
 *    strike_radius = the model's R2, stem axis (1, 0, 0): perpendicular to the rig's
 *    strike direction, +z of that frame).
 * Topics /NS/force, /NS/audio, /NS/apple (NS default lane1), in 1024-sample
 * SignalChunks whose header stamp is the time of their first sample (bag
 * start 1700000000 s + first_sample / rate) and whose bag time is that of
 * their last. The truth CSV (default: FILE without .bag + .truth.csv) has
 * one row per strike: apple_id, modulus_pa, mass_kg, resonance_hz (0S2),
 * contact_time_s and peak_force_n (the model's), contact_start_s (stamp),
 * velocity_m_s (the strike's contact velocity), modulus_factor (F) and
 * clipped (1: an unreliable strike, below).
 *
 * --unreliable-fraction P: each strike is, with probability P (its own
 * seeded stream, so that the apples are those of P = 0), struck too hard for
 * the transducer: its force pulse scaled so that its peak is 1.25 x
 * strike_full_scale_n and saturated there (the detector flags it clipped,
 * the fit of E2 on it is wrong, its 0S2 is the apple's: a strike that must
 * not feed the learned modulus factor).
 *
 * --tap-only: a microphone-only rig: no /NS/force topic at all;
 * the audio and the apples as above (the node and firmness_report then run
 * with tap_only true).
 *
 * Size: before anything is written, the bag's size (1024-sample chunks of
 * 4 bytes a sample, plus rosbag's records) and the tool's peak memory are
 * estimated; a bag above --max-size (default 16 GB) or above the free space
 * of the output's folder is refused with one line giving the estimate and
 * the limit. The strikes are drawn twice from the seed (the truth and the
 * smallest peak, then the bag), each pulse held only while its chunks are
 * made: memory does not grow with --strikes (only rosbag's chunk index
 * does, by some 3 bytes a message). A write that fails (a full disk, a
 * file-size limit) ends the tool with one line and exit 1, the partial bag
 * removed.
 *
 * Seeded (af_synth_rng, splitmix64): the same seed gives the same bag on
 * every machine. Exit 0, 2 on bad arguments, 1 on failure. */
#define _POSIX_C_SOURCE 200809L /* statvfs, dirname */
#include <errno.h>
#include <libgen.h>
#include <math.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/statvfs.h>

#include "closeout.h"
#include "af_bag.h"
#include "impact.h"
#include "model_table.h"
#include "tool_config.h"
#include "options.h"
#include "settings.h"
#include "lamb.h"
#include "synth.h"

#ifndef M_PI /* strict C11 <math.h> does not define it */
#define M_PI 3.14159265358979323846
#endif

#define CHUNK 1024
#define OVERSAMPLE 64
#define FINE_CAP 65536 /* 41 ms at dt/64: far beyond the softest apple's contact */
#define BAG_START_S 1700000000.0
#define LEAD_IN_S 1.0
#define TAIL_S 0.5
#define APPLE_LEAD_S 0.2

/* The station, the cultivar and the strike: the parameter table's defaults
 * (what config/station.yaml, config/jonagold.yaml and the rig's URDF ship),
 * derived as the node derives them, so that no figure is typed here. */
typedef struct {
  af_lane_config lane;   /* the stream rates, the cultivar's domain and density */
  af_model_params model; /* the strike; R2 = model.c's example apple's */
} station;

/* Imperfections. */
#define FORCE_SNR_DB 40.0
#define AUDIO_SNR_DB 30.0
#define MODE_AMPLITUDE_PA 0.2
#define MODE_Q 30.0
#define LOUD_MODE_HZ 2600.0
#define LOUD_MODE_Q 60.0
#define LOUD_MODE_GAIN 2.0

/* ---- the strikes ----------------------------------------------------------- */

typedef struct {
  double t_s;          /* contact start, from the bag start [s] */
  double velocity_m_s; /* contact velocity v0 of this strike [m/s] */
  double modulus_pa, mass_kg, radius_m;
  double resonance_hz, tau_s; /* 0S2 and its amplitude decay time */
  double modulus_factor;      /* this apple's true E_dyn / E2 [-] */
  af_synth_pulse pulse;       /* the RK4 force at fine_dt_s, in force_n */
  bool clipped;               /* --unreliable-fraction: gain x pulse saturated at full scale */
  double force_gain;          /* 1, or 1.25 full scale / peak for a clipped strike */
  double *force_n;            /* owned: pulse.n samples */
} strike;

/* The model's time step [s]: OVERSAMPLE per force sample. */
static double fine_dt_s(const station *st)
{
  return 1.0 / (st->lane.force.sample_rate_hz * OVERSAMPLE);
}

/* The table's strike (the rig's hammer, velocity, e, nu, damping law) on s. */
static af_impact_params impact_for(const station *st, const strike *s)
{
  af_impact_params p = st->model.impact;
  p.fruit_modulus_pa = s->modulus_pa;
  p.velocity_m_s = s->velocity_m_s;
  return p;
}

/* ---- arguments ---------------------------------------------------------------- */

typedef struct {
  long strikes;
  const char *out, *truth, *ns;
  uint64_t seed;
  double spacing_s;
  double velocity_drift;      /* relative change of v0 from the first strike to the last [-] */
  double modulus_factor;      /* true E_dyn / E2 of the 0S2 [-] */
  double unreliable_fraction; /* share of clipped strikes [-] */
  double factor_spread;       /* relative SD (log) of the factor between apples [-] */
  bool tap_only;              /* --tap-only: no force topic */
  double max_size_gb;         /* --max-size: the largest bag written [GB] */
} args;

#define STRIKES_MAX 100000    /* strikes in one bag */
#define SPACING_MIN_S 0.1     /* [s] */
#define SPACING_MAX_S 60      /* [s] */
#define DRIFT_MAX 0.5         /* |--velocity-drift| [-] */
#define UNRELIABLE_MAX 0.9    /* share of clipped strikes */
#define FACTOR_SPREAD_MAX 0.3 /* relative SD of the factor between apples */
#define CLIP_OVERDRIVE 1.25   /* a clipped strike's peak / strike_full_scale_n */
#define MAX_SIZE_GB 16        /* --max-size default: 100000 strikes at 0.5 s are 20 GB [GB] */
#define MAX_SIZE_CAP_GB 1e6   /* --max-size at most [GB] */

/* The defaults the parser starts from; --strikes and --out are required. */
static const args args_defaults = {0,   NULL, NULL, "lane1", 1,     0.5,
                                   0.0, 1.0,  0.0,  0.0,     false, MAX_SIZE_GB};

#define AF_ARG(field) offsetof(args, field)
static const af_option options[] = {
    {"--strikes", "N", AF_OPTION_LONG, AF_ARG(strikes), -1, "[1, " AF_OPTION_STR(STRIKES_MAX) "]",
     "strikes (apples)", NULL, false},
    {"--out", "FILE", AF_OPTION_TEXT, AF_ARG(out), -1, NULL, "the bag", NULL, false},
    {"--seed", "S", AF_OPTION_U64, AF_ARG(seed), -1, "[0, 18446744073709551615]",
     "seed of the noise and the apples", NULL, false},
    {"--truth", "FILE", AF_OPTION_TEXT, AF_ARG(truth), -1, NULL, "the truth CSV",
     "FILE of --out without .bag, + .truth.csv", false},
    {"--ns", "NAME", AF_OPTION_TEXT, AF_ARG(ns), -1, NULL,
     "lane namespace of the topics /NS/force, /NS/audio, /NS/apple", NULL, false},
    {"--spacing", "S", AF_OPTION_NUMBER, AF_ARG(spacing_s), -1,
     "[" AF_OPTION_STR(SPACING_MIN_S) ", " AF_OPTION_STR(SPACING_MAX_S) "] s",
     "time between strikes", NULL, false},
    {"--velocity-drift", "X", AF_OPTION_NUMBER, AF_ARG(velocity_drift), -1,
     "[-" AF_OPTION_STR(DRIFT_MAX) ", " AF_OPTION_STR(DRIFT_MAX) "]",
     "contact velocity of strike k of N: strike_velocity_m_s (1 + X k / (N - 1)) (0.05: +5 % "
     "over the bag)",
     "0: a constant contact velocity", false},
    {"--modulus-factor", "F", AF_OPTION_NUMBER, AF_ARG(modulus_factor), AF_SETTING_MODULUS_FACTOR,
     NULL, "true dynamic / quasi-static modulus of the 0S2 (the modulus_factor row's range)", NULL,
     false},
    {"--modulus-factor-spread", "S", AF_OPTION_NUMBER, AF_ARG(factor_spread), -1,
     "[0, " AF_OPTION_STR(FACTOR_SPREAD_MAX) "]",
     "relative SD of the true factor between apples (lognormal)", "0: every apple has F", false},
    {"--unreliable-fraction", "P", AF_OPTION_NUMBER, AF_ARG(unreliable_fraction), -1,
     "[0, " AF_OPTION_STR(UNRELIABLE_MAX) "]",
     "share of strikes clipped (too hard for the transducer)", "0: none clipped", false},
    {"--tap-only", NULL, AF_OPTION_SWITCH, AF_ARG(tap_only), -1, NULL,
     "a microphone-only rig: no force topic (audio and apples only)", NULL, false},
    {"--max-size", "GB", AF_OPTION_NUMBER, AF_ARG(max_size_gb), -1,
     "(0, " AF_OPTION_STR(MAX_SIZE_CAP_GB) "] GB",
     "refuse, before writing, a bag estimated above this size or the free disk space", NULL, false},
};
#define N_OPTIONS (sizeof options / sizeof options[0])

static void help(void)
{
  printf("usage: strike_bag --strikes N --out FILE [flags]\n\n"
         "A rosbag of synthetic strikes (force 50 kHz, audio 48 kHz, AppleEstimates) for the\n"
         "replay demo and the tests, and the truth CSV it was made from. Each file written is\n"
         "told by a line \"wrote FILE\" on stderr.\n\nflags:\n");
  af_options_help(stdout, options, N_OPTIONS, &args_defaults, NULL);
  printf("\nexit status: 0 done, 1 failure, 2 bad input\n");
}

static int usage(const char *msg, const char *value)
{
  fprintf(stderr, "strike_bag: %s%s%s (see --help)\n", msg, value ? " " : "", value ? value : "");
  return 2;
}

static int parse(int argc, char **argv, args *a)
{
  *a = args_defaults;
  const af_options_parser p = {"strike_bag", {{options, N_OPTIONS, a, NULL, NULL}}, 1, NULL, false};
  if (!af_options_parse(&p, argc, argv, 1))
    return 2;
  if (a->strikes == 0)
    return usage("--strikes is required", NULL);
  if (a->out == NULL || a->out[0] == '\0')
    return usage("--out is required", NULL);
  return 0;
}

/* ---- writing ------------------------------------------------------------------ */

static af_time stamp_of(double t_s)
{
  double abs_s = BAG_START_S + t_s;
  af_time t;
  double sec = floor(abs_s);
  long long ns = llround((abs_s - sec) * 1e9);
  if (ns >= 1000000000LL) {
    sec += 1.0;
    ns -= 1000000000LL;
  }
  t.sec = (uint32_t)sec;
  t.nsec = (uint32_t)ns;
  return t;
}

/* Chunk number k of a stream into c (samples in buf). */
static void make_chunk(const station *st, const strike *s, size_t n_strikes, bool force,
                       uint64_t first, af_synth_rng *g, double noise_rms, float *buf,
                       af_signal_chunk *c)
{
  const double hum_hz = st->lane.strikes.measure.response.hum_hz; /* the site's mains [Hz] */
  const double rate = force ? st->lane.force.sample_rate_hz : st->lane.audio.sample_rate_hz;
  const double two_pi = 2.0 * M_PI;
  memset(c, 0, sizeof *c);
  c->header.stamp = stamp_of((double)first / rate);
  snprintf(c->header.frame_id, sizeof c->header.frame_id, "%s",
           force ? "force_transducer" : "microphone");
  c->first_sample = first;
  c->sample_rate_hz = rate;
  snprintf(c->unit, sizeof c->unit, "%s", force ? "N" : "Pa");
  c->data = buf;
  c->n = CHUNK;
  /* The strikes that reach into this chunk (the audio rings for 0.5 s). */
  const double t_first = (double)first / rate, t_last = (double)(first + CHUNK) / rate;
  size_t near[16], n_near = 0;
  for (size_t j = 0; j < n_strikes && n_near < 16; j++)
    if (s[j].t_s < t_last && s[j].t_s + (force ? s[j].pulse.res.contact_time_s : 0.5) > t_first)
      near[n_near++] = j;
  const double full_scale_n = st->lane.strikes.strike.full_scale_n;
  for (size_t k = 0; k < CHUNK; k++) {
    double t = (double)(first + k) / rate;
    double x = noise_rms * af_synth_gauss(g);
    bool saturate = false;
    if (force)
      x += 0.5 * noise_rms * sin(two_pi * hum_hz * t + 0.3) + 0.4 + 0.01 * t;
    for (size_t i = 0; i < n_near; i++) {
      size_t j = near[i];
      double u = t - s[j].t_s;
      if (u <= 0.0 || u > (force ? s[j].pulse.res.contact_time_s : 0.5))
        continue;
      if (force) {
        x += s[j].force_gain * af_synth_pulse_at(&s[j].pulse, u);
        saturate = saturate || s[j].clipped;
      } else {
        x += MODE_AMPLITUDE_PA * exp(-u / s[j].tau_s) * sin(two_pi * s[j].resonance_hz * u);
        x += LOUD_MODE_GAIN * MODE_AMPLITUDE_PA * exp(-u * M_PI * LOUD_MODE_HZ / LOUD_MODE_Q) *
             sin(two_pi * LOUD_MODE_HZ * u + 1.0);
      }
    }
    buf[k] = (float)(saturate && x > full_scale_n ? full_scale_n : x);
  }
}

static int fail(const char *what, af_status st)
{
  fprintf(stderr, "strike_bag: %s: %s (%s)\n", what, af_strerror(st), af_bag_last_error(NULL));
  return 1;
}

/* The strikes, drawn in order from the seed. Drawn twice with the same
 * streams, so that nothing of the whole bag is held: first for the truth
 * CSV and the smallest peak (which sets the force noise of every chunk),
 * then again while the bag is written, each strike's pulse kept only while
 * chunks it reaches are being made. The model is deterministic: both passes
 * give the same strikes, bit for bit. */
typedef struct {
  const args *a;
  const station *st;
  af_impact *w;
  double *fine; /* the model's scratch: FINE_CAP fine steps */
  af_synth_rng g, clip;
  size_t n;     /* strikes in the bag */
  size_t drawn; /* strikes drawn so far */
} strike_source;

static void source_start(strike_source *src, const args *a, const station *st, af_impact *w,
                         double *fine)
{
  src->a = a;
  src->st = st;
  src->w = w;
  src->fine = fine;
  src->n = (size_t)a->strikes;
  src->drawn = 0;
  af_synth_rng_seed(&src->g, a->seed);
  af_synth_rng_seed(&src->clip, a->seed ^ 0x636c6970u); /* "clip": its own stream */
}

/* Draws the next strike into *sk and runs the model for it; its pulse is in
 * the shared scratch (sk->pulse.force_n = src->fine) until the next draw. */
static int source_next(strike_source *src, strike *sk)
{
  const af_lane_config *c = &src->st->lane;
  const af_impact_params nominal = src->st->model.impact;
  const double xi = c->resonance_xi, density = src->st->model.fruit_density_kg_m3;
  const size_t k = src->drawn++, n = src->n;
  memset(sk, 0, sizeof *sk);
  sk->modulus_pa =
      c->modulus_min_pa + (c->modulus_max_pa - c->modulus_min_pa) * af_synth_uniform(&src->g);
  sk->mass_kg = c->mass_min_kg + (c->mass_max_kg - c->mass_min_kg) * af_synth_uniform(&src->g);
  sk->radius_m = af_lamb_sphere_radius_m(sk->mass_kg, density);
  /* sub-sample offsets */
  sk->t_s = LEAD_IN_S + (double)k * src->a->spacing_s + 1e-3 * af_synth_uniform(&src->g);
  sk->modulus_factor =
      src->a->modulus_factor * exp(src->a->factor_spread * af_synth_gauss(&src->clip));
  sk->resonance_hz = af_lamb_frequency_hz(xi, sk->modulus_factor * sk->modulus_pa,
                                          nominal.fruit_poisson, density, sk->mass_kg);
  sk->clipped = af_synth_uniform(&src->clip) < src->a->unreliable_fraction;
  sk->tau_s = MODE_Q / (M_PI * sk->resonance_hz);
  const double ramp = n > 1 ? (double)k / (double)(n - 1) : 0.0;
  sk->velocity_m_s = nominal.velocity_m_s * (1.0 + src->a->velocity_drift * ramp);
  af_impact_params p = impact_for(src->st, sk);
  af_status rc =
      af_synth_pulse_rk4(src->w, &p, fine_dt_s(src->st), src->fine, FINE_CAP, &sk->pulse);
  if (rc != AF_OK)
    return fail("impact model", rc);
  sk->force_gain =
      sk->clipped ? CLIP_OVERDRIVE * c->strikes.strike.full_scale_n / sk->pulse.res.peak_force_n
                  : 1.0;
  return 0;
}

/* The strikes whose chunks are being written, in order: strike lo + i in
 * s[i], each owning a copy of its pulse. At least 0.1 s apart, and a strike
 * is kept from its AppleEstimate (0.2 s ahead) to the end of its audio
 * (0.5 s): about ten at most. */
#define WINDOW_MAX 64
typedef struct {
  strike s[WINDOW_MAX];
  size_t lo, len;
} strike_window;

/* Draws strikes into w until strike `index` is in it and the last one
 * drawn starts at or after until_s (or every strike is drawn). */
static int window_fill(strike_window *w, strike_source *src, size_t index, double until_s)
{
  while (src->drawn < src->n &&
         (src->drawn <= index || w->len == 0 || w->s[w->len - 1].t_s < until_s)) {
    if (w->len == WINDOW_MAX)
      return fail("more strikes in flight than the window holds", AF_ESIZE);
    strike *sk = &w->s[w->len];
    int rc = source_next(src, sk);
    if (rc != 0)
      return rc;
    sk->force_n = malloc((sk->pulse.n + 1) * sizeof *sk->force_n);
    if (!sk->force_n)
      return fail("pulse", AF_ENOMEM);
    memcpy(sk->force_n, src->fine, sk->pulse.n * sizeof *src->fine);
    sk->pulse.force_n = sk->force_n; /* off the shared scratch buffer */
    w->len++;
  }
  return 0;
}

/* Drops the strikes at the front that no chunk and no estimate still to be
 * written reaches: their AppleEstimate written, and ended (contact, audio
 * ring) before the next chunk of each stream starts. */
static void window_drop(strike_window *w, size_t next_apple, bool force_stream, double force_next_s,
                        double audio_next_s)
{
  size_t k = 0;
  while (k < w->len && w->lo + k < next_apple &&
         (!force_stream || w->s[k].t_s + w->s[k].pulse.res.contact_time_s <= force_next_s) &&
         w->s[k].t_s + 0.5 <= audio_next_s) {
    free(w->s[k].force_n);
    k++;
  }
  if (k > 0) {
    memmove(w->s, w->s + k, (w->len - k) * sizeof w->s[0]);
    w->len -= k;
    w->lo += k;
  }
}

static void window_free(strike_window *w)
{
  for (size_t k = 0; k < w->len; k++)
    free(w->s[k].force_n);
  w->len = 0;
}

/* ---- the size, before anything is written ---------------------------------------- */

/* What one message costs in the bag beyond its samples: the SignalChunk's
 * other fields, rosbag's record header and its index entry (a bag of 200
 * strikes: 4215 bytes per 1024-sample chunk) [bytes]. */
#define MSG_OVERHEAD_BYTES 120.0
#define APPLE_MSG_BYTES 300.0 /* an AppleEstimate with its record and index entry [bytes] */
#define TRUTH_ROW_BYTES 120.0 /* a row of the truth CSV [bytes] */
/* Memory: the tool's own (the libraries, the model's scratch, the strike
 * window, rosbag's chunk buffer), whatever the bag; and rosbag's index of
 * its chunks, kept until the bag is closed: a ChunkInfo per 768 kB chunk,
 * some 3 bytes per message (measured: 20 MB peak for 2,000 strikes, 35 MB
 * for 100,000) [bytes]. */
#define BASE_MEMORY_BYTES 20e6
#define INDEX_BYTES_PER_MSG 4.0

typedef struct {
  double messages;     /* SignalChunks and AppleEstimates [-] */
  double bytes;        /* the bag and the truth CSV [bytes] */
  double memory_bytes; /* peak resident memory [bytes] */
} size_estimate;

static size_estimate estimate(const args *a, const station *st)
{
  const double strikes = (double)a->strikes;
  const double duration_s = LEAD_IN_S + strikes * a->spacing_s + TAIL_S;
  double chunks = floor(duration_s * st->lane.audio.sample_rate_hz / CHUNK);
  if (!a->tap_only)
    chunks += floor(duration_s * st->lane.force.sample_rate_hz / CHUNK);
  size_estimate e;
  e.messages = chunks + strikes;
  e.bytes = chunks * (CHUNK * sizeof(float) + MSG_OVERHEAD_BYTES) +
            strikes * (APPLE_MSG_BYTES + TRUTH_ROW_BYTES);
  e.memory_bytes = BASE_MEMORY_BYTES + e.messages * INDEX_BYTES_PER_MSG;
  return e;
}

/* bytes as "2.4 TB", "812 MB" (decimal units, as df -H). */
static void human(double bytes, char *buf, size_t len)
{
  static const char *const unit[] = {"B", "kB", "MB", "GB", "TB", "PB"};
  size_t k = 0;
  while (bytes >= 1000.0 && k + 1 < sizeof unit / sizeof unit[0]) {
    bytes /= 1000.0;
    k++;
  }
  snprintf(buf, len, "%.*f %s", bytes < 10.0 && k > 0 ? 1 : 0, bytes, unit[k]);
}

/* Refuses (exit 1, one line) a bag estimated above --max-size or the free
 * space of the folder it goes to: a refusal costs nothing, a bag cut by a
 * full disk costs the time spent on it and the disk of everyone else. */
static int check_size(const args *a, const station *st)
{
  const size_estimate e = estimate(a, st);
  char size[32], mem[32], cap[32];
  human(e.bytes, size, sizeof size);
  human(e.memory_bytes, mem, sizeof mem);
  human(a->max_size_gb * 1e9, cap, sizeof cap);
  if (e.bytes > a->max_size_gb * 1e9) {
    fprintf(stderr,
            "strike_bag: refused: %ld strikes %g s apart make about %s (%.3g messages; about %s "
            "of memory), above the --max-size cap of %s\n",
            a->strikes, a->spacing_s, size, e.messages, mem, cap);
    return 1;
  }
  char dir[4096];
  snprintf(dir, sizeof dir, "%s", a->out);
  const char *folder = dirname(dir);
  struct statvfs fs;
  if (statvfs(folder, &fs) != 0) /* no such folder: the open says so, naming it */
    return 0;
  const double free_bytes = (double)fs.f_bavail * (double)fs.f_frsize;
  if (e.bytes > free_bytes) {
    char avail[32];
    human(free_bytes, avail, sizeof avail);
    fprintf(stderr,
            "strike_bag: refused: %ld strikes %g s apart make about %s (about %s of memory), "
            "above the %s free in %s\n",
            a->strikes, a->spacing_s, size, mem, avail, folder);
    return 1;
  }
  return 0;
}

/* The first pass: every strike drawn once, its truth row written;
 * *min_peak_n: the smallest peak of the bag. */
static int write_truth(const char *path, strike_source *src, double *min_peak_n)
{
  FILE *tf = fopen(path, "w");
  if (!tf) {
    fprintf(stderr, "strike_bag: cannot write %s: %s\n", path, strerror(errno));
    return 1;
  }
  fprintf(tf, "apple_id,modulus_pa,mass_kg,resonance_hz,contact_time_s,peak_force_n,"
              "contact_start_s,velocity_m_s,modulus_factor,clipped\n");
  *min_peak_n = INFINITY;
  int rc = 0;
  for (size_t k = 0; k < src->n && rc == 0 && !ferror(tf); k++) {
    strike sk;
    rc = source_next(src, &sk);
    if (rc != 0)
      break;
    *min_peak_n = fmin(*min_peak_n, sk.pulse.res.peak_force_n);
    fprintf(tf, "%zu,%.6e,%.6f,%.6f,%.9e,%.6f,%.9f,%.6f,%.6f,%d\n", k + 1, sk.modulus_pa,
            sk.mass_kg, sk.resonance_hz, sk.pulse.res.contact_time_s, sk.pulse.res.peak_force_n,
            BAG_START_S + sk.t_s, sk.velocity_m_s, sk.modulus_factor, sk.clipped);
  }
  if (af_closeout_file(tf, path) != 0)
    return 1;
  if (rc == 0)
    af_options_wrote(path);
  return rc;
}

/* The bag: the three streams merged in bag-time order. */
/* The second pass: the strikes drawn again through a window (src restarted). */
static int write_bag(const args *a, const station *sta, strike_source *src, double force_noise,
                     double audio_noise, const char *truth_path)
{
  const size_t n = src->n;
  static strike_window win; /* static: 64 strikes are large for the stack */
  memset(&win, 0, sizeof win);
  const double force_rate_hz = sta->lane.force.sample_rate_hz;
  const double audio_rate_hz = sta->lane.audio.sample_rate_hz;
  char topic[3][128]; /* force, audio, apple */
  snprintf(topic[0], sizeof topic[0], "/%s/force", a->ns);
  snprintf(topic[1], sizeof topic[1], "/%s/audio", a->ns);
  snprintf(topic[2], sizeof topic[2], "/%s/apple", a->ns);
  af_bag *bag = NULL;
  af_status st = af_bag_open_write(a->out, &bag);
  if (st != AF_OK)
    return fail(a->out, st);
  const double duration_s = LEAD_IN_S + (double)n * a->spacing_s + TAIL_S;
  uint64_t next_force = 0, next_audio = 0;
  size_t next_apple = 0;
  af_synth_rng gf, ga;
  af_synth_rng_seed(&gf, a->seed ^ 0xF0F0F0F0ULL);
  af_synth_rng_seed(&ga, a->seed ^ 0x0A0A0A0AULL);
  float buf[CHUNK];
  for (;;) {
    double tf_s = (double)(next_force + CHUNK) / force_rate_hz; /* bag time: the last sample */
    double ta_s = (double)(next_audio + CHUNK) / audio_rate_hz;
    window_drop(&win, next_apple, !a->tap_only, (double)next_force / force_rate_hz,
                (double)next_audio / audio_rate_hz);
    /* Every strike that starts before either next chunk ends, and the next
     * AppleEstimate's. */
    if (window_fill(&win, src, next_apple, fmax(tf_s, ta_s)) != 0) {
      window_free(&win);
      (void)af_bag_close(bag);
      return 1;
    }
    const strike *s = win.s;
    const size_t in_window = win.len;
    double tp_s = next_apple < n ? s[next_apple - win.lo].t_s - APPLE_LEAD_S : INFINITY;
    bool force_due = !a->tap_only && tf_s <= duration_s, audio_due = ta_s <= duration_s;
    if (!force_due && !audio_due && next_apple >= n)
      break;
    af_signal_chunk c;
    if (tp_s <= fmin(force_due ? tf_s : INFINITY, audio_due ? ta_s : INFINITY)) {
      const strike *sk = &s[next_apple - win.lo];
      af_apple_estimate e;
      memset(&e, 0, sizeof e);
      e.header.stamp = stamp_of(tp_s);
      snprintf(e.header.frame_id, sizeof e.header.frame_id, "camera_optical_frame");
      e.apple_id = (uint32_t)(next_apple + 1);
      e.mass_kg = sk->mass_kg;
      e.equatorial_radius_m = sk->radius_m;
      e.strike_radius_m = sta->model.impact.strike_radius_m;
      e.stem_axis.x = 1.0;
      e.confidence = 0.9;
      st = af_bag_write(bag, topic[2], AF_MSG_APPLE_ESTIMATE, &e, e.header.stamp);
      next_apple++;
    } else if (force_due && (!audio_due || tf_s <= ta_s)) {
      make_chunk(sta, s, in_window, true, next_force, &gf, force_noise, buf, &c);
      st = af_bag_write(bag, topic[0], AF_MSG_SIGNAL_CHUNK, &c, stamp_of(tf_s));
      next_force += CHUNK;
    } else {
      make_chunk(sta, s, in_window, false, next_audio, &ga, audio_noise, buf, &c);
      st = af_bag_write(bag, topic[1], AF_MSG_SIGNAL_CHUNK, &c, stamp_of(ta_s));
      next_audio += CHUNK;
    }
    if (st == AF_EIO) { /* the file failed (a full disk): the close removes the partial bag */
      window_free(&win);
      (void)af_bag_close(bag);
      fprintf(stderr, "strike_bag: cannot write %s\n", af_bag_last_error(NULL));
      return 1;
    }
    if (st != AF_OK) {
      fprintf(stderr, "strike_bag: writing %s: %s (%s)\n", a->out, af_strerror(st),
              af_bag_last_error(bag));
      window_free(&win);
      af_bag_close(bag);
      return 1;
    }
  }
  window_free(&win);
  st = af_bag_close(bag);
  if (st != AF_OK) {
    fprintf(stderr, "strike_bag: cannot write %s\n", af_bag_last_error(NULL));
    return 1;
  }
  af_options_wrote(a->out);
  printf("strike_bag: %zu strikes, %.1f s (force %llu samples at %.0f Hz%s, audio %llu at %.0f "
         "Hz), seed %llu -> %s, truth %s\n",
         n, duration_s, (unsigned long long)next_force, force_rate_hz,
         a->tap_only ? ": tap-only, no force topic" : "", (unsigned long long)next_audio,
         audio_rate_hz, (unsigned long long)a->seed, a->out, truth_path);
  return 0;
}

int main(int argc, char **argv)
{
  af_closeout_install("strike_bag");
  args a;
  if (!af_options_args_plain("strike_bag", argc, argv))
    return 2;
  if (af_options_want_help(argc, argv, 1)) {
    help();
    return 0;
  }
  int rc = parse(argc, argv, &a);
  if (rc)
    return rc;
  char truth_path[1024];
  if (a.truth) {
    snprintf(truth_path, sizeof truth_path, "%s", a.truth);
  } else {
    size_t len = strlen(a.out);
    size_t stem = len > 4 && strcmp(a.out + len - 4, ".bag") == 0 ? len - 4 : len;
    snprintf(truth_path, sizeof truth_path, "%.*s.truth.csv", (int)stem, a.out);
  }
  static station sta; /* static: a lane configuration is large for the stack */
  char err[512];
  af_settings table;
  af_settings_reset(&table);
  if (af_lane_config_for_tool(&table, &sta.lane, err, sizeof err) != AF_OK ||
      af_model_params_from_settings(&table, &sta.model, err, sizeof err) != AF_OK) {
    fprintf(stderr, "strike_bag: the parameter table's defaults: %s\n", err);
    return 1;
  }
  rc = check_size(&a, &sta);
  if (rc != 0)
    return rc;
  double *fine = calloc(FINE_CAP, sizeof *fine);
  af_impact *w = NULL;
  double min_peak_n = INFINITY;
  strike_source src;
  if (!fine || af_impact_create(&w) != AF_OK)
    rc = fail("workspace", AF_ENOMEM);
  if (rc == 0) {
    source_start(&src, &a, &sta, w, fine);
    rc = write_truth(truth_path, &src, &min_peak_n);
  }
  if (rc == 0) {
    source_start(&src, &a, &sta, w, fine);
    rc = write_bag(&a, &sta, &src, af_synth_noise_rms(min_peak_n, FORCE_SNR_DB),
                   af_synth_noise_rms(MODE_AMPLITUDE_PA, AUDIO_SNR_DB), truth_path);
  }
  af_impact_destroy(w);
  free(fine);
  return rc;
}
