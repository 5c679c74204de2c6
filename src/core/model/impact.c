/* impact.c — hammer-on-fruit impact: Hertz contact with hysteresis damping.
 *
 * The model is integrated in elastic-dimensionless form. With the scales
 *     D = (5 m1 v0^2 / (4 K))^(2/5)  [m]  (elastic d_max, PHYSICS.md 3),
 *     T = D / v0                     [s],
 *     F0 = m1 v0^2 / D               [N],
 * x = d/D, u = d'/v0 and tau = t/T obey
 *     x' = u,   u' = gamma - (5/4) x^1.5 (1 + chi u),   gamma = g D / v0^2,
 * so the elastic pulse is universal (tau_c = 2.94328, x_max = 1, F_max = 5/4)
 * and the restitution delivered by a given chi depends on nothing else when
 * g = 0. Tolerances are then plain numbers and the exact damping law is one
 * table, built once per process (by the first af_impact_create, about 10 ms
 * of ODE runs) and read by every workspace after it.
 */
#include "impact.h"

#include <gsl/gsl_errno.h>
#include <gsl/gsl_interp.h>
#include <gsl/gsl_odeiv2.h>
#include <math.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>
#include <threads.h>

#include "af_defaults.h"
#include "numeric.h"

/* Elastic contact time without gravity in units of (m1^2/(R E*^2 v0))^(1/5):
 * tau_c (15/16)^(2/5), with tau_c = 2 int_0^1 dx / sqrt(1 - x^2.5)
 * = (4/5) B(2/5, 1/2) = 2.9432751843 in units of D/v0. */
#define AF_HERTZ_TIME_FACTOR 2.8682656991953315

/* Integration tolerances on x and u (both of order 1): the delivered
 * restitution, the event times and the samples then carry errors of about
 * 1e-9. Measured at the default strike, Cash-Karp 4(5) takes about 66 steps
 * (460 evaluations, 11 us) per pulse; rk8pd ran as fast only with steps so
 * long that the interpolated samples fell to 2e-7, rkf45 needed 15 % more
 * evaluations. */
#define AF_EPS_ABS 1e-10
#define AF_EPS_REL 1e-9
/* First trial step [D/v0]: x^1.5 has an unbounded second derivative at
 * contact, so the controller starts small and grows. */
#define AF_H_START 1e-3
/* Accepted Newton step in the event search [D/v0]. The extremum values get a
 * second-order correction after it, so their error is ~ this cubed. */
#define AF_EVENT_TOL 1e-5
#define AF_EVENT_ITER 60
/* Largest step [D/v0] (the elastic pulse lasts 2.94): keeps the quintic
 * interpolant that writes the samples to ~1e-9. */
#define AF_H_MAX 0.15
/* A contact longer than this [D/v0] (about 340 elastic pulses) is a hammer
 * resting on the fruit, not a strike. */
#define AF_TAU_LIMIT 1000.0

/* Exact damping law table: nodes e = 0.05, 0.075, ..., 1. The smooth and
 * bounded y(e) = chi e / (1 - e) (Hu-Guo would be 1.5 everywhere) is
 * interpolated, not chi itself, which diverges at e -> 0. */
#define AF_EXACT_E_MIN 0.05
#define AF_EXACT_N 39
#define AF_EXACT_STEP 0.025
/* y at e = 1, where chi e/(1 - e) is 0/0: to first order in chi the energy
 * lost over the elastic pulse is chi (5/4) int x^1.5 u^2 dtau = (2/3) chi
 * (units m1 v0^2), so (1 - e^2)/2 = 2 chi/3: Lankarani-Nikravesh is exact in
 * this limit and y -> 3 (1 + e) e/4 = 1.5. */
#define AF_EXACT_Y_ELASTIC 1.5

typedef struct {
  double chi;   /* damping coefficient [-] */
  double gamma; /* g D / v0^2 [-] */
} af_rhs_params;

/* A dimensionless state: time, deformation, deformation rate. */
typedef struct {
  double t, x, u;
} af_state;

struct af_impact {
  gsl_odeiv2_step *step;
  gsl_odeiv2_control *control;
  gsl_odeiv2_evolve *evolve;
  gsl_odeiv2_system sys;
  af_rhs_params rhs;          /* sys.params points here */
  size_t steps_left;          /* of AF_IMPACT_STEP_BUDGET, for the pulse being run */
  double tol_factor;          /* control's tolerances: AF_EPS_ABS, AF_EPS_REL times this */
  gsl_interp *exact;          /* y(e) of the exact law */
  double exact_e[AF_EXACT_N]; /* nodes [-] */
  double exact_y[AF_EXACT_N]; /* chi e/(1-e) at the nodes [-] */
};

