/* fuzz_analyze.c — libFuzzer harness: `firmness_model analyze` end to end
 * (src/tools/analyze.c: the raw float32 reader recording.c, the YAML
 * configuration, the core lane: detector, queue, apple, measurement with
 * the fit and the microphone analysis) on two arbitrary recordings: the
 * input's first byte chooses the rates and the split, the rest is the force
 * and the audio files as raw bytes (odd sizes included). Every run must end
 * with exit 0, 1 or 2 (never a crash, hang or sanitizer report); the JSON
 * goes to /dev/null. */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "analyze.h"
#include "fuzz_scratch.h"

static void write_file(const char *path, const uint8_t *p, size_t n)
{
  FILE *f = fopen(path, "wb");
  if (f == NULL)
    abort();
  fwrite(p, 1, n, f);
  fclose(f);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
  static const char *const rates[] = {"25600", "44100", "48000", "50000"};
  static int quiet;
  const char *force = af_fuzz_scratch(0, "force", "f32");
  const char *audio = af_fuzz_scratch(1, "audio", "f32");
  if (!quiet) {
    if (freopen("/dev/null", "w", stdout) == NULL)
      abort();
    quiet = 1;
  }
  if (size < 1)
    return 0;
  uint8_t head = data[0];
  data++;
  size--;
  /* the split: force first, audio after, at a fraction set by the head */
  size_t n_force = size * (size_t)((head >> 4) + 1) / 17;
  write_file(force, data, n_force);
  write_file(audio, data + n_force, size - n_force);
  char *argv[] = {"firmness_model",
                  "analyze",
                  "--force",
                  (char *)force,
                  "--audio",
                  (char *)audio,
                  "--rate-force",
                  (char *)rates[head & 3],
                  "--rate-audio",
                  (char *)rates[(head >> 2) & 3],
                  "--mass",
                  "0.175",
                  "--R2",
                  "0.04",
                  NULL};
  int code = af_analyze_main(14, argv, 2);
  if (code < 0 || code > 2)
    abort();
  return 0;
}
