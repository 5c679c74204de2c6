/* sweep.h — `firmness_model sweep`: one model flag stepped over a range. */
#ifndef AF_SWEEP_H
#define AF_SWEEP_H

/* argv[first..argc): --param NAME --from X --to Y --steps N [--csv FILE] and
 * model flags. Returns the process exit code. */
int af_sweep_main(int argc, char **argv, int first);

#endif
