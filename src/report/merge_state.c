/* merge_state.c — a bag's merge state written into its JSON report and
 * read back (see merge_state.h). */
#include "merge_state.h"

#include <inttypes.h>
#include <math.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include "json.h"
#include "snapshot_text.h"

typedef enum { F_U64, F_SIZE, F_F64, F_BOOL, F_TEXT } field_kind;

typedef struct {
  const char *name;
  field_kind kind;
  size_t offset, size; /* in its struct; size: F_TEXT's array */
} field;

#define SU(n, m)                                                                                   \
  {                                                                                                \
    n, F_SIZE, offsetof(af_summary, m), 0                                                          \
  }
#define SF(n, m)                                                                                   \
  {                                                                                                \
    n, F_F64, offsetof(af_summary, m), 0                                                           \
  }
#define SL(n, m)                                                                                   \
  {                                                                                                \
    n, F_U64, offsetof(af_summary, m), 0                                                           \
  }

/* af_summary: what af_combined adds up (the rest it computes again). */
static const field summary_fields[] = {
    SU("strikes", strikes),
    SU("reliable", reliable),
    SU("with_apple", with_apple),
    SU("without_apple", without_apple),
    SU("without_audio", without_audio),
    SU("doubtful", doubtful),
    SU("apples", apples),
    SU("apples_refused", apples_refused),
    SU("apples_without_strike", apples_without_strike),
    SU("apples_predicted_reliable", apples_predicted_reliable),
    SF("modulus_factor_now", modulus_factor_now),
    SU("factor_learned.n", factor_learned.n),
    SL("factor_learned.taken", factor_learned.taken),
    SL("factor_learned.refused", factor_learned.refused),
    SF("factor_learned.estimate", factor_learned.estimate),
    SF("factor_learned.ci_low_95", factor_learned.ci_low_95),
    SF("factor_learned.ci_high_95", factor_learned.ci_high_95),
    SF("factor_learned.applied", factor_learned.applied),
    SF("factor_learned.previous", factor_learned.previous),
    SL("factor_learned.changes", factor_learned.changes),
};

#define EU(n, m)                                                                                   \
  {                                                                                                \
    n, F_U64, offsetof(af_session, m), 0                                                           \
  }
#define EZ(n, m)                                                                                   \
  {                                                                                                \
    n, F_SIZE, offsetof(af_session, m), 0                                                          \
  }
#define EF(n, m)                                                                                   \
  {                                                                                                \
    n, F_F64, offsetof(af_session, m), 0                                                           \
  }
#define EB(n, m)                                                                                   \
  {                                                                                                \
    n, F_BOOL, offsetof(af_session, m), 0                                                          \
  }
#define ET(n, m)                                                                                   \
  {                                                                                                \
    n, F_TEXT, offsetof(af_session, m), sizeof(((af_session *)0)->m)                               \
  }
#define STREAM(p, m)                                                                               \
  EU(p ".chunks", m.chunks), EU(p ".gaps", m.gaps), EU(p ".lost_samples", m.lost_samples),         \
      EU(p ".restarts", m.restarts), EU(p ".bad_rate", m.bad_rate), EU(p ".bad_unit", m.bad_unit), \
      EU(p ".bad_index", m.bad_index), EU(p ".malformed", m.malformed),                            \
      EU(p ".oversized", m.oversized), EU(p ".refused_samples", m.refused_samples),                \
      EU(p ".refused_spans", m.refused_spans), EU(p ".duplicates", m.duplicates),                  \
      EU(p ".overlaps", m.overlaps), EU(p ".duplicate_samples", m.duplicate_samples),              \
      EU(p ".clock_steps", m.clock_steps), EU(p ".clock_frozen", m.clock_frozen),                  \
      EB(p ".clock_rate_wrong", m.clock_rate_wrong), ET(p ".clock_problem", m.clock_problem)

/* af_session without its strikes and apples: what af_combined_add reads,
 * but the wall and CPU time (only --bench prints them, which --merge does
 * not take; a report's bytes stay the same from run to run). */
