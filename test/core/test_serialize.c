/* test_serialize.c — the strike serializer (serialize.h) on a hand-filled
 * report: the JSON object read back by a small parser written here (strict
 * JSON grammar for a flat object: strings with escapes, numbers, null, true,
 * false, arrays of strings), the CSV read back by an RFC 4180 reader written
 * here; keys and columns are the table's names in order, the header has as
 * many cells as a row, a NaN is null in JSON and an empty cell in CSV, text
 * with quotes, a backslash and a control character comes back unchanged,
 * reals come back as the same double (strtod of the text) in the fewest
 * digits that do, every field the table says a message carries is a field
 * of that message's .msg file (read from msg/) and every field of StrikeReport
 * and Reliability is mapped, every name ends in its unit's suffix
 * (resonance_hz, impulse_n_s) and the markdown table has a row per field. */
#include <ctype.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "af_test.h"
#include "serialize.h"

#define TEXT_MAX 8192
#define CELLS_MAX 64

/* --- the writers' output as a string ----------------------------------------------- */

typedef void writer_fn(FILE *out, const af_serial_strike *s);

static void write_to(char *buf, size_t len, writer_fn *fn, const af_serial_strike *s)
{
  FILE *f = tmpfile();
  buf[0] = '\0';
  if (f == NULL)
    return;
  fn(f, s);
  rewind(f);
  size_t n = fread(buf, 1, len - 1, f);
  buf[n] = '\0';
  fclose(f);
}

static void json_one(FILE *out, const af_serial_strike *s)
{
  af_serialize_json(out, s);
}

static void csv_header(FILE *out, const af_serial_strike *s)
{
  (void)s;
  af_serialize_csv_header(out);
}

/* --- a flat JSON object parser ------------------------------------------------------ */

typedef struct {
  char key[64];
  char raw[512];  /* the value's text as written (numbers, null, true, false, arrays) */
  char text[512]; /* a string value, unescaped */
  int is_string;
} member;

static const char *ws(const char *p)
{
  while (*p == ' ' || *p == '\n' || *p == '\t' || *p == '\r')
    p++;
  return p;
}

/* A JSON string at p into out (unescaped); the position after it, or NULL. */
static const char *string_at(const char *p, char *out, size_t len)
{
  size_t n = 0;
  if (*p++ != '"')
    return NULL;
  for (; *p != '"'; p++) {
    char c = *p;
    if (c == '\0' || (unsigned char)c < 0x20)
      return NULL;
    if (c == '\\') {
      p++;
      if (*p == 'u') {
        unsigned v;
        if (sscanf(p + 1, "%4x", &v) != 1 || v > 0x7f)
          return NULL;
        c = (char)v;
        p += 4;
      } else if (*p == '"' || *p == '\\' || *p == '/')
        c = *p;
      else if (*p == 'n')
        c = '\n';
      else if (*p == 't')
        c = '\t';
      else
        return NULL;
    }
    if (n + 1 >= len)
      return NULL;
    out[n++] = c;
  }
  out[n] = '\0';
  return p + 1;
}

/* A JSON number (the grammar's: -?int frac? exp?); the position after it, or NULL. */
static const char *number_at(const char *p)
{
  if (*p == '-')
    p++;
  if (*p == '0')
    p++;
  else if (isdigit((unsigned char)*p))
    while (isdigit((unsigned char)*p))
      p++;
  else
    return NULL;
  if (*p == '.') {
    p++;
    if (!isdigit((unsigned char)*p))
      return NULL;
    while (isdigit((unsigned char)*p))
      p++;
  }
  if (*p == 'e' || *p == 'E') {
    p++;
    if (*p == '+' || *p == '-')
      p++;
    if (!isdigit((unsigned char)*p))
      return NULL;
    while (isdigit((unsigned char)*p))
      p++;
  }
  return p;
}

