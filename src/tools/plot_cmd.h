/* plot_cmd.h — `firmness_model plot [model flags] --out FILE.png|FILE.svg
 * [--modulus-min PA] [--modulus-max PA]`: the predicted strike as a figure
 * (pulse; spectrum with lobes, band, level and the 0S2; shear on the axis
 * against the yield), drawn by src/plot/plot.h. */
#ifndef AF_PLOT_CMD_H
#define AF_PLOT_CMD_H

#include <stddef.h>

#include "options.h"

/* argv[first..argc). Returns the process exit code (2 for bad input). */
int af_plot_main(int argc, char **argv, int first);

/* Its flag table (the usage of firmness_model lists it); *n entries. */
const af_option *af_plot_options(size_t *n);

#endif
