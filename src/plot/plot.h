/* plot.h — the package's one plotting module, in C on PLplot.
 *
 * Why PLplot (libplplot-dev, Debian main): a C API (no C++ or Python in the
 * product path), output to PNG and SVG files through its cairo drivers and
 * to a caller's RGB buffer through the in-memory cairo driver (memcairo), so
 * the node's live image and the report's files come from the same drawing
 * code; anti-aliased text and lines; no display needed.
 *
 * One verb draws one page: panels laid out nx x ny, each a plain x-y plot
 * with a title, axis labels (the caller writes the unit in the label:
 * "time [ms]"), a legend naming every series, shaded span and rule that has a
 * label, and these layers, in drawing order: shaded x-intervals (spans),
 * series (lines, dashed lines, points, histogram steps), vertical and
 * horizontal rules (lines across the panel at an x or a y).
 *
 * PLplot keeps global state: one page at a time per process (not
 * thread-safe). Each af_plot_draw makes its own PLplot stream and ends it,
 * so PLplot allocates and frees its stream state inside the call (its
 * in-memory drivers release their page at the page's end and cannot be kept
 * open between pages); the caller's RGB buffer is written in place. */
#ifndef AF_PLOT_H
#define AF_PLOT_H

#include <stdbool.h>
#include <stddef.h>

#include "status.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum {
  AF_PLOT_PNG = 0, /* pngcairo, to target.path */
  AF_PLOT_SVG,     /* svgcairo, to target.path */
  AF_PLOT_MEMORY   /* memcairo, into target.rgb */
} af_plot_format;

typedef struct {
  af_plot_format format;
  const char *path;   /* PNG / SVG file */
  unsigned char *rgb; /* MEMORY: width_px x height_px x 3 bytes, rows top first (rgb8) */
  int width_px, height_px;
} af_plot_target;

/* A PNG or SVG target from the file name's extension (.png / .svg, any
 * case). AF_EINVAL for another extension or a size outside [64, 8192] px. */
af_status af_plot_target_file(const char *path, int width_px, int height_px, af_plot_target *out);

/* The palette (PLplot cmap0 indices set by the module). */
typedef enum {
  AF_PLOT_BLACK = 1,
  AF_PLOT_GREY,
  AF_PLOT_BLUE,
  AF_PLOT_ORANGE,
  AF_PLOT_GREEN,
  AF_PLOT_RED,
  AF_PLOT_PURPLE,
  AF_PLOT_LIGHT_BLUE,
  AF_PLOT_LIGHT_ORANGE,
  AF_PLOT_LIGHT_GREEN,
  AF_PLOT_LIGHT_GREY,
  AF_PLOT_LIGHT_RED,
  AF_PLOT_LIGHT_PURPLE,
  AF_PLOT_COLOURS
} af_plot_colour;

typedef enum {
  AF_PLOT_LINE = 0,
  AF_PLOT_DASHED,
  AF_PLOT_POINTS,
  AF_PLOT_STEPS, /* histogram: x[k] the left edge of bin k, bins of equal width x[1] - x[0] */
  AF_PLOT_MARKER /* a large diamond outlined in black per point, drawn over the data: a choice */
} af_plot_style;

typedef struct {
  const char *label; /* legend text; NULL = not in the legend */
  const double *x, *y;
  size_t n; /* non-finite points are skipped (a line breaks there) */
  af_plot_colour colour;
  af_plot_style style;
} af_plot_series;

/* A shaded interval x0..x1 across the panel's height. */
typedef struct {
  const char *label; /* NULL = not in the legend (e.g. the second of alternate shades) */
  double x0, x1;
  af_plot_colour colour;
} af_plot_span;

/* A line across the panel at x = at (vertical) or y = at (horizontal). */
typedef struct {
  const char *label;
  double at;
  af_plot_colour colour;
  bool dashed;
} af_plot_rule;

typedef enum {
  AF_PLOT_LEGEND_TOP_RIGHT = 0,
  AF_PLOT_LEGEND_TOP_LEFT,
  AF_PLOT_LEGEND_BOTTOM_RIGHT,
  AF_PLOT_LEGEND_BOTTOM_LEFT,
  AF_PLOT_LEGEND_BELOW /* outside the axes, under the x label */
} af_plot_legend_at;

typedef struct {
  const char *title, *x_label, *y_label; /* labels with their unit */
  const char *subtitle;                  /* a smaller line under the title; NULL = none */
  double x_min, x_max, y_min, y_max;     /* NaN: from the data (with a margin) */
  const af_plot_series *series;
  size_t n_series;
  const af_plot_span *spans;
  size_t n_spans;
  const af_plot_rule *x_rules; /* vertical lines */
  size_t n_x_rules;
  const af_plot_rule *y_rules; /* horizontal lines */
  size_t n_y_rules;
  af_plot_legend_at legend;
} af_plot_panel;

/* A panel with no data, NaN limits, legend at the top right. */
af_plot_panel af_plot_panel_empty(void);

/* Draws panels[0 .. nx*ny) (row by row) on one page of t. AF_EINVAL for bad
 * arguments (err says which), AF_EIO when PLplot cannot open the output
 * (the file's directory, a missing driver). */
af_status af_plot_draw(const af_plot_target *t, const af_plot_panel *panels, int nx, int ny,
                       char *err, size_t len);

#ifdef __cplusplus
}
#endif
#endif