static const char *value_at(const char *p, member *m)
{
  const char *start = p;
  char scratch[512];
  m->is_string = 0;
  if (*p == '"') {
    m->is_string = 1;
    p = string_at(p, m->text, sizeof m->text);
  } else if (*p == '[') {
    p = ws(p + 1);
    while (p && *p != ']') {
      p = string_at(p, scratch, sizeof scratch);
      if (p == NULL)
        return NULL;
      p = ws(p);
      if (*p == ',')
        p = ws(p + 1);
      else if (*p != ']')
        return NULL;
    }
    p = p ? p + 1 : NULL;
  } else if (strncmp(p, "null", 4) == 0 || strncmp(p, "true", 4) == 0)
    p += 4;
  else if (strncmp(p, "false", 5) == 0)
    p += 5;
  else
    p = number_at(p);
  if (p == NULL || (size_t)(p - start) >= sizeof m->raw)
    return NULL;
  memcpy(m->raw, start, (size_t)(p - start));
  m->raw[p - start] = '\0';
  return p;
}

/* The members of the object text (nothing after it); their count, or -1. */
static int parse_object(const char *text, member *out, int max)
{
  const char *p = ws(text);
  int n = 0;
  if (*p++ != '{')
    return -1;
  p = ws(p);
  while (*p != '}') {
    if (n >= max)
      return -1;
    p = string_at(p, out[n].key, sizeof out[n].key);
    if (p == NULL)
      return -1;
    p = ws(p);
    if (*p++ != ':')
      return -1;
    p = value_at(ws(p), &out[n]);
    if (p == NULL)
      return -1;
    n++;
    p = ws(p);
    if (*p == ',')
      p = ws(p + 1);
    else if (*p != '}')
      return -1;
  }
  return *ws(p + 1) == '\0' ? n : -1;
}

/* --- an RFC 4180 line reader -------------------------------------------------------- */

/* The cells of one line (no line end); their count, or -1. */
static int parse_csv(const char *p, char cells[][512], int max)
{
  int n = 0;
  for (;;) {
    size_t k = 0;
    if (n >= max)
      return -1;
    if (*p == '"') {
      for (p++;; p++) {
        if (*p == '\0')
          return -1;
        if (*p == '"') {
          if (p[1] != '"')
            break;
          p++;
        }
        if (k + 1 >= 512)
          return -1;
        cells[n][k++] = *p;
      }
      p++;
      if (*p != ',' && *p != '\0')
        return -1;
    } else
      for (; *p != ',' && *p != '\0'; p++) {
        if (*p == '"' || k + 1 >= 512)
          return -1;
        cells[n][k++] = *p;
      }
    cells[n++][k] = '\0';
    if (*p == '\0')
      return n;
    p++;
  }
}

/* --- the strike ---------------------------------------------------------------------- */

static af_measure_report report;
static af_grade grade;

static af_serial_strike hand_filled(void)
{
  memset(&report, 0, sizeof report);
  report.contact_time_s = 1.0 / 3.0 * 1e-3; /* no short decimal: needs 17 digits */
  report.peak_force_n = 0.1 + 0.2;
  report.impulse_n_s = nextafter(0.015, 1.0);
  report.band_low_hz = 0.0;
  report.band_high_hz = 2762.625061;
  report.resonance_hz = NAN;     /* not measured */
  report.resonance_q = INFINITY; /* not finite: written as not measured too */
  report.snr_db = -3.5;
  report.stiffness_factor = 1.2345678901234567e5;
  report.modulus_from_resonance_pa = 5e-324; /* the smallest subnormal */
  report.fitted_modulus_pa = 1.7976931348623157e308;
  report.fitted_restitution = 0.6;
  report.fit_residual = NAN;
  report.delivered_energy_j = 0.0098;
  report.absorbed_energy_j = 0.006272;
  report.double_hit = true;
  report.lost_samples = 4294967295u;
  report.excites_mode = true;
  report.max_shear_stress_pa = 1.5e5;
  report.yield_shear_stress_pa = 1.8e5;
  report.verdict.flags = AF_VERDICT_NO_RESONANCE | AF_VERDICT_DAMAGE;
  report.modes.method = AF_MODES_METHOD_LOUDEST;
  report.modes.confidence = 0.2;
  snprintf(report.modes_text, sizeof report.modes_text, "0S2 900 Hz, \"loudest\"");
  snprintf(report.reason, sizeof report.reason, "a \"quoted\" word, a back\\slash,\ta tab");
  memset(&grade, 0, sizeof grade);
  grade.index = 2;
  snprintf(grade.name, sizeof grade.name, "very, firm");
  af_serial_strike s = {1700000000123456789LL, "force_link", 42u, true, &report, &grade};
  return s;
}

