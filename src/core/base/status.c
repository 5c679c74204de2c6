/* status.c — status strings and the process-wide GSL error policy. */
#include "status.h"

#include <threads.h>

#include <gsl/gsl_errno.h>

const char *af_strerror(af_status s)
{
  switch (s) {
  case AF_OK: return "success";
  case AF_EINVAL: return "argument outside its accepted range";
  case AF_ENOMEM: return "out of memory";
  case AF_ENOCONV: return "iteration did not converge";
  case AF_ENOROOT: return "no root in the searched bracket";
  case AF_ENUMERIC: return "non-finite value in a computation";
  case AF_ENOLOBE: return "requested spectral lobe does not exist";
  case AF_ESIZE: return "buffer too small";
  case AF_EIO: return "input/output error";
  case AF_ENODATA: return "not enough signal";
  case AF_EROS: return "ROS layer error";
  case AF_EBUDGET_ODE_STEPS:
    return "impact ODE budget exhausted (20000 steps or 1000 elastic contact times: the contact "
           "does not end, a hammer resting on the fruit?)";
  case AF_EBUDGET_ROOT_ITER: return "root-finding iteration budget exhausted";
  case AF_EBUDGET_FIT_ITER: return "fit iteration budget exhausted";
  case AF_EBUDGET_SEARCH: return "R2_min search evaluation budget exhausted";
  }
  return "unknown status";
}

static void handler_off(void)
{
  gsl_set_error_handler_off();
}

void af_status_init(void)
{
  /* GSL's default handler calls abort(); a grading station must not die on a
   * bad apple, so every GSL status is checked where it is returned instead.
   * GSL keeps the handler in one global: it is written once per process
   * (call_once), so create functions on several threads (firmness_report's
   * workers, stress.c's solver) never write it concurrently. */
  static once_flag once = ONCE_FLAG_INIT;
  call_once(&once, handler_off);
}
