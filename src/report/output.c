/* output.c — text, JSON and CSV of a session (see output.h). */
#include "json.h"
#include "merge_state.h"
#include "output.h"
#include "serialize.h"

#include <inttypes.h>
#include <math.h>
#include <string.h>

/* ---- text ----------------------------------------------------------------------- */

/* A number in a fixed width, "-" when not finite. */
static void cell(FILE *out, const char *fmt, int width, double v)
{
  if (isfinite(v))
    fprintf(out, fmt, width, v);
  else
    fprintf(out, "%*s", width, "-");
}

static void text_strike(FILE *out, const af_session_strike *r)
{
  const af_measure_report *q = &r->report;
  fprintf(out, "%5" PRIu32 " %17.6f ", r->apple_id, (double)r->start_ns * 1e-9);
  cell(out, "%*.1f", 6, r->mass_kg * 1e3);
  if (r->predicted)
    fprintf(out, " %5.0f-%-5.0f %-8s", r->predicted_band_low_hz, r->predicted_band_high_hz,
            r->predicted_reliable ? "reliable" : "NOT");
  else
    fprintf(out, " %11s %-8s", "-", r->has_apple ? "refused" : "no apple");
  fputs(" |", out);
  cell(out, "%*.1f", 7, q->resonance_hz);
  cell(out, "%*.1f", 6, q->resonance_q);
  cell(out, "%*.1f", 6, q->snr_db);
  cell(out, "%*.4g", 10, q->stiffness_factor);
  cell(out, "%*.2f", 7, q->modulus_from_resonance_pa * 1e-6);
  cell(out, "%*.2f", 7, q->fitted_modulus_pa * 1e-6);
  cell(out, "%*.3f", 6, q->fitted_restitution);
  cell(out, "%*.3f", 7, q->contact_time_s * 1e3);
  cell(out, "%*.2f", 7, q->peak_force_n);
  fprintf(out, " | %2u %-10s |", r->grade.index, r->grade.name);
  if (q->reliable) {
    /* A reliable strike is ungraded only for a reason of the grading's own. */
    fprintf(out, " reliable%s%s\n", r->grade.index ? "" : "; ungraded: ", r->grade.reason);
    return;
  }
  fputs(" NOT reliable [", out);
  af_serialize_flags(out, q->verdict.flags, "|");
  fprintf(out, "]: %s\n", q->reason);
}

/* The modulus factor the lane learned on the line (factor_learn.h). */
static void text_learned(FILE *out, const af_factor_learn_state *f)
{
  if (isnan(f->estimate))
    fprintf(out,
            "  modulus_factor learned on the line: none yet (%zu reliable strikes), "
            "applied %.4f\n",
            f->n, f->applied);
  else
    fprintf(out,
            "  modulus_factor learned on the line: %.4f (95 %% interval %.4f-%.4f, the newest "
            "%zu reliable strikes); applied %.4f after %llu changes\n",
            f->estimate, f->ci_low_95, f->ci_high_95, f->n, f->applied,
            (unsigned long long)f->changes);
}

static void text_quantiles(FILE *out, const char *name, const af_quantiles *q, double scale,
                           const char *fmt)
{
  fprintf(out, "  %-34s %5zu ", name, q->n);
  for (int k = 0; k < AF_SUMMARY_QUANTILES; k++)
    cell(out, fmt, 9, q->q[k] * scale);
  fputc('\n', out);
}

static void text_stream(FILE *out, const char *name, const af_session_stream *s)
{
  fprintf(out,
          "  %-5s %8" PRIu64 " chunks, %" PRIu64 " gaps (%" PRIu64 " samples lost), %" PRIu64
          " restarts, %" PRIu64 " duplicates, %" PRIu64 " overlaps (%" PRIu64
          " samples sent twice), %" PRIu64 " refused (rate %" PRIu64 ", unit %" PRIu64
          ", index %" PRIu64 ", malformed %" PRIu64 ", oversized %" PRIu64 "), %" PRIu64
          " non-finite samples refused in %" PRIu64 " spans\n",
          name, s->chunks, s->gaps, s->lost_samples, s->restarts, s->duplicates, s->overlaps,
          s->duplicate_samples,
          s->bad_rate + s->bad_unit + s->bad_index + s->malformed + s->oversized, s->bad_rate,
          s->bad_unit, s->bad_index, s->malformed, s->oversized, s->refused_samples,
          s->refused_spans);
  if (s->clock_steps + s->clock_frozen > 0 || s->clock_rate_wrong)
    fprintf(out, "  WARN %s clock: %" PRIu64 " steps, %" PRIu64 " frozen chunks; last: %s\n", name,
            s->clock_steps, s->clock_frozen, s->clock_problem);
}

