/* stage.h — optional timing of the stages of one strike, for benchmarks
 * (firmness_report --bench): the core reads the clock around each stage only
 * when a hook is given; without one (the node, every tool by default) a
 * stage costs one NULL check and no clock read.
 *
 *   setup      making the lane (af_lane_create; timed by its caller, once per lane)
 *   detect     the strike detector over each force chunk (lane.c)
 *   window     the audio window and the noise reference cut from the ring (lane.c)
 *   predict    an AppleEstimate's prediction (the model, per apple; lane.c)
 *   fft        the force pulse's spectrum and band, the audio window's
 *              transform (DC and hum out, window, FFT, power) (measure.c, response_list.c)
 *   modes      the damped peaks of the band and the 0S2 among them (measure.c)
 *   fit        the inverse fit of E2 and e (measure.c)
 *   verdict    stress, criteria, flags and their words, the lane's flags and the grade
 *   serialize  the strike's row written by the tool (firmness_report)
 *
 * The hook is called from the thread that runs the lane; it must not block.
 * No allocation. */
#ifndef AF_STAGE_H
#define AF_STAGE_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef enum {
  AF_STAGE_SETUP = 0,
  AF_STAGE_DETECT,
  AF_STAGE_WINDOW,
  AF_STAGE_PREDICT,
  AF_STAGE_FFT,
  AF_STAGE_MODES,
  AF_STAGE_FIT,
  AF_STAGE_VERDICT,
  AF_STAGE_SERIALIZE,
  AF_STAGES
} af_stage;

/* One timed call of stage: elapsed_ns [ns] on the monotonic clock (af_stage_now_ns). */
typedef void af_stage_fn(af_stage stage, int64_t elapsed_ns, void *user);

typedef struct {
  af_stage_fn *fn; /* NULL: no timing */
  void *user;
} af_stage_hook;

/* "setup", "detect", "window", "predict", "fft", "modes", "fit", "verdict",
 * "serialize"; "?" otherwise. */
const char *af_stage_name(af_stage stage);

/* The monotonic clock, CLOCK_MONOTONIC [ns]. Not the thread's CPU time
 * (CLOCK_THREAD_CPUTIME_ID): that clock is a system call, 1.3-1.6 us a read
 * on this project's 2-core VM, and firmness_report --bench reads it 31.5
 * times a strike (44 us, 10 % of the CPU per strike it prints); the
 * monotonic clock is read without one (27 ns). A stage is therefore charged
 * for the time another process ran while its thread was in it: on a loaded
 * machine its tail (p99, max) shows it. The workers' totals stay CPU time
 * (src/report/session.c). */
int64_t af_stage_now_ns(void);

/* The calling thread's CPU time, CLOCK_THREAD_CPUTIME_ID [ns]: for work
 * counted rarely (a table row's build, fastpath.c), not per stage. */
int64_t af_stage_cpu_ns(void);

/* The start of a stage: the clock when h times, else 0 (no clock read). */
static inline int64_t af_stage_begin(const af_stage_hook *h)
{
  return h != NULL && h->fn != NULL ? af_stage_now_ns() : 0;
}

/* The end of a stage begun at t0_ns: reported to h when it times. */
static inline void af_stage_end(const af_stage_hook *h, af_stage stage, int64_t t0_ns)
{
  if (h != NULL && h->fn != NULL)
    h->fn(stage, af_stage_now_ns() - t0_ns, h->user);
}

#ifdef __cplusplus
}
#endif
#endif
