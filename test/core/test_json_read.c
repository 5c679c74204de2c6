/* test_json_read.c — the strict JSON reader (json_read.h) against RFC 8259:
 * the grammar's examples and edge cases written out by hand, the values read
 * back exactly (numbers as strtod reads their text, escapes as the RFC maps
 * them to UTF-8), and every kind of text that is not JSON refused with the
 * byte offset of the fault. */
#include <float.h>
#include <math.h>
#include <string.h>

#include "af_test.h"
#include "json_read.h"

static af_json_doc doc;
static char err[128];

static af_status parse(const char *text)
{
  af_json_free(&doc);
  return af_json_parse(text, strlen(text), &doc, err, sizeof err);
}

/* The RFC's object example, trimmed: members, nesting, every value kind. */
static void test_values(void)
{
  AF_CHECK(parse("{\"Image\": {\"Width\": 800, \"Title\": \"View from 15th Floor\", "
                 "\"Animated\": false, \"Thumb\": null, \"IDs\": [116, 943, 234, 38793], "
                 "\"Ratio\": -0.5e-3, \"Big\": 1E+2, \"On\": true}}") == AF_OK);
  size_t image = af_json_member(&doc, 0, "Image");
  AF_CHECK(image != 0 && doc.nodes[image].type == AF_JSON_OBJECT && doc.nodes[image].count == 8);
  double v = 0;
  AF_CHECK(af_json_number(&doc, af_json_member(&doc, image, "Width"), false, &v) && v == 800.0);
  AF_CHECK(af_json_number(&doc, af_json_member(&doc, image, "Ratio"), false, &v) && v == -0.5e-3);
  AF_CHECK(af_json_number(&doc, af_json_member(&doc, image, "Big"), false, &v) && v == 100.0);
  AF_CHECK(doc.nodes[af_json_member(&doc, image, "Animated")].type == AF_JSON_FALSE);
  AF_CHECK(doc.nodes[af_json_member(&doc, image, "On")].type == AF_JSON_TRUE);
  size_t thumb = af_json_member(&doc, image, "Thumb");
  AF_CHECK(!af_json_number(&doc, thumb, false, &v));
  AF_CHECK(af_json_number(&doc, thumb, true, &v) && isnan(v));
  char title[32];
  AF_CHECK(af_json_string_of(&doc, af_json_member(&doc, image, "Title"), title, sizeof title) &&
           strcmp(title, "View from 15th Floor") == 0);
  AF_CHECK(!af_json_string_of(&doc, af_json_member(&doc, image, "Title"), title, 20)); /* 21 */
  size_t ids = af_json_member(&doc, image, "IDs");
  AF_CHECK(doc.nodes[ids].type == AF_JSON_ARRAY && doc.nodes[ids].count == 4);
  uint64_t u = 0, sum = 0;
  for (size_t k = doc.nodes[ids].child; k != 0; k = doc.nodes[k].next)
    sum += af_json_u64(&doc, k, &u) ? u : 0;
  AF_CHECK(sum == 116 + 943 + 234 + 38793);
  AF_CHECK(af_json_member(&doc, image, "width") == 0); /* names are case-sensitive */
  AF_CHECK(af_json_member(&doc, 0, "Width") == 0);     /* not a member of the top */
}

/* Numbers read exactly as strtod reads their text: the 17-digit round trip. */
static void test_numbers(void)
{
  double v = 0;
  uint64_t u = 0;
  AF_CHECK(parse("[0.1, 2.2250738585072014e-308, 1.7976931348623157e308, -0, "
                 "18446744073709551615, 18446744073709551616, 1.5, 1e3]") == AF_OK);
  size_t k = doc.nodes[0].child;
  AF_CHECK(af_json_number(&doc, k, false, &v) && v == 0.1);
  k = doc.nodes[k].next;
  AF_CHECK(af_json_number(&doc, k, false, &v) && v == DBL_MIN);
  k = doc.nodes[k].next;
  AF_CHECK(af_json_number(&doc, k, false, &v) && v == DBL_MAX);
  k = doc.nodes[k].next;
  AF_CHECK(af_json_number(&doc, k, false, &v) && v == 0.0 && signbit(v));
  AF_CHECK(!af_json_u64(&doc, k, &u)); /* "-0" is not a count */
  k = doc.nodes[k].next;
  AF_CHECK(af_json_u64(&doc, k, &u) && u == UINT64_MAX);
  k = doc.nodes[k].next;
  AF_CHECK(!af_json_u64(&doc, k, &u)); /* 2^64 overflows */
  k = doc.nodes[k].next;
  AF_CHECK(!af_json_u64(&doc, k, &u)); /* a fraction */
  k = doc.nodes[k].next;
  AF_CHECK(!af_json_u64(&doc, k, &u)); /* exponent form: not a count as written */
  AF_CHECK(parse("1e999") == AF_OK && !af_json_number(&doc, 0, false, &v)); /* overflows */
}

