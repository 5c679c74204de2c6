/* test_absent.c — the stream-absent warning (absent.h) on injected times:
 * the boundary at exactly stream_absent_warn_s after the start (hand-computed
 * nanoseconds, on a ROS-like clock of 1.7e9 s since 1970), a stream that
 * delivered, a refused chunk named, the check off (0 s) and a clock that has
 * not started (0: simulated time before its first /clock). */
#include <stdint.h>
#include <string.h>

#include "absent.h"
#include "af_test.h"
#include "stream.h"

#define T0_NS INT64_C(1795550000000000000) /* the start: 1795550000 s since 1970 */

static af_stream_config stream_cfg(const char *unit)
{
  af_stream_config c;
  memset(&c, 0, sizeof c);
  c.sample_rate_hz = 50000.0;
  c.buffer_s = 0.1;
  c.capacity_samples = 5000;
  strcpy(c.units[0], unit);
  c.to_si = 1.0;
  return c;
}

static af_chunk chunk(const char *unit, const float *x, size_t n)
{
  af_chunk c = {T0_NS, 0, 50000.0, unit, "f", x, n};
  return c;
}

int main(void)
{
  af_stream_config fc = stream_cfg("N"), ac = stream_cfg("Pa");
  af_stream force, audio;
  char text[512];
  const float x[4] = {0.0f, 1.0f, 2.0f, 3.0f};
  AF_CHECK(af_stream_create(&force, "force", &fc) == AF_OK);
  AF_CHECK(af_stream_create(&audio, "audio", &ac) == AF_OK);

  /* 5 s = 5 000 000 000 ns: 1 ns before, nothing; at the boundary, both. */
  AF_CHECK(!af_absent_warning(&force, &audio, T0_NS, T0_NS + INT64_C(4999999999), 5.0, text,
                              sizeof text));
  AF_CHECK(strcmp(text, "") == 0);
  AF_CHECK(af_absent_warning(&force, &audio, T0_NS, T0_NS + INT64_C(5000000000), 5.0, text,
                             sizeof text));
  AF_CHECK(strcmp(text, "no force and no audio chunk within 5.0 s of start") == 0);
  /* 0.1 s, the table's smallest: 100 000 000 ns. */
  AF_CHECK(!af_absent(&force, T0_NS, T0_NS + INT64_C(99999999), 0.1));
  AF_CHECK(af_absent(&force, T0_NS, T0_NS + INT64_C(100000000), 0.1));
  /* Off, and a clock not started yet. */
  AF_CHECK(!af_absent_warning(&force, &audio, T0_NS, T0_NS + INT64_C(3600000000000), 0.0, text,
                              sizeof text));
  AF_CHECK(!af_absent_warning(&force, &audio, 0, T0_NS, 5.0, text, sizeof text));

  /* A force chunk in volts on a newton stream is refused: still absent, and said why. */
  af_chunk bad = chunk("V", x, 4);
  AF_CHECK(af_stream_push(&force, &bad, T0_NS + INT64_C(1000000000), NULL) == AF_CHUNK_BAD_UNIT);
  AF_CHECK(af_absent_warning(&force, &audio, T0_NS, T0_NS + INT64_C(6000000000), 5.0, text,
                             sizeof text));
  AF_CHECK(strcmp(text, "no force and no audio chunk within 5.0 s of start (1 refused: force "
                        "chunk at sample 0: unit 'V', expected 'N')") == 0);

  /* The force delivers: only the audio is missing. */
  af_chunk good = chunk("N", x, 4);
  AF_CHECK(af_stream_push(&force, &good, T0_NS + INT64_C(2000000000), NULL) == AF_CHUNK_OK);
  AF_CHECK(af_absent_warning(&force, &audio, T0_NS, T0_NS + INT64_C(7500000000), 7.5, text,
                             sizeof text));
  AF_CHECK(strcmp(text, "no audio chunk within 7.5 s of start") == 0);
  /* Both deliver: no warning, however long after the start. */
  af_chunk sound = chunk("Pa", x, 4);
  AF_CHECK(af_stream_push(&audio, &sound, T0_NS + INT64_C(2000000000), NULL) == AF_CHUNK_OK);
  AF_CHECK(!af_absent_warning(&force, &audio, T0_NS, T0_NS + INT64_C(86400000000000), 5.0, text,
                              sizeof text));
  AF_CHECK(strcmp(text, "") == 0);

  af_stream_destroy(&force);
  af_stream_destroy(&audio);
  return af_test_summary("test_absent");
}
