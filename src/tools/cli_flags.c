/* cli_flags.c — the model flags of firmness_model as one af_option table,
 * read by the one parser (options.h). */
#include "cli_flags.h"

#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <string.h>

#include "model_table.h"
#include "settings.h"

#define P(field) offsetof(af_model_params, field)
#define CHOICE(flag, row, help)                                                                    \
  {                                                                                                \
    flag, "WORD", AF_OPTION_SETTING, 0, row, NULL, help, NULL, false                               \
  }

/* Each number's row is the one af_model_params_check (model.c) applies to
 * its field, so the parser refuses at once what the check would. */
static const af_option model_options[] = {
    {"--E2", "X", AF_OPTION_NUMBER, P(impact.fruit_modulus_pa), AF_SETTING_MODULUS_NOMINAL_PA, NULL,
     "fruit elastic modulus", NULL, false},
    {"--nu2", "X", AF_OPTION_NUMBER, P(impact.fruit_poisson), AF_SETTING_FRUIT_POISSON, NULL,
     "fruit Poisson ratio", NULL, false},
    {"--R2", "X", AF_OPTION_NUMBER, P(impact.strike_radius_m), AF_SETTING_STRIKE_RADIUS_MIN_M, NULL,
     "local radius of curvature under the hammer", NULL, false},
    {"--e", "X", AF_OPTION_NUMBER, P(impact.restitution), AF_SETTING_RESTITUTION, NULL,
     "coefficient of restitution", NULL, false},
    {"--mass", "X", AF_OPTION_NUMBER, P(fruit_mass_kg), AF_SETTING_MASS_MIN_KG, NULL, "fruit mass",
     NULL, false},
    {"--density", "X", AF_OPTION_NUMBER, P(fruit_density_kg_m3), AF_SETTING_DENSITY_KG_M3, NULL,
     "fruit density", NULL, false},
    {"--hammer-mass", "X", AF_OPTION_NUMBER, P(impact.hammer_mass_kg), AF_SETTING_HAMMER_MASS_KG,
     NULL, "hammer mass", NULL, false},
    {"--v0", "X", AF_OPTION_NUMBER, P(impact.velocity_m_s), AF_SETTING_STRIKE_VELOCITY_M_S, NULL,
     "contact velocity", NULL, false},
    {"--hammer-E", "X", AF_OPTION_NUMBER, P(impact.hammer_modulus_pa), AF_SETTING_HAMMER_MODULUS_PA,
     NULL, "hammer tip modulus, 0 = rigid", "rigid", false},
    {"--hammer-nu", "X", AF_OPTION_NUMBER, P(impact.hammer_poisson), AF_SETTING_HAMMER_POISSON,
     NULL, "hammer tip Poisson ratio", NULL, false},
    {"--hammer-radius", "X", AF_OPTION_NUMBER, P(impact.hammer_radius_m),
     AF_SETTING_HAMMER_TIP_RADIUS_M, NULL, "hammer tip radius, 0 = flat", "flat", false},
    {"--gravity", "X", AF_OPTION_NUMBER, P(impact.gravity_m_s2), AF_SETTING_GRAVITY_M_S2, NULL,
     "gravity along the strike", "0, none", false},
    CHOICE("--damping", AF_SETTING_DAMPING_LAW, "damping law"),
    {"--lobe", "N", AF_OPTION_UINT, P(lobe), AF_SETTING_LOBE, NULL,
     "spectral lobe of the criterion, 1 = main lobe", NULL, false},
    CHOICE("--band-level", AF_SETTING_BAND_LEVEL, "half-power reading"),
    CHOICE("--shear-ratio", AF_SETTING_SHEAR_RATIO, "tau_max/p0: paper (0.31) or exact (for nu2)"),
    {"--yield-ratio", "X", AF_OPTION_NUMBER, P(yield_ratio), AF_SETTING_YIELD_RATIO, NULL,
     "yield law tau_y / E2 at E_ref (calibration)", NULL, false},
    {"--yield-exponent", "X", AF_OPTION_NUMBER, P(yield_exponent), AF_SETTING_YIELD_EXPONENT, NULL,
     "yield law exponent p, tau_y ~ E2^p (1 = ratio law)", NULL, false},
    {"--yield-reference-modulus", "X", AF_OPTION_NUMBER, P(yield_reference_modulus_pa),
     AF_SETTING_YIELD_REFERENCE_MODULUS_PA, NULL, "yield law reference modulus E_ref", NULL, false},
    {"--modulus-factor", "X", AF_OPTION_NUMBER, P(modulus_factor), AF_SETTING_MODULUS_FACTOR, NULL,
     "dynamic / quasi-static modulus", NULL, false},
    {"--profile", "default|paper", AF_OPTION_NONE, 0, -1, NULL,
     "starting values: default = shipped, paper = paper-literal (model.h); the other flags "
     "override it wherever it stands",
     "default", false},
};
#define N_MODEL (sizeof model_options / sizeof model_options[0])

/* af_param_error's field names (model.c) of the entries, in the table's
 * order: af_cli_validate names the flag of a refused field. */
static const char *const model_fields[N_MODEL] = {
    "impact.fruit_modulus_pa",
    "impact.fruit_poisson",
    "impact.strike_radius_m",
    "impact.restitution",
    "fruit_mass_kg",
    "fruit_density_kg_m3",
    "impact.hammer_mass_kg",
    "impact.velocity_m_s",
    "impact.hammer_modulus_pa",
    "impact.hammer_poisson",
    "impact.hammer_radius_m",
    "impact.gravity_m_s2",
    "impact.damping",
    "lobe",
    "band_level",
    "shear_ratio",
    "yield_ratio",
    "yield_exponent",
    "yield_reference_modulus_pa",
    "modulus_factor",
    "profile",
};

