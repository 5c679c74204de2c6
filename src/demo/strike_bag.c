/* strike_bag — a rosbag of synthetic strikes for the replay demo and the
 * strikes rostest, with the truth it was made from.
 *
 *   strike_bag --strikes N --out FILE [--seed S] [--truth FILE] [--ns NAME]
 *              [--spacing S] [--velocity-drift X] [--modulus-factor F]
 *              [--modulus-factor-spread S] [--unreliable-fraction P] [--tap-only]
 *                                     (flags: the table `options`; --help)
 *
 * Per strike k (apple_id k + 1), spacing S apart (default 0.5 s) after a
 * 1 s lead-in, with a random sub-millisecond offset:
 * The station, the cultivar and the strike are the parameter table's
 * defaults (src/core/settings_table.c; what config/station.yaml,
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
 * --tap-only: a microphone-only rig (issue 19): no /NS/force topic at all;
 * the audio and the apples as above (the node and firmness_report then run
 * with tap_only true).
 *
 * Seeded (af_synth_rng, splitmix64): the same seed gives the same bag on
 * every machine. Exit 0, 2 on bad arguments, 1 on failure. */
#include <errno.h>
#include <math.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

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
} args;

#define STRIKES_MAX 100000    /* strikes in one bag */
#define SPACING_MIN_S 0.1     /* [s] */
#define SPACING_MAX_S 60      /* [s] */
#define DRIFT_MAX 0.5         /* |--velocity-drift| [-] */
#define UNRELIABLE_MAX 0.9    /* share of clipped strikes */
#define FACTOR_SPREAD_MAX 0.3 /* relative SD of the factor between apples */
#define CLIP_OVERDRIVE 1.25   /* a clipped strike's peak / strike_full_scale_n */

/* The defaults the parser starts from; --strikes and --out are required. */
static const args args_defaults = {0, NULL, NULL, "lane1", 1, 0.5, 0.0, 1.0, 0.0, 0.0, false};

