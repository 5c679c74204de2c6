/* grade.h — the firmness grade of a measured strike, for the sorter.
 *
 * The cultivar's YAML names firmness classes by their boundaries on one
 * measured quantity, as a commercial acoustic firmness sensor sorts into
 * firmness bands:
 *
 *   grade_quantity: stiffness_factor     # stiffness_factor | modulus_from_resonance |
 * fitted_modulus grade_classes: "soft | 7.0e+4 | medium | 1.1e+5 | firm | 1.6e+5 | very firm"
 *
 * grade_classes lists the class names from the softest up, each pair of
 * neighbours separated by the boundary between them (in the quantity's unit,
 * strictly rising); a value equal to a boundary belongs to the class above.
 * N names give classes 1..N; "" turns grading off. Both are rows of the one
 * parameter table (settings.h); the spec is checked here, one line per error
 * naming the row, the token and what is accepted.
 *
 * A measured strike gets class index 1..N and its name, or index 0
 * ("ungraded") with a reason: the strike is not reliable (its own reason),
 * its quantity could not be measured, or grading is off. No allocation; pure
 * functions. */
#ifndef AF_GRADE_H
#define AF_GRADE_H

#include <stdbool.h>
#include <stddef.h>

#include "measure.h"
#include "settings.h"
#include "status.h"

#ifdef __cplusplus
extern "C" {
#endif

#define AF_GRADE_CLASSES_MAX 16 /* classes of one cultivar */
#define AF_GRADE_NAME_MAX 32    /* a class name, with its NUL */
#define AF_GRADE_TEXT_MAX 256   /* a reason, with its NUL */
#define AF_GRADE_UNGRADED "ungraded"

/* What the classes are read on (the figures of a StrikeReport). */
typedef enum {
  AF_GRADE_BY_STIFFNESS_FACTOR = 0,   /* f^2 m^(2/3) [Hz^2 kg^(2/3)] */
  AF_GRADE_BY_MODULUS_FROM_RESONANCE, /* E2 from the 0S2, modulus factor applied [Pa] */
  AF_GRADE_BY_FITTED_MODULUS          /* E2 of the impact model fitted to the pulse [Pa] */
} af_grade_quantity;

typedef struct {
  af_grade_quantity quantity;
  size_t n_classes;                                    /* 0 = grading off */
  char names[AF_GRADE_CLASSES_MAX][AF_GRADE_NAME_MAX]; /* softest first */
  double lower[AF_GRADE_CLASSES_MAX];                  /* lower[k]: boundary below class k + 1
                                                          (lower[0] = -inf) [the quantity's unit] */
} af_grade_config;

/* The quantity's word ("stiffness_factor", ...) and unit ("Hz2 kg^(2/3)", "Pa"). */
const char *af_grade_quantity_name(af_grade_quantity q);
const char *af_grade_quantity_unit(af_grade_quantity q);
/* AF_OK and *out for a word of grade_quantity; AF_EINVAL otherwise. */
af_status af_grade_quantity_parse(const char *word, af_grade_quantity *out);
/* The accepted interval of a boundary on q: stiffness factor [1e3, 1e8]
 * Hz^2 kg^(2/3) (a sphere of 100-3000 kg/m3 over the table's modulus range);
 * the moduli take the range of the table's modulus_nominal_pa row. */
void af_grade_quantity_range(af_grade_quantity q, double *lo, double *hi);

/* Parses spec for quantity q into *out (zeroed first). name is how messages
 * call the spec (e.g. "~grade_classes"). AF_OK; AF_EINVAL with one line in
 * err: more than AF_GRADE_CLASSES_MAX classes, an empty or too long name, a
 * name given twice, a boundary that is not a number, outside the quantity's
 * range or not above the one before, a missing name or boundary. */
af_status af_grade_config_parse(af_grade_quantity q, const char *spec, const char *name,
                                af_grade_config *out, char *err, size_t len);

/* grade_quantity and grade_classes of s (with its name prefix in messages). */
af_status af_grade_config_from_settings(const af_settings *s, af_grade_config *out, char *err,
                                        size_t len);

/* "soft < 7e+04 <= medium < ... (stiffness_factor, Hz2 kg^(2/3))", or "off". */
void af_grade_config_format(const af_grade_config *g, char *buf, size_t len);

/* The class of value (index 1..n); 0 when grading is off or value is not finite. */
unsigned af_grade_classify(const af_grade_config *g, double value);

/* One measured strike's grade. */
typedef struct {
  unsigned index;                 /* 1..n_classes; 0 = ungraded */
  char name[AF_GRADE_NAME_MAX];   /* the class name, or AF_GRADE_UNGRADED */
  double value;                   /* the quantity it was read on; NaN when not measured */
  char reason[AF_GRADE_TEXT_MAX]; /* why ungraded; "" when graded */
} af_grade;

/* Grades r: ungraded when grading is off, when r is not reliable (reason
 * "not reliable: " + r's reason) or when its quantity is NaN. */
void af_grade_strike(const af_grade_config *g, const af_measure_report *r, af_grade *out);

#ifdef __cplusplus
}
#endif
#endif
