/* bench_response.c — af_bench_response: the peak list (af_response_execute_peaks)
 * on windows made elsewhere (scripts/bench_response.py writes them with
 * Python's own synthesis, or any raw float32 file), its readings and its CPU
 * cost per window.
 *
 *   af_bench_response WINDOWS.f32 BANDS.csv [--repeat N]
 *
 * WINDOWS.f32: windows of 4096 float32 samples at 48 kHz, back to back;
 * BANDS.csv: one line per window, "f_lo_hz,f_hi_hz" (the 0S2 range; the list
 * band is af_modes_list_band's around it, as the measurement takes it).
 * --repeat: analyses per window for the timing, a whole number in [1, 1000],
 * default 5. Prints one line per window, "index,status,n,f1,q1,snr1,..."
 * (Hz, -, dB), then "# cpu_us median,p90,max,mean" of one analysis and
 * "# fits converged,capped,stalled,failed,iterations,max_iterations".
 * Exit 0; 2 for a usage error or an unreadable file. */
#define _POSIX_C_SOURCE 200809L /* clock_gettime */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "closeout.h"
#include "modes.h"
#include "response.h"

#define WINDOW_SAMPLES 4096
#define MAX_WINDOWS 100000

static double cpu_us(void)
{
  struct timespec t;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return 1e6 * (double)t.tv_sec + 1e-3 * (double)t.tv_nsec;
}

static int cmp_double(const void *a, const void *b)
{
  double x = *(const double *)a, y = *(const double *)b;
  return (x > y) - (x < y);
}

static int usage(const char *msg)
{
  fprintf(stderr,
          "af_bench_response: %s\nusage: af_bench_response WINDOWS.f32 BANDS.csv "
          "[--repeat N]  (N a whole number in [1, 1000], default 5)\n",
          msg);
  return 2;
}

int main(int argc, char **argv)
{
  af_closeout_install("af_bench_response");
  long repeat = 5;
  if (argc != 3 && argc != 5)
    return usage("two files and optionally --repeat N");
  if (argc == 5) {
    char *end = NULL;
    errno = 0;
    repeat = strtol(argv[4], &end, 10);
    if (strcmp(argv[3], "--repeat") != 0 || errno != 0 || *end != '\0' || repeat < 1 ||
        repeat > 1000)
      return usage("--repeat: a whole number in [1, 1000]");
  }
  FILE *fw = fopen(argv[1], "rb"), *fb = fopen(argv[2], "r");
  if (fw == NULL || fb == NULL)
    return usage("cannot open the windows or the bands file");
  static float x[WINDOW_SAMPLES];
  static double times[MAX_WINDOWS];
  af_response_config c = af_response_config_default();
  af_response *r = NULL;
  if (af_response_create(&c, &r) != AF_OK)
    return usage("cannot create the response");
  size_t w = 0;
  double f_lo, f_hi;
  while (w < MAX_WINDOWS && fread(x, sizeof x[0], WINDOW_SAMPLES, fw) == WINDOW_SAMPLES &&
         fscanf(fb, "%lf,%lf", &f_lo, &f_hi) == 2) {
    double lo, hi, best = 1e300;
    af_response_result peaks[AF_RESPONSE_MAX_PEAKS];
    size_t n = 0;
    af_status st = af_modes_list_band(f_lo, f_hi, c.sample_rate_hz, &lo, &hi);
    for (long k = 0; st == AF_OK && k < repeat; ++k) {
      double t0 = cpu_us();
      st =
          af_response_execute_peaks(r, x, WINDOW_SAMPLES, lo, hi, peaks, AF_RESPONSE_MAX_PEAKS, &n);
      double t = cpu_us() - t0;
      best = t < best ? t : best;
      if (st != AF_OK && st != AF_ENODATA)
        break;
      st = AF_OK;
    }
    st = af_response_execute_peaks(r, x, WINDOW_SAMPLES, lo, hi, peaks, AF_RESPONSE_MAX_PEAKS, &n);
    printf("%zu,%d,%zu", w, (int)st, st == AF_OK ? n : 0);
    for (size_t i = 0; st == AF_OK && i < n; ++i)
      printf(",%.6f,%.5f,%.3f", peaks[i].frequency_hz, peaks[i].q, peaks[i].snr_db);
    printf("\n");
    times[w++] = best;
  }
  if (w == 0)
    return usage("no window read");
  double mean = 0.0;
  for (size_t i = 0; i < w; ++i)
    mean += times[i] / (double)w;
  qsort(times, w, sizeof times[0], cmp_double);
  printf("# cpu_us median,p90,max,mean %.1f,%.1f,%.1f,%.1f\n", times[w / 2], times[w * 9 / 10],
         times[w - 1], mean);
#ifdef AF_BENCH_FIT_STATS
  af_response_fit_stats s;
  af_response_get_fit_stats(r, &s);
  printf(
      "# fits converged,capped,stalled,failed,iterations,max_iterations %zu,%zu,%zu,%zu,%zu,%zu\n",
      s.fits[AF_RESPONSE_FIT_CONVERGED], s.fits[AF_RESPONSE_FIT_CAPPED],
      s.fits[AF_RESPONSE_FIT_STALLED], s.fits[AF_RESPONSE_FIT_FAILED], s.iterations,
      s.max_iterations);
#endif
  af_response_destroy(r);
  fclose(fw);
  fclose(fb);
  return 0;
}
