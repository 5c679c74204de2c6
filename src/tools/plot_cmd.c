/* plot_cmd.c — `firmness_model plot`: one predicted strike as a figure
 * (src/plot/plot.h), three panels:
 *   the force pulse of the impact model;
 *   its spectrum in dB re its maximum, the lobes shaded in turn, the
 *   selected lobe's half-power band and level, the 0S2 of this apple's mass
 *   over the firmness range (--modulus-min .. --modulus-max) and at E2;
 *   the shear stress on the axis under the contact (Hertz, at the peak
 *   centre pressure) against the depth, with the yield stress and the
 *   criterion's tau_max. */
#include "plot_cmd.h"

#include <errno.h>
#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli_flags.h"
#include "impact.h"
#include "model.h"
#include "options.h"
#include "plot.h"
#include "lamb.h"
#include "settings.h"
#include "spectrum.h"
#include "text.h"

#ifndef M_PI /* strict C11 <math.h> does not define it */
#define M_PI 3.14159265358979323846
#endif

#define AF_PULSE_CAP 8192
#define AF_FREQS 800
#define AF_DEPTHS 300
#define AF_W_PX 1500
#define AF_H_PX 620

typedef struct {
  const char *out;
  double modulus_min_pa, modulus_max_pa;
} af_plot_args;

/* The defaults the parser starts from: the firmness range is the parameter
 * table's (modulus_min_pa, modulus_max_pa); --out is required. */
static af_plot_args plot_defaults(af_settings *s)
{
  af_settings_reset(s);
  af_plot_args a = {NULL, af_settings_number(s, AF_SETTING_MODULUS_MIN_PA),
                    af_settings_number(s, AF_SETTING_MODULUS_MAX_PA)};
  return a;
}

/* plot's own flags; the model flags are cli_flags.c's. */
static const af_option plot_options[] = {
    {"--out", "FILE", AF_OPTION_TEXT, offsetof(af_plot_args, out), -1, NULL,
     "the figure, FILE.png or FILE.svg", NULL, false},
    {"--modulus-min", "PA", AF_OPTION_NUMBER, offsetof(af_plot_args, modulus_min_pa),
     AF_SETTING_MODULUS_MIN_PA, NULL, "softest fruit of the 0S2 range drawn", NULL, false},
    {"--modulus-max", "PA", AF_OPTION_NUMBER, offsetof(af_plot_args, modulus_max_pa),
     AF_SETTING_MODULUS_MAX_PA, NULL, "firmest fruit of the 0S2 range drawn", NULL, false},
};
#define N_OPTIONS (sizeof plot_options / sizeof plot_options[0])

const af_option *af_plot_options(size_t *n)
{
  *n = N_OPTIONS;
  return plot_options;
}

static void plot_help(void)
{
  af_settings s;
  af_plot_args d = plot_defaults(&s);
  printf("usage: firmness_model plot [model flags] --out FILE.png|FILE.svg [--modulus-min PA]\n"
         "                           [--modulus-max PA]\n\n"
         "The predicted strike as a figure: the force pulse; its spectrum with the lobes, the\n"
         "band and the 0S2 over the firmness range; the shear on the axis against the yield.\n\n"
         "flags:\n");
  af_options_help(stdout, plot_options, N_OPTIONS, &d, &s);
  printf("\nmodel flags (SI units):\n");
  af_cli_print_flags();
  printf("\nexit status: 0 done, 1 model failure, 2 bad input\n");
}

static int print_usage(const char *fmt, const char *a, const char *b)
{
  fprintf(stderr, "firmness_model plot: ");
  fprintf(stderr, fmt, a, b);
  fputc('\n', stderr);
  return AF_CLI_EXIT_USAGE;
}

/* What the table cannot say: --out is required, the range not reversed. */
static int plot_check(const af_plot_args *a)
{
  if (!a->out)
    return print_usage("--out FILE.png|FILE.svg is required%s%s", "", "");
  if (!(a->modulus_max_pa > a->modulus_min_pa))
    return print_usage("--modulus-max must be above --modulus-min%s%s", "", "");
  return 0;
}

