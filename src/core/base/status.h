/* status.h — the one status enum of the acoustic_firmness core.
 *
 * Conventions of the core (src/core/), in the manner of GSL and SQLite:
 *  - every fallible function returns an af_status; results come back through
 *    OUT pointers, last in the argument list;
 *  - objects are created with af_<module>_create(cfg, &out), freed with
 *    af_<module>_destroy(obj) which accepts NULL; all memory is taken in
 *    create, none while executing;
 *  - the library never aborts and never prints: GSL's error handler is turned
 *    off (af_status_init) and GSL/FFTW results are mapped where they are called;
 *  - SI units everywhere, the unit in the name (_s, _hz, _n, _pa, _m, _kg).
 */
#ifndef AF_STATUS_H
#define AF_STATUS_H

#ifdef __cplusplus
extern "C" {
#endif

typedef enum {
  AF_OK = 0,
  AF_EINVAL,   /* an argument lies outside its accepted range */
  AF_ENOMEM,   /* allocation failed (only ever at create time) */
  AF_ENOCONV,  /* an iteration did not converge */
  AF_ENOROOT,  /* no sign change in the searched bracket */
  AF_ENUMERIC, /* a NaN or infinity appeared in a computation */
  AF_ENOLOBE,  /* the requested spectral lobe does not exist */
  AF_ESIZE,    /* a buffer is too small for the data */
  AF_EIO,      /* a file could not be read or written */
  AF_ENODATA,  /* not enough signal to answer (no strike, no peak) */
  AF_EROS,     /* the ROS layer failed (shim only) */
  /* A work budget ran out: every loop whose length depends on its input has
   * one, and says which when it stops (never a hang on any input). */
  AF_EBUDGET_ODE_STEPS, /* impact ODE: AF_IMPACT_STEP_BUDGET steps or 1000 D/v0 per pulse */
  AF_EBUDGET_ROOT_ITER, /* a root finder's (or extremum search's) iteration budget */
  AF_EBUDGET_FIT_ITER,  /* the pulse fit's max_iterations */
  AF_EBUDGET_SEARCH     /* the R2_min search's evaluation budget */
} af_status;

/* A short, static, human-readable description of s. Never NULL. */
const char *af_strerror(af_status s);

/* Turns GSL's aborting error handler off, once per process. Every create
 * function of the core calls it; calling it again is harmless. */
void af_status_init(void);

#ifdef __cplusplus
}
#endif
#endif
