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

/* The same, its set-up kept for many runs over files that change between
 * them (the fuzz harness's): create parses the flags (0, or the exit status
 * and *out NULL); each run reads the two files as they are then, the YAML
 * files once (at the first run), and judges them as af_analyze_main does,
 * with the last run's lane reset rather than made again when the
 * configuration came out the same; it returns the run's exit status. */
typedef struct af_analyze_session af_analyze_session;
int af_analyze_session_create(int argc, char **argv, int first, af_analyze_session **out);
int af_analyze_session_run(af_analyze_session *ss);
void af_analyze_session_destroy(af_analyze_session *ss); /* NULL-safe */

/* Its flag table (the usage of firmness_model lists it); *n entries. */
const af_option *af_analyze_options(size_t *n);

#endif
