/* report_bench.h — firmness_report --bench: the cost of each stage of a strike
 * (stage.h) over a run, as a table.
 *
 * A recorder per worker thread: its hook goes into that worker's lane
 * configuration (af_measure_config.stages), every timed call of a stage is
 * added to the stage's total and to the current strike's sum, and
 * af_report_bench_strike closes the strike (called from the session's strike
 * callback): each stage's sum becomes one per-strike sample (detect and
 * predict: the force chunks and apples since the previous strike; setup:
 * one sample per lane). The rows written by the tool are
 * timed by af_report_bench_serialize_hook in the main thread, text or JSON
 * and CSV of one strike adding up to one sample. The recorders are merged
 * and printed at the end. Allocates (samples grow by doubling): a desk tool. */
#ifndef AF_REPORT_BENCH_H
#define AF_REPORT_BENCH_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "stage.h"

typedef struct {
  int64_t total_ns[AF_STAGES];  /* every timed call [ns] */
  uint64_t calls[AF_STAGES];    /* timed calls */
  int64_t strike_ns[AF_STAGES]; /* the current strike's sum so far [ns] */
  int64_t *samples[AF_STAGES];  /* per-strike sums [ns] */
  size_t n[AF_STAGES], cap[AF_STAGES];
  size_t serialize_base, serialize_at; /* the serialize sample of the row being written */
  bool out_of_memory;
  af_stage_hook hook;           /* for the lane: records into this recorder */
  af_stage_hook serialize_hook; /* for the output functions: one row's write */
} af_report_bench;

void af_report_bench_init(af_report_bench *b); /* zeroed, hooks set: b must not move */
void af_report_bench_free(af_report_bench *b); /* safe twice */

/* Closes the current strike: each lane stage's sum becomes a sample. */
void af_report_bench_strike(af_report_bench *b);

/* Before each output pass over a bag's strikes (the text or JSON rows, then
 * the CSV rows): the pass's k-th row adds to the bag's k-th serialize
 * sample. After the bag's passes: af_report_bench_bag_written(b, n_strikes). */
void af_report_bench_pass(af_report_bench *b);
void af_report_bench_bag_written(af_report_bench *b, size_t n_strikes);

/* Adds from's totals and samples to into. false: out of memory. */
bool af_report_bench_merge(af_report_bench *into, const af_report_bench *from);

/* The table on out: per stage the calls, the median and mean per strike,
 * the total [us] and its share of all the CPU time (the workers' sessions,
 * cpu_s, and the rows written), the 99th percentile and the maximum per
 * strike [us]; other: the rest of the workers' CPU
 * (reading the bags, the streams, the match); then the real-time factor:
 * recorded_s of recording over run_wall_s of wall-clock time (all workers)
 * and over cpu_s. */
void af_report_bench_print(FILE *out, const af_report_bench *b, size_t strikes, double recorded_s,
                           double run_wall_s, double cpu_s, int jobs);

#endif
