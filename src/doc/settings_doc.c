/* settings_doc — prints, from the one parameter table (src/core/params/settings_table.c),
 * the parameter reference of doc/parameters.md and the two shipped YAML
 * files, so that no default, range or unit is typed a second time:
 *
 *   settings_doc                  the generated part of doc/parameters.md, markdown
 *   settings_doc --yaml station   config/station.yaml
 *   settings_doc --yaml cultivar  config/jonagold.yaml, the cultivar template
 *
 * Markdown: two lists, the rows of config/station.yaml and those of the
 * cultivar's YAML, each row as af_settings_print writes it:
 * "- **name** (kind, default, range, unit): help."
 * YAML: a fixed preamble (below), then one `key: default  # range: help`
 * line per row in the table's order, under the section titles of
 * station_sections / cultivar_sections (each opened by its first key); an
 * optional row (absent by default) is a commented line with the shipped
 * rig's value. The defaults are the table's text as it is (YAML 1.1:
 * 8.0e+6, never 8.0e6). The cultivar template holds the table's defaults:
 * they are Jonagold's (no override).
 * test/scripts/test_doc_parameters.sh checks that doc/parameters.md (between
 * its "generated" markers) and both YAML files hold exactly this; `bash
 * scripts/docs.sh` rewrites them. Installed with the package (`rosrun
 * acoustic_firmness af_settings_doc`). Exit 0; 2 on a bad argument; 1 when
 * stdout cannot be written or the table's grades cannot be read. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "closeout.h"
#include "grade.h"
#include "lamb.h"
#include "settings.h"

/* Column of the '#' of a row's comment (key: value padded to it). */
#define COMMENT_COLUMN 40

/* A section of a YAML file: its title, opened before the row named first;
 * note: comment lines printed under the title (NULL: none). */
typedef struct {
  const char *first, *title, *note;
} section;

static const section station_sections[] = {
    {"hammer_link", "the hammer: from the rig's URDF", NULL},
    {"strike_velocity_m_s", "the strike", NULL},
    {"latitude_tolerance_deg", "strike advice", NULL},
    {"force_sample_rate_hz", "force and audio streams", NULL},
    {"markers_enabled", "rviz markers (topic markers)", NULL},
    {"strike_plot_width_px", "the live strike picture (topic strike_plot, sensor_msgs/Image rgb8)",
     NULL},
    {"strike_full_scale_n", "measured strikes: the detector on the force stream", NULL},
    {"measure_fit_velocity", "measured strikes: the measurement", NULL},
    {"modulus_factor_learn_window",
     "the modulus factor learned on the line (src/core/lane/factor_learn.h)",
     "# The median of E(0S2) / fitted E2 x the factor in use over the newest\n"
     "# reliable strikes, with its 95 % interval, in /diagnostics and the report.\n"},
};

static const section cultivar_sections[] = {
    {"cultivar", "the cultivar", NULL},
    {"grade_quantity", "firmness grades for the sorter (src/core/lane/grade.h)",
     "# Each measured strike's class, published with its StrikeReport. Class names\n"
     "# from the softest up, the boundary between neighbours between them, in\n"
     "# grade_quantity's unit; a value on a boundary belongs to the class above;\n"
     "# \"\" = no grading.\n"},
};

static const char station_preamble[] =
    "# firmness_node — station defaults (one lane). Loaded into the node's private\n"
    "# namespace by launch/station.launch; read by `firmness_model analyze` too.\n"
    "# The node refuses to start when one of these is missing or out of range,\n"
    "# naming it.\n";

static const char cultivar_preamble[] =
    "# Cultivar: Jonagold. Loaded into the node's private namespace after\n"
    "# config/station.yaml; read by `firmness_model analyze` too. Firmness as the\n"
    "# quasi-static Young's modulus of the flesh; the model is evaluated at the\n"
    "# nominal value, the resonance band over [modulus_min_pa, modulus_max_pa].\n"
    "# A template for other cultivars: copy it and change the values.\n";

/* Said in both files, after their own preamble. */
static const char common_preamble[] =
    "# GENERATED from the one parameter table (src/core/params/settings_table.c) by\n"
    "# af_settings_doc. Do not edit: change the table and run `bash scripts/docs.sh`\n"
    "# (scripts_doc_parameters fails when this file differs). Each comment: the\n"
    "# accepted range and its unit (none: dimensionless) or the accepted words,\n"
    "# then the table's help. Write exponents with a dot and a sign (8.0e+6):\n"
    "# YAML 1.1 reads 8.0e6 as text.\n";

/* Note before the first optional row (the URDF's overrides). */
static const char optional_note[] =
    "# Optional overrides of the URDF (uncomment to use). With both "
    "given, the node\n# also runs without any URDF (the strike "
    "direction is then unknown).\n";

/* The accepted values of a row, as its comment starts: "[0.05, 10] m/s",
 * "paper | exact | hu-guo", "true | false", "text of at most 63 characters". */
static void accepted(af_setting_id id, const af_setting_def *d, char *buf, size_t len)
{
  buf[0] = '\0';
  if (d->range) {
    snprintf(buf, len, "%s", d->range);
  } else if (d->kind == AF_SETTING_CHOICE) {
    char w[64];
    for (size_t i = 0; af_setting_choice_word(id, i, w, sizeof w) == AF_OK; i++)
      snprintf(buf + strlen(buf), len - strlen(buf), "%s%s", i ? " | " : "", w);
  } else if (d->kind == AF_SETTING_BOOL) {
    snprintf(buf, len, "true | false");
  } else {
    snprintf(buf, len, "text of at most %zu characters", d->max_chars);
  }
}