/* Where and how one pulse is sampled. */
typedef struct {
  double tau_first;      /* first sample's time [D/v0], >= 0 (0: at contact) */
  double dtau;           /* sampling step [D/v0] */
  size_t cap;            /* samples that fit */
  double *force_n;       /* may be NULL */
  double *deformation_m; /* may be NULL */
  double force_scale_n;  /* F0 */
  double length_scale_m; /* D */
} af_sink;

/* What one pulse delivers, dimensionless. */
typedef struct {
  double tau_c;    /* contact end */
  double u_c;      /* d'/v0 at the contact end (negative) */
  double tau_peak; /* force peak */
  double f_peak;   /* F / F0 at the peak */
  double x_max;    /* d_max / D */
  size_t n;        /* samples written */
} af_pulse;

/* ---- names, parameters, closed forms ---------------------------------- */

const char *af_damping_law_name(af_damping_law law)
{
  switch (law) {
  case AF_DAMPING_PAPER: return "paper";
  case AF_DAMPING_EXACT: return "exact";
  case AF_DAMPING_HU_GUO: return "hu-guo";
  }
  return "unknown";
}

af_status af_damping_law_parse(const char *name, af_damping_law *law)
{
  static const af_damping_law laws[] = {AF_DAMPING_PAPER, AF_DAMPING_EXACT, AF_DAMPING_HU_GUO};
  if (name == NULL || law == NULL)
    return AF_EINVAL;
  for (size_t i = 0; i < sizeof laws / sizeof laws[0]; i++) {
    if (strcmp(name, af_damping_law_name(laws[i])) == 0) {
      *law = laws[i];
      return AF_OK;
    }
  }
  return AF_EINVAL;
}

af_impact_params af_impact_params_default(void)
{
  af_impact_params p = {
      /* the shipped rig's hammer, said once in the parameter table */
      .hammer_mass_kg = AF_RIG_HAMMER_MASS_KG,
      .velocity_m_s = AF_DEFAULT_STRIKE_VELOCITY_M_S,
      .hammer_modulus_pa = AF_DEFAULT_HAMMER_MODULUS_PA,
      .hammer_poisson = AF_DEFAULT_HAMMER_POISSON,
      .hammer_radius_m = AF_RIG_HAMMER_TIP_RADIUS_M,
      .fruit_modulus_pa = AF_DEFAULT_MODULUS_NOMINAL_PA,
      .fruit_poisson = AF_DEFAULT_FRUIT_POISSON,
      .strike_radius_m = 0.04, /* R2 [m]: no row (per apple, from its estimate) */
      .restitution = AF_DEFAULT_RESTITUTION,
      .gravity_m_s2 = AF_DEFAULT_GRAVITY_M_S2,
      .damping = AF_DAMPING_EXACT,
  };
  return p;
}

double af_impact_effective_modulus_pa(const af_impact_params *p)
{
  if (p == NULL)
    return NAN;
  double compliance = (1.0 - p->fruit_poisson * p->fruit_poisson) / p->fruit_modulus_pa;
  if (p->hammer_modulus_pa > 0.0) /* 0 = rigid hammer: no compliance of its own */
    compliance += (1.0 - p->hammer_poisson * p->hammer_poisson) / p->hammer_modulus_pa;
  return 1.0 / compliance;
}

double af_impact_effective_radius_m(const af_impact_params *p)
{
  if (p == NULL)
    return NAN;
  double curvature = 1.0 / p->strike_radius_m;
  if (p->hammer_radius_m > 0.0) /* 0 = flat face: no curvature of its own */
    curvature += 1.0 / p->hammer_radius_m;
  return 1.0 / curvature;
}

double af_impact_stiffness(const af_impact_params *p)
{
  if (p == NULL)
    return NAN;
  return 4.0 / 3.0 * af_impact_effective_modulus_pa(p) * sqrt(af_impact_effective_radius_m(p));
}

double af_impact_hertz_contact_time_s(const af_impact_params *p)
{
  if (p == NULL)
    return NAN;
  double e_star = af_impact_effective_modulus_pa(p);
  double m1 = p->hammer_mass_kg;
  return AF_HERTZ_TIME_FACTOR *
         pow(m1 * m1 / (af_impact_effective_radius_m(p) * e_star * e_star * p->velocity_m_s), 0.2);
}

double af_impact_delivered_energy_j(double hammer_mass_kg, double velocity_m_s)
{
  return 0.5 * hammer_mass_kg * velocity_m_s * velocity_m_s; /* NaN propagates */
}

