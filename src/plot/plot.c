/* plot.c — panels on PLplot (see plot.h). */
#define _POSIX_C_SOURCE 200809L
#include "plot.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <plplot.h>
#include <stdio.h>
#include <string.h>

#include "text.h"

#define AF_PLOT_LEGEND_MAX 24
#define AF_PLOT_RUN_MAX 4096 /* points per drawn run of a series (longer ones are split) */

/* cmap0: 0 = background, then af_plot_colour in order. */
static const PLINT af_r[AF_PLOT_COLOURS] = {255, 0,   110, 31,  255, 44,  214,
                                            148, 174, 255, 152, 222, 255, 197};
static const PLINT af_g[AF_PLOT_COLOURS] = {255, 0,   110, 119, 127, 160, 39,
                                            103, 199, 187, 223, 222, 179, 176};
static const PLINT af_b[AF_PLOT_COLOURS] = {255, 0,   110, 180, 14,  44,  40,
                                            189, 232, 120, 138, 222, 179, 213};
/* The light colours are shades: half transparent, so overlapping spans both show. */
static const PLFLT af_a[AF_PLOT_COLOURS] = {1, 1, 1, 1, 1, 1, 1, 1, 0.5, 0.5, 0.5, 1, 0.5, 0.5};

af_plot_panel af_plot_panel_empty(void)
{
  af_plot_panel p;
  memset(&p, 0, sizeof p);
  p.x_min = p.x_max = p.y_min = p.y_max = NAN;
  p.legend = AF_PLOT_LEGEND_TOP_RIGHT;
  return p;
}

static bool ends_with(const char *s, const char *suffix)
{
  size_t n = strlen(s), m = strlen(suffix);
  if (n < m)
    return false;
  for (size_t k = 0; k < m; k++)
    if (tolower((unsigned char)s[n - m + k]) != suffix[k])
      return false;
  return true;
}

af_status af_plot_target_file(const char *path, int width_px, int height_px, af_plot_target *out)
{
  if (!path || !out || width_px < 64 || width_px > 8192 || height_px < 64 || height_px > 8192)
    return AF_EINVAL;
  memset(out, 0, sizeof *out);
  if (ends_with(path, ".png"))
    out->format = AF_PLOT_PNG;
  else if (ends_with(path, ".svg"))
    out->format = AF_PLOT_SVG;
  else
    return AF_EINVAL;
  out->path = path;
  out->width_px = width_px;
  out->height_px = height_px;
  return AF_OK;
}

/* ---- limits ------------------------------------------------------------------- */

static void extend(double v, double *lo, double *hi)
{
  if (!isfinite(v))
    return;
  if (v < *lo)
    *lo = v;
  if (v > *hi)
    *hi = v;
}

/* The panel's window: given limits, else the data's range with a 5 % margin. */
static void axis_limits(const af_plot_panel *p, double *x0, double *x1, double *y0, double *y1)
{
  double xl = INFINITY, xh = -INFINITY, yl = INFINITY, yh = -INFINITY;
  for (size_t s = 0; s < p->n_series; s++) {
    const af_plot_series *ser = &p->series[s];
    for (size_t k = 0; k < ser->n; k++) {
      if (!isfinite(ser->x[k]) || !isfinite(ser->y[k]))
        continue;
      extend(ser->x[k], &xl, &xh);
      extend(ser->y[k], &yl, &yh);
      if (ser->style == AF_PLOT_STEPS) { /* the bin's right edge and the floor */
        if (ser->n > 1)
          extend(ser->x[k] + (ser->x[1] - ser->x[0]), &xl, &xh);
        extend(0.0, &yl, &yh);
      }
    }
  }
  for (size_t k = 0; k < p->n_x_rules; k++)
    extend(p->x_rules[k].at, &xl, &xh);
  for (size_t k = 0; k < p->n_y_rules; k++)
    extend(p->y_rules[k].at, &yl, &yh);
  if (!(xl <= xh))
    xl = 0.0, xh = 1.0;
  if (!(yl <= yh))
    yl = 0.0, yh = 1.0;
  double dx = xh > xl ? 0.05 * (xh - xl) : fmax(1.0, fabs(xl) * 0.1);
  double dy = yh > yl ? 0.05 * (yh - yl) : fmax(1.0, fabs(yl) * 0.1);
  *x0 = isfinite(p->x_min) ? p->x_min : xl - dx;
  *x1 = isfinite(p->x_max) ? p->x_max : xh + dx;
  *y0 = isfinite(p->y_min) ? p->y_min : yl - dy;
  *y1 = isfinite(p->y_max) ? p->y_max : yh + (p->n_series || p->n_y_rules ? 3.0 : 1.0) * dy;
  if (!(*x1 > *x0))
    *x1 = *x0 + 1.0;
  if (!(*y1 > *y0))
    *y1 = *y0 + 1.0;
}