static const field session_fields[] = {
    STREAM("force", force),
    STREAM("audio", audio),
    EU("stats.overflows", stats.overflows),
    EU("stats.late_apples", stats.late_apples),
    EU("stats.pulse_cut", stats.pulse_cut),
    EU("stats.apples_implausible", stats.apples_implausible),
    EU("stats.apples_skipped", stats.apples_skipped),
    ET("stats.last_apples_skipped", stats.last_apples_skipped),
    EU("stats.audio_clipped", stats.audio_clipped),
    EU("stats.clock_faulted", stats.clock_faulted),
    EU("stats.lag_no_onset", stats.lag_no_onset),
    EU("stats.lag_moves", stats.lag_moves),
    EF("stats.lag_median_s", stats.lag_median_s),
    EF("stats.lag_mad_s", stats.lag_mad_s),
    EF("stats.lag_applied_s", stats.lag_applied_s),
    EZ("stats.lag_strikes", stats.lag_strikes),
    ET("stats.lag_warning", stats.lag_warning),
    ET("stats.last_implausible_apple", stats.last_implausible_apple),
    EF("stats.transit_observed_s", stats.transit_observed_s),
    EZ("stats.transit_strikes", stats.transit_strikes),
    ET("stats.transit_warning", stats.transit_warning),
    EU("messages", messages),
    EU("refused_messages", refused_messages),
    EU("refused_apples", refused_apples),
    EF("recorded_s", recorded_s),
    EB("tap_only", tap_only),
};

#define N_OF(a) (sizeof(a) / sizeof((a)[0]))

/* Settings rows that name where and which lane, not how it measures: reports
 * of several lanes or machines merge though these differ. */
static bool identity_row(const char *line)
{
  static const char *const rows[] = {"frame_prefix", "hardware_id", "urdf_file", "hammer_link"};
  for (size_t k = 0; k < N_OF(rows); k++) {
    size_t n = strlen(rows[k]);
    if (strncmp(line, rows[k], n) == 0 && line[n] == ':')
      return true;
  }
  return false;
}

/* ---- writing --------------------------------------------------------------------- */

/* A double that reads back as itself: %.17g; NaN as null, infinities as
 * the strings "inf" and "-inf" (JSON has neither). */
static void put_real(FILE *out, double v)
{
  if (isnan(v))
    fputs("null", out);
  else if (isinf(v))
    fputs(v > 0 ? "\"inf\"" : "\"-inf\"", out);
  else
    fprintf(out, "%.17g", v);
}

static void put_field(FILE *out, const field *f, const void *base)
{
  const char *p = (const char *)base + f->offset;
  fprintf(out, "\"%s\": ", f->name);
  switch (f->kind) {
  case F_U64: fprintf(out, "%" PRIu64, *(const uint64_t *)(const void *)p); break;
  case F_SIZE: fprintf(out, "%zu", *(const size_t *)(const void *)p); break;
  case F_F64: put_real(out, *(const double *)(const void *)p); break;
  case F_BOOL: fputs(*(const bool *)(const void *)p ? "true" : "false", out); break;
  case F_TEXT: af_json_string(out, p); break;
  }
}

static void put_fields(FILE *out, const char *name, const field *fs, size_t n, const void *base)
{
  fprintf(out, ",\n    \"%s\": {", name);
  for (size_t k = 0; k < n; k++) {
    fputs(k ? ", " : "", out);
    put_field(out, &fs[k], base);
  }
  fputs("}", out);
}

static void put_counts(FILE *out, const char *name, const size_t *v, size_t n)
{
  fprintf(out, ",\n    \"%s\": [", name);
  for (size_t k = 0; k < n; k++)
    fprintf(out, "%s%zu", k ? ", " : "", v[k]);
  fputs("]", out);
}

/* The settings as the node's snapshot writes them (snapshot_text.h), one
 * JSON string per line, the identity rows left out. */
static void put_settings(FILE *out, const af_settings *settings)
{
  static char text[AF_SNAPSHOT_MAX_BYTES]; /* large: not on the stack; the writer's thread only */
  fputs(",\n    \"settings\": [", out);
  (void)af_settings_snapshot(settings, text, sizeof text); /* every row fits the bound */
  bool first = true;
  for (char *line = text, *end; *line != '\0'; line = end + 1) {
    end = strchr(line, '\n');
    *end = '\0'; /* every snapshot line ends in one */
    if (identity_row(line))
      continue;
    fputs(first ? "\n      " : ",\n      ", out);
    af_json_string(out, line);
    first = false;
  }
  fputs("]", out);
}

