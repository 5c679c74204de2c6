/* test_analyze_session.c — af_analyze_session (analyze.h), the fuzz harness's
 * way into `firmness_model analyze`: one session's runs over files that
 * change between them must print, byte for byte, what af_analyze_main prints
 * for each file alone. The files are the two real captures (test/data, the
 * same rates: the session's lane is reset, not made again) with a bad input
 * between them (an empty force file: exit 2, and the next run unharmed). */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "af_test.h"
#include "analyze.h"

#define DATA "test/data/hammer_capture_"

/* Copies the file at from (NULL: empty) to to; 0 on any failure. */
static int copy(const char *from, const char *to)
{
  FILE *out = fopen(to, "wb");
  if (out == NULL)
    return 0;
  int ok = 1;
  if (from != NULL) {
    FILE *in = fopen(from, "rb");
    char buf[1 << 14];
    size_t n;
    ok = in != NULL;
    while (ok && (n = fread(buf, 1, sizeof buf, in)) > 0)
      ok = fwrite(buf, 1, n, out) == n;
    if (in != NULL)
      fclose(in);
  }
  return fclose(out) == 0 && ok;
}

/* stdout into path for what follows; 0 on failure. */
static int stdout_to(const char *path)
{
  return fflush(stdout) == 0 && freopen(path, "w", stdout) != NULL;
}

/* The whole of a file, NUL-terminated (malloc'd), or NULL. */
static char *slurp(const char *path)
{
  FILE *f = fopen(path, "rb");
  if (f == NULL)
    return NULL;
  char *s = calloc(1 << 20, 1);
  size_t n = s ? fread(s, 1, (1 << 20) - 1, f) : 0;
  fclose(f);
  if (s != NULL && n == 0) {
    free(s);
    return NULL;
  }
  return s;
}

static int same_text(const char *a, const char *b)
{
  char *x = slurp(a), *y = slurp(b);
  int same = x != NULL && y != NULL && strcmp(x, y) == 0;
  if (!same)
    fprintf(stderr, "%s and %s differ\n", a, b);
  free(x);
  free(y);
  return same;
}

int main(void)
{
  char dir[] = "/tmp/af_test_session_XXXXXX", force[96], audio[96], path[128];
  AF_CHECK(mkdtemp(dir) != NULL);
  snprintf(force, sizeof force, "%s/force.f32", dir);
  snprintf(audio, sizeof audio, "%s/audio.f32", dir);
  const int saved_stdout = dup(fileno(stdout));
  AF_CHECK(saved_stdout >= 0);
  char *argv[] = {"firmness_model",
                  "analyze",
                  "--force",
                  force,
                  "--audio",
                  audio,
                  "--rate-force",
                  "25600",
                  "--rate-audio",
                  "25600",
                  "--mass",
                  "0.175",
                  "--R2",
                  "0.04",
                  NULL};
  /* alone: a new process's worth of set-up for each capture */
  for (int n = 4; n <= 5; n++) {
    AF_CHECK(copy(n == 4 ? DATA "4.force.f32" : DATA "5.force.f32", force));
    AF_CHECK(copy(n == 4 ? DATA "4.response.f32" : DATA "5.response.f32", audio));
    snprintf(path, sizeof path, "%s/alone_%d.json", dir, n);
    AF_CHECK(stdout_to(path));
    AF_CHECK(af_analyze_main(14, argv, 2) == 0);
  }
  /* one session: 4, 5, an empty force, 4 again */
  af_analyze_session *ss = NULL;
  AF_CHECK(af_analyze_session_create(14, argv, 2, &ss) == 0 && ss != NULL);
  const int order[] = {4, 5, 0, 4};
  for (size_t k = 0; ss != NULL && k < sizeof order / sizeof order[0]; k++) {
    const int n = order[k];
    AF_CHECK(copy(n == 0 ? NULL : n == 4 ? DATA "4.force.f32" : DATA "5.force.f32", force));
    AF_CHECK(copy(n == 5 ? DATA "5.response.f32" : DATA "4.response.f32", audio));
    snprintf(path, sizeof path, "%s/run_%zu.json", dir, k);
    AF_CHECK(stdout_to(path));
    AF_CHECK(af_analyze_session_run(ss) == (n == 0 ? 2 : 0));
  }
  af_analyze_session_destroy(ss);
  AF_CHECK(fflush(stdout) == 0 && dup2(saved_stdout, fileno(stdout)) >= 0);
  char a[128], b[128];
  const size_t runs[] = {0, 1, 3};
  for (size_t k = 0; k < 3; k++) {
    snprintf(a, sizeof a, "%s/run_%zu.json", dir, runs[k]);
    snprintf(b, sizeof b, "%s/alone_%d.json", dir, k == 1 ? 5 : 4);
    AF_CHECK(same_text(a, b));
  }
  /* every file made here, then the folder */
  const char *names[] = {"force.f32",  "audio.f32",  "alone_4.json", "alone_5.json",
                         "run_0.json", "run_1.json", "run_2.json",   "run_3.json"};
  for (size_t k = 0; k < sizeof names / sizeof names[0]; k++) {
    snprintf(path, sizeof path, "%s/%s", dir, names[k]);
    AF_CHECK(unlink(path) == 0);
  }
  AF_CHECK(rmdir(dir) == 0);
  return af_test_summary("test_analyze_session");
}
