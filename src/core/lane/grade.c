/* grade.c — firmness classes of measured strikes (see grade.h). */
#include "grade.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "text.h"

static const char *const quantity_names[] = {"stiffness_factor", "modulus_from_resonance",
                                             "fitted_modulus"};

static bool valid_quantity(af_grade_quantity q)
{
  return (int)q >= 0 && (size_t)q < sizeof quantity_names / sizeof quantity_names[0];
}

const char *af_grade_quantity_name(af_grade_quantity q)
{
  return valid_quantity(q) ? quantity_names[q] : "?";
}

const char *af_grade_quantity_unit(af_grade_quantity q)
{
  return q == AF_GRADE_BY_STIFFNESS_FACTOR ? "Hz2 kg^(2/3)" : "Pa";
}

af_status af_grade_quantity_parse(const char *word, af_grade_quantity *out)
{
  if (word == NULL || out == NULL)
    return AF_EINVAL;
  for (size_t k = 0; k < sizeof quantity_names / sizeof quantity_names[0]; k++)
    if (strcmp(word, quantity_names[k]) == 0) {
      *out = (af_grade_quantity)k;
      return AF_OK;
    }
  return AF_EINVAL;
}

void af_grade_quantity_range(af_grade_quantity q, double *lo, double *hi)
{
  if (q == AF_GRADE_BY_STIFFNESS_FACTOR) {
    *lo = 1e3, *hi = 1e8;
    return;
  }
  af_setting_range r;
  if (af_setting_range_of(AF_SETTING_MODULUS_NOMINAL_PA, &r) == AF_OK)
    *lo = r.lo, *hi = r.hi;
  else
    *lo = 1e5, *hi = 1e9;
}

/* t[0..n) without its leading and trailing blanks into buf; false when it
 * does not fit. */
static bool trimmed(const char *t, size_t n, char *buf, size_t size)
{
  while (n > 0 && (*t == ' ' || *t == '\t'))
    t++, n--;
  while (n > 0 && (t[n - 1] == ' ' || t[n - 1] == '\t'))
    n--;
  if (n >= size)
    return false;
  memcpy(buf, t, n);
  buf[n] = '\0';
  return true;
}

static af_status parse_name(const char *tok, size_t n, const char *name, af_grade_config *g,
                            char *err, size_t len)
{
  char *dst = g->names[g->n_classes];
  if (!trimmed(tok, n, dst, AF_GRADE_NAME_MAX)) {
    af_text_line(err, len, "%s: class %zu's name '%.40s...' is longer than %d characters", name,
                 g->n_classes + 1, tok, AF_GRADE_NAME_MAX - 1);
    return AF_EINVAL;
  }
  if (dst[0] == '\0') {
    af_text(err, len, "%s: class %zu has no name (expected 'name | boundary | name ...')", name,
            g->n_classes + 1);
    return AF_EINVAL;
  }
  if (strcmp(dst, AF_GRADE_UNGRADED) == 0) {
    af_text_line(err, len, "%s: '%s' is reserved for strikes without a class", name, dst);
    return AF_EINVAL;
  }
  for (size_t k = 0; k < g->n_classes; k++)
    if (strcmp(g->names[k], dst) == 0) {
      af_text_line(err, len, "%s: class name '%s' is given twice", name, dst);
      return AF_EINVAL;
    }
  g->n_classes++;
  return AF_OK;
}

static af_status parse_bound(const char *tok, size_t n, const char *name, af_grade_config *g,
                             char *err, size_t len)
{
  char text[64], *end;
  double lo, hi;
  af_grade_quantity_range(g->quantity, &lo, &hi);
  const char *after = g->names[g->n_classes - 1];
  if (!trimmed(tok, n, text, sizeof text) || text[0] == '\0') {
    af_text_line(err, len, "%s: no boundary after class '%s' (expected a number in %s)", name,
                 after, af_grade_quantity_unit(g->quantity));
    return AF_EINVAL;
  }
  errno = 0;
  double v = strtod(text, &end);
  if (end == text || *end != '\0' || errno == ERANGE || !isfinite(v)) {
    af_text_line(err, len, "%s: boundary '%s' after class '%s' is not a number", name, text, after);
    return AF_EINVAL;
  }
  if (!(v >= lo && v <= hi)) {
    af_text(err, len,
            "%s: boundary %g after class '%s' is outside the accepted range [%g, %g] %s of %s",
            name, v, after, lo, hi, af_grade_quantity_unit(g->quantity),
            af_grade_quantity_name(g->quantity));
    return AF_EINVAL;
  }
  if (g->n_classes >= 2 && !(v > g->lower[g->n_classes - 1])) {
    af_text_line(err, len, "%s: boundary %g after class '%s' must be above the one before (%g)",
                 name, v, after, g->lower[g->n_classes - 1]);
    return AF_EINVAL;
  }
  if (g->n_classes >= AF_GRADE_CLASSES_MAX) {
    af_text(err, len, "%s: more than %d classes", name, AF_GRADE_CLASSES_MAX);
    return AF_EINVAL;
  }
  g->lower[g->n_classes] = v;
  return AF_OK;
}

