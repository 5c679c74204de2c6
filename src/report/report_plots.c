/* report_plots.c — firmness_report --plots (see report_plots.h). */
#define _POSIX_C_SOURCE 200809L
#include "report_plots.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "options.h"
#include "plot.h"
#include "lamb.h"
#include "strike_view.h"
#include "text.h"

#define AF_PATH_MAX 1024
#define AF_STRIKE_W_PX 1200
#define AF_STRIKE_H_PX 600
#define AF_SESSION_W_PX 900
#define AF_SESSION_H_PX 560
#define AF_HIST_BIN_MPA 0.5

struct af_report_plots {
  char dir[AF_PATH_MAX];
  const af_lane_config *cfg;
  af_strike_view *view;
  size_t strikes, failed;
  char first_error[256];
};

af_status af_report_plots_create(const char *dir, const af_lane_config *cfg, af_report_plots **out,
                                 char *err, size_t len)
{
  *out = NULL;
  struct stat st;
  if (stat(dir, &st) != 0 && mkdir(dir, 0777) != 0) {
    af_text(err, len, "cannot make the folder: %s", strerror(errno));
    return AF_EIO;
  }
  if (stat(dir, &st) != 0 || !S_ISDIR(st.st_mode)) {
    af_text(err, len, "not a folder");
    return AF_EIO;
  }
  af_report_plots *p = calloc(1, sizeof *p);
  if (!p) {
    af_text(err, len, "out of memory");
    return AF_ENOMEM;
  }
  af_text(p->dir, sizeof p->dir, "%s", dir);
  p->cfg = cfg;
  af_status s = af_strike_view_create(cfg, &p->view);
  if (s != AF_OK) {
    af_text(err, len, "cannot make the strike figure: %s", af_strerror(s));
    free(p);
    return s;
  }
  *out = p;
  return AF_OK;
}

void af_report_plots_destroy(af_report_plots *p)
{
  if (!p)
    return;
  af_strike_view_destroy(p->view);
  free(p);
}

static void plot_failed(af_report_plots *p, const char *err)
{
  if (p->failed++ == 0)
    af_text(p->first_error, sizeof p->first_error, "%s", err);
}

void af_report_plots_strike(const af_lane_strike *s, const af_lane *lane, void *user)
{
  af_report_plots *p = user;
  char path[AF_PATH_MAX + 64], err[256];
  p->strikes++;
  af_text(path, sizeof path, "%s/strike_%04zu_apple_%u.png", p->dir, p->strikes, s->apple_id);
  af_strike_view_capture(p->view, s, lane);
  af_plot_target t;
  if (af_strike_view_prepare(p->view) != AF_OK ||
      af_plot_target_file(path, AF_STRIKE_W_PX, AF_STRIKE_H_PX, &t) != AF_OK ||
      af_strike_view_draw(p->view, &t, err, sizeof err) != AF_OK)
    plot_failed(p, path);
  else
    af_options_wrote(path);
}

/* ---- session figures ----------------------------------------------------------- */

static af_status draw_one(af_report_plots *p, const char *name, const af_plot_panel *panel,
                          char *err, size_t len)
{
  char path[AF_PATH_MAX + 64];
  af_plot_target t;
  af_text(path, sizeof path, "%s/%s", p->dir, name);
  if (af_plot_target_file(path, AF_SESSION_W_PX, AF_SESSION_H_PX, &t) != AF_OK) {
    af_text(err, len, "%s: bad target", path);
    return AF_EINVAL;
  }
  af_status st = af_plot_draw(&t, panel, 1, 1, err, len);
  if (st == AF_OK)
    af_options_wrote(path);
  return st;
}

/* k columns of n doubles for one session figure (one block, freed by the
 * caller), or NULL with "out of memory" in err. */
static double *columns(size_t n, size_t k, char *err, size_t len)
{
  double *buf = malloc((k * n + 1) * sizeof *buf);
  if (!buf)
    af_text(err, len, "out of memory");
  return buf;
}