/* --- the checks ---------------------------------------------------------------------- */

static const member *find(const member *m, int n, const char *key)
{
  for (int k = 0; k < n; k++)
    if (strcmp(m[k].key, key) == 0)
      return &m[k];
  return NULL;
}

static int same_double(const char *text, double expected)
{
  char *end;
  double v = strtod(text, &end);
  return *end == '\0' && memcmp(&v, &expected, sizeof v) == 0;
}

static void test_json(void)
{
  af_serial_strike s = hand_filled();
  size_t nf;
  const af_serial_field *f = af_serial_fields(&nf);
  static char text[TEXT_MAX];
  static member m[CELLS_MAX];
  write_to(text, sizeof text, json_one, &s);
  int n = parse_object(text, m, CELLS_MAX);
  AF_CHECK(n == (int)nf);
  if (n != (int)nf) {
    fprintf(stderr, "not a JSON object of %zu members: %s\n", nf, text);
    return;
  }
  for (size_t k = 0; k < nf; k++)
    AF_CHECK(strcmp(m[k].key, f[k].name) == 0);
  const member *x;
  AF_CHECK((x = find(m, n, "stamp_ns")) && strcmp(x->raw, "1700000000123456789") == 0);
  AF_CHECK((x = find(m, n, "apple_id")) && strcmp(x->raw, "42") == 0);
  AF_CHECK((x = find(m, n, "lost_samples")) && strcmp(x->raw, "4294967295") == 0);
  AF_CHECK((x = find(m, n, "contact_time_s")) && same_double(x->raw, report.contact_time_s));
  AF_CHECK((x = find(m, n, "peak_force_n")) && same_double(x->raw, 0.1 + 0.2));
  AF_CHECK((x = find(m, n, "impulse_n_s")) && same_double(x->raw, report.impulse_n_s));
  AF_CHECK((x = find(m, n, "stiffness_factor_hz2_kg2_3")) &&
           same_double(x->raw, report.stiffness_factor));
  AF_CHECK((x = find(m, n, "modulus_from_resonance_pa")) && same_double(x->raw, 5e-324));
  AF_CHECK((x = find(m, n, "fitted_modulus_pa")) && same_double(x->raw, report.fitted_modulus_pa));
  AF_CHECK((x = find(m, n, "band_low_hz")) && same_double(x->raw, 0.0));
  AF_CHECK((x = find(m, n, "resonance_hz")) && strcmp(x->raw, "null") == 0);
  AF_CHECK((x = find(m, n, "resonance_q")) && strcmp(x->raw, "null") == 0);
  AF_CHECK((x = find(m, n, "fit_residual")) && strcmp(x->raw, "null") == 0);
  AF_CHECK((x = find(m, n, "double_hit")) && strcmp(x->raw, "true") == 0);
  AF_CHECK((x = find(m, n, "clipped")) && strcmp(x->raw, "false") == 0);
  AF_CHECK((x = find(m, n, "flags")) && strcmp(x->raw, "[\"no_resonance\", \"damage\"]") == 0);
  AF_CHECK((x = find(m, n, "reason")) && x->is_string && strcmp(x->text, report.reason) == 0);
  AF_CHECK((x = find(m, n, "grade")) && x->is_string && strcmp(x->text, "very, firm") == 0);
  AF_CHECK((x = find(m, n, "grade_reason")) && x->is_string && x->text[0] == '\0');
  AF_CHECK((x = find(m, n, "mode_method")) && strcmp(x->text, "loudest in range") == 0);
  AF_CHECK((x = find(m, n, "frame_id")) && strcmp(x->text, "force_link") == 0);
  /* The shortest of 15-17 digits that reads back: 0.2 as written, 0.1 + 0.2 needs 17. */
  AF_CHECK((x = find(m, n, "mode_confidence")) && strcmp(x->raw, "0.2") == 0);
  AF_CHECK((x = find(m, n, "peak_force_n")) && strcmp(x->raw, "0.30000000000000004") == 0);
  AF_CHECK((x = find(m, n, "fitted_restitution")) && strcmp(x->raw, "0.6") == 0);
  AF_CHECK((x = find(m, n, "delivered_energy_j")) && strcmp(x->raw, "0.0098") == 0);
  AF_CHECK((x = find(m, n, "absorbed_energy_j")) && strcmp(x->raw, "0.006272") == 0);
}

