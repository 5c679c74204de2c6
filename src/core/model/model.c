/* model.c — one full evaluation of a strike: impact -> spectrum -> lobes ->
 * resonance -> shear -> criteria; the minimum strike radius through r2_search. */
#include "model.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "af_defaults.h"
#include "criteria.h"
#include "r2_search.h"
#include "lamb.h"
#include "settings.h"

/* Pulse sampling: the closed-form elastic contact time divided into this many
 * steps. Damping and gravity lengthen the pulse by tens of percent at most,
 * so AF_MODEL_MAX_SAMPLES leaves room for very lossy or very soft fruit. */
#define AF_MODEL_SAMPLES_PER_PULSE 128
#define AF_MODEL_MAX_SAMPLES 1024
#define AF_MODEL_FFT_SIZE 4096
/* A pulse longer than the buffer is sampled again at twice the step, up to
 * 2^7 = 128 times the first: a contact of up to 1024 elastic contact times
 * (a heavy, slow hammer on a soft fruit under gravity: more a push than a
 * tap) is still sampled at 1024 points, and the work stays bounded. */
#define AF_MODEL_SAMPLING_ATTEMPTS 8

struct af_model {
  af_impact *impact;
  af_spectrum *spectrum;
  double *force_n;
  double *deformation_m;
  /* xi and the shear ratio depend on the Poisson ratio only: cached. */
  af_lamb_cache xi;
  af_shear_cache shear;
};

af_model_params af_model_params_default(void)
{
  af_model_params p;
  p.impact = af_impact_params_default();
  p.fruit_mass_kg = 0.175; /* [kg]: no row (per apple, from its estimate) */
  p.fruit_density_kg_m3 = AF_DEFAULT_DENSITY_KG_M3;
  p.modulus_factor = AF_DEFAULT_MODULUS_FACTOR;
  p.lobe = AF_DEFAULT_LOBE;
  p.band_level = AF_BAND_AMPLITUDE_HALF;
  p.shear_ratio = AF_SHEAR_EXACT;
  /* The yield law, calibrated on the shipped profile (doc/paper.md, "The
   * yield law"): tau_y = yield_ratio E_ref (E2/E_ref)^yield_exponent, the
   * table's rows. */
  p.yield_ratio = AF_DEFAULT_YIELD_RATIO;
  p.yield_exponent = AF_DEFAULT_YIELD_EXPONENT;
  p.yield_reference_modulus_pa = AF_DEFAULT_YIELD_REFERENCE_MODULUS_PA;
  p.yield_measured.n = 0;
  p.bruise_energy_j = AF_DEFAULT_BRUISE_ENERGY_J;
  return p;
}

af_model_params af_model_params_paper(void)
{
  af_model_params p = af_model_params_default();
  p.impact.damping = AF_DAMPING_PAPER;
  p.lobe = 2;
  p.band_level = AF_BAND_POWER_HALF;
  p.shear_ratio = AF_SHEAR_PAPER;
  return p;
}

/* One checked field: its value and the row of the parameter table
 * (settings.h) that holds its accepted range, so that the model, the node,
 * the YAML files and the CLI accept exactly the same values. */
typedef struct {
  const char *field;
  double value;
  af_setting_id row;
} af_field_check;

/* The exact damping law is tabulated from e = 0.05 (impact.c's
 * AF_EXACT_E_MIN): below that chi grows without bound. The table's
 * restitution range, (0, 1], is that of the closed-form laws. */
#define AF_MODEL_EXACT_E_MIN 0.05

static void model_refuse(af_param_error *err, const char *field, double value, const char *range)
{
  if (err) {
    err->field = field;
    err->value = value;
    err->range = range;
  }
}

af_yield_law af_model_yield_law(const af_model_params *p)
{
  af_yield_law law;
  law.ratio = p->yield_ratio;
  law.reference_modulus_pa = p->yield_reference_modulus_pa;
  law.exponent = p->yield_exponent;
  law.measured = p->yield_measured;
  return law;
}

