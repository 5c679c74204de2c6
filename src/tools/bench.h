/* bench.h — `firmness_model bench`: full evaluations per second. */
#ifndef AF_BENCH_H
#define AF_BENCH_H

#include <stddef.h>

#include "options.h"

/* argv[first..argc): [--seconds S] and model flags. Returns the exit code. */
int af_bench_main(int argc, char **argv, int first);

/* Its flag table (the usage of firmness_model lists it); *n entries. */
const af_option *af_bench_options(size_t *n);

#endif