/* Histogram counts of x [Pa] in AF_HIST_BIN_MPA bins from 0; edges in MPa. */
static void histogram(const af_session *s, bool from_resonance, double *edges, double *counts,
                      size_t bins)
{
  for (size_t k = 0; k < bins; k++) {
    edges[k] = (double)k * AF_HIST_BIN_MPA;
    counts[k] = 0.0;
  }
  for (size_t k = 0; k < s->n_strikes; k++) {
    const af_measure_report *r = &s->strikes[k].report;
    double v = (from_resonance ? r->modulus_from_resonance_pa : r->fitted_modulus_pa) * 1e-6;
    if (!isfinite(v) || v < 0.0)
      continue;
    size_t b = (size_t)(v / AF_HIST_BIN_MPA);
    counts[b < bins ? b : bins - 1] += 1.0;
  }
}

static af_status plot_histogram(af_report_plots *p, const af_session *s, const af_summary *m,
                                char *err, size_t len)
{
  double top = fmax(p->cfg->modulus_max_pa * 1e-6,
                    fmax(m->modulus_from_resonance_pa.q[6], m->fitted_modulus_pa.q[6]) * 1e-6);
  if (!isfinite(top))
    top = p->cfg->modulus_max_pa * 1e-6;
  size_t bins = (size_t)ceil(top / AF_HIST_BIN_MPA) + 2;
  double *buf = columns(bins, 4, err, len);
  if (!buf)
    return AF_ENOMEM;
  histogram(s, true, buf, buf + bins, bins);
  histogram(s, false, buf + 2 * bins, buf + 3 * bins, bins);
  char title[160], l1[96], l2[96];
  af_text(title, sizeof title, "firmness of %zu strikes (%s)", s->n_strikes, p->cfg->cultivar);
  af_text(l1, sizeof l1, "from the 0S2 (median %.2f MPa)",
          m->modulus_from_resonance_pa.q[3] * 1e-6);
  af_text(l2, sizeof l2, "fitted to the pulse (median %.2f MPa)", m->fitted_modulus_pa.q[3] * 1e-6);
  af_plot_series ser[2] = {
      {l1, buf, buf + bins, bins, AF_PLOT_BLUE, AF_PLOT_STEPS},
      {l2, buf + 2 * bins, buf + 3 * bins, bins, AF_PLOT_ORANGE, AF_PLOT_STEPS}};
  af_plot_span range = {"cultivar's firmness range", p->cfg->modulus_min_pa * 1e-6,
                        p->cfg->modulus_max_pa * 1e-6, AF_PLOT_LIGHT_GREEN};
  af_plot_panel panel = af_plot_panel_empty();
  panel.title = title;
  panel.x_label = "modulus E#d2#u [MPa]";
  panel.y_label = "strikes per 0.5 MPa";
  panel.series = ser;
  panel.n_series = 2;
  panel.spans = &range;
  panel.n_spans = 1;
  panel.x_min = 0.0;
  panel.x_max = (double)bins * AF_HIST_BIN_MPA;
  panel.y_min = 0.0;
  double most = 1.0;
  for (size_t k = 0; k < bins; k++)
    most = fmax(most, fmax(buf[bins + k], buf[3 * bins + k]));
  panel.y_max = 1.4 * most; /* room for the legend */
  af_status st = draw_one(p, "firmness_histogram.png", &panel, err, len);
  free(buf);
  return st;
}

/* Verdict classes of the scatter. */
enum { AF_CLASS_RELIABLE = 0, AF_CLASS_OUTSIDE_BAND, AF_CLASS_OTHER, AF_CLASSES };

static int class_of(const af_measure_report *r)
{
  if (r->reliable)
    return AF_CLASS_RELIABLE;
  return r->verdict.flags == AF_VERDICT_OUTSIDE_BAND ? AF_CLASS_OUTSIDE_BAND : AF_CLASS_OTHER;
}

/* The stiffness factor f^2 m^(2/3) of a sphere of modulus e_pa: independent
 * of the mass (E = C f^2 m^(2/3) rho^(1/3)). */
static double stiffness_of(const af_lane_config *c, double xi, double e_pa)
{
  const af_model_params *m = &c->model;
  const double mass_kg = 0.175; /* any: the factor does not depend on it */
  double f = af_lamb_frequency_hz(xi, m->modulus_factor * e_pa, m->impact.fruit_poisson,
                                  m->fruit_density_kg_m3, mass_kg);
  return f * f * pow(mass_kg, 2.0 / 3.0);
}

