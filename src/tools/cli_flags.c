/* cli_flags.c — the flag table of firmness_model and its parser. */
#include "cli_flags.h"

#include <errno.h>
#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "model_table.h"

#define AF_DOUBLE_FLAG(name, field, help)                                                          \
  {                                                                                                \
    name, #field, AF_FLAG_DOUBLE, offsetof(af_model_params, field), help                           \
  }
#define AF_CHOICE_FLAG(name, field, kind, help)                                                    \
  {                                                                                                \
    name, field, kind, 0, help                                                                     \
  }

static const af_cli_flag flags[] = {
    AF_DOUBLE_FLAG("E2", impact.fruit_modulus_pa, "fruit elastic modulus [Pa]"),
    AF_DOUBLE_FLAG("nu2", impact.fruit_poisson, "fruit Poisson ratio [-]"),
    AF_DOUBLE_FLAG("R2", impact.strike_radius_m, "local radius of curvature under the hammer [m]"),
    AF_DOUBLE_FLAG("e", impact.restitution, "coefficient of restitution [-]"),
    AF_DOUBLE_FLAG("mass", fruit_mass_kg, "fruit mass [kg]"),
    AF_DOUBLE_FLAG("density", fruit_density_kg_m3, "fruit density [kg/m3]"),
    AF_DOUBLE_FLAG("hammer-mass", impact.hammer_mass_kg, "hammer mass [kg]"),
    AF_DOUBLE_FLAG("v0", impact.velocity_m_s, "contact velocity [m/s]"),
    AF_DOUBLE_FLAG("hammer-E", impact.hammer_modulus_pa, "hammer tip modulus [Pa], 0 = rigid"),
    AF_DOUBLE_FLAG("hammer-nu", impact.hammer_poisson, "hammer tip Poisson ratio [-]"),
    AF_DOUBLE_FLAG("hammer-radius", impact.hammer_radius_m, "hammer tip radius [m], 0 = flat"),
    AF_DOUBLE_FLAG("gravity", impact.gravity_m_s2, "gravity along the strike [m/s2]"),
    AF_CHOICE_FLAG("damping", "impact.damping", AF_FLAG_DAMPING,
                   "damping law: paper | exact | hu-guo"),
    AF_CHOICE_FLAG("lobe", "lobe", AF_FLAG_LOBE,
                   "spectral lobe of the criterion [-], 1 = main lobe"),
    AF_CHOICE_FLAG("band-level", "band_level", AF_FLAG_BAND,
                   "half-power reading: power-half | amplitude-half"),
    AF_CHOICE_FLAG("shear-ratio", "shear_ratio", AF_FLAG_SHEAR,
                   "tau_max/p0: paper (0.31) | exact (for nu2)"),
    AF_DOUBLE_FLAG("yield-ratio", yield_ratio, "yield law tau_y / E2 at E_ref [-] (calibration)"),
    AF_DOUBLE_FLAG("yield-exponent", yield_exponent,
                   "yield law exponent p, tau_y ~ E2^p [-] (1 = ratio law)"),
    AF_DOUBLE_FLAG("yield-reference-modulus", yield_reference_modulus_pa,
                   "yield law reference modulus E_ref [Pa]"),
    AF_DOUBLE_FLAG("modulus-factor", modulus_factor, "dynamic / quasi-static modulus [-]"),
};
#define N_FLAGS (sizeof flags / sizeof flags[0])

/* The double fields are reached by offset; memcpy keeps that free of
 * pointer casts between unrelated types. */
static void set_double(const af_cli_flag *f, af_model_params *p, double v)
{
  memcpy((char *)p + f->offset, &v, sizeof v);
}

static double get_double(const af_cli_flag *f, const af_model_params *p)
{
  double v;
  memcpy(&v, (const char *)p + f->offset, sizeof v);
  return v;
}

const af_cli_flag *af_cli_flag_find(const char *name)
{
  if (strncmp(name, "--", 2) == 0)
    name += 2;
  for (size_t k = 0; k < N_FLAGS; k++)
    if (strcmp(flags[k].name, name) == 0)
      return &flags[k];
  return NULL;
}

