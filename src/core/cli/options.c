/* options.c — a tool's flag table: lookup, --help and the "wrote" line. */
#define _POSIX_C_SOURCE 200809L /* strnlen */
#include "options.h"

#include <inttypes.h>
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

bool af_option_store(const af_option *o, const char *value, void *args)
{
  const bool on = true;
  switch (o->kind) {
  case AF_OPTION_SWITCH: memcpy((char *)args + o->offset, &on, sizeof on); return true;
  case AF_OPTION_TEXT: memcpy((char *)args + o->offset, &value, sizeof value); return true;
  default: return false;
  }
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
  case AF_OPTION_NUMBER: /* 0 = not given: `absent` or required */
    field(defaults, o->offset, d, sizeof d[0]);
    if (d[0] != 0.0)
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
  case AF_OPTION_SETTING:
  case AF_OPTION_NONE: break;
  }
}

/* "(default X)", "(default: what absence means)" or "(required)". */
static void field_note(const af_option *o, const void *defaults, char *buf, size_t len)
{
  char def[AF_SETTINGS_TEXT_MAX];
  field_default(o, defaults, def, sizeof def);
  if (def[0] != '\0')
    snprintf(buf, len, "(default %s)", def);
  else if (o->absent != NULL)
    snprintf(buf, len, "(default: %s)", o->absent);
  else
    snprintf(buf, len, "(required)");
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

void af_options_help(FILE *out, const af_option *table, size_t n, const void *defaults,
                     const af_settings *s)
{
  for (size_t k = 0; k < n; k++) {
    const af_option *o = &table[k];
    char flag[64], note[AF_SETTINGS_TEXT_MAX + 32];
    snprintf(flag, sizeof flag, "%s%s%s", o->name, o->value ? " " : "", o->value ? o->value : "");
    if (o->kind == AF_OPTION_SETTING) {
      setting_line(out, flag, o, s);
      continue;
    }
    field_note(o, defaults, note, sizeof note);
    fprintf(out, "  %-28s %s %s\n", flag, o->help ? o->help : "", note);
  }
  fprintf(out, "  %-28s %s\n", "-h, --help", "this help");
}

void af_options_unknown(const char *tool, const af_option *table, size_t n, const char *flag,
                        const char *more)
{
  fprintf(stderr, "%s: unknown flag '%s'; accepted:", tool, flag);
  for (size_t k = 0; k < n; k++)
    fprintf(stderr, "%s %s", k ? "," : "", table[k].name);
  if (more != NULL)
    fprintf(stderr, " and %s", more);
  fprintf(stderr, " (%s --help: units and defaults)\n", tool);
}

void af_options_missing(const char *tool, const af_option *o)
{
  fprintf(stderr, "%s: %s needs a value: %s, %s\n", tool, o->name, o->value ? o->value : "",
          o->help ? o->help : "");
}

void af_options_wrote(const char *path)
{
  fprintf(stderr, "wrote %s\n", path);
}

bool af_options_once(const char *tool, const af_option *o, char **argv, int first, int k)
{
  for (int j = first; j < k; j++)
    if (strcmp(argv[j], o->name) == 0) {
      fprintf(stderr, "%s: %s is given twice (as argument %d and %d); it is accepted once\n", tool,
              o->name, j - first + 1, k - first + 1);
      return false;
    }
  return true;
}