#define AF_ARG(field) offsetof(args, field)
static const af_option options[] = {
    {"--strikes", "N", AF_OPTION_LONG, AF_ARG(strikes), -1,
     "strikes (apples), a whole number in [1, " AF_OPTION_STR(STRIKES_MAX) "] [-]", NULL},
    {"--out", "FILE", AF_OPTION_TEXT, AF_ARG(out), -1, "the bag", NULL},
    {"--seed", "S", AF_OPTION_U64, AF_ARG(seed), -1,
     "seed of the noise and the apples, a whole number >= 0 [-]", NULL},
    {"--truth", "FILE", AF_OPTION_TEXT, AF_ARG(truth), -1, "the truth CSV",
     "FILE of --out without .bag, + .truth.csv"},
    {"--ns", "NAME", AF_OPTION_TEXT, AF_ARG(ns), -1,
     "lane namespace of the topics /NS/force, /NS/audio, /NS/apple", NULL},
    {"--spacing", "S", AF_OPTION_NUMBER, AF_ARG(spacing_s), -1,
     "time between strikes, in [" AF_OPTION_STR(SPACING_MIN_S) ", " AF_OPTION_STR(
         SPACING_MAX_S) "] [s]",
     NULL},
    {"--velocity-drift", "X", AF_OPTION_NUMBER, AF_ARG(velocity_drift), -1,
     "contact velocity of strike k of N: strike_velocity_m_s (1 + X k / (N - 1)), X in "
     "[-" AF_OPTION_STR(DRIFT_MAX) ", " AF_OPTION_STR(DRIFT_MAX) "] (0.05: +5 % over the bag) [-]",
     "0: a constant contact velocity"},
    {"--modulus-factor", "F", AF_OPTION_NUMBER, AF_ARG(modulus_factor), -1,
     "true dynamic / quasi-static modulus of the 0S2 (within the modulus_factor row's range) [-]",
     NULL},
    {"--modulus-factor-spread", "S", AF_OPTION_NUMBER, AF_ARG(factor_spread), -1,
     "relative SD of the true factor between apples (lognormal), in [0, " AF_OPTION_STR(
         FACTOR_SPREAD_MAX) "] [-]",
     "0: every apple has F"},
    {"--unreliable-fraction", "P", AF_OPTION_NUMBER, AF_ARG(unreliable_fraction), -1,
     "share of strikes clipped (too hard for the transducer), in [0, " AF_OPTION_STR(
         UNRELIABLE_MAX) "] [-]",
     "0: none clipped"},
    {"--tap-only", NULL, AF_OPTION_SWITCH, AF_ARG(tap_only), -1,
     "a microphone-only rig: no force topic (audio and apples only)", NULL},
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
  for (int i = 1; i < argc; i++) {
    const char *flag = argv[i];
    const af_option *o = af_option_find(options, N_OPTIONS, flag);
    if (o == NULL) {
      af_options_unknown("strike_bag", options, N_OPTIONS, flag, NULL);
      return 2;
    }
    if (o->value == NULL) { /* a switch: --tap-only */
      a->tap_only = true;
      continue;
    }
    if (i + 1 >= argc) {
      af_options_missing("strike_bag", o);
      return 2;
    }
    const char *v = argv[++i];
    char *end = NULL;
    errno = 0;
    if (strcmp(flag, "--strikes") == 0) {
      a->strikes = strtol(v, &end, 10);
      if (errno || *end || a->strikes < 1 || a->strikes > STRIKES_MAX)
        return usage("--strikes must be a whole number in [1, " AF_OPTION_STR(STRIKES_MAX) "], got",
                     v);
    } else if (strcmp(flag, "--seed") == 0) {
      unsigned long long s = strtoull(v, &end, 10);
      if (errno || *end || v[0] == '-')
        return usage("--seed must be a non-negative whole number, got", v);
      a->seed = (uint64_t)s;
    } else if (strcmp(flag, "--spacing") == 0) {
      a->spacing_s = strtod(v, &end);
      if (errno || *end || !(a->spacing_s >= SPACING_MIN_S && a->spacing_s <= SPACING_MAX_S))
        return usage("--spacing must be in [" AF_OPTION_STR(SPACING_MIN_S) ", " AF_OPTION_STR(
                         SPACING_MAX_S) "] s, got",
                     v);
    } else if (strcmp(flag, "--velocity-drift") == 0) {
      a->velocity_drift = strtod(v, &end);
      if (errno || *end || end == v || !(fabs(a->velocity_drift) <= DRIFT_MAX))
        return usage("--velocity-drift must be in [-" AF_OPTION_STR(DRIFT_MAX) ", " AF_OPTION_STR(
                         DRIFT_MAX) "], got",
                     v);
    } else if (strcmp(flag, "--modulus-factor") == 0) {
      af_setting_range r;
      a->modulus_factor = strtod(v, &end);
      if (af_setting_range_of(AF_SETTING_MODULUS_FACTOR, &r) != AF_OK || errno || *end ||
          !af_setting_range_contains(&r, a->modulus_factor)) {
        char msg[96];
        snprintf(msg, sizeof msg,
                 "--modulus-factor must be in [%g, %g] (the modulus_factor row), got", r.lo, r.hi);
        return usage(msg, v);
      }
    } else if (strcmp(flag, "--modulus-factor-spread") == 0) {
      a->factor_spread = strtod(v, &end);
      if (errno || *end || !(a->factor_spread >= 0.0 && a->factor_spread <= FACTOR_SPREAD_MAX))
        return usage(
            "--modulus-factor-spread must be in [0, " AF_OPTION_STR(FACTOR_SPREAD_MAX) "], got", v);
    } else if (strcmp(flag, "--unreliable-fraction") == 0) {
      a->unreliable_fraction = strtod(v, &end);
      if (errno || *end ||
          !(a->unreliable_fraction >= 0.0 && a->unreliable_fraction <= UNRELIABLE_MAX))
        return usage("--unreliable-fraction must be in [0, " AF_OPTION_STR(UNRELIABLE_MAX) "], got",
                     v);
    } else {
      (void)af_option_store(o, v, a);
    }
  }
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
  const double hum_hz = st->lane.measured.measure.response.hum_hz; /* the site's mains [Hz] */
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
  const double full_scale_n = st->lane.measured.strike.full_scale_n;
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

/* Draws the strikes and runs the model for each; *min_peak_n: the smallest peak. */
static int make_strikes(const args *a, const station *st, af_impact *w, double *fine, strike *s,
                        size_t n, double *min_peak_n)
{
  const af_lane_config *c = &st->lane;
  const af_impact_params nominal = st->model.impact;
  const double xi = c->resonance_xi, density = st->model.fruit_density_kg_m3;
  af_synth_rng g, clip;
  af_synth_rng_seed(&g, a->seed);
  af_synth_rng_seed(&clip, a->seed ^ 0x636c6970u); /* "clip": its own stream */
  *min_peak_n = INFINITY;
  for (size_t k = 0; k < n; k++) {
    strike *sk = &s[k];
    sk->modulus_pa =
        c->modulus_min_pa + (c->modulus_max_pa - c->modulus_min_pa) * af_synth_uniform(&g);
    sk->mass_kg = c->mass_min_kg + (c->mass_max_kg - c->mass_min_kg) * af_synth_uniform(&g);
    sk->radius_m = af_lamb_sphere_radius_m(sk->mass_kg, density);
    /* sub-sample offsets */
    sk->t_s = LEAD_IN_S + (double)k * a->spacing_s + 1e-3 * af_synth_uniform(&g);
    sk->modulus_factor = a->modulus_factor * exp(a->factor_spread * af_synth_gauss(&clip));
    sk->resonance_hz = af_lamb_frequency_hz(xi, sk->modulus_factor * sk->modulus_pa,
                                            nominal.fruit_poisson, density, sk->mass_kg);
    sk->clipped = af_synth_uniform(&clip) < a->unreliable_fraction;
    sk->tau_s = MODE_Q / (M_PI * sk->resonance_hz);
    const double ramp = n > 1 ? (double)k / (double)(n - 1) : 0.0;
    sk->velocity_m_s = nominal.velocity_m_s * (1.0 + a->velocity_drift * ramp);
    af_impact_params p = impact_for(st, sk);
    af_status rc = af_synth_pulse_rk4(w, &p, fine_dt_s(st), fine, FINE_CAP, &sk->pulse);
    if (rc != AF_OK)
      return fail("impact model", rc);
    sk->force_n = malloc((sk->pulse.n + 1) * sizeof *sk->force_n);
    if (!sk->force_n)
      return fail("pulse", AF_ENOMEM);
    memcpy(sk->force_n, fine, sk->pulse.n * sizeof *fine);
    sk->pulse.force_n = sk->force_n; /* off the shared scratch buffer */
    *min_peak_n = fmin(*min_peak_n, sk->pulse.res.peak_force_n);
    sk->force_gain =
        sk->clipped ? CLIP_OVERDRIVE * c->measured.strike.full_scale_n / sk->pulse.res.peak_force_n
                    : 1.0;
  }
  return 0;
}

static int write_truth(const char *path, const strike *s, size_t n)
{
  FILE *tf = fopen(path, "w");
  if (!tf) {
    fprintf(stderr, "strike_bag: cannot write %s: %s\n", path, strerror(errno));
    return 1;
  }
  fprintf(tf, "apple_id,modulus_pa,mass_kg,resonance_hz,contact_time_s,peak_force_n,"
              "contact_start_s,velocity_m_s,modulus_factor,clipped\n");
  for (size_t k = 0; k < n; k++)
    fprintf(tf, "%zu,%.6e,%.6f,%.6f,%.9e,%.6f,%.9f,%.6f,%.6f,%d\n", k + 1, s[k].modulus_pa,
            s[k].mass_kg, s[k].resonance_hz, s[k].pulse.res.contact_time_s,
            s[k].pulse.res.peak_force_n, BAG_START_S + s[k].t_s, s[k].velocity_m_s,
            s[k].modulus_factor, s[k].clipped);
  if (fclose(tf) != 0) {
    fprintf(stderr, "strike_bag: cannot write %s\n", path);
    return 1;
  }
  af_options_wrote(path);
  return 0;
}

/* The bag: the three streams merged in bag-time order. */
static int write_bag(const args *a, const station *sta, const strike *s, size_t n,
                     double force_noise, double audio_noise, const char *truth_path)
{
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
    double tp_s = next_apple < n ? s[next_apple].t_s - APPLE_LEAD_S : INFINITY;
    bool force_due = !a->tap_only && tf_s <= duration_s, audio_due = ta_s <= duration_s;
    if (!force_due && !audio_due && next_apple >= n)
      break;
    af_signal_chunk c;
    if (tp_s <= fmin(force_due ? tf_s : INFINITY, audio_due ? ta_s : INFINITY)) {
      const strike *sk = &s[next_apple];
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
      make_chunk(sta, s, n, true, next_force, &gf, force_noise, buf, &c);
      st = af_bag_write(bag, topic[0], AF_MSG_SIGNAL_CHUNK, &c, stamp_of(tf_s));
      next_force += CHUNK;
    } else {
      make_chunk(sta, s, n, false, next_audio, &ga, audio_noise, buf, &c);
      st = af_bag_write(bag, topic[1], AF_MSG_SIGNAL_CHUNK, &c, stamp_of(ta_s));
      next_audio += CHUNK;
    }
    if (st != AF_OK) {
      fprintf(stderr, "strike_bag: writing %s: %s (%s)\n", a->out, af_strerror(st),
              af_bag_last_error(bag));
      af_bag_close(bag);
      return 1;
    }
  }
  st = af_bag_close(bag);
  if (st != AF_OK)
    return fail(a->out, st);
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
  const size_t n = (size_t)a.strikes;
  strike *s = calloc(n, sizeof *s);
  double *fine = calloc(FINE_CAP, sizeof *fine);
  af_impact *w = NULL;
  double min_peak_n = INFINITY;
  if (!s || !fine || af_impact_create(&w) != AF_OK)
    rc = fail("workspace", AF_ENOMEM);
  if (rc == 0)
    rc = make_strikes(&a, &sta, w, fine, s, n, &min_peak_n);
  if (rc == 0)
    rc = write_truth(truth_path, s, n);
  if (rc == 0)
    rc = write_bag(&a, &sta, s, n, af_synth_noise_rms(min_peak_n, FORCE_SNR_DB),
                   af_synth_noise_rms(MODE_AMPLITUDE_PA, AUDIO_SNR_DB), truth_path);
  for (size_t k = 0; s && k < n; k++)
    free(s[k].force_n);
  af_impact_destroy(w);
  free(fine);
  free(s);
  return rc;
}