double af_impact_absorbed_energy_j(double delivered_energy_j, double restitution)
{
  return (1.0 - restitution * restitution) * delivered_energy_j;
}

/* ---- dimensionless dynamics ------------------------------------------- */

/* F / F0. Contact cannot pull: the factor 1 + chi u is clamped at 0. In exact
 * arithmetic the clamp never binds, since w = 1 + chi u obeys
 * w' = chi gamma - chi (5/4) x^1.5 w and so cannot cross 0 from above (the
 * delivered restitution stays below 1/chi); it guards round-off only. Out of
 * contact (x <= 0) the hammer flies free. */
static double hertz_force(double x, double u, double chi)
{
  if (x <= 0.0)
    return 0.0;
  double w = 1.0 + chi * u;
  return w > 0.0 ? 1.25 * x * sqrt(x) * w : 0.0;
}

static int ode_rhs(double t, const double y[], double dydt[], void *params)
{
  (void)t;
  const af_rhs_params *p = params;
  if (!isfinite(y[0]) || !isfinite(y[1]))
    return GSL_EBADFUNC; /* stops the integration at once: AF_ENUMERIC */
  dydt[0] = y[1];
  dydt[1] = p->gamma - hertz_force(y[0], y[1], p->chi);
  return GSL_SUCCESS;
}

static double accel(const af_rhs_params *p, const af_state *s)
{
  return p->gamma - hertz_force(s->x, s->u, p->chi);
}

/* dF/dtau / F0 (the force-peak event) and its derivative, using u' = a and
 * a' = -dF/dtau. Zero out of contact. */
static void force_rate(const af_rhs_params *p, const af_state *s, double *g, double *dg)
{
  if (s->x <= 0.0) {
    *g = 0.0;
    *dg = -INFINITY; /* the rate falls to 0 like -sqrt(x) as contact ends */
    return;
  }
  double rx = sqrt(s->x), w = 1.0 + p->chi * s->u, a = accel(p, s);
  *g = 1.25 * (1.5 * rx * s->u * w + s->x * rx * p->chi * a);
  *dg = 1.25 * (0.75 * s->u * s->u * w / rx + 1.5 * rx * a * (w + 2.0 * p->chi * s->u) -
                s->x * rx * p->chi * *g);
}

typedef enum { AF_EVENT_CONTACT_END, AF_EVENT_MAX_DEFORMATION, AF_EVENT_FORCE_PEAK } af_event;

/* The event function (each crosses from + to -) and its tau-derivative. */
static void event_eval(const af_rhs_params *p, af_event ev, const af_state *s, double *f,
                       double *df)
{
  switch (ev) {
  case AF_EVENT_CONTACT_END:
    *f = s->x;
    *df = s->u;
    return;
  case AF_EVENT_MAX_DEFORMATION:
    *f = s->u;
    *df = accel(p, s);
    return;
  case AF_EVENT_FORCE_PEAK: force_rate(p, s, f, df); return;
  }
}

static af_status status_from_gsl(int gsl_status)
{
  if (gsl_status == GSL_SUCCESS)
    return AF_OK;
  return gsl_status == GSL_EBADFUNC ? AF_ENUMERIC : AF_ENOCONV;
}

/* One accepted adaptive step from s; *h is the trial step in, the next
 * suggested step out, capped at AF_H_MAX so the interpolant between steps
 * stays accurate. */
static af_status ode_step(af_impact *w, af_state *s, double *h)
{
  double y[2] = {s->x, s->u};
  double t = s->t;
  if (w->steps_left == 0)
    return AF_EBUDGET_ODE_STEPS;
  w->steps_left--;
  *h = fmin(*h, AF_H_MAX);
  int rc = gsl_odeiv2_evolve_apply(w->evolve, w->control, w->step, &w->sys, &t, AF_TAU_LIMIT, h, y);
  if (rc != GSL_SUCCESS)
    return status_from_gsl(rc);
  if (!isfinite(y[0]) || !isfinite(y[1]))
    return AF_ENUMERIC;
  s->t = t;
  s->x = y[0];
  s->u = y[1];
  return AF_OK;
}

/* The state at t >= from->t, integrated afresh from `from`: usually one
 * step, since t lies inside an interval the controller already accepted.
 * evolve keeps the derivative at the end of its last step for the next one
 * (GSL 2.7), so it is reset on leaving and rejoining the main trajectory. */
