/* fastpath.c — the table of normalised pulses and its interpolation. */
#include "fastpath.h"

#include <math.h>
#include <stdatomic.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>
#include <threads.h>

#include "criteria.h"
#include "impact.h"
#include "r2_search.h"
#include "lamb.h"
#include "settings.h"
#include "spectrum.h"
#include "stage.h"
#include "stress.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

/* The grid: chi 0 .. 5 (exact law e >= 0.2, LN all, Hu-Guo e >= 0.23),
 * gamma 0 .. 0.3 (the paper's strike: 0.003; 0.3 = a 100 g hammer at
 * 0.3 m/s on a soft fruit), phi = f T 0 .. 1.6 (the main lobe ends near
 * 0.61, the eighth near 2.9). */
#define AF_FP_NCHI 101
#define AF_FP_CHI_STEP 0.05
#define AF_FP_NGAM 13
#define AF_FP_GAM_STEP 0.025
#define AF_FP_NPHI 401
#define AF_FP_PHI_STEP 0.004
/* Selected band edges: the cubic on the chi stencil and on the stencil
 * shifted by one node must agree to this (relative to the band's upper
 * edge), or the strike goes to the ODE path. */
#define AF_FP_EDGE_AGREEMENT 3e-4
/* As model.c: the pulse sampled at the elastic contact time / 128, at most
 * 1024 samples, transformed on 4096 points. */
#define AF_FP_SAMPLES_PER_PULSE 128
#define AF_FP_MAX_SAMPLES 1024
#define AF_FP_FFT_SIZE 4096
#define AF_FP_LOBES AF_MODEL_MAX_LOBES
/* Per-lobe figures: start, end, peak, peak magnitude, then band low/high at
 * power-half and at amplitude-half. */
#define AF_FP_LOBE_FIGS 8
enum {
  Q_TAU_C,
  Q_TAU_PEAK,
  Q_F_PEAK,
  Q_X_MAX,
  Q_E_DELIVERED,
  Q_PMAX, /* max over the samples of f / x: p0 = 3 F0 / (2 pi R D) x this */
  Q_MAG_MAX,
  Q_N_SAMPLES,
  Q_LOBES,
  NQ = Q_LOBES + AF_FP_LOBES * AF_FP_LOBE_FIGS
};

/* A chi row of the table (its 13 gamma nodes): not built yet, built, or
 * its build failed (a strike whose stencil touches it takes the ODE path). */
enum { ROW_EMPTY = 0, ROW_READY, ROW_FAILED };

/* The table: one per process, shared by every handle on every thread. A
 * row is built the first time a strike's stencil needs it (under the lock,
 * by whichever thread asks first) and read-only after: a strike near the
 * shipped profile needs about 6 of the 101 rows. A row's numbers do not
 * depend on when or on which thread it is built (every pulse starts from a
 * reset integrator, impact.c). */
typedef struct {
  double *q;                                 /* [chi][gamma][NQ] */
  int *n_lobes;                              /* [chi][gamma]; -1: not tabulated */
  double *mag;                               /* [chi][gamma][phi]: |X| / (F0 T) */
  af_setting_range ranges[AF_SETTING_COUNT]; /* the parameter table's ranges, parsed once */
  atomic_int row[AF_FP_NCHI];                /* ROW_*: stored under lock, loaded without */
  mtx_t lock;                                /* held while a row is built */
  /* The builder's workspace (under lock). */
  af_impact *imp;
  af_spectrum *spec;
  double *force, *defo;
  double build_cpu_s;  /* CPU time [s] spent building rows so far (under lock) */
  af_status row_error; /* the first row build that failed (under lock) */
} af_fp_table;

/* One user's handle: the table's address, its own caches, fallback and counts. */
struct af_fastpath {
  af_fp_table *t; /* the shared table; NULL until the first execute */
  af_model *ode;  /* the reference, for fallbacks; made at the first one */
  af_shear_cache shear;
  af_lamb_cache xi;
  af_impact *impact;      /* for chi(e) */
  af_damping_law chi_law; /* chi of the last (law, e) asked */
  double chi_e, chi;
  size_t from_table, fallbacks;
};

/* The process's table and the status of its build (call_once). */
static struct {
  af_status status; /* of making the table (not of its rows) */
  af_fp_table *table;
} shared;
static once_flag shared_once = ONCE_FLAG_INIT;

static size_t node_index(int i, int j)
{
  return (size_t)i * AF_FP_NGAM + (size_t)j;
}

/* Frequencies evaluated side by side in grid_magnitudes: independent
 * phasor recurrences that the CPU overlaps (one chain is latency-bound). */
#define AF_FP_LANES 8

/* |X(f_k)| / dt [N] of the samples x[0..n) at f_k = k df_hz, k = 0 .. count-1,
 * dt_s the step: the DTFT that af_spectrum_magnitude evaluates one frequency
 * at a time, here AF_FP_LANES at once on the pulse folded about its centre
 * (pairs at +-m: e = x(c+m) + x(c-m), o = x(c+m) - x(c-m); |A|^2 =
 * (sum e cos m theta)^2 + (sum o sin m theta)^2). The recurrence p *= z
 * drifts by ~n eps: negligible. ws holds n doubles. */
