/* settings_yaml.c — YAML 1.1 scalars typed as rosparam (PyYAML) types them,
 * and the reader of the flat YAML files (config/station.yaml, the
 * cultivar's), both checked against the parameter table. */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "settings_private.h"

/* ---- YAML 1.1 scalars ------------------------------------------------------ */

static bool one_of(const char *t, const char *const *words)
{
  for (; *words; words++)
    if (strcmp(t, *words) == 0)
      return true;
  return false;
}

/* Digits of set (plus '_') from t, at least one; returns the end. */
static const char *span_of(const char *t, const char *set)
{
  const char *p = t;
  while (*p && (strchr(set, *p) != NULL || *p == '_'))
    p++;
  return p;
}

/* t without its underscores into buf. */
static void without_underscores(const char *t, char *buf, size_t len)
{
  size_t n = 0;
  for (; *t && n + 1 < len; t++)
    if (*t != '_')
      buf[n++] = *t;
  buf[n] = '\0';
}

/* YAML 1.1 int (PyYAML's resolver, sexagesimal left out). */
static bool yaml_int(const char *t, double *out)
{
  const char *p = t + (*t == '-' || *t == '+');
  int base = 10;
  const char *digits = p;
  if (p[0] == '0' && p[1] == 'b') {
    base = 2, digits = p + 2;
    if (*digits == '\0' || *span_of(digits, "01") != '\0')
      return false;
  } else if (p[0] == '0' && p[1] == 'x') {
    base = 16, digits = p + 2;
    if (*digits == '\0' || *span_of(digits, "0123456789abcdefABCDEF") != '\0')
      return false;
  } else if (p[0] == '0' && p[1] != '\0') {
    base = 8, digits = p + 1;
    if (*span_of(digits, "01234567") != '\0')
      return false;
  } else if (!(p[0] == '0' && p[1] == '\0') &&
             !(p[0] >= '1' && p[0] <= '9' && *span_of(p + 1, "0123456789") == '\0')) {
    return false;
  }
  char clean[80];
  if (strlen(digits) >= sizeof clean)
    return false;
  without_underscores(digits, clean, sizeof clean);
  errno = 0;
  char *end;
  unsigned long long u = strtoull(clean, &end, base);
  if (errno == ERANGE || *end != '\0')
    return false;
  *out = (*t == '-' ? -1.0 : 1.0) * (double)u;
  return true;
}

/* YAML 1.1 float (PyYAML's resolver, sexagesimal left out): a dot is
 * required, an exponent needs its sign. */
static bool yaml_float(const char *t, double *out)
{
  static const char *const inf[] = {".inf", ".Inf", ".INF", NULL};
  static const char *const nan[] = {".nan", ".NaN", ".NAN", NULL};
  const char *p = t + (*t == '-' || *t == '+');
  if (one_of(p, inf)) {
    *out = *t == '-' ? -INFINITY : INFINITY;
    return true;
  }
  if (one_of(t, nan)) {
    *out = NAN;
    return true;
  }
  const char *q;
  if (*p >= '0' && *p <= '9') {
    q = span_of(p, "0123456789");
    if (*q != '.')
      return false;
    q = span_of(q + 1, "0123456789");
  } else if (*p == '.' && p == t) { /* ".5": no sign in this form */
    q = span_of(p + 1, "0123456789");
    if (q == p + 1)
      return false;
  } else {
    return false;
  }
  if (*q == 'e' || *q == 'E') {
    if (q[1] != '+' && q[1] != '-')
      return false;
    const char *e = q + 2;
    q = e;
    while (*q >= '0' && *q <= '9')
      q++;
    if (q == e)
      return false;
  }
  if (*q != '\0')
    return false;
  char clean[80];
  if (strlen(t) >= sizeof clean)
    return false;
  without_underscores(t, clean, sizeof clean);
  char *end;
  *out = strtod(clean, &end);
  return *end == '\0';
}

/* A bare (plain) YAML scalar, typed as PyYAML types it. */
static void resolve_plain(const char *t, af_value *v)
{
  static const char *const nulls[] = {"", "~", "null", "Null", "NULL", NULL};
  static const char *const trues[] = {"true", "True", "TRUE", "yes", "Yes",
                                      "YES",  "on",   "On",   "ON",  NULL};
  static const char *const falses[] = {"false", "False", "FALSE", "no",  "No",
                                       "NO",    "off",   "Off",   "OFF", NULL};
  v->text = t;
  v->quoted = false;
  if (one_of(t, nulls))
    v->type = AF_V_NULL;
  else if (one_of(t, trues))
    v->type = AF_V_BOOL, v->boolean = true;
  else if (one_of(t, falses))
    v->type = AF_V_BOOL, v->boolean = false;
  else if (yaml_int(t, &v->number) || yaml_float(t, &v->number))
    v->type = AF_V_NUMBER;
  else
    v->type = AF_V_STRING;
}