static af_status state_at(af_impact *w, const af_state *from, double t, af_state *out)
{
  *out = *from;
  double h = t - from->t;
  gsl_odeiv2_evolve_reset(w->evolve);
  int rc = GSL_SUCCESS;
  while (out->t < t && rc == GSL_SUCCESS) {
    if (w->steps_left == 0)
      return AF_EBUDGET_ODE_STEPS;
    w->steps_left--;
    double y[2] = {out->x, out->u};
    rc = gsl_odeiv2_evolve_apply(w->evolve, w->control, w->step, &w->sys, &out->t, t, &h, y);
    out->x = y[0];
    out->u = y[1];
  }
  gsl_odeiv2_evolve_reset(w->evolve);
  if (rc != GSL_SUCCESS)
    return status_from_gsl(rc);
  return isfinite(out->x) && isfinite(out->u) ? AF_OK : AF_ENUMERIC;
}

/* Cubic Hermite value and slope on s in [0, 1] from end values f0, f1 and
 * end slopes m0, m1 (already multiplied by the interval length). */
static void hermite(double f0, double m0, double f1, double m1, double s, double *p, double *dp)
{
  double s2 = s * s, s3 = s2 * s;
  *p =
      (2 * s3 - 3 * s2 + 1) * f0 + (s3 - 2 * s2 + s) * m0 + (3 * s2 - 2 * s3) * f1 + (s3 - s2) * m1;
  *dp = (6 * s2 - 6 * s) * f0 + (3 * s2 - 4 * s + 1) * m0 + (6 * s - 6 * s2) * f1 +
        (3 * s2 - 2 * s) * m1;
}

/* A first guess in (0, 1) for the root of the cubic Hermite interpolant,
 * f0 > 0 >= f1: Newton safeguarded by bisection. The midpoint when a slope
 * is not finite (the force rate at the contact end). */
static double hermite_root(double f0, double m0, double f1, double m1)
{
  if (!isfinite(m0) || !isfinite(m1))
    return 0.5;
  double lo = 0.0, hi = 1.0, s = f0 / (f0 - f1);
  for (int i = 0; i < 20; i++) {
    double p, dp;
    hermite(f0, m0, f1, m1, s, &p, &dp);
    if (p > 0.0)
      lo = s;
    else
      hi = s;
    double next = s - p / dp;
    if (!(next > lo && next < hi))
      next = 0.5 * (lo + hi);
    if (fabs(next - s) < 1e-13)
      return next;
    s = next;
  }
  return s;
}

/* Locates the event ev in (a->t, b->t), where it crosses from + to -,
 * integrating from a at each trial time (Newton safeguarded by bisection,
 * first guess from the Hermite interpolant). *root is the integrated state
 * at the last trial, within AF_EVENT_TOL of the event; the caller applies
 * the final Newton correction analytically. */
static af_status locate(af_impact *w, af_event ev, const af_state *a, const af_state *b,
                        af_state *root)
{
  const af_rhs_params *p = &w->rhs;
  double fa, dfa, fb, dfb, len = b->t - a->t;
  event_eval(p, ev, a, &fa, &dfa);
  event_eval(p, ev, b, &fb, &dfb);
  double lo = a->t, hi = b->t;
  double t = a->t + len * hermite_root(fa, dfa * len, fb, dfb * len);
  for (int i = 0; i < AF_EVENT_ITER; i++) {
    af_status st = state_at(w, a, t, root);
    if (st != AF_OK)
      return st;
    double f, df;
    event_eval(p, ev, root, &f, &df);
    if (f > 0.0)
      lo = t;
    else
      hi = t;
    /* Every event falls through 0, so df < 0 near the root; elsewhere (the
     * force rate close to separation rises again, like -sqrt(x)) Newton
     * would head the wrong way: bisect. */
    double step = df < 0.0 ? -f / df : NAN;
    if (fabs(step) < AF_EVENT_TOL || hi - lo < AF_EVENT_TOL)
      return AF_OK;
    double next = t + step;
    t = next > lo && next < hi ? next : 0.5 * (lo + hi);
  }
  return AF_EBUDGET_ROOT_ITER;
}

/* ---- one pulse ---------------------------------------------------------- */

/* Quintic Hermite on s in [0, 1]; c = {f0, f0', f0'', f1, f1', f1''} with the
 * derivatives already scaled by the interval length (and its square). */
AF_NUMERIC_KERNEL static double quintic_fit(const double c[6], double s)
{
  double s2 = s * s, s3 = s2 * s, s4 = s3 * s, s5 = s4 * s;
  return c[0] * (1.0 - 10.0 * s3 + 15.0 * s4 - 6.0 * s5) +
         c[1] * (s - 6.0 * s3 + 8.0 * s4 - 3.0 * s5) +
         c[2] * 0.5 * (s2 - 3.0 * s3 + 3.0 * s4 - s5) + c[3] * (10.0 * s3 - 15.0 * s4 + 6.0 * s5) +
         c[4] * (-4.0 * s3 + 7.0 * s4 - 3.0 * s5) + c[5] * 0.5 * (s3 - 2.0 * s4 + s5);
}

