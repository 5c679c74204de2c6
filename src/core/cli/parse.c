/* parse.c — the one parser of the tools' flags (options.h): every flag's
 * value read by one number reader, checked against the range its table
 * entry states, refused in one message format. No allocation. */
#include <errno.h>
#include <inttypes.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "options.h"

/* A value quoted in a message: at most this many characters of it (the
 * arguments are at most AF_OPTIONS_ARG_MAX_BYTES; a line stays readable). */
#define AF_QUOTE "%.40s"

bool af_options_read_number(const char *text, double *out)
{
  char *end;
  errno = 0;
  *out = strtod(text, &end);
  /* ERANGE: "1e999" (inf) and "1e-999" (an underflow read as 0 or a
   * denormal) are refused rather than silently changed. */
  return end != text && *end == '\0' && errno != ERANGE && isfinite(*out);
}

void af_options_number_text(double v, char *buf, size_t len)
{
  if (v == floor(v) && fabs(v) < 1e15) { /* a whole number: every digit, no exponent */
    snprintf(buf, len, "%.0f", v);
    return;
  }
  for (int digits = 1; digits <= 17; digits++) {
    snprintf(buf, len, "%.*g", digits, v);
    if (strtod(buf, NULL) == v)
      return;
  }
}

bool af_option_range(const af_option *o, af_setting_range *r, const char **text)
{
  const char *t = o->range;
  if (t == NULL && o->setting >= 0 && o->kind != AF_OPTION_SETTING) {
    const af_setting_def *row = af_setting_def_of((af_setting_id)o->setting);
    t = row != NULL ? row->range : NULL;
  }
  if (t == NULL || !af_setting_parse_range(t, r, NULL))
    return false;
  if (text != NULL)
    *text = t;
  return true;
}

void af_options_outside(const char *tool, const char *flag, double v, const char *range,
                        const char *why)
{
  char value[32];
  af_options_number_text(v, value, sizeof value);
  fprintf(stderr, "%s: %s %s is outside the accepted range %s%s\n", tool, flag, value, range,
          why != NULL ? why : "");
}

static bool whole_kind(af_option_kind k)
{
  return k == AF_OPTION_LONG || k == AF_OPTION_U64 || k == AF_OPTION_UINT;
}

bool af_option_number(const char *tool, const af_option *o, const char *text, double *out)
{
  af_setting_range r;
  const char *range = NULL;
  const bool ranged = af_option_range(o, &r, &range);
  const char *what = NULL;
  if (!af_options_read_number(text, out))
    what = "a finite number";
  else if (whole_kind(o->kind) && *out != floor(*out))
    what = "a whole number";
  if (what != NULL) {
    fprintf(stderr, "%s: %s '" AF_QUOTE "' is not %s%s%s%s\n", tool, o->name, text, what,
            ranged ? " (accepted range " : "", ranged ? range : "", ranged ? ")" : "");
    return false;
  }
  if (ranged && !af_setting_range_contains(&r, *out)) {
    af_options_outside(tool, o->name, *out, range, NULL);
    return false;
  }
  return true;
}

/* ---- storing ---------------------------------------------------------------- */

/* The fields are reached by offset; memcpy keeps that free of pointer casts
 * between unrelated types. */
static void put(void *args, size_t offset, const void *v, size_t size)
{
  memcpy((char *)args + offset, v, size);
}

/* "A:B" into lo and hi, each a number of o's range, A <= B. */
static bool read_pair(const char *tool, const af_option *o, const char *text, double v[2])
{
  const char *colon = strchr(text, ':');
  const char *range = "any finite numbers";
  af_setting_range r;
  (void)af_option_range(o, &r, &range);
  char a[64];
  if (colon == NULL || (size_t)(colon - text) >= sizeof a) {
    fprintf(stderr, "%s: %s '" AF_QUOTE "' is not A:B (each in %s)\n", tool, o->name, text, range);
    return false;
  }
  memcpy(a, text, (size_t)(colon - text));
  a[colon - text] = '\0';
  if (!af_option_number(tool, o, a, &v[0]) || !af_option_number(tool, o, colon + 1, &v[1]))
    return false;
  if (v[1] < v[0]) {
    fprintf(stderr, "%s: %s " AF_QUOTE " is reversed: A:B needs A <= B (each in %s)\n", tool,
            o->name, text, range);
    return false;
  }
  return true;
}

/* A whole number already checked into its field's type. U64: the digits
 * themselves when the text is only digits (a double holds 2^53 exactly, a
 * seed may be larger). */
static void put_whole(const af_option *o, const char *text, double v, void *args)
{
  /* Each cast only for its own kind: v fits that type (checked), not the others. */
  switch (o->kind) {
  case AF_OPTION_LONG: {
    long l = (long)v;
    put(args, o->offset, &l, sizeof l);
    break;
  }
  case AF_OPTION_UINT: {
    unsigned u = (unsigned)v;
    put(args, o->offset, &u, sizeof u);
    break;
  }
  default: {
    uint64_t w = strspn(text, "0123456789") == strlen(text) ? (uint64_t)strtoull(text, NULL, 10)
                                                            : (uint64_t)v;
    put(args, o->offset, &w, sizeof w);
    break;
  }
  }
}

