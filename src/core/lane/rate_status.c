/* rate_status.c — FrequencyStatus and TimeStampStatus semantics (see rate_status.h). */
#include "rate_status.h"

#include <math.h>
#include <string.h>

void af_rate_init(af_rate_status *r, const af_rate_config *cfg, int64_t now_ns)
{
  memset(r, 0, sizeof *r);
  r->cfg = *cfg;
  if (r->cfg.window < 1)
    r->cfg.window = 1;
  if (r->cfg.window > AF_RATE_WINDOW_MAX)
    r->cfg.window = AF_RATE_WINDOW_MAX;
  for (size_t k = 0; k < r->cfg.window; k++)
    r->times_ns[k] = now_ns;
}

void af_rate_tick(af_rate_status *r)
{
  r->count++;
}

void af_rate_run(af_rate_status *r, int64_t now_ns, af_rate_report *out)
{
  const af_rate_config *c = &r->cfg;
  memset(out, 0, sizeof *out);
  out->events = r->count - r->counts[r->next];
  out->events_total = r->count;
  out->window_s = (double)(now_ns - r->times_ns[r->next]) * 1e-9;
  out->rate_hz = out->window_s > 0.0 ? (double)out->events / out->window_s : 0.0;
  out->min_ok_hz = c->min_hz * (1.0 - c->tolerance);
  out->max_ok_hz = isfinite(c->max_hz) ? c->max_hz * (1.0 + c->tolerance) : INFINITY;
  r->counts[r->next] = r->count;
  r->times_ns[r->next] = now_ns;
  r->next = (r->next + 1) % c->window;
  if (out->window_s <= 0.0) { /* an update at the start's own time: nothing to judge */
    out->level = AF_HEALTH_OK;
    out->message = "no window yet";
  } else if (out->events == 0) {
    out->level = c->min_hz > 0.0 ? AF_HEALTH_WARN : AF_HEALTH_OK;
    out->message = "no events";
  } else if (out->rate_hz < out->min_ok_hz) {
    out->level = AF_HEALTH_WARN;
    out->message = "rate too low";
  } else if (out->rate_hz > out->max_ok_hz) {
    out->level = AF_HEALTH_WARN;
    out->message = "rate too high";
  } else {
    out->level = AF_HEALTH_OK;
    out->message = "rate ok";
  }
}

void af_stamp_init(af_stamp_status *t, const af_stamp_config *cfg)
{
  memset(t, 0, sizeof *t);
  t->cfg = *cfg;
}

void af_stamp_tick(af_stamp_status *t, int64_t stamp_ns, int64_t now_ns)
{
  if (stamp_ns == 0) {
    t->zero_seen = true;
    return;
  }
  const double delay_s = (double)(now_ns - stamp_ns) * 1e-9;
  if (!t->valid || delay_s > t->max_s)
    t->max_s = delay_s;
  if (!t->valid || delay_s < t->min_s)
    t->min_s = delay_s;
  t->valid = true;
}

void af_stamp_run(af_stamp_status *t, af_stamp_report *out)
{
  memset(out, 0, sizeof *out);
  out->level = AF_HEALTH_OK;
  out->message = t->valid ? "stamps ok" : "no data";
  /* As diagnostic_updater, the later check's message wins; the zero stamp,
   * an ERROR, last. */
  if (t->valid && t->min_s < t->cfg.min_delay_s) {
    out->level = AF_HEALTH_WARN;
    out->message = "stamps too early";
    t->early_updates++;
  }
  if (t->valid && t->max_s > t->cfg.max_delay_s) {
    out->level = AF_HEALTH_WARN;
    out->message = "stamps too late";
    t->late_updates++;
  }
  if (t->zero_seen) {
    out->level = AF_HEALTH_ERROR;
    out->message = "zero stamp";
    t->zero_updates++;
  }
  out->valid = t->valid;
  out->min_delay_s = t->min_s;
  out->max_delay_s = t->max_s;
  out->early_updates = t->early_updates;
  out->late_updates = t->late_updates;
  out->zero_updates = t->zero_updates;
  t->valid = t->zero_seen = false;
  t->min_s = t->max_s = 0.0;
}