static double share(size_t part, size_t whole)
{
  return whole ? 100.0 * (double)part / (double)whole : 0.0;
}

void af_output_text_strikes(FILE *out, const af_session *s, const af_stage_hook *timer)
{
  fprintf(out, "%5s %17s %6s %-11s %-8s |%7s %6s %6s %10s %7s %7s %6s %7s %7s | %-13s | %s\n",
          "apple", "contact start [s]", "m [g]", "pred. band", "pred.", "0S2", "Q", "SNR", "S",
          "E(0S2)", "E2 fit", "e", "t_c", "F_max", "grade", "measured verdict [flags]");
  fprintf(out, "%5s %17s %6s %-11s %-8s |%7s %6s %6s %10s %7s %7s %6s %7s %7s | %-13s |\n", "", "",
          "", "[Hz]", "verdict", "[Hz]", "", "[dB]", "[Hz2kg^2/3]", "[MPa]", "[MPa]", "", "[ms]",
          "[N]", "index name");
  for (size_t k = 0; k < s->n_strikes; k++) {
    const int64_t t0_ns = af_stage_begin(timer);
    text_strike(out, &s->strikes[k]);
    af_stage_end(timer, AF_STAGE_SERIALIZE, t0_ns);
  }
  size_t without = 0;
  for (size_t k = 0; k < s->n_apples; k++)
    without += s->apples[k].strikes == 0;
  if (without > 0) {
    fprintf(out, "apples without a strike (%zu):", without);
    for (size_t k = 0; k < s->n_apples; k++)
      if (s->apples[k].strikes == 0)
        fprintf(out, " %" PRIu32, s->apples[k].apple_id);
    fputc('\n', out);
  }
}

/* "strike N" or "never" of a first warning. */
static const char *first_at(uint64_t strike, char *buf, size_t len)
{
  if (strike == 0)
    return "never";
  snprintf(buf, len, "strike %" PRIu64, strike);
  return buf;
}

/* The hammer health at the end of the session (hammer_health.h): the last
 * window's figures with their limits, and when each check first warned. */
static void text_health(FILE *out, const af_session *s)
{
  const af_hammer_health_stats *h = &s->stats.health;
  const af_hammer_health_config *c = &s->health_cfg;
  char b[3][32];
  if (h->strikes == 0)
    return; /* no strike, or a combined summary (per bag only) */
  fprintf(out, "  hammer health (the last %zu strikes): %s%s\n", h->window_strikes,
          h->warnings ? "WARN: " : "OK", h->text);
  fprintf(
      out,
      "    contact velocity %.4f m/s from the impulse (SD %.4f over %zu clean strikes; %+.2f %% "
      "of strike_velocity_m_s %.4g, band +- %.1f %%)\n",
      h->velocity_m_s, h->velocity_sd_m_s, h->velocity_strikes, 100.0 * h->velocity_deviation,
      c->velocity_m_s, 100.0 * c->velocity_band);
  if (h->fit_velocity_strikes > 0)
    fprintf(out, "    contact velocity fitted to the pulse %.4f m/s (mean of %zu strikes)\n",
            h->fit_velocity_m_s, h->fit_velocity_strikes);
  else
    fprintf(out, "    contact velocity not fitted (measure_fit_velocity false, or no fit)\n");
  fprintf(out,
          "    delivered restitution %.3f fitted (%zu strikes; cultivar's %.3f); baseline %.4f N "
          "(reference %.4f, drift %+.4f, limit %.4g N); noise %.4f N RMS\n",
          h->restitution, h->restitution_strikes, c->restitution, h->baseline_n,
          h->baseline_reference_n, h->baseline_drift_n, c->baseline_drift_limit_n, h->noise_rms_n);
  fprintf(
      out,
      "    peak force mean %.3f N, SD %.3f, %.3f .. %.3f; clipping %zu of %zu strikes (%.1f %%, "
      "limit %.1f %%)\n",
      h->peak_force_n, h->peak_force_sd_n, h->peak_force_min_n, h->peak_force_max_n,
      h->clipped_strikes, h->window_strikes, 100.0 * h->clip_rate, 100.0 * c->clip_rate_limit);
  fprintf(out,
          "    first warned: velocity %s, baseline %s, clipping %s (warned after %" PRIu64
          " of %" PRIu64 " strikes)\n",
          first_at(h->first_warning_strike[0], b[0], sizeof b[0]),
          first_at(h->first_warning_strike[1], b[1], sizeof b[1]),
          first_at(h->first_warning_strike[2], b[2], sizeof b[2]), h->warned_strikes, h->strikes);
}