static void grid_magnitudes(const double *x, size_t n, double dt_s, double df_hz, int count,
                            double *ws, double *out)
{
  size_t half = n / 2, pairs = (n + 1) / 2;
  double m0 = n % 2 ? 0.0 : 0.5, *e = ws, *o = ws + pairs;
  for (size_t j = 0; j < pairs; j++) {
    size_t up = half + j, down = n - 1 - up;
    e[j] = up == down ? x[up] : x[up] + x[down];
    o[j] = up == down ? 0.0 : x[up] - x[down];
  }
  for (int k0 = 0; k0 < count; k0 += AF_FP_LANES) {
    double pr[AF_FP_LANES], pi[AF_FP_LANES], zr[AF_FP_LANES], zi[AF_FP_LANES];
    double ar[AF_FP_LANES] = {0}, ai[AF_FP_LANES] = {0};
    for (int l = 0; l < AF_FP_LANES; l++) {
      double theta = 2.0 * M_PI * (double)(k0 + l) * df_hz * dt_s;
      zr[l] = cos(theta);
      zi[l] = -sin(theta);
      pr[l] = cos(m0 * theta);
      pi[l] = -sin(m0 * theta);
    }
    for (size_t j = 0; j < pairs; j++)
      for (int l = 0; l < AF_FP_LANES; l++) {
        ar[l] += e[j] * pr[l];
        ai[l] += o[j] * pi[l];
        double r = pr[l] * zr[l] - pi[l] * zi[l];
        pi[l] = pr[l] * zi[l] + pi[l] * zr[l];
        pr[l] = r;
      }
    for (int l = 0; l < AF_FP_LANES && k0 + l < count; l++)
      out[k0 + l] = dt_s * sqrt(ar[l] * ar[l] + ai[l] * ai[l]);
  }
}

/* The normalising strike of a node: 10 g at 1 m/s on 8 MPa, R 40 mm, rigid
 * flat hammer; chi set through Hu-Guo's law (e = 3 / (3 + 2 chi) gives
 * exactly chi), gamma through g. */
static af_status build_node(af_fp_table *f, af_impact *imp, af_spectrum *spec, double *force,
                            double *defo, double chi, double gamma, size_t at)
{
  af_impact_params ip = af_impact_params_default();
  ip.velocity_m_s = 1.0;
  ip.damping = AF_DAMPING_HU_GUO;
  ip.restitution = 3.0 / (3.0 + 2.0 * chi);
  double k = af_impact_stiffness(&ip);
  double d = pow(5.0 * ip.hammer_mass_kg * ip.velocity_m_s * ip.velocity_m_s / (4.0 * k), 0.4);
  double t = d / ip.velocity_m_s, f0 = ip.hammer_mass_kg * ip.velocity_m_s * ip.velocity_m_s / d;
  ip.gravity_m_s2 = gamma * ip.velocity_m_s * ip.velocity_m_s / d;
  double dt = af_impact_hertz_contact_time_s(&ip) / AF_FP_SAMPLES_PER_PULSE;
  af_impact_result res;
  af_status st = af_impact_execute(imp, &ip, dt, force, defo, AF_FP_MAX_SAMPLES, &res);
  if (st == AF_OK)
    st = af_spectrum_execute(spec, force, res.n_samples, res.dt_s);
  double p0 = 0.0;
  if (st == AF_OK)
    st = af_stress_max_center_pressure_pa(force, defo, res.n_samples,
                                          af_impact_effective_radius_m(&ip), &p0, NULL);
  if (st == AF_ESIZE || st == AF_EBUDGET_ODE_STEPS) {
    /* A pulse the ODE path samples more coarsely (over 8 elastic contact
     * times): not tabulated; strikes near it take the ODE path. */
    f->n_lobes[at] = -1;
    return AF_OK;
  }
  if (st != AF_OK)
    return st;
  double *q = f->q + at * NQ;
  q[Q_TAU_C] = res.contact_time_s / t;
  q[Q_TAU_PEAK] = res.time_of_peak_s / t;
  q[Q_F_PEAK] = res.peak_force_n / f0;
  q[Q_X_MAX] = res.max_deformation_m / d;
  q[Q_E_DELIVERED] = res.delivered_restitution;
  q[Q_PMAX] = p0 * 2.0 * M_PI * af_impact_effective_radius_m(&ip) * d / (3.0 * f0);
  q[Q_MAG_MAX] = af_spectrum_max_magnitude(spec) / (f0 * t);
  q[Q_N_SAMPLES] = (double)res.n_samples;
  size_t count = af_spectrum_lobe_count(spec);
  int n = (int)(count < AF_FP_LOBES ? count : AF_FP_LOBES);
  f->n_lobes[at] = n;
  memset(q + Q_LOBES, 0, AF_FP_LOBES * AF_FP_LOBE_FIGS * sizeof *q);
  for (int l = 0; l < n; l++) {
    double *g = q + Q_LOBES + l * AF_FP_LOBE_FIGS;
    af_lobe power, amp;
    if (af_spectrum_lobe(spec, (unsigned)(l + 1), AF_BAND_POWER_HALF, &power) != AF_OK ||
        af_spectrum_lobe(spec, (unsigned)(l + 1), AF_BAND_AMPLITUDE_HALF, &amp) != AF_OK)
      return AF_ENUMERIC;
    g[0] = power.start_hz * t;
    g[1] = power.end_hz * t;
    g[2] = power.peak_hz * t;
    g[3] = power.peak_magnitude_n_s / (f0 * t);
    g[4] = power.band_low_hz * t;
    g[5] = power.band_high_hz * t;
    g[6] = amp.band_low_hz * t;
    g[7] = amp.band_high_hz * t;
  }
  double *m = f->mag + at * AF_FP_NPHI;
  grid_magnitudes(force, res.n_samples, res.dt_s, AF_FP_PHI_STEP / t, AF_FP_NPHI, defo, m);
  for (int k2 = 0; k2 < AF_FP_NPHI; k2++) {
#ifdef AF_FP_CHECK_GRID
    double ref = af_spectrum_magnitude(spec, k2 * AF_FP_PHI_STEP / t);
    if (fabs(m[k2] - ref) > 1e-12 * af_spectrum_max_magnitude(spec))
      return AF_ENUMERIC;
#endif
    m[k2] /= f0 * t;
  }
  return AF_OK;
}

