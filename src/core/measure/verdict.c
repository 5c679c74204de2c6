/* verdict.c — the flags of an unreliable strike in words (see verdict.h). */
#include "verdict.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#include "criteria.h"

void af_verdict_clear(af_verdict *v)
{
  memset(v, 0, sizeof *v);
  v->fit_residual = v->snr_db = v->snr_threshold_db = NAN;
  v->bounce_noise_ratio = v->bounce_peak_ratio = v->bounce_impulse_excess = NAN;
  v->f_lo_hz = v->f_hi_hz = v->resonance_hz = v->band_low_hz = v->band_high_hz = NAN;
  v->resonance_q = v->fruit_q_min = v->fruit_q_max = NAN;
  v->stray_hz = v->stray_db = v->mode_confidence = v->fruit_confidence_min = NAN;
  v->max_shear_pa = v->yield_shear_pa = v->apple_stale_s = v->audio_seconds = v->audio_clip_max =
      v->audio_clip_min = NAN;
  v->apple_transit_s = v->apple_tolerance_s = v->nearest_apple_lag_s = NAN;
  v->outside_hz = v->outside_snr_db = v->outside_modulus_pa = NAN;
  v->modulus_min_pa = v->modulus_max_pa = NAN;
}

/* Appends one part, "; "-separated, never overflowing. */
static void add(char *buf, size_t len, const char *fmt, ...)
{
  size_t used = strlen(buf);
  if (used + 3 >= len)
    return;
  if (used > 0) {
    memcpy(buf + used, "; ", 3);
    used += 2;
  }
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(buf + used, len - used, fmt, ap);
  va_end(ap);
}

static const char *fit_failure(af_status st)
{
  switch (st) {
  case AF_EINVAL: return "pulse too short or not finite";
  case AF_ESIZE: return "pulse longer than the fit's max_samples";
  case AF_ENODATA: return "the model does not explain the pulse";
  case AF_ENOCONV: return "not converged";
  case AF_ENUMERIC: return "numerical failure";
  default: return af_strerror(st);
  }
}

const char *af_audio_cause_name(af_audio_cause c)
{
  switch (c) {
  case AF_AUDIO_NOT_GIVEN: return "no audio given";
  case AF_AUDIO_TOO_SHORT: return "audio window too short";
  case AF_AUDIO_NONE_RECEIVED: return "no audio chunk received";
  case AF_AUDIO_STREAM_STALE: return "audio stream stale";
  case AF_AUDIO_BEFORE_STREAM: return "audio window before the audio stream";
  case AF_AUDIO_NOT_RECEIVED: return "audio window not received";
  case AF_AUDIO_LEFT_RING: return "audio window no longer in the ring";
  case AF_AUDIO_UNREADABLE: return "audio window unreadable";
  case AF_AUDIO_LOST_IN_WINDOW: return "audio window holds lost samples";
  case AF_AUDIO_QUEUE_FULL: return "strike queue full";
  case AF_AUDIO_STREAM_ENDED: return "recording ends before the audio window";
  case AF_AUDIO_REFUSED_IN_WINDOW: return "audio window holds refused (non-finite) samples";
  }
  return "unknown";
}

