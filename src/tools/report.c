/* report.c — JSON, CSV and text renderings of one model evaluation. */
#include "report.h"

#include <math.h>

af_status af_report_compute(af_model *m, const af_model_params *p, af_report *rep)
{
  rep->params = *p;
  af_status st = af_model_execute(m, p, &rep->result);
  if (st != AF_OK)
    return st;
  st = af_model_min_strike_radius(m, p, AF_REPORT_R2_LO_M, AF_REPORT_R2_HI_M,
                                  &rep->min_strike_radius_m);
  if (st == AF_ENOROOT) {
    rep->min_strike_radius_m = NAN;
    st = AF_OK;
  }
  return st;
}

af_status af_report_compute_fast(af_fastpath *f, const af_model_params *p, af_report *rep)
{
  rep->params = *p;
  af_status st = af_fastpath_execute(f, p, &rep->result);
  if (st != AF_OK)
    return st;
  st = af_fastpath_min_strike_radius(f, p, AF_REPORT_R2_LO_M, AF_REPORT_R2_HI_M,
                                     &rep->min_strike_radius_m);
  if (st == AF_ENOROOT) {
    rep->min_strike_radius_m = NAN;
    st = AF_OK;
  }
  return st;
}

/* JSON has no NaN: a missing figure is null. */
static void json_number(FILE *out, const char *key, double v, const char *sep)
{
  if (isfinite(v))
    fprintf(out, "  \"%s\": %.10g%s\n", key, v, sep);
  else
    fprintf(out, "  \"%s\": null%s\n", key, sep);
}

static void json_lobes(FILE *out, const af_model_result *r)
{
  fprintf(out, "  \"lobes\": [");
  for (size_t k = 0; k < r->n_lobes; k++) {
    const af_lobe *l = &r->lobes[k];
    fprintf(out,
            "%s\n    {\"index\": %u, \"start_hz\": %.10g, \"end_hz\": %.10g, \"peak_hz\": %.10g, "
            "\"band_low_hz\": %.10g, \"band_high_hz\": %.10g}",
            k ? "," : "", l->index, l->start_hz, l->end_hz, l->peak_hz, l->band_low_hz,
            l->band_high_hz);
  }
  fprintf(out, "%s],\n", r->n_lobes ? "\n  " : "");
}

void af_report_json(FILE *out, const af_report *rep)
{
  const af_model_result *r = &rep->result;
  fprintf(out, "{\n");
  json_number(out, "contact_time_s", r->impact.contact_time_s, ",");
  json_number(out, "peak_force_n", r->impact.peak_force_n, ",");
  json_number(out, "max_deformation_m", r->impact.max_deformation_m, ",");
  json_number(out, "delivered_restitution", r->impact.delivered_restitution, ",");
  json_lobes(out, r);
  json_number(out, "band_low_hz", r->band_found ? r->band.band_low_hz : NAN, ",");
  json_number(out, "band_high_hz", r->band_found ? r->band.band_high_hz : NAN, ",");
  json_number(out, "resonance_hz", r->resonance_hz, ",");
  json_number(out, "excitation_at_resonance_db", r->excitation_at_resonance_db, ",");
  json_number(out, "max_contact_pressure_pa", r->max_contact_pressure_pa, ",");
  json_number(out, "max_shear_stress_pa", r->max_shear_stress_pa, ",");
  json_number(out, "yield_shear_stress_pa", r->yield_shear_stress_pa, ",");
  json_number(out, "min_strike_radius_m", rep->min_strike_radius_m, ",");
  fprintf(out, "  \"excites_mode\": %s,\n", r->excites_mode ? "true" : "false");
  fprintf(out, "  \"no_damage\": %s,\n", r->no_damage ? "true" : "false");
  fprintf(out, "  \"reliable\": %s,\n", r->reliable ? "true" : "false");
  json_number(out, "delivered_energy_j", r->delivered_energy_j, ",");
  json_number(out, "absorbed_energy_j", r->absorbed_energy_j, ",");
  json_number(out, "bruise_energy_j", rep->params.bruise_energy_j, ",");
  fprintf(out, "  \"below_bruise_energy\": %s\n}\n", r->below_bruise_energy ? "true" : "false");
}