/* The apples' transit from the camera to the hammer, as observed, and the
 * estimates refused before any match. */
static void text_transit(FILE *out, const af_lane_stats *st)
{
  if (st->transit_strikes > 0)
    fprintf(out,
            "  apple transit: %.1f ms from estimate to strike (median of the latest %zu matched "
            "strikes)\n",
            1e3 * st->transit_observed_s, st->transit_strikes);
  else
    fprintf(out, "  apple transit: no strike matched to an estimate\n");
  if (st->transit_warning[0] != '\0')
    fprintf(out, "  WARN apple estimates: %s\n", st->transit_warning);
  if (st->lag_strikes > 0)
    fprintf(out,
            "  audio lag: %.2f ms median (MAD %.2f ms over the latest %zu strikes), windows moved "
            "%.2f ms; onset not found in %" PRIu64 " strikes\n",
            1e3 * st->lag_median_s, 1e3 * st->lag_mad_s, st->lag_strikes, 1e3 * st->lag_applied_s,
            st->lag_no_onset);
  if (st->lag_moves > 0)
    fprintf(out, "  WARN audio lag moved %" PRIu64 " times (last: %s)\n", st->lag_moves,
            st->lag_warning);
  if (st->clock_faulted > 0)
    fprintf(out,
            "  WARN %" PRIu64 " strikes judged across a stream's clock fault (flag clock_fault)\n",
            st->clock_faulted);
  if (st->audio_clipped > 0)
    fprintf(out, "  WARN microphone clipped on %" PRIu64 " strikes: lower the microphone gain\n",
            st->audio_clipped);
  if (st->apples_skipped > 0)
    fprintf(out, "  WARN apple estimates that never came: %" PRIu64 " (last: %s)\n",
            st->apples_skipped, st->last_apples_skipped);
  if (st->apples_implausible > 0)
    fprintf(out, "  WARN apple estimates refused: %" PRIu64 " (last: %s)\n", st->apples_implausible,
            st->last_implausible_apple);
}