static af_status plot_stiffness(af_report_plots *p, const af_session *s, char *err, size_t len)
{
  const size_t n = s->n_strikes;
  double *buf = columns(n, 2 * AF_CLASSES, err, len);
  if (!buf)
    return AF_ENOMEM;
  size_t count[AF_CLASSES] = {0};
  for (size_t k = 0; k < n; k++) {
    const af_session_strike *r = &s->strikes[k];
    int c = class_of(&r->report);
    double *x = buf + 2 * (size_t)c * n, *y = x + n;
    x[count[c]] = r->mass_kg * 1e3;
    y[count[c]] = r->report.stiffness_factor * 1e-3;
    count[c]++;
  }
  /* cppcheck-suppress variableScope ; the rules point to lo and hi until the draw */
  char labels[AF_CLASSES][64], title[128], lo[64], hi[64];
  static const char *const names[AF_CLASSES] = {"reliable", "NOT: 0S2 outside the band",
                                                "NOT: other reasons"};
  static const af_plot_colour colours[AF_CLASSES] = {AF_PLOT_GREEN, AF_PLOT_ORANGE, AF_PLOT_RED};
  af_plot_series ser[AF_CLASSES];
  for (int c = 0; c < AF_CLASSES; c++) {
    af_text(labels[c], sizeof labels[c], "%s (%zu)", names[c], count[c]);
    ser[c] =
        (af_plot_series){labels[c],  buf + 2 * (size_t)c * n, buf + 2 * (size_t)c * n + n, count[c],
                         colours[c], AF_PLOT_POINTS};
  }
  double xi = NAN;
  af_plot_rule rules[2];
  size_t nr = 0;
  if (af_lamb_root(p->cfg->model.impact.fruit_poisson, &xi) == AF_OK) {
    af_text(lo, sizeof lo, "a sphere of %.0f MPa", p->cfg->modulus_min_pa * 1e-6);
    af_text(hi, sizeof hi, "a sphere of %.0f MPa", p->cfg->modulus_max_pa * 1e-6);
    rules[nr++] = (af_plot_rule){lo, stiffness_of(p->cfg, xi, p->cfg->modulus_min_pa) * 1e-3,
                                 AF_PLOT_GREY, true};
    rules[nr++] = (af_plot_rule){hi, stiffness_of(p->cfg, xi, p->cfg->modulus_max_pa) * 1e-3,
                                 AF_PLOT_BLACK, true};
  }
  af_text(title, sizeof title, "stiffness factor against mass, %zu strikes, by measured verdict",
          n);
  af_plot_panel panel = af_plot_panel_empty();
  panel.title = title;
  panel.x_label = "apple mass [g]";
  panel.y_label = "stiffness factor f#u2#d m#u2/3#d [10#u3#d Hz#u2#d kg#u2/3#d]";
  panel.series = ser;
  panel.n_series = AF_CLASSES;
  panel.y_rules = rules;
  panel.n_y_rules = nr;
  panel.legend = AF_PLOT_LEGEND_TOP_LEFT;
  af_status st = draw_one(p, "stiffness_vs_mass.png", &panel, err, len);
  free(buf);
  return st;
}

static af_status plot_band(af_report_plots *p, const af_session *s, char *err, size_t len)
{
  const size_t n = s->n_strikes;
  double *buf = columns(n, 7, err, len);
  if (!buf)
    return AF_ENOMEM;
  double *idx = buf, *lo = buf + n, *hi = buf + 2 * n, *xin = buf + 3 * n, *yin = buf + 4 * n;
  double *xout = buf + 5 * n, *yout = buf + 6 * n;
  size_t nin = 0, nout = 0;
  for (size_t k = 0; k < n; k++) {
    const af_measure_report *r = &s->strikes[k].report;
    idx[k] = (double)k + 0.5; /* the left edge of strike k + 1's step */
    lo[k] = r->band_low_hz;
    hi[k] = r->band_high_hz;
    if (!isfinite(r->resonance_hz))
      continue;
    bool inside = r->resonance_hz >= r->band_low_hz && r->resonance_hz <= r->band_high_hz;
    if (inside) {
      xin[nin] = (double)(k + 1);
      yin[nin++] = r->resonance_hz;
    } else {
      xout[nout] = (double)(k + 1);
      yout[nout++] = r->resonance_hz;
    }
  }
  char lin[64], lout[64], title[128];
  af_text(lin, sizeof lin, "0S2 inside the band (%zu)", nin);
  af_text(lout, sizeof lout, "0S2 outside the band (%zu)", nout);
  af_text(title, sizeof title, "measured 0S2 against the half-power band of lobe %u",
          p->cfg->model.lobe);
  af_plot_series ser[4] = {{"band, upper edge", idx, hi, n, AF_PLOT_ORANGE, AF_PLOT_STEPS},
                           {"band, lower edge", idx, lo, n, AF_PLOT_ORANGE, AF_PLOT_DASHED},
                           {lin, xin, yin, nin, AF_PLOT_GREEN, AF_PLOT_POINTS},
                           {lout, xout, yout, nout, AF_PLOT_RED, AF_PLOT_POINTS}};
  af_plot_panel panel = af_plot_panel_empty();
  panel.title = title;
  panel.x_label = "strike (in recorded order)";
  panel.y_label = "frequency [Hz]";
  panel.series = ser;
  panel.n_series = 4;
  panel.y_min = 0.0;
  panel.x_min = 0.0;
  panel.x_max = (double)n + 1.0;
  af_status st = draw_one(p, "resonance_vs_band.png", &panel, err, len);
  free(buf);
  return st;
}

