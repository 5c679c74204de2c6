/* pulse_table.c — the normalised Hertz pulse on a (chi, gamma) grid and its
 * interpolation (see pulse_table.h).
 *
 * Every interpolation is a four-point Lagrange cubic (error O(h^4), the
 * stencil shifted inwards at the grid's edges); its derivative weights give
 * the slopes, so the fit's Jacobian comes with the value at no extra lookup.
 */
#include "pulse_table.h"

#include <math.h>
#include <stddef.h>
#include <string.h>
#include <threads.h>

#include "impact.h"
#include "numeric.h"

/* Per-node figures besides the profile. */
enum { FIG_LN_TAU_C, FIG_IMPULSE, FIG_PEAK, N_FIGS };

/* The grid's largest chi and gamma [-]. */
#define AF_PT_CHI_MAX ((AF_PULSE_TABLE_NCHI - 1) * AF_PULSE_TABLE_CHI_STEP)
#define AF_PT_GAMMA_MAX ((AF_PULSE_TABLE_NGAMMA - 1) * AF_PULSE_TABLE_GAMMA_STEP)
/* Samples of the second (profile) run: the nodes and a spare for the one
 * at tau_c, which rounding may or may not write. */
#define AF_PT_RUN_CAP (AF_PULSE_TABLE_NODES + 1)
/* Sampling step of the first (events only) run [s]: far longer than any
 * tabulated contact (a few ms), so only the sample at contact is written. */
#define AF_PT_EVENTS_DT_S 1.0

struct af_pulse_table {
  double g[AF_PULSE_TABLE_NCHI][AF_PULSE_TABLE_NGAMMA][AF_PULSE_TABLE_NODES];
  double fig[AF_PULSE_TABLE_NCHI][AF_PULSE_TABLE_NGAMMA][N_FIGS];
};

/* The process's table (static storage: 0.45 MB, no allocation). */
static af_pulse_table shared_table;
static af_status shared_status;
static once_flag shared_once = ONCE_FLAG_INIT;

/* ---- one node ----------------------------------------------------------- */

/* g at the contact start and end: f ~ (5/4) x^1.5 (1 + chi u) with x = tau,
 * u = 1 at the start and x = e_d (tau_c - tau), u = -e_d at the end. */
static double g_start(double chi, double tau_c)
{
  return 1.25 * (1.0 + chi) * tau_c * sqrt(tau_c);
}

static double g_end(double chi, double e_d, double tau_c)
{
  return 1.25 * e_d * sqrt(e_d) * (1.0 - chi * e_d) * tau_c * sqrt(tau_c);
}

/* The node (chi, gamma): a normalising strike (the default hammer and apple
 * at 1 m/s) with chi set through Hu-Guo's law (e = 3 / (3 + 2 chi) gives
 * exactly chi) and gamma through g. Two runs: the contact time, then the
 * pulse sampled at tau_c / INTERVALS. */
static af_status build_node(af_impact *imp, double chi, double gamma, double *g, double *fig)
{
  af_impact_params ip = af_impact_params_default();
  ip.velocity_m_s = 1.0;
  ip.damping = AF_DAMPING_HU_GUO;
  ip.restitution = 3.0 / (3.0 + 2.0 * chi);
  double m1 = ip.hammer_mass_kg, v0 = ip.velocity_m_s;
  double d = pow(1.25 * m1 * v0 * v0 / af_impact_stiffness(&ip), 0.4); /* D [m] */
  double t = d / v0, f0 = m1 * v0 * v0 / d;                            /* T [s], F0 [N] */
  ip.gravity_m_s2 = gamma * v0 * v0 / d;
  af_impact_result res;
  af_status st = af_impact_execute(imp, &ip, AF_PT_EVENTS_DT_S, NULL, NULL, 1, &res);
  if (st != AF_OK)
    return st;
  double force_n[AF_PT_RUN_CAP];
  double dt_s = res.contact_time_s / AF_PULSE_TABLE_INTERVALS;
  st = af_impact_execute(imp, &ip, dt_s, force_n, NULL, AF_PT_RUN_CAP, &res);
  if (st != AF_OK)
    return st;
  if (res.n_samples < AF_PULSE_TABLE_INTERVALS)
    return AF_ENUMERIC;
  double tau_c = res.contact_time_s / t, e_d = res.delivered_restitution;
  g[0] = g_start(chi, tau_c);
  g[AF_PULSE_TABLE_INTERVALS] = g_end(chi, e_d, tau_c);
  for (int j = 1; j < AF_PULSE_TABLE_INTERVALS; j++) {
    double s = (double)j / AF_PULSE_TABLE_INTERVALS, q = s * (1.0 - s);
    g[j] = force_n[j] / f0 / (q * sqrt(q));
  }
  fig[FIG_LN_TAU_C] = log(tau_c);
  fig[FIG_IMPULSE] = 1.0 + e_d + gamma * tau_c;
  fig[FIG_PEAK] = res.peak_force_n / f0;
  return AF_OK;
}

static void shared_build(void)
{
  af_impact *imp = NULL;
  shared_status = af_impact_create(&imp);
  for (int i = 0; i < AF_PULSE_TABLE_NCHI && shared_status == AF_OK; i++)
    for (int j = 0; j < AF_PULSE_TABLE_NGAMMA && shared_status == AF_OK; j++)
      shared_status = build_node(imp, i * AF_PULSE_TABLE_CHI_STEP, j * AF_PULSE_TABLE_GAMMA_STEP,
                                 shared_table.g[i][j], shared_table.fig[i][j]);
  af_impact_destroy(imp);
}