void af_output_text_summary(FILE *out, const af_session *s, const af_summary *m)
{
  fprintf(out, "\nsummary\n");
  fprintf(out,
          "  strikes %zu: %zu on an apple, %zu without apple, %zu without audio, %zu doubtful "
          "matches\n",
          m->strikes, m->with_apple, m->without_apple, m->without_audio, m->doubtful);
  fprintf(out, "  apples %zu: %zu refused, %zu without a strike, %zu predicted reliable\n",
          m->apples, m->apples_refused, m->apples_without_strike, m->apples_predicted_reliable);
  fprintf(out, "  reliable (measured): %zu of %zu strikes (%.1f %%)\n", m->reliable, m->strikes,
          share(m->reliable, m->strikes));
  if (m->reliable < m->strikes)
    fprintf(out, "  not reliable, by reason (a strike may have several):\n");
  for (unsigned b = 0; b < AF_SUMMARY_FLAGS; b++)
    if (m->by_flag[b])
      fprintf(out, "    %-18s %6zu (%.1f %% of strikes)\n",
              af_verdict_flag_name((af_verdict_flag)(1u << b)), m->by_flag[b],
              share(m->by_flag[b], m->strikes));
  for (unsigned c = 0; c < AF_SUMMARY_AUDIO_CAUSES; c++)
    if (m->by_audio_cause[c])
      fprintf(out, "    no audio: %-30s %zu\n", af_audio_cause_name((af_audio_cause)c),
              m->by_audio_cause[c]);
  fprintf(out, "  firmness, quantiles over the strikes %5s ", "n");
  for (int k = 0; k < AF_SUMMARY_QUANTILES; k++)
    fprintf(out, "%8.0f%%", af_summary_levels[k] * 100.0);
  fputc('\n', out);
  text_quantiles(out, "0S2 [Hz]", &m->resonance_hz, 1.0, "%*.1f");
  text_quantiles(out, "modulus from the 0S2 [MPa]", &m->modulus_from_resonance_pa, 1e-6, "%*.3f");
  text_quantiles(out, "fitted E2 [MPa]", &m->fitted_modulus_pa, 1e-6, "%*.3f");
  text_quantiles(out, "stiffness factor [Hz^2 kg^(2/3)]", &m->stiffness_factor, 1.0, "%*.0f");
  text_quantiles(out, "E(0S2) / fitted E2 [-]", &m->modulus_ratio, 1.0, "%*.4f");
  if (m->modulus_ratio.n > 0)
    fprintf(out,
            "  modulus agreement: E(0S2) / fitted E2 median %.4f, spread %.2f %% (1.4826 MAD), "
            "p10-p90 %.4f-%.4f over %zu strikes;\n"
            "    modulus_factor should be %.4f (run with %.4f)\n",
            m->modulus_ratio.q[3], 100.0 * m->modulus_ratio_spread, m->modulus_ratio.q[1],
            m->modulus_ratio.q[5], m->modulus_ratio.n, m->modulus_factor_suggested,
            m->modulus_factor_now);
  else
    fprintf(out, "  modulus agreement: no strike has both moduli\n");
  text_learned(out, &m->factor_learned);
  fprintf(out, "  streams (recorded %.1f s of %s):\n", s->recorded_s,
          s->tap_only ? "audio, tap-only" : "force");
  text_stream(out, "force", &s->force);
  text_stream(out, "audio", &s->audio);
  fprintf(out,
          "  lane: %" PRIu64 " strike queue overflows, %" PRIu64
          " estimates after their strike, %" PRIu64 " strike pulses cut\n",
          s->stats.overflows, s->stats.late_apples, s->stats.pulse_cut);
  text_transit(out, &s->stats);
  text_health(out, s);
  fprintf(out,
          "  bag: %" PRIu64 " messages read, %" PRIu64
          " refused (oversized or not their type; %" PRIu64 " of them apples)\n",
          s->messages, s->refused_messages, s->refused_apples);
}

void af_output_text(FILE *out, const af_session *s, const af_summary *m, const af_stage_hook *timer)
{
  af_output_text_strikes(out, s, timer);
  af_output_text_summary(out, s, m);
}

/* ---- JSON ----------------------------------------------------------------------- */

static void json_num(FILE *out, const char *key, double v)
{
  fprintf(out, "\"%s\": ", key);
  if (isfinite(v))
    af_serialize_real(out, v); /* the strike's own format */
  else
    fputs("null", out);
  fputs(", ", out);
}

/* The modulus factor the lane learned on the line (factor_learn.h). */
static void json_learned(FILE *out, const af_factor_learn_state *f)
{
  json_num(out, "modulus_factor_learned", f->estimate);
  json_num(out, "modulus_factor_learned_ci95_low", f->ci_low_95);
  json_num(out, "modulus_factor_learned_ci95_high", f->ci_high_95);
  fprintf(out, "\"modulus_factor_learned_strikes\": %zu, ", f->n);
  fprintf(out, "\"modulus_factor_learned_refused\": %llu, ", (unsigned long long)f->refused);
  json_num(out, "modulus_factor_applied", f->applied);
  fprintf(out, "\"modulus_factor_changes\": %llu,", (unsigned long long)f->changes);
}

