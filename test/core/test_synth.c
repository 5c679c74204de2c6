/* test_synth.c — the seeded test-signal synthesis (synth.h): splitmix64
 * against its published reference outputs (seed 0), the uniform and normal
 * draws derived by hand from them and their moments, the noise RMS of an
 * SNR, hum and drift against their closed forms evaluated here, clipping,
 * the pulse's interpolation on a hand-built fine grid, and the model pulse
 * against PHYSICS.md 3 (elastic Hertz t_c, F_max, symmetry) and the
 * momentum balance (its integral is m1 v0 (1 + e) + m1 g t_c). */
#include <math.h>
#include <string.h>

#include "af_test.h"
#include "synth.h"

static const double PI = 3.14159265358979323846;

/* splitmix64, seed 0: Vigna's reference implementation's first outputs. */
static const uint64_t SPLITMIX_SEED0[3] = {0xE220A8397B1DCDAFULL, 0x6E789E6AA1B965F4ULL,
                                           0x06C45D188009454FULL};

static void test_rng(void)
{
  af_synth_rng g;
  af_synth_rng_seed(&g, 0);
  for (int k = 0; k < 3; k++)
    AF_CHECK(af_synth_rng_next(&g) == SPLITMIX_SEED0[k]);
  /* Uniform: the top 53 bits over 2^53. */
  af_synth_rng_seed(&g, 0);
  AF_CHECK(af_synth_uniform(&g) == (double)(SPLITMIX_SEED0[0] >> 11) / 9007199254740992.0);
  AF_CHECK(af_synth_uniform(&g) == (double)(SPLITMIX_SEED0[1] >> 11) / 9007199254740992.0);
  /* Normal, Marsaglia's polar method by hand from the first two uniforms
   * (u = 2 U - 1 = 0.767.., v = -0.137..: s < 1, accepted): u f, then the spare v f. */
  double u = 2.0 * (double)(SPLITMIX_SEED0[0] >> 11) / 9007199254740992.0 - 1.0;
  double v = 2.0 * (double)(SPLITMIX_SEED0[1] >> 11) / 9007199254740992.0 - 1.0;
  double s = u * u + v * v;
  AF_CHECK(s < 1.0 && s > 0.0);
  double f = sqrt(-2.0 * log(s) / s);
  af_synth_rng_seed(&g, 0);
  AF_CHECK_REL(af_synth_gauss(&g), u * f, 1e-15);
  AF_CHECK(g.has_spare);
  AF_CHECK_REL(af_synth_gauss(&g), v * f, 1e-15);
  AF_CHECK(!g.has_spare);
  /* Reseeding forgets a spare: the same seed, the same stream. */
  af_synth_gauss(&g);
  af_synth_rng_seed(&g, 0);
  AF_CHECK(!g.has_spare);
  AF_CHECK_REL(af_synth_gauss(&g), u * f, 1e-15);

  /* Moments over N draws: uniform mean 1/2, variance 1/12; normal mean 0,
   * variance 1 (within 5 standard errors). */
  const int n = 200000;
  double su = 0, suu = 0, sg = 0, sgg = 0;
  af_synth_rng_seed(&g, 12345);
  for (int k = 0; k < n; k++) {
    double x = af_synth_uniform(&g);
    if (!(x >= 0.0 && x < 1.0))
      af_test_failed++;
    su += x;
    suu += x * x;
  }
  double mu = su / n, vu = suu / n - mu * mu;
  AF_CHECK_ABS(mu, 0.5, 5.0 * sqrt(1.0 / 12.0 / n));
  AF_CHECK_ABS(vu, 1.0 / 12.0, 5.0 * sqrt(1.0 / 180.0 / n)); /* var of U^2-ish: < 1/180 */
  for (int k = 0; k < n; k++) {
    double x = af_synth_gauss(&g);
    sg += x;
    sgg += x * x;
  }
  double mg = sg / n, vg = sgg / n - mg * mg;
  AF_CHECK_ABS(mg, 0.0, 5.0 / sqrt((double)n));
  AF_CHECK_ABS(vg, 1.0, 5.0 * sqrt(2.0 / n));
}

