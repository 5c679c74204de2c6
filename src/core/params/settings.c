/* settings.c — the values object of the parameter table: every row at its
 * default, typed values and "name=value" text checked against the rows,
 * the getters, the values as YAML text, the table printed. The rows are in
 * settings_table.c, the YAML reader in settings_yaml.c. */
#include "settings.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <threads.h>

#include "settings_private.h"
#include "text.h"

/* ---- helpers (shared: settings_private.h) ------------------------------- */

af_name af_settings_name_of(const af_settings *s, af_setting_id id)
{
  af_name n;
  snprintf(n.text, sizeof n.text, "%.*s%.63s", AF_SETTINGS_PREFIX_MAX - 1, s->name_prefix,
           af_setting_rows[id].name);
  return n;
}

/* Slot of a string row in s->text: the string rows before it. */
static int string_slot(af_setting_id id)
{
  int slot = 0;
  for (int k = 0; k < (int)id; k++)
    if (af_setting_rows[k].kind == AF_SETTING_STRING)
      slot++;
  return slot < AF_SETTINGS_STRINGS ? slot : -1;
}

/* A whole C number: strtod consumed all of text (not empty, no range error). */
static bool c_number(const char *text, double *out)
{
  char *end;
  errno = 0;
  double v = strtod(text, &end);
  if (end == text || *end != '\0' || errno == ERANGE)
    return false;
  *out = v;
  return true;
}

/* Index of word among a choice row's words, or -1. */
static int choice_index(af_setting_id id, const char *word)
{
  char w[64];
  for (size_t k = 0; af_setting_choice_word(id, k, w, sizeof w) == AF_OK; k++)
    if (strcmp(w, word) == 0)
      return (int)k;
  return -1;
}

/* ---- the values object ---------------------------------------------------- */

/* The value as messages show it: 1.4, true, 'text'. */
static void value_shown(const af_value *v, char *buf, size_t len)
{
  switch (v->type) {
  case AF_V_NULL: snprintf(buf, len, "(nothing)"); break;
  case AF_V_BOOL: snprintf(buf, len, "%s", v->boolean ? "true" : "false"); break;
  case AF_V_NUMBER: snprintf(buf, len, "%g", v->number); break;
  case AF_V_STRING: snprintf(buf, len, "'%.60s%s'", v->text, strlen(v->text) > 60 ? "..." : "");
  }
}

/* What a row expects, for the messages: "a number in (0, 10] m/s". */
static void expected_text(af_setting_id id, char *buf, size_t len)
{
  const af_setting_def *d = &af_setting_rows[id];
  switch (d->kind) {
  case AF_SETTING_NUMBER: snprintf(buf, len, "a number in %s", d->range); break;
  case AF_SETTING_WHOLE: snprintf(buf, len, "a whole number in %s", d->range); break;
  case AF_SETTING_BOOL: snprintf(buf, len, "true or false"); break;
  case AF_SETTING_STRING: snprintf(buf, len, "a string"); break;
  case AF_SETTING_CHOICE: snprintf(buf, len, "one of: %s", d->choices); break;
  }
}

/* A number for a number or whole row: range, then wholeness. */
static af_status store_number(af_settings *s, af_setting_id id, double v, char *err, size_t len)
{
  const af_setting_def *d = &af_setting_rows[id];
  af_name n = af_settings_name_of(s, id);
  if (d->zero_is_absent && v == 0.0) {
    s->value[id] = NAN;
    s->present[id] = false;
    s->given[id] = true;
    return AF_OK;
  }
  af_setting_range r;
  if (af_setting_range_of(id, &r) != AF_OK) {
    af_text_line(err, len, "%s has no valid range in the table", n.text);
    return AF_EINVAL;
  }
  if (!af_setting_range_contains(&r, v)) {
    if (d->optional)
      af_text_line(err, len, "%s = %g is outside the accepted range %s (%sabsent = %s)", n.text, v,
                   d->range, d->zero_is_absent ? "0 or " : "", d->absent);
    else
      af_text_line(err, len, "%s = %g is outside the accepted range %s", n.text, v, d->range);
    return AF_EINVAL;
  }
  if (d->kind == AF_SETTING_WHOLE && v != floor(v)) {
    af_text_line(err, len, "%s = %g is not a whole number in %s", n.text, v, d->range);
    return AF_EINVAL;
  }
  s->value[id] = v;
  s->present[id] = true;
  s->given[id] = true;
  return AF_OK;
}