af_status af_grade_config_parse(af_grade_quantity q, const char *spec, const char *name,
                                af_grade_config *out, char *err, size_t len)
{
  if (out == NULL || spec == NULL || !valid_quantity(q)) {
    af_text(err, len, "af_grade_config_parse: a NULL argument or an unknown quantity");
    return AF_EINVAL;
  }
  memset(out, 0, sizeof *out);
  out->quantity = q;
  out->lower[0] = -INFINITY;
  if (name == NULL)
    name = "grade_classes";
  char blank[2];
  if (trimmed(spec, strlen(spec), blank, sizeof blank) && blank[0] == '\0')
    return AF_OK; /* grading off */
  /* name | bound | name | ... : names at even tokens, boundaries at odd ones. */
  const char *p = spec;
  for (size_t k = 0;; k++) {
    size_t n = strcspn(p, "|");
    af_status st =
        k % 2 == 0 ? parse_name(p, n, name, out, err, len) : parse_bound(p, n, name, out, err, len);
    if (st != AF_OK) {
      memset(out, 0, sizeof *out);
      return st;
    }
    if (p[n] == '\0') {
      if (k % 2 == 1) {
        af_text(err, len, "%s: no class name after the last boundary %g", name,
                out->lower[out->n_classes]);
        memset(out, 0, sizeof *out);
        return AF_EINVAL;
      }
      return AF_OK;
    }
    p += n + 1;
  }
}

af_status af_grade_config_from_settings(const af_settings *s, af_grade_config *out, char *err,
                                        size_t len)
{
  char word[64] = "", name[96];
  af_grade_quantity q;
  const af_setting_def *d = af_setting_def_of(AF_SETTING_GRADE_QUANTITY);
  if (af_settings_choice(s, AF_SETTING_GRADE_QUANTITY, word, sizeof word) != AF_OK ||
      af_grade_quantity_parse(word, &q) != AF_OK) {
    af_text_line(err, len, "%s%s = '%s' is not one of: %s", s->name_prefix, d->name, word,
                 d->choices);
    return AF_EINVAL;
  }
  snprintf(name, sizeof name, "%s%s", s->name_prefix,
           af_setting_def_of(AF_SETTING_GRADE_CLASSES)->name);
  const char *spec = af_settings_string(s, AF_SETTING_GRADE_CLASSES);
  return af_grade_config_parse(q, spec ? spec : "", name, out, err, len);
}

void af_grade_config_format(const af_grade_config *g, char *buf, size_t len)
{
  if (buf == NULL || len == 0)
    return;
  if (g == NULL || g->n_classes == 0) {
    snprintf(buf, len, "off");
    return;
  }
  size_t used = 0;
  buf[0] = '\0';
  for (size_t k = 0; k < g->n_classes && used < len; k++) {
    int w = k == 0 ? snprintf(buf + used, len - used, "%s", g->names[k])
                   : snprintf(buf + used, len - used, " < %g <= %s", g->lower[k], g->names[k]);
    used += w > 0 ? (size_t)w : 0;
  }
  if (used < len)
    snprintf(buf + used, len - used, " (%s, %s)", af_grade_quantity_name(g->quantity),
             af_grade_quantity_unit(g->quantity));
}

unsigned af_grade_classify(const af_grade_config *g, double value)
{
  if (g == NULL || g->n_classes == 0 || !isfinite(value))
    return 0;
  size_t k = g->n_classes - 1;
  while (k > 0 && !(value >= g->lower[k]))
    k--;
  return (unsigned)k + 1;
}

static double quantity_of(af_grade_quantity q, const af_measure_report *r)
{
  switch (q) {
  case AF_GRADE_BY_STIFFNESS_FACTOR: return r->stiffness_factor;
  case AF_GRADE_BY_MODULUS_FROM_RESONANCE: return r->modulus_from_resonance_pa;
  case AF_GRADE_BY_FITTED_MODULUS: return r->fitted_modulus_pa;
  }
  return NAN;
}

static void ungraded(af_grade *out)
{
  out->index = 0;
  snprintf(out->name, sizeof out->name, "%s", AF_GRADE_UNGRADED);
}

void af_grade_strike(const af_grade_config *g, const af_measure_report *r, af_grade *out)
{
  memset(out, 0, sizeof *out);
  out->value = NAN;
  if (g == NULL || r == NULL || g->n_classes == 0) {
    ungraded(out);
    snprintf(out->reason, sizeof out->reason,
             "no firmness classes configured (grade_classes is empty)");
    return;
  }
  out->value = quantity_of(g->quantity, r);
  if (!r->reliable) {
    ungraded(out);
    snprintf(out->reason, sizeof out->reason, "not reliable: %.*s",
             (int)(sizeof out->reason - sizeof "not reliable: "),
             r->reason[0] ? r->reason : "(no reason given)");
  } else if (!isfinite(out->value)) {
    ungraded(out);
    snprintf(out->reason, sizeof out->reason, "no %s measured",
             af_grade_quantity_name(g->quantity));
  } else {
    out->index = af_grade_classify(g, out->value);
    snprintf(out->name, sizeof out->name, "%s", g->names[out->index - 1]);
  }
}