static bool parse_number(const char *text, double *out)
{
  char *end;
  errno = 0;
  *out = strtod(text, &end);
  return end != text && *end == '\0' && errno != ERANGE;
}

bool af_cli_flag_set(const af_cli_flag *f, const char *text, af_model_params *p)
{
  double v;
  af_status st = AF_OK;
  switch (f->kind) {
  case AF_FLAG_DOUBLE:
    if (!parse_number(text, &v)) {
      fprintf(stderr, "firmness_model: --%s '%s' is not a number\n", f->name, text);
      return false;
    }
    set_double(f, p, v);
    return true;
  case AF_FLAG_LOBE:
    if (!parse_number(text, &v) || v != floor(v) || v < 1 || v > AF_MODEL_MAX_LOBES) {
      fprintf(stderr, "firmness_model: --lobe '%s' must be a whole number in 1 .. %d\n", text,
              AF_MODEL_MAX_LOBES);
      return false;
    }
    p->lobe = (unsigned)v;
    return true;
  case AF_FLAG_DAMPING: st = af_damping_law_parse(text, &p->impact.damping); break;
  case AF_FLAG_BAND: st = af_band_level_parse(text, &p->band_level); break;
  case AF_FLAG_SHEAR: st = af_shear_ratio_parse(text, &p->shear_ratio); break;
  }
  if (st != AF_OK)
    fprintf(stderr, "firmness_model: --%s '%s' must be one of: %s\n", f->name, text,
            strchr(f->help, ':') + 2);
  return st == AF_OK;
}

double af_cli_flag_get(const af_cli_flag *f, const af_model_params *p)
{
  switch (f->kind) {
  case AF_FLAG_DOUBLE: return get_double(f, p);
  case AF_FLAG_LOBE: return p->lobe;
  case AF_FLAG_DAMPING: return p->impact.damping;
  case AF_FLAG_BAND: return p->band_level;
  case AF_FLAG_SHEAR: return p->shear_ratio;
  }
  return NAN;
}

/* The starting values: the parameter table's defaults (af_model_params_table:
 * what the node and firmness_report derive, with model.c's example apple). */
static bool table_params(af_model_params *p)
{
  char err[512];
  if (af_model_params_table(p, err, sizeof err) == AF_OK)
    return true;
  fprintf(stderr, "firmness_model: the parameter table's defaults: %s\n", err);
  return false;
}

/* --profile default|paper, looked for first so that later flags override it. */
static bool apply_profile(int argc, char **argv, int first, af_model_params *p)
{
  if (!table_params(p))
    return false;
  for (int k = first; k < argc; k++) {
    if (strcmp(argv[k], "--profile") != 0)
      continue;
    const char *v = k + 1 < argc ? argv[k + 1] : "";
    if (strcmp(v, "paper") == 0)
      *p = af_model_params_paper_of(p);
    else if (strcmp(v, "default") != 0) {
      fprintf(stderr, "firmness_model: --profile '%s' must be one of: default | paper\n", v);
      return false;
    }
  }
  return true;
}

static const af_cli_flag *flag_of_field(const char *field)
{
  for (size_t k = 0; k < N_FLAGS; k++)
    if (strcmp(flags[k].field, field) == 0)
      return &flags[k];
  return NULL;
}

void af_cli_number_text(double v, char *buf, size_t len)
{
  /* The fewest digits that read back as v: 1e9 + 1 shows as 1000000001, never
   * as %g's 1e+09, which would look inside a range that ends at 1e9. */
  if (v == floor(v) && fabs(v) < 1e15) { /* a whole number: every digit, no exponent */
    snprintf(buf, len, "%.0f", v);
    return;
  }
  for (int digits = 1; digits <= 17; digits++) {
    snprintf(buf, len, "%.*g", digits, v);
    if (strtod(buf, NULL) == v)
      return;
  }
}

