/* combined.h — the summary over several bags (firmness_report BAG BAG... or
 * a folder): each bag's summary counts added up, its streams' counters and
 * recorded time summed, and the quantiles taken again over every strike of
 * every bag (not averaged over bags), so that a season's figures come out as
 * if it had been one bag. Keeps six numbers per strike, not the strikes: a
 * bag's rows are freed once written. Allocates (columns grow by doubling). */
#ifndef AF_REPORT_COMBINED_H
#define AF_REPORT_COMBINED_H

#include <stddef.h>

#include "session.h"
#include "summary.h"

typedef struct {
  size_t bags, failed; /* bags added; bags that could not be read (not added) */
  af_summary counts;   /* the additive counts of the bags' summaries */
  af_session totals;   /* no strikes: the streams, lane counters, messages, recorded,
                          wall and CPU time summed over the bags */
  double *col[AF_SUMMARY_COLUMNS];
  size_t n, cap; /* strikes in the columns */
} af_combined;

void af_combined_init(af_combined *c);
void af_combined_free(af_combined *c); /* safe twice */

/* Adds one bag: its session and its summary m. AF_OK or AF_ENOMEM. */
af_status af_combined_add(af_combined *c, const af_session *s, const af_summary *m);

/* Adds one bag known by its merge state (merge_state.h): s without strikes,
 * its summary m and its strikes' columns as n rows of AF_SUMMARY_COLUMNS
 * (af_summary_columns_of's). AF_OK or AF_ENOMEM. */
af_status af_combined_add_rows(af_combined *c, const af_session *s, const af_summary *m,
                               const double *rows, size_t n);

/* The summary over every bag added (the columns are reordered). */
void af_combined_summary(af_combined *c, af_summary *out);

#endif
