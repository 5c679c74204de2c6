/* options.c — a tool's flag table: lookup, --help and the "wrote" line. */
#define _POSIX_C_SOURCE 200809L /* strnlen */
#include "options.h"

#include <inttypes.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "text.h"

const af_option *af_option_find(const af_option *table, size_t n, const char *name)
{
  if (table == NULL || name == NULL)
    return NULL;
  for (size_t k = 0; k < n; k++)
    if (strcmp(table[k].name, name) == 0)
      return &table[k];
  return NULL;
}

/* The fields are reached by offset; memcpy keeps that free of pointer casts
 * between unrelated types. */
static void field(const void *defaults, size_t offset, void *out, size_t size)
{
  memcpy(out, (const char *)defaults + offset, size);
}

/* The first characters of arg into shown[len], control characters as '?',
 * "..." appended when cut. */
static void arg_head(const char *arg, char *shown, size_t len)
{
  size_t n = 0;
  for (; arg[n] != '\0' && n + 4 < len; n++)
    shown[n] = af_text_is_control(arg[n]) ? '?' : arg[n];
  snprintf(shown + n, len - n, "%s", arg[n] != '\0' ? "..." : "");
}

bool af_options_args_plain(const char *tool, int argc, char **argv)
{
  for (int k = 1; k < argc; k++) {
    const size_t n = strnlen(argv[k], AF_OPTIONS_ARG_MAX_BYTES + 1);
    const char *c = argv[k];
    while (c < argv[k] + n && !af_text_is_control(*c))
      c++;
    if (n <= AF_OPTIONS_ARG_MAX_BYTES && *c == '\0')
      continue;
    char shown[44]; /* 40 characters and "..." */
    arg_head(argv[k], shown, sizeof shown);
    if (n > AF_OPTIONS_ARG_MAX_BYTES)
      fprintf(stderr,
              "%s: argument %d '%s' is %zu bytes long, above the %d accepted (a path or a value "
              "is shorter)\n",
              tool, k, shown, strlen(argv[k]), AF_OPTIONS_ARG_MAX_BYTES);
    else
      fprintf(stderr, "%s: argument %d '%s' holds a control character (shown as ?)\n", tool, k,
              shown);
    return false;
  }
  return true;
}

bool af_options_want_help(int argc, char **argv, int first)
{
  for (int k = first; k < argc; k++)
    if (strcmp(argv[k], "--help") == 0 || strcmp(argv[k], "-h") == 0)
      return true;
  return false;
}

/* The default of a field entry into buf; "" when there is none (required). */
static void field_default(const af_option *o, const void *defaults, char *buf, size_t len)
{
  const char *text;
  double d[2];
  long l;
  uint64_t u;
  unsigned w;
  bool b;
  buf[0] = '\0';
  if (defaults == NULL && o->kind != AF_OPTION_NONE)
    return;
  switch (o->kind) {
  case AF_OPTION_SWITCH:
    field(defaults, o->offset, &b, sizeof b);
    snprintf(buf, len, "%s", b ? "on" : "off");
    break;
  case AF_OPTION_TEXT:
    field(defaults, o->offset, &text, sizeof text);
    if (text != NULL)
      snprintf(buf, len, "%s", text);
    break;
  case AF_OPTION_NUMBER: /* 0 or NaN = not given: `absent` or required */
    field(defaults, o->offset, d, sizeof d[0]);
    if (d[0] != 0.0 && !isnan(d[0]))
      snprintf(buf, len, "%g", d[0]);
    break;
  case AF_OPTION_RANGE:
    field(defaults, o->offset, d, sizeof d);
    snprintf(buf, len, "%g:%g", d[0], d[1]);
    break;
  case AF_OPTION_LONG:
    field(defaults, o->offset, &l, sizeof l);
    if (l != 0)
      snprintf(buf, len, "%ld", l);
    break;
  case AF_OPTION_U64:
    field(defaults, o->offset, &u, sizeof u);
    snprintf(buf, len, "%" PRIu64, u);
    break;
  case AF_OPTION_UINT:
    field(defaults, o->offset, &w, sizeof w);
    if (w != 0)
      snprintf(buf, len, "%u", w);
    break;
  case AF_OPTION_SETTING:
  case AF_OPTION_NONE: break;
  }
}