static void test_imperfections(void)
{
  AF_CHECK_REL(af_synth_noise_rms(100.0, 40.0), 1.0, 1e-12);
  AF_CHECK_REL(af_synth_noise_rms(100.0, 20.0), 10.0, 1e-12);
  AF_CHECK_REL(af_synth_noise_rms(38.71, 0.0), 38.71, 1e-12);
  AF_CHECK_REL(af_synth_noise_rms(2.0, -6.0), 2.0 * 1.9952623149688795, 1e-12);

  enum { N = 50000 };
  static double x[N];
  const double dt = 20e-6, t1 = 0.1234;
  /* Noise of RMS 0.3 on a zero signal: measured RMS within 1 %. */
  memset(x, 0, sizeof x);
  af_synth_rng g;
  af_synth_rng_seed(&g, 7);
  af_synth_add_noise(x, N, 0.3, &g);
  double ss = 0;
  for (int k = 0; k < N; k++)
    ss += x[k] * x[k];
  AF_CHECK_REL(sqrt(ss / N), 0.3, 0.01);

  /* Hum: 0.2 sin(2 pi 50 (t1 + k dt) + 0.7); 1 s of it holds 50 whole
   * periods: mean 0, RMS 0.2 / sqrt 2. */
  memset(x, 0, sizeof x);
  af_synth_add_hum(x, N, dt, t1, 0.2, 50.0, 0.7);
  double worst = 0, sum = 0, sq = 0;
  for (int k = 0; k < N; k++) {
    double e = 0.2 * sin(2.0 * PI * 50.0 * (t1 + k * dt) + 0.7);
    worst = fmax(worst, fabs(x[k] - e));
    sum += x[k];
    sq += x[k] * x[k];
  }
  AF_CHECK(worst < 1e-12);
  AF_CHECK_ABS(sum / N, 0.0, 1e-12);
  AF_CHECK_REL(sqrt(sq / N), 0.2 / sqrt(2.0), 1e-9);
  AF_CHECK_ABS(x[0], 0.2 * sin(2.0 * PI * 50.0 * 0.1234 + 0.7), 1e-12);

  /* Drift: 0.05 + 0.4 t + 1.5 exp(-t / 0.02), added to what is there. */
  for (int k = 0; k < N; k++)
    x[k] = 1.0;
  af_synth_add_drift(x, N, dt, t1, 0.05, 0.4, 1.5, 0.02);
  worst = 0;
  for (int k = 0; k < N; k++) {
    double t = t1 + k * dt;
    worst = fmax(worst, fabs(x[k] - (1.0 + 0.05 + 0.4 * t + 1.5 * exp(-t / 0.02))));
  }
  AF_CHECK(worst < 1e-12);
  /* tau <= 0 leaves the exponential out. */
  double y[3] = {0, 0, 0};
  af_synth_add_drift(y, 3, 0.5, 0.0, 1.0, 2.0, 100.0, 0.0);
  AF_CHECK(y[0] == 1.0 && y[1] == 2.0 && y[2] == 3.0);
  af_synth_add_drift(y, 3, 0.5, 0.0, 0.0, 0.0, 100.0, -1.0);
  AF_CHECK(y[0] == 1.0 && y[2] == 3.0);

  /* Clipping at +-2. */
  double c[6] = {-5.0, -2.0, -1.999, 0.0, 2.0, 1e9};
  af_synth_clip(c, 6, 2.0);
  AF_CHECK(c[0] == -2.0 && c[1] == -2.0 && c[2] == -1.999 && c[3] == 0.0 && c[4] == 2.0 &&
           c[5] == 2.0);
  float fl[3];
  double d[3] = {0.1, -3.5, 1e-40};
  af_synth_to_float(d, 3, fl);
  AF_CHECK(fl[0] == 0.1f && fl[1] == -3.5f && fl[2] == (float)1e-40);
}

/* A hand-built pulse: F = 0, 10, 20, 10 N at 0, 0.1, 0.2, 0.3 ms, t_c
 * 0.35 ms (the last segment falls linearly from 10 N to 0). */
