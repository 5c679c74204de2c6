/* evaluate.c — the ~evaluate service (see evaluate.h). */
#include "evaluate.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "model.h"
#include "prediction.h"
#include "lamb.h"
#include "settings.h"
#include "text.h"

struct af_evaluate {
  af_ros *ros;
  const af_node_config *cfg;
  af_model *model;
  unsigned long long calls, refused;
  char last_refusal[AF_TEXT_MAX];
};

/* One request field against the range of its table row: 0 takes the
 * configured value (when there is one), anything else must lie in the row's
 * range. false with one line in err. */
static bool field(const char *name, double v, af_setting_id row, double configured, double *out,
                  char *err, size_t len)
{
  const af_setting_def *d = af_setting_def_of(row);
  af_setting_range r;
  if (v == 0.0 && !isnan(configured)) {
    *out = configured;
    return true;
  }
  if (v == 0.0) {
    af_text(err, len, "%s is required (a number in %s, the range of ~%s)", name, d->range, d->name);
    return false;
  }
  if (af_setting_range_of(row, &r) != AF_OK || !af_setting_range_contains(&r, v)) {
    af_text(err, len, "%s = %g is outside the accepted range %s (the range of ~%s)", name, v,
            d->range, d->name);
    return false;
  }
  *out = v;
  return true;
}

static void all_nan(af_evaluate_response *res)
{
  double *figures[] = {&res->modulus_pa,
                       &res->restitution,
                       &res->velocity_m_s,
                       &res->hammer_mass_kg,
                       &res->contact_time_s,
                       &res->peak_force_n,
                       &res->max_deformation_m,
                       &res->delivered_restitution,
                       &res->band_low_hz,
                       &res->band_high_hz,
                       &res->resonance_hz,
                       &res->resonance_low_hz,
                       &res->resonance_high_hz,
                       &res->excitation_at_resonance_db,
                       &res->max_contact_pressure_pa,
                       &res->max_shear_stress_pa,
                       &res->yield_shear_stress_pa,
                       &res->min_strike_radius_m};
  for (size_t k = 0; k < sizeof figures / sizeof figures[0]; k++)
    *figures[k] = NAN;
}

/* The model's parameters for req: the lane's template, the request's apple,
 * strike and overrides. false with the refusal in res->error. */
static bool params_of(const af_evaluate *e, const af_evaluate_request *req, af_model_params *p,
                      af_evaluate_response *res)
{
  const af_lane_config *c = &e->cfg->lane;
  char *err = res->error;
  const size_t len = sizeof res->error;
  *p = c->model;
  af_impact_params *i = &p->impact;
  if (!field("mass", req->mass_kg, AF_SETTING_MASS_MIN_KG, NAN, &p->fruit_mass_kg, err, len) ||
      !field("strike_radius", req->strike_radius_m, AF_SETTING_STRIKE_RADIUS_MIN_M, NAN,
             &i->strike_radius_m, err, len) ||
      !field("modulus", req->modulus_pa, AF_SETTING_MODULUS_NOMINAL_PA, i->fruit_modulus_pa,
             &i->fruit_modulus_pa, err, len) ||
      !field("restitution", req->restitution, AF_SETTING_RESTITUTION, i->restitution,
             &i->restitution, err, len) ||
      !field("velocity", req->velocity_m_s, AF_SETTING_STRIKE_VELOCITY_M_S, i->velocity_m_s,
             &i->velocity_m_s, err, len) ||
      !field("hammer_mass", req->hammer_mass_kg, AF_SETTING_HAMMER_MASS_KG, i->hammer_mass_kg,
             &i->hammer_mass_kg, err, len))
    return false;
  /* The cultivar's ranges, as the lane's prediction refuses an apple: the
   * table's alone would answer for fruit the lane never grades. */
  if (af_prediction_check_apple(c, p->fruit_mass_kg, i->strike_radius_m,
                                "the lane would refuse this apple", err, len) != AF_OK)
    return false;
  af_param_error pe;
  if (af_model_params_check(p, &pe) != AF_OK) {
    af_text(err, len, "the model refuses %s = %g (accepted: %s)", pe.field, pe.value, pe.range);
    return false;
  }
  return true;
}

