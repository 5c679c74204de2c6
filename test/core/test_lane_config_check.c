/* test_lane_config_check.c — af_lane_config_derive's check of settings that
 * are each valid alone but cannot work together: the audio ring against what
 * a strike's audio must wait, the force ring against one strike's event, the
 * noise band against the cultivar's 0S2 search range, the equatorial-radius
 * range against the masses, density and aspect ratios. Each bound is worked
 * out here by hand from its closed form and the shipped values, and each
 * refusal is one line naming both sides. Run from the repository root (the
 * shipped files are read as config/station.yaml and config/jonagold.yaml). */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "af_test.h"
#include "lane_config.h"
#include "settings.h"

#define STATION "config/station.yaml"
#define CULTIVAR "config/jonagold.yaml"
#define ERR_MAX 1024

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

/* The shipped values (station.yaml, jonagold.yaml) this file's bounds are
 * worked out from. */
#define NOISE_WINDOW_S 0.02  /* measure_noise_window_s */
#define NOISE_GUARD_S 0.005  /* measure_noise_guard_s */
#define AUDIO_DELAY_S 0.0005 /* measure_audio_delay_s */
#define AUDIO_WINDOW_S 0.04  /* measure_audio_window_s */
#define APPLE_WAIT_S 0.5     /* apple_wait_s */
#define STALE_S 1.0          /* stream_stale_after_s */
#define PRE_S 0.002          /* strike_pre_trigger_s */
#define CONTACT_S 0.01       /* strike_max_contact_s */
#define GAP_S 0.005          /* strike_double_hit_gap_s */
#define POST_S 0.005         /* strike_post_s */
#define FORCE_HZ 50000.0     /* force_sample_rate_hz */
#define AUDIO_HZ 48000.0     /* audio_sample_rate_hz */
#define BUFFER_S 2.0         /* force_buffer_s, audio_buffer_s */
#define E_MIN_PA 2e6         /* modulus_min_pa */
#define E_MAX_PA 12e6        /* modulus_max_pa */
#define M_MIN_KG 0.100       /* mass_min_kg */
#define M_MAX_KG 0.250       /* mass_max_kg */
#define RHO 840.0            /* density_kg_m3 */
#define NU 0.35              /* fruit_poisson */
#define XI 2.6519            /* Lamb's 0S2 root at nu = 0.35 (PHYSICS.md 5, test_lamb.c) */
#define MARGIN 0.15          /* measure_range_margin */
#define ASPECT_MIN 0.5       /* aspect_ratio_min */
#define ASPECT_MAX 1.5       /* aspect_ratio_max */

/* Derives the shipped files (and the rig's hammer) with args set on top. */
static af_status derive(const char *const *args, af_lane_config *c, char *err)
{
  af_settings s;
  af_settings_reset(&s);
  af_status st = af_settings_load_yaml(&s, STATION, err, ERR_MAX);
  if (st == AF_OK)
    st = af_settings_load_yaml(&s, CULTIVAR, err, ERR_MAX);
  if (st == AF_OK)
    st = af_settings_set_arg(&s, "hammer_mass_kg=0.010", err, ERR_MAX);
  if (st == AF_OK)
    st = af_settings_set_arg(&s, "hammer_tip_radius_m=0", err, ERR_MAX);
  for (; st == AF_OK && *args; args++)
    st = af_settings_set_arg(&s, *args, err, ERR_MAX);
  return st == AF_OK ? af_lane_config_derive(&s, c, err, ERR_MAX) : AF_EIO;
}

static af_lane_config cfg; /* large: one, reused */

#define DERIVE(err, ...) derive((const char *const[]){__VA_ARGS__, NULL}, &cfg, err)

/* The derive was accepted (err printed when not). */
static void expect_ok(af_status st, const char *err, const char *what)
{
  AF_CHECK_STATUS(st, AF_OK);
  if (st != AF_OK)
    fprintf(stderr, "  %s: %s\n", what, err);
}

/* Refused with one line holding every word of want (NULL-terminated). */
static void expect_refused(af_status st, const char *err, const char *const *want)
{
  AF_CHECK_STATUS(st, AF_EINVAL);
  AF_CHECK(err[0] != '\0' && strchr(err, '\n') == NULL);
  for (; *want; want++)
    if (strstr(err, *want) == NULL) {
      AF_CHECK(strstr(err, *want) != NULL);
      fprintf(stderr, "  want '%s' in: %s\n", *want, err);
    }
}
#define REFUSED(call, err, ...) expect_refused(call, err, (const char *const[]){__VA_ARGS__, NULL})

/* The shipped files pass, and each stream takes chunks up to its ring. */
static void test_shipped_pass(void)
{
  char err[ERR_MAX] = "";
  expect_ok(DERIVE(err, "cultivar=Jonagold"), err, "shipped");
  AF_CHECK(cfg.force.max_chunk_samples == (size_t)(BUFFER_S * FORCE_HZ));
  AF_CHECK(cfg.audio.max_chunk_samples == (size_t)(BUFFER_S * AUDIO_HZ));
}