void af_report_text(FILE *out, const af_report *rep)
{
  const af_model_params *p = &rep->params;
  const af_model_result *r = &rep->result;
  char reason[256];
  fprintf(out,
          "strike: hammer %.1f g at %.2f m/s on E2 %.2f MPa, R2 %.1f mm, e %.2f (%s damping)\n",
          p->impact.hammer_mass_kg * 1e3, p->impact.velocity_m_s, p->impact.fruit_modulus_pa * 1e-6,
          p->impact.strike_radius_m * 1e3, p->impact.restitution,
          af_damping_law_name(p->impact.damping));
  fprintf(out, "  contact time      %8.4f ms\n", r->impact.contact_time_s * 1e3);
  fprintf(out, "  peak force        %8.3f N\n", r->impact.peak_force_n);
  fprintf(out, "  max deformation   %8.4f mm\n", r->impact.max_deformation_m * 1e3);
  fprintf(out, "  delivered e       %8.4f\n", r->impact.delivered_restitution);
  for (size_t k = 0; k < r->n_lobes; k++)
    fprintf(out, "  lobe %zu: %7.1f .. %7.1f Hz, peak %7.1f Hz, %s band %7.1f .. %7.1f Hz\n", k + 1,
            r->lobes[k].start_hz, r->lobes[k].end_hz, r->lobes[k].peak_hz,
            af_band_level_name(p->band_level), r->lobes[k].band_low_hz, r->lobes[k].band_high_hz);
  fprintf(out, "  resonance (0S2)   %8.1f Hz at %.1f dB, fruit %.0f g\n", r->resonance_hz,
          r->excitation_at_resonance_db, p->fruit_mass_kg * 1e3);
  fprintf(out, "  contact pressure  %8.4f MPa\n", r->max_contact_pressure_pa * 1e-6);
  fprintf(out, "  max shear         %8.4f MPa (yield %.4f MPa)\n", r->max_shear_stress_pa * 1e-6,
          r->yield_shear_stress_pa * 1e-6);
  fprintf(
      out,
      "  impact energy     %8.3f mJ delivered (m1 v0^2 / 2), %.3f mJ absorbed (1 - e^2, e %.4f)\n",
      r->delivered_energy_j * 1e3, r->absorbed_energy_j * 1e3, r->impact.delivered_restitution);
  if (isfinite(rep->min_strike_radius_m))
    fprintf(out, "  min strike radius %8.2f mm\n", rep->min_strike_radius_m * 1e3);
  else
    fprintf(out, "  min strike radius     none reliable in [%g, %g] mm\n", AF_REPORT_R2_LO_M * 1e3,
            AF_REPORT_R2_HI_M * 1e3);
  af_model_reason(r, p->lobe, reason, sizeof reason);
  fprintf(out, "  excites mode %s, no damage %s: %s%s%s\n", r->excites_mode ? "yes" : "no",
          r->no_damage ? "yes" : "no", r->reliable ? "RELIABLE" : "NOT RELIABLE",
          r->reliable ? "" : " - ", reason);
  /* The energy reading is shown, never judged by: the shear criterion above is the verdict. */
  fprintf(out,
          "  damage readings: shear %s (shear / yield %.3f); bruise energy %s (absorbed / "
          "threshold %.3f of %.1f mJ)\n",
          r->no_damage ? "no damage" : "DAMAGE", r->max_shear_stress_pa / r->yield_shear_stress_pa,
          r->below_bruise_energy ? "no bruise" : "BRUISE",
          r->absorbed_energy_j / p->bruise_energy_j, p->bruise_energy_j * 1e3);
}

void af_report_csv_header(FILE *out, const char *param)
{
  fprintf(out,
          "%s,contact_time_s,peak_force_n,max_deformation_m,delivered_restitution,"
          "band_low_hz,band_high_hz,resonance_hz,excitation_at_resonance_db,"
          "max_contact_pressure_pa,max_shear_stress_pa,yield_shear_stress_pa,"
          "min_strike_radius_m,excites_mode,no_damage,reliable,delivered_energy_j,"
          "absorbed_energy_j,below_bruise_energy\n",
          param);
}

void af_report_csv_row(FILE *out, double value, const af_report *rep)
{
  const af_model_result *r = &rep->result;
  fprintf(out,
          "%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%d,%d,%d,"
          "%.10g,%.10g,%d\n",
          value, r->impact.contact_time_s, r->impact.peak_force_n, r->impact.max_deformation_m,
          r->impact.delivered_restitution, r->band_found ? r->band.band_low_hz : NAN,
          r->band_found ? r->band.band_high_hz : NAN, r->resonance_hz,
          r->excitation_at_resonance_db, r->max_contact_pressure_pa, r->max_shear_stress_pa,
          r->yield_shear_stress_pa, rep->min_strike_radius_m, r->excites_mode, r->no_damage,
          r->reliable, r->delivered_energy_j, r->absorbed_energy_j, r->below_bruise_energy);
}