/* The "no audio" part with its cause and values. */
static void add_no_audio(const af_verdict *v, char *buf, size_t len)
{
  const unsigned long long first = v->audio_first, last = v->audio_last, end = v->audio_end;
  switch (v->audio_cause) {
  case AF_AUDIO_NOT_GIVEN: add(buf, len, "no audio"); break;
  case AF_AUDIO_TOO_SHORT: add(buf, len, "no audio (%zu samples)", v->n_audio); break;
  case AF_AUDIO_NONE_RECEIVED:
    add(buf, len, "no audio (no audio chunk received within %g s of the strike)", v->audio_seconds);
    break;
  case AF_AUDIO_STREAM_STALE:
    add(buf, len, "no audio (audio stream stale (silent for more than %g s))", v->audio_seconds);
    break;
  case AF_AUDIO_BEFORE_STREAM:
    add(buf, len, "no audio (audio window starts %.4f s before the audio stream's first sample)",
        v->audio_seconds);
    break;
  case AF_AUDIO_NOT_RECEIVED:
    add(buf, len,
        "no audio (audio window (samples %llu..%llu) not received within %g s of the strike "
        "(audio at sample %llu))",
        first, last, v->audio_seconds, end);
    break;
  case AF_AUDIO_LEFT_RING:
    add(buf, len, "no audio (audio window (sample %llu) no longer in the %g s audio ring)", first,
        v->audio_seconds);
    break;
  case AF_AUDIO_UNREADABLE:
    add(buf, len, "no audio (audio window (samples %llu..%llu) could not be read from the ring)",
        first, last);
    break;
  case AF_AUDIO_LOST_IN_WINDOW:
    add(buf, len, "no audio (audio window holds %zu lost samples)", v->n_audio);
    break;
  case AF_AUDIO_REFUSED_IN_WINDOW:
    add(buf, len,
        "no audio (audio window (samples %llu..%llu) holds %zu refused (non-finite) samples)",
        first, last, v->n_audio);
    break;
  case AF_AUDIO_QUEUE_FULL:
    add(buf, len, "no audio (strike queue full (%zu strikes waiting for audio))", v->queue_size);
    break;
  case AF_AUDIO_STREAM_ENDED:
    add(buf, len,
        "no audio (the audio recording ends at sample %llu, before the window %llu..%llu)", end,
        first, last);
    break;
  }
}

static void add_audio(const af_verdict *v, char *buf, size_t len)
{
  if (v->flags & AF_VERDICT_NO_AUDIO)
    add_no_audio(v, buf, len);
  if ((v->flags & AF_VERDICT_NO_RESONANCE) && isfinite(v->outside_hz))
    add(buf, len,
        "a %.0f dB peak at %.0f Hz lies %s the cultivar's 0S2 range [%.0f, %.0f] Hz: E2 %.1f MPa "
        "by Lamb, outside modulus_min_pa..modulus_max_pa %g..%g MPa",
        v->outside_snr_db, v->outside_hz, v->outside_hz < v->f_lo_hz ? "below" : "above",
        v->f_lo_hz, v->f_hi_hz, 1e-6 * v->outside_modulus_pa, 1e-6 * v->modulus_min_pa,
        1e-6 * v->modulus_max_pa);
  else if ((v->flags & AF_VERDICT_NO_RESONANCE) && isfinite(v->snr_db))
    add(buf, len,
        "no 0S2 resonance above the SNR threshold (%.0f dB; best %.1f dB in [%.0f, %.0f] Hz)",
        v->snr_threshold_db, v->snr_db, v->f_lo_hz, v->f_hi_hz);
  else if (v->flags & AF_VERDICT_NO_RESONANCE)
    add(buf, len, "no 0S2 resonance above the SNR threshold (%.0f dB; silence in [%.0f, %.0f] Hz)",
        v->snr_threshold_db, v->f_lo_hz, v->f_hi_hz);
  if (v->flags & AF_VERDICT_RANGE_NYQUIST)
    add(buf, len, "0S2 range [%.0f, %.0f] Hz beyond the audio's Nyquist frequency", v->f_lo_hz,
        v->f_hi_hz);
  if (v->flags & AF_VERDICT_AUDIO_FAILED)
    add(buf, len, "audio analysis failed: %s", af_strerror(v->audio_status));
  if (v->flags & AF_VERDICT_MODE_AMBIGUOUS)
    add(buf, len, "%s", v->mode_text); /* af_modes_format: "ambiguous 0S2: ..." */
}

/* The criteria's own words (criteria.h), for the criteria flags alone. */
static void add_criteria(const af_verdict *v, char *buf, size_t len)
{
  const uint32_t criteria = AF_VERDICT_NO_LOBE | AF_VERDICT_OUTSIDE_BAND | AF_VERDICT_DAMAGE;
  if (!(v->flags & criteria))
    return;
  af_lobe band = {.end_hz = INFINITY, .band_low_hz = -INFINITY, .band_high_hz = INFINITY};
  double f = 0.0, shear = 0.0, yield = 1.0;
  if (v->flags & AF_VERDICT_OUTSIDE_BAND) {
    band.band_low_hz = v->band_low_hz;
    band.band_high_hz = v->band_high_hz;
    f = v->resonance_hz;
  }
  if (v->flags & AF_VERDICT_DAMAGE) {
    shear = v->max_shear_pa;
    yield = v->yield_shear_pa;
  }
  char part[256];
  af_criteria_reason((v->flags & AF_VERDICT_NO_LOBE) ? NULL : &band, v->lobe, f, shear, yield, part,
                     sizeof part);
  if (part[0] != '\0')
    add(buf, len, "%s", part);
}