/* Writes the samples tau_k = tau_first + k dtau lying in (a->t, b->t] from the quintic
 * interpolants of x and u across the step, whose ends carry x, u, u' and u''
 * = -dF/dtau exactly: sixth-order accurate, so the sampling step never
 * constrains the integration step. AF_ESIZE when a sample falls beyond cap. */
static af_status sink_fill(const af_sink *k, const af_rhs_params *p, const af_state *a,
                           const af_state *b, size_t *next)
{
  double len = b->t - a->t;
  double t = k->tau_first + (double)*next * k->dtau;
  if (t > b->t)
    return AF_OK;
  double ga, dga, gb, dgb;
  force_rate(p, a, &ga, &dga);
  force_rate(p, b, &gb, &dgb);
  double aa = accel(p, a), ab = accel(p, b), l2 = len * len;
  const double cx[6] = {a->x, a->u * len, aa * l2, b->x, b->u * len, ab * l2};
  const double cu[6] = {a->u, aa * len, -ga * l2, b->u, ab * len, -gb * l2};
  for (; t <= b->t; t = k->tau_first + (double)*next * k->dtau) {
    if (*next >= k->cap)
      return AF_ESIZE;
    double s = (t - a->t) / len;
    double x = quintic_fit(cx, s), u = quintic_fit(cu, s);
    if (k->force_n != NULL)
      k->force_n[*next] = k->force_scale_n * hertz_force(x, u, p->chi);
    if (k->deformation_m != NULL)
      k->deformation_m[*next] = k->length_scale_m * (x > 0.0 ? x : 0.0);
    ++*next;
  }
  return AF_OK;
}

/* Refines the extrema whose events cross inside (a, b): the deformation
 * maximum where u = 0 and the force peak where dF/dtau = 0. A pulse has one
 * of each; should rounding produce more, the largest wins. */
static af_status refine_extrema(af_impact *w, const af_state *a, const af_state *b, af_pulse *out)
{
  const af_rhs_params *p = &w->rhs;
  af_state s;
  double f, df;
  if (a->u > 0.0 && b->u <= 0.0) {
    af_status st = locate(w, AF_EVENT_MAX_DEFORMATION, a, b, &s);
    if (st != AF_OK)
      return st;
    event_eval(p, AF_EVENT_MAX_DEFORMATION, &s, &f, &df);
    out->x_max = fmax(out->x_max, s.x - 0.5 * f * f / df); /* x'' = u' < 0 at the top */
  }
  double ga, gb;
  event_eval(p, AF_EVENT_FORCE_PEAK, a, &ga, &df);
  event_eval(p, AF_EVENT_FORCE_PEAK, b, &gb, &df);
  /* The force rate is 0 at contact but the first step (AF_H_START) is far
   * shorter than the rise, so ga > 0 holds from the second interval on. */
  if (ga > 0.0 && (gb <= 0.0 || b->x <= 0.0)) {
    af_status st = locate(w, AF_EVENT_FORCE_PEAK, a, b, &s);
    if (st != AF_OK)
      return st;
    event_eval(p, AF_EVENT_FORCE_PEAK, &s, &f, &df);
    double peak = hertz_force(s.x, s.u, p->chi) - 0.5 * f * f / df;
    if (peak > out->f_peak) {
      out->f_peak = peak;
      out->tau_peak = s.t - f / df;
    }
  }
  return AF_OK;
}

/* The contact end in (a, b), a in contact, b not: tau_c and u there. */
static af_status contact_end(af_impact *w, const af_state *a, const af_state *b, af_state *end)
{
  af_state s;
  af_status st = locate(w, AF_EVENT_CONTACT_END, a, b, &s);
  if (st != AF_OK)
    return st;
  double dt = -s.x / s.u; /* last Newton step, error ~ gamma dt^2 */
  end->t = s.t + dt;
  end->x = 0.0;
  end->u = s.u + accel(&w->rhs, &s) * dt;
  return AF_OK;
}

static void reset_state(af_impact *w, double chi, double gamma)
{
  w->rhs.chi = chi;
  w->rhs.gamma = gamma;
  gsl_odeiv2_step_reset(w->step);
  gsl_odeiv2_evolve_reset(w->evolve);
}

