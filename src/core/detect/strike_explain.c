/* strike_explain.c — why no strike came: af_strike_get_diagnosis (what the
 * detector saw since the stream started, and the verdict), its short phrase
 * (af_strike_why_text) and its one-line explanation with the figures
 * (af_strike_explain). */
#include "strike.h"

#include <math.h>
#include <stdio.h>

#include "strike_private.h"

void af_strike_get_diagnosis(const af_strike *d, af_strike_diagnosis *out)
{
  if (d == NULL || out == NULL)
    return;
  const af_record *rec = &d->rec;
  double factor = d->cfg.threshold_noise_factor, min_n = d->cfg.threshold_min_n;
  double idle_thr = fmax(factor * sqrt(rec->idle_ms), min_n);
  *out = (af_strike_diagnosis){
      .strikes = rec->strikes,
      .samples = rec->samples,
      .primed = d->primed,
      .armed = d->phase != AF_PHASE_WARMUP && d->phase != AF_PHASE_SETTLE,
      .armed_sample = rec->armed_ever ? rec->armed_at : UINT64_MAX,
      .warmup_samples = (uint64_t)d->warmup,
      .warmup_learned = (uint64_t)(d->learned < d->warmup ? d->learned : d->warmup),
      .arm_threshold_n = rec->armed_ever ? rec->arm_threshold : NAN,
      .warmup_max_n = isfinite(rec->warm_max) ? rec->warm_max : NAN,
      .warmup_max_sample = rec->warm_at,
      .armed_max_n = isfinite(rec->idle_max) ? rec->idle_max : NAN,
      .armed_max_sample = rec->idle_at,
      .armed_max_threshold_n = isfinite(rec->idle_max) ? idle_thr : NAN,
      .settle_max_n = isfinite(rec->settle_max) ? rec->settle_max : NAN,
      .settle_max_sample = rec->settle_at,
      .settle_max_threshold_n = isfinite(rec->settle_max) ? rec->settle_threshold : NAN,
      .pending_trigger_sample = in_event(d) ? d->ev.trigger : 0,
      .threshold_n = threshold_now(d),
      .noise_rms_n = sqrt(d->mean_square)};
  /* The verdict: the state in which the largest excursion came. */
  double w = rec->warm_max, a = rec->idle_max, st = rec->settle_max;
  if (in_event(d))
    out->why = AF_STRIKE_PENDING;
  else if (rec->strikes > 0)
    out->why = AF_STRIKE_FOUND;
  else if (rec->samples == 0)
    out->why = AF_STRIKE_NO_SIGNAL;
  else if (!rec->armed_ever ||
           (w > rec->arm_threshold && w >= a && w >= st)) /* -inf when never seen */
    out->why = AF_STRIKE_IN_WARMUP;
  else if (!isfinite(a) || (st > rec->settle_threshold && st >= a))
    out->why = AF_STRIKE_WAITING_QUIET;
  else
    out->why = AF_STRIKE_BELOW_THRESHOLD;
}

const char *af_strike_why_text(af_strike_why why)
{
  switch (why) {
  case AF_STRIKE_FOUND: return "strike found";
  case AF_STRIKE_NO_SIGNAL: return "no signal";
  case AF_STRIKE_IN_WARMUP: return "still in warm-up";
  case AF_STRIKE_BELOW_THRESHOLD: return "never above threshold";
  case AF_STRIKE_WAITING_QUIET: return "waiting for quiet";
  case AF_STRIKE_PENDING: return "strike still in progress";
  }
  return "unknown";
}

af_status af_strike_explain(const af_strike *d, char *buf, size_t size)
{
  if (d == NULL || buf == NULL || size == 0)
    return AF_EINVAL;
  af_strike_diagnosis g;
  af_strike_get_diagnosis(d, &g);
  const char *why = af_strike_why_text(g.why);
  double fs = d->cfg.sample_rate_hz;
  unsigned long long warm_at = g.warmup_max_sample, armed_at = g.armed_sample;
  int len = 0;
  switch (g.why) {
  case AF_STRIKE_FOUND:
    len = snprintf(buf, size, "%llu strike%s found", (unsigned long long)g.strikes,
                   g.strikes == 1 ? "" : "s");
    break;
  case AF_STRIKE_NO_SIGNAL: len = snprintf(buf, size, "%s: nothing written", why); break;
  case AF_STRIKE_PENDING:
    len = snprintf(buf, size,
                   "%s: triggered at sample %llu, emitted %g s after its contact ends "
                   "(af_strike_flush emits it now)",
                   why, (unsigned long long)g.pending_trigger_sample, d->cfg.post_s);
    break;
  case AF_STRIKE_IN_WARMUP:
    if (g.armed_sample == UINT64_MAX)
      len = snprintf(buf, size,
                     "%s: %llu of the %llu samples (%g s) learned before arming, largest "
                     "excursion %.4g N at sample %llu; prime the detector or start earlier",
                     why, (unsigned long long)g.warmup_learned,
                     (unsigned long long)g.warmup_samples, (double)g.warmup_samples / fs,
                     isfinite(g.warmup_max_n) ? g.warmup_max_n : 0.0, warm_at);
    else
      len = snprintf(buf, size,
                     "%s when the largest excursion came (%.4g N at sample %llu; armed from "
                     "sample %llu, threshold %.4g N then); prime the detector or start "
                     "earlier",
                     why, g.warmup_max_n, warm_at, armed_at, g.arm_threshold_n);
    break;
  case AF_STRIKE_WAITING_QUIET:
    len = snprintf(buf, size,
                   "%s after a cut event when the largest excursion came (%.4g N at sample "
                   "%llu, threshold %.4g N)",
                   why, isfinite(g.settle_max_n) ? g.settle_max_n : 0.0,
                   (unsigned long long)g.settle_max_sample,
                   isfinite(g.settle_max_threshold_n) ? g.settle_max_threshold_n : g.threshold_n);
    break;
  case AF_STRIKE_BELOW_THRESHOLD:
    len = snprintf(buf, size,
                   "%s: largest excursion %.4g N at sample %llu, threshold %.4g N there "
                   "(max(%g x noise RMS, %g N); noise RMS now %.4g N)",
                   why, g.armed_max_n, (unsigned long long)g.armed_max_sample,
                   g.armed_max_threshold_n, d->cfg.threshold_noise_factor, d->cfg.threshold_min_n,
                   g.noise_rms_n);
    break;
  }
  return len >= 0 && (size_t)len < size ? AF_OK : AF_ESIZE;
}
