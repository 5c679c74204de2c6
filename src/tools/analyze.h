/* analyze.h — `firmness_model analyze`: measured strikes from recorded force
 * and audio files, through the node's own pipeline (af_strike, af_measure). */
#ifndef AF_ANALYZE_H
#define AF_ANALYZE_H

#include <stddef.h>

#include "options.h"

/* argv[first..argc): --force FILE --audio FILE --rate-force HZ --rate-audio HZ
 * --mass KG --R2 M [--audio-offset S] [--modulus-min PA] [--modulus-max PA]
 * [--bench] and model flags. Prints a JSON array, one object per strike.
 * Returns the process exit code (2 for bad input). */
int af_analyze_main(int argc, char **argv, int first);

/* Its flag table (the usage of firmness_model lists it); *n entries. */
const af_option *af_analyze_options(size_t *n);

#endif