/* Integrates one pulse from contact to separation with free adaptive steps,
 * samples it on tau_first + k dtau and locates the contact end and the
 * extrema inside the step where each happens. */
static af_status pulse_run(af_impact *w, double chi, double gamma, const af_sink *sink,
                           af_pulse *out)
{
  if (sink->cap == 0)
    return AF_ESIZE;
  reset_state(w, chi, gamma);
  w->steps_left = AF_IMPACT_STEP_BUDGET;
  memset(out, 0, sizeof *out);
  af_state prev = {0.0, 0.0, 1.0}, cur;
  double h = AF_H_START;
  size_t next = 0;
  if (sink->tau_first == 0.0) { /* the sample at contact */
    if (sink->force_n != NULL)
      sink->force_n[0] = 0.0;
    if (sink->deformation_m != NULL)
      sink->deformation_m[0] = 0.0;
    next = 1;
  }
  af_status st = AF_OK;
  while (st == AF_OK) {
    cur = prev;
    st = ode_step(w, &cur, &h);
    if (st != AF_OK)
      return st;
    if (cur.t >= AF_TAU_LIMIT)
      return AF_EBUDGET_ODE_STEPS; /* the budget of simulated time */
    bool ended = cur.x <= 0.0;
    if (ended) {
      af_state past = cur; /* free flight, just beyond the contact end */
      st = contact_end(w, &prev, &past, &cur);
      if (st != AF_OK)
        return st;
    }
    st = refine_extrema(w, &prev, &cur, out);
    if (st == AF_OK)
      st = sink_fill(sink, &w->rhs, &prev, &cur, &next);
    if (ended && st == AF_OK) {
      out->tau_c = cur.t;
      out->u_c = cur.u;
      out->n = next;
      return AF_OK;
    }
    prev = cur;
  }
  return st;
}

/* ---- exact damping law ------------------------------------------------- */

/* Restitution delivered by chi without gravity (universal, PHYSICS.md 2). */
static af_status delivered_of(af_impact *w, double chi, double *e)
{
  /* One sample (at contact): only the events matter here. */
  af_sink sink = {.dtau = 2.0 * AF_TAU_LIMIT, .cap = 1};
  af_pulse pulse;
  af_status st = pulse_run(w, chi, 0.0, &sink, &pulse);
  if (st == AF_OK)
    *e = -pulse.u_c;
  return st;
}

/* chi delivering e (0 < e < 1) without gravity. The answer lies between 0.70
 * (e = 0.05) and 1 (e -> 1) times Hu-Guo's, and below 1/e (see hertz_force:
 * chi e -> 1 as e -> 0), so [0.5 Hu-Guo, min(1.5 Hu-Guo, 1/e)] brackets it;
 * the 1e-6 margin keeps the upper end strictly beyond the root. */
static af_status exact_chi_solve(af_impact *w, double e, double *chi)
{
  double lo = 0.5 * 1.5 * (1.0 - e) / e, hi = fmin(3.0 * lo, (1.0 + 1e-6) / e);
  double flo, fhi;
  af_status st = delivered_of(w, lo, &flo);
  if (st == AF_OK)
    st = delivered_of(w, hi, &fhi);
  if (st != AF_OK)
    return st;
  flo -= e;
  fhi -= e;
  if (!(flo > 0.0 && fhi < 0.0))
    return AF_ENOROOT;
  /* Illinois variant of regula falsi: bracketed, superlinear. */
  int side = 0;
  for (int i = 0; i < 100; i++) {
    double c = (lo * fhi - hi * flo) / (fhi - flo), fc;
    st = delivered_of(w, c, &fc);
    if (st != AF_OK)
      return st;
    fc -= e;
    /* 1e-10: the integration noise on the delivered restitution. */
    if (fabs(fc) < 1e-10 || hi - lo < 1e-12 * hi) {
      *chi = c;
      return AF_OK;
    }
    if (fc > 0.0) {
      lo = c;
      flo = fc;
      if (side == 1)
        fhi *= 0.5;
      side = 1;
    } else {
      hi = c;
      fhi = fc;
      if (side == -1)
        flo *= 0.5;
      side = -1;
    }
  }
  return AF_EBUDGET_ROOT_ITER;
}

/* The nodes of the exact law's y(e), computed with the integrator of w. */
static af_status exact_nodes(af_impact *w, double *e_nodes, double *y_nodes)
{
  for (int i = 0; i < AF_EXACT_N - 1; i++) {
    double e = AF_EXACT_E_MIN + AF_EXACT_STEP * i, chi;
    af_status st = exact_chi_solve(w, e, &chi);
    if (st != AF_OK)
      return st;
    e_nodes[i] = e;
    y_nodes[i] = chi * e / (1.0 - e);
  }
  e_nodes[AF_EXACT_N - 1] = 1.0;
  y_nodes[AF_EXACT_N - 1] = AF_EXACT_Y_ELASTIC;
  return AF_OK;
}

