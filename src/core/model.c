/* model.c — one full evaluation of a strike: impact -> spectrum -> lobes ->
 * resonance -> shear -> criteria, and the minimum strike radius. */
#include "model.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "criteria.h"
#include "resonance.h"

/* Pulse sampling: the closed-form elastic contact time divided into this many
 * steps. Damping and gravity lengthen the pulse by tens of percent at most,
 * so AF_MODEL_MAX_SAMPLES leaves room for very lossy or very soft fruit. */
#define AF_MODEL_SAMPLES_PER_PULSE 128
#define AF_MODEL_MAX_SAMPLES 1024
#define AF_MODEL_FFT_SIZE 4096
/* R2_min search: scan points over the bracket, then bisection to this
 * relative width. */
#define AF_MODEL_RADIUS_SCAN 24
#define AF_MODEL_RADIUS_RTOL 1e-4

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
  p.fruit_mass_kg = 0.175;
  p.fruit_density_kg_m3 = 840.0;
  p.modulus_factor = 1.0;
  p.lobe = 1;
  p.band_level = AF_BAND_AMPLITUDE_HALF;
  p.shear_ratio = AF_SHEAR_EXACT;
  p.yield_ratio = 0.04;
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

/* One accepted range: lo/hi with open or closed ends. */
typedef struct {
  const char *field;
  double value;
  double lo, hi;
  int lo_open, hi_open;
  const char *range;
} af_range;

static int in_range(const af_range *r)
{
  double v = r->value;
  if (!isfinite(v))
    return 0;
  if (r->lo_open ? !(v > r->lo) : !(v >= r->lo))
    return 0;
  return r->hi_open ? v < r->hi : v <= r->hi;
}