void af_merge_state_write(FILE *out, const af_session *s, const af_summary *m,
                          const af_settings *settings)
{
  fputs("\"merge_state\": {\n    \"format\": \"" AF_MERGE_STATE_FORMAT "\"", out);
  put_settings(out, settings);
  put_fields(out, "summary", summary_fields, N_OF(summary_fields), m);
  put_counts(out, "by_flag", m->by_flag, AF_SUMMARY_FLAGS);
  put_counts(out, "by_audio_cause", m->by_audio_cause, AF_SUMMARY_AUDIO_CAUSES);
  put_fields(out, "session", session_fields, N_OF(session_fields), s);
  fputs(",\n    \"columns\": [", out);
  for (size_t k = 0; k < s->n_strikes; k++) {
    double row[AF_SUMMARY_COLUMNS];
    af_summary_columns_of(&s->strikes[k], row);
    fputs(k ? ",\n      [" : "\n      [", out);
    for (int j = 0; j < AF_SUMMARY_COLUMNS; j++) {
      fputs(j ? ", " : "", out);
      put_real(out, row[j]);
    }
    fputs("]", out);
  }
  fputs("]\n  }", out);
}

/* ---- reading --------------------------------------------------------------------- */

typedef struct {
  const af_json_doc *doc;
  char *err;
  size_t len;
} reader;

static bool bad(reader *r, const char *what, const char *name, const char *why)
{
  snprintf(r->err, r->len, "merge_state: %s%s%s: %s", what, name ? "." : "", name ? name : "", why);
  return false;
}

/* A real as put_real wrote it. */
static bool get_real(const af_json_doc *d, size_t k, double *v)
{
  char text[8];
  if (af_json_string_of(d, k, text, sizeof text) &&
      (strcmp(text, "inf") == 0 || strcmp(text, "-inf") == 0)) {
    *v = text[0] == '-' ? -INFINITY : INFINITY;
    return true;
  }
  return af_json_number(d, k, true, v);
}

static bool get_field(reader *r, const char *group, size_t obj, const field *f, void *base)
{
  const af_json_doc *d = r->doc;
  size_t k = af_json_member(d, obj, f->name);
  char *p = (char *)base + f->offset;
  uint64_t u = 0;
  if (k == 0)
    return bad(r, group, f->name, "missing");
  switch (f->kind) {
  case F_U64:
  case F_SIZE:
    if (!af_json_u64(d, k, &u) || (f->kind == F_SIZE && u > SIZE_MAX))
      return bad(r, group, f->name, "not a whole number >= 0");
    if (f->kind == F_U64)
      *(uint64_t *)(void *)p = u;
    else
      *(size_t *)(void *)p = (size_t)u;
    return true;
  case F_F64:
    return get_real(d, k, (double *)(void *)p) || bad(r, group, f->name, "not a number or null");
  case F_BOOL:
    if (d->nodes[k].type != AF_JSON_TRUE && d->nodes[k].type != AF_JSON_FALSE)
      return bad(r, group, f->name, "not true or false");
    *(bool *)(void *)p = d->nodes[k].type == AF_JSON_TRUE;
    return true;
  case F_TEXT:
    return af_json_string_of(d, k, p, f->size) ||
           bad(r, group, f->name, "not a string, or too long");
  }
  return false;
}

static bool get_fields(reader *r, size_t state, const char *group, const field *fs, size_t n,
                       void *base)
{
  size_t obj = af_json_member(r->doc, state, group);
  if (obj == 0 || r->doc->nodes[obj].type != AF_JSON_OBJECT)
    return bad(r, group, NULL, "missing, or not an object");
  for (size_t k = 0; k < n; k++)
    if (!get_field(r, group, obj, &fs[k], base))
      return false;
  return true;
}

static bool get_counts(reader *r, size_t state, const char *name, size_t *v, size_t n)
{
  const af_json_doc *d = r->doc;
  size_t arr = af_json_member(d, state, name);
  if (arr == 0 || d->nodes[arr].type != AF_JSON_ARRAY || d->nodes[arr].count != n)
    return bad(r, name, NULL, "missing, or not an array of the expected length");
  size_t k = 0;
  for (size_t e = d->nodes[arr].child; e != 0; e = d->nodes[e].next) {
    uint64_t u;
    if (!af_json_u64(d, e, &u) || u > SIZE_MAX)
      return bad(r, name, NULL, "an element is not a whole number >= 0");
    v[k++] = (size_t)u;
  }
  return true;
}

