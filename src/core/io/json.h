/* json.h — the pieces of JSON the desk tools print (firmness_model analyze,
 * firmness_report): a quoted, escaped string, a number or null, and the
 * names of a verdict's flags. Each tool keeps its own layout. */
#ifndef AF_JSON_H
#define AF_JSON_H

#include <stdint.h>
#include <stdio.h>

#ifdef __cplusplus
extern "C" {
#endif

/* s as a JSON string: quoted, '"' and '\' escaped, control characters as \u00XX. */
void af_json_string(FILE *out, const char *s);

/* v with `digits` significant digits (%.*g), or null when not finite
 * (JSON has no NaN or infinity). */
void af_json_double(FILE *out, double v, int digits);

/* The names of the set af_verdict_flag bits (verdict.h), as a JSON array in
 * flag order, e.g. ["fit_failed", "no_resonance"]. */
void af_json_flags(FILE *out, uint32_t flags);

#ifdef __cplusplus
}
#endif
#endif