/* The strike's fields (serialize.h), then what the station knew of its apple. */
static void json_strike(FILE *out, const af_session_strike *r, bool last)
{
  const af_serial_strike v = af_session_serial(r);
  fputs("    {", out);
  af_serialize_json_members(out, &v, ", ");
  if (r->has_apple)
    fprintf(out, ", \"apple_stamp_ns\": %" PRId64 ", ", r->apple_stamp_ns);
  else
    fputs(", \"apple_stamp_ns\": null, ", out);
  json_num(out, "mass_kg", r->mass_kg);
  fputs("\"predicted\": ", out);
  if (r->predicted) {
    fputc('{', out);
    json_num(out, "band_low_hz", r->predicted_band_low_hz);
    json_num(out, "band_high_hz", r->predicted_band_high_hz);
    json_num(out, "resonance_hz", r->predicted_resonance_hz);
    fprintf(out, "\"reliable\": %s, \"reason\": ", r->predicted_reliable ? "true" : "false");
    af_json_string(out, r->predicted_reason);
    fputc('}', out);
  } else
    fputs("null", out);
  fprintf(out, "}%s\n", last ? "" : ",");
}

static void json_quantiles(FILE *out, const char *key, const af_quantiles *q, bool last)
{
  fprintf(out, "    \"%s\": {\"n\": %zu, \"q\": [", key, q->n);
  for (int k = 0; k < AF_SUMMARY_QUANTILES; k++) {
    if (isfinite(q->q[k]))
      fprintf(out, "%.10g", q->q[k]);
    else
      fputs("null", out);
    fputs(k + 1 < AF_SUMMARY_QUANTILES ? ", " : "", out);
  }
  fprintf(out, "]}%s\n", last ? "" : ",");
}

static void json_stream(FILE *out, const char *key, const af_session_stream *s)
{
  fprintf(out,
          "    \"%s\": {\"chunks\": %" PRIu64 ", \"gaps\": %" PRIu64 ", \"lost_samples\": %" PRIu64
          ", \"restarts\": %" PRIu64 ", \"bad_rate\": %" PRIu64 ", \"bad_unit\": %" PRIu64
          ", \"bad_index\": %" PRIu64 ", \"malformed\": %" PRIu64 ", \"oversized\": %" PRIu64
          ", \"duplicates\": %" PRIu64 ", \"overlaps\": %" PRIu64
          ", \"duplicate_samples\": %" PRIu64 ", \"refused_samples\": %" PRIu64
          ", \"refused_spans\": %" PRIu64 "},\n",
          key, s->chunks, s->gaps, s->lost_samples, s->restarts, s->bad_rate, s->bad_unit,
          s->bad_index, s->malformed, s->oversized, s->duplicates, s->overlaps,
          s->duplicate_samples, s->refused_samples, s->refused_spans);
}

/* A first warning's strike number, null for never. */
static void json_first(FILE *out, const char *key, uint64_t strike, const char *sep)
{
  if (strike == 0)
    fprintf(out, "\"%s\": null%s", key, sep);
  else
    fprintf(out, "\"%s\": %" PRIu64 "%s", key, strike, sep);
}

/* "    \"hammer_health\": {...},\n" (hammer_health.h): the last window's
 * figures, the limits, the first warnings, each strike's v0 from its impulse
 * (velocity_m_s_per_strike, null where not clean); nothing in a combined summary. */