static void table_free(af_fp_table *t)
{
  if (t == NULL)
    return;
  af_spectrum_destroy(t->spec);
  af_impact_destroy(t->imp);
  free(t->force);
  free(t->defo);
  free(t->q);
  free(t->n_lobes);
  free(t->mag);
  free(t);
}

/* Makes shared.table with no row built (call_once: one thread, once per
 * process): the arrays (their pages touched as rows are built), the
 * parameter ranges and the builder's workspace. */
static void shared_build(void)
{
  af_fp_table *t = calloc(1, sizeof *t);
  size_t nodes = (size_t)AF_FP_NCHI * AF_FP_NGAM;
  af_status st = AF_ENOMEM;
  if (t != NULL) {
    t->q = malloc(nodes * NQ * sizeof *t->q);
    t->n_lobes = malloc(nodes * sizeof *t->n_lobes);
    t->mag = malloc(nodes * AF_FP_NPHI * sizeof *t->mag);
    t->force = malloc(AF_FP_MAX_SAMPLES * sizeof *t->force);
    t->defo = malloc(AF_FP_MAX_SAMPLES * sizeof *t->defo);
    st = t->q && t->n_lobes && t->mag && t->force && t->defo ? AF_OK : AF_ENOMEM;
  }
  for (int k = 0; k < AF_SETTING_COUNT && st == AF_OK; k++)
    if (af_setting_range_of((af_setting_id)k, &t->ranges[k]) != AF_OK)
      t->ranges[k].lo = NAN; /* not a number row: never asked */
  af_spectrum_config sc = af_spectrum_config_default();
  sc.max_samples = AF_FP_MAX_SAMPLES;
  sc.fft_size = AF_FP_FFT_SIZE;
  sc.max_lobes = AF_FP_LOBES;
  if (st == AF_OK)
    st = af_impact_create(&t->imp);
  if (st == AF_OK)
    st = af_spectrum_create(&sc, &t->spec);
  if (st == AF_OK && mtx_init(&t->lock, mtx_plain) != thrd_success)
    st = AF_ENOMEM;
  if (st != AF_OK) {
    table_free(t);
    t = NULL;
  }
  if (t != NULL)
    for (int i = 0; i < AF_FP_NCHI; i++)
      atomic_init(&t->row[i], ROW_EMPTY);
  shared.status = st;
  shared.table = t;
}

/* Whether row i of t is built, building it first if no thread has. */
static bool row_ready(af_fp_table *t, int i)
{
  int state = atomic_load_explicit(&t->row[i], memory_order_acquire);
  if (state != ROW_EMPTY)
    return state == ROW_READY;
  mtx_lock(&t->lock);
  state = atomic_load_explicit(&t->row[i], memory_order_relaxed);
  if (state == ROW_EMPTY) {
    const int64_t t0_ns = af_stage_cpu_ns(); /* a row's build is counted in CPU time */
    af_status st = AF_OK;
    for (int j = 0; j < AF_FP_NGAM && st == AF_OK; j++)
      st = build_node(t, t->imp, t->spec, t->force, t->defo, i * AF_FP_CHI_STEP, j * AF_FP_GAM_STEP,
                      node_index(i, j));
    state = st == AF_OK ? ROW_READY : ROW_FAILED;
    if (st != AF_OK && t->row_error == AF_OK)
      t->row_error = st;
    t->build_cpu_s += (double)(af_stage_cpu_ns() - t0_ns) * 1e-9;
    atomic_store_explicit(&t->row[i], state, memory_order_release);
  }
  mtx_unlock(&t->lock);
  return state == ROW_READY;
}

/* Rows lo .. hi (clipped to the grid) built. */
static bool rows_ready(af_fp_table *t, int lo, int hi)
{
  bool ok = true;
  for (int i = lo < 0 ? 0 : lo; i <= hi && i < AF_FP_NCHI; i++)
    ok = row_ready(t, i) && ok;
  return ok;
}

af_status af_fastpath_table_build(double *build_cpu_s)
{
  call_once(&shared_once, shared_build);
  af_fp_table *t = shared.table;
  if (build_cpu_s)
    *build_cpu_s = 0.0;
  if (t == NULL)
    return shared.status;
  (void)rows_ready(t, 0, AF_FP_NCHI - 1);
  mtx_lock(&t->lock);
  af_status st = t->row_error;
  if (build_cpu_s)
    *build_cpu_s = t->build_cpu_s;
  mtx_unlock(&t->lock);
  return st;
}

