/* paper_work.h — what the files of `firmness_model paper` share (private to
 * src/tools): the run's workspace, the claim rows, the profiles and the
 * figures' and claims' entry points. paper.c is the command, paper_figures.c
 * the Figs. 2-8, paper_claims.c each claim's figure and verdict,
 * paper_report.c DIR/paper.md. */
#ifndef AF_TOOLS_PAPER_WORK_H
#define AF_TOOLS_PAPER_WORK_H

#include <stdbool.h>
#include <stddef.h>

#include "impact.h"
#include "model.h"
#include "spectrum.h"

#define AF_PAPER_PULSE_CAP 8192
#define AF_PAPER_FREQS 600
#define AF_PAPER_FAMILY 6
#define AF_PAPER_SWEEP 81
#define AF_PAPER_W_PX 1400
#define AF_PAPER_H_PX 700
#define AF_PAPER_MD_LINE 1024

/* AF_V_CALIBRATED: the figure agrees because a calibration was chosen to put
 * it there (the yield law's reference on the 31 mm), so the agreement tests
 * nothing and is not called reproduced. */
typedef enum { AF_V_REPRODUCES = 0, AF_V_DIFFERENT, AF_V_DOES_NOT, AF_V_CALIBRATED } af_verdict;

extern const char *const af_paper_verdict_name[4];  /* by af_verdict */
extern const char *const af_paper_profile_key[2];   /* by profile: file names */
extern const char *const af_paper_profile_title[2]; /* by profile: titles */

typedef struct {
  char figure[AF_PAPER_MD_LINE];
  char why[AF_PAPER_MD_LINE];
  af_verdict verdict;
} af_claim_row;

typedef struct {
  af_model *model;
  af_impact *impact;
  af_spectrum *spectrum;
  const char *out_dir;
  char fig_dir[512];
  bool quick;
} af_paper;

/* Profile k: 0 the paper-literal choices, else the shipped one (exit 1 when
 * the parameter table's defaults do not derive). */
af_model_params af_paper_profile(int k);

/* "<m1> g, <v0> m/s; else E2 ..., R2 ..., e ..., nu2 ..." of p (PLplot escapes). */
void af_paper_subtitle(char *buf, size_t len, const af_model_params *p, const char *sep);

/* 0S2 [Hz] of a fruit of mass_kg under p. */
double af_paper_resonance_hz(const af_model_params *p, double mass_kg);

/* The model on the ODE path (the reference). */
af_status af_paper_eval(af_paper *w, const af_model_params *p, af_model_result *r);

/* ---- the figures (paper_figures.c) ---- */

typedef void af_vary_fn(af_model_params *p, double v);
void af_paper_vary_e2(af_model_params *p, double v);
void af_paper_vary_r2(af_model_params *p, double v);
void af_paper_vary_e(af_model_params *p, double v);
void af_paper_vary_nu(af_model_params *p, double v);

typedef struct {
  int number;           /* the paper's figure */
  const char *property; /* "E#d2#u" */
  const char *unit_fmt; /* label of one value, e.g. "E#d2#u %.0f MPa" */
  double scale;         /* value x scale in the label */
  af_vary_fn *vary;
  double values[AF_PAPER_FAMILY];
  size_t n;
} af_family;

typedef struct {
  int number;
  const char *x_label, *property;
  double from, to, scale; /* x axis = value x scale */
  af_vary_fn *vary;
} af_sweep_fig;

/* Figs. 2, 4, 6, 8 and Figs. 3, 5, 7 of profile prof: 0, or 1 after a line. */
int af_paper_family_figure(af_paper *w, int prof, const af_family *fam);
int af_paper_sweep_figure(af_paper *w, int prof, const af_sweep_fig *sf);

/* ---- the claims (paper_claims.c) and the report (paper_report.c) ---- */

typedef af_status af_claim_fn(af_paper *w, int prof, af_claim_row *row);

typedef struct {
  const char *claim, *paper_says, *figs;
  af_claim_fn *fn;
} af_claim;

#define AF_PAPER_N_CLAIMS 7
extern const af_claim af_paper_claims[AF_PAPER_N_CLAIMS];

/* DIR/paper.md from the rows of every claim and profile: 0, or 1. */
int af_paper_write_report(af_paper *w, af_claim_row rows[][2]);

#endif