bool af_cli_validate(const af_model_params *p, const char *tool)
{
  af_param_error err;
  if (af_model_params_check(p, &err) == AF_OK)
    return true;
  const af_cli_flag *f = flag_of_field(err.field);
  char value[32];
  af_cli_number_text(err.value, value, sizeof value);
  fprintf(stderr, "%s: --%s %s is outside the accepted range %s\n", tool, f ? f->name : err.field,
          value, err.range);
  return false;
}

/* A model flag (or --profile) given twice: refused, since which one wins
 * would be a silent choice. */
static bool once(int argc, char **argv, int first, int k)
{
  for (int j = first; j < k; j++) {
    if (strcmp(argv[j], argv[k]) != 0)
      continue;
    fprintf(stderr,
            "firmness_model: %s is given twice (arguments %d and %d: '%.40s' and '%.40s'); "
            "a model flag is accepted once\n",
            argv[k], j - first + 1, k - first + 1, j + 1 < argc ? argv[j + 1] : "",
            k + 1 < argc ? argv[k + 1] : "");
    return false;
  }
  return true;
}

bool af_cli_parse_model(int argc, char **argv, int first, af_model_params *p, int *rest,
                        int *n_rest)
{
  if (n_rest)
    *n_rest = 0;
  if (!apply_profile(argc, argv, first, p))
    return false;
  for (int k = first; k < argc; k++) {
    if (strcmp(argv[k], "--profile") == 0) {
      if (!once(argc, argv, first, k))
        return false;
      k++;
      continue;
    }
    const af_cli_flag *f = strncmp(argv[k], "--", 2) == 0 ? af_cli_flag_find(argv[k]) : NULL;
    if (f != NULL && !once(argc, argv, first, k))
      return false;
    if (f == NULL) {
      if (rest == NULL) {
        char names[1024];
        af_cli_flag_names(names, sizeof names);
        fprintf(stderr,
                "firmness_model: unknown flag or subcommand '%s'; accepted: %s, --json, "
                "or a subcommand first (firmness_model --help: units and defaults)\n",
                argv[k], names);
        return false;
      }
      rest[(*n_rest)++] = k;
      continue;
    }
    if (k + 1 >= argc) {
      fprintf(stderr, "firmness_model: --%s needs a value: %s\n", f->name, f->help);
      return false;
    }
    if (!af_cli_flag_set(f, argv[++k], p))
      return false;
  }
  return af_cli_validate(p, "firmness_model");
}

void af_cli_flag_names(char *buf, size_t len)
{
  size_t used = (size_t)snprintf(buf, len, "the model flags");
  for (size_t k = 0; k < N_FLAGS && used < len; k++)
    used += (size_t)snprintf(buf + used, len - used, "%s --%s", k ? "," : "", flags[k].name);
  if (used < len)
    snprintf(buf + used, len - used, ", --profile");
}

void af_cli_print_flags(void)
{
  af_model_params d;
  if (!table_params(&d))
    return;
  for (size_t k = 0; k < N_FLAGS; k++) {
    const af_cli_flag *f = &flags[k];
    char def[32];
    switch (f->kind) {
    case AF_FLAG_DOUBLE: snprintf(def, sizeof def, "%g", af_cli_flag_get(f, &d)); break;
    case AF_FLAG_LOBE: snprintf(def, sizeof def, "%u", d.lobe); break;
    case AF_FLAG_DAMPING:
      snprintf(def, sizeof def, "%s", af_damping_law_name(d.impact.damping));
      break;
    case AF_FLAG_BAND: snprintf(def, sizeof def, "%s", af_band_level_name(d.band_level)); break;
    case AF_FLAG_SHEAR: snprintf(def, sizeof def, "%s", af_shear_ratio_name(d.shear_ratio)); break;
    }
    char flag[64];
    snprintf(flag, sizeof flag, "--%s %s", f->name,
             f->kind == AF_FLAG_DOUBLE ? "X"
             : f->kind == AF_FLAG_LOBE ? "N"
                                       : "WORD");
    printf("  %-28s %s (default %s)\n", flag, f->help, def);
  }
  /* Read by apply_profile before the table's flags. */
  printf("  %-28s %s\n", "--profile default|paper",
         "starting values: default = shipped, paper = paper-literal (model.h) "
         "(default default)");
}