af_status af_pulse_table_get(const af_pulse_table **out)
{
  if (out == NULL)
    return AF_EINVAL;
  call_once(&shared_once, shared_build);
  *out = shared_status == AF_OK ? &shared_table : NULL;
  return shared_status;
}

bool af_pulse_table_covers(double chi, double gamma)
{
  return chi >= 0.0 && chi <= AF_PT_CHI_MAX && gamma >= 0.0 && gamma <= AF_PT_GAMMA_MAX;
}

/* ---- interpolation ------------------------------------------------------ */

/* Four-point Lagrange weights on the nodes -1, 0, 1, 2 at u, and their
 * derivatives in u. */
static inline void lagrange4(double u, double w[4], double dw[4])
{
  double a = u + 1.0, b = u, c = u - 1.0, d = u - 2.0;
  w[0] = -b * c * d / 6.0;
  w[1] = a * c * d / 2.0;
  w[2] = -a * b * d / 2.0;
  w[3] = a * b * c / 6.0;
  dw[0] = -(c * d + b * d + b * c) / 6.0;
  dw[1] = (c * d + a * d + a * c) / 2.0;
  dw[2] = -(b * d + a * d + a * b) / 2.0;
  dw[3] = (b * c + a * c + a * b) / 6.0;
}

/* The stencil of x on nodes 0, step, ..., (count - 1) step: its first node
 * and the weights (derivative weights per unit of x). */
static int stencil(double x, double step, int count, double w[4], double dw[4])
{
  double pos = x / step;
  int i0 = (int)floor(pos) - 1;
  if (i0 < 0)
    i0 = 0;
  if (i0 > count - 4)
    i0 = count - 4;
  lagrange4(pos - (double)(i0 + 1), w, dw);
  for (int a = 0; a < 4; a++)
    dw[a] /= step;
  return i0;
}

AF_NUMERIC_KERNEL af_status af_pulse_table_shape(const af_pulse_table *t, double chi, double gamma,
                                                 af_pulse_shape *s)
{
  if (t == NULL || s == NULL || !af_pulse_table_covers(chi, gamma))
    return AF_EINVAL;
  double wc[4], dwc[4], wg[4], dwg[4];
  int ic = stencil(chi, AF_PULSE_TABLE_CHI_STEP, AF_PULSE_TABLE_NCHI, wc, dwc);
  int ig = stencil(gamma, AF_PULSE_TABLE_GAMMA_STEP, AF_PULSE_TABLE_NGAMMA, wg, dwg);
  memset(s, 0, sizeof *s);
  s->chi = chi;
  s->gamma = gamma;
  double ln_tau_c = 0.0;
  for (int a = 0; a < 4; a++) {
    for (int b = 0; b < 4; b++) {
      double w = wc[a] * wg[b], w_chi = dwc[a] * wg[b], w_gamma = wc[a] * dwg[b];
      const double *row = t->g[ic + a][ig + b], *fig = t->fig[ic + a][ig + b];
      for (int j = 0; j < AF_PULSE_TABLE_NODES; j++) {
        s->g[j] += w * row[j];
        s->g_chi[j] += w_chi * row[j];
        s->g_gamma[j] += w_gamma * row[j];
      }
      ln_tau_c += w * fig[FIG_LN_TAU_C];
      s->dln_tau_c[0] += w_chi * fig[FIG_LN_TAU_C];
      s->dln_tau_c[1] += w_gamma * fig[FIG_LN_TAU_C];
      s->impulse += w * fig[FIG_IMPULSE];
      s->peak += w * fig[FIG_PEAK];
    }
  }
  s->tau_c = exp(ln_tau_c);
  return AF_OK;
}

void af_pulse_shape_eval(const af_pulse_shape *s, double tau, double *f, double *df_dtau,
                         double *df_dchi, double *df_dgamma)
{
  double v = 0.0, v_tau = 0.0, v_chi = 0.0, v_gamma = 0.0;
  double x = tau / s->tau_c;
  if (x > 0.0 && x < 1.0) {
    /* stencil() on the s axis, written out: this runs for every sample */
    double w[4], dw[4], pos = x * AF_PULSE_TABLE_INTERVALS;
    int j0 = (int)pos - 1; /* pos > 0: truncation is floor */
    j0 = j0 < 0 ? 0 : j0 > AF_PULSE_TABLE_INTERVALS - 3 ? AF_PULSE_TABLE_INTERVALS - 3 : j0;
    lagrange4(pos - (double)(j0 + 1), w, dw);
    double g = 0.0, g_s = 0.0, g_chi = 0.0, g_gamma = 0.0;
    for (int a = 0; a < 4; a++) {
      g += w[a] * s->g[j0 + a];
      g_s += dw[a] * s->g[j0 + a];
      g_chi += w[a] * s->g_chi[j0 + a];
      g_gamma += w[a] * s->g_gamma[j0 + a];
    }
    g_s *= AF_PULSE_TABLE_INTERVALS; /* per unit s */
    double q = x * (1.0 - x), rq = sqrt(q), phi = q * rq, dphi = 1.5 * rq * (1.0 - 2.0 * x);
    double p_s = dphi * g + phi * g_s; /* dP/ds */
    v = phi * g;
    v_tau = p_s / s->tau_c;
    v_chi = phi * g_chi - p_s * x * s->dln_tau_c[0];
    v_gamma = phi * g_gamma - p_s * x * s->dln_tau_c[1];
  }
  *f = v;
  if (df_dtau != NULL)
    *df_dtau = v_tau;
  if (df_dchi != NULL)
    *df_dchi = v_chi;
  if (df_dgamma != NULL)
    *df_dgamma = v_gamma;
}
