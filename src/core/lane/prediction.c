/* prediction.c — one apple's prediction (see prediction.h). */
#include "prediction.h"

#include <math.h>
#include <string.h>

#include "fastpath.h"
#include "lamb.h"
#include "r2_search.h"
#include "text.h"

/* One field of an apple estimate and its accepted range. */
typedef struct {
  const char *field;
  double value;
  double lo, hi;
  bool zero_ok; /* 0 = unknown is accepted too */
  const char *unit;
} af_field_check;

static bool field_ok(const af_field_check *f, const char *what, char *why, size_t len)
{
  if (isfinite(f->value) &&
      ((f->zero_ok && f->value == 0.0) || (f->value >= f->lo && f->value <= f->hi)))
    return true;
  const char *sp = f->unit[0] ? " " : "";
  if (isinf(f->lo) && isinf(f->hi))
    af_text(why, len, "%s: %s = %g is outside the accepted range (any finite value)", what,
            f->field, f->value);
  else
    af_text(why, len, "%s: %s = %g%s%s is outside the accepted range %s[%g, %g]%s%s", what,
            f->field, f->value, sp, f->unit, f->zero_ok ? "0 (unknown) or " : "", f->lo, f->hi, sp,
            f->unit);
  return false;
}

af_status af_prediction_check_apple(const af_lane_config *cfg, double mass_kg,
                                    double strike_radius_m, const char *what, char *why, size_t len)
{
  const af_field_check checks[] = {
      {"mass", mass_kg, cfg->mass_min_kg, cfg->mass_max_kg, false, "kg"},
      {"strike_radius", strike_radius_m, cfg->strike_radius_min_m, cfg->strike_radius_max_m, true,
       "m"},
  };
  for (size_t k = 0; k < sizeof checks / sizeof checks[0]; k++)
    if (!field_ok(&checks[k], what, why, len))
      return AF_EINVAL;
  return AF_OK;
}

/* Every field finite and in range, and mass and radius a plausible shape. */
static bool apple_valid(const af_lane_config *c, const af_apple *a, af_prediction *out)
{
  const af_field_check checks[] = {
      {"mass", a->mass_kg, c->mass_min_kg, c->mass_max_kg, false, "kg"},
      {"equatorial_radius", a->equatorial_radius_m, c->equatorial_radius_min_m,
       c->equatorial_radius_max_m, false, "m"},
      {"strike_radius", a->strike_radius_m, c->strike_radius_min_m, c->strike_radius_max_m, true,
       "m"},
      {"stem_axis.x", a->stem_axis[0], -INFINITY, INFINITY, false, ""},
      {"stem_axis.y", a->stem_axis[1], -INFINITY, INFINITY, false, ""},
      {"stem_axis.z", a->stem_axis[2], -INFINITY, INFINITY, false, ""},
      {"confidence", a->confidence, 0.0, 1.0, false, ""},
  };
  for (size_t k = 0; k < sizeof checks / sizeof checks[0]; k++)
    if (!field_ok(&checks[k], "invalid AppleEstimate", out->why, sizeof out->why))
      return false;
  /* The shape follows from mass, density and equatorial radius; an absurd
   * aspect means the estimates disagree with each other. */
  out->polar_semi_axis_m =
      af_advice_polar_semi_axis_m(a->mass_kg, c->model.fruit_density_kg_m3, a->equatorial_radius_m);
  double aspect = out->polar_semi_axis_m / a->equatorial_radius_m;
  if (aspect >= c->aspect_ratio_min && aspect <= c->aspect_ratio_max)
    return true;
  af_text(out->why, sizeof out->why,
          "invalid AppleEstimate: mass = %g kg and equatorial_radius = %g m give a polar "
          "semi-axis of %.4f m (density %g kg/m3), aspect %.2f outside the accepted range [%g, "
          "%g]",
          a->mass_kg, a->equatorial_radius_m, out->polar_semi_axis_m, c->model.fruit_density_kg_m3,
          aspect, c->aspect_ratio_min, c->aspect_ratio_max);
  return false;
}

/* The strike's geometry on this apple: latitude, normal and R2. */
static void locate_strike(const af_apple *a, af_prediction *out)
{
  af_advice_input in;
  memset(&in, 0, sizeof in);
  in.equatorial_radius_m = a->equatorial_radius_m;
  in.polar_semi_axis_m = out->polar_semi_axis_m;
  memcpy(in.stem_axis, a->stem_axis, sizeof in.stem_axis);
  memcpy(in.strike_direction, a->strike_direction, sizeof in.strike_direction);
  in.strike_radius_m = a->strike_radius_m;
  /* Cannot fail: apple_valid checked a, the shape and the strike radius. */
  af_advice_geometry_eval(&in, &out->geo);
}