void af_evaluate_execute(af_evaluate *e, const af_evaluate_request *req, af_evaluate_response *res)
{
  const af_lane_config *c = &e->cfg->lane;
  af_model_params p;
  af_model_result r;
  memset(res, 0, sizeof *res);
  all_nan(res);
  e->calls++;
  af_status st = AF_EINVAL;
  if (params_of(e, req, &p, res)) {
    st = af_model_execute(e->model, &p, &r);
    if (st != AF_OK)
      af_text(res->error, sizeof res->error, "the model failed: %s", af_strerror(st));
  }
  if (st != AF_OK) {
    e->refused++;
    af_text(e->last_refusal, sizeof e->last_refusal, "%s", res->error);
    af_ros_log(e->ros, AF_LOG_WARN, "~evaluate refused: %s", res->error);
    return;
  }
  res->ok = true;
  res->modulus_pa = p.impact.fruit_modulus_pa;
  res->restitution = p.impact.restitution;
  res->velocity_m_s = p.impact.velocity_m_s;
  res->hammer_mass_kg = p.impact.hammer_mass_kg;
  res->contact_time_s = r.impact.contact_time_s;
  res->peak_force_n = r.impact.peak_force_n;
  res->max_deformation_m = r.impact.max_deformation_m;
  res->delivered_restitution = r.impact.delivered_restitution;
  res->lobe = (uint8_t)p.lobe;
  res->band_low_hz = r.band_found ? r.band.band_low_hz : NAN;
  res->band_high_hz = r.band_found ? r.band.band_high_hz : NAN;
  res->resonance_hz = r.resonance_hz;
  res->resonance_low_hz =
      af_lamb_frequency_hz(c->resonance_xi, p.modulus_factor * c->modulus_min_pa,
                           p.impact.fruit_poisson, p.fruit_density_kg_m3, p.fruit_mass_kg);
  res->resonance_high_hz =
      af_lamb_frequency_hz(c->resonance_xi, p.modulus_factor * c->modulus_max_pa,
                           p.impact.fruit_poisson, p.fruit_density_kg_m3, p.fruit_mass_kg);
  res->excitation_at_resonance_db = r.excitation_at_resonance_db;
  res->max_contact_pressure_pa = r.max_contact_pressure_pa;
  res->max_shear_stress_pa = r.max_shear_stress_pa;
  res->yield_shear_stress_pa = r.yield_shear_stress_pa;
  res->excites_mode = r.excites_mode;
  res->no_damage = r.no_damage;
  res->reliable = r.reliable;
  af_model_reason(&r, p.lobe, res->reason, sizeof res->reason);
  /* AF_ENOROOT (not reliable even at the top of the bracket) and a spent
   * budget both mean: no reliable R2 found. */
  if (af_model_min_strike_radius(e->model, &p, c->r2_search_low_m, c->r2_search_high_m,
                                 &res->min_strike_radius_m) != AF_OK)
    res->min_strike_radius_m = 0.0;
}

static void on_evaluate(const af_evaluate_request *req, af_evaluate_response *res, void *user)
{
  af_evaluate_execute(user, req, res);
}

void af_evaluate_diag(const af_evaluate *e, af_diag_status *d)
{
  if (!e)
    return;
  af_diag_add(d, "evaluate calls", "%llu (refused %llu)", e->calls, e->refused);
  if (e->refused)
    af_diag_add(d, "evaluate last refusal", "%s", e->last_refusal);
}

af_status af_evaluate_create(af_ros *ros, const af_node_config *cfg, af_evaluate **out,
                             const char **what)
{
  *out = NULL;
  *what = "the ~evaluate service";
  af_evaluate *e = calloc(1, sizeof *e);
  if (!e)
    return AF_ENOMEM;
  e->ros = ros;
  e->cfg = cfg;
  af_status s = af_model_create(&e->model);
  if (s == AF_OK)
    s = af_ros_advertise_evaluate(ros, "~evaluate", on_evaluate, e);
  if (s != AF_OK) {
    af_evaluate_destroy(e);
    return s;
  }
  *out = e;
  return AF_OK;
}

void af_evaluate_destroy(af_evaluate *e)
{
  if (!e)
    return;
  af_model_destroy(e->model);
  free(e); /* the service belongs to the af_ros */
}
