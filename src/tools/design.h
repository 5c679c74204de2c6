/* design.h — `firmness_model design`: the strike designer. */
#ifndef AF_TOOLS_DESIGN_H
#define AF_TOOLS_DESIGN_H

#include <stddef.h>

#include "options.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

/* argv[first..] are the designer's flags. Exit status: 0, 1 model failure,
 * 2 bad input. */
int af_design_main(int argc, char **argv, int first);

/* Its flag table (the usage of firmness_model lists it); *n entries. */
const af_option *af_design_options(size_t *n);

#endif