af_status af_model_params_check(const af_model_params *p, af_param_error *err)
{
  const af_impact_params *i = &p->impact;
  /* The exact law is tabulated from e = 0.05: below that chi grows without bound. */
  double e_lo = i->damping == AF_DAMPING_EXACT ? 0.05 : 0.0;
  const af_range ranges[] = {
      {"impact.hammer_mass_kg", i->hammer_mass_kg, 0, INFINITY, 1, 1, "(0, inf) kg"},
      {"impact.velocity_m_s", i->velocity_m_s, 0, INFINITY, 1, 1, "(0, inf) m/s"},
      {"impact.hammer_modulus_pa", i->hammer_modulus_pa, 0, INFINITY, 0, 1,
       "[0, inf) Pa, 0 = rigid"},
      {"impact.hammer_poisson", i->hammer_poisson, 0, 0.5, 0, 1, "[0, 0.5)"},
      {"impact.hammer_radius_m", i->hammer_radius_m, 0, INFINITY, 0, 1, "[0, inf) m, 0 = flat"},
      {"impact.fruit_modulus_pa", i->fruit_modulus_pa, 0, INFINITY, 1, 1, "(0, inf) Pa"},
      {"impact.fruit_poisson", i->fruit_poisson, 0, 0.5, 0, 1, "[0, 0.5)"},
      {"impact.strike_radius_m", i->strike_radius_m, 0, INFINITY, 1, 1, "(0, inf) m"},
      {"impact.restitution", i->restitution, e_lo, 1, e_lo == 0.0, 0,
       e_lo == 0.0 ? "(0, 1]" : "[0.05, 1] with the exact damping law"},
      {"impact.gravity_m_s2", i->gravity_m_s2, 0, INFINITY, 0, 1, "[0, inf) m/s2"},
      {"impact.damping", (double)i->damping, AF_DAMPING_PAPER, AF_DAMPING_HU_GUO, 0, 0,
       "paper, exact or hu-guo"},
      {"fruit_mass_kg", p->fruit_mass_kg, 0, INFINITY, 1, 1, "(0, inf) kg"},
      {"fruit_density_kg_m3", p->fruit_density_kg_m3, 0, INFINITY, 1, 1, "(0, inf) kg/m3"},
      {"modulus_factor", p->modulus_factor, 0, INFINITY, 1, 1, "(0, inf)"},
      {"lobe", (double)p->lobe, 1, AF_MODEL_MAX_LOBES, 0, 0, "1 .. 8"},
      {"band_level", (double)p->band_level, AF_BAND_POWER_HALF, AF_BAND_AMPLITUDE_HALF, 0, 0,
       "power-half or amplitude-half"},
      {"shear_ratio", (double)p->shear_ratio, AF_SHEAR_PAPER, AF_SHEAR_EXACT, 0, 0,
       "paper or exact"},
      {"yield_ratio", p->yield_ratio, 0, INFINITY, 1, 1, "(0, inf)"},
  };
  for (size_t k = 0; k < sizeof ranges / sizeof ranges[0]; k++) {
    if (!in_range(&ranges[k])) {
      if (err) {
        err->field = ranges[k].field;
        err->value = ranges[k].value;
        err->range = ranges[k].range;
      }
      return AF_EINVAL;
    }
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
  af_lamb_cache_init(&m->xi);
  af_shear_cache_init(&m->shear);
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

/* Samples the pulse; a pulse longer than the buffer (very lossy fruit) is
 * retried with a coarser step rather than refused. */
static af_status run_impact(af_model *m, const af_impact_params *ip, af_impact_result *res)
{
  double dt_s = af_impact_hertz_contact_time_s(ip) / AF_MODEL_SAMPLES_PER_PULSE;
  af_status st = AF_ESIZE;
  for (int attempt = 0; attempt < 3 && st == AF_ESIZE; attempt++, dt_s *= 2.0)
    st =
        af_impact_run(m->impact, ip, dt_s, m->force_n, m->deformation_m, AF_MODEL_MAX_SAMPLES, res);
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
  r->yield_shear_stress_pa = af_stress_yield_shear_pa(p->yield_ratio, p->impact.fruit_modulus_pa);
  return AF_OK;
}

af_status af_model_evaluate(af_model *m, const af_model_params *p, af_model_result *r)
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
    st = af_resonance_lamb_root_cached(&m->xi, p->impact.fruit_poisson, &xi);
  if (st == AF_OK)
    st = stress_figures(m, p, r);
  if (st != AF_OK)
    return st;
  /* The modulus factor maps the quasi-static E2 of the contact to the dynamic
   * modulus that sets the vibration (PHYSICS.md 5). */
  r->resonance_hz =
      af_resonance_frequency_hz(xi, p->modulus_factor * p->impact.fruit_modulus_pa,
                                p->impact.fruit_poisson, p->fruit_density_kg_m3, p->fruit_mass_kg);
  r->excitation_at_resonance_db = af_spectrum_level_db(m->spectrum, r->resonance_hz);
  r->excites_mode = af_criteria_excites_mode(r->band_found ? &r->band : NULL, r->resonance_hz);
  r->no_damage = af_criteria_no_damage(r->max_shear_stress_pa, r->yield_shear_stress_pa);
  r->reliable = r->excites_mode && r->no_damage;
  return AF_OK;
}

void af_model_reason(const af_model_result *r, unsigned lobe, char *buf, size_t len)
{
  af_criteria_reason(r->band_found ? &r->band : NULL, lobe, r->resonance_hz, r->max_shear_stress_pa,
                     r->yield_shear_stress_pa, buf, len);
}

static af_status reliable_at(af_model *m, const af_model_params *p, double radius_m, bool *ok)
{
  af_model_params q = *p;
  af_model_result r;
  q.impact.strike_radius_m = radius_m;
  af_status st = af_model_evaluate(m, &q, &r);
  *ok = st == AF_OK && r.reliable;
  return st;
}

af_status af_model_min_strike_radius(af_model *m, const af_model_params *p, double r_lo_m,
                                     double r_hi_m, double *r_min_m)
{
  bool ok;
  if (!(r_lo_m > 0.0 && r_hi_m > r_lo_m && isfinite(r_hi_m)))
    return AF_EINVAL;
  af_status st = reliable_at(m, p, r_hi_m, &ok);
  if (st != AF_OK)
    return st;
  if (!ok)
    return AF_ENOROOT;
  /* Walk down a geometric scan from r_hi to the first unreliable radius, then
   * bisect between it and the last reliable one: the criteria need not be
   * monotonic far below R2_min, only near it. */
  double step = pow(r_lo_m / r_hi_m, 1.0 / (AF_MODEL_RADIUS_SCAN - 1));
  double good = r_hi_m, bad = 0.0;
  for (int k = 1; k < AF_MODEL_RADIUS_SCAN; k++) {
    double r = k == AF_MODEL_RADIUS_SCAN - 1 ? r_lo_m : r_hi_m * pow(step, k);
    st = reliable_at(m, p, r, &ok);
    if (st != AF_OK)
      return st;
    if (!ok) {
      bad = r;
      break;
    }
    good = r;
  }
  if (bad == 0.0) {
    *r_min_m = r_lo_m;
    return AF_OK;
  }
  while (good - bad > AF_MODEL_RADIUS_RTOL * good) {
    double mid = sqrt(good * bad);
    st = reliable_at(m, p, mid, &ok);
    if (st != AF_OK)
      return st;
    if (ok)
      good = mid;
    else
      bad = mid;
  }
  *r_min_m = good;
  return AF_OK;
}