static af_status store_string(af_settings *s, af_setting_id id, const char *v, char *err,
                              size_t len)
{
  const af_setting_def *d = &af_setting_rows[id];
  int slot = string_slot(id);
  if (slot < 0) {
    af_text_line(err, len, "%s: no room for its text", af_settings_name_of(s, id).text);
    return AF_EINVAL;
  }
  if (strlen(v) > d->max_chars) {
    af_text_line(err, len, "%s = '%.40s...' is longer than %zu characters",
                 af_settings_name_of(s, id).text, v, d->max_chars);
    return AF_EINVAL;
  }
  /* Every text row is one line (a frame, a link, a path, a class list): a
   * newline or tab from a YAML escape would split the messages, names and
   * markers that quote it. */
  for (size_t k = 0; v[k] != '\0'; k++)
    if (af_text_is_control(v[k])) {
      af_text_line(err, len, "%s = '%.40s%s' holds a control character (0x%02x at character %zu)",
                   af_settings_name_of(s, id).text, v, strlen(v) > 40 ? "..." : "",
                   (unsigned)(unsigned char)v[k], k + 1);
      return AF_EINVAL;
    }
  snprintf(s->text[slot], sizeof s->text[slot], "%s", v);
  s->present[id] = true;
  s->given[id] = true;
  return AF_OK;
}

/* Checks v against row id and stores it, or says why not. */
af_status af_settings_apply(af_settings *s, af_setting_id id, const af_value *v, char *err,
                            size_t len)
{
  const af_setting_def *d = &af_setting_rows[id];
  af_name n = af_settings_name_of(s, id);
  char shown[96];
  value_shown(v, shown, sizeof shown);
  if (v->type == AF_V_NULL) {
    char expected[160];
    expected_text(id, expected, sizeof expected);
    af_text_line(err, len, "%s has no value (expected %s)", n.text, expected);
    return AF_EINVAL;
  }
  switch (d->kind) {
  case AF_SETTING_NUMBER:
  case AF_SETTING_WHOLE: {
    double x;
    if (v->type == AF_V_NUMBER)
      return store_number(s, id, v->number, err, len);
    if (v->type == AF_V_STRING && v->lenient && !v->quoted && c_number(v->text, &x))
      return store_number(s, id, x, err, len);
    if (v->type == AF_V_STRING && !v->quoted && c_number(v->text, &x))
      af_text_line(
          err, len,
          "%s = %s is not a number (YAML 1.1 reads it as a string: write a dot and a signed "
          "exponent, e.g. 8.0e+6)",
          n.text, shown);
    else
      af_text_line(err, len, "%s = %s is not a number (expected %s)", n.text, shown, d->range);
    return AF_EINVAL;
  }
  case AF_SETTING_BOOL:
    if (v->type == AF_V_BOOL) {
      s->value[id] = v->boolean ? 1.0 : 0.0;
      s->present[id] = true;
      s->given[id] = true;
      return AF_OK;
    }
    af_text_line(err, len, "%s = %s is not true or false", n.text, shown);
    return AF_EINVAL;
  case AF_SETTING_STRING:
    if (v->type == AF_V_STRING)
      return store_string(s, id, v->text, err, len);
    af_text_line(err, len, "%s = %s is not a string (quote it)", n.text, shown);
    return AF_EINVAL;
  case AF_SETTING_CHOICE: {
    int k = v->type == AF_V_STRING ? choice_index(id, v->text) : -1;
    if (k < 0) {
      af_text_line(err, len, "%s = %s is not one of: %s", n.text, shown, d->choices);
      return AF_EINVAL;
    }
    s->value[id] = k;
    s->present[id] = true;
    s->given[id] = true;
    return AF_OK;
  }
  }
  return AF_EINVAL;
}

static af_status check_args(const af_settings *s, af_setting_id id, char *err, size_t len)
{
  if (s == NULL) {
    af_text_line(err, len, "settings: s is NULL");
    return AF_EINVAL;
  }
  if (!setting_valid_id(id)) {
    af_text_line(err, len, "unknown parameter #%d", (int)id);
    return AF_EINVAL;
  }
  return AF_OK;
}

af_status af_settings_set_number(af_settings *s, af_setting_id id, double v, char *err, size_t len)
{
  af_value x = {.type = AF_V_NUMBER, .number = v};
  return check_args(s, id, err, len) == AF_OK ? af_settings_apply(s, id, &x, err, len) : AF_EINVAL;
}