/* ---- layers ------------------------------------------------------------------- */

static void span(const af_plot_span *s, double x0, double x1, double y0, double y1)
{
  double a = fmax(fmin(s->x0, s->x1), x0), b = fmin(fmax(s->x0, s->x1), x1);
  if (!(b > a))
    return;
  PLFLT x[4] = {a, b, b, a}, y[4] = {y0, y0, y1, y1};
  plcol0(s->colour);
  plpsty(0);
  plfill(4, x, y);
}

/* A line through the finite points, broken where a point is not finite. */
static void draw_line(const double *x, const double *y, size_t n)
{
  PLFLT bx[AF_PLOT_RUN_MAX], by[AF_PLOT_RUN_MAX];
  size_t m = 0;
  for (size_t k = 0; k <= n; k++) {
    bool good = k < n && isfinite(x[k]) && isfinite(y[k]);
    if (good) {
      bx[m] = x[k];
      by[m] = y[k];
      m++;
    }
    if ((!good || m == AF_PLOT_RUN_MAX) && m > 0) {
      if (m > 1)
        plline((PLINT)m, bx, by);
      if (good) { /* split: the next run starts at this point */
        bx[0] = bx[m - 1];
        by[0] = by[m - 1];
        m = 1;
      } else
        m = 0;
    }
  }
}

static void steps(const af_plot_series *s)
{
  if (s->n == 0)
    return;
  double w = s->n > 1 ? s->x[1] - s->x[0] : 1.0;
  for (size_t k = 0; k < s->n; k++) {
    if (!isfinite(s->x[k]) || !isfinite(s->y[k]))
      continue;
    double prev = k > 0 && isfinite(s->y[k - 1]) ? s->y[k - 1] : 0.0;
    double next = k + 1 < s->n && isfinite(s->y[k + 1]) ? s->y[k + 1] : 0.0;
    PLFLT x[4] = {s->x[k], s->x[k], s->x[k] + w, s->x[k] + w};
    PLFLT y[4] = {fmin(prev, s->y[k]), s->y[k], s->y[k], fmin(next, s->y[k])};
    plline(4, x, y);
  }
}

#define AF_PLOT_DIAMOND "\xe2\x97\x86" /* U+25C6, a filled diamond */

static void draw_series(const af_plot_series *s)
{
  plcol0(s->colour);
  pllsty(s->style == AF_PLOT_DASHED ? 2 : 1);
  plwidth(s->style == AF_PLOT_POINTS ? 1.0 : 2.0);
  switch (s->style) {
  case AF_PLOT_POINTS:
    for (size_t k = 0; k < s->n; k++)
      if (isfinite(s->x[k]) && isfinite(s->y[k])) {
        PLFLT x = s->x[k], y = s->y[k];
        plpoin(1, &x, &y, 17);
      }
    break;
  case AF_PLOT_STEPS: steps(s); break;
  case AF_PLOT_MARKER: {
    PLFLT def_mm, height_mm; /* the page's character scale, restored after the markers */
    plgchr(&def_mm, &height_mm);
    for (size_t k = 0; k < s->n; k++)
      if (isfinite(s->x[k]) && isfinite(s->y[k])) {
        PLFLT x = s->x[k], y = s->y[k];
        plcol0(AF_PLOT_BLACK);
        plschr(0.0, 2.4);
        plstring(1, &x, &y, AF_PLOT_DIAMOND);
        plcol0(s->colour);
        plschr(0.0, 1.7);
        plstring(1, &x, &y, AF_PLOT_DIAMOND);
      }
    plschr(0.0, def_mm > 0.0 ? height_mm / def_mm : 1.0);
    break;
  }
  default: draw_line(s->x, s->y, s->n); break;
  }
  pllsty(1);
  plwidth(1.0);
}

