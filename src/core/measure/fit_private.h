/* fit_private.h — what fit.c (the fit, its ODE path) and fit_table.c (its
 * table path) share: the workspace and the helpers both call. Not part of
 * the API (fit.h). */
#ifndef AF_FIT_PRIVATE_H
#define AF_FIT_PRIVATE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include <gsl/gsl_matrix.h>
#include <gsl/gsl_multifit_nlinear.h>
#include <gsl/gsl_vector.h>

#include "fit.h"
#include "pulse_table.h"

#define AF_FIT_MAX_PARAMS 4
#define AF_IX_MODULUS 0
#define AF_IX_RESTITUTION 1
#define AF_IX_NONE SIZE_MAX

/* The scalars of one interpolated pulse (af_pulse_shape's) that the
 * figures read, for the (chi, gamma) they were interpolated at. */
typedef struct {
  double chi, gamma;
  double tau_c, dln_tau_c[2], impulse, peak;
  bool valid;
} af_fit_figures;

struct af_fit {
  af_fit_config cfg;
  size_t n_params;    /* p */
  size_t ix_velocity; /* index of ln v0 in x, or AF_IX_NONE */
  size_t ix_time;     /* index of t0 / dt in x, or AF_IX_NONE */
  size_t model_cap;   /* samples per model buffer */
  af_impact *impact;
  gsl_multifit_nlinear_workspace *nls;
  gsl_multifit_nlinear_fdf fdf;
  gsl_vector *x_start;                            /* start point */
  gsl_vector *x_prev;                             /* position before the last iteration */
  gsl_matrix *normal;                             /* p x p: scaled J^T J, then its inverse */
  double *model_n;                                /* model at the base point, every h [N] */
  double *probe_n;                                /* model at a perturbed point, every h [N] */
  double *base_at_n;                              /* base model at k dt - t0 [N] */
  double *base_slope_n_s;                         /* its time derivative [N/s] */
  double probe_contact_time_s[AF_FIT_MAX_PARAMS]; /* at x + step e_j, last Jacobian */

  /* The table path. */
  const af_pulse_table *table;    /* the process's, shared read-only */
  af_pulse_shape shape;           /* the base point's interpolated pulse */
  af_fit_figures start_figures;   /* the last matched start's, kept from fit to
                                     fit (af_fit_table_start_figures) */
  double *jac_n;                  /* max_samples x AF_FIT_MAX_PARAMS, row-major, the
                                     columns past n_params 0: the base's Jacobian
                                     [scaled residual per unit x] */
  double *res_n;                  /* the base's scaled residual [-] */
  gsl_matrix_view jac_view;       /* n x p over jac_n, for this fit */
  gsl_vector_view res_view;       /* n over res_n */
  double lm_x[AF_FIT_MAX_PARAMS]; /* the table search's position */
  double lm_jtj[AF_FIT_MAX_PARAMS * AF_FIT_MAX_PARAMS]; /* J^T J of the base's jac_n, p x p
                                                           (lm_normal) ... */
  bool lm_jtj_kept;                                     /* ... while jac_n is that J */
  double res_norm;                                      /* |r| at the reported point */
  size_t lm_iterations;                                 /* its accepted steps */
  double *check_n;                     /* the ODE model at k dt - t0, the check [N] */
  double tc_grad_s[AF_FIT_MAX_PARAMS]; /* d t_c / d x_j at the base [s] */
  size_t from_table, fallbacks;        /* af_fit_counts */
  double *final_res_n;                 /* pulse - model at the reported point [N] ... */
  size_t final_n;                      /* ... its length; 0: no final model (af_fit_get_residual) */

  /* The problem of the current af_fit_execute call. */
  af_impact_params start; /* damping overridden by cfg */
  const double *pulse_n;
  size_t n;
  double dt_s, h_s, t0_start_s;
  double peak_n; /* max_k pulse_k */
  double scale;  /* 1 / (peak sqrt(n)) [1/N] */
  size_t model_runs;
  bool on_table;     /* this search's model: the table (else the ODE) */
  bool left_table;   /* a point of this search left the table's grid */
  bool check_failed; /* the ODE check at the table's optimum failed */

  /* The base point: last parameters the model was evaluated at. */
  bool base_valid;  /* base_x, base_* describe the current problem */
  bool base_failed; /* the model run failed there */
  double base_x[AF_FIT_MAX_PARAMS];
  af_impact_result base_res;
};

/* The scales of one point and their logarithmic derivatives per unit of
 * each scaled parameter (impact.c's scaling: D ~ (m1 v0^2 / E*)^0.4, so
 * d ln T = -0.4 d ln E* - 0.2 d ln v0, d ln F0 = 0.4 d ln E* + 1.2 d ln v0,
 * d ln gamma = -0.4 d ln E* - 1.2 d ln v0). */
typedef struct {
  double t_s, f0_n, chi, gamma;
  double dln_t[AF_FIT_MAX_PARAMS], dln_f0[AF_FIT_MAX_PARAMS];
  double dln_gamma[AF_FIT_MAX_PARAMS], dchi[AF_FIT_MAX_PARAMS];
} af_fit_scales;

/* fit.c */
bool af_fit_is_positive(double v);
double af_fit_restitution_slope(double x); /* de/dx at the scaled x */
void af_fit_unpack(const af_fit *w, const double *x, af_impact_params *p, double *t0_s);
void af_fit_interp(const double *g, size_t n_g, double h_s, double tau_s, double *value,
                   double *slope);
af_status af_fit_base(af_fit *w, const gsl_vector *xv);
bool af_fit_converged(const gsl_vector *dx, const gsl_matrix *J, const gsl_vector *r,
                      double step_tol, double gradient_tol);
const gsl_matrix *af_fit_jacobian(const af_fit *w);
const gsl_vector *af_fit_residual(const af_fit *w);

/* fit_table.c */
af_status af_fit_table_figures(af_fit *w, const double *x, af_fit_scales *sc, double *t0_s);
af_status af_fit_table_start_figures(af_fit *w, const double *x, af_fit_scales *sc, double *t0_s);
af_status af_fit_table_model(af_fit *w, const double *x);
af_status af_fit_table_search(af_fit *w);
af_status af_fit_check_run(af_fit *w, const double *x, af_fit_result *out);
double af_fit_check_shift(const af_fit *w);

#endif
