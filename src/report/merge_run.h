/* merge_run.h — firmness_report --merge: reports made apart (each bag's
 * --json, on several machines) read back and added in the order given into
 * the combined summary one run over all their bags prints (merge_state.h
 * says what each report carries). */
#ifndef AF_REPORT_MERGE_RUN_H
#define AF_REPORT_MERGE_RUN_H

#include <stdbool.h>
#include <stddef.h>

#include "combined.h"

/* A report read is at most this long [bytes]. */
#define AF_MERGE_MAX_BYTES ((size_t)1 << 30)

/* The combined section: its heading and the summary over all, as text, or
 * the "combined" member's value as JSON (stdout). */
void af_report_print_combined(af_combined *all, bool json);

/* Reads the reports paths[0..n) and prints their combined summary (with
 * json: {"merged": [paths], "combined": {...}}). The exit status: 0; 2 with
 * one line on stderr naming the report and the fault (not a report, another
 * format, other settings, a member missing, cut short); 1 out of memory. */
int af_report_merge(char *const *paths, size_t n, bool json);

#endif
