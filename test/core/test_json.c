/* test_json.c — the JSON pieces (json.h) against hand-written JSON: strings
 * with quotes, backslashes, control characters and UTF-8 kept as is;
 * numbers at a given number of significant digits, NaN and infinities as
 * null; flag sets as the array of their names in flag order. */
#include <math.h>
#include <string.h>

#include "af_test.h"
#include "json.h"
#include "verdict.h"

#define OUT_MAX 1024

/* What f wrote, read back from a temporary file. */
static char out_text[OUT_MAX];
static FILE *out_file;

static FILE *begin(void)
{
  out_file = tmpfile();
  return out_file;
}

static const char *end(void)
{
  out_text[0] = '\0';
  if (out_file == NULL)
    return out_text;
  long n = ftell(out_file);
  rewind(out_file);
  size_t got = n > 0 ? fread(out_text, 1, sizeof out_text - 1, out_file) : 0;
  out_text[got] = '\0';
  fclose(out_file);
  out_file = NULL;
  return out_text;
}

static int string_is(const char *in, const char *expected)
{
  FILE *f = begin();
  AF_CHECK(f != NULL);
  if (f == NULL)
    return 0;
  af_json_string(f, in);
  const char *got = end();
  if (strcmp(got, expected) != 0) {
    fprintf(stderr, "  af_json_string: got %s, expected %s\n", got, expected);
    return 0;
  }
  return 1;
}

static int double_is(double v, int digits, const char *expected)
{
  FILE *f = begin();
  if (f == NULL)
    return 0;
  af_json_double(f, v, digits);
  const char *got = end();
  if (strcmp(got, expected) != 0) {
    fprintf(stderr, "  af_json_double(%g, %d): got %s, expected %s\n", v, digits, got, expected);
    return 0;
  }
  return 1;
}

static int flags_are(uint32_t flags, const char *expected)
{
  FILE *f = begin();
  if (f == NULL)
    return 0;
  af_json_flags(f, flags);
  const char *got = end();
  if (strcmp(got, expected) != 0) {
    fprintf(stderr, "  af_json_flags(0x%x): got %s, expected %s\n", flags, got, expected);
    return 0;
  }
  return 1;
}

static void test_string(void)
{
  AF_CHECK(string_is("", "\"\""));
  AF_CHECK(string_is("jonagold", "\"jonagold\""));
  AF_CHECK(string_is("say \"hi\"", "\"say \\\"hi\\\"\""));
  AF_CHECK(string_is("C:\\data\\a.bag", "\"C:\\\\data\\\\a.bag\""));
  AF_CHECK(string_is("a\nb\tc\rd", "\"a\\u000ab\\u0009c\\u000dd\""));
  AF_CHECK(string_is("\x01\x1f", "\"\\u0001\\u001f\""));
  AF_CHECK(string_is(" ~\x7f", "\" ~\x7f\"")); /* 0x20, 0x7e, DEL: legal JSON as is */
  AF_CHECK(string_is("/", "\"/\""));           /* '/' may stay unescaped */
  /* UTF-8 (bytes >= 0x80) passes through, not as \u00XX of each byte. */
  AF_CHECK(string_is("gr\xc3\xb6\xc3\x9f"
                     "e \xce\xbc"
                     "m",
                     "\"gr\xc3\xb6\xc3\x9f"
                     "e \xce\xbc"
                     "m\""));
}

static void test_double(void)
{
  AF_CHECK(double_is(0.0, 10, "0"));
  AF_CHECK(double_is(899.796, 10, "899.796"));
  AF_CHECK(double_is(899.796, 3, "900"));
  AF_CHECK(double_is(-1.25e-7, 10, "-1.25e-07"));
  AF_CHECK(double_is(8.0e6, 17, "8000000"));
  AF_CHECK(double_is(0.1, 17, "0.10000000000000001")); /* the double nearest 0.1 */
  AF_CHECK(double_is(1.0 / 3.0, 6, "0.333333"));
  AF_CHECK(double_is(NAN, 10, "null"));
  AF_CHECK(double_is(INFINITY, 10, "null"));
  AF_CHECK(double_is(-INFINITY, 17, "null"));
}

static void test_flags(void)
{
  AF_CHECK(flags_are(0, "[]"));
  AF_CHECK(flags_are(AF_VERDICT_NO_APPLE, "[\"no_apple\"]"));
  /* Flag order, not the order they are or-ed in. */
  AF_CHECK(flags_are(AF_VERDICT_NO_RESONANCE | AF_VERDICT_FIT_FAILED,
                     "[\"fit_failed\", \"no_resonance\"]"));
  AF_CHECK(flags_are(AF_VERDICT_DAMAGE | AF_VERDICT_OUTSIDE_BAND | AF_VERDICT_NO_LOBE |
                         AF_VERDICT_DOUBLE_HIT,
                     "[\"double_hit\", \"no_lobe\", \"outside_band\", \"damage\"]"));
  /* A bit no flag uses is named "unknown" rather than dropped. */
  AF_CHECK(flags_are(1u << 31 | AF_VERDICT_CLIPPED, "[\"clipped\", \"unknown\"]"));
  /* All 19 flags, in order. */
  AF_CHECK(flags_are((1u << 19) - 1,
                     "[\"no_apple\", \"no_prediction\", \"apple_doubtful\", \"measure_failed\", "
                     "\"double_hit\", \"clipped\", \"lost_samples\", \"truncated\", "
                     "\"spectrum_failed\", \"fit_failed\", \"poisson\", \"no_audio\", "
                     "\"no_resonance\", \"range_nyquist\", \"audio_failed\", \"mode_ambiguous\", "
                     "\"no_lobe\", \"outside_band\", \"damage\"]"));
}

int main(void)
{
  test_string();
  test_double();
  test_flags();
  return af_test_summary("test_json");
}
