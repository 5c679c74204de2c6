/* closeout.c — the exit-time check of stdout and the checked close of files
 * (see closeout.h). */
#define _POSIX_C_SOURCE 200809L
#include "closeout.h"

#include <errno.h>
#include <signal.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static const char *g_tool = "af";

/* Flushes and closes f; the cause of the first failure in *err (0 when
 * stdio kept no errno: an earlier write failed and its data was dropped). */
static bool close_checked(FILE *f, int *err)
{
  /* glibc keeps a buffer whose write failed and tries it again on the
   * next flush, so this flush names the cause (ENOSPC, EFBIG, EBADF). */
  errno = 0;
  bool ok = fflush(f) == 0;
  *err = ok ? 0 : errno;
  if (ferror(f))
    ok = false;
  errno = 0;
  if (fclose(f) != 0 && ok) {
    ok = false;
    *err = errno;
  }
  return ok;
}

static const char *cause(int err)
{
  return err != 0 ? strerror(err) : "an earlier write failed";
}

static void check_stdout(void)
{
  int err = 0;
  if (close_checked(stdout, &err))
    return;
  fprintf(stderr, "%s: cannot write standard output: %s\n", g_tool, cause(err));
  /* _exit: the exit status is already decided, and the remaining handlers
   * would only try the dead stream again. */
  _exit(1);
}

void af_closeout_install(const char *tool)
{
  if (tool != NULL)
    g_tool = tool;
  signal(SIGXFSZ, SIG_IGN);
  atexit(check_stdout);
}

int af_closeout_file(FILE *f, const char *path)
{
  int err = 0;
  if (f == NULL || close_checked(f, &err))
    return 0;
  fprintf(stderr, "%s: cannot write %s: %s\n", g_tool, path != NULL ? path : "a file", cause(err));
  return 1;
}
