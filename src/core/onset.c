/* onset.c — taps found in the audio's energy against its running noise floor
 * (see onset.h). */
#include "onset.h"

#include <math.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

#include "af_defaults.h"

struct af_onset {
  af_onset_config cfg;
  size_t frame_n;     /* samples per frame */
  double threshold;   /* 10^(snr_db / 10) */
  double alpha;       /* floor update weight per frame: frame_s / floor_time_constant_s */
  uint64_t holdoff_n; /* [samples] */
  float *frame;       /* the current frame's samples (frame_n) */
  size_t fill;        /* samples in the current frame */
  double sum;         /* their sum of squares */
  bool bad;           /* a non-finite sample in this frame */
  uint64_t frame_start, next_sample;
  bool started;
  double floor;     /* mean square of the noise; NaN: none yet */
  uint64_t warm;    /* frames averaged so far in the warm-up */
  double before[2]; /* the energies of the two frames before this one; NaN: none */
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

void af_onset_reset(af_onset *o)
{
  if (o == NULL)
    return;
  o->fill = 0;
  o->sum = 0.0;
  o->bad = false;
  o->started = false;
  o->floor = NAN;
  o->warm = 0;
  o->before[0] = o->before[1] = NAN;
  o->fired_once = false;
  o->count = 0;
}

static int cmp_double(const void *a, const void *b)
{
  const double x = *(const double *)a, y = *(const double *)b;
  return (x > y) - (x < y);
}

af_status af_onset_prime(af_onset *o, const float *x, size_t n)
{
  if (o == NULL || (x == NULL && n > 0))
    return AF_EINVAL;
  const size_t frames = n / o->frame_n;
  double *e = frames ? malloc(frames * sizeof *e) : NULL;
  size_t m = 0;
  for (size_t f = 0; f < frames; f++) {
    double s = 0.0;
    for (size_t k = 0; k < o->frame_n; k++)
      s += (double)x[f * o->frame_n + k] * x[f * o->frame_n + k];
    if (isfinite(s))
      e[m++] = s / (double)o->frame_n;
  }
  af_status st = AF_ENODATA;
  if (m >= AF_ONSET_WARMUP_FRAMES) {
    qsort(e, m, sizeof *e, cmp_double);
    double s = 0.0;
    size_t half = m / 2 + 1;
    for (size_t k = 0; k < half; k++)
      s += e[k];
    o->floor = s / (double)half;
    o->warm = AF_ONSET_WARMUP_FRAMES;
    st = AF_OK;
  }
  free(e);
  return st;
}

/* The first sample of the firing frame whose square reaches the threshold. */
static uint64_t onset_sample(const af_onset *o, double level)
{
  for (size_t k = 0; k < o->fill; k++)
    if ((double)o->frame[k] * o->frame[k] >= level)
      return o->frame_start + k;
  return o->frame_start;
}

/* One complete frame: the floor, the hold-off, perhaps an onset. */
static void frame_done(af_onset *o, af_onset_fn *fn, void *user)
{
  const double e = o->sum / (double)o->frame_n;
  const double two_before = o->before[1];
  o->before[1] = o->before[0];
  o->before[0] = e;
  if (o->warm < AF_ONSET_WARMUP_FRAMES) { /* the first floor: a plain mean */
    o->warm++;
    o->floor = isnan(o->floor) ? e : o->floor + (e - o->floor) / (double)o->warm;
    return;
  }
  const double level = o->floor * o->threshold;
  const bool held = o->fired_once && o->frame_start < o->last_onset + o->holdoff_n;
  if (e < level) {
    if (!held)
      o->floor += o->alpha * (e - o->floor);
    return;
  }
  /* A rise: e reaches the threshold over the frame two before too (the one
   * before may hold the start of the tap); the swell of a ring already
   * sounding (beats of two close modes) does not; a new tap over the tail
   * of the last one does. */
  if (held || e < o->threshold * two_before)
    return;
  af_onset_event ev = {
      .sample = onset_sample(o, level), .snr_db = 10.0 * log10(e / o->floor), .floor_ms = o->floor};
  o->fired_once = true;
  o->last_onset = ev.sample;
  o->count++;
  if (fn != NULL)
    fn(&ev, user);
}

af_status af_onset_write(af_onset *o, uint64_t first_sample, const float *x, size_t n,
                         af_onset_fn *fn, void *user)
{
  if (o == NULL || (x == NULL && n > 0))
    return AF_EINVAL;
  if (!o->started || first_sample != o->next_sample) { /* a new frame at a jump */
    o->fill = 0;
    o->sum = 0.0;
    o->bad = false;
    o->started = true;
  }
  for (size_t k = 0; k < n; k++) {
    if (o->fill == 0)
      o->frame_start = first_sample + k;
    const float v = x[k];
    o->frame[o->fill++] = v;
    if (isfinite(v))
      o->sum += (double)v * v;
    else
      o->bad = true;
    if (o->fill == o->frame_n) {
      if (!o->bad)
        frame_done(o, fn, user);
      else
        o->before[0] = o->before[1] = NAN; /* no rise judged across lost samples */
      o->fill = 0;
      o->sum = 0.0;
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
  return o == NULL || o->warm < AF_ONSET_WARMUP_FRAMES ? NAN : o->floor;
}