/* The scalar at p (settings_private.h). */
bool af_settings_parse_scalar(const char *p, char *buf, size_t size, af_value *v, const char **rest,
                              const char **why)
{
  size_t n = 0;
  *v = (af_value){.type = AF_V_NULL};
  if (*p == '"' || *p == '\'') {
    char q = *p++;
    for (;; p++) {
      if (*p == '\0') {
        *why = "an unterminated quoted string";
        return false;
      }
      char c = *p;
      if (c == q) {
        if (q == '\'' && p[1] == '\'') { /* '' is a quote inside '...' */
          p++;
        } else {
          p++;
          break;
        }
      } else if (q == '"' && c == '\\') {
        static const char from[] = "\\\"/ntr0", to[] = "\\\"/\n\t\r";
        const char *k = p[1] ? strchr(from, p[1]) : NULL;
        if (k == NULL || *k == '0') {
          *why = "an escape other than \\\\ \\\" \\/ \\n \\t \\r in a quoted string";
          return false;
        }
        c = to[k - from];
        p++;
      }
      if (n + 1 >= size) {
        *why = "a value longer than the line buffer";
        return false;
      }
      buf[n++] = c;
    }
    buf[n] = '\0';
    v->type = AF_V_STRING;
    v->text = buf;
    v->quoted = true;
    *rest = p;
    return true;
  }
  if (*p != '\0' && strchr("[]{}&*!|>%@`,", *p) != NULL) {
    *why = "not a flat value (a list, a map, a tag, an anchor or a block scalar)";
    return false;
  }
  if ((*p == '-' || *p == '?') && (p[1] == ' ' || p[1] == '\0')) {
    *why = "not a flat value (a list)";
    return false;
  }
  /* A plain scalar runs to " #" or the end; its trailing blanks are not part of it. */
  const char *end = p;
  while (*end && !((*end == '#') && end > p && (end[-1] == ' ' || end[-1] == '\t')))
    end++;
  const char *stop = end;
  while (stop > p && (stop[-1] == ' ' || stop[-1] == '\t'))
    stop--;
  if ((size_t)(stop - p) >= size) {
    *why = "a value longer than the line buffer";
    return false;
  }
  memcpy(buf, p, (size_t)(stop - p));
  buf[stop - p] = '\0';
  n = strlen(buf);
  if (strstr(buf, ": ") != NULL || strstr(buf, ":\t") != NULL || (n > 0 && buf[n - 1] == ':')) {
    *why = "not a flat value (a map inside a value)";
    return false;
  }
  resolve_plain(buf, v);
  *rest = end;
  return true;
}

/* Nothing but blanks and a comment. */
bool af_settings_blank_or_comment(const char *p)
{
  while (*p == ' ' || *p == '\t')
    p++;
  return *p == '\0' || *p == '#';
}

/* set_text and set_arg: one scalar for the row called name. */
/* ---- the YAML file --------------------------------------------------------- */

#define AF_YAML_LINE_MAX 1024 /* with its NUL */

af_status af_settings_load_yaml(af_settings *s, const char *path, char *err, size_t len)
{
  if (s == NULL || path == NULL) {
    af_settings_say(err, len, "settings: a NULL argument");
    return AF_EINVAL;
  }
  FILE *f = fopen(path, "r");
  if (f == NULL) {
    af_settings_say(err, len, "%s: cannot be opened: %s", path, strerror(errno));
    return AF_EIO;
  }
  af_settings copy = *s;
  int first_line[AF_SETTING_COUNT] = {0};
  char line[AF_YAML_LINE_MAX + 1], value[AF_YAML_LINE_MAX], why_buf[AF_SETTINGS_TEXT_MAX];
  af_status st = AF_OK;
  int number = 0;
  bool any = false;
  while (st == AF_OK && fgets(line, sizeof line, f) != NULL) {
    number++;
    size_t n = strlen(line);
    if (n == sizeof line - 1 && line[n - 1] != '\n' && !feof(f)) {
      af_settings_say(err, len, "%s:%d: a line longer than %d characters", path, number,
                      AF_YAML_LINE_MAX - 1);
      st = AF_EINVAL;
      break;
    }
    while (n > 0 && (line[n - 1] == '\n' || line[n - 1] == '\r'))
      line[--n] = '\0';
    if (af_settings_blank_or_comment(line))
      continue;
    if (!any && strcmp(line, "---") == 0) { /* a document start before any key */
      any = true;
      continue;
    }
    any = true;
    const char *p = line;
    while ((*p >= 'a' && *p <= 'z') || (*p >= 'A' && *p <= 'Z') || (*p >= '0' && *p <= '9') ||
           *p == '_')
      p++;
    if (p == line || *p != ':' || (p[1] != '\0' && p[1] != ' ' && p[1] != '\t')) {
      af_settings_say(err, len, "%s:%d: not a flat `key: value` line: '%.60s'", path, number, line);
      st = AF_EINVAL;
      break;
    }
    char key[80];
    snprintf(key, sizeof key, "%.*s", (int)(p - line) < 79 ? (int)(p - line) : 79, line);
    af_setting_id id;
    if (af_setting_find(key, &id) != AF_OK) {
      af_settings_say(err, len, "%s:%d: unknown parameter '%s'", path, number, key);
      st = AF_EINVAL;
      break;
    }
    if (first_line[id] != 0) {
      af_settings_say(err, len, "%s:%d: duplicate key '%s' (first on line %d)", path, number, key,
                      first_line[id]);
      st = AF_EINVAL;
      break;
    }
    first_line[id] = number;
    p++;
    while (*p == ' ' || *p == '\t')
      p++;
    af_value v;
    const char *rest = p, *why = NULL;
    if (!af_settings_parse_scalar(p, value, sizeof value, &v, &rest, &why) ||
        !af_settings_blank_or_comment(rest)) {
      af_settings_say(err, len, "%s:%d: %s: %s", path, number, key,
                      why ? why : "text after the quoted value");
      st = AF_EINVAL;
      break;
    }
    st = af_settings_apply(&copy, id, &v, why_buf, sizeof why_buf);
    if (st != AF_OK)
      af_settings_say(err, len, "%s:%d: %s", path, number, why_buf);
  }
  if (st == AF_OK && ferror(f)) {
    af_settings_say(err, len, "%s: read error after line %d", path, number);
    st = AF_EIO;
  }
  fclose(f);
  if (st == AF_OK)
    *s = copy;
  return st;
}