static void test_interpolation(void)
{
  static const double fine[4] = {0.0, 10.0, 20.0, 10.0};
  af_synth_pulse p;
  memset(&p, 0, sizeof p);
  p.force_n = fine;
  p.n = 4;
  p.fine_dt_s = 1e-4;
  p.res.contact_time_s = 3.5e-4;
  AF_CHECK_ABS(af_synth_pulse_at(&p, 0.5e-4), 5.0, 1e-9);
  AF_CHECK_ABS(af_synth_pulse_at(&p, 1.5e-4), 15.0, 1e-9);
  AF_CHECK_ABS(af_synth_pulse_at(&p, 2.0e-4), 20.0, 1e-9);
  AF_CHECK_ABS(af_synth_pulse_at(&p, 2.75e-4), 12.5, 1e-9);
  AF_CHECK_ABS(af_synth_pulse_at(&p, 3.0e-4), 10.0, 1e-9);
  AF_CHECK_ABS(af_synth_pulse_at(&p, 3.25e-4), 5.0, 1e-9);
  AF_CHECK(af_synth_pulse_at(&p, 0.0) == 0.0);
  AF_CHECK(af_synth_pulse_at(&p, -1e-5) == 0.0);
  AF_CHECK(af_synth_pulse_at(&p, 3.5e-4) == 0.0);
  AF_CHECK(af_synth_pulse_at(&p, 1.0) == 0.0);
  AF_CHECK(af_synth_pulse_at(&p, NAN) == 0.0);
  p.n = 0;
  AF_CHECK(af_synth_pulse_at(&p, 1e-4) == 0.0);
  p.n = 4;

  /* On a 50 us grid from t = 1 ms, the pulse starting at t0 = 1.0125 ms,
   * twice: x[k] = 2 F(t_k - t0) for t_k in (t0, t0 + t_c), untouched
   * elsewhere. Samples at t - t0 = 37.5, 87.5, ... us. */
  double x[12];
  for (int k = 0; k < 12; k++)
    x[k] = 1.0;
  af_synth_add_pulse(x, 12, 50e-6, 1e-3, &p, 1.0125e-3, 2.0);
  const double want[12] = {1.0,
                           1.0 + 2.0 * 3.75,  /* 37.5 us: 3.75 N */
                           1.0 + 2.0 * 8.75,  /* 87.5 us */
                           1.0 + 2.0 * 13.75, /* 137.5 us */
                           1.0 + 2.0 * 18.75, /* 187.5 us */
                           1.0 + 2.0 * 16.25, /* 237.5 us: 20 - 10 (37.5/100) */
                           1.0 + 2.0 * 11.25, /* 287.5 us */
                           1.0 + 2.0 * 2.5,   /* 337.5 us: last segment, 10 (350-337.5)/50 */
                           1.0,               /* 387.5 us: after t_c */
                           1.0,
                           1.0,
                           1.0};
  int ok = 1;
  for (int k = 0; k < 12; k++)
    if (fabs(x[k] - want[k]) > 1e-9) {
      fprintf(stderr, "  add_pulse x[%d] = %g, expected %g\n", k, x[k], want[k]);
      ok = 0;
    }
  AF_CHECK(ok);
}

/* Trapezoid of F over [0, t_c] on a grid 16 times finer than the pulse's. */
static double integral_n_s(const af_synth_pulse *p)
{
  const int m = 16 * (int)p->n;
  const double h = p->res.contact_time_s / m;
  double sum = 0.0;
  for (int k = 1; k < m; k++)
    sum += af_synth_pulse_at(p, k * h);
  return sum * h;
}

