/* output.h — what firmness_report prints: a table per apple and the summary
 * as text, the same as one JSON document, and one CSV row per strike. A
 * strike's fields are written by the core serializer (serialize.h: the
 * StrikeReport's names, every real at %.17g, so that it can be compared with
 * the node's messages to the last bit), followed by the apple's own
 * (apple_stamp_ns, mass_kg, the prediction).
 *
 * Several bags (firmness_report BAG BAG...): a text section per bag, then the
 * combined summary; JSON {"bags": [one document per bag, or {"bag", "error"}],
 * "combined": {"bags", "failed", "summary"}}; CSV rows with a first column
 * "bag". timer (may be NULL): each strike's row is timed as the serialize
 * stage (stage.h, firmness_report --bench). */
#ifndef AF_REPORT_OUTPUT_H
#define AF_REPORT_OUTPUT_H

#include <stdbool.h>
#include <stdio.h>

#include "session.h"
#include "settings.h"
#include "stage.h"
#include "summary.h"

/* The strike table and the apples without a strike, then the summary. */
void af_output_text(FILE *out, const af_session *s, const af_summary *m,
                    const af_stage_hook *timer);
void af_output_text_strikes(FILE *out, const af_session *s, const af_stage_hook *timer);
void af_output_text_summary(FILE *out, const af_session *s, const af_summary *m);

/* One bag's document; its last member is the bag's merge state
 * (merge_state.h), settings: what the bag was run with. */
void af_output_json(FILE *out, const char *bag, const char *ns, const af_session *s,
                    const af_summary *m, const af_settings *settings, const af_stage_hook *timer);
/* A bag that could not be read: {"bag": BAG, "error": LINE}. */
void af_output_json_failed(FILE *out, const char *bag, const char *error);
/* {"bags": N, "failed": F, "summary": {...}} (no newline after it); totals:
 * the summed streams, counters and recorded time (combined.h). */
void af_output_json_combined(FILE *out, size_t bags, size_t failed, const af_session *totals,
                             const af_summary *m);

/* The header (with a first column "bag" when with_bag), then the rows of a
 * session (bag: that column's value; NULL: no such column). */
void af_output_csv_header(FILE *out, bool with_bag);
void af_output_csv_rows(FILE *out, const af_session *s, const char *bag,
                        const af_stage_hook *timer);

#endif
