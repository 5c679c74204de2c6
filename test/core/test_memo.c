/* test_memo.c — the process-wide memo of pure functions (memo.h): one call
 * of the function per kind and key, the kept bytes copied exactly, failures
 * not kept, the bounds (entries, key length) falling back to calling the
 * function, the shared references of af_memo_ref, and two threads asking at
 * once. */
#include <string.h>
#include <threads.h>

#include "af_test.h"
#include "memo.h"

static int calls; /* of square_table, by the main thread's tests */

/* out[k] = (key + k)^2 / 3 for k < 100: exact in no binary digit count, so a
 * copy that lost a bit would show. */
static af_status square_table(const void *key, void *out)
{
  double x = *(const double *)key, *t = out;
  calls++;
  for (int k = 0; k < 100; k++)
    t[k] = (x + k) * (x + k) / 3.0;
  return AF_OK;
}

static af_status refuse(const void *key, void *out)
{
  (void)key;
  (void)out;
  calls++;
  return AF_ENODATA;
}

static const char kind_square[] = "test square", kind_other[] = "test other";

static void test_once_per_key(void)
{
  double a[100], b[100], expect[100], x = 1.25, y = 2.5;
  for (int k = 0; k < 100; k++)
    expect[k] = (x + k) * (x + k) / 3.0;
  calls = 0;
  AF_CHECK_STATUS(af_memo_get(kind_square, &x, sizeof x, square_table, a, sizeof a), AF_OK);
  memset(b, 0, sizeof b);
  AF_CHECK_STATUS(af_memo_get(kind_square, &x, sizeof x, square_table, b, sizeof b), AF_OK);
  AF_CHECK(calls == 1);
  AF_CHECK(memcmp(a, expect, sizeof a) == 0 && memcmp(b, expect, sizeof b) == 0);
  /* another key, another kind, another size: computed each */
  AF_CHECK_STATUS(af_memo_get(kind_square, &y, sizeof y, square_table, b, sizeof b), AF_OK);
  AF_CHECK_ABS(b[0], y * y / 3.0, 0.0);
  AF_CHECK_STATUS(af_memo_get(kind_other, &x, sizeof x, square_table, b, sizeof b), AF_OK);
  AF_CHECK_STATUS(af_memo_get(kind_square, &x, sizeof x, square_table, b, 50 * sizeof *b), AF_OK);
  AF_CHECK(calls == 4);
}

static void test_failure_not_kept(void)
{
  double x = 7.0, out[100];
  calls = 0;
  AF_CHECK_STATUS(af_memo_get(kind_other, &x, sizeof x, refuse, out, sizeof out), AF_ENODATA);
  AF_CHECK_STATUS(af_memo_get(kind_other, &x, sizeof x, refuse, out, sizeof out), AF_ENODATA);
  AF_CHECK(calls == 2);
  /* now it succeeds: kept from then on */
  AF_CHECK_STATUS(af_memo_get(kind_other, &x, sizeof x, square_table, out, sizeof out), AF_OK);
  AF_CHECK_STATUS(af_memo_get(kind_other, &x, sizeof x, refuse, out, sizeof out), AF_OK);
  AF_CHECK(calls == 3);
  AF_CHECK_ABS(out[1], 64.0 / 3.0, 0.0);
}

/* Past AF_MEMO_ENTRIES values, and for a key longer than kept: the function
 * runs every time and its answer still comes back. */
static void test_bounds(void)
{
  double out[100];
  for (int k = 0; k < AF_MEMO_ENTRIES + 4; k++) {
    double x = 1000.0 + k;
    AF_CHECK_STATUS(af_memo_get(kind_square, &x, sizeof x, square_table, out, sizeof out), AF_OK);
  }
  double x = 1000.0 + AF_MEMO_ENTRIES + 3;
  calls = 0;
  AF_CHECK_STATUS(af_memo_get(kind_square, &x, sizeof x, square_table, out, sizeof out), AF_OK);
  AF_CHECK(calls == 1);
  AF_CHECK_ABS(out[2], (x + 2) * (x + 2) / 3.0, 0.0);
  double long_key[16] = {3.0};
  calls = 0;
  for (int k = 0; k < 2; k++)
    AF_CHECK_STATUS(
        af_memo_get(kind_square, long_key, sizeof long_key, square_table, out, sizeof out), AF_OK);
  AF_CHECK(calls == 2);
  AF_CHECK_ABS(out[0], 3.0, 0.0);
  /* the store full: a reference cannot be kept */
  double fresh = -1.0;
  AF_CHECK(af_memo_ref(kind_square, &fresh, sizeof fresh, square_table, sizeof out) == NULL);
}

/* af_memo_ref: one call per key and the same shared bytes for every caller;
 * a failure is not kept (NULL, then the function again); a value larger than
 * the whole store, or asked past AF_MEMO_ENTRIES, gives NULL (the caller
 * computes its own). Runs before test_bounds fills the store. */
static void test_ref(void)
{
  static const char kind_ref[] = "test ref", kind_ref_fail[] = "test ref refused";
  double x = 4.5, expect[100];
  for (int k = 0; k < 100; k++)
    expect[k] = (x + k) * (x + k) / 3.0;
  calls = 0;
  const double *a = af_memo_ref(kind_ref, &x, sizeof x, square_table, sizeof expect);
  const double *b = af_memo_ref(kind_ref, &x, sizeof x, square_table, sizeof expect);
  AF_CHECK(a != NULL && a == b && calls == 1);
  AF_CHECK(a != NULL && memcmp(a, expect, sizeof expect) == 0);
  double y = 5.5;
  const double *c = af_memo_ref(kind_ref, &y, sizeof y, square_table, sizeof expect);
  AF_CHECK(c != NULL && c != a && calls == 2 && c[0] == y * y / 3.0);
  AF_CHECK(af_memo_ref(kind_ref_fail, &x, sizeof x, refuse, sizeof expect) == NULL);
  AF_CHECK(af_memo_ref(kind_ref_fail, &x, sizeof x, refuse, sizeof expect) == NULL);
  AF_CHECK(calls == 4);
  AF_CHECK(af_memo_ref(kind_ref, &x, sizeof x, square_table, AF_MEMO_BYTES + 1) == NULL);
  double long_key[16] = {4.5}; /* longer than a kept key */
  AF_CHECK(af_memo_ref(kind_ref, long_key, sizeof long_key, square_table, sizeof expect) == NULL);
}

/* Two threads ask the same key (a value already kept: the table is full by
 * now, so the early keys) and must read the same exact bytes. */
static int reader(void *arg)
{
  double x = 1.25, out[100];
  int bad = 0;
  for (int k = 0; k < 2000; k++) {
    memset(out, 0, sizeof out);
    if (af_memo_get(kind_square, &x, sizeof x, square_table, out, sizeof out) != AF_OK ||
        out[99] != (x + 99) * (x + 99) / 3.0)
      bad++;
  }
  *(int *)arg = bad;
  return 0;
}

static void test_threads(void)
{
  thrd_t t[2];
  int bad[2] = {-1, -1};
  for (int i = 0; i < 2; i++)
    AF_CHECK(thrd_create(&t[i], reader, &bad[i]) == thrd_success);
  for (int i = 0; i < 2; i++)
    AF_CHECK(thrd_join(t[i], NULL) == thrd_success);
  AF_CHECK(bad[0] == 0 && bad[1] == 0);
}

int main(void)
{
  test_once_per_key();
  test_failure_not_kept();
  test_ref();
  test_bounds();
  test_threads();
  return af_test_summary("test_memo");
}