/* The shared table, made (no row built) on the first call; NULL out of memory. */
static af_fp_table *shared_table(void)
{
  call_once(&shared_once, shared_build);
  return shared.table;
}

af_status af_fastpath_create(af_fastpath **out)
{
  af_fastpath *f = calloc(1, sizeof *f);
  *out = NULL;
  if (f == NULL)
    return AF_ENOMEM;
  af_shear_cache_reset(&f->shear);
  af_lamb_cache_reset(&f->xi);
  f->chi_e = NAN;
  af_status st = af_impact_create(&f->impact);
  if (st != AF_OK) {
    af_fastpath_destroy(f);
    return st;
  }
  *out = f;
  return AF_OK;
}

void af_fastpath_destroy(af_fastpath *f)
{
  if (f == NULL)
    return;
  af_model_destroy(f->ode);
  af_impact_destroy(f->impact);
  free(f);
}

af_model *af_fastpath_model(af_fastpath *f)
{
  if (f != NULL && f->ode == NULL && af_model_create(&f->ode) != AF_OK)
    f->ode = NULL;
  return f ? f->ode : NULL;
}

void af_fastpath_counts(const af_fastpath *f, size_t *from_table, size_t *fallbacks)
{
  if (from_table)
    *from_table = f ? f->from_table : 0;
  if (fallbacks)
    *fallbacks = f ? f->fallbacks : 0;
}

/* Four-point Lagrange weights on a uniform grid of n nodes at x (in node
 * units): first node *i0, weights w[4]; l0 the node below x. */
typedef struct {
  int i0;
  double w[4];
  int l0;
} af_fp_weights;

/* Lagrange weights of nodes 0..3 at t (in node units). */
static void cubic_weights(double t, double w[4])
{
  w[0] = -(t - 1.0) * (t - 2.0) * (t - 3.0) / 6.0;
  w[1] = t * (t - 2.0) * (t - 3.0) / 2.0;
  w[2] = -t * (t - 1.0) * (t - 3.0) / 2.0;
  w[3] = t * (t - 1.0) * (t - 2.0) / 6.0;
}

static bool weights(double x, int n, af_fp_weights *out)
{
  if (!(x >= 0.0 && x <= n - 1))
    return false;
  int i = (int)floor(x);
  if (i > n - 2)
    i = n - 2;
  out->l0 = i;
  int i0 = i - 1;
  if (i0 < 0)
    i0 = 0;
  if (i0 > n - 4)
    i0 = n - 4;
  out->i0 = i0;
  cubic_weights(x - i0, out->w);
  return true;
}

/* Bicubic value of quantity k over the (chi, gamma) stencil. */
static double bicubic_q(const af_fp_table *f, const af_fp_weights *a, const af_fp_weights *b, int k)
{
  double s = 0.0;
  for (int i = 0; i < 4; i++) {
    const double *row = f->q + node_index(a->i0 + i, b->i0) * NQ + k;
    double r = row[0] * b->w[0] + row[NQ] * b->w[1] + row[2 * NQ] * b->w[2] + row[3 * NQ] * b->w[3];
    s += a->w[i] * r;
  }
  return s;
}

/* The strike's figures and each lobe's: blocks of this many in q. */
#define AF_FP_BLOCK 8
_Static_assert(Q_LOBES == AF_FP_BLOCK && AF_FP_LOBE_FIGS == AF_FP_BLOCK, "q in blocks of 8");

/* bicubic_q of figures k .. k + 7 (a block) into out, each by the same
 * operations in the same order (the same bits), side by side: one pass over
 * the stencil's rows for a lobe's figures. */
static void bicubic_block(const af_fp_table *f, const af_fp_weights *a, const af_fp_weights *b,
                          int k, double out[AF_FP_BLOCK])
{
  double s[AF_FP_BLOCK] = {0}; /* local: no aliasing with q, so the compiler pairs the lanes */
  for (int i = 0; i < 4; i++) {
    const double *row = f->q + node_index(a->i0 + i, b->i0) * NQ + k;
    for (int m = 0; m < AF_FP_BLOCK; m++) {
      double r = row[m] * b->w[0] + row[NQ + m] * b->w[1] + row[2 * NQ + m] * b->w[2] +
                 row[3 * NQ + m] * b->w[3];
      s[m] += a->w[i] * r;
    }
  }
  memcpy(out, s, sizeof s);
}

/* |X| / (F0 T) at phi: bicubic in (chi, gamma), cubic in phi. */
static double magnitude(const af_fp_table *f, const af_fp_weights *a, const af_fp_weights *b,
                        const af_fp_weights *c)
{
  double s = 0.0;
  for (int i = 0; i < 4; i++)
    for (int j = 0; j < 4; j++) {
      const double *m = f->mag + node_index(a->i0 + i, b->i0 + j) * AF_FP_NPHI + c->i0;
      double v = m[0] * c->w[0] + m[1] * c->w[1] + m[2] * c->w[2] + m[3] * c->w[3];
      s += a->w[i] * b->w[j] * v;
    }
  return s;
}

static bool lobes_agree(const af_fp_table *f, const af_fp_weights *a, const af_fp_weights *b)
{
  int n = f->n_lobes[node_index(a->i0, b->i0)];
  for (int i = 0; i < 4; i++)
    for (int j = 0; j < 4; j++)
      if (f->n_lobes[node_index(a->i0 + i, b->i0 + j)] != n)
        return false;
  return true;
}

