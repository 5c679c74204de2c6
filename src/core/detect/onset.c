/* onset.c — taps found in the audio's energy against its running noise floor
 * (see onset.h). */
#include "onset.h"

#include <math.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

#include "af_defaults.h"

/* The least share of two frames' energy about dc that must alternate about
 * their own mean for a candidate to be a sound: a ring loses at most a
 * tenth to its mean over more than a period, a step of the level nearly
 * all of it. */
#define AF_ONSET_AC_SHARE 0.5

/* A rise is judged against the mean of the frames 2..4 before (the one
 * before may hold the start of the tap): over a ring's tail a single frame
 * shorter than its period may catch a zero crossing, and the next one its
 * crest 12 dB above; three frames (3 ms at the default) span a period of
 * any 0S2 above 330 Hz and most of one down to 250 Hz, and their mean over
 * noise varies less than one frame's, so a weak tap is not lost to it. */
#define AF_ONSET_RISE_FRAMES 4

struct af_onset {
  af_onset_config cfg;
  size_t frame_n;     /* samples per frame */
  double threshold;   /* 10^(snr_db / 10) */
  double alpha;       /* floor update weight per frame: frame_s / floor_time_constant_s */
  uint64_t holdoff_n; /* [samples] */
  double floor_min;   /* the floor's lower bound: max(floor_rms, quantum)^2 [unit^2] */
  float *frame;       /* the current frame's samples (frame_n) */
  size_t fill;        /* samples in the current frame */
  bool bad;           /* a non-finite sample in this frame */
  uint64_t frame_start, next_sample;
  bool started;
  double floor;  /* mean square of the noise about dc; NaN: none yet */
  double dc;     /* the signal's resting level [unit]: energies are taken about it */
  uint64_t warm; /* frames averaged so far in the warm-up */
  double before[AF_ONSET_RISE_FRAMES]; /* the energies of the frames before this one, the
                                          last first; NaN: none */
  /* The candidate onset, held for holdoff_s before it is reported: a rise
   * of SNR over everything since replaces it (the candidate was a noise
   * gate opening onto noise, the tap comes now), and it is reported only
   * when a frame pair after its own frame holds alternating energy above
   * the threshold (a step of the level is no tap). */
  bool pending;
  af_onset_event cand;
  uint64_t cand_frame; /* the candidate frame's first sample */
  double cand_peak;    /* the largest frame energy since it [unit^2] */
  bool cand_ac;        /* alternating energy heard after its frame */
  bool prev_valid;     /* prev_s1, prev_s2: the last frame's sums about dc, after cand_frame */
  double prev_s1, prev_s2;
  bool fired_once;
  uint64_t last_onset;
  uint64_t count;
};

af_onset_config af_onset_config_default(void)
{
  af_onset_config c = {
      .sample_rate_hz = AF_DEFAULT_AUDIO_SAMPLE_RATE_HZ,
      .frame_s = AF_DEFAULT_ONSET_FRAME_S,
      .snr_db = AF_DEFAULT_ONSET_SNR_DB,
      .holdoff_s = AF_DEFAULT_ONSET_HOLDOFF_S,
      .floor_time_constant_s = AF_DEFAULT_ONSET_FLOOR_TIME_CONSTANT_S,
      .floor_rms = AF_DEFAULT_ONSET_FLOOR,
      .quantum = 0.0,
  };
  return c;
}

af_status af_onset_config_check(const af_onset_config *c, const char **field)
{
  const char *f = NULL;
  if (c == NULL)
    f = "config";
  else if (!(isfinite(c->sample_rate_hz) && c->sample_rate_hz > 0.0))
    f = "sample_rate_hz";
  else if (!(isfinite(c->frame_s) && c->frame_s * c->sample_rate_hz >= AF_ONSET_MIN_FRAME_SAMPLES))
    f = "onset_frame_s";
  else if (!(isfinite(c->snr_db) && c->snr_db > 0.0))
    f = "onset_snr_db";
  else if (!(isfinite(c->holdoff_s) && c->holdoff_s >= c->frame_s))
    f = "onset_holdoff_s";
  else if (!(isfinite(c->floor_time_constant_s) && c->floor_time_constant_s >= c->frame_s))
    f = "onset_floor_time_constant_s";
  else if (!(isfinite(c->floor_rms) && c->floor_rms > 0.0))
    f = "onset_floor";
  else if (!(isfinite(c->quantum) && c->quantum >= 0.0))
    f = "quantum";
  if (field != NULL)
    *field = f;
  return f == NULL ? AF_OK : AF_EINVAL;
}

