/* serialize.c — a measured strike as JSON and CSV from one table (see serialize.h). */
#include "serialize.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "json.h"
#include "verdict.h"

#define SR "StrikeReport"
#define REL "Reliability"

/* The fields in the order written. Their values: value_of, by the same index. */
typedef enum {
  F_STAMP_NS,
  F_FRAME_ID,
  F_APPLE_ID,
  F_WITH_AUDIO,
  F_CONTACT_TIME,
  F_PEAK_FORCE,
  F_IMPULSE,
  F_BAND_LOW,
  F_BAND_HIGH,
  F_RESONANCE,
  F_RESONANCE_Q,
  F_SNR_DB,
  F_STIFFNESS_FACTOR,
  F_MODULUS_FROM_RESONANCE,
  F_FITTED_MODULUS,
  F_FITTED_RESTITUTION,
  F_FIT_RESIDUAL,
  F_DELIVERED_ENERGY,
  F_ABSORBED_ENERGY,
  F_DOUBLE_HIT,
  F_CLIPPED,
  F_LOST_SAMPLES,
  F_AUDIO_CLIPPED,
  F_AUDIO_LAG,
  F_AUDIO_LAG_APPLIED,
  F_GRADE_INDEX,
  F_GRADE,
  F_GRADE_REASON,
  F_EXCITES_MODE,
  F_NO_DAMAGE,
  F_RELIABLE,
  F_MAX_SHEAR_STRESS,
  F_YIELD_SHEAR_STRESS,
  F_REASON,
  F_FLAGS,
  F_MODE_METHOD,
  F_MODE_CONFIDENCE,
  F_MODE_AMBIGUOUS,
  F_MODE_TEXT,
  F_TAP_ONLY,
  F_JUDGED_FROM_MODEL,
  F_COUNT
} field_id;

