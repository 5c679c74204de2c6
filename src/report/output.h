/* output.h — what firmness_report prints: a table per apple and the summary
 * as text, the same as one JSON document, and one CSV row per strike. A
 * strike's fields are written by the core serializer (serialize.h: the
 * StrikeReport's names, every real at %.17g, so that it can be compared with
 * the node's messages to the last bit), followed by the apple's own
 * (apple_stamp_ns, mass_kg, the prediction). */
#ifndef AF_REPORT_OUTPUT_H
#define AF_REPORT_OUTPUT_H

#include <stdio.h>

#include "session.h"
#include "summary.h"

void af_output_text(FILE *out, const af_session *s, const af_summary *m);
void af_output_json(FILE *out, const char *bag, const char *ns, const af_session *s,
                    const af_summary *m);
void af_output_csv(FILE *out, const af_session *s);

#endif
