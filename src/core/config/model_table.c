/* model_table.c — the model's parameters from the parameter table. */
#include "model_table.h"

#include "tool_config.h"

af_status af_model_params_from_settings(const af_settings *s, af_model_params *out, char *err,
                                        size_t len)
{
  af_lane_config c;
  af_status st = af_lane_config_for_tool(s, &c, err, len);
  if (st != AF_OK)
    return st;
  const af_model_params example = af_model_params_default();
  *out = c.model;
  out->fruit_mass_kg = example.fruit_mass_kg;
  out->impact.strike_radius_m = example.impact.strike_radius_m;
  return AF_OK;
}

af_status af_model_params_table(af_model_params *out, char *err, size_t len)
{
  af_settings s;
  af_settings_reset(&s);
  return af_model_params_from_settings(&s, out, err, len);
}

af_model_params af_model_params_paper_of(const af_model_params *p)
{
  const af_model_params paper = af_model_params_paper();
  af_model_params q = *p;
  q.impact.damping = paper.impact.damping;
  q.lobe = paper.lobe;
  q.band_level = paper.band_level;
  q.shear_ratio = paper.shear_ratio;
  return q;
}