/* Figure k equals figure edge at some nodes of the stencil but not all. */
static bool clipped_mixed(const af_fp_table *f, const af_fp_weights *a, const af_fp_weights *b,
                          int k, int edge)
{
  int clipped = 0;
  for (int i = 0; i < 4; i++)
    for (int j = 0; j < 4; j++) {
      const double *q = f->q + node_index(a->i0 + i, b->i0 + j) * NQ;
      clipped += q[k] == q[edge];
    }
  return clipped != 0 && clipped != 16;
}

static af_status fallback(af_fastpath *f, const af_model_params *p, af_model_result *r)
{
  af_model *ode = af_fastpath_model(f);
  f->fallbacks++;
  if (ode == NULL) {
    memset(r, 0, sizeof *r);
    return AF_ENOMEM;
  }
  return af_model_execute(ode, p, r);
}

/* af_model_params_check's numeric rows, with the ranges parsed once: the
 * quick test of every call. A strike it refuses (or a choice out of its
 * enum) goes to af_model_params_check itself for the verdict and message. */
static bool quick_check(const af_fp_table *f, const af_model_params *p)
{
  const af_impact_params *i = &p->impact;
  const struct {
    double v;
    af_setting_id row;
  } fields[] = {
      {i->hammer_mass_kg, AF_SETTING_HAMMER_MASS_KG},
      {i->velocity_m_s, AF_SETTING_STRIKE_VELOCITY_M_S},
      {i->hammer_modulus_pa, AF_SETTING_HAMMER_MODULUS_PA},
      {i->hammer_poisson, AF_SETTING_HAMMER_POISSON},
      {i->hammer_radius_m, AF_SETTING_HAMMER_TIP_RADIUS_M},
      {i->fruit_modulus_pa, AF_SETTING_MODULUS_NOMINAL_PA},
      {i->fruit_poisson, AF_SETTING_FRUIT_POISSON},
      {i->strike_radius_m, AF_SETTING_STRIKE_RADIUS_MIN_M},
      {i->restitution, AF_SETTING_RESTITUTION},
      {i->gravity_m_s2, AF_SETTING_GRAVITY_M_S2},
      {p->fruit_mass_kg, AF_SETTING_MASS_MIN_KG},
      {p->fruit_density_kg_m3, AF_SETTING_DENSITY_KG_M3},
      {p->modulus_factor, AF_SETTING_MODULUS_FACTOR},
      {(double)p->lobe, AF_SETTING_LOBE},
      {p->yield_ratio, AF_SETTING_YIELD_RATIO},
      {p->yield_exponent, AF_SETTING_YIELD_EXPONENT},
      {p->yield_reference_modulus_pa, AF_SETTING_YIELD_REFERENCE_MODULUS_PA},
      {p->bruise_energy_j, AF_SETTING_BRUISE_ENERGY_J},
  };
  for (size_t k = 0; k < sizeof fields / sizeof fields[0]; k++)
    if (!af_setting_range_contains(&f->ranges[fields[k].row], fields[k].v))
      return false;
  return (i->damping != AF_DAMPING_EXACT || i->restitution >= 0.05) &&
         (i->damping == AF_DAMPING_PAPER || i->damping == AF_DAMPING_EXACT ||
          i->damping == AF_DAMPING_HU_GUO) &&
         (p->band_level == AF_BAND_POWER_HALF || p->band_level == AF_BAND_AMPLITUDE_HALF) &&
         (p->shear_ratio == AF_SHEAR_PAPER || p->shear_ratio == AF_SHEAR_EXACT) &&
         p->yield_measured.n <= AF_YIELD_MAX_POINTS;
}

/* af_fastpath_execute; with full false only what the criteria read (the
 * configured lobe, the 0S2, the shear and yield, the verdicts), the same
 * numbers and the same fallbacks: the R2_min search's evaluation. */
/* chi of the strike, from the handle's cache of the last (law, e) asked. */
static af_status chi_cached(af_fastpath *f, const af_impact_params *ip, double *chi)
{
  af_status st = AF_OK;
  if (!(ip->restitution == f->chi_e && ip->damping == f->chi_law)) {
    st = af_impact_chi(f->impact, ip->damping, ip->restitution, chi);
    f->chi = *chi;
    f->chi_e = st == AF_OK ? ip->restitution : NAN;
    f->chi_law = ip->damping;
  }
  *chi = f->chi;
  return st;
}

/* The error estimate's stencil: the same cubic in chi on the stencil a
 * shifted by one node (both hold the strike's interval); false when it
 * would leave the grid. */
static bool shifted_stencil(const af_fp_weights *a, double chi, af_fp_weights *a2)
{
  *a2 = *a;
  a2->i0 = a->i0 + 1 <= a->l0 && a->i0 + 4 <= AF_FP_NCHI - 1 ? a->i0 + 1 : a->i0 - 1;
  if (a2->i0 < 0 || a2->i0 + 3 > AF_FP_NCHI - 1)
    return false;
  cubic_weights(chi / AF_FP_CHI_STEP - a2->i0, a2->w);
  return true;
}

/* Whether the band's edges low2, high2 on the shifted stencil agree with
 * low, high on the strike's (all in units of 1 / T) to the table's
 * tolerance, relative to the upper edge. */