static void rule(const af_plot_rule *r, bool vertical, double x0, double x1, double y0, double y1)
{
  if (!isfinite(r->at))
    return;
  PLFLT x[2], y[2];
  if (vertical)
    x[0] = x[1] = r->at, y[0] = y0, y[1] = y1;
  else
    x[0] = x0, x[1] = x1, y[0] = y[1] = r->at;
  plcol0(r->colour);
  pllsty(r->dashed ? 2 : 1);
  plwidth(2.0);
  plline(2, x, y);
  pllsty(1);
  plwidth(1.0);
}

/* ---- legend ------------------------------------------------------------------- */

typedef struct {
  PLINT opt[AF_PLOT_LEGEND_MAX], text_colour[AF_PLOT_LEGEND_MAX];
  const char *text[AF_PLOT_LEGEND_MAX];
  PLINT box_colour[AF_PLOT_LEGEND_MAX], box_pattern[AF_PLOT_LEGEND_MAX];
  PLFLT box_scale[AF_PLOT_LEGEND_MAX], box_width[AF_PLOT_LEGEND_MAX];
  PLINT line_colour[AF_PLOT_LEGEND_MAX], line_style[AF_PLOT_LEGEND_MAX];
  PLFLT line_width[AF_PLOT_LEGEND_MAX];
  PLINT symbol_colour[AF_PLOT_LEGEND_MAX], symbol_number[AF_PLOT_LEGEND_MAX];
  PLFLT symbol_scale[AF_PLOT_LEGEND_MAX];
  const char *symbol[AF_PLOT_LEGEND_MAX];
  int n;
} af_legend;

static int legend_add(af_legend *l, const char *text, PLINT opt, af_plot_colour c, bool dashed)
{
  if (!text || l->n == AF_PLOT_LEGEND_MAX)
    return -1;
  int k = l->n++;
  l->opt[k] = opt;
  l->text[k] = text;
  l->text_colour[k] = AF_PLOT_BLACK;
  l->box_colour[k] = c;
  l->box_pattern[k] = 0;
  l->box_scale[k] = 0.8;
  l->box_width[k] = 1.0;
  l->line_colour[k] = c;
  l->line_style[k] = dashed ? 2 : 1;
  l->line_width[k] = 2.0;
  l->symbol_colour[k] = c;
  l->symbol_number[k] = 1;
  l->symbol_scale[k] = 1.0;
  l->symbol[k] = "\xe2\x80\xa2"; /* U+2022, a bullet (cairo draws Unicode) */
  return k;
}

static void legend_draw(const af_plot_panel *p)
{
  af_legend l;
  memset(&l, 0, sizeof l);
  for (size_t k = 0; k < p->n_spans; k++)
    legend_add(&l, p->spans[k].label, PL_LEGEND_COLOR_BOX, p->spans[k].colour, false);
  for (size_t k = 0; k < p->n_series; k++) {
    const af_plot_series *s = &p->series[k];
    bool symbol = s->style == AF_PLOT_POINTS || s->style == AF_PLOT_MARKER;
    int at = legend_add(&l, s->label, symbol ? PL_LEGEND_SYMBOL : PL_LEGEND_LINE, s->colour,
                        s->style == AF_PLOT_DASHED);
    if (at >= 0 && s->style == AF_PLOT_MARKER) {
      l.symbol[at] = AF_PLOT_DIAMOND;
      l.symbol_scale[at] = 1.2;
    }
  }
  for (size_t k = 0; k < p->n_x_rules; k++)
    legend_add(&l, p->x_rules[k].label, PL_LEGEND_LINE, p->x_rules[k].colour, p->x_rules[k].dashed);
  for (size_t k = 0; k < p->n_y_rules; k++)
    legend_add(&l, p->y_rules[k].label, PL_LEGEND_LINE, p->y_rules[k].colour, p->y_rules[k].dashed);
  if (l.n == 0)
    return;
  const bool below = p->legend == AF_PLOT_LEGEND_BELOW;
  PLINT pos = below ? PL_POSITION_OUTSIDE | PL_POSITION_BOTTOM : PL_POSITION_INSIDE;
  if (!below) {
    pos |= p->legend == AF_PLOT_LEGEND_TOP_LEFT || p->legend == AF_PLOT_LEGEND_BOTTOM_LEFT
               ? PL_POSITION_LEFT
               : PL_POSITION_RIGHT;
    pos |= p->legend == AF_PLOT_LEGEND_BOTTOM_LEFT || p->legend == AF_PLOT_LEGEND_BOTTOM_RIGHT
               ? PL_POSITION_BOTTOM
               : PL_POSITION_TOP;
  }
  const PLINT columns = 1, rows = l.n;
  PLFLT w, h;
  pllegend(&w, &h, PL_LEGEND_BACKGROUND | PL_LEGEND_BOUNDING_BOX, pos, 0.0, below ? 0.20 : 0.01,
           0.06, 0, AF_PLOT_GREY, 1, rows, columns, l.n, l.opt, 0.6, below ? 0.6 : 0.7, 1.8, 0.0,
           l.text_colour, l.text, l.box_colour, l.box_pattern, l.box_scale, l.box_width,
           l.line_colour, l.line_style, l.line_width, l.symbol_colour, l.symbol_scale,
           l.symbol_number, l.symbol);
}