static void test_csv(void)
{
  af_serial_strike s = hand_filled();
  size_t nf;
  const af_serial_field *f = af_serial_fields(&nf);
  static char head[TEXT_MAX], row[TEXT_MAX], hc[CELLS_MAX][512], rc[CELLS_MAX][512];
  write_to(head, sizeof head, csv_header, &s);
  write_to(row, sizeof row, af_serialize_csv_row, &s);
  AF_CHECK(strchr(head, '\n') == NULL && strchr(row, '\n') == NULL); /* the caller ends lines */
  int nh = parse_csv(head, hc, CELLS_MAX), nr = parse_csv(row, rc, CELLS_MAX);
  AF_CHECK(nh == (int)nf);
  AF_CHECK(nr == nh);
  if (nh != (int)nf || nr != nh) {
    fprintf(stderr, "header %d cells, row %d, table %zu:\n%s\n%s\n", nh, nr, nf, head, row);
    return;
  }
  for (int k = 0; k < nh; k++) {
    AF_CHECK(strcmp(hc[k], f[k].name) == 0);
    const char *c = rc[k];
    if (strcmp(hc[k], "resonance_hz") == 0 || strcmp(hc[k], "resonance_q") == 0 ||
        strcmp(hc[k], "fit_residual") == 0)
      AF_CHECK(c[0] == '\0'); /* NaN and inf: empty, as JSON's null */
    else if (strcmp(hc[k], "peak_force_n") == 0)
      AF_CHECK(same_double(c, 0.1 + 0.2));
    else if (strcmp(hc[k], "contact_time_s") == 0)
      AF_CHECK(same_double(c, report.contact_time_s));
    else if (strcmp(hc[k], "modulus_from_resonance_pa") == 0)
      AF_CHECK(same_double(c, 5e-324));
    else if (strcmp(hc[k], "stamp_ns") == 0)
      AF_CHECK(strcmp(c, "1700000000123456789") == 0);
    else if (strcmp(hc[k], "double_hit") == 0)
      AF_CHECK(strcmp(c, "1") == 0);
    else if (strcmp(hc[k], "clipped") == 0)
      AF_CHECK(strcmp(c, "0") == 0);
    else if (strcmp(hc[k], "reason") == 0)
      AF_CHECK(strcmp(c, report.reason) == 0);
    else if (strcmp(hc[k], "grade") == 0)
      AF_CHECK(strcmp(c, "very, firm") == 0);
    else if (strcmp(hc[k], "flags") == 0)
      AF_CHECK(strcmp(c, "no_resonance|damage") == 0);
    else if (strcmp(hc[k], "mode_text") == 0)
      AF_CHECK(strcmp(c, report.modes_text) == 0);
  }
}

