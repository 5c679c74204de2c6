/* fuzz_response.c — libFuzzer harness: the microphone analysis
 * (src/core/measure/response.h: the 0S2 search) on arbitrary audio: any window
 * length up to the configured one (and beyond, refused), any finite samples,
 * any search band (valid or not), with or without a noise reference, at one
 * of three microphone rates. Results must be finite where the status says
 * they are; no input may crash, hang or trip a sanitizer. */
#include <stdlib.h>

#include "fuzz_input.h"
#include "response.h"

#define AF_FUZZ_RATES 3

static af_response *analysis[AF_FUZZ_RATES];

static af_response *analysis_for(unsigned k)
{
  static const double rates[AF_FUZZ_RATES] = {25600.0, 44100.0, 48000.0};
  if (analysis[k] == NULL) {
    af_response_config cfg = af_response_config_default();
    cfg.sample_rate_hz = rates[k];
    cfg.window_samples = (size_t)(0.04 * rates[k]);
    cfg.fft_size = 1;
    while (cfg.fft_size < 4 * cfg.window_samples)
      cfg.fft_size *= 2;
    if (af_response_create(&cfg, &analysis[k]) != AF_OK)
      abort();
  }
  return analysis[k];
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
  static float audio[4096];
  af_fuzz_in in = {data, size};
  uint8_t head = af_fuzz_u8(&in);
  af_response *r = analysis_for(head % AF_FUZZ_RATES);
  const af_response_config *cfg = af_response_get_config(r);
  double f_lo, f_hi;
  if (head & 0x80) { /* any band, valid or not */
    f_lo = af_fuzz_double(&in);
    f_hi = af_fuzz_double(&in);
  } else {
    f_lo = af_fuzz_range(&in, 1.0, 0.5 * cfg->sample_rate_hz);
    f_hi = af_fuzz_range(&in, f_lo, 0.5 * cfg->sample_rate_hz);
  }
  size_t n = af_fuzz_u16(&in) % (cfg->window_samples + 16);
  float scale = (float)af_fuzz_range(&in, 0.0, 1.0);
  int raw = (head & 0x40) != 0;
  for (size_t k = 0; k < n; k++)
    audio[k] = af_fuzz_sample(&in, scale, raw);
  af_response_clear_noise(r);
  if (head & 0x20) {
    static float noise[4096];
    size_t nn = af_fuzz_u16(&in) % (cfg->window_samples + 16);
    for (size_t k = 0; k < nn; k++)
      noise[k] = af_fuzz_sample(&in, scale, raw);
    (void)af_response_add_noise(r, noise, nn);
  }
  af_response_result out;
  af_status st = af_response_execute(r, audio, n, f_lo, f_hi, &out);
  if (st == AF_OK && !(isfinite(out.frequency_hz) && out.frequency_hz >= f_lo &&
                       out.frequency_hz <= f_hi && !isnan(out.q) && !isnan(out.snr_db)))
    abort();
  return 0;
}