/* Escapes (RFC 8259 section 7): the two-character ones, \u, a surrogate pair. */
static void test_strings(void)
{
  char s[64];
  AF_CHECK(parse("\"a\\\"b\\\\c\\/d\\b\\f\\n\\r\\t\\u00e9\\u20AC\\ud834\\udd1e\"") == AF_OK);
  AF_CHECK(af_json_string_of(&doc, 0, s, sizeof s) &&
           strcmp(s, "a\"b\\c/d\b\f\n\r\t\xc3\xa9\xe2\x82\xac\xf0\x9d\x84\x9e") == 0);
  AF_CHECK(parse("\"caf\xc3\xa9\"") == AF_OK && af_json_string_of(&doc, 0, s, sizeof s) &&
           strcmp(s, "caf\xc3\xa9") == 0); /* raw UTF-8 kept byte for byte */
  AF_CHECK(parse("\"\"") == AF_OK && af_json_string_of(&doc, 0, s, sizeof s) && s[0] == '\0');
  AF_CHECK(parse("  [ ]\n") == AF_OK && doc.nodes[0].count == 0 && doc.nodes[0].child == 0);
  AF_CHECK(parse("{}") == AF_OK && doc.nodes[0].type == AF_JSON_OBJECT);
}

/* Refusals, each with the offset of its fault. */
static void expect_refused(const char *text, const char *offset)
{
  af_status st = parse(text);
  AF_CHECK(st == AF_EINVAL);
  if (st == AF_EINVAL && strstr(err, offset) == NULL)
    fprintf(stderr, "'%s': message '%s' lacks '%s'\n", text, err, offset);
  AF_CHECK(strstr(err, offset) != NULL);
}

static void test_refused(void)
{
  expect_refused("", "offset 0:");
  expect_refused("[1, 2,]", "offset 6:");     /* trailing comma */
  expect_refused("{\"a\": 1,}", "offset 8:"); /* trailing comma in an object */
  expect_refused("[1] x", "offset 4:");       /* text after the value */
  expect_refused("{'a': 1}", "offset 1:");    /* single quotes */
  expect_refused("[NaN]", "offset 1:");       /* no NaN in JSON */
  expect_refused("[01]", "offset 2:");        /* a leading zero ends the number */
  expect_refused("[1.]", "offset 3:");        /* a digit after the point */
  expect_refused("[.5]", "offset 1:");
  expect_refused("[1e]", "offset 3:");
  expect_refused("[+1]", "offset 1:");
  expect_refused("\"a\tb\"", "offset 2:");     /* a raw control character */
  expect_refused("\"\\x41\"", "offset 2:");    /* no \x escape */
  expect_refused("\"\\udd1e\"", "offset 7:");  /* a lone low surrogate */
  expect_refused("\"\\ud834x\"", "offset 7:"); /* a high one without its pair */
  expect_refused("\"open", "offset 0:");
  expect_refused("{\"a\" 1}", "offset 5:");
  expect_refused("{1: 2}", "offset 1:");
  expect_refused("[1 2]", "offset 3:");
  expect_refused("/* c */ 1", "offset 0:");
  expect_refused("tru", "offset 0:");
  /* Nesting: 64 levels are read, 65 refused (no stack exhaustion at any depth). */
  char deep[200001];
  memset(deep, '[', 64);
  memset(deep + 64, ']', 64);
  deep[128] = '\0';
  AF_CHECK(parse(deep) == AF_OK);
  memset(deep, '[', 65);
  memset(deep + 65, ']', 65);
  deep[130] = '\0';
  expect_refused(deep, "nested deeper than 64");
  memset(deep, '[', 200000);
  deep[200000] = '\0';
  expect_refused(deep, "nested deeper than 64");
}

int main(void)
{
  test_values();
  test_numbers();
  test_strings();
  test_refused();
  af_json_free(&doc);
  af_json_free(&doc); /* safe twice */
  printf("test_json_read: %d passed, %d failed\n", af_test_passed, af_test_failed);
  return af_test_failed ? 1 : 0;
}