static const section *section_of(const section *secs, size_t n, const char *name)
{
  for (size_t k = 0; k < n; k++)
    if (strcmp(secs[k].first, name) == 0)
      return &secs[k];
  return NULL;
}

/* One row: `key: default  # accepted: help`; an optional row commented out,
 * with the shipped rig's value. */
static void yaml_row(FILE *out, af_setting_id id, const af_setting_def *d)
{
  char line[1024], acc[256];
  if (d->optional)
    snprintf(line, sizeof line, "# %s: %s", d->name, d->rig ? d->rig : "0");
  else
    snprintf(line, sizeof line, "%s: %s", d->name, d->def);
  accepted(id, d, acc, sizeof acc);
  fprintf(out, "%-*s # %s: %s", COMMENT_COLUMN - 1, line, acc, d->help);
  if (d->optional)
    fprintf(out, "; %sabsent = %s", d->zero_is_absent ? "0 or " : "", d->absent);
  fputc('\n', out);
}

/* The stiffness factor f^2 m^(2/3) [Hz^2 kg^(2/3)] of a sphere of the
 * table's density, Poisson ratio and modulus factor, per Pa of E2 (it does
 * not depend on the mass); NAN when Lamb's root cannot be found. */
static double stiffness_factor_per_pa(void)
{
  af_settings s;
  af_settings_reset(&s);
  double nu = af_settings_number(&s, AF_SETTING_FRUIT_POISSON);
  double rho = af_settings_number(&s, AF_SETTING_DENSITY_KG_M3);
  double factor = af_settings_number(&s, AF_SETTING_MODULUS_FACTOR);
  double xi, m = 1.0, e2 = 1e6;
  if (af_lamb_root(nu, &xi) != AF_OK)
    return NAN;
  double f = af_lamb_frequency_hz(xi, factor * e2, nu, rho, m);
  return f * f * pow(m, 2.0 / 3.0) / e2;
}

/* The default grades in MPa of E2: computed from the table, not typed. */
static int grades_note(FILE *out)
{
  af_settings s;
  af_grade_config g;
  char err[256];
  af_settings_reset(&s);
  if (af_grade_config_from_settings(&s, &g, err, sizeof err) != AF_OK) {
    fprintf(stderr, "settings_doc: %s\n", err);
    return 1;
  }
  double k = stiffness_factor_per_pa();
  if (g.quantity != AF_GRADE_BY_STIFFNESS_FACTOR || g.n_classes < 2 || !isfinite(k))
    return 0;
  fprintf(out,
          "# The stiffness factor f^2 m^(2/3) [Hz^2 kg^(2/3)] of a sphere of this\n"
          "# density, Poisson ratio and modulus factor is %.3g per MPa of E2: these\n"
          "# boundaries lie at about",
          k * 1e6);
  for (size_t c = 1; c < g.n_classes; c++)
    fprintf(out, "%s %.2g",
            c == 1                 ? ""
            : c + 1 == g.n_classes ? " and"
                                   : ",",
            g.lower[c] / k * 1e-6);
  fputs(" MPa.\n", out);
  return 0;
}

static int print_yaml(FILE *out, unsigned file)
{
  bool station = file == AF_SETTINGS_STATION;
  const section *secs = station ? station_sections : cultivar_sections;
  size_t n_secs = station ? sizeof station_sections / sizeof *station_sections
                          : sizeof cultivar_sections / sizeof *cultivar_sections;
  fputs(station ? station_preamble : cultivar_preamble, out);
  fputs(common_preamble, out);
  bool optional_seen = false;
  for (int k = 0; k < AF_SETTING_COUNT; k++) {
    const af_setting_def *d = af_setting_def_of((af_setting_id)k);
    if (d == NULL || d->file != file)
      continue;
    const section *sec = section_of(secs, n_secs, d->name);
    if (sec) {
      fprintf(out, "\n# --- %s ", sec->title);
      for (size_t c = strlen(sec->title); c < 72; c++)
        fputc('-', out);
      fputc('\n', out);
      if (sec->note)
        fputs(sec->note, out);
      if (sec->first == cultivar_sections[1].first && grades_note(out) != 0)
        return 1;
    }
    if (d->optional && !optional_seen)
      fputs(optional_note, out);
    optional_seen = optional_seen || d->optional;
    yaml_row(out, (af_setting_id)k, d);
  }
  return 0;
}

int main(int argc, char **argv)
{
  af_closeout_install("af_settings_doc");
  int st = 0;
  if (argc == 1) {
    puts("### config/station.yaml (the station: rig, strike, streams, detector, measurement)\n");
    af_settings_print(stdout, AF_SETTINGS_STATION, AF_SETTINGS_PRINT_MARKDOWN);
    puts("\n### The cultivar's YAML (config/jonagold.yaml)\n");
    af_settings_print(stdout, AF_SETTINGS_CULTIVAR, AF_SETTINGS_PRINT_MARKDOWN);
  } else if (argc == 3 && strcmp(argv[1], "--yaml") == 0 &&
             (strcmp(argv[2], "station") == 0 || strcmp(argv[2], "cultivar") == 0)) {
    st = print_yaml(stdout, argv[2][0] == 's' ? AF_SETTINGS_STATION : AF_SETTINGS_CULTIVAR);
  } else {
    fprintf(stderr, "settings_doc: usage: af_settings_doc [--yaml station|cultivar]\n");
    return 2;
  }
  if (st != 0)
    return st;
  return fflush(stdout) == 0 && !ferror(stdout) ? 0 : 1;
}