/* tau_1 / p0 on the axis of a Hertz contact at depth z / a (Johnson 3.45):
 * half the difference of the axial and radial stresses. */
static double axis_shear(double za, double nu)
{
  if (za <= 0.0)
    return 0.5 * fabs(-1.0 + 0.5 * (1.0 + 2.0 * nu));
  double sz = -1.0 / (1.0 + za * za);
  double sr = -((1.0 + nu) * (1.0 - za * atan(1.0 / za)) - 0.5 / (1.0 + za * za));
  return 0.5 * fabs(sz - sr);
}

typedef struct {
  double t_ms[AF_PULSE_CAP], f_n[AF_PULSE_CAP];
  double freq_hz[AF_FREQS], level_db[AF_FREQS];
  double depth_mm[AF_DEPTHS], shear_mpa[AF_DEPTHS];
  size_t n_pulse;
} af_curves;

static int draw(const af_plot_args *a, const af_model_params *p, const af_model_result *r,
                const af_curves *c, double level_db, double res_lo, double res_hi)
{
  /* band is pointed to by spans[] until the plot is drawn: not scoped to its if. */
  // cppcheck-suppress variableScope
  char t1[160], t2[160], t3[160], band[96], range[96], res[96], level[64], yield[64], tau[64];
  af_text(t1, sizeof t1, "impact: %.0f g at %.2f m/s on E#d2#u %.1f MPa, R#d2#u %.0f mm",
          p->impact.hammer_mass_kg * 1e3, p->impact.velocity_m_s, p->impact.fruit_modulus_pa * 1e-6,
          p->impact.strike_radius_m * 1e3);
  af_text(t2, sizeof t2, "lobe %u, %s: %s", p->lobe, af_band_level_name(p->band_level),
          r->excites_mode ? "0S2 in the band" : "0S2 NOT in the band");
  af_text(t3, sizeof t3, "shear on the axis: %s", r->no_damage ? "below the yield" : "BRUISE");
  af_plot_series pulse = {"force, contact time", c->t_ms,     c->f_n, c->n_pulse,
                          AF_PLOT_BLUE,          AF_PLOT_LINE};
  char pulse_label[96];
  af_text(pulse_label, sizeof pulse_label, "model pulse: t#dc#u %.3f ms, %.1f N, e %.2f",
          r->impact.contact_time_s * 1e3, r->impact.peak_force_n, p->impact.restitution);
  pulse.label = pulse_label;
  af_plot_panel pan[3] = {af_plot_panel_empty(), af_plot_panel_empty(), af_plot_panel_empty()};
  pan[0].title = t1;
  pan[0].x_label = "time [ms]";
  pan[0].y_label = "force [N]";
  pan[0].series = &pulse;
  pan[0].n_series = 1;
  pan[0].y_min = 0.0;
  /* Spectrum: lobes shaded in turn, then the band and the 0S2. */
  af_plot_span spans[AF_MODEL_MAX_LOBES + 2];
  size_t ns = 0;
  for (size_t k = 0; k < r->n_lobes; k++)
    spans[ns++] = (af_plot_span){k == 0   ? "lobes (odd)"
                                 : k == 1 ? "lobes (even)"
                                          : NULL,
                                 r->lobes[k].start_hz, r->lobes[k].end_hz,
                                 k % 2 ? AF_PLOT_LIGHT_GREEN : AF_PLOT_LIGHT_BLUE};
  if (r->band_found) {
    af_text(band, sizeof band, "half-power band %.0f-%.0f Hz", r->band.band_low_hz,
            r->band.band_high_hz);
    spans[ns++] =
        (af_plot_span){band, r->band.band_low_hz, r->band.band_high_hz, AF_PLOT_LIGHT_ORANGE};
  }
  af_text(range, sizeof range, "0S2 at %.0f g over %.0f-%.0f MPa", p->fruit_mass_kg * 1e3,
          a->modulus_min_pa * 1e-6, a->modulus_max_pa * 1e-6);
  spans[ns++] = (af_plot_span){range, res_lo, res_hi, AF_PLOT_LIGHT_PURPLE};
  af_plot_series spec = {"|F(f)| of the pulse", c->freq_hz,  c->level_db, AF_FREQS,
                         AF_PLOT_BLUE,          AF_PLOT_LINE};
  af_text(res, sizeof res, "0S2 at E#d2#u: %.0f Hz", r->resonance_hz);
  af_text(level, sizeof level, "%s level (%.1f dB)", af_band_level_name(p->band_level), level_db);
  af_plot_rule xr = {res, r->resonance_hz, AF_PLOT_RED, false};
  af_plot_rule yr = {level, level_db, AF_PLOT_ORANGE, true};
  pan[1].title = t2;
  pan[1].x_label = "frequency [Hz]";
  pan[1].y_label = "level [dB re max]";
  pan[1].series = &spec;
  pan[1].n_series = 1;
  pan[1].spans = spans;
  pan[1].n_spans = ns;
  pan[1].x_rules = &xr;
  pan[1].n_x_rules = 1;
  pan[1].y_rules = &yr;
  pan[1].n_y_rules = isfinite(level_db) ? 1 : 0;
  pan[1].x_min = 0.0;
  pan[1].x_max = c->freq_hz[AF_FREQS - 1];
  pan[1].y_min = -60.0;
  pan[1].y_max = 5.0;
  /* Shear. */
  af_plot_series shear = {"Hertz, at the peak centre pressure",
                          c->depth_mm,
                          c->shear_mpa,
                          AF_DEPTHS,
                          AF_PLOT_BLUE,
                          AF_PLOT_LINE};
  af_text(yield, sizeof yield, "yield %.3f MPa (%.3f E#d2#u)", r->yield_shear_stress_pa * 1e-6,
          p->yield_ratio);
  af_text(tau, sizeof tau, "criterion's #gt#dmax#u %.3f MPa (%s)", r->max_shear_stress_pa * 1e-6,
          af_shear_ratio_name(p->shear_ratio));
  af_plot_rule rules[2] = {{yield, r->yield_shear_stress_pa * 1e-6, AF_PLOT_RED, false},
                           {tau, r->max_shear_stress_pa * 1e-6, AF_PLOT_BLUE, true}};
  pan[2].title = t3;
  pan[2].x_label = "depth below the contact on its axis [mm]";
  pan[2].y_label = "shear stress #gt#d1#u [MPa]";
  pan[2].series = &shear;
  pan[2].n_series = 1;
  pan[2].y_rules = rules;
  pan[2].n_y_rules = 2;
  pan[2].y_min = 0.0;
  pan[0].legend = pan[1].legend = pan[2].legend = AF_PLOT_LEGEND_BELOW;
  af_plot_target t;
  char err[256];
  if (af_plot_target_file(a->out, AF_W_PX, AF_H_PX, &t) != AF_OK)
    return print_usage("--out %s: the file must end in .png or .svg%s", a->out, "");
  af_status st = af_plot_draw(&t, pan, 3, 1, err, sizeof err);
  if (st == AF_EIO)
    return print_usage("--out %s%s", err, "");
  if (st != AF_OK) {
    fprintf(stderr, "firmness_model plot: %s\n", err);
    return 1;
  }
  af_options_wrote(a->out);
  return 0;
}