af_status af_settings_set_bool(af_settings *s, af_setting_id id, bool v, char *err, size_t len)
{
  af_value x = {.type = AF_V_BOOL, .boolean = v};
  return check_args(s, id, err, len) == AF_OK ? af_settings_apply(s, id, &x, err, len) : AF_EINVAL;
}

af_status af_settings_set_string(af_settings *s, af_setting_id id, const char *v, char *err,
                                 size_t len)
{
  af_value x = {.type = v ? AF_V_STRING : AF_V_NULL, .text = v};
  return check_args(s, id, err, len) == AF_OK ? af_settings_apply(s, id, &x, err, len) : AF_EINVAL;
}

static af_status set_default(af_settings *s, af_setting_id id)
{
  const af_setting_def *d = &af_setting_rows[id];
  s->value[id] = NAN;
  s->present[id] = false;
  if (d->def == NULL)
    return AF_OK;
  char err[8];
  return af_settings_set_text(s, d->name, d->def, err, sizeof err);
}

/* The table's defaults, parsed once per process and copied by every reset:
 * parsing every row's text took most of a fuzz input's time. */
static af_settings defaults;
static once_flag defaults_once = ONCE_FLAG_INIT;

static void defaults_build(void)
{
  memset(&defaults, 0, sizeof defaults);
  for (int k = 0; k < AF_SETTING_COUNT; k++)
    set_default(&defaults, (af_setting_id)k); /* the test checks every default is accepted */
  memset(defaults.given, 0, sizeof defaults.given);
}

void af_settings_reset(af_settings *s)
{
  if (s == NULL)
    return;
  call_once(&defaults_once, defaults_build);
  *s = defaults;
}

void af_settings_set_name_prefix(af_settings *s, const char *prefix)
{
  if (s != NULL)
    snprintf(s->name_prefix, sizeof s->name_prefix, "%s", prefix ? prefix : "");
}

static af_status set_scalar(af_settings *s, const char *name, const char *text, bool lenient,
                            char *err, size_t len)
{
  if (s == NULL || name == NULL || text == NULL) {
    af_text_line(err, len, "settings: a NULL argument");
    return AF_EINVAL;
  }
  af_setting_id id;
  if (af_setting_find(name, &id) != AF_OK) {
    af_text_line(err, len, "unknown parameter '%s%.64s'", s->name_prefix, name);
    return AF_EINVAL;
  }
  char buf[AF_SETTINGS_TEXT_MAX * 2];
  af_value v;
  const char *rest = text, *why = NULL;
  while (*text == ' ' || *text == '\t')
    text++;
  if (!af_settings_parse_scalar(text, buf, sizeof buf, &v, &rest, &why)) {
    af_text_line(err, len, "%s: %s", af_settings_name_of(s, id).text, why);
    return AF_EINVAL;
  }
  if (!af_settings_blank_or_comment(rest)) {
    af_text_line(err, len, "%s: text after the value: '%.40s'", af_settings_name_of(s, id).text,
                 rest);
    return AF_EINVAL;
  }
  v.lenient = lenient;
  if (lenient && v.type == AF_V_NULL && af_setting_rows[id].kind == AF_SETTING_STRING &&
      buf[0] == '\0' && text[0] == '\0')
    v = (af_value){.type = AF_V_STRING, .text = "", .quoted = true}; /* "name=" */
  af_settings copy = *s;
  af_status st = af_settings_apply(&copy, id, &v, err, len);
  if (st == AF_OK)
    *s = copy;
  return st;
}

af_status af_settings_set_text(af_settings *s, const char *name, const char *text, char *err,
                               size_t len)
{
  return set_scalar(s, name, text, false, err, len);
}

af_status af_settings_set_arg(af_settings *s, const char *arg, char *err, size_t len)
{
  const char *eq = arg ? strchr(arg, '=') : NULL;
  if (eq == NULL) {
    af_text_line(err, len, "'%.80s' is not name=value", arg ? arg : "(null)");
    return AF_EINVAL;
  }
  char name[80];
  if ((size_t)(eq - arg) >= sizeof name) {
    af_text_line(err, len, "unknown parameter '%.*s...'", 60, arg);
    return AF_EINVAL;
  }
  memcpy(name, arg, (size_t)(eq - arg));
  name[eq - arg] = '\0';
  return set_scalar(s, name, eq + 1, true, err, len);
}