static void json_health(FILE *out, const af_session *s)
{
  const af_hammer_health_stats *h = &s->stats.health;
  const af_hammer_health_config *c = &s->health_cfg;
  if (h->strikes == 0)
    return;
  fprintf(out,
          "    \"hammer_health\": {\"status\": \"%s\", \"text\": ", h->warnings ? "warn" : "ok");
  af_json_string(out, h->text);
  fprintf(out, ", \"strikes\": %" PRIu64 ", \"window_strikes\": %zu, ", h->strikes,
          h->window_strikes);
  json_num(out, "velocity_m_s", h->velocity_m_s);
  json_num(out, "velocity_sd_m_s", h->velocity_sd_m_s);
  fprintf(out, "\"velocity_strikes\": %zu, ", h->velocity_strikes);
  json_num(out, "velocity_deviation", h->velocity_deviation);
  json_num(out, "velocity_set_m_s", c->velocity_m_s);
  json_num(out, "velocity_band", c->velocity_band);
  json_num(out, "fit_velocity_m_s", h->fit_velocity_m_s);
  json_num(out, "restitution", h->restitution);
  json_num(out, "restitution_set", c->restitution);
  json_num(out, "baseline_n", h->baseline_n);
  json_num(out, "baseline_reference_n", h->baseline_reference_n);
  json_num(out, "baseline_drift_n", h->baseline_drift_n);
  json_num(out, "baseline_drift_limit_n", c->baseline_drift_limit_n);
  json_num(out, "noise_rms_n", h->noise_rms_n);
  json_num(out, "peak_force_n", h->peak_force_n);
  json_num(out, "peak_force_sd_n", h->peak_force_sd_n);
  json_num(out, "peak_force_min_n", h->peak_force_min_n);
  json_num(out, "peak_force_max_n", h->peak_force_max_n);
  fprintf(out, "\"clipped_strikes\": %zu, ", h->clipped_strikes);
  json_num(out, "clip_rate", h->clip_rate);
  json_num(out, "clip_rate_limit", c->clip_rate_limit);
  fputs("\"first_warning_strike\": {", out);
  json_first(out, "velocity", h->first_warning_strike[0], ", ");
  json_first(out, "baseline", h->first_warning_strike[1], ", ");
  json_first(out, "clipping", h->first_warning_strike[2], "");
  fprintf(out, "}, \"warned_strikes\": %" PRIu64 ", \"velocity_m_s_per_strike\": [",
          h->warned_strikes);
  for (size_t k = 0; k < s->n_strikes; k++) { /* each strike's v0 from its impulse */
    const double v = s->strikes[k].hammer_velocity_m_s;
    fputs(k ? ", " : "", out);
    if (isfinite(v))
      fprintf(out, "%.6f", v);
    else
      fputs("null", out);
  }
  fputs("]},\n", out);
}

/* "  \"summary\": {...}" (no newline after its closing brace). */
static void json_summary(FILE *out, const af_session *s, const af_summary *m)
{
  bool first = true;
  fputs("  \"summary\": {\n", out);
  fprintf(out,
          "    \"strikes\": %zu, \"reliable\": %zu, \"with_apple\": %zu, \"without_apple\": %zu, "
          "\"without_audio\": %zu, \"doubtful\": %zu,\n",
          m->strikes, m->reliable, m->with_apple, m->without_apple, m->without_audio, m->doubtful);
  fprintf(out,
          "    \"apples\": %zu, \"apples_refused\": %zu, \"apples_without_strike\": %zu, "
          "\"apples_predicted_reliable\": %zu,\n",
          m->apples, m->apples_refused, m->apples_without_strike, m->apples_predicted_reliable);
  fputs("    \"unreliable_by_reason\": {", out);
  for (unsigned b = 0; b < AF_SUMMARY_FLAGS; b++)
    if (m->by_flag[b]) {
      fprintf(out, "%s\"%s\": %zu", first ? "" : ", ",
              af_verdict_flag_name((af_verdict_flag)(1u << b)), m->by_flag[b]);
      first = false;
    }
  fputs("},\n    \"quantile_levels\": [0, 0.1, 0.25, 0.5, 0.75, 0.9, 1],\n", out);
  json_quantiles(out, "resonance_hz", &m->resonance_hz, false);
  json_quantiles(out, "modulus_from_resonance_pa", &m->modulus_from_resonance_pa, false);
  json_quantiles(out, "fitted_modulus_pa", &m->fitted_modulus_pa, false);
  json_quantiles(out, "stiffness_factor_hz2_kg2_3", &m->stiffness_factor, false);
  json_quantiles(out, "modulus_ratio", &m->modulus_ratio, false);
  fputs("    ", out);
  json_num(out, "modulus_ratio_spread", m->modulus_ratio_spread);
  json_num(out, "modulus_factor_now", m->modulus_factor_now);
  json_num(out, "modulus_factor_suggested", m->modulus_factor_suggested);
  fputs("\n    ", out);
  json_learned(out, &m->factor_learned);
  fputc('\n', out);
  json_stream(out, "force", &s->force);
  json_stream(out, "audio", &s->audio);
  json_health(out, s);
  fprintf(out,
          "    \"recorded_s\": %.9g, \"messages\": %" PRIu64 ", \"refused_messages\": %" PRIu64
          ", \"refused_apples\": %" PRIu64 "\n  }",
          s->recorded_s, s->messages, s->refused_messages, s->refused_apples);
}

