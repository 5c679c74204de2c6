/* paper_figures.c — `firmness_model paper`'s figures: Figs. 2, 4, 6, 8 (a
 * family of pulses and their spectra for E2, R2, e, nu2 varied) and Figs.
 * 3, 5, 7 (the selected lobe's band against the 0S2 of 100 g and 250 g
 * fruit, and the shear against the yield), each as PNG and SVG. */
#define _POSIX_C_SOURCE 200809L
#include "paper.h"

#include <errno.h>
#include <math.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "cli_flags.h"
#include "closeout.h"
#include "design.h"
#include "impact.h"
#include "model.h"
#include "model_table.h"
#include "options.h"
#include "plot.h"
#include "lamb.h"
#include "spectrum.h"
#include "text.h"
#include "paper_work.h"

/* ---- Figs. 2, 4, 6, 8: a family of pulses and their spectra ------------- */

typedef struct {
  double t_ms[AF_PAPER_PULSE_CAP], f_n[AF_PAPER_PULSE_CAP];
  double mag[AF_PAPER_FREQS], db[AF_PAPER_FREQS];
  size_t n;
  char label[160];
} af_curve;

static double freqs_hz[AF_PAPER_FREQS];

/* Pulse of p into c (time in ms, force in N, closed by F = 0 at t_c). */
static af_status pulse_of(af_paper *w, const af_model_params *p, af_curve *c, double *tc_s,
                          double *dt_s)
{
  af_impact_result ir;
  double dt = af_impact_hertz_contact_time_s(&p->impact) / 400.0;
  af_status st =
      af_impact_execute(w->impact, &p->impact, dt, c->f_n, NULL, AF_PAPER_PULSE_CAP - 1, &ir);
  if (st != AF_OK)
    return st;
  c->n = ir.n_samples;
  for (size_t k = 0; k < c->n; k++)
    c->t_ms[k] = (double)k * dt * 1e3;
  c->t_ms[c->n] = ir.contact_time_s * 1e3;
  c->f_n[c->n++] = 0.0;
  *tc_s = ir.contact_time_s;
  *dt_s = dt;
  return AF_OK;
}

void af_paper_vary_e2(af_model_params *p, double v)
{
  p->impact.fruit_modulus_pa = v;
}
void af_paper_vary_r2(af_model_params *p, double v)
{
  p->impact.strike_radius_m = v;
}
void af_paper_vary_e(af_model_params *p, double v)
{
  p->impact.restitution = v;
}
void af_paper_vary_nu(af_model_params *p, double v)
{
  p->impact.fruit_poisson = v;
}

static int draw(const af_paper *w, int fig, int prof, const af_plot_panel *pan, int nx)
{
  static const char *const ext[2] = {"png", "svg"};
  for (int k = 0; k < 2; k++) {
    char path[640], err[256];
    af_plot_target t;
    af_text(path, sizeof path, "%s/fig%d_%s.%s", w->fig_dir, fig, af_paper_profile_key[prof],
            ext[k]);
    if (af_plot_target_file(path, AF_PAPER_W_PX, AF_PAPER_H_PX, &t) != AF_OK ||
        af_plot_draw(&t, pan, nx, 1, err, sizeof err) != AF_OK) {
      fprintf(stderr, "firmness_model paper: cannot draw %s\n", path);
      return 1;
    }
    af_options_wrote(path);
  }
  return 0;
}

static const af_plot_colour family_colour[AF_PAPER_FAMILY] = {
    AF_PLOT_BLUE, AF_PLOT_ORANGE, AF_PLOT_GREEN, AF_PLOT_RED, AF_PLOT_PURPLE, AF_PLOT_BLACK};

