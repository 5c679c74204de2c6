/* apple_csv.c — the apple list of capture_to_bag (see apple_csv.h). */
#define _POSIX_C_SOURCE 200809L
#include "apple_csv.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "settings.h"

typedef enum {
  COL_ID,
  COL_STAMP,
  COL_MASS,
  COL_EQ_RADIUS,
  COL_STRIKE_RADIUS,
  COL_STEM_X,
  COL_STEM_Y,
  COL_STEM_Z,
  COL_CONFIDENCE,
  COL_COUNT
} af_csv_col;

static const char *const col_names[COL_COUNT] = {
    "apple_id",    "stamp_s",     "mass_kg",     "equatorial_radius_m", "strike_radius_m",
    "stem_axis_x", "stem_axis_y", "stem_axis_z", "confidence"};

/* The reader's state: the file, the line, the column order. */
typedef struct {
  const char *path;
  size_t line;
  int order[COL_COUNT]; /* order[k]: the column of field k of a row */
  double stamp_min_s, stamp_max_s;
  char *err;
  size_t len;
} af_csv;

/* Trims blanks (and a CR) around s in place. */
static char *trim(char *s)
{
  while (isspace((unsigned char)*s))
    s++;
  size_t n = strlen(s);
  while (n > 0 && isspace((unsigned char)s[n - 1]))
    s[--n] = '\0';
  return s;
}

/* Splits line at commas into at most max fields, each trimmed once cut
 * (blanks before a comma too); the field count. */
static size_t split(char *line, char **fields, size_t max)
{
  size_t n = 0;
  for (char *p = line;;) {
    char *comma = strchr(p, ',');
    if (comma != NULL)
      *comma = '\0';
    if (n < max)
      fields[n] = trim(p);
    n++;
    if (comma == NULL)
      return n;
    p = comma + 1;
  }
}

static af_status header(af_csv *c, char *line)
{
  char *f[COL_COUNT + 1];
  bool seen[COL_COUNT] = {false};
  size_t n = split(line, f, COL_COUNT + 1);
  for (size_t k = 0; k < n && k < COL_COUNT + 1; k++) {
    int col = -1;
    for (int j = 0; j < COL_COUNT; j++)
      if (strcmp(f[k], col_names[j]) == 0)
        col = j;
    if (col < 0 || seen[col] || k >= COL_COUNT) {
      snprintf(c->err, c->len,
               "%s:%zu: header column %zu '%s' is %s (the columns: apple_id, stamp_s, mass_kg, "
               "equatorial_radius_m, strike_radius_m, stem_axis_x, stem_axis_y, stem_axis_z, "
               "confidence)",
               c->path, c->line, k + 1, f[k], col < 0 ? "not a known column" : "given twice");
      return AF_EINVAL;
    }
    seen[col] = true;
    c->order[k] = col;
  }
  for (int j = 0; j < COL_COUNT; j++)
    if (!seen[j]) {
      snprintf(c->err, c->len, "%s:%zu: the header has no column '%s'", c->path, c->line,
               col_names[j]);
      return AF_EINVAL;
    }
  return AF_OK;
}

/* The accepted range of column col: [lo, hi], 0 too when zero_ok; its text. */
static void range_of(const af_csv *c, af_csv_col col, double *lo, double *hi, bool *zero_ok,
                     char *text, size_t len)
{
  af_setting_id row = col == COL_MASS            ? AF_SETTING_MASS_MIN_KG
                      : col == COL_EQ_RADIUS     ? AF_SETTING_EQUATORIAL_RADIUS_MIN_M
                      : col == COL_STRIKE_RADIUS ? AF_SETTING_STRIKE_RADIUS_MIN_M
                                                 : AF_SETTING_COUNT;
  af_setting_range r;
  *zero_ok = col == COL_STRIKE_RADIUS;
  if (row != AF_SETTING_COUNT && af_setting_range_of(row, &r) == AF_OK) {
    *lo = r.lo, *hi = r.hi;
    snprintf(text, len, "%sa number in %s", *zero_ok ? "0 (unknown) or " : "",
             af_setting_def_of(row)->range);
  } else if (col == COL_STAMP) {
    *lo = c->stamp_min_s, *hi = c->stamp_max_s;
    snprintf(text, len, "a number in [%g, %g] s (from the force recording's start)", *lo, *hi);
  } else if (col == COL_CONFIDENCE) {
    *lo = 0.0, *hi = 1.0;
    snprintf(text, len, "a number in [0, 1]");
  } else if (col == COL_ID) {
    *lo = 1.0, *hi = 4294967295.0;
    snprintf(text, len, "a whole number in [1, 4294967295] (0 is StrikeReport's \"no apple\")");
  } else {
    *lo = -INFINITY, *hi = INFINITY;
    snprintf(text, len, "a finite number");
  }
}

/* Field text of column col into *v; false with a message. */
static bool field(const af_csv *c, af_csv_col col, const char *text, double *v)
{
  double lo, hi;
  bool zero_ok;
  char range[128], *end;
  range_of(c, col, &lo, &hi, &zero_ok, range, sizeof range);
  errno = 0;
  *v = strtod(text, &end);
  bool number = end != text && *end == '\0' && errno != ERANGE && isfinite(*v);
  bool whole = col != COL_ID || (*v == floor(*v) && strspn(text, "0123456789") == strlen(text));
  if (number && whole && ((zero_ok && *v == 0.0) || (*v >= lo && *v <= hi)))
    return true;
  snprintf(c->err, c->len, "%s:%zu: column %s: '%s' is not %s", c->path, c->line, col_names[col],
           text, range);
  return false;
}