/* No estimate matched: the window searched and, when one lay near, the
 * estimate nearest the strike, so that a systematic lag names itself. */
static void no_apple(const af_verdict *v, char *buf, size_t len)
{
  if (isnan(v->apple_transit_s)) {
    add(buf, len, "no apple estimate within %g s before the strike", v->apple_stale_s);
    return;
  }
  if (v->nearest_apple_id == 0) {
    add(buf, len, "no apple estimate stamped %g +- %g s before the strike", v->apple_transit_s,
        v->apple_tolerance_s);
    return;
  }
  const double lag_s = v->nearest_apple_lag_s;
  add(buf, len,
      "no apple estimate stamped %g +- %g s before the strike (the nearest, apple %u, is "
      "stamped %.3f s %s it)",
      v->apple_transit_s, v->apple_tolerance_s, v->nearest_apple_id, fabs(lag_s),
      lag_s >= 0.0 ? "before" : "after");
}

/* Each failed test of the fruit-or-not gate, with its figure and its row. */
static void add_not_fruit(const af_verdict *v, char *buf, size_t len)
{
  if (v->not_fruit & AF_NOT_FRUIT_Q)
    add(buf, len, "Q %.0f at %.0f Hz: %s, not fruit flesh (fruit_q_min..fruit_q_max %g..%g)",
        v->resonance_q, v->resonance_hz,
        v->resonance_q > v->fruit_q_max ? "a ringing object" : "a dull thud", v->fruit_q_min,
        v->fruit_q_max);
  if (v->not_fruit & AF_NOT_FRUIT_NEIGHBOURS)
    add(buf, len, "a partial at %.2fx the %.0f Hz mode (%+.0f dB), none of the sphere's: not fruit",
        v->stray_hz / v->resonance_hz, v->resonance_hz, v->stray_db);
  if (v->not_fruit & AF_NOT_FRUIT_CONFIDENCE)
    add(buf, len, "0S2 %.0f Hz at confidence %.2f, below fruit_confidence_min %g", v->resonance_hz,
        v->mode_confidence, v->fruit_confidence_min);
}

