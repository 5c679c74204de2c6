/* pulse_table.h — the normalised Hertz pulse on a (chi, gamma) grid.
 *
 * After scaling (impact.c: D = (5 m1 v0^2 / (4 K))^(2/5), T = D / v0,
 * F0 = m1 v0^2 / D) the pulse f(tau) = F(t) / F0 with tau = t / T depends
 * only on the damping chi and the gravity number gamma = g D / v0^2. This
 * module runs af_impact_execute once per node of a (chi, gamma) grid and
 * keeps, on the contact's own time s = tau / tau_c in [0, 1], the smooth
 * factor g(s) = f / (s (1 - s))^1.5 (f rises and falls like a 1.5 power at
 * both ends, so g is smooth there), with the node's ln tau_c, normalised
 * impulse and peak. The table is built once per process (call_once, about
 * 0.02 s of ODE runs) and shared read-only by every thread.
 *
 * Evaluation: af_pulse_table_shape interpolates the profile of one
 * (chi, gamma) (cubic Lagrange in chi and gamma, with the slopes in both),
 * af_pulse_shape_eval reads it at any tau (cubic Lagrange in s) with the
 * partial derivatives the fit's Jacobian needs. Accuracy against the ODE:
 * test/core/test_pulse_table.c. No allocation after the build.
 */
#ifndef AF_PULSE_TABLE_H
#define AF_PULSE_TABLE_H

#include <stdbool.h>
#include <stddef.h>

#include "status.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The grid: chi 0 .. 5 in steps of 0.05 (the exact law's e down to 0.2,
 * Hu-Guo's to 0.23), gamma 0 .. 0.06 in steps of 0.01 (the station's strike:
 * 0.003 to 0.006; a 100 g hammer at 0.5 m/s on 2 MPa: 0.05. Under strong
 * gravity and heavy damping the hammer comes to rest on the fruit, a
 * contact without end: from chi 5.5 at gamma 0.06, chi 1 at gamma 0.25),
 * the contact time cut into 64 intervals. */
#define AF_PULSE_TABLE_NCHI 101
#define AF_PULSE_TABLE_CHI_STEP 0.05
#define AF_PULSE_TABLE_NGAMMA 7
#define AF_PULSE_TABLE_GAMMA_STEP 0.01
#define AF_PULSE_TABLE_INTERVALS 64
#define AF_PULSE_TABLE_NODES (AF_PULSE_TABLE_INTERVALS + 1)

typedef struct af_pulse_table af_pulse_table;

/* The process's table, built by the first call (call_once; 1,414 ODE runs).
 * AF_OK and *out set, or the build's status (then *out is NULL). */
af_status af_pulse_table_get(const af_pulse_table **out);

/* Whether (chi, gamma) lies on the grid [0, 5] x [0, 0.06]. */
bool af_pulse_table_covers(double chi, double gamma);

/* One pulse interpolated from the table, with its slopes in chi and gamma;
 * caller-owned (about 1.6 kB), filled by af_pulse_table_shape. */
typedef struct {
  double chi, gamma;
  double tau_c;                         /* contact time [T] */
  double dln_tau_c[2];                  /* d ln tau_c / d chi, d ln tau_c / d gamma */
  double impulse;                       /* int f dtau = 1 + e_delivered + gamma tau_c [m1 v0] */
  double peak;                          /* max f [F0] */
  double g[AF_PULSE_TABLE_NODES];       /* g(s_j), s_j = j / INTERVALS */
  double g_chi[AF_PULSE_TABLE_NODES];   /* dg/dchi */
  double g_gamma[AF_PULSE_TABLE_NODES]; /* dg/dgamma */
} af_pulse_shape;

/* Fills s for (chi, gamma); AF_EINVAL when t or s is NULL or (chi, gamma)
 * lies off the grid (af_pulse_table_covers). */
af_status af_pulse_table_shape(const af_pulse_table *t, double chi, double gamma,
                               af_pulse_shape *s);

/* f = F / F0 at tau [T] (0 before contact and after tau_c) and, when the
 * pointers are not NULL, df/dtau, df/dchi and df/dgamma at fixed tau. */
void af_pulse_shape_eval(const af_pulse_shape *s, double tau, double *f, double *df_dtau,
                         double *df_dchi, double *df_dgamma);

#ifdef __cplusplus
}
#endif
#endif
