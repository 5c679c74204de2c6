/* merge_run.c — firmness_report --merge (see merge_run.h). */
#include "merge_run.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "file_read.h"
#include "json.h"
#include "json_read.h"
#include "merge_state.h"
#include "output.h"

#define AF_EXIT_USAGE 2
#define AF_ERR_MAX 512

void af_report_print_combined(af_combined *all, bool json)
{
  af_summary m;
  af_combined_summary(all, &m);
  if (json) {
    af_output_json_combined(stdout, all->bags, all->failed, &all->totals, &m);
    return;
  }
  printf("== combined: %zu bags", all->bags);
  if (all->failed)
    printf(" (%zu more not read)", all->failed);
  printf(", %zu strikes ==\n", m.strikes);
  af_output_text_summary(stdout, &all->totals, &m);
}

/* A report's bags: its own merge state (one bag), each element of "bags"
 * (several), a bag not read ({"bag", "error"}) counted as failed. */
static int merge_document(af_combined *all, const af_json_doc *d, af_merge_settings *set, char *err,
                          size_t len)
{
  size_t bags = af_json_member(d, 0, "bags");
  size_t first = bags && d->nodes[bags].type == AF_JSON_ARRAY ? d->nodes[bags].child : 0;
  if (bags == 0)
    first = 0; /* one bag: the document itself */
  else if (d->nodes[bags].type != AF_JSON_ARRAY) {
    snprintf(err, len, "\"bags\" is %s, not an array", af_json_type_name(d->nodes[bags].type));
    return AF_EXIT_USAGE;
  } else if (first == 0)
    return 0; /* a report of no bag */
  for (size_t k = first;; k = d->nodes[k].next) {
    size_t state = af_json_member(d, k, "merge_state");
    if (state == 0 && af_json_member(d, k, "error") != 0)
      all->failed++;
    else if (state == 0) {
      snprintf(err, len, "no \"merge_state\": not a report of firmness_report --json");
      return AF_EXIT_USAGE;
    } else {
      af_status st = af_merge_state_add(all, d, state, set, all->bags == 0, err, len);
      if (st != AF_OK)
        return st == AF_ENOMEM ? 1 : AF_EXIT_USAGE;
    }
    if (bags == 0 || d->nodes[k].next == 0)
      return 0;
  }
}

/* path's bytes, whole (af_file_read_whole: a regular file of at most
 * max_bytes), with no NUL byte: not a text report. */
static af_status read_text(const char *path, size_t max_bytes, char **text, size_t *n, char *err,
                           size_t len)
{
  af_status st = af_file_read_whole(path, max_bytes, "a report", text, n, err, len);
  if (st == AF_OK && memchr(*text, '\0', *n) != NULL) {
    snprintf(err, len, "%s: holds a NUL byte: not a JSON report", path);
    free(*text);
    *text = NULL;
    st = AF_EINVAL;
  }
  return st;
}

/* One report file, read whole (a regular file of at most AF_MERGE_MAX_BYTES). */
static int merge_file(af_combined *all, const char *path, af_merge_settings *set)
{
  char err[AF_ERR_MAX];
  size_t n = 0;
  char *text = NULL;
  af_status st = read_text(path, AF_MERGE_MAX_BYTES, &text, &n, err, sizeof err);
  if (st != AF_OK) {
    fprintf(stderr, "firmness_report: --merge %s\n", err);
    return st == AF_ENOMEM ? 1 : AF_EXIT_USAGE;
  }
  af_json_doc d;
  int code;
  st = af_json_parse(text, n, &d, err, sizeof err);
  if (st != AF_OK)
    code = st == AF_ENOMEM ? 1 : AF_EXIT_USAGE;
  else
    code = merge_document(all, &d, set, err, sizeof err);
  if (code)
    fprintf(stderr, "firmness_report: --merge %s: %s\n", path, err);
  af_json_free(&d);
  free(text);
  return code;
}

int af_report_merge(char *const *paths, size_t n, bool json)
{
  static af_merge_settings set; /* large: not on the stack */
  af_combined all;
  af_combined_init(&all);
  int code = 0;
  for (size_t k = 0; k < n && code == 0; k++)
    code = merge_file(&all, paths[k], &set);
  if (code == 0) {
    if (json) {
      fputs("{\n  \"merged\": [", stdout);
      for (size_t k = 0; k < n; k++) {
        fputs(k ? ", " : "", stdout);
        af_json_string(stdout, paths[k]);
      }
      fputs("],\n  \"combined\": ", stdout);
    }
    af_report_print_combined(&all, json);
    if (json)
      fputs("\n}\n", stdout);
  }
  af_combined_free(&all);
  return code;
}