/* ---- one panel ------------------------------------------------------------------ */

/* chars: character height scale (PLplot scales it with the subpage). */
static void draw_panel(const af_plot_panel *p, double chars)
{
  plschr(0.0, chars);
  double x0, x1, y0, y1;
  axis_limits(p, &x0, &x1, &y0, &y1);
  plvpor(0.13, 0.96, p->legend == AF_PLOT_LEGEND_BELOW ? 0.42 : 0.13, p->subtitle ? 0.86 : 0.90);
  plwind(x0, x1, y0, y1);
  for (size_t k = 0; k < p->n_spans; k++)
    span(&p->spans[k], x0, x1, y0, y1);
  plcol0(AF_PLOT_LIGHT_GREY);
  plbox("g", 0.0, 0, "g", 0.0, 0);
  for (size_t k = 0; k < p->n_series; k++)
    draw_series(&p->series[k]);
  for (size_t k = 0; k < p->n_x_rules; k++)
    rule(&p->x_rules[k], true, x0, x1, y0, y1);
  for (size_t k = 0; k < p->n_y_rules; k++)
    rule(&p->y_rules[k], false, x0, x1, y0, y1);
  plcol0(AF_PLOT_BLACK);
  plbox("bcnst", 0.0, 0, "bcnstv", 0.0, 0);
  pllab(p->x_label ? p->x_label : "", p->y_label ? p->y_label : "", p->title ? p->title : "");
  if (p->subtitle) {
    plschr(0.0, 0.85 * chars);
    plmtex("t", 1.0, 0.5, 0.5, p->subtitle);
    plschr(0.0, chars);
  }
  legend_draw(p);
}

af_status af_plot_draw(const af_plot_target *t, const af_plot_panel *panels, int nx, int ny,
                       char *err, size_t len)
{
  if (!t || !panels || nx < 1 || ny < 1 || nx * ny > 16 || t->width_px < 64 || t->height_px < 64 ||
      t->width_px > 8192 || t->height_px > 8192) {
    af_text(err, len, "bad plot arguments (panels %d x %d, %d x %d px)", nx, ny,
            t ? t->width_px : 0, t ? t->height_px : 0);
    return AF_EINVAL;
  }
  if (t->format == AF_PLOT_MEMORY ? t->rgb == NULL : t->path == NULL) {
    af_text(err, len, "no output given for the plot");
    return AF_EINVAL;
  }
  if (t->format != AF_PLOT_MEMORY) {
    /* PLplot exits the process when it cannot open its file: try it first. */
    FILE *f = fopen(t->path, "wb");
    if (!f) {
      af_text(err, len, "%s: cannot write: %s", t->path, strerror(errno));
      return AF_EIO;
    }
    fclose(f);
  }
  PLINT previous, stream;
  plgstrm(&previous);
  plmkstrm(&stream);
  if (stream < 0) {
    af_text(err, len, "PLplot has no free stream");
    return AF_EIO;
  }
  if (t->format == AF_PLOT_MEMORY) {
    memset(t->rgb, 255, (size_t)t->width_px * (size_t)t->height_px * 3);
    plsdev("memcairo");
    plsmem(t->width_px, t->height_px, t->rgb);
  } else {
    plsdev(t->format == AF_PLOT_PNG ? "pngcairo" : "svgcairo");
    plsfnam(t->path);
    plspage(0.0, 0.0, t->width_px, t->height_px, 0, 0);
  }
  plscmap0a(af_r, af_g, af_b, af_a, AF_PLOT_COLOURS);
  plstar(nx, ny); /* plinit with nx x ny subpages */
  for (int k = 0; k < nx * ny; k++) {
    pladv(k + 1);
    draw_panel(&panels[k], nx >= 3 ? 0.55 : 0.7);
  }
  plend1();
  plsstrm(previous);
  return AF_OK;
}