int af_paper_family_figure(af_paper *w, int prof, const af_family *fam)
{
  static af_curve c[AF_PAPER_FAMILY];
  af_plot_series pulse[AF_PAPER_FAMILY], spec[AF_PAPER_FAMILY];
  double tc_min = INFINITY, ref = 0.0;
  double tc[AF_PAPER_FAMILY];
  af_model_result r[AF_PAPER_FAMILY];
  for (size_t i = 0; i < fam->n; i++) {
    af_model_params p = af_paper_profile(prof);
    fam->vary(&p, fam->values[i]);
    double dt;
    af_status st = pulse_of(w, &p, &c[i], &tc[i], &dt);
    if (st == AF_OK)
      st = af_paper_eval(w, &p, &r[i]);
    if (st != AF_OK) {
      fprintf(stderr, "firmness_model paper: Fig. %d: the model failed: %s\n", fam->number,
              af_strerror(st));
      return 1;
    }
    tc_min = fmin(tc_min, tc[i]);
  }
  double f_max = 4.0 / tc_min;
  for (size_t k = 0; k < AF_PAPER_FREQS; k++)
    freqs_hz[k] = f_max * (double)k / (AF_PAPER_FREQS - 1);
  for (size_t i = 0; i < fam->n; i++) {
    af_model_params p = af_paper_profile(prof);
    fam->vary(&p, fam->values[i]);
    double dt = af_impact_hertz_contact_time_s(&p.impact) / 400.0;
    if (af_spectrum_execute(w->spectrum, c[i].f_n, c[i].n, dt) != AF_OK)
      return 1;
    for (size_t k = 0; k < AF_PAPER_FREQS; k++) {
      c[i].mag[k] = af_spectrum_magnitude(w->spectrum, freqs_hz[k]);
      ref = fmax(ref, c[i].mag[k]);
    }
    char value[64];
    af_text(value, sizeof value, fam->unit_fmt, fam->values[i] * fam->scale);
    af_text(c[i].label, sizeof c[i].label, "%s: t#dc#u %.2f ms, %.1f N", value, tc[i] * 1e3,
            r[i].impact.peak_force_n);
    pulse[i] =
        (af_plot_series){c[i].label, c[i].t_ms, c[i].f_n, c[i].n, family_colour[i], AF_PLOT_LINE};
    spec[i] =
        (af_plot_series){NULL, freqs_hz, c[i].db, AF_PAPER_FREQS, family_colour[i], AF_PLOT_LINE};
  }
  for (size_t i = 0; i < fam->n; i++)
    for (size_t k = 0; k < AF_PAPER_FREQS; k++)
      c[i].db[k] = fmax(20.0 * log10(c[i].mag[k] / ref), -60.0);
  /* The spectrum's legend names the curves by value only (the pulse's says more). */
  static char spec_label[AF_PAPER_FAMILY][64];
  for (size_t i = 0; i < fam->n; i++) {
    af_text(spec_label[i], sizeof spec_label[i], fam->unit_fmt, fam->values[i] * fam->scale);
    spec[i].label = spec_label[i];
  }
  char ta[200], tb[200], sub[200];
  af_model_params p0 = af_paper_profile(prof);
  af_text(ta, sizeof ta, "Fig. %d(a) analogue: influence of %s on the pulse", fam->number,
          fam->property);
  af_text(tb, sizeof tb, "Fig. %d(b) analogue: its spectrum (%s profile)", fam->number,
          af_paper_profile_title[prof]);
  char strike_text[160];
  af_paper_subtitle(strike_text, sizeof strike_text, &p0, ", ");
  af_text(sub, sizeof sub, "%s; %s damping", strike_text, af_damping_law_name(p0.impact.damping));
  af_plot_panel pan[2] = {af_plot_panel_empty(), af_plot_panel_empty()};
  pan[0].title = ta;
  pan[0].subtitle = sub;
  pan[0].x_label = "time [ms]";
  pan[0].y_label = "impact force [N]";
  pan[0].series = pulse;
  pan[0].n_series = fam->n;
  pan[0].y_min = 0.0;
  pan[0].x_min = 0.0;
  pan[1].title = tb;
  pan[1].subtitle = "|F(f)| in dB re the largest of the family";
  pan[1].x_label = "frequency [Hz]";
  pan[1].y_label = "|F(f)| [dB]";
  pan[1].series = spec;
  pan[1].n_series = fam->n;
  pan[1].x_min = 0.0;
  pan[1].x_max = f_max;
  pan[1].y_min = -60.0;
  pan[1].y_max = 5.0;
  pan[0].legend = pan[1].legend = AF_PLOT_LEGEND_BELOW;
  return draw(w, fam->number, prof, pan, 2);
}

