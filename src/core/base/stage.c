/* stage.c — the names of the timed stages and their clock (see stage.h). */
#define _POSIX_C_SOURCE 200809L
#include "stage.h"

#include <time.h>

const char *af_stage_name(af_stage stage)
{
  static const char *const names[AF_STAGES] = {"setup", "detect", "window",  "predict",  "fft",
                                               "modes", "fit",    "verdict", "serialize"};
  return (unsigned)stage < AF_STAGES ? names[stage] : "?";
}

static int64_t clock_ns(clockid_t id)
{
  struct timespec ts;
  clock_gettime(id, &ts);
  return (int64_t)ts.tv_sec * 1000000000LL + (int64_t)ts.tv_nsec;
}

int64_t af_stage_now_ns(void)
{
  return clock_ns(CLOCK_MONOTONIC);
}

int64_t af_stage_cpu_ns(void)
{
  return clock_ns(CLOCK_THREAD_CPUTIME_ID);
}