/* The hammer health's v0 over the session: each strike's from its impulse
 * (green while the velocity check is quiet, red while it warns), the
 * window's mean, the set velocity and its band. */
static af_status plot_hammer(af_report_plots *p, const af_session *s, char *err, size_t len)
{
  const size_t n = s->n_strikes;
  double *buf = columns(n, 6, err, len);
  if (!buf)
    return AF_ENOMEM;
  double *idx = buf, *mean = buf + n, *xok = buf + 2 * n, *yok = buf + 3 * n;
  double *xw = buf + 4 * n, *yw = buf + 5 * n;
  size_t nok = 0, nw = 0;
  for (size_t k = 0; k < n; k++) {
    const af_session_strike *r = &s->strikes[k];
    idx[k] = (double)(k + 1);
    mean[k] = r->hammer_velocity_mean_m_s;
    if (!isfinite(r->hammer_velocity_m_s))
      continue;
    const bool warned = (r->hammer_warnings & AF_HAMMER_WARN_VELOCITY) != 0;
    (warned ? xw : xok)[warned ? nw : nok] = (double)(k + 1);
    (warned ? yw : yok)[warned ? nw++ : nok++] = r->hammer_velocity_m_s;
  }
  const af_hammer_health_config *c = &s->health_cfg;
  char lok[64], lw[64], lmean[64], lset[64], lband[64], lfirst[64], title[160];
  af_text(lok, sizeof lok, "strike, velocity check OK (%zu)", nok);
  af_text(lw, sizeof lw, "strike, velocity check WARN (%zu)", nw);
  af_text(lmean, sizeof lmean, "mean of the last %zu strikes", c->window);
  af_text(lset, sizeof lset, "strike_velocity_m_s %.4g m/s", c->velocity_m_s);
  af_text(lband, sizeof lband, "band +- %.1f %%", 100.0 * c->velocity_band);
  af_plot_series ser[3] = {{lok, xok, yok, nok, AF_PLOT_GREEN, AF_PLOT_POINTS},
                           {lw, xw, yw, nw, AF_PLOT_RED, AF_PLOT_POINTS},
                           {lmean, idx, mean, n, AF_PLOT_BLUE, AF_PLOT_LINE}};
  const af_plot_rule rules[3] = {
      {lset, c->velocity_m_s, AF_PLOT_BLACK, false},
      {lband, c->velocity_m_s * (1.0 + c->velocity_band), AF_PLOT_ORANGE, true},
      {NULL, c->velocity_m_s * (1.0 - c->velocity_band), AF_PLOT_ORANGE, true}};
  const uint64_t first = s->stats.health.first_warning_strike[0];
  af_text(lfirst, sizeof lfirst, "first velocity warning, strike %llu", (unsigned long long)first);
  const af_plot_rule marker = {lfirst, (double)first, AF_PLOT_RED, true};
  af_text(title, sizeof title, "hammer contact velocity from the impulse, %zu strikes", n);
  af_plot_panel panel = af_plot_panel_empty();
  panel.title = title;
  panel.x_label = "strike (in recorded order)";
  panel.y_label = "contact velocity v#d0#u [m/s]";
  panel.series = ser;
  panel.n_series = 3;
  panel.y_rules = rules;
  panel.n_y_rules = 3;
  panel.x_rules = &marker;
  panel.n_x_rules = first > 0;
  panel.x_min = 0.0;
  panel.x_max = (double)n + 1.0;
  panel.legend = AF_PLOT_LEGEND_BELOW;
  af_status st = draw_one(p, "hammer_velocity.png", &panel, err, len);
  free(buf);
  return st;
}