/* The audio ring holds the noise reference before the contact and, after
 * it, the later of apple_wait_s, the detector's emission (two contacts, the
 * gap, the wait after) and the window, plus stream_stale_after_s that the
 * audio may lead the force by. */
static void test_audio_ring(void)
{
  char err[ERR_MAX];
  const double before = NOISE_WINDOW_S + NOISE_GUARD_S;
  const double emission = 2.0 * CONTACT_S + GAP_S + POST_S; /* 0.03 s */
  /* apple_wait_s dominates: 0.025 + 0.5 + 1 = 1.525 s */
  const double need_wait = before + APPLE_WAIT_S + STALE_S;
  AF_CHECK(fabs(need_wait - 1.525) < 1e-12);
  REFUSED(DERIVE(err, "audio_buffer_s=1.52"), err, "audio_buffer_s = 1.52 s", "apple_wait_s 0.5 s",
          "stream_stale_after_s 1 s", "at least 1.525 s");
  expect_ok(DERIVE(err, "audio_buffer_s=1.53"), err, "audio 1.53 s");
  /* The case: a ring shorter than the apple wait. */
  REFUSED(DERIVE(err, "audio_buffer_s=0.2"), err, "audio_buffer_s = 0.2 s", "apple_wait_s");
  /* Without the apple wait the window dominates the emission (0.0405 > 0.03):
   * 0.025 + 0.0405 + 1 = 1.0655 s. */
  AF_CHECK(AUDIO_DELAY_S + AUDIO_WINDOW_S > emission);
  REFUSED(DERIVE(err, "apple_wait_s=0", "audio_buffer_s=1.06"), err,
          "measure_audio_delay_s + measure_audio_window_s = 0.0405 s", "at least 1.066 s");
  expect_ok(DERIVE(err, "apple_wait_s=0", "audio_buffer_s=1.07"), err, "no wait, 1.07 s");
  /* A 10 ms window: the emission, 0.03 s, dominates: 0.025 + 0.03 + 1 = 1.055 s. */
  REFUSED(DERIVE(err, "apple_wait_s=0", "measure_audio_window_s=0.01", "audio_buffer_s=1.05"), err,
          "detector's emission 0.03 s", "at least 1.055 s");
  /* A shorter stale time lowers the bound: 0.025 + 0.5 + 0.1 = 0.625 s. */
  REFUSED(DERIVE(err, "stream_stale_after_s=0.1", "audio_buffer_s=0.62"), err,
          "stream_stale_after_s 0.1 s", "at least 0.625 s");
  expect_ok(DERIVE(err, "stream_stale_after_s=0.1", "audio_buffer_s=0.63"), err, "stale 0.1");
  /* No noise reference: no guard either: 0.5 + 1 = 1.5 s. */
  expect_ok(DERIVE(err, "measure_noise_window_s=0", "audio_buffer_s=1.501"), err, "no noise");
  REFUSED(DERIVE(err, "measure_noise_window_s=0", "audio_buffer_s=1.499"), err, "at least 1.5 s");
}

/* The force ring takes a chunk of one strike's event: pre-trigger + two
 * contacts + gap + wait after = 0.032 s, 1600 samples at 50 kHz (the
 * detector rounds each part up and keeps a few samples more). */
static void test_force_ring(void)
{
  char err[ERR_MAX];
  const double event_s = PRE_S + 2.0 * CONTACT_S + GAP_S + POST_S;
  AF_CHECK(fabs(event_s - 0.032) < 1e-12);
  /* The case: 0.0001 s is ceil(5) samples, every chunk refused. */
  REFUSED(DERIVE(err, "force_buffer_s=0.0001"), err, "force_buffer_s = 0.0001 s holds 5 samples",
          "strike_max_contact_s", "strike_post_s", "= 0.032 s", "raise force_buffer_s");
  /* 1604 samples: 100 + 2 x 500 + 250 + 250 and the detector's 4. */
  REFUSED(DERIVE(err, "force_buffer_s=0.031"), err, "at least 0.03208 s");
  REFUSED(DERIVE(err, "force_buffer_s=0.031"), err, "holds 1550 samples");
  expect_ok(DERIVE(err, "force_buffer_s=0.033"), err, "force 0.033 s");
  /* Tap-only: no force stream, no force check. */
  expect_ok(DERIVE(err, "tap_only=true", "force_buffer_s=0.0001"), err, "tap-only");
}

/* The 0S2 of a sphere: f = xi c_s / (2 pi R), c_s = sqrt(E / (2 (1 + nu) rho)),
 * R = cbrt(3 m / (4 pi rho)) [Hz]. */
static double f_0s2_hz(double e_pa, double m_kg)
{
  const double cs = sqrt(e_pa / (2.0 * (1.0 + NU) * RHO));
  return XI * cs / (2.0 * M_PI * cbrt(3.0 * m_kg / (4.0 * M_PI * RHO)));
}

