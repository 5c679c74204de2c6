/* test_text.c — af_text (text.h): formats like snprintf, cuts at len - 1
 * characters and always ends with a NUL, never writes past len, and writes
 * nothing at all for len 0. */
#include <string.h>

#include "af_test.h"
#include "text.h"

#define GUARD '#'

/* buf[0..cap) filled with GUARD, so that a write past len shows. */
static void guard(char *buf, size_t cap)
{
  memset(buf, GUARD, cap);
}

static int untouched_from(const char *buf, size_t from, size_t cap)
{
  for (size_t k = from; k < cap; k++)
    if (buf[k] != GUARD)
      return 0;
  return 1;
}

static void test_fits(void)
{
  char buf[64];
  guard(buf, sizeof buf);
  af_text(buf, sizeof buf, "mass = %g kg, %d strikes, '%s'", 0.185, 12, "jonagold");
  AF_CHECK(strcmp(buf, "mass = 0.185 kg, 12 strikes, 'jonagold'") == 0);
  af_text(buf, sizeof buf, "%.3f MPa", 8.0e6 * 1e-6);
  AF_CHECK(strcmp(buf, "8.000 MPa") == 0);
  af_text(buf, sizeof buf, "%s", "");
  AF_CHECK(buf[0] == '\0');
  /* exactly len - 1 characters: no cut */
  char small[6];
  guard(small, sizeof small);
  af_text(small, sizeof small, "%s", "abcde");
  AF_CHECK(strcmp(small, "abcde") == 0);
}

static void test_cut(void)
{
  char buf[16];
  guard(buf, sizeof buf);
  /* Into 8 of the 16 bytes: 7 characters and the NUL, bytes 8.. untouched. */
  af_text(buf, 8, "no apple estimate within %g s", 0.5);
  AF_CHECK(strcmp(buf, "no appl") == 0);
  AF_CHECK(untouched_from(buf, 8, sizeof buf));
  guard(buf, sizeof buf);
  af_text(buf, 1, "%s", "anything");
  AF_CHECK(buf[0] == '\0' && untouched_from(buf, 1, sizeof buf));
  guard(buf, sizeof buf);
  af_text(buf, 0, "%s", "anything"); /* len 0: nothing written, not even the NUL */
  AF_CHECK(untouched_from(buf, 0, sizeof buf));
  af_text(NULL, 16, "%s", "anything"); /* no buffer (an optional error text): no write, no crash */
  AF_CHECK(untouched_from(buf, 0, sizeof buf));
  /* A long reason into a message-sized field: cut at 255 characters. */
  char big[300], field[256];
  memset(big, 'x', sizeof big - 1);
  big[sizeof big - 1] = '\0';
  af_text(field, sizeof field, "%s", big);
  AF_CHECK(strlen(field) == sizeof field - 1);
}

int main(void)
{
  test_fits();
  test_cut();
  return af_test_summary("test_text");
}