af_status af_settings_check_required(const af_settings *s, unsigned files, char *err, size_t len)
{
  if (s == NULL) {
    af_text_line(err, len, "settings: s is NULL");
    return AF_EINVAL;
  }
  for (int k = 0; k < AF_SETTING_COUNT; k++) {
    const af_setting_def *d = &af_setting_rows[k];
    if (!(d->file & files) || d->optional || s->given[k])
      continue;
    char expected[160];
    expected_text((af_setting_id)k, expected, sizeof expected);
    af_text_line(err, len, "%s is missing (expected %s; %s)",
                 af_settings_name_of(s, (af_setting_id)k).text, expected,
                 d->file == AF_SETTINGS_STATION
                     ? "its default is in config/station.yaml"
                     : "a cultivar value: see the cultivar's YAML, e.g. config/jonagold.yaml");
    return AF_EINVAL;
  }
  return AF_OK;
}

/* ---- reading values -------------------------------------------------------- */

bool af_settings_given(const af_settings *s, af_setting_id id)
{
  return s != NULL && setting_valid_id(id) && s->given[id];
}

af_status af_settings_use_rig_hammer(af_settings *s, char *err, size_t len)
{
  for (int k = 0; k < AF_SETTING_COUNT; k++) {
    af_setting_id id = (af_setting_id)k;
    if (af_setting_rows[k].rig == NULL || s->present[k])
      continue;
    af_status st = af_settings_set_number(s, id, af_setting_rig_value(id), err, len);
    if (st != AF_OK)
      return st;
  }
  return AF_OK;
}

bool af_settings_present(const af_settings *s, af_setting_id id)
{
  return s != NULL && setting_valid_id(id) && s->present[id];
}

double af_settings_number(const af_settings *s, af_setting_id id)
{
  if (!af_settings_present(s, id) || af_setting_rows[id].kind == AF_SETTING_STRING)
    return NAN;
  return s->value[id];
}

bool af_settings_bool(const af_settings *s, af_setting_id id)
{
  return af_settings_present(s, id) && af_setting_rows[id].kind == AF_SETTING_BOOL &&
         s->value[id] != 0.0;
}

const char *af_settings_string(const af_settings *s, af_setting_id id)
{
  if (s == NULL || !setting_valid_id(id) || af_setting_rows[id].kind != AF_SETTING_STRING)
    return NULL;
  int slot = string_slot(id);
  return slot < 0 ? NULL : s->text[slot];
}

af_status af_settings_choice(const af_settings *s, af_setting_id id, char *buf, size_t len)
{
  if (!af_settings_present(s, id) || af_setting_rows[id].kind != AF_SETTING_CHOICE)
    return AF_EINVAL;
  return af_setting_choice_word(id, (size_t)s->value[id], buf, len);
}

/* Shortest %g that reads back as v. */
static void shortest(double v, char *buf, size_t len)
{
  for (int digits = 6; digits <= 17; digits++) {
    snprintf(buf, len, "%.*g", digits, v);
    if (strtod(buf, NULL) == v)
      return;
  }
}

/* v as a YAML 1.1 number: a dot before any exponent ("9.0e+06"), .inf, .nan. */
static void yaml_number(double v, char *buf, size_t len)
{
  if (isnan(v) || isinf(v)) {
    snprintf(buf, len, "%s", isnan(v) ? ".nan" : v > 0 ? ".inf" : "-.inf");
    return;
  }
  char t[40];
  shortest(v, t, sizeof t);
  char *e = strchr(t, 'e');
  if (e != NULL && strchr(t, '.') == NULL)
    snprintf(buf, len, "%.*s.0%s", (int)(e - t), t, e);
  else
    snprintf(buf, len, "%s", t);
}

/* t as a YAML scalar that reads back as the string t: bare when it would,
 * else double-quoted with \\ and \" escaped. */
static void yaml_string(const char *t, char *buf, size_t len)
{
  char copy[AF_SETTINGS_TEXT_MAX * 2];
  af_value v;
  const char *rest = NULL, *why = NULL;
  if (t[0] != ' ' && af_settings_parse_scalar(t, copy, sizeof copy, &v, &rest, &why) &&
      *rest == '\0' && v.type == AF_V_STRING && strcmp(copy, t) == 0) {
    snprintf(buf, len, "%s", t);
    return;
  }
  size_t n = 0;
  if (len < 3) {
    if (len)
      buf[0] = '\0';
    return;
  }
  buf[n++] = '"';
  for (; *t && n + 3 < len; t++) {
    if (*t == '"' || *t == '\\')
      buf[n++] = '\\';
    buf[n++] = *t;
  }
  buf[n++] = '"';
  buf[n] = '\0';
}