void af_output_json(FILE *out, const char *bag, const char *ns, const af_session *s,
                    const af_summary *m, const af_settings *settings, const af_stage_hook *timer)
{
  fputs("{\n  \"bag\": ", out);
  af_json_string(out, bag);
  fputs(",\n  \"ns\": ", out);
  af_json_string(out, ns);
  fputs(",\n  \"strikes\": [\n", out);
  for (size_t k = 0; k < s->n_strikes; k++) {
    const int64_t t0_ns = af_stage_begin(timer);
    json_strike(out, &s->strikes[k], k + 1 == s->n_strikes);
    af_stage_end(timer, AF_STAGE_SERIALIZE, t0_ns);
  }
  fputs("  ],\n  \"apples_without_strike\": [", out);
  bool first = true;
  for (size_t k = 0; k < s->n_apples; k++)
    if (s->apples[k].strikes == 0) {
      fprintf(out, "%s%" PRIu32, first ? "" : ", ", s->apples[k].apple_id);
      first = false;
    }
  fputs("],\n", out);
  json_summary(out, s, m);
  fputs(",\n  ", out);
  af_merge_state_write(out, s, m, settings);
  fputs("\n}\n", out);
}

void af_output_json_failed(FILE *out, const char *bag, const char *error)
{
  fputs("{\n  \"bag\": ", out);
  af_json_string(out, bag);
  fputs(",\n  \"error\": ", out);
  af_json_string(out, error);
  fputs("\n}\n", out);
}

void af_output_json_combined(FILE *out, size_t bags, size_t failed, const af_session *totals,
                             const af_summary *m)
{
  fprintf(out, "{\n  \"bags\": %zu,\n  \"failed\": %zu,\n", bags, failed);
  json_summary(out, totals, m);
  fputs("\n}", out);
}

/* ---- CSV ------------------------------------------------------------------------ */

static void csv_num(FILE *out, double v, bool last)
{
  if (isfinite(v))
    af_serialize_real(out, v);
  fputc(last ? '\n' : ',', out);
}

void af_output_csv_header(FILE *out, bool with_bag)
{
  if (with_bag)
    fputs("bag,", out);
  af_serialize_csv_header(out);
  fputs(",apple_stamp_ns,mass_kg,predicted_band_low_hz,predicted_band_high_hz,"
        "predicted_resonance_hz,predicted_reliable\n",
        out);
}

void af_output_csv_rows(FILE *out, const af_session *s, const char *bag, const af_stage_hook *timer)
{
  for (size_t k = 0; k < s->n_strikes; k++) {
    const int64_t t0_ns = af_stage_begin(timer);
    const af_session_strike *r = &s->strikes[k];
    const af_serial_strike v = af_session_serial(r);
    if (bag) {
      af_serialize_csv_text(out, bag);
      fputc(',', out);
    }
    af_serialize_csv_row(out, &v);
    fputc(',', out);
    if (r->has_apple)
      fprintf(out, "%" PRId64, r->apple_stamp_ns);
    fputc(',', out);
    csv_num(out, r->mass_kg, false);
    csv_num(out, r->predicted_band_low_hz, false);
    csv_num(out, r->predicted_band_high_hz, false);
    csv_num(out, r->predicted_resonance_hz, false);
    fprintf(out, "%s\n", r->predicted ? (r->predicted_reliable ? "1" : "0") : "");
    af_stage_end(timer, AF_STAGE_SERIALIZE, t0_ns);
  }
}
