/* settings_yaml.c — YAML 1.1 scalars typed as rosparam (PyYAML) types them,
 * and the settings file's bounds checked before any parser sees its bytes
 * (the file itself is parsed by libyaml, settings_libyaml.c). */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "file_read.h"
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

/* A bare (plain) YAML scalar, typed as PyYAML types it (settings_private.h). */
void af_settings_resolve_plain(const char *t, af_value *v)
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
  af_settings_resolve_plain(buf, v);
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

/* ---- the YAML file --------------------------------------------------------- */

/* The file is read as bytes, whole, after fstat: a settings file is a
 * regular file of at most AF_YAML_FILE_MAX_BYTES, so /dev/zero, a FIFO, a
 * directory or 200 MB of anything is refused before a byte is read. Then,
 * byte by byte: a UTF-8 byte-order mark at the very start is skipped (editors
 * on Windows write one; rosparam's PyYAML skips it too); a line ends at LF or
 * CR LF; a NUL byte or a CR not followed by LF anywhere is refused with
 * file:line:column (a NUL would end a C string in silence, a lone CR is an
 * old Mac line end PyYAML would read as a line break where we would not); a
 * line longer than AF_YAML_LINE_MAX - 1 bytes is refused; a key given twice
 * is refused naming both lines. */

/* The whole file into *data (malloc'd, size bytes), or one line in err
 * (settings_private.h). */
af_status af_settings_read_whole(const char *path, char **data, size_t *size, char *err, size_t len)
{
  return af_file_read_whole(path, AF_YAML_FILE_MAX_BYTES, "a settings file", data, size, err, len);
}

/* The line at data[*pos..size) into line[AF_YAML_LINE_MAX] without its end;
 * *pos moves past the end. false with file:line:column on a NUL, a lone CR or
 * an over-long line (settings_private.h). */
bool af_settings_next_line(const char *data, size_t size, size_t *pos, char *line, const char *path,
                           int number, char *err, size_t len)
{
  size_t n = 0, p = *pos;
  for (; p < size && data[p] != '\n'; p++) {
    int column = (int)n + 1;
    if (data[p] == '\0') {
      af_text_line(err, len, "%s:%d:%d: a NUL byte; a settings file is text", path, number, column);
      return false;
    }
    if (data[p] == '\r' && (p + 1 == size || data[p + 1] != '\n')) {
      af_text_line(err, len,
                   "%s:%d:%d: a carriage return not followed by a line feed; lines end with "
                   "LF or CR LF",
                   path, number, column);
      return false;
    }
    if (data[p] == '\r') /* CR LF: the CR ends the line */
      continue;
    if (n + 1 >= AF_YAML_LINE_MAX) {
      af_text_line(err, len, "%s:%d: a line longer than %d bytes", path, number,
                   AF_YAML_LINE_MAX - 1);
      return false;
    }
    line[n++] = data[p];
  }
  line[n] = '\0';
  *pos = p + (p < size); /* past the LF */
  return true;
}
