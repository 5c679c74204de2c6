/* fuzz_analyze.c — libFuzzer harness: `firmness_model analyze`
 * (src/tools/analyze.c: the raw float32 reader recording.c, the YAML
 * configuration, the core lane: detector, queue, apple, measurement with
 * the fit and the microphone analysis) on two arbitrary recordings: the
 * input's first byte chooses the rates and the split, the rest is the force
 * and the audio files as raw bytes (odd sizes included). The tool's set-up
 * is made once per choice of rates (af_analyze_session: the flags, the YAML
 * files, the lane, reset between inputs as analyze's own runs reset it), so
 * that an input costs what judging it costs. Every run must end with exit 0,
 * 1 or 2 (never a crash, hang or sanitizer report); the JSON goes to
 * /dev/null. */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "analyze.h"
#include "fuzz_scratch.h"

/* 4 force rates x 4 audio rates, chosen by the head's low 4 bits. */
#define AF_FUZZ_RATE_PAIRS 16

static void write_file(const char *path, const uint8_t *p, size_t n)
{
  FILE *f = fopen(path, "wb");
  if (f == NULL)
    abort();
  if (n > 0 && fwrite(p, 1, n, f) != n)
    abort();
  if (fclose(f) != 0)
    abort();
}

/* The session of one rate pair, made at its first input and kept (the
 * process's end frees it). */
static af_analyze_session *session_of(unsigned pair, const char *force, const char *audio)
{
  static const char *const rates[] = {"25600", "44100", "48000", "50000"};
  static char *argv[AF_FUZZ_RATE_PAIRS][14];
  static af_analyze_session *sessions[AF_FUZZ_RATE_PAIRS];
  if (sessions[pair] != NULL)
    return sessions[pair];
  char *const args[] = {"firmness_model", "analyze",
                        "--force",        (char *)force,
                        "--audio",        (char *)audio,
                        "--rate-force",   (char *)rates[pair & 3],
                        "--rate-audio",   (char *)rates[(pair >> 2) & 3],
                        "--mass",         "0.175",
                        "--R2",           "0.04"};
  memcpy(argv[pair], args, sizeof args);
  if (af_analyze_session_create(14, argv[pair], 2, &sessions[pair]) != 0)
    abort(); /* the flags are this harness's own: they must parse */
  return sessions[pair];
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
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
  int code = af_analyze_session_run(session_of(head & 15u, force, audio));
  if (code < 0 || code > 2)
    abort();
  return 0;
}
