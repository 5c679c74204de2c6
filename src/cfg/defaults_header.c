/* defaults_header — writes af_defaults.h, the parameter table's numeric
 * defaults as C macros, so that the core's *_default() functions take their
 * numbers from the one table instead of typing them again. Run at
 * build time (CMakeLists.txt) before af_core is compiled; built from
 * src/core/params/settings_table.c alone.
 *
 *   defaults_header OUT.h
 *
 * For every number and whole row with a default:
 *   #define AF_DEFAULT_<NAME> <value>   (number rows: a double literal;
 *                                        whole rows: an integer literal)
 * for every row with a rig value (the shipped rig's hammer):
 *   #define AF_RIG_<NAME> <value>       (a double literal)
 * and AF_DEFAULTS_LIST(X), X(AF_SETTING_<NAME>, AF_DEFAULT_<NAME>) for each
 * default, so that a test can check every macro against its row. <NAME> is
 * the row's name in capitals. The value is the row's text read with strtod
 * and written in the fewest digits that read back the same double. Exit 0,
 * or 1 with a line on stderr. */
#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "settings.h"

/* The row's name in capitals. */
static void upper(FILE *f, const char *name)
{
  for (; *name; name++)
    fputc(toupper((unsigned char)*name), f);
}

/* v as a C literal in the fewest digits that read back as v; a double
 * literal (with a dot or an exponent) unless whole. */
static void literal(FILE *f, double v, int whole)
{
  char buf[48];
  if (v < 0.0) { /* "(-3)": a macro's value is an expression */
    fputc('(', f);
    fputc('-', f);
    literal(f, -v, whole);
    fputc(')', f);
    return;
  }
  if (whole) {
    fprintf(f, "%.0f", v);
    return;
  }
  for (int digits = 6; digits <= 17; digits++) {
    snprintf(buf, sizeof buf, "%.*g", digits, v);
    if (strtod(buf, NULL) == v)
      break;
  }
  fputs(buf, f);
  if (strpbrk(buf, ".e") == NULL)
    fputs(".0", f);
}

/* The row's text as a finite double, or -1 with a line on stderr. */
static int parse(const char *name, const char *text, double *v)
{
  char *end;
  errno = 0;
  *v = strtod(text, &end);
  if (end == text || *end != '\0' || errno == ERANGE || !isfinite(*v)) {
    fprintf(stderr, "defaults_header: %s: '%s' is not a finite number\n", name, text);
    return -1;
  }
  return 0;
}

static int write_rows(FILE *f)
{
  for (int k = 0; k < AF_SETTING_COUNT; k++) {
    const af_setting_def *d = af_setting_def_of((af_setting_id)k);
    int numeric = d->kind == AF_SETTING_NUMBER || d->kind == AF_SETTING_WHOLE;
    double v;
    if (numeric && d->def != NULL) {
      if (parse(d->name, d->def, &v) != 0)
        return -1;
      fputs("#define AF_DEFAULT_", f);
      upper(f, d->name);
      fputc(' ', f);
      literal(f, v, d->kind == AF_SETTING_WHOLE);
      fprintf(f, " /* %s %s */\n", d->name, d->range ? d->range : "");
    }
    if (d->rig != NULL) {
      if (parse(d->name, d->rig, &v) != 0)
        return -1;
      fputs("#define AF_RIG_", f);
      upper(f, d->name);
      fputc(' ', f);
      literal(f, v, 0);
      fprintf(f, " /* the shipped rig's %s */\n", d->name);
    }
  }
  return 0;
}

static void write_list(FILE *f)
{
  fputs("\n/* X(AF_SETTING_<NAME>, AF_DEFAULT_<NAME>) for every default above. */\n"
        "#define AF_DEFAULTS_LIST(X)",
        f);
  for (int k = 0; k < AF_SETTING_COUNT; k++) {
    const af_setting_def *d = af_setting_def_of((af_setting_id)k);
    if ((d->kind != AF_SETTING_NUMBER && d->kind != AF_SETTING_WHOLE) || d->def == NULL)
      continue;
    fputs(" \\\n  X(AF_SETTING_", f);
    upper(f, d->name);
    fputs(", AF_DEFAULT_", f);
    upper(f, d->name);
    fputc(')', f);
  }
  fputc('\n', f);
}

int main(int argc, char **argv)
{
  if (argc != 2) {
    fprintf(stderr, "usage: defaults_header OUT.h\n");
    return 1;
  }
  FILE *f = fopen(argv[1], "w");
  if (f == NULL) {
    fprintf(stderr, "defaults_header: %s: %s\n", argv[1], strerror(errno));
    return 1;
  }
  fputs("/* af_defaults.h — generated at build time by src/cfg/defaults_header.c\n"
        " * from the parameter table (src/core/params/settings_table.c): do not edit.\n"
        " * Units: the range's, in the comment. */\n"
        "#ifndef AF_DEFAULTS_H\n#define AF_DEFAULTS_H\n\n",
        f);
  int st = write_rows(f);
  if (st == 0)
    write_list(f);
  fputs("\n#endif\n", f);
  if (fclose(f) != 0 || st != 0) {
    if (st == 0)
      fprintf(stderr, "defaults_header: %s: cannot be written\n", argv[1]);
    remove(argv[1]);
    return 1;
  }
  return 0;
}