void af_verdict_format(const af_verdict *v, char *buf, size_t len)
{
  if (buf == NULL || len == 0)
    return;
  buf[0] = '\0';
  if (v == NULL)
    return;
  const uint32_t f = v->flags;
  if (f & AF_VERDICT_NO_APPLE)
    no_apple(v, buf, len);
  if (f & AF_VERDICT_NO_PREDICTION)
    add(buf, len, "apple %u got no prediction: %s", v->apple_id, v->apple_why);
  if (f & AF_VERDICT_APPLE_DOUBTFUL)
    add(buf, len, "doubtful apple match (apple %u: %s)", v->apple_id, v->doubtful_why);
  if (f & AF_VERDICT_CLOCK_FAULT)
    add(buf, len, "judged across a clock fault, not the fruit's: %s", v->clock_why);
  if (f & AF_VERDICT_MEASURE_FAILED)
    add(buf, len, "measurement failed: %s", af_strerror(v->measure_status));
  if ((f & AF_VERDICT_DOUBLE_HIT) && v->bounce_inside)
    add(buf, len,
        "double hit (a second impact inside the contact: the fit leaves a structured residual, "
        "%.3g x the noise's power, %.2g %% of the peak)",
        v->bounce_noise_ratio, 100.0 * v->bounce_peak_ratio);
  else if ((f & AF_VERDICT_DOUBLE_HIT) && v->bounce_impulse_excess > 0.0)
    add(buf, len,
        "double hit (a second impact inside the contact: the impulse is %.0f %% above the "
        "hammer's recent strikes, beyond their spread)",
        100.0 * v->bounce_impulse_excess);
  else if (f & AF_VERDICT_DOUBLE_HIT)
    add(buf, len, "double hit");
  if (f & AF_VERDICT_CLIPPED)
    add(buf, len, "clipped at full scale");
  if (f & AF_VERDICT_LOST_SAMPLES)
    add(buf, len, "%llu samples lost", (unsigned long long)v->lost_samples);
  if (f & AF_VERDICT_REFUSED_SAMPLES)
    add(buf, len, "%llu refused (non-finite) force samples in the strike's span",
        (unsigned long long)v->refused_samples);
  if (f & AF_VERDICT_TRUNCATED)
    add(buf, len, "contact truncated");
  if (f & AF_VERDICT_SPECTRUM_FAILED)
    add(buf, len, "excitation spectrum failed: %s", af_strerror(v->spectrum_status));
  if ((f & AF_VERDICT_FIT_FAILED) && isfinite(v->fit_residual))
    add(buf, len, "fit failed: %s (residual %.0f %% of the peak)", fit_failure(v->fit_status),
        100.0 * v->fit_residual);
  else if (f & AF_VERDICT_FIT_FAILED)
    add(buf, len, "fit failed: %s", fit_failure(v->fit_status));
  if (f & AF_VERDICT_POISSON)
    add(buf, len, "Poisson ratio: %s", af_strerror(v->judge_status));
  if (f & AF_VERDICT_NOT_FRUIT)
    add_not_fruit(v, buf, len);
  if (f & AF_VERDICT_AUDIO_CLIPPED)
    add(buf, len,
        "microphone clipped (%zu samples at its extremes %.4g and %.4g, %zu flat tops): lower "
        "the microphone gain",
        v->audio_clip_samples, v->audio_clip_max, v->audio_clip_min, v->audio_clip_tops);
  add_audio(v, buf, len);
  add_criteria(v, buf, len);
}

const char *af_verdict_flag_name(af_verdict_flag f)
{
  switch (f) {
  case AF_VERDICT_NO_APPLE: return "no_apple";
  case AF_VERDICT_NO_PREDICTION: return "no_prediction";
  case AF_VERDICT_APPLE_DOUBTFUL: return "apple_doubtful";
  case AF_VERDICT_MEASURE_FAILED: return "measure_failed";
  case AF_VERDICT_DOUBLE_HIT: return "double_hit";
  case AF_VERDICT_CLIPPED: return "clipped";
  case AF_VERDICT_LOST_SAMPLES: return "lost_samples";
  case AF_VERDICT_TRUNCATED: return "truncated";
  case AF_VERDICT_SPECTRUM_FAILED: return "spectrum_failed";
  case AF_VERDICT_FIT_FAILED: return "fit_failed";
  case AF_VERDICT_POISSON: return "poisson";
  case AF_VERDICT_NO_AUDIO: return "no_audio";
  case AF_VERDICT_NO_RESONANCE: return "no_resonance";
  case AF_VERDICT_RANGE_NYQUIST: return "range_nyquist";
  case AF_VERDICT_AUDIO_FAILED: return "audio_failed";
  case AF_VERDICT_MODE_AMBIGUOUS: return "mode_ambiguous";
  case AF_VERDICT_NO_LOBE: return "no_lobe";
  case AF_VERDICT_OUTSIDE_BAND: return "outside_band";
  case AF_VERDICT_DAMAGE: return "damage";
  case AF_VERDICT_REFUSED_SAMPLES: return "refused_samples";
  case AF_VERDICT_AUDIO_CLIPPED: return "audio_clipped";
  case AF_VERDICT_CLOCK_FAULT: return "clock_fault";
  case AF_VERDICT_NOT_FRUIT: return "not_fruit";
  }
  return "unknown";
}

void af_verdict_format_model_only(const af_verdict *v, char *buf, size_t len)
{
  if (buf == NULL || len == 0)
    return;
  buf[0] = '\0';
  if (v == NULL)
    return;
  if (v->model_only & AF_VERDICT_MODEL_EXCITATION)
    add(buf, len, "excitation judged from the model only");
  if (v->model_only & AF_VERDICT_MODEL_SHEAR)
    add(buf, len, "shear judged from the model only");
}