/* The learned modulus factor over the session (factor_learn.h): each
 * strike's own factor (green: reliable, fed to the estimate; grey: not
 * reliable, never fed), the running median and its 95 % interval, and the
 * applied value. */
static af_status plot_factor(af_report_plots *p, const af_session *s, char *err, size_t len)
{
  const size_t n = s->n_strikes;
  double *buf = columns(n, 9, err, len);
  if (!buf)
    return AF_ENOMEM;
  double *idx = buf, *est = buf + n, *lo = buf + 2 * n, *hi = buf + 3 * n, *app = buf + 4 * n;
  double *xr = buf + 5 * n, *yr = buf + 6 * n, *xu = buf + 7 * n, *yu = buf + 8 * n;
  size_t nr = 0, nu = 0;
  for (size_t k = 0; k < n; k++) {
    const af_session_strike *r = &s->strikes[k];
    idx[k] = (double)(k + 1);
    est[k] = r->factor_estimate;
    lo[k] = r->factor_ci_low_95;
    hi[k] = r->factor_ci_high_95;
    app[k] = r->factor_applied;
    if (!isfinite(r->factor_true) || !(r->factor_true > 0.0))
      continue;
    const bool fed = r->report.reliable;
    (fed ? xr : xu)[fed ? nr : nu] = (double)(k + 1);
    (fed ? yr : yu)[fed ? nr++ : nu++] = r->factor_true;
  }
  char lr[64], lu[64], title[160], lstart[64];
  af_text(lr, sizeof lr, "strike's factor, reliable: learned from (%zu)", nr);
  af_text(lu, sizeof lu, "strike's factor, not reliable: never used (%zu)", nu);
  af_text(lstart, sizeof lstart, "cultivar's modulus_factor %.4g", p->cfg->model.modulus_factor);
  af_plot_series ser[6] = {
      {lu, xu, yu, nu, AF_PLOT_GREY, AF_PLOT_POINTS},
      {lr, xr, yr, nr, AF_PLOT_GREEN, AF_PLOT_POINTS},
      {"learned estimate (running median)", idx, est, n, AF_PLOT_BLUE, AF_PLOT_LINE},
      {"its 95 % interval", idx, lo, n, AF_PLOT_BLUE, AF_PLOT_DASHED},
      {NULL, idx, hi, n, AF_PLOT_BLUE, AF_PLOT_DASHED},
      {"applied from the next strike", idx, app, n, AF_PLOT_ORANGE, AF_PLOT_LINE}};
  const af_plot_rule start = {lstart, p->cfg->model.modulus_factor, AF_PLOT_BLACK, true};
  af_text(title, sizeof title, "modulus factor E(0S2) / fitted E2 learned on the line, %zu strikes",
          n);
  af_plot_panel panel = af_plot_panel_empty();
  panel.title = title;
  panel.x_label = "strike (in recorded order)";
  panel.y_label = "modulus factor (dynamic / quasi-static) [-]";
  panel.series = ser;
  panel.n_series = 6;
  panel.y_rules = &start;
  panel.n_y_rules = 1;
  panel.x_min = 0.0;
  panel.x_max = (double)n + 1.0;
  panel.legend = AF_PLOT_LEGEND_BELOW;
  af_status st = draw_one(p, "modulus_factor.png", &panel, err, len);
  free(buf);
  return st;
}

af_status af_report_plots_session(af_report_plots *p, const af_session *s, const af_summary *m,
                                  char *err, size_t len)
{
  af_status st = plot_histogram(p, s, m, err, len);
  if (st == AF_OK)
    st = plot_stiffness(p, s, err, len);
  if (st == AF_OK)
    st = plot_band(p, s, err, len);
  if (st == AF_OK)
    st = plot_hammer(p, s, err, len);
  if (st == AF_OK)
    st = plot_factor(p, s, err, len);
  if (st == AF_OK && p->failed > 0) {
    af_text(err, len, "%zu of %zu strike figures could not be drawn, the first %s", p->failed,
            p->strikes, p->first_error);
    st = AF_EIO;
  }
  return st;
}
