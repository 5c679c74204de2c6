/* paper.h — `firmness_model paper`: the paper's Figs. 2-8 and its claims,
 * recomputed under the paper-literal and the shipped default profile. */
#ifndef AF_TOOLS_PAPER_H
#define AF_TOOLS_PAPER_H

#include <stddef.h>

#include "options.h"

/* argv[first..] are the verb's flags (--out DIR, --quick). Writes
 * DIR/paper/fig<N>_<profile>.png and .svg and DIR/paper.md. Exit status:
 * 0, 1 model or output failure, 2 bad input. */
int af_paper_main(int argc, char **argv, int first);

/* Its flag table (the usage of firmness_model lists it); *n entries. */
const af_option *af_paper_options(size_t *n);

#endif
