/* criteria.c — excites_mode, no_damage and the reason text. */
#include "criteria.h"

#include <stdio.h>

bool af_criteria_excites_mode(const af_lobe *band, double resonance_hz)
{
  return band != NULL && resonance_hz >= band->band_low_hz && resonance_hz <= band->band_high_hz;
}

bool af_criteria_no_damage(double max_shear_pa, double yield_shear_pa)
{
  return max_shear_pa < yield_shear_pa;
}

/* Appends to buf at *used, keeping it NUL-terminated and never overflowing. */
static void append(char *buf, size_t len, size_t *used, const char *text)
{
  if (*used >= len)
    return;
  int n = snprintf(buf + *used, len - *used, "%s%s", *used > 0 ? "; " : "", text);
  if (n > 0)
    *used += (size_t)n;
}

void af_criteria_reason(const af_lobe *band, unsigned lobe, double resonance_hz,
                        double max_shear_pa, double yield_shear_pa, char *buf, size_t len)
{
  char part[160];
  size_t used = 0;
  if (len == 0)
    return;
  buf[0] = '\0';
  if (band == NULL) {
    snprintf(part, sizeof part, "spectrum has no lobe %u", lobe);
    append(buf, len, &used, part);
  } else if (!af_criteria_excites_mode(band, resonance_hz)) {
    snprintf(part, sizeof part,
             "resonance %.0f Hz outside the half-power band [%.0f, %.0f] Hz of lobe %u",
             resonance_hz, band->band_low_hz, band->band_high_hz, lobe);
    append(buf, len, &used, part);
  }
  if (!af_criteria_no_damage(max_shear_pa, yield_shear_pa)) {
    snprintf(part, sizeof part, "max shear %.3f MPa not below yield %.3f MPa (bruise risk)",
             max_shear_pa * 1e-6, yield_shear_pa * 1e-6);
    append(buf, len, &used, part);
  }
}