/* ---- workspace -------------------------------------------------------- */

/* The integrator of w (w zeroed before); AF_ENOMEM, the parts made left for
 * integrator_free. */
static af_status integrator_alloc(af_impact *w)
{
  w->step = gsl_odeiv2_step_alloc(gsl_odeiv2_step_rkck, 2);
  w->control = gsl_odeiv2_control_y_new(AF_EPS_ABS, AF_EPS_REL);
  w->tol_factor = 1.0;
  w->evolve = gsl_odeiv2_evolve_alloc(2);
  w->sys = (gsl_odeiv2_system){ode_rhs, NULL, 2, &w->rhs};
  return w->step && w->control && w->evolve ? AF_OK : AF_ENOMEM;
}

static void integrator_free(af_impact *w)
{
  gsl_odeiv2_evolve_free(w->evolve);
  gsl_odeiv2_control_free(w->control);
  gsl_odeiv2_step_free(w->step);
}

/* The exact law's nodes, shared read-only by every workspace of the
 * process. They depend on nothing but the integrator and its tolerances
 * (every pulse_run starts from a reset stepper), so the numbers are the
 * ones each workspace used to compute for itself, bit for bit. */
static struct {
  af_status status; /* of the build; AF_OK: e, y hold the nodes */
  double e[AF_EXACT_N];
  double y[AF_EXACT_N];
} shared_exact;
static once_flag shared_exact_once = ONCE_FLAG_INIT;

/* Builds shared_exact in a workspace of its own (call_once: one thread, once). */
static void shared_exact_build(void)
{
  af_impact w;
  memset(&w, 0, sizeof w);
  shared_exact.status = integrator_alloc(&w);
  if (shared_exact.status == AF_OK)
    shared_exact.status = exact_nodes(&w, shared_exact.e, shared_exact.y);
  integrator_free(&w);
}

/* w's interpolant of the shared nodes (built on first use). */
static af_status exact_table(af_impact *w)
{
  call_once(&shared_exact_once, shared_exact_build);
  if (shared_exact.status != AF_OK)
    return shared_exact.status;
  memcpy(w->exact_e, shared_exact.e, sizeof w->exact_e);
  memcpy(w->exact_y, shared_exact.y, sizeof w->exact_y);
  return gsl_interp_init(w->exact, w->exact_e, w->exact_y, AF_EXACT_N) == GSL_SUCCESS ? AF_OK
                                                                                      : AF_ENUMERIC;
}

af_status af_impact_create(af_impact **out)
{
  if (out == NULL)
    return AF_EINVAL;
  *out = NULL;
  af_status_init();
  af_impact *w = calloc(1, sizeof *w);
  if (w == NULL)
    return AF_ENOMEM;
  w->exact = gsl_interp_alloc(gsl_interp_cspline, AF_EXACT_N);
  af_status st = w->exact == NULL ? AF_ENOMEM : integrator_alloc(w);
  if (st == AF_OK)
    st = exact_table(w);
  if (st != AF_OK) {
    af_impact_destroy(w);
    return st;
  }
  *out = w;
  return AF_OK;
}

void af_impact_destroy(af_impact *w)
{
  if (w == NULL)
    return;
  gsl_interp_free(w->exact);
  integrator_free(w);
  free(w);
}

af_status af_impact_chi(const af_impact *w, af_damping_law law, double e, double *chi)
{
  if (chi == NULL || !(e > 0.0 && e <= 1.0))
    return AF_EINVAL;
  switch (law) {
  case AF_DAMPING_PAPER: *chi = 0.75 * (1.0 - e * e); return AF_OK;
  case AF_DAMPING_HU_GUO: *chi = 1.5 * (1.0 - e) / e; return AF_OK;
  case AF_DAMPING_EXACT:
    if (w == NULL || e < AF_EXACT_E_MIN)
      return AF_EINVAL;
    *chi = gsl_interp_eval(w->exact, w->exact_e, w->exact_y, e, NULL) * (1.0 - e) / e;
    return AF_OK;
  }
  return AF_EINVAL;
}

/* ---- one run ------------------------------------------------------------ */

static bool in_range(double v, double lo, double hi, bool lo_open, bool hi_open)
{
  return isfinite(v) && (lo_open ? v > lo : v >= lo) && (hi_open ? v < hi : v <= hi);
}