af_status af_model_params_check(const af_model_params *p, af_param_error *err)
{
  const af_impact_params *i = &p->impact;
  const af_field_check fields[] = {
      {"impact.hammer_mass_kg", i->hammer_mass_kg, AF_SETTING_HAMMER_MASS_KG},
      {"impact.velocity_m_s", i->velocity_m_s, AF_SETTING_STRIKE_VELOCITY_M_S},
      {"impact.hammer_modulus_pa", i->hammer_modulus_pa, AF_SETTING_HAMMER_MODULUS_PA},
      {"impact.hammer_poisson", i->hammer_poisson, AF_SETTING_HAMMER_POISSON},
      {"impact.hammer_radius_m", i->hammer_radius_m, AF_SETTING_HAMMER_TIP_RADIUS_M},
      {"impact.fruit_modulus_pa", i->fruit_modulus_pa, AF_SETTING_MODULUS_NOMINAL_PA},
      {"impact.fruit_poisson", i->fruit_poisson, AF_SETTING_FRUIT_POISSON},
      {"impact.strike_radius_m", i->strike_radius_m, AF_SETTING_STRIKE_RADIUS_MIN_M},
      {"impact.restitution", i->restitution, AF_SETTING_RESTITUTION},
      {"impact.gravity_m_s2", i->gravity_m_s2, AF_SETTING_GRAVITY_M_S2},
      {"fruit_mass_kg", p->fruit_mass_kg, AF_SETTING_MASS_MIN_KG},
      {"fruit_density_kg_m3", p->fruit_density_kg_m3, AF_SETTING_DENSITY_KG_M3},
      {"modulus_factor", p->modulus_factor, AF_SETTING_MODULUS_FACTOR},
      {"lobe", (double)p->lobe, AF_SETTING_LOBE},
      {"yield_ratio", p->yield_ratio, AF_SETTING_YIELD_RATIO},
      {"yield_exponent", p->yield_exponent, AF_SETTING_YIELD_EXPONENT},
      {"yield_reference_modulus_pa", p->yield_reference_modulus_pa,
       AF_SETTING_YIELD_REFERENCE_MODULUS_PA},
      {"bruise_energy_j", p->bruise_energy_j, AF_SETTING_BRUISE_ENERGY_J},
  };
  for (size_t k = 0; k < sizeof fields / sizeof fields[0]; k++) {
    const af_field_check *f = &fields[k];
    af_setting_range r;
    if (af_setting_range_of(f->row, &r) != AF_OK || !af_setting_range_contains(&r, f->value)) {
      model_refuse(err, f->field, f->value, af_setting_def_of(f->row)->range);
      return AF_EINVAL;
    }
    if (f->row == AF_SETTING_RESTITUTION && i->damping == AF_DAMPING_EXACT &&
        !(f->value >= AF_MODEL_EXACT_E_MIN)) {
      model_refuse(err, f->field, f->value, "[0.05, 1] with the exact damping law");
      return AF_EINVAL;
    }
  }
  /* The choices: the enums' own ranges, named with the table's words. */
  if (!((double)i->damping >= AF_DAMPING_PAPER && (double)i->damping <= AF_DAMPING_HU_GUO)) {
    model_refuse(err, "impact.damping", (double)i->damping,
                 af_setting_def_of(AF_SETTING_DAMPING_LAW)->choices);
    return AF_EINVAL;
  }
  if (!((double)p->band_level >= AF_BAND_POWER_HALF &&
        (double)p->band_level <= AF_BAND_AMPLITUDE_HALF)) {
    model_refuse(err, "band_level", (double)p->band_level,
                 af_setting_def_of(AF_SETTING_BAND_LEVEL)->choices);
    return AF_EINVAL;
  }
  if (!((double)p->shear_ratio >= AF_SHEAR_PAPER && (double)p->shear_ratio <= AF_SHEAR_EXACT)) {
    model_refuse(err, "shear_ratio", (double)p->shear_ratio,
                 af_setting_def_of(AF_SETTING_SHEAR_RATIO)->choices);
    return AF_EINVAL;
  }
  return AF_OK;
}

af_status af_model_create(af_model **out)
{
  af_spectrum_config sc = af_spectrum_config_default();
  af_model *m = calloc(1, sizeof *m);
  af_status st;
  *out = NULL;
  if (m == NULL)
    return AF_ENOMEM;
  sc.max_samples = AF_MODEL_MAX_SAMPLES;
  sc.fft_size = AF_MODEL_FFT_SIZE;
  sc.max_lobes = AF_MODEL_MAX_LOBES;
  m->force_n = malloc(AF_MODEL_MAX_SAMPLES * sizeof *m->force_n);
  m->deformation_m = malloc(AF_MODEL_MAX_SAMPLES * sizeof *m->deformation_m);
  af_lamb_cache_reset(&m->xi);
  af_shear_cache_reset(&m->shear);
  if (m->force_n == NULL || m->deformation_m == NULL) {
    af_model_destroy(m);
    return AF_ENOMEM;
  }
  st = af_impact_create(&m->impact);
  if (st == AF_OK)
    st = af_spectrum_create(&sc, &m->spectrum);
  if (st != AF_OK) {
    af_model_destroy(m);
    return st;
  }
  *out = m;
  return AF_OK;
}

void af_model_destroy(af_model *m)
{
  if (m == NULL)
    return;
  af_impact_destroy(m->impact);
  af_spectrum_destroy(m->spectrum);
  free(m->force_n);
  free(m->deformation_m);
  free(m);
}

/* Samples the pulse; a pulse longer than the buffer (very lossy fruit, a
 * hammer pushed by gravity) is retried with a coarser step rather than
 * refused. */