/* The settings lines into *out (first) or compared with it. */
static bool get_settings(reader *r, size_t state, af_merge_settings *out, bool first)
{
  const af_json_doc *d = r->doc;
  size_t arr = af_json_member(d, state, "settings");
  if (arr == 0 || d->nodes[arr].type != AF_JSON_ARRAY || d->nodes[arr].count > AF_SETTING_COUNT)
    return bad(r, "settings", NULL, "missing, or not an array of at most one line per row");
  size_t k = 0;
  for (size_t e = d->nodes[arr].child; e != 0; e = d->nodes[e].next, k++) {
    char line[sizeof out->text[0]];
    if (!af_json_string_of(d, e, line, sizeof line))
      return bad(r, "settings", NULL, "a line is not a string, or too long");
    if (first)
      memcpy(out->text[k], line, sizeof line);
    else if (strcmp(out->text[k], line) != 0) {
      char why[2 * sizeof line + 64];
      snprintf(why, sizeof why, "'%s' here, '%s' in the first report: not one configuration", line,
               out->text[k]);
      return bad(r, "settings", NULL, why);
    }
  }
  if (first && k < AF_SETTING_COUNT)
    out->text[k][0] = '\0';
  else if (!first && k < AF_SETTING_COUNT && out->text[k][0] != '\0')
    return bad(r, "settings", NULL, "fewer rows than the first report's");
  return true;
}

/* The columns as n rows of AF_SUMMARY_COLUMNS (allocated; *rows NULL for none). */
static bool get_columns(reader *r, size_t state, double **rows, size_t *n)
{
  const af_json_doc *d = r->doc;
  size_t arr = af_json_member(d, state, "columns");
  *rows = NULL;
  if (arr == 0 || d->nodes[arr].type != AF_JSON_ARRAY)
    return bad(r, "columns", NULL, "missing, or not an array");
  *n = d->nodes[arr].count;
  if (*n && !(*rows = malloc(*n * AF_SUMMARY_COLUMNS * sizeof **rows)))
    return bad(r, "columns", NULL, "out of memory");
  size_t k = 0;
  for (size_t e = d->nodes[arr].child; e != 0; e = d->nodes[e].next, k++) {
    if (d->nodes[e].type != AF_JSON_ARRAY || d->nodes[e].count != AF_SUMMARY_COLUMNS)
      return bad(r, "columns", NULL, "a row is not an array of the six columns");
    size_t j = 0;
    for (size_t c = d->nodes[e].child; c != 0; c = d->nodes[c].next, j++)
      if (!get_real(d, c, &(*rows)[k * AF_SUMMARY_COLUMNS + j]))
        return bad(r, "columns", NULL, "an element is not a number or null");
  }
  return true;
}

af_status af_merge_state_add(af_combined *c, const af_json_doc *doc, size_t k,
                             af_merge_settings *settings, bool first, char *err, size_t len)
{
  reader r = {doc, err, len};
  char format[64];
  size_t f = af_json_member(doc, k, "format");
  if (f == 0 || !af_json_string_of(doc, f, format, sizeof format) ||
      strcmp(format, AF_MERGE_STATE_FORMAT) != 0) {
    bad(&r, "format", NULL, "not \"" AF_MERGE_STATE_FORMAT "\"");
    return AF_EINVAL;
  }
  static af_session s; /* large: not on the stack; one merge at a time */
  af_summary m;
  memset(&s, 0, sizeof s);
  memset(&m, 0, sizeof m);
  double *rows = NULL;
  size_t n = 0;
  bool ok = get_settings(&r, k, settings, first) &&
            get_fields(&r, k, "summary", summary_fields, N_OF(summary_fields), &m) &&
            get_counts(&r, k, "by_flag", m.by_flag, AF_SUMMARY_FLAGS) &&
            get_counts(&r, k, "by_audio_cause", m.by_audio_cause, AF_SUMMARY_AUDIO_CAUSES) &&
            get_fields(&r, k, "session", session_fields, N_OF(session_fields), &s) &&
            get_columns(&r, k, &rows, &n);
  af_status st = !ok ? AF_EINVAL : af_combined_add_rows(c, &s, &m, rows, n);
  if (ok && st != AF_OK)
    snprintf(err, len, "merge_state: out of memory for %zu strikes", n);
  free(rows);
  return st;
}