/* " [unit] (default X, range R)", "(default: what absence means, range R)"
 * or "(required, range R)": R and the unit from the range the parser
 * applies; no range, no unit added (the help carries it). */
static void field_note(const af_option *o, const void *defaults, char *buf, size_t len)
{
  char def[AF_SETTINGS_TEXT_MAX], range[96] = "";
  af_setting_range r;
  const char *text, *unit;
  field_default(o, defaults, def, sizeof def);
  if (o->kind != AF_OPTION_TEXT && af_option_range(o, &r, &text) &&
      af_setting_parse_range(text, &r, &unit)) {
    int n = (int)(unit - text); /* the interval, without its unit */
    while (n > 0 && text[n - 1] == ' ')
      n--;
    snprintf(range, sizeof range, ", range %.*s", n, text);
    snprintf(buf, len, " [%s]", unit[0] != '\0' ? unit : "-"); /* "-": dimensionless */
  } else
    buf[0] = '\0';
  const size_t used = strlen(buf);
  if (def[0] != '\0')
    snprintf(buf + used, len - used, " (default %s%s)", def, range);
  else if (o->absent != NULL)
    snprintf(buf + used, len - used, " (default: %s%s)", o->absent, range);
  else
    snprintf(buf + used, len - used, " (required%s)", range);
}

/* A parameter table row: its help, unit, value in s and range. */
static void setting_line(FILE *out, const char *flag, const af_option *o, const af_settings *s)
{
  const af_setting_def *row = af_setting_def_of((af_setting_id)o->setting);
  if (row == NULL) {
    fprintf(out, "  %-28s %s\n", flag, o->help ? o->help : "?");
    return;
  }
  char value[AF_SETTINGS_TEXT_MAX];
  af_settings fallback;
  if (s == NULL) {
    af_settings_reset(&fallback);
    s = &fallback;
  }
  af_settings_value_text(s, (af_setting_id)o->setting, value, sizeof value);
  const char *unit = af_setting_unit((af_setting_id)o->setting);
  fprintf(out, "  %-28s %s", flag, o->help ? o->help : row->help);
  fprintf(out, " [%s]", unit[0] != '\0' ? unit : "-"); /* "-": dimensionless */
  fprintf(out, " (default %s", value);
  if (row->range != NULL)
    fprintf(out, ", range %s", row->range);
  else if (row->choices != NULL)
    fprintf(out, ", one of: %s", row->choices);
  fprintf(out, "; parameter %s)\n", row->name);
}

void af_options_help_rows(FILE *out, const af_option *table, size_t n, const void *defaults,
                          const af_settings *s)
{
  for (size_t k = 0; k < n; k++) {
    const af_option *o = &table[k];
    char flag[64], note[AF_SETTINGS_TEXT_MAX + 160];
    snprintf(flag, sizeof flag, "%s%s%s", o->name, o->value ? " " : "", o->value ? o->value : "");
    if (o->kind == AF_OPTION_SETTING) {
      setting_line(out, flag, o, s);
      continue;
    }
    field_note(o, defaults, note, sizeof note);
    fprintf(out, "  %-28s %s%s\n", flag, o->help ? o->help : "", note);
  }
}

void af_options_help(FILE *out, const af_option *table, size_t n, const void *defaults,
                     const af_settings *s)
{
  af_options_help_rows(out, table, n, defaults, s);
  fprintf(out, "  %-28s %s\n", "-h, --help", "this help");
}

void af_options_wrote(const char *path)
{
  fprintf(stderr, "wrote %s\n", path);
}