/* The model's verdict; R2 is the input it hangs on most (the paper's
 * 31 mm): when it is only the equatorial radius because the strike point is
 * unknown, the prediction cannot be trusted whatever the model says. */
static void verdict(const af_apple *a, af_prediction *out)
{
  char model_reason[AF_PREDICTION_TEXT_MAX];
  af_model_reason(&out->result, out->params.lobe, model_reason, sizeof model_reason);
  bool r2_guessed = out->geo.r2_source == AF_R2_EQUATORIAL;
  out->reliable = out->result.reliable && !r2_guessed;
  if (r2_guessed)
    af_text(out->reason, sizeof out->reason,
            "%s: R2 unknown, equatorial radius %.1f mm assumed%s%s", a->direction_note,
            out->geo.strike_radius_m * 1e3, model_reason[0] ? "; " : "", model_reason);
  else
    af_text(out->reason, sizeof out->reason, "%s", model_reason);
}

/* One path of the model: its evaluation and its R2_min search. */
typedef struct {
  af_r2_evaluate_fn evaluate;
  af_status (*min_strike_radius)(void *ctx, const af_model_params *p, double r_lo_m, double r_hi_m,
                                 double *r_min_m);
  void *ctx;
} af_model_path;

/* The prediction on one path of the model (the ODE path's or the fast
 * path's): the strike itself, then the R2_min search on the same path. */
static af_status predict(const af_model_path *path, const af_lane_config *cfg, const af_apple *a,
                         af_prediction *out)
{
  memset(out, 0, sizeof *out);
  if (!apple_valid(cfg, a, out))
    return AF_EINVAL;
  locate_strike(a, out);
  out->params = cfg->model;
  out->params.fruit_mass_kg = a->mass_kg;
  out->params.impact.strike_radius_m = out->geo.strike_radius_m;
  af_status s = path->evaluate(path->ctx, &out->params, &out->result);
  if (s != AF_OK) {
    af_text(out->why, sizeof out->why, "model evaluation failed: %s", af_strerror(s));
    return s;
  }
  s = path->min_strike_radius(path->ctx, &out->params, cfg->r2_search_low_m, cfg->r2_search_high_m,
                              &out->min_strike_radius_m);
  if (s != AF_OK) /* AF_ENOROOT: not reliable even at the top of the bracket */
    out->min_strike_radius_m = 0.0;
  af_advice_decide(&out->geo, a->stem_axis, cfg->latitude_tolerance_rad, out->min_strike_radius_m,
                   &out->rotation);
  const af_model_params *p = &out->params;
  /* 0S2 grows with the modulus: the firmness range maps onto its ends. */
  out->resonance_low_hz =
      af_lamb_frequency_hz(cfg->resonance_xi, p->modulus_factor * cfg->modulus_min_pa,
                           p->impact.fruit_poisson, p->fruit_density_kg_m3, a->mass_kg);
  out->resonance_high_hz =
      af_lamb_frequency_hz(cfg->resonance_xi, p->modulus_factor * cfg->modulus_max_pa,
                           p->impact.fruit_poisson, p->fruit_density_kg_m3, a->mass_kg);
  verdict(a, out);
  out->valid = true;
  return AF_OK;
}

static af_status evaluate_ode(void *ctx, const af_model_params *p, af_model_result *r)
{
  return af_model_execute(ctx, p, r);
}

static af_status min_radius_ode(void *ctx, const af_model_params *p, double r_lo_m, double r_hi_m,
                                double *r_min_m)
{
  return af_model_min_strike_radius(ctx, p, r_lo_m, r_hi_m, r_min_m);
}

static af_status evaluate_fast(void *ctx, const af_model_params *p, af_model_result *r)
{
  return af_fastpath_execute(ctx, p, r);
}

/* Its search evaluates only what the criteria read (fastpath.c). */
static af_status min_radius_fast(void *ctx, const af_model_params *p, double r_lo_m, double r_hi_m,
                                 double *r_min_m)
{
  return af_fastpath_min_strike_radius(ctx, p, r_lo_m, r_hi_m, r_min_m);
}

af_status af_prediction_execute(af_model *model, const af_lane_config *cfg, const af_apple *a,
                                af_prediction *out)
{
  const af_model_path path = {evaluate_ode, min_radius_ode, model};
  return predict(&path, cfg, a, out);
}

af_status af_prediction_execute_fast(af_fastpath *fast, const af_lane_config *cfg,
                                     const af_apple *a, af_prediction *out)
{
  const af_model_path path = {evaluate_fast, min_radius_fast, fast};
  return predict(&path, cfg, a, out);
}