static bool edges_agree(double low2, double high2, double low, double high)
{
  return !(fabs(low2 - low) > AF_FP_EDGE_AGREEMENT * high ||
           fabs(high2 - high) > AF_FP_EDGE_AGREEMENT * high);
}

static af_status evaluate(af_fastpath *f, const af_model_params *p, af_model_result *r, bool full)
{
  const af_impact_params *ip = &p->impact;
  double chi = f->chi, xi, ratio;
  af_status st = AF_OK;
  if (f->t == NULL)
    f->t = shared_table();
  af_fp_table *tb = f->t;
  if (tb == NULL) /* no table (out of memory): every strike by the ODE path */
    return fallback(f, p, r);
  if (!quick_check(tb, p)) {
    st = af_model_params_check(p, NULL);
    if (st != AF_OK) {
      memset(r, 0, sizeof *r);
      return st;
    }
  }
  st = chi_cached(f, ip, &chi);
  if (st == AF_OK)
    st = af_lamb_root_cached(&f->xi, ip->fruit_poisson, &xi);
  if (st == AF_OK)
    st = af_stress_shear_ratio_cached(&f->shear, p->shear_ratio, ip->fruit_poisson, &ratio);
  if (st != AF_OK)
    return fallback(f, p, r);
  double m1 = ip->hammer_mass_kg, v0 = ip->velocity_m_s;
  double radius = af_impact_effective_radius_m(ip);
  double k = 4.0 / 3.0 * af_impact_effective_modulus_pa(ip) * sqrt(radius);
  double d = pow(1.25 * m1 * v0 * v0 / k, 0.4);
  double t = d / v0, f0 = m1 * v0 * v0 / d;
  double gamma = ip->gravity_m_s2 * d / (v0 * v0);
  double res_hz = af_lamb_frequency_hz(xi, p->modulus_factor * ip->fruit_modulus_pa,
                                       ip->fruit_poisson, p->fruit_density_kg_m3, p->fruit_mass_kg);
  af_fp_weights a, b, c;
  if (!weights(chi / AF_FP_CHI_STEP, AF_FP_NCHI, &a) ||
      !weights(gamma / AF_FP_GAM_STEP, AF_FP_NGAM, &b) ||
      !weights(res_hz * t / AF_FP_PHI_STEP, AF_FP_NPHI, &c) ||
      !rows_ready(tb, a.i0 - 1, a.i0 + 4) || !lobes_agree(tb, &a, &b))
    return fallback(f, p, r);
  memset(r, 0, sizeof *r);
  int n = tb->n_lobes[node_index(a.i0, b.i0)];
  int band_fig = p->band_level == AF_BAND_POWER_HALF ? 4 : 6;
  r->n_lobes = (size_t)n;
  const int lobe = (int)p->lobe; /* >= 1: checked above */
  for (int l = full ? 0 : lobe - 1; l < (full || lobe > n ? n : lobe); l++) {
    int base = Q_LOBES + l * AF_FP_LOBE_FIGS;
    af_lobe *lb = &r->lobes[l];
    double g[AF_FP_BLOCK];
    bicubic_block(tb, &a, &b, base, g);
    lb->index = (unsigned)(l + 1);
    lb->start_hz = l == 0 ? 0.0 : g[0] / t;
    lb->end_hz = g[1] / t;
    lb->peak_hz = l == 0 ? 0.0 : g[2] / t;
    lb->peak_magnitude_n_s = g[3] * f0 * t;
    lb->band_low_hz = l == 0 ? 0.0 : g[band_fig] / t;
    lb->band_high_hz = g[band_fig + 1] / t;
  }
  r->band_found = p->lobe <= r->n_lobes;
  if (r->band_found) {
    int base = Q_LOBES + (int)(p->lobe - 1) * AF_FP_LOBE_FIGS + band_fig;
    r->band = r->lobes[p->lobe - 1];
    /* A band edge clipped to its lobe's end at some nodes of the stencil and
     * not at others has a kink inside it: not interpolated. */
    if (clipped_mixed(tb, &a, &b, base, base - band_fig) ||
        clipped_mixed(tb, &a, &b, base + 1, base - band_fig + 1))
      return fallback(f, p, r);
    af_fp_weights a2;
    if (!shifted_stencil(&a, chi, &a2) || !lobes_agree(tb, &a2, &b) ||
        !edges_agree(bicubic_q(tb, &a2, &b, base), bicubic_q(tb, &a2, &b, base + 1),
                     r->band.band_low_hz * t, r->band.band_high_hz * t))
      return fallback(f, p, r);
  }
  r->resonance_hz = res_hz;
  double g[AF_FP_BLOCK]; /* the strike's figures (Q_*) */
  if (full) {
    bicubic_block(tb, &a, &b, 0, g);
    af_impact_result *im = &r->impact;
    im->contact_time_s = g[Q_TAU_C] * t;
    im->peak_force_n = g[Q_F_PEAK] * f0;
    im->time_of_peak_s = g[Q_TAU_PEAK] * t;
    im->max_deformation_m = g[Q_X_MAX] * d;
    im->delivered_restitution = g[Q_E_DELIVERED];
    im->chi = chi;
    im->dt_s = af_impact_hertz_contact_time_s(ip) / AF_FP_SAMPLES_PER_PULSE;
    im->n_samples = (size_t)lround(tb->q[node_index(a.l0, b.l0) * NQ + Q_N_SAMPLES]);
    r->excitation_at_resonance_db = 20.0 * log10(magnitude(tb, &a, &b, &c) / g[Q_MAG_MAX]);
  } else
    g[Q_PMAX] = bicubic_q(tb, &a, &b, Q_PMAX);
  r->max_contact_pressure_pa = 3.0 * f0 / (2.0 * M_PI * radius * d) * g[Q_PMAX];
  r->max_shear_stress_pa = ratio * r->max_contact_pressure_pa;
  af_yield_law law = af_model_yield_law(p);
  r->yield_shear_stress_pa = af_yield_shear_pa(&law, ip->fruit_modulus_pa);
  r->excites_mode = af_criteria_excites_mode(r->band_found ? &r->band : NULL, r->resonance_hz);
  r->no_damage = af_criteria_no_damage(r->max_shear_stress_pa, r->yield_shear_stress_pa);
  r->reliable = r->excites_mode && r->no_damage;
  if (full) /* the search reads reliable only */
    af_model_energy_figures(p, r);
  f->from_table++;
  return AF_OK;
}