/* The null/empty rule holds for every real of the table: all NaN. */
static void test_all_nan(void)
{
  af_serial_strike s = hand_filled();
  double *reals[] = {&report.contact_time_s,        &report.peak_force_n,
                     &report.impulse_n_s,           &report.band_low_hz,
                     &report.band_high_hz,          &report.resonance_hz,
                     &report.resonance_q,           &report.snr_db,
                     &report.stiffness_factor,      &report.modulus_from_resonance_pa,
                     &report.fitted_modulus_pa,     &report.fitted_restitution,
                     &report.fit_residual,          &report.max_shear_stress_pa,
                     &report.yield_shear_stress_pa, &report.modes.confidence,
                     &report.audio_lag_s,           &report.audio_lag_applied_s,
                     &report.delivered_energy_j,    &report.absorbed_energy_j};
  for (size_t k = 0; k < sizeof reals / sizeof reals[0]; k++)
    *reals[k] = NAN;
  size_t nf, n_real = 0;
  const af_serial_field *f = af_serial_fields(&nf);
  static char text[TEXT_MAX], row[TEXT_MAX], rc[CELLS_MAX][512];
  static member m[CELLS_MAX];
  write_to(text, sizeof text, json_one, &s);
  write_to(row, sizeof row, af_serialize_csv_row, &s);
  int n = parse_object(text, m, CELLS_MAX), nr = parse_csv(row, rc, CELLS_MAX);
  AF_CHECK(n == (int)nf && nr == (int)nf);
  if (n != (int)nf || nr != (int)nf)
    return;
  for (size_t k = 0; k < nf; k++)
    if (f[k].kind == AF_SERIAL_REAL) {
      n_real++;
      AF_CHECK(strcmp(m[k].raw, "null") == 0);
      AF_CHECK(rc[k][0] == '\0');
    }
  AF_CHECK(n_real == sizeof reals / sizeof reals[0]); /* every real of the table was set */
}

/* The fields of msg/NAME.msg (not its comments), their count; -1 when unreadable. */
static int msg_fields(const char *msg, char names[][64], int max)
{
  char path[128], line[512];
  snprintf(path, sizeof path, "msg/%s.msg", msg);
  FILE *in = fopen(path, "r");
  if (in == NULL) {
    fprintf(stderr, "cannot read %s (run from the package's root)\n", path);
    return -1;
  }
  int n = 0;
  while (n < max && fgets(line, sizeof line, in)) {
    char type[64];
    if (line[0] != '#' && sscanf(line, "%63s %63s", type, names[n]) == 2)
      n++;
  }
  fclose(in);
  return n;
}

/* The rows that name message field `field` of msg, or a sub-field of it
 * (header: header.stamp, header.frame_id). */
static int rows_mapping(const char *msg, const char *field)
{
  size_t nf, len = strlen(field);
  const af_serial_field *f = af_serial_fields(&nf);
  int rows = 0;
  for (size_t k = 0; k < nf; k++)
    if (f[k].message && strcmp(f[k].message, msg) == 0 &&
        strncmp(f[k].message_field, field, len) == 0 &&
        (f[k].message_field[len] == '\0' || f[k].message_field[len] == '.'))
      rows++;
  return rows;
}

/* Every row's message field is a field of its .msg file, and every field of
 * StrikeReport.msg and Reliability.msg is some row's (Reliability's header,
 * apple_id and source excepted: the strike is matched by its stamp, the
 * apple_id is StrikeReport's, the source is "measured"). */
static void test_message_names(void)
{
  size_t nf, n_msg = 0;
  const af_serial_field *f = af_serial_fields(&nf);
  for (size_t k = 0; k < nf; k++) {
    AF_CHECK(f[k].unit != NULL && f[k].meaning != NULL && f[k].meaning[0] != '\0');
    AF_CHECK((f[k].message == NULL) == (f[k].message_field == NULL));
    if (f[k].message == NULL || f[k].message_field == NULL)
      continue;
    n_msg++;
    char names[64][64], top[64];
    const int n = msg_fields(f[k].message, names, 64);
    snprintf(top, sizeof top, "%.*s", (int)strcspn(f[k].message_field, "."), f[k].message_field);
    int found = 0;
    for (int j = 0; j < n; j++)
      found |= strcmp(names[j], top) == 0;
    AF_CHECK(found);
    if (!found)
      fprintf(stderr, "%s: %s is not a field of %s.msg\n", f[k].name, f[k].message_field,
              f[k].message);
  }
  AF_CHECK(n_msg >= 20);
  const char *msgs[] = {"StrikeReport", "Reliability"};
  for (int m = 0; m < 2; m++) {
    char names[64][64];
    const int n = msg_fields(msgs[m], names, 64);
    AF_CHECK(n >= (m == 0 ? 20 : 8));
    for (int j = 0; j < n; j++) {
      const int skipped =
          m == 1 && (strcmp(names[j], "header") == 0 || strcmp(names[j], "apple_id") == 0 ||
                     strcmp(names[j], "source") == 0);
      const int rows = rows_mapping(msgs[m], names[j]);
      const int want = strcmp(names[j], "header") == 0 ? 2 : 1; /* stamp and frame_id */
      AF_CHECK(skipped ? rows == 0 : rows == want);
      if (skipped ? rows != 0 : rows != want)
        fprintf(stderr, "%s.%s: mapped by %d rows\n", msgs[m], names[j], rows);
    }
  }
}