static const af_serial_field fields[F_COUNT] = {
    [F_STAMP_NS] = {"stamp_ns", AF_SERIAL_INT, "ns", SR, "header.stamp",
                    "contact start, since the epoch"},
    [F_FRAME_ID] = {"frame_id", AF_SERIAL_TEXT, "", SR, "header.frame_id",
                    "the force chunk's frame"},
    [F_APPLE_ID] = {"apple_id", AF_SERIAL_INT, "-", SR, "apple_id", "the matched apple; 0 = none"},
    [F_WITH_AUDIO] = {"with_audio", AF_SERIAL_BOOL, "-", NULL, NULL,
                      "an audio window was analysed"},
    [F_CONTACT_TIME] = {"contact_time_s", AF_SERIAL_REAL, "s", SR, "contact_time",
                        "contact time of the fitted impact model (the detector's when the fit "
                        "fails)"},
    [F_PEAK_FORCE] = {"peak_force_n", AF_SERIAL_REAL, "N", SR, "peak_force",
                      "peak force, baseline removed"},
    [F_IMPULSE] = {"impulse_n_s", AF_SERIAL_REAL, "N s", SR, "impulse",
                   "force integrated over the contact"},
    [F_BAND_LOW] = {"band_low_hz", AF_SERIAL_REAL, "Hz", SR, "band_low",
                    "half-power band of the configured lobe of the pulse, low edge"},
    [F_BAND_HIGH] = {"band_high_hz", AF_SERIAL_REAL, "Hz", SR, "band_high",
                     "the same band, high edge"},
    [F_RESONANCE] = {"resonance_hz", AF_SERIAL_REAL, "Hz", SR, "resonance",
                     "0S2 frequency found in the audio"},
    [F_RESONANCE_Q] = {"resonance_q", AF_SERIAL_REAL, "-", SR, "resonance_q", "its quality factor"},
    [F_SNR_DB] = {"snr_db", AF_SERIAL_REAL, "dB", SR, "snr_db", "its peak over the noise per bin"},
    [F_STIFFNESS_FACTOR] = {"stiffness_factor_hz2_kg2_3", AF_SERIAL_REAL, "Hz^2 kg^(2/3)", SR,
                            "stiffness_factor", "resonance^2 mass^(2/3)"},
    [F_MODULUS_FROM_RESONANCE] = {"modulus_from_resonance_pa", AF_SERIAL_REAL, "Pa", SR,
                                  "modulus_from_resonance",
                                  "E2 from the 0S2 (Lamb), divided by the modulus factor"},
    [F_FITTED_MODULUS] = {"fitted_modulus_pa", AF_SERIAL_REAL, "Pa", SR, "fitted_modulus",
                          "E2 of the impact model fitted to the pulse"},
    [F_FITTED_RESTITUTION] = {"fitted_restitution", AF_SERIAL_REAL, "-", SR, "fitted_restitution",
                              "coefficient of restitution of that fit"},
    [F_FIT_RESIDUAL] = {"fit_residual", AF_SERIAL_REAL, "-", SR, "fit_residual",
                        "RMS residual of the fit / peak force"},
    [F_DELIVERED_ENERGY] = {"delivered_energy_j", AF_SERIAL_REAL, "J", SR, "delivered_energy",
                            "the hammer's kinetic energy at contact, m1 v0^2 / 2; NaN: v0 not "
                            "known"},
    [F_ABSORBED_ENERGY] = {"absorbed_energy_j", AF_SERIAL_REAL, "J", SR, "absorbed_energy",
                           "the share the fruit absorbed, (1 - e^2) of it with the fitted e; "
                           "NaN: no fit"},
    [F_DOUBLE_HIT] = {"double_hit", AF_SERIAL_BOOL, "-", SR, "double_hit", "the hammer bounced"},
    [F_CLIPPED] = {"clipped", AF_SERIAL_BOOL, "-", SR, "clipped",
                   "a force sample reached full scale"},
    [F_LOST_SAMPLES] = {"lost_samples", AF_SERIAL_INT, "samples", SR, "lost_samples",
                        "force samples missing around the strike"},
    [F_AUDIO_CLIPPED] = {"audio_clipped", AF_SERIAL_BOOL, "-", SR, "audio_clipped",
                         "the microphone saturated in the strike's audio window"},
    [F_AUDIO_LAG] = {"audio_lag_s", AF_SERIAL_REAL, "s", SR, "audio_lag",
                     "the sound's onset by the audio's stamps minus the contact start; NaN: "
                     "not measured"},
    [F_AUDIO_LAG_APPLIED] = {"audio_lag_applied_s", AF_SERIAL_REAL, "s", SR, "audio_lag_applied",
                             "the audio window was taken this much later (audio_lag_learn)"},
    [F_GRADE_INDEX] = {"grade_index", AF_SERIAL_INT, "-", SR, "grade_index",
                       "firmness class 1..N, softest first; 0 = ungraded"},
    [F_GRADE] = {"grade", AF_SERIAL_TEXT, "", SR, "grade", "the class name, or \"ungraded\""},
    [F_GRADE_REASON] = {"grade_reason", AF_SERIAL_TEXT, "", SR, "grade_reason",
                        "why ungraded; \"\" when graded"},
    [F_EXCITES_MODE] = {"excites_mode", AF_SERIAL_BOOL, "-", REL, "excites_mode",
                        "the resonance lies in the measured band"},
    [F_NO_DAMAGE] = {"no_damage", AF_SERIAL_BOOL, "-", REL, "no_damage",
                     "max shear stress below the yield shear stress"},
    [F_RELIABLE] = {"reliable", AF_SERIAL_BOOL, "-", REL, "reliable", "both, and a clean strike"},
    [F_MAX_SHEAR_STRESS] = {"max_shear_stress_pa", AF_SERIAL_REAL, "Pa", REL, "max_shear_stress",
                            "tau_max from the peak force and the fitted E2"},
    [F_YIELD_SHEAR_STRESS] = {"yield_shear_stress_pa", AF_SERIAL_REAL, "Pa", REL,
                              "yield_shear_stress", "yield shear stress of the fitted E2"},
    [F_REASON] = {"reason", AF_SERIAL_TEXT, "", REL, "reason",
                  "why not reliable; \"\" when reliable"},
    [F_FLAGS] = {"flags", AF_SERIAL_FLAGS, "", NULL, NULL, "the verdict's flags (verdict.h)"},
    [F_MODE_METHOD] = {"mode_method", AF_SERIAL_TEXT, "", NULL, NULL,
                       "how the 0S2 was identified among the peaks (modes.h)"},
    [F_MODE_CONFIDENCE] = {"mode_confidence", AF_SERIAL_REAL, "-", NULL, NULL,
                           "confidence of that identification, [0, 1]"},
    [F_MODE_AMBIGUOUS] = {"mode_ambiguous", AF_SERIAL_BOOL, "-", NULL, NULL,
                          "another peak could be the 0S2"},
    [F_MODE_TEXT] = {"mode_text", AF_SERIAL_TEXT, "", NULL, NULL,
                     "the identification in words; \"\" when none ran"},
    [F_TAP_ONLY] = {"tap_only", AF_SERIAL_BOOL, "-", SR, "tap_only",
                    "measured from the microphone alone (tap_only): no pulse, no fit"},
    [F_JUDGED_FROM_MODEL] = {"judged_from_model", AF_SERIAL_TEXT, "", SR, "judged_from_model",
                             "what the verdict took from the prediction, not a measurement "
                             "(tap-only: excitation, shear); \"\" when none"},
};