/* The noise band must lie outside the search range: from the softest,
 * heaviest apple (x 0.85) to the firmest, lightest (x 1.15): 257.2 ..
 * 1156.9 Hz for Jonagold. */
static void test_noise_band(void)
{
  char err[ERR_MAX], lo[64], hi[64];
  const double f_lo = (1.0 - MARGIN) * f_0s2_hz(E_MIN_PA, M_MAX_KG);
  const double f_hi = (1.0 + MARGIN) * f_0s2_hz(E_MAX_PA, M_MIN_KG);
  AF_CHECK(fabs(f_lo - 257.2) < 0.1 && fabs(f_hi - 1156.9) < 0.1);
  /* The case: a band inside the 0S2's range. */
  REFUSED(DERIVE(err, "measure_noise_band_low_hz=500", "measure_noise_band_high_hz=700"), err,
          "measure_noise_band_low_hz = 500", "measure_noise_band_high_hz = 700", "modulus_min_pa",
          "mass_max_kg", "0S2", "put the band above 1157 Hz or below 257 Hz");
  /* Just above f_hi: accepted; just below: refused. */
  snprintf(lo, sizeof lo, "measure_noise_band_low_hz=%.1f", f_hi * 1.01);
  expect_ok(DERIVE(err, lo), err, "band above f_hi");
  snprintf(lo, sizeof lo, "measure_noise_band_low_hz=%.1f", f_hi * 0.99);
  REFUSED(DERIVE(err, lo), err, "overlaps the 0S2's search range");
  /* Below f_lo: accepted; reaching into it: refused. */
  snprintf(hi, sizeof hi, "measure_noise_band_high_hz=%.1f", f_lo * 0.99);
  expect_ok(DERIVE(err, "measure_noise_band_low_hz=100", hi), err, "band below f_lo");
  snprintf(hi, sizeof hi, "measure_noise_band_high_hz=%.1f", f_lo * 1.01);
  REFUSED(DERIVE(err, "measure_noise_band_low_hz=100", hi), err, "overlaps");
  /* A modulus factor of 2 moves the range up by sqrt(2): 1.01 f_hi is inside. */
  snprintf(lo, sizeof lo, "measure_noise_band_low_hz=%.1f", f_hi * 1.01);
  REFUSED(DERIVE(err, lo, "modulus_factor=2"), err, "modulus_factor = 2");
}

/* Equatorial semi-axis of mass m, density RHO, polar / equatorial aspect:
 * m = 4/3 pi rho a^2 (aspect a) [m]. */
static double radius_m(double m_kg, double aspect)
{
  return cbrt(3.0 * m_kg / (4.0 * M_PI * RHO * aspect));
}

/* Some apple in the radius range must have a mass in range and an aspect in
 * range: the lightest, tallest is 0.026659 m, the heaviest, flattest
 * 0.052184 m. A suggested bound is rounded to 4 digits towards passing. */
static void test_radius_range(void)
{
  char err[ERR_MAX];
  const double smallest = radius_m(M_MIN_KG, ASPECT_MAX), largest = radius_m(M_MAX_KG, ASPECT_MIN);
  AF_CHECK(fabs(smallest - 0.026659) < 1e-6 && fabs(largest - 0.052184) < 1e-6);
  REFUSED(DERIVE(err, "equatorial_radius_min_m=0.01", "equatorial_radius_max_m=0.026"), err,
          "equatorial_radius_max_m = 0.026 m is smaller", "mass_min_kg = 0.1",
          "aspect_ratio_max = 1.5", "0.026659", "at least 0.02666 m", "density_kg_m3 = 840");
  expect_ok(DERIVE(err, "equatorial_radius_min_m=0.01", "equatorial_radius_max_m=0.027"), err,
            "radius max 0.027");
  REFUSED(DERIVE(err, "equatorial_radius_min_m=0.053"), err,
          "equatorial_radius_min_m = 0.053 m is larger", "mass_max_kg = 0.25",
          "aspect_ratio_min = 0.5", "0.052184", "at most 0.05218 m");
  expect_ok(DERIVE(err, "equatorial_radius_min_m=0.052"), err, "radius min 0.052");
  /* A denser fruit is smaller: at 1000 kg/m3 the heaviest, flattest apple
   * is 0.052184 x cbrt(840 / 1000) = 0.049237 m, so 0.050 m is refused. */
  AF_CHECK(fabs(largest * cbrt(RHO / 1000.0) - 0.049237) < 1e-6);
  REFUSED(DERIVE(err, "equatorial_radius_min_m=0.050", "density_kg_m3=1000"), err, "0.049237",
          "at most 0.04923 m");
}

int main(void)
{
  test_shipped_pass();
  test_audio_ring();
  test_force_ring();
  test_noise_band();
  test_radius_range();
  return af_test_summary("test_lane_config_check");
}