/* Pulse, spectrum and shear curves of p; the 0S2 range [res_lo, res_hi]. */
static af_status curves_of(const af_model_params *p, const af_model_result *r,
                           const af_plot_args *a, af_curves *c, double *level_db, double *res_lo,
                           double *res_hi)
{
  af_impact *imp = NULL;
  af_spectrum *spec = NULL;
  af_impact_result ir;
  double xi;
  af_status st = af_lamb_root(p->impact.fruit_poisson, &xi);
  if (st == AF_OK)
    st = af_impact_create(&imp);
  double dt = af_impact_hertz_contact_time_s(&p->impact) / 500.0;
  if (st == AF_OK)
    st = af_impact_execute(imp, &p->impact, dt, c->f_n, NULL, AF_PULSE_CAP - 1, &ir);
  af_impact_destroy(imp);
  if (st != AF_OK)
    return st;
  c->n_pulse = ir.n_samples;
  for (size_t k = 0; k < c->n_pulse; k++)
    c->t_ms[k] = (double)k * dt * 1e3;
  c->t_ms[c->n_pulse] = ir.contact_time_s * 1e3;
  c->f_n[c->n_pulse++] = 0.0;
  af_spectrum_config sc = af_spectrum_config_default();
  sc.max_samples = AF_PULSE_CAP;
  sc.fft_size = 4 * AF_PULSE_CAP;
  if ((st = af_spectrum_create(&sc, &spec)) == AF_OK)
    st = af_spectrum_execute(spec, c->f_n, c->n_pulse, dt);
  *res_lo = af_lamb_frequency_hz(xi, p->modulus_factor * a->modulus_min_pa, p->impact.fruit_poisson,
                                 p->fruit_density_kg_m3, p->fruit_mass_kg);
  *res_hi = af_lamb_frequency_hz(xi, p->modulus_factor * a->modulus_max_pa, p->impact.fruit_poisson,
                                 p->fruit_density_kg_m3, p->fruit_mass_kg);
  double f_max =
      fmax(1.3 * *res_hi, r->n_lobes >= 3 ? r->lobes[2].end_hz : 3.0 / ir.contact_time_s);
  for (size_t k = 0; k < AF_FREQS && st == AF_OK; k++) {
    c->freq_hz[k] = f_max * (double)k / (AF_FREQS - 1);
    c->level_db[k] = fmax(af_spectrum_level_db(spec, c->freq_hz[k]), -60.0);
  }
  *level_db = r->band_found
                  ? 20.0 * log10(r->band.peak_magnitude_n_s * af_band_level_ratio(p->band_level) /
                                 af_spectrum_max_magnitude(spec))
                  : NAN;
  af_spectrum_destroy(spec);
  /* The shear profile at the peak centre pressure p0: a = sqrt(3 F / (2 pi p0)). */
  double p0 = r->max_contact_pressure_pa, a_m = sqrt(3.0 * ir.peak_force_n / (2.0 * M_PI * p0));
  for (size_t k = 0; k < AF_DEPTHS; k++) {
    double za = 3.0 * (double)k / (AF_DEPTHS - 1);
    c->depth_mm[k] = za * a_m * 1e3;
    c->shear_mpa[k] = p0 * axis_shear(za, p->impact.fruit_poisson) * 1e-6;
  }
  return st;
}

int af_plot_main(int argc, char **argv, int first)
{
  if (af_options_want_help(argc, argv, first)) {
    plot_help();
    return 0;
  }
  af_model_params p;
  af_settings s;
  af_plot_args a = plot_defaults(&s);
  const af_option_set own = {plot_options, N_OPTIONS, &a, NULL, NULL};
  if (!af_cli_parse_model("firmness_model plot", &own, NULL, argc, argv, first, &p))
    return AF_CLI_EXIT_USAGE;
  int code = plot_check(&a);
  if (code)
    return code;
  static af_curves c; /* large: not on the stack */
  af_model *m = NULL;
  af_model_result r;
  af_status st = af_model_create(&m);
  if (st == AF_OK)
    st = af_model_execute(m, &p, &r);
  af_model_destroy(m);
  double level_db = NAN, lo = NAN, hi = NAN;
  if (st == AF_OK)
    st = curves_of(&p, &r, &a, &c, &level_db, &lo, &hi);
  if (st != AF_OK) {
    fprintf(stderr, "firmness_model plot: the model failed on this strike: %s\n", af_strerror(st));
    return 1;
  }
  return draw(&a, &p, &r, &c, level_db, lo, hi);
}