typedef struct {
  double real;
  long long integer;
  bool boolean;
  const char *text;
  uint32_t flags;
} value;

static value value_of(const af_serial_strike *s, field_id id)
{
  const af_measure_report *r = s->report;
  value v = {NAN, 0, false, "", 0};
  switch (id) {
  case F_STAMP_NS: v.integer = s->stamp_ns; break;
  case F_FRAME_ID: v.text = s->frame_id; break;
  case F_APPLE_ID: v.integer = s->apple_id; break;
  case F_WITH_AUDIO: v.boolean = s->with_audio; break;
  case F_CONTACT_TIME: v.real = r->contact_time_s; break;
  case F_PEAK_FORCE: v.real = r->peak_force_n; break;
  case F_IMPULSE: v.real = r->impulse_n_s; break;
  case F_BAND_LOW: v.real = r->band_low_hz; break;
  case F_BAND_HIGH: v.real = r->band_high_hz; break;
  case F_RESONANCE: v.real = r->resonance_hz; break;
  case F_RESONANCE_Q: v.real = r->resonance_q; break;
  case F_SNR_DB: v.real = r->snr_db; break;
  case F_STIFFNESS_FACTOR: v.real = r->stiffness_factor; break;
  case F_MODULUS_FROM_RESONANCE: v.real = r->modulus_from_resonance_pa; break;
  case F_FITTED_MODULUS: v.real = r->fitted_modulus_pa; break;
  case F_FITTED_RESTITUTION: v.real = r->fitted_restitution; break;
  case F_FIT_RESIDUAL: v.real = r->fit_residual; break;
  case F_DELIVERED_ENERGY: v.real = r->delivered_energy_j; break;
  case F_ABSORBED_ENERGY: v.real = r->absorbed_energy_j; break;
  case F_DOUBLE_HIT: v.boolean = r->double_hit; break;
  case F_CLIPPED: v.boolean = r->clipped; break;
  case F_LOST_SAMPLES: v.integer = r->lost_samples; break;
  case F_AUDIO_CLIPPED: v.boolean = r->audio_clipped; break;
  case F_AUDIO_LAG: v.real = r->audio_lag_s; break;
  case F_AUDIO_LAG_APPLIED: v.real = r->audio_lag_applied_s; break;
  case F_GRADE_INDEX: v.integer = s->grade->index; break;
  case F_GRADE: v.text = s->grade->name; break;
  case F_GRADE_REASON: v.text = s->grade->reason; break;
  case F_EXCITES_MODE: v.boolean = r->excites_mode; break;
  case F_NO_DAMAGE: v.boolean = r->no_damage; break;
  case F_RELIABLE: v.boolean = r->reliable; break;
  case F_MAX_SHEAR_STRESS: v.real = r->max_shear_stress_pa; break;
  case F_YIELD_SHEAR_STRESS: v.real = r->yield_shear_stress_pa; break;
  case F_REASON: v.text = r->reason; break;
  case F_FLAGS: v.flags = r->verdict.flags; break;
  case F_MODE_METHOD: v.text = af_modes_method_name(r->modes.method); break;
  case F_MODE_CONFIDENCE: v.real = r->modes.confidence; break;
  case F_MODE_AMBIGUOUS: v.boolean = r->modes.ambiguous; break;
  case F_MODE_TEXT: v.text = r->modes_text; break;
  case F_TAP_ONLY: v.boolean = r->tap_only; break;
  case F_JUDGED_FROM_MODEL: v.text = r->model_only_text; break;
  case F_COUNT: break;
  }
  return v;
}

af_serial_strike af_serial_of_lane(const af_lane_strike *s)
{
  af_serial_strike v = {s->start_ns,   s->frame_id, s->apple_id,
                        s->with_audio, &s->report,  &s->grade};
  return v;
}

const af_serial_field *af_serial_fields(size_t *n)
{
  if (n)
    *n = F_COUNT;
  return fields;
}

const char *af_serial_kind_name(af_serial_kind kind)
{
  switch (kind) {
  case AF_SERIAL_REAL: return "real";
  case AF_SERIAL_INT: return "integer";
  case AF_SERIAL_BOOL: return "boolean";
  case AF_SERIAL_TEXT: return "text";
  case AF_SERIAL_FLAGS: return "flags";
  }
  return "?";
}

