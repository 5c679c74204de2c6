/* serialize.h — one measured strike as text: a JSON object and a CSV row,
 * from one table of fields, for every desk tool (firmness_model analyze,
 * firmness_report). The node sends the same figures as messages (its
 * StrikeReport and measured Reliability); the messages' field names stay
 * as they are (an interface for subscribers), but here every field carries
 * its SI unit in its name (`resonance_hz`, `peak_force_n`, `impulse_n_s`,
 * `max_shear_stress_pa`; a dimensionless one none: `resonance_q`), and each
 * row of the table names the message field it is (StrikeReport.resonance;
 * NULL: report-only), so that a strike can be compared with the node's
 * field by field through the table (firmness_report --fields --json, read
 * by scripts/node_vs_report.py).
 *
 * One precision: every real in the fewest of 15, 16 or 17 significant
 * digits (%.*g) that read back as the same double (17 always do), so that
 * the node's messages and a report can be compared to the last bit, and 0.2
 * is written 0.2. A figure not measured (NaN, or infinite) is
 * JSON null and an empty CSV cell; text is a JSON string, and a CSV cell in
 * double quotes with its quotes doubled (RFC 4180); booleans are true/false
 * in JSON and 1/0 in CSV; the verdict's flags are a JSON array of names and
 * one CSV cell "name|name".
 *
 * The caller writes its own wrapper around a strike (analyze's list,
 * firmness_report's apple and prediction columns): the members and the
 * cells come without braces and without a line end. Pure functions, no
 * allocation; the strike is read during the call only. */
#ifndef AF_SERIALIZE_H
#define AF_SERIALIZE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "grade.h"
#include "lane.h"
#include "measure.h"

#ifdef __cplusplus
extern "C" {
#endif

/* What is written of one strike: the lane's strike result (lane.h), or a
 * copy of its parts that a tool kept. Every pointer must be valid. */
typedef struct {
  int64_t stamp_ns;                /* contact start [ns] (StrikeReport header.stamp) */
  const char *frame_id;            /* the force chunk's (StrikeReport header.frame_id) */
  uint32_t apple_id;               /* 0 = none */
  bool with_audio;                 /* an audio window was analysed */
  const af_measure_report *report; /* the figures and the measured verdict */
  const af_grade *grade;           /* the firmness grade */
} af_serial_strike;

/* The view of a lane's strike result (borrowed: valid while s is). */
af_serial_strike af_serial_of_lane(const af_lane_strike *s);

typedef enum {
  AF_SERIAL_REAL, /* double, af_serialize_real; null / empty when not finite */
  AF_SERIAL_INT,  /* integer */
  AF_SERIAL_BOOL, /* true/false; 1/0 in CSV */
  AF_SERIAL_TEXT, /* string */
  AF_SERIAL_FLAGS /* the verdict's flag names */
} af_serial_kind;

/* One row of the table. */
typedef struct {
  const char *name; /* JSON key and CSV column: unit-suffixed (the unit's
                       lower-case symbols joined by _: "N s" -> _n_s) */
  af_serial_kind kind;
  const char *unit;          /* SI unit, "-" for none, "" for text and flags */
  const char *message;       /* "StrikeReport" or "Reliability": the node's message that
                                carries it, or NULL: report-only */
  const char *message_field; /* its field there ("resonance", "header.stamp" as ns), or NULL */
  const char *meaning;
} af_serial_field;

/* The table, in the order written: *n rows. */
const af_serial_field *af_serial_fields(size_t *n);
/* "real", "integer", "boolean", "text" or "flags". */
const char *af_serial_kind_name(af_serial_kind kind);
/* The table as a markdown table (field, type, unit, message.field or
 * "report-only", meaning), header line included, each row ending in \n:
 * firmness_report --fields, the generated block of doc/report.md. */
void af_serialize_fields_markdown(FILE *out);
/* The same as a JSON array of {name, type, unit, message, message_field,
 * meaning} (null for a report-only field's message): firmness_report
 * --fields --json, read by scripts/node_vs_report.py. */
void af_serialize_fields_json(FILE *out);

/* The members of s's JSON object, "key": value, separated by sep (", " for
 * one line, ",\n      " for one member per line); no braces. */
void af_serialize_json_members(FILE *out, const af_serial_strike *s, const char *sep);
/* {members} on one line, without a line end. */
void af_serialize_json(FILE *out, const af_serial_strike *s);

/* x in the fewest significant digits (15 to 17, %g) that strtod reads back
 * as x: the one format of every real (finite x; the callers write NaN). */
void af_serialize_real(FILE *out, double x);
/* The names of the verdict flags set in flags (verdict.h), in flag order,
 * separated by sep (nothing when none is set). */
void af_serialize_flags(FILE *out, uint32_t flags, const char *sep);
/* A CSV cell of text: in double quotes, its quotes doubled (RFC 4180). */
void af_serialize_csv_text(FILE *out, const char *text);

/* The CSV header cells (the table's names), comma separated, no line end. */
void af_serialize_csv_header(FILE *out);
/* s's CSV cells in the header's order, comma separated, no line end. */
void af_serialize_csv_row(FILE *out, const af_serial_strike *s);

#ifdef __cplusplus
}
#endif
#endif
