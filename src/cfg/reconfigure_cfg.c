/* reconfigure_cfg — writes the node's dynamic_reconfigure description
 * (Station.cfg, a Python script of dynamic_reconfigure's generator) from the
 * one parameter table: every row of src/core/config/reconfigure.h with its kind,
 * default, range and help as the table has them, so that the .cfg cannot
 * drift from the table. Run at build time (CMakeLists.txt); not installed.
 *
 *   reconfigure_cfg OUT.cfg
 *
 * Number rows: double_t / int_t with the table's interval as min and max
 * (dynamic_reconfigure clamps to them; an open end is then refused by the
 * table, as at start-up); choice rows: str_t with an enum of the words;
 * string rows: str_t; bool rows: bool_t. Exit 0, or 1 with a line on stderr. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "reconfigure.h"
#include "settings.h"

/* v in the fewest digits that read back as v. */
static void number(FILE *f, double v)
{
  char buf[40];
  for (int digits = 6; digits <= 17; digits++) {
    snprintf(buf, sizeof buf, "%.*g", digits, v);
    if (strtod(buf, NULL) == v)
      break;
  }
  fputs(buf, f);
}

/* s as a Python string literal body (quotes and backslashes escaped). */
static void py_text(FILE *f, const char *s)
{
  for (; *s; s++) {
    if (*s == '"' || *s == '\\')
      fputc('\\', f);
    fputc(*s, f);
  }
}

/* A choice word as a Python identifier: the row's name, '_', the word with
 * '-' made '_' (constants are global to the description). */
static void const_name(FILE *f, const char *row, const char *word)
{
  fprintf(f, "%s_", row);
  for (; *word; word++)
    fputc(*word == '-' ? '_' : *word, f);
}

static int write_row(FILE *f, const af_reconfigure_row *r)
{
  const af_setting_def *d = af_setting_def_of(r->id);
  af_settings s;
  af_settings_reset(&s);
  fprintf(f, "%s.add(\"%s\", ", r->group, d->name);
  switch (d->kind) {
  case AF_SETTING_NUMBER:
  case AF_SETTING_WHOLE: {
    af_setting_range range;
    if (af_setting_range_of(r->id, &range) != AF_OK) {
      fprintf(stderr, "reconfigure_cfg: %s has no range\n", d->name);
      return 1;
    }
    const int whole = d->kind == AF_SETTING_WHOLE;
    fprintf(f, "%s, 0, \"", whole ? "int_t" : "double_t");
    py_text(f, d->help);
    fprintf(f, " (%s)\", ", d->range);
    number(f, af_settings_number(&s, r->id));
    fputs(", ", f);
    number(f, range.lo);
    fputs(", ", f);
    number(f, range.hi);
    fputs(")\n", f);
    return 0;
  }
  case AF_SETTING_BOOL:
    fprintf(f, "bool_t, 0, \"");
    py_text(f, d->help);
    fprintf(f, "\", %s)\n", af_settings_bool(&s, r->id) ? "True" : "False");
    return 0;
  case AF_SETTING_STRING:
    fprintf(f, "str_t, 0, \"");
    py_text(f, d->help);
    fprintf(f, "\", \"");
    py_text(f, af_settings_string(&s, r->id));
    fprintf(f, "\")\n");
    return 0;
  case AF_SETTING_CHOICE: {
    char word[64], def[AF_SETTINGS_TEXT_MAX];
    if (af_settings_choice(&s, r->id, def, sizeof def) != AF_OK)
      return 1;
    fprintf(f, "str_t, 0, \"");
    py_text(f, d->help);
    fprintf(f, "\", \"%s\", edit_method=gen.enum([", def);
    for (size_t k = 0; af_setting_choice_word(r->id, k, word, sizeof word) == AF_OK; k++) {
      fprintf(f, "%sgen.const(\"", k ? ", " : "");
      const_name(f, d->name, word);
      fprintf(f, "\", str_t, \"%s\", \"%s\")", word, word);
    }
    fprintf(f, "], \"%s\"))\n", d->name);
    return 0;
  }
  }
  return 1;
}

int main(int argc, char **argv)
{
  if (argc != 2) {
    fprintf(stderr, "usage: reconfigure_cfg OUT.cfg\n");
    return 1;
  }
  FILE *f = fopen(argv[1], "w");
  if (!f) {
    perror(argv[1]);
    return 1;
  }
  size_t n;
  const af_reconfigure_row *rows = af_reconfigure_rows(&n);
  fprintf(f, "#!/usr/bin/python3\n"
             "# Generated at build time by src/cfg/reconfigure_cfg.c from the parameter table\n"
             "# (src/core/params/settings_table.c) and its reconfigurable rows "
             "(src/core/config/reconfigure.c).\n"
             "# Do not edit: change the table.\n"
             "PACKAGE = \"acoustic_firmness\"\n"
             "from dynamic_reconfigure.parameter_generator_catkin import *\n"
             "gen = ParameterGenerator()\n");
  const char *groups[] = {"criterion", "thresholds", "grades"};
  for (size_t g = 0; g < sizeof groups / sizeof groups[0]; g++)
    fprintf(f, "%s = gen.add_group(\"%s\")\n", groups[g], groups[g]);
  int status = 0;
  for (size_t k = 0; k < n && status == 0; k++)
    status = write_row(f, &rows[k]);
  fprintf(f, "exit(gen.generate(PACKAGE, \"firmness_node\", \"Station\"))\n");
  if (fclose(f) != 0 || status != 0) {
    fprintf(stderr, "reconfigure_cfg: could not write %s\n", argv[1]);
    return 1;
  }
  return 0;
}
