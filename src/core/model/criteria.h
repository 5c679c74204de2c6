/* criteria.h — the two criteria of a reliable strike (Chen & De Baerdemaeker):
 * the 0S2 resonance lies in the half-power band of the chosen lobe
 * (excites_mode), and the maximum subsurface shear stays below the tissue's
 * yield shear stress (no_damage). Shared by the prediction and the
 * measurement so that both judge with the same settings. */
#ifndef AF_CRITERIA_H
#define AF_CRITERIA_H

#include <stdbool.h>
#include <stddef.h>

#include "spectrum.h"

#ifdef __cplusplus
extern "C" {
#endif

/* band_low_hz <= resonance_hz <= band_high_hz; false for a NULL band. */
bool af_criteria_excites_mode(const af_lobe *band, double resonance_hz);
/* max_shear_pa < yield_shear_pa. */
bool af_criteria_no_damage(double max_shear_pa, double yield_shear_pa);

/* Why a strike is not reliable, in words, into buf ("" when both hold).
 * band may be NULL (the configured lobe does not exist). */
void af_criteria_reason(const af_lobe *band, unsigned lobe, double resonance_hz,
                        double max_shear_pa, double yield_shear_pa, char *buf, size_t len);

#ifdef __cplusplus
}
#endif
#endif