void af_serialize_fields_markdown(FILE *out)
{
  fputs("| field | type | unit | message field | meaning |\n|---|---|---|---|---|\n", out);
  for (int k = 0; k < F_COUNT; k++) {
    const af_serial_field *f = &fields[k];
    fprintf(out, "| `%s` | %s | %s | ", f->name, af_serial_kind_name(f->kind), f->unit);
    if (f->message)
      fprintf(out, "%s.%s", f->message, f->message_field);
    else
      fputs("report-only", out);
    fprintf(out, " | %s |\n", f->meaning);
  }
}

/* A JSON string, or null for NULL. */
static void json_text_or_null(FILE *out, const char *text)
{
  if (text)
    af_json_string(out, text);
  else
    fputs("null", out);
}

void af_serialize_fields_json(FILE *out)
{
  fputs("[\n", out);
  for (int k = 0; k < F_COUNT; k++) {
    const af_serial_field *f = &fields[k];
    fputs("  {\"name\": ", out);
    af_json_string(out, f->name);
    fprintf(out, ", \"type\": \"%s\", \"unit\": ", af_serial_kind_name(f->kind));
    af_json_string(out, f->unit);
    fputs(", \"message\": ", out);
    json_text_or_null(out, f->message);
    fputs(", \"message_field\": ", out);
    json_text_or_null(out, f->message_field);
    fputs(", \"meaning\": ", out);
    af_json_string(out, f->meaning);
    fprintf(out, "}%s\n", k + 1 < F_COUNT ? "," : "");
  }
  fputs("]\n", out);
}

void af_serialize_flags(FILE *out, uint32_t flags, const char *sep)
{
  const char *between = "";
  for (uint32_t bit = 1; bit != 0; bit <<= 1)
    if (flags & bit) {
      fprintf(out, "%s%s", between, af_verdict_flag_name((af_verdict_flag)bit));
      between = sep;
    }
}

void af_serialize_real(FILE *out, double x)
{
  char text[32];
  for (int digits = 15; digits <= 17; digits++) {
    snprintf(text, sizeof text, "%.*g", digits, x);
    if (digits == 17 || strtod(text, NULL) == x)
      break;
  }
  fputs(text, out);
}

void af_serialize_json_members(FILE *out, const af_serial_strike *s, const char *sep)
{
  for (int k = 0; k < F_COUNT; k++) {
    const value v = value_of(s, (field_id)k);
    fprintf(out, "%s\"%s\": ", k ? sep : "", fields[k].name);
    switch (fields[k].kind) {
    case AF_SERIAL_REAL:
      if (isfinite(v.real))
        af_serialize_real(out, v.real);
      else
        fputs("null", out);
      break;
    case AF_SERIAL_INT: fprintf(out, "%lld", v.integer); break;
    case AF_SERIAL_BOOL: fputs(v.boolean ? "true" : "false", out); break;
    case AF_SERIAL_TEXT: af_json_string(out, v.text ? v.text : ""); break;
    case AF_SERIAL_FLAGS: af_json_flags(out, v.flags); break;
    }
  }
}

void af_serialize_json(FILE *out, const af_serial_strike *s)
{
  fputc('{', out);
  af_serialize_json_members(out, s, ", ");
  fputc('}', out);
}

void af_serialize_csv_header(FILE *out)
{
  for (int k = 0; k < F_COUNT; k++)
    fprintf(out, "%s%s", k ? "," : "", fields[k].name);
}

void af_serialize_csv_text(FILE *out, const char *text)
{
  fputc('"', out);
  for (const char *c = text; *c; c++) {
    if (*c == '"')
      fputc('"', out);
    fputc(*c, out);
  }
  fputc('"', out);
}

void af_serialize_csv_row(FILE *out, const af_serial_strike *s)
{
  for (int k = 0; k < F_COUNT; k++) {
    const value v = value_of(s, (field_id)k);
    if (k)
      fputc(',', out);
    switch (fields[k].kind) {
    case AF_SERIAL_REAL:
      if (isfinite(v.real))
        af_serialize_real(out, v.real);
      break;
    case AF_SERIAL_INT: fprintf(out, "%lld", v.integer); break;
    case AF_SERIAL_BOOL: fputc(v.boolean ? '1' : '0', out); break;
    case AF_SERIAL_TEXT: af_serialize_csv_text(out, v.text ? v.text : ""); break;
    case AF_SERIAL_FLAGS:
      fputc('"', out);
      af_serialize_flags(out, v.flags, "|");
      fputc('"', out);
      break;
    }
  }
}
