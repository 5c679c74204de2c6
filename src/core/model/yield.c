/* yield.c — the yield shear stress law and the measured override. */
#include "yield.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

static double law_at(const af_yield_law *law, double modulus_pa)
{
  return law->ratio * law->reference_modulus_pa *
         pow(modulus_pa / law->reference_modulus_pa, law->exponent);
}

/* Log-log interpolation between the measured points; the law's exponent
 * beyond them. */
static double measured_at(const af_yield_law *law, double modulus_pa)
{
  const af_yield_points *m = &law->measured;
  size_t last = m->n - 1;
  if (modulus_pa <= m->modulus_pa[0])
    return m->yield_shear_pa[0] * pow(modulus_pa / m->modulus_pa[0], law->exponent);
  if (modulus_pa >= m->modulus_pa[last])
    return m->yield_shear_pa[last] * pow(modulus_pa / m->modulus_pa[last], law->exponent);
  size_t k = 0;
  while (k + 1 < last && modulus_pa > m->modulus_pa[k + 1])
    k++;
  double w = log(modulus_pa / m->modulus_pa[k]) / log(m->modulus_pa[k + 1] / m->modulus_pa[k]);
  return exp((1.0 - w) * log(m->yield_shear_pa[k]) + w * log(m->yield_shear_pa[k + 1]));
}

double af_yield_shear_pa(const af_yield_law *law, double modulus_pa)
{
  if (law == NULL || !(modulus_pa > 0.0) || !isfinite(modulus_pa) || !(law->ratio > 0.0) ||
      !isfinite(law->ratio) || !(law->reference_modulus_pa > 0.0) ||
      !isfinite(law->reference_modulus_pa) || !(law->exponent >= 0.0) || !isfinite(law->exponent) ||
      law->measured.n > AF_YIELD_MAX_POINTS)
    return NAN;
  return law->measured.n > 0 ? measured_at(law, modulus_pa) : law_at(law, modulus_pa);
}

static const char *skip_separators(const char *s)
{
  while (*s == ' ' || *s == '\t' || *s == ',')
    s++;
  return s;
}

static int read_positive(const char *s, char **end, double *v)
{
  errno = 0;
  *v = strtod(s, end);
  return *end != s && errno != ERANGE && *v > 0.0 && isfinite(*v);
}

af_status af_yield_points_parse(const char *text, af_yield_points *out, char *err, size_t len)
{
  af_yield_points p = {0};
  const char *s = text ? skip_separators(text) : "";
  while (*s != '\0') {
    char *end;
    double e2, tau;
    if (p.n == AF_YIELD_MAX_POINTS) {
      snprintf(err, err ? len : 0, "more than %d measured yield points", AF_YIELD_MAX_POINTS);
      return AF_EINVAL;
    }
    if (!read_positive(s, &end, &e2) || *end != ':' || !read_positive(end + 1, &end, &tau)) {
      snprintf(err, err ? len : 0,
               "measured yield point %zu is not 'E2:tau' with two positive numbers [Pa]", p.n + 1);
      return AF_EINVAL;
    }
    if (p.n > 0 && !(e2 > p.modulus_pa[p.n - 1])) {
      snprintf(err, err ? len : 0,
               "measured yield point %zu: E2 %g Pa does not increase on the previous point's",
               p.n + 1, e2);
      return AF_EINVAL;
    }
    p.modulus_pa[p.n] = e2;
    p.yield_shear_pa[p.n] = tau;
    p.n++;
    if (*end != '\0' && *end != ' ' && *end != '\t' && *end != ',') {
      snprintf(err, err ? len : 0, "measured yield point %zu is followed by '%c'", p.n, *end);
      return AF_EINVAL;
    }
    s = skip_separators(end);
  }
  *out = p;
  return AF_OK;
}