/* ---- Figs. 3, 5, 7: the band against the 0S2 lines, shear against yield -- */

typedef struct {
  double x[AF_PAPER_SWEEP], lo[AF_PAPER_SWEEP], hi[AF_PAPER_SWEEP];
  double f100[AF_PAPER_SWEEP], f250[AF_PAPER_SWEEP];
  double shear[AF_PAPER_SWEEP], yield[AF_PAPER_SWEEP];
} af_sweep_curves;

int af_paper_sweep_figure(af_paper *w, int prof, const af_sweep_fig *sf)
{
  static af_sweep_curves s;
  size_t n = w->quick ? 11 : AF_PAPER_SWEEP;
  for (size_t i = 0; i < n; i++) {
    double v = sf->from + (sf->to - sf->from) * (double)i / (double)(n - 1);
    af_model_params p = af_paper_profile(prof);
    af_model_result r;
    sf->vary(&p, v);
    af_status st = af_paper_eval(w, &p, &r);
    if (st != AF_OK) {
      fprintf(stderr, "firmness_model paper: Fig. %d: the model failed at %g: %s\n", sf->number, v,
              af_strerror(st));
      return 1;
    }
    s.x[i] = v * sf->scale;
    s.lo[i] = r.band_found ? r.band.band_low_hz : NAN;
    s.hi[i] = r.band_found ? r.band.band_high_hz : NAN;
    s.f100[i] = af_paper_resonance_hz(&p, 0.100);
    s.f250[i] = af_paper_resonance_hz(&p, 0.250);
    s.shear[i] = r.max_shear_stress_pa * 1e-6;
    s.yield[i] = r.yield_shear_stress_pa * 1e-6;
  }
  af_model_params p0 = af_paper_profile(prof);
  char band_label[128], ta[160], tb[160];
  af_text(band_label, sizeof band_label, "lobe %u %s band: low edge", p0.lobe,
          af_band_level_name(p0.band_level));
  af_plot_series a[4] = {
      {band_label, s.x, s.lo, n, AF_PLOT_BLUE, AF_PLOT_LINE},
      {"band: high edge", s.x, s.hi, n, AF_PLOT_GREEN, AF_PLOT_LINE},
      {"0S2 of a 100 g apple", s.x, s.f100, n, AF_PLOT_RED, AF_PLOT_DASHED},
      {"0S2 of a 250 g apple", s.x, s.f250, n, AF_PLOT_PURPLE, AF_PLOT_DASHED},
  };
  af_plot_series b[2] = {
      {"max shear stress in the impact", s.x, s.shear, n, AF_PLOT_BLUE, AF_PLOT_LINE},
      {"yield shear stress (the law)", s.x, s.yield, n, AF_PLOT_RED, AF_PLOT_DASHED},
  };
  af_text(ta, sizeof ta, "Fig. %d(a) analogue: %s vs the half-power range (%s)", sf->number,
          sf->property, af_paper_profile_title[prof]);
  af_text(tb, sizeof tb, "Fig. %d(b) analogue: %s vs the shear stress", sf->number, sf->property);
  af_plot_panel pan[2] = {af_plot_panel_empty(), af_plot_panel_empty()};
  pan[0].title = ta;
  char sub[160];
  const af_model_params nominal = af_paper_profile(prof);
  af_paper_subtitle(sub, sizeof sub, &nominal, " at ");
  pan[0].subtitle = sub;
  pan[0].x_label = sf->x_label;
  pan[0].y_label = "frequency [Hz]";
  pan[0].series = a;
  pan[0].n_series = 4;
  pan[0].y_min = 0.0;
  pan[1].title = tb;
  pan[1].subtitle = "damage when the shear passes the yield";
  pan[1].x_label = sf->x_label;
  pan[1].y_label = "shear stress [MPa]";
  pan[1].series = b;
  pan[1].n_series = 2;
  pan[1].y_min = 0.0;
  pan[0].legend = pan[1].legend = AF_PLOT_LEGEND_BELOW;
  return draw(w, sf->number, prof, pan, 2);
}
