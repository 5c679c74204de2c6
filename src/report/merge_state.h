/* merge_state.h — what a bag's report must carry so that reports made apart
 * (a season spread over several machines) merge into the very summary one
 * run over all the bags prints.
 *
 * The combined summary (combined.h) adds each bag's counts, streams and lane
 * counters and takes its quantiles again over six numbers per strike; the
 * report's printed summary rounds them. So every JSON report holds a
 * "merge_state" member with exactly what af_combined_add reads, each real in
 * the digits that read back as the same double (null for NaN), plus the
 * settings the bag was run with: reports run with different settings are
 * not merged (their figures do not belong in one distribution). One table
 * of fields serves the writer and the reader, so the two cannot drift. */
#ifndef AF_REPORT_MERGE_STATE_H
#define AF_REPORT_MERGE_STATE_H

#include <stdio.h>

#include "combined.h"
#include "json_read.h"
#include "settings.h"

/* The format's name, first member of every merge_state; a reader refuses others. */
#define AF_MERGE_STATE_FORMAT "acoustic_firmness merge_state 1"

/* Writes `"merge_state": {...}` (no comma around it) for one bag: its
 * session s (streams, lane counters; its strikes as six columns each), its
 * summary m and the settings it ran with. */
void af_merge_state_write(FILE *out, const af_session *s, const af_summary *m,
                          const af_settings *settings);

/* The settings as run, the node's snapshot lines (snapshot_text.h) in row
 * order: what two reports must share to merge (and what a message quotes
 * when they do not). A line is at most a name, ": " and a value quoted and
 * escaped. */
typedef struct {
  char text[AF_SETTING_COUNT][AF_SETTINGS_NAME_MAX + 2 * AF_SETTINGS_TEXT_MAX + 8];
} af_merge_settings;

/* Adds the bag whose merge_state is node k of doc to c. settings: the
 * first bag's (filled when first is true, else compared). AF_OK; AF_EINVAL
 * with one line in err naming the member that is missing, of the wrong type,
 * out of range, or the first setting that differs; AF_ENOMEM. */
af_status af_merge_state_add(af_combined *c, const af_json_doc *doc, size_t k,
                             af_merge_settings *settings, bool first, char *err, size_t len);

#endif