const af_option *af_cli_model_options(size_t *n)
{
  *n = N_MODEL;
  return model_options;
}

const af_option *af_cli_model_number(const char *name)
{
  char flag[64];
  snprintf(flag, sizeof flag, "--%s", name);
  const af_option *o = af_option_find(model_options, N_MODEL, flag);
  return o != NULL && (o->kind == AF_OPTION_NUMBER || o->kind == AF_OPTION_UINT) ? o : NULL;
}

void af_cli_model_set(const af_option *o, double v, af_model_params *p)
{
  const unsigned u = (unsigned)v;
  if (o->kind == AF_OPTION_UINT)
    memcpy((char *)p + o->offset, &u, sizeof u);
  else
    memcpy((char *)p + o->offset, &v, sizeof v);
}

double af_cli_model_get(const af_option *o, const af_model_params *p)
{
  double v;
  unsigned u;
  if (o->kind != AF_OPTION_UINT) {
    memcpy(&v, (const char *)p + o->offset, sizeof v);
    return v;
  }
  memcpy(&u, (const char *)p + o->offset, sizeof u);
  return u;
}

/* ---- the parse ------------------------------------------------------------------- */

/* What is applied after the numbers: the profile, then the choices. */
typedef struct {
  const char *tool;
  bool paper;
  const af_option *choice[3];
  const char *word[3];
  size_t n_choices;
} af_model_later;

/* A choice word into p; false (no message) when it is not one. */
static bool set_choice(const af_option *o, const char *word, af_model_params *p)
{
  switch (o->setting) {
  case AF_SETTING_DAMPING_LAW: return af_damping_law_parse(word, &p->impact.damping) == AF_OK;
  case AF_SETTING_BAND_LEVEL: return af_band_level_parse(word, &p->band_level) == AF_OK;
  default: return af_shear_ratio_parse(word, &p->shear_ratio) == AF_OK;
  }
}

/* --profile and the choices, checked now, applied after the parse. */
static bool model_hand(void *user, const af_option *o, const char *value)
{
  af_model_later *later = user;
  af_model_params scratch;
  if (o->kind == AF_OPTION_NONE) { /* --profile */
    later->paper = strcmp(value, "paper") == 0;
    if (later->paper || strcmp(value, "default") == 0)
      return true;
    fprintf(stderr, "%s: --profile '%.40s' is not one of: default, paper\n", later->tool, value);
    return false;
  }
  if (!set_choice(o, value, &scratch)) {
    fprintf(stderr, "%s: %s '%.40s' is not one of: %s\n", later->tool, o->name, value,
            af_setting_def_of((af_setting_id)o->setting)->choices);
    return false;
  }
  later->choice[later->n_choices] = o;
  later->word[later->n_choices++] = value; /* each choice once: at most 3 */
  return true;
}

/* The starting values: the parameter table's defaults (af_model_params_table:
 * what the node and firmness_report derive, with model.c's example apple). */
static bool table_params(const char *tool, af_model_params *p)
{
  char err[512];
  if (af_model_params_table(p, err, sizeof err) == AF_OK)
    return true;
  fprintf(stderr, "%s: the parameter table's defaults: %s\n", tool, err);
  return false;
}

bool af_cli_parse_model(const char *tool, const af_option_set *own, const char *more, int argc,
                        char **argv, int first, af_model_params *p)
{
  af_model_later later = {tool, false, {NULL}, {NULL}, 0};
  af_options_parser parser = {tool, {{0}}, 0, more, false};
  if (own != NULL)
    parser.sets[parser.n_sets++] = *own;
  parser.sets[parser.n_sets++] = (af_option_set){model_options, N_MODEL, p, model_hand, &later};
  if (!table_params(tool, p))
    return false;
  const unsigned table_lobe = p->lobe;
  p->lobe = 0; /* 0: --lobe not given (its range starts at 1) */
  if (!af_options_parse(&parser, argc, argv, first))
    return false;
  /* The profile sets the choices and the lobe (model_table.h): the numbers
   * given stand, the choice flags and --lobe given override it. */
  const unsigned lobe = p->lobe;
  p->lobe = table_lobe;
  if (later.paper)
    *p = af_model_params_paper_of(p);
  if (lobe != 0)
    p->lobe = lobe;
  for (size_t k = 0; k < later.n_choices; k++)
    (void)set_choice(later.choice[k], later.word[k], p);
  return af_cli_validate(p, tool);
}

bool af_cli_validate(const af_model_params *p, const char *tool)
{
  af_param_error err;
  if (af_model_params_check(p, &err) == AF_OK)
    return true;
  const char *flag = err.field;
  for (size_t k = 0; k < N_MODEL; k++)
    if (strcmp(model_fields[k], err.field) == 0)
      flag = model_options[k].name;
  af_options_outside(tool, flag, err.value, err.range, NULL);
  return false;
}

void af_cli_print_flags(void)
{
  af_model_params d;
  af_settings s;
  if (!table_params("firmness_model", &d))
    return;
  af_settings_reset(&s);
  af_options_help_rows(stdout, model_options, N_MODEL, &d, &s);
}