void af_settings_value_text(const af_settings *s, af_setting_id id, char *buf, size_t len)
{
  if (buf == NULL || len == 0)
    return;
  if (s == NULL || !setting_valid_id(id)) {
    snprintf(buf, len, "?");
    return;
  }
  if (af_setting_rows[id].kind == AF_SETTING_STRING) {
    yaml_string(af_settings_string(s, id), buf, len);
    return;
  }
  if (!s->present[id]) {
    snprintf(buf, len, "absent");
    return;
  }
  switch (af_setting_rows[id].kind) {
  case AF_SETTING_BOOL: snprintf(buf, len, "%s", s->value[id] != 0.0 ? "true" : "false"); break;
  case AF_SETTING_CHOICE:
    if (af_settings_choice(s, id, buf, len) != AF_OK)
      snprintf(buf, len, "?");
    break;
  default: yaml_number(s->value[id], buf, len); break;
  }
}

/* ---- printing --------------------------------------------------------------- */

static const char *kind_word(af_setting_kind k)
{
  switch (k) {
  case AF_SETTING_NUMBER: return "double";
  case AF_SETTING_WHOLE: return "int";
  case AF_SETTING_BOOL: return "bool";
  case AF_SETTING_STRING:
  case AF_SETTING_CHOICE: return "string";
  }
  return "?";
}

void af_settings_print(FILE *out, unsigned files, af_settings_print_format format)
{
  if (out == NULL)
    return;
  if (format == AF_SETTINGS_PRINT_TEXT)
    fprintf(out, "%-32s %-6s %-15s %-26s %-8s %s\n", "name", "kind", "default", "range / choices",
            "file", "help");
  for (int k = 0; k < AF_SETTING_COUNT; k++) {
    const af_setting_def *d = &af_setting_rows[k];
    if (d->name == NULL || !(d->file & files))
      continue;
    char def[80], choices[96];
    snprintf(def, sizeof def, "%s", d->def ? d->def : "absent");
    /* "paper, exact, hu-guo" -> "paper | exact | hu-guo" */
    choices[0] = '\0';
    if (d->choices) {
      char w[64];
      for (size_t i = 0; af_setting_choice_word((af_setting_id)k, i, w, sizeof w) == AF_OK; i++)
        snprintf(choices + strlen(choices), sizeof choices - strlen(choices), "%s%s",
                 i ? " | " : "", w);
    }
    const char *unit = af_setting_unit((af_setting_id)k);
    if (format == AF_SETTINGS_PRINT_TEXT) {
      char range[96];
      if (d->range)
        snprintf(range, sizeof range, "%s", d->range);
      else
        snprintf(range, sizeof range, "%s", d->choices ? choices : "");
      fprintf(out, "%-32s %-6s %-15s %-26s %-8s %s%s%s%s\n", d->name, kind_word(d->kind), def,
              range, d->file == AF_SETTINGS_STATION ? "station" : "cultivar", d->help,
              d->optional ? (d->zero_is_absent ? " (0 or absent = " : " (absent = ") : "",
              d->optional ? d->absent : "", d->optional ? ")" : "");
      continue;
    }
    /* doc/parameters.md: "- **name** (double, 1.4, (0, 10], m/s): help." */
    bool backticks = d->kind == AF_SETTING_STRING || d->kind == AF_SETTING_CHOICE;
    fprintf(out, "- **%s** (%s, %s%s%s", d->name, kind_word(d->kind), backticks ? "`" : "", def,
            backticks ? "`" : "");
    if (d->range) {
      af_setting_range r;
      const char *u = "";
      af_setting_parse_range(d->range, &r, &u);
      fprintf(out, ", %.*s, %s", (int)(strlen(d->range) - strlen(u) - (u[0] ? 1 : 0)), d->range,
              unit[0] ? unit : "–");
    } else if (d->choices) {
      fprintf(out, ", %s", choices);
    }
    if (d->optional)
      fprintf(out, "): %s; %sabsent = %s.\n", d->help, d->zero_is_absent ? "0 or " : "", d->absent);
    else
      fprintf(out, "): %s.\n", d->help);
  }
}