static void test_model_pulse(void)
{
  af_impact *w = NULL;
  AF_CHECK_STATUS(af_impact_create(&w), AF_OK);
  if (w == NULL)
    return;
  static double buf[8192];
  af_synth_pulse p;
  /* PHYSICS.md 3, elastic and without gravity: t_c = 1.33059 ms, F_max =
   * 38.710 N for 10 g at 1.4 m/s on E2 8 MPa, nu2 0.35, R 40 mm. */
  af_impact_params ip = af_impact_params_default();
  ip.restitution = 1.0;
  ip.gravity_m_s2 = 0.0;
  AF_CHECK_STATUS(af_synth_pulse_model(w, &ip, 20e-6 / 64, buf, 8192, &p), AF_OK);
  AF_CHECK(p.force_n == buf && p.n == p.res.n_samples && p.fine_dt_s == 20e-6 / 64);
  AF_CHECK_REL(p.res.contact_time_s, 1.33059e-3, 1e-4);
  AF_CHECK_REL(p.res.peak_force_n, 38.710, 1e-4);
  /* The sampled peak: at most the refined one, within 0.1 %. */
  double peak = 0.0;
  for (size_t k = 0; k < p.n; k++)
    peak = fmax(peak, buf[k]);
  AF_CHECK(peak <= p.res.peak_force_n * (1 + 1e-12));
  AF_CHECK_REL(peak, 38.710, 1e-3);
  /* Elastic without gravity: F(t) = F(t_c - t). */
  double asym = 0.0;
  for (int k = 1; k < 20; k++) {
    double t = p.res.contact_time_s * k / 20.0;
    asym = fmax(asym,
                fabs(af_synth_pulse_at(&p, t) - af_synth_pulse_at(&p, p.res.contact_time_s - t)));
  }
  AF_CHECK(asym < 1e-3 * 38.710);
  /* Momentum: the integral of F is m1 v0 (1 + 1) = 0.028 N s. */
  AF_CHECK_REL(p.impulse_n_s, 0.028, 1e-4);
  AF_CHECK_REL(integral_n_s(&p), 0.028, 2e-4);

  /* The default strike (e 0.6, gravity): t_c with gravity for e = 1 is
   * 1.33217 ms; with damping the momentum balance includes m1 g t_c. */
  ip.gravity_m_s2 = 9.80665;
  AF_CHECK_STATUS(af_synth_pulse_model(w, &ip, 20e-6 / 64, buf, 8192, &p), AF_OK);
  AF_CHECK_REL(p.res.contact_time_s, 1.33217e-3, 1e-4);
  ip = af_impact_params_default();
  AF_CHECK_STATUS(af_synth_pulse_model(w, &ip, 20e-6 / 64, buf, 8192, &p), AF_OK);
  /* The exact law delivers what is asked without gravity; gravity's m1 g
   * during the contact shifts it by a few 0.1 %. */
  AF_CHECK_REL(p.res.delivered_restitution, 0.6, 1e-2);
  AF_CHECK_REL(p.impulse_n_s,
               0.010 * (1.4 * (1.0 + p.res.delivered_restitution) + 9.80665 * p.res.contact_time_s),
               1e-12);
  AF_CHECK_REL(integral_n_s(&p), p.impulse_n_s, 2e-3);
  ip.gravity_m_s2 = 0.0;
  AF_CHECK_STATUS(af_synth_pulse_model(w, &ip, 20e-6 / 64, buf, 8192, &p), AF_OK);
  AF_CHECK_REL(p.res.delivered_restitution, 0.6, 2e-3);
  AF_CHECK_REL(p.impulse_n_s, 0.010 * 1.4 * (1.0 + p.res.delivered_restitution), 1e-12);
  AF_CHECK_REL(integral_n_s(&p), p.impulse_n_s, 2e-3);
  ip.gravity_m_s2 = 9.80665;

  /* Refusals pass through: too small a buffer, a bad step. */
  AF_CHECK_STATUS(af_synth_pulse_model(w, &ip, 20e-6 / 64, buf, 16, &p), AF_ESIZE);
  AF_CHECK_STATUS(af_synth_pulse_model(w, &ip, 0.0, buf, 8192, &p), AF_EINVAL);
  ip.velocity_m_s = -1.0;
  AF_CHECK_STATUS(af_synth_pulse_model(w, &ip, 20e-6 / 64, buf, 8192, &p), AF_EINVAL);
  af_impact_destroy(w);
}

/* The independent RK4 pulse: the same closed forms as the model (PHYSICS.md
 * 3), and the model's own figures within the two integrators' errors. */