af_status af_onset_create(const af_onset_config *cfg, af_onset **out)
{
  if (out == NULL)
    return AF_EINVAL;
  *out = NULL;
  if (af_onset_config_check(cfg, NULL) != AF_OK)
    return AF_EINVAL;
  af_onset *o = calloc(1, sizeof *o);
  if (o == NULL)
    return AF_ENOMEM;
  o->cfg = *cfg;
  o->frame_n = (size_t)llround(cfg->frame_s * cfg->sample_rate_hz);
  o->threshold = pow(10.0, cfg->snr_db / 10.0);
  o->alpha = cfg->frame_s / cfg->floor_time_constant_s;
  o->holdoff_n = (uint64_t)llround(cfg->holdoff_s * cfg->sample_rate_hz);
  const double q = fmax(cfg->floor_rms, cfg->quantum);
  o->floor_min = q * q;
  o->frame = malloc(o->frame_n * sizeof *o->frame);
  if (o->frame == NULL) {
    free(o);
    return AF_ENOMEM;
  }
  af_onset_reset(o);
  *out = o;
  return AF_OK;
}

void af_onset_destroy(af_onset *o)
{
  if (o == NULL)
    return;
  free(o->frame);
  free(o);
}

static void set_before(af_onset *o, double e)
{
  for (size_t k = 0; k < AF_ONSET_RISE_FRAMES; k++)
    o->before[k] = e;
}

/* The mean energy of the frames 2..4 before this one (those known); NaN
 * when none is known. */
static double rise_reference(const af_onset *o)
{
  double sum = 0.0;
  size_t n = 0;
  for (size_t k = 1; k < AF_ONSET_RISE_FRAMES; k++)
    if (!isnan(o->before[k])) {
      sum += o->before[k];
      n++;
    }
  return n > 0 ? sum / (double)n : NAN;
}

void af_onset_reset(af_onset *o)
{
  if (o == NULL)
    return;
  o->fill = 0;
  o->bad = false;
  o->started = false;
  o->floor = NAN;
  o->dc = 0.0;
  o->warm = 0;
  set_before(o, NAN);
  o->pending = false;
  o->prev_valid = false;
  o->fired_once = false;
  o->count = 0;
}

static int cmp_double(const void *a, const void *b)
{
  const double x = *(const double *)a, y = *(const double *)b;
  return (x > y) - (x < y);
}

/* The mean of the values at or below the median of v[0..m) (sorts v). */
static double lower_half_mean(double *v, size_t m)
{
  qsort(v, m, sizeof *v, cmp_double);
  double s = 0.0;
  const size_t half = m / 2 + 1;
  for (size_t k = 0; k < half; k++)
    s += v[k];
  return s / (double)half;
}

af_status af_onset_prime(af_onset *o, const float *x, size_t n)
{
  if (o == NULL || (x == NULL && n > 0))
    return AF_EINVAL;
  const size_t frames = n / o->frame_n;
  double *mean = frames ? malloc(2 * frames * sizeof *mean) : NULL;
  double *e = mean + frames;
  if (frames > 0 && mean == NULL)
    return AF_ENOMEM;
  size_t m = 0;
  for (size_t f = 0; f < frames; f++) {
    double s = 0.0;
    for (size_t k = 0; k < o->frame_n; k++)
      s += x[f * o->frame_n + k];
    if (isfinite(s))
      mean[m++] = s / (double)o->frame_n;
  }
  af_status st = AF_ENODATA;
  if (m >= AF_ONSET_WARMUP_FRAMES) {
    /* The resting level: the median frame mean (a tap's frames are few). */
    qsort(mean, m, sizeof *mean, cmp_double);
    const double dc = mean[m / 2];
    /* The energies about it; frames that vary by less than the floor's
     * bound (digital silence: a gate closed, padding) say nothing about the
     * noise and are left out while enough others remain. */
    size_t heard = 0, all = 0;
    for (size_t f = 0; f < frames; f++) {
      double s = 0.0, s1 = 0.0;
      for (size_t k = 0; k < o->frame_n; k++) {
        const double y = x[f * o->frame_n + k] - dc;
        s += y * y;
        s1 += y;
      }
      if (!isfinite(s))
        continue;
      const double ms = s / (double)o->frame_n, mu = s1 / (double)o->frame_n;
      if (ms - mu * mu >= o->floor_min)
        e[heard++] = ms;
      all++;
    }
    if (heard < AF_ONSET_WARMUP_FRAMES) { /* silence throughout: the bound */
      heard = 0;
      for (size_t k = 0; k < all; k++)
        e[heard++] = 0.0;
    }
    o->floor = lower_half_mean(e, heard);
    o->dc = dc;
    o->warm = AF_ONSET_WARMUP_FRAMES;
    st = AF_OK;
  }
  free(mean);
  return st;
}

/* The first sample of the firing frame whose square about dc reaches the
 * threshold. */
static uint64_t onset_sample(const af_onset *o, double level)
{
  for (size_t k = 0; k < o->fill; k++) {
    const double y = o->frame[k] - o->dc;
    if (y * y >= level)
      return o->frame_start + k;
  }
  return o->frame_start;
}

/* A candidate from the current frame. */
static void candidate(af_onset *o, double e, double fl, double level)
{
  o->pending = true;
  o->cand = (af_onset_event){
      .sample = onset_sample(o, level), .snr_db = 10.0 * log10(e / fl), .floor_ms = fl};
  o->cand_frame = o->frame_start;
  o->cand_peak = e;
  o->cand_ac = false;
  o->prev_valid = false;
}

