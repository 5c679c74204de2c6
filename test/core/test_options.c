/* test_options.c — the one parser of the tools' flags (options.h): every
 * kind stored, each range at and past its bounds, the number reader's
 * refusals, a flag given twice, without its value or unknown, the values
 * handed back in order, and a help line with its range. The expected
 * messages and bounds are the ranges written in the table below (the spec),
 * not output copied from a run. */
#define _POSIX_C_SOURCE 200809L /* dup, fileno */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include "af_test.h"
#include "options.h"
#include "settings.h"

typedef struct {
  bool on;
  const char *path;
  double x, pair[2], open, zero_or;
  long n;
  uint64_t seed;
  unsigned lobe;
} t_args;

#define A(f) offsetof(t_args, f)
static const af_option table[] = {
    {"--on", NULL, AF_OPTION_SWITCH, A(on), -1, NULL, "a switch", NULL, false},
    {"--path", "FILE", AF_OPTION_TEXT, A(path), -1, NULL, "a file", "none", false},
    {"--x", "X", AF_OPTION_NUMBER, A(x), -1, "[-1.5, 2.5] m", "a closed range", NULL, false},
    {"--pair", "A:B", AF_OPTION_RANGE, A(pair), -1, "[0, 10] kg", "a pair", NULL, false},
    {"--open", "S", AF_OPTION_NUMBER, A(open), -1, "(0, 600) s", "an open range", NULL, false},
    {"--zero-or", "PA", AF_OPTION_NUMBER, A(zero_or), -1, "0 or [1e5, 1e12] Pa", "zero or", "rigid",
     false},
    {"--n", "N", AF_OPTION_LONG, A(n), -1, "[1, 256] workers", "a whole number", NULL, false},
    {"--seed", "S", AF_OPTION_U64, A(seed), -1, "[0, 18446744073709551615]", "a seed", NULL, false},
    {"--lobe", "N", AF_OPTION_UINT, A(lobe), AF_SETTING_LOBE, NULL, "the row's range", NULL, false},
    {"--row", "PA", AF_OPTION_SETTING, 0, AF_SETTING_MODULUS_MIN_PA, NULL, NULL, NULL, false},
    {"--set", "NAME=VALUE", AF_OPTION_NONE, 0, -1, NULL, "repeatable", "none", true},
};
#define N (sizeof table / sizeof table[0])

/* What was handed back, in order. */
typedef struct {
  const char *flag[8], *value[8];
  int n;
} t_hand;

static bool hand(void *user, const af_option *o, const char *value)
{
  t_hand *h = user;
  h->flag[h->n] = o ? o->name : "(positional)";
  h->value[h->n++] = value;
  return true;
}

static char err[1024]; /* stderr of the last parse */

/* Parses the arguments (NULL-terminated list after "tool") into a, stderr into err. */
static bool parse_into(t_args *a, t_hand *h, const char *const *args)
{
  char *argv[32];
  int argc = 0;
  argv[argc++] = (char *)"tool";
  while (*args != NULL)
    argv[argc++] = (char *)*args++;
  memset(a, 0, sizeof *a);
  memset(h, 0, sizeof *h);
  const af_options_parser p = {"t", {{table, N, a, hand, h}}, 1, NULL, true};
  FILE *tmp = tmpfile();
  fflush(stderr);
  int saved = dup(fileno(stderr));
  dup2(fileno(tmp), fileno(stderr));
  bool ok = af_options_parse(&p, argc, argv, 1);
  fflush(stderr);
  dup2(saved, fileno(stderr));
  close(saved);
  rewind(tmp);
  size_t n = fread(err, 1, sizeof err - 1, tmp);
  err[n] = '\0';
  fclose(tmp);
  return ok;
}

#define PARSE(...) parse_into(&a, &h, (const char *const[]){__VA_ARGS__, NULL})
#define SAID(text) (strstr(err, text) != NULL)

static void test_reader(void)
{
  double v;
  AF_CHECK(af_options_read_number("12.5", &v) && v == 12.5);
  AF_CHECK(af_options_read_number("-1e3", &v) && v == -1000.0);
  const char *bad[] = {"",      "nan", "NaN", "inf", "-inf",  "1e999",
                       "12abc", " ",   "12 ", "0x",  "1e-999"};
  for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++)
    AF_CHECK(!af_options_read_number(bad[k], &v));
}

static void test_kinds(void)
{
  t_args a;
  t_hand h;
  AF_CHECK(PARSE("--on", "--path", "p.txt", "--x", "2", "--pair", "1:2.5", "--n", "7", "--seed",
                 "18446744073709551615", "--lobe", "3", "--zero-or", "0", "--open", "599"));
  AF_CHECK(a.on && a.path && strcmp(a.path, "p.txt") == 0 && a.x == 2.0);
  AF_CHECK(a.pair[0] == 1.0 && a.pair[1] == 2.5 && a.n == 7 && a.lobe == 3u);
  AF_CHECK(a.seed == UINT64_MAX); /* every digit, past a double's 2^53 */
  AF_CHECK(a.zero_or == 0.0 && a.open == 599.0 && h.n == 0 && err[0] == '\0');
  /* SETTING and NONE (repeatable) handed back in order, positional too. */
  AF_CHECK(PARSE("--set", "a=1", "bag", "--row", "2e6", "--set", "b=2"));
  AF_CHECK(h.n == 4 && strcmp(h.flag[0], "--set") == 0 && strcmp(h.value[0], "a=1") == 0);
  AF_CHECK(strcmp(h.flag[1], "(positional)") == 0 && strcmp(h.value[1], "bag") == 0);
  AF_CHECK(strcmp(h.flag[2], "--row") == 0 && strcmp(h.value[3], "b=2") == 0);
}