/* The value of a stored kind into args (NULL: checked already, a later
 * pass). false after one line. */
static bool store(const char *tool, const af_option *o, const char *value, void *args)
{
  const bool on = true;
  double v[2];
  if (args == NULL)
    return true;
  switch (o->kind) {
  case AF_OPTION_SWITCH: put(args, o->offset, &on, sizeof on); return true;
  case AF_OPTION_TEXT: put(args, o->offset, &value, sizeof value); return true;
  case AF_OPTION_RANGE:
    if (!read_pair(tool, o, value, v))
      return false;
    put(args, o->offset, v, sizeof v);
    return true;
  case AF_OPTION_NUMBER:
    if (!af_option_number(tool, o, value, &v[0]))
      return false;
    put(args, o->offset, &v[0], sizeof v[0]);
    return true;
  default:
    if (!af_option_number(tool, o, value, &v[0]))
      return false;
    put_whole(o, value, v[0], args);
    return true;
  }
}

/* ---- the flags ---------------------------------------------------------------- */

/* The entry of name in p's sets: its set, and its index over all sets. */
static const af_option *lookup(const af_options_parser *p, const char *name, size_t *set,
                               size_t *index)
{
  size_t base = 0;
  for (size_t s = 0; s < p->n_sets; s++) {
    const af_option *o = af_option_find(p->sets[s].table, p->sets[s].n, name);
    if (o != NULL) {
      *set = s;
      *index = base + (size_t)(o - p->sets[s].table);
      return o;
    }
    base += p->sets[s].n;
  }
  return NULL;
}

/* "TOOL: unknown flag 'F'; accepted: --a, --b[ and MORE] (TOOL --help: ...)". */
static void unknown(const af_options_parser *p, const char *flag)
{
  fprintf(stderr, "%s: unknown flag '" AF_QUOTE "'; accepted:", p->tool, flag);
  bool first = true;
  for (size_t s = 0; s < p->n_sets; s++)
    for (size_t k = 0; k < p->sets[s].n; k++) {
      fprintf(stderr, "%s %s", first ? "" : ",", p->sets[s].table[k].name);
      first = false;
    }
  if (p->more != NULL)
    fprintf(stderr, " and %s", p->more);
  fprintf(stderr, " (%s --help: units and defaults)\n", p->tool);
}

/* A flag not `repeat` seen before (at[index]: its argument number, 0 = not
 * yet): refused rather than the last silently winning. */
static bool once(const char *tool, const af_option *o, int *at, size_t index, int here)
{
  if (o->repeat || at[index] == 0) {
    at[index] = here;
    return true;
  }
  fprintf(stderr, "%s: %s is given twice (as argument %d and %d); it is accepted once\n", tool,
          o->name, at[index], here);
  return false;
}

static bool handed(const af_option_set *set, const af_option *o, const char *value)
{
  return set->hand == NULL || set->hand(set->user, o, value);
}

static size_t entries(const af_options_parser *p)
{
  size_t n = 0;
  for (size_t s = 0; s < p->n_sets; s++)
    n += p->sets[s].n;
  return n;
}

bool af_options_parse(const af_options_parser *p, int argc, char **argv, int first)
{
  int at[AF_OPTIONS_ENTRIES_MAX] = {0};
  if (p->n_sets > AF_OPTIONS_SETS_MAX || entries(p) > AF_OPTIONS_ENTRIES_MAX) {
    fprintf(stderr, "%s: the flag tables hold more than %d entries\n", p->tool,
            AF_OPTIONS_ENTRIES_MAX);
    return false;
  }
  for (int k = first; k < argc; k++) {
    size_t s, index;
    const af_option *o = lookup(p, argv[k], &s, &index);
    if (o == NULL && p->positional && p->n_sets > 0 && strncmp(argv[k], "--", 2) != 0) {
      if (!handed(&p->sets[0], NULL, argv[k]))
        return false;
      continue;
    }
    if (o == NULL) {
      unknown(p, argv[k]);
      return false;
    }
    if (!once(p->tool, o, at, index, k - first + 1))
      return false;
    const char *value = NULL;
    if (o->value != NULL) {
      if (k + 1 >= argc || argv[k + 1][0] == '\0') { /* "" is no value: a script's empty variable */
        fprintf(stderr, "%s: %s needs a value: %s, %s\n", p->tool, o->name, o->value,
                o->help ? o->help : "");
        return false;
      }
      value = argv[++k];
    }
    const bool stored = o->kind != AF_OPTION_SETTING && o->kind != AF_OPTION_NONE;
    if (stored ? !store(p->tool, o, value, p->sets[s].args) : !handed(&p->sets[s], o, value))
      return false;
  }
  return true;
}