af_status af_fastpath_execute(af_fastpath *f, const af_model_params *p, af_model_result *r)
{
  return evaluate(f, p, r, true);
}

/* The R2_min search: the strike p at each radius of the scan and the
 * bisection. Only the radius changes, and with it the length, time and force
 * scales (D goes as R^(-1/5)), gamma and the stencil in gamma: the checks of
 * the other parameters, chi, the 0S2, the shear ratio, the yield and the chi
 * stencil are the same at every radius and are worked out once
 * (search_prepare), and what reads a stencil alone (its rows, lobes and
 * clipping) once per stencil. Each radius then takes the same steps as
 * evaluate with full false, in the same order of operations (the same bits),
 * down to the verdict: the same fallbacks, the same counts. */

/* What a gamma stencil (with the search's chi stencils) says of a strike on
 * it, whatever the weights. */
enum {
  STENCIL_TABLE,    /* interpolated */
  STENCIL_FALLBACK, /* by the ODE path: rows, lobes or clipping */
  STENCIL_EVALUATE  /* no lobe tabulated: left to evaluate itself */
};

typedef struct {
  af_fastpath *f;
  af_model_params q; /* the strike; its radius set per evaluation */
  bool ready;        /* the fields below hold; else each radius by evaluate */
  af_fp_weights a;   /* chi stencil */
  af_fp_weights a2;  /* the shifted one (a2_ok: inside the grid) */
  bool a2_ok;
  double res_hz;     /* 0S2 [Hz] */
  double ratio;      /* shear / centre pressure [-] */
  double yield_pa;   /* the yield shear stress [Pa] */
  double k_per_root; /* Hertz stiffness / sqrt(R) [N m^-3/2]: 4/3 E* */
  double scale_num;  /* 5/4 m1 v0^2 [J]: D^(5/2) = this / stiffness */
  int band_fig;      /* per-lobe figure of the band's low edge */
  int stencil_b0;    /* the gamma stencil stencil_kind is of; -1: none yet */
  int stencil_kind;  /* STENCIL_* */
  bool low_zero;     /* the band's low edge 0 at every node of the shifted stencil */
} af_fp_search;

/* The radius-independent part of evaluate for s->q (full false); ready
 * false when a step would not go as on the table at every radius (a check
 * to make in full, a cache that failed, chi off the grid). */
static void search_prepare(af_fp_search *s)
{
  af_fastpath *f = s->f;
  const af_model_params *p = &s->q;
  const af_impact_params *ip = &p->impact;
  double chi, xi;
  s->ready = false;
  s->stencil_b0 = -1;
  if (f->t == NULL)
    f->t = shared_table();
  if (f->t == NULL || !quick_check(f->t, p) || chi_cached(f, ip, &chi) != AF_OK ||
      af_lamb_root_cached(&f->xi, ip->fruit_poisson, &xi) != AF_OK ||
      af_stress_shear_ratio_cached(&f->shear, p->shear_ratio, ip->fruit_poisson, &s->ratio) !=
          AF_OK ||
      !weights(chi / AF_FP_CHI_STEP, AF_FP_NCHI, &s->a))
    return;
  s->res_hz = af_lamb_frequency_hz(xi, p->modulus_factor * ip->fruit_modulus_pa, ip->fruit_poisson,
                                   p->fruit_density_kg_m3, p->fruit_mass_kg);
  s->a2_ok = shifted_stencil(&s->a, chi, &s->a2);
  af_yield_law law = af_model_yield_law(p);
  s->yield_pa = af_yield_shear_pa(&law, ip->fruit_modulus_pa);
  s->k_per_root = 4.0 / 3.0 * af_impact_effective_modulus_pa(ip);
  s->scale_num = 1.25 * ip->hammer_mass_kg * ip->velocity_m_s * ip->velocity_m_s;
  s->band_fig = p->band_level == AF_BAND_POWER_HALF ? 4 : 6;
  s->ready = true;
}

/* Figure k is zero at every node of the stencil: its interpolation is
 * exactly +0 (0.0 plus products of zeros with finite weights). */
static bool zero_on(const af_fp_table *f, const af_fp_weights *a, const af_fp_weights *b, int k)
{
  for (int i = 0; i < 4; i++)
    for (int j = 0; j < 4; j++)
      if (f->q[node_index(a->i0 + i, b->i0 + j) * NQ + k] != 0.0)
        return false;
  return true;
}