/* A unit's name suffix: its symbols in lower case, separated by _, without
 * ^ and parentheses, / as _ ("N s" -> "_n_s", "Hz^2 kg^(2/3)" -> "_hz2_kg2_3");
 * none for "-" (dimensionless) and "" (text, flags). */
static void unit_suffix(const char *unit, char *out, size_t len)
{
  size_t n = 0;
  out[0] = '\0';
  if (strcmp(unit, "-") == 0 || unit[0] == '\0')
    return;
  out[n++] = '_';
  for (const char *c = unit; *c && n + 1 < len; c++)
    if (*c == ' ' || *c == '/')
      out[n++] = '_';
    else if (*c != '^' && *c != '(' && *c != ')')
      out[n++] = (char)tolower((unsigned char)*c);
  out[n] = '\0';
}

/* Every name carries its unit: it ends in the unit's suffix; a dimensionless
 * field ends in none of the table's suffixes. */
static void test_unit_names(void)
{
  size_t nf, n_suffixed = 0;
  const af_serial_field *f = af_serial_fields(&nf);
  for (size_t k = 0; k < nf; k++) {
    char want[64];
    unit_suffix(f[k].unit, want, sizeof want);
    const size_t ln = strlen(f[k].name), ls = strlen(want);
    if (ls == 0) {
      for (size_t j = 0; j < nf; j++) {
        char other[64];
        unit_suffix(f[j].unit, other, sizeof other);
        const size_t lo = strlen(other);
        const int clash = lo > 0 && ln > lo && strcmp(f[k].name + ln - lo, other) == 0;
        AF_CHECK(!clash);
        if (clash)
          fprintf(stderr, "%s (unit '%s') ends in %s's unit %s\n", f[k].name, f[k].unit, f[j].name,
                  other);
      }
      continue;
    }
    n_suffixed++;
    const int ok = ln > ls && strcmp(f[k].name + ln - ls, want) == 0;
    AF_CHECK(ok);
    if (!ok)
      fprintf(stderr, "%s: unit %s, the name should end in %s\n", f[k].name, f[k].unit, want);
  }
  AF_CHECK(n_suffixed >= 14);
}

/* The table as markdown: a header, a separator, one row per field with its
 * message field or report-only. */
static void fields_md(FILE *out, const af_serial_strike *s)
{
  (void)s;
  af_serialize_fields_markdown(out);
}

static void test_fields_markdown(void)
{
  size_t nf;
  (void)af_serial_fields(&nf);
  static char text[TEXT_MAX * 2];
  write_to(text, sizeof text, fields_md, NULL);
  int lines = 0;
  for (const char *c = text; *c; c++)
    lines += *c == '\n';
  AF_CHECK(lines == (int)nf + 2);
  AF_CHECK(strstr(text, "| `resonance_hz` | real | Hz | StrikeReport.resonance | ") != NULL);
  AF_CHECK(strstr(text, "| `stamp_ns` | integer | ns | StrikeReport.header.stamp | ") != NULL);
  AF_CHECK(strstr(text, "| `max_shear_stress_pa` | real | Pa | Reliability.max_shear_stress | ") !=
           NULL);
  AF_CHECK(strstr(text, "| `mode_text` | text |  | report-only | ") != NULL);
}

int main(void)
{
  test_json();
  test_csv();
  test_all_nan();
  test_message_names();
  test_unit_names();
  test_fields_markdown();
  return af_test_summary("test_serialize");
}
