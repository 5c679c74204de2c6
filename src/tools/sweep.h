/* sweep.h — `firmness_model sweep`: one model flag stepped over a range. */
#ifndef AF_SWEEP_H
#define AF_SWEEP_H

#include <stddef.h>

#include "options.h"

/* argv[first..argc): --param NAME --from X --to Y --steps N [--csv FILE] and
 * model flags. Returns the process exit code. */
int af_sweep_main(int argc, char **argv, int first);

/* Its flag table (the usage of firmness_model lists it); *n entries. */
const af_option *af_sweep_options(size_t *n);

#endif
