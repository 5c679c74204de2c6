/* test_strike_plot.c — the node's live strike picture (src/node/strike_plot.c)
 * without ROS: one strike measured by the core lane, copied into the strike
 * view in the lane's callback, then rendered in memory (PLplot memcairo)
 * N times, as the node renders it once per strike in its loop.
 *
 * Checks: the picture is not blank (the pulse's blue, the model's orange and
 * the audio spectrum's green are drawn), every render gives the same pixels,
 * and memory stays bounded: the heap in use (glibc mallinfo2) and the RSS
 * after render 100 and after render N (default 1000) differ by less than
 * 64 KiB and 1 MiB. PLplot allocates and frees its stream inside every
 * render (plot.h); this is where a leak there would show. Prints the render
 * time (mean, max) and the memory figures the README quotes.
 *
 * Signals: the impact model's pulse (the default strike, af_synth) on a 0.3 N
 * offset with seeded noise (0.02 N RMS) at 50 kHz, the microphone a
 * decaying sinusoid (682 Hz, Q 30) with noise 40 dB down at 48 kHz.
 * Usage: test_strike_plot [N [OUT.ppm]] (run from the package root; OUT.ppm:
 * the picture, to look at). */
#define _GNU_SOURCE /* mallinfo2, sysconf */
#include <malloc.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "af_test.h"
#include "lane.h"
#include "settings.h"
#include "strike_view.h"
#include "synth.h"

#define FS_FORCE 50000.0
#define FS_AUDIO 48000.0
#define SPAN_S 1.0
#define STRIKE_S 0.4
#define PI 3.14159265358979323846
#define W_PX 800 /* the node's default ~strike_plot size */
#define H_PX 450

typedef struct {
  af_strike_view *view;
  const af_lane *lane;
  int strikes;
} capture;

static af_test_rng rng = {20261122}; /* test noise (af_test.h) */

/* The lane's callback, as the node's: a copy into the view, nothing drawn. */
static void on_strike(const af_lane_strike *s, void *user)
{
  capture *c = user;
  af_strike_view_capture(c->view, s, c->lane);
  c->strikes++;
}

static af_lane_config config(void)
{
  af_settings st;
  af_lane_config cfg;
  char err[512] = "";
  af_settings_reset(&st);
  if (af_settings_load_yaml(&st, "config/station.yaml", err, sizeof err) != AF_OK ||
      af_settings_load_yaml(&st, "config/jonagold.yaml", err, sizeof err) != AF_OK ||
      af_settings_set_arg(&st, "hammer_mass_kg=0.010", err, sizeof err) != AF_OK ||
      af_settings_set_arg(&st, "hammer_tip_radius_m=0", err, sizeof err) != AF_OK ||
      af_lane_config_derive(&st, &cfg, err, sizeof err) != AF_OK) {
    fprintf(stderr, "config: %s\n", err);
    exit(1);
  }
  return cfg;
}

/* Feeds one strike's second of force and audio in 1024-sample chunks. */
static void feed(af_lane *l)
{
  const size_t nf = (size_t)(SPAN_S * FS_FORCE), na = (size_t)(SPAN_S * FS_AUDIO);
  float *force = malloc(nf * sizeof *force), *audio = malloc(na * sizeof *audio);
  if (!force || !audio)
    exit(1);
  /* The impact model's pulse (the default strike: 10 g at 1.4 m/s on 8 MPa, R2 40 mm). */
  static double fine[1 << 16];
  af_impact *w = NULL;
  af_synth_pulse pulse;
  af_impact_params p = af_impact_params_default();
  if (af_impact_create(&w) != AF_OK ||
      af_synth_pulse_model(w, &p, 1.0 / (64.0 * FS_FORCE), fine, sizeof fine / sizeof *fine,
                           &pulse) != AF_OK)
    exit(1);
  for (size_t k = 0; k < nf; k++)
    force[k] = (float)(0.3 + 0.02 * af_test_gauss(&rng) +
                       af_synth_pulse_at(&pulse, (double)k / FS_FORCE - STRIKE_S));
  af_impact_destroy(w);
  const double f0 = 682.0, tau = 30.0 / (PI * f0);
  for (size_t k = 0; k < na; k++) {
    double u = (double)k / FS_AUDIO - STRIKE_S;
    audio[k] = (float)(0.01 * af_test_gauss(&rng) +
                       (u > 0.0 ? exp(-u / tau) * sin(2.0 * PI * f0 * u) : 0.0));
  }
  af_apple a;
  memset(&a, 0, sizeof a);
  a.apple_id = 7;
  a.stamp_ns = (int64_t)llround((STRIKE_S - 0.2) * 1e9);
  a.mass_kg = 0.175;
  a.equatorial_radius_m = 0.0370;
  a.strike_radius_m = 0.040;
  a.confidence = 1.0;
  AF_CHECK_STATUS(af_lane_apple(l, &a, a.stamp_ns, NULL), AF_OK);
  for (size_t kf = 0, ka = 0; kf < nf || ka < na;) {
    bool take_force = kf < nf && (ka >= na || (double)kf / FS_FORCE <= (double)ka / FS_AUDIO);
    size_t *k = take_force ? &kf : &ka, end = take_force ? nf : na;
    size_t n = end - *k < 1024 ? end - *k : 1024;
    double rate = take_force ? FS_FORCE : FS_AUDIO;
    af_chunk c = {(int64_t)llround((double)*k / rate * 1e9),
                  *k,
                  rate,
                  take_force ? "N" : "Pa",
                  take_force ? "force_transducer" : "microphone",
                  (take_force ? force : audio) + *k,
                  n};
    int64_t now = (int64_t)llround((double)(*k + n) / rate * 1e9);
    AF_CHECK(take_force ? af_lane_force(l, &c, now, NULL) == AF_CHUNK_OK
                        : af_lane_audio(l, &c, now, NULL) == AF_CHUNK_OK);
    *k += n;
  }
  af_lane_finish(l);
  free(force);
  free(audio);
}