/* The held candidate, given the current frame (its sums s1, s2 about dc):
 * replaced, confirmed by alternating energy, and at the end of its hold-off
 * reported or dropped. */
static void hold(af_onset *o, double s1, double s2, double e, double level, double rise_ref,
                 af_onset_fn *fn, void *user)
{
  const double n = (double)o->frame_n;
  const double fl = level / o->threshold;
  if (o->frame_start >= o->cand_frame + 2 * o->frame_n && e >= level &&
      e >= o->threshold * o->cand_peak && !(e < o->threshold * rise_ref)) {
    candidate(o, e, fl, level); /* the held one was no tap: a gate opening, a hum's swell */
    return;
  }
  o->cand_peak = fmax(o->cand_peak, e);
  if (o->frame_start > o->cand_frame) {
    /* Alternating energy over two frames (2 ms at the default: more than a
     * period of the 0S2): most of their mean square about dc is about their
     * own mean too (a ring, or noise; a step of the level is not). */
    if (o->prev_valid) {
      const double mu = (o->prev_s1 + s1) / (2.0 * n), ms = (o->prev_s2 + s2) / (2.0 * n);
      if (ms - mu * mu >= AF_ONSET_AC_SHARE * ms && ms > 0.0)
        o->cand_ac = true;
    }
    o->prev_valid = true;
    o->prev_s1 = s1;
    o->prev_s2 = s2;
  }
  if (o->frame_start + o->frame_n < o->cand.sample + o->holdoff_n)
    return;
  o->pending = false;
  if (!o->cand_ac) {
    /* A step of the level, no ring: the resting level moves to it, and
     * nothing is reported. */
    const double mu = s1 / n;
    o->dc += mu;
    set_before(o, s2 / n - mu * mu);
    return;
  }
  o->fired_once = true;
  o->last_onset = o->cand.sample;
  o->count++;
  if (fn != NULL)
    fn(&o->cand, user);
}

/* One complete frame: the floor, the hold-off, perhaps an onset. */
static void frame_done(af_onset *o, af_onset_fn *fn, void *user)
{
  const double n = (double)o->frame_n;
  double s1 = 0.0, s2 = 0.0;
  for (size_t k = 0; k < o->frame_n; k++) {
    const double y = o->frame[k] - o->dc;
    s1 += y;
    s2 += y * y;
  }
  const double e = s2 / n, mu = s1 / n;
  /* Nothing varies in it by the floor's bound: digital silence (exact zeros
   * between sounds, a constant level) teaches the floor nothing. */
  const bool silent = e - mu * mu < o->floor_min;
  const double rise_ref = rise_reference(o);
  memmove(o->before + 1, o->before, (AF_ONSET_RISE_FRAMES - 1) * sizeof o->before[0]);
  o->before[0] = e;
  if (o->warm < AF_ONSET_WARMUP_FRAMES) { /* the first floor: a plain mean */
    o->warm++;
    o->floor = isnan(o->floor) ? e : o->floor + (e - o->floor) / (double)o->warm;
    o->dc += mu / (double)o->warm;
    return;
  }
  const double fl = fmax(o->floor, o->floor_min);
  const double level = fl * o->threshold;
  if (o->pending) {
    hold(o, s1, s2, e, level, rise_ref, fn, user);
    return;
  }
  if (e < level) {
    if (!silent) {
      o->floor += o->alpha * (e - o->floor);
      o->dc += o->alpha * mu;
    }
    return;
  }
  /* A rise: e reaches the threshold over the frames 2..4 before too
   * (rise_reference; the one before may hold the start of the tap); the
   * swell of a ring already sounding (beats of two close modes) does not;
   * a new tap over the tail of the last one does. */
  if (e < o->threshold * rise_ref)
    return;
  candidate(o, e, fl, level);
}

af_status af_onset_write(af_onset *o, uint64_t first_sample, const float *x, size_t n,
                         af_onset_fn *fn, void *user)
{
  if (o == NULL || (x == NULL && n > 0))
    return AF_EINVAL;
  if (!o->started || first_sample != o->next_sample) { /* a new frame at a jump */
    o->fill = 0;
    o->bad = false;
    o->started = true;
  }
  for (size_t k = 0; k < n; k++) {
    if (o->fill == 0)
      o->frame_start = first_sample + k;
    const float v = x[k];
    o->frame[o->fill++] = v;
    if (!isfinite(v))
      o->bad = true;
    if (o->fill == o->frame_n) {
      if (!o->bad)
        frame_done(o, fn, user);
      else
        set_before(o, NAN); /* no rise judged across lost samples */
      o->fill = 0;
      o->bad = false;
    }
  }
  o->next_sample = first_sample + n;
  return AF_OK;
}

uint64_t af_onset_count(const af_onset *o)
{
  return o == NULL ? 0 : o->count;
}

double af_onset_floor(const af_onset *o)
{
  return o == NULL || o->warm < AF_ONSET_WARMUP_FRAMES ? NAN : fmax(o->floor, o->floor_min);
}