static bool params_valid(const af_impact_params *p)
{
  return in_range(p->hammer_mass_kg, 0.0, INFINITY, true, true) &&
         in_range(p->velocity_m_s, 0.0, INFINITY, true, true) &&
         in_range(p->hammer_modulus_pa, 0.0, INFINITY, false, true) &&
         in_range(p->hammer_poisson, 0.0, 0.5, false, true) &&
         in_range(p->hammer_radius_m, 0.0, INFINITY, false, true) &&
         in_range(p->fruit_modulus_pa, 0.0, INFINITY, true, true) &&
         in_range(p->fruit_poisson, 0.0, 0.5, false, true) &&
         in_range(p->strike_radius_m, 0.0, INFINITY, true, true) &&
         in_range(p->restitution, 0.0, 1.0, true, false) &&
         in_range(p->gravity_m_s2, 0.0, INFINITY, false, true);
}

/* Sets w's control to AF_EPS_ABS and AF_EPS_REL times factor: at factor 1
 * the very numbers control_y_new took (x 1.0 is exact), so that
 * af_impact_execute's runs stay the same whatever ran before them. */
static af_status set_tolerance(af_impact *w, double factor)
{
  if (factor == w->tol_factor)
    return AF_OK;
  if (gsl_odeiv2_control_init(w->control, AF_EPS_ABS * factor, AF_EPS_REL * factor, 1.0, 0.0) !=
      GSL_SUCCESS)
    return AF_EINVAL;
  w->tol_factor = factor;
  return AF_OK;
}

/* af_impact_execute and af_impact_execute_from: samples at t_first_s + k dt_s,
 * the tolerances times tol_factor. */
static af_status impact_run(af_impact *w, const af_impact_params *p, double t_first_s, double dt_s,
                            double tol_factor, double *force_n, double *deformation_m, size_t cap,
                            af_impact_result *res)
{
  if (w == NULL || p == NULL || res == NULL || !params_valid(p) ||
      !in_range(dt_s, 0.0, INFINITY, true, true) ||
      !in_range(t_first_s, 0.0, INFINITY, false, true) ||
      !in_range(tol_factor, 1.0, AF_IMPACT_MAX_TOL_FACTOR, false, false))
    return AF_EINVAL;
  double chi;
  af_status st = af_impact_chi(w, p->damping, p->restitution, &chi);
  if (st == AF_OK)
    st = set_tolerance(w, tol_factor);
  if (st != AF_OK)
    return st;
  double v0 = p->velocity_m_s, m1 = p->hammer_mass_kg;
  double d_scale = pow(1.25 * m1 * v0 * v0 / af_impact_stiffness(p), 0.4); /* D [m] */
  double t_scale = d_scale / v0;                                           /* T [s] */
  af_sink sink = {.tau_first = t_first_s / t_scale,
                  .dtau = dt_s / t_scale,
                  .cap = cap,
                  .force_n = force_n,
                  .deformation_m = deformation_m,
                  .force_scale_n = m1 * v0 * v0 / d_scale,
                  .length_scale_m = d_scale};
  if (!isfinite(sink.dtau) || !isfinite(sink.force_scale_n) || !(sink.dtau > 0.0) ||
      !isfinite(sink.tau_first))
    return AF_ENUMERIC;
  af_pulse pulse;
  st = pulse_run(w, chi, p->gravity_m_s2 * d_scale / (v0 * v0), &sink, &pulse);
  if (st != AF_OK)
    return st;
  *res = (af_impact_result){.contact_time_s = pulse.tau_c * t_scale,
                            .peak_force_n = pulse.f_peak * sink.force_scale_n,
                            .time_of_peak_s = pulse.tau_peak * t_scale,
                            .max_deformation_m = pulse.x_max * d_scale,
                            .delivered_restitution = -pulse.u_c,
                            .chi = chi,
                            .dt_s = dt_s,
                            .n_samples = pulse.n};
  return AF_OK;
}

af_status af_impact_execute(af_impact *w, const af_impact_params *p, double dt_s, double *force_n,
                            double *deformation_m, size_t cap, af_impact_result *res)
{
  return impact_run(w, p, 0.0, dt_s, 1.0, force_n, deformation_m, cap, res);
}

af_status af_impact_execute_from(af_impact *w, const af_impact_params *p, double t_first_s,
                                 double dt_s, double tol_factor, double *force_n, size_t cap,
                                 af_impact_result *res)
{
  return impact_run(w, p, t_first_s, dt_s, tol_factor, force_n, NULL, cap, res);
}