/* evaluate's checks that read gamma stencil b alone (with the chi stencils):
 * the rows built (a row's state is final once asked), the lobes of one
 * number, a band edge clipped at all nodes or none, the shifted chi stencil
 * inside the grid with the same lobes. */
static int stencil_kind(af_fp_search *s, const af_fp_weights *b)
{
  af_fp_table *tb = s->f->t;
  if (!rows_ready(tb, s->a.i0 - 1, s->a.i0 + 4) || !lobes_agree(tb, &s->a, b))
    return STENCIL_FALLBACK;
  int n = tb->n_lobes[node_index(s->a.i0, b->i0)];
  if (n < 0)
    return STENCIL_EVALUATE;
  if ((int)s->q.lobe > n)
    return STENCIL_TABLE; /* no band: nothing more read */
  int base = Q_LOBES + (int)(s->q.lobe - 1) * AF_FP_LOBE_FIGS + s->band_fig;
  if (clipped_mixed(tb, &s->a, b, base, base - s->band_fig) ||
      clipped_mixed(tb, &s->a, b, base + 1, base - s->band_fig + 1) || !s->a2_ok ||
      !lobes_agree(tb, &s->a2, b))
    return STENCIL_FALLBACK;
  s->low_zero = zero_on(tb, &s->a2, b, base); /* the main lobe's: from 0 Hz */
  return STENCIL_TABLE;
}

/* The band's edges [Hz] at time scale t_s [s] into band; false when the two
 * chi stencils disagree on them (the strike goes to the ODE path). */
static bool search_band(const af_fp_search *s, const af_fp_weights *b, double t_s, af_lobe *band)
{
  const af_fp_table *tb = s->f->t;
  int base = Q_LOBES + (int)(s->q.lobe - 1) * AF_FP_LOBE_FIGS + s->band_fig;
  band->band_low_hz = s->q.lobe == 1 ? 0.0 : bicubic_q(tb, &s->a, b, base) / t_s;
  band->band_high_hz = bicubic_q(tb, &s->a, b, base + 1) / t_s;
  double low2 = s->low_zero ? 0.0 : bicubic_q(tb, &s->a2, b, base);
  return edges_agree(low2, bicubic_q(tb, &s->a2, b, base + 1), band->band_low_hz * t_s,
                     band->band_high_hz * t_s);
}

/* The strike s->q (radius set) by evaluate, or by the ODE path, into a verdict. */
static af_status search_other(af_fp_search *s, bool by_ode, bool *ok)
{
  af_model_result r;
  af_status st = by_ode ? fallback(s->f, &s->q, &r) : evaluate(s->f, &s->q, &r, false);
  *ok = st == AF_OK && r.reliable;
  return st;
}

/* The search's verdict at radius_m [m]: evaluate's with full false. */
static af_status search_reliable(void *ctx, double radius_m, bool *ok)
{
  af_fp_search *s = ctx;
  const af_impact_params *ip = &s->q.impact;
  s->q.impact.strike_radius_m = radius_m;
  if (!s->ready ||
      !af_setting_range_contains(&s->f->t->ranges[AF_SETTING_STRIKE_RADIUS_MIN_M], radius_m))
    return search_other(s, false, ok);
  double m1 = ip->hammer_mass_kg, v0 = ip->velocity_m_s;
  double radius = af_impact_effective_radius_m(ip);
  double d = pow(s->scale_num / (s->k_per_root * sqrt(radius)), 0.4);
  double t = d / v0, f0 = m1 * v0 * v0 / d;
  double gamma = ip->gravity_m_s2 * d / (v0 * v0), phi = s->res_hz * t / AF_FP_PHI_STEP;
  af_fp_weights b;
  if (!weights(gamma / AF_FP_GAM_STEP, AF_FP_NGAM, &b) || !(phi >= 0.0 && phi <= AF_FP_NPHI - 1))
    return search_other(s, true, ok);
  if (b.i0 != s->stencil_b0) {
    s->stencil_b0 = b.i0;
    s->stencil_kind = stencil_kind(s, &b);
  }
  if (s->stencil_kind != STENCIL_TABLE)
    return search_other(s, s->stencil_kind == STENCIL_FALLBACK, ok);
  af_lobe band = {0};
  bool band_found = (int)s->q.lobe <= s->f->t->n_lobes[node_index(s->a.i0, b.i0)];
  if (band_found && !search_band(s, &b, t, &band))
    return search_other(s, true, ok);
  s->f->from_table++;
  *ok = af_criteria_excites_mode(band_found ? &band : NULL, s->res_hz);
  if (*ok) { /* else the shear is not needed */
    double pressure = 3.0 * f0 / (2.0 * M_PI * radius * d) * bicubic_q(s->f->t, &s->a, &b, Q_PMAX);
    *ok = af_criteria_no_damage(s->ratio * pressure, s->yield_pa);
  }
  return AF_OK;
}

af_status af_fastpath_min_strike_radius(af_fastpath *f, const af_model_params *p, double r_lo_m,
                                        double r_hi_m, double *r_min_m)
{
  af_fp_search s = {.f = f, .q = *p};
  s.q.impact.strike_radius_m = r_hi_m; /* search_prepare's checks at a radius of the search */
  search_prepare(&s);
  return af_r2_search_radius(search_reliable, &s, r_lo_m, r_hi_m, r_min_m);
}