static void test_bounds(void)
{
  t_args a;
  t_hand h;
  /* [-1.5, 2.5] m: both ends accepted, past them refused. */
  AF_CHECK(PARSE("--x", "-1.5") && a.x == -1.5);
  AF_CHECK(PARSE("--x", "2.5") && a.x == 2.5);
  AF_CHECK(!PARSE("--x", "2.5000001"));
  AF_CHECK(SAID("t: --x 2.5000001 is outside the accepted range [-1.5, 2.5] m\n"));
  AF_CHECK(!PARSE("--x", "-1.6") &&
           SAID("t: --x -1.6 is outside the accepted range [-1.5, 2.5] m"));
  /* (0, 600) s: neither end accepted. */
  AF_CHECK(!PARSE("--open", "0") && SAID("t: --open 0 is outside the accepted range (0, 600) s"));
  AF_CHECK(!PARSE("--open", "600") && SAID("--open 600 is outside the accepted range (0, 600) s"));
  AF_CHECK(PARSE("--open", "1e-300") && a.open == 1e-300);
  /* 0 or [1e5, 1e12] Pa */
  AF_CHECK(PARSE("--zero-or", "1e5") && PARSE("--zero-or", "1e12"));
  AF_CHECK(!PARSE("--zero-or", "5e4") && SAID("--zero-or 50000 is outside the accepted range 0 or "
                                              "[1e5, 1e12] Pa"));
  AF_CHECK(!PARSE("--zero-or", "1000000000001"));
  /* [1, 256] workers, whole */
  AF_CHECK(PARSE("--n", "1") && a.n == 1 && PARSE("--n", "256") && a.n == 256);
  AF_CHECK(!PARSE("--n", "0") && SAID("t: --n 0 is outside the accepted range [1, 256] workers"));
  AF_CHECK(!PARSE("--n", "257") && SAID("--n 257 is outside the accepted range [1, 256] workers"));
  AF_CHECK(!PARSE("--n", "2.5") && SAID("t: --n '2.5' is not a whole number (accepted range [1, "
                                        "256] workers)"));
  /* --lobe: the parameter table row's range, [1, 8] */
  AF_CHECK(PARSE("--lobe", "8") && a.lobe == 8u);
  AF_CHECK(!PARSE("--lobe", "9") && SAID("--lobe 9 is outside the accepted range [1, 8]"));
  AF_CHECK(!PARSE("--seed", "-1") && SAID("--seed -1 is outside the accepted range [0, "));
  /* A pair: each end in [0, 10] kg, A <= B. */
  AF_CHECK(PARSE("--pair", "0:10") && a.pair[0] == 0.0 && a.pair[1] == 10.0);
  AF_CHECK(!PARSE("--pair", "0:11") &&
           SAID("t: --pair 11 is outside the accepted range [0, 10] kg"));
  AF_CHECK(!PARSE("--pair", "3:2") && SAID("--pair 3:2 is reversed: A:B needs A <= B (each in [0, "
                                           "10] kg)"));
  AF_CHECK(!PARSE("--pair", "3") && SAID("--pair '3' is not A:B (each in [0, 10] kg)"));
}

static void test_refusals(void)
{
  t_args a;
  t_hand h;
  const char *bad[] = {"nan", "inf", "1e999", "12abc", "-inf", "0x1p500000"};
  for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) {
    AF_CHECK(!PARSE("--x", bad[k]));
    AF_CHECK(SAID("' is not a finite number (accepted range [-1.5, 2.5] m)"));
  }
  AF_CHECK(!PARSE("--x") && SAID("t: --x needs a value: X, a closed range\n"));
  AF_CHECK(!PARSE("--path", "") && SAID("t: --path needs a value: FILE"));
  AF_CHECK(!PARSE("--x", "1", "--x", "2"));
  AF_CHECK(SAID("t: --x is given twice (as argument 1 and 3); it is accepted once\n"));
  AF_CHECK(PARSE("--set", "a", "--set", "b") && h.n == 2); /* repeatable */
  AF_CHECK(!PARSE("--on", "--bogus"));
  AF_CHECK(SAID("t: unknown flag '--bogus'; accepted: --on, --path, --x, --pair, --open, "
                "--zero-or, --n, --seed, --lobe, --row, --set (t --help: units and defaults)\n"));
  /* One line for each refusal. */
  AF_CHECK(strchr(err, '\n') == err + strlen(err) - 1);
}

static void test_help(void)
{
  FILE *out = tmpfile();
  t_args d;
  char text[4096];
  memset(&d, 0, sizeof d);
  d.n = 4;
  af_options_help(out, table, N, &d, NULL);
  rewind(out);
  size_t n = fread(text, 1, sizeof text - 1, out);
  text[n] = '\0';
  fclose(out);
  AF_CHECK(strstr(text, "\n  --x X                        a closed range [m] (required, range "
                        "[-1.5, 2.5])\n") != NULL);
  AF_CHECK(strstr(text, "  --n N                        a whole number [workers] (default 4, "
                        "range [1, 256])\n") != NULL);
  AF_CHECK(strstr(text, "  --zero-or PA                 zero or [Pa] (default: rigid, range 0 or "
                        "[1e5, 1e12])\n") != NULL);
  AF_CHECK(strstr(text, "  --lobe N                     the row's range [-] (required, range "
                        "[1, 8])\n") != NULL);
  AF_CHECK(strstr(text, "  --path FILE                  a file (default: none)\n") != NULL);
}

int main(void)
{
  test_reader();
  test_kinds();
  test_bounds();
  test_refusals();
  test_help();
  return af_test_summary("test_options");
}