static af_status run_impact(af_model *m, const af_impact_params *ip, af_impact_result *res)
{
  double dt_s = af_impact_hertz_contact_time_s(ip) / AF_MODEL_SAMPLES_PER_PULSE;
  af_status st = AF_ESIZE;
  for (int attempt = 0; attempt < AF_MODEL_SAMPLING_ATTEMPTS && st == AF_ESIZE;
       attempt++, dt_s *= 2.0)
    st = af_impact_execute(m->impact, ip, dt_s, m->force_n, m->deformation_m, AF_MODEL_MAX_SAMPLES,
                           res);
  return st;
}

static af_status spectrum_figures(af_model *m, const af_model_params *p, af_model_result *r)
{
  af_status st = af_spectrum_execute(m->spectrum, m->force_n, r->impact.n_samples, r->impact.dt_s);
  if (st != AF_OK)
    return st;
  size_t count = af_spectrum_lobe_count(m->spectrum);
  r->n_lobes = count < AF_MODEL_MAX_LOBES ? count : AF_MODEL_MAX_LOBES;
  for (size_t k = 0; k < r->n_lobes; k++) {
    st = af_spectrum_lobe(m->spectrum, (unsigned)(k + 1), p->band_level, &r->lobes[k]);
    if (st != AF_OK)
      return st;
  }
  r->band_found = p->lobe <= r->n_lobes;
  if (r->band_found)
    r->band = r->lobes[p->lobe - 1];
  return AF_OK;
}

static af_status stress_figures(af_model *m, const af_model_params *p, af_model_result *r)
{
  double ratio;
  double radius_m = af_impact_effective_radius_m(&p->impact);
  af_status st = af_stress_max_center_pressure_pa(m->force_n, m->deformation_m, r->impact.n_samples,
                                                  radius_m, &r->max_contact_pressure_pa, NULL);
  if (st == AF_OK)
    st = af_stress_shear_ratio_cached(&m->shear, p->shear_ratio, p->impact.fruit_poisson, &ratio);
  if (st != AF_OK)
    return st;
  r->max_shear_stress_pa = ratio * r->max_contact_pressure_pa;
  af_yield_law law = af_model_yield_law(p);
  r->yield_shear_stress_pa = af_yield_shear_pa(&law, p->impact.fruit_modulus_pa);
  return AF_OK;
}

af_status af_model_execute(af_model *m, const af_model_params *p, af_model_result *r)
{
  double xi;
  af_status st = af_model_params_check(p, NULL);
  memset(r, 0, sizeof *r);
  if (st != AF_OK)
    return st;
  st = run_impact(m, &p->impact, &r->impact);
  if (st == AF_OK)
    st = spectrum_figures(m, p, r);
  if (st == AF_OK)
    st = af_lamb_root_cached(&m->xi, p->impact.fruit_poisson, &xi);
  if (st == AF_OK)
    st = stress_figures(m, p, r);
  if (st != AF_OK)
    return st;
  /* The modulus factor maps the quasi-static E2 of the contact to the dynamic
   * modulus that sets the vibration (PHYSICS.md 5). */
  r->resonance_hz =
      af_lamb_frequency_hz(xi, p->modulus_factor * p->impact.fruit_modulus_pa,
                           p->impact.fruit_poisson, p->fruit_density_kg_m3, p->fruit_mass_kg);
  r->excitation_at_resonance_db = af_spectrum_level_db(m->spectrum, r->resonance_hz);
  r->excites_mode = af_criteria_excites_mode(r->band_found ? &r->band : NULL, r->resonance_hz);
  r->no_damage = af_criteria_no_damage(r->max_shear_stress_pa, r->yield_shear_stress_pa);
  r->reliable = r->excites_mode && r->no_damage;
  af_model_energy_figures(p, r);
  return AF_OK;
}

void af_model_energy_figures(const af_model_params *p, af_model_result *r)
{
  r->delivered_energy_j =
      af_impact_delivered_energy_j(p->impact.hammer_mass_kg, p->impact.velocity_m_s);
  r->absorbed_energy_j =
      af_impact_absorbed_energy_j(r->delivered_energy_j, r->impact.delivered_restitution);
  r->below_bruise_energy = r->absorbed_energy_j < p->bruise_energy_j;
}

void af_model_reason(const af_model_result *r, unsigned lobe, char *buf, size_t len)
{
  af_criteria_reason(r->band_found ? &r->band : NULL, lobe, r->resonance_hz, r->max_shear_stress_pa,
                     r->yield_shear_stress_pa, buf, len);
}

/* af_model_execute as the R2_min search's callback. */
static af_status evaluate_ode(void *ctx, const af_model_params *p, af_model_result *r)
{
  return af_model_execute(ctx, p, r);
}

af_status af_model_min_strike_radius(af_model *m, const af_model_params *p, double r_lo_m,
                                     double r_hi_m, double *r_min_m)
{
  return af_r2_search(evaluate_ode, m, p, r_lo_m, r_hi_m, r_min_m);
}
