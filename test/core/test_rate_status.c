/* test_rate_status.c — the inputs' frequency and timestamp checks
 * (rate_status.h) on injected times, against diagnostic_updater's
 * FrequencyStatus and TimeStampStatus semantics: 10 events/s against an
 * expected 5..15 /s is OK, 2 /s is WARN "rate too low", 20 /s against
 * 5..15 with 10 % tolerance (16.5 /s accepted) WARN "rate too high"; a window
 * without events WARN (OK when the minimum is 0); the window is the last
 * `window` updates; stamps 0.3 s late against a 0.1 s maximum WARN, 0.05 s
 * late OK, 2 s ahead against -1 s WARN, a zero stamp ERROR; no data OK. */
#include <math.h>
#include <stdint.h>
#include <string.h>

#include "af_test.h"
#include "rate_status.h"

#define T0_NS INT64_C(1795550000000000000) /* a ROS-like clock: 1795550000 s since 1970 */
#define S_NS INT64_C(1000000000)           /* one second [ns] */

/* n events spread over one second, then an update at its end. */
static void second_of(af_rate_status *r, int n, int64_t *now_ns, af_rate_report *out)
{
  for (int k = 0; k < n; k++)
    af_rate_tick(r);
  *now_ns += S_NS;
  af_rate_run(r, *now_ns, out);
}

static void frequency(void)
{
  const af_rate_config cfg = {5.0, 15.0, 0.1, 5};
  af_rate_status r;
  af_rate_report rep;
  int64_t now = T0_NS;
  af_rate_init(&r, &cfg, now);

  second_of(&r, 10, &now, &rep); /* 10 /s in 5..15 */
  AF_CHECK(rep.level == AF_HEALTH_OK);
  AF_CHECK(strcmp(rep.message, "rate ok") == 0);
  AF_CHECK(rep.events == 10 && rep.events_total == 10);
  AF_CHECK_ABS(rep.window_s, 1.0, 1e-9);
  AF_CHECK_ABS(rep.rate_hz, 10.0, 1e-9);
  AF_CHECK_ABS(rep.min_ok_hz, 4.5, 1e-9);  /* 5 (1 - 0.1) */
  AF_CHECK_ABS(rep.max_ok_hz, 16.5, 1e-9); /* 15 (1 + 0.1) */

  /* 2 /s from now on: the window (5 updates) still holds the 10 at first. */
  second_of(&r, 2, &now, &rep); /* 12 events over 2 s: 6 /s */
  AF_CHECK(rep.level == AF_HEALTH_OK);
  AF_CHECK_ABS(rep.rate_hz, 6.0, 1e-9);
  for (int k = 0; k < 4; k++)
    second_of(&r, 2, &now, &rep);
  /* 5 updates on, the window is the last 5 s: 10 events, 2 /s. */
  AF_CHECK(rep.level == AF_HEALTH_WARN);
  AF_CHECK(strcmp(rep.message, "rate too low") == 0);
  AF_CHECK_ABS(rep.window_s, 5.0, 1e-9);
  AF_CHECK_ABS(rep.rate_hz, 2.0, 1e-9);

  for (int k = 0; k < 5; k++)
    second_of(&r, 20, &now, &rep); /* 20 /s, above 16.5 */
  AF_CHECK(rep.level == AF_HEALTH_WARN);
  AF_CHECK(strcmp(rep.message, "rate too high") == 0);
  AF_CHECK_ABS(rep.rate_hz, 20.0, 1e-9);

  for (int k = 0; k < 5; k++)
    second_of(&r, 0, &now, &rep); /* silence for a whole window */
  AF_CHECK(rep.level == AF_HEALTH_WARN);
  AF_CHECK(strcmp(rep.message, "no events") == 0);
  AF_CHECK(rep.events == 0 && rep.events_total == 10 + 2 * 5 + 20 * 5);

  /* A rate that may pause (min 0) and has no upper bound: silence is OK. */
  const af_rate_config open = {0.0, INFINITY, 0.1, 1};
  af_rate_init(&r, &open, now);
  second_of(&r, 0, &now, &rep);
  AF_CHECK(rep.level == AF_HEALTH_OK);
  AF_CHECK(isinf(rep.max_ok_hz));
  second_of(&r, 100000, &now, &rep);
  AF_CHECK(rep.level == AF_HEALTH_OK);
  AF_CHECK_ABS(rep.rate_hz, 100000.0, 1e-6);

  /* An update at the start's own time has no window to judge. */
  af_rate_init(&r, &cfg, now);
  af_rate_tick(&r);
  af_rate_run(&r, now, &rep);
  AF_CHECK(rep.level == AF_HEALTH_OK && strcmp(rep.message, "no window yet") == 0);

  /* A window clamped into 1..AF_RATE_WINDOW_MAX. */
  const af_rate_config zero = {5.0, 15.0, 0.1, 0}, huge = {5.0, 15.0, 0.1, 100000};
  af_rate_init(&r, &zero, now);
  AF_CHECK(r.cfg.window == 1);
  af_rate_init(&r, &huge, now);
  AF_CHECK(r.cfg.window == AF_RATE_WINDOW_MAX);
}

static void stamps(void)
{
  const af_stamp_config cfg = {-1.0, 0.1};
  af_stamp_status t;
  af_stamp_report rep;
  af_stamp_init(&t, &cfg);

  af_stamp_run(&t, &rep); /* nothing ticked */
  AF_CHECK(rep.level == AF_HEALTH_OK && !rep.valid);
  AF_CHECK(strcmp(rep.message, "no data") == 0);

  const int64_t now = T0_NS + 10 * S_NS;
  af_stamp_tick(&t, now - 50000000, now); /* 0.05 s late */
  af_stamp_run(&t, &rep);
  AF_CHECK(rep.level == AF_HEALTH_OK && rep.valid);
  AF_CHECK(strcmp(rep.message, "stamps ok") == 0);
  AF_CHECK_ABS(rep.max_delay_s, 0.05, 1e-9);

  af_stamp_tick(&t, now - 300000000, now); /* 0.3 s late against 0.1 s */
  af_stamp_tick(&t, now - 20000000, now);
  af_stamp_run(&t, &rep);
  AF_CHECK(rep.level == AF_HEALTH_WARN);
  AF_CHECK(strcmp(rep.message, "stamps too late") == 0);
  AF_CHECK_ABS(rep.max_delay_s, 0.3, 1e-9);
  AF_CHECK_ABS(rep.min_delay_s, 0.02, 1e-9);
  AF_CHECK(rep.late_updates == 1 && rep.early_updates == 0);

  af_stamp_run(&t, &rep); /* cleared by the update */
  AF_CHECK(rep.level == AF_HEALTH_OK && !rep.valid && rep.late_updates == 1);

  af_stamp_tick(&t, now + 2 * S_NS, now); /* 2 s ahead against -1 s */
  af_stamp_run(&t, &rep);
  AF_CHECK(rep.level == AF_HEALTH_WARN);
  AF_CHECK(strcmp(rep.message, "stamps too early") == 0);
  AF_CHECK_ABS(rep.min_delay_s, -2.0, 1e-9);
  AF_CHECK(rep.early_updates == 1);

  af_stamp_tick(&t, 0, now); /* a zero stamp */
  af_stamp_tick(&t, now, now);
  af_stamp_run(&t, &rep);
  AF_CHECK(rep.level == AF_HEALTH_ERROR);
  AF_CHECK(strcmp(rep.message, "zero stamp") == 0);
  AF_CHECK(rep.zero_updates == 1);
}

int main(void)
{
  frequency();
  stamps();
  return af_test_summary("test_rate_status");
}