static void test_rk4_pulse(void)
{
  af_impact *w = NULL;
  AF_CHECK_STATUS(af_impact_create(&w), AF_OK);
  if (w == NULL)
    return;
  static double buf[8192], ref[8192];
  af_synth_pulse p, q;
  const double h = 20e-6 / 64;
  af_impact_params ip = af_impact_params_default();
  ip.restitution = 1.0;
  ip.gravity_m_s2 = 0.0;
  AF_CHECK_STATUS(af_synth_pulse_rk4(w, &ip, h, buf, 8192, &p), AF_OK);
  AF_CHECK(p.force_n == buf && p.n == p.res.n_samples && p.fine_dt_s == h);
  AF_CHECK_REL(p.res.contact_time_s, 1.33059e-3, 1e-4);
  AF_CHECK_REL(p.res.peak_force_n, 38.710, 1e-4);
  AF_CHECK_REL(p.res.delivered_restitution, 1.0, 1e-6);
  AF_CHECK_REL(integral_n_s(&p), 0.028, 2e-4);
  /* Gravity on, e = 1: 1.33217 ms. */
  ip.gravity_m_s2 = 9.80665;
  AF_CHECK_STATUS(af_synth_pulse_rk4(w, &ip, h, buf, 8192, &p), AF_OK);
  AF_CHECK_REL(p.res.contact_time_s, 1.33217e-3, 1e-4);
  /* Damped strikes over the cultivar's moduli, both laws: the two
   * integrators agree on t_c, the peak, e delivered and every sample. */
  const double moduli_pa[3] = {2e6, 8e6, 12e6};
  const af_damping_law laws[2] = {AF_DAMPING_EXACT, AF_DAMPING_PAPER};
  for (int l = 0; l < 2; l++)
    for (int m = 0; m < 3; m++) {
      ip = af_impact_params_default();
      ip.fruit_modulus_pa = moduli_pa[m];
      ip.damping = laws[l];
      AF_CHECK_STATUS(af_synth_pulse_rk4(w, &ip, h, buf, 8192, &p), AF_OK);
      AF_CHECK_STATUS(af_synth_pulse_model(w, &ip, h, ref, 8192, &q), AF_OK);
      AF_CHECK_REL(p.res.contact_time_s, q.res.contact_time_s, 1e-6);
      AF_CHECK_REL(p.res.peak_force_n, q.res.peak_force_n, 1e-5);
      AF_CHECK_REL(p.res.delivered_restitution, q.res.delivered_restitution, 1e-4);
      AF_CHECK_REL(p.impulse_n_s, q.impulse_n_s, 1e-5);
      double worst = 0.0;
      for (int k = 1; k < 50; k++) {
        double t = q.res.contact_time_s * k / 50.0;
        worst = fmax(worst, fabs(af_synth_pulse_at(&p, t) - af_synth_pulse_at(&q, t)));
      }
      AF_CHECK(worst < 1e-6 * q.res.peak_force_n);
    }
  /* Refusals: too small a buffer, a bad step, a bad hammer, e outside the law. */
  ip = af_impact_params_default();
  AF_CHECK_STATUS(af_synth_pulse_rk4(w, &ip, h, buf, 16, &p), AF_ESIZE);
  AF_CHECK_STATUS(af_synth_pulse_rk4(w, &ip, 0.0, buf, 8192, &p), AF_EINVAL);
  AF_CHECK_STATUS(af_synth_pulse_rk4(w, &ip, NAN, buf, 8192, &p), AF_EINVAL);
  ip.hammer_mass_kg = 0.0;
  AF_CHECK_STATUS(af_synth_pulse_rk4(w, &ip, h, buf, 8192, &p), AF_EINVAL);
  ip = af_impact_params_default();
  ip.restitution = 0.01; /* the exact law is defined from 0.05 */
  AF_CHECK_STATUS(af_synth_pulse_rk4(w, &ip, h, buf, 8192, &p), AF_EINVAL);
  af_impact_destroy(w);
}

int main(void)
{
  test_rng();
  test_imperfections();
  test_interpolation();
  test_model_pulse();
  test_rk4_pulse();
  return af_test_summary("test_synth");
}