static double wall_ms(void)
{
  struct timespec ts;
  timespec_get(&ts, TIME_UTC);
  return (double)ts.tv_sec * 1e3 + (double)ts.tv_nsec * 1e-6;
}

static double rss_kib(void)
{
  long pages = 0, resident = 0;
  FILE *f = fopen("/proc/self/statm", "r");
  if (!f || fscanf(f, "%ld %ld", &pages, &resident) != 2)
    resident = 0;
  if (f)
    fclose(f);
  return (double)resident * (double)sysconf(_SC_PAGESIZE) / 1024.0;
}

static double heap_kib(void)
{
  return (double)mallinfo2().uordblks / 1024.0;
}

/* Pixels of roughly colour (r, g, b) (within 60 per channel). */
static size_t count_colour(const unsigned char *rgb, int r, int g, int b)
{
  size_t n = 0;
  for (size_t k = 0; k < (size_t)W_PX * H_PX; k++)
    n += abs(rgb[3 * k] - r) < 60 && abs(rgb[3 * k + 1] - g) < 60 && abs(rgb[3 * k + 2] - b) < 60;
  return n;
}

int main(int argc, char **argv)
{
  const int n_renders = argc > 1 ? atoi(argv[1]) : 1000;
  af_lane_config cfg = config();
  capture cap = {NULL, NULL, 0};
  af_lane *lane = NULL;
  const char *what = "";
  AF_CHECK_STATUS(af_strike_view_create(&cfg, &cap.view), AF_OK);
  AF_CHECK_STATUS(af_lane_create(&cfg, on_strike, &cap, &lane, &what), AF_OK);
  if (!cap.view || !lane)
    return af_test_summary("test_strike_plot");
  cap.lane = lane;
  feed(lane);
  AF_CHECK(cap.strikes == 1);
  AF_CHECK(af_strike_view_pending(cap.view));

  unsigned char *rgb = malloc((size_t)W_PX * H_PX * 3), *first = malloc((size_t)W_PX * H_PX * 3);
  if (!rgb || !first)
    return 1;
  af_plot_target t = {AF_PLOT_MEMORY, NULL, rgb, W_PX, H_PX};
  char err[256] = "";
  double sum_ms = 0.0, max_ms = 0.0, rss_100 = 0.0, heap_100 = 0.0, rss_1 = 0.0;
  int same = 1;
  for (int k = 1; k <= n_renders; k++) {
    double t0 = wall_ms();
    af_status s = af_strike_view_prepare(cap.view);
    if (s == AF_OK)
      s = af_strike_view_draw(cap.view, &t, err, sizeof err);
    double ms = wall_ms() - t0;
    if (s != AF_OK) {
      fprintf(stderr, "render %d: %s\n", k, err);
      AF_CHECK(s == AF_OK);
      break;
    }
    sum_ms += ms;
    max_ms = ms > max_ms ? ms : max_ms;
    if (k == 1) {
      memcpy(first, rgb, (size_t)W_PX * H_PX * 3);
      rss_1 = rss_kib();
    } else
      same &= memcmp(first, rgb, (size_t)W_PX * H_PX * 3) == 0;
    if (k == 100 || (n_renders < 100 && k == 1)) {
      rss_100 = rss_kib();
      heap_100 = heap_kib();
    }
  }
  const double rss_n = rss_kib(), heap_n = heap_kib();
  /* Not blank: white background, then the pulse (blue), the model (orange),
   * the audio spectrum (green) in plot.c's palette. */
  size_t white = count_colour(first, 255, 255, 255);
  size_t blue = count_colour(first, 31, 119, 180), orange = count_colour(first, 255, 127, 14);
  size_t green = count_colour(first, 44, 160, 44);
  printf("strike plot %d x %d px, %d renders: %.2f ms mean, %.2f ms max; RSS %.0f KiB after "
         "render 1, %.0f after 100, %.0f after %d (%+.0f KiB from 100 to %d); heap in use "
         "%+.1f KiB from 100 to %d\n",
         W_PX, H_PX, n_renders, sum_ms / n_renders, max_ms, rss_1, rss_100, rss_n, n_renders,
         rss_n - rss_100, n_renders, heap_n - heap_100, n_renders);
  printf("pixels: %zu not white of %d; blue %zu, orange %zu, green %zu\n",
         (size_t)W_PX * H_PX - white, W_PX * H_PX, blue, orange, green);
  if (argc > 2) {
    FILE *f = fopen(argv[2], "wb");
    AF_CHECK(f != NULL);
    if (f) {
      fprintf(f, "P6\n%d %d\n255\n", W_PX, H_PX);
      AF_CHECK(fwrite(first, 3, (size_t)W_PX * H_PX, f) == (size_t)W_PX * H_PX);
      fclose(f);
    }
  }
  AF_CHECK((size_t)W_PX * H_PX - white > (size_t)W_PX * H_PX / 50); /* > 2 % drawn */
  AF_CHECK(blue > 200 && orange > 200 && green > 200);
  AF_CHECK(same);
  if (n_renders >= 200) {               /* the first renders fill font caches */
    AF_CHECK(rss_n - rss_100 < 1024.0); /* [KiB] */
    AF_CHECK(heap_n - heap_100 < 64.0); /* [KiB] */
  }
  AF_CHECK(sum_ms / n_renders < 100.0); /* [ms], generous: a shared 2-core machine */
  af_lane_destroy(lane);
  af_strike_view_destroy(cap.view);
  free(rgb);
  free(first);
  return af_test_summary("test_strike_plot");
}
