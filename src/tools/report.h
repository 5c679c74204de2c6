/* report.h — what firmness_model prints: JSON (the keys rig scripts and tests
 * read), CSV rows for sweeps, and a readable summary. */
#ifndef AF_REPORT_H
#define AF_REPORT_H

#include <stdio.h>

#include "fastpath.h"
#include "model.h"

/* R2_min search bracket [m]: from a sharp bump to a nearly flat cheek. */
#define AF_REPORT_R2_LO_M 0.002
#define AF_REPORT_R2_HI_M 0.5

typedef struct {
  af_model_params params;
  af_model_result result;
  double min_strike_radius_m; /* NAN when no radius in the bracket is reliable */
} af_report;

/* Evaluates p and searches R2_min into rep. */
af_status af_report_compute(af_model *m, const af_model_params *p, af_report *rep);
/* The same on the fast path (fastpath.h): the table, the ODE path where it
 * falls back. */
af_status af_report_compute_fast(af_fastpath *f, const af_model_params *p, af_report *rep);

void af_report_json(FILE *out, const af_report *rep);
void af_report_text(FILE *out, const af_report *rep);
/* CSV header and row; the first column is the swept flag. */
void af_report_csv_header(FILE *out, const char *param);
void af_report_csv_row(FILE *out, double value, const af_report *rep);

#endif