static af_status parse_row(af_csv *c, char *line, af_csv_apple *a)
{
  char *f[COL_COUNT + 1];
  size_t n = split(line, f, COL_COUNT + 1);
  if (n != COL_COUNT) {
    snprintf(c->err, c->len, "%s:%zu: %zu fields, the header has %d", c->path, c->line, n,
             COL_COUNT);
    return AF_EINVAL;
  }
  double v[COL_COUNT];
  for (size_t k = 0; k < COL_COUNT; k++)
    if (!field(c, (af_csv_col)c->order[k], f[k], &v[c->order[k]]))
      return AF_EINVAL;
  a->apple_id = (uint32_t)v[COL_ID];
  a->stamp_s = v[COL_STAMP];
  a->mass_kg = v[COL_MASS];
  a->equatorial_radius_m = v[COL_EQ_RADIUS];
  a->strike_radius_m = v[COL_STRIKE_RADIUS];
  a->stem_axis[0] = v[COL_STEM_X];
  a->stem_axis[1] = v[COL_STEM_Y];
  a->stem_axis[2] = v[COL_STEM_Z];
  a->confidence = v[COL_CONFIDENCE];
  return AF_OK;
}

/* Row k against the rows before it: a new id, not earlier than the last. */
static af_status against_earlier(af_csv *c, const af_csv_apple *a, size_t k)
{
  if (k > 0 && a[k].stamp_s < a[k - 1].stamp_s) {
    snprintf(c->err, c->len,
             "%s:%zu: stamp_s '%g' is before the previous row's %g s (rows in time order)", c->path,
             c->line, a[k].stamp_s, a[k - 1].stamp_s);
    return AF_EINVAL;
  }
  for (size_t j = 0; j < k; j++)
    if (a[j].apple_id == a[k].apple_id) {
      snprintf(c->err, c->len, "%s:%zu: apple_id '%u' is given twice (apple row %zu too)", c->path,
               c->line, (unsigned)a[k].apple_id, j + 1);
      return AF_EINVAL;
    }
  return AF_OK;
}

/* Appends one row (growing *rows); AF_ESIZE / AF_ENOMEM with a message. */
static af_status grow(af_csv *c, af_csv_apple **rows, size_t n, size_t *cap)
{
  if (n < *cap)
    return AF_OK;
  if (n >= AF_APPLE_CSV_MAX_ROWS) {
    snprintf(c->err, c->len, "%s:%zu: more than %zu apples (split the list)", c->path, c->line,
             AF_APPLE_CSV_MAX_ROWS);
    return AF_ESIZE;
  }
  size_t want = *cap ? 2 * *cap : 64;
  want = want > AF_APPLE_CSV_MAX_ROWS ? AF_APPLE_CSV_MAX_ROWS : want;
  af_csv_apple *p = realloc(*rows, want * sizeof *p);
  if (p == NULL) {
    snprintf(c->err, c->len, "%s: out of memory at line %zu", c->path, c->line);
    return AF_ENOMEM;
  }
  *rows = p;
  *cap = want;
  return AF_OK;
}

/* Every line of f after the header into *rows. */
static af_status rows_of(af_csv *c, FILE *f, af_csv_apple **rows, size_t *n)
{
  char line[AF_APPLE_CSV_LINE_MAX];
  size_t cap = 0;
  bool have_header = false;
  af_status s = AF_OK;
  while (s == AF_OK && fgets(line, sizeof line, f) != NULL) {
    c->line++;
    if (strchr(line, '\n') == NULL && !feof(f)) {
      snprintf(c->err, c->len, "%s:%zu: longer than %d characters", c->path, c->line,
               AF_APPLE_CSV_LINE_MAX - 1);
      return AF_EINVAL;
    }
    /* A UTF-8 byte-order mark, as spreadsheets write it, before the header. */
    char *t = c->line == 1 && strncmp(line, "\xEF\xBB\xBF", 3) == 0 ? line + 3 : line;
    t = trim(t);
    if (t[0] == '\0')
      continue;
    if (!have_header) {
      s = header(c, t);
      have_header = true;
    } else if ((s = grow(c, rows, *n, &cap)) == AF_OK &&
               (s = parse_row(c, t, &(*rows)[*n])) == AF_OK &&
               (s = against_earlier(c, *rows, *n)) == AF_OK) {
      (*n)++;
    }
  }
  if (s == AF_OK && ferror(f)) {
    snprintf(c->err, c->len, "%s: cannot read line %zu", c->path, c->line + 1);
    s = AF_EIO;
  }
  if (s == AF_OK && *n == 0) {
    snprintf(c->err, c->len, "%s: %s", c->path,
             have_header ? "no apple rows after the header" : "empty (a header row is needed)");
    s = AF_EINVAL;
  }
  return s;
}

af_status af_apple_csv_read(const char *path, double stamp_min_s, double stamp_max_s,
                            af_csv_apple **out, size_t *n, char *err, size_t len)
{
  *out = NULL;
  *n = 0;
  FILE *f = fopen(path, "r");
  if (f == NULL) {
    snprintf(err, len, "%s: cannot read: %s", path, strerror(errno));
    return AF_EIO;
  }
  af_csv c = {path, 0, {0}, stamp_min_s, stamp_max_s, err, len};
  af_status s = rows_of(&c, f, out, n);
  fclose(f);
  if (s != AF_OK) {
    free(*out);
    *out = NULL;
    *n = 0;
  }
  return s;
}
